"""Planned cycle time against an independent time-optimal lower bound, on the planned geometry.

Run from the repository root::

    python benchmarks/plan_vs_bound.py [--quick] [--no-check] [--plain-grid] [--no-jerk-reference]
                                       [--jerk-window N]

For every test path (generated below) the program is interpreted once with
``fagorcnc.simulate`` and planned twice with the fagorcnc planner: with unlimited
jerk (``jerk=False``: trapezoidal speed profiles) and jerk-limited (``jerk=True``,
what ``simulate`` reports).  The lower bound comes from ``lower_bound.topp_time``
(a TOPP solver written independently of the planner; jerk ignored) evaluated on
the geometry the planner actually moves along: its pieces, including the corner
blends it inserted in G05 / HSC, with

* the same per-axis velocity limits (``max_feed`` if > 0 else ``max_velocity`` for
  feed moves, ``max_velocity`` for rapids) and acceleration limits;
* the same feed cap (programmed F times the feed override, as a cap on the true
  path speed ``|q'| sdot``; none for rapids, which the axes' velocities cap);
* the same stops: every junction where the plan is at rest (a motion segment
  with ``v0 == 0`` or ``v1 == 0``, a dwell or auxiliary function between motions,
  the program start and end).

Not modelled (none of the test paths uses them): feed adaptation G108/G109/G193
and HSC FAST change a span's feed away from the record's F, and #SLOPE / G130-G133
scale the axis limits; the bound uses the record's F and the machine's limits.

The grid: each motion piece is sampled at a spacing of ``min(0.05 mm, length/4)``,
on curved pieces also at most R/20 (R the smallest radius of curvature, from the
piece's curvature bound; ``lower_bound.py`` needs it for ~0.2 % accuracy: on the
0.04 mm blends of the zig-zag the plain rule overestimates the bound by ~20 %;
``--plain-grid`` drops the R/20 rule), at least 4 intervals per piece, in the
piece's own parameter (arc length for
lines and blends, nearly so for arcs; ``topp_time`` works with any
parameterisation because the feed cap is passed as ``feed / |q'|``).  The per-piece
grids are concatenated with the cumulative length as offset, so ``s`` is strictly
increasing by construction; a junction point carries the derivatives of the
OUTGOING piece (the interval after it belongs to that piece; the interval before
it is constrained through the incoming piece's previous grid point), so the
incoming piece's end point constraints are only seen one grid step earlier.

jerk on and jerk off can plan different geometry (the blend size follows the
jerk limit when the tolerance does not bind), so the bound is computed on each
plan's own geometry; the table's "lower bound" column is the jerk-off one and a
separate column shows the jerk-on one when they differ.

Planning speed: motion segments planned (blends included) per second of the
jerk-on planning loop alone (``Result.segments(jerk=True, keep_profiles=False)``,
as ``simulate`` plans), after interpretation; the best of repeated runs for the
small paths (until 0.2 s are spent), one run for the raster.

After the table: the grid convergence of the bound (spacing / 4), a jerk-informed
estimate (see :func:`jerk_estimate`; not a bound), the trajectory limit check and
the anomalies (a ratio below 1, a limit exceeded, a planner error).

The jerk-limited reference (``jerk_bound.py``) is computed on every path; on the rasters it is
solved in windows of ``--jerk-window`` grid points (default 400) with free speed and acceleration
where two windows meet: a relaxation, so its time is a lower bound of the whole problem's optimum
(up to the SLP's local optimality in each window) and "jerk on / reference" an upper estimate.

``--quick`` shrinks the big finishing raster from 10 049 to 2 009 segments.
``--no-check`` skips the trajectory limit check (sampling both plans every 1 ms
and comparing analytic and finite-difference axis velocity/acceleration/jerk
with the limits), which is otherwise run for every path and summarised after
the table.
"""

from __future__ import annotations

import argparse
import hashlib
import math
import subprocess
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

import jerk_bound
from lower_bound import topp_time

import fagorcnc
from fagorcnc.plan import sample

