"""The closed-form feasibility test that spares ruckig's failures (plan.profile.too_short)."""

from __future__ import annotations

import math
import random

import pytest
from plan_helpers import reference_duration

from fagorcnc.plan.profile import Solver, shortest_length, too_short


def test_shortest_length_of_a_jerk_triangle():
    # 0 -> 10 mm/s, A 1000, J 10000: dv = 10 <= A²/J = 100, a jerk triangle of
    # T = 2 sqrt(10 / 10000) = 0.0632456 s at a mean speed of 5 mm/s: 0.316228 mm
    assert shortest_length(0.0, 10.0, 1000.0, 10000.0) == pytest.approx(0.316228, rel=1e-6)


def test_shortest_length_of_a_trapezoid():
    # 0 -> 200 mm/s, A 1000, J 10000: dv = 200 > 100, T = 200/1000 + 1000/10000 = 0.3 s
    # at a mean speed of 100 mm/s: 30 mm (and the same slowing down)
    assert shortest_length(0.0, 200.0, 1000.0, 10000.0) == pytest.approx(30.0, rel=1e-12)
    assert shortest_length(200.0, 0.0, 1000.0, 10000.0) == pytest.approx(30.0, rel=1e-12)


def test_a_stop_on_the_way_is_shorter_when_one_speed_is_far_below():
    # 162 -> 12 mm/s, A 2000, J 1600 (A²/J = 2500: triangles):
    # one pulse: dv 150, T = 2 sqrt(150/1600) = 0.612372 s, mean 87: 53.2764 mm;
    # stopping: 81 x 2 sqrt(162/1600) = 51.5481 mm, then 6 x 2 sqrt(12/1600) = 1.03923 mm: 52.5873 mm
    assert shortest_length(162.0, 12.0, 2000.0, 1600.0) == pytest.approx(52.5873, rel=1e-5)
    solver = Solver()
    assert solver.duration(52.60, 162.0, 12.0, 200.0, 2000.0, 1600.0) < math.inf   # ruckig agrees
    assert too_short(52.50, 162.0, 12.0, 2000.0, 1600.0)
    assert not too_short(52.59, 162.0, 12.0, 2000.0, 1600.0)


def test_equal_speeds_need_no_length():
    assert shortest_length(35.0, 35.0, 1000.0, 20000.0) == 0.0
    assert not too_short(1e-9, 35.0, 35.0, 1000.0, 20000.0)


def test_too_short_only_where_ruckig_finds_no_profile():
    # seeded random requests around the shortest length: whenever the closed form refuses, ruckig
    # (asked directly, bypassing the test) finds no profile either
    from ruckig import InputParameter, Result, Ruckig, RuckigError, Trajectory

    otg, inp, traj = Ruckig(1), InputParameter(1), Trajectory(1)
    inp.current_position, inp.current_acceleration, inp.target_acceleration = [0.0], [0.0], [0.0]
    inp.min_velocity = [0.0]
    rng = random.Random(27)
    refused = 0
    for _ in range(3000):
        acc, jerk = 10 ** rng.uniform(1, 4), 10 ** rng.uniform(2, 6)
        v0, v1 = rng.uniform(0, 200) * (rng.random() > 0.2), rng.uniform(0, 200) * (rng.random() > 0.2)
        least = shortest_length(v0, v1, acc, jerk)
        length = least * 10 ** rng.uniform(-0.3, 0.3) if least > 0 else rng.uniform(1e-6, 1.0)
        if not too_short(length, v0, v1, acc, jerk):
            continue
        refused += 1
        inp.current_velocity, inp.target_position, inp.target_velocity = [v0], [length], [v1]
        inp.max_velocity, inp.max_acceleration, inp.max_jerk = [max(v0, v1) * 1.5], [acc], [jerk]
        try:
            found = otg.calculate(inp, traj) in (Result.Working, Result.Finished)
        except (RuckigError, RuntimeError):
            found = False
        assert not found, (length, v0, v1, acc, jerk, traj.duration)
    assert refused > 1000



def test_the_duration_tests_feasibility_as_too_short_does():
    """Solver.duration's inline feasibility test answers inf exactly where too_short says no profile
    exists, and asks ruckig otherwise (the same duration as a request made after too_short)."""
    import numpy as np
    rng = np.random.default_rng(4)
    solver = Solver()
    refused = 0
    for _ in range(400):
        acc, jerk = float(rng.uniform(100, 3000)), float(rng.choice([rng.uniform(1e3, 1e5), math.inf]))
        v0, v1 = (float(x) for x in rng.uniform(0.0, 150.0, size=2))
        if rng.random() < 0.2:
            v1 = v0 if rng.random() < 0.5 else 0.0
        length = shortest_length(v0, v1, acc, jerk) * float(rng.uniform(0.5, 2.0)) + 1e-3
        vc = max(v0, v1) * 1.2 + 1.0
        got = solver.duration(length, v0, v1, vc, acc, jerk)
        assert got == reference_duration(length, v0, v1, vc, acc, jerk)
        refused += got == math.inf
    assert 20 < refused < 380   # both answers were exercised
