"""Feed modes, G20 planes, the M table, tool and G-state variables (hand-worked numbers)."""

from __future__ import annotations

import math

import pytest

import fagorcnc
from fagorcnc.simulate import estimate_time

TOOLS = {"tools": {"5": {"1": {"length": 100.0, "radius": 4.0}, "2": {"length": 90.0, "radius": 3.0}}}}


def _linear(r):
    return [m for m in r.moves if m.kind == "linear"]


def test_g94_feed_is_mm_per_min_and_g70_feed_is_converted():
    # seed 002 L4127-L4192: G94 mm/min; G70: F20 in/min = 508 mm/min (L2440-L2447)
    r = fagorcnc.simulate("G94 G1 X10 F600\nG70 X1 F20\nM30\n")
    assert [m.feed for m in _linear(r)] == [pytest.approx(600.0), pytest.approx(508.0)]


def test_g95_feed_per_revolution_times_spindle_speed():
    # F0.1 mm/rev at S2000 rpm = 200 mm/min; 10 mm takes 3 s
    r = fagorcnc.simulate("S2000 M3\nG95 G1 X10 F0.1\nM30\n")
    assert r.ok
    (m,) = _linear(r)
    assert m.feed == pytest.approx(200.0) and m.feed_mode == "G95"
    assert estimate_time(r.machine, r.moves) == pytest.approx(3.0)
    # planned: the 3.333 mm/s speed change is below A²/J = 50 mm/s, so each ramp is a pure jerk
    # S-curve of T = 2 sqrt(dv/J) = 2 sqrt(3.333/20000) = 0.02582 s at average speed v/2: +T/2 per ramp
    assert r.cycle_time == pytest.approx(3.0 + 2 * math.sqrt(10 / 3 / 20000))


def test_g95_with_the_spindle_stopped_is_an_error():
    r = fagorcnc.simulate("S2000\nG95 G1 X10 F0.1\nM30\n")
    assert [d.code for d in r.errors] == ["INT065"] and r.errors[0].line == 2


def test_g96_constant_surface_speed_gives_rpm_from_the_radius():
    # G96 S100 m/min at X radius 25 mm: rpm = 100000 / (2 pi 25) = 636.62; F0.2 mm/rev -> 127.32 mm/min
    r = fagorcnc.simulate("G0 X25\nG96 S100 M3\nG95 G1 Z-10 F0.2\nM30\n")
    assert r.ok, [str(d) for d in r.diagnostics]
    (m,) = _linear(r)
    assert m.feed == pytest.approx(0.2 * 100000 / (2 * math.pi * 25))


def test_g192_limits_the_g96_spindle_speed():
    # at X5: 100000 / (2 pi 5) = 3183 rpm, limited to 1000 rpm by G192 -> 0.2 * 1000 = 200 mm/min
    r = fagorcnc.simulate("G192 S1000\nG0 X5\nG96 S100 M3\nG95 G1 Z-10 F0.2\nM30\n")
    assert r.ok, [str(d) for d in r.diagnostics]
    assert _linear(r)[0].feed == pytest.approx(200.0)


def test_g93_feed_is_the_time_of_the_move():
    # G93 F2: the 30 mm move takes 2 s -> 900 mm/min
    r = fagorcnc.simulate("G93 G1 X30 F2\nM30\n")
    (m,) = _linear(r)
    assert m.feed == pytest.approx(900.0) and estimate_time(r.machine, r.moves) == pytest.approx(2.0)


def test_max_feed_clamps_silently():
    # seed 002 L4072: MAXFEED clamps the programmed feed without an error
    r = fagorcnc.simulate("G1 X10 F9000\nM30\n", {"max_feed": 5000.0})
    assert r.ok and _linear(r)[0].feed == 5000.0


def test_g20_plane_from_axis_roles():
    # seed 002 L3096-L3125: G20 X1 Z2 Y3 -> abscissa X, ordinate Z, longitudinal Y
    # polar R10 Q90 about (0, 0) -> ordinate Z = 10
    r = fagorcnc.simulate("G20 X1 Z2 Y3\nG1 R10 Q90 F100\nP1 = V.G.PLANE P2 = V.G.LONGAX P3 = V.G.TOOLDIR\nM30\n")
    assert r.ok, [str(d) for d in r.diagnostics]
    assert r.state.position() == pytest.approx({"X": 0.0, "Y": 0.0, "Z": 10.0}, abs=1e-12)
    assert (r.state.param(1), r.state.param(2), r.state.param(3)) == (1030.0, 20.0, 1.0)


