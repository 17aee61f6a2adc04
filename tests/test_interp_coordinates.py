"""Coordinates, planes, origins and units (spec 02 §1-§8, seed 002 L2400-L4042).

Every expected number is worked out by hand from the manual (the arithmetic
is in the comment next to it); the test names state the rule and cite the
seed line.
"""

from __future__ import annotations

import math

import pytest

import fagorcnc

A = 1e-9


def approx(v):
    return pytest.approx(v, abs=A)


def run(program: str, machine: dict | None = None):
    return fagorcnc.simulate(program, machine=machine)


def ok(program: str, machine: dict | None = None):
    r = run(program, machine)
    assert r.ok, [(d.code, d.line, d.message) for d in r.diagnostics]
    return r


def motions(r) -> list:
    return [m for m in r.moves if m.kind in ("rapid", "linear", "arc")]


def xy(pos: dict) -> tuple:
    return (pos["X"], pos["Y"])


def error_codes(r) -> list:
    return [d.code for d in r.diagnostics if d.is_error]


def params(r, *ns) -> list:
    return [r.state.param(n) for n in ns]


LIN = {"type": "linear"}


def rotary_machine(mode: str, **extra) -> dict:
    return {"axes": {"X": LIN, "Y": LIN, "Z": LIN, "C": {"type": "rotary", "rotary_mode": mode, **extra}}}


# ---------------------------------------------------------------- §1 G70 / G71


def test_g70_inch_coordinates_are_multiplied_by_25_4_seed002_l2408():
    r = ok("G70 G00 X1 Y-2\nM30\n")
    # X: 1 in * 25.4 = 25.4 mm ; Y: -2 in * 25.4 = -50.8 mm
    assert xy(motions(r)[0].end) == (approx(25.4), approx(-50.8))


def test_g70_inch_feed_is_converted_to_mm_per_min_seed002_l2446():
    r = ok("G70 G01 X1 F20\nM30\n")
    # F20 in/min * 25.4 = 508 mm/min (manual: 508 mm/min <-> 20 in/min)
    assert motions(r)[0].feed == approx(508.0)


def test_g71_to_g70_keeps_the_physical_feed_seed002_l2440_l2447():
    r = ok("G01 G71 X100 Y100 F508\nG70\nX5 Y5\nM30\n")
    first, second = motions(r)
    # N1: F508 mm/min; the G70 block converts the active feed to 20 in/min,
    # i.e. still 508 mm/min.  X5 Y5 inch = 127 mm each.
    assert first.feed == approx(508.0)
    assert second.feed == approx(508.0)
    assert xy(second.end) == (approx(127.0), approx(127.0))


def test_inches_machine_default_selects_g70_at_power_on_seed002_l2434():
    r = ok("G00 X1\nM30\n", {"defaults": {"INCHES": 1}})
    # INCHES = 1 -> G70 at power-on: X1 = 25.4 mm
    assert motions(r)[0].end["X"] == approx(25.4)


def test_m30_restores_the_inches_default_unit_seed002_l2434_l2436():
    r = ok("G70\nM30\n")
    # INCHES = 0 (default machine) -> G71 after M30
    assert r.state.modes["units"] == 71


# ---------------------------------------------------------------- §2 G90 / G91


def test_g90_absolute_example_visits_35_55_75_25_0_0_seed002_l2486_l2492():
    r = ok("N10 G00 G71 G90 X0 Y0\nN20 G01 X35 Y55 F450\nN30 X75 Y25\nN40 X0 Y0\nN50 M30\n")
    assert [xy(m.end) for m in motions(r)] == [(0, 0), (35, 55), (75, 25), (0, 0)]


def test_g91_incremental_example_visits_35_55_75_25_0_0_seed002_l2494_l2500():
    r = ok("N10 G00 G71 G90 X0 Y0\nN20 G01 G91 X35 Y55 F450\nN30 X40 Y-30\nN40 X-75 Y-25\nN50 M30\n")
    # (0,0)+(35,55)=(35,55); +(40,-30)=(75,25); +(-75,-25)=(0,0)
    ends = [xy(m.end) for m in motions(r)]
    assert ends == [(0, 0), (approx(35), approx(55)), (approx(75), approx(25)), (approx(0), approx(0))]


