"""Corners the batches of :mod:`.junctions` know to hold: which batched corners surely pass the
checks of :meth:`~.junctions.CornerMixin._junction` (their floats are the lines', so
the tests here keep well clear of every threshold), what a corner whose lines still stand as its
batch took them is made of, and a line's trim whose end point the batch made.  Each shortcut
gives the very floats of the general path (tests/test_plan_batches.py)."""

from __future__ import annotations

import math
import operator

import numpy as np

from ..interp.records import Arc, Line
from .blend import BlendRow
from .corners import TANGENT_EPS
from .geometry import ArcPiece, LinePiece, arc_bound_rows
from .limits import curve_limits_rows
from .span import Span


def fast_corners(chain: list[Span], dirs: np.ndarray, feeds: np.ndarray, size: np.ndarray,
                 least_angle: float) -> list[bool]:
    """Which corners of a batch of G05 line corners (:meth:`~.junctions.CornerMixin._line_blend_batch`)
    surely reach the batched curve in :meth:`~.junctions.CornerMixin._junction`: blocks of their own
    (plain lines, no thread, no transformation), positive feeds, the chain's path limits, a curve made
    (size > 0), and a turn well clear of the tests of a tangent junction and a reversal (the floats of
    those tests are the lines', these only estimate them).  What a trim changes (the lines' lengths and
    ends) is tested at the corner itself (:func:`batched_line_corner`)."""
    first = chain[0]
    pa, pj = first.path_acc, first.path_jerk
    plain = [type(r) is Line and r.thread is None and r.frame is None and s.path_acc == pa and s.path_jerk == pj
             for s, r in zip(chain, [s.record for s in chain], strict=True)]
    if not (feeds > 0.0).all() or not np.isfinite(feeds).all():
        return [False] * (len(chain) - 1)
    u_in, u_out = dirs[:-1], dirs[1:]
    gap = u_out - u_in
    turn = np.degrees(np.arccos(np.clip((u_in * u_out).sum(axis=1), -1.0, 1.0)))
    clear = ((gap * gap).sum(axis=1) > 1e-12) & (turn <= 180.0 - 2.0 * least_angle) & (size > 0.0)
    return [ok and a and b and ra is not rb for ok, a, b, ra, rb in zip(
        clear.tolist(), plain, plain[1:], [s.record for s in chain], [s.record for s in chain[1:]], strict=False)]


def fast_splines(chain: list[Span], u: np.ndarray, angle: np.ndarray, least_angle: float) -> list[bool]:
    """Which corners of a batch of HSC spline candidates (:meth:`~.junctions.CornerMixin._batch`; ``u``:
    the lines' directions, ``angle``: each corner's included angle) surely reach the spline in
    :meth:`~.junctions.CornerMixin._junction`: not the first (being decided), plain lines of their own
    (no thread, no transformation) with the planning context of the chain's second line, and an angle
    well clear of the tests of a tangent junction, a reversal and a sharp edge (the floats of those
    tests are the lines', these only estimate them)."""
    n = len(chain) - 1
    dyn = chain[1].dyn
    if n < 2 or dyn is None or dyn.hsc is None:
        return [False] * n   # the first corner alone (the chain ends at nxt)
    least = max(dyn.hsc.corner, least_angle) + 1e-6
    gap = u[1:n + 1] - u[:n]
    clear = (((gap * gap).sum(axis=1) > 1e-12) & (angle[:n] >= least) & (angle[:n] <= 180.0 - 1e-6)).tolist()
    records = [s.record for s in chain]
    plain = [type(r) is Line and r.thread is None and r.frame is None and s.dyn is dyn
             for s, r in zip(chain, records, strict=True)]
    return [i > 0 and ok and a and b and ra is not rb for i, (ok, a, b, ra, rb) in enumerate(zip(
        clear, plain, plain[1:], records, records[1:], strict=False))]


