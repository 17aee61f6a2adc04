"""Corner aids on the programmed contour: G36 rounding, G39 chamfer, G37/G38 tangential entry/exit.

seed 002 L8393-L8703; geometry per spec 04 §3-§6.  Each aid sits in a block
of its own between two path blocks; the interpreter marks it in the record
stream with an :class:`Aid` record and :func:`apply_aids` rewrites the two
neighbouring moves (a streaming stage with one record of look-ahead).

Elements are planar: a line ``(p, q)`` or an arc ``(p, q, centre, ccw)`` in
(abscissa, ordinate) coordinates.  Moves with a component off the plane
(helices, 3-D lines) next to an aid are rejected.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Iterator
from dataclasses import dataclass, replace

from . import arcs as arcgeo

Point = tuple[float, float]


class AidError(ValueError):
    """A corner aid that cannot be built; the message names the reason."""


@dataclass(frozen=True, slots=True)
class Aid:
    """Marker: a G36/G37/G38/G39 block; ``aid`` is "round", "entry", "exit" or "chamfer"."""

    kind: str            # always "aid"
    aid: str
    size: float          # mm, after scaling
    feed: float | None   # F written in the aid block (mm/min) or None
    plane: tuple
    src: object

    @property
    def line(self) -> int:
        return self.src.line


# ---------------------------------------------------------------- element geometry
def _unit(v: Point) -> Point:
    n = math.hypot(*v)
    if n < 1e-12:
        raise AidError("a move of length 0 next to the corner aid")
    return (v[0] / n, v[1] / n)


def _left(v: Point) -> Point:
    return (-v[1], v[0])


def _cross(u: Point, v: Point) -> float:
    return u[0] * v[1] - u[1] * v[0]


def _tangent(el, at_end: bool) -> Point:
    p, q, c, ccw = el
    if c is None:
        return _unit((q[0] - p[0], q[1] - p[1]))
    x = q if at_end else p
    r = (x[0] - c[0], x[1] - c[1])
    t = _left(_unit(r))
    return t if ccw else (-t[0], -t[1])


def _line_circle(p: Point, d: Point, c: Point, r: float) -> list[Point]:
    fx, fy = p[0] - c[0], p[1] - c[1]
    b = fx * d[0] + fy * d[1]
    cc = fx * fx + fy * fy - r * r
    disc = b * b - cc
    if disc < -1e-9:
        return []
    s = math.sqrt(max(disc, 0.0))
    return [(p[0] + (-b + k) * d[0], p[1] + (-b + k) * d[1]) for k in (s, -s)]


def _circle_circle(c1: Point, r1: float, c2: Point, r2: float) -> list[Point]:
    d = math.dist(c1, c2)
    if d < 1e-12 or d > r1 + r2 + 1e-9 or d < abs(r1 - r2) - 1e-9:
        return []
    a = (r1 * r1 - r2 * r2 + d * d) / (2 * d)
    h = math.sqrt(max(r1 * r1 - a * a, 0.0))
    mx, my = c1[0] + a * (c2[0] - c1[0]) / d, c1[1] + a * (c2[1] - c1[1]) / d
    ox, oy = -(c2[1] - c1[1]) / d * h, (c2[0] - c1[0]) / d * h
    return [(mx + ox, my + oy), (mx - ox, my - oy)]


def _offset(el, side: float, dist: float):
    """The element moved ``dist`` to its ``side`` (+1 left, -1 right): a line (point, dir) or a circle."""
    p, _q, c, ccw = el
    if c is None:
        t = _tangent(el, False)
        n = _left(t)
        return ("line", (p[0] + side * dist * n[0], p[1] + side * dist * n[1]), t)
    rho = math.dist(p, c)
    delta = 1.0 if ccw else -1.0
    r = rho - side * delta * dist
    if r <= 1e-9:
        raise AidError("the rounding radius is larger than the arc it meets")
    return ("circle", c, r)


def _intersections(g1, g2) -> list[Point]:
    if g1[0] == "line" and g2[0] == "line":
        (_, p1, d1), (_, p2, d2) = g1, g2
        den = _cross(d1, d2)
        if abs(den) < 1e-12:
            return []
        k = _cross((p2[0] - p1[0], p2[1] - p1[1]), d2) / den
        return [(p1[0] + k * d1[0], p1[1] + k * d1[1])]
    if g1[0] == "line":
        return _line_circle(g1[1], g1[2], g2[1], g2[2])
    if g2[0] == "line":
        return _line_circle(g2[1], g2[2], g1[1], g1[2])
    return _circle_circle(g1[1], g1[2], g2[1], g2[2])


def _foot(el, x: Point) -> Point:
    """Point of the element's line or circle nearest to ``x``."""
    p, _q, c, _ccw = el
    if c is None:
        t = _tangent(el, False)
        k = (x[0] - p[0]) * t[0] + (x[1] - p[1]) * t[1]
        return (p[0] + k * t[0], p[1] + k * t[1])
    u = _unit((x[0] - c[0], x[1] - c[1]))
    rho = math.dist(p, c)
    return (c[0] + rho * u[0], c[1] + rho * u[1])


