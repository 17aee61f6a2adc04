"""Kinematics families: forward and inverse against hand-worked poses (fagorcnc.kinematics; seed 002
L28779-L28846 for the types, L13024-L13040 for the choice between the two solutions)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from fagorcnc.kinematics.frames import compose, make, mode_1, mode_2, mode_6, mode_345
from fagorcnc.kinematics.solve import forward, linear_for_tip, orientations, tool_direction_machine
from fagorcnc.machine import MachineError, load_machine

S30, C30 = 0.5, math.sqrt(3) / 2


def machine(kin: list, rotary=("A", "C")) -> object:
    axes = {a: {} for a in "XYZ"} | {r: {"type": "rotary", "min_limit": -360, "max_limit": 360} for r in rotary}
    return load_machine({"axes": axes, "kinematics": kin})


def close(a, b, tol=1e-9):
    return np.allclose(np.asarray(a, dtype=float), np.asarray(b, dtype=float), atol=tol)


# ------------------------------------------------------------------ rotary table AC (type 10)
def table_ac(pivots=([0, 0, 0], [0, 0, 0])):
    return machine([{"type": 10, "pivots": [list(p) for p in pivots]}]).kinematics[0]


def test_table_ac_defaults_from_the_type():
    k = table_ac()
    assert k.family == "rotary table" and k.axes == ("A", "C")
    assert [j.head for j in k.joints] == [False, False]
    assert k.joints[0].direction == (1.0, 0.0, 0.0) and k.joints[1].direction == (0.0, 0.0, 1.0)


def test_table_ac_forward_c90():
    # the table turned +90 about Z brings the part point (0, -10, 0) under the tool at machine (10, 0, 0):
    # Rz(90) (0, -10, 0) = (10, 0, 0); the tool stays along part +Z
    tip, d = forward(table_ac(), (10, 0, 0), {"A": 0.0, "C": 90.0})
    assert close(tip, (0, -10, 0)) and close(d, (0, 0, 1))


def test_table_ac_forward_a90_tool_along_part_y():
    # Rx(-90) (0, 0, 10) = (0, 10, 0) and Rx(-90) (0, 0, 1) = (0, 1, 0)
    tip, d = forward(table_ac(), (0, 0, 10), {"A": 90.0, "C": 0.0})
    assert close(tip, (0, 10, 0)) and close(d, (0, 1, 0))


def test_table_pivots_and_tool_length():
    # A line through (0, 0, -100): the tip at machine 0 is, relative to the pivot, (0, 0, 100);
    # Rx(-90) (0, 0, 100) = (0, 100, 0), back at the pivot: part (0, 100, -100)
    k = table_ac(([0, 0, -100], [50, 0, 0]))
    tip, _ = forward(k, (0, 0, 0), {"A": 90.0, "C": 0.0})
    assert close(tip, (0, 100, -100))
    # the inverse: the same tip with a 50 mm tool puts the head reference point 50 higher
    assert close(linear_for_tip(k, (0, 100, -100), {"A": 90.0, "C": 0.0}, 0.0), (0, 0, 0))
    assert close(linear_for_tip(k, (0, 100, -100), {"A": 90.0, "C": 0.0}, 50.0), (0, 0, 50))


def test_table_ac_two_solutions_and_the_choice():
    # tool tilted 30 deg toward part +Y: Rx(-30) Z = (0, sin 30, cos 30); the other solution turns C half a
    # turn: Rz(-180) Rx(30) Z = Rz(180) (0, -0.5, 0.866) = (0, 0.5, 0.866).  |A| is 30 in both: the one
    # that leaves C where it is (0) is solution 1
    sols = orientations(table_ac(), (0, S30, C30), {"A": 0.0, "C": 0.0})
    assert len(sols) == 2
    assert close([sols[0]["A"], sols[0]["C"]], [30, 0])
    assert close([sols[1]["A"], abs(sols[1]["C"])], [-30, 180])


def test_table_ac_singular_pose_keeps_c():
    # tool along the C axis (part Z): A = 0 and any C gives it; C stays where it is (37)
    sols = orientations(table_ac(), (0, 0, 1), {"A": 10.0, "C": 37.0})
    assert close([sols[0]["A"], sols[0]["C"]], [0, 37])
    assert all(abs(s["A"]) < 1e-9 for s in sols)


def test_unreachable_orientation():
    # a BC table (B about Y, C about Z) reaches every direction; an AB table reaches them too,
    # but a head whose two directions are both Z-like cannot: parallel directions are refused at load
    with pytest.raises(MachineError, match="parallel"):
        machine([{"type": 10, "directions": [[0, 0, 1], [0, 0, -1]]}])


# ------------------------------------------------------------------ spindle head ZX (type 2)
def head_zx(length=100.0):
    return machine([{"type": 2}]).kinematics[0]


def test_head_zx_default_axes():
    k = head_zx()
    assert k.axes == ("C", "A") and all(j.head for j in k.joints)


def test_head_zx_forward():
    # A = 90 turns the tool (rest: tip -> spindle = +Z) to Rx(90) Z = (0, -1, 0); the tip 100 mm from
    # the reference point: m + Rx(90) (0, 0, -100) = m + (0, 100, 0)
    k = head_zx()
    tip, d = forward(k, (1, 2, 3), {"C": 0.0, "A": 90.0}, 100.0)
    assert close(d, (0, -1, 0)) and close(tip, (1, 102, 3))
    # C = 90 turns that about Z: Rz(90) (0, -1, 0) = (1, 0, 0), the tip at m + (-100, 0, 0)
    tip, d = forward(k, (0, 0, 0), {"C": 90.0, "A": 90.0}, 100.0)
    assert close(d, (1, 0, 0)) and close(tip, (-100, 0, 0))


def test_head_zx_inverse_solution_1_turns_c_least():
    # tool along -Y: (C 0, A 90) or (C 180, A -90); solution 1 moves the main axis C least from 0
    sols = orientations(head_zx(), (0, -1, 0))
    assert close([sols[0]["C"], sols[0]["A"]], [0, 90])
    assert close([abs(sols[1]["C"]), sols[1]["A"]], [180, -90])
    for s in sols:
        assert close(tool_direction_machine(head_zx(), s), (0, -1, 0))


def test_head_singular_pose():
    # tool along Z (the C axis): A = 0, C keeps its value
    sols = orientations(head_zx(), (0, 0, 1), {"C": -45.0, "A": 5.0})
    assert close([sols[0]["C"], sols[0]["A"]], [-45, 0])


def test_head_yx_type_1():
    # B about Y main, A about X secondary: B = 90 turns Z to Ry(90) Z = (1, 0, 0)
    m = machine([{"type": 1}], rotary=("A", "B"))
    k = m.kinematics[0]
    assert k.axes == ("B", "A")
    assert close(tool_direction_machine(k, {"B": 90.0, "A": 0.0}), (1, 0, 0))
    sols = orientations(k, (1, 0, 0))
    assert close([sols[0]["B"], sols[0]["A"]], [90, 0])


def test_angular_head_needs_its_directions():
    with pytest.raises(MachineError, match="angular head"):
        machine([{"type": 5}])
    # a 45-degree (Huron) head: main C about Z, secondary about n = (0, 1, 1)/sqrt2; half a turn of the
    # secondary: rot(n, 180) Z = 2 (n.Z) n - Z = (0, 1, 1) - (0, 0, 1) = (0, 1, 0)
    m = machine([{"type": 7, "axes": ["C", "B"], "directions": [[0, 0, 1], [0, 1, 1]]}], rotary=("B", "C"))
    k = m.kinematics[0]
    assert close(tool_direction_machine(k, {"C": 0.0, "B": 180.0}), (0, 1, 0))
    # the tool along -X: Rz(90) (0, 1, 0) = (-1, 0, 0), so C = 90 with the secondary at 180
    sols = orientations(k, (-1, 0, 0))
    assert close(tool_direction_machine(k, sols[0]), (-1, 0, 0))
    assert close([sols[0]["C"], abs(sols[0]["B"])], [90, 180])


# ------------------------------------------------------------------ spindle-table AC (type 14)
def test_spindle_table_ac():
    k = machine([{"type": 14}]).kinematics[0]
    assert [j.head for j in k.joints] == [True, False]
    # head A = 90: tool (0, -1, 0) in the machine; table C = 90: in the part Rz(-90) (0, -1, 0) = (-1, 0, 0)
    _, d = forward(k, (0, 0, 0), {"A": 90.0, "C": 90.0})
    assert close(d, (-1, 0, 0))
    sols = orientations(k, (-1, 0, 0))
    assert any(close([s["A"], s["C"]], [90, 90]) for s in sols)
    for s in sols:
        assert close(forward(k, (0, 0, 0), s)[1], (-1, 0, 0))


# ------------------------------------------------------------------ three-rotary head, C axis
def test_three_rotary_head_forward():
    m = machine([{"type": 17, "axes": ["A", "B", "A2"]}], rotary=("A", "B", "A2"))
    k = m.kinematics[0]
    # A = 90 (main, about X): Rx(90) Z = (0, -1, 0); then nothing else turns
    assert close(tool_direction_machine(k, {"A": 90.0, "B": 0.0, "A2": 0.0}), (0, -1, 0))
    # B = 90 alone: Ry(90) Z = (1, 0, 0); A2 = 90 after it turns about the rest X: Ry(90) Rx(90) Z = (0, -1, 0)
    assert close(tool_direction_machine(k, {"A": 0.0, "B": 90.0, "A2": 90.0}), (0, -1, 0))
    # the inverse is solved too (tests/test_three_rotary.py): Z with every axis at 0
    assert close([orientations(k, (0, 0, 1))[0][a] for a in ("A", "B", "A2")], [0, 0, 0])


def test_c_axis_types_and_config_errors():
    m = machine([{"type": 41, "axes": ["C"]}, {"type": 43}], rotary=("C",))
    assert [k.type for k in m.kinematics] == [41, 43] and m.kinematics[1].c_axis
    with pytest.raises(MachineError, match="OEM"):
        machine([{"type": 101}])
    with pytest.raises(MachineError, match="unknown kinematics type"):
        machine([{"type": 30}])
    with pytest.raises(MachineError, match="not a rotary axis"):
        machine([{"type": 10, "axes": ["X", "C"]}])
    with pytest.raises(MachineError, match="at most 6"):
        machine([{"type": 10}] * 7)
    with pytest.raises(MachineError, match="kinid"):
        load_machine({"axes": {a: {} for a in "XYZ"} | {"A": {"type": "rotary"}, "C": {"type": "rotary"}},
                      "kinematics": [{"type": 10}], "kinid": 2})


# ------------------------------------------------------------------ #CS modes
def test_mode_1_manual_plane():
    # spec 05 §6.4.1: [MODE 1, 0,0,20, 30,0,0] = Rx(30); the plane point (60, 20, 3) is at part
    # (60, 20 cos30 - 3 sin30, 20 + 20 sin30 + 3 cos30) = (60, 15.8205, 32.5981)
    cs = make(1, (0, 0, 20), mode_1(30, 0, 0))
    r, v = compose([cs])
    assert close(v + r @ np.array([60, 20, 3]), (60, 15.8205081, 32.5980762), 1e-6)


def test_mode_1_is_intrinsic():
    # [MODE 1, 0,0,0, 90,90,0]: Rx(90) Ry(90) takes X to Rx(90) (0, 0, -1) = (0, 1, 0): X' = +Y
    assert close(mode_1(90, 90, 0)[:, 0], (0, 1, 0))


def test_mode_2_euler():
    # Rz(90) Ry(90) Rz(0): Z' = Rz(90) (1, 0, 0) = (0, 1, 0)
    assert close(mode_2(90, 90, 0)[:, 2], (0, 1, 0))


def test_modes_3_to_5_at_zero():
    assert close(mode_345(3, 0, 0, 0, 0), np.eye(3))
    assert close(mode_345(4, 0, 0, 0, 0), np.column_stack([(1, 0, 0), (0, 0, 1), (0, -1, 0)]))
    assert close(mode_345(5, 0, 0, 0, 0), np.column_stack([(0, 1, 0), (0, 0, 1), (1, 0, 0)]))


def test_mode_6_first_and_second():
    n = np.array([0, -S30, C30])   # tool turned 30 deg about X
    r = mode_6(n, 0, "FIRST")
    assert close(r[:, 2], n) and close(r[:, 0], (1, 0, 0))
    r = mode_6(n, 0, "SECOND")
    assert close(r[:, 1], (0, C30, S30))


def test_composition_order():
    # two systems: T1(T2(p)); T1 = shift (10, 0, 0), T2 = Rz(90): p = (1, 0, 0) -> (10, 1, 0)
    r, v = compose([make(1, (10, 0, 0), np.eye(3)), make(1, (0, 0, 0), mode_1(0, 0, 90))])
    assert close(v + r @ np.array([1, 0, 0]), (10, 1, 0))