#: Grid spacing of the bound (mm) and the least number of intervals per piece.
SPACING = 0.05
MIN_INTERVALS = 4
#: On curved pieces the spacing also stays below this fraction of the smallest radius of curvature
#: (lower_bound.py: below ~R/20 for 0.2 % accuracy; ``--plain-grid`` drops the rule).
CURVATURE_FRACTION = 1.0 / 20.0
#: Grid of the jerk-limited reference (``jerk_bound.py``): spacing (mm) and fraction of the radius of curvature.
JERK_SPACING = 0.1
JERK_CURVATURE = 1.0 / 8.0
#: The rasters' jerk-limited reference is solved in windows of at most this many grid points with free
#: speed and acceleration where they meet (``jerk_bound.jerk_time``: a lower bound of the reference).
JERK_WINDOW = 400

#: Planning-speed timing: best of up to TIMING_RUNS runs, stopping once TIMING_BUDGET seconds are spent.
TIMING_RUNS = 50
TIMING_BUDGET = 0.2

HSC = "#HSC ON [CONTERROR 0.01]"
MODES = {"G07": "G07", "G05": "G05", "HSC": HSC}


# ---------------------------------------------------------------- test programs
def _num(v: float) -> str:
    text = f"{v:.5f}".rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text


def _program(mode: str, body: list[str]) -> str:
    lines = ["; generated by benchmarks/plan_vs_bound.py", "G90 G17", MODES[mode], *body]
    if mode == "HSC":
        lines.append("#HSC OFF")
    lines.append("M30")
    return "\n".join(lines) + "\n"


def square(mode: str) -> str:
    """A 50 mm square from the origin, F6000."""
    return _program(mode, ["G01 X50 Y0 F6000", "X50 Y50", "X0 Y50", "X0 Y0"])


def circles(mode: str) -> str:
    """Five full circles of radius 2 mm (centre at X-2 Y0), F6000."""
    return _program(mode, ["G02 X0 Y0 I-2 J0 F6000", *["G02 X0 Y0 I-2 J0"] * 4])


def zigzag(mode: str, n: int = 400, step: float = 0.05) -> str:
    """``n`` segments of ``step`` mm alternating +45° / -45° in XY, F3000."""
    d = step / math.sqrt(2.0)
    body, x, y = [], 0.0, 0.0
    for i in range(n):
        x += d
        y += d if i % 2 == 0 else -d
        body.append(f"G01 X{_num(x)} Y{_num(y)}" + (" F3000" if i == 0 else ""))
    return _program(mode, body)


def helix(mode: str) -> str:
    """Radius 5 mm, 10 turns, Z down 1 mm per turn (one block per turn), F3000."""
    body = [f"G02 X0 Y0 Z{-k} I-5 J0" + (" F3000" if k == 1 else "") for k in range(1, 11)]
    return _program(mode, body)


def raster(mode: str, feed: float, rows: int) -> str:
    """A zig-zag raster over z = 2 sin(x/7) cos(y/9): 0.5 mm steps along X (0..100), rows 1 mm apart."""
    xs = np.linspace(0.0, 100.0, 201)
    body = []
    for r in range(rows):
        y = float(r)
        row = xs if r % 2 == 0 else xs[::-1]
        for k, x in enumerate(row):
            if r == 0 and k == 0:
                continue   # the start point (0, 0, 0) is where the machine is
            z = 2.0 * math.sin(x / 7.0) * math.cos(y / 9.0)
            body.append(f"G01 X{_num(x)} Y{_num(y)} Z{_num(z)}" + (f" F{feed:g}" if not body else ""))
    return _program(mode, body)


def cases(quick: bool) -> list[tuple[str, str, str]]:
    rows = 10 if quick else 50
    out = [("square 50 mm", m, square(m)) for m in ("G07", "G05")]
    out += [("circle R2 x5", m, circles(m)) for m in ("G05", "HSC")]
    out += [("zig-zag 400 x 0.05 mm", m, zigzag(m)) for m in ("G05", "HSC")]
    out += [("helix R5 10 turns", "HSC", helix("HSC"))]
    for feed in (3000, 10000):
        out += [(f"raster {rows * 200 + rows - 1} seg F{feed}", m, raster(m, feed, rows)) for m in ("HSC", "G05")]
    return out


