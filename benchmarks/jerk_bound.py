"""Jerk-limited time-optimal path parameterisation: a reference the planner's jerk-on times are compared with.

Independent of the planner (only numpy, scipy and ``lower_bound.py``); it takes the geometry as
derivatives sampled along the path and per-axis velocity, acceleration and jerk limits.

Formulation (arc-length grid ``s_0 < ... < s_{N-1}``, variables ``b_k = sdot²`` and ``a_k = sddot``
at every grid point):

* ``b_{k+1} - b_k = (a_k + a_{k+1}) Δ_k`` (``db/ds = 2 sddot``, trapezoidal);
* velocity and feed: ``b_k <= xmax_k`` (``|q_i'| sdot <= V_i``, ``|q'| sdot <= F``);
* acceleration at every point: ``|q_i' a_k + q_i'' b_k| <= A_i`` (at a junction of two pieces
  with the derivatives of both);
* jerk over every interval, with the derivatives at its midpoint, ``d a/ds = jerk / sdot`` and
  ``sdot_mid = sqrt((b_k + b_{k+1}) / 2)``:
  ``sdot_mid |q_i' (a_{k+1} - a_k)/Δ_k + 3 q_i'' a_mid + q_i''' b_mid| <= J_i``;
* rest (``b = a = 0``) at both ends and at every stop;
* time ``T = sum 2 Δ_k / (sqrt b_k + sqrt b_{k+1})``.

Only ``sdot_mid`` makes the problem non-convex.  Sequential linear programming with a trust
region: around the current profile ``b̄`` every ``b_k`` stays in ``[b̄_k (1 - ρ), ub_k]`` with
``ub_k = min(xmax_k, b̄_k (1 + ρ) + δ)``, the jerk rows use ``sqrt(ub_mid)`` in place of
``sdot_mid`` (so every solution of the LP is feasible for the non-convex problem: its true
``sdot_mid`` is below ``sqrt(ub_mid)``), and the time is linearised at ``b̄``.  A step is kept
when it shortens the time, otherwise ρ is halved; the iteration starts from the jerk-free
time-optimal profile (``lower_bound.topp_profile``, an upper envelope of every jerk-limited
profile) with jerk rows from that envelope and stops when ρ is below ``tol`` or a step gains
less than ``gain``.  The LPs are solved by HiGHS (``scipy.optimize.linprog``).

What the result is: the time of a FEASIBLE profile of the discretised problem, locally optimal
(the SLP converges to a stationary point; nothing certifies the global optimum).  Near a rest
the speed grows like ``s^(2/3)``, which a uniform grid resolves badly, so the grid is graded
geometrically towards every stop (see :func:`graded`); with that a rest-to-rest line matches
ruckig's time within 0.3 % (``tests/test_jerk_bound.py``).

Long stretches without a stop (a G05 raster: 10⁵ grid points) are solved in windows of a few
hundred points (``jerk_time(..., window=...)``) whose speed and acceleration are FREE where two
windows meet: dropping that coupling relaxes the problem, so with each window at its optimum the
sum is a LOWER bound of the stretch's optimum (and never below the jerk-free optimum, every
window's cap).  Each window is still solved by the SLP above (locally optimal, feasible for the
window), so the windowed figure is a lower bound up to that local-optimality gap; on the 2-row
rasters it comes within 0.01-0.3 % below the whole-stretch solution, 1.6 to 5.7 times faster.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from itertools import pairwise

import numpy as np
from lower_bound import topp_profile
from scipy import sparse
from scipy.optimize import linprog

#: Smallest step of the grid at a stop (mm) and the growth factor of the steps away from it.
FIRST_STEP = 1e-8
GROWTH = 1.25
#: Seconds one LP may take (plus 2 ms per grid point): HiGHS now and then stalls on a step.
TIME_LIMIT = 5.0
#: Trust region: besides the relative radius, b may grow by this share of the jerk-free envelope times it.
REACH = 0.05


@dataclass
class JerkPath:
    """The sampled path.

    ``s`` (N,) grid; ``points`` the grid index of every acceleration row and ``q1``/``q2`` (M, D)
    its derivatives (a junction point has two rows: the incoming and the outgoing piece);
    ``xmax`` (N,) the cap on ``sdot²`` from the velocity limits and the feed; ``stops`` indices
    at rest; ``m1``/``m2``/``m3`` (N-1, D) the derivatives at the midpoints of the intervals.
    """

    s: np.ndarray
    points: np.ndarray
    q1: np.ndarray
    q2: np.ndarray
    xmax: np.ndarray
    stops: np.ndarray
    m1: np.ndarray
    m2: np.ndarray
    m3: np.ndarray


@dataclass
class JerkResult:
    time: float
    b: np.ndarray
    a: np.ndarray
    iterations: int
    start_time: float   # the first feasible profile's time (the jerk-free envelope with jerk rows from it)


def graded(length: float, spacing: float, at_start: bool, at_end: bool, min_intervals: int = 4) -> np.ndarray:
    """Grid over ``[0, length]``: spacing at most ``spacing`` (and at least ``min_intervals``
    intervals), steps growing geometrically from :data:`FIRST_STEP` away from an end at rest."""
    h = min(spacing, length / min_intervals)
    if not (at_start or at_end):
        return np.linspace(0.0, length, max(min_intervals, math.ceil(length / h - 1e-9)) + 1)
    ramp = [0.0]
    step = min(FIRST_STEP, h / 4)
    while ramp[-1] + step < (length / 2 if at_start and at_end else length) * 0.5 and step < h:
        ramp.append(ramp[-1] + step)
        step *= GROWTH
    ramp = np.array(ramp)
    lo = ramp if at_start else np.array([0.0])
    hi = length - ramp[::-1] if at_end else np.array([length])
    a, b = lo[-1], hi[0]
    n = max(1, math.ceil((b - a) / h - 1e-9))
    middle = np.linspace(a, b, n + 1)
    return np.concatenate([lo[:-1], middle, hi[1:]])


def line_path(direction, length: float, vmax, feed: float = math.inf, spacing: float = 0.5) -> JerkPath:
    """A straight line from rest to rest (for the tests and as the simplest example)."""
    u = np.asarray(direction, float)
    u = u / np.linalg.norm(u)
    s = graded(length, spacing, True, True)
    n, d = s.size, u.size
    with np.errstate(divide="ignore"):
        vcap = min(feed, float(np.min(np.where(np.abs(u) > 0, np.asarray(vmax, float) / np.abs(u), np.inf))))
    xmax = np.full(n, vcap * vcap)
    zeros = np.zeros((n, d))
    return JerkPath(s, np.arange(n), np.tile(u, (n, 1)), zeros, xmax, np.array([0, n - 1]),
                    np.tile(u, (n - 1, 1)), zeros[:-1], zeros[:-1])


def _time(b: np.ndarray, ds: np.ndarray) -> float:
    v = np.sqrt(np.maximum(b, 0.0))
    with np.errstate(divide="ignore"):
        return float(np.sum(2.0 * ds / (v[:-1] + v[1:])))


def _gradient(b: np.ndarray, ds: np.ndarray) -> np.ndarray:
    """dT/db_k of :func:`_time` (speeds clipped away from zero: the stops are fixed anyway)."""
    v = np.sqrt(np.maximum(b, 0.0))
    v = np.maximum(v, 1e-6 * max(float(v.max()), 1e-12))
    w = 2.0 * ds / (v[:-1] + v[1:]) ** 2
    g = np.zeros_like(b)
    g[:-1] -= w / (2.0 * v[:-1])
    g[1:] -= w / (2.0 * v[1:])
    return g


class _Problem:
    """The constant part of the LPs: equality rows, acceleration rows, jerk row coefficients."""

    def __init__(self, path: JerkPath, amax: np.ndarray, jmax: np.ndarray) -> None:
        s = path.s
        n = s.size
        d = path.q1.shape[1]
        self.n = n
        self.ds = ds = np.diff(s)
        k = np.arange(n - 1)
        # b_{k+1} - b_k - Δ a_k - Δ a_{k+1} = 0; variables [b (n), a (n)]
        rows = np.concatenate([k, k, k, k])
        cols = np.concatenate([k + 1, k, n + k, n + k + 1])
        vals = np.concatenate([np.ones(n - 1), -np.ones(n - 1), -ds, -ds])
        self.a_eq = sparse.csr_matrix((vals, (rows, cols)), shape=(n - 1, 2 * n))
        # acceleration: ± (q1 a + q2 b) <= A, for every row and axis
        m = path.points.size
        r = np.arange(m * d)
        p = np.repeat(path.points, d)
        c1, c2 = path.q1.reshape(-1), path.q2.reshape(-1)
        acc = sparse.csr_matrix((np.concatenate([c2, c1]), (np.concatenate([r, r]), np.concatenate([p, n + p]))),
                                shape=(m * d, 2 * n))
        used = np.abs(c1) + np.abs(c2) > 0   # an axis that does not move on a piece bounds nothing there
        acc = acc[used]
        self.acc = sparse.vstack([acc, -acc]).tocsr()
        self.acc_rhs = np.tile(np.tile(amax, m)[used], 2)
        # jerk over interval k, axis i: coefficients of a_k, a_{k+1}, b_k, b_{k+1}
        finite = np.isfinite(jmax)
        q1, q2, q3 = path.m1[:, finite], path.m2[:, finite], path.m3[:, finite]
        dj = int(finite.sum())
        self.jerk_limit = np.tile(jmax[finite], n - 1)
        r = np.arange((n - 1) * dj)
        kk = np.repeat(k, dj)
        inv = (1.0 / ds)[:, None]
        coefs = [(-q1 * inv + 1.5 * q2), (q1 * inv + 1.5 * q2), 0.5 * q3, 0.5 * q3]
        cols = [n + kk, n + kk + 1, kk, kk + 1]
        jerk = sparse.csr_matrix((np.concatenate([x.reshape(-1) for x in coefs]),
                                  (np.tile(r, 4), np.concatenate(cols))), shape=((n - 1) * dj, 2 * n))
        used = (np.abs(q1) + np.abs(q2) + np.abs(q3)).reshape(-1) > 0
        jerk = jerk[used]
        self.jerk = sparse.vstack([jerk, -jerk]).tocsr()
        self.jerk_interval = np.tile(kk[used], 2)
        self.jerk_limit = self.jerk_limit[used]
        self.stops = np.unique(np.asarray(path.stops, dtype=int))   # a window's free end is not one

    def solve(self, weights: np.ndarray, lo: np.ndarray, ub: np.ndarray, jerk_rows, jerk_rhs) -> np.ndarray | None:
        """The LP: ``b`` in ``[lo, ub]`` with the given jerk rows (rest at the stops)."""
        n = self.n
        a_ub = sparse.vstack([self.acc, jerk_rows]).tocsr()
        b_ub = np.concatenate([self.acc_rhs, jerk_rhs])
        bounds_b = np.stack([lo, ub], axis=1)
        bounds_a = np.tile([-np.inf, np.inf], (n, 1))
        bounds_a[self.stops] = 0.0
        bounds_b[self.stops] = 0.0
        c = np.concatenate([weights, np.zeros(n)])
        res = linprog(c, A_ub=a_ub, b_ub=b_ub, A_eq=self.a_eq, b_eq=np.zeros(n - 1),
                      bounds=np.concatenate([bounds_b, bounds_a]), method="highs",
                      options={"time_limit": TIME_LIMIT + n / 500.0})
        if res.status != 0:   # infeasible, or HiGHS stalled (it does on some badly scaled steps): a failed step
            return None
        return res.x

    def conservative(self, ub: np.ndarray):
        """Jerk rows ``|L| <= J / sqrt(ub_mid)``: every profile below ``ub`` that meets them meets the jerk limits."""
        speed = np.sqrt(0.5 * (ub[:-1] + ub[1:]))[self.jerk_interval]
        with np.errstate(divide="ignore"):
            rhs = np.tile(self.jerk_limit, 2) / speed
        keep = np.isfinite(rhs) & (rhs < 1e250)
        return self.jerk[keep], rhs[keep]

    def linearised(self, z: np.ndarray):
        """First-order rows of ``± sqrt(b_mid) L <= J`` around the profile ``z`` (the SLP step)."""
        n = self.n
        b = z[:n]
        bmid = np.maximum(0.5 * (b[:-1] + b[1:]), 1e-12 * max(float(b.max()), 1e-12))[self.jerk_interval]
        root = np.sqrt(bmid)
        lval = self.jerk @ z                      # L (and -L) of the current profile, per row
        slope = lval / (2.0 * root)               # d(sqrt(b_mid) L)/d b_mid
        kk = self.jerk_interval
        mid = sparse.csr_matrix(
            (np.full(2 * kk.size, 0.5), (np.tile(np.arange(kk.size), 2), np.concatenate([kk, kk + 1]))),
            shape=(kk.size, 2 * n),
        )
        rows = sparse.diags(root) @ self.jerk + sparse.diags(slope) @ mid
        rhs = np.tile(self.jerk_limit, 2) + slope * bmid
        return rows.tocsr(), rhs

    def violation(self, z: np.ndarray) -> float:
        """Largest ``sdot_mid |L| / J - 1`` (0 when the profile meets every jerk limit)."""
        n = self.n
        b = z[:n]
        speed = np.sqrt(np.maximum(0.5 * (b[:-1] + b[1:]), 0.0))[self.jerk_interval]
        return max(0.0, float(np.max(speed * (self.jerk @ z) / np.tile(self.jerk_limit, 2))) - 1.0)


def jerk_time(path: JerkPath, amax, jmax, *, window: int | None = None, **options) -> JerkResult:
    """Time of a locally time-optimal jerk-limited profile along ``path`` (see the module docstring),
    solved stop to stop: at a stop ``b = a = 0``, which separates the problem exactly into the
    stretches between stops (``options``: those of :func:`jerk_time_between_stops`).

    ``window``: a stretch of more grid points than that is solved in windows of at most ``window``
    points each, with FREE speed and acceleration where two windows meet (see :func:`windows`):
    each window is the problem with the coupling across its ends dropped, a relaxation, so the sum
    of the windows' optima is a LOWER bound of the stretch's optimum (equal where the windows split
    at rest points, which is what the stops already do).  The profile returned is then not one
    motion (the windows' speeds disagree where they meet) and its time is not a plan's.
    """
    stops = np.unique(np.concatenate([[0, path.s.size - 1], np.asarray(path.stops, dtype=int)]))
    if stops.size == 2 and (window is None or path.s.size <= window):
        return jerk_time_between_stops(path, amax, jmax, **options)
    total = start = 0.0
    iterations = 0
    bs, as_ = [np.zeros(1)], [np.zeros(1)]
    for lo, hi in pairwise(stops.tolist()):
        envelope = None
        cuts = windows(lo, hi, window)
        if len(cuts) > 2:   # the stretch's jerk-free optimum caps every window (see jerk_time_between_stops)
            envelope = _envelope(_part(path, lo, hi, True, True), amax)
        for w0, w1 in pairwise(cuts):
            part = _part(path, w0, w1, w0 == lo, w1 == hi)
            r = jerk_time_between_stops(part, amax, jmax, envelope=None if envelope is None else
                                        envelope[w0 - lo:w1 - lo + 1], **options)
            total += r.time
            start += r.start_time
            iterations += r.iterations
            bs.append(r.b[1:])
            as_.append(r.a[1:])
    return JerkResult(total, np.concatenate(bs), np.concatenate(as_), iterations, start)


def windows(lo: int, hi: int, window: int | None) -> list[int]:
    """The grid indices ``lo = w_0 < w_1 < ... < w_m = hi`` that cut the stretch ``[lo, hi]`` into
    windows of at most ``window`` points (consecutive windows share their end point), as even as
    they can be; ``[lo, hi]`` when it fits in one."""
    if window is None or hi - lo + 1 <= window:
        return [lo, hi]
    if window < 3:
        raise ValueError("a window needs at least 3 points")
    count = math.ceil((hi - lo) / (window - 1))
    return [lo + round(i * (hi - lo) / count) for i in range(count + 1)]


def _part(path: JerkPath, lo: int, hi: int, rest_start: bool, rest_end: bool) -> JerkPath:
    """The grid points ``lo..hi`` of ``path`` as a path of their own, at rest at its start and end
    only where asked (a stop inside it stays one).  A point's acceleration rows all come along
    (a junction's incoming and outgoing ones; at a stop the other side's bound nothing)."""
    rows = (path.points >= lo) & (path.points <= hi)
    inner = np.asarray(path.stops, dtype=int)
    inner = inner[(inner > lo) & (inner < hi)] - lo
    ends = [i for i, rest in ((0, rest_start), (hi - lo, rest_end)) if rest]
    return JerkPath(path.s[lo:hi + 1] - path.s[lo], path.points[rows] - lo, path.q1[rows], path.q2[rows],
                    path.xmax[lo:hi + 1], np.unique(np.concatenate([np.array(ends, dtype=int), inner])),
                    path.m1[lo:hi], path.m2[lo:hi], path.m3[lo:hi])


def _envelope(path: JerkPath, amax: np.ndarray) -> np.ndarray:
    """The jerk-free time-optimal ``sdot²`` along ``path`` from rest to rest (``lower_bound.topp_profile``
    on the points' outgoing rows, velocity caps passed as a path-speed cap): above every profile
    that meets the velocity and acceleration limits, so a cap that loses no jerk-limited profile."""
    n = path.s.size
    amax = np.broadcast_to(np.asarray(amax, float), (path.q1.shape[1],))
    stops = np.unique(np.concatenate([[0, n - 1], np.asarray(path.stops, dtype=int)]))
    xmax = np.minimum(path.xmax, 1e200)
    xmax[stops] = 0.0
    last = np.zeros(n, dtype=int)
    last[path.points] = np.arange(path.points.size)
    envelope = topp_profile(path.q1[last], path.q1[last], path.q2[last], path.s, np.full(amax.shape, np.inf), amax,
                            vcap=np.sqrt(xmax), stops=stops)
    return np.minimum(envelope, xmax)


def jerk_time_between_stops(path: JerkPath, amax, jmax, *, rho: float = 1.0, tol: float = 1e-5, gain: float = 1e-8,
                            max_iterations: int = 80, envelope: np.ndarray | None = None) -> JerkResult:
    """Time of a locally time-optimal jerk-limited profile along ``path`` (see the module docstring).

    Args:
        path: the sampled path (:class:`JerkPath`).
        amax, jmax: (D,) per-axis acceleration (mm/s²) and jerk (mm/s³) limits (``inf`` jerk: none).
        rho: initial trust-region radius (relative change of ``b`` per step).
        tol, gain: stop once ρ < ``tol`` or a kept step shortens the time by less than ``gain`` (relative).
        envelope: the cap on ``b`` (default: the jerk-free optimum of ``path`` from rest to rest); a
            window of a longer stretch passes that stretch's (its own ends are not at rest).
    """
    amax = np.broadcast_to(np.asarray(amax, float), (path.q1.shape[1],)).copy()
    jmax = np.broadcast_to(np.asarray(jmax, float), (path.q1.shape[1],)).copy()
    problem = _Problem(path, amax, jmax)
    n = path.s.size
    stops = problem.stops
    ds = problem.ds
    xmax = np.minimum(path.xmax, 1e200)
    xmax[stops] = 0.0
    if envelope is None:
        envelope = _envelope(path, amax)
    envelope = np.minimum(envelope, xmax)
    x = problem.solve(_gradient(envelope, ds), np.zeros(n), envelope, *problem.conservative(envelope))
    if x is None:
        raise RuntimeError("no jerk-limited profile below the jerk-free optimum (infeasible LP)")
    t = start = _time(x[:n], ds)
    iterations = 1
    while rho >= tol and iterations < max_iterations:
        b = x[:n]
        lo = np.maximum(b * (1.0 - rho), 0.0)
        ub = np.minimum(b * (1.0 + rho) + REACH * rho * envelope, envelope)
        trial = problem.solve(_gradient(b, ds), lo, ub, *problem.linearised(x))
        iterations += 1
        if trial is None:
            rho /= 2.0
            continue
        # back onto the feasible set: the best profile below the step with conservative jerk rows
        trial = problem.solve(_gradient(trial[:n], ds), np.zeros(n), trial[:n], *problem.conservative(trial[:n]))
        iterations += 1
        t_new = math.inf if trial is None else _time(trial[:n], ds)
        if t_new < t:
            improved = (t - t_new) / t
            x, t = trial, t_new
            rho = min(2.0 * rho, 4.0)
            if improved < gain:
                break
        else:
            rho /= 2.0
    return JerkResult(_time(x[:n], ds), x[:n], x[n:], iterations, start)
