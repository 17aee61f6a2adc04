"""#CS/#ACS, #TOOL ORI, #RTCP, #TLC and #KIN ID computed (seed 002 ch. 17; spec 05 §6): the records end in
machine joints, numbers worked out by hand."""

from __future__ import annotations

import math

import numpy as np
import pytest

import fagorcnc
from fagorcnc.kinematics.solve import forward

C30, S30 = math.cos(math.radians(30)), 0.5

AXES3 = {a: {"min_limit": -1000, "max_limit": 1000} for a in "XYZ"}
# a rotary-table AC machine: A about X through (0, 0, -100), C about Z through the same point
TABLE_AC = {
    "axes": AXES3 | {"A": {"type": "rotary", "min_limit": -120, "max_limit": 120},
                     "C": {"type": "rotary", "min_limit": -9999, "max_limit": 9999}},
    "kinematics": [{"type": 10, "pivots": [[0, 0, -100], [0, 0, -100]]}],
    "tools": {"1": {"1": {"radius": 3.0}}},
}
# a B head (type 1: B about Y, main; A about X, secondary), the tool 100 mm from the pivot
HEAD_B = {
    "axes": AXES3 | {"A": {"type": "rotary", "min_limit": -120, "max_limit": 120},
                     "B": {"type": "rotary", "min_limit": -120, "max_limit": 120}},
    "kinematics": [{"type": 1}],
    "tools": {"1": {"1": {"length": 100.0}}},
}


def run(text: str, machine=None):
    return fagorcnc.simulate(text, machine)


def moves(r):
    return [m for m in r.moves if m.kind in ("linear", "rapid", "arc")]


def codes(r):
    return [d.code for d in r.diagnostics]


def approx(d: dict, **want):
    return all(d[k] == pytest.approx(v, abs=1e-4) for k, v in want.items())


# ------------------------------------------------------------------ #CS / #ACS geometry
def test_cs_mode_1_plane_of_the_tool_ori_example():
    # seed 002 L13139: [MODE 1, 0,0,20, 30,0,0] = Rx(30) at (0, 0, 20).  Plane point (60, 20, 3):
    # y = 20 cos30 - 3 sin30 = 15.8205, z = 20 + 20 sin30 + 3 cos30 = 32.5981.  The drilling Z-13 runs
    # along Z' = (0, -sin30, cos30): (60, 15.8205 + 6.5, 32.5981 - 11.2583)
    r = run("#CS ON [1] [MODE 1, 0, 0, 20, 30, 0, 0]\nG0 X60 Y20 Z3\nG1 G91 Z-13 F1000\nG90\n#CS OFF\n"
            "G0 X0 Y0 Z0\nM30\n")
    assert r.ok, r.diagnostics
    a, b, c = moves(r)
    assert approx(a.end, X=60, Y=15.8205081, Z=32.5980762) and a.frame is not None
    assert approx(b.end, X=60, Y=22.3205081, Z=21.3397460)
    assert b.end_part["Z"] == pytest.approx(-10)   # the plane's own coordinates stay on end_part
    assert b.feed == 1000 and c.frame is None and approx(c.end, X=0, Y=0, Z=0)


def test_cs_statement_sequence_of_the_manual():
    # seed 002 L12700-L12735.  NEW [3] activates CS3 (L12665), ON [3] activates it again ("un système
    # peut être activé plusieurs fois", L13104): CS3 twice, the plane zero at V + R V with
    # V = (2, 15, 5), R = Rx(2) Ry(3) Rz(4.5)
    from fagorcnc.kinematics.frames import mode_1

    v = np.array([2.0, 15.0, 5.0])
    want = v + mode_1(2, 3, 4.5) @ v
    r = run("P1=2\n#CS NEW [3] [MODE 1,2,15,5,2,3,4.5]\n#CS DEF [2] [MODE 1,P1,15,5,2,3,4.5]\n"
            "#CS DEF [5] [MODE 2,0,1,2,0,30,30]\n#CS ON\n#CS OFF\n#CS ON [3]\n#CS DEF [2] [MODE 1,1,1.2,1.3,0,0,33]\n"
            "G0 X0 Y0 Z0\nM30\n")
    assert r.ok, r.diagnostics
    assert approx(moves(r)[0].end, X=want[0], Y=want[1], Z=want[2])


