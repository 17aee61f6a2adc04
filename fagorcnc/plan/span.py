"""The planner's unit of work: one piece of path with its limits, and the
events (dwells, auxiliary functions) that synchronise with the motion."""

from __future__ import annotations

import math

import numpy as np

from .geometry import LinePiece, Piece
from .limits import (
    ARRAY_TERMS,
    AxisLimits,
    TermArrays,
    Terms,
    axis_terms,
    curve_limits,
    line_limits,
    reach_without_jerk,
    tangential,
    tangential_arrays,
    term_arrays,
)
from .lookahead import reachable

#: Curves in a group from which their limits are taken from their bounds as arrays at once
#: (:func:`~fagorcnc.plan.limits.term_arrays`) rather than from each curve's terms: the arrays cost
#: about as much as a loop over 16 arcs' terms per cap asked, and their making far more.
ARRAY_CURVES = 16
#: Lower caps tried on curves (fractions of the highest cap).
LADDER = (0.97, 0.94, 0.91, 0.88, 0.85, 0.8, 0.75, 0.7, 0.62, 0.55, 0.4, 0.25, 0.12, 0.05)


class Span:
    """A piece with what the look-ahead needs: speed cap ``vc`` (mm/s),
    tangential acceleration ``acc`` and jerk ``jerk``, and whether the motion
    must stop at its end."""

    __slots__ = ("_terms", "acc", "blend", "dyn", "feed", "jerk", "length", "lim", "line", "mid_k",
                 "orig_length", "path_acc", "path_jerk", "piece", "rapid", "record", "stale", "stop_after", "vc")

    def __init__(self, piece: Piece, record, feed: float, lim: AxisLimits, rapid: bool, dyn,
                 path_acc: float = 0.0, path_jerk: float = 0.0, blend: bool = False, later: bool = False) -> None:
        self.piece = piece
        self.record = record
        self.line = record.src.line if record is not None else 0
        self.feed = feed
        self.lim = lim
        self.rapid = rapid
        self.dyn = dyn
        self.path_acc = path_acc
        self.path_jerk = path_jerk
        self.blend = blend
        self.orig_length = piece.length
        self.stop_after = False
        self.mid_k = None   # HSC spline: curvature the path has where this span now starts
        if later:   # a curve's limits once the corners at both its ends are decided (see trim)
            self._leave_stale()
        else:
            self.refresh()

    @classmethod
    def with_limits(cls, piece: Piece, record, feed: float, lim: AxisLimits, dyn, path_acc: float,
                    path_jerk: float, vc: float, acc: float, jerk: float) -> Span:
        """A corner curve's span whose limits ``vc, acc, jerk`` were already computed (with those of
        other curves, :func:`~fagorcnc.plan.limits.curve_limits_rows`)."""
        out = cls.__new__(cls)
        out.piece, out.record, out.line = piece, record, record.src.line
        out.feed, out.lim, out.rapid, out.dyn = feed, lim, False, dyn
        out.path_acc, out.path_jerk, out.blend = path_acc, path_jerk, True
        out.orig_length = out.length = piece.length
        out.stop_after, out.mid_k, out._terms, out.stale = False, None, None, False
        out.vc, out.acc, out.jerk = vc, acc, jerk
        return out

    @classmethod
    def of_line(cls, piece: LinePiece, record, feed: float, lim: AxisLimits, rapid: bool, dyn, path_acc: float,
             path_jerk: float) -> Span:
        """A straight line's span: :meth:`__init__` and :meth:`refresh` in one, with the loop of
        :func:`~fagorcnc.plan.limits.line_limits` inline over the direction (``|u_i|`` is its ``d1``):
        the same operations, so the same numbers (every line planned makes one)."""
        out = cls.__new__(cls)
        out.piece, out.record, out.line = piece, record, record.src.line
        out.feed, out.lim, out.rapid, out.dyn = feed, lim, rapid, dyn
        out.path_acc, out.path_jerk, out.blend = path_acc, path_jerk, False
        out.orig_length = out.length = piece.length
        out.stop_after, out.mid_k, out._terms, out.stale = False, None, None, False
        vc = feed
        acc = path_acc if path_acc > 0 else math.inf
        jerk = path_jerk if path_jerk > 0 else math.inf
        for x, (v, a, j) in zip(piece.ul, lim.rows):  # noqa: B905 (one entry per axis, see limits._AXES)
            if x != 0.0:
                g = x if x > 0.0 else -x
                if (y := v / g) < vc:
                    vc = y
                if (y := a / g) < acc:
                    acc = y
                if (y := j / g) < jerk:
                    jerk = y
        out.vc, out.acc, out.jerk = vc, acc, jerk
        return out

    def refresh(self) -> None:
        """Recompute the limits from the (possibly trimmed) piece."""
        p = self.piece
        self.length = p.length
        self._terms = None
        self.stale = False
        if p.curved:
            self.vc, self.acc, self.jerk = curve_limits(*p.bound_lists(), self.lim, self.feed / p.speed_factor(),
                                                        self.path_acc, self.path_jerk)
        else:
            self.vc, self.acc, self.jerk = line_limits(p.d1.tolist(), self.lim, self.feed, self.path_acc,
                                                       self.path_jerk)

    @property
    def terms(self) -> Terms:
        """The :func:`~fagorcnc.plan.limits.axis_terms` of a curved piece, made on first use: a
        group of curves below a lower cap needs them (most corner curves are never asked)."""
        if self._terms is None:
            p = self.piece
            self._terms = axis_terms(*p.bound_lists(), self.lim)
        return self._terms

    def trim(self, s0: float, s1: float, start=None, later: bool = False) -> None:
        """Keep the stretch ``[s0, s1]`` of the piece (a line: ``start`` its point at s0 when already
        known).  A line's limits depend on its direction alone, so a trimmed line only changes its
        length.  ``later``: a curved piece's limits are left stale until :meth:`settle` (a corner
        trims the start of the next span, whose end the corner after it most often trims again)."""
        self.piece = self.piece.sub(s0, s1) if start is None else self.piece.sub(s0, s1, start)
        if not self.piece.curved:
            self.length = self.piece.length
        elif later:
            self._leave_stale()
        else:
            self.refresh()

    def _leave_stale(self) -> None:
        """The piece's length now, its limits when :meth:`settle` asks."""
        self.length = self.piece.length
        self._terms = None
        self.stale = True

    def settle(self) -> None:
        """Recompute the limits a trim left stale (see :meth:`trim`)."""
        if self.stale and self.piece is not None:
            self.refresh()

    def parts(self, cuts: list[float]) -> list[Span]:
        """:meth:`part` ``(cuts[i], cuts[i + 1], later=True)`` for the increasing ``cuts`` of an arc
        (:meth:`~fagorcnc.plan.geometry.ArcPiece.pieces`: the point at each cut made once)."""
        return [Span(piece, self.record, self.feed, self.lim, self.rapid, self.dyn, self.path_acc, self.path_jerk,
                     self.blend, True) for piece in self.piece.pieces(cuts)]

    def part(self, s0: float, s1: float, feed: float | None = None, later: bool = False) -> Span:
        """The stretch ``[s0, s1]`` of this span as a new span (optionally with another feed; ``later``:
        its limits made when :meth:`settle` asks, as with :meth:`trim`)."""
        return Span(self.piece.sub(s0, s1), self.record, self.feed if feed is None else feed, self.lim, self.rapid,
                    self.dyn, self.path_acc, self.path_jerk, self.blend, later)


