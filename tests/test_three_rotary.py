"""Three-rotary orthogonal heads (MPK.TYPE 17-24, seed 002 L28831-L28845): the inverse kinematics, the
choice between its solutions, the singular and unreachable poses, #TOOL ORI and #RTCP on such a head.
Numbers worked out by hand; rotations right-hand rule, ``H = R1 R2 R3`` (main joint carries the others)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import fagorcnc
from fagorcnc.kinematics.solve import KinematicsError, forward, orientations, tool_direction_machine
from fagorcnc.machine import MachineError, load_machine

S30, C30 = 0.5, math.sqrt(3) / 2
AXES3 = {a: {"min_limit": -1000, "max_limit": 1000} for a in "XYZ"}


def machine(kin: dict, rotary=("A", "B", "C")):
    axes = AXES3 | {r: {"type": "rotary", "min_limit": -360, "max_limit": 360} for r in rotary}
    return {"axes": axes, "kinematics": [kin], "tools": {"1": {"1": {"length": 100.0}}}}


def kin_of(kin: dict, rotary=("A", "B", "C")):
    return load_machine(machine(kin, rotary)).kinematics[0]


def close(a, b, tol=1e-9):
    return np.allclose(np.asarray(a, dtype=float), np.asarray(b, dtype=float), atol=tol)


def test_aba_main_axis_stays_at_zero_and_the_two_solutions():
    # type 17 ABA (A about X, B about Y, A1 about X).  The last two reach every direction with the
    # main A at 0: Ry(B) Rx(A1) Z = (cos A1 sin B, -sin A1, cos A1 cos B).  v = (sin30, 0, cos30):
    # A1 = 0, B = 30, or A1 = 180, B = -150 (Rx(180) Z = -Z, Ry(-150) (-Z) = (sin150... ) = (0.5, 0, 0.866))
    k = kin_of({"type": 17, "axes": ["A", "B", "A1"]}, ("A", "B", "A1"))
    sols = orientations(k, (S30, 0, C30))
    assert len(sols) == 2
    assert close([sols[0][a] for a in ("A", "B", "A1")], [0, 30, 0])
    assert close([sols[1][a] for a in ("A", "B", "A1")], [0, -150, 180])
    for s in sols:
        assert close(tool_direction_machine(k, s), (S30, 0, C30))


def test_cab_inverse():
    # type 23 CAB (C about Z main, A about X, B about Y): C = 0, then Rx(A) Ry(B) Z =
    # (sin B, -sin A cos B, cos A cos B) = (0, -0.5, 0.866): B = 0, A = 30; or B = 180, A = -150
    k = kin_of({"type": 23})
    sols = orientations(k, (0, -S30, C30))
    assert close([sols[0][a] for a in "CAB"], [0, 30, 0])
    assert close([sols[1][a] for a in "CAB"], [0, -150, 180])


@pytest.mark.parametrize("kind", range(17, 25))
def test_every_type_round_trip(kind):
    # forward(inverse(v)) = v for a spread of directions (the default axes of each type)
    from fagorcnc.config.kinematics import TYPES

    names = list(TYPES[kind][1])   # the rotary axes named after the type (ABA ... CBA)
    if names[2] == names[0]:
        names[2] += "1"   # ABA: the third axis is another A (A1)
    k = kin_of({"type": kind, "axes": names}, ("A", "B", "C", "A1", "B1"))
    rng = np.random.default_rng(kind)
    for v in rng.normal(size=(200, 3)):
        v = v / np.linalg.norm(v)
        sols = orientations(k, v)
        assert sols and abs(sols[0][k.axes[0]]) < 1e-12   # the tool's Z is reached with the main at 0
        for s in sols:
            assert close(tool_direction_machine(k, s), v)


def test_main_axis_turns_when_the_last_two_cannot_reach():
    # type 18 ACA with the tool leaning 36.87 deg from Z toward X: t0 = (0.6, 0, 0.8).  Rx(A1) t0 keeps
    # its X part 0.6, so Rz(C) Rx(A1) t0 has Z part at most 0.8: v = Z needs the main A.  Z . Rx(-A) Z
    # = cos A = 0.8 -> A = +-36.8699 (as little from 0 either way: both are given, + first).
    # A = 36.8699: Rz(C) t0 must be Rx(-A) Z = (0, sin A, cos A) = (0, 0.6, 0.8): C = 90, A1 = 0.
    k = kin_of({"type": 18, "axes": ["A", "C", "A1"], "tool_direction": [0.6, 0, 0.8]}, ("A", "C", "A1"))
    sols = orientations(k, (0, 0, 1))
    a = math.degrees(math.acos(0.8))
    assert close([sols[0][x] for x in ("A", "C", "A1")], [a, 90, 0])
    assert close([sols[1][x] for x in ("A", "C", "A1")], [-a, -90, 0])
    for s in sols:
        assert close(tool_direction_machine(k, s), (0, 0, 1))


def test_singular_pose_keeps_the_free_axis():
    # ABA, v = Y: A = 0, Rx(A1) Z = Y at A1 = -90, and Ry(B) leaves Y where it is: B is free and keeps
    # where it stands (the singular pose, the tool along the secondary axis)
    k = kin_of({"type": 17, "axes": ["A", "B", "A1"]}, ("A", "B", "A1"))
    sols = orientations(k, (0, 1, 0), {"A": 0.0, "B": 12.5, "A1": 0.0})
    assert close([sols[0][a] for a in ("A", "B", "A1")], [0, 12.5, -90])


def test_unreachable_direction_is_refused():
    # a Huron-like ACA: C about Z, the middle axis at 45 deg between X and Z, the third about Z; the
    # middle turns Z over a 45 deg cone (from Z to X), so nothing below the XY plane is reached
    k = kin_of({"type": 18, "axes": ["C", "B", "C1"], "directions": [[0, 0, 1], [1, 0, 1], [0, 0, 1]]},
               ("B", "C", "C1"))
    with pytest.raises(KinematicsError, match="no position of C, B and C1"):
        orientations(k, (0, 0, -1))
    # X is the cone's rim: B = 180 (Rot((1,0,1)/sqrt2, 180) Z = X), C = 0
    s = orientations(k, (1, 0, 0))[0]
    assert close(tool_direction_machine(k, s), (1, 0, 0)) and abs(s["C"]) < 1e-9


def test_parallel_secondary_and_third_refused():
    with pytest.raises(MachineError, match="secondary and third"):
        load_machine(machine({"type": 17, "axes": ["A", "B", "A1"], "directions": [[1, 0, 0], [0, 1, 0],
                                                                                   [0, 1, 0]]},
                             ("A", "B", "A1")))


def test_tool_ori_on_a_bca_head():
    # type 21 BCA: B (about Y) main, C (Z) secondary, A (X) third.  Plane Rx(30): Z' = (0, -0.5, 0.866).
    # B = 0 (the last two reach it); Rz(C) Rx(A) Z = (sin A sin C, -sin A cos C, cos A): A = 30, C = 0
    # (solution 1, C least from 0) or A = -30, C = 180 (solution 2).
    m = machine({"type": 21})
    text = ("#CS ON [1] [MODE 1, 0, 0, 0, 30, 0, 0]\nP1=V.G.TOOLORIF1\nP2=V.G.TOOLORIS1\nP3=V.G.TOOLORIF2\n"
            "P4=V.G.TOOLORIS2\n#TOOL ORI\nG0 X10 Y0 Z50\n#CS OFF\nM30\n")
    r = fagorcnc.simulate(text, m)
    assert r.ok, r.diagnostics
    assert [round(r.state.param(i), 9) for i in (1, 2, 3, 4)] == [0, 0, 0, 180]
    last = [x for x in r.moves if x.kind in ("linear", "rapid") and x.src.line == 7][-1]
    assert last.end["A"] == pytest.approx(30) and last.end["B"] == pytest.approx(0)
    assert last.end["C"] == pytest.approx(0)


def test_rtcp_on_a_bca_head_keeps_the_tip():
    # type 21 BCA, tool 100: the head reference point is m = tip + 100 Ry(B) Rz(C) Rx(A) Z.
    # A30: Rx(30) Z = (0, -0.5, 0.866) -> m = (10, -50, 86.6025); then C90: Rz(90) (0, -0.5, 0.866) =
    # (0.5, 0, 0.866) -> m = (60, 0, 86.6025); the tip stays at (10, 0, 0) all the way
    m = machine({"type": 21})
    text = "T1 D1 M6\n#RTCP ON\nG1 X10 Y0 Z0 A0 B0 C0 F1000\nA30\nC90\n#RTCP OFF\nM30\n"
    r = fagorcnc.simulate(text, m)
    assert r.ok, r.diagnostics
    by_line: dict[int, list] = {}
    for x in r.moves:
        if x.kind in ("linear", "rapid", "arc"):
            by_line.setdefault(x.src.line, []).append(x)
    e4, e5 = by_line[4][-1].end, by_line[5][-1].end
    assert close([e4["X"], e4["Y"], e4["Z"]], [10, -50, 100 * C30], 1e-6)
    assert close([e5["X"], e5["Y"], e5["Z"]], [60, 0, 100 * C30], 1e-6)
    kin = r.machine.kinematics[0]
    for x in by_line[4] + by_line[5]:
        tip, _ = forward(kin, (x.end["X"], x.end["Y"], x.end["Z"]), {a: x.end[a] for a in "ABC"}, 100.0)
        assert math.dist(tip, (10, 0, 0)) < 1e-9
