"""Canned hole cycles G81-G86, their modal state and errors (spec 09 §1, §2.1-§2.6, worked examples §3.1-§3.7).

Every expected list is the digest's; the arithmetic is repeated in the comments.
"""

from __future__ import annotations

import pytest
from cycles_helpers import channel, codes, moves, run, split

SPINDLE = "S1000 M03\n"


# ------------------------------------------------------------------ §3.1 G81
def test_g81_g98_then_g99_in_the_influence_zone():
    # Zs = 50 (tool level at the definition), Zr = Z2, Zb = I-15; K0.5 s at the bottom
    program = SPINDLE + "G00 G90 X0 Y0 Z50\nG98 G81 X10 Y20 Z2 I-15 K0.5 F200\nX30\nG99 X50\nG80\nM30\n"
    assert moves(program, 3) == split("R(10,20,50) R(10,20,2) F(10,20,-15)@200 DWELL(0.5) R(10,20,50)")
    assert moves(program, 4) == split("R(30,20,50) R(30,20,2) F(30,20,-15)@200 DWELL(0.5) R(30,20,50)")
    # G99 in a block of the influence zone: the return goes to Zr = 2 from this hole on
    assert moves(program, 5) == split("R(50,20,50) R(50,20,2) F(50,20,-15)@200 DWELL(0.5) R(50,20,2)")


def test_g81_incremental_levels_computed_once_and_nr():
    # G91: Zr = Zs + Z = 50 - 45 = 5, Zb = Zr + I = 5 - 20 = -15, computed once at the definition
    program = SPINDLE + "G00 G90 X0 Y0 Z50\nG91 G99 G81 X10 Y10 Z-45 I-20 F100\nY15 NR3\nG80\nM30\n"
    assert moves(program, 3) == split("R(10,10,50) R(10,10,5) F(10,10,-15)@100 R(10,10,5)")
    # Y15 NR3: three holes 15 mm apart (seed 002 L1109-L1116, L11252)
    assert moves(program, 4) == split("R(10,25,5) F(10,25,-15)@100 R(10,25,5) "
                                      "R(10,40,5) F(10,40,-15)@100 R(10,40,5) "
                                      "R(10,55,5) F(10,55,-15)@100 R(10,55,5)")


def test_nr0_moves_without_the_cycle():
    program = SPINDLE + "G00 G90 X0 Y0 Z50\nG91 G99 G81 X10 Y10 Z-45 I-20 F100\nY15 NR0\nG80\nM30\n"
    assert moves(program, 4) == ["R(10,25,5)"]   # seed 002 L1115-L1116


def test_seed_example_drills_at_the_current_point():
    # seed 002 L11248-L11252: G01 G90 X23 F100 / G81 Z5 I-20 drills at X23; G91 Y15 NR4 = 4 more holes
    program = SPINDLE + "G00 X0 Y0 Z20\nG01 G90 X23 F100\nG81 Z5 I-20\nG91 Y15 NR4\nG80\nG90 Z20\nM30\n"
    assert moves(program, 4) == split("R(23,0,5) F(23,0,-20)@100 R(23,0,20)")
    got = moves(program, 5)
    assert [m for m in got if m.startswith("F")] == [f"F(23,{15 * k},-20)@100" for k in (1, 2, 3, 4)]
    assert moves(program, 7) == ["F(23,60,20)@100"]   # G90 Z20: already there (the G98 return); G01 again after G80


# ------------------------------------------------------------------ §3.2 G82
def test_g82_variable_peck_worked_example():
    # s1 = B + D = 8 -> -6; s2 = 0.8*6 = 4.8 -> -10.8; s3 = 0.64*6 = 3.84 -> -14.64 (3rd step: full retract, J3);
    # s4 = 3.072 -> -17.712; s5 = max(L2, 2.4576) -> -20.1696 clipped at Zb = -20.  H2 retract, C1 approach.
    program = SPINDLE + "G00 G90 X0 Y0 Z20\nG98 G82 Z2 I-20 B6 C1 D2 H2 J3 K0.2 L2 R0.8 F150\nM30\n"
    assert moves(program, 3) == split(
        "R(0,0,2) F(0,0,-6)@150 R(0,0,-4) R(0,0,-5) F(0,0,-10.8)@150 R(0,0,-8.8) R(0,0,-9.8) F(0,0,-14.64)@150 "
        "R(0,0,2) R(0,0,-13.64) F(0,0,-17.712)@150 R(0,0,-15.712) R(0,0,-16.712) F(0,0,-20)@150 DWELL(0.2) "
        "R(0,0,20)")


