"""Curves sampled into chords: Akima splines (#SPLINE, seed 002 L15688-L15821) and the polynomials of
#POLY (L15822-L15870).

Pure numpy.  The interpreter turns the chords into G01 records the planner times like any other
move; each chord stays within :data:`CHORD_TOLERANCE` of the curve.  The bound is exact, not
estimated: a curve ``c`` and its chord over ``[a, b]`` (same parameter, linear interpolation) differ by
at most ``(b - a)² / 8 · max |c''|`` on the interval, and the sampling takes enough chords for the
largest ``|c''|`` of each interval.
"""

from __future__ import annotations

import math
from itertools import pairwise

import numpy as np

#: Largest distance (mm; degrees count as mm) between a curve and the chords that stand for it.
CHORD_TOLERANCE = 0.001
#: Most chords one curve may become (a larger curve is refused, not sampled coarser).
MAX_CHORDS = 200_000
#: Intervals a #POLY parameter range is cut into, each sampled for its own curvature.
POLY_INTERVALS = 16


class CurveError(ValueError):
    """A curve that cannot be sampled within the limits (too many chords)."""


def akima_slopes(t: np.ndarray, y: np.ndarray, start: np.ndarray | None = None,
                 end: np.ndarray | None = None) -> np.ndarray:
    """Akima's slopes ``dy/dt`` at the knots ``t`` (increasing, n >= 2) of the values ``y`` (n, D).

    With ``m_i`` the slope of segment ``i`` (knots i, i+1), the slope at knot ``i`` is
    ``(|m_{i+1} - m_i| m_{i-1} + |m_{i-1} - m_{i-2}| m_i) / (|m_{i+1} - m_i| + |m_{i-1} - m_{i-2}|)``,
    the mean of ``m_{i-1}`` and ``m_i`` when both weights are 0 (Akima 1970), per coordinate.  Two
    slopes are added at each end by Akima's extrapolation ``m_{-1} = 2 m_0 - m_1``,
    ``m_{-2} = 2 m_{-1} - m_0`` (the same at the far end); with two knots every slope is the chord's.
    ``start`` / ``end`` replace the slope at the first / last knot (a given tangent).
    """
    t = np.asarray(t, dtype=float)
    y = np.asarray(y, dtype=float)
    if y.ndim == 1:
        y = y[:, None]
    n = len(t)
    m = np.diff(y, axis=0) / np.diff(t)[:, None]
    ext = np.empty((n + 3, y.shape[1]))
    ext[2:n + 1] = m
    if n == 2:
        ext[:] = m[0]
    else:
        ext[1] = 2.0 * m[0] - m[1]
        ext[0] = 2.0 * ext[1] - m[0]
        ext[n + 1] = 2.0 * m[-1] - m[-2]
        ext[n + 2] = 2.0 * ext[n + 1] - m[-1]
    w_next = np.abs(ext[3:] - ext[2:-1])    # |m_{i+1} - m_i| at knot i
    w_prev = np.abs(ext[1:-2] - ext[:-3])   # |m_{i-1} - m_{i-2}|
    total = w_next + w_prev
    with np.errstate(invalid="ignore", divide="ignore"):
        s = np.where(total > 0.0, (w_next * ext[1:-2] + w_prev * ext[2:-1]) / total, (ext[1:-2] + ext[2:-1]) / 2.0)
    if start is not None:
        s[0] = start
    if end is not None:
        s[-1] = end
    return s


def hermite_coefficients(y0: np.ndarray, y1: np.ndarray, s0: np.ndarray, s1: np.ndarray, h: float) -> np.ndarray:
    """The cubic ``y0 + s0 τ + c2 τ² + c3 τ³`` (τ in [0, h]) with values y0, y1 and slopes s0, s1 at
    its ends: rows (y0, s0, c2, c3) of shape (4, D)."""
    m = (y1 - y0) / h
    c2 = (3.0 * m - 2.0 * s0 - s1) / h
    c3 = (s0 + s1 - 2.0 * m) / (h * h)
    return np.array([y0, s0, c2, c3])


def _chords(h: float, second: float, tol: float) -> int:
    """Chords of equal parameter step over a length ``h`` of parameter for ``|c''| <= second``."""
    if second <= 0.0 or h <= 0.0:
        return 1
    return max(1, math.ceil(h * math.sqrt(second / (8.0 * tol))))


