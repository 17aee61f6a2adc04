"""Tool radius compensation G40/G41/G42 with G136/G137 and G138/G139 (seed 002 L9427-L10071).

A streaming stage over the interpreter's records.  Each compensated move
carries ``comp = (side, radius, transition, start, plane)``: side +1 for G41
(tool on the left of the path), -1 for G42; ``transition`` 136 (circular
joins) or 137 (linear joins) at outside corners; ``start`` 138 (direct) or 139
(indirect) activation and cancellation.  A move without compensation carries
``joins = (transition, start)``: both may be programmed while compensation is
active (L9554, L9597), so each corner takes them from the block after it, the
activation from its own block and the cancellation from the G40 move (spec 04
§18-§20):

* inside corners: both offsets are trimmed to their intersection;
* outside corners: G136 inserts an arc of radius R about the programmed
  corner; G137 prolongs the offsets in straight lines (one point for a
  corner up to 90 degrees, two beyond);
* whether a corner is inside or outside comes from the turn of the tangents,
  except where arcs make the answer geometric: near a tangent reversal (a
  cusp) the offsets of an arc and of the next element may cross although the
  tangents turn away from the tool (then it is an inside corner, trimmed where
  they cross), or miss each other although the tangents turn toward it (then
  the tool goes round the corner);
* an arc corrected by G264 runs on the circle of its start radius (L6996), and
  so does its offset.

The CNC looks ahead for compensation problems and does not execute the blocks
that cause them, with a warning that the programmed profile was modified
(L9455-L9459).  So does this stage, holding up to :data:`LOOKAHEAD` plane
elements: a move whose offset the trims reverse or eliminate (a *step*,
INT120), an arc the tool cannot follow (offset radius 0 or less, INT121), and a
move whose offset does not meet the offset of the move before the dropped ones
(a *gap* narrower than the tool, INT122) are dropped and their neighbours
re-joined at the intersection of their offsets.  Every kept move, with its
joins, is checked (exactly) to keep R from the two moves before it, its own,
the next and the dropped ones.  What cannot be resolved is an error (INT086),
never an approximated path: a dropped move that also moves an axis off the
plane, a path that would come nearer than R to those moves (an arc tighter than
the tool curling back into a corner, a neck a few blocks wide), arcs as
activation or cancellation moves.

Moves off the plane (a Z plunge) between compensated moves are kept at the
joint.  A change of side (G41 <-> G42) or of radius without G40 joins the two
offsets at their intersection near the corner, else by a connecting segment
(spec 04 §22).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Iterator
from dataclasses import replace

from .aids import _arc_record, _circle_circle, _cross, _left, _line_circle, _line_record, _moved, _unit
from .arcs import sweep

Point = tuple[float, float]

#: Plane elements held back at most (spec 04 §16.2 asks for 3 or more): a dropped block is re-joined with
#: neighbours still held; needing one already handed on is an error.
LOOKAHEAD = 6
#: Consecutive blocks dropped at most before the problem is refused instead (the profile would change too much).
MAX_DROPS = 3


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


def _offset_radius(rec, a, o, s: float, r: float) -> float:
    """Radius of an arc's offset: its start radius (an arc corrected by G264 runs with the radius of its start
    point about the programmed centre, seed 002 L6996) minus R with the tool inside, plus R outside."""
    p, _q = _pts(rec, a, o)
    delta = 1.0 if rec.direction == "ccw" else -1.0
    return math.dist(p, (rec.center[a], rec.center[o])) - s * delta * r


def _followable(rec, a, o, s: float, r: float) -> bool:
    """Not an arc whose offset has a radius of zero or less (a concave arc smaller than the tool)."""
    return rec.kind != "arc" or _offset_radius(rec, a, o, s, r) > 1e-9


def _geometry(rec, a, o, s: float, r: float):
    """The offset of a move: ("line", point, direction) or ("circle", centre, radius, ccw)."""
    p, q = _pts(rec, a, o)
    if rec.kind != "arc":
        t = _unit((q[0] - p[0], q[1] - p[1]))
        n = _left(t)
        return ("line", (p[0] + s * r * n[0], p[1] + s * r * n[1]), t)
    return ("circle", (rec.center[a], rec.center[o]), _offset_radius(rec, a, o, s, r), rec.direction == "ccw")


def _hits(g1, g2) -> list[Point]:
    """The intersections of two offsets (lines taken as infinite, arcs as full circles)."""
    if g1[0] == "line" and g2[0] == "line":
        den = _cross(g1[2], g2[2])
        if abs(den) < 1e-12:
            return []
        d = (g2[1][0] - g1[1][0], g2[1][1] - g1[1][1])
        k = _cross(d, g2[2]) / den
        return [(g1[1][0] + k * g1[2][0], g1[1][1] + k * g1[2][1])]
    if g1[0] == "line":
        return _line_circle(g1[1], g1[2], g2[1], g2[2])
    if g2[0] == "line":
        return _line_circle(g2[1], g2[2], g1[1], g1[2])
    return _circle_circle(g1[1], g1[2], g2[1], g2[2])


def _meet(g1, g2, near: Point) -> Point | None:
    hits = _hits(g1, g2)
    return min(hits, key=lambda x: math.dist(x, near)) if hits else None


def _within(g, p: Point, q: Point, x: Point, eps: float = 1e-9) -> bool:
    """``x`` (on the offset ``g``) lies on its stretch from ``p`` to ``q``."""
    if g[0] == "line":
        d = (q[0] - p[0], q[1] - p[1])
        k = (x[0] - p[0]) * d[0] + (x[1] - p[1]) * d[1]
        return -eps <= k <= d[0] * d[0] + d[1] * d[1] + eps
    if math.dist(x, p) <= eps or math.dist(x, q) <= eps:
        return True
    return abs(sweep(p, x, g[1], g[3])) <= abs(sweep(p, q, g[1], g[3]))


def _offset_point(rec, a, o, s, r, at_end: bool) -> Point:
    """The perpendicular point of the offset at the start or the end of a move (of an arc: on its offset
    circle, which with G264 is the one of the start radius)."""
    p, q = _pts(rec, a, o)
    x = q if at_end else p
    if rec.kind == "arc":
        c = (rec.center[a], rec.center[o])
        u = _unit((x[0] - c[0], x[1] - c[1]))
        rr = _offset_radius(rec, a, o, s, r)
        return (c[0] + rr * u[0], c[1] + rr * u[1])
    n = _left(_tangent(rec, a, o, at_end))
    return (x[0] + s * r * n[0], x[1] + s * r * n[1])


class _Move:
    """A compensated move: its record, the plane points fixed so far, and (once its end is fixed) the
    records held after it, executed at its end, and the join elements inserted after them."""

    __slots__ = ("activation", "end", "feed", "held", "inserted", "rec", "start")

    def __init__(self, rec, start: Point | None, activation: bool = False) -> None:
        self.rec, self.start, self.end, self.activation = rec, start, None, activation
        self.held: list = []
        self.inserted: list = []
        self.feed = None


def _join(prev: _Move, nxt_rec, a, o, s, r, transition: int, start_mode: int, cancel: bool):
    """Close the corner between ``prev`` and ``nxt_rec`` (spec 04 §18-§20).

    Returns (points inserted between them as a list of ("line"|"arc", p, q, centre, ccw),
    the start point of the next move).  Sets ``prev.end``.
    """
    rec = prev.rec
    activation = prev.activation
    _, corner = _pts(rec, a, o)
    t1 = _tangent(rec, a, o, True)
    t2 = _tangent(nxt_rec, a, o, False)
    pa = _offset_point(rec, a, o, s, r, True)
    pb = _offset_point(nxt_rec, a, o, s, r, False)
    cross = _cross(t1, t2)
    dot = t1[0] * t2[0] + t1[1] * t2[1]
    if dot > 0 and (abs(cross) < 1e-9 or math.dist(pa, pb) < 1e-6):
        # tangent (or as good as): the offsets meet at A = B (a G264 arc ends on its start radius: the next
        # move starts there); a join arc of a few nanometres would read as a full circle
        prev.end = pa
        return [], pa
    g1 = ("line", pa, t1) if activation else _geometry(rec, a, o, s, r)
    g2 = ("line", pb, t2) if cancel else _geometry(nxt_rec, a, o, s, r)
    if s * cross > 1e-9:
        # the tangents turn toward the tool: an inside corner, trimmed where the offsets meet; arcs whose
        # offsets miss each other (near a reversal) leave the tool to go round the corner
        x = _meet(g1, g2, corner)
    elif g1[0] == "circle" or g2[0] == "circle":
        # the tangents turn away from the tool, but the offset of an arc may still cross the other offset
        # near the corner (a cusp: the arc ends heading against the next move): an inside corner where they
        # cross, else the path would cut into the arc
        p1 = prev.start if prev.start is not None and not activation else pa
        q2 = _pts(nxt_rec, a, o)[1] if cancel else _offset_point(nxt_rec, a, o, s, r, True)
        crossing = [x for x in _hits(g1, g2) if _within(g1, p1, pa, x) and _within(g2, pb, q2, x)
                    and math.dist(x, pa) > 1e-9 and math.dist(x, pb) > 1e-9]
        x = min(crossing, key=lambda x: math.dist(x, corner)) if crossing else None
    else:
        x = None
    if x is not None:
        prev.end = x
        return [], x
    # outside corner (or a reversal)
    if (activation or cancel) and start_mode == 138:   # G138: straight to / from the offset point
        prev.end = pb if activation else pa
        return [], prev.end
    prev.end = pa
    if transition == 136:
        return [("arc", pa, pb, corner, s < 0)], pb
    psi = math.atan2(abs(cross), dot)
    if psi <= math.pi / 2 + 1e-12:
        k = r * math.tan(psi / 2)
        q = (pa[0] + k * t1[0], pa[1] + k * t1[1])
        return [("line", pa, q, None, True), ("line", q, pb, None, True)], pb
    a2 = (pa[0] + r * t1[0], pa[1] + r * t1[1])
    b2 = (pb[0] - r * t2[0], pb[1] - r * t2[1])
    return [("line", pa, a2, None, True), ("line", a2, b2, None, True), ("line", b2, pb, None, True)], pb


def _rejoin(prev: _Move, nxt_rec, a, o, s, r, cancel: bool):
    """After dropped blocks: ``prev`` and ``nxt_rec`` are joined where their offsets meet, nearest to the
    gap between them; two offsets on one straight line continue along it.  None if they do not meet."""
    rec = prev.rec
    g1 = ("line", _offset_point(rec, a, o, s, r, True), _tangent(rec, a, o, True)) if prev.activation \
        else _geometry(rec, a, o, s, r)
    pb = _offset_point(nxt_rec, a, o, s, r, False)
    g2 = ("line", pb, _tangent(nxt_rec, a, o, False)) if cancel else _geometry(nxt_rec, a, o, s, r)
    if g1[0] == g2[0] == "line" and abs(_cross(g1[2], g2[2])) < 1e-12:
        if g1[2][0] * g2[2][0] + g1[2][1] * g2[2][1] > 0 and abs(_cross(g1[2], (pb[0] - g1[1][0],
                                                                               pb[1] - g1[1][1]))) < 1e-9:
            x = _offset_point(rec, a, o, s, r, True)
            prev.end = x
            return [], x
        return None
    p1, p2 = _pts(rec, a, o)[1], _pts(nxt_rec, a, o)[0]
    mid = ((p1[0] + p2[0]) / 2, (p1[1] + p2[1]) / 2)
    x = _meet(g1, g2, mid)
    if x is None or math.dist(x, mid) > math.dist(p1, p2) + 2 * r:
        return None   # no meeting point, or one far beyond the gap (nearly parallel offsets)
    prev.end = x
    return [], x


def _reversed(move: _Move, a, o) -> bool:
    """The offset stretch of a move runs backwards or vanishes: the trims of its corners took it all (a step,
    seed 002 L9455)."""
    rec = move.rec
    p, q = _pts(rec, a, o)
    ns, ne = move.start or p, move.end or q
    if rec.kind != "arc":
        return (ne[0] - ns[0]) * (q[0] - p[0]) + (ne[1] - ns[1]) * (q[1] - p[1]) < -1e-9
    if math.dist(ns, ne) <= 1e-9:
        return rec.turns == 0 and math.dist(p, q) > 1e-9
    c = (rec.center[a], rec.center[o])
    ccw = rec.direction == "ccw"
    # trimmed past each other, the stretch wraps round (its sweep nears 360 degrees); a hair longer than the
    # programmed sweep is a trim a hair past the end (a G264 arc ends on its start radius): not a step
    programmed = abs(sweep(p, q, c, ccw))
    return abs(sweep(ns, ne, c, ccw)) > programmed + min(1.0, (360.0 - programmed) / 2)


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


def _element(rec, a, o, start: Point | None = None, end: Point | None = None) -> tuple:
    """A plane element (kind, p, q, centre, ccw): the programmed move, or its compensated
    stretch from ``start`` to ``end``."""
    p, q = _pts(rec, a, o)
    centre = (rec.center[a], rec.center[o]) if rec.kind == "arc" else None
    return (rec.kind, start or p, end or q, centre, rec.direction == "ccw" if centre else True)


def _record(rec, a, o, start: Point | None, end: Point | None, activation: bool = False):
    probe = _Move(rec, start)
    probe.end = end
    if not activation and _reversed(probe, a, o):   # the stage drops such moves first: never hand one on
        raise CompensationError(rec, "this move is too short for the tool radius: its compensated path "
                                "would run backwards (a step in the profile)")
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


def _off_plane(rec, a, o) -> bool:
    """The move changes an axis other than the plane's (a helix, a 3-D line)."""
    return any(abs(rec.end[x] - rec.start[x]) > 1e-9 for x in rec.end if x not in (a, o))


