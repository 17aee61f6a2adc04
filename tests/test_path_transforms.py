"""Mirror G10-G14, scaling G72/#SCALE, rotation G73 and tool length compensation (hand-worked)."""

from __future__ import annotations

import pytest

import fagorcnc

A = pytest.approx


def run(text: str, machine=None):
    r = fagorcnc.simulate(text, machine)
    assert r.ok, [str(d) for d in r.diagnostics]
    return r


def ends(r, kinds=("rapid", "linear", "arc")):
    return [m.end_part for m in r.moves if m.kind in kinds]


def test_mirror_on_x_negates_x_and_turns_g02_into_g03():
    # seed 002 L8705-L8740: G11 mirrors X; one plane axis mirrored -> the arc runs the other way
    r = run("G11\nG01 X10 Y5 F100\nG00 X0 Y0\nG02 X20 Y0 I10 J0\nP1 = V.G.MIRROR\nM30\n")
    line, _, arc = [m for m in r.moves if m.kind in ("linear", "rapid", "arc")]
    assert line.end_part == A({"X": -10.0, "Y": 5.0, "Z": 0.0})
    assert arc.end_part == A({"X": -20.0, "Y": 0.0, "Z": 0.0}) and arc.center_part == A({"X": -10.0, "Y": 0.0})
    assert arc.direction == "ccw"
    assert r.state.param(1) == 1.0   # bit 0 = first axis X


def test_mirror_on_both_plane_axes_keeps_the_direction():
    r = run("G11 G12\nG02 X20 Y0 I10 J0 F100\nM30\n")
    (arc,) = [m for m in r.moves if m.kind == "arc"]
    assert arc.end_part["X"] == A(-20.0) and arc.direction == "cw"


def test_g14_sets_and_clears_mirror_per_axis_and_g10_cancels():
    r = run("G14 Y-1\nG01 X3 Y4 F100\nG14 Y1\nY5\nG12\nY6\nG10\nY7\nM30\n")
    assert [(p["X"], p["Y"]) for p in ends(r)] == [(3.0, -4.0), (3.0, 5.0), (3.0, -6.0), (3.0, 7.0)]


def test_g10_with_g11_in_one_block_is_an_error():
    r = fagorcnc.simulate("G10 G11\nM30\n")
    assert [d.code for d in r.errors] == ["INT012"]


def test_incremental_move_under_mirror_is_negated():
    r = run("G11\nG01 X10 F100\nG91 X5\nM30\n")
    assert [p["X"] for p in ends(r)] == [-10.0, -15.0]


def test_scale_factor_g72_and_scale_sentence():
    # seed 002 L8989-L9047: G72 S2 doubles the coordinates; S before G72 is the spindle speed
    r = run("G72 S2\nG01 X10 Y5 F100\n#SCALE [3]\nX10\nG72\nX10\nP1 = V.G.SCALE\nM30\n")
    # an axis that is not written does not move: Y stays at part 10 when the factor changes
    assert [(p["X"], p["Y"]) for p in ends(r)] == [(20.0, 10.0), (30.0, 10.0), (10.0, 10.0)]
    assert r.state.param(1) == 1.0
    r = run("S2 G72\nP1 = V.G.SCALE\nM30\n")
    assert r.state.param(1) == 1.0
    assert [m.value for m in r.moves if getattr(m, "function", "") == "S"] == [2.0]


def test_scale_applies_to_arc_centres_and_radii():
    # scaled profile is similar: arc r 10 about (10,0) becomes r 20 about (20,0)
    r = run("G72 S2\nG02 X20 Y0 I10 J0 F100\nM30\n")
    (arc,) = [m for m in r.moves if m.kind == "arc"]
    assert arc.center_part == A({"X": 20.0, "Y": 0.0}) and arc.radius == A(20.0)
    assert arc.end_part["X"] == A(40.0)


def test_scale_then_rotation_example_from_the_variables_chapter():
    # spec 08 §B.4 (seed 002 L35692-L35707): #SCALE [2], G1 X10 -> PPOS.X 20; after G73 Q90 G1 X10 moves Y to 20
    r = run("#SCALE [2]\nG1 X10 F100\nP1 = V.A.PPOS.X\nG73 Q90\nG1 X10\nP2 = V.A.PPOS.Y\nM30\n")
    assert r.state.param(1) == A(20.0) and r.state.param(2) == A(20.0)


