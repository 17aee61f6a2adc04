"""Multiple machining G160-G165 and the V.C variables (spec 09 §2.10, §3.11-§3.13; seed 002 L40298-L40443)."""

from __future__ import annotations

import math

import pytest
from cycles_helpers import channel, codes, moves, run, split

SPINDLE = "S1000 M03\n"


def holes(program: str, line: int, machine=None) -> list[tuple[float, float]]:
    """(x, y) of each feed move to the bottom made by the block on ``line``."""
    result = run(program, machine)
    assert result.ok, [str(d) for d in result.diagnostics]
    return [(round(r.end_part["X"], 4), round(r.end_part["Y"], 4)) for r in result.moves
            if r.line == line and r.kind == "linear"]


def test_g160_seed_example_skips_point_6():
    # I = X/(K-1) = 100/9; point n at (n-1)*I*(cos 30, sin 30) = (n-1)*(9.6225, 5.5556)
    program = SPINDLE + "G00 G90 X0 Y0 Z20\nG99 G81 X0 Y0 Z2 I-10 F100\nG160 A30 X100 K10 P6\nM30\n"
    step = (100 / 9 * math.cos(math.radians(30)), 100 / 9 * math.sin(math.radians(30)))
    expected = [(round((n - 1) * step[0], 4), round((n - 1) * step[1], 4)) for n in (2, 3, 4, 5, 7, 8, 9, 10)]
    assert holes(program, 4) == expected
    got = moves(program, 4)
    assert got[:3] == split("R(9.6225,5.5556,2) F(9.6225,5.5556,-10)@100 R(9.6225,5.5556,2)")
    assert got[12] == "R(57.735,33.3333,2)"   # from point 5 straight to point 7


def test_g160_length_and_step():
    # X40 I10 -> K = 40/10 + 1 = 5: four more holes 10 mm apart
    program = SPINDLE + "G00 G90 X10 Y10 Z20\nG98 G81 Z2 I-5 F100\nG160 X40 I10\nM30\n"
    got = moves(program, 4)
    assert got[:4] == split("R(20,10,20) R(20,10,2) F(20,10,-5)@100 R(20,10,20)")
    assert holes(program, 4) == [(20, 10), (30, 10), (40, 10), (50, 10)]


@pytest.mark.parametrize(("block", "points"), [
    ("G161 A0 B90 X30 I10 Y20 J10",     # K = 4, D = 3: 2*(4+3)-4 = 10 points, 9 after point 1
     [(10, 0), (20, 0), (30, 0), (30, 10), (30, 20), (20, 20), (10, 20), (0, 20), (0, 10)]),
    ("G161 A30 B60 X20 K3 Y10 D2",      # I = 10, J = 10, 6 points
     [(8.6603, 5), (17.3205, 10), (17.3205, 20), (8.6603, 15), (0, 10)]),
    ("G162 A0 B90 X20 I10 Y10 J10", [(10, 0), (20, 0), (20, 10), (10, 10), (0, 10)]),
    ("G162 A0 B90 X30 K4 Y20 D3 P6.007",   # 12 points, 6 and 7 skipped
     [(10, 0), (20, 0), (30, 0), (30, 10), (0, 10), (0, 20), (10, 20), (20, 20), (30, 20)]),
])
def test_g161_g162_point_lists(block, points):
    program = SPINDLE + "G00 G90 X0 Y0 Z20\nG99 G81 Z2 I-5 F100\n" + block + "\nM30\n"
    assert holes(program, 4) == [(float(x), float(y)) for x, y in points]


@pytest.mark.parametrize(("block", "points"), [
    ("G163 X-20 Y0 K4", [(50, 70), (30, 50), (50, 30)]),           # centre (50,50), I = 90 CCW
    ("G163 X-20 Y0 I-90 C2 F500", [(50, 30), (30, 50), (50, 70)]),  # clockwise
    ("G164 X-20 Y0 B90 I30 C3 F600", [(67.3205, 60), (60, 67.3205), (50, 70)]),   # K = 90/30 + 1 = 4
    ("G165 X-20 Y0 A45", [(50, 70)]),
    ("G165 X-20 Y0 I28.2843", [(50, 70)]),   # 2*asin(28.2843/40) = 90 degrees, counter-clockwise
])
def test_g163_g164_g165_point_lists(block, points):
    program = SPINDLE + "G00 G90 X70 Y50 Z20\nG99 G81 Z2 I-5 F100\n" + block + "\nM30\n"
    assert holes(program, 4) == [(float(x), float(y)) for x, y in points]


def test_g163_arcs_between_points():
    program = SPINDLE + "G00 G90 X70 Y50 Z20\nG99 G81 Z2 I-5 F100\nG163 X-20 Y0 I-90 C2 F500\nM30\n"
    got = moves(program, 4)
    assert [m for m in got if m.startswith("CW")] == split(
        "CW(50,30,2; 50,50)@500 CW(30,50,2; 50,50)@500 CW(50,70,2; 50,50)@500")
    # F500 is local to the G163 block: the holes keep F100
    assert [m for m in got if m.startswith("F")] == ["F(50,30,-5)@100", "F(30,50,-5)@100", "F(50,70,-5)@100"]


def test_g164_ccw_arcs():
    program = SPINDLE + "G00 G90 X70 Y50 Z20\nG99 G81 Z2 I-5 F100\nG164 X-20 Y0 B90 I30 C3 F600\nM30\n"
    assert [m for m in moves(program, 4) if m.startswith("CCW")] == split(
        "CCW(67.3205,60,2; 50,50)@600 CCW(60,67.3205,2; 50,50)@600 CCW(50,70,2; 50,50)@600")


