"""Compatibility path: the machine configuration lives in :mod:`fagorcnc.config.machine`.

``from fagorcnc.machine import Machine, MachineError, load_machine`` keeps working for user code.
"""

from .config.machine import *  # noqa: F403
from .config.machine import DEFAULT_MACHINE, Machine, MachineError, load_machine

__all__ = ["DEFAULT_MACHINE", "Machine", "MachineError", "load_machine"]
