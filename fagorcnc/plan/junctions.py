"""The corners between spans: junction speeds, G05 and HSC blends (one at a time or in batches), HSC
splines through dense polylines and the transitions into them, and the feed adaptation of
#SLOPE/#HSC.  A mixin of :class:`~fagorcnc.plan.planner.Planner`: the methods use its limits and
settings; the look-ahead and timing stay in :mod:`.planner`."""

from __future__ import annotations

import math
import operator
from collections import deque
from collections.abc import Iterable, Iterator
from itertools import islice, pairwise, repeat

import numpy as np

from . import links
from .blend import BlendPiece, BlendRow, blend_rows, blends, corner_deviations
from .corner_batch import blend_batch
from .corners import (
    BLEND_PARTS,
    CURVATURE_EPS,
    TANGENT_EPS,
    _roundpar,
    _roundpar_rows,
    line_corner_arrays,
    line_corner_sizes,
    make_blend,
    split_blend,
    transition_curve,
)
from .geometry import ArcPiece, LinePiece
from .limits import curve_limits_rows
from .lookahead import distance
from .shortcuts import (
    arc_batch_limits,
    batched_arc_corner,
    batched_line_corner,
    cut_arc,
    cut_line,
    fast_arc_corners,
    fast_corners,
    fast_splines,
    sharpest_turn,
)
from .span import Event, Span

#: Auxiliary functions that do not stop the motion.
NO_SYNC = frozenset({"H", "D"})
#: Control-point spacing of HSC spline curves: uniform (2/5 of each half), which keeps the
#: curvature of a polyline sampled from a circle constant through the curve.
SPLINE_SHAPE = 0.4
#: Corners sharper than this (included angle, degrees) are never rounded: the tool stops.
MIN_CORNER_ANGLE = 1.0
#: Items the corner stage looks ahead (and corner curves computed in one batch).  64 costs 6 %
#: (G05) and 10 % (HSC) fewer instructions than 32 at no loss in time; beyond that the batches'
#: arrays leave the processor's caches and the time no longer falls.
LOOK = 64
#: G05 line corners made alone rather than in a batch when the chain has at most this many
#: (a batch's fixed cost is that of about four corners made alone).
BATCH_LEAST = 4
#: HSC transition curves tried at once (the halving rarely goes further than a few steps).
TRANSITION_TRIES = 4
#: Pieces shorter than this (mm) are dropped: nothing moves.
MIN_LENGTH = 1e-9
#: No batched corner curve for a corner as it now stands (see :meth:`Planner._arc_blend`).
_MISSING = object()