def test_cs_on_activates_the_last_stored():
    # #CS ON alone: CS5 [MODE 2, 0,1,2, 0,30,30]: its zero is (0, 1, 2)
    r = run("#CS DEF [5] [MODE 2,0,1,2,0,30,30]\n#CS ON\nG0 X0 Y0 Z0\nM30\n")
    assert approx(moves(r)[0].end, X=0, Y=1, Z=2)


def test_every_acs_acts_before_every_cs():
    # seed 002 L13085: result = T_A(T_C(p)).  CS = Rz(90), ACS = shift (10, 0, 0); p = (1, 0, 0):
    # T_C -> (0, 1, 0), T_A -> (10, 1, 0) (activation order would give Rz(90) (11, 0, 0) = (0, 11, 0))
    r = run("#CS ON [1] [MODE 1, 0,0,0, 0,0,90]\n#ACS ON [1] [MODE 1, 10,0,0, 0,0,0]\nG0 X1 Y0 Z0\nM30\n")
    assert r.ok and approx(moves(r)[0].end, X=10, Y=1, Z=0)


def test_nesting_trace_of_the_manual():
    # seed 002 L13112-L13128: the OFF statements remove the last of their kind; OFF ALL every one
    text = ("#CS DEF [1] [MODE 1, 1,0,0, 0,0,0]\n#CS DEF [2] [MODE 1, 0,2,0, 0,0,0]\n"
            "#CS DEF [3] [MODE 1, 0,0,4, 0,0,0]\n"
            "#ACS DEF [1] [MODE 1, 10,0,0, 0,0,0]\n#ACS DEF [2] [MODE 1, 0,20,0, 0,0,0]\n"
            "#CS ON [1]\n#ACS ON [2]\n#ACS ON [1]\n#CS ON [2]\n#ACS OFF\n#CS OFF\n#CS ON [3]\nG0 X0 Y0 Z0\n"
            "#ACS OFF ALL\nG0 X0 Y0 Z0\n#CS OFF ALL\nG0 X0 Y0 Z0\nM30\n")
    r = run(text)
    assert r.ok, r.diagnostics
    a, b, c = moves(r)
    assert approx(a.end, X=1, Y=20, Z=4)   # ACS2 + CS1 + CS3: (0,20,0) + (1,0,0) + (0,0,4)
    assert approx(b.end, X=1, Y=0, Z=4)    # CS1 + CS3
    assert approx(c.end, X=0, Y=0, Z=0) and c.frame is None


def test_part_zero_comes_back_unless_keep():
    # seed 002 L12586: a preset made in the plane is dropped by #CS OFF; #CS OFF KEEP keeps it.
    # G54 X100; in the plane (shifted 0) G92 X0 at machine X130; after OFF, X0 is machine 100 again
    m = {"origins": {"G54": {"X": 100.0}}}
    base = "G54\n#CS ON [1] [MODE 1, 0,0,0, 0,0,0]\nG0 X30\nG92 X0\n#CS OFF{}\nG0 X0\nM30\n"
    assert approx(moves(run(base.format(""), m))[-1].end, X=100)
    assert approx(moves(run(base.format(" KEEP"), m))[-1].end, X=130)


def test_radius_compensation_in_the_inclined_plane():
    # G42 with R3 in the plane Rx(30) at (0, 0, 20): the compensated line X0 -> X50 runs at plane
    # Y = -3, Z = -2: part y = -3 cos30 + 2 sin30 = -1.5981, z = 20 - 3 sin30 - 2 cos30 = 16.7679
    r = run("T1 D1 M6\n#CS ON [1] [MODE 1, 0, 0, 20, 30, 0, 0]\nG0 X-10 Y0 Z5\nG1 Z-2 F500\nG42 G1 X0 Y0\nX50\n"
            "G40 G1 X60 Y0\n#CS OFF\nM30\n", TABLE_AC)
    assert r.ok, r.diagnostics
    line = next(m for m in moves(r) if m.end_part["X"] == pytest.approx(50))
    assert approx(line.start, X=0, Y=-1.5980762, Z=16.7679492)
    assert approx(line.end, X=50, Y=-1.5980762, Z=16.7679492)


