"""The per-record and per-segment layers of :func:`fagorcnc.simulate.dry_run` (simulate.py): the moves it
counts, the clock it keeps (the latest end of a segment: #MOVE's overlap the general ones) and PLN100,
which it asks of the envelope for curved pieces alone, must be what the records and segments of
:func:`fagorcnc.simulate` give when every one is looked at."""

from __future__ import annotations

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
