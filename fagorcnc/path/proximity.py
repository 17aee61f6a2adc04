"""Distances between plane elements, for the gouge checks of radius compensation (spec 04 §16.2).

An element is ``(kind, p, q, centre, ccw)``: a line from p to q, or an arc about ``centre``.
"""

from __future__ import annotations

import math

from .aids import _circle_circle, _cross, _line_circle
from .arcs import sweep

Point = tuple[float, float]

#: A compensated path nearer to the profile than R minus this (mm) gouges it.
GOUGE_TOLERANCE = 1e-6


def to_segment(x: Point, p: Point, q: Point) -> float:
    d = (q[0] - p[0], q[1] - p[1])
    den = d[0] * d[0] + d[1] * d[1]
    t = 0.0 if den == 0.0 else max(0.0, min(1.0, ((x[0] - p[0]) * d[0] + (x[1] - p[1]) * d[1]) / den))
    return math.dist(x, (p[0] + t * d[0], p[1] + t * d[1]))


def to_arc(x: Point, p: Point, q: Point, centre: Point, ccw: bool) -> float:
    """Distance from ``x`` to the arc from p to q about ``centre``."""
    rho = math.dist(p, centre)
    if math.dist(x, centre) > 1e-12 and abs(sweep(p, x, centre, ccw)) <= abs(sweep(p, q, centre, ccw)):
        return abs(math.dist(x, centre) - rho)   # x lies within the arc's angular span
    return min(math.dist(x, p), math.dist(x, q))


def segments_distance(p1: Point, q1: Point, p2: Point, q2: Point) -> float:
    """Least distance between two segments (0 when they cross)."""
    def side(a: Point, b: Point, c: Point) -> float:
        return _cross((b[0] - a[0], b[1] - a[1]), (c[0] - a[0], c[1] - a[1]))
    if side(p1, q1, p2) * side(p1, q1, q2) < 0 and side(p2, q2, p1) * side(p2, q2, q1) < 0:
        return 0.0
    return min(to_segment(p1, p2, q2), to_segment(q1, p2, q2), to_segment(p2, p1, q1), to_segment(q2, p1, q1))


def _on_arc(x: Point, p: Point, q: Point, centre: Point, ccw: bool) -> bool:
    """``x`` (on the arc's circle) lies within its angular span."""
    if math.dist(x, p) <= 1e-12 or math.dist(x, q) <= 1e-12:
        return True
    return abs(sweep(p, x, centre, ccw)) <= abs(sweep(p, q, centre, ccw))


def _arc_segment(arc: tuple, s1: Point, s2: Point) -> float:
    _k, p, q, c, ccw = arc
    rho = math.dist(p, c)
    best = min(to_arc(s1, p, q, c, ccw), to_arc(s2, p, q, c, ccw), to_segment(p, s1, s2), to_segment(q, s1, s2))
    length = math.dist(s1, s2)
    if length <= 1e-12:
        return best
    d = ((s2[0] - s1[0]) / length, (s2[1] - s1[1]) / length)
    k = (c[0] - s1[0]) * d[0] + (c[1] - s1[1]) * d[1]
    foot = (s1[0] + k * d[0], s1[1] + k * d[1])
    for x in _line_circle(s1, d, c, rho):   # crossings
        along = (x[0] - s1[0]) * d[0] + (x[1] - s1[1]) * d[1]
        if -1e-12 <= along <= length + 1e-12 and _on_arc(x, p, q, c, ccw):
            return 0.0
    h = math.dist(foot, c)
    if 0.0 <= k <= length and h > 1e-12:
        x = (c[0] + rho * (foot[0] - c[0]) / h, c[1] + rho * (foot[1] - c[1]) / h)
        if _on_arc(x, p, q, c, ccw):
            best = min(best, abs(h - rho))
    return best


def _arc_arc(a1: tuple, a2: tuple) -> float:
    _k, p1, q1, c1, ccw1 = a1
    _k, p2, q2, c2, ccw2 = a2
    r1, r2 = math.dist(p1, c1), math.dist(p2, c2)
    best = min(to_arc(p1, p2, q2, c2, ccw2), to_arc(q1, p2, q2, c2, ccw2),
               to_arc(p2, p1, q1, c1, ccw1), to_arc(q2, p1, q1, c1, ccw1))
    for x in _circle_circle(c1, r1, c2, r2):   # crossings
        if _on_arc(x, p1, q1, c1, ccw1) and _on_arc(x, p2, q2, c2, ccw2):
            return 0.0
    d = math.dist(c1, c2)
    if d > 1e-12:   # the other critical points lie on the line of the centres
        u = ((c2[0] - c1[0]) / d, (c2[1] - c1[1]) / d)
        for sgn in (1.0, -1.0):
            x1 = (c1[0] + sgn * r1 * u[0], c1[1] + sgn * r1 * u[1])
            if _on_arc(x1, p1, q1, c1, ccw1):
                best = min(best, to_arc(x1, p2, q2, c2, ccw2))
            x2 = (c2[0] + sgn * r2 * u[0], c2[1] + sgn * r2 * u[1])
            if _on_arc(x2, p2, q2, c2, ccw2):
                best = min(best, to_arc(x2, p1, q1, c1, ccw1))
    return best


def nearest(path: tuple, profile: tuple) -> float:
    """Least distance between two elements (a compensated one and a programmed one): exact, from the end
    points, the crossings and the critical points of lines and circles."""
    kind, p, q, _centre, _ccw = path
    pkind, pp, pq, _pcentre, _pccw = profile
    if kind != "arc" and pkind != "arc":
        return segments_distance(p, q, pp, pq)
    if pkind != "arc":
        return _arc_segment(path, pp, pq)
    if kind != "arc":
        return _arc_segment(profile, p, q)
    return _arc_arc(path, profile)