@pytest.mark.parametrize(("block", "code"), [
    ("G160 X45 I10", "CYC008"),        # 45/10 is not a whole number of steps
    ("G160 X40", "CYC008"),            # only one of X, I, K
    ("G160 X40 I10 K4", "CYC008"),     # disagree: 10*(4-1) != 40
    ("G163 X0 Y0 K4", "CYC008"),       # radius 0
    ("G163 X-20 Y0 I70", "CYC008"),    # 360/70 not whole
    ("G165 X-20 Y0 I50", "CYC008"),    # chord longer than the diameter 40
    ("G165 X-20 Y0 A45 I10", "CYC008"),
    ("G163 X-20 Y0 K4 C5", "CYC008"),
    ("G160 X40 I10 P3.002", "CYC008"),   # range end before its start
])
def test_pattern_errors(block, code):
    program = SPINDLE + "G00 G90 X70 Y50 Z20\nG99 G81 Z2 I-5 F100\n" + block + "\nM30\n"
    result = run(program)
    assert (4, code) in [(d.line, d.code) for d in result.diagnostics if d.is_error]
    assert [r for r in result.moves if r.line == 4] == []


def test_pattern_needs_a_cycle_or_a_modal_subroutine():
    assert (3, "CYC007") in codes(SPINDLE + "G00 Z20\nG160 X40 I10\nM30\n")
    assert (5, "CYC007") in codes(SPINDLE + "G00 Z20\nG81 Z2 I-5 F100\nG80\nG160 X40 I10\nM30\n")


def test_pattern_repeats_a_modal_subroutine():
    program = ("%L SUB\nG04 K0.5\nM17\n%MAIN\n" + SPINDLE +
               "G00 G90 X0 Y0 Z20\n#MCALL SUB\nG160 X20 I10\nM30\n")
    result = run(program)
    assert result.ok, [str(d) for d in result.diagnostics]
    rec = [(r.kind, round(r.end["X"], 4)) for r in result.moves if r.kind in ("rapid", "dwell")]
    # the #MCALL runs SUB once, then the two points of G160 are each followed by SUB
    assert rec == [("rapid", 0.0), ("dwell", 0.0), ("rapid", 10.0), ("dwell", 10.0), ("rapid", 20.0),
                   ("dwell", 20.0)]


# ------------------------------------------------------------------ V.C variables
def test_vc_call_parameters_seed_examples():
    # seed 002 L40369-L40386: G90 G81 Z0 I-15 -> V.C.Z = 0, V.C.I = -15, CALLP_Z = CALLP_I = 1, CALLP_K = 0
    program = (SPINDLE + "G00 Z20\nG90 G81 Z0 I-15 F100\nP1=V.C.Z\nP2=V.C.I\nP3=V.C.CALLP_Z\nP4=V.C.CALLP_I\n"
               "P5=V.C.CALLP_K\nP6=V.C.G\n"
               # L40428-L40443: G160 A30 X100 K10 P6 -> V.C.P_A = 30, V.C.P_X = 100, P_CALLP_A/K = 1, R = 0
               "G160 A30 X100 K10 P6\nP7=V.C.P_A\nP8=V.C.P_X\nP9=V.C.P_CALLP_A\nP10=V.C.P_CALLP_K\n"
               "P11=V.C.P_CALLP_R\nM30\n")
    result = run(program)
    assert result.ok, [str(d) for d in result.diagnostics]
    got = [result.state.param(n) for n in range(1, 12)]
    assert got == [0, -15, 1, 1, 0, 0, 30, 100, 1, 1, 0]   # V.C.G: no letter G among the parameters


def test_cycletypeon_is_for_the_plc_not_the_program():
    # seed 002 L40300: "Variable de lecture depuis le programme PLC et l'Interface"
    from fagorcnc.interp.cycles.variables import cycle_type

    assert (3, "INT044") in codes(SPINDLE + "G81 Z2 I-5 F100\nP1=V.G.CYCLETYPEON\nM30\n")
    result = run(SPINDLE + "G00 Z20\nG81 Z2 I-5 F100\nM00\n")
    assert result.ok
    assert cycle_type(channel(result)) == 81


def test_vc_write_changes_the_next_hole():
    # V.C.I = -8 recomputes Zb with the definition's G90; V.C.K adds a dwell
    program = SPINDLE + "G00 G90 X0 Y0 Z20\nG99 G81 Z2 I-5 F100\nV.C.I=-8\nV.C.K=0.3\nX10\nM30\n"
    assert moves(program, 6) == split("R(10,0,2) F(10,0,-8)@100 DWELL(0.3) R(10,0,2)")


def test_vc_write_is_checked_at_the_next_hole():
    program = SPINDLE + "G00 G90 X0 Y0 Z20\nG99 G81 Z2 I-5 F100\nV.C.I=2\nX10\nM30\n"
    result = run(program)
    assert (5, "CYC002") in [(d.line, d.code) for d in result.diagnostics]
    assert [r for r in result.moves if r.line == 5] == []


def test_pattern_points_count_as_blocks_for_the_runaway_guard():
    machine = {"limits": {"max_blocks": 20}}
    result = run(SPINDLE + "G00 Z20\nG99 G81 Z2 I-5 F100\nG160 X500 K100\nM30\n", machine)
    assert (4, "INT080") in [(d.line, d.code) for d in result.diagnostics]


def test_a_hole_of_too_many_moves_is_refused_before_it_moves():
    # G82 with pecks of 0.001 mm over 500 mm: 500 000 steps, over MAX_MOVES_PER_HOLE
    result = run(SPINDLE + "G00 Z20\nG82 Z2 I-498 B0.001 L0.001 C0.0005 F100\nM30\n")
    assert (3, "CYC004") in [(d.line, d.code) for d in result.diagnostics]
