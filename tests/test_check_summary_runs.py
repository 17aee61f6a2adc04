"""check's summary of the moves (commands/extents.py MoveSummary) widens its boxes by runs of points
reduced per axis, and lets a plain line that continues the last move through a short way: the
tools, origins and boxes (values and the order of the axes) must be those of a plain point-by-point
reference, whatever the stream: arcs and helices, rapids and feeds interleaved, T, M06 and D, the
origin changing between records, a move that does not start where the last one ended, axes that
appear later, part points that are or are not the machine points."""

from __future__ import annotations

import dataclasses
import math
import random
from types import SimpleNamespace

import pytest

from fagorcnc.commands import extents
from fagorcnc.commands.extents import Box, MoveSummary, ToolBox, ToolUse, _orientation, _reduce, arc_points
from fagorcnc.interp.records import Arc, Aux, CurveLine, Dwell, Line, Source


# ----------------------------------------------------------------------------- the reference
class Reference:
    """Every point of every move into the boxes one by one: start, end and an arc's quarter-turn points."""

    def __init__(self) -> None:
        self.tools: dict[int, ToolUse] = {}
        self.used: dict[str, list] = {}
        self.boxes: dict[int, ToolBox] = {}
        self.tool = self.next_tool = 0
        self.part_here = None

    def add(self, rec, interp) -> None:
        if rec.kind == "aux":
            value = int(rec.value)
            if rec.function == "T":
                self.next_tool = value
                use = self.tools.setdefault(value, ToolUse(value))
                if rec.line not in use.lines:
                    use.lines.append(rec.line)
            elif rec.function == "M" and value == 6:
                self.tool = self.next_tool
                self.tools.setdefault(self.tool, ToolUse(self.tool)).loaded = True
            elif rec.function == "D":
                use = self.tools.setdefault(self.tool, ToolUse(self.tool))
                if value not in use.offsets:
                    use.offsets.append(value)
            return
        end_part = getattr(rec, "end_part", None)
        if rec.kind == "dwell" or end_part is None:
            return
        label = interp.state.origin_source
        self.used.setdefault(label, [label, rec.line, 0])[2] += 1
        start, end = rec.start, rec.end
        start_part = self.part_here if self.part_here is not None else \
            {a: start.get(a, 0.0) - (end.get(a, 0.0) - end_part[a]) for a in end_part}
        machine, part = [start, end], [start_part, end_part]
        if rec.kind == "arc":
            machine += arc_points(start, end, rec.center, rec.plane, rec.sweep)
            part += arc_points(start_part, end_part, rec.center_part or {}, rec.plane,
                               rec.sweep * _orientation(rec, start_part, end_part))
        box = self.boxes.setdefault(self.tool, ToolBox(self.tool))
        for p in machine:
            box.machine.add(p)
            if not rec.rapid:
                box.feed_machine.add(p)
        for p in part:
            box.part.add(p)
            if not rec.rapid:
                box.feed_part.add(p)
        self.part_here = end_part


def _fed(summary, stream, between=None):
    """Feed ``stream`` ((record, origin label) pairs) to ``summary`` as dry_run does; ``between(i)``
    after record i (asking for the boxes midway)."""
    state = SimpleNamespace(origin_source="G53")
    interp = SimpleNamespace(state=state)
    for i, (rec, label) in enumerate(stream):
        state.origin_source = label
        summary.add(rec, interp)
        if between is not None:
            between(i)
    return summary


def _box(box: Box) -> tuple:
    return list(box.lo.items()), list(box.hi.items())   # values and the order of the axes


def _outcome(summary) -> tuple:
    if isinstance(summary, Reference):
        tools, origins, boxes = list(summary.tools.values()), list(summary.used.values()), \
            [summary.boxes[t] for t in sorted(summary.boxes)]
    else:
        tools, origins, boxes = summary.tools(), [[o.origin, o.first_line, o.moves] for o in summary.origins()], \
            summary.boxes()
    return ([(t.tool, t.loaded, t.offsets, t.lines) for t in tools], origins,
            [(b.tool, [_box(x) for x in (b.machine, b.part, b.feed_machine, b.feed_part)]) for b in boxes])


# ----------------------------------------------------------------------------- random streams
_ORIGINS = {"G53": {}, "G54": {"X": 100.0, "Y": -50.0, "Z": 20.0}, "G55": {"X": -3.5, "Z": 0.25},
            "G159=7": {"Y": 7.0, "A": 90.0}, "G92": {"X": 1.0, "Y": 1.0, "Z": 1.0, "A": 1.0}}
