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
``"G95"`` mm/rev times the spindle speed, ``"G93"`` the move's time,
``"G33"``/``"G63"`` a thread or a rigid tap whose :class:`Thread` says how the
feed follows the spindle.
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
class Thread:
    """The spindle synchronisation of a G33 thread or a G63 rigid tap (seed 002 ch. 8.7-8.8).

    ``pitch`` is in mm per spindle revolution along ``axis`` (G33: the axis of the pitch letter,
    L7326; G63: the pitch F/S of the whole move, L7562); ``speed`` the spindle speed in rpm the
    feed was computed from, negative when the spindle turns against M03 (a G63 return, L7567);
    ``entry`` the G33 entry angle Q1 in degrees when the block synchronises on it, None for a
    thread joined to the one before (L7436-L7441) and for G63.  ``rigid`` is True for G63: the
    CNC interpolates the spindle with the axes and the feed override applies (L7633); a G33
    runs at 100 % of pitch x speed (L7449).
    """

    rigid: bool
    spindle: str
    speed: float
    pitch: float
    axis: str
    entry: float | None


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
    thread: Thread | None = None  # G33/G63: the feed follows the spindle
    css: tuple | None = None      # G95 under G96: the feed follows the radius (see :func:`css_rpm`)

    @property
    def line(self) -> int:
        return self.src.line

    @property
    def rapid(self) -> bool:
        return self.kind == "rapid"

    @property
    def plc_marks(self) -> tuple:
        """PLC marks the channel holds on during the move (``Dynamics.plc_marks``; TAPPING, RIGID)."""
        return self.dyn.plc_marks if self.dyn is not None else ()

    @property
    def length(self) -> float:
        """Length of the move over all axes that change (mm; degrees count as mm)."""
        return math.sqrt(sum((self.end[a] - self.start[a]) ** 2 for a in self.end))


@dataclass(frozen=True, slots=True)
class CurveLine(Line):
    """A chord of a sampled curve (#POLY, #SPLINE; interp/curves.py): ``curve`` is one object for
    all the chords of one curve, which the planner joins without a corner."""

    curve: object = None


@dataclass(frozen=True, slots=True)
class IndependentMove(Line):
    """A #MOVE positioning of one axis (seed 002 L16684-L16747): ``link`` is how it ends, PRESENT
    (at its own feed), NEXT (at the next #MOVE's feed), NULL (at rest) or WAITINPOS (at rest, in
    position); ``axis`` the axis it moves (its own interpolator, plan/independent.py)."""

    link: str = "NULL"
    axis: str = ""


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
    css: tuple | None = None    # G95 under G96: the feed follows the radius (see :func:`css_rpm`)

    @property
    def line(self) -> int:
        return self.src.line

    @property
    def rapid(self) -> bool:
        """Run at rapid: an arc inserted before a G00 carries no feed."""
        return self.feed is None

    @property
    def plc_marks(self) -> tuple:
        """PLC marks the channel holds on during the move (``Dynamics.plc_marks``; TAPPING, RIGID)."""
        return self.dyn.plc_marks if self.dyn is not None else ()

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
    plc_marks: tuple = ()   # PLC marks on during the dwell (a tapping cycle's: TAPPING, RIGID)


@dataclass(frozen=True, slots=True)
class IndependentSync(Dwell):
    """``#SYNC POS`` after #MOVE positionings (seed 002 L16657-L16665): the general interpolator takes the
    axes' positions; the general motion waits there until the independent axes have stopped
    (plan/independent.py).  A dwell of no time of its own."""


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
    plc_marks: tuple = ()   # PLC marks on while it runs (a tapping cycle's spindle reversal: TAPPING)


Record = Line | Arc | Dwell | Aux

#: Samples along a G95/G96 move for its time (midpoint rule; the feed varies smoothly with the radius).
CSS_SAMPLES = 64


def css_rpm(css: tuple, radius: float) -> float:
    """Spindle speed (rpm) under G96 at ``radius`` (mm) from the axis: ``css = (mm/rev, surface m/min,
    G192 limit rpm or 0, radius axis, machine - part offset of that axis)``; seed 002 L5406-L5464:
    rpm = 1000 S / (2 pi r), at most the G192 limit (infinite at the centre without one)."""
    _per_rev, surface, limit, _axis, _offset = css
    rpm = surface * 1000.0 / (2.0 * math.pi * radius) if radius > 1e-9 else math.inf
    return min(rpm, limit) if limit > 0 else rpm


def css_feed(css: tuple, machine_coordinate: float, max_feed: float) -> float:
    """The G95 feed (mm/min) at a machine coordinate of the radius axis, within MAXFEED (L4072)."""
    feed = css[0] * css_rpm(css, abs(machine_coordinate - css[4]))
    return min(feed, max_feed) if max_feed > 0 else feed


def axis_at(record, axis: str, t: float) -> float:
    """The machine coordinate of ``axis`` at the fraction ``t`` of a line's or an arc's sweep."""
    if record.kind == "arc" and axis in record.plane[:2]:
        a, o = record.plane[0], record.plane[1]
        c = (record.center[a], record.center[o])
        angle = math.atan2(record.start[o] - c[1], record.start[a] - c[0]) + t * math.radians(record.sweep)
        r = math.dist((record.start[a], record.start[o]), c)
        return c[0] + r * math.cos(angle) if axis == a else c[1] + r * math.sin(angle)
    return record.start[axis] + t * (record.end[axis] - record.start[axis])


def _css_time(machine, record) -> float:
    """Seconds of a G95 move under G96: the feed follows the radius along it (midpoint rule)."""
    axis = record.css[3]
    total = 0.0
    for i in range(CSS_SAMPLES):
        feed = css_feed(record.css, axis_at(record, axis, (i + 0.5) / CSS_SAMPLES), machine.max_feed)
        total += 0.0 if math.isinf(feed) else record.length / CSS_SAMPLES / feed
    return total * 60.0

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
    if record.css is not None:
        return _css_time(machine, record)
    return length / record.feed * 60.0 if record.feed else 0.0