def test_g73_rotation_is_incremental_and_about_its_centre():
    # seed 002 L8906-L8980: Q values add up; G73 Q90 I10 J0: (20,0) rotates about (10,0) to (10,10)
    r = run("G73 Q45\nG73 Q45\nG01 X10 F100\nM30\n")
    assert ends(r)[0] == A({"X": 0.0, "Y": 10.0, "Z": 0.0}, abs=1e-12)
    r = run("G73 Q90 I10 J0\nG01 X20 Y0 F100\nP1 = V.G.ORGROT P2 = V.G.ROTPF\nG73\nX20\nM30\n")
    # after the cancel, Y is not written and stays at part 10
    assert [(p["X"], p["Y"]) for p in ends(r)] == [(A(10.0), A(10.0)), (A(20.0), A(10.0))]
    assert (r.state.param(1), r.state.param(2)) == (90.0, 10.0)


def test_rotated_eight_times_45_is_a_full_turn():
    r = run("$FOR P1 = 1, 8, 1\nG73 Q45\n$ENDFOR\nG01 X10 F100\nM30\n")
    assert ends(r)[0] == A({"X": 10.0, "Y": 0.0, "Z": 0.0}, abs=1e-9)


def test_plane_change_cancels_the_rotation():
    r = run("G73 Q90\nG18\nG17\nG01 X10 F100\nM30\n")
    assert ends(r)[0] == A({"X": 10.0, "Y": 0.0, "Z": 0.0})


def test_mirror_is_applied_before_rotation():
    # X10 -> mirror X -> (-10, 0) -> rotate 90 -> (0, -10)
    r = run("G11\nG73 Q90\nG01 X10 F100\nM30\n")
    assert ends(r)[0] == A({"X": 0.0, "Y": -10.0, "Z": 0.0}, abs=1e-12)


def test_g91_after_a_rotation_moves_in_the_rotated_frame():
    r = run("G73 Q90\nG01 X10 F100\nG91 X5\nM30\n")
    assert [(p["X"], p["Y"]) for p in ends(r)] == [(A(0.0, abs=1e-12), A(10.0)), (A(0.0, abs=1e-12), A(15.0))]


def test_tool_length_compensation_on_the_longitudinal_axis():
    # seed 002 L10072-L10171: with D active the controlled point is the tool base, length + wear above the tip
    machine = {"tools": {"1": {"1": {"length": 100.0, "length_wear": -0.5}}}}
    r = run("T1 D1 M6\nG0 X10 Z5\nP1 = V.A.PPOS.Z P2 = V.A.POS.Z\nD0\nG0 Z5\nM30\n", machine)
    moves = [m for m in r.moves if m.kind == "rapid"]
    assert moves[0].end["Z"] == A(104.5) and moves[0].end_part["Z"] == A(5.0)
    assert (r.state.param(1), r.state.param(2)) == (A(5.0), A(104.5))
    assert moves[1].end["Z"] == A(5.0)   # D0: cancelled on the next move of Z


def test_length_compensation_waits_for_a_move_of_the_longitudinal_axis():
    machine = {"tools": {"1": {"1": {"length": 100.0}}}}
    r = run("T1 D1 M6\nG0 X10\nZ0\nM30\n", machine)
    xmove, zmove = [m for m in r.moves if m.kind == "rapid"]
    assert xmove.end["Z"] == 0.0 and zmove.end["Z"] == 100.0


def test_tool_ax_selects_another_longitudinal_axis():
    # seed 002 L3126-L3166: #TOOL AX [X+]: the tool points along +X, the base is at X - L
    machine = {"tools": {"1": {"1": {"length": 50.0}}}}
    r = run("T1 D1 M6\n#TOOL AX [X+]\nG0 X100\nM30\n", machine)
    (move,) = [m for m in r.moves if m.kind == "rapid"]
    assert move.end["X"] == 50.0 and move.end_part["X"] == 100.0
