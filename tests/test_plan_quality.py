"""Plan quality (issue 27 item 3): caps that follow the curvature on arc parts, corner curves in parts
without a jerk limit, and the limits still hold on what those plans sample to."""

from __future__ import annotations

import importlib
import math
import sys
from itertools import pairwise
from pathlib import Path

import numpy as np
import pytest

import fagorcnc
from fagorcnc.plan.blend import BlendPiece
from fagorcnc.plan.corners import part_bounds, split_blend
from fagorcnc.plan.limits import (
    AxisLimits,
    axis_terms,
    curve_limits,
    curve_limits_rows,
    piece_cap,
    reach_without_jerk,
    tangential,
)

_BENCH = Path(__file__).resolve().parents[1] / "benchmarks"
if str(_BENCH) not in sys.path:
    sys.path.insert(0, str(_BENCH))
pvb = importlib.import_module("plan_vs_bound")

LIM = AxisLimits((1e4, 1e4), (1000.0, 1000.0), (math.inf, math.inf))


def test_cap_of_an_arc_part_gives_the_crossing_axis_its_budget() -> None:
    # the 10° part of an R2 circle starting where X takes the whole centripetal acceleration:
    # d1 = (sin 10°, 1), d2 = (1/R, sin 10°/R) = (0.5, 0.08682)
    s10 = math.sin(math.radians(10.0))
    d1, d2, d3 = [s10, 1.0], [0.5, s10 / 2.0], [0.0, 0.0]
    # a line along these bounds gets min(1000 / 0.17365, 1000 / 1) = 1000 mm/s²; 10 % of it is kept: 100
    # X: vc² <= (1000 - 100 x 0.17365) / 0.5 = 1965.27 -> 44.331 mm/s (Y: sqrt(900 / 0.08682) = 101.8)
    vc = piece_cap(d1, d2, d3, LIM, 1e9)
    assert vc == pytest.approx(math.sqrt((1000.0 - 100.0 * s10) / 0.5), rel=1e-12)
    assert vc == pytest.approx(44.331, abs=1e-3)
    assert vc > math.sqrt(0.9 * 1000.0 / 0.5)   # the former 90 % rule: 42.43 mm/s
    # at that cap X leaves (1000 - 1965.27 x 0.5) / 0.17365 = 100 mm/s² of tangential acceleration (Y: 829)
    cap, acc, _ = curve_limits(d1, d2, d3, LIM, 1e9)
    assert cap == vc and acc == pytest.approx(100.0, rel=1e-9)
    # the rows form gives the same numbers
    rows = curve_limits_rows(np.array([d1]), np.array([d2]), np.array([d3]), LIM, 1e9)
    assert rows[0][0] == vc and rows[1][0] == acc


def test_cap_never_below_the_90_percent_rule() -> None:
    # every axis keeps at least 90 % of its budget for the curvature: reserve x d1_i <= 0.1 A_i
    rng = np.random.default_rng(3)
    for _ in range(200):
        d1, d2 = rng.uniform(0.01, 1.0, 2), rng.uniform(0.01, 5.0, 2)
        vc = piece_cap(d1.tolist(), d2.tolist(), [0.0, 0.0], LIM, 1e9)
        assert vc >= min(math.sqrt(0.9 * 1000.0 / k) for k in d2) * (1 - 1e-12)
        _, acc, _ = curve_limits(d1.tolist(), d2.tolist(), [0.0, 0.0], LIM, 1e9)
        assert acc >= 0.1 * min(1000.0 / g for g in d1) * (1 - 1e-9)


def test_split_blend_is_the_same_curve() -> None:
    blend = BlendPiece(np.array([0.0, 0.0]), np.array([1.0, 0.0]), np.zeros(2), 0.4,
                       np.array([1.0, 1.0]), np.array([0.0, 1.0]), np.zeros(2), 0.4)
    parts = split_blend(blend, 4)
    assert len(parts) == 4
    assert np.allclose(parts[0].start, blend.start) and np.allclose(parts[-1].end, blend.end)
    for a, b in pairwise(parts):
        assert np.allclose(a.end, b.start, atol=1e-14)
    # lengths add up; points of a part lie on the whole curve (u in [i/4, (i+1)/4] maps to 4u - i)
    assert sum(p.length for p in parts) == pytest.approx(blend.length, rel=1e-9)
    whole = blend.points(97)   # u = k / 96
    assert np.allclose(parts[1].points(25), whole[24:49], atol=1e-12)
    # each part's bounds are the sampled maxima of its own stretch with the same margins: within the whole
    # curve's up to its sampling (97 points over the whole, 97 over each quarter: 1.71835 vs 1.71796 here)
    for p in parts:
        assert np.all(p.d2 <= blend.d2 * 1.001)
    assert parts[0].d2[0] < 0.95 * blend.d2[0]   # the end parts are less curved than the middle


