"""The pieces of a run of records made together (Planner._pieces, geometry.line_pieces) are exactly the
pieces made one by one: LinePiece(start, end) and ArcPiece of each record's end points in machine axis
order, a block that starts where the one before ended starting at that one's end vector."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

import fagorcnc
from fagorcnc.plan import Planner
from fagorcnc.plan.geometry import ArcPiece, LinePiece, line_pieces
from fagorcnc.plan.junctions import MIN_LENGTH
from fagorcnc.simulate import Run


def same_line(a: LinePiece, b: LinePiece) -> None:
    """Every number of the two lines identical (signs of zeros too)."""
    assert repr((a.start.tolist(), a.end.tolist(), a.length, a.ul)) == \
        repr((b.start.tolist(), b.end.tolist(), b.length, b.ul))
    assert repr(a.u.tolist()) == repr(b.u.tolist())
    assert a.d2.tolist() == b.d2.tolist() == a.d3.tolist() == [0.0] * len(a.ul)


def test_lines_made_together_are_the_lines_made_one_by_one():
    rng = np.random.default_rng(7)
    starts = rng.uniform(-50.0, 50.0, (200, 3))
    ends = starts + rng.uniform(-2.0, 2.0, (200, 3)) * rng.integers(0, 2, (200, 3))   # some axes still
    ends[5] = starts[5]                     # no move
    ends[6] = starts[6] + [1e-10, 0.0, 0.0]   # shorter than MIN_LENGTH
    ends[7] = starts[7] + [-0.0, 3.0, -0.0]
    start_points, end_points = list(starts.copy()), list(ends.copy())
    made = line_pieces(start_points, end_points, starts, ends, MIN_LENGTH)
    assert made[5] is None and made[6] is None
    for a, b, piece in zip(start_points, end_points, made, strict=True):
        line = LinePiece(a, b)
        if not line.length > MIN_LENGTH:
            assert piece is None
            continue
        same_line(piece, line)
        assert piece.start is a and piece.end is b
        assert piece.sub(0.25 * piece.length, piece.length).start.tolist() == \
            line.sub(0.25 * line.length, line.length).start.tolist()


def _line(start: dict, end: dict) -> SimpleNamespace:
    return SimpleNamespace(kind="linear", start=start, end=end)


def _arc(start: dict, end: dict, centre: tuple[float, float], sweep: float) -> SimpleNamespace:
    return SimpleNamespace(kind="arc", start=start, end=end, plane=("X", "Y", "Z"),
                           center={"X": centre[0], "Y": centre[1]}, sweep=sweep)


def _one_by_one(planner: Planner, rec) -> LinePiece | ArcPiece:
    start, end = planner._vector(rec.start), planner._vector(rec.end)
    if rec.kind == "arc":
        return ArcPiece(start, end, 0, 1, (rec.center["X"], rec.center["Y"]), math.radians(rec.sweep))
    return LinePiece(start, end)


@pytest.mark.parametrize("every_axis", [True, False])
def test_the_pieces_of_a_run_are_those_of_its_records_one_by_one(every_axis):
    """Lines and arcs mixed, a block that does not start where the one before ended (its own start), a
    move too short to plan, and (``every_axis`` false) end points that leave out an axis (at 0)."""
    planner = Planner(fagorcnc.load_machine(None))
    z = {"Z": 0.5} if every_axis else {}
    p = [{"X": 0.0, "Y": 0.0, **z}, {"X": 3.0, "Y": 4.0, **z}, {"X": 3.0, "Y": 4.0, "Z": 1.5},
         {"X": 0.0, "Y": 5.0, "Z": 1.5}, {"X": 0.0, "Y": 5.0, "Z": 1.5 + 1e-12}]
    records = [_line(p[0], p[1]), _line(p[1], p[2]), _arc(dict(p[2]), p[3], (0.0, 0.0), 36.87),
               _line(p[3], p[4]), _line(p[4], {"X": 1.0, "Y": 1.0, **z}),
               _line({"X": 9.0, "Y": 9.0, "Z": 9.0}, {"X": 8.0, "Y": 9.0, "Z": 9.0}),
               _arc(p[2], p[3], (0.0, 0.0), 36.87), _line({"X": 0.0, "Y": 5.0, "Z": 1.5}, p[0])]
    pieces = planner._pieces(records[:3]) + planner._pieces(records[3:])   # two runs: the second goes on
    assert pieces[3] is None   # 1e-12 mm: nothing moves
    for i, (rec, piece) in enumerate(zip(records, pieces, strict=True)):
        if piece is None:
            continue
        one = _one_by_one(planner, rec)
        assert type(piece) is type(one)
        if isinstance(one, LinePiece):
            same_line(piece, one)
        else:
            assert (piece.start.tolist(), piece.end.tolist(), piece.length, piece.theta0, piece.w, piece.dr) == \
                (one.start.tolist(), one.end.tolist(), one.length, one.theta0, one.w, one.dr)
        before = records[i - 1] if i else None
        chained = before is not None and (rec.start is before.end or rec.start == before.end)
        if chained and pieces[i - 1] is not None:
            assert piece.start is pieces[i - 1].end   # the vector of the end before, not a new one
    assert pieces[5].start.tolist() == [9.0, 9.0, 9.0]   # its own start


def test_a_list_of_records_plans_as_the_same_records_streamed():
    """The planner reads a list in runs as it takes a stream (runs of READ_AHEAD across a run's end)."""
    from fagorcnc.plan import planner as planner_module

    machine = fagorcnc.load_machine(None)
    text = ["G01 F3000"] + [f"X{(i % 7) * 0.8:.3f} Y{i * 0.3:.3f} Z{(i % 3) * 0.1:.3f}" for i in range(60)] + \
        ["G02 X0 Y30 I-9 J0", "G04 K0.1", "G00 X5 Y5", "M30"]
    records = list(Run(iter(text), "<runs>", machine))

    def plan(source) -> list[tuple]:
        return [(s.kind, s.line, s.t0, s.duration, s.v0, s.v1) for s in Planner(machine).timed(source)]

    whole = plan(iter(records))
    saved = planner_module.READ_AHEAD
    try:
        planner_module.READ_AHEAD = 16
        assert plan(records) == plan(iter(records)) == whole
    finally:
        planner_module.READ_AHEAD = saved