def _held_at(held: list, point: Point | None, a, o, first_from: Point | None = None) -> list:
    """The records held at a joint, their moves off the plane placed at ``point``."""
    out = []
    for k, h in enumerate(held):
        if point is not None and h.kind in ("rapid", "linear") and not _planar(h, a, o):
            start = first_from if (first_from is not None and k == 0) else point
            h = replace(h, start={**h.start, a: start[0], o: start[1]},
                        end={**h.end, a: point[0], o: point[1]},
                        end_part={**h.end_part, a: h.end_part[a] + point[0] - h.end[a],
                                  o: h.end_part[o] + point[1] - h.end[o]})
        out.append(h)
    return out


def _emit(move: _Move, a, o) -> Iterator:
    """A move whose end is fixed: its record, the records held after it, its join elements."""
    yield _record(move.rec, a, o, None if move.activation else move.start, move.end, move.activation)
    yield from _held_at(move.held, move.end, a, o)
    yield from _inserted(move.rec, a, o, move.inserted, move.feed)


Warn = Callable[[object, str, str], None]


def compensate(records: Iterable, warn: Warn | None = None) -> Iterator:
    """Offset the compensated moves of a record stream (see the module docstring).

    A compensated record carries ``comp = (side, radius, transition, start, (abscissa, ordinate))``.
    ``warn(record, code, message)`` reports a block not executed (INT120-INT122); without it such a block
    is an error.
    """
    ready: list[_Move] = []        # moves with their end fixed, not handed on yet (the look-ahead)
    pending: _Move | None = None   # the last compensated move, end not fixed yet
    waiting = False                # activation without plane motion seen, waiting for the plane move
    held: list = []                # records after pending (off-plane moves, aux)
    dropped: list = []             # programmed elements dropped after pending
    comp = None
    clear: Clearance | None = None  # the path handed on and the profile, for the gouges the look-ahead cannot see

    exiting: _Move | None = None   # the last move before a G40: its joins are the exit transition
    follows_activation = False     # the move handed on last was the activation
    opening = None                 # the record of the first move after the activation

    def _why(rec) -> str:
        if rec is opening or (exiting is not None and rec is exiting.rec):
            return ("(the contour closes at the corner where compensation started: the activation and the last "
                    "move end on the perpendiculars of that corner and leave it untrimmed, spec 04 §19.2, §20; "
                    "start the contour in the middle of an edge or approach it tangentially)")
        return f"(a part of the contour narrower than the tool diameter {2 * comp[1]:g})"

    def emit(move: _Move) -> Iterator:
        """Hand a move on, after the no-gouge watch has seen its path (spec 04 §16.2): not the approach
        (the activation move and its transition) nor the exit transition, which reach the profile's ends
        on purpose (G139/G138, spec 04 §18.3, §19.1).  The first move's stretch and the last move are watched
        like any other: a closed contour started at one of its corners leaves that corner untrimmed (the
        activation ends on the first move's perpendicular, spec 04 §19.2, the last move on its own, §20), and
        at an inside corner that cuts into the closing edge and the first edge (spec 04 §26's square closed):
        refused, the contour must start in the middle of an edge or with a tangent approach."""
        nonlocal follows_activation, opening
        if follows_activation:
            opening = move.rec
        follows_activation = move.activation
        if clear is not None and not move.activation:
            pieces = _pieces(move, [] if move is exiting else move.inserted, a, o)
            for piece in pieces:
                hit = clear.path(piece, move.rec)
                if hit is not None:
                    raise CompensationError(move.rec, f"the tool does not fit here: its path would come "
                                            f"{hit[0]:.4f} mm into the profile of line {hit[1].line} "
                                            f"{_why(move.rec)}")
        yield from _emit(move, a, o)

    def watch(rec) -> None:
        """A programmed element of the contour: refused when the path already handed on comes into it."""
        hit = clear.profile(_element(rec, a, o), rec) if clear is not None else None
        if hit is not None:
            raise CompensationError(rec, f"the tool does not fit here: the path of line {hit[1].line} would come "
                                    f"{hit[0]:.4f} mm into this block's profile {_why(hit[1])}")

    def drop(rec, code: str, message: str) -> None:
        if warn is None or _off_plane(rec, a, o) or len(dropped) >= MAX_DROPS:
            why = "" if warn is None else " (it also moves an axis off the plane)" if _off_plane(rec, a, o) else \
                f" ({MAX_DROPS} blocks in a row are not executed already: fagorcnc does not drop more)"
            raise CompensationError(rec, message + why)
        warn(rec, code, message + ": the block is not executed, the programmed profile is modified")
        dropped.append(_element(rec, a, o))

    def attach(rec, cancel: bool, transition: int, start_mode: int) -> Point | None:
        """Join pending with ``rec`` (dropping what the tool cannot machine); pending joins the look-ahead.
        Returns where ``rec``'s offset starts, or None when ``rec`` itself was dropped."""
        nonlocal pending, held

        def back_off(code: str, message: str) -> bool:
            """Drop pending and reopen the move before it; False if there is none to reopen."""
            nonlocal pending, held
            if pending.activation or not ready or ready[-1].activation:
                return False   # the first move of the contour is where the activation leads: never dropped
            drop(pending.rec, code, message)
            before = ready.pop()
            held = before.held + held
            before.held, before.inserted, before.end = [], [], None
            pending = before
            return True

        gap = f"the tool does not fit between the moves around this one (a gap narrower than the tool diameter " \
              f"{2 * r:g})"
        while True:
            adjacent = not dropped and math.dist(_pts(pending.rec, a, o)[1], _pts(rec, a, o)[0]) <= 1e-9
            if adjacent:
                inserted, start = _join(pending, rec, a, o, s, r, transition, start_mode, cancel)
            else:
                joined = _rejoin(pending, rec, a, o, s, r, cancel)
                if joined is None:
                    # the neighbours of the dropped moves do not meet: drop this move if the one before it
                    # would meet the next one clear of everything dropped (a wall facing a narrow mouth),
                    # else the next one (the far wall of a narrow slot); the cancellation stays
                    if (cancel or _off_plane(rec, a, o) or _clear(ready[-1] if ready else None, pending, rec,
                                                                  cancel, dropped, a, o, s, r)) \
                            and back_off("INT122", gap):
                        continue
                    if not cancel and not _off_plane(rec, a, o):
                        drop(rec, "INT122", gap)
                        return None
                    raise CompensationError(rec, "the compensated moves do not meet after the blocks that were "
                                            "not executed")
                inserted, start = joined
            if pending.activation and not adjacent and _reversed(pending, a, o):
                raise CompensationError(rec, "the activation move would run backwards to meet this move after "
                                        "the blocks that are not executed")
            if not pending.activation and _reversed(pending, a, o):
                if back_off("INT120", "this move is too short for the tool radius at its corners (a step in the "
                            "profile)"):
                    continue
                raise CompensationError(pending.rec, "this move is too short for the tool radius (a step in the "
                                        "profile) and the move before it is already executed")
            try:
                if dropped:
                    _check_dropped(pending, rec, start, cancel, dropped, a, o, s, r)
                _check_local(pending, ready[-2:], rec, inserted, cancel, dropped, a, o, r)
            except CompensationError as exc:   # the tool does not fit: drop back while the look-ahead allows
                if _off_plane(pending.rec, a, o) or warn is None or not back_off("INT122", gap):
                    raise exc from None
                continue
            dropped.clear()
            pending.held, held = held, []
            pending.inserted, pending.feed = inserted, rec.feed if rec.kind != "rapid" else None
            ready.append(pending)
            return start

    def flush() -> Iterator:
        while ready:
            yield from emit(ready.pop(0))

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
            pending = _Move(rec, _pts(rec, a, o)[0], activation=True)
            from .clearance import Clearance  # on first use: a program without G41/G42 never needs it
            clear = Clearance(rc[1])
            continue
        s, r, _t, _m, (a, o) = comp
        if rc is not None and not _planar(rec, a, o):
            held.append(rec)          # a move off the plane: executed at the joint
            continue
        if rc is not None and rc[4] != (a, o):
            raise CompensationError(rec, "the plane changed while radius compensation is active: cancel it "
                                    "with G40 first")
        if rc is not None and (rc[0] != s or abs(rc[1] - r) > 1e-12) and not waiting:
            # G41 <-> G42 (or a new radius) without G40 (seed 002 L9867-L9966)
            if dropped:
                raise CompensationError(rec, "the side or the radius changes right after a block that is not "
                                        "executed: fagorcnc cannot join the two sides there")
            inserted, next_start = _side_change(pending, rec, a, o, comp, rc, pending.activation)
            pending.held, held = held, []
            pending.inserted, pending.feed = inserted, rec.feed if rec.kind != "rapid" else None
            ready.append(pending)
            clear = None   # the joins of a side change cross the profile on purpose (spec 04 §22)
            yield from flush()
            comp = rc
            from .clearance import Clearance  # on first use: a program without G41/G42 never needs it
            clear = Clearance(rc[1])   # the other side, or another radius: watched from here on
            pending = _Move(rec, next_start)
            continue
        if waiting:
            if rc is None:   # G40 before any plane move: nothing was compensated
                waiting = False
                yield from _held_at(held, None, a, o)
                held = []
                yield rec
                continue
            # the zero-motion block moves to the offset start of this first plane move
            b = _offset_point(rec, a, o, s, r, False)
            here = _pts(rec, a, o)[0]
            yield from _held_at(held, b, a, o, first_from=here)
            held = []
            waiting = False
            pending = _Move(rec, b)
            from .clearance import Clearance  # on first use: a program without G41/G42 never needs it
            clear = Clearance(r)
            watch(rec)
            if not _followable(rec, a, o, s, r):
                raise CompensationError(rec, f"the tool radius {r:g} is not smaller than the concave arc radius: "
                                        "the arc cannot be followed")
            continue
        cancel = rc is None
        joins = rc[2:4] if rc is not None else (rec.joins or comp[2:4])
        transition = joins[0]
        start_mode = pending.rec.comp[3] if pending.activation else joins[1]
        if cancel and rec.kind == "arc":
            raise CompensationError(rec, "radius compensation is cancelled with a straight move (G00/G01), "
                                    "not an arc (L9971)")
        if cancel and not _planar(rec, a, o):
            # cancellation without plane motion (L9994-L10029): the last move ends at its
            # perpendicular point; this block goes from there to the uncompensated end point
            if dropped:
                raise CompensationError(rec, "compensation is cancelled right after a block that is not "
                                        "executed: fagorcnc cannot end the path there")
            pending.end = _offset_point(pending.rec, a, o, s, r, True)
            pending.held, held = held, []
            ready.append(pending)
            exiting = pending
            yield from flush()
            yield _record(rec, a, o, pending.end, None)
            pending, comp = None, None
            continue
        if not cancel:
            watch(rec)
        if not cancel and not _followable(rec, a, o, s, r):
            drop(rec, "INT121", f"the tool radius {r:g} is not smaller than the radius of this concave arc: "
                 "the arc cannot be followed")
            continue
        next_start = attach(rec, cancel, transition, start_mode)
        if next_start is None:
            continue
        while len(ready) > LOOKAHEAD:
            yield from emit(ready.pop(0))
        if cancel:
            exiting = ready[-1] if ready else None
            yield from flush()
            yield _record(rec, a, o, next_start, None)
            pending, comp = None, None
        else:
            pending = _Move(rec, next_start)
    if pending is not None:
        s, r, _t, _m, (a, o) = comp
        if dropped:
            raise CompensationError(pending.rec, "the program ends right after a block that is not executed")
        pending.end = _offset_point(pending.rec, a, o, s, r, True)
        pending.held, held = held, []
        ready.append(pending)
        yield from flush()
    else:
        yield from held