_PLANES = [("X", "Y", "Z"), ("Z", "X", "Y"), ("Y", "Z", "X")]


def _stream(seed: int, n: int = 250) -> list:
    """Random records as the interpreter makes them: the next move's start is the last end (the same
    dict) unless it jumps; part points shifted by the origin's offset (the machine dict itself when
    there is none, sometimes an equal copy), mirrored in X now and then; axis A appears midway."""
    rng = random.Random(seed)
    axes = ["X", "Y", "Z"]
    pos = {a: 0.0 for a in axes}
    label, mirror, line = "G53", False, 0

    def value() -> float:
        return rng.choice([round(rng.uniform(-60, 60) * 2) / 2, rng.uniform(-60, 60), 0.0])

    def part_of(point: dict) -> dict:
        off = _ORIGINS[label]
        if not off and not mirror:
            return point if rng.random() < 0.8 else dict(point)
        out = {a: v - off.get(a, 0.0) for a, v in point.items()}
        if mirror:
            out["X"] = -out["X"]
        return out

    out = []
    while len(out) < n:
        line += 1
        src = Source("p.nc", line, "")
        r = rng.random()
        if r < 0.04:
            out.append((Aux("aux", "T", float(rng.randint(1, 4)), "before", pos, src), label))
            continue
        if r < 0.08:
            out.append((Aux("aux", "M", 6.0, "before", pos, src), label))
            continue
        if r < 0.10:
            out.append((Aux("aux", "D", float(rng.randint(1, 3)), "before", pos, src), label))
            continue
        if r < 0.12:
            out.append((Dwell("dwell", 1.0, pos, src), label))
            continue
        if r < 0.15:
            label = rng.choice(list(_ORIGINS))   # the origin changes between two records
        if r < 0.17:
            mirror = not mirror
        if "A" not in axes and len(out) > n // 2 and rng.random() < 0.1:
            axes.append("A")   # an axis appearing later: the next move's end has it, its start not
        start = pos
        if rng.random() < 0.08:   # a move that does not start where the last one ended
            start = {a: (value() if rng.random() < 0.5 else v) for a, v in pos.items()}
        elif rng.random() < 0.05:
            start = dict(pos)   # where it ended, not the same dict
        rapid = rng.random() < 0.3
        feed = None if rapid else 1000.0
        if rng.random() < 0.35:
            a, o, _n = plane = rng.choice(_PLANES)
            radius = rng.choice([0.5, 5.0, rng.uniform(0.1, 40.0)])
            angle = rng.uniform(-math.pi, math.pi)
            center = {a: start.get(a, 0.0) - radius * math.cos(angle), o: start.get(o, 0.0) - radius * math.sin(angle)}
            turn = rng.uniform(-2 * math.pi, 2 * math.pi)
            r1 = radius * rng.choice([1.0, 1.0, 0.8, 1.3])   # a spiral now and then
            end = {x: start.get(x, 0.0) for x in axes}
            end[a], end[o] = center[a] + r1 * math.cos(angle + turn), center[o] + r1 * math.sin(angle + turn)
            if rng.random() < 0.3:
                end[_n] = end[_n] + rng.uniform(-5, 5)   # a helix
            end_part = part_of(end)
            off = _ORIGINS[label]
            center_part = {x: v - off.get(x, 0.0) for x, v in center.items()}
            if mirror and "X" in center_part:
                center_part["X"] = -center_part["X"]
            rec = Arc("arc", start, end, end_part, center, center_part, rng.choice(["cw", "ccw"]), plane, radius,
                      rng.choice([0, 0, 0, 1]), feed, "G94", src)
        else:
            end = {x: (value() if rng.random() < 0.6 else start.get(x, 0.0)) for x in axes}
            kind = "rapid" if rapid else "linear"
            cls = CurveLine if rng.random() < 0.1 else Line
            rec = cls(kind, start, end, part_of(end), feed, "G94", src)
        out.append((rec, label))
        pos = rec.end
    return out


@pytest.mark.parametrize("seed", range(60))
def test_random_streams_give_the_reference_summary(seed):
    stream = _stream(seed)
    assert _outcome(_fed(MoveSummary(), stream)) == _outcome(_fed(Reference(), stream))