def test_g20_arc_uses_i_for_the_abscissa_and_j_for_the_ordinate():
    # spec 03 §0: in G20 I/J belong to abscissa/ordinate.  Plane X (abscissa), Z (ordinate):
    # from (X10, Z0), G03 X0 Z10 I-10 J0 -> centre (0, 0), radius 10
    r = fagorcnc.simulate("G0 X10\nG20 X1 Z2 Y3\nG3 X0 Z10 I-10 J0 F100\nM30\n")
    assert r.ok, [str(d) for d in r.diagnostics]
    (arc,) = [m for m in r.moves if m.kind == "arc"]
    assert arc.center == pytest.approx({"X": 0.0, "Z": 0.0}) and arc.radius == pytest.approx(10.0)


@pytest.mark.parametrize(("text", "why"), [
    ("G20 X1 Y1 Z3", "two abscissas"),
    ("G20 X1 Z3", "no ordinate"),
    ("G20 X1 Y2 X3", "tool axis in the plane without a perpendicular axis"),
    ("G20 X1 Y2 Z4", "type 4 is reserved"),
])
def test_g20_errors(text, why):
    r = fagorcnc.simulate(text + "\nM30\n")
    assert [d.code for d in r.errors] == ["INT066"], why


def test_g20_with_perpendicular_axis():
    # seed 002 L3113: G20 X1 Y2 X3 Z5 -> plane XY, tool along X, perpendicular Z
    r = fagorcnc.simulate("G20 X1 Y2 X3 Z5\nP1 = V.G.LONGAX\nM30\n")
    assert r.ok and r.state.param(1) == 10.0


def test_m_table_timing_from_the_machine():
    # seed 002 L5020-L5029: M functions run before the motion unless the M table says after
    r = fagorcnc.simulate("G1 X10 F100 M8 M9\nM30\n", {"m_functions": {"9": "after"}})
    kinds = [(m.kind, getattr(m, "value", None)) for m in r.moves][:3]
    assert kinds == [("aux", 8.0), ("linear", None), ("aux", 9.0)]


def test_tool_variables_read_and_write_the_active_offset():
    # seed 002 L37896-L37967: V.TM.TOR / TOL of the active (or given) offset
    text = "T5 D1 M6\nP1 = V.TM.TOR P2 = V.TM.TOL[2]\nV.TM.TOR = 4.5\nP3 = V.TM.TOR P4 = V.TM.TOOL P5 = V.TM.TOD\nM30\n"
    r = fagorcnc.simulate(text, TOOLS)
    assert r.ok, [str(d) for d in r.diagnostics]
    assert [r.state.param(i) for i in range(1, 6)] == [4.0, 90.0, 4.5, 5.0, 1.0]


def test_g_state_variables():
    # seed 002 L40147, L40179-L40258: GS[n] and the HGS words; XYZ planes 1020 / 3010
    r = fagorcnc.simulate("G1 G18 G91 X0 F100\nP1 = V.G.GS[18] P2 = V.G.GS[17] P3 = V.G.PLANE\n"
                          "P4 = [V.G.HGS3 & [2**27]] == 2**27\nM30\n")
    assert r.ok
    # G91 is bit 91 - 64 = 27 of HGS3
    assert [r.state.param(i) for i in range(1, 5)] == [1.0, 0.0, 3010.0, 1.0]


def test_call_letters_feed_speed_and_program_state_variables():
    # seed 002 L40409: #PCALL sub A12.56 D3 -> V.C.PCALLP_A = 1, PCALLP_D = 1, others 0
    # L36198: V.G.FEED = active G94 feed; L43028: V.G.BLKN = last N executed;
    # L43219: V.G.CYTIME in hundredths of a second: 10 mm at 600 mm/min = 1 s -> 100
    # L36746: V.A.SPEED.S / V.SP.SPEED = active G97 speed; L43175: V.G.PARTC +1 at M30
    text = """%L SUB
P101 = V.C.PCALLP_A P102 = V.C.PCALLP_D P103 = V.C.PCALLP_B
M17
%MAIN
N10 G1 X10 F600
P104 = V.G.FEED P105 = V.G.BLKN P106 = V.G.CYTIME
S1200 M3
P107 = V.A.SPEED.S P108 = V.SP.SPEED P109 = V.A.SREAL.S
#PCALL SUB A12.56 D3
P110 = V.C.PCALLP_A
V.G.PARTC = 7
M30
"""
    r = fagorcnc.simulate(text)
    assert r.ok, [str(d) for d in r.diagnostics]
    assert [r.state.param(i) for i in range(101, 111)] == [1.0, 1.0, 0.0, 600.0, 10.0, 100.0, 1200.0, 1200.0,
                                                           1200.0, 0.0]
    assert r.state.var("V.G.PARTC") == 8.0