def _on_element(el, x: Point, eps: float = 1e-7) -> bool:
    p, q, c, ccw = el
    if c is None:
        t = _tangent(el, False)
        k = (x[0] - p[0]) * t[0] + (x[1] - p[1]) * t[1]
        return -eps <= k <= math.dist(p, q) + eps
    total = abs(arcgeo.sweep(p, q, c, ccw))
    part = abs(arcgeo.sweep(p, x, c, ccw)) if math.dist(p, x) > eps else 0.0
    return part <= total + 1e-6


# ---------------------------------------------------------------- the four aids
def rounding(el1, el2, r: float):
    """G36: returns (T1, T2, centre, ccw) or None when the elements are tangent."""
    if r <= 0:
        raise AidError("the rounding radius must be greater than 0")
    t1, t2 = _tangent(el1, True), _tangent(el2, False)
    cross, dot = _cross(t1, t2), t1[0] * t2[0] + t1[1] * t2[1]
    if abs(cross) < 1e-12:
        if dot > 0:
            return None
        raise AidError("the path reverses at the corner: nothing to round")
    side = 1.0 if cross > 0 else -1.0
    p = el1[1]
    candidates = _intersections(_offset(el1, side, r), _offset(el2, side, r))
    if not candidates:
        raise AidError("no rounding of that radius fits between the two moves")
    c = min(candidates, key=lambda x: math.dist(x, p))
    t_1, t_2 = _foot(el1, c), _foot(el2, c)
    if not (_on_element(el1, t_1) and _on_element(el2, t_2)):
        raise AidError("the rounding radius is too large for the moves around the corner")
    return t_1, t_2, c, side > 0


def chamfer(el1, el2, size: float):
    """G39: the chamfer's two ends, at straight distance ``size`` from the corner on each element."""
    if size <= 0:
        raise AidError("the chamfer size must be greater than 0")
    p = el1[1]

    def point(el, before: bool) -> Point:
        a, b, c, _ccw = el
        if c is None:
            t = _tangent(el, False)
            if size > math.dist(a, b) + 1e-9:
                raise AidError("the chamfer is longer than the move it cuts")
            k = -size if before else size
            return (p[0] + k * t[0], p[1] + k * t[1])
        hits = [x for x in _circle_circle(p, size, c, math.dist(a, c)) if _on_element(el, x)]
        if not hits:
            raise AidError("the chamfer is longer than the arc it cuts")
        return hits[0]

    return point(el1, True), point(el2, False)


def entry(approach, first, r: float):
    """G37: (T, centre, ccw) -- approach P0 -> T, then the entry arc T -> P1 (spec 04 §5)."""
    p0, p1, c0, _ = approach
    if c0 is not None:
        raise AidError("G37 modifies a straight approach move (G00/G01)")
    if r <= 0 or math.dist(p0, p1) < 2 * r - 1e-9:
        raise AidError("G37: the approach move must be at least twice the entry radius long (L8636)")
    u, v = _tangent(approach, True), _tangent(first, False)
    cross = _cross(u, v)
    if abs(cross) < 1e-12:
        if u[0] * v[0] + u[1] * v[1] > 0:
            return None
        raise AidError("G37: the profile starts straight back along the approach")
    s = 1.0 if cross > 0 else -1.0
    n = _left(v)
    c = (p1[0] + r * s * n[0], p1[1] + r * s * n[1])
    t = _tangent_point(p0, c, r, s, entering=True)
    return t, c, s > 0