@pytest.mark.parametrize(("points", "batch"), [(1, 1), (2, 3), (3, 64), (7, 2), (1024, 5)])
@pytest.mark.parametrize("seed", range(12))
def test_short_lists_batches_and_boxes_asked_midway_change_nothing(monkeypatch, seed, points, batch):
    # the lists reduced every few points (bounded memory), the records summarised every few (the
    # origin changing inside a batch or between two), and the boxes asked for now and then
    stream = _stream(100 + seed)
    expected = _outcome(_fed(Reference(), stream))
    monkeypatch.setattr(extents, "RUN_POINTS", points)
    monkeypatch.setattr(extents, "BATCH", batch)
    summary = MoveSummary()
    assert _outcome(_fed(summary, stream, lambda i: i % 17 == 5 and summary.boxes())) == expected


@pytest.mark.parametrize("seed", range(12))
def test_the_short_way_gives_what_the_general_one_gives(monkeypatch, seed):
    # every record through the general path (no record type takes the short way): the same summary
    stream = _stream(200 + seed)
    fast = _outcome(_fed(MoveSummary(), stream))
    monkeypatch.setattr(extents, "_LINES", frozenset())
    assert _outcome(_fed(MoveSummary(), stream)) == fast == _outcome(_fed(Reference(), stream))


# ----------------------------------------------------------------------------- the short way
def _line(kind: str, start: dict, end: dict, line: int, end_part=None, cls=Line):
    return cls(kind, start, end, end if end_part is None else end_part, None if kind == "rapid" else 500.0, "G94",
               Source("p.nc", line, ""))


def _chain(*kinds_and_ends) -> list:
    """Lines, each starting at the last one's end (the same dict)."""
    pos, out = {"X": 0.0, "Y": 0.0, "Z": 0.0}, []
    for i, (kind, end) in enumerate(kinds_and_ends, start=1):
        out.append((_line(kind, pos, end, i), "G54"))
        pos = end
    return out


def test_continuing_lines_take_the_short_way(monkeypatch):
    # only the first line of each kind switch and the line after M06 go the general way
    calls = []
    general = MoveSummary._add
    monkeypatch.setattr(MoveSummary, "_add", lambda self, rec, kind: calls.append(rec.line) or general(self, rec, kind))
    stream = _chain(("rapid", {"X": 0.0, "Y": 0.0, "Z": 10.0}), ("linear", {"X": 5.0, "Y": 0.0, "Z": 10.0}),
                    ("linear", {"X": 5.0, "Y": 5.0, "Z": 10.0}), ("linear", {"X": 5.0, "Y": 5.0, "Z": 2.0}),
                    ("rapid", {"X": 5.0, "Y": 5.0, "Z": 30.0}), ("rapid", {"X": -1.0, "Y": 5.0, "Z": 30.0}))
    summary = _fed(MoveSummary(), stream)
    assert _outcome(summary) == _outcome(_fed(Reference(), stream))
    assert calls == [1, 2, 5]
    box = summary.boxes()[0]
    assert box.feed_machine.lo == {"X": 0.0, "Y": 0.0, "Z": 2.0}   # the first feed's start (the rapid's end) is in
    assert box.machine.hi["Z"] == 30.0 and box.feed_machine.hi["Z"] == 10.0


def test_continuing_arcs_at_feed_take_the_short_way(monkeypatch):
    # an arc at feed that starts at the last end of the feeds' run skips _add too; an arc at rapid (no feed)
    # and the arc at feed after it do not (its start is not in the feeds' lists)
    calls = []
    general = MoveSummary._add
    monkeypatch.setattr(MoveSummary, "_add", lambda self, rec, kind: calls.append(rec.line) or general(self, rec, kind))
    stream = _chain(("rapid", {"X": 0.0, "Y": 0.0, "Z": 10.0}), ("linear", {"X": 10.0, "Y": 0.0, "Z": 10.0}))
    plane, src = ("X", "Y", "Z"), Source("p.nc", 0, "")
    pos = stream[-1][0].end
    for line, (end, center, direction, feed) in enumerate([
            ({"X": 0.0, "Y": 10.0, "Z": 10.0}, {"X": 0.0, "Y": 0.0}, "ccw", 800.0),   # a quarter turn: no point
            ({"X": 0.0, "Y": -10.0, "Z": 8.0}, {"X": 0.0, "Y": 0.0}, "ccw", 800.0),   # a half helix over -X
            ({"X": 5.0, "Y": -5.0, "Z": 8.0}, {"X": 5.0, "Y": -10.0}, "ccw", None),
            ({"X": 5.0, "Y": -15.0, "Z": 8.0}, {"X": 5.0, "Y": -10.0}, "cw", 800.0)], start=3):
        arc = Arc("arc", pos, end, end, center, dict(center), direction, plane, math.dist(
            (end["X"], end["Y"]), (center["X"], center["Y"])), 0, feed, "G94", dataclasses.replace(src, line=line))
        stream.append((arc, "G54"))
        pos = end
    summary = _fed(MoveSummary(), stream)
    assert _outcome(summary) == _outcome(_fed(Reference(), stream))
    assert calls == [1, 2, 5, 6]
    box = summary.boxes()[0]
    assert box.feed_machine.lo["X"] == pytest.approx(-10.0) and box.feed_machine.hi["X"] == pytest.approx(10.0)
    assert box.machine.hi["X"] == pytest.approx(10.0) and box.feed_machine.lo["Y"] == pytest.approx(-15.0)


