"""Canonical motion records: what the interpreter hands downstream.

Like LinuxCNC's canonical machining functions, the records say *what* path
the tool follows, never how fast in time.  Positions are ``{axis: float}`` in
**machine** coordinates (mm, degrees); ``end_part`` gives the same end point in
part coordinates.  Every record keeps its :class:`Source` so later errors can
name the block.

``frame`` is the transformation (#CS/#ACS, #RTCP, #TLC, #TOOL ORI) a move was made under, None
when there is none; the joint-space stage (:mod:`fagorcnc.kinematics.stage`) has then already put
``start``/``end`` in machine joints, ``end_part`` stays in the programmed frame.

``feed`` is always the programmed feed along the path in **mm/min** (after
MAXFEED); ``feed_mode`` says how it was programmed: ``"G94"`` mm/min,
``"G95"`` mm/rev times the spindle speed, ``"G93"`` the move's time.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..path.arcs import sweep as _sweep


@dataclass(frozen=True, slots=True)
class Source:
    """Where a record comes from: file, 1-based line, the block's text."""

    file: str
    line: int
    text: str


@dataclass(frozen=True, slots=True)
class Line:
    """A straight move; ``kind`` is ``"rapid"`` (G00) or ``"linear"`` (G01)."""

    kind: str
    start: dict
    end: dict
    end_part: dict
    feed: float | None
    feed_mode: str
    src: Source
    comp: tuple | None = None   # radius compensation (side, R, G136/G137, G138/G139, plane)
    dyn: object = None          # planning context (interp.dynamics.Dynamics); None = defaults
    frame: object = None        # active transformation (kinematics.frame.Frame): #CS/#ACS, #RTCP, #TLC
    joins: tuple | None = None  # without compensation: (G136/G137, G138/G139) in force, for a cancellation

    @property
    def line(self) -> int:
        return self.src.line

    @property
    def rapid(self) -> bool:
        return self.kind == "rapid"

    @property
    def length(self) -> float:
        """Length of the move over all axes that change (mm; degrees count as mm)."""
        return math.sqrt(sum((self.end[a] - self.start[a]) ** 2 for a in self.end))


@dataclass(frozen=True, slots=True)
class Arc:
    """A circular or helical move in the plane (``abscissa``, ``ordinate``).

    ``center``/``center_part`` hold the centre's plane coordinates;
    ``direction`` is ``"cw"`` (G02) or ``"ccw"`` (G03) seen from the positive
    side of the plane's normal; ``turns`` counts extra full turns (0 for an
    ordinary arc).  Other axes that change move linearly (helix).  An arc with
    no ``feed`` runs at rapid: one the path stage inserts before a G00 (a G36
    rounding, seed 002 L8460; a compensation transition), see :attr:`rapid`.
    """

    kind: str
    start: dict
    end: dict
    end_part: dict
    center: dict
    center_part: dict
    direction: str
    plane: tuple
    radius: float
    turns: int
    feed: float | None
    feed_mode: str
    src: Source
    comp: tuple | None = None   # radius compensation (side, R, G136/G137, G138/G139, plane)
    dyn: object = None          # planning context (interp.dynamics.Dynamics); None = defaults
    frame: object = None        # active transformation (kinematics.frame.Frame): #CS/#ACS, #RTCP, #TLC
    joins: tuple | None = None  # without compensation: (G136/G137, G138/G139) in force, for a cancellation

    @property
    def line(self) -> int:
        return self.src.line

    @property
    def rapid(self) -> bool:
        """Run at rapid: an arc inserted before a G00 carries no feed."""
        return self.feed is None

    @property
    def sweep(self) -> float:
        """Signed sweep angle in degrees (negative clockwise), full turns included."""
        a, o = self.plane[0], self.plane[1]
        d = _sweep((self.start[a], self.start[o]), (self.end[a], self.end[o]),
                  (self.center[a], self.center[o]), self.direction == "ccw")
        return d + math.copysign(360.0 * self.turns, d)

    @property
    def length(self) -> float:
        """Path length of the arc (helix included), mm."""
        a, o = self.plane[0], self.plane[1]
        planar = abs(math.radians(self.sweep)) * self.radius
        other = sum((self.end[x] - self.start[x]) ** 2 for x in self.end if x not in (a, o))
        return math.hypot(planar, math.sqrt(other))


class _AtPosition:
    """Records that happen at one position: ``start`` and ``end`` are ``position``."""

    __slots__ = ()

    @property
    def line(self) -> int:
        return self.src.line

    @property
    def start(self) -> dict:
        return self.position

    @property
    def end(self) -> dict:
        return self.position


@dataclass(frozen=True, slots=True)
class Dwell(_AtPosition):
    """A dwell (G04, #TIME) of ``seconds`` at ``position`` (machine coordinates)."""

    kind: str
    seconds: float
    position: dict
    src: Source


@dataclass(frozen=True, slots=True)
class Aux(_AtPosition):
    """An auxiliary function for the machine: M, H, S, T or D; SPOS is the angular position (degrees,
    0-360) an S gives in an M19 block (seed 002 L5703-L5713).

    ``timing`` is ``"before"`` or ``"after"`` the block's motion (seed 002
    L5020-L5029: M functions not in the M table run before the motion);
    ``spindle`` names the spindle of an S record.
    """

    kind: str
    function: str
    value: float
    timing: str
    position: dict
    src: Source
    spindle: str | None = None


Record = Line | Arc | Dwell | Aux

_FEED_MODES: dict[int, str] = {}
_JOINS: dict[tuple, tuple] = {}


def feed_mode(g: int) -> str:
    """``"G94"`` for 94...: one string per feed mode, shared by every record (simulate() keeps them all)."""
    name = _FEED_MODES.get(g)
    if name is None:
        name = _FEED_MODES[g] = f"G{g}"
    return name


def shared_tuple(value: tuple) -> tuple:
    """One tuple object per value of the small modal tuples records carry (``joins``)."""
    return _JOINS.setdefault(value, value)


def record_time(machine, record) -> float:
    """Seconds a record takes at its programmed feed, without acceleration
    (rapids: every axis within its maximum speed, seed 002 L5969-L6030)."""
    kind = record.kind
    if kind == "dwell":
        return record.seconds
    if kind in ("aux", "aid"):
        return 0.0
    length = record.length
    if length == 0.0:
        return 0.0
    if kind == "rapid":
        t = max((abs(record.end[a] - record.start[a]) / machine.axes[a].max_velocity for a in record.end),
                default=0.0)
        if machine.rapid_feed > 0:
            t = max(t, length / machine.rapid_feed)
        return t * 60.0
    if kind == "arc" and record.feed is None:   # at rapid: within the slowest of its plane's axes
        speed = min(machine.axes[a].max_velocity for a in record.plane[:2])
        if machine.rapid_feed > 0:
            speed = min(speed, machine.rapid_feed)
        return length / speed * 60.0
    return length / record.feed * 60.0 if record.feed else 0.0