def _pieces(move: _Move, inserted: list, a, o) -> list:
    """The compensated elements of a move: its stretch (not for the activation) and its joins."""
    out = [] if move.activation else [_element(move.rec, a, o, move.start, move.end)]
    return out + [item for item in inserted if math.dist(item[1], item[2]) > 1e-9]


def _check_local(move: _Move, before: list, nxt_rec, inserted: list, cancel: bool, dropped: list,
                 a, o, r: float) -> None:
    """The stretch of a move and the joins after it keep R from the programmed moves around it: the two before,
    its own, the next and any dropped between; the paths of the two before keep R from its own.  Only curvature
    and the G137 prolongations can break this (an arc curling back into a corner's join, a join reaching back
    to a move two blocks away): the tool does not fit there, and fagorcnc refuses it."""
    from .proximity import GOUGE_TOLERANCE, nearest

    profiles = [*dropped, *(_element(m.rec, a, o) for m in before if not m.activation)]
    if not move.activation:
        profiles.append(_element(move.rec, a, o))
    if not cancel:
        profiles.append(_element(nxt_rec, a, o))
    pairs = [(piece, profile) for piece in _pieces(move, inserted, a, o) for profile in profiles]
    if not move.activation:
        own = _element(move.rec, a, o)
        pairs += [(piece, own) for m in before for piece in _pieces(m, m.inserted, a, o)]
    for piece, profile in pairs:
        near = nearest(piece, profile)
        if near < r - GOUGE_TOLERANCE:
            raise CompensationError(move.rec, f"the tool does not fit here: its path would come {r - near:.4f} "
                                    f"mm into the profile (a gap or a curve narrower than the tool diameter "
                                    f"{2 * r:g})")