def fast_arc_corners(chain: list[Span], rows: list[int], made_with: list[tuple]) -> list[bool]:
    """Which corners at arcs of a batch (:meth:`~.junctions.CornerMixin._arc_batch`; corner ``j``:
    chain[rows[j]] -> chain[rows[j] + 1], made with ``made_with[j]``) may be taken at the top of
    :meth:`~.junctions.CornerMixin._junction` (:func:`batched_arc_corner`): not the first (being
    decided), blocks of their own (plain lines and arcs, no thread, no transformation, not rapid) on
    lines and arcs, and what the corner was made with comparable to what _arc_blend asks (no NaN:
    the feed positive and finite, the halves of the blocks numbers).  The rest of _junction's checks
    are the spans' own: the batch's chain has one planning context and one set of axis limits."""
    plain = [((type(r) is Line and r.thread is None) or type(r) is Arc) and r.frame is None and not s.rapid
             and type(s.piece) in _TANGENTS for s, r in zip(chain, [s.record for s in chain], strict=True)]
    return [i > 0 and plain[i] and plain[i + 1] and half_p == half_p and half_q == half_q and 0.0 < feed < math.inf
            for i, (half_p, half_q, *_, feed) in zip(rows, made_with, strict=True)]


#: The pieces a corner taken by :func:`batched_arc_corner` may join (the ones with ``tangent_list``).
_TANGENTS = frozenset({LinePiece, ArcPiece})
#: How far (radians) :func:`turn_estimate` must be from the turns where _junction's tests on the
#: tangents change their answer for those tests to be known without their floats (the estimate and
#: the angle of the tests' unit tangents differ by about 1e-15 rad; acos near the sharpest turn
#: rounded, at most 179 degrees, adds less than 1e-13).
TURN_MARGIN = 1e-8
_TAU = 2.0 * math.pi
_NAN = math.nan


def sharpest_turn(least: float) -> float:
    """The largest turn (radians) whose :func:`turn_estimate` below it shows that a corner passes the
    test of its included angle against ``least`` (degrees): the turn of that angle less the margin;
    none where that turn is under 1e-4 rad (the error of the test's acos grows as 1 / sin of the
    angle: above 1e-4 rad it stays under 1e-11 rad, far inside the margin)."""
    turn = math.radians(180.0 - least)
    return turn - TURN_MARGIN if turn >= 1e-4 else 0.0


def turn_estimate(p: LinePiece | ArcPiece, q: LinePiece | ArcPiece) -> float:
    """The angle (radians, 0 to pi) between the tangents at the end of ``p`` and the start of ``q``
    from their direction angles in the plane of the arc among them, when both move in that plane
    alone (an arc: theta + atan2(rho w, dr), the angle of its q' = R(theta) (dr, rho w); a line: that of
    its direction); NaN otherwise.  Cheaper than the unit tangents and their product, and within
    about 1e-15 rad of the angle between them."""
    arc = p if type(p) is ArcPiece else q
    if type(arc) is not ArcPiece:
        return _NAN
    ia, io, off = arc.ia, arc.io, arc._lin[3]
    a = _direction_angle(p, p.length, ia, io, off)
    d = (_direction_angle(q, 0.0, ia, io, off) - a) % _TAU
    return d if d <= math.pi else _TAU - d


def _direction_angle(piece: LinePiece | ArcPiece, s: float, ia: int, io: int, off: tuple[int, ...]) -> float:
    """The angle in the plane of the axes ``ia``, ``io`` of the tangent of ``piece`` at ``s`` when the
    piece moves in that plane alone (none along the axes ``off``); NaN otherwise."""
    if type(piece) is ArcPiece:
        if piece.ia != ia or piece.io != io or piece._lin[2] != 0.0:
            return _NAN
        w = piece.w
        return piece.theta0 + w * s + math.atan2((piece.r0 + piece.dr * s) * w, piece.dr)
    u = piece.ul
    for k in off:
        if u[k] != 0.0:
            return _NAN
    return math.atan2(u[io], u[ia])


