"""#CYL with radius 0: the cylinder's radius is the tool tip's distance to the rotation line (seed 002
L11748), taken when #CYL is given; the line from the machine file's type-43 kinematics."""

from __future__ import annotations

import math

import pytest

import fagorcnc

AXES = {"X": {}, "Y": {}, "Z": {}, "B": {"type": "rotary", "min_limit": -9999, "max_limit": 9999}}
# B turns about the line through (0, 0, -50) along Y
MILL_B = {"axes": AXES, "kinematics": [{"type": 43, "axes": ["B"], "directions": [[0, 1, 0]],
                                        "pivots": [[0, 0, -50]]}],
          "tools": {"1": {"1": {"length": 10.0}}}}


def codes(r):
    return [d.code for d in r.diagnostics if d.severity == "error"]


def b_of(r, line: int) -> float:
    return [m for m in r.moves if m.kind in ("linear", "rapid") and m.src.line == line][-1].end["B"]


def test_radius_from_the_tool_tip():
    # the tip at X12 Z-34 (the 10 mm tool: the axes show Z-24), 12 and 16 from the line: radius 20.
    # B31.416 developed = 31.416 / 20 rad = 90.0002 deg; after G91 Z-4 the radius stays 20 (taken at
    # the activation, as the manual's example keeps its radius while Z moves): B62.832 -> 180.0004 deg
    text = "T1 D1 M6\nG0 X12 Y0 Z-34 B0\n#CYL [Y,B,Z0]\nG1 B31.416 F100\nG91 Z-4\nG90 B62.832\n#CYL OFF\nM30\n"
    r = fagorcnc.simulate(text, MILL_B)
    assert r.ok, r.diagnostics
    assert b_of(r, 4) == pytest.approx(math.degrees(31.416 / 20))
    assert b_of(r, 6) == pytest.approx(math.degrees(62.832 / 20))


def test_kinematics_number_picks_the_line():
    # two type-43 kinematics: [2] turns B about the line through (0, 0, 0) along Y; tip at X0 Z-30 -> R 30
    m = dict(MILL_B, kinematics=[MILL_B["kinematics"][0], {"type": 43, "axes": ["B"], "directions": [[0, 1, 0]]}])
    text = "T1 D1 M6\nG0 X0 Y0 Z-30 B0\n#CYL [Y,B,Z0][2]\nG1 B30 F100\n#CYL OFF\nM30\n"
    r = fagorcnc.simulate(text, m)
    assert r.ok, r.diagnostics
    assert b_of(r, 4) == pytest.approx(math.degrees(30 / 30))
    # without the number, the first type-43 kinematics of B: the line through Z-50, R = 20
    r = fagorcnc.simulate(text.replace("[2]", ""), m)
    assert b_of(r, 4) == pytest.approx(math.degrees(30 / 20))


@pytest.mark.parametrize(("machine", "text", "code"), [
    # no kinematics gives the line
    ({"axes": AXES}, "#CYL [Y,B,Z0]\n", "KIN071"),
    # a type-43 kinematics of another axis
    ({"axes": AXES | {"C": {"type": "rotary"}}, "kinematics": [{"type": 43}]}, "#CYL [Y,B,Z0][1]\n", "KIN071"),
    # the tool tip on the rotation line (X0 Z-50 with no tool)
    (dict(MILL_B, tools={}), "G0 X0 Z-50\n#CYL [Y,B,Z0]\n", "KIN072"),
    (MILL_B, "#CYL [Y,B,Z-20]\n", "KIN070"),
])
def test_refusals(machine, text, code):
    r = fagorcnc.simulate(text + "M30\n", machine)
    assert codes(r) == [code]