# ---------------------------------------------------------------- §6 polar coordinates


def test_g30_polar_origin_example_seed002_l3969_l3994():
    r = ok("G30 I35 J30\nG90 G01 R25 Q0 F100\nG03 Q90\nG01 X0 Y0\nM30\n")
    p1, arc, p0 = motions(r)
    # P1 = PO + 25*(cos 0, sin 0) = (35+25, 30) = (60, 30)
    assert xy(p1.end) == (approx(60), approx(30))
    # G03 Q90: centre = PO (35,30), radius 25, end = (35 + 25 cos 90, 30 + 25 sin 90) = (35, 55)
    assert arc.kind == "arc" and arc.direction == "ccw"
    assert (arc.center_part["X"], arc.center_part["Y"]) == (approx(35), approx(30))
    assert arc.radius == approx(25)
    assert xy(arc.end_part) == (approx(35), approx(55))
    assert xy(p0.end) == (approx(0), approx(0))


def test_polar_omitted_r_keeps_the_current_radius_spec02_6_3():
    r = ok("G01 X10 Y0 F100\nG01 Q90\nM30\n")
    # current point (10,0) about PO (0,0): R_cur = 10 -> (10 cos 90, 10 sin 90) = (0, 10)
    assert xy(motions(r)[1].end) == (approx(0), approx(10))


def test_polar_omitted_q_keeps_the_current_angle_spec02_6_3():
    r = ok("G01 X0 Y10 F100\nG01 R20\nM30\n")
    # current point (0,10): Q_cur = atan2(10, 0) = 90 -> (20 cos 90, 20 sin 90) = (0, 20)
    assert xy(motions(r)[1].end) == (approx(0), approx(20))


def test_g91_polar_r_and_q_are_increments_seed002_l2662_l2668():
    r = ok("G01 X10 Y0 F100\nG91 R5 Q30\nM30\n")
    # R = 10 + 5 = 15, Q = 0 + 30 = 30 -> (15 cos 30, 15 sin 30) = (12.99038..., 7.5)
    end = motions(r)[1].end
    assert xy(end) == (approx(15 * math.sqrt(3) / 2), approx(7.5))


def test_g91_negative_r_increment_allowed_if_result_not_negative_seed002_l2666():
    r = ok("G01 X10 Y0 F100\nG91 R-4 Q-90\nM30\n")
    # R = 10 - 4 = 6, Q = 0 - 90 = -90 -> (0, -6)
    assert xy(motions(r)[1].end) == (approx(0), approx(-6))


def test_g91_polar_radius_resulting_negative_is_an_error_seed002_l2666():
    r = run("G01 X10 Y0 F100\nG91 R-15\nM30\n")
    # R = 10 - 15 = -5 < 0
    assert "INT019" in error_codes(r)
    assert [d.line for d in r.errors] == [2]


def test_q_above_360_is_reduced_modulo_360_q420_is_q60_seed002_l2670_l2672():
    r = ok("G01 R10 Q420 F100\nM30\n")
    # Q420 = Q60: (10 cos 60, 10 sin 60) = (5, 8.66025...)
    assert xy(motions(r)[0].end) == (approx(5), approx(10 * math.sqrt(3) / 2))


def test_g90_negative_polar_radius_is_an_error_seed002_l2664():
    r = run("G01 R-10 Q0 F100\nM30\n")
    assert error_codes(r) == ["INT019"]


def test_g30_with_i_but_no_j_is_an_error_seed002_l3960():
    r = run("G30 I10\nM30\n")
    assert error_codes(r) == ["INT018"]


def test_g30_alone_takes_the_current_tool_position_seed002_l3961_l3967():
    r = ok("G01 X10 Y5 F100\nG30\nG90 R5 Q180\nM30\n")
    # PO = (10,5); R5 Q180 -> (10 - 5, 5 + 0) = (5, 5)
    assert xy(motions(r)[1].end) == (approx(5), approx(5))


def test_plane_change_resets_polar_origin_to_work_zero_seed002_l2682_l3996():
    r = ok("G17\nG30 I10 J10\nG18\nG17\nG01 R10 Q0 F100\nM30\n")   # G30 alone in its block (L3953)
    # PO back to (0,0) after the plane changes: (0 + 10, 0) = (10, 0), not (20, 10)
    assert xy(motions(r)[0].end) == (approx(10), approx(0))