def test_arc_in_a_plane_turned_about_its_normal_stays_an_arc():
    # Rz(90): the G17 arc stays an XY arc; plane centre (10, 0) -> machine (0, 10)
    r = run("#CS ON [1] [MODE 1, 0,0,0, 0,0,90]\nG0 X0 Y0 Z0\nG3 X20 Y0 I10 J0 F500\nM30\n")
    arc = moves(r)[-1]
    assert arc.kind == "arc" and approx(arc.center, X=0, Y=10) and approx(arc.end, X=0, Y=20)
    assert arc.direction == "ccw"


def test_arc_in_an_inclined_plane_runs_as_lines_near_the_arc():
    r = run("#CS ON [1] [MODE 1, 0,0,0, 30,0,0]\nG0 X10 Y0 Z0\nG3 X-10 Y0 I-10 J0 F500\nM30\n")
    assert r.ok and "KIN022" in codes(r)
    pieces = moves(r)[1:]
    assert len(pieces) > 2 and all(m.kind == "linear" for m in pieces)
    for m in pieces:
        # every joint point on the circle of radius 10 about 0 in the plane Rx(30), whose normal is
        # Z' = (0, -sin30, cos30): distance 10 from 0 and nothing along Z'
        x, y, z = m.end["X"], m.end["Y"], m.end["Z"]
        assert math.hypot(x, y, z) == pytest.approx(10, abs=1e-9)
        assert -S30 * y + C30 * z == pytest.approx(0, abs=1e-9)
    # between the joint points the chord stays within the tolerance: the sagitta of each piece
    for m in pieces:
        mid = [(m.start[a] + m.end[a]) / 2 for a in "XYZ"]
        assert 10 - math.hypot(*mid) <= r.machine.kinematics_tolerance + 1e-12


# ------------------------------------------------------------------ #CS errors
@pytest.mark.parametrize(("text", "code"), [
    ("#CS ON [6] [MODE 1,0,0,0,0,0,0]\n", "KIN006"),
    ("#CS ON [1] [MODE 7,0,0,0,0,0,0]\n", "KIN007"),
    ("#CS ON [1] [MODE 1,0,0,0,0,0]\n", "KIN007"),
    ("#CS ON [4]\n", "KIN008"),
    ("#CS ON\n", "KIN008"),
    ("#CS ON [MODE 1,0,0,0,0,0,0]\n#CS ON [MODE 1,0,0,0,0,0,0]\n", "KIN009"),
    ("#CS ON KEEP [1] [MODE 1,0,0,0,0,0,0]\n", "KIN010"),
    ("#CS ON [1] [MODE 1,0,0,0,0,0,0, FIRST]\n", "KIN010"),
    ("#CS ON [1] [MODE 3,0,0,0,0,0,0,2]\n", "KIN010"),
    ("#CS DEF [1] [MODE 1,0,0,0,0,0,0]\n" + "#CS ON [1]\n" * 11, "KIN011"),
])
def test_cs_errors(text, code):
    r = run(text + "M30\n")
    assert codes(r) == [code], r.diagnostics


def test_cs_off_with_none_active_changes_nothing():
    r = run("#CS OFF\nG0 X1\nM30\n")
    assert r.ok and codes(r) == ["KIN012"] and approx(moves(r)[0].end, X=1)


