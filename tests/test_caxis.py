"""C axis: #FACE and #CYL computed (seed 002 ch. 14, L11664-L11810; spec 05 §3.2-§3.3)."""

from __future__ import annotations

import math

import pytest

import fagorcnc

LATHE = {"axes": {"X": {}, "Z": {}, "C": {"type": "rotary", "min_limit": -9999, "max_limit": 9999}},
         "tools": {"1": {"1": {"radius": 5.0}}}}
MILL_B = {"axes": {"X": {}, "Y": {}, "Z": {}, "B": {"type": "rotary", "min_limit": -9999, "max_limit": 9999}}}


def moves(r):
    return [m for m in r.moves if m.kind in ("linear", "rapid", "arc")]


def last_of(r) -> dict[int, object]:
    out = {}
    for m in moves(r):
        out[m.src.line] = m
    return out


def codes(r):
    return [d.code for d in r.diagnostics]


def test_face_polar_transformation():
    # r = sqrt(x² + c²) on X, theta = atan2(c, x) on C.  (0, -90): r 90, theta -90.
    # (37.5, -40): r = 54.8293, theta = -46.8476.  (-37.5, 0): r 37.5, theta 180 (followed, not -180)
    r = fagorcnc.simulate("#FACE [X,C]\nG90 X0 C-90\nG01 C-40 F600\nX37.5\nC0\nX-37.5\n#FACE OFF\nM30\n", LATHE)
    assert r.ok, r.diagnostics
    m = last_of(r)
    assert m[2].end["X"] == pytest.approx(90) and m[2].end["C"] == pytest.approx(-90)
    assert m[4].end["X"] == pytest.approx(math.hypot(37.5, 40)) and m[4].end["C"] == pytest.approx(
        math.degrees(math.atan2(-40, 37.5)))
    assert m[6].end["X"] == pytest.approx(37.5) and m[6].end["C"] == pytest.approx(180)
    # between the joint points the tool stays on the programmed line X37.5 (C from -40 to 0)
    for p in (p for p in moves(r) if p.src.line == 5):
        x = p.end["X"] * math.cos(math.radians(p.end["C"]))
        assert x == pytest.approx(37.5, abs=1e-9)
        mx = (p.start["X"] * math.cos(math.radians(p.start["C"])) + x) / 2
        assert abs(mx - 37.5) < 0.01   # the chord between joint points stays near the line


def test_face_manual_example_with_compensation():
    # seed 002 L11713-L11730 without the G36/G37/G38 corner aids (their G42 combination is refused
    # by the compensation stage, also in the XY plane): G42 with R5 in the X-C plane, a G03 arc
    text = ("T1 D1 M6\n#FACE [X,C]\nG90 X0 C-90\nG01 G42 C-40 F600\nX37.5\nC0\nX12.56 C38.2\n"
            "G03 X-12.58 C38.2 R15\nG01 X-37.5 C0\nC-40\nX0\nG40 C-90\n#FACE OFF\nG0 C0\nM30\n")
    r = fagorcnc.simulate(text, LATHE)
    assert r.ok, r.diagnostics
    m = last_of(r)
    # back at (0, -90) after a full turn about the centre: C at -90 + 360
    assert m[12].end["X"] == pytest.approx(90) and m[12].end["C"] == pytest.approx(270)
    # every joint point is the polar image of a point of the compensated contour: on the arc block the
    # tool centre is 15 - 5 = 10 from the arc centre (G42 on a G03 arc: the tool inside)
    arc = [p for p in moves(r) if p.src.line == 8]
    assert len(arc) > 2
    # after #FACE OFF, C0 is a quarter turn on from the C axis' real 270
    assert m[14].start["C"] == pytest.approx(270) and m[14].end["C"] == pytest.approx(360)
    assert r.state.modes["plane"] == 17 and r.state.modes["feed"] == 94


def test_cylinder_manual_example():
    # seed 002 L11789-L11810, R = 20: theta = s / 20 * 180/pi; B125.664 -> 360.0008 deg
    # (the G42 of the example left out: with radius 0 it changes nothing; see the face test)
    text = ("#CYL [Y,B,Z20]\nG90 G01 Y70 B0 F500\nG91 Z-4\nG90 B15.708\nG36 I3\nY130 B31.416\nG36 I3\n"
            "B39.270\nG36 I3\nY190 B54.978\nG36 I3\nB70.686\nG36 I3\nY130 B86.394\nG36 I3\nB94.248\nG36 I3\n"
            "Y70 B109.956\nG36 I3\nB125.664\nG91 Z4\n#CYL OFF\nM30\n")
    r = fagorcnc.simulate(text, MILL_B)
    assert r.ok, r.diagnostics
    m = last_of(r)
    assert m[2].end["Y"] == pytest.approx(70) and m[2].end["B"] == pytest.approx(0)
    assert m[20].end["B"] == pytest.approx(math.degrees(125.664 / 20))
    assert m[21].end["Z"] == pytest.approx(0)
    # a straight move of the developed plane is a straight move of Y and B: one record
    line = [p for p in moves(r) if p.src.line == 20]
    assert line[-1].end["B"] == pytest.approx(360.00084, abs=1e-4)


def test_cylinder_g01_with_b_alone_is_one_line():
    r = fagorcnc.simulate("#CYL [Y,B,Z20]\nG1 B31.416 F100\nM30\n", MILL_B)
    ms = moves(r)
    assert len(ms) == 1 and ms[0].end["B"] == pytest.approx(90, abs=1e-3)


@pytest.mark.parametrize(("text", "code"), [
    ("#CYL [Y,B,Z]\n", "KIN030"),
    ("#CYL [Y,B]\n", "KIN030"),
    ("#CYL [Y,B,Z0]\n", "KIN071"),   # radius 0 needs the rotation line (tests/test_cyl_radius.py)
    ("#CYL [Y,B,Z-5]\n", "KIN070"),
    ("#FACE [X,Y]\n", "KIN032"),
    ("#FACE [X,C]\n", "KIN032"),
    ("#CYL [Y,B,Z20]\n#FACE [X,B]\n", "KIN034"),
    ("#FACE [X,B][1]\n", "KIN033"),
    ("G92 B10\n#CYL [Y,B,Z20]\n", "KIN035"),
])
def test_caxis_errors(text, code):
    assert codes(fagorcnc.simulate(text + "M30\n", MILL_B)) == [code]
