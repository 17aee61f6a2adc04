"""``python -m fagorcnc`` runs the ``fagorcnc`` command."""

import sys

from .cli import command

sys.exit(command())
