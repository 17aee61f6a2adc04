"""The back-ends by name: the built-in ``sim`` and ``interpcnc``, plus any package that declares
an entry point in the group ``fagorcnc.backends``.

It lives apart from :mod:`.base` so that the protocol imports no implementation.
"""

from __future__ import annotations

from importlib.metadata import entry_points

from ..config.machine import Machine
from .base import Backend, BackendError


def available() -> dict[str, object]:
    """Back-end factories by name: built-ins first, then entry points."""
    from .sim import SimulatorBackend

    found: dict[str, object] = {"sim": SimulatorBackend}
    try:
        from .interpcnc import InterpCncBackend

        found["interpcnc"] = InterpCncBackend
    except ImportError:   # pragma: no cover - pymodbus missing
        pass
    for ep in entry_points(group="fagorcnc.backends"):
        found.setdefault(ep.name, ep)
    return found


def get_backend(name: str, machine: Machine, **options) -> Backend:
    """Build the back-end called ``name`` for ``machine`` (options are back-end specific)."""
    factories = available()
    if name not in factories:
        raise BackendError(f"unknown back-end {name!r} (available: {', '.join(sorted(factories))})")
    factory = factories[name]
    if hasattr(factory, "load"):
        factory = factory.load()
    return factory(machine, **options)
