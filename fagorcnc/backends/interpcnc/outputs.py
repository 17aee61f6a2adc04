"""Auxiliary functions (M, S, T, H, D) -> synchronised actions (command 1010), from the ``outputs`` table.

The table is described in :mod:`.options`.  A function is looked up by its
full name first (``M3``), then by its letter (``M``).  One that is neither
mapped nor in ``ignore`` is *unmapped*: the back-end reports it, never drops
it silently.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from . import protocol as proto
from .options import Options, OutputAction


@dataclass
class Translation:
    """The commands for one auxiliary function, and what a machinist should be told about it."""

    commands: list[proto.Words] = field(default_factory=list)
    mapped: bool = True
    warnings: list[str] = field(default_factory=list)


class OutputTable:
    """Look-ups in the ``outputs`` and ``ignore`` options."""

    def __init__(self, options: Options) -> None:
        self.outputs = options.outputs
        self.ignore = options.ignore

    @staticmethod
    def _key(function: str, value: float) -> str | None:
        return f"{function}{int(value)}" if float(value).is_integer() else None

    def actions(self, function: str, value: float) -> tuple[OutputAction, ...] | None:
        """The actions for ``function`` with ``value``; None when unmapped."""
        key = self._key(function, value)
        if key is not None and key in self.outputs:
            return self.outputs[key]
        return self.outputs.get(function)

    def ignored(self, function: str, value: float) -> bool:
        return self._key(function, value) in self.ignore or function in self.ignore

    def unmapped(self, function: str, value: float) -> bool:
        return self.actions(function, value) is None and not self.ignored(function, value)

    @staticmethod
    def unmapped_message(line: int, function: str, value: float) -> str:
        return (f"line {line}: {function}{value:g} has no entry in [backends.interpcnc.outputs]; "
                "it was not sent to the card")

    def translate(self, line: int, function: str, value: float) -> Translation:
        """The 1010 commands of one auxiliary function (a scaled value out of range is clamped, with a warning)."""
        actions = self.actions(function, value)
        if actions is None:
            unmapped = not self.ignored(function, value)
            return Translation([], not unmapped, [self.unmapped_message(line, function, value)] if unmapped else [])
        out = Translation()
        for a in actions:
            v, clamped = a.resolve(value)
            if clamped:
                out.warnings.append(f"line {line}: {function}{value:g} gives {v} after clamping to "
                                    f"{a.low}..{a.high} (action type {a.type})")
            out.commands.append(proto.encode_action(a.type, a.address, v))
        return out