def test_the_short_way_steps_aside_after_m06():
    # the line after M06 starts at the last end (the same dict), but that point belongs to tool 1's
    # boxes only: tool 2's must get it too
    stream = _chain(("linear", {"X": 4.0, "Y": 0.0, "Z": 0.0}), ("linear", {"X": 4.0, "Y": 3.0, "Z": 0.0}))
    stream.insert(1, (Aux("aux", "T", 2.0, "before", stream[0][0].end, Source("p.nc", 9, "")), "G54"))
    stream.insert(2, (Aux("aux", "M", 6.0, "before", stream[0][0].end, Source("p.nc", 9, "")), "G54"))
    summary = _fed(MoveSummary(), stream)
    assert _outcome(summary) == _outcome(_fed(Reference(), stream))
    tool2 = {b.tool: b for b in summary.boxes()}[2]
    assert tool2.feed_machine.lo == {"X": 4.0, "Y": 0.0, "Z": 0.0}


def test_the_short_way_steps_aside_for_a_record_whose_rapid_is_not_its_kind():
    # a record type of its own whose "linear" kind runs at rapid: not one of the plain lines, so it
    # goes the general way and into the rapids' boxes alone
    @dataclasses.dataclass(frozen=True)
    class Odd:
        kind: str
        start: dict
        end: dict
        end_part: dict
        src: Source
        rapid: bool = True

        @property
        def line(self) -> int:
            return self.src.line

    first = _chain(("linear", {"X": 1.0, "Y": 0.0, "Z": 0.0}))
    end = first[0][0].end
    stream = [*first, (Odd("linear", end, {"X": 9.0, "Y": 0.0, "Z": 0.0}, {"X": 9.0, "Y": 0.0, "Z": 0.0},
                           Source("p.nc", 2, "")), "G54")]
    summary = _fed(MoveSummary(), stream)
    assert _outcome(summary) == _outcome(_fed(Reference(), stream))
    box = summary.boxes()[0]
    assert box.machine.hi["X"] == 9.0 and box.feed_machine.hi["X"] == 1.0


def test_the_short_way_steps_aside_for_a_line_that_does_not_start_at_the_last_end():
    # equal values in another dict are not taken for the last end; a jump's start counts
    a = _chain(("linear", {"X": 1.0, "Y": 1.0, "Z": 0.0}))
    jump = _line("linear", {"X": -7.0, "Y": 1.0, "Z": 0.0}, {"X": 2.0, "Y": 2.0, "Z": 0.0}, 2)
    copy = _line("linear", dict(jump.end), {"X": 3.0, "Y": 2.0, "Z": 0.0}, 3)
    stream = [*a, (jump, "G54"), (copy, "G54")]
    summary = _fed(MoveSummary(), stream)
    assert _outcome(summary) == _outcome(_fed(Reference(), stream))
    assert summary.boxes()[0].feed_machine.lo["X"] == -7.0


def test_a_line_without_part_point_is_not_counted():
    # end_part None: not a move of the summary (neither its origin nor its boxes), short way or not
    stream = _chain(("linear", {"X": 1.0, "Y": 0.0, "Z": 0.0}))
    end = stream[0][0].end
    stream.append((dataclasses.replace(_line("linear", end, {"X": 50.0, "Y": 0.0, "Z": 0.0}, 2), end_part=None), "G55"))
    summary = _fed(MoveSummary(), stream)
    assert [o.origin for o in summary.origins()] == ["G54"]
    assert summary.boxes()[0].machine.hi["X"] == 1.0