def test_polar_in_g18_uses_z_as_abscissa_and_x_as_ordinate_spec02_6_1():
    r = ok("G18 G01 R10 Q90 F100\nM30\n")
    # Z = 0 + 10 cos 90 = 0 ; X = 0 + 10 sin 90 = 10
    end = motions(r)[0].end
    assert (end["Z"], end["X"]) == (approx(0), approx(10))


# ---------------------------------------------------------------- §7 planes


def test_g18_arc_centre_words_are_k_for_z_and_i_for_x_seed002_l2961_l3012():
    r = ok("G18 G01 X0 Z0 F100\nG02 Z20 X0 K10 I5\nM30\n")
    arc = motions(r)[1]
    # G18: abscissa Z, ordinate X. Centre = start + (K, I) = (Z 0+10, X 0+5) = (Z10, X5)
    # radius = hypot(10, 5) = sqrt(125); end (Z20, X0) is at hypot(10, -5) = sqrt(125)
    assert arc.plane[:2] == ("Z", "X")
    assert (arc.center_part["Z"], arc.center_part["X"]) == (approx(10), approx(5))
    assert arc.radius == approx(math.sqrt(125))
    assert (arc.end["Z"], arc.end["X"]) == (approx(20), approx(0))


# ---------------------------------------------------------------- §8 origins

MILL_TABLE = {"origins": {"G54": {"X": 20, "Y": 70}, "G55": {"X": 50, "Y": 30}, "G56": {"X": 120, "Y": 10}}}


def test_mill_origin_example_g56_x20_y30_ends_at_machine_140_40_seed002_l3484_l3531():
    r = ok("N100 G54\nN200 G159=2\nN300 G56 X20 Y30\nM30\n", MILL_TABLE)
    (move,) = motions(r)
    # G56 = ORGT[3] = (120,10); (20,30) + (120,10) = (140, 40)
    assert xy(move.end) == (approx(140), approx(40))
    assert xy(move.end_part) == (approx(20), approx(30))
    assert r.state.origin == "G56"


def test_origin_table_set_by_v_a_orgt_then_g54_seed002_l3481():
    r = ok("N100 V.A.ORGT[1].X=20 V.A.ORGT[1].Y=70\nG54\nG00 X0 Y0\nM30\n")
    # part (0,0) + ORGT[1] (20,70) = machine (20,70)
    assert xy(motions(r)[0].end) == (approx(20), approx(70))
    assert r.state.var("V.A.ORG.X") == approx(20)


def test_g159_11_applies_origin_table_entry_11_seed002_l3469_l3479():
    r = ok("G159=11\nG00 X0\nM30\n", {"origins": {"G159.11": {"X": 5}}})
    # part 0 + entry 11 (X5) = machine 5
    assert motions(r)[0].end["X"] == approx(5)
    assert r.state.origin == "G159=11"


def test_g92_preset_example_seed002_l3428_l3440():
    r = ok("N100 G90 G01 X40 Y30 F100\nN110 G92 X0 Y0\nP101=V.A.ORG.X\nP102=V.A.ORG.Y\n"
           "N200 G90 G01 X80 Y0\nN210 G92 X0 Y0\nP103=V.A.ORG.X\nP104=V.A.ORG.Y\n"
           "N300 G92 X120 Y30\nP105=V.A.ORG.X\nP106=V.A.ORG.Y\nM30\n")
    p0, p1 = motions(r)
    assert xy(p0.end) == (approx(40), approx(30))
    # N110: ABS = (40,30); N200: part (80,0) -> machine (120, 30)
    assert params(r, 101, 102) == [approx(40), approx(30)]
    assert xy(p1.end) == (approx(120), approx(30))
    # N210: ABS = MC (120,30) - (0,0) = (120,30); N300: ABS = (120,30) - (120,30) = (0,0)
    assert params(r, 103, 104) == [approx(120), approx(30)]
    assert params(r, 105, 106) == [approx(0), approx(0)]
    assert r.state.origin == "G92"


