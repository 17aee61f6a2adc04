"""What ``fagorcnc check`` reports of the moves: tools, origins and the bounding box per tool.

:class:`MoveSummary` is fed every motion record as the dry run makes it, takes them in batches and
widens the boxes by runs of points reduced per axis at C speed (:func:`_reduce`): the values
widening them point by point (:meth:`Box.add`) gives.  :func:`extent`, :func:`_add_to_both` and
:func:`_merge_into_both` widen boxes by one block or one point (public helpers, not on the
summary's way any more).
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from dataclasses import dataclass, field
from operator import is_, itemgetter
from typing import Any

from ..interp.records import Arc, CurveLine, IndependentMove, Line


def _round(v: float) -> float:
    return round(v, 6) + 0.0   # + 0.0 turns -0.0 into 0.0


def _num(v: float) -> str:
    text = f"{_round(v):.4f}".rstrip("0").rstrip(".")
    return "0" if text == "-0" else text


@dataclass
class Box:
    """An axis-aligned box: ``lo``/``hi`` per axis (mm, degrees)."""

    lo: dict[str, float] = field(default_factory=dict)
    hi: dict[str, float] = field(default_factory=dict)

    def add(self, point: dict[str, float]) -> None:
        mine_lo, mine_hi = self.lo, self.hi
        for axis, v in point.items():
            lo = mine_lo.get(axis)
            if lo is None:
                mine_lo[axis] = mine_hi[axis] = v
            elif v < lo:
                mine_lo[axis] = v
            elif v > mine_hi[axis]:
                mine_hi[axis] = v

    def merge(self, lo: dict[str, float], hi: dict[str, float]) -> None:
        """Widen the box to hold the box ``lo``..``hi`` (one call per block, see :func:`extent`)."""
        mine_lo, mine_hi = self.lo, self.hi
        for axis, v in lo.items():
            if axis not in mine_lo:
                mine_lo[axis], mine_hi[axis] = v, hi[axis]
                continue
            if v < mine_lo[axis]:
                mine_lo[axis] = v
            w = hi[axis]
            if w > mine_hi[axis]:
                mine_hi[axis] = w

    def __bool__(self) -> bool:
        return bool(self.lo)

    def to_dict(self) -> dict[str, dict[str, float]]:
        return {"min": {a: _round(v) for a, v in self.lo.items()}, "max": {a: _round(v) for a, v in self.hi.items()}}

    def text(self) -> str:
        return "  ".join(f"{a} {_num(self.lo[a])}..{_num(self.hi[a])}" for a in self.lo)


@dataclass
class ToolUse:
    """A tool the program selected (T), whether M06 loaded it, the offsets D used with it."""

    tool: int
    loaded: bool = False
    offsets: list[int] = field(default_factory=list)
    lines: list[int] = field(default_factory=list)


@dataclass
class OriginUse:
    """An absolute origin active while moves ran: ``"G54"``, ``"G159=7"``, ``"G92"``, ``"G53"``."""

    origin: str
    first_line: int
    moves: int = 0


@dataclass
class ToolBox:
    """Extent of the motion while ``tool`` was in the spindle (all moves, and feeds alone)."""

    tool: int
    machine: Box = field(default_factory=Box)
    part: Box = field(default_factory=Box)
    feed_machine: Box = field(default_factory=Box)
    feed_part: Box = field(default_factory=Box)

    def to_dict(self) -> dict[str, Any]:
        feed = {"machine": self.feed_machine.to_dict(), "part": self.feed_part.to_dict()} if self.feed_machine \
            else None
        return {"tool": self.tool, "machine": self.machine.to_dict(), "part": self.part.to_dict(), "feed": feed}


class MoveSummary:
    """Tools, origins and per-tool boxes, from the motion records as the interpreter makes them
    (:meth:`add`; the absolute origin in force is read from its state at that moment).

    The boxes are widened by runs, not point by point: the points of the moves made with one tool
    are kept in plain lists (machine and part coordinates; rapids and feeds apart), and reduced per
    axis at C speed when the tool changes, a list holds :data:`RUN_POINTS` points or the boxes are
    asked for (:func:`_reduce`).  A move's points are its start (unless it starts where the last
    move of its kind ended: already in), its end and an arc's quarter-turn points
    (:func:`arc_points`); a plain line that continues the last move, and an arc at feed that continues
    a run of feeds, take a short way in :meth:`_summarise`.  The boxes get the values widening them
    point by point gives.
    """

    __slots__ = (
        "_boxes",
        "_feed",
        "_feeds",
        "_in_force",
        "_interp",
        "_labels",
        "_last_end",
        "_line_kind",
        "_machine_points",
        "_next_tool",
        "_order",
        "_part_here",
        "_part_points",
        "_pending",
        "_rapids",
        "_run",
        "_seen",
        "_tool",
        "_tools",
        "_used",
    )

    def __init__(self) -> None:
        self._tools: dict[int, ToolUse] = {}
        self._used: dict[str, OriginUse] = {}
        self._boxes: dict[int, ToolBox] = {}
        self._tool = self._next_tool = 0
        self._part_here: dict[str, float] | None = None
        self._interp = None
        # records not yet summarised, where the origin changed among them (index, origin), the origin
        # last seen and the one in force at the first of them
        self._pending: list = []
        self._labels: list[tuple[int, str]] = []
        self._seen: str | None = None
        self._in_force = "?"
        # the run: the tool's boxes its points go into; the points of its rapids and of its feeds (machine,
        # part); those the next move adds to (``_feed``: the feeds'); where each list took over, in turn
        self._run: ToolBox | None = None
        self._rapids: tuple[list, list] = ([], [])
        self._feeds: tuple[list, list] = ([], [])
        self._feed = False
        self._machine_points, self._part_points = self._rapids
        self._order: list[tuple[bool, int, int]] = [(False, 0, 0)]
        # the end of the last move, when it is in the current lists (or the boxes), and the kind a plain
        # line (:data:`_LINES`) has when it goes into the current lists: "rapid", "linear" or None
        self._last_end: dict[str, float] | None = None
        self._line_kind: str | None = None

    def add(self, rec, interp) -> None:
        """Take one record (``on_record`` of :func:`fagorcnc.simulate.dry_run`): kept, with the origin in
        force if it changed, and summarised with the others of its batch (:meth:`_take`)."""
        pending = self._pending
        pending.append(rec)
        label = getattr(interp.state, "origin_source", "?")
        if label is not self._seen:   # (an equal string made again: one more mark, nothing else)
            self._seen = label
            self._labels.append((len(pending) - 1, label))
        self._interp = interp
        if len(pending) >= BATCH:
            self._take()

    def _take(self) -> None:
        """The pending records into the summary, each under the origin in force when it came."""
        pending, labels = self._pending, self._labels
        if not pending:
            return
        begin, label = 0, self._in_force
        for at, following in labels:
            if at > begin:
                self._summarise(pending[begin:at], label)
            begin, label = at, following
        self._summarise(pending[begin:] if begin else pending, label)
        self._in_force = label
        pending.clear()
        labels.clear()

    def _summarise(self, records: list, label: str) -> None:
        """``records``, made under the origin ``label``, into the summary: a plain line that continues
        the last move by its end points alone, an arc at feed that continues the feeds by its end and
        quarter-turn points, any other record by :meth:`_add`."""
        moves = 0
        for rec in records:
            kind = rec.kind
            if (kind is self._line_kind and rec.start is self._last_end and type(rec) in _LINES) or (
                    kind == "arc" and self._line_kind == "linear" and rec.start is self._last_end
                    and type(rec) is Arc and rec.feed is not None):
                # a plain line continuing the last move of its kind, or an arc at feed continuing the feeds
                end_part = rec.end_part
                if end_part is None:
                    continue
                if not moves:
                    self._enter(label, rec)
                moves += 1
                points, part = self._machine_points, self._part_points
                points.append(end := rec.end)
                part.append(end_part)
                if kind == "arc":
                    _arc_points_of(rec, self._part_here, end_part, points, part)
                self._part_here, self._last_end = end_part, end
                if len(points) >= RUN_POINTS:
                    self._flush()
            elif self._add(rec, kind):
                if not moves:
                    self._enter(label, rec)
                moves += 1
        if moves:
            self._used[label].moves += moves

    def _enter(self, label: str, rec) -> None:
        """The entry of the origin ``label``, made at its first move ``rec``."""
        if label not in self._used:
            self._used[label] = OriginUse(label, rec.line)

    def _add(self, rec, kind: str) -> bool:
        """Any record but a line continuing the last move: whether it is a move (counted for its origin)."""
        if kind == "aux":
            self._aux(rec)
            return False
        end_part = getattr(rec, "end_part", None)
        if kind == "dwell" or end_part is None:
            return False
        start, end = rec.start, rec.end
        feed = not rec.rapid
        box = self._boxes.get(self._tool)
        if box is None:
            box = self._boxes[self._tool] = ToolBox(self._tool)
        if box is not self._run:
            self._flush()
            self._run, self._last_end = box, None
            self._use_lists(feed)
            self._order = [(feed, 0, 0)]
        elif feed is not self._feed:
            self._use_lists(feed)
            self._order.append((feed, len(self._machine_points), len(self._part_points)))
            self._last_end = None   # its start was not a point of these lists
        machine, part = self._machine_points, self._part_points
        part_here = self._part_here
        if start is self._last_end:
            start_part = part_here   # the last move of the run ended there: both already in
        else:
            start_part = part_here if part_here is not None else \
                {a: start.get(a, 0.0) - (end.get(a, 0.0) - end_part[a]) for a in end_part}
            machine.append(start)
            part.append(start_part)
        machine.append(end)
        part.append(end_part)
        if kind == "arc":
            _arc_points_of(rec, start_part, end_part, machine, part)
        self._part_here, self._last_end = end_part, end
        self._line_kind = "linear" if feed else "rapid"
        if len(machine) >= RUN_POINTS:
            self._flush()
        return True

    def _use_lists(self, feed: bool) -> None:
        """The next points go to the feeds' lists (``feed``) or the rapids'."""
        self._feed = feed
        self._machine_points, self._part_points = self._feeds if feed else self._rapids

    def _aux(self, rec) -> None:
        """T, M06 and D: the tools used and their offsets."""
        tools = self._tools
        f, value = rec.function, int(rec.value)
        if f == "T":
            self._next_tool = value
            use = tools.setdefault(value, ToolUse(value))
            if rec.line not in use.lines:
                use.lines.append(rec.line)
        elif f == "M" and value == 6:   # the preselected tool goes to the spindle (seed 002 L4700)
            self._tool = self._next_tool
            tools.setdefault(self._tool, ToolUse(self._tool)).loaded = True
            self._line_kind = None   # the next move may go into other boxes
        elif f == "D":
            use = tools.setdefault(self._tool, ToolUse(self._tool))
            if value not in use.offsets:
                use.offsets.append(value)

    def _flush(self) -> None:
        """The run's points into its boxes (the lists emptied; the run goes on)."""
        box = self._run
        if box is None:
            return
        (rapid_machine, rapid_part), (feed_machine, feed_part) = self._rapids, self._feeds
        if rapid_machine or feed_machine:
            if not box.machine or not box.part:
                self._seed(box)
            rapids, feeds = _reduce(rapid_machine), _reduce(feed_machine)
            rapids_part = rapids if _same(rapid_machine, rapid_part) else _reduce(rapid_part)
            feeds_part = feeds if _same(feed_machine, feed_part) else _reduce(feed_part)
            if not (_widen(box.machine, box.feed_machine, rapids, feeds)
                    and _widen(box.part, box.feed_part, rapids_part, feeds_part)):
                self._pointwise(box)
            for points in (rapid_machine, rapid_part, feed_machine, feed_part):
                points.clear()
        self._order = [(self._feed, 0, 0)]

    def _seed(self, box: ToolBox) -> None:
        """An empty box of all moves widened by the run's first point alone, as point by point: its axes then
        stand in that point's order, and the reductions of the lists (:func:`_widen`) can do the rest (a point
        again changes nothing, should it go point by point after all)."""
        for frame, every in ((0, box.machine), (1, box.part)):
            if not every:
                first = next((points[0] for _feed, points in self._arrivals(frame) if points), None)
                if first is not None:
                    every.add(first)

    def _pointwise(self, box: ToolBox) -> None:
        """:meth:`_flush` point by point, in the order the points came (axes appearing later: their order
        in the boxes is that of their first point)."""
        for frame, every, feeds in ((0, box.machine, box.feed_machine), (1, box.part, box.feed_part)):
            for feed, points in self._arrivals(frame):
                for point in points:
                    every.add(point)
                    if feed:
                        feeds.add(point)

    def _arrivals(self, frame: int) -> Iterator[tuple[bool, list]]:
        """The run's points in the machine (``frame`` 0) or the part frame (1) in the order they came: each
        stretch of one list as ``(feed, points)``."""
        lists = {False: self._rapids[frame], True: self._feeds[frame]}
        ends = {feed: [entry[1 + frame] for entry in self._order if entry[0] is feed] + [len(lists[feed])]
                for feed in (False, True)}
        taken = {False: 0, True: 0}
        for feed, *begins in self._order:
            n = taken[feed] = taken[feed] + 1
            yield feed, lists[feed][begins[frame]:ends[feed][n]]

    def tools(self) -> list[ToolUse]:
        self._take()
        return list(self._tools.values())

    def origins(self) -> list[OriginUse]:
        self._take()
        return list(self._used.values())

    def cycles(self) -> list[dict[str, Any]]:
        """The canned cycles that ran: one entry per definition block, with its holes (interp/cycles)."""
        return self._interp.state.cycles.report() if self._interp is not None else []

    def boxes(self) -> list[ToolBox]:
        self._take()
        self._flush()
        return [self._boxes[t] for t in sorted(self._boxes)]