def exit_(last, leave, r: float):
    """G38: (T, centre, ccw) -- exit arc P1 -> T, then T -> P2 (spec 04 §6)."""
    p1, p2, c0, _ = leave
    if c0 is not None:
        raise AidError("G38 modifies a straight exit move (G00/G01)")
    if r <= 0 or math.dist(p1, p2) < 2 * r - 1e-9:
        raise AidError("G38: the exit move must be at least twice the exit radius long (L8682)")
    v, u = _tangent(last, True), _tangent(leave, False)
    cross = _cross(v, u)
    if abs(cross) < 1e-12:
        if u[0] * v[0] + u[1] * v[1] > 0:
            return None
        raise AidError("G38: the exit goes straight back along the profile")
    s = 1.0 if cross > 0 else -1.0
    n = _left(v)
    c = (p1[0] + r * s * n[0], p1[1] + r * s * n[1])
    t = _tangent_point(p2, c, r, s, entering=False)
    return t, c, s > 0


def _tangent_point(x: Point, c: Point, r: float, s: float, entering: bool) -> Point:
    """The tangent point from ``x`` on the circle (c, r) travelled in sense ``s``.

    Entering, the straight move x -> T continues along the circle; leaving,
    the circle's direction at T points to x.  Of the two tangent points the
    one whose circle direction agrees is returned.
    """
    d = math.dist(x, c)
    if d < r:
        raise AidError("the point lies inside the entry/exit circle")
    w = _unit((x[0] - c[0], x[1] - c[1]))
    beta = math.acos(r / d)
    for sign in (1.0, -1.0):
        ang = sign * beta
        tp = (c[0] + r * (w[0] * math.cos(ang) - w[1] * math.sin(ang)),
              c[1] + r * (w[0] * math.sin(ang) + w[1] * math.cos(ang)))
        tang = _left(_unit((tp[0] - c[0], tp[1] - c[1])))
        tang = tang if s > 0 else (-tang[0], -tang[1])
        along = _unit((tp[0] - x[0], tp[1] - x[1])) if entering else _unit((x[0] - tp[0], x[1] - tp[1]))
        if tang[0] * along[0] + tang[1] * along[1] > 0.999:
            return tp
    raise AidError("no tangent entry/exit fits")


# ---------------------------------------------------------------- the streaming stage
def _element(rec, plane):
    a, o = plane[0], plane[1]
    if any(abs(rec.end[x] - rec.start[x]) > 1e-9 for x in rec.end if x not in (a, o)):
        raise AidError("a corner aid needs moves in the plane only (no helix or 3-D move next to it)")
    p, q = (rec.start[a], rec.start[o]), (rec.end[a], rec.end[o])
    if rec.kind == "arc":
        if rec.plane[:2] != (a, o):
            raise AidError("the arc next to the corner aid is in another plane")
        return (p, q, (rec.center[a], rec.center[o]), rec.direction == "ccw")
    return (p, q, None, True)


def _moved(rec, plane, start: Point | None = None, end: Point | None = None):
    a, o = plane[0], plane[1]
    changes = {}
    if start is not None:
        changes["start"] = {**rec.start, a: start[0], o: start[1]}
    if end is not None:
        da, do = end[0] - rec.end[a], end[1] - rec.end[o]
        changes["end"] = {**rec.end, a: end[0], o: end[1]}
        changes["end_part"] = {**rec.end_part, a: rec.end_part[a] + da, o: rec.end_part[o] + do}
    return replace(rec, **changes)


def _arc_record(template, plane, s: Point, e: Point, c: Point, ccw: bool, feed):
    from ..interp.records import Arc

    a, o = plane[0], plane[1]
    start = {**template.end, a: s[0], o: s[1]}
    end = {**template.end, a: e[0], o: e[1]}
    shift = {x: template.end_part[x] - template.end[x] for x in template.end}
    return Arc("arc", start, end, {x: v + shift[x] for x, v in end.items()}, {a: c[0], o: c[1]},
               {a: c[0] + shift[a], o: c[1] + shift[o]}, "ccw" if ccw else "cw", tuple(plane),
               math.dist(s, c), 0, feed, template.feed_mode, template.src, template.comp, template.dyn, template.frame,
               template.joins)