def test_g82_b_and_d_are_parameters_not_an_axis_and_an_offset():
    # the issue: without G82 its B and D were read as an axis and a tool offset
    result = run(SPINDLE + "G00 Z20\nG98 G82 Z2 I-8 B4 D1 H1 J2 F100\nM30\n")
    assert result.ok, [str(d) for d in result.diagnostics]
    assert result.state.var("V.G.TOD") == 0   # no D1 selected
    assert result.state.var("V.C.D") == 1


# ------------------------------------------------------------------ §3.3, §3.4 G83
def test_g83_g90_g99():
    # Zb = Zr + I*J = 2 + 5*(-4) = -18; re-approach 1 mm short of each previous bottom
    program = SPINDLE + "G00 G90 X0 Y0 Z30\nG99 G83 X5 Y5 Z2 I-4 J5 F120\nM30\n"
    assert moves(program, 3) == split(
        "R(5,5,30) R(5,5,2) F(5,5,-2)@120 R(5,5,2) R(5,5,-1) F(5,5,-6)@120 R(5,5,2) R(5,5,-5) F(5,5,-10)@120 "
        "R(5,5,2) R(5,5,-9) F(5,5,-14)@120 R(5,5,2) R(5,5,-13) F(5,5,-18)@120 R(5,5,2)")


def test_g83_g91_g98():
    # Zr = 25 - 20 = 5; Zb = 5 + 2*(-3) = -1; point X10 incremental from X0
    program = SPINDLE + "G00 G90 X0 Y0 Z25\nG91 G98 G83 X10 Z-20 I-3 J2 F100\nM30\n"
    assert moves(program, 3) == split(
        "R(10,0,25) R(10,0,5) F(10,0,2)@100 R(10,0,5) R(10,0,3) F(10,0,-1)@100 R(10,0,25)")


# ------------------------------------------------------------------ §3.5 G84
def test_g84_normal_with_srevm05():
    # pitch 750/500 = 1.5; SREVM05: the spindle stops before each reversal (seed 002 L21990-L21997)
    program = "G00 G90 X0 Y0 Z20\nS500 M03\nG98 G84 X15 Y15 Z3 I-12 K0.5 R0 F750\nM30\n"
    assert moves(program, 3, {"defaults": {"SREVM05": 1}}) == split(
        "R(15,15,20) R(15,15,3) F(15,15,-12)@750 M5 DWELL(0.5) M4 F(15,15,3)@750 M5 M3 R(15,15,20)")


def test_g84_normal_without_srevm05_and_override_locked():
    program = "G00 G90 X0 Y0 Z20\nS500 M03\nG98 G84 X15 Y15 Z3 I-12 K0.5 R0 F750\nM30\n"
    assert moves(program, 3) == split(
        "R(15,15,20) R(15,15,3) F(15,15,-12)@750 DWELL(0.5) M4 F(15,15,3)@750 M3 R(15,15,20)")
    taps = [r for r in run(program).moves if r.kind == "linear"]
    assert len(taps) == 2 and all(r.dyn.override_locked for r in taps)   # TAP: override at 100 %


def test_g84_rigid_with_pecks():
    # R1 B5: taps to 3-5 = -2, back to Zr, to -7, back, to Zb = -12, back; no M05/M04 (spindle interpolated)
    program = "G00 G90 X0 Y0 Z20\nS500 M03\nG98 G84 X15 Y15 Z3 I-12 R1 B5 F750\nM30\n"
    assert moves(program, 3) == split(
        "R(15,15,20) R(15,15,3) F(15,15,-2)@750 F(15,15,3)@750 F(15,15,-7)@750 F(15,15,3)@750 "
        "F(15,15,-12)@750 F(15,15,3)@750 R(15,15,20)")


# ------------------------------------------------------------------ §3.6 G85, §3.7 G86
def test_g85_feeds_back_to_the_reference_plane():
    program = SPINDLE + "G00 G90 X0 Y0 Z10\nG98 G85 X20 Z1 I-10 K1 F80\nM30\n"
    assert moves(program, 3) == split("R(20,0,10) R(20,0,1) F(20,0,-10)@80 DWELL(1) F(20,0,1)@80 R(20,0,10)")


