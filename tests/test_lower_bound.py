"""Tests of benchmarks/lower_bound.py, the independent TOPP lower bound on traversal time (jerk ignored)."""

from __future__ import annotations

import importlib
import math
import sys
from pathlib import Path

import numpy as np
import pytest

_BENCH = Path(__file__).resolve().parents[1] / "benchmarks"
if str(_BENCH) not in sys.path:
    sys.path.insert(0, str(_BENCH))
lb = importlib.import_module("lower_bound")


def _line(direction: np.ndarray, length: float, h: float) -> tuple[np.ndarray, ...]:
    """Straight line from the origin: (q, dq, ddq, s) on a grid of spacing ~h."""
    u = np.asarray(direction, float) / np.linalg.norm(direction)
    s = np.linspace(0.0, length, round(length / h) + 1)
    return s[:, None] * u, np.tile(u, (s.size, 1)), np.zeros((s.size, u.size)), s


def _circle(radius: float, turns: float, h: float) -> tuple[np.ndarray, ...]:
    """Circle of the given radius in XY, centred on the origin, `turns` revolutions, arc-length grid."""
    s = np.linspace(0.0, 2 * np.pi * radius * turns, round(2 * np.pi * radius * turns / h) + 1)
    th = s / radius
    q = radius * np.stack([np.cos(th), np.sin(th)], axis=1)
    dq = np.stack([-np.sin(th), np.cos(th)], axis=1)
    return q, dq, -q / radius**2, s


def _trapezoid(length: float, v: float, a: float) -> float:
    """Rest-to-rest time on a line with path limits v, a: trapezoid if L >= v²/a, else triangle."""
    return length / v + v / a if length >= v * v / a else 2.0 * math.sqrt(length / a)


@pytest.mark.parametrize(
    ("length", "expected"),
    [
        (100.0, 2.05),  # v²/a = 2.5 mm <= 100: T = 100/50 + 50/1000 = 2.0 + 0.05 = 2.05 s
        (1.0, 0.0632455532),  # v²/a = 2.5 mm > 1: triangle, T = 2 sqrt(1/1000) = 0.0632456 s
    ],
)
def test_line_along_x_is_a_trapezoid(length: float, expected: float) -> None:
    q, dq, ddq, s = _line(np.array([1.0, 0.0, 0.0]), length, 0.01)
    vmax, amax = np.array([50.0, 20.0, 10.0]), np.array([1000.0, 300.0, 100.0])  # only X moves
    assert _trapezoid(length, 50.0, 1000.0) == pytest.approx(expected, rel=1e-9)
    assert lb.topp_time(q, dq, ddq, s, vmax, amax) == pytest.approx(expected, rel=5e-3)


def test_line_on_nonuniform_grid() -> None:
    # Same 100 mm X line, random grid spacing in [0.01, 0.5] mm: still 2.05 s (constant u is exact in x).
    rng = np.random.default_rng(1)
    s = np.r_[0.0, np.cumsum(rng.uniform(0.01, 0.5, 2000))]
    s = s[s < 100.0]
    s = np.r_[s, 100.0]
    dq = np.tile([1.0, 0.0], (s.size, 1))
    t = lb.topp_time(s[:, None] * dq, dq, np.zeros_like(dq), s, np.array([50.0, 50.0]), np.array([1000.0, 1000.0]))
    assert t == pytest.approx(2.05, rel=5e-3)


def test_diagonal_line_uses_both_axes() -> None:
    # Along (1,1,0)/sqrt2 each axis sees 1/sqrt2 of the path speed/acceleration, so the path limits are
    # v sqrt2 = 70.71 mm/s and a sqrt2 = 1414.2 mm/s²; v²/a = 3.54 mm <= 100, T = 100/70.71 + 70.71/1414.2
    # = 1.41421 + 0.05 = 1.46421 s.
    q, dq, ddq, s = _line(np.array([1.0, 1.0, 0.0]), 100.0, 0.01)
    t = lb.topp_time(q, dq, ddq, s, np.full(3, 50.0), np.full(3, 1000.0))
    expected = _trapezoid(100.0, 50.0 * math.sqrt(2), 1000.0 * math.sqrt(2))
    assert expected == pytest.approx(1.46421356, rel=1e-7)
    assert t == pytest.approx(expected, rel=5e-3)