class Event:
    """A dwell or an auxiliary function: the motion stops before it (a synchronisation point)."""

    __slots__ = ("duration", "kind", "line", "record")

    def __init__(self, record, duration: float) -> None:
        self.record = record
        self.kind = record.kind if record is not None else "dwell"
        self.line = record.src.line if record is not None else 0
        self.duration = duration


class Group:
    """Consecutive short spans planned as one motion (one ruckig profile over their total
    length), so the speed can change across their junctions without returning to zero
    acceleration at each one; each member keeps its own segment, cut from the profile.

    Limits are the most restrictive of the members' (each member's are valid below its own
    cap, and the group stays below the lowest cap)."""

    __slots__ = ("_path", "_rungs", "_terms", "acc", "curves", "jerk", "length", "line", "line_acc", "line_jerk",
                 "members", "record", "stop_after", "vc")

    def __init__(self, first: Span) -> None:
        self.members = [first]
        self.length = first.length
        self.vc, self.acc, self.jerk = first.vc, first.acc, first.jerk
        self.stop_after = first.stop_after
        self.line, self.record = first.line, first.record
        self._rungs: list | None = None   # made when the look-ahead asks (see rungs())
        self._terms = None
        self._path: tuple[float, float] | None = None   # the path limits below any cap (see _tangential)
        # below a lower cap only the curves' limits change: a line's terms in the formulas of
        # :func:`~fagorcnc.plan.limits.tangential` reduce exactly to its own limits
        self.curves: list[Span] = []
        self.line_acc = self.line_jerk = math.inf
        self._classify(first)

    def _classify(self, span: Span) -> None:
        # plain comparisons, no min() calls: this runs for every span planned
        if span.piece.curved:
            self.curves.append(span)
        else:
            if span.acc < self.line_acc:
                self.line_acc = span.acc
            if span.jerk < self.line_jerk:
                self.line_jerk = span.jerk

    def add(self, span: Span) -> None:
        self.members.append(span)
        self.length += span.length
        if span.vc < self.vc:
            self.vc = span.vc
        if span.acc < self.acc:
            self.acc = span.acc
        if span.jerk < self.jerk:
            self.jerk = span.jerk
        self.stop_after = span.stop_after
        self._rungs = None
        self._terms = None
        self._path = None
        self._classify(span)

    @property
    def curved(self) -> bool:
        return bool(self.curves)

    def rungs(self, v: float) -> list[tuple[float, float, float]]:
        """(cap, tangential acceleration, tangential jerk) for the descending caps ``vc * LADDER``
        at least down to the speed ``v`` (below a lower cap a curve leaves more of the axes' budget
        for speed changes; a motion at ``v`` has no use for caps below it); lines: the cap alone.
        Made as they are needed: most junctions run close to the top cap."""
        rungs = self._top()
        if self.curves:
            while len(rungs) <= len(LADDER) and (cap := self.vc * LADDER[len(rungs) - 1]) >= v:
                rungs.append((cap, *self._tangential(cap)))
        return rungs

    def rung(self, i: int) -> tuple[float, float, float]:
        """The ``i``-th rung of :meth:`rungs`, the ones above it made first (the same list)."""
        rungs = self._rungs
        if rungs is None:   # _top() inline (the solver asks for every rung it tries)
            rungs = self._rungs = [(self.vc, self.acc, self.jerk)]
        if i < len(rungs):
            return rungs[i]
        while len(rungs) <= i:
            cap = self.vc * LADDER[len(rungs) - 1]
            rungs.append((cap, *self._tangential(cap)))
        return rungs[i]

    def _top(self) -> list[tuple[float, float, float]]:
        if self._rungs is None:
            self._rungs = [(self.vc, self.acc, self.jerk)]
        return self._rungs

    def reach(self, v: float) -> float:
        """Highest speed at the other end of the group from speed ``v`` at one end (either
        direction: the profiles are symmetric), within the cap."""
        if not self.curves:
            reach = reachable(v, self.length, self.acc, self.jerk)
            return reach if reach < self.vc else self.vc
        if self.jerk == math.inf and v < self.vc and (exact := self._reach_without_jerk(v)) is not None:
            return exact
        # down the ladder one cap at a time, each made only when reached: once a cap is reached
        # within the length, no lower cap can do better; nor can a cap at most the best speed found
        # (a rung gives at most its cap), so the walk stops there before making the rung
        best = 0.0
        rungs = self._rungs
        if rungs is None:   # _top() inline
            rungs = self._rungs = [(self.vc, self.acc, self.jerk)]
        top, length = self.vc, self.length
        i, made = 0, len(rungs)   # made: len(rungs), counted as they are made
        while True:
            if i < made:
                c, a, j = rungs[i]
                if c <= best:
                    break
            else:
                if i > len(LADDER) or (c := top * LADDER[i - 1]) < v or c <= best:
                    break
                a, j = self._tangential(c)
                rungs.append((c, a, j))
                made += 1
            if c < v or a <= 0 or j <= 0:
                break
            r = reachable(v, length, a, j)
            if r >= c:
                if c > best:
                    best = c
                break
            if r > best:
                best = r
            i += 1
        return best if best > 0.0 else min(self.vc, v)

    def _reach_without_jerk(self, v: float) -> float | None:
        """:meth:`reach` with no jerk limit below the cap: the exact speed of
        :func:`~fagorcnc.plan.limits.reach_without_jerk` (the ladder's rungs only come within a rung
        of it: on a G05 zig-zag of 0.05 mm steps, 3 % of speed is 20 % of what a tight curve leaves for
        speed changes); None when the cap itself is reached (the ladder's top rung then)."""
        self._tangential(self.vc)   # makes the terms
        c = reach_without_jerk(self._terms, v, self.length, self._path[0])
        if not c < self.vc:
            return None
        # the profile is later timed below a cap a hair above its top speed: reach with that cap's acceleration
        acc = self._tangential(c * (1.0 + 1e-9))[0]
        if not acc > 0.0:
            return None
        r = reachable(v, self.length, acc, math.inf)
        return r if r < c else c

    def limits_at(self, vc: float) -> tuple[float, float]:
        """The members' tangential limits below the cap ``vc``."""
        if vc >= self.vc or not self.curves:
            return self.acc, self.jerk
        return self._tangential(vc)

    def _tangential(self, cap: float) -> tuple[float, float]:
        """Tangential acceleration and jerk below ``cap``: the limits of every curved member's
        axes together, and the lines' own."""
        terms = self._terms
        if terms is None:   # the terms and the path limits, made once per group (add resets both)
            terms = self._make_terms()
        path = self._path
        if type(terms) is Terms:
            return tangential(terms, cap, path[0], path[1])
        return tangential_arrays(terms, cap, path[0], path[1])

    def _make_terms(self) -> Terms | TermArrays:
        """The curves' terms of :meth:`_tangential` (kept), and the path limits below any cap: the first
        member's and the lines' own."""
        curves = self.curves
        if len(curves) == 1:   # most groups with a curve: one corner curve alone
            terms = curves[0].terms
        elif len(curves) >= ARRAY_CURVES and all(m.lim is curves[0].lim for m in curves):
            pieces = [m.piece for m in curves]
            terms = term_arrays(np.array([p.d1 for p in pieces]), np.array([p.d2 for p in pieces]),
                                np.array([p.d3 for p in pieces]), curves[0].lim)
        else:
            joined = Terms.joined(m.terms for m in curves)
            terms = joined.arrays() if joined.total() > ARRAY_TERMS else joined
        first = self.members[0]
        self._path = (min(first.path_acc or math.inf, self.line_acc), min(first.path_jerk or math.inf, self.line_jerk))
        self._terms = terms
        return terms