# ------------------------------------------------------------------ #TOOL ORI on a rotary table AC
def test_tool_ori_turns_the_table_during_the_next_move():
    # the plane Rx(30) at (0, 0, 20): Z' = (0, -sin30, cos30).  The tool (part frame) is Rx(-A) Z =
    # (0, sin A, cos A): A = -30, C = 0 (solution 1), or A = 30 with C = 180 (solution 2).
    # The plane point (60, 20, 3) is the part point (60, 15.8205, 32.5981); about the A line through
    # (0, 0, -100): Rx(-30) (60, 15.8205, 132.5981) = (60, 0.8660*15.8205 + 0.5*132.5981,
    # -0.5*15.8205 + 0.8660*132.5981) = (60, 80.0000, 106.9230) -> machine (60, 80, 6.9230)
    text = ("#CS ON [1] [MODE 1, 0, 0, 20, 30, 0, 0]\nP1=V.G.TOOLORIF1\nP2=V.G.TOOLORIS1\nP3=V.G.TOOLORIF2\n"
            "P4=V.G.TOOLORIS2\n#TOOL ORI\nG0 X60 Y20 Z3\nG1 G91 Z-13 F1000\nG0 Z13\nG90\n#CS OFF\nM30\n")
    r = run(text, TABLE_AC)
    assert r.ok, r.diagnostics
    assert [round(r.state.param(i), 9) for i in (1, 2, 3, 4)] == [-30, 0, 30, 180]
    ms = moves(r)
    turn = [m for m in ms if m.src.line == 7]
    assert len(turn) > 2 and approx(turn[-1].end, X=60, Y=80, Z=6.9230485, A=-30, C=0)
    drill = next(m for m in ms if m.src.line == 8)
    assert approx(drill.end, X=60, Y=80, Z=6.9230485 - 13, A=-30)   # the drilling is vertical now
    # the tool tip of every joint point of the turning move is on the programmed line, from the part
    # point (0, 0, 0) under the tool at the start to (60, 15.8205, 32.5981)
    kin = r.machine.kinematics[0]
    end = np.array([60, 20 * C30 - 3 * S30, 20 + 20 * S30 + 3 * C30])
    u = end / np.linalg.norm(end)
    for m in turn:
        tip, _ = forward(kin, (m.end["X"], m.end["Y"], m.end["Z"]), {"A": m.end["A"], "C": m.end["C"]})
        assert np.linalg.norm(tip - (tip @ u) * u) < 1e-9


def test_tool_ori_needs_a_kinematics():
    m = {"axes": AXES3 | {"A": {"type": "rotary"}}}
    assert codes(run("#TOOL ORI\nM30\n", m)) == ["KIN003"]


# ------------------------------------------------------------------ #RTCP (the manual's example 3)
def test_rtcp_example_3_tool_tip_on_the_path():
    # seed 002 L13280 (G18 plane, B head; B0 = tool along Z).  Tool 100 mm: the head reference point is
    # m = tip - Ry(B) (0, 0, -100) = tip + 100 (sin B, 0, cos B).  The length is taken on Z (G17) in
    # the first block; G18 is given at the arc, the only block it changes.
    text = ("T1 D1 M6\nG90 G17\n#RTCP ON\nG01 X40 Z0 B0 F1000\nX100\nB-35\nX200 Z70\nB90\n"
            "G18 G02 X270 Z0 R70 B0\nG01 X340\n#RTCP OFF\nM30\n")
    r = run(text, HEAD_B)
    assert r.ok, r.diagnostics
    by_line: dict[int, list] = {}
    for m in moves(r):
        by_line.setdefault(m.src.line, []).append(m)
    s35, c35 = math.sin(math.radians(35)), math.cos(math.radians(35))
    assert approx(by_line[4][-1].end, X=40, Y=0, Z=100, B=0)
    assert approx(by_line[5][-1].end, X=100, Z=100)
    # B-35 with the tip fixed at (100, 0): m = (100 - 100 sin35, 0, 100 cos35) = (42.6424, 0, 81.9152)
    assert approx(by_line[6][-1].end, X=100 - 100 * s35, Z=100 * c35, B=-35)
    assert len(by_line[6]) > 2
    # a line with B held: one joint-space line to (200 - 57.3576, 0, 70 + 81.9152)
    assert len(by_line[7]) == 1 and approx(by_line[7][0].end, X=200 - 100 * s35, Z=70 + 100 * c35)
    # B90: m = (200 + 100, 0, 70); the arc ends at the tip (270, 0) with B0: m = (270, 0, 100)
    assert approx(by_line[8][-1].end, X=300, Z=70, B=90)
    assert approx(by_line[9][-1].end, X=270, Z=100, B=0)
    assert approx(by_line[10][-1].end, X=340, Z=100)
    kin = r.machine.kinematics[0]
    # every joint point of the turning B-35 keeps the tip at (100, 0, 0); every arc point is on the
    # circle of radius 70 about (X270, Z70)
    for m in by_line[6]:
        tip, _ = forward(kin, (m.end["X"], m.end["Y"], m.end["Z"]), {"B": m.end["B"], "A": 0.0}, 100.0)
        assert math.dist(tip, (100, 0, 0)) < 1e-9
    for m in by_line[9]:
        tip, _ = forward(kin, (m.end["X"], m.end["Y"], m.end["Z"]), {"B": m.end["B"], "A": 0.0}, 100.0)
        assert math.hypot(tip[0] - 270, tip[2] - 70) == pytest.approx(70, abs=1e-9)
    # the feed of a piece makes the tip run at F: F times joint length over tip length.  On the arc the
    # reference point turns about the centre at radius 100 - 70 = 30 while B turns as fast (degrees
    # counted as mm): per radian 30 mm and 57.2958 deg against 70 mm of tip path:
    # 1000 sqrt(30^2 + 57.2958^2) / 70 = 923.92
    piece = by_line[9][0]
    assert piece.feed == pytest.approx(1000 * math.hypot(30, 180 / math.pi) / 70, rel=1e-4)


