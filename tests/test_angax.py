"""#ANGAX: the angular transformation of an inclined axis (seed 002 ch. 15; spec 05 §4)."""

from __future__ import annotations

import math

import pytest

import fagorcnc
from fagorcnc.machine import MachineError, load_machine

LATHE = {"axes": {"X": {}, "Y": {}, "Z": {}},
         "angular_axes": [{"angular_axis": "X", "orthogonal_axis": "Z", "angle": 30}]}
T30, C30 = math.tan(math.radians(30)), math.cos(math.radians(30))


def moves(r):
    return [m for m in r.moves if m.kind in ("linear", "rapid", "arc")]


def codes(r):
    return [d.code for d in r.diagnostics]


def test_cartesian_to_real_axes():
    # x' = x / cos30, z_r = z - x tan30: (10, 0) -> (11.5470, -5.7735); (10, 20) -> (11.5470, 14.2265)
    r = fagorcnc.simulate("#ANGAX ON [1]\nG1 X10 Z0 F100\nZ20\n#ANGAX OFF\nG1 X0\nM30\n", LATHE)
    assert r.ok, r.diagnostics
    a, b, c = moves(r)
    assert a.end["X"] == pytest.approx(10 / C30) and a.end["Z"] == pytest.approx(-10 * T30)
    assert b.end["X"] == pytest.approx(10 / C30) and b.end["Z"] == pytest.approx(20 - 10 * T30)
    assert a.frame is not None and a.frame.description == "#ANGAX"
    # off: the real axes again, from where the slides stand
    assert c.frame is None and c.start["X"] == pytest.approx(10 / C30) and c.end["X"] == 0


def test_suspended_moves_only_the_angular_slide():
    # seed 002 L11939: suspended, a block with only X moves only X': x' = 20 / cos30, z_r stays
    # at -10 tan30; with Z in the block the normal transformation: (20, 0) -> (23.0940, -11.5470)
    r = fagorcnc.simulate("#ANGAX ON [1]\nG1 X10 Z0 F100\n#ANGAX SUSP\nP1=V.G.ANGAXST\nG1 X20\nX20 Z0\n"
                          "#ANGAX ON [1]\nP2=V.G.ANGIDST[1]\nM30\n", LATHE)
    assert r.ok, r.diagnostics
    _a, b, c = moves(r)
    assert b.end["X"] == pytest.approx(20 / C30) and b.end["Z"] == pytest.approx(-10 * T30)
    assert c.end["X"] == pytest.approx(20 / C30) and c.end["Z"] == pytest.approx(-20 * T30)
    assert r.state.param(1) == 2 and r.state.param(2) == 1


def test_variables_and_errors():
    r = fagorcnc.simulate("P1=V.MPK.NANG\nP2=V.MPK.ANGAXNA[1]\nP3=V.MPK.ORTAXNA[1]\nP4=V.MPK.ANGANTR[1]\n"
                          "P5=V.G.ANGAXST\nM30\n", LATHE)
    assert [r.state.param(i) for i in range(1, 6)] == [1, 1, 3, 30, 0]   # X logical 1, Z logical 3
    assert codes(fagorcnc.simulate("#ANGAX ON\nM30\n", LATHE)) == ["KIN040"]
    assert codes(fagorcnc.simulate("#ANGAX ON [2]\nM30\n", LATHE)) == ["KIN040"]
    assert codes(fagorcnc.simulate("#ANGAX ON [1]\nG74 X1\nM30\n", LATHE)) == ["KIN042"]
    with pytest.raises(MachineError, match="linear"):
        load_machine({"axes": {"X": {}, "C": {"type": "rotary"}},
                      "angular_axes": [{"angular_axis": "X", "orthogonal_axis": "C", "angle": 30}]})
    with pytest.raises(MachineError, match="OFFANGAX"):
        load_machine({**LATHE, "angular_axes": [{**LATHE["angular_axes"][0], "offset": 5}]})


def test_arc_runs_as_lines_of_the_real_axes():
    # a G02 in the Cartesian Z-X plane (G18) is an ellipse of the real axes: joint-space lines whose
    # points are on the programmed circle once turned back into Cartesian coordinates
    r = fagorcnc.simulate("G18\n#ANGAX ON [1]\nG1 X0 Z10 F100\nG2 X10 Z0 R10\nM30\n", LATHE)
    assert r.ok, r.diagnostics
    pieces = [m for m in moves(r) if m.src.line == 4]
    assert len(pieces) > 2
    for m in pieces:
        x = m.end["X"] * C30
        z = m.end["Z"] + m.end["X"] * math.sin(math.radians(30))
        # G02 in G18 (Z abscissa, X ordinate) from (Z10, X0) to (Z0, X10) with R10: centre (Z10, X10)
        assert math.hypot(x - 10, z - 10) == pytest.approx(10, abs=1e-9)
