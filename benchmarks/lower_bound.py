"""Independent time-optimal path parameterisation (TOPP): a lower bound on traversal time.

Given a geometric path sampled on an arc-length grid ``s`` (positions ``q``, unit tangent ``dq = q'`` and
curvature vector ``ddq = q''``) and per-axis velocity / acceleration limits, :func:`topp_time` returns the
minimum time needed to traverse it from rest to rest.  Jerk is ignored, so the result is a LOWER BOUND on
the time of any jerk-limited planner that honours the same velocity and acceleration limits; it is used
to report "planned time / lower bound" ratios.  Only numpy is used; nothing is shared with the planner.

Method (TOPP-RA style, Pham & Pham 2018), in the variables x = sdot^2 and u = sddot:

* constraints are evaluated at grid points only: |q'_i| sqrt(x) <= vmax_i, sqrt(x) <= vcap_k and
  |q'_i u + q''_i x| <= amax_i; between grid points x_{k+1} = x_k + 2 u_k (s_{k+1} - s_k);
* the maximum velocity curve (MVC) is the largest x allowed by the velocity limits and by
  u-feasibility of the acceleration limits (for every axis pair the u-interval must not be empty,
  which gives the closed form ``min_{i<j} (A_j a_i + A_i a_j) / |c_j a_i - c_i a_j|``);
* a backward pass builds the controllable sets [0, K_k]: starting from K = 0 at the end and at every
  stop, K_k = min(MVC_k, largest x_k that can still decelerate into [0, K_{k+1}]), which is the min
  of one affine function of K_{k+1} per axis;
* a greedy forward pass from x_0 = 0 takes the largest feasible u:
  x_{k+1} = min(K_{k+1}, min_i(x_k + 2 Δ (A_i - c_i x_k) / a_i));
* time = sum 2 Δ / (v_k + v_{k+1}), exact for constant u over each interval, except that where the
  optimum peaks between two grid points the interval is integrated bang-bang (max acceleration, then
  max deceleration, peak capped by the MVC of its ends), which is never slower: a straight line gives
  the exact trapezoid/triangle time on any grid, and curves converge to the continuous time from below.

Both passes are sequential recursions ``y_{m+1} = min(cap_{m+1}, min_i(a_mi y_m + b_mi))``.  They are
vectorised for the common case (y sits on its cap: cruising on the MVC, the feed cap or the
controllable-set boundary); a plain Python loop runs only over the stretches that leave the cap
(acceleration / deceleration ramps), with the per-axis pieces reduced beforehand to the (at most two)
that can be active at each step.  The discrete problem approximates the continuous one to O(Δ);
with a grid spacing below ~R/20 (R the smallest radius of curvature) it is within ~0.2 % of the exact
continuous value.
"""

from __future__ import annotations

import numpy as np

_BIG = 1e300  # "no constraint" for a piece of the recursions (finite, to keep 0 * _BIG well defined)
_HUGE = 1e200  # stand-in for an infinite maximum velocity curve
_TINY = 1e-12  # |q'_i| below this: axis i does not constrain u (only x, through the MVC)


def _rowmin(m: np.ndarray) -> np.ndarray:
    """Row-wise minimum of an (M, W) array (faster than ``np.min(axis=1)`` for small W)."""
    out = m[:, 0].copy()
    for j in range(1, m.shape[1]):
        np.minimum(out, m[:, j], out=out)
    return out