def test_g86_stops_the_spindle_and_restarts_it():
    program = "G00 G90 X0 Y0 Z10\nS800 M03\nG99 G86 Y30 Z2 I-25 F60\nM30\n"
    assert moves(program, 3) == split("R(0,30,10) R(0,30,2) F(0,30,-25)@60 M5 R(0,30,2) M3")


# ------------------------------------------------------------------ influence zone and modal state
def test_axisless_blocks_do_not_repeat_the_cycle_and_g01_keeps_it():
    program = SPINDLE + ("G00 G90 X0 Y0 Z20\nG99 G81 Z2 I-5 F100\nM08\nF200\nP1=3\nG01 X10\n"
                         "G00 X20\nG80\nX30\nM30\n")
    assert moves(program, (4, 5, 6)) == ["M8"]
    # G01 X10: a point of the influence zone, positioned in rapid (spec 09 §1.4), drilled at the new F200
    assert moves(program, 7) == split("R(10,0,2) F(10,0,-5)@200 R(10,0,2)")
    assert moves(program, 8) == split("R(20,0,2) F(20,0,-5)@200 R(20,0,2)")
    assert moves(program, 10) == ["R(30,0,2)"]   # after G80: a plain move


def test_a_block_that_also_moves_the_longitudinal_axis_is_a_plain_move():
    program = SPINDLE + "G00 G90 X0 Y0 Z20\nG99 G81 Z2 I-5 F100\nX10 Z30\nX20\nM30\n"
    assert moves(program, 4, ok=False) == ["R(10,0,30)"]
    assert (4, "CYC010") in codes(program)
    # the cycle stays active; the starting plane stays Zs = 20 (Zr = 2 by G99 anyway)
    assert moves(program, 5, ok=False) == split("R(20,0,30) R(20,0,2) F(20,0,-5)@100 R(20,0,2)")


def test_z_omitted_reference_plane_is_the_starting_plane():
    program = SPINDLE + "G00 G90 X0 Y0 Z3\nG98 G81 X5 I-4 F100\nM30\n"
    assert moves(program, 3) == split("R(5,0,3) F(5,0,-4)@100 R(5,0,3)")


def test_another_cycle_replaces_the_active_one_and_m30_resets():
    program = SPINDLE + "G00 G90 X0 Y0 Z20\nG98 G81 Z2 I-5 F100\nG85 X10 Z2 I-6\nX20\nM30\n"
    result = run(program)
    assert result.ok
    assert [m for m in moves(program, 5) if m.startswith("F")] == ["F(20,0,-6)@100", "F(20,0,2)@100"]
    assert channel(result).cycles.active is None and result.state.modes["cycle"] == 80
    assert result.state.modes["cycle_return"] == 98


def test_plane_change_and_tool_axis_cancel_the_cycle():
    program = SPINDLE + "G00 G90 X0 Y0 Z20\nG98 G81 Z2 I-5 F100\nG18\nG17 X10\nG81 Z2 I-5\n#TOOL AX [Z+]\nX30\nM30\n"
    assert moves(program, 5) == ["R(10,0,20)"]
    assert moves(program, 8) == ["R(30,0,20)"]


def test_g18_and_g19_longitudinal_axes():
    # G18: plane ZX, longitudinal Y (seed 002 L2991): Z is the reference plane parameter, X positions
    program = SPINDLE + "G00 G90 X0 Y50 Z7\nG18 G98 G81 X10 Z5 I-10 F100\nM30\n"
    assert moves(program, 3) == split("R(10,50,7) R(10,5,7) F(10,-10,7)@100 R(10,50,7)")
    # G19: plane YZ, longitudinal X; Y positions, Z is the parameter
    program = SPINDLE + "G00 G90 X40 Y0 Z7\nG19 G99 G81 Y10 Z2 I-3 F100\nM30\n"
    assert moves(program, 3) == split("R(40,10,7) R(2,10,7) F(-3,10,7)@100 R(2,10,7)")


def test_tool_axis_towards_plus_drills_upwards():
    # #TOOL AX [Z+]: the cycle's direction is the sign of Zb - Zr (spec 09 §1.3)
    program = SPINDLE + "#TOOL AX [Z+]\nG00 G90 X0 Y0 Z-20\nG98 G81 Z-2 I10 F100\nM30\n"
    assert moves(program, 4) == split("R(0,0,-2) F(0,0,10)@100 R(0,0,-20)")