def test_spindle_variables_need_an_existing_spindle():
    r = fagorcnc.simulate("P1 = V.A.SPEED.S7\nM30\n")
    assert [d.code for d in r.errors] == ["INT046"]
    r = fagorcnc.simulate("V.A.SPEED.S = 5\nM30\n")
    assert [d.code for d in r.errors] == ["INT048"]


def test_g74_home_search_by_order_groups():
    # seed 002 L2357-L2406: G74 X2 Z1 A3 -> Z first, then X, then A; the numbers need not be consecutive.
    # Offsets are kept (L2351): with G54 X100 the part position after homing X is 0 - 100 = -100.
    machine = {"axes": {"X": {"home": 0.0}, "Y": {}, "Z": {"home": 50.0},
                        "A": {"type": "rotary", "home": 0.0}},
               "origins": {"G54": {"X": 100.0}}}
    r = fagorcnc.simulate("G54\nG0 X10 Y5 Z-20 A30\nG74 X2 Z1 A3\nM30\n", machine)
    assert r.ok, [str(d) for d in r.diagnostics]
    homing = [m for m in r.moves if m.kind == "rapid" and m.line == 3]
    assert [sorted(a for a in m.end if m.end[a] != m.start[a]) for m in homing] == [["Z"], ["X"], ["A"]]
    assert r.state.position("machine") == {"X": 0.0, "Y": 5.0, "Z": 50.0, "A": 0.0}
    assert r.state.position("part")["X"] == -100.0


def test_g74_cancels_arcs_and_needs_axes():
    # seed 002 L6333: G74 cancels G02/G03 (the motion mode becomes the IMOVE default, G00)
    r = fagorcnc.simulate("G0 X10\nG2 X10 Y0 I-10 J0 F100\nG74 X1\nP1 = V.G.GS[0]\nM30\n")
    assert r.ok and r.state.param(1) == 1.0
    assert [d.code for d in fagorcnc.simulate("G74\nM30\n").errors] == ["INT067"]
    assert [d.code for d in fagorcnc.simulate("G74 X1.5\nM30\n").errors] == ["INT067"]


def test_arc_of_zero_radius_is_an_error():
    r = fagorcnc.simulate("G2 X0 Y0 I0 J0 F100\nM30\n")
    assert [d.code for d in r.errors] == ["INT061"]


def test_huge_nr_is_stopped_by_the_block_limit():
    # NR repetitions count as executed blocks: an NR the loop limit allows still ends at max_blocks
    # (an NR above max_loop_iterations is refused at once: tests/test_guards.py)
    r = fagorcnc.simulate("G91 G1 X0.001 F1000 NR1000000\nM30\n", {"limits": {"max_blocks": 1000}})
    assert [d.code for d in r.errors] == ["INT080"]
    assert len([m for m in r.moves if m.kind == "linear"]) == 1000  # the block and 999 repetitions


def test_manual_tool_and_offset_example():
    # seed 002 L4972-L4996: T1 M06 loads T1 with D1; T2 only prepares T2; D2 selects D2 *of T1*;
    # M6 loads T2 with its D1
    machine = {"tools": {"1": {"1": {"length": 10.0}, "2": {"length": 20.0}}, "2": {"1": {"length": 30.0}}}}
    text = """N20 T1 M06
P1 = V.TM.TOOL P2 = V.TM.TOD
N50 T2
P3 = V.TM.TOOL P4 = V.TM.NXTOOL
N60 D2
P5 = V.TM.TOOL P6 = V.TM.TOD P7 = V.TM.TOL
N90 M6
P8 = V.TM.TOOL P9 = V.TM.TOD P10 = V.TM.TOL
M30
"""
    r = fagorcnc.simulate(text, machine)
    assert r.ok, [str(d) for d in r.diagnostics]
    assert [r.state.param(i) for i in range(1, 11)] == [1.0, 1.0, 1.0, 2.0, 1.0, 2.0, 20.0, 2.0, 1.0, 30.0]