@pytest.mark.parametrize("batch", [1, 2, 256])
def test_the_origin_is_read_at_each_record(monkeypatch, batch):
    # the origin changes between two continuing lines: the second counts for the new one, from its
    # line; an auxiliary function under a third origin counts for none; labels made again (equal
    # strings, other objects) are the same origin
    monkeypatch.setattr(extents, "BATCH", batch)
    stream = _chain(("linear", {"X": 1.0, "Y": 0.0, "Z": 0.0}), ("linear", {"X": 2.0, "Y": 0.0, "Z": 0.0}),
                    ("linear", {"X": 3.0, "Y": 0.0, "Z": 0.0}), ("linear", {"X": 4.0, "Y": 0.0, "Z": 0.0}))
    aux = Aux("aux", "M", 3.0, "before", stream[2][0].end, Source("p.nc", 7, ""))
    again = "".join(["G", "55"])
    stream = [stream[0], (stream[1][0], "G55"), (aux, "G56"), (stream[2][0], "G54"), (stream[3][0], again)]
    summary = _fed(MoveSummary(), stream)
    assert [(o.origin, o.first_line, o.moves) for o in summary.origins()] == [("G54", 1, 2), ("G55", 2, 2)]


# ----------------------------------------------------------------------------- the reduction
def test_axes_appearing_later_keep_the_order_of_their_first_point():
    # tool 0: X Y, then a point with A, then one with Z: the box lists X Y A Z as Box.add does, in
    # the box of all moves (rapids and feeds interleaved) and in the feeds' box
    pos = {"X": 0.0, "Y": 0.0}
    ends = [("rapid", {"X": 1.0, "Y": 2.0}), ("linear", {"X": 1.0, "Y": 3.0, "A": 5.0}),
            ("rapid", {"X": 2.0, "Y": 3.0, "A": 5.0, "Z": -1.0}), ("linear", {"Z": 4.0, "X": 0.5, "Y": 1.0, "A": 6.0})]
    stream = []
    for i, (kind, end) in enumerate(ends, start=1):
        stream.append((_line(kind, pos, end, i), "G54"))
        pos = end
    summary = _fed(MoveSummary(), stream)
    assert _outcome(summary) == _outcome(_fed(Reference(), stream))
    box = summary.boxes()[0]
    assert list(box.machine.lo) == ["X", "Y", "A", "Z"]
    assert list(box.feed_machine.lo) == ["X", "Y", "A", "Z"]


def test_an_empty_box_takes_the_first_point_then_the_reductions(monkeypatch):
    # a tool's first points: its empty box of all moves takes the first point that came (a feed's start, its
    # axes in the order Z X Y), the rest by the lists' reductions (the rapids' points in the order X Y Z), not
    # point by point; the same boxes, the axes in the same order, as the reference
    def pointwise(self, box):
        raise AssertionError("point by point")

    monkeypatch.setattr(MoveSummary, "_pointwise", pointwise)
    zxy = {"Z": 1.0, "X": 0.0, "Y": 0.0}
    stream = [(_line("linear", zxy, {"Z": 0.5, "X": 4.0, "Y": -2.0}, 1), "G54")]
    stream += _chain(("rapid", {"X": -3.0, "Y": 1.0, "Z": 9.0}), ("linear", {"X": 6.0, "Y": 1.0, "Z": 2.0}))
    summary = _fed(MoveSummary(), stream)
    assert _outcome(summary) == _outcome(_fed(Reference(), stream))
    box = summary.boxes()[0]
    assert list(box.machine.lo) == list(box.part.lo) == ["Z", "X", "Y"]
    assert box.machine.lo == {"Z": 0.0, "X": -3.0, "Y": -2.0} and box.machine.hi == {"Z": 9.0, "X": 6.0, "Y": 1.0}