def test_cycle_definition_cancels_the_modal_subroutine():
    program = ("%L SUB\nG04 K0.1\nM17\n%MAIN\n" + SPINDLE + "G00 G90 X0 Y0 Z20\n#MCALL SUB\nX5\n"
               "G98 G81 Z2 I-5 F100\nX10\nM30\n")
    result = run(program)
    assert result.ok, [str(d) for d in result.diagnostics]
    kinds = [r.kind for r in result.moves]
    first_hole = next(i for i, r in enumerate(result.moves) if r.line == 9)
    # SUB runs at the #MCALL and after X5 (seed 002 L10518); not after the cycle's holes (L10570)
    assert kinds.count("dwell") == 2 and "dwell" not in kinds[first_hole:]


def test_length_compensation_takes_effect_in_the_cycle():
    machine = {"tools": {"1": {"1": {"length": 100.0, "radius": 3.0}}}}
    program = SPINDLE + "T1 D1 M6\nG00 G90 X0 Y0 Z50\nG98 G81 X5 Z2 I-5 F100\nM30\n"
    result = run(program, machine)
    assert result.ok
    feed = next(r for r in result.moves if r.kind == "linear")
    assert feed.end_part["Z"] == pytest.approx(-5.0) and feed.end["Z"] == pytest.approx(95.0)


# ------------------------------------------------------------------ errors of §1.5
@pytest.mark.parametrize(("block", "code"), [
    ("G81 Z2 F100", "CYC001"),            # no depth I
    ("G83 Z2 I-2 F100", "CYC001"),        # G83 needs J
    ("G81 Z2 I2 F100", "CYC002"),         # Zb == Zr
    ("G81 Z2 I-5 K-1 F100", "CYC004"),    # negative dwell
    ("G84 Z2 I-5 R2 F100", "CYC004"),     # R2 (8055) not on the 8065
    ("G84 Z2 I-5 R0 B2 F100", "CYC004"),  # pecks need rigid tapping
    ("G83 Z2 I-2 J0 F100", "CYC004"),
    ("G83 Z2 I-2 J2.5 F100", "CYC004"),
    ("G82 Z2 I-10 F100", "CYC004"),       # no peck B
    ("G82 Z2 I-10 B2 C3 F100", "CYC004"),  # approach C >= B
    ("G82 Z2 I-10 B2 R1.5 F100", "CYC004"),
    ("G81 Z5 Z2 I-3 F100", "CYC006"),     # Z both positioning and parameter
])
def test_errors_nothing_moves(block, code):
    program = SPINDLE + "G00 G90 X0 Y0 Z20\n" + block + "\nM30\n"
    result = run(program)
    assert (3, code) in [(d.line, d.code) for d in result.diagnostics if d.is_error]
    assert [r for r in result.moves if r.line == 3] == []
    d = next(d for d in result.diagnostics if d.code == code)
    assert d.col >= 1 and d.message


def test_radius_compensation_is_refused():
    machine = {"tools": {"1": {"1": {"radius": 3.0}}}}
    program = SPINDLE + "T1 D1 M6\nG00 G90 X0 Y0 Z20\nG41 G01 X10 F100\nG81 Z2 I-5\nM30\n"
    result = run(program, machine)
    assert (5, "CYC003") in [(d.line, d.code) for d in result.diagnostics]
    assert [r for r in result.moves if r.line == 5] == []


def test_tapping_with_the_spindle_stopped_is_refused_and_drilling_warns():
    assert (2, "CYC004") in codes("G00 Z20\nG84 Z2 I-5 F100\nM30\n")
    assert (2, "CYC011") in codes("G00 Z20\nG81 Z2 I-5 F100\nX10\nM30\n")
    assert [c for c in codes("G00 Z20\nG81 Z2 I-5 F100\nX10\nM30\n") if c[1] == "CYC011"] == [(2, "CYC011")]


def test_an_arc_cannot_position_a_hole():
    program = SPINDLE + "G00 Z20\nG81 Z2 I-5 F100\nG02 X10 I5\nM30\n"
    assert (4, "CYC012") in codes(program)
    assert (4, "CYC012") in codes(SPINDLE + "G00 Z20\nG81 Z2 I-5 F100\nG02 X10 R5\nM30\n")
    # polar positioning under G00/G01: R radius, Q angle from the polar origin
    assert moves(SPINDLE + "G00 G90 X0 Y0 Z20\nG99 G81 Z2 I-5 F100\nG01 R10 Q90\nM30\n", 4) == split(
        "R(0,10,2) F(0,10,-5)@100 R(0,10,2)")


