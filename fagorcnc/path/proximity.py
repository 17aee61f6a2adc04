"""Distances between plane elements, for the gouge checks of radius compensation (spec 04 §16.2).

An element is ``(kind, p, q, centre, ccw)``: a line from p to q, or an arc about ``centre``.
"""

from __future__ import annotations

import math

from .aids import _cross
from .arcs import sweep

Point = tuple[float, float]

#: Samples along an arc when measuring how close a compensated path comes to the profile.
ARC_SAMPLES = 48
#: A compensated path nearer to the profile than R minus this (mm) gouges it.
GOUGE_TOLERANCE = 1e-6


def points_along(kind: str, p: Point, q: Point, centre: Point | None, ccw: bool) -> list[Point]:
    """Points along a line (its two ends: distances to a segment or an arc are checked exactly
    or densely on the other side) or along an arc (``ARC_SAMPLES`` and its ends)."""
    if kind != "arc" or centre is None:
        return [p, q]
    a0 = math.atan2(p[1] - centre[1], p[0] - centre[0])
    rho = math.dist(p, centre)
    total = math.radians(sweep(p, q, centre, ccw))   # sweep() is in degrees
    return [(centre[0] + rho * math.cos(a0 + total * i / ARC_SAMPLES),
             centre[1] + rho * math.sin(a0 + total * i / ARC_SAMPLES)) for i in range(ARC_SAMPLES + 1)]


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


def nearest(path: tuple, profile: tuple) -> float:
    """Least distance from a compensated element to a programmed one (exact between two lines,
    from dense samples with an arc)."""
    kind, p, q, centre, ccw = path
    pkind, pp, pq, pcentre, pccw = profile
    if kind != "arc" and pkind != "arc":
        return segments_distance(p, q, pp, pq)
    if pkind != "arc":
        return min(to_segment(x, pp, pq) for x in points_along(kind, p, q, centre, ccw))
    points = points_along(kind, p, q, centre, ccw)
    if kind != "arc":   # a line against an arc: the line's points densely
        points = [(p[0] + (q[0] - p[0]) * i / ARC_SAMPLES, p[1] + (q[1] - p[1]) * i / ARC_SAMPLES)
                  for i in range(ARC_SAMPLES + 1)]
    return min(to_arc(x, pp, pq, pcentre, pccw) for x in points)
