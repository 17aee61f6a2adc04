"""The ``[compat]`` policy: what fagorcnc does with constructs CAM posts write that the manual does not.

Posts for the 8060/8065 have written some blocks for years that the programming manual (seed 002)
does not describe, and the controls evidently accept them: ``G51 A45 E0.002`` (the 8055's
look-ahead), ``G61`` alone in a block, ``G501``/``G500`` with no subroutine file, program names with
``_``, ``.`` or blanks, the program name alone on the first line, ``T202 LM06``, lower-case keywords
inside a ``#`` sentence's brackets.  Each of them is a *construct* with an action in the machine
file::

    [compat]
    strict = false          # true: every construct below is an error (the manual's letter)
    g51 = "warn"            # "accept" (a note), "warn" (a warning) or "error"
    lone_g61 = "warn"
    oem_smoothing = "warn"
    program_name = "warn"
    bare_name = "warn"
    tool_subroutine = "warn"
    keyword_case = "warn"

``fagorcnc check --strict`` is ``strict = true`` for one check.  The machinist's lint
(:data:`LINT`: G58 after another work offset, a move at feed with the spindle stopped, a G
number written with a leading zero) is configured in the same table but ``strict`` leaves it
alone: those blocks are the manual's letter, only likely mistakes.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Any

from ..diagnostics import Diagnostic
from .errors import MachineError

ACTIONS = ("accept", "warn", "error")
#: action -> severity of its diagnostic ("accept" keeps a note, visible with -v)
SEVERITY = {"accept": "info", "warn": "warning", "error": "error"}

#: construct -> (default action, what it is): the README "CAM posts" section lists them.
CONSTRUCTS: dict[str, tuple[str, str]] = {
    "g51": ("warn", "G51 A.. E..: the 8055's look-ahead, not a G function of the 8060/8065 (L1354)"),
    "lone_g61": ("warn", "G61 alone in its block (it acts on the move of its own block only, L8088-L8107)"),
    "oem_smoothing": ("warn", "G501 / G500 with no subroutine file: fagorcnc's built-in HSC on / off"),
    "program_name": ("warn", "program name with '_', '.', blanks or over 14 characters (L843)"),
    "bare_name": ("warn", "the program name alone on the first line, without '%'"),
    "tool_subroutine": ("warn", "T202 LM06: a global subroutine call glued to the T word, with no file"),
    "keyword_case": ("warn", "a keyword in a # sentence's brackets not in capitals (#CS ON [1] [Mode 1, ...])"),
}
#: lint -> (default action, what it is); `strict` does not change them.
LINT: dict[str, tuple[str, str]] = {
    "g58_after_offset": ("warn", "G58 right after another work offset (G58 is absolute origin 5: it replaces it)"),
    "feed_spindle_stopped": ("warn", "a move at feed (G01/G02/G03) while the spindle is stopped"),
    "leading_zeros": ("warn", "a G number written with a leading zero before two digits (G011 reads as G11)"),
}

#: diagnostic code -> the construct whose action sets its severity (front end and interpreter)
CODE_CONSTRUCTS: dict[str, str] = {
    "CAM001": "g51",
    "CAM002": "lone_g61",
    "CAM003": "oem_smoothing",
    "CAM004": "program_name",
    "STR011": "bare_name",
    "CAM006": "tool_subroutine",
    "CAM007": "keyword_case",
    "CAM013": "g58_after_offset",
    "CAM014": "feed_spindle_stopped",
    "CAM010": "leading_zeros",
}


@dataclass(frozen=True)
class Compat:
    """The actions of a machine's ``[compat]`` table (every key present)."""

    actions: dict[str, str] = field(default_factory=lambda: {k: v[0] for k, v in {**CONSTRUCTS, **LINT}.items()})
    strict: bool = False

    def action(self, key: str) -> str:
        """``"accept"``, ``"warn"`` or ``"error"`` for a construct or lint key."""
        if self.strict and key in CONSTRUCTS:
            return "error"
        return self.actions[key]

    def severity(self, key: str) -> str:
        """The severity of the diagnostic a construct gets: ``"info"``, ``"warning"`` or ``"error"``."""
        return SEVERITY[self.action(key)]

    def strictly(self) -> Compat:
        """The same policy with ``strict = true`` (``fagorcnc check --strict``)."""
        return replace(self, strict=True)

    def adjust(self, diag: Diagnostic) -> Diagnostic:
        """``diag`` with the severity this policy gives its construct (others unchanged)."""
        key = CODE_CONSTRUCTS.get(diag.code)
        if key is None:
            return diag
        severity = self.severity(key)
        if severity == diag.severity:
            return diag
        message = f"{diag.message} {self.refusal(key)}" if severity == "error" else diag.message
        return replace(diag, severity=severity, message=message)

    def refusal(self, key: str) -> str:
        """What an error message adds to say which setting refused the construct."""
        if self.strict and key in CONSTRUCTS:
            return "[refused: strict compatibility]"
        return f'[refused: compat.{key} = "error"]'


#: the built-in policy (no [compat] table)
DEFAULT = Compat()


def parse_compat(table: Any) -> Compat:
    """The :class:`Compat` of a machine file's ``[compat]`` table (``MachineError`` names the key)."""
    if not isinstance(table, dict):
        raise MachineError("compat: expected a table, e.g. [compat] strict = true")
    actions = dict(DEFAULT.actions)
    strict = False
    for key, value in table.items():
        if key == "strict":
            if not isinstance(value, bool):
                raise MachineError(f"compat.strict: expected true or false, got {value!r}")
            strict = value
        elif key in actions:
            if value not in ACTIONS:
                raise MachineError(f"compat.{key} = {value!r}: must be \"accept\", \"warn\" or \"error\"")
            actions[key] = value
        else:
            known = ", ".join(["strict", *actions])
            raise MachineError(f"compat.{key}: unknown key (known: {known})")
    return Compat(actions, strict)