def test_g158_incremental_offset_replaces_per_axis_example_seed002_l3801_l3837():
    prog = "N100 G54\n"
    for n, block in enumerate(["", "N200 G158 X20 Y60", "N300 G158 X50 Y30", "N400 G158 X100",
                               "N500 G158 Y0", "N600 G158 X0"]):
        prog += f"{block}\nP{110 + 2 * n}=V.A.ORG.X\nP{111 + 2 * n}=V.A.ORG.Y\n"
    r = ok(prog + "M30\n", {"origins": {"G54": {"X": 20, "Y": 20}}})
    got = [tuple(params(r, 110 + 2 * n, 111 + 2 * n)) for n in range(6)]
    # ORG = G54 (20,20) + INC: (0,0) (20,60) (50,30) (100,30) (100,0) (0,0)
    assert got == [(20, 20), (40, 80), (70, 50), (120, 50), (120, 20), (20, 20)]


def test_g158_is_kept_when_another_absolute_offset_is_selected_seed002_l3765():
    r = ok("G54\nG158 X5\nG55\nM30\n", MILL_TABLE)
    # ORG.X = G55 50 + G158 5 = 55 ; ADDORG.X = 5
    assert r.state.var("V.A.ORG.X") == approx(55)
    assert r.state.var("V.A.ADDORG.X") == approx(5)


def test_g157_axis_equals_1_keeps_previous_offset_once_seed002_l3838_l3868():
    r = ok("G54\nG157 X1\nG55\nP101=V.A.ORG.X\nP102=V.A.ORG.Y\nG56\nP103=V.A.ORG.X\nM30\n", MILL_TABLE)
    # G55 with X excluded: X keeps G54's 20, Y loads G55's 30
    assert params(r, 101, 102) == [approx(20), approx(30)]
    # exclusion consumed: G56 loads X = 120
    assert r.state.param(103) == approx(120)


def test_g157_bare_axis_letters_exclude_them_seed002_l3851_l3876():
    # manual example L3876: "G157 X Z" (no values) excludes X and Z
    r = ok("G54\nG157 X Z\nG55\nP101=V.A.ORG.X\nP102=V.A.ORG.Y\nM30\n", MILL_TABLE)
    assert params(r, 101, 102) == [approx(20), approx(30)]


def test_g157_in_the_same_block_applies_before_the_offset_seed002_l3854_l3888():
    # manual example L3888: "G59 G157 Y"
    r = ok("G54\nG55 G157 Y\nP101=V.A.ORG.X\nP102=V.A.ORG.Y\nM30\n", MILL_TABLE)
    # X loads G55's 50, Y keeps G54's 70
    assert params(r, 101, 102) == [approx(50), approx(70)]


FIX_MACHINE = {"origins": {"G54": {"X": 20, "Y": 20}}, "fixtures": {"1": {"X": 30, "Y": 50}}}


def test_g53_cancels_g54_and_g158_but_keeps_the_fixture_seed002_l3897_l3902():
    r = ok("V.G.FIX=1\nG54\nG158 X5 Y7\nG00 X1 Y2\nG53\nG00 X1 Y2\nM30\n", FIX_MACHINE)
    before, after = motions(r)
    # before: 1 + 30 + 20 + 5 = 56 ; 2 + 50 + 20 + 7 = 79
    assert xy(before.end) == (approx(56), approx(79))
    # after G53: only the fixture: 1 + 30 = 31 ; 2 + 50 = 52
    assert xy(after.end) == (approx(31), approx(52))
    assert r.state.var("V.G.FIX") == 1
    assert r.state.var("V.A.ORG.X") == approx(0)
    assert r.state.origin == "G53"


def test_fixture_table_example_seed002_l3376_l3399():
    r = ok("N100 V.A.FIXT[1].X=30 V.A.FIXT[1].Y=50\nN110 V.A.FIXT[2].X=120 V.A.FIXT[2].Y=50\n"
           "N200 V.G.FIX=1\nG00 X0 Y0\nN300 V.G.FIX=2\nG00 X0 Y0\nN400 V.G.FIX=0\nG00 X0 Y0\nM30\n")
    # part (0,0) at fixture 1 -> (30,50); fixture 2 -> (120,50); no fixture -> (0,0)
    assert [xy(m.end) for m in motions(r)] == [(30, 50), (120, 50), (0, 0)]