def test_rtcp_and_tlc_exclude_each_other_and_kin_id():
    m = HEAD_B
    assert codes(run("#TLC ON [1]\n#RTCP ON\nM30\n", m)) == ["KIN004"]
    assert codes(run("#RTCP ON\n#TLC ON [1]\nM30\n", m)) == ["KIN004"]
    assert codes(run("#RTCP ON\n#KIN ID [1]\nM30\n", m)) == ["KIN002"]
    assert codes(run("#KIN ID [2]\nM30\n", m)) == ["KIN001"]
    assert codes(run("#KIN ID [7]\nM30\n", m)) == ["KIN001"]
    assert run("#KIN ID [1]\n#RTCP ON\n#RTCP OFF\nM30\n", m).ok


def test_rtcp_on_a_three_axis_machine_is_the_identity():
    r = run("#KIN ID[1]\n#RTCP ON\nG1 X10 Y5 Z-1 F100\n#RTCP OFF\nM30\n")
    assert r.ok and codes(r) == ["KIN024"] and moves(r)[0].frame is None
    assert approx(moves(r)[0].end, X=10, Y=5, Z=-1)


# ------------------------------------------------------------------ #TLC
def test_tlc_moves_along_the_tool():
    # seed 002 L13343: d = 1.5 toward the spindle: for a vertical tool machine Z = programmed Z + 1.5
    r = run("#TLC ON [1.5]\nG1 X10 Z0 F100\n#TLC OFF\nG1 Z0\nM30\n")
    a, b = moves(r)
    assert approx(a.end, X=10, Z=1.5) and approx(b.end, Z=0)
    # a head at A = 90 (type 2, C about Z, A about X): the tool is Rx(90) Z = (0, -1, 0): -2 on Y
    m = {"axes": AXES3 | {"A": {"type": "rotary"}, "C": {"type": "rotary"}}, "kinematics": [{"type": 2}]}
    r = run("G1 A90 F100\n#TLC ON [2]\nG1 X10 Y0 Z0\nM30\n", m)
    assert approx(moves(r)[-1].end, X=10, Y=-2, Z=0)


# ------------------------------------------------------------------ V.MPK
def test_mpk_variables():
    r = run("P1=V.MPK.NKIN\nP2=V.MPK.TYPE[1]\nP3=V.MPK.NKINAX[1]\nP4=V.G.POSROTF\nM30\n", TABLE_AC)
    assert [r.state.param(i) for i in (1, 2, 3, 4)] == [1, 10, 2, 0]
    assert codes(run("P1=V.MPK.TDATA1[3]\nM30\n", TABLE_AC)) == ["KIN023"]
    assert codes(run("P1=V.MPK.TYPE[2]\nM30\n", TABLE_AC)) == ["INT045"]


def test_machine_position_variables_are_the_joints():
    # V.A.POS and the final machine position are the real axes, the plane point (60, 20, 3) of the
    # MODE 1 plane being machine (60, 15.8205, 32.5981); V.A.PPOS is in the plane
    r = run("#CS ON [1] [MODE 1, 0, 0, 20, 30, 0, 0]\nG0 X60 Y20 Z3\nP1=V.A.POS.Y\nP2=V.A.PPOS.Y\nM30\n")
    assert r.state.param(1) == pytest.approx(15.8205081) and r.state.param(2) == pytest.approx(20)
    assert approx(r.state.position("machine"), Y=15.8205081, Z=32.5980762)


