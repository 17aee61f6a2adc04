"""Configuration: the machine file (schema, defaults, loading), the LinuxCNC INI import and the
parameter file kept between runs.

Layering: :mod:`.errors` ← :mod:`.linuxcnc` ← :mod:`.machine` ← :mod:`.parameter_file`; the
LinuxCNC importer knows nothing of the machine schema (it returns a plain dict the machine
loader merges), so the two never import each other both ways.
"""

from .errors import MachineError
from .machine import DEFAULT_MACHINE, Machine, load_machine

__all__ = ["DEFAULT_MACHINE", "Machine", "MachineError", "load_machine"]