def batched_arc_corner(prev: Span, nxt: Span, fast: tuple) -> tuple | None:
    """``(curve, d1, d2) or None, feed, limits`` of the corner at an arc prev -> nxt from its entry of
    a batch (see :func:`fast_arc_corners`) when the spans still stand as the batch took them (the same
    next piece and end of prev, the curvature kept before prev: an HSC spline or not, and the same
    most prev may give up, as :meth:`~.junctions.CornerMixin._arc_blend` asks) and the corner passes
    _junction's tests of a smooth junction, a reversal and a sharp HSC edge (``least``: the least
    included angle rounded) on the same floats, or known to pass them (:func:`turn_estimate` clear by
    :data:`TURN_MARGIN` of a smooth junction and of ``sharpest``, the largest turn rounded less that
    margin); None: the corner is decided as any other."""
    _, _, q, end, spline_before, lim_p, made, limits, feed, least, sharpest = fast
    p = prev.piece
    if nxt.piece is not q or p.end is not end or (prev.mid_k is not None) is not spline_before:
        return None
    half_p = prev.orig_length / (4.0 if spline_before else 2.0)
    now = half_p if half_p <= p.length else p.length
    if not abs(now - lim_p) <= 1e-12 * lim_p:
        return None
    if TURN_MARGIN < turn_estimate(p, q) < sharpest:
        return made, feed, limits   # the tests below would pass
    pu, qu = p.tangent_list(p.length), q.tangent_list(0.0)
    if not math.dist(pu, qu) > TANGENT_EPS:
        return None   # the curvatures decide (most likely a smooth junction)
    c = sum(map(operator.mul, pu, qu))
    if not 180.0 - math.degrees(math.acos(-1.0 if c < -1.0 else 1.0 if c > 1.0 else c)) >= least:
        return None   # a stop
    return made, feed, limits


def arc_batch_limits(chain: list[Span], rows: list[int], found: list, bounds: tuple, feeds: list[float],
                     least: float) -> tuple[list[tuple | None], list[tuple | None]]:
    """The limits of a batch's corner curves at arcs (:meth:`~.junctions.CornerMixin._arc_batch`; curve
    ``found[j]`` at chain[rows[j]] -> chain[rows[j] + 1], None where there is none; ``bounds``: the
    curves' bound rows, ``feeds`` each corner's), at each corner's feed with the chain's first span's
    axis and path limits (a curve's span takes prev's), and of the arcs it trims at both ends in the
    same rows (:func:`arc_trims`, ``least``: the shortest arc kept): per corner, the curve's limits and
    what :func:`cut_arc` takes for the arc before it (None: none)."""
    limits: list[tuple | None] = [None] * len(found)
    trims: list[tuple | None] = [None] * len(found)
    made = [j for j, m in enumerate(found) if m is not None]
    if not made:
        return limits, trims
    first = chain[0]
    lim = first.lim
    corners, arcs, theta0, r0, length, arc_feeds = arc_trims(chain, rows, found, first.path_acc, first.path_jerk,
                                                             least)
    rate = [feeds[j] for j in made]
    if corners:
        arc_bounds = arc_bound_rows(arcs, theta0, r0, length)
        bounds = tuple(np.concatenate(x) for x in zip(bounds, arc_bounds, strict=True))
        rate += arc_feeds
    rows_of = zip(*(x.tolist() for x in curve_limits_rows(*bounds, lim, np.array(rate), first.path_acc,
                                                          first.path_jerk)), strict=True)
    for j, row in zip(made, rows_of, strict=False):   # the curves' rows, then the arcs'
        limits[j] = row
    if corners:
        for j, arc, t, r, s, row, *lists in zip(corners, arcs, theta0, r0, length, rows_of,
                                                *(x.tolist() for x in arc_bounds), strict=True):
            trims[j] = (arc._lin, t, r, s, chain[rows[j]].feed, lim, tuple(lists), row)
    return limits, trims