class CornerMixin:
    """The corners between spans: junction speeds, G05 and HSC blends (one at a time or in batches), HSC"""

    #: The key and curve of the next :meth:`_single`, made with a transition (see :meth:`_transition`).
    _single_ahead: tuple | None = None

    # ------------------------------------------------------------ corners
    def _junction(self, prev: Span, nxt: Span) -> Span | None:
        """Decide the junction prev -> nxt: sets ``prev.stop_after`` or returns a blend span."""
        # a corner a batch knows to hold (no batch, nothing asked: most G50 and arc programs)
        if self._line_blends and (fast := self._line_blends.get(id(prev))) is not None and fast[0] is nxt:
            made = batched_line_corner(prev, nxt, fast)
            if made is not None:
                return self._blend_span(prev, nxt, *made)
        if self._arc_blends and (fast := self._arc_blends.get(id(prev))) is not None and fast[0] is nxt:
            found = batched_arc_corner(prev, nxt, fast)
            if found is not None:
                made, feed, limits = found
                if made is None:
                    prev.stop_after = True
                    return None
                return self._blend_span(prev, nxt, made, feed, limits)
        if (self._candidates and (cached := self._candidates.get(id(nxt))) is not None and cached[7] is not None
                and cached[7][0] is nxt and cached[0] is prev):
            found = self._batched_spline(prev, nxt, cached)
            if found is not _MISSING:
                return found
        dyn = prev.dyn
        corner = dyn.corner if dyn is not None else "G50"
        a = prev.record
        if a is nxt.record or ((f := getattr(a, "frame", None)) is not None and f is getattr(nxt.record, "frame", None)
                               and getattr(f, "pieces", False)):
            # parts of one block (a long arc, a feed ramp), joint-space lines of one transformed move
            # (fagorcnc.kinematics.stage gives them one frame): no corner between them
            return None
        if links.decided(prev, nxt):
            return None   # chords of one curve, #MOVE links (plan/links.py)
        if prev.rapid or nxt.rapid or corner in ("G07", "G50") or getattr(nxt.record, "thread", None) is not None:
            # no curve cuts into the start of a thread or a tap either (under G05 or HSC before it)
            if corner == "G50" and _thread_runs_on(prev, nxt):
                return None
            prev.stop_after = True
            return None
        p, q = prev.piece, nxt.piece
        # smooth (tangent and curvature continuous: nothing to round) or how sharp, on lists of floats
        if p.curved or q.curved:
            pu, qu = p.tangent_list(p.length), q.tangent_list(0.0)
            if math.dist(pu, qu) <= TANGENT_EPS and math.dist(p.direction_list(p.length)[1],
                                                              q.direction_list(0.0)[1]) <= CURVATURE_EPS:
                return None
        else:
            pu, qu = p.ul, q.ul
            if math.dist(pu, qu) <= TANGENT_EPS:
                return None
        c = sum(map(operator.mul, pu, qu))
        angle = 180.0 - math.degrees(math.acos(-1.0 if c < -1.0 else 1.0 if c > 1.0 else c))
        if angle < MIN_CORNER_ANGLE:
            prev.stop_after = True   # a reversal cannot be rounded
            return None
        feed = prev.feed if prev.feed <= nxt.feed else nxt.feed
        tolerance: float | None = None
        speed: float | None = feed
        distances = None
        corner_measure = False
        if corner == "HSC":
            hsc = dyn.hsc
            if angle < hsc.corner:   # L13537: sharp edge
                prev.stop_after = True
                return None
            tolerance = hsc.tolerance
            if hsc.mode == "FAST":
                feed *= hsc.fast / 100.0
                speed = feed
            made = self._spline(prev, nxt, tolerance)
            if made is not None:
                return self._blend_span(prev, nxt, made, feed, self._spline_limit(made[0], prev, feed))
        else:   # G05 / G61 with #ROUNDPAR
            corner_measure = True
            if dyn.roundpar[0] == 5:
                prev.stop_after = True   # not modelled (INT115 was reported): a sharp corner
                return None
            feed, speed, tolerance, distances = _roundpar(dyn.roundpar, feed)
            if distances is None and isinstance(p, LinePiece) and isinstance(q, LinePiece):
                found = self._line_blend(prev, nxt, feed, speed, tolerance)
                if found is not None:
                    return self._blend_span(prev, nxt, found[0], feed, found[1], found[2])
        acc = min(prev.lim.least_acceleration, nxt.lim.least_acceleration)
        jerk = min(prev.lim.least_jerk, nxt.lim.least_jerk)
        # a span that starts on an HSC spline keeps room for its transition back to a straight line
        half_p = prev.orig_length / (4.0 if prev.mid_k is not None else 2.0)
        inputs = (half_p, nxt.orig_length / 2.0, speed, tolerance, acc, jerk, corner_measure, feed)
        found = self._arc_blend(prev, nxt, inputs) if distances is None and (p.curved or q.curved) else _MISSING
        if found is not _MISSING:
            made, limits = found
        else:
            made = make_blend(p, q, half_p, nxt.orig_length / 2.0, tolerance=tolerance,
                              speed=speed, acc=acc, jerk=jerk, distances=distances, corner=corner_measure)
            limits = None
        if made is None:
            prev.stop_after = True
            return None
        return self._blend_span(prev, nxt, made, feed, limits)

    def _line_blend(self, prev: Span, nxt: Span, feed: float, speed: float | None,
                    tolerance: float | None) -> tuple | None:
        """The G05 corner curve between the lines of ``prev`` and ``nxt`` and its limits, computed in
        one batch with those of the line corners after it in the look-ahead (see
        :meth:`_line_blend_batch`); None where the batch has none for the corner as it now stands
        (the corner is then made alone)."""
        p, q = prev.piece, nxt.piece
        lp, lq = prev.lim, nxt.lim
        half_p = prev.orig_length / (4.0 if prev.mid_k is not None else 2.0)
        half_q = nxt.orig_length / 2.0
        inputs = (half_p if half_p <= p.length else p.length, half_q if half_q <= q.length else q.length, speed,
                  tolerance, lp.least_acceleration if lp.least_acceleration <= lq.least_acceleration
                  else lq.least_acceleration, lp.least_jerk if lp.least_jerk <= lq.least_jerk else lq.least_jerk,
                  feed, lp, prev.path_acc, prev.path_jerk)
        key = (id(p.u), id(q.u))
        for attempt in range(2):
            found = self._line_blends.get(key)
            if found is not None and found[2] is p.end and found[3] == inputs:
                _, _, _, _, size, curve, limits, start = found
                if size == 0.0:
                    return None
                return (BlendRow.of(*curve), size, size), limits, start
            if attempt == 0:
                self._line_blend_batch(prev, nxt)
        return None

    def _line_blend_batch(self, prev: Span, nxt: Span) -> None:
        """The G05 curves of the line corners from prev -> nxt on through the look-ahead (lines of
        the same dynamics and axis limits, each corner with its own feed), all at once: unit blends
        (:func:`line_corner_arrays`), sizes (:func:`line_corner_sizes`), curves and their limits
        (:func:`curve_limits_rows`), each with what :meth:`_line_blend` asks of its corner.  A line
        after this corner still has its full length then: the corner before it takes at most half
        of it, so the most the next corner may take is half of it too."""
        dyn, lim = prev.dyn, prev.lim
        chain = [prev, nxt]
        if nxt.dyn is dyn and nxt.lim is lim:
            for x in self._ahead:
                if len(chain) > LOOK or not (isinstance(x, Span) and x.dyn is dyn and x.lim is lim and _g05_line(x)):
                    break
                chain.append(x)
        if len(chain) - 1 <= BATCH_LEAST:
            return   # a few corners: made alone (a batch's fixed cost would be more than it saves)
        # per corner: the lower feed of its two lines, then #ROUNDPAR's speed and tolerance
        feeds = np.array([s.feed for s in chain])
        f, speeds, tolerance = _roundpar_rows(dyn.roundpar, np.minimum(feeds[:-1], feeds[1:]))
        f_list = f.tolist()
        speed_list = f_list if speeds is not None else [None] * len(f_list)
        acc, jerk = lim.least_acceleration, lim.least_jerk
        halves = [s.orig_length / 2.0 for s in chain]
        lim_p = [min(prev.orig_length / (4.0 if prev.mid_k is not None else 2.0), prev.piece.length), *halves[1:-1]]
        lim_q = [h if h <= s.piece.length else s.piece.length for h, s in zip(halves[1:], chain[1:], strict=True)]
        dirs = np.array([s.piece.u for s in chain])
        unit = line_corner_arrays(dirs[:-1], dirs[1:])
        size = line_corner_sizes(unit, np.array(lim_p), np.array(lim_q), speeds, tolerance, acc, jerk, corner=True)
        ends = [s.piece.end for s in chain[:-1]]
        vertices = np.array(ends)
        with np.errstate(divide="ignore", invalid="ignore"):
            controls = vertices[:, None, :] + size[:, None, None] * unit.controls
            d2 = unit.d2 / size[:, None]
            d3 = unit.d3 / (size * size)[:, None]
            tables = size[:, None] * unit.table
            starts = vertices + size[:, None] * dirs[1:]   # where each next line starts once trimmed
        limits = zip(*(x.tolist() for x in curve_limits_rows(unit.d1, d2, d3, lim, f, prev.path_acc, prev.path_jerk)),
                     strict=True)
        path = (lim, prev.path_acc, prev.path_jerk)
        # each curve as BlendRow.of takes it: the batch's arrays, its row, start point, bounds and length
        batch = (controls, tables)
        curves = zip(repeat(batch), range(len(controls)), list(controls[:, 0]), list(unit.d1), list(d2),
                     list(d3), tables[:, -1].tolist(), strict=False)
        # keyed by the identity of the two directions (a trimmed line keeps its direction array);
        # the entries hold the arrays, so no other array can take their ids
        blends = self._line_blends = {}
        fast = fast_corners(chain, dirs, feeds, size, MIN_CORNER_ANGLE)
        # where each line ends once the corner after it trims it, its start trimmed by the corner before
        # (Span.trim's floats: the length kept, then start + kept * u)
        kept = np.array([s.piece.length for s in chain[:-1]])
        kept[1:] -= size[:-1]
        whole = (kept - size == kept).tolist()
        kept -= size
        cut_ends = list(np.vstack([chain[0].piece.start[None], starts[:-1]]) + kept[:, None] * dirs[:-1])
        before = chain[0].piece.start
        for a, b, end, lp, lq, sp, fd, sz, curve, lm, st, ok, kp, ce, same in zip(
                chain, chain[1:], ends, lim_p, lim_q, speed_list, f_list, size.tolist(), curves, limits, list(starts),
                fast, kept.tolist(), cut_ends, whole, strict=False):
            st = st if b.piece.start is end else None
            blends[id(a.piece.u), id(b.piece.u)] = (a.piece.u, b.piece.u, end, (lp, lq, sp, tolerance, acc, jerk, fd,
                                                                                *path), sz, curve, lm, st)
            if ok:   # and by the first span's id: what _junction asks of the corner known to hold already
                blends[id(a)] = (b, a, end, lp, lq, fd, sz, curve, lm, st,
                                 None if before is None or same else (before, kp, ce))
            before = st

    def _arc_blend(self, prev: Span, nxt: Span, inputs: tuple) -> tuple | object:
        """The corner curve at an arc between ``prev`` and ``nxt`` (None: none fits) and its limits,
        computed in one batch with the other corners at arcs in the look-ahead (see
        :meth:`_arc_batch`); ``_MISSING`` where the batch has none for the corner as it now stands
        with ``inputs`` (half of each block, speed, tolerance, acceleration, jerk, corner measure,
        feed): it is then made alone."""
        key = (id(prev), id(nxt))
        for attempt in range(2):
            found = self._arc_blends.get(key)
            if found is not None:
                fp, fn, q, end, made_with, lim_p, made, limits, _ = found
                p = prev.piece
                now = inputs[0] if inputs[0] <= p.length else p.length
                if (fp is prev and fn is nxt and nxt.piece is q and made_with == inputs
                        and abs(now - lim_p) <= 1e-12 * lim_p
                        and (p.end is end or math.dist(p.end.tolist(), end.tolist()) <= 1e-9)):
                    return made, limits
                return _MISSING
            if attempt == 0:
                self._arc_batch(prev, nxt)
        return _MISSING

    def _arc_batch(self, prev: Span, nxt: Span) -> None:
        """The corner curves at arcs from prev -> nxt on through the look-ahead (spans of the same
        dynamics and axis limits), all at once (:func:`~fagorcnc.plan.corner_batch.blend_batch`),
        each with what :meth:`_junction` will ask of its corner: a block's half as it will stand
        (a quarter after an HSC spline between two lines), the lower feed of its two blocks.  A
        block after this corner still has its full length: the corner before it takes at most
        half of it, so what the next corner may take is unchanged."""
        dyn, lim = prev.dyn, prev.lim
        chain = [prev, nxt]
        if nxt.dyn is dyn and nxt.lim is lim and not _adapts(nxt):
            for x in self._ahead:
                if (len(chain) > LOOK or not isinstance(x, Span) or x.dyn is not dyn or x.lim is not lim
                        or x.rapid or _adapts(x)):
                    break
                chain.append(x)
        hsc = dyn.corner == "HSC"
        tolerance = dyn.hsc.tolerance if hsc else None
        rows, ps, qs, lim_p, lim_q, speeds, feeds, made_with, splines = [], [], [], [], [], [], [], [], []
        acc = min(prev.lim.least_acceleration, nxt.lim.least_acceleration)
        jerk = min(prev.lim.least_jerk, nxt.lim.least_jerk)
        for i, (a, b) in enumerate(pairwise(chain)):
            p, q = a.piece, b.piece
            if a.record is b.record or not (p.curved or q.curved):
                continue
            feed = a.feed if a.feed <= b.feed else b.feed
            if hsc:
                if dyn.hsc.mode == "FAST":
                    feed *= dyn.hsc.fast / 100.0
                speed = feed
            else:
                if dyn.roundpar[0] in (3, 5):
                    return   # fixed distances (cheap alone) or not modelled
                feed, speed, tolerance, _ = _roundpar(dyn.roundpar, feed)
            # after the first corner: one between two HSC lines before this one is a spline, most likely
            spline_before = a.mid_k is not None if i == 0 else hsc and not (chain[i - 1].piece.curved or p.curved)
            half_p = a.orig_length / (4.0 if spline_before else 2.0)
            half_q = b.orig_length / 2.0
            rows.append(i)
            ps.append(p)
            qs.append(q)
            lim_p.append(half_p if half_p <= p.length else p.length)
            lim_q.append(half_q if half_q <= q.length else q.length)
            speeds.append(speed)
            feeds.append(feed)
            made_with.append((half_p, half_q, speed, tolerance, acc, jerk, not hsc, feed))
            splines.append(spline_before)
        if not rows:
            return
        found, bounds = blend_batch(ps, qs, np.array(lim_p), np.array(lim_q), tolerance=tolerance,
                                    speed=None if speeds[0] is None else np.array(speeds), acc=acc, jerk=jerk,
                                    corner=not hsc, memo=self._corner_memo)
        # the curves' limits at once, at each corner's feed (the curve's span takes prev's limits), and
        # those of the arcs the batch trims at both ends (see cut_arc)
        limits, trims = arc_batch_limits(chain, rows, found, bounds, feeds, MIN_LENGTH)
        # keyed by the spans' identity; the entries hold the spans, so no other span can take their ids
        blends = self._arc_blends = {
            (id(chain[i]), id(chain[i + 1])): (chain[i], chain[i + 1], qs[j], ps[j].end, made_with[j],
                                               lim_p[j], found[j], limits[j], trims[j])
            for j, i in enumerate(rows)}
        # and by the first span's id: what _junction asks of a corner known to reach its curve
        least = max(dyn.hsc.corner, MIN_CORNER_ANGLE) if hsc else MIN_CORNER_ANGLE
        sharpest = sharpest_turn(least)
        for j, ok in enumerate(fast_arc_corners(chain, rows, made_with)):
            if ok:
                i = rows[j]
                blends[id(chain[i])] = (chain[i + 1], chain[i], qs[j], ps[j].end, splines[j], lim_p[j], found[j],
                                        limits[j], feeds[j], least, sharpest)

    def _blend_span(self, prev: Span, nxt: Span, made: tuple, feed: float, limits: tuple | None = None,
                    start: np.ndarray | None = None, cut: tuple | None = None) -> Span | None:
        """Trim both spans for the corner curve ``made`` = (piece, d1, d2) (with its ``limits`` and the
        point where ``nxt`` then starts when already known; ``cut``: prev's start, its length kept and
        the point where it then ends, when already known); None (a stop) when running through the
        curve would be slower than stopping."""
        blend, d1, d2 = made
        if limits is None:
            span = Span(blend, prev.record, feed, prev.lim, False, prev.dyn, prev.path_acc, prev.path_jerk, blend=True)
        else:
            span = Span.with_limits(blend, prev.record, feed, prev.lim, prev.dyn, prev.path_acc, prev.path_jerk,
                                    *limits)
        if _crawls(span):
            prev.stop_after = True   # stopping at the corner is faster than creeping round it
            nxt.mid_k = None
            self._spline_used = False
            return None
        nxt.trim(d2, nxt.piece.length, start, True)   # later: settled once its own end is decided
        p = prev.piece
        keep = p.length - d1
        if keep > MIN_LENGTH:
            if cut is not None and cut[1] == keep and p.start is cut[0]:
                cut_line(prev, keep, cut[2])
            elif (type(p) is ArcPiece and (known := self._arc_blends.get((id(prev), id(nxt)))) is not None
                  and known[0] is prev and known[1] is nxt and known[8] is not None):
                cut_arc(prev, keep, known[8])   # an arc whose stretch's limits the batch made
            else:
                prev.trim(0.0, keep)
        else:
            prev.piece = None
        return span

    # ------------------------------------------------------------ HSC splines through dense polylines
    def _spline(self, prev: Span, nxt: Span, tolerance: float) -> tuple | None:
        """HSC corner between two lines as a curve from the middle of one to the middle of the
        next, with the curvature the polyline suggests there (seed 002 L13486: the CNC builds
        splines through the points).  Consecutive curves then meet with equal curvature, so a
        dense CAM polyline becomes one smooth curve instead of a chain of corner rounds whose
        curvature drops to zero between corners.  None when it does not fit the tolerance."""
        self._spline_used = False
        p, q = prev.piece, nxt.piece
        if not (isinstance(p, LinePiece) and isinstance(q, LinePiece)) or _adapts(prev) or _adapts(nxt):
            return None
        d1 = min(prev.orig_length / 2.0, p.length)
        cached = self._candidates.pop(id(nxt), None)
        if not _fits(cached, prev, d1):
            if cached is not None and cached[0] is prev and _same_length(cached[2], d1):
                # only prev's curvature differs (the spline before it was not taken): this corner
                # alone is made again, and the candidates after it still hold (same end curvature)
                cached = self._single(prev, nxt, d1, cached)
            else:
                self._candidates.clear()
                self._batch(prev, nxt)
                cached = self._candidates.pop(id(nxt))
        _, _, _, blend, d2, k5, dev, _ = cached
        if not blend.valid or dev > 0.95 * tolerance:
            return None
        nxt.mid_k = k5
        self._spline_used = True
        return blend, d1, d2

    def _batched_spline(self, prev: Span, nxt: Span, cached: tuple) -> Span | object | None:
        """The HSC corner prev -> nxt from its batched spline candidate whose checks :meth:`_batch` knows to
        hold (see :func:`~.shortcuts.fast_splines`; its curve valid and within the tolerance): what
        :meth:`_junction` and :meth:`_spline` make of it when it fits as the corner now stands (prev's
        curvature, the length it may give up); ``_MISSING``: the corner is decided as any other."""
        d1 = min(prev.orig_length / 2.0, prev.piece.length)
        _, mid_k, length, blend, d2, k5, _, (_, piece, start) = cached
        if mid_k is not prev.mid_k or not _same_length(length, d1):
            return _MISSING
        hsc = prev.dyn.hsc   # the curve is valid and keeps the tolerance (_batch tested them as _spline does)
        feed = prev.feed if prev.feed <= nxt.feed else nxt.feed
        if hsc.mode == "FAST":
            feed *= hsc.fast / 100.0
        del self._candidates[id(nxt)]
        nxt.mid_k = k5
        self._spline_used = True
        return self._blend_span(prev, nxt, (blend, d1, d2), feed, self._spline_limit(blend, prev, feed),
                                start if nxt.piece is piece else None)

    def _spline_limit(self, blend, prev: Span, feed: float) -> tuple | None:
        """The limits of the spline ``blend`` computed with its batch (see :meth:`_batch`) when they
        were made with what its span now takes (``prev``'s axis and path limits, ``feed``); None:
        the span makes them itself."""
        found = self._spline_limits.get(id(blend))
        if (found is not None and found[0] is blend and found[1] == feed and found[2] is prev.lim
                and found[3] == prev.path_acc and found[4] == prev.path_jerk):
            return found[5]
        return None

    def _single(self, prev: Span, nxt: Span, d1: float, cached: tuple) -> tuple:
        """The spline candidate of the corner prev -> nxt made again from prev's curvature as it
        now stands, with the end (d2, curvature) of the batched one (its curve made already with
        the transition before it when made as it now stands, see :meth:`_transition`)."""
        _, _, _, _, d2, k5, _, _ = cached
        ahead, self._single_ahead = self._single_ahead, None
        if ahead is not None and ahead[1] == d1 and all(map(operator.is_, ahead[0], _single_key(prev, nxt, cached))):
            p0, vertex, p5, (curves, samples) = ahead[2]
        else:
            p0, vertex, p5, rows = _single_rows(prev, nxt, d1, cached)
            curves, samples = blends(*rows)
        dev = float(corner_deviations(samples, p0[None], vertex[None], p5[None])[0]) if curves[0].valid else math.inf
        return prev, prev.mid_k, d1, curves[0], d2, k5, dev, None

    def _single_ahead_rows(self, prev: Span, dim: int) -> tuple | None:
        """The key of :meth:`_single` of the corner from ``prev`` to the span after it and the rows it
        makes its curve from, when that corner's batched candidate was made with another curvature of
        prev than it now has (None otherwise, and for fewer than three axes: see
        :func:`~fagorcnc.plan.blend.blend_groups`)."""
        nxt = self._ahead[0] if self._ahead and dim > 2 else None
        if not (isinstance(nxt, Span) and isinstance(prev.piece, LinePiece) and isinstance(nxt.piece, LinePiece)):
            return None
        cached = self._candidates.get(id(nxt))
        if cached is None or cached[0] is not prev or cached[1] is prev.mid_k:
            return None
        d1 = min(prev.orig_length / 2.0, prev.piece.length)
        if not _same_length(cached[2], d1):
            return None
        return _single_key(prev, nxt, cached), d1, _single_rows(prev, nxt, d1, cached)

    def _batch(self, prev: Span, nxt: Span) -> None:
        """Spline candidates for the run of HSC lines starting at ``prev``, ``nxt`` and going on
        through the look-ahead up to its first sharp corner, all computed at once
        (:func:`~fagorcnc.plan.blend.blends`); each assumes the previous one is taken (its end
        curvature is the next one's start), which a stop at a sharp corner undoes."""
        chain = [prev, nxt]
        # the chain goes on only through HSC lines: nxt may be the end of the HSC run (a G60 block, a
        # G50 after it), whose own corner is no spline, however HSC the lines after it are (issue 30)
        ahead = self._ahead if _spline_line(nxt) else ()
        for j, x in enumerate(ahead):
            if not (isinstance(x, Span) and isinstance(x.piece, LinePiece) and _spline_line(x)):
                break
            if j == len(ahead) - 1 or len(chain) >= LOOK:
                break   # keep the item after the chain known: it decides the last line's curvature
            chain.append(x)
        follow = ahead[len(chain) - 2] if len(ahead) > len(chain) - 2 else None
        after_ok = isinstance(follow, Span) and isinstance(follow.piece, LinePiece) and _spline_line(follow)
        lines = [*chain, follow] if after_ok else chain
        u = np.array([s.piece.u for s in lines])
        angle = 180.0 - np.degrees(np.arccos(np.clip((u[:-1] * u[1:]).sum(axis=1), -1.0, 1.0)))
        sharp = angle[1:len(chain) - 1] < np.maximum([s.dyn.hsc.corner for s in chain[1:-1]], MIN_CORNER_ANGLE)
        if sharp.any():   # the corner chain[cut - 1] -> chain[cut]: the tool stops there
            cut = int(sharp.argmax()) + 2
            follow, after_ok, chain = chain[cut], True, chain[:cut]
            lines, u, angle = [*chain, follow], u[:cut + 1], angle[:cut]
        n = len(chain) - 1                       # corners chain[i] -> chain[i + 1]
        dim = u.shape[1]
        orig = np.array([s.orig_length for s in lines] + ([] if after_ok else [1.0]))
        vertex = np.array([s.piece.start for s in chain[1:]])
        # curvature at the middle of each line: the mean of its two corners', normal to the line,
        # where the corner after it is rounded by a spline too (an HSC line beyond, angle >= CORNER)
        u_next = u[2:] if after_ok else np.vstack([u[2:], np.zeros((1, dim))])
        corner = [x.dyn.hsc.corner for x in lines[2:]] + ([] if after_ok else [180.0])
        angle_ok = (angle[1:] if after_ok else np.append(angle[1:], 0.0)) >= np.maximum(corner, MIN_CORNER_ANGLE)
        angle_ok[-1] &= after_ok
        k_in = (u[1:n + 1] - u[:n]) / ((orig[:n] + orig[1:n + 1]) / 2.0)[:, None]
        k_out = (u_next - u[1:n + 1]) / ((orig[1:n + 1] + orig[2:]) / 2.0)[:, None]
        k = (k_in + k_out) / 2.0
        k -= (k * u[1:n + 1]).sum(axis=1)[:, None] * u[1:n + 1]
        kmid = np.zeros((n + 1, dim))
        kmid[1:] = np.where(angle_ok[:, None], k, 0.0)
        if prev.mid_k is not None:
            kmid[0] = prev.mid_k
        d1 = orig[:n] / 2.0
        d1[0] = min(prev.orig_length / 2.0, prev.piece.length)
        d2 = orig[1:n + 1] / 2.0
        p0 = vertex - d1[:, None] * u[:n]
        p5 = vertex + d2[:, None] * u[1:n + 1]
        curves, samples, valid, bounds = blend_rows(p0, u[:n], kmid[:-1], SPLINE_SHAPE * d1, p5, u[1:n + 1],
                                                    kmid[1:], SPLINE_SHAPE * d2)
        devs = corner_deviations(samples, p0, vertex, p5)
        devs[~valid] = np.inf
        curved = (np.abs(kmid).max(axis=1) > 0.0).tolist()
        self._spline_batch_limits(chain, curves, valid, bounds)
        previous_k = prev.mid_k
        fast = fast_splines(chain, u, angle, MIN_CORNER_ANGLE)
        if any(fast):   # and the curve valid and within the tolerance, as _spline tests it (the lines taken
            # have the planning context of the chain's second, see fast_splines)
            kept = (valid & (devs <= 0.95 * chain[1].dyn.hsc.tolerance)).tolist()
            fast = [ok and within for ok, within in zip(fast, kept, strict=True)]
        for i, (curve, d_1, d_2, dev, ok, start) in enumerate(zip(curves, d1.tolist(), d2.tolist(), devs.tolist(),
                                                                  fast, list(p5), strict=True)):
            k5 = kmid[i + 1] if curved[i + 1] else None
            # the last, when the corner's checks are known to hold (see _batched_spline): the line after
            # it, its piece and where it starts once trimmed (Span.trim's floats: start + d2 * u)
            nxt = chain[i + 1]
            self._candidates[id(nxt)] = (chain[i], previous_k, d_1, curve, d_2, k5, dev,
                                         (nxt, nxt.piece, start) if ok else None)
            previous_k = k5

    def _spline_batch_limits(self, chain: list[Span], curves: list[BlendPiece], valid: np.ndarray,
                             bounds: tuple) -> None:
        """The limits of the spline candidates ``curves`` (corner i: chain[i] -> chain[i + 1]) at
        once (:func:`~fagorcnc.plan.limits.curve_limits_rows`, the same numbers as each span's
        own :func:`~fagorcnc.plan.limits.curve_limits`), with what :meth:`_junction` will give
        each one's span: the lower feed of its two lines (FAST: times its share), the axis and
        path limits of the first line of the chain (a corner whose line has others makes its own).
        ``valid``, ``bounds``: which curves are valid and their bounds (d1, d2, d3), as arrays."""
        self._spline_limits = {}
        first = chain[0]
        rows = np.flatnonzero(valid).tolist()
        if len(rows) < BATCH_LEAST:
            return
        feeds = []
        for i in rows:
            a, b = chain[i], chain[i + 1]
            feed = a.feed if a.feed <= b.feed else b.feed
            hsc = a.dyn.hsc
            if hsc.mode == "FAST":
                feed *= hsc.fast / 100.0
            feeds.append(feed)
        picked = [curves[i] for i in rows]
        d1, d2, d3 = bounds   # the picked curves' rows: their own d1, d2, d3
        limits = curve_limits_rows(d1[rows], d2[rows], d3[rows], first.lim, np.array(feeds), first.path_acc,
                                   first.path_jerk)
        path = (first.lim, first.path_acc, first.path_jerk)
        # keyed by the curves' identity; the entries hold the curves, so no other curve can take their ids
        self._spline_limits = {id(c): (c, f, *path, row) for c, f, row in
                               zip(picked, feeds, zip(*(x.tolist() for x in limits), strict=True), strict=True)}

    def _transition(self, span: Span, after: Span | None = None) -> Span | None:
        """A span that starts on an HSC spline with curvature but does not end on one: a short
        curve back to its straight line (curvature stays continuous), cut from its start: the
        longest of 1/8 of the block, half that, ... (down to 1e-6 mm) that keeps the tolerance,
        tried a few at a time.  ``after``: the span after it, whose spline candidate (made as if
        this corner had been a spline) is most often made again next (:meth:`_single`): made with
        the first tries (one set of array operations for both)."""
        k, p = span.mid_k, span.piece
        span.mid_k = None
        if k is None or p is None or not isinstance(p, LinePiece):
            return None
        tol = span.dyn.hsc.tolerance if span.dyn is not None and span.dyn.hsc is not None else 0.01
        steps, step = [], min(span.orig_length / 8.0, p.length / 2.0)
        while step > 1e-6:
            steps.append(step)
            step /= 2.0
        for i in range(0, len(steps), TRANSITION_TRIES):
            single = self._single_ahead_rows(after, len(k)) if i == 0 and after is not None else None
            found, made = transition_curve(p, k, steps[i:i + TRANSITION_TRIES], tol, single and single[2][3])
            if made is not None:
                self._single_ahead = (single[0], single[1], (*single[2][:3], made))
            if found is not None:
                curve, step = found
                span.trim(step, p.length)
                return Span(curve, span.record, span.feed, span.lim, False, span.dyn, span.path_acc,
                            span.path_jerk, blend=True)
        return None

    def _adapt(self, prev: Span, nxt: Span) -> tuple[list[Span], list[Span], Span]:
        """Feed adaptation at a junction without a stop (seed 002 L4193-L4270).

        Returns the spans replacing ``prev``, the spans to emit before ``nxt``'s
        last part, and that last part (which waits for its own junction).
        Default: the junction speed is the lower feed (G108 when the feed rises,
        G109 when it falls).  G108 in ``prev``: ``nxt`` starts at prev's F and
        slows down at its start; G109 in ``prev``: ``prev`` speeds up to nxt's F at
        its end; G193 in ``nxt``: nxt's feed goes linearly from prev's F to its
        own over the block (8 steps).
        """
        before, head = [prev], []
        f0, f1 = prev.feed, nxt.feed
        adapt = prev.dyn.adaptation if prev.dyn is not None else None
        if adapt == "G109" and f1 > f0 and prev.piece is not None:
            ramp = min(distance(f0, f1, prev.acc, prev.jerk), prev.length)
            cut = prev.length - ramp
            before = ([prev.part(0.0, cut)] if cut > MIN_LENGTH else []) + [prev.part(cut, prev.length, f1)]
        elif adapt == "G108" and f0 > f1:
            ramp = min(distance(f1, f0, nxt.acc, nxt.jerk), nxt.length)
            if nxt.length - ramp > MIN_LENGTH:
                head = [nxt.part(0.0, ramp, f0)]
                nxt = nxt.part(ramp, nxt.length)
            else:
                nxt = nxt.part(0.0, nxt.length, f0)
        if nxt.dyn is not None and nxt.dyn.adaptation == "G193" and f0 != f1 and math.isfinite(f0 + f1):
            steps = 8
            cuts = [nxt.length * i / steps for i in range(steps + 1)]
            parts = [nxt.part(cuts[i], cuts[i + 1], f0 + (f1 - f0) * (i + 0.5) / steps) for i in range(steps)]
            head += parts[:-1]
            nxt = parts[-1]
        return before, head, nxt

    def _corners(self, items: Iterable[Span | Event]) -> Iterator[Span | Event]:
        prev: Span | None = None
        pending: list[Event] = []        # events that do not stop the motion, after prev
        settle = self.config.inposition_time
        whole = bool(self.jerk)   # corner curves stay whole (see _blend_parts)
        source = iter(items)
        ahead = self._ahead = deque(islice(source, LOOK))
        while ahead:
            item = ahead.popleft()
            following = next(source, None)     # kept full: the batches of corner curves then span all of it
            if following is not None:
                ahead.append(following)
            if isinstance(item, Event):
                if item.kind == "aux" and item.record.function in NO_SYNC and prev is not None:
                    pending.append(item)
                    continue
                if prev is not None:
                    prev.stop_after = True
                    prev.settle()
                    yield from self._lead(prev)
                    yield from self._emit(prev, pending, settle)
                    prev, pending = None, []
                yield item
                continue
            if prev is not None:
                self._spline_used = False
                blend = self._junction(prev, item)
                if prev.stale:   # its end is decided: limits left for now can be made (see Span.trim)
                    prev.settle()
                if not self._spline_used and prev.mid_k is not None:
                    yield from self._lead(prev, item)
                if prev.stop_after:   # _emit inline (a stop at most blocks under G50)
                    if prev.piece is not None:
                        yield prev
                    if pending:
                        yield from pending
                    if settle > 0 and prev.dyn is not None and prev.dyn.corner == "G07":
                        yield Event(None, settle)   # in-position wait after a square corner (INPOSW)
                elif ((dyn := prev.dyn) is None or dyn.adaptation is None) and \
                        ((dyn := item.dyn) is None or dyn.adaptation is None):   # no feed adaptation: the usual case
                    if prev.piece is not None:
                        yield prev
                    if pending:
                        yield from pending
                    if blend is not None:
                        if whole:
                            yield blend
                        else:
                            yield from self._blend_parts(blend)
                else:
                    item.settle()
                    before, head, item = self._adapt(prev, item)
                    for span in before:
                        if span.piece is not None:
                            yield span
                    yield from pending
                    if blend is not None:
                        yield from self._blend_parts(blend)
                    yield from head
                pending = []
            prev = item
        if prev is not None:
            prev.stop_after = True
            prev.settle()
            yield from self._lead(prev)
            yield from self._emit(prev, pending, settle)

    def _blend_parts(self, blend: Span) -> Iterator[Span]:
        """A corner curve's span, in :data:`~fagorcnc.plan.corners.BLEND_PARTS` parts when the planner
        has no jerk limit: each part then has a cap from its own curvature (dense G05 zig-zag of
        0.05 mm steps, jerk off: 1.34 x the time-optimal bound in one part).  With a jerk limit every
        junction between parts returns the path acceleration to zero, which costs more than the
        finer caps gain, so the curve stays whole."""
        if self.jerk or not isinstance(blend.piece, BlendPiece):
            yield blend
            return
        for piece in split_blend(blend.piece, BLEND_PARTS):
            yield Span(piece, blend.record, blend.feed, blend.lim, False, blend.dyn, blend.path_acc, blend.path_jerk,
                       blend=True)

    def _lead(self, span: Span, after: Span | None = None) -> Iterator[Span]:
        """The transition curve a span needs at its start, if any (see :meth:`_transition`)."""
        curve = self._transition(span, after) if span.mid_k is not None else None
        if curve is not None:
            yield curve

    @staticmethod
    def _emit(span: Span, pending: list, settle: float) -> Iterator[Span | Event]:
        if span.piece is not None:
            yield span
        yield from pending
        if span.stop_after and settle > 0 and span.dyn is not None and span.dyn.corner == "G07":
            yield Event(None, settle)   # in-position wait after a square corner (INPOSW)


