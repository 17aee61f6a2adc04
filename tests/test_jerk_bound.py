"""Tests of benchmarks/jerk_bound.py, the jerk-limited time-optimal reference (on cases with a known optimum)."""

from __future__ import annotations

import importlib
import math
import sys
from pathlib import Path

import numpy as np
import pytest
from ruckig import InputParameter, Ruckig, Trajectory

_BENCH = Path(__file__).resolve().parents[1] / "benchmarks"
if str(_BENCH) not in sys.path:
    sys.path.insert(0, str(_BENCH))
jb = importlib.import_module("jerk_bound")


def _ruckig(length: float, v: float, a: float, j: float) -> float:
    """ruckig's rest-to-rest time on one axis: time-optimal for a 1-DOF jerk-limited motion."""
    otg, inp, traj = Ruckig(1), InputParameter(1), Trajectory(1)
    inp.current_position, inp.target_position = [0.0], [length]
    inp.max_velocity, inp.max_acceleration, inp.max_jerk = [v], [a], [j]
    otg.calculate(inp, traj)
    return traj.duration


@pytest.mark.parametrize(
    ("length", "expected"),
    [
        # 50 mm at 100 mm/s, 1000 mm/s², 20000 mm/s³: a/j = 0.05 s of jerk, 0.1 s more to reach v, so each ramp
        # takes 0.15 s over 7.5 mm; cruise (50 - 15) / 100 = 0.35 s: 0.15 + 0.35 + 0.15 = 0.65 s
        (50.0, 0.65),
        # 0.05 mm: neither v nor a is reached, four jerk phases of tau = (L / 2J)^(1/3) = (1.25e-6)^(1/3) s
        (0.05, 4.0 * (0.05 / 40000.0) ** (1.0 / 3.0)),
    ],
)
def test_rest_to_rest_line_equals_ruckig(length: float, expected: float) -> None:
    ruck = _ruckig(length, 100.0, 1000.0, 20000.0)
    assert ruck == pytest.approx(expected, rel=1e-9)
    path = jb.line_path([1.0, 0.0], length, [100.0, 100.0], spacing=length / 50)
    result = jb.jerk_time(path, [1000.0, 1000.0], [20000.0, 20000.0])
    # the reference is a feasible profile of the discretised problem: at or a little above the optimum
    assert ruck * (1 - 1e-4) <= result.time <= ruck * 1.005
    assert result.time < result.start_time or result.start_time == pytest.approx(ruck, rel=1e-3)


def test_diagonal_line_uses_the_projected_limits() -> None:
    # along (3, 4)/5 the X axis carries 3/5 of the path motion and Y 4/5: Y binds everything, so the path limits
    # are v = 100 / 0.8 = 125 mm/s, a = 1000 / 0.8 = 1250 mm/s², j = 20000 / 0.8 = 25000 mm/s³
    ruck = _ruckig(20.0, 125.0, 1250.0, 25000.0)
    path = jb.line_path([3.0, 4.0], 20.0, [100.0, 100.0], spacing=0.4)
    result = jb.jerk_time(path, [1000.0, 1000.0], [20000.0, 20000.0])
    assert ruck * (1 - 1e-4) <= result.time <= ruck * 1.005


def test_feed_cap_and_no_jerk_limit() -> None:
    # jerk unlimited: the trapezoid, 10 mm at F 50 mm/s, 1000 mm/s²: 10/50 + 50/1000 = 0.25 s (exact on any grid)
    path = jb.line_path([1.0], 10.0, [100.0], feed=50.0, spacing=0.2)
    result = jb.jerk_time(path, [1000.0], [math.inf])
    assert result.time == pytest.approx(0.25, rel=2e-3)


def test_profile_meets_the_limits() -> None:
    path = jb.line_path([1.0, 1.0], 5.0, [100.0, 100.0], spacing=0.1)
    result = jb.jerk_time(path, [1000.0, 1000.0], [20000.0, 20000.0])
    b, a = result.b, result.a
    u = 1 / math.sqrt(2.0)
    assert np.all(b >= -1e-9) and np.all(np.sqrt(np.maximum(b, 0)) * u <= 100.0 * (1 + 1e-6))
    assert np.all(np.abs(a) * u <= 1000.0 * (1 + 1e-6))
    ds = np.diff(path.s)
    jerk = np.sqrt(0.5 * (b[:-1] + b[1:])) * np.abs(np.diff(a) / ds) * u
    assert np.max(jerk) <= 20000.0 * (1 + 1e-6)
    assert b[0] == b[-1] == 0.0 and a[0] == a[-1] == 0.0
