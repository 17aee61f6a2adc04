"""Pocket cycles G87/G88 and bore milling G210 (spec 09 §2.7-§2.9, worked examples §3.8-§3.10, §3.14)."""

from __future__ import annotations

import pytest
from cycles_helpers import codes, moves, run, split

TOOLS = {"tools": {"1": {"1": {"radius": 5.0}}, "2": {"1": {"radius": 4.0}}}}


def _level(z: float) -> str:
    """§3.8 level block at z (tool radius 5): plunge @V50, central segment, two rings, finishing @H100."""
    return (f"F(50,40,{z:g})@50 F(40,40,{z:g})@200 F(60,40,{z:g})@200 "
            f"F(64.75,40,{z:g})@200 F(64.75,35.25,{z:g})@200 F(35.25,35.25,{z:g})@200 F(35.25,44.75,{z:g})@200 "
            f"F(64.75,44.75,{z:g})@200 F(64.75,40,{z:g})@200 "
            f"F(69.5,40,{z:g})@200 F(69.5,30.5,{z:g})@200 F(30.5,30.5,{z:g})@200 F(30.5,49.5,{z:g})@200 "
            f"F(69.5,49.5,{z:g})@200 F(69.5,40,{z:g})@200 "
            f"CW(70,40,{z:g}; 69.75,40)@100 F(70,30,{z:g})@100 F(30,30,{z:g})@100 F(30,50,{z:g})@100 "
            f"F(70,50,{z:g})@100 F(70,40,{z:g})@100 CW(69.5,40,{z:g}; 69.75,40)@100 "
            f"R(69.5,40,{z + 1:g}) R(50,40,{z + 1:g})")


def test_g87_clockwise_with_finishing():
    # Zsurf = Zr - D = 0, T = 10, B5 -> levels -5, -10.  a = 25-5-0.5 = 19.5, b = 15-5-0.5 = 9.5, d = 10;
    # m = ceil(9.5/8) = 2, s = 4.75: rings (14.75, 4.75), (19.5, 9.5); finishing (20, 10); J > 0 -> CW
    program = ("T1 D1 M6\nS1000 M3\nG00 G90 X0 Y0 Z20\n"
               "G98 G87 X50 Y40 Z2 I-10 D2 J25 K15 B5 C8 L0.5 H100 V50 F200\nM30\n")
    expected = split("R(50,40,20) R(50,40,2) " + _level(-5) + " " + _level(-10) + " R(50,40,20)")
    assert moves(program, 4, TOOLS) == expected


def test_g87_finishing_corners_follow_the_sign_of_l():
    program = "T1 D1 M6\nS1000 M3\nG00 G90 X0 Y0 Z20\nG98 G87 X50 Y40 Z2 I-10 D2 J25 K15 B5 C8 L{} H100 V50 F200\nM30\n"
    square = [r for r in run(program.format(0.5), TOOLS).moves if getattr(r, "feed", None) == 100]
    rounded = [r for r in run(program.format(-0.5), TOOLS).moves if getattr(r, "feed", None) == 100]
    assert {r.dyn.corner for r in square} == {"G07"} and {r.dyn.corner for r in rounded} == {"G05"}


def test_g87_counter_clockwise_defaults_negative_b_and_g99():
    # r = 4: C default 0.75*8 = 6, V default F/2 = 150.  D0: Zsurf = 1, T = 8, B-3 -> -2, -5, -7.
    # a = 20-4 = 16, b = 10-4 = 6, d = 10, m = 1: ring (16, 6); J < 0 -> CCW; no L, no finishing
    program = "T2 D1 M6\nS1000 M3\nG00 G90 X0 Y0 Z10\nG99 G87 Z1 I-7 J-20 K10 B-3 F300\nM30\n"

    def level(z: float) -> str:
        return (f"F(0,0,{z:g})@150 F(-10,0,{z:g})@300 F(10,0,{z:g})@300 F(16,0,{z:g})@300 F(16,6,{z:g})@300 "
                f"F(-16,6,{z:g})@300 F(-16,-6,{z:g})@300 F(16,-6,{z:g})@300 F(16,0,{z:g})@300 "
                f"R(16,0,{z + 1:g}) R(0,0,{z + 1:g})")

    expected = split("R(0,0,1) " + level(-2) + " " + level(-5) + " " + level(-7) + " R(0,0,1)")
    assert moves(program, 4, TOOLS) == expected


def test_g87_angle_a_turns_the_pocket():
    # A90: the long side along Y; one level (Z1 -> I-1, B2) and one ring of half sizes (16, 6) turned by 90
    # degrees about the centre
    program = "T2 D1 M6\nS1000 M3\nG00 G90 X0 Y0 Z10\nG99 G87 Z1 I-1 A90 J-20 K10 B2 F300\nM30\n"
    got = moves(program, 4, TOOLS)
    assert got[2:4] == ["F(0,-10,-1)@300", "F(0,10,-1)@300"]       # central segment along Y
    assert got[4:6] == ["F(0,16,-1)@300", "F(-6,16,-1)@300"]        # ring from (P,0) = (0,16), CCW


