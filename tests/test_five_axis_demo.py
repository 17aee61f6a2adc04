"""The shipped 5-axis demos on machines/five_axis_ac.toml (issue 24 "done when"): the tool tip lands where
hand computation says, the joints stay within their limits on the sampled trajectory, and the cycle
time comes from the joint-space plan."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import fagorcnc

ROOT = Path(__file__).resolve().parent.parent
MACHINE = ROOT / "machines" / "five_axis_ac.toml"
C30, S30 = math.cos(math.radians(30)), 0.5
C20, S20 = math.cos(math.radians(20)), math.sin(math.radians(20))


def by_block(r) -> dict[int, list]:
    """The moves of each block, by its N number."""
    out: dict[int, list] = {}
    for m in r.moves:
        if m.kind in ("linear", "rapid", "arc"):
            out.setdefault(int(m.src.text.split()[0][1:]), []).append(m)
    return out


def near(d: dict, **want) -> bool:
    return all(d[k] == pytest.approx(v, abs=1e-4) for k, v in want.items())


def within_limits(r) -> None:
    traj = r.trajectory()
    for name, axis in r.machine.axes.items():
        pos = np.asarray(traj.position[name])
        assert pos.min() >= axis.min_limit - 1e-6 and pos.max() <= axis.max_limit + 1e-6, name


@pytest.fixture(scope="module")
def tilted():
    return fagorcnc.simulate(ROOT / "programs" / "five_axis" / "tilted_plane.nc", MACHINE)


@pytest.fixture(scope="module")
def rtcp():
    return fagorcnc.simulate(ROOT / "programs" / "five_axis" / "rtcp_table.nc", MACHINE)


def test_tilted_plane_holes_and_slot(tilted):
    r = tilted
    assert r.ok and not r.diagnostics, r.diagnostics
    moves = by_block(r)
    # #TOOL ORI: the table at A -30 makes the plane Rx(30) at (0, 0, 20) horizontal.  Its zero goes to
    # Rx(-30) (0, 0, 120) about the A line (0, 0, -100): (0, 120 sin30, 120 cos30 - 100) = (0, 60, 3.9230);
    # its X', Y', Z' become X, Y, Z.  Plane point (x, y, z) -> machine (x, 60 + y, 3.9230 + z) + tool length.
    z0 = 120 * C30 - 100
    # hole 1 over (60, 20, 3) with the 80 mm drill, down to plane Z -10
    assert near(moves[60][-1].end, X=60, Y=80, Z=z0 + 3 + 80, A=-30, C=0)
    assert near(moves[70][-1].end, X=60, Y=80, Z=z0 - 10 + 80)
    assert near(moves[100][-1].end, X=120, Y=80, Z=z0 - 10 + 80)
    # the slot: G42 with R3 puts the tool centre at plane Y 57, plane Z -2, with the 60 mm end mill
    assert near(moves[180][-1].start, X=20, Y=60 + 57, Z=z0 - 2 + 60, A=-30)
    assert near(moves[180][-1].end, X=100, Y=60 + 57, Z=z0 - 2 + 60)
    within_limits(r)
    assert r.cycle_time > 0


def test_rtcp_program_tip_follows(rtcp):
    r = rtcp
    assert r.ok and not r.diagnostics, r.diagnostics
    moves = by_block(r)
    # the table turns the part point x to T_A(T_C(x)) about the lines through (0, 0, -100); the head
    # reference point is the tip plus 60 (tool length) on Z.
    # N80: tip (40, 0, 5) with A -20: Rx(-20) (40, 0, 105) = (40, 105 sin20, 105 cos20) -> (40, 35.9121, -1.3315)
    assert near(moves[80][-1].end, X=40, Y=105 * S20, Z=105 * C20 - 100 + 60, A=-20, C=0)
    # N90: C 90 first: Rz(90) (40, 0, 105) = (0, 40, 105); then Rx(-20): (0, 40 cos20 + 105 sin20,
    # -40 sin20 + 105 cos20) = (0, 73.4998, 84.9872) -> Z 84.9872 - 100 + 60
    assert near(moves[90][-1].end, X=0, Y=40 * C20 + 105 * S20, Z=-40 * S20 + 105 * C20 - 40, A=-20, C=90)
    assert len(moves[90]) > 2   # the table turns: joint-space lines
    # N100: tip (0, 40, 5), A 0, C 180: Rz(180) (0, 40, 105) = (0, -40, 105) -> (0, -40, 5 + 60)
    assert near(moves[100][-1].end, X=0, Y=-40, Z=65, A=0, C=180)
    # every joint point of N90 keeps the tip on the part point (40, 0, 5)
    from fagorcnc.kinematics.solve import forward

    kin = r.machine.kinematics[0]
    for m in moves[90]:
        tip, _ = forward(kin, (m.end["X"], m.end["Y"], m.end["Z"]), {"A": m.end["A"], "C": m.end["C"]}, 60.0)
        assert math.dist(tip, (40, 0, 5)) < 1e-9
    within_limits(r)


def test_cycle_time_is_the_joint_space_plan(rtcp):
    # the turn N90 alone: C turns 90 deg at most 10800 deg/min while X, Y, Z follow the tip's circle of
    # radius 40 (and its tilt): it cannot take less than 90 / (10800/60) = 0.5 s
    segs = [s for s in rtcp.segments()
            if getattr(s, "record", None) is not None and s.record.src.text.startswith("N90 ")]
    assert sum(s.duration for s in segs) >= 0.5
    assert rtcp.cycle_time == pytest.approx(sum(s.duration for s in rtcp.segments()), rel=1e-6)


@pytest.mark.parametrize("name", ["tilted_plane.nc", "rtcp_table.nc"])
def test_demos_pass_check(name):
    # `fagorcnc check --machine machines/five_axis_ac.toml programs/five_axis/...`: the streamed
    # verification (PLN100 envelope of the planned path included) agrees with simulate()
    from fagorcnc.commands.check import check_file

    path = ROOT / "programs" / "five_axis" / name
    report = check_file(path, MACHINE)
    result = fagorcnc.simulate(path, MACHINE)
    assert report.verdict() == "pass" and not report.diagnostics, report.diagnostics
    assert report.cycle_time == pytest.approx(result.cycle_time, rel=1e-9)


def test_sampled_tool_tip_stays_on_the_part_point(rtcp):
    # the 1 ms samples of N90 (the table turns C 0 -> 90 at A -20): the tip, through the forward
    # kinematics, stays at the part point (40, 0, 5) within the joint-space tolerance
    from fagorcnc.kinematics.tip import tool_tip

    traj = rtcp.trajectory()
    tip = tool_tip(traj, rtcp.machine.kinematics[0], 60.0)
    line = next(m.src.line for m in rtcp.moves if m.src.text.startswith("N90 "))
    sel = np.asarray(traj.line) == line
    assert sel.sum() > 100
    dist = np.sqrt((tip["X"][sel] - 40) ** 2 + tip["Y"][sel] ** 2 + (tip["Z"][sel] - 5) ** 2)
    assert dist.max() < 0.002