def _line_record(template, plane, s: Point, e: Point, feed, kind: str):
    from ..interp.records import Line

    a, o = plane[0], plane[1]
    start = {**template.end, a: s[0], o: s[1]}
    end = {**template.end, a: e[0], o: e[1]}
    shift = {x: template.end_part[x] - template.end[x] for x in template.end}
    return Line(kind, start, end, {x: v + shift[x] for x, v in end.items()}, feed, template.feed_mode,
                template.src, template.comp, template.dyn, template.frame, template.joins)


def apply_aids(records: Iterable, on_error) -> Iterator:
    """Rewrite the moves around each :class:`Aid` marker; other records pass through in order.

    The last move and the records after it are held until the next move shows
    whether an aid sits between them.  ``on_error(aid, message)`` is called for
    an impossible aid; it raises to stop the run.
    """
    held = None          # the last move
    after: list = []     # non-motion records that came after it
    aid = None
    for rec in records:
        kind = rec.kind
        if kind == "aid":
            if held is None:
                on_error(rec, "a corner aid needs a move before it")
            aid = rec
        elif kind in ("rapid", "linear", "arc"):
            if aid is None:
                if held is not None:
                    yield held
                    if after:   # (most moves follow a move: no list to go through)
                        yield from after
                        after.clear()
                held = rec
                continue
            try:
                first, inserted, second = _apply(aid, held, rec)
            except AidError as exc:
                on_error(aid, str(exc))
                return
            yield first
            yield from after
            yield from inserted
            after.clear()
            aid, held = None, second
        elif held is None:
            yield rec
        else:
            after.append(rec)
    if aid is not None:
        on_error(aid, "the corner aid is not followed by a move")
    if held is not None:
        yield held
    yield from after


def _radius_above_tool(aid: Aid, prev, nxt) -> None:
    """G37/G38 under radius compensation: the entry (exit) radius must be greater than the tool radius
    (seed 002 L8626-L8628 for G37, L8672-L8674 for G38): the arc is part of the programmed contour and its
    offset, of radius I - R on the inside, would vanish or turn back."""
    for rec in (prev, nxt):
        comp = getattr(rec, "comp", None)
        if comp is not None and comp[1] > 0 and not aid.size > comp[1]:
            what = "entry" if aid.aid == "entry" else "exit"
            raise AidError(f"G{37 if aid.aid == 'entry' else 38}: the tangential {what} radius {aid.size:g} must "
                           f"be greater than the tool radius {comp[1]:g} while radius compensation is active "
                           f"(L{8628 if aid.aid == 'entry' else 8674})")


def _apply(aid: Aid, prev, nxt):
    plane = aid.plane
    el1, el2 = _element(prev, plane), _element(nxt, plane)
    feed = nxt.feed if nxt.kind != "rapid" else None
    if aid.feed is not None and nxt.kind != "rapid":
        feed = aid.feed
    if aid.aid == "round":
        got = rounding(el1, el2, aid.size)
        if got is None:
            return prev, [], nxt
        t1, t2, c, ccw = got
        # before a G00 the rounding is run in G00 (seed 002 L8460): an arc without a feed
        rounding_feed = None if nxt.kind == "rapid" else feed if feed is not None else prev.feed
        fillet = _arc_record(prev, plane, t1, t2, c, ccw, rounding_feed)
        return _moved(prev, plane, end=t1), [fillet], _moved(nxt, plane, start=t2)
    if aid.aid == "chamfer":
        c1, c2 = chamfer(el1, el2, aid.size)
        cut = _line_record(prev, plane, c1, c2, feed if feed is not None else prev.feed,
                           "rapid" if nxt.kind == "rapid" else "linear")
        return _moved(prev, plane, end=c1), [cut], _moved(nxt, plane, start=c2)
    if aid.aid in ("entry", "exit"):
        _radius_above_tool(aid, prev, nxt)
    if aid.aid == "entry":
        got = entry(el1, el2, aid.size)
        if got is None:
            return prev, [], nxt
        t, c, ccw = got
        arc = _arc_record(prev, plane, t, el1[1], c, ccw, prev.feed if prev.kind != "rapid" else nxt.feed)
        return _moved(prev, plane, end=t), [arc], nxt
    got = exit_(el1, el2, aid.size)
    if got is None:
        return prev, [], nxt
    t, c, ccw = got
    arc = _arc_record(prev, plane, el2[0], t, c, ccw, nxt.feed if nxt.kind != "rapid" else prev.feed)
    return prev, [arc], _moved(nxt, plane, start=t)