def _clear(before: _Move | None, move: _Move, nxt_rec, cancel: bool, dropped: list, a, o, s, r) -> bool:
    """Whether ``before`` and ``nxt_rec`` would meet with the next move's offset clear of the dropped moves and
    of ``move`` dropped too (a guess of which way to drop: what is kept is checked in full afterwards)."""
    from .proximity import GOUGE_TOLERANCE, nearest

    if before is None or move.activation:
        return False
    trial = _Move(before.rec, before.start, before.activation)
    joined = _rejoin(trial, nxt_rec, a, o, s, r, cancel)
    if joined is None:
        return False
    end = _pts(nxt_rec, a, o)[1] if cancel else _offset_point(nxt_rec, a, o, s, r, True)
    piece = _element(nxt_rec, a, o, joined[1], end)
    return all(nearest(piece, el) >= r - GOUGE_TOLERANCE for el in [*dropped, _element(move.rec, a, o)])


def _check_dropped(prev: _Move, nxt_rec, start: Point, cancel: bool, dropped: list, a, o, s, r) -> None:
    """The path re-joined over dropped blocks must keep the tool radius from them: the stretch of ``prev`` and
    the offset of the next move up to its end (or, cancelling, the move to its end point)."""
    from .proximity import GOUGE_TOLERANCE, nearest

    pieces = [_element(prev.rec, a, o, prev.start if not prev.activation else None, prev.end)]
    end = _pts(nxt_rec, a, o)[1] if cancel else _offset_point(nxt_rec, a, o, s, r, True)
    pieces.append(_element(nxt_rec, a, o, start, end))
    for piece in pieces:
        for el in dropped:
            near = nearest(piece, el)
            if near < r - GOUGE_TOLERANCE:
                raise CompensationError(nxt_rec, f"the path past the blocks that are not executed would come "
                                        f"{r - near:.4f} mm into them: fagorcnc cannot join the moves around them")
