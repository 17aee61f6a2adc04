"""G74 under a transformation (seed 002 L2357-L2406, L11867, L13320): refused where the manual forbids it
(#ANGAX; under #RTCP the axes outside it), otherwise the joints go to the reference point and the
position in the active frame is worked out from them again.  Numbers worked out by hand."""

from __future__ import annotations

import math

import pytest

import fagorcnc

C30, S30 = math.cos(math.radians(30)), 0.5
AXES3 = {a: {"min_limit": -1000, "max_limit": 1000, "home": 100.0 if a == "Z" else 0.0} for a in "XYZ"}
HEAD_B = {   # type 1: B about Y (main), A about X; tool 100 mm; a U axis outside the kinematics
    "axes": AXES3 | {"A": {"type": "rotary", "min_limit": -120, "max_limit": 120},
                     "B": {"type": "rotary", "min_limit": -120, "max_limit": 120},
                     "U": {"min_limit": -100, "max_limit": 100, "home": 50.0}},
    "kinematics": [{"type": 1}],
    "tools": {"1": {"1": {"length": 100.0}}},
}


def by_line(r) -> dict[int, list]:
    out: dict[int, list] = {}
    for m in r.moves:
        if m.kind in ("linear", "rapid", "arc"):
            out.setdefault(m.src.line, []).append(m)
    return out


def close(d: dict, **want) -> bool:
    return all(d[k] == pytest.approx(v, abs=1e-6) for k, v in want.items())


def test_home_inside_an_inclined_plane():
    # plane Rx(30): (10, 20, 30) -> joints (10, 20 cos30 - 30 sin30, 20 sin30 + 30 cos30) = (10, 2.3205,
    # 35.9808).  G74 Z1: Z to its reference point 100, X and Y stay.  Back in the plane: Rx(-30)
    # (10, 2.3205, 100) = (10, 2.3205 cos30 + 100 sin30, -2.3205 sin30 + 100 cos30) = (10, 52.0096, 85.4423);
    # the G91 X5 after it runs along X' = X from the joints where the homing left them
    text = ("#CS ON [1] [MODE 1, 0,0,0, 30,0,0]\nG0 X10 Y20 Z30\nG74 Z1\nG1 G91 X5 F100\nG90\n"
            "P1=V.A.ATIPPOS.Y\nP2=V.A.ATIPPOS.Z\n#CS OFF\nM30\n")
    r = fagorcnc.simulate(text, {"axes": AXES3})
    assert r.ok, r.diagnostics
    m = by_line(r)
    y = 20 * C30 - 30 * S30
    assert close(m[3][0].start, X=10, Y=y, Z=20 * S30 + 30 * C30) and close(m[3][0].end, X=10, Y=y, Z=100)
    assert m[3][0].frame is None   # a joint move, not transformed again
    assert close(m[4][-1].start, X=10, Y=y, Z=100) and close(m[4][-1].end, X=15, Y=y, Z=100)
    assert r.state.param(1) == pytest.approx(y * C30 + 100 * S30)
    assert r.state.param(2) == pytest.approx(-y * S30 + 100 * C30)


def test_home_of_an_rtcp_axis():
    # B30 with the tip at (10, 0, 0): m = tip + 100 (sin30, 0, cos30) = (60, 0, 86.6025).  G74 B1 turns B
    # to 0 with the linear axes still: the tip is now m - 100 Z = (60, 0, -13.3975); G1 X20 keeps that
    # tip height: m = (20, 0, 86.6025)
    text = "T1 D1 M6\n#RTCP ON\nG1 X10 Y0 Z0 B30 F1000\nG74 B1\nG1 X20\n#RTCP OFF\nM30\n"
    r = fagorcnc.simulate(text, HEAD_B)
    assert r.ok, r.diagnostics
    m = by_line(r)
    assert close(m[4][0].start, X=60, Z=100 * C30, B=30) and close(m[4][0].end, X=60, Z=100 * C30, B=0)
    assert close(m[5][-1].end, X=20, Y=0, Z=100 * C30, B=0)


def test_home_in_order_under_a_cylinder():
    # #CYL [Y,B,Z20]: B31.416 developed = 90 deg.  G74 Z1 B2: Z to 100 first, then B to 0 (two moves);
    # then B10 = 10 / 20 rad = 28.6479 deg from there
    text = "#CYL [Y,B,Z20]\nG1 Y10 B31.416 F100\nG74 Z1 B2\nG1 B10\n#CYL OFF\nM30\n"
    machine = {"axes": AXES3 | {"B": {"type": "rotary", "min_limit": -9999, "max_limit": 9999}}}
    r = fagorcnc.simulate(text, machine)
    assert r.ok, r.diagnostics
    m = by_line(r)
    assert len(m[3]) == 2
    assert close(m[3][0].end, Z=100, B=math.degrees(31.416 / 20)) and close(m[3][1].end, Z=100, B=0)
    assert close(m[4][-1].end, B=math.degrees(10 / 20), Z=100)


def test_refused_where_the_manual_forbids():
    # L13320: under #RTCP, not the axes outside it (U); L11867: not with #ANGAX (tests/test_angax.py)
    r = fagorcnc.simulate("#RTCP ON\nG74 U1\nM30\n", HEAD_B)
    assert [d.code for d in r.diagnostics if d.severity == "error"] == ["KIN042"]
    assert not [m for m in r.moves if m.kind == "rapid"]   # nothing moved


def test_face_homes_its_radial_axis_but_not_its_c_axis():
    # #FACE [X,C]: X10 C10 is r = 14.1421 at 45 deg; G74 X1 puts X (the radius) at 0, C stays at 45
    lathe = {"axes": {"X": {}, "Z": {}, "C": {"type": "rotary", "min_limit": -9999, "max_limit": 9999}}}
    r = fagorcnc.simulate("#FACE [X,C]\nG1 X10 C10 F100\nG74 X1\n#FACE OFF\nM30\n", lathe)
    assert r.ok, r.diagnostics
    home = by_line(r)[3]
    assert len(home) == 1 and close(home[0].start, X=math.hypot(10, 10), C=45) and close(home[0].end, X=0, C=45)
    r = fagorcnc.simulate("#FACE [X,C]\nG1 X10 C10 F100\nG74 C1\nM30\n", lathe)
    assert [d.code for d in r.diagnostics if d.severity == "error"] == ["KIN073"]
