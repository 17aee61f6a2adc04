"""Back-ends: where planned segments go (the embedded simulator or an InterpCNC card)."""

from .base import Backend, BackendError, Status
from .registry import available, get_backend
from .sim import SimulatorBackend

__all__ = ["Backend", "BackendError", "SimulatorBackend", "Status", "available", "get_backend"]
