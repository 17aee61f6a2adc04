"""The per-record and per-segment layers of :func:`fagorcnc.simulate.dry_run` (simulate.py): the moves it
counts, the clock it keeps (the latest end of a segment: #MOVE's overlap the general ones) and PLN100,
which it asks of the envelope for curved pieces alone, must be what the records and segments of
:func:`fagorcnc.simulate` give when every one is looked at."""

from __future__ import annotations

import dataclasses
import itertools

import pytest

import fagorcnc
from fagorcnc.plan.envelope import Envelope
from fagorcnc.simulate import dry_run
from fagorcnc.summary import is_move

AXIS = {"max_acceleration": 500.0, "max_jerk": 1e9, "max_velocity": 10000.0, "min_limit": -1000.0,
        "max_limit": 1000.0}
MACHINE = {"axes": {a: dict(AXIS) for a in ("X", "Y", "Z", "U")}}

PROGRAMS = {
    # the independent U move outlasts the general X move: the clock is the latest end, not the last one
    "move": "G0 X0 Y0 U0\n#MOVE [U100, F1000]\nG1 X50 F600\nM30\n",
    # arcs bulging past X1000 and a G05 corner curve, dwells and auxiliary functions among the moves
    "bulge": "T1 M6\nG0 X990 Y-20\nM3 S1000\nG3 X990 Y20 I0 J20 F1000\nG4 K0.5\nG05\nG1 X995 Y30\nG1 X999 Y31\n"
             "G1 X990 Y40\nG2 X990 Y60 I0 J10\nG0 Z10\nM30\n",
    "plain": "G0 X0 Y0 Z5\nG1 Z0 F500\nG1 X10\nG2 X20 Y0 I5 J0\nG1 Y5\nG0 Z50\nM30\n",
}


@pytest.mark.parametrize("name", sorted(PROGRAMS))
def test_dry_run_counts_clocks_and_checks_as_every_record_and_segment_says(name):
    text = PROGRAMS[name]
    machine = fagorcnc.load_machine(MACHINE)
    seen, segments = [], []
    run = dry_run(text=text, machine=machine, on_record=lambda rec, interp: seen.append(rec),
                  on_segment=segments.append)
    result = fagorcnc.simulate(text=text, machine=machine)
    assert run.moves == sum(map(is_move, seen)) == sum(map(is_move, result.moves))
    assert run.cycle_time == max(s.t0 + s.duration for s in segments) == result.cycle_time
    envelope = Envelope(machine)
    for seg in segments:   # every segment, straight ones included, as Envelope.add takes them
        envelope.add(seg)
    pln100 = [d for d in run.diagnostics if d.code == "PLN100"]
    assert pln100 == envelope.diagnostics("<string>")
    assert [d for d in run.diagnostics if d.code != "PLN100"] == result.diagnostics   # simulate() has no PLN100
    if name == "move":
        ends = [s.t0 + s.duration for s in segments]   # a segment that ends before the one before it (the #MOVE's)
        assert any(later < earlier for earlier, later in itertools.pairwise(ends))
    if name == "bulge":
        assert pln100 and any(getattr(s.piece, "curved", False) for s in segments)


def _inside_reference(envelope: Envelope, piece) -> bool:
    """Envelope._inside as first written (max, min and all() of a generator)."""
    from fagorcnc.plan.blend import BlendPiece
    from fagorcnc.plan.envelope import ENVELOPE_TOLERANCE
    from fagorcnc.plan.geometry import ArcPiece

    limits, tol = envelope._limits, ENVELOPE_TOLERANCE
    if isinstance(piece, BlendPiece):   # a batch's curve (blend.BlendRow) too
        reach = piece.length * (1.0 + 1e-6) + tol
        return all(lo <= v - reach and v + reach <= hi for v, (lo, hi) in zip(piece.start.tolist(), limits,
                                                                               strict=True))
    if type(piece) is ArcPiece:
        radius = max(piece.r0, piece.r0 + piece.dr * piece.length) + tol
        (cx, cy), (alo, ahi), (olo, ohi) = piece.center, limits[piece.ia], limits[piece.io]
        if cx - radius < alo or cx + radius > ahi or cy - radius < olo or cy + radius > ohi:
            return False
        start, end = piece.start.tolist(), piece.end.tolist()
        return all(min(start[i], end[i]) >= lo - tol and max(start[i], end[i]) <= hi + tol
                   for i, (lo, hi) in enumerate(limits) if i not in (piece.ia, piece.io))
    return False


