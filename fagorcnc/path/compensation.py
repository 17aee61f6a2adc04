"""Tool radius compensation G40/G41/G42 with G136/G137 and G138/G139 (seed 002 L9427-L10071).

A streaming stage over the interpreter's records.  Each compensated move
carries ``comp = (side, radius, transition, start)``: side +1 for G41 (tool on
the left of the path), -1 for G42; ``transition`` 136 (circular joins) or 137
(linear joins) at outside corners; ``start`` 138 (direct) or 139 (indirect)
activation and cancellation.  The stage holds one programmed element until
the next one shows the corner (spec 04 §18):

* inside corners (the path turns toward the tool): both offsets are trimmed
  to their intersection;
* outside corners: G136 inserts an arc of radius R about the programmed
  corner; G137 prolongs the offsets in straight lines (one point for a
  corner up to 90 degrees, two beyond);
* the activation block (the first compensated move, a straight one) and the
  cancellation block (the first move after G40, straight) follow the tables
  of spec 04 §19-§20.

Moves off the plane (a Z plunge) between compensated moves are kept at the
joint.  A change of side (G41 <-> G42) or of radius without G40 joins the two
offsets at their intersection near the corner, else by a connecting segment
(spec 04 §22).  Reported as errors rather than handled: an inside corner whose
trim would reverse a move (a "step", which the CNC removes with a warning), a
move whose compensated path comes nearer than R to the profile two blocks back
or whose profile the path two blocks back comes that near (a gap narrower than
the tool, which the corner trims alone do not see; the CNC's look-ahead finds
such problems, L9455-L9459), arcs as activation or cancellation moves.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Iterator
from dataclasses import replace

from .aids import _arc_record, _circle_circle, _cross, _left, _line_circle, _line_record, _moved, _unit

Point = tuple[float, float]


class CompensationError(ValueError):
    """A compensated path fagorcnc cannot build; the message says why."""

    def __init__(self, record, message: str) -> None:
        super().__init__(message)
        self.record = record


def _planar(rec, a: str, o: str) -> bool:
    return math.hypot(rec.end[a] - rec.start[a], rec.end[o] - rec.start[o]) > 1e-9


def _pts(rec, a, o):
    return (rec.start[a], rec.start[o]), (rec.end[a], rec.end[o])


def _tangent(rec, a, o, at_end: bool) -> Point:
    p, q = _pts(rec, a, o)
    if rec.kind != "arc":
        return _unit((q[0] - p[0], q[1] - p[1]))
    c = (rec.center[a], rec.center[o])
    x = q if at_end else p
    t = _left(_unit((x[0] - c[0], x[1] - c[1])))
    return t if rec.direction == "ccw" else (-t[0], -t[1])


def _geometry(rec, a, o, s: float, r: float):
    """The offset of a move: ("line", point, direction) or ("circle", centre, radius)."""
    p, q = _pts(rec, a, o)
    if rec.kind != "arc":
        t = _unit((q[0] - p[0], q[1] - p[1]))
        n = _left(t)
        return ("line", (p[0] + s * r * n[0], p[1] + s * r * n[1]), t)
    c = (rec.center[a], rec.center[o])
    rho = math.dist(p, c)
    delta = 1.0 if rec.direction == "ccw" else -1.0
    rr = rho - s * delta * r
    if rr <= 1e-9:
        raise CompensationError(rec, f"the tool radius {r:g} is not smaller than the concave arc radius "
                                f"{rho:g}: the arc cannot be followed")
    return ("circle", c, rr)


def _meet(g1, g2, near: Point) -> Point | None:
    if g1[0] == "line" and g2[0] == "line":
        den = _cross(g1[2], g2[2])
        if abs(den) < 1e-12:
            return None
        d = (g2[1][0] - g1[1][0], g2[1][1] - g1[1][1])
        k = _cross(d, g2[2]) / den
        hits = [(g1[1][0] + k * g1[2][0], g1[1][1] + k * g1[2][1])]
    elif g1[0] == "line":
        hits = _line_circle(g1[1], g1[2], g2[1], g2[2])
    elif g2[0] == "line":
        hits = _line_circle(g2[1], g2[2], g1[1], g1[2])
    else:
        hits = _circle_circle(g1[1], g1[2], g2[1], g2[2])
    return min(hits, key=lambda x: math.dist(x, near)) if hits else None


def _offset_point(rec, a, o, s, r, at_end: bool) -> Point:
    """The perpendicular point of the offset at the start or the end of a move."""
    p, q = _pts(rec, a, o)
    x = q if at_end else p
    n = _left(_tangent(rec, a, o, at_end))
    return (x[0] + s * r * n[0], x[1] + s * r * n[1])


class _Move:
    """A move being compensated: its record and the plane points fixed so far.

    A compensated arc is checked at once: the tool must fit inside a concave arc.
    """

    __slots__ = ("end", "rec", "start")

    def __init__(self, rec, start: Point | None) -> None:
        self.rec, self.start, self.end = rec, start, None
        comp = getattr(rec, "comp", None)
        if rec.kind == "arc" and comp is not None:
            _geometry(rec, comp[4][0], comp[4][1], comp[0], comp[1])


def _join(prev: _Move, nxt_rec, a, o, s, r, transition, start_mode, activation: bool, cancel: bool):
    """Close the corner between ``prev`` and ``nxt_rec``.

    Returns (points inserted between them as a list of ("line"|"arc", p, q, centre, ccw),
    the start point of the next move).  Sets ``prev.end``.
    """
    rec = prev.rec
    _, corner = _pts(rec, a, o)
    t1 = _tangent(rec, a, o, True)
    t2 = _tangent(nxt_rec, a, o, False)
    n1, n2 = _left(t1), _left(t2)
    pa = (corner[0] + s * r * n1[0], corner[1] + s * r * n1[1])
    pb = (corner[0] + s * r * n2[0], corner[1] + s * r * n2[1])
    cross = _cross(t1, t2)
    dot = t1[0] * t2[0] + t1[1] * t2[1]
    if dot > 0 and (abs(cross) < 1e-9 or math.dist(pa, pb) < 1e-6):
        # tangent (or as good as): the offsets meet at A = B; a join arc of a few nanometres
        # would read as a full circle
        prev.end = pa
        return [], pb
    if s * cross > 1e-9:                  # inside corner: trim both offsets to their intersection
        g1 = (("line", pa, t1) if activation else _geometry(rec, a, o, s, r))
        g2 = (("line", pb, t2) if cancel else _geometry(nxt_rec, a, o, s, r))
        x = _meet(g1, g2, corner)
        if x is None or math.dist(x, corner) > 100 * max(r, 1e-9):
            raise CompensationError(nxt_rec, "the compensated moves do not meet at this inside corner")
        _check_step(prev, rec, a, o, x, t1)
        prev.end = x
        return [], x
    # outside corner (or a reversal)
    if (activation or cancel) and start_mode == 138:   # G138: straight to / from the offset point
        prev.end = pb if activation else pa
        return [], prev.end
    prev.end = pa
    if transition == 136:
        return [("arc", pa, pb, corner, s < 0)], pb
    psi = math.acos(max(-1.0, min(1.0, dot)))
    if psi <= math.pi / 2 + 1e-12:
        k = r * math.tan(psi / 2)
        q = (pa[0] + k * t1[0], pa[1] + k * t1[1])
        return [("line", pa, q, None, True), ("line", q, pb, None, True)], pb
    a2 = (pa[0] + r * t1[0], pa[1] + r * t1[1])
    b2 = (pb[0] - r * t2[0], pb[1] - r * t2[1])
    return [("line", pa, a2, None, True), ("line", a2, b2, None, True), ("line", b2, pb, None, True)], pb


def _side_change(prev: _Move, nxt_rec, a, o, old, new, activation: bool):
    """Case A: the two offsets meet near the corner -> trim both there; case B: a segment
    from the old side's perpendicular point A to the new side's B (spec 04 §22)."""
    s1, r1 = old[0], old[1]
    s2, r2 = new[0], new[1]
    rec = prev.rec
    _, corner = _pts(rec, a, o)
    n1 = _left(_tangent(rec, a, o, True))
    n2 = _left(_tangent(nxt_rec, a, o, False))
    pa = (corner[0] + s1 * r1 * n1[0], corner[1] + s1 * r1 * n1[1])
    pb = (corner[0] + s2 * r2 * n2[0], corner[1] + s2 * r2 * n2[1])
    g1 = ("line", pa, _tangent(rec, a, o, True)) if activation else _geometry(rec, a, o, s1, r1)
    g2 = _geometry(nxt_rec, a, o, s2, r2)
    x = _meet(g1, g2, corner)
    if x is not None and math.dist(x, corner) <= 4 * max(r1, r2):
        prev.end = x
        return [], x
    prev.end = pa
    return [("line", pa, pb, None, True)], pb


def _check_step(prev: _Move, rec, a, o, x: Point, t1: Point) -> None:
    if prev.start is None:
        return
    if rec.kind == "arc":
        # the offset arc, from its (trimmed) start to the trim point, must not sweep further
        # than the programmed arc: a longer sweep means the trim went past its start (a step)
        from .arcs import sweep

        c = (rec.center[a], rec.center[o])
        p, q = _pts(rec, a, o)
        ccw = rec.direction == "ccw"
        if abs(sweep(prev.start, x, c, ccw)) > abs(sweep(p, q, c, ccw)) + 1e-6:
            raise CompensationError(rec, "this arc is too short for the tool radius at the inside corner "
                                    "(a step in the profile); fagorcnc does not remove such moves yet")
        return
    along = (x[0] - prev.start[0]) * t1[0] + (x[1] - prev.start[1]) * t1[1]
    if along < -1e-9:
        raise CompensationError(rec, "this move is too short for the tool radius at the inside corner "
                                "(a step in the profile); fagorcnc does not remove such moves yet")


#: Samples along an arc when measuring how close a compensated path comes to the profile.
ARC_SAMPLES = 48
#: A compensated path nearer to the profile than R minus this (mm) gouges it.
GOUGE_TOLERANCE = 1e-6


def _points_along(kind: str, p: Point, q: Point, centre: Point | None, ccw: bool) -> list[Point]:
    """Points along a line (its two ends: distances to a segment or an arc are checked exactly
    or densely on the other side) or along an arc (``ARC_SAMPLES`` and its ends)."""
    if kind != "arc" or centre is None:
        return [p, q]
    from .arcs import sweep

    a0 = math.atan2(p[1] - centre[1], p[0] - centre[0])
    rho = math.dist(p, centre)
    total = math.radians(sweep(p, q, centre, ccw))   # sweep() is in degrees
    return [(centre[0] + rho * math.cos(a0 + total * i / ARC_SAMPLES),
             centre[1] + rho * math.sin(a0 + total * i / ARC_SAMPLES)) for i in range(ARC_SAMPLES + 1)]


def _to_segment(x: Point, p: Point, q: Point) -> float:
    d = (q[0] - p[0], q[1] - p[1])
    den = d[0] * d[0] + d[1] * d[1]
    t = 0.0 if den == 0.0 else max(0.0, min(1.0, ((x[0] - p[0]) * d[0] + (x[1] - p[1]) * d[1]) / den))
    return math.dist(x, (p[0] + t * d[0], p[1] + t * d[1]))


def _to_arc(x: Point, p: Point, q: Point, centre: Point, ccw: bool) -> float:
    """Distance from ``x`` to the arc from p to q about ``centre``."""
    from .arcs import sweep

    rho = math.dist(p, centre)
    if math.dist(x, centre) > 1e-12 and abs(sweep(p, x, centre, ccw)) <= abs(sweep(p, q, centre, ccw)):
        return abs(math.dist(x, centre) - rho)   # x lies within the arc's angular span
    return min(math.dist(x, p), math.dist(x, q))


def _segments_distance(p1: Point, q1: Point, p2: Point, q2: Point) -> float:
    """Least distance between two segments (0 when they cross)."""
    def side(a: Point, b: Point, c: Point) -> float:
        return _cross((b[0] - a[0], b[1] - a[1]), (c[0] - a[0], c[1] - a[1]))
    if side(p1, q1, p2) * side(p1, q1, q2) < 0 and side(p2, q2, p1) * side(p2, q2, q1) < 0:
        return 0.0
    return min(_to_segment(p1, p2, q2), _to_segment(q1, p2, q2), _to_segment(p2, p1, q1), _to_segment(q2, p1, q1))


def _element(rec, a, o, start: Point | None = None, end: Point | None = None) -> tuple:
    """A plane element (kind, p, q, centre, ccw): the programmed move, or its compensated
    stretch from ``start`` to ``end``."""
    p, q = _pts(rec, a, o)
    centre = (rec.center[a], rec.center[o]) if rec.kind == "arc" else None
    return (rec.kind, start or p, end or q, centre, rec.direction == "ccw" if centre else True)


def _nearest(path: tuple, profile: tuple) -> float:
    """Least distance from a compensated element to a programmed one (exact between two lines,
    from dense samples with an arc)."""
    kind, p, q, centre, ccw = path
    pkind, pp, pq, pcentre, pccw = profile
    if kind != "arc" and pkind != "arc":
        return _segments_distance(p, q, pp, pq)
    if pkind != "arc":
        return min(_to_segment(x, pp, pq) for x in _points_along(kind, p, q, centre, ccw))
    points = _points_along(kind, p, q, centre, ccw)
    if kind != "arc":   # a line against an arc: the line's points densely
        points = [(p[0] + (q[0] - p[0]) * i / ARC_SAMPLES, p[1] + (q[1] - p[1]) * i / ARC_SAMPLES)
                  for i in range(ARC_SAMPLES + 1)]
    return min(_to_arc(x, pp, pq, pcentre, pccw) for x in points)


def _check_neck(rec, profile: tuple, path: tuple, history: list, r: float) -> None:
    """A compensated move against the programmed move two blocks before it, and that one's
    compensated path against this programmed move: nearer than R is a neck narrower than the
    tool.  The corner trims only see neighbours; the CNC looks further ahead for such
    problems (seed 002 L9455-L9459, spec 04 §16.2), and like a step it is refused here."""
    if len(history) < 2:
        return
    back_profile, back_path = history[-2]
    near = min(_nearest(path, back_profile), _nearest(back_path, profile))
    if near < r - GOUGE_TOLERANCE:
        raise CompensationError(rec, f"the tool does not fit here: its path comes {r - near:.4f} mm into the "
                                f"profile two blocks back (a gap narrower than the tool diameter {2 * r:g})")


def _record(rec, a, o, start: Point | None, end: Point | None):
    p, q = _pts(rec, a, o)
    ns, ne = start or p, end or q
    if rec.kind != "arc":
        if (ne[0] - ns[0]) * (q[0] - p[0]) + (ne[1] - ns[1]) * (q[1] - p[1]) < -1e-9:
            raise CompensationError(rec, "this move is too short for the tool radius: its compensated path "
                                    "would run backwards (a step in the profile)")
    elif math.dist(ns, ne) > 1e-9:
        from .arcs import sweep

        c = (rec.center[a], rec.center[o])
        ccw = rec.direction == "ccw"
        if abs(sweep(ns, ne, c, ccw)) > abs(sweep(p, q, c, ccw)) + 1e-6:
            raise CompensationError(rec, "this arc is too short for the tool radius: its compensated path "
                                    "would turn the wrong way (a step in the profile)")
    moved = _moved(rec, (a, o), start, end)
    if rec.kind == "arc" and (start is not None or end is not None):
        centre_radius = math.dist(end or start, (rec.center[a], rec.center[o]))
        moved = replace(moved, radius=centre_radius if end is not None else moved.radius,
                        feed=_centre_feed(rec, centre_radius))
    return moved


def _centre_feed(rec, centre_radius: float):
    """The tool centre's feed on a compensated arc: under G196 the programmed F is at the contact point
    (seed 002 L4298-L4325: contact = F R / (R + r), so the centre runs at F (R + r) / R, r negative
    inside), on arcs of a radius above #TANGFEED RMIN (L4305); under G197 F is the centre's."""
    dyn = rec.dyn
    rmin = getattr(dyn, "contact_feed", None)
    if rmin is None or not rec.feed or rec.feed_mode == "G93" or not rec.radius > rmin:
        return rec.feed
    return rec.feed * centre_radius / rec.radius