#: Points a list of :class:`MoveSummary` keeps before they are reduced into its boxes.
RUN_POINTS = 1024
#: Records :meth:`MoveSummary.add` keeps before it summarises them (in one warm loop, not one by one
#: between the interpreter's and the planner's work).
BATCH = 256

#: The record types whose ``rapid`` is ``kind == "rapid"``: a line of one of them that starts where
#: the last move ended, of the kind the current lists take, goes into them (unless M06 came between).
_LINES = frozenset({Line, CurveLine, IndependentMove})


def _arc_points_of(rec, start_part: dict, end_part: dict, machine: list, part: list) -> None:
    """An arc's quarter-turn points (:func:`arc_points`) added to ``machine`` and ``part``: none for an
    arc that stays inside one quadrant of its centre (:func:`_in_one_quadrant`); in part coordinates
    the same points when the arc is the same there (no origin shift: equal points)."""
    start, end, center = rec.start, rec.end, rec.center
    center_part = getattr(rec, "center_part", None) or {}
    same = (end_part is end or end_part == end) and (start_part is start or start_part == start) \
        and center_part == center   # (a dict is equal to itself: no need to compare it value by value)
    short = _in_one_quadrant(rec, start, end, center)
    if short and same:
        return
    sweep = rec.sweep
    points = [] if short else arc_points(start, end, center, rec.plane, sweep)
    machine += points
    if same:
        part += points   # the same arithmetic on equal values; _orientation is 1 on equal points
        return
    part += arc_points(start_part, end_part, center_part, rec.plane, sweep * _orientation(rec, start_part, end_part))


