"""Helpers shared by the planner's tests."""

from __future__ import annotations

import math

from fagorcnc.plan.profile import too_short


def reference_duration(length: float, v0: float, v1: float, vc: float, acc: float, jerk: float) -> float:
    """The duration of a 1-axis span as ``too_short`` then ruckig itself answer it (inf: no profile):
    the reference ``Solver.duration``'s shortcuts are checked against."""
    from ruckig import InputParameter, Result, Ruckig, Trajectory

    if too_short(length, v0, v1, acc, jerk):
        return math.inf
    otg, inp, traj = Ruckig(1), InputParameter(1), Trajectory(1)
    inp.current_position, inp.current_acceleration, inp.target_acceleration = [0.0], [0.0], [0.0]
    inp.min_velocity = [0.0]
    inp.current_velocity, inp.target_position, inp.target_velocity = [v0], [length], [v1]
    inp.max_velocity, inp.max_acceleration, inp.max_jerk = [vc], [acc], [jerk]
    try:
        result = otg.calculate(inp, traj)
    except Exception:
        return math.inf
    return traj.duration if result in (Result.Working, Result.Finished) else math.inf
