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
from .corners import TANGENT_EPS
from .geometry import ArcPiece, BlendRow, LinePiece
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


def batched_arc_corner(prev: Span, nxt: Span, fast: tuple) -> tuple | None:
    """``(curve, d1, d2) or None, feed, limits`` of the corner at an arc prev -> nxt from its entry of
    a batch (see :func:`fast_arc_corners`) when the spans still stand as the batch took them (the same
    next piece and end of prev, the curvature kept before prev: an HSC spline or not, and the same
    most prev may give up, as :meth:`~.junctions.CornerMixin._arc_blend` asks) and the corner passes
    _junction's tests of a smooth junction, a reversal and a sharp HSC edge (``least``: the least
    included angle rounded) on the same floats; None: the corner is decided as any other."""
    _, _, q, end, spline_before, lim_p, made, limits, feed, least = fast
    p = prev.piece
    if nxt.piece is not q or p.end is not end or (prev.mid_k is not None) is not spline_before:
        return None
    half_p = prev.orig_length / (4.0 if spline_before else 2.0)
    now = half_p if half_p <= p.length else p.length
    if not abs(now - lim_p) <= 1e-12 * lim_p:
        return None
    pu, qu = p.tangent_list(p.length), q.tangent_list(0.0)
    if not math.dist(pu, qu) > TANGENT_EPS:
        return None   # the curvatures decide (most likely a smooth junction)
    c = sum(map(operator.mul, pu, qu))
    if not 180.0 - math.degrees(math.acos(-1.0 if c < -1.0 else 1.0 if c > 1.0 else c)) >= least:
        return None   # a stop
    return made, feed, limits


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