#: How far (relative) from a quadrant's edges an arc's ends and how far from a straight line its turn
#: must be for :func:`_in_one_quadrant` (the float error of the angles is some 1e-15 of them).
_CLEAR = 1e-9


def _in_one_quadrant(rec, start: dict, end: dict, center: dict) -> bool:
    """Whether the arc surely crosses no quarter turn, so that :func:`arc_points` gives no point
    (without its sweep): no full turn, both ends clearly inside one quadrant of the centre, the
    end clearly on the side its direction turns to (the short way, under 90 degrees), the ends
    apart (a full circle is programmed with the end at the start).  False when in doubt."""
    if rec.turns:
        return False
    plane = rec.plane
    a, o = plane[0], plane[1]
    ca, co = center.get(a), center.get(o)
    if ca is None or co is None:
        return False
    sa, so, ea, eo = start[a], start[o], end[a], end[o]
    ua, uo, va, vo = sa - ca, so - co, ea - ca, eo - co
    aua, auo, ava, avo = abs(ua), abs(uo), abs(va), abs(vo)
    size_u, size_v = aua + auo, ava + avo
    clear = _CLEAR * (size_u + size_v)
    if not (aua > clear and auo > clear and ava > clear and avo > clear):
        return False   # an end near an edge of its quadrant (or the centre), or a coordinate not finite
    if (ua > 0.0) != (va > 0.0) or (uo > 0.0) != (vo > 0.0):
        return False   # the ends in two quadrants
    if abs(ea - sa) <= 1e-6 and abs(eo - so) <= 1e-6:
        return False   # a full circle (the end at the start: within 1e-7, path/arcs.py sweep)
    cross = ua * vo - uo * va
    turn = _CLEAR * size_u * size_v
    return cross > turn if rec.direction == "ccw" else cross < -turn