def _inserted(template, a, o, items, feed):
    """Records for the join elements (lines and arcs) computed by :func:`_join`."""
    plane = template.plane if template.kind == "arc" else (a, o, None)
    out = []
    for kind, p, q, c, ccw in items:
        if math.dist(p, q) < 1e-6:
            continue
        if kind == "arc":
            out.append(_arc_record(template, plane, p, q, c, ccw, feed))
        else:
            out.append(_line_record(template, plane, p, q, feed, "rapid" if feed is None else "linear"))
    return out


def compensate(records: Iterable) -> Iterator:
    """Offset the compensated moves of a record stream (see the module docstring).

    A compensated record carries ``comp = (side, radius, transition, start, (abscissa, ordinate))``.
    """
    pending: _Move | None = None   # the last compensated move, end not fixed yet
    activation = False             # pending is the activation move
    waiting = False                # activation without plane motion seen, waiting for the plane move
    held: list = []                # records after pending (off-plane moves, aux)
    comp = None
    history: list = []             # (programmed, compensated) elements of the last two contour moves

    def flush_held(point: Point | None, a, o, first_from: Point | None = None):
        out = []
        for k, h in enumerate(held):
            if point is not None and h.kind in ("rapid", "linear") and not _planar(h, a, o):
                start = first_from if (first_from is not None and k == 0) else point
                h = replace(h, start={**h.start, a: start[0], o: start[1]},
                            end={**h.end, a: point[0], o: point[1]},
                            end_part={**h.end_part, a: h.end_part[a] + point[0] - h.end[a],
                                      o: h.end_part[o] + point[1] - h.end[o]})
            out.append(h)
        held.clear()
        return out

    for rec in records:
        kind = rec.kind
        if kind not in ("rapid", "linear", "arc"):
            if pending is None and not waiting:
                yield rec
            else:
                held.append(rec)
            continue
        rc = getattr(rec, "comp", None)
        if pending is None and not waiting:
            if rc is None:
                yield rec
                continue
            comp = rc
            a, o = rc[4]
            if not _planar(rec, a, o):   # activation without plane motion (L9684-L9734)
                waiting = True
                held.append(rec)
                continue
            if rec.kind == "arc":
                raise CompensationError(rec, "radius compensation starts with a straight move (G00/G01), "
                                        "not an arc (L9659)")
            pending, activation = _Move(rec, _pts(rec, a, o)[0]), True
            continue
        s, r, transition, start_mode, (a, o) = comp
        if rc is not None and not _planar(rec, a, o):
            held.append(rec)          # a move off the plane: executed at the joint
            continue
        if rc is not None and rc[4] != (a, o):
            raise CompensationError(rec, "the plane changed while radius compensation is active: cancel it "
                                    "with G40 first")
        if rc is not None and (rc[0] != s or abs(rc[1] - r) > 1e-12) and not waiting:
            # G41 <-> G42 (or a new radius) without G40 (seed 002 L9867-L9966)
            inserted, next_start = _side_change(pending, rec, a, o, comp, rc, activation)
            yield _record(pending.rec, a, o, None if activation else pending.start, pending.end)
            yield from flush_held(pending.end, a, o)
            yield from _inserted(pending.rec, a, o, inserted, rec.feed if rec.kind != "rapid" else None)
            activation = False
            comp = rc
            pending = _Move(rec, next_start)
            history = []
            continue
        if waiting:
            if rc is None:   # G40 before any plane move: nothing was compensated
                waiting = False
                yield from flush_held(None, a, o)
                yield rec
                continue
            # the zero-motion block moves to the offset start of this first plane move
            b = _offset_point(rec, a, o, s, r, False)
            here = _pts(rec, a, o)[0]
            yield from flush_held(b, a, o, first_from=here)
            waiting = False
            pending, activation = _Move(rec, b), False
            continue
        cancel = rc is None
        if cancel and rec.kind == "arc":
            raise CompensationError(rec, "radius compensation is cancelled with a straight move (G00/G01), "
                                    "not an arc (L9971)")
        if cancel and not _planar(rec, a, o):
            # cancellation without plane motion (L9994-L10029): the last move ends at its
            # perpendicular point; this block goes from there to the uncompensated end point
            pending.end = _offset_point(pending.rec, a, o, s, r, True)
            yield _record(pending.rec, a, o, None if activation else pending.start, pending.end)
            yield from flush_held(pending.end, a, o)
            yield _record(rec, a, o, pending.end, None)
            pending, comp, activation = None, None, False
            continue
        inserted, next_start = _join(pending, rec, a, o, s, r, transition, start_mode, activation, cancel)
        feed = rec.feed if rec.kind != "rapid" else None
        if not activation:   # a contour move: its path against the profile two blocks back
            profile = _element(pending.rec, a, o)
            path = _element(pending.rec, a, o, pending.start, pending.end)
            _check_neck(pending.rec, profile, path, history, r)
            history = [*history[-1:], (profile, path)]
        yield _record(pending.rec, a, o, None if activation else pending.start, pending.end)
        yield from flush_held(pending.end, a, o)
        yield from _inserted(pending.rec, a, o, inserted, feed)
        activation = False
        if cancel:
            yield _record(rec, a, o, next_start, None)
            pending, comp, history = None, None, []
        else:
            pending = _Move(rec, next_start)
    if pending is not None:
        s, r, _t, _m, (a, o) = comp
        pending.end = _offset_point(pending.rec, a, o, s, r, True)
        yield _record(pending.rec, a, o, None if activation else pending.start, pending.end)
        yield from flush_held(pending.end, a, o)
    else:
        yield from held
