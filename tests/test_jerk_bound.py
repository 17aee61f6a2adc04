"""Tests of benchmarks/jerk_bound.py, the jerk-limited time-optimal reference (on cases with a known optimum)."""

from __future__ import annotations

import importlib
import math
import sys
from itertools import pairwise
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


def test_windows_cut_a_stretch_into_overlapping_windows() -> None:
    # 11 points (0..10) in windows of at most 4: ceil(10 / 3) = 4 windows, cut as evenly as they can be
    cuts = jb.windows(0, 10, 4)
    assert cuts[0] == 0 and cuts[-1] == 10 and len(cuts) == 5
    assert all(0 < b - a <= 3 for a, b in pairwise(cuts))   # consecutive windows share their end point
    assert jb.windows(5, 8, 4) == [5, 8]                     # 4 points fit in one window
    assert jb.windows(0, 10, None) == [0, 10]


def test_windowed_short_line_is_the_relaxation_optimum() -> None:
    # 0.05 mm from rest to rest at 100 mm/s, 1000 mm/s², 20000 mm/s³: ruckig (the known optimum) takes
    # 4 (L / 2J)^(1/3) = 4 x 0.0107722 = 0.0430887 s.  Cut in two windows with a FREE speed and acceleration
    # where they meet, each window is its best half alone: from rest, full jerk all the way, s = J t³ / 6,
    # so t = (6 s / J)^(1/3) (0.0196 s for s = L/2; a = J t = 391 mm/s² < 1000, v = J t² / 2 = 3.8 mm/s < 100:
    # neither limit binds): 2 x 0.0195743 = 0.0391487 s for an even cut, 9 % below the optimum.  A lower bound.
    length, j = 0.05, 20000.0
    path = jb.line_path([1.0, 0.0], length, [100.0, 100.0], spacing=length / 50)
    n = path.s.size
    exact = jb.jerk_time(path, [1000.0, 1000.0], [j, j])
    windowed = jb.jerk_time(path, [1000.0, 1000.0], [j, j], window=n - 1)
    cut = path.s[jb.windows(0, n - 1, n - 1)[1]]
    expected = (6.0 * cut / j) ** (1.0 / 3.0) + (6.0 * (length - cut) / j) ** (1.0 / 3.0)
    assert expected == pytest.approx(2.0 * (3.0 * length / j) ** (1.0 / 3.0), rel=1e-3)   # the cut is near L/2
    assert windowed.time == pytest.approx(expected, rel=5e-3)
    assert windowed.time < exact.time
    assert windowed.time < _ruckig(length, 100.0, 1000.0, j)


def test_windowed_long_line_is_between_the_jerk_free_and_the_jerk_limited_optimum() -> None:
    # 50 mm: 0.65 s with the jerk limit (the docstring of the first test).  Cut in 4 windows, each with a free
    # speed where it meets the next, the relaxation skips the jerk phases of the ramps wherever a cut falls in
    # one, but every window stays below the jerk-free optimum (its cap), whose time is the trapezoid's:
    # 50 / 100 + 100 / 1000 = 0.55 s (exact on any grid): 0.55 s <= windowed <= exact
    path = jb.line_path([1.0, 0.0], 50.0, [100.0, 100.0], spacing=1.0)
    exact = jb.jerk_time(path, [1000.0, 1000.0], [20000.0, 20000.0])
    windowed = jb.jerk_time(path, [1000.0, 1000.0], [20000.0, 20000.0], window=path.s.size // 4 + 2)
    assert len(jb.windows(0, path.s.size - 1, path.s.size // 4 + 2)) == 5
    assert 0.55 * (1 - 1e-6) <= windowed.time <= exact.time * (1 + 1e-9)
    assert windowed.time < 0.65


def test_windows_at_rest_points_give_the_exact_time() -> None:
    # two lines with a stop between them (0.05 mm, then 50 mm): b = a = 0 at the stop separates the problem
    # exactly, so windows that fit each stretch change nothing, and the time is the sum of the two known
    # optima: 0.0430887 + 0.65 = 0.6930887 s
    short = jb.line_path([1.0, 0.0], 0.05, [100.0, 100.0], spacing=0.001)
    long_ = jb.line_path([1.0, 0.0], 50.0, [100.0, 100.0], spacing=1.0)
    n = short.s.size
    both = jb.JerkPath(np.concatenate([short.s, 0.05 + long_.s[1:]]),
                       np.concatenate([short.points, n - 1 + long_.points]), np.concatenate([short.q1, long_.q1]),
                       np.concatenate([short.q2, long_.q2]), np.concatenate([short.xmax, long_.xmax[1:]]),
                       np.array([0, n - 1, n - 2 + long_.s.size]), np.concatenate([short.m1, long_.m1]),
                       np.concatenate([short.m2, long_.m2]), np.concatenate([short.m3, long_.m3]))
    limits = ([1000.0, 1000.0], [20000.0, 20000.0])
    exact = jb.jerk_time(both, *limits)
    windowed = jb.jerk_time(both, *limits, window=max(n, long_.s.size))
    assert windowed.time == exact.time
    expected = _ruckig(0.05, 100.0, 1000.0, 20000.0) + _ruckig(50.0, 100.0, 1000.0, 20000.0)
    assert expected == pytest.approx(4.0 * (0.05 / 40000.0) ** (1.0 / 3.0) + 0.65, rel=1e-9)
    assert expected * (1 - 1e-4) <= exact.time <= expected * 1.005