def arc_trims(chain: list[Span], rows: list[int], found: list, path_acc: float, path_jerk: float,
              least: float) -> tuple[list[int], list[ArcPiece], list[float], list[float], list[float], list[float]]:
    """The arcs of a batch of corners at arcs (:meth:`~.junctions.CornerMixin._arc_batch`; corner ``j``:
    chain[rows[j]] -> chain[rows[j] + 1], its curve ``found[j]`` = (piece, d1, d2) or None) as they will
    stand once the corners at both their ends are made (Span.trim's floats: the corner before trims the
    arc's start by its d2, the corner after keeps its first ``length - d1``, longer than ``least``):
    ``(corners, arcs, theta0, r0, length, feeds)``, the corner at the end of each such arc, the arc
    (whose w, dr and axes the stretch keeps), the stretch's start angle, start radius and length, and
    the feed its limits take (the span's over the stretch's speed factor).  Only arcs with a curve at
    their end and the path limits ``path_acc``, ``path_jerk`` (those the rows' limits take)."""
    at_end = {i: j for j, i in enumerate(rows)}
    corners: list[int] = []
    arcs: list[ArcPiece] = []
    theta0: list[float] = []
    r0: list[float] = []
    length: list[float] = []
    feeds: list[float] = []
    for j, i in enumerate(rows):
        made, span = found[j], chain[i]
        p = span.piece
        if made is None or type(p) is not ArcPiece or span.path_acc != path_acc or span.path_jerk != path_jerk:
            continue
        t, r, s = p.theta0, p.r0, p.length
        before = at_end.get(i - 1)
        if before is not None and (cut := found[before]) is not None:   # ArcPiece.sub(d2, length)
            t, r, s = t + p.w * cut[2], r + p.dr * cut[2], s - cut[2]
        keep = s - made[1]
        if not keep > least:
            continue   # the corner drops the arc
        t, r, s = t + p.w * 0.0, r + p.dr * 0.0, keep - 0.0   # ArcPiece.sub(0.0, keep)
        end = r + p.dr * s
        rmax = end if end > r else r   # ArcPiece.speed_factor's max(r0, end radius)
        corners.append(j)
        arcs.append(p)
        theta0.append(t)
        r0.append(r)
        length.append(s)
        feeds.append(span.feed / math.sqrt((p.dr ** 2 + (rmax * p.w) ** 2) + p._lin[2]))
    return corners, arcs, theta0, r0, length, feeds


def cut_arc(span: Span, keep: float, known: tuple) -> None:
    """``span.trim(0.0, keep)`` of an arc whose stretch left, bounds and limits a batch made (``known``,
    see :func:`arc_trims`: the arc's shared numbers, the stretch's start angle, start radius and
    length, the span's feed and axis limits, the bounds and the limits): when the piece made is that
    stretch (the corner before trimmed the arc as the batch took it) it takes them, else its own."""
    lin, theta0, r0, length, feed, lim, bounds, limits = known
    p = span.piece = span.piece.sub(0.0, keep)
    if (p._lin is lin and p.theta0 == theta0 and p.r0 == r0 and p.length == length and span.feed == feed
            and span.lim is lim):
        p._bounded = bounds
        span.length, span._terms, span.stale = length, None, False   # Span.refresh's
        span.vc, span.acc, span.jerk = limits
    else:
        span.refresh()


def batched_line_corner(prev: Span, nxt: Span, fast: tuple) -> tuple | None:
    """The arguments of :meth:`~.junctions.CornerMixin._blend_span` for the corner prev -> nxt from its
    entry of a batch of G05 line corners (see :func:`fast_corners`) when the lines still stand as the
    batch took them (the same ends, the same most each may give up); None: the corner is decided as any
    other (:meth:`~.junctions.CornerMixin._junction`)."""
    _, _, end, lim_p, lim_q, feed, size, curve, limits, start, cut = fast
    p, q = prev.piece, nxt.piece
    if p.end is not end:
        return None
    half_p = prev.orig_length / (4.0 if prev.mid_k is not None else 2.0)
    half_q = nxt.orig_length / 2.0
    if (half_p if half_p <= p.length else p.length) != lim_p or (half_q if half_q <= q.length else q.length) != lim_q:
        return None
    return (BlendRow.of(*curve), size, size), feed, limits, start, cut


def cut_line(span: Span, keep: float, end: np.ndarray) -> None:
    """``span.trim(0.0, keep)`` of a line whose point at ``keep`` is known already (``end``): the same
    piece as :meth:`~fagorcnc.plan.geometry.LinePiece.sub` makes, without computing that point."""
    p = span.piece
    out = LinePiece.__new__(LinePiece)
    out.start, out.end, out.length = p.start, end, keep - 0.0
    out.u, out.ul, out.d2, out.d3 = p.u, p.ul, p.d2, p.d3   # d1: |u| when asked
    span.piece = out
    span.length = out.length
