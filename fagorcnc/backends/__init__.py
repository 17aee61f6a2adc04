"""Back-ends: where planned segments go (the embedded simulator or an InterpCNC card).

The registry (which reads the entry points) and the simulator are imported on first use
(PEP 562, :mod:`fagorcnc._lazy`): a module that only needs the protocol (:class:`Status`) does not
load them.
"""

from typing import Any as _Any

from .. import _lazy
from .base import Backend, BackendError, Status

#: names imported on first use: name -> the module that defines it
_LAZY = {"available": "fagorcnc.backends.registry", "get_backend": "fagorcnc.backends.registry",
         "SimulatorBackend": "fagorcnc.backends.sim"}


def __getattr__(name: str) -> _Any:
    """The names of :data:`_LAZY`, imported on first use and kept (PEP 562)."""
    return _lazy.attribute(globals(), _LAZY, name)


def __dir__() -> list[str]:
    """The module's names, the lazy ones included."""
    return _lazy.names(globals(), _LAZY)


__all__ = ["Backend", "BackendError", "SimulatorBackend", "Status", "available", "get_backend"]
