"""The ``interpcnc`` back-end: a SOPROLEC InterpCNC V3 motion card driven over Modbus (TCP or RTU).

* :mod:`.registers` - register addresses and command ids, with seed 000 citations;
* :mod:`.protocol` - command encoders/decoders (pure functions);
* :mod:`.translate` - planner segments to commands (and what is left of an interrupted one);
* :mod:`.options`, :mod:`.outputs` - the ``[backends.interpcnc]`` table, auxiliary functions to actions;
* :mod:`.link` - the fail-stop pymodbus client;
* :mod:`.backend` - :class:`InterpCncBackend` (flow control, markers), with :mod:`.polling` (reading the
  card back), :mod:`.recovery` (faults, resume) and :mod:`.watchdog` (timeouts) mixed in; :mod:`.records`
  its error, status and sent-segment records;
* :mod:`.markers` - which straight moves share one sequence marker, and where a resume restarts in a group;
* :mod:`.refusals` - what a real run refuses before the start (#KIN, #RTCP ... active);
* :mod:`.card`, :mod:`.emulator` - an emulated card served over Modbus, for tests and dry runs;
* :mod:`.verify` - compares what the emulated card executed with what was planned.

Needs ``pymodbus>=3.16,<4`` (and ``pyserial`` for RTU).
"""

from .backend import InterpCncBackend, InterpCncError
from .options import Options, OutputAction
from .records import InterpCncStatus

__all__ = ["InterpCncBackend", "InterpCncError", "InterpCncStatus", "Options", "OutputAction"]