def _reduce_pieces(cap: np.ndarray, a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Keep, per step, the (at most two) pieces of min_i(a_i y + b_i) that matter for y in [0, cap_m].

    (y = sdot² >= 0 in both passes, and y_m <= cap_m by construction.)
    The lower envelope of lines on [0, cap] starts with the piece minimal at 0 and ends with the one
    minimal at cap; those two describe it exactly unless a third line dips below their crossing point.
    Returns (a2, b2) of shape (M-1, 2), or the inputs unchanged if some step needs more than two pieces.
    """
    rows = np.arange(a.shape[0])
    at_cap = a * cap[:-1, None] + b
    j0, j1 = np.argmin(b, axis=1), np.argmin(at_cap, axis=1)
    a2 = np.stack([a[rows, j0], a[rows, j1]], axis=1)
    b2 = np.stack([b[rows, j0], b[rows, j1]], axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        ycross = np.clip((b2[:, 1] - b2[:, 0]) / (a2[:, 0] - a2[:, 1]), 0.0, cap[:-1])
    ycross = np.where(np.isfinite(ycross), ycross, 0.0)
    two = _rowmin(a2 * ycross[:, None] + b2)
    full = _rowmin(a * ycross[:, None] + b)
    if np.all(full >= two - 1e-12 * np.abs(two)):
        return a2, b2
    return a, b


def _sweep(cap: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Solve y_0 = cap_0, y_{m+1} = min(cap_{m+1}, min_i(a[m, i] * y_m + b[m, i])) for m = 0..M-2."""
    y = cap.copy()
    a, b = _reduce_pieces(cap, a, b)
    on_cap_step = _rowmin(a * cap[:-1, None] + b)  # next value when y_m == cap_m
    starts = np.flatnonzero(on_cap_step < cap[1:])  # where the sequence leaves its cap
    last = y.size - 1
    done = 0  # y is final for every index < done
    for m0 in starts.tolist():
        if m0 < done:
            continue  # inside a stretch already integrated
        m, ym, chunk, back_on_cap = m0, float(y[m0]), 64, False
        while m < last and not back_on_cap:
            hi = min(m + chunk, last)
            out: list[float] = []
            caps = cap[m + 1 : hi + 1].tolist()
            if a.shape[1] == 2:  # fast path: two pieces, unrolled
                cols = (caps, *a[m:hi].T.tolist(), *b[m:hi].T.tolist())
                for c, a0, a1, b0, b1 in zip(*cols, strict=True):
                    v = a0 * ym + b0
                    t = a1 * ym + b1
                    if t < v:
                        v = t
                    if v >= c:
                        v = c
                        back_on_cap = True
                    out.append(v)
                    ym = v
                    if back_on_cap:
                        break
            else:
                for c, ra, rb in zip(caps, a[m:hi].tolist(), b[m:hi].tolist(), strict=True):
                    v = c
                    for ai, bi in zip(ra, rb, strict=True):
                        t = ai * ym + bi
                        if t < v:
                            v = t
                    out.append(v)
                    ym = v
                    if v == c:
                        back_on_cap = True
                        break
            y[m + 1 : m + 1 + len(out)] = out
            m += len(out)
            chunk = min(2 * chunk, 1 << 16)
        done = m
    return y


def _solve(
    q: np.ndarray,
    dq: np.ndarray,
    ddq: np.ndarray,
    s: np.ndarray,
    vmax: np.ndarray,
    amax: np.ndarray,
    vcap: np.ndarray | None = None,
    stops: np.ndarray | None = None,
) -> tuple[np.ndarray, ...]:
    """Return (x, xmax, a, c, amax, ds): the optimal sdot², the MVC and the sign-normalised coefficients."""
    s = np.asarray(s, dtype=float)
    dq = np.asarray(dq, dtype=float)
    ddq = np.asarray(ddq, dtype=float)
    n, d = dq.shape
    if np.shape(q) != (n, d) or ddq.shape != (n, d) or s.shape != (n,) or n < 2:
        raise ValueError("q, dq, ddq must be (N, D) and s (N,) with N >= 2")
    ds = np.diff(s)
    if np.any(ds <= 0):
        raise ValueError("s must be strictly increasing")
    vmax = np.broadcast_to(np.asarray(vmax, dtype=float), (d,))
    amax = np.broadcast_to(np.asarray(amax, dtype=float), (d,))

    # Flip each axis so that the tangent component is >= 0: a_i = |q'_i| and c_i = sign(q'_i) q''_i.
    sign = np.where(dq >= 0.0, 1.0, -1.0)
    a = np.abs(dq)
    c = ddq * sign

    # Maximum velocity curve (in x = sdot²): velocity limits, feed cap, u-feasibility of acceleration limits.
    with np.errstate(divide="ignore", invalid="ignore"):
        xmax = np.min(np.where(a > 0.0, (vmax / a) ** 2, np.inf), axis=1)
        for i in range(d):
            for j in range(i + 1, d):
                num = amax[j] * a[:, i] + amax[i] * a[:, j]
                den = np.abs(c[:, j] * a[:, i] - c[:, i] * a[:, j])
                xmax = np.minimum(xmax, np.where(den > 0.0, num / den, np.inf))
    if vcap is not None:
        xmax = np.minimum(xmax, np.asarray(vcap, dtype=float) ** 2)
    xmax[[0, -1]] = 0.0
    if stops is not None:
        xmax[np.asarray(stops, dtype=int)] = 0.0
    xmax = np.minimum(xmax, _HUGE)  # keep the recursions finite where nothing bounds the speed

    ak, ck, dsk = a[:-1], c[:-1], ds[:, None]  # coefficients of interval k use point k
    with np.errstate(divide="ignore", invalid="ignore"):
        # Backward: x_k + 2Δ u_lo(x_k) <= K_{k+1} with u_lo = max_i (-A_i - c_i x)/a_i, solved for x_k
        # per axis: x_k <= (a_i K_{k+1} + 2Δ A_i) / (a_i - 2Δ c_i) when the denominator is positive.
        den = ak - 2.0 * dsk * ck
        ok = den > 0.0
        alpha = np.where(ok, ak / den, 0.0)
        beta = np.where(ok, 2.0 * dsk * amax / den, _BIG)
        # Forward: x_{k+1} <= x_k + 2Δ u_hi(x_k) with u_hi = min_i (A_i - c_i x)/a_i over axes with a_i > 0.
        moving = ak > _TINY
        gamma = np.where(moving, 1.0 - 2.0 * dsk * ck / ak, 0.0)
        delta = np.where(moving, 2.0 * dsk * amax / ak, _BIG)
    kmax = _sweep(xmax[::-1], alpha[::-1], beta[::-1])[::-1]
    return np.maximum(_sweep(kmax, gamma, delta), 0.0), xmax, a, c, amax, ds


def topp_profile(
    q: np.ndarray,
    dq: np.ndarray,
    ddq: np.ndarray,
    s: np.ndarray,
    vmax: np.ndarray,
    amax: np.ndarray,
    vcap: np.ndarray | None = None,
    stops: np.ndarray | None = None,
) -> np.ndarray:
    """Time-optimal squared path speed x_k = sdot_k² (mm²/s²) at every grid point.

    Arguments as for :func:`topp_time`.  The result is zero at both ends and at the stops, and
    u_k = (x_{k+1} - x_k) / (2 Δs_k) satisfies the acceleration limits at grid point k.
    """
    return _solve(q, dq, ddq, s, vmax, amax, vcap, stops)[0]


def topp_time(
    q: np.ndarray,
    dq: np.ndarray,
    ddq: np.ndarray,
    s: np.ndarray,
    vmax: np.ndarray,
    amax: np.ndarray,
    vcap: np.ndarray | None = None,
    stops: np.ndarray | None = None,
) -> float:
    """Minimum rest-to-rest traversal time (s) of a sampled path under per-axis velocity/acceleration limits.

    Args:
        q: (N, D) positions in mm (only its shape is used; the geometry enters through dq and ddq).
        dq: (N, D) first derivative dq/ds (unit tangent for an arc-length parameterisation).  At a stop
            between two segments give the outgoing segment's derivatives (the incoming side is
            constrained through the preceding grid point).
        ddq: (N, D) second derivative d²q/ds² (curvature vector).
        s: (N,) strictly increasing arc-length grid in mm, s[0] = 0; spacing may be non-uniform.
        vmax: (D,) per-axis velocity limits in mm/s (``np.inf`` allowed if something else bounds speed).
        amax: (D,) per-axis acceleration limits in mm/s² (positive).
        vcap: optional (N,) path-speed cap in mm/s at each grid point (programmed feed); None = no cap.
        stops: optional integer indices where the path speed must be zero; the first and last points
            are always stops.

    Returns:
        The minimum traversal time in seconds of the discretised problem (jerk ignored): a lower bound
        on the time of any plan that respects these limits, up to the O(Δs) discretisation error.
    """
    x, xmax, a, c, amax, ds = _solve(q, dq, ddq, s, vmax, amax, vcap, stops)
    x0, x1, v0, v1 = x[:-1], x[1:], np.sqrt(x[:-1]), np.sqrt(x[1:])
    with np.errstate(divide="ignore", invalid="ignore"):
        dt = 2.0 * ds / (v0 + v1)  # constant u over the interval (inf between two adjacent stops)
        # Lower the bound further where the optimum peaks between two grid points: accelerate with the
        # largest u at x_k, then brake with the largest deceleration at x_{k+1} (both with point k's
        # coefficients), the peak capped by the larger MVC of the two ends.
        moving = a[:-1] > _TINY
        inv = np.where(moving, 1.0 / a[:-1], 0.0)
        acc = _rowmin(np.where(moving, (amax - c[:-1] * x0[:, None]) * inv, np.inf))
        dec = _rowmin(np.where(moving, (amax + c[:-1] * x1[:, None]) * inv, np.inf))
        xpeak = (dec * x0 + acc * x1 + 2.0 * acc * dec * ds) / (acc + dec)
        xcap = np.maximum(np.maximum(xmax[:-1], xmax[1:]), np.maximum(x0, x1))
        xtop = np.minimum(xpeak, xcap)
        vtop = np.sqrt(xtop)
        cruise = ds - (xtop - x0) / (2.0 * acc) - (xtop - x1) / (2.0 * dec)
        bang = (vtop - v0) / acc + (vtop - v1) / dec + np.where(cruise > 0.0, cruise / vtop, 0.0)
        valid = (acc > 0.0) & (dec > 0.0) & np.isfinite(bang) & (xpeak >= np.maximum(x0, x1))
    dt = np.where(valid, np.minimum(dt, bang), dt)
    return float(np.sum(dt))
