"""The planned motion, sampled every 1 ms, never exceeds an axis' velocity, acceleration or jerk.

Checked two ways on every path: the planner's own per-axis values at the
samples, and finite differences of the sampled positions (velocity, acceleration
and jerk as a servo sampling the positions would see them).  Tolerance 1e-6
relative.  Under HSC the sampled path stays within the tolerance E of the
programmed polyline.
"""

from __future__ import annotations

import importlib
import math
import sys
from pathlib import Path

import numpy as np
import pytest

import fagorcnc

_BENCH = Path(__file__).resolve().parents[1] / "benchmarks"   # the benchmarks' programs, planned here too
if str(_BENCH) not in sys.path:
    sys.path.insert(0, str(_BENCH))
contour_pass = importlib.import_module("plan_speed").contour_pass

PERIOD = 0.001
TOL = 1e-6


def square() -> str:
    return "G90 G1 X0 Y0 F6000\nX30\nY30\nX0\nY0\n"


def small_circle() -> str:
    # radius 1 mm, three full turns then a tangent exit
    return "G90 G1 X0 Y0 F6000\nX10\n" + "G3 X10 Y0 I0 J1\n" * 3 + "G1 X20\n"


def zigzag(turn_deg: float, n: int = 300, step: float = 0.05) -> str:
    out, x, y = ["G90 G1 X0 Y0 F3000"], 0.0, 0.0
    half = math.radians(turn_deg) / 2
    for i in range(n):
        a = half if i % 2 else -half
        x, y = x + step * math.cos(a), y + step * math.sin(a)
        out.append(f"X{x:.6f} Y{y:.6f}")
    return "\n".join(out) + "\n"


def helix() -> str:
    # radius 5, four turns, 1 mm down per turn
    return "G90 G1 X5 Y0 Z0 F3000\n" + "".join(f"G2 X5 Y0 Z{-(i + 1)} I-5 J0\n" for i in range(4))


def surface(n: int, step: float = 0.5, feed: int = 3000) -> str:
    """A 3D finishing raster over z = 2 sin(x/7) cos(y/9): n short segments."""
    out, k, row, y = [f"G90 G1 X0 Y0 Z2 F{feed}"], 0, 0, 0.0
    while k < n:
        xs = np.arange(0.0, 50.0 + 1e-9, step)
        for x in xs[::-1] if row % 2 else xs:
            out.append(f"X{x:.4f} Y{y:.4f} Z{2 * math.sin(x / 7) * math.cos(y / 9):.4f}")
            k += 1
            if k >= n:
                break
        y += 1.0
        row += 1
    return "\n".join(out) + "\n"


def arc_contour(per: int = 60) -> str:
    """The benchmarks' freeform contour as CAM arc fitting writes it (``plan_speed.contour_pass``):
    arcs meeting at small kinks (corners at arcs), every fourth piece a line."""
    return "\n".join(["G90 G1 X40 Y0 Z0 F3000", *contour_pass(per)]) + "\n"


MODES = {"G50": "", "G05": "G05\n", "HSC": "#HSC ON [CONTERROR 0.01]\n"}
PATHS = {"square": square, "circle": small_circle, "zigzag": lambda: zigzag(60), "zigzag-gentle": lambda: zigzag(8),
         "helix": helix, "arcs": arc_contour}


def check_limits(result, jerk: bool = True) -> dict:
    tr = result.trajectory(PERIOD)
    t = tr.t
    assert np.allclose(np.diff(t), PERIOD)
    worst = {}
    for a, ax in result.machine.axes.items():
        v_max, a_max, j_max = ax.max_velocity / 60.0, ax.max_acceleration, ax.max_jerk
        # the planner's values at the samples
        assert np.abs(tr.velocity[a]).max() <= v_max * (1 + TOL), a
        assert np.abs(tr.acceleration[a]).max() <= a_max * (1 + TOL), a
        if jerk:
            assert np.abs(tr.jerk[a]).max() <= j_max * (1 + TOL), a
        # what a servo sampling the positions sees
        p = tr.position[a]
        v = np.diff(p) / PERIOD
        acc = np.diff(v) / PERIOD
        j = np.diff(acc) / PERIOD
        worst[a] = (np.abs(v).max() / v_max, np.abs(acc).max() / a_max, np.abs(j).max() / j_max)
        assert worst[a][0] <= 1 + TOL and worst[a][1] <= 1 + TOL, (a, worst[a])
        if jerk:
            assert worst[a][2] <= 1 + TOL, (a, worst[a])
    return worst


def run(program: str):
    r = fagorcnc.simulate(program + "M30\n")
    assert r.ok, [str(d) for d in r.diagnostics]
    return r


@pytest.mark.parametrize("mode", MODES)
@pytest.mark.parametrize("path", PATHS)
def test_limits_hold_on_the_test_paths(path, mode):
    check_limits(run(MODES[mode] + PATHS[path]()))