def _widen(every: Box, feeds: Box, rapids: list | None, feed: list | None) -> bool:
    """Widen the box of all moves by the reductions of both lists (:func:`_reduce`) and that of the
    feeds by ``feed``'s: False, and nothing done, when that must go point by point: a reduction is
    None, or an axis is not yet in the box of all moves (its place there is that of its first point)."""
    if rapids is None or feed is None:
        return False
    lo, hi = every.lo, every.hi
    if any(axis not in lo for axis, _, _ in rapids) or any(axis not in lo for axis, _, _ in feed):
        return False
    for reduced in (rapids, feed):
        for axis, low, high in reduced:
            if low < lo[axis]:
                lo[axis] = low
            if high > hi[axis]:
                hi[axis] = high
    lo, hi = feeds.lo, feeds.hi
    for axis, low, high in feed:
        mine = lo.get(axis)
        if mine is None:   # the feeds' first: the axes in the order of their first point
            lo[axis], hi[axis] = low, high
            continue
        if low < mine:
            lo[axis] = low
        if high > hi[axis]:
            hi[axis] = high
    return True


def _same(machine: list, part: list) -> bool:
    """Whether every part point is its machine point (one dict: no origin shift), at C speed."""
    return len(machine) == len(part) and all(map(is_, machine, part))


