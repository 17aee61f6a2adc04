"""Rotation arithmetic of the kinematics (degrees, right-hand rule, numpy 3-vectors).

``rot(d, a)`` turns a vector by ``a`` degrees about the unit direction ``d``: positive counter-clockwise
looking from the tip of ``d`` toward the origin (the right-hand rule; spec 05 §6.4, A20).
"""

from __future__ import annotations

import math

import numpy as np

EPS = 1e-9


def unit(v) -> np.ndarray:
    """``v`` scaled to length 1 (ValueError for a null vector)."""
    v = np.asarray(v, dtype=float)
    n = float(np.linalg.norm(v))
    if n < EPS:
        raise ValueError("a direction needs a non-zero vector")
    return v / n


def rot(d, degrees: float) -> np.ndarray:
    """The 3x3 rotation by ``degrees`` about the unit vector ``d`` (Rodrigues)."""
    x, y, z = d
    a = math.radians(degrees)
    c, s = math.cos(a), math.sin(a)
    k = 1.0 - c
    return np.array([
        [c + x * x * k, x * y * k - z * s, x * z * k + y * s],
        [y * x * k + z * s, c + y * y * k, y * z * k - x * s],
        [z * x * k - y * s, z * y * k + x * s, c + z * z * k],
    ])


def rx(a: float) -> np.ndarray:
    return rot((1.0, 0.0, 0.0), a)


def ry(a: float) -> np.ndarray:
    return rot((0.0, 1.0, 0.0), a)


def rz(a: float) -> np.ndarray:
    return rot((0.0, 0.0, 1.0), a)


def angle_about(d, u, w) -> float | None:
    """The angle (degrees, in (-180, 180]) that turns ``u`` onto ``w`` about ``d`` (Paden-Kahan subproblem 1),
    or None when ``u`` lies along ``d`` (any angle does: the singular case)."""
    d = np.asarray(d, dtype=float)
    up = u - d * float(d @ u)
    wp = w - d * float(d @ w)
    if np.linalg.norm(up) < 1e-9 or np.linalg.norm(wp) < 1e-9:
        return None
    return math.degrees(math.atan2(float(d @ np.cross(up, wp)), float(up @ wp)))


def two_angles(a, b, p, q) -> list[tuple[float | None, float | None]]:
    """All (t1, t2) with ``rot(a, t1) @ rot(b, t2) @ p == q`` (Paden-Kahan subproblem 2, unit ``p``, ``q``).

    Zero, one or two solutions; an angle is None where it is free (``p`` along ``b`` for t2, the
    intermediate vector along ``a`` for t1).  ``a`` and ``b`` must not be parallel.
    """
    a, b, p, q = (np.asarray(v, dtype=float) for v in (a, b, p, q))
    ab = float(a @ b)
    den = ab * ab - 1.0
    if abs(den) < 1e-12:
        raise ValueError("the two rotation axes are parallel")
    # z = rot(b, t2) p = rot(a, -t1) q: z.b = p.b, z.a = q.a, |z| = |p|
    alpha = (ab * float(b @ p) - float(a @ q)) / den
    beta = (ab * float(a @ q) - float(b @ p)) / den
    axb = np.cross(a, b)
    g2 = (float(p @ p) - alpha * alpha - beta * beta - 2.0 * alpha * beta * ab) / float(axb @ axb)
    if g2 < -1e-9:
        return []
    gammas = [0.0] if g2 < 1e-12 else [math.sqrt(g2), -math.sqrt(g2)]
    out = []
    for g in gammas:
        z = alpha * a + beta * b + g * axb
        t2 = angle_about(b, p, z)
        t1 = angle_about(a, z, q)
        out.append((t1, t2))
    return out


def wrap(a: float) -> float:
    """``a`` degrees brought into (-180, 180]."""
    r = math.fmod(a, 360.0)
    if r <= -180.0:
        r += 360.0
    elif r > 180.0:
        r -= 360.0
    return r
