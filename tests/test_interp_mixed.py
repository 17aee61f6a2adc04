"""A program mixing subroutines, loops, parameters, G159 origins and polar
coordinates, against a hand calculation; and the streaming run against simulate()."""

from __future__ import annotations

import math

import pytest

import fagorcnc

MIXED = """%L SIDE
; one polar step of P0 degrees about the polar origin (seed 002 L6610: G91 Q adds to the angle)
G91 G01 Q[P0] F500
G90
#RET
%MIXED
G71 G90 G17
V.A.ORGT[7].X = 100
V.A.ORGT[7].Y = 50
G159=7
G30 I10 J0
G00 X30 Y0
P100 = 0
$FOR P1 = 1, 3, 1
#PCALL SIDE A30
P100 = P100 + 1
$ENDFOR
G91 G00 X5 Y[P100*2]
G90
M30
"""


def test_mixed_program_matches_the_hand_calculation():
    r = fagorcnc.simulate(MIXED)
    assert r.ok, [str(d) for d in r.diagnostics]
    motion = [m for m in r.moves if m.kind in ("rapid", "linear")]
    # G159=7 loads ORGT[7] = (100, 50) (seed 002 L3470); G30 I10 J0: polar origin part (10, 0) (L3958)
    # G00 X30 Y0 -> part (30, 0), machine (130, 50); polar radius 20, angle 0
    # three #PCALL SIDE A30: P0 = 30 in the new level (L10487), G91 Q30 adds 30 degrees each time:
    #   angle 30: (10 + 20 cos 30, 20 sin 30) = (27.320508, 10)
    #   angle 60: (10 + 10, 17.320508) = (20, 17.320508)
    #   angle 90: (10, 20)            -> machine (110, 70)
    # P100 counts 3 calls; G91 G00 X5 Y[3*2] -> part (15, 26), machine (115, 76)
    expected_part = [(30.0, 0.0), (10 + 20 * math.cos(math.radians(30)), 10.0),
                     (20.0, 20 * math.sin(math.radians(60))), (10.0, 20.0), (15.0, 26.0)]
    assert [(m.end_part["X"], m.end_part["Y"]) for m in motion] == [
        (pytest.approx(x, abs=1e-9), pytest.approx(y, abs=1e-9)) for x, y in expected_part]
    assert [(m.end["X"], m.end["Y"]) for m in motion] == [
        (pytest.approx(x + 100, abs=1e-9), pytest.approx(y + 50, abs=1e-9)) for x, y in expected_part]
    assert [m.kind for m in motion] == ["rapid", "linear", "linear", "linear", "rapid"]
    assert r.state.position("part") == pytest.approx({"X": 15.0, "Y": 26.0, "Z": 0.0})
    assert r.state.position("machine") == pytest.approx({"X": 115.0, "Y": 76.0, "Z": 0.0})
    # $FOR P1 = 1, 3, 1 leaves the first value that failed the test (spec 06 §5.4)
    assert r.state.param(1) == 4 and r.state.param(100) == 3
    assert r.state.origin == "G159=7"
    assert r.ended_by == "M30"


def test_streaming_run_gives_the_same_records_as_simulate():
    r = fagorcnc.simulate(MIXED)
    run = fagorcnc.interpret(MIXED)
    streamed = list(run)
    assert run.ok
    assert [(m.kind, m.line, getattr(m, "end", None)) for m in streamed] == [
        (m.kind, m.line, getattr(m, "end", None)) for m in r.moves]


def test_streaming_stops_before_a_syntax_error_further_down():
    text = "G1 X1 F100\nG1 X2\nG1 X[3\nG1 X4\nM30\n"
    run = fagorcnc.interpret(text)
    moves = list(run)
    assert [m.end["X"] for m in moves] == [1.0, 2.0]
    assert [d.code for d in run.diagnostics if d.is_error] == ["SYN003"]
    # simulate() checks the whole program first and runs nothing
    assert fagorcnc.simulate(text).moves == []


def test_streaming_releases_blocks_of_a_long_program():
    from fagorcnc.simulate import Run

    def lines(n):
        yield "%LONG"
        for i in range(n):
            yield f"G1 X{i % 100} Y{i % 37} F1000"
        yield "M30"

    run = Run(lines(20_000), "<gen>", fagorcnc.load_machine(None))
    held = []
    for m in run:
        assert m.kind == "linear" or m.kind == "aux"
        held.append(len(run._stream._builder.blocks))
    assert len(held) == 20_001
    assert run._stream.released >= 10_000   # memory does not keep the consumed blocks
    # a few blocks held at a time (net growth of the collector's objects: few collections, see RELEASE_BLOCKS)
    from fagorcnc.interp.source import RELEASE_BLOCKS
    from fagorcnc.syntax.reader import CHUNK_LINES

    assert max(held) <= 2 * RELEASE_BLOCKS + CHUNK_LINES   # + the read-ahead of a chunk of plain lines


def test_streaming_loops_and_backward_jumps_keep_their_blocks():
    from fagorcnc.simulate import Run

    def lines(n):
        yield "%LOOPS"
        yield "P1 = 0"
        yield "[TOP]"
        for i in range(n):
            yield f"G1 X{i % 100} F1000"
        yield "P1 = P1 + 1"
        yield "$IF P1 < 2 $GOTO [TOP]"
        yield "M30"

    run = Run(lines(6000), "<gen>", fagorcnc.load_machine(None))
    assert sum(1 for m in run if m.kind == "linear") == 12_000
    assert run.ok