def test_g87_rounded_corners_m1():
    # M1 Q7, r = 5: finishing corners are arcs of radius Q - r = 2 about (a_f-2, b_f-2) ...
    program = "T1 D1 M6\nS1000 M3\nG00 G90 X0 Y0 Z20\nG98 G87 Z2 I-3 J25 K15 M1 Q7 B5 C8 L0.5 H100 F200\nM30\n"
    arcs = [m for m in moves(program, 4, TOOLS) if m.startswith("CW")]
    # entry semicircle, 4 corners, exit semicircle; first corner (20,-10): from (20,-8) to (18,-10) about (18,-8)
    assert len(arcs) == 6 and arcs[1] == "CW(18,-10,-3; 18,-8)@100"


def test_g88_circular_pocket():
    # Levels -8, -16; a = 30-5-1 = 24, m = ceil(24/7) = 4, s = 6; a_f = 25; J < 0 -> CCW
    program = "T1 D1 M6\nS1000 M3\nG00 G90 X100 Y100 Z30\nG99 G88 Z2 I-16 D2 J-30 B8 C7 L1 H200 V100 F400\nM30\n"

    def level(z: float) -> str:
        rings = " ".join(f"F({100 + r},100,{z:g})@400 CCW({100 + r},100,{z:g}; 100,100)@400" for r in (6, 12, 18, 24))
        return (f"F(100,100,{z:g})@100 {rings} CCW(125,100,{z:g}; 124.5,100)@200 "
                f"CCW(125,100,{z:g}; 100,100)@200 CCW(124,100,{z:g}; 124.5,100)@200 "
                f"R(124,100,{z + 1:g}) R(100,100,{z + 1:g})")

    assert moves(program, 4, TOOLS) == split("R(100,100,2) " + level(-8) + " " + level(-16) + " R(100,100,2)")
    full = [r for r in run(program, TOOLS).moves if r.kind == "arc" and r.line == 4]
    # the first ring is a full circle of radius 6: 360 degrees, 2*pi*6 = 37.699 mm
    assert full[0].sweep == pytest.approx(-360.0 if full[0].direction == "cw" else 360.0)
    assert full[0].length == pytest.approx(2 * 3.141592653589793 * 6)


def test_pocket_starts_a_stopped_spindle():
    program = "T2 D1 M6\nG00 G90 X0 Y0 Z10\nG99 G88 Z1 I-2 J-20 B2 F300\nM30\n"
    assert moves(program, 3, TOOLS)[0] == "M3"


def test_g210_bore_milling_provisional():
    # r = 4: rho = 12-4 = 8; 3 helix turns (12/4), J > 0 -> CW; C1 bottom circle at H default = F
    program = "T2 D1 M6\nS1000 M3\nG00 G90 X0 Y0 Z20\nG98 G210 Z2 I-10 J12 B4 C1 F300\nM30\n"
    assert moves(program, 4, TOOLS, ok=False) == split(
        "R(0,0,2) CW(8,0,2; 4,0)@300 CW(8,0,-2; 0,0)@300 CW(8,0,-6; 0,0)@300 CW(8,0,-10; 0,0)@300 "
        "CW(8,0,-10; 0,0)@300 CW(0,0,-10; 4,0)@300 R(0,0,20)")
    assert (4, "CYC009") in codes(program, TOOLS)


@pytest.mark.parametrize(("block", "code"), [
    ("G88 Z2 I-5 J5 B2", "CYC005"),              # radius 5 pocket, radius 5 tool
    ("G87 Z2 I-5 J20 K5 B2", "CYC005"),
    ("G87 Z2 I-5 J20 B2", "CYC004"),             # no K
    ("G87 Z2 I-5 J20 K10 B2 C11", "CYC004"),     # C above the tool diameter 10
    ("G87 Z2 I-5 J20 K10", "CYC004"),            # no B
    ("G87 Z2 I-5 J20 K10 B2 M3", "CYC004"),      # corner type
    ("G87 Z2 I-5 J20 K10 B2 D9", "CYC004"),      # surface below the bottom
    ("G210 Z2 I-5 J5 B2", "CYC005"),
    ("G210 Z2 I-5 J10 B0", "CYC004"),
])
def test_pocket_errors(block, code):
    program = "T1 D1 M6\nS1000 M3\nG00 Z20\n" + block + " F100\nM30\n"
    result = run(program, TOOLS)
    assert (4, code) in [(d.line, d.code) for d in result.diagnostics if d.is_error]
    assert [r for r in result.moves if r.line == 4] == []


def test_g87_taller_than_long_keeps_its_direction():
    # J10 K20, r = 4: a = 6, b = 16; the pocket axes turn by 90 degrees (not swapped, which would mirror
    # the direction): central segment along Y, the ring from (0,16) clockwise (J > 0)
    program = "T2 D1 M6\nS1000 M3\nG00 G90 X0 Y0 Z10\nG99 G87 Z1 I-1 J10 K20 B2 C6 F300\nM30\n"
    assert moves(program, 4, {"tools": {"2": {"1": {"radius": 4.0}}}}) == split(
        "R(0,0,1) F(0,0,-1)@150 F(0,-10,-1)@300 F(0,10,-1)@300 F(0,16,-1)@300 F(6,16,-1)@300 F(6,-16,-1)@300 "
        "F(-6,-16,-1)@300 F(-6,16,-1)@300 F(0,16,-1)@300 R(0,16,0) R(0,0,0) R(0,0,1)")
