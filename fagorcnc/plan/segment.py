"""The planner's output and its error: :class:`Segment` (a timed part of the motion) and :class:`PlanningError`.

A module of their own so that the planner and the independent axes' timeline (plan/independent.py), which
the planner runs its segments through, both build on them without importing each other.
"""

from __future__ import annotations

from dataclasses import dataclass

from .geometry import Piece
from .profile import Profile


@dataclass(slots=True)
class Segment:
    """A timed part of the motion.

    ``kind`` is ``"motion"``, ``"dwell"`` or ``"aux"``; ``t0`` its start time (s)
    and ``duration``; ``v0``/``v1`` the path speeds (mm/s) at its ends; ``piece``
    the geometry (machine coordinates), ``profile`` the motion along it when the
    planner was asked to keep profiles; ``record`` the motion record it comes
    from (for a corner blend: the block whose end it rounds); ``blend`` is True
    for a curve the planner inserted (G05/HSC).
    """

    kind: str
    t0: float
    duration: float
    line: int
    record: object
    piece: Piece | None = None
    v0: float = 0.0
    v1: float = 0.0
    profile: Profile | None = None
    blend: bool = False


class PlanningError(RuntimeError):
    """Raised when a span cannot be planned; carries the source line (and ``code``, its diagnostic's)."""

    code = "PLN001"

    def __init__(self, message: str, line: int, record=None) -> None:
        super().__init__(message)
        self.line = line
        self.record = record


def planning_code(exc: PlanningError) -> str:
    """The diagnostic code of a planning error: PLN001, or the code of its kind (INT232, plan/independent.py)."""
    return getattr(exc, "code", "PLN001")