@pytest.mark.parametrize("limit", [1000.0, 1001.0, 999.5, 60.0, 12.0])
def test_the_envelope_cheap_test_is_the_reference_one(limit):
    # arcs (spirals, helices) and corner blends near and far from limits moved about: the same verdicts
    zigzag = "".join(f"G1 X{999.2 + 0.6 * (k % 2):.1f} Y{k * 0.5:.1f} Z{k % 3}\n" for k in range(30))
    program = (f"G90 G1 X990 Y0 Z0 F3000\nG05\n{zigzag}G1 X991 Y30\nG3 X999 Y30 I4 J0\nG1 X990 Y40\n"
               "G2 X980 Y40 Z5 I-5 J0\nG1 X10 Y10 Z0\nG3 X20 Y10 Z-3 I5 J0\nG2 X10 Y12 I-5 J1\nM30\n")
    default = fagorcnc.load_machine(None)
    result = fagorcnc.simulate(text=program, machine=default)
    assert result.ok, [str(d) for d in result.errors]
    pieces = [s.piece for s in result.segments() if getattr(s.piece, "curved", False)]
    axes = {a: dataclasses.replace(ax, max_limit=limit, min_limit=-limit) for a, ax in default.axes.items()}
    envelope = Envelope(dataclasses.replace(default, axes=axes))
    verdicts = [envelope._inside(p) for p in pieces]
    assert verdicts == [_inside_reference(envelope, p) for p in pieces]
    assert len(pieces) >= 20
    if limit == 999.5:
        assert any(verdicts) and not all(verdicts)


def test_the_envelope_cheap_test_is_the_reference_one_at_its_edges():
    # each axis's limit put at the very values the cheap test compares against (a circle's extreme
    # of the larger radius, a helix's end, a blend's start plus its length), and 1e-9 either side
    program = ("G90 G1 X10 Y10 Z0 F3000\nG05\nG1 X12 Y10.5 Z0.2\nG1 X14 Y10 Z0\nG3 X20 Y10 Z-3 I3 J0\n"
               "G2 X10 Y12 I-5 J1\nG2 X4.005 Y12 Z4 I-3 J0\nG3 X10 Y12 I2.995 J0\nM30\n")
    default = fagorcnc.load_machine(None)
    result = fagorcnc.simulate(text=program, machine=default)
    assert result.ok, [str(d) for d in result.errors]
    pieces = [s.piece for s in result.segments() if getattr(s.piece, "curved", False)]
    from fagorcnc.plan.envelope import ENVELOPE_TOLERANCE as TOL
    from fagorcnc.plan.geometry import ArcPiece

    names, checked, flips = default.axis_names, 0, 0
    for piece in pieces:
        start, end = piece.start.tolist(), piece.end.tolist()
        if type(piece) is ArcPiece:
            radii = (piece.r0, piece.r0 + piece.dr * piece.length)
            edges = {piece.ia: [piece.center[0] + s * r for s in (1, -1) for r in radii],
                     piece.io: [piece.center[1] + s * r for s in (1, -1) for r in radii]}
        else:
            edges = {}
        reach = piece.length * (1.0 + 1e-6)
        for i, axis in enumerate(names[:3]):
            values = edges.get(i, [start[i], end[i], start[i] + reach, start[i] - reach])
            verdicts = set()
            for value in values:
                for limit in (value + TOL - 1e-9, value + TOL, value + TOL + 1e-9, value - TOL - 1e-9, value - TOL,
                              value - TOL + 1e-9):
                    bound = {"max_limit": limit} if limit > start[i] else {"min_limit": limit}
                    ax = dataclasses.replace(default.axes[axis], **bound)
                    envelope = Envelope(dataclasses.replace(default, axes={**default.axes, axis: ax}))
                    verdict = envelope._inside(piece)
                    assert verdict == _inside_reference(envelope, piece), (piece, axis, limit)
                    verdicts.add(verdict)
                    checked += 1
            flips += len(verdicts) == 2
    assert checked > 300 and flips > 10   # the limits do sit on the edges: both verdicts there


def test_moves_counted_past_a_planning_error(monkeypatch):
    """After a planning error the rest of the program is still interpreted (for its diagnostics): its moves
    count too, as the records say (_Watched counts in a local, set when the stream ends)."""
    from fagorcnc.plan import Planner, PlanningError

    planned = Planner.segments

    def failing(self, records):
        for seg in planned(self, records):   # the first segment, then the error
            yield seg
            raise PlanningError("stopped here", 1)

    text = PROGRAMS["bulge"]
    seen = []
    monkeypatch.setattr(Planner, "segments", failing)
    run = dry_run(text=text, machine=fagorcnc.load_machine(MACHINE), on_record=lambda rec, interp: seen.append(rec))
    assert [d.code for d in run.diagnostics if d.is_error] == ["PLN001"]
    everything = fagorcnc.simulate(text=text, machine=fagorcnc.load_machine(MACHINE)).moves   # (unplanned: patched)
    assert run.moves == sum(map(is_move, seen)) == sum(map(is_move, everything)) == 7   # the rest's moves too