@pytest.mark.parametrize("case", ["circle", "zigzag"])
def test_jerk_free_plans_keep_the_limits(case: str) -> None:
    text = pvb.circles("G05") if case == "circle" else pvb.zigzag("G05", n=80)
    result = fagorcnc.simulate(text)
    assert result.ok
    off = list(result.segments(jerk=False, keep_profiles=True))
    worst = pvb.limit_check(off, result.machine)
    for key in ("v", "a", "v_fd", "a_fd", "feed"):
        assert worst[key] <= 1.001, (key, worst)
    # the finer caps pay: R2 circle, five turns at F6000: 1.4536 s (1.5417 s in 30° parts with the 90 % rule)
    if case == "circle":
        assert sum(s.duration for s in off) < 1.47


def test_reach_without_jerk_is_the_exact_trapezoid() -> None:
    # bounds d1 = (0.6, 0.8), d2 = (2, 1), A = 1000 on both axes, from v = 10 mm/s over L = 0.01 mm (2L = 0.02):
    # X: c² = (100 + 0.02 x 1000 / 0.6) / (1 + 0.02 x 2 / 0.6) = 133.333 / 1.066667 = 125.0
    # Y: c² = (100 + 0.02 x 1000 / 0.8) / (1 + 0.02 x 1 / 0.8) = 125 / 1.025 = 121.951 -> c = 11.0432 mm/s
    terms = axis_terms([0.6, 0.8], [2.0, 1.0], [0.0, 0.0], LIM)
    c = reach_without_jerk(terms, 10.0, 0.01, math.inf)
    assert c * c == pytest.approx(125.0 / 1.025, rel=1e-12)
    # at that cap the tangential acceleration min((1000 - 2 c²) / 0.6, (1000 - c²) / 0.8) = 1097.56 mm/s²
    # runs the trapezoid exactly: 100 + 0.02 x 1097.56 = 121.951 = c²
    acc, _ = tangential(terms, c)
    assert acc == pytest.approx((1000.0 - 125.0 / 1.025) / 0.8, rel=1e-12)
    assert 100.0 + 0.02 * acc == pytest.approx(c * c, rel=1e-12)
    # the array form gives the same speed; a path acceleration of 500 mm/s² binds first: c² = 100 + 0.02 x 500
    assert reach_without_jerk(terms.arrays(), 10.0, 0.01, math.inf) == pytest.approx(c, rel=1e-15)
    assert reach_without_jerk(terms, 10.0, 0.01, 500.0) == pytest.approx(math.sqrt(110.0), rel=1e-15)


def test_part_bounds_hold_between_the_samples() -> None:
    # a 90-degree corner curve in 32 parts: each part's bounds of |q'| and |q''| (97 samples, 0.5 % plus twice
    # the largest second difference) are above the values at 20 001 points of the part, and below the whole
    # curve's margins (2 % and 5 % over the samples' largest)
    blend = BlendPiece(np.array([0.0, 0.0]), np.array([1.0, 0.0]), np.zeros(2), 0.375 * 0.025,
                       np.array([0.025, -0.025]), np.array([0.0, -1.0]), np.zeros(2), 0.375 * 0.025)
    dense = np.linspace(0.0, 1.0, 20001)
    for part in split_blend(blend, 32):
        _, t, k, _ = part._geometric(dense)
        assert np.all(np.abs(t).max(axis=0) <= part.d1 * (1 + 1e-12))   # |t| = 1: the cap at 1 is exact
        assert np.all(np.abs(k).max(axis=0) <= part.d2)
        _, ts, ks, _ = part._geometric(np.linspace(0.0, 1.0, 97))
        assert np.all(part.d1 <= np.minimum(np.abs(ts).max(axis=0) * 1.02, 1.0) + 1e-15)
        assert np.all(part.d2 <= np.abs(ks).max(axis=0) * 1.05)
    # a constant sampled |f| gets exactly its 0.5 %; a kink (|f| through 0) widens the bound by its second difference
    assert part_bounds(np.full((97, 1), 2.0))[0] == pytest.approx(2.01, rel=1e-15)
    kink = np.abs(np.linspace(-1.0, 1.0, 97))[:, None]   # second difference 2 x (2 / 96) at the middle
    assert part_bounds(kink)[0] == pytest.approx(1.005 + 2.0 * 2.0 * 2.0 / 96.0, rel=1e-12)


def test_g05_zigzag_jerk_off_within_5_percent_of_the_bound() -> None:
    # issue 27 item 3: 80 steps of 0.05 mm at +-45 degrees, G05, jerk off: planned / time-optimal bound <= 1.05
    # (1.089 on the 400-step zig-zag in 16 parts with the whole curve's margins, 1.035 now; plan_vs_bound.py)
    result = fagorcnc.simulate(pvb.zigzag("G05", n=80))
    off = list(result.segments(jerk=False, keep_profiles=False))
    bound = pvb.bound_time(pvb.build_grid(off, result.machine))
    assert 1.0 <= sum(s.duration for s in off) / bound <= 1.05