def test_fixture_g54_mcs_g53_example_seed002_l3921_l3930():
    r = ok("N10 V.G.FIX=1\nN20 G54\nN30 #MCS X20 Y20\nN40 G01 X60 Y0 F100\nN50 G53\nG00 X0 Y0\nM30\n",
           FIX_MACHINE)
    mcs, n40, n60 = motions(r)
    # N30 relative to OM: machine (20,20)
    assert xy(mcs.end) == (approx(20), approx(20))
    # N40 relative to OW: (60,0) + FIX (30,50) + G54 (20,20) = (110, 70)
    assert xy(n40.end) == (approx(110), approx(70))
    # after N50 G53, relative to OF: (0,0) + (30,50)
    assert xy(n60.end) == (approx(30), approx(50))


def test_mcs_single_block_move_example_seed002_l3237_l3245():
    r = ok("G00 X30 Y30\nG92 X0 Y0\nG01 X20 Y20 F100\n#MCS X30 Y30\nG01 X40 Y40\nG01 X60 Y60\nM30\n")
    # G92 at machine (30,30): ABS = (30,30). (20,20)+30 = 50; #MCS -> 30; (40,40)+30 = 70; (60,60)+30 = 90
    assert [xy(m.end) for m in motions(r)] == [(30, 30), (50, 50), (30, 30), (70, 70), (90, 90)]


def test_mcs_on_block_runs_arcs_in_machine_coordinates_seed002_l3251_l3264():
    # the manual's #MCS ON example runs G01, G02 and G00; only polar coordinates are refused (L3225).
    # G92 at machine (30,30): part = machine - 30.  Inside #MCS: G01 to machine (60,50); G02 I10 J0 from
    # there: centre (70,50), to (80,50); G02 R10 to (70,40): clockwise about (70,50) (a quarter; the
    # other centre, (80,40), would be three quarters); G00 to machine (0,0); after #MCS OFF, part (10,10).
    r = ok("G00 X30 Y30\nG92 X0 Y0\nG01 X20 Y20 F500\n#MCS ON\nG01 X60 Y50\nG02 X80 Y50 I10 J0\n"
           "G02 X70 Y40 R10\nG00 X0 Y0\n#MCS OFF\nG01 X10 Y10\nM30\n")
    moves = motions(r)
    assert [xy(m.end) for m in moves] == [(30, 30), (50, 50), (60, 50), (80, 50), (70, 40), (0, 0), (40, 40)]
    first, second = moves[3], moves[4]
    assert first.kind == second.kind == "arc" and first.direction == second.direction == "cw"
    assert xy(first.center) == xy(second.center) == (approx(70), approx(50))
    assert xy(first.center_part) == (approx(40), approx(20)) and xy(first.end_part) == (approx(50), approx(20))
    assert second.sweep == approx(-90.0) and second.radius == approx(10.0)
    # a polar move (Q, or R with no end point in the plane) is still refused
    for bad in ("#MCS ON\nG01 R10 Q30 F500\n#MCS OFF\nM30\n", "#MCS ON\nG02 R10 F500\n#MCS OFF\nM30\n"):
        assert [d.code for d in fagorcnc.simulate(bad).diagnostics if d.severity == "error"] == ["INT063"]


def test_mcs_move_ignores_g70_and_uses_inches_unit_seed002_l3265_l3271():
    r = ok("G70\n#MCS X10\nM30\n")
    # INCHES = 0: X10 = 10 mm even though G70 is active
    assert motions(r)[0].end["X"] == approx(10)


def test_g174_sets_machine_coordinate_without_motion_seed002_l3272_l3305():
    r = ok("G54\nG00 X10\nG174 X100\nM30\n", {"origins": {"G54": {"X": 20}}})
    # one move only (G00 X10 -> machine 10 + 20 = 30); G174 declares the current point machine 100
    assert len(motions(r)) == 1
    assert r.state.position("machine")["X"] == approx(100)
    # part = 100 - G54 20 = 80
    assert r.state.position("part")["X"] == approx(80)


def test_g174_does_not_rewrite_the_previous_move_record_seed002_l3303():
    r = ok("G00 X10\nG174 X100\nM30\n")
    # the G00 block ended at machine 10; G174 makes no motion and cannot change that record
    (move,) = motions(r)
    assert move.end["X"] == approx(10)


