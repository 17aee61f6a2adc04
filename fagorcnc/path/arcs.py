"""Arc geometry in the plane (seed 002 ch. 8.3-8.6; spec 03 §B.3-B.12).

Points are ``(a, o)`` pairs: abscissa and ordinate of the active plane.
Angles are degrees; a positive sweep is counter-clockwise (G03), seen with
+a to the right and +o up.  Functions raise :class:`ArcError` with a message
for a machinist; the interpreter turns it into a diagnostic on the block.
"""

from __future__ import annotations

import math

Point = tuple[float, float]


class ArcError(ValueError):
    """An arc that cannot be built from what the block gives."""


def sweep(s: Point, e: Point, c: Point, ccw: bool, eps: float = 1e-7) -> float:
    """Signed sweep from ``s`` to ``e`` about ``c``; a full turn when ``e`` is ``s`` (L6353)."""
    a0 = math.atan2(s[1] - c[1], s[0] - c[0])
    a1 = math.atan2(e[1] - c[1], e[0] - c[0])
    if math.dist(s, e) <= eps:
        return 360.0 if ccw else -360.0
    d = math.degrees(a1 - a0)
    if ccw:
        d %= 360.0
        return d or 360.0
    d = (-d) % 360.0
    return -(d or 360.0)


def centre_from_radius(s: Point, e: Point, r: float, clockwise: bool, tol: float = 1e-6) -> Point:
    """Centre of the arc of signed radius ``r`` from ``s`` to ``e`` (seed 002 L6406-L6435).

    ``r > 0`` gives the arc up to 180 degrees, ``r < 0`` the arc over 180.
    """
    if r == 0:
        raise ArcError("the arc radius must not be 0")
    chord = math.dist(s, e)
    if chord < 1e-12:
        raise ArcError("a full circle cannot be programmed by its radius (L6568)")
    half = chord / 2.0
    if abs(r) < half - tol:
        raise ArcError(f"radius {abs(r):g} is too small for the chord {chord:.4f} between start and end")
    h = math.sqrt(max(r * r - half * half, 0.0))
    ua, uo = (e[0] - s[0]) / chord, (e[1] - s[1]) / chord
    na, no = -uo, ua   # left normal of the chord
    sigma = 1.0 if (not clockwise) == (r > 0) else -1.0
    return ((s[0] + e[0]) / 2.0 + sigma * h * na, (s[1] + e[1]) / 2.0 + sigma * h * no)


def corrected_centre(s: Point, e: Point, c: Point) -> Point:
    """G265: the centre on the bisector of SE nearest to the programmed one (seed 002 L6976-L7018)."""
    chord = math.dist(s, e)
    if chord < 1e-12:
        return c
    m = ((s[0] + e[0]) / 2.0, (s[1] + e[1]) / 2.0)
    na, no = -(e[1] - s[1]) / chord, (e[0] - s[0]) / chord
    k = (c[0] - m[0]) * na + (c[1] - m[1]) * no
    return (m[0] + k * na, m[1] + k * no)


def tangent_arc(s: Point, t: Point, e: Point) -> tuple[Point, float, bool]:
    """G08: the arc from ``s`` tangent to the unit direction ``t`` ending at ``e``.

    Returns ``(centre, radius, ccw)`` (seed 002 L7019-L7081).
    """
    da, do = e[0] - s[0], e[1] - s[1]
    na, no = -t[1], t[0]
    k = da * na + do * no
    if abs(k) < 1e-12:
        raise ArcError("G08: the end point lies on the tangent of the previous path, there is no arc")
    r_signed = (da * da + do * do) / (2.0 * k)
    return (s[0] + r_signed * na, s[1] + r_signed * no), abs(r_signed), k > 0


def three_point_arc(s: Point, p: Point, e: Point) -> tuple[Point, float, bool]:
    """G09: the circle through ``s``, ``p`` and ``e``; ``(centre, radius, ccw)`` (seed 002 L7155-L7201)."""
    ax, ay = p[0] - s[0], p[1] - s[1]
    bx, by = e[0] - s[0], e[1] - s[1]
    cross = ax * by - ay * bx
    if abs(cross) < 1e-12 or math.dist(s, e) < 1e-12:
        raise ArcError("G09: the three points must be different and not on one line")
    a2, b2 = ax * ax + ay * ay, bx * bx + by * by
    ca = s[0] + (by * a2 - ay * b2) / (2.0 * cross)
    co = s[1] + (ax * b2 - bx * a2) / (2.0 * cross)
    return (ca, co), math.dist(s, (ca, co)), cross > 0


def end_tangent(s: Point, e: Point, c: Point | None, ccw: bool) -> Point | None:
    """Unit direction of travel at the end of a line (``c`` None) or an arc."""
    if c is None:
        d = math.dist(s, e)
        return None if d < 1e-12 else ((e[0] - s[0]) / d, (e[1] - s[1]) / d)
    ra, ro = e[0] - c[0], e[1] - c[1]
    r = math.hypot(ra, ro)
    if r < 1e-12:
        return None
    return (-ro / r, ra / r) if ccw else (ro / r, -ra / r)


def point_on(c: Point, r: float, angle: float) -> Point:
    """The point of the circle (``c``, ``r``) at ``angle`` degrees."""
    q = math.radians(angle)
    return (c[0] + r * math.cos(q), c[1] + r * math.sin(q))