def test_soft_limit_inside_a_hole_refuses_the_whole_hole():
    machine = {"axes": {"X": {}, "Y": {}, "Z": {"min_limit": -10.0}}}
    program = SPINDLE + "G00 Z20\nG81 X5 Z2 I-12 F100\nM30\n"
    result = run(program, machine)
    assert (3, "INT100") in [(d.line, d.code) for d in result.diagnostics]
    assert [r for r in result.moves if r.line == 3] == []   # not even the positioning of the failed hole


def test_g93_cannot_drive_a_cycle():
    assert (3, "CYC004") in codes(SPINDLE + "G00 Z20\nG93 G81 Z2 I-5 F2\nM30\n")


def test_inch_programs_give_levels_in_inches():
    # G70: Z0.1 in = 2.54 mm, I-0.5 in = -12.7 mm; F10 in/min = 254 mm/min; Zs = Z1 in = 25.4 mm
    program = SPINDLE + "G70 G00 G90 X0 Y0 Z1\nG98 G81 X1 Z0.1 I-0.5 F10\nM30\n"
    assert moves(program, 3) == split("R(25.4,0,25.4) R(25.4,0,2.54) F(25.4,0,-12.7)@254 R(25.4,0,25.4)")


def test_rotation_turns_the_points_not_the_depth():
    # G73 Q90: the hole at programmed X10 lands at part X0 Y10 (rotation about the part zero)
    program = SPINDLE + "G00 G90 X0 Y0 Z20\nG73 Q90\nG99 G81 X10 Z2 I-5 F100\nM30\n"
    assert moves(program, 4) == split("R(0,10,20) R(0,10,2) F(0,10,-5)@100 R(0,10,2)")


def test_seed_example_points_in_a_local_subroutine():
    # seed 002 L929-L951: the points 2-4 of a G81, then of a G84 that replaces it without G80, are G01
    # blocks of a local subroutine called from the influence zone
    program = ("%L POINTS\nG01 X20 Y0\nG01 X20 Y20\nG01 X0 Y20\nM17\n%PROGRAM\nS500 M03\nG00 X0 Y0 Z20\n"
               "G98 G81 X0 Y0 Z2 I-8 F150\nLL POINTS\nG84 X0 Y0 Z2 I-6 F750\nLL POINTS\nG80\nM30\n")
    result = run(program)
    assert result.ok, [str(d) for d in result.diagnostics]
    bottoms = [(r.end_part["X"], r.end_part["Y"], r.end_part["Z"]) for r in result.moves
               if r.kind == "linear" and r.end_part["Z"] < 0]
    corners = [(0, 0), (20, 0), (20, 20), (0, 20)]
    assert bottoms == [(x, y, -8) for x, y in corners] + [(x, y, -6) for x, y in corners]


def test_executing_a_cycle_cancels_a_modal_subroutine_programmed_in_its_zone():
    # seed 002 L10807: executing a canned cycle cancels the modal subroutine; after G80, X20 is a plain move
    program = ("%L SUB\nG04 K0.1\nM17\n%MAIN\n" + SPINDLE + "G00 G90 X0 Y0 Z20\nG98 G81 Z2 I-5 F100\n"
               "#MCALL SUB\nX10\nG80\nX20\nM30\n")
    result = run(program)
    assert result.ok, [str(d) for d in result.diagnostics]
    assert [r.kind for r in result.moves].count("dwell") == 1   # SUB ran only at its #MCALL


def test_feed_per_revolution_and_defaultfeed():
    # G95: F0.1 mm/rev at S1000 = 100 mm/min; no F at all with DEFAULTFEED 1: MAXFEED (seed 002 L4062)
    assert moves(SPINDLE + "G00 Z20\nG95 G99 G81 Z2 I-5 F0.1\nM30\n", 3) == split("R(0,0,2) F(0,0,-5)@100 R(0,0,2)")
    machine = {"defaults": {"DEFAULTFEED": 1}, "max_feed": 3000.0}
    assert moves(SPINDLE + "G00 Z20\nG99 G81 Z2 I-5\nM30\n", 3, machine) == split(
        "R(0,0,2) F(0,0,-5)@3000 R(0,0,2)")
    assert (3, "INT060") in codes(SPINDLE + "G00 Z20\nG99 G81 Z2 I-5\nM30\n")


def test_no_cycle_under_mcs_on():
    assert (3, "CYC004") in codes(SPINDLE + "#MCS ON\nG81 Z2 I-5 F100\nM30\n")