def _reduce(points: list[dict[str, float]]) -> list[tuple[str, float, float]] | None:
    """Per axis of the points, in the order of the first one: ``(axis, min, max)``, the values point
    by point widening gives ([] for no point); None when the points do not all have the same axes,
    or a NaN leads an axis (min/max would keep it)."""
    if not points:
        return []
    first = points[0]
    if sum(map(len, points)) != len(first) * len(points):
        return None
    out = []
    try:
        for axis in first:
            values = list(map(itemgetter(axis), points))
            lo, hi = min(values), max(values)
            if lo != lo or hi != hi:
                return None
            out.append((axis, lo, hi))
    except KeyError:   # the same number of axes, not the same axes
        return None
    return out


def _add_to_both(a: Box, b: Box, point: dict[str, float]) -> None:
    """``a.add(point)`` and ``b.add(point)`` in one pass over the point (a feed's end widens the box
    of all moves and that of the feeds alike): the same comparisons, box by box."""
    a_lo, a_hi, b_lo, b_hi = a.lo, a.hi, b.lo, b.hi
    for axis, v in point.items():
        lo = a_lo.get(axis)
        if lo is None:
            a_lo[axis] = a_hi[axis] = v
        elif v < lo:
            a_lo[axis] = v
        elif v > a_hi[axis]:
            a_hi[axis] = v
        lo = b_lo.get(axis)
        if lo is None:
            b_lo[axis] = b_hi[axis] = v
        elif v < lo:
            b_lo[axis] = v
        elif v > b_hi[axis]:
            b_hi[axis] = v