def test_reduce_steps_aside_for_mixed_axes_and_a_leading_nan():
    assert _reduce([{"X": 1.0, "Y": 2.0}, {"X": -1.0, "Y": 5.0}]) == [("X", -1.0, 1.0), ("Y", 2.0, 5.0)]
    assert _reduce([{"Y": 2.0, "X": 1.0}, {"X": -1.0, "Y": 5.0}]) == [("Y", 2.0, 5.0), ("X", -1.0, 1.0)]
    assert _reduce([]) == []
    assert _reduce([{"X": 1.0}, {"X": 2.0, "Y": 0.0}]) is None   # an axis more
    assert _reduce([{"X": 1.0, "Y": 0.0}, {"X": 2.0, "Z": 0.0}]) is None   # as many axes, not the same
    assert _reduce([{"X": math.nan}, {"X": 2.0}]) is None   # min() would keep the NaN, Box.add the 2
    assert _reduce([{"X": 2.0}, {"X": math.nan}, {"X": 1.0}]) == [("X", 1.0, 2.0)]   # as Box.add


def test_a_nan_point_widens_as_box_add_does():
    pos = {"X": 0.0}
    stream = []
    for i, x in enumerate([math.nan, 2.0, -1.0], start=1):
        end = {"X": x}
        stream.append((_line("linear", pos, end, i), "G54"))
        pos = end
    new, ref = _fed(MoveSummary(), stream).boxes()[0], _fed(Reference(), stream).boxes[0]
    assert (new.machine.lo, new.machine.hi) == (ref.machine.lo, ref.machine.hi) == ({"X": -1.0}, {"X": 2.0})


def test_arcs_in_the_part_frame_when_it_is_not_the_machine_frame():
    # an arc through the +Y quarter point: with no offset the part points are the machine points
    # (the same dict), with G54 shifted, and mirrored (turning the other way in the part frame)
    src = Source("p.nc", 1, "")
    start = {"X": 0.0, "Y": 0.0, "Z": 0.0}
    for end_part, center_part in [(None, None), ({"X": -100.0, "Y": 50.0, "Z": -20.0}, {"X": -95.0, "Y": 50.0}),
                                  ({"X": -10.0, "Y": 0.0, "Z": 0.0}, {"X": -5.0, "Y": 0.0})]:
        end = {"X": 10.0, "Y": 0.0, "Z": 0.0}
        center = {"X": 5.0, "Y": 0.0}
        arc = Arc("arc", start, end, end if end_part is None else end_part, center,
                  center if center_part is None else center_part, "cw", ("X", "Y", "Z"), 5.0, 0, 800.0, "G94", src)
        lead = _line("rapid", {"X": 0.0, "Y": 0.0, "Z": 0.0}, start, 0,
                     None if end_part is None else {"X": -100.0 if end_part["X"] < -50 else 0.0,
                                                    "Y": 50.0 if end_part["X"] < -50 else 0.0,
                                                    "Z": -20.0 if end_part["X"] < -50 else 0.0})
        stream = [(lead, "G54"), (arc, "G54")]
        summary = _fed(MoveSummary(), stream)
        assert _outcome(summary) == _outcome(_fed(Reference(), stream))
        assert summary.boxes()[0].machine.hi["Y"] == pytest.approx(5.0)


def test_part_points_told_from_machine_points_by_more_than_their_first_ones():
    # every point shared (the same dicts: start, end) but the part centre elsewhere: the machine arc
    # (about X5 Y0, from 100 to 80 degrees) crosses the +Y quarter turn, a point more (Y5), the part
    # arc (about X30 Y0, from 169 to 149 degrees) none: the part box is not the machine box
    src = Source("p.nc", 3, "")
    rad = math.radians
    start = {"X": 5 + 5 * math.cos(rad(100)), "Y": 5 * math.sin(rad(100)), "Z": 0.0}
    end = {"X": 5 + 5 * math.cos(rad(80)), "Y": 5 * math.sin(rad(80)), "Z": 0.0}
    first = {"X": 0.0, "Y": -1.0, "Z": 0.0}
    stream = [(_line("rapid", {"X": 0.0, "Y": 0.0, "Z": 0.0}, first, 1), "G54"),
              (_line("linear", first, start, 2), "G54"),
              (Arc("arc", start, end, end, {"X": 5.0, "Y": 0.0}, {"X": 30.0, "Y": 0.0}, "cw", ("X", "Y", "Z"), 5.0, 0,
                   800.0, "G94", src), "G54")]
    summary = MoveSummary()
    _fed(summary, stream, lambda i: i < 2 and summary.boxes())   # the axes in the boxes: reduced, not point by point
    assert _outcome(summary) == _outcome(_fed(Reference(), stream))
    box = summary.boxes()[0]
    assert box.feed_machine.hi["Y"] == pytest.approx(5.0) and box.feed_part.hi["Y"] == start["Y"]


