"""Names a package imports on first use (PEP 562), so that ``fagorcnc check`` does not load what a
check never runs (the back-ends, the trajectory sampler ...).

A package keeps a table ``{name: module}`` and forwards its module-level ``__getattr__`` and
``__dir__`` here::

    _LAZY = {"run": "fagorcnc.commands.run"}

    def __getattr__(name):
        return attribute(globals(), _LAZY, name)

The first access imports the module, takes the name from it and stores it in the package, so a
later access is an ordinary attribute lookup (``__getattr__`` is not called again).
:class:`LazyModule` does the same for a whole module a module-level name stands for.
"""

from __future__ import annotations

import importlib
import sys
from types import ModuleType
from typing import Any


def attribute(namespace: dict[str, Any], table: dict[str, str], name: str) -> Any:
    """``name`` of the package whose globals are ``namespace``: imported from the module ``table``
    names for it, stored in ``namespace``; :class:`AttributeError` for a name the table lacks."""
    module = table.get(name)
    if module is None:
        raise AttributeError(f"module {namespace['__name__']!r} has no attribute {name!r}")
    value = getattr(importlib.import_module(module), name)
    namespace[name] = value
    return value


def names(namespace: dict[str, Any], table: dict[str, str]) -> list[str]:
    """The package's ``dir()``: its globals and the names still to be imported."""
    return sorted(set(namespace) | set(table))


class LazyModule:
    """Stands for the module ``name`` until it is needed: the first attribute read (or write)
    imports it, and every access goes to the module itself (``sys.modules``), so a module-level
    ``family = LazyModule(...)`` reads as ``from . import family`` would, without the import.

    For modules only some programs use (the canned-cycle families): their names stay in the
    module that uses them, its function bodies unchanged."""

    __slots__ = ("_name",)

    def __init__(self, name: str) -> None:
        object.__setattr__(self, "_name", name)

    def _module(self) -> ModuleType:
        return sys.modules.get(self._name) or importlib.import_module(self._name)

    def __getattr__(self, attr: str) -> Any:
        return getattr(self._module(), attr)

    def __setattr__(self, attr: str, value: Any) -> None:
        setattr(self._module(), attr, value)

    def __delattr__(self, attr: str) -> None:
        delattr(self._module(), attr)

    def __dir__(self) -> list[str]:
        return dir(self._module())

    def __repr__(self) -> str:
        return f"<lazy module {self._name!r}{'' if self._name in sys.modules else ' (not imported yet)'}>"