def test_g174_ignores_g70_seed002_l3289_l3291():
    r = ok("G70\nG174 X10\nM30\n")
    # INCHES = 0: 10 mm, not 254
    assert r.state.position("machine")["X"] == approx(10)


def test_absolute_origin_survives_m30_seed002_l3552_l3554():
    r = ok("G54\nG00 X0\nM30\n", MILL_TABLE)
    assert r.ended_by == "M30"
    assert r.state.origin == "G54"
    assert r.state.var("V.A.ORG.X") == approx(20)


def test_offset_change_shares_block_with_motion_origin_first_seed002_l3535_l3537():
    r = ok("G53 G00 X10\nG55 X10\nM30\n", MILL_TABLE)
    # block 2: G55 (50) first, then X10 -> machine 60
    assert [m.end["X"] for m in motions(r)] == [approx(10), approx(60)]


# ---------------------------------------------------------------- chain invariant


def test_every_move_reports_machine_equal_part_plus_fixture_plus_origin_spec02_8_0():
    r = ok("V.G.FIX=1\nG54\nG158 X5 Y-3\nG00 X0 Y0\nG01 X10 F100\nG02 X20 Y0 I5 J0\nG91 G01 Y7\nM30\n",
           FIX_MACHINE)
    # chain = FIX (30,50) + G54 (20,20) + G158 (5,-3) = (55, 67)
    chain = {"X": 55.0, "Y": 67.0, "Z": 0.0}
    moves = motions(r)
    assert len(moves) == 4
    for m in moves:
        for a in ("X", "Y", "Z"):
            assert m.end[a] == approx(m.end_part[a] + chain[a])
    arc = moves[2]
    # centre (10+5, 0) part -> machine (70, 67)
    assert (arc.center_part["X"], arc.center_part["Y"]) == (approx(15), approx(0))
    assert (arc.center["X"], arc.center["Y"]) == (approx(70), approx(67))
    # final part (20, 7) -> machine (75, 74)
    assert xy(moves[3].end_part) == (approx(20), approx(7))
    assert xy(r.state.position("machine")) == (approx(75), approx(74))


# ---------------------------------------------------------------- §3 rotary axes


def test_normal_rotary_g90_sign_is_direction_abs_value_is_position_seed002_l2533_l2548():
    r = ok("G90 G00 C-90\nM30\n", rotary_machine("normal"))
    end = motions(r)[0].end["C"]
    # |−90| = 90 is the final position, reached in the negative direction:
    # from 0 going negative to 90 is 0 -> -270 (unrolled), displayed 90
    assert end == approx(-270)
    assert end % 360 == approx(90)


def test_normal_rotary_g90_positive_goes_positive_direction_seed002_l2533():
    r = ok("G90 G00 C270\nM30\n", rotary_machine("normal"))
    # from 0 positive to 270: +270
    assert motions(r)[0].end["C"] == approx(270)


def test_normal_rotary_g91_may_exceed_one_turn_seed002_l2540_l2548():
    r = ok("G91 G00 C400\nM30\n", rotary_machine("normal"))
    assert motions(r)[0].end["C"] == approx(400)


def test_rotary_axis_ignores_g70_seed002_l2513_l2516():
    r = ok("G70 G00 C10\nM30\n", rotary_machine("normal"))
    assert motions(r)[0].end["C"] == approx(10)


def test_positioning_rotary_takes_shortest_path_seed002_l2566_l2585():
    r = ok("G90 G00 C350\nC10\nM30\n", rotary_machine("positioning"))
    first, second = motions(r)
    # 0 -> 350 shortest is -10 ; then -10 (=350) -> 10 shortest is +20
    assert first.end["C"] == approx(-10)
    assert second.end["C"] == approx(10)


def test_unidirectional_rotary_g91_against_direction_is_an_error_seed002_l2555_l2558():
    r = run("G91 G00 C-30\nM30\n", rotary_machine("unidirectional"))
    assert error_codes(r) == ["INT026"]