def test_limits_hold_on_a_3d_finishing_path_of_10000_segments_under_hsc():
    r = run(MODES["HSC"] + surface(10_000))
    assert sum(1 for m in r.moves if m.kind == "linear") >= 10_000
    check_limits(r)


def test_limits_hold_on_a_3d_finishing_path_of_10000_segments_with_rounding():
    check_limits(run(MODES["G05"] + surface(10_000)))


def test_limits_hold_on_a_3d_finishing_path_with_stops():
    check_limits(run(surface(2_000)))


def test_limits_hold_with_unlimited_jerk():
    # #SLOPE [0]: linear acceleration: velocity and acceleration still hold
    check_limits(run("#SLOPE [0]\nG05\n" + surface(1_000)), jerk=False)


def test_limits_hold_with_a_slow_rotary_like_axis():
    machine = {"axes": {"X": {"max_velocity": 6000.0, "max_acceleration": 800.0, "max_jerk": 9000.0},
                        "Y": {"max_velocity": 3000.0, "max_acceleration": 300.0, "max_jerk": 4000.0},
                        "Z": {"max_velocity": 2000.0, "max_acceleration": 200.0, "max_jerk": 2000.0}}}
    r = fagorcnc.simulate(MODES["HSC"] + surface(1_500, feed=10_000) + "M30\n", machine)
    assert r.ok
    check_limits(r)


def _distance_to_polyline(points: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    ab = b - a
    den = np.maximum((ab * ab).sum(axis=1), 1e-300)
    rel = points[:, None, :] - a[None]
    t = np.clip((rel * ab[None]).sum(axis=2) / den[None], 0.0, 1.0)
    gap = rel - t[..., None] * ab[None]
    return np.sqrt((gap * gap).sum(axis=2))


@pytest.mark.parametrize("tolerance", [0.01, 0.05])
@pytest.mark.parametrize("path", ["zigzag-gentle", "surface"])
def test_hsc_path_stays_within_the_contour_error(path, tolerance):
    program = f"#HSC ON [CONTERROR {tolerance}]\n" + (zigzag(8) if path == "zigzag-gentle" else surface(3_000))
    r = run(program)
    tr = r.trajectory(PERIOD)
    axes = r.machine.axis_names
    pts = np.stack([tr.position[a] for a in axes], axis=1)
    lines = [m for m in r.moves if m.kind == "linear"]
    seg_a = np.array([[m.start[a] for a in axes] for m in lines])
    seg_b = np.array([[m.end[a] for a in axes] for m in lines])
    seg_line = np.array([m.line for m in lines])
    worst = 0.0
    for line in np.unique(tr.line):
        sel = tr.line == line
        near = np.abs(seg_line - line) <= 1        # a corner curve spans its block and the next
        d = _distance_to_polyline(pts[sel], seg_a[near], seg_b[near]).min(axis=1)
        worst = max(worst, float(d.max()))
    assert worst <= tolerance + 1e-9
    assert worst > 1e-4   # the corners really are rounded


def _programmed_points(move, per: int = 400) -> np.ndarray:
    """Points along a programmed move (XY arcs and lines here), ``per`` of them: dense enough that
    the polyline through them is within 1e-6 mm of the arc."""
    a = np.array([move.start["X"], move.start["Y"], move.start["Z"]])
    b = np.array([move.end["X"], move.end["Y"], move.end["Z"]])
    f = np.linspace(0.0, 1.0, per)
    if move.kind != "arc":
        return a + f[:, None] * (b - a)
    cx, cy = move.center["X"], move.center["Y"]
    r0, r1 = math.hypot(a[0] - cx, a[1] - cy), math.hypot(b[0] - cx, b[1] - cy)
    th = math.atan2(a[1] - cy, a[0] - cx) + math.radians(move.sweep) * f
    r = r0 + (r1 - r0) * f
    return np.stack([cx + r * np.cos(th), cy + r * np.sin(th), a[2] + f * (b[2] - a[2])], axis=1)


def test_hsc_path_with_arcs_stays_within_the_contour_error():
    """The corner curves at arcs (made in batches) keep the sampled path within E of the
    programmed arcs and lines, and the corners really are rounded."""
    tolerance = 0.01
    r = run(f"#HSC ON [CONTERROR {tolerance}]\n" + arc_contour())
    assert sum(1 for m in r.moves if m.kind == "arc") >= 40
    tr = r.trajectory(PERIOD)
    pts = np.stack([tr.position[a] for a in ("X", "Y", "Z")], axis=1)
    moves = [m for m in r.moves if m.kind in ("linear", "arc")]
    worst = 0.0
    for line in np.unique(tr.line):
        sel = tr.line == line
        near = [m for m in moves if abs(m.line - line) <= 1]   # a corner curve spans its block and the next
        ref = [_programmed_points(m) for m in near]
        a = np.concatenate([p[:-1] for p in ref])
        b = np.concatenate([p[1:] for p in ref])
        worst = max(worst, float(_distance_to_polyline(pts[sel], a, b).min(axis=1).max()))
    assert worst <= tolerance + 1e-6
    assert worst > 1e-4