def _thread_runs_on(prev: Span, nxt: Span) -> bool:
    """A G33 thread joined to the one before in the same direction runs on without stopping (seed 002
    L7366-L7370: joined threads are not synchronised again); at any other joint the thread's G50 context
    stops the axes at the programmed corner, nothing is rounded inside a thread."""
    t = getattr(nxt.record, "thread", None)
    if t is None or t.rigid or t.entry is not None or getattr(prev.record, "thread", None) is None:
        return False
    p, q = prev.piece, nxt.piece
    return not p.curved and not q.curved and math.dist(p.ul, q.ul) <= TANGENT_EPS


def _single_key(prev: Span, nxt: Span, cached: tuple) -> tuple:
    """What :func:`_single_rows` makes its rows from besides d1 (matched by identity)."""
    return prev, nxt, cached, prev.mid_k, prev.piece.u, nxt.piece.u, nxt.piece.start


def _single_rows(prev: Span, nxt: Span, d1: float, cached: tuple) -> tuple:
    """``p0, vertex, p5`` and the rows of :func:`~fagorcnc.plan.blend.blends` of the spline candidate of
    :meth:`CornerMixin._single`: from the middle of prev (``d1`` before its end, its curvature as it
    now stands) to the batched candidate's end on nxt (its d2 and curvature)."""
    _, _, _, _, d2, k5, _, _ = cached
    u0, u1 = prev.piece.u, nxt.piece.u
    vertex = nxt.piece.start
    zero = np.zeros_like(u0)
    k0 = zero if prev.mid_k is None else prev.mid_k
    p0, p5 = vertex - d1 * u0, vertex + d2 * u1
    return p0, vertex, p5, (p0[None], u0[None], k0[None], np.array([SPLINE_SHAPE * d1]), p5[None], u1[None],
                            (zero if k5 is None else k5)[None], np.array([SPLINE_SHAPE * d2]))


