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
from fagorcnc.plan.corners import split_blend
from fagorcnc.plan.geometry import BlendPiece
from fagorcnc.plan.limits import AxisLimits, curve_limits, curve_limits_rows, piece_cap

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