def test_memory_stays_bounded():
    # a long stream of continuing lines and arcs: never more than BATCH records kept, nor more than
    # RUN_POINTS points in a list (plus the few points of the record that filled it)
    stream = _stream(7, n=3000)
    summary = MoveSummary()
    sizes = []
    _fed(summary, stream, lambda i: sizes.append((len(summary._pending), *map(len, summary._rapids),
                                                  *map(len, summary._feeds))))
    assert max(s[0] for s in sizes) < extents.BATCH
    assert max(max(s[1:]) for s in sizes) < extents.RUN_POINTS + 10
    assert _outcome(summary) == _outcome(_fed(Reference(), stream))


# ----------------------------------------------------------------------------- arcs inside one quadrant
def _arc(start_angle: float, sweep: float, radius: float = 10.0, center=(3.0, -2.0), r1=None, turns: int = 0,
         plane=("X", "Y", "Z")) -> Arc:
    a, o, n = plane
    ca, co = center
    r1 = radius if r1 is None else r1
    start = {a: ca + radius * math.cos(start_angle), o: co + radius * math.sin(start_angle), n: 1.0}
    end = {a: ca + r1 * math.cos(start_angle + sweep), o: co + r1 * math.sin(start_angle + sweep), n: 1.0}
    return Arc("arc", start, end, end, {a: ca, o: co}, {a: ca, o: co}, "ccw" if sweep > 0 else "cw", plane, radius,
               turns, 100.0, "G94", Source("p.nc", 1, ""))


def _no_point(arc: Arc) -> bool:
    return arc_points(arc.start, arc.end, arc.center, arc.plane, arc.sweep) == []


def test_an_arc_inside_one_quadrant_has_no_quarter_turn_point():
    # random arcs, many of them close to a quadrant's edge, tiny, huge, spirals or nearly full turns:
    # whenever the cheap test says "inside one quadrant", arc_points (with the sweep) gives no point
    rng = random.Random(5)
    said = 0
    for _ in range(20000):
        edge = rng.randint(-4, 4) * math.pi / 2
        start = edge + rng.choice([rng.uniform(-1.6, 1.6), rng.uniform(-1e-6, 1e-6), rng.uniform(-1e-12, 1e-12)])
        full = math.copysign(2 * math.pi - rng.uniform(0, 1e-6), rng.random() - 0.5)
        sweep = rng.choice([rng.uniform(-1.6, 1.6), rng.uniform(-1e-6, 1e-6), edge - start + rng.uniform(-1e-9, 1e-9),
                            rng.uniform(-6.3, 6.3), full])
        if sweep == 0.0:
            continue
        radius = rng.choice([1e-4, 0.5, 10.0, 1e5])
        center = (rng.choice([0.0, 1e6, -3.25]), rng.choice([0.0, -1e6, 7.5]))
        arc = _arc(start, sweep, radius, center, r1=radius * rng.choice([1.0, 1.0, 0.5, 1.5]))
        if extents._in_one_quadrant(arc, arc.start, arc.end, arc.center):
            said += 1
            assert _no_point(arc), (start, sweep, radius, center)
    assert said > 2000   # the cheap test does pass short arcs


@pytest.mark.parametrize(("arc", "why"), [
    (_arc(0.3, 0.5, turns=1), "an extra full turn"),
    (_arc(0.0, 0.5), "the start on the X axis"),
    (_arc(0.3, math.pi / 2 - 0.3), "the end on the Y axis"),
    (_arc(0.3, 1.5), "the ends in two quadrants"),
    (_arc(0.3, 0.2 - 2 * math.pi), "the long way round"),
    (_arc(0.3, 1e-12), "the end at the start: a full circle"),
    (_arc(0.3, 1e-13, r1=20.0), "a straight radial move: a full circle"),
    (_arc(0.3, 0.5, plane=("Z", "X", "Y")), "in G18"),
])
def test_the_quadrant_test_steps_aside(arc, why):
    if why == "in G18":   # the plane's own axes: inside one quadrant there too
        assert extents._in_one_quadrant(arc, arc.start, arc.end, arc.center) and _no_point(arc)
        return
    assert not extents._in_one_quadrant(arc, arc.start, arc.end, arc.center), why
    if why in ("the start on the X axis", "the ends in two quadrants", "the long way round", "an extra full turn"):
        assert not _no_point(arc)   # those do cross a quarter turn