def test_m19_s_is_an_angular_position_modulo_360_not_a_speed():
    # seed 002 L5703-L5713 and the example L5776-L5794: with M19 the S value is the spindle's angular
    # position in degrees, absolute, taken modulo 360 (S-100 -> 260); the speed for M03 stays 2500
    r = fagorcnc.simulate("N10 G97 S2500 M03\nN20 M19 S50\nN50 M19 S-100\nN55 M19 S725\nN60 M03\n"
                          "N65 G95 G01 X1 F0.1\nN70 M30\n")
    assert r.ok, r.diagnostics
    aux = [(a.function, a.value) for a in r.moves if a.kind == "aux" and a.function in ("S", "SPOS")]
    assert aux == [("S", 2500.0), ("SPOS", 50.0), ("SPOS", 260.0), ("SPOS", 5.0)]
    # G95 0.1 mm/rev at the 2500 rpm M03 runs again: 250 mm/min
    assert [m.feed for m in r.moves if m.kind == "linear"] == [pytest.approx(250.0)]
    # an S without M19 is still a speed, and a negative one is still refused
    assert [d.code for d in fagorcnc.simulate("S-100 M03\nM30\n").diagnostics] == ["INT027"]


def test_a_d_programmed_with_t_is_the_offset_the_next_m6_selects():
    # seed 002 L4946-L4966: "N20 T7 D1 (outil T7 et correcteur D1) / N30 M06 (on charge T7)"; D1 only when
    # no other was programmed.  T1 D2 then M6: D2 (length 60) is active, V.TM.NXTOD said so before the change
    machine = {"tools": {"1": {"1": {"length": 50.0}, "2": {"length": 60.0}}}}
    r = fagorcnc.simulate("T1 D2\nP1=V.TM.TOD\nP2=V.TM.NXTOD\nM6\nP3=V.TM.TOD\nP4=V.TM.NXTOD\nG1 Z0 F100\n"
                          "P5=V.A.POS.Z\nM30\n", machine)
    assert r.ok, r.diagnostics
    assert [r.state.param(i) for i in range(1, 6)] == [0.0, 2.0, 2.0, 0.0, 60.0]
    assert [a.value for a in r.moves if a.kind == "aux" and a.function == "D"] == [2.0]
    # no D with T: D1 (L4942); a D the next tool lacks is refused at its block
    assert fagorcnc.simulate("T1\nM6\nP1=V.TM.TOD\nM30\n", machine).state.param(1) == 1.0
    bad = fagorcnc.simulate("T1 D3\nM6\nM30\n", machine)
    assert [(d.code, d.line) for d in bad.diagnostics] == [("INT051", 1)]


def test_tool_table_variables_of_any_tool_and_offset():
    # seed 002 L38632-L38725: V.TM.TORT[tl][ofd] (radius), TOIT, TOLT, TOKT of tool tl's offset ofd, read and
    # written from the program; [tl] alone: the active offset number
    machine = {"tools": {"1": {"1": {"radius": 5.0}},
                         "2": {"1": {"radius": 3.0, "length": 70.0, "length_wear": 0.2}, "2": {"radius": 2.0}}}}
    r = fagorcnc.simulate("T1 D1 M6\nP1=V.TM.TORT[2][1]\nP2=V.TM.TOLT[2][1]\nP3=V.TM.TOKT[2][1]\n"
                          "P4=V.TM.TORT[1]\nV.TM.TORT[2][2]=2.5\nP5=V.TM.TORT[2][2]\nT2 D2 M6\nP6=V.TM.TOR\nM30\n",
                          machine)
    assert r.ok, r.diagnostics
    assert [r.state.param(i) for i in range(1, 7)] == [3.0, 70.0, pytest.approx(0.2), 5.0, 2.5, 2.5]
    bad = fagorcnc.simulate("P1=V.TM.TORT[2][9]\nM30\n", machine)
    assert [d.code for d in bad.diagnostics] == ["INT051"]