def test_unidirectional_rotary_g90_moves_in_its_direction_seed002_l2550_l2553():
    r = ok("G90 G00 C300\nM30\n", rotary_machine("unidirectional", direction=-1))
    # fixed negative direction: 0 -> 300 going negative = -60
    assert motions(r)[0].end["C"] == approx(-60)


# ---------------------------------------------------------------- §4 diameter programming

LATHE_X = {"axes": {"X": {"diameter": True}, "Y": LIN, "Z": LIN}}


def test_g151_diameter_axis_x40_means_radius_20_seed002_l2586_l2617():
    r = ok("G151 G00 X40\nM30\n", LATHE_X)
    assert motions(r)[0].end["X"] == approx(20)


def test_g151_is_default_when_an_axis_has_diamprog_spec02_4():
    r = ok("G00 X40\nG152 X40\nM30\n", LATHE_X)
    # default G151: X40 -> 20 ; G152: X40 -> 40
    assert [m.end["X"] for m in motions(r)] == [approx(20), approx(40)]


def test_g151_does_not_affect_non_diameter_axes_seed002_l2614():
    r = ok("G151 G00 X40 Z40\nM30\n", LATHE_X)
    end = motions(r)[0].end
    assert (end["X"], end["Z"]) == (approx(20), approx(40))


# ---------------------------------------------------------------- soft limits, G198 / G199


def test_move_beyond_soft_limit_is_int100_naming_axis_and_line_seed002_l9233():
    r = run("G00 X10\nG01 Y600 F100\nM30\n", {"axes": {"X": LIN, "Y": {"max_limit": 500}, "Z": LIN}})
    (d,) = r.errors
    assert d.code == "INT100" and d.line == 2
    assert "Y" in d.message
    assert len(motions(r)) == 1


def test_soft_limits_are_checked_in_machine_coordinates_seed002_l9233():
    r = run("G54\nG00 Y450\nM30\n",
            {"axes": {"X": LIN, "Y": {"max_limit": 500}, "Z": LIN}, "origins": {"G54": {"Y": 100}}})
    # part 450 + 100 = machine 550 > 500
    assert error_codes(r) == ["INT100"]


def test_g199_upper_limit_program_seed002_l9205_l9211():
    r = run("G199 X100\nG00 X100\nG00 X150\nM30\n")
    # X100 is on the limit (allowed), X150 beyond
    assert [m.end["X"] for m in motions(r)] == [approx(100)]
    assert error_codes(r) == ["INT100"] and r.errors[0].line == 3


def test_g198_lower_limit_program_seed002_l9205_l9211():
    r = run("G198 X-50\nG00 X-60\nM30\n")
    assert error_codes(r) == ["INT100"]


def test_g199_value_is_in_machine_coordinates_seed002_l9213_l9215():
    r = run("G54\nG199 X150\nG00 X60\nM30\n", {"origins": {"G54": {"X": 100}}})
    # limit 150 machine; part 60 + 100 = 160 > 150
    assert error_codes(r) == ["INT100"]


def test_g91_g199_is_relative_to_the_active_limit_seed002_l9213_l9215():
    r = ok("G91 G199 X-100\nG90 G00 X850\nM30\n")
    # new upper limit = 1000 - 100 = 900 ; X850 is inside
    assert motions(r)[0].end["X"] == approx(850)


def test_g198_and_g199_zero_cancel_the_axis_limits_seed002_l9219_l9221():
    r = ok("G198 X0\nG199 X0\nG00 X2000\nM30\n")
    # both limits 0 -> X has no software limits at all, machine-parameter ones included
    assert motions(r)[0].end["X"] == approx(2000)


def test_g199_on_diameter_axis_is_a_radius_seed002_l9229_l9231():
    r = run("G199 X100\nG151 G00 X180\nG00 X220\nM30\n", LATHE_X)
    # X180 diameter = radius 90 <= 100 ok ; X220 = radius 110 > 100
    assert [m.end["X"] for m in motions(r)] == [approx(90)]
    assert error_codes(r) == ["INT100"]


# ---------------------------------------------------------------- G function errors


def test_incompatible_g90_g91_in_one_block_is_int012_seed002_l2480():
    r = run("G90 G91 X1\nM30\n")
    assert error_codes(r) == ["INT012"]