def _merge_into_both(a: Box, b: Box, lo: dict[str, float], hi: dict[str, float]) -> None:
    """``a.merge(lo, hi)`` and ``b.merge(lo, hi)`` in one pass over the box of a feed (see
    :func:`_add_to_both`): the same comparisons, box by box."""
    a_lo, a_hi, b_lo, b_hi = a.lo, a.hi, b.lo, b.hi
    for axis, v in lo.items():
        w = hi[axis]
        mine = a_lo.get(axis)
        if mine is None:
            a_lo[axis], a_hi[axis] = v, w
        else:
            if v < mine:
                a_lo[axis] = v
            if w > a_hi[axis]:
                a_hi[axis] = w
        mine = b_lo.get(axis)
        if mine is None:
            b_lo[axis], b_hi[axis] = v, w
        else:
            if v < mine:
                b_lo[axis] = v
            if w > b_hi[axis]:
                b_hi[axis] = w


def extent(start: dict, end: dict, others) -> tuple[dict[str, float], dict[str, float]]:
    """The box (lo, hi per axis) of a move's points: its end points and ``others`` (an arc's
    quarter-turn points, :func:`arc_points`); an axis of one end point only counts there."""
    lo, hi = {}, {}
    for axis, v in start.items():
        w = end.get(axis, v)
        if v <= w:
            lo[axis], hi[axis] = v, w
        else:
            lo[axis], hi[axis] = w, v
    if end.keys() != start.keys():
        for axis, w in end.items():
            if axis not in lo:
                lo[axis] = hi[axis] = w
    for p in others:
        for axis, v in p.items():
            if axis not in lo:
                lo[axis] = hi[axis] = v
            elif v < lo[axis]:
                lo[axis] = v
            elif v > hi[axis]:
                hi[axis] = v
    return lo, hi


_QUARTER = math.pi / 2


def arc_points(start: dict, end: dict, center: dict, plane: tuple, sweep: float) -> list[dict]:
    """Points of an arc (helix) where its angle crosses a quarter turn: with the end
    points they give its exact bounding box.  ``sweep`` in degrees, signed (negative
    clockwise), full turns included; ``center`` holds the plane axes."""
    a, o = plane[0], plane[1]
    if a not in center or o not in center or sweep == 0.0:
        return []
    ca, co = center[a], center[o]
    th0 = math.atan2(start[o] - co, start[a] - ca)
    sw = math.radians(sweep)
    quarter = _QUARTER
    th1 = th0 + sw
    k0 = math.ceil((th1 if th1 < th0 else th0) / quarter)   # min(th0, th1), max(th0, th1)
    k1 = math.floor((th1 if th1 > th0 else th0) / quarter)
    if k1 < k0:
        return []   # no quarter turn crossed (most short arcs)
    r0 = math.hypot(start[a] - ca, start[o] - co)
    r1 = math.hypot(end[a] - ca, end[o] - co)
    out = []
    for k in range(k0, min(k1, k0 + 4000) + 1):
        th = k * quarter
        t = (th - th0) / sw
        r = r0 + (r1 - r0) * t
        p = {x: start[x] + (end[x] - start[x]) * t for x in end if x in start}
        p[a], p[o] = ca + r * math.cos(th), co + r * math.sin(th)
        out.append(p)
    return out


def _orientation(rec, start_part: dict, end_part: dict) -> float:
    """-1 when the part frame is a mirror image of the machine frame in the arc's plane
    (the arc turns the other way in part coordinates), else 1."""
    a, o = rec.plane[0], rec.plane[1]
    cm, cp = rec.center, getattr(rec, "center_part", None) or {}

    def cross(s, e, c) -> tuple[float, float]:
        u = (s[a] - c[a], s[o] - c[o])
        v = (e[a] - c[a], e[o] - c[o])
        return u[0] * v[1] - u[1] * v[0], (u[0] ** 2 + u[1] ** 2)

    try:
        xm, rm = cross(rec.start, rec.end, cm)
        xp, rp = cross(start_part, end_part, cp)
    except KeyError:
        return 1.0
    if abs(xm) > 1e-6 * rm and abs(xp) > 1e-6 * rp and (xm > 0) != (xp > 0):
        return -1.0
    return 1.0
