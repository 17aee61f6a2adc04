"""``python -m fagorcnc`` runs the ``fagorcnc`` command."""

import sys

from .cli import main

sys.exit(main())