def test_incompatible_planes_in_one_block_is_int012_seed002_l2995():
    r = run("G17 G18\nM30\n")
    assert error_codes(r) == ["INT012"]


def test_unknown_g_function_is_int010():
    r = run("G999\nM30\n")
    assert error_codes(r) == ["INT010"]


def test_an_unknown_g_is_reported_before_the_words_it_makes_meaningless():
    # Autodesk posts write another CNC's smoothing, "G51 A45 E0.002": G51 is the mistake, not axis A
    # (alone in its block it is the [compat] construct CAM001, tests/test_cam_posts.py)
    r = run("G51 A45 E0.002 X1\nM30\n")
    assert [(d.code, d.col) for d in r.diagnostics if d.is_error] == [("INT010", 1)]
    assert error_codes(run("G1 A45 F100\nM30\n")) == ["INT024"]   # no unknown G: the axis it is


def test_unsupported_g_function_is_int011():
    # G100 (probing, described in another manual, L1433) is not computed by fagorcnc: reported, never dropped
    r = run("G100 N1\nM30\n")
    assert error_codes(r) == ["INT011"]


def test_tool_base_and_tip_positions_in_machine_and_part_coordinates_seed002_l35734_l35859():
    # POS/TPOS: machine, tool base (L35803); TIPPOS/TIPTPOS: machine, tool tip (L35846); APOS/ATPOS: part,
    # tool base (L35734); ATIPPOS/ATIPTPOS: part, tool tip (L35775).  G54 Z-200, tool length 50 + wear 0.5:
    # the tip at part Z30 is machine Z-170; the base is 50.5 above: machine Z-119.5, part Z80.5.
    machine = {"origins": {"G54": {"Z": -200.0}}, "tools": {"1": {"1": {"length": 50.0, "length_wear": 0.5}}}}
    names = ("POS", "TPOS", "TIPPOS", "TIPTPOS", "APOS", "ATPOS", "ATIPPOS", "ATIPTPOS")
    reads = "".join(f"P{i}=V.A.{n}.Z\n" for i, n in enumerate(names, start=1))
    r = ok(f"G54\nT1 D1\nM6\nG1 Z30 F1000\n{reads}M30\n", machine)
    assert [r.state.param(i) for i in range(1, 9)] == [approx(v) for v in
                                                       (-119.5, -119.5, -170, -170, 80.5, 80.5, 30, 30)]


def test_under_g70_variables_read_and_write_lengths_in_inches():
    # a program reads positions, origins and tool sizes in the units it is written in: under G70
    # "G1 X[V.A.PPOS.X]" must stay where it is (it went from 1 inch to 25.4 inches, reading millimetres)
    r = ok("G70\nG1 X1 F10\nP1=V.A.PPOS.X\nG1 X[P1]\nP2=V.A.POS.X\nG71\nP3=V.A.POS.X\nM30\n")
    assert [r.state.param(i) for i in (1, 2, 3)] == [approx(1.0), approx(1.0), approx(25.4)]
    assert [m.end["X"] for m in motions(r)] == [approx(25.4), approx(25.4)]
    # origins and tool sizes: G54 X25.4 mm reads 1 inch, a write of 2 inches is 50.8 mm; R 2.54 mm = 0.1 inch
    machine = {"origins": {"G54": {"X": 25.4}}, "tools": {"1": {"1": {"radius": 2.54}}}}
    r = ok("G70 G54\nT1 D1 M6\nP1=V.A.ORGT[1].X\nP2=V.TM.TOR\nV.A.ORGT[2].X=2\nG55 G0 X0\nM30\n", machine)
    assert (r.state.param(1), r.state.param(2)) == (approx(1.0), approx(0.1))
    assert motions(r)[-1].end["X"] == approx(50.8)


def test_an_axis_by_its_number_after_an_index_seed002_l35221_l35432():
    # V.A.ORGT[1].2: table origin 1, the channel's second axis (the manual's form, L35221, L35432)
    r = ok("P1=V.A.ORGT[1].2\nP2=V.A.ORGT[1].Y\nP3=V.A.ORGT[1].1+.5\nM30\n", {"origins": {"G54": {"X": 100, "Y": 50}}})
    assert [r.state.param(i) for i in (1, 2, 3)] == [50.0, 50.0, 100.5]