def test_vcap_limits_cruise() -> None:
    # Feed cap 20 mm/s below the axis limit 50 mm/s: T = 100/20 + 20/1000 = 5.02 s.
    q, dq, ddq, s = _line(np.array([1.0, 0.0]), 100.0, 0.01)
    t = lb.topp_time(q, dq, ddq, s, np.full(2, 50.0), np.full(2, 1000.0), vcap=np.full(s.size, 20.0))
    assert t == pytest.approx(5.02, rel=5e-3)


def test_square_with_stops_is_four_trapezoids() -> None:
    # 40 mm square X+, Y+, X-, Y-, stop at each corner.  X: v=50, a=1000 (v²/a=2.5 <= 40) -> 40/50 + 0.05
    # = 0.85 s per side; Y: v=30, a=500 (v²/a=1.8 <= 40) -> 40/30 + 30/500 = 1.39333 s.  Total 4.48667 s.
    side, h = 40.0, 0.02
    per_side = round(side / h)
    dirs = [(1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (0.0, -1.0)]
    dq = np.concatenate([np.tile(d, (per_side, 1)) for d in dirs] + [np.array([[0.0, -1.0]])])
    s = np.arange(dq.shape[0]) * h
    corners = np.arange(1, 4) * per_side  # dq at a corner is the outgoing direction
    q = np.cumsum(np.r_[np.zeros((1, 2)), dq[:-1] * h], axis=0)
    t = lb.topp_time(q, dq, np.zeros_like(dq), s, np.array([50.0, 30.0]), np.array([1000.0, 500.0]), stops=corners)
    expected = 2 * (_trapezoid(side, 50.0, 1000.0) + _trapezoid(side, 30.0, 500.0))
    assert expected == pytest.approx(4.4866667, rel=1e-7)
    assert t == pytest.approx(expected, rel=5e-3)
    # Without the stops the corners are not constrained at all (ddq = 0 models no turn), so it is faster.
    assert lb.topp_time(q, dq, np.zeros_like(dq), s, np.array([50.0, 30.0]), np.array([1000.0, 500.0])) < t


def test_circle_per_revolution_time() -> None:
    # R = 10 mm, A = 1000 mm/s² on X and Y, vmax large.  Constant speed sqrt(A R) = 100 mm/s is feasible
    # (each axis sees (v²/R)|cos| or |sin| <= A), so a revolution takes at most 2 pi R / sqrt(A R) = 0.6283 s.
    # The acceleration vector norm is at most A sqrt2, so v²/R <= A sqrt2: at least 2 pi R / sqrt(sqrt2 A R)
    # = 0.5284 s.  Between the axis-aligned points the planner may exceed sqrt(A R) (up to ~2.6 % faster).
    # T(20 turns) - T(19 turns) is one periodic (middle) revolution: the ramps from/to rest cancel.
    radius, acc, vmax = 10.0, 1000.0, np.full(2, 1e4)
    t20 = lb.topp_time(*_circle(radius, 20, 0.05), vmax, np.full(2, acc))
    t19 = lb.topp_time(*_circle(radius, 19, 0.05), vmax, np.full(2, acc))
    per_rev = t20 - t19
    upper = 2 * np.pi * radius / math.sqrt(acc * radius)
    lower = 2 * np.pi * radius / math.sqrt(math.sqrt(2) * acc * radius)
    assert lower < per_rev <= upper
    assert per_rev == pytest.approx(upper, rel=0.03)
    # The ramp overhead (start and end at rest) is small: less than one extra revolution.
    assert 20 * per_rev < t20 < 21 * per_rev


def test_coarse_grid_does_not_overestimate() -> None:
    # Peaks between grid points are integrated bang-bang, so a line is exact on any grid: 1 mm triangle on a
    # 0.3 mm grid = 2 sqrt(1/1000) = 0.0632456 s, 3 mm trapezoid on 0.35 mm = 3/50 + 50/1000 = 0.11 s.
    for length, h, expected in ((1.0, 0.3, 0.0632455532), (3.0, 0.35, 0.11)):
        s = np.r_[np.arange(0.0, length, h), length]
        dq = np.tile([1.0, 0.0], (s.size, 1))
        t = lb.topp_time(s[:, None] * dq, dq, np.zeros_like(dq), s, np.full(2, 50.0), np.full(2, 1000.0))
        assert t == pytest.approx(expected, rel=1e-6)
    # A curve converges from below: a 0.5 mm grid on an R = 10 mm circle is within 0.1 % of a 0.01 mm one.
    radius, vmax, amax = 10.0, np.full(2, 1e4), np.full(2, 1000.0)
    coarse = lb.topp_time(*_circle(radius, 1, 0.5), vmax, amax)
    fine = lb.topp_time(*_circle(radius, 1, 0.01), vmax, amax)
    assert fine * (1 - 1e-3) < coarse <= fine


def test_profile_respects_the_constraints() -> None:
    # The profile x = sdot², with u_k = (x_{k+1} - x_k) / (2 Δs), satisfies every limit at the grid points.
    q, dq, ddq, s = _circle(8.0, 1.5, 0.05)
    vmax, amax = np.array([60.0, 80.0]), np.array([900.0, 600.0])
    vcap = np.where(s > 30.0, 40.0, 1e9)
    x = lb.topp_profile(q, dq, ddq, s, vmax, amax, vcap=vcap, stops=[200])
    u = np.diff(x) / (2 * np.diff(s))
    assert x[0] == x[-1] == x[200] == 0.0
    assert np.all(np.abs(dq) * np.sqrt(x)[:, None] <= vmax * (1 + 1e-9))
    assert np.all(np.sqrt(x) <= vcap * (1 + 1e-9))
    acc = np.abs(dq[:-1] * u[:, None] + ddq[:-1] * x[:-1, None])
    assert np.all(acc <= amax * (1 + 1e-6) + 1e-6)


@pytest.mark.parametrize("pieces", [1, 2, 3, 4])
def test_sweep_matches_plain_recursion(pieces: int) -> None:
    # The vectorised sweep (on-cap shortcut, two-piece reduction, chunked loop) equals the plain recursion,
    # for slopes of either sign (y stays >= 0 as x = sdot² does: offsets exceed |negative slope| * max cap).
    rng = np.random.default_rng(7 + pieces)
    m = 3000
    cap = rng.uniform(0.0, 10.0, m)
    cap[[0, 1000, 2000]] = 0.0
    slope = rng.uniform(-0.05, 1.5, (m - 1, pieces))
    offset = rng.uniform(0.5, 2.0, (m - 1, pieces))
    y = np.empty(m)
    y[0] = cap[0]
    for k in range(m - 1):
        y[k + 1] = min(cap[k + 1], float(np.min(slope[k] * y[k] + offset[k])))
    np.testing.assert_allclose(lb._sweep(cap, slope, offset), y, rtol=1e-12, atol=1e-12)


def test_matches_toppra_on_a_spline() -> None:
    # toppra (TOPP-RA reference implementation) with the same collocation discretisation on the same grid.
    import toppra
    from toppra import algorithm, constraint
    waypoints = np.array([[0, 0, 0], [30, 10, 0], [50, 40, 5], [20, 60, 10], [-10, 40, 5]], dtype=float)
    knots = np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(waypoints, axis=0), axis=1))]
    path = toppra.SplineInterpolator(knots, waypoints)
    vmax, amax = np.array([100.0, 80.0, 50.0]), np.array([1000.0, 800.0, 500.0])
    grid = np.linspace(0.0, knots[-1], 2001)
    instance = algorithm.TOPPRA(
        [
            constraint.JointVelocityConstraint(np.stack([-vmax, vmax], axis=1)),
            constraint.JointAccelerationConstraint(
                np.stack([-amax, amax], axis=1), discretization_scheme=constraint.DiscretizationType.Collocation
            ),
        ],
        path,
        gridpoints=grid,
        solver_wrapper="seidel",
    )
    sd = instance.compute_parameterization(0, 0)[1]
    reference = float(np.sum(2 * np.diff(grid) / (sd[:-1] + sd[1:])))  # constant u per interval
    args = (path(grid), path(grid, 1), path(grid, 2), grid, vmax, amax)
    # Same discrete problem, so the speed profiles agree to rounding (~1e-9 in practice).
    np.testing.assert_allclose(np.sqrt(lb.topp_profile(*args)), sd, rtol=1e-6, atol=1e-6 * sd.max())
    # Our time integrates between-grid peaks bang-bang, so it is slightly lower (~3e-4 on this grid); the
    # brief asked for 2 %, we assert 0.1 %.
    ours = lb.topp_time(*args)
    assert reference * (1 - 1e-3) < ours <= reference * (1 + 1e-9)