def test_mode_6_retract_along_the_tool():
    # seed 002 L13415-L13431: after a lost plane, #CS ON [MODE 6, 0, 0, 0, 0] makes Z' the present tool
    # direction and G91 Z20 backs the tool out along it.  A head ZX (C about Z, A about X) at A = 90:
    # the tool (tip -> spindle) is Rx(90) Z = (0, -1, 0), so the retract is 20 along -Y
    m = {"axes": AXES3 | {"A": {"type": "rotary"}, "C": {"type": "rotary"}}, "kinematics": [{"type": 2}]}
    r = run("G1 A90 F1000\n#KIN ID [1]\n#CS ON [1] [MODE 6, 0, 0, 0, 0]\nG0 G91 Z20\nM30\n", m)
    assert r.ok, r.diagnostics
    assert approx(moves(r)[-1].end, X=0, Y=-20, Z=0, A=90)


def test_g17_arc_in_a_plane_turned_onto_machine_zx():
    # Rx(90): X' = X, Y' = Z.  The plane's G03 from (10, 0) to (-10, 0) about 0 passes machine (0, 0, 10):
    # a machine Z-X (G18 order) arc, clockwise in that order
    r = run("#CS ON [1] [MODE 1, 0,0,0, 90,0,0]\nG0 X10 Y0 Z0\nG3 X-10 Y0 I-10 J0 F500\nM30\n")
    arc = moves(r)[-1]
    assert arc.kind == "arc" and arc.plane[:2] == ("Z", "X") and arc.direction == "cw"
    assert approx(arc.end, X=-10, Y=0, Z=0) and approx(arc.center, Z=0, X=0)


def test_tool_axis_in_the_inclined_plane():
    # #TOOL AX [Y+] under the plane Rx(30), no kinematics: the tool is along the machine's Y, so its
    # length (50, orientation +: the controlled point at -50 on the axis) stays on machine Y while
    # the tip goes to the plane's zero: machine (0, -50, 0)
    r = run("#CS ON [1] [MODE 1, 0,0,0, 30,0,0]\nT1 D1 M6\n#TOOL AX [Y+]\nG1 X0 Y0 Z0 F100\nM30\n",
            {"tools": {"1": {"1": {"length": 50.0}}}})
    assert r.ok, r.diagnostics
    assert approx(moves(r)[-1].end, X=0, Y=-50, Z=0)


def test_homing_under_a_transformation_moves_the_joints():
    # L13320 forbids only the axes outside the RTCP (tests/test_home_transformed.py): G74 under a plane or
    # of the RTCP's own axes moves the joints to the reference point
    assert codes(run("#CS ON [1] [MODE 1, 0,0,0, 30,0,0]\nG74 Z1\nM30\n")) == []
    assert codes(run("#RTCP ON\nG74 Z1\nM30\n", HEAD_B)) == []


def test_mcs_moves_inside_an_inclined_plane():
    # seed 002 L13195: "#MCS ON / G1 G91 Z-10 / G0 Z10 / #MCS OFF" inside a plane drills along the
    # machine's Z; after #MCS OFF the plane's coordinates again.  Plane Rx(30) at (0, 0, 20): the plane
    # point (0, 0, 0) is machine (0, 0, 20); the #MCS move goes to machine Z 10; G90 X0 Y0 Z0 of the
    # plane comes back to machine (0, 0, 20)
    r = run("#CS ON [1] [MODE 1, 0, 0, 20, 30, 0, 0]\nG0 X0 Y0 Z0\n#MCS ON\nG1 G91 Z-10 F1000\n#MCS OFF\n"
            "G90 G0 X0 Y0 Z0\nM30\n")
    assert r.ok, r.diagnostics
    a, b, c = moves(r)
    assert approx(a.end, X=0, Y=0, Z=20)
    assert approx(b.start, X=0, Y=0, Z=20) and approx(b.end, X=0, Y=0, Z=10) and b.frame is None
    assert approx(c.start, X=0, Y=0, Z=10) and approx(c.end, X=0, Y=0, Z=20) and c.frame is not None


def test_plane_variables():
    # seed 002 L41252-L41430: after #CS ON [2] [MODE 1, 5,0,0, 0,0,90] (Rz(90)): V.G.CS = 2, CSMAT1..9
    # row by row = (0,-1,0, 1,0,0, 0,0,1), CSMAT10..12 = the plane zero (5, 0, 0); #RTCP -> TOOLCOMP 1
    r = run("#CS ON [2] [MODE 1, 5,0,0, 0,0,90]\nP1=V.G.CS\nP2=V.G.ACS\nP3=V.G.CSMAT2\nP4=V.G.CSMAT4\n"
            "P5=V.G.CSMAT10\nP6=V.G.TOOLCOMP\n#CS OFF\n#RTCP ON\nP7=V.G.TOOLCOMP\nP8=V.G.KINID\nM30\n", HEAD_B)
    assert r.ok, r.diagnostics
    assert [round(r.state.param(i), 9) for i in range(1, 9)] == [2, 0, -1, 1, 5, 3, 1, 1]


