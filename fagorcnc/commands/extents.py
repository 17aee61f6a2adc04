"""What ``fagorcnc check`` reports of the moves: tools, origins and the bounding box per tool.

:class:`MoveSummary` is fed every motion record as the dry run makes it; the boxes are widened
once per block from the block's own box (:func:`extent`), not point by point.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any


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
    (:meth:`add`; the absolute origin in force is read from its state at that moment)."""

    def __init__(self) -> None:
        self._tools: dict[int, ToolUse] = {}
        self._used: dict[str, OriginUse] = {}
        self._boxes: dict[int, ToolBox] = {}
        self._tool = self._next_tool = 0
        self._part_here: dict[str, float] | None = None
        self._interp = None
        # the last move's end point, the box it went into and whether it was a rapid: a line that
        # starts there (the same dict: consecutive records share it) widens the boxes by its end alone
        self._after: tuple = (None, None, None)

    def add(self, rec, interp) -> None:
        self._interp = interp
        tools = self._tools
        kind = rec.kind
        if kind == "aux":
            f, value = rec.function, int(rec.value)
            if f == "T":
                self._next_tool = value
                use = tools.setdefault(value, ToolUse(value))
                if rec.line not in use.lines:
                    use.lines.append(rec.line)
            elif f == "M" and value == 6:   # the preselected tool goes to the spindle (seed 002 L4700)
                self._tool = self._next_tool
                tools.setdefault(self._tool, ToolUse(self._tool)).loaded = True
            elif f == "D":
                use = tools.setdefault(self._tool, ToolUse(self._tool))
                if value not in use.offsets:
                    use.offsets.append(value)
            return
        end_part = getattr(rec, "end_part", None)
        if kind == "dwell" or end_part is None:
            return
        label = getattr(interp.state, "origin_source", "?")
        used = self._used
        if label not in used:
            used[label] = OriginUse(label, rec.line)
        used[label].moves += 1
        part_here = self._part_here
        start, end = rec.start, rec.end
        rapid = rec.rapid
        last_end, last_box, last_rapid = self._after
        if kind != "arc" and start is last_end and part_here is not None and rapid is last_rapid:
            box = self._boxes.get(self._tool)
            if box is last_box:
                # its start is already in these boxes (the last move ended there): the box of
                # start and end widens them exactly as its end alone does
                if rapid:
                    box.machine.add(end)
                    box.part.add(end_part)
                else:
                    _add_to_both(box.machine, box.feed_machine, end)
                    _add_to_both(box.part, box.feed_part, end_part)
                self._part_here = end_part
                self._after = (end, box, rapid)
                return
        start_part = part_here if part_here is not None else \
            {a: rec.start.get(a, 0.0) - (rec.end.get(a, 0.0) - end_part[a]) for a in end_part}
        if kind == "arc":
            sweep = rec.sweep
            machine_lo, machine_hi = extent(start, end, arc_points(start, end, rec.center, rec.plane, sweep))
            part_lo, part_hi = extent(start_part, end_part, arc_points(
                start_part, end_part, getattr(rec, "center_part", None) or {}, rec.plane,
                sweep * _orientation(rec, start_part, end_part)))
        else:
            machine_lo, machine_hi = extent(start, end, ())
            part_lo, part_hi = extent(start_part, end_part, ())
        box = self._boxes.get(self._tool)
        if box is None:
            box = self._boxes[self._tool] = ToolBox(self._tool)
        if rapid:
            box.machine.merge(machine_lo, machine_hi)
            box.part.merge(part_lo, part_hi)
        else:
            _merge_into_both(box.machine, box.feed_machine, machine_lo, machine_hi)
            _merge_into_both(box.part, box.feed_part, part_lo, part_hi)
        self._part_here = end_part
        self._after = (end, box, rapid)

    def tools(self) -> list[ToolUse]:
        return list(self._tools.values())

    def origins(self) -> list[OriginUse]:
        return list(self._used.values())

    def cycles(self) -> list[dict[str, Any]]:
        """The canned cycles that ran: one entry per definition block, with its holes (interp/cycles)."""
        return self._interp.state.cycles.report() if self._interp is not None else []

    def boxes(self) -> list[ToolBox]:
        return [self._boxes[t] for t in sorted(self._boxes)]


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


def arc_points(start: dict, end: dict, center: dict, plane: tuple, sweep: float) -> list[dict]:
    """Points of an arc (helix) where its angle crosses a quarter turn: with the end
    points they give its exact bounding box.  ``sweep`` in degrees, signed (negative
    clockwise), full turns included; ``center`` holds the plane axes."""
    a, o = plane[0], plane[1]
    if a not in center or o not in center or sweep == 0.0:
        return []
    ca, co = center[a], center[o]
    th0 = math.atan2(start[o] - co, start[a] - ca)
    r0 = math.hypot(start[a] - ca, start[o] - co)
    r1 = math.hypot(end[a] - ca, end[o] - co)
    sw = math.radians(sweep)
    quarter = math.pi / 2
    k0 = math.ceil(min(th0, th0 + sw) / quarter)
    k1 = math.floor(max(th0, th0 + sw) / quarter)
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