def sample_cubic(coeffs: np.ndarray, h: float, tol: float = CHORD_TOLERANCE) -> np.ndarray:
    """Parameters τ in ``[0, h]`` (both ends included) whose chords stay within ``tol`` of the cubic.

    ``c''(τ) = 2 c2 + 6 c3 τ`` is linear in τ, so its norm is largest at an end of the interval."""
    c2, c3 = coeffs[2], coeffs[3]
    second = max(float(np.linalg.norm(2.0 * c2)), float(np.linalg.norm(2.0 * c2 + 6.0 * c3 * h)))
    return np.linspace(0.0, h, _chords(h, second, tol) + 1)


def cubic_points(coeffs: np.ndarray, tau: np.ndarray) -> np.ndarray:
    """Points (len(tau), D) of the cubic ``coeffs`` (rows y0, s0, c2, c3)."""
    powers = np.vander(tau, 4, increasing=True)   # 1, τ, τ², τ³
    return powers @ coeffs


def poly_points(coeffs: np.ndarray, p0: float, p1: float,
                tol: float = CHORD_TOLERANCE) -> tuple[np.ndarray, np.ndarray]:
    """#POLY: parameters from ``p0`` to ``p1`` and the points (n, D) of the polynomials ``coeffs``
    (D, 5: a + b p + c p² + d p³ + e p⁴ per axis) whose chords stay within ``tol`` of the curve.

    Per interval the bound on ``|c''|`` is the norm of each axis's largest ``|2c + 6d p + 12e p²|``,
    a parabola whose largest magnitude is at an end or at its vertex.  Raises :class:`CurveError`
    beyond :data:`MAX_CHORDS`."""
    cuts = np.linspace(p0, p1, POLY_INTERVALS + 1)
    c2, c3, c4 = 2.0 * coeffs[:, 2], 6.0 * coeffs[:, 3], 12.0 * coeffs[:, 4]
    params = [np.array([p0])]
    total = 0
    for a, b in pairwise(cuts.tolist()):
        lo, hi = min(a, b), max(a, b)
        cand = [np.full_like(c2, lo), np.full_like(c2, hi)]
        with np.errstate(invalid="ignore", divide="ignore"):
            vertex = np.where(c4 != 0.0, -c3 / (2.0 * np.where(c4 != 0.0, c4, 1.0)), lo)
        cand.append(np.clip(vertex, lo, hi))
        worst = np.max([np.abs(c2 + c3 * x + c4 * x * x) for x in cand], axis=0)
        n = _chords(abs(b - a), float(np.linalg.norm(worst)), tol)
        total += n
        if total > MAX_CHORDS:
            raise CurveError(f"the curve needs more than {MAX_CHORDS} chords of {tol * 1000:g} µm")
        params.append(np.linspace(a, b, n + 1)[1:])
    p = np.concatenate(params)
    points = np.vander(p, 5, increasing=True) @ coeffs.T
    return p, points


def poly_tangent(coeffs: np.ndarray, p: float) -> np.ndarray:
    """Derivative (D,) of the polynomials ``coeffs`` (D, 5) at ``p``."""
    return coeffs[:, 1] + 2.0 * coeffs[:, 2] * p + 3.0 * coeffs[:, 3] * p * p + 4.0 * coeffs[:, 4] * p ** 3


def spline_points(points: np.ndarray, start: np.ndarray | None = None, end: np.ndarray | None = None,
                  tol: float = CHORD_TOLERANCE) -> list[np.ndarray]:
    """The Akima spline through ``points`` (n >= 2, distinct consecutive), parameterised by the
    cumulative chord length, as chord end points per segment: item ``i`` holds the points after
    knot ``i`` up to knot ``i + 1`` included.  ``start`` / ``end``: unit tangents at the ends (None:
    Akima's automatic slope).  Raises :class:`CurveError` beyond :data:`MAX_CHORDS`."""
    t = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(points, axis=0), axis=1))])
    slopes = akima_slopes(t, points, start, end)
    out, total = [], 0
    for i in range(len(points) - 1):
        h = float(t[i + 1] - t[i])
        coeffs = hermite_coefficients(points[i], points[i + 1], slopes[i], slopes[i + 1], h)
        tau = sample_cubic(coeffs, h, tol)
        total += len(tau) - 1
        if total > MAX_CHORDS:
            raise CurveError(f"the spline needs more than {MAX_CHORDS} chords of {tol * 1000:g} µm")
        seg = cubic_points(coeffs, tau[1:])
        seg[-1] = points[i + 1]   # the knot exactly as programmed
        out.append(seg)
    return out