def test_arc_in_a_plane_turned_37_degrees_about_z_stays_an_arc():
    # Rz(37): the G17 circle of radius 10 about 0 stays a G17 arc of radius 10 about 0, end point
    # (10 cos37, 10 sin37) -> after a half turn (-10 cos37, -10 sin37)
    r = run("#CS ON [1] [MODE 1, 0,0,0, 0,0,37]\nG0 X10 Y0 Z0\nG3 X-10 Y0 I-10 J0 F500\nM30\n")
    arc = moves(r)[-1]
    c, s = math.cos(math.radians(37)), math.sin(math.radians(37))
    assert arc.kind == "arc" and arc.plane[:2] == ("X", "Y") and arc.direction == "ccw"
    assert approx(arc.start, X=10 * c, Y=10 * s) and approx(arc.end, X=-10 * c, Y=-10 * s)
    assert approx(arc.center, X=0, Y=0) and arc.radius == pytest.approx(10)


def test_tool_ori_example_of_the_manual_four_holes():
    # seed 002 L13139-L13173 on the AC table: once the table is at A -30 the plane is horizontal, its
    # zero at machine (0, 120 sin30, 120 cos30 - 100) = (0, 60, 3.9230) and its axes along X, Y, Z:
    # the plane point (x, y, 3) is machine (x, 60 + y, 6.9230), the bottom of each hole (x, y, -10)
    # is machine (x, 60 + y, -6.0770)
    text = ("#CS ON [1] [MODE 1, 0, 0, 20, 30, 0, 0]\n#TOOL ORI\nG90 G0 X60 Y20 Z3\nG1 G91 Z-13 F1000\nG0 Z13\n"
            "G0 G90 X120 Y20\nG1 G91 Z-13 F1000\nG0 Z13\nG0 G90 X120 Y120\nG1 G91 Z-13 F1000\nG0 Z13\n"
            "G0 G90 X60 Y120\nG1 G91 Z-13 F1000\nG0 Z13\nM30\n")
    r = run(text, TABLE_AC)
    assert r.ok, r.diagnostics
    z0 = 120 * C30 - 100
    bottoms = [m.end for m in moves(r) if m.kind == "linear" and m.feed == 1000]
    assert len(bottoms) == 4
    for end, (x, y) in zip(bottoms, [(60, 20), (120, 20), (120, 120), (60, 120)], strict=True):
        assert approx(end, X=x, Y=60 + y, Z=z0 - 10, A=-30, C=0)


def test_tool_ori_on_a_spindle_head():
    # head ZX (C about Z, A about X), tool 100: the tool along Z' = (0, -sin30, cos30) is Rx(30) Z, so
    # A = 30, C = 0 (C least from 0).  The tip at the plane point (60, 20, 3) = part (60, 15.8205,
    # 32.5981); the head reference point is the tip + 100 Z' = (60, -34.1795, 119.2006); the drilling
    # runs along -Z': 13 * (0, 0.5, -0.8660) further
    m = {"axes": AXES3 | {"A": {"type": "rotary", "min_limit": -120, "max_limit": 120},
                          "C": {"type": "rotary", "min_limit": -400, "max_limit": 400}},
         "kinematics": [{"type": 2}], "tools": {"1": {"1": {"length": 100.0}}}}
    r = run("T1 D1 M6\n#CS ON [1] [MODE 1, 0, 0, 20, 30, 0, 0]\n#TOOL ORI\nG0 X60 Y20 Z3\nG1 G91 Z-13 F100\n"
            "#CS OFF\nM30\n", m)
    assert r.ok, r.diagnostics
    *_, turn, drill = moves(r)
    y0, z0 = 20 * C30 - 3 * S30 - 100 * S30, 20 + 20 * S30 + 3 * C30 + 100 * C30
    assert approx(turn.end, X=60, Y=y0, Z=z0, A=30, C=0)
    assert approx(drill.end, X=60, Y=y0 + 13 * S30, Z=z0 - 13 * C30)