def _fits(cached: tuple | None, prev: Span, d1: float) -> bool:
    """Whether a batched spline candidate was made for this corner as it now stands."""
    return cached is not None and cached[0] is prev and cached[1] is prev.mid_k and _same_length(cached[2], d1)


def _same_length(a: float, b: float) -> bool:
    return abs(a - b) <= 1e-9 * max(b, 1e-9)


def _g05_line(span: Span) -> bool:
    """A line whose corners G05 rounds (batched unit blends)."""
    return isinstance(span.piece, LinePiece) and not span.rapid and span.dyn is not None and span.dyn.corner == "G05"


def _spline_line(span: Span) -> bool:
    """A line that can carry an HSC spline through its middle."""
    dyn = span.dyn
    return dyn is not None and dyn.corner == "HSC" and dyn.adaptation is None and not span.rapid


def _adapts(span: Span) -> bool:
    return span.dyn is not None and span.dyn.adaptation is not None


def _crawls(span: Span) -> bool:
    """True when running through a corner curve at its speed cap takes longer than
    covering its length from rest to rest (a near-reversal): better stop there."""
    length, vc, jerk = span.length, span.vc, span.jerk
    at_cap = length / vc if vc > 0 else math.inf
    rest = 2.0 * math.sqrt(length / span.acc)
    if jerk == math.inf or (at_cap <= rest and jerk > 0.0):
        return at_cap > rest   # with a jerk limit the rest only grows (a sum of a term >= 0 and this one)
    return at_cap > 4.0 * (length / (2.0 * jerk)) ** (1.0 / 3.0) + rest