def test_longax_and_tooldir_follow_tool_ax():
    # seed 002 L3126-L3166: #TOOL AX [Y-] makes Y the longitudinal axis with a negative orientation;
    # V.G.LONGAX codes the axis (Y = 20), V.G.TOOLDIR 1 positive, 2 negative (the default plane's Z: 2)
    def read(pre: str) -> tuple[float, float]:
        r = fagorcnc.simulate(f"{pre}P1=V.G.LONGAX\nP2=V.G.TOOLDIR\nM30\n")
        assert r.ok, r.diagnostics
        return r.state.param(1), r.state.param(2)

    assert read("") == (30.0, 2.0)
    assert read("#TOOL AX [Y-]\n") == (20.0, 2.0)
    assert read("#TOOL AX [Z+]\n") == (30.0, 1.0)
    assert read("#TOOL AX [X+]\n") == (10.0, 1.0)


def test_soft_limit_variables_are_read_and_set_from_the_program():
    # seed 002 L33066-L33080: V.A.POSLIMIT / V.A.NEGLIMIT, the limits of the machine parameters; "si on
    # modifie ces variables, la CNC assume ces valeurs comme des nouvelles limites"
    machine = {"axes": {"X": {"min_limit": -100.0, "max_limit": 500.0}, "Y": {}, "Z": {}}}
    r = fagorcnc.simulate("P1=V.A.POSLIMIT.X\nP2=V.A.NEGLIMIT.X\nV.A.POSLIMIT.X=50\nG1 X40 F1000\nG1 X60\nM30\n",
                          machine)
    assert (r.state.param(1), r.state.param(2)) == (500.0, -100.0)
    assert [(d.code, d.line) for d in r.diagnostics if d.is_error] == [("INT100", 5)]   # beyond the new limit 50


@pytest.mark.parametrize(("middle", "stops"), [
    ("P1=V.A.POS.X", True),          # an execution value (L35803): reading it stops block preparation
    ("G1 X[V.A.POS.X+10]", True),    # read in the moving block itself: the stop comes before its move
    ("#FLUSH", True),                # L17446: preparation waits for execution
    ("P1=V.A.PPOS.X", False),        # a preparation value (L35650): no stop
])
def test_reading_an_execution_value_stops_the_motion_there(middle, stops):
    # seed 002 L17437-L17450: "sa lecture arrête la préparation des blocs"; under G05 the corner at X10 would
    # otherwise be run through at 50 mm/s
    r = fagorcnc.simulate(f"G5 G1 X10 F3000\n{middle}\nG1 X20 Y10\nM30\n")
    assert r.ok, r.diagnostics
    assert any(m.kind == "dwell" and m.seconds == 0.0 for m in r.moves) is stops
    first = next(s for s in r.segments(keep_profiles=False) if s.kind == "motion" and s.line == 1)
    assert (first.v1 == 0.0) is stops
    # inside a compensated profile the read stops the motion too, and the profile is still machined
    comp = fagorcnc.simulate(f"T1 D1 M6\nG1 G41 X0 Y0 F500\nX10\n{middle}\nY10\nG40 X0 Y20\nM30\n",
                             {"tools": {"1": {"1": {"radius": 2.0}}}})
    assert comp.ok, comp.diagnostics


def test_gs_reports_the_transformations_and_offsets_in_force():
    # seed 002 L40147: V.G.GS[n] is 1 while G n is active; G158, G73, G72 and G11-G13 have no modal
    # group but stay active while their offset, rotation, scale or mirror lasts
    r = fagorcnc.simulate("G158 X10\nG73 Q30\nG72 S2\nG11\nP1=V.G.GS[158]\nP2=V.G.GS[73]\nP3=V.G.GS[72]\n"
                          "P4=V.G.GS[11]\nP5=V.G.GS[12]\nP6=V.G.HGS5\nG158\nG73\nG72 S1\nG10\n"
                          "P7=V.G.GS[158]+V.G.GS[73]+V.G.GS[72]+V.G.GS[11]\nM30\n")
    assert r.ok, r.diagnostics
    assert [r.state.param(i) for i in range(1, 6)] == [1.0, 1.0, 1.0, 1.0, 0.0]
    assert int(r.state.param(6)) & (1 << (158 - 128))   # HGS5 holds G128-G159: bit 30 is G158
    assert r.state.param(7) == 0.0
