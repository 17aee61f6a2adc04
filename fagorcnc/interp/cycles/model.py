"""The modal canned-cycle state: the active cycle, its call parameters, the hole count.

Seed 002 L1447-L1487 lists the cycles; the rules of their modal life (definition block,
influence zone, cancellation) are in ``09-canned-cycles.md`` §1.  The call parameters
are the ``V.C.A`` ... ``V.C.Z`` variables (seed 002 L40310-L40386), kept as programmed
(program units) so that the program reads back what it wrote.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

#: Hole-making and pocketing cycles: they form one modal group with G80 (seed 002 L1449-L1487).
CYCLE_CODES = frozenset({81, 82, 83, 84, 85, 86, 87, 88, 210, 211, 212})
#: Multiple machining (positioning) cycles, acting in their block only (seed 002 L1471-L1481).
PATTERN_CODES = frozenset({160, 161, 162, 163, 164, 165})

LETTERS = "ABCDEFGHIJKLMNOPQRSTUVWXYZ"


def unit(angle: float) -> tuple[float, float]:
    """Unit vector at ``angle`` degrees; exact on the axes (no 6e-17 residues at 90, 180, 270)."""
    quarter = angle / 90.0
    if quarter == math.floor(quarter):
        return ((1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (0.0, -1.0))[int(quarter) % 4]
    rad = math.radians(angle)
    return (math.cos(rad), math.sin(rad))


@dataclass
class ActiveCycle:
    """A defined canned cycle: what its definition block fixed for the whole influence zone."""

    code: int
    params: dict[str, float]          # letter -> value as programmed (V.C.x); shared with CycleState.params
    cols: dict[str, int]              # letter -> column in the definition block (for diagnostics)
    incremental: bool                 # G91 at the definition (Z, I relative, §1.3)
    inch: bool                        # G70 at the definition (letters in inches)
    plane: tuple[str, str, str]       # abscissa, ordinate, longitudinal axis of the cycle
    zs: float                         # starting plane: longitudinal position at the definition (mm)
    key: tuple[str, int, int]         # (file, line, G number) of the definition block
    plan: object = None               # the validated geometry, rebuilt after a V.C write
    warned: bool = False              # the spindle-stopped warning was given (once per definition)

    def has(self, letter: str) -> bool:
        return letter in self.params

    def get(self, letter: str, default: float | None = None) -> float | None:
        return self.params.get(letter, default)

    def col(self, letter: str) -> int:
        return self.cols.get(letter, self.cols.get("G", 1))


@dataclass
class CycleState:
    """Canned-cycle part of the channel state (see ``ChannelState.cycles``)."""

    active: ActiveCycle | None = None
    params: dict[str, float] = field(default_factory=dict)          # V.C.A..Z of the last definition
    called: frozenset = frozenset()                                 # V.C.CALLP_x
    pattern_params: dict[str, float] = field(default_factory=dict)  # V.C.P_x of the last G160-G165
    pattern_called: frozenset = frozenset()                         # V.C.P_CALLP_x
    holes: dict[tuple[str, int, int], int] = field(default_factory=dict)   # definition -> holes made

    def cancel(self, modes: dict) -> None:
        """G80, another cycle, a plane or tool-axis change, M02/M30/reset (digest §1.1)."""
        self.active = None
        modes["cycle"] = 80

    def reset(self) -> None:
        self.active = None

    def count(self) -> None:
        """One more hole (one machining of the cycle) for the active definition."""
        key = self.active.key
        self.holes[key] = self.holes.get(key, 0) + 1

    def report(self) -> list[dict]:
        """The cycles that ran, in order of definition: ``{"code", "file", "line", "holes"}``."""
        return [{"code": f"G{code}", "file": file, "line": line, "holes": n}
                for (file, line, code), n in self.holes.items()]