# ---------------------------------------------------------------- the bound
@dataclass
class Grid:
    s: np.ndarray
    q: np.ndarray
    dq: np.ndarray
    ddq: np.ndarray
    dddq: np.ndarray
    vcap: np.ndarray
    stops: np.ndarray
    vmax: np.ndarray
    amax: np.ndarray


def _axis_limits(machine) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(feed-move velocity, rapid velocity) in mm/s and acceleration in mm/s², machine axis order."""
    axes = [machine.axes[a] for a in machine.axis_names]
    v_feed = np.array([(a.max_feed if a.max_feed > 0 else a.max_velocity) / 60.0 for a in axes])
    v_feed = np.minimum(v_feed, np.array([a.max_velocity / 60.0 for a in axes]))
    v_rapid = np.array([a.max_velocity / 60.0 for a in axes])
    acc = np.array([a.max_acceleration for a in axes])
    return v_feed, v_rapid, acc


def build_grid(segments, machine, refine: float = 1.0, curvature_spacing: bool = True) -> Grid:
    """The bound's grid over the planned pieces (see the module docstring).

    ``refine`` divides the spacing (used to check the grid convergence);
    ``curvature_spacing`` also keeps it below R/20 (R the piece's smallest radius of curvature).
    """
    v_feed, v_rapid, acc = _axis_limits(machine)
    override = machine.planner.feed_override / 100.0
    rapid_feed = machine.rapid_feed / 60.0 if machine.rapid_feed > 0 else math.inf
    rapid_feed *= machine.planner.rapid_override / 100.0 if machine.planner.rapid_override > 0 else 1.0
    ss, qs, d1s, d2s, d3s, caps = [], [], [], [], [], []
    stops: list[int] = [0]
    offset, count = 0.0, 0
    last = None   # (s, q, q1, q2, cap) of the end point of the last motion piece
    for seg in segments:
        if seg.kind != "motion":
            stops.append(count)   # a dwell / aux between motions: at rest (the planner stops before it)
            continue
        piece, rec = seg.piece, seg.record
        length = piece.length
        h = min(SPACING, length / MIN_INTERVALS)
        if curvature_spacing:
            kappa = float(np.linalg.norm(piece.d2))   # bounds the curvature (|q'| ~ 1)
            if kappa > 0:
                h = min(h, CURVATURE_FRACTION / kappa)
        n = max(MIN_INTERVALS, math.ceil(length / h * refine - 1e-9))
        s_loc = np.linspace(0.0, length, n + 1)
        q, q1, q2, q3 = piece.derivatives(s_loc)
        q1 = np.asarray(q1, dtype=float)
        speed = np.linalg.norm(q1, axis=1)
        rapid = rec.kind == "rapid"
        feed = rapid_feed if rapid else (rec.feed / 60.0 * override if rec.feed else math.inf)
        vlim = v_rapid if rapid else v_feed
        with np.errstate(divide="ignore"):
            cap = np.minimum(feed / speed, np.min(np.where(np.abs(q1) > 0, vlim / np.abs(q1), np.inf), axis=1))
        if seg.v0 == 0.0:
            stops.append(count)
        ss.append(offset + s_loc[:-1])
        qs.append(q[:-1])
        d1s.append(q1[:-1])
        d2s.append(q2[:-1])
        d3s.append(q3[:-1])
        caps.append(cap[:-1])
        count += n
        offset += length
        if seg.v1 == 0.0:
            stops.append(count)
        last = (offset, q[-1], q1[-1], q2[-1], q3[-1], cap[-1])
    if last is None:
        raise ValueError("no motion")
    ss.append(np.array([last[0]]))
    qs.append(last[1][None, :])
    d1s.append(last[2][None, :])
    d2s.append(last[3][None, :])
    d3s.append(last[4][None, :])
    caps.append(np.array([last[5]]))
    stops.append(count)
    s = np.concatenate(ss)
    if not np.all(np.diff(s) > 0):
        raise AssertionError("the grid is not strictly increasing")
    vmax = np.maximum(v_feed, v_rapid)   # the per-point limits are folded into vcap
    return Grid(s, np.concatenate(qs), np.concatenate(d1s), np.concatenate(d2s), np.concatenate(d3s),
                np.concatenate(caps), np.unique(np.array(stops, dtype=int)), vmax, acc)


def bound_time(grid: Grid) -> float:
    return topp_time(grid.q, grid.dq, grid.ddq, grid.s, grid.vmax, grid.amax, vcap=grid.vcap, stops=grid.stops)


def jerk_estimate(grid: Grid, machine) -> float:
    """The bound with the speed also capped pointwise by ``|q_i'''| v³ <= J_i`` (NOT a bound).

    That is the axis jerk at constant path speed; with a varying speed the tangential terms
    ``q_i' j + 3 q_i'' v a`` can offset it, so this only estimates how much of the jerk-on time
    the curvature rate of the geometry (mostly the blends) explains.
    """
    jmax = np.array([machine.axes[a].max_jerk for a in machine.axis_names])
    with np.errstate(divide="ignore"):
        vj = np.min(np.cbrt(jmax / np.abs(grid.dddq)), axis=1)
    return topp_time(grid.q, grid.dq, grid.ddq, grid.s, grid.vmax, grid.amax, vcap=np.minimum(grid.vcap, vj),
                     stops=grid.stops)


def jerk_path(segments, machine, spacing: float = JERK_SPACING, curvature_fraction: float = JERK_CURVATURE):
    """The planned pieces as a :class:`jerk_bound.JerkPath`: the same limits, feeds and stops as
    :func:`build_grid`, each piece sampled at ``min(spacing, length/4)`` (curved pieces also at most
    ``curvature_fraction`` x R), graded towards its ends where the plan is at rest; a junction
    carries the derivatives of both pieces, each interval those of its own piece at its midpoint."""
    v_feed, v_rapid, _acc = _axis_limits(machine)
    override = machine.planner.feed_override / 100.0
    rapid_feed = machine.rapid_feed / 60.0 if machine.rapid_feed > 0 else math.inf
    rapid_feed *= machine.planner.rapid_override / 100.0 if machine.planner.rapid_override > 0 else 1.0
    ss, pts, q1s, q2s, caps, m1s, m2s, m3s = [], [], [], [], [], [], [], []
    stops: list[int] = [0]
    offset, count = 0.0, 0
    rest = True   # at rest at the next piece's start (program start, or after a dwell / aux)
    for seg in segments:
        if seg.kind != "motion":
            rest = True
            if count:
                stops.append(count)
            continue
        piece, rec = seg.piece, seg.record
        length = piece.length
        h = spacing
        kappa = float(np.linalg.norm(piece.d2)) if piece.curved else 0.0
        if kappa > 0:
            h = min(h, curvature_fraction / kappa)
        s_loc = jerk_bound.graded(length, h, rest or seg.v0 == 0.0, seg.v1 == 0.0)
        mid = 0.5 * (s_loc[:-1] + s_loc[1:])
        _, q1, q2, _ = piece.derivatives(s_loc)
        _, m1, m2, m3 = piece.derivatives(mid)
        q1, q2 = np.asarray(q1, dtype=float), np.asarray(q2, dtype=float)
        rapid = rec.kind == "rapid"
        feed = rapid_feed if rapid else (rec.feed / 60.0 * override if rec.feed else math.inf)
        vlim = v_rapid if rapid else v_feed
        with np.errstate(divide="ignore"):
            cap = np.minimum(feed / np.linalg.norm(q1, axis=1),
                             np.min(np.where(np.abs(q1) > 0, vlim / np.abs(q1), np.inf), axis=1))
        if rest or seg.v0 == 0.0:
            stops.append(count)
        index = count + np.arange(len(s_loc))
        if count:   # the junction point is the previous piece's last point: cap it by both pieces
            caps[-1][-1] = min(caps[-1][-1], cap[0])
        ss.append(offset + (s_loc if not count else s_loc[1:]))
        pts.append(index)
        q1s.append(q1)
        q2s.append(q2)
        caps.append(cap if not count else cap[1:])
        m1s.append(np.asarray(m1, dtype=float))
        m2s.append(np.asarray(m2, dtype=float))
        m3s.append(np.asarray(m3, dtype=float))
        count += len(s_loc) - 1
        offset += length
        rest = False
        if seg.v1 == 0.0:
            stops.append(count)
    if not ss:
        raise ValueError("no motion")
    stops.append(count)
    s = np.concatenate(ss)
    if not np.all(np.diff(s) > 0):
        raise AssertionError("the grid is not strictly increasing")
    xmax = np.concatenate(caps) ** 2
    return jerk_bound.JerkPath(s, np.concatenate(pts), np.concatenate(q1s), np.concatenate(q2s), xmax,
                               np.unique(np.array(stops, dtype=int)), np.concatenate(m1s), np.concatenate(m2s),
                               np.concatenate(m3s))


def jerk_reference(segments, machine, window: int | None = None) -> jerk_bound.JerkResult:
    """:func:`jerk_bound.jerk_time` on the planned pieces with the machine's axis limits (``window``:
    solved in windows of that many grid points, a lower bound of the whole problem's optimum)."""
    axes = [machine.axes[a] for a in machine.axis_names]
    acc = np.array([a.max_acceleration for a in axes])
    jerk = np.array([a.max_jerk for a in axes])
    return jerk_bound.jerk_time(jerk_path(segments, machine), acc, jerk, window=window)


# ---------------------------------------------------------------- trajectory check
def limit_check(segments, machine, period: float = 0.001) -> dict[str, float]:
    """Largest |value| / limit over the axes, sampled every ``period`` from the profiles:
    ``v``/``a``/``j`` analytic, ``v_fd``/``a_fd`` by finite differences of the positions
    (interior samples only), ``feed`` the path speed over the programmed feed."""
    axes = machine.axis_names
    v_feed, v_rapid, acc = _axis_limits(machine)
    jerk = np.array([machine.axes[a].max_jerk for a in axes])
    vlim = np.maximum(v_feed, v_rapid)
    segs = list(segments)
    traj = sample(segs, axes, period, None if not segs else dict(zip(axes, segs[0].piece.start, strict=True)))
    pos = np.stack([traj.position[a] for a in axes], axis=1)
    vel = np.stack([traj.velocity[a] for a in axes], axis=1)
    acl = np.stack([traj.acceleration[a] for a in axes], axis=1)
    jrk = np.stack([traj.jerk[a] for a in axes], axis=1)
    out = {"v": float(np.max(np.abs(vel) / vlim)), "a": float(np.max(np.abs(acl) / acc)),
           "j": float(np.max(np.abs(jrk) / jerk))}
    t = traj.t
    uniform = np.all(np.abs(np.diff(t) - period) < 1e-9)
    if uniform and len(t) > 3:
        vfd = np.diff(pos, axis=0) / period
        afd = np.diff(pos, n=2, axis=0) / period ** 2
        out["v_fd"] = float(np.max(np.abs(vfd) / vlim))
        out["a_fd"] = float(np.max(np.abs(afd) / acc))
    # path speed against the feed of the segment being run
    worst = 0.0
    for seg in segs:
        if seg.kind != "motion" or seg.profile is None or not seg.record.feed:
            continue
        tau = np.linspace(0.0, seg.duration, 9)
        s, v, _, _ = seg.profile.at(tau)
        _, q1, _, _ = seg.piece.derivatives(s)
        speed = np.linalg.norm(q1, axis=1) * v
        worst = max(worst, float(np.max(speed)) / (seg.record.feed / 60.0 * machine.planner.feed_override / 100.0))
    out["feed"] = worst
    return out


# ---------------------------------------------------------------- one path
@dataclass
class Row:
    path: str
    mode: str
    blocks: int = 0
    segments: int = 0
    blends: int = 0
    t_off: float = math.nan
    t_on: float = math.nan
    lb_off: float = math.nan
    lb_on: float = math.nan
    lb_fine: float = math.nan
    lb_plain: float = math.nan
    jerk_est: float = math.nan
    jerk_ref: float = math.nan
    jerk_ref_seconds: float = 0.0
    jerk_ref_points: int = 0
    jerk_windowed: bool = False
    speed: float = math.nan
    cycle_time: float = math.nan
    grid_points: int = 0
    bound_seconds: float = 0.0
    notes: list[str] = field(default_factory=list)
    check_off: dict = field(default_factory=dict)
    check_on: dict = field(default_factory=dict)


def _same_geometry(a: list, b: list) -> bool:
    if len(a) != len(b):
        return False
    return all(x.kind == y.kind and (x.kind != "motion" or (abs(x.piece.length - y.piece.length) < 1e-12
                                                          and np.allclose(x.piece.start, y.piece.start)))
               for x, y in zip(a, b, strict=True))


def run_case(path: str, mode: str, text: str, *, check: bool, refine_check: bool, curvature_spacing: bool,
             big: bool = False, jerk_ref: bool = False, jerk_window: int | None = None) -> Row:
    row = Row(path, mode)
    result = fagorcnc.simulate(text)
    if not result.ok:
        row.notes.append("; ".join(f"{d.code} L{d.line}: {d.message}" for d in result.errors))
        return row
    machine = result.machine
    row.blocks = sum(1 for m in result.moves if m.kind in ("linear", "arc", "rapid"))
    row.cycle_time = result.cycle_time
    try:
        off = list(result.segments(jerk=False, keep_profiles=check))
        # planning speed: the planning loop only (the records are already interpreted); small paths are
        # planned again until 0.2 s have been spent and the best run counts
        elapsed, spent = math.inf, 0.0
        for _ in range(TIMING_RUNS):
            t0 = time.perf_counter()
            on = list(result.segments(jerk=True, keep_profiles=False))
            dt = time.perf_counter() - t0
            elapsed, spent = min(elapsed, dt), spent + dt
            if spent >= TIMING_BUDGET:
                break
    except Exception as exc:   # a planner failure is a result of the benchmark, not a crash of it
        row.notes.append(f"planner raised {type(exc).__name__}: {exc}")
        return row
    motion_on = [s for s in on if s.kind == "motion"]
    row.segments = len(motion_on)
    row.blends = sum(1 for s in motion_on if s.blend)
    row.speed = len(motion_on) / elapsed
    row.t_off = sum(s.duration for s in off)
    row.t_on = sum(s.duration for s in on)
    if abs(row.t_on - row.cycle_time) > 1e-9 * max(1.0, row.cycle_time):
        row.notes.append(f"jerk-on plan {row.t_on:.6f} s != simulate().cycle_time {row.cycle_time:.6f} s")
    t0 = time.perf_counter()
    grid_off = build_grid(off, machine, curvature_spacing=curvature_spacing)
    row.grid_points = len(grid_off.s)
    row.lb_off = bound_time(grid_off)
    same = _same_geometry(off, on)
    grid_on = grid_off if same else build_grid(on, machine, curvature_spacing=curvature_spacing)
    row.lb_on = row.lb_off if same else bound_time(grid_on)
    row.jerk_est = jerk_estimate(grid_on, machine)
    if refine_check:
        row.lb_fine = bound_time(build_grid(off, machine, refine=4.0, curvature_spacing=curvature_spacing))
        if curvature_spacing and not big:
            row.lb_plain = bound_time(build_grid(off, machine, curvature_spacing=False))
    row.bound_seconds = time.perf_counter() - t0
    if jerk_ref:
        t0 = time.perf_counter()
        ref = jerk_reference(on, machine, jerk_window)
        row.jerk_ref, row.jerk_ref_points = ref.time, len(ref.b)
        row.jerk_windowed = jerk_window is not None and len(ref.b) > jerk_window
        row.jerk_ref_seconds = time.perf_counter() - t0
    if check:
        row.check_off = limit_check(off, machine)
        row.check_on = limit_check(result.segments(jerk=True, keep_profiles=True), machine)
    return row


# ---------------------------------------------------------------- report
def source_version() -> str:
    """Git HEAD and a fingerprint of the fagorcnc sources as run (the planner may have local edits)."""
    root = Path(__file__).resolve().parent.parent
    digest = hashlib.sha1()
    for f in sorted((root / "fagorcnc").rglob("*.py")):
        digest.update(f.relative_to(root).as_posix().encode())
        digest.update(f.read_bytes())
    try:
        head = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=root, capture_output=True, text=True,
                              check=True).stdout.strip()
        dirty = subprocess.run(["git", "status", "--porcelain", "--", "fagorcnc"], cwd=root, capture_output=True,
                               text=True, check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        head, dirty = "unknown", ""
    local = " + local changes in fagorcnc/" if dirty else ""
    return f"git {head}{local}, fagorcnc sources sha1 {digest.hexdigest()[:12]}"


def _f(v: float, digits: int = 4) -> str:
    return "n/a" if not math.isfinite(v) else f"{v:.{digits}f}"


def table(rows: list[Row]) -> str:
    head = ["path", "mode", "segments", "planned time jerk off (s)", "lower bound (s)", "ratio (jerk off)",
            "planned time jerk on (s)", "ratio (jerk on)", "lower bound, jerk-on geometry (s)",
            "jerk-limited reference (s)", "jerk on / reference", "planning speed (motion segments/s, jerk on)"]
    out = ["| " + " | ".join(head) + " |", "|" + "|".join(["---"] * len(head)) + "|"]
    for r in rows:
        segs = f"{r.segments} ({r.blends} blends)" if r.segments else "-"
        lb_on = "same" if r.lb_on == r.lb_off else _f(r.lb_on)
        out.append("| " + " | ".join([
            r.path, r.mode, segs, _f(r.t_off), _f(r.lb_off), _f(r.t_off / r.lb_off, 3), _f(r.t_on),
            _f(r.t_on / r.lb_on, 3), lb_on, _f(r.jerk_ref) + (" (windows)" if r.jerk_windowed else ""),
            _f(r.t_on / r.jerk_ref, 3),
            "n/a" if not math.isfinite(r.speed) else f"{r.speed:,.0f}",
        ]) + " |")
    return "\n".join(out)


INTERPRETATION = """\
Interpretation: "ratio" is planned time / lower bound, both on the geometry the planner moves along \
(its pieces and the corner blends it inserted), with the same per-axis velocity and acceleration \
limits, feed caps and stops.  The bound is the time-optimal traversal with jerk ignored, so any plan\
 that respects those limits needs at least that long: both ratios are >= 1 by construction if the \
planner and the bound are right (up to the bound's discretisation error, which the "spacing / 4" \
check above measures), and a ratio below 1 means one of them is wrong.  A jerk-off ratio near 1 says\
 the planner leaves little on the table; above 1 it measures the planner's own simplifications (one \
speed cap and one tangential acceleration per piece from its derivative bounds, the 10 % of the \
tangential acceleration a curve keeps at its cap, so a curve started from rest ramps up with what \
the cap leaves).  With jerk on the speed must also ramp its acceleration and, on curves, keep v^3 \
|q\'\'\'| within the jerk limit, none of which the bound sees, so the jerk-on ratio is expected to \
be higher: most on very short moves (S-curves that never reach full acceleration) and on paths made \
of small G2 blends (their curvature changes fast), which the jerk-informed estimate separates from \
the planner's own slack.  The jerk-limited reference (jerk_bound.py) is the time of a feasible, \
locally time-optimal profile WITH the per-axis jerk limits on the jerk-on geometry (sequential \
linear programming; a rest-to-rest line comes within 0.3 % of ruckig's optimum): "jerk on / \
reference" is how far the planner is from it.  On the rasters the reference is solved in windows \
of a few hundred grid points with free speed and acceleration where they meet: a relaxation, so a \
lower bound of the reference\'s optimum and "jerk on / reference" an upper estimate of the true ratio."""


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true", help="shrink the big raster to 2 009 segments")
    ap.add_argument("--no-check", action="store_true", help="skip the sampled-trajectory limit check")
    ap.add_argument("--no-jerk-reference", action="store_true",
                    help="skip the jerk-limited reference (jerk_bound.py: a sequence of LPs, the slowest part)")
    ap.add_argument("--jerk-window", type=int, default=JERK_WINDOW,
                    help="grid points per window of the rasters' jerk-limited reference (free speed and acceleration "
                         "where windows meet: a lower bound; 0: the whole stretch between stops at once, LPs of "
                         f"~10^5 variables on the big raster; default {JERK_WINDOW})")
    ap.add_argument("--plain-grid", action="store_true",
                    help="bound grid spacing min(0.05 mm, length/4) only (no R/20 rule on curved pieces)")
    args = ap.parse_args(argv)
    start = time.perf_counter()
    version = source_version()
    rows = []
    for path, mode, text in cases(args.quick):
        t0 = time.perf_counter()
        big = path.startswith("raster")
        row = run_case(path, mode, text, check=not args.no_check, refine_check=args.quick or not big,
                       curvature_spacing=not args.plain_grid, big=big,
                       jerk_ref=not args.no_jerk_reference,
                       jerk_window=args.jerk_window if big and args.jerk_window > 0 else None)
        rows.append(row)
        print(f"  {path} {mode}: {time.perf_counter() - t0:.1f} s (bound grid {row.grid_points} points, "
              f"{row.bound_seconds:.1f} s; jerk-limited reference {row.jerk_ref_points} points, "
              f"{row.jerk_ref_seconds:.1f} s)", file=sys.stderr)
    print(f"fagorcnc: {version}; numpy {np.__version__}; Python {sys.version.split()[0]}")
    print()
    print(table(rows))
    print()
    print("Bound grid convergence (jerk-off geometry): the table's grid -> spacing / 4"
          + ("" if args.plain_grid else "; and with the plain min(0.05 mm, length/4) grid (no R/20 rule)") + ":")
    for r in rows:
        if math.isfinite(r.lb_fine):
            plain = ""
            if math.isfinite(r.lb_plain):
                plain = f"; plain grid {_f(r.lb_plain, 5)} s ({(r.lb_plain / r.lb_off - 1) * 100:+.3f} %)"
            print(f"  {r.path} {r.mode}: {_f(r.lb_off, 5)} s -> {_f(r.lb_fine, 5)} s "
                  f"({(r.lb_fine / r.lb_off - 1) * 100:+.3f} %){plain}")
    print()
    print("Jerk-informed estimate on the jerk-on geometry (the bound with v <= min_i (J_i / |q_i'''|)^(1/3) "
          "pointwise; NOT a strict bound, see jerk_estimate()):")
    for r in rows:
        if math.isfinite(r.jerk_est):
            print(f"  {r.path} {r.mode}: {_f(r.jerk_est)} s, planned jerk on / estimate = {r.t_on / r.jerk_est:.3f}")
    if not args.no_check:
        print()
        print("Sampled trajectory (1 ms) against the limits, max |value| / limit over the axes "
              "(v, a, j analytic; v_fd, a_fd finite differences; feed = path speed / F):")
        for r in rows:
            for label, c in (("jerk off", r.check_off), ("jerk on", r.check_on)):
                if c:
                    items = ", ".join(f"{k} {v:.4f}" for k, v in c.items() if not (label == "jerk off" and k == "j"))
                    print(f"  {r.path} {r.mode} {label}: {items}")
    anomalies = []
    for r in rows:
        anomalies += [f"{r.path} {r.mode}: {n}" for n in r.notes]
        for name, t, lb in (("jerk off", r.t_off, r.lb_off), ("jerk on", r.t_on, r.lb_on)):
            if math.isfinite(t) and t < lb:
                anomalies.append(f"{r.path} {r.mode}: {name} plan {t:.6f} s is BELOW the bound {lb:.6f} s")
        if math.isfinite(r.jerk_ref) and r.t_on < r.jerk_ref * (1 - 1e-3):
            anomalies.append(f"{r.path} {r.mode}: jerk-on plan {r.t_on:.6f} s is faster than the jerk-limited "
                             f"reference {r.jerk_ref:.6f} s (the reference: a feasible, locally optimal profile "
                             "of the discretised problem)")
        for label, c in (("jerk off", r.check_off), ("jerk on", r.check_on)):
            for k, v in c.items():
                if v > 1.001 and not (label == "jerk off" and k == "j"):
                    anomalies.append(f"{r.path} {r.mode} {label}: {k} reaches {v:.4f} x its limit")
    print()
    print("Anomalies:" if anomalies else "Anomalies: none")
    for a in anomalies:
        print(f"  {a}")
    print()
    print(INTERPRETATION)
    print()
    print(f"Total run time: {time.perf_counter() - start:.1f} s{' (--quick)' if args.quick else ''}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
