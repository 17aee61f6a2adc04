"""The planner: motion records in, timed segments out (streaming).

    records -> spans (pieces + limits) -> corners (stop / run through / blend)
            -> look-ahead (junction speeds) -> ruckig profiles -> Segment stream

Synchronisation points stop the motion: dwells and the auxiliary functions
that wait for the PLC (M, S, T; seed 002 L5020-L5029).  H functions are sent
without waiting (L5088) and D only selects an offset: they do not stop it.
"""

from __future__ import annotations

import math
from collections import deque
from collections.abc import Iterable, Iterator
from itertools import accumulate, chain, islice
from operator import attrgetter, itemgetter

import numpy as np

from ..config.machine import Machine, load_machine
from ..interp.records import css_feed
from .corner_memo import CornerMemo
from .geometry import ArcPiece, Piece, line_pieces
from .independent import IndependentAxes
from .junctions import MIN_LENGTH, CornerMixin
from .limits import AxisLimits
from .lookahead import backward
from .profile import MICRO, PHASES, Profile, ProfileError, ProfileWindow, Solver
from .segment import PlanningError, Segment
from .span import Event, Group, Span

#: Arcs are planned in parts of at most this sweep (radians): each part's cap and tangential limits
#: come from its derivative bounds, which follow the curve more closely on shorter parts.  With a
#: jerk limit every part junction returns the path acceleration to zero, which costs more than the
#: finer caps gain (R2 circle at F6000: 1.83 s in 30° parts, 1.96 s in 10° parts); without one,
#: nothing is lost at a junction and 10° parts come within 3 % of the time-optimal bound (6.6 %
#: in 30° parts; benchmarks/plan_vs_bound.py).
ARC_PART = math.radians(30.0)
#: A G95 move under G96 (feed following the radius) is planned in parts whose feed changes by at most this
#: ratio, and in at most so many parts.
CSS_STEP = 1.02
CSS_PARTS = 64
ARC_PART_JERK_FREE = math.radians(10.0)
#: Grouping of short spans into one motion: span length, group length (mm) and members at most.
GROUP_SPAN = 2.0
GROUP_LENGTH = 20.0
GROUP_MEMBERS = 64
#: Records taken from a streamed source at a time: a run of blocks interpreted, then planned,
#: keeps each stage's code and data in the processor's caches, where taking them one by one
#: alternates the two (a dry run is 11 to 22 % faster); the records read ahead are a few
#: milliseconds of interpretation, and the look-ahead window holds far more than that anyway.
READ_AHEAD = 1024
#: The end speed's reductions (relative) a span is timed with in turn until ruckig has a profile.
SHRINKS = (0.0, 1e-9, 1e-6, 1e-4, 1e-2)
#: A span's length (a group's members' lengths without a generator).
_LENGTH = attrgetter("length")
#: A record's end point (a run's end points without a generator).
_END = attrgetter("end")
#: The kinds of records that move along a path.
_MOTION = ("linear", "rapid", "arc")


class Planner(CornerMixin):
    """Jerk-limited look-ahead planner for one channel.

    ``jerk=False`` plans with unlimited jerk (trapezoidal speed, used to
    compare against time-optimal bounds); ``keep_profiles`` keeps each
    segment's profile for sampling.
    """

    def __init__(self, machine: Machine | dict | str | None = None, *, jerk: bool = True,
                 keep_profiles: bool = False) -> None:
        self.machine = m = load_machine(machine)
        self.axes = m.axis_names
        self.index = {a: i for i, a in enumerate(self.axes)}
        self._linear = [i for i, a in enumerate(self.axes) if not m.axes[a].rotary]
        self.jerk = jerk
        self._arc_part = ARC_PART if jerk else ARC_PART_JERK_FREE
        self.keep = keep_profiles
        self.config = m.planner
        self.window = max(16, m.planner.lookahead)
        self._limits: dict = {}
        self._last_limits: tuple = (None, None, None)   # the last (dynamics, rapid, limits) asked
        self.solver = Solver()
        self._ahead: deque = deque()             # the corner stage's look-ahead
        self._candidates: dict[int, tuple] = {}  # batched HSC spline curves by the id of their second line
        self._spline_limits: dict[int, tuple] = {}  # their limits by the curve's id (see CornerMixin._batch)
        self._line_blends: dict[tuple[int, int], tuple] = {}  # batched G05 line corners by their directions' ids
        self._arc_blends: dict[tuple[int, int], tuple] = {}   # batched corners at arcs by their spans' ids
        self._corner_memo = CornerMemo()        # the corner curves at arcs already made (plan/corner_memo.py)
        self._spline_used = False
        self._known: list[float] = []           # the last backward pass's limits of the queue's groups
        self._last_end: tuple = (None, None)    # the last record's end and its vector
        self._origin = (0.0,) * len(self.axes)
        self._end_values = itemgetter(*self.axes)   # an end point's values in machine axis order (2 axes or more)
        self.independent = None                 # the independent axes of the last segments() (plan/independent.py)

    # ------------------------------------------------------------ records -> spans
    def _axis_limits(self, dyn, rapid: bool) -> AxisLimits:
        last = self._last_limits
        if dyn is last[0] and rapid is last[1]:   # the blocks of a run share their dynamics object
            return last[2]
        key = (dyn, rapid)
        lim = self._limits.get(key)
        if lim is None:
            axes = self.machine.axes
            linear_slope = dyn is not None and dyn.slope[0] == 0
            # V.G.DYNOVR: one percentage of the dynamics of every axis of the channel (seed 002 L36672)
            k = dyn.dynamic_override / 100.0 if dyn is not None else 1.0
            vel, acc, jerk = [], [], []
            for a in self.axes:
                # the axis's dynamics in its G112 parameter set (machine file axes.X.sets; set 1: its own)
                max_velocity, max_feed, max_acceleration, max_jerk = axes[a].dynamics(
                    dyn.param_set(a) if dyn is not None and dyn.param_sets else 1)
                v = max_velocity if rapid or max_feed <= 0 else min(max_feed, max_velocity)
                vel.append(v / 60.0 * k)
                fa = dyn.acceleration_factor(a, rapid) if dyn is not None else 1.0
                fj = dyn.jerk_factor(a, rapid) if dyn is not None else 1.0
                acc.append(max_acceleration * fa * k)
                jerk.append(math.inf if (not self.jerk or linear_slope) else max_jerk * fj * k)
            lim = self._limits[key] = AxisLimits(tuple(vel), tuple(acc), tuple(jerk))
        self._last_limits = (dyn, rapid, lim)
        return lim

    def _vector(self, pos: dict) -> np.ndarray:
        """A position in machine axis order (axes it does not name at 0)."""
        return np.fromiter(map(pos.get, self.axes, self._origin), float, len(self.axes))

    def _pieces(self, motion: list) -> list[Piece | None]:
        """The pieces of a run of motion records (None: not longer than :data:`MIN_LENGTH`, nothing moves).
        Their end points in machine axis order are read as one array, and a block that starts where the one
        before ended starts at that one's end (the same vector); the lines are made together
        (:func:`~.geometry.line_pieces`)."""
        n, dim = len(motion), len(self.axes)
        if not n:
            return []
        ends = None
        if dim > 1:
            try:   # every end names every axis (the interpreter's records): one getter, no default per axis
                ends = np.fromiter(chain.from_iterable(map(self._end_values, map(_END, motion))), float, n * dim)
            except KeyError:
                ends = None
        if ends is None:
            ends = np.array([list(map(rec.end.get, self.axes, self._origin)) for rec in motion], float)
        ends = ends.reshape(n, dim)
        end_points = list(ends)   # a view a row: each piece's end, and the start of the one after it
        rows = np.empty_like(ends)   # the start points as rows
        rows[1:] = ends[:-1]
        last, point = self._last_end
        if point is not None:
            rows[0] = point
        starts = []
        for i, rec in enumerate(motion):
            start = rec.start
            if not (start is last or start == last):
                point = rows[i] = self._vector(start)
            starts.append(point)
            last, point = rec.end, end_points[i]
        self._last_end = last, point
        lines = [i for i, rec in enumerate(motion) if rec.kind != "arc"]
        if len(lines) == n:
            return line_pieces(starts, end_points, rows, ends, MIN_LENGTH)
        pieces: list[Piece | None] = [None] * n
        if lines:
            made = line_pieces([starts[i] for i in lines], [end_points[i] for i in lines], rows[lines], ends[lines],
                               MIN_LENGTH)
            for i, piece in zip(lines, made):  # noqa: B905 (a piece a line)
                pieces[i] = piece
        index = self.index
        for i, rec in enumerate(motion):
            if rec.kind == "arc":
                a, o = rec.plane[0], rec.plane[1]
                piece = ArcPiece(starts[i], end_points[i], index[a], index[o], (rec.center[a], rec.center[o]),
                                 math.radians(rec.sweep))
                if piece.length > MIN_LENGTH:
                    pieces[i] = piece
        return pieces

    def _span(self, rec, piece: Piece | None) -> Span | None:
        """The span of a motion record whose piece :meth:`_pieces` made (None: nothing moves)."""
        if piece is None:
            return None
        cfg = self.config
        dyn = rec.dyn
        rapid = rec.rapid   # G00, or an arc inserted before one (no feed: run at rapid, seed 002 L8460)
        if rapid:   # the channel's rapid is a linear speed: a move of rotary axes alone is not held to it
            linear = self.machine.rapid_feed > 0 and (piece.curved or any(map(piece.ul.__getitem__, self._linear)))
            feed = self.machine.rapid_feed / 60.0 if linear else math.inf
            override = min(cfg.rapid_override, 100.0)
            if override <= 0:   # seed 002 L20355: the 0 % position always holds the axes, G00 included
                raise PlanningError("the rapid override is 0 %: the rapid move never ends", rec.src.line, rec)
            if override < 100.0:
                # the override scales the rapid as the axes run it: without a channel rapid that is the
                # speed at which the first axis reaches its maximum (seed 002 L5969), not an infinite feed
                feed = min(feed, self._rapid_speed(piece, rec)) * (override / 100.0)
        else:
            feed = rec.feed / 60.0 if rec.feed else math.inf
            if not (dyn is not None and dyn.override_locked):
                feed *= cfg.feed_override / 100.0
        if feed <= 0:
            raise PlanningError("the feed override is 0 %: nothing moves", rec.src.line, rec)
        # an arc's limits wait until the corners at its ends are decided (``later``: settled in
        # _corners; positional, as keywords cost a little on every block)
        # the program's V.G.MAXACCEL/MAXJERK replace the machine parameters until M30/reset (seed 002 L36469)
        path = dyn.path_limits if dyn is not None and dyn.path_limits is not None else \
            (cfg.max_path_acceleration, cfg.max_path_jerk)
        last = self._last_limits   # the limits of the block before when it asked the same (inline: every block)
        lim = last[2] if dyn is last[0] and rapid is last[1] else self._axis_limits(dyn, rapid)
        if not piece.curved:
            return Span.of_line(piece, rec, feed, lim, rapid, dyn, path[0], path[1])
        return Span(piece, rec, feed, lim, rapid, dyn, path[0], path[1], False, True)

    def _rapid_speed(self, piece: Piece, rec) -> float:
        """Path speed (mm/s) of a rapid at which its fastest axis reaches its max_velocity: on a line
        ``min(v_i / |u_i|)``; on an arc (at rapid before a G00) the slower of its plane's axes."""
        axes = self.machine.axes
        if piece.curved:
            return min(axes[a].max_velocity for a in rec.plane[:2]) / 60.0
        return min((axes[a].max_velocity / 60.0 / abs(u) for a, u in zip(self.axes, piece.ul, strict=True) if u),
                   default=math.inf)

    def _spans(self, records: Iterable) -> Iterator[Span | Event]:
        for run in _read_ahead(records):
            pieces = iter(self._pieces([rec for rec in run if rec.kind in _MOTION]))
            for rec in run:
                kind = rec.kind
                if kind in _MOTION:
                    span = self._span(rec, next(pieces))
                    if span is None:
                        continue
                    if getattr(rec, "css", None) is not None and not span.rapid:   # G95 under G96 (feed follows r)
                        yield from self._css_parts(span, rec)
                        continue
                    parts = math.ceil(abs(span.piece.w) * span.length / self._arc_part) if kind == "arc" else 1
                    if parts <= 1:
                        yield span
                        continue
                    # long arcs in parts: each part picks its own cap (more tangential budget where slow)
                    yield from span.parts([span.length * i / parts for i in range(parts + 1)])
                elif kind == "dwell":
                    yield Event(rec, rec.seconds)
                elif kind == "aux":
                    yield Event(rec, 0.0)

    def _css_parts(self, span: Span, rec) -> Iterator[Span]:
        """A G95 move under G96 in parts, each capped at the lowest feed the spindle gives over it (seed 002
        L5406-L5464: the speed follows the radius, and F mm/rev with it): never above the real feed, and
        where the radius changes monotonically over a part at most :data:`CSS_STEP` below it (the
        :data:`CSS_PARTS`-th root of the move's whole feed ratio when that is larger: 3.6 % for a facing
        move from r = 50 to the G192 radius 5.3)."""
        css, mf = rec.css, self.machine.max_feed
        i = self.index[css[3]]
        probe = span.piece.derivatives(np.linspace(0.0, span.length, 33))[0][:, i]
        feeds = [css_feed(css, float(x), mf) for x in probe]
        low, high = min(feeds), max(feeds)
        n = CSS_PARTS if not math.isfinite(high) or low <= 0 else math.ceil(math.log(high / low) / math.log(CSS_STEP))
        if span.piece.curved:
            n = max(n, math.ceil(abs(span.piece.w) * span.length / ARC_PART))
        n = max(1, min(n, CSS_PARTS, int(span.length / 0.5)))
        factor = span.feed * 60.0 / rec.feed if rec.feed else 1.0   # the feed override (or 100 %)
        cuts = [span.length * k / n for k in range(n + 1)]
        mids = [(cuts[k] + cuts[k + 1]) / 2 for k in range(n)]
        at = span.piece.derivatives(np.array(cuts + mids))[0][:, i].tolist()
        for k in range(n):
            feed = min(css_feed(css, at[k], mf), css_feed(css, at[k + 1], mf), css_feed(css, at[n + 1 + k], mf))
            yield span.part(cuts[k], cuts[k + 1], feed / 60.0 * factor, later=span.piece.curved)

    # ------------------------------------------------------------ look-ahead and timing
    def segments(self, records: Iterable) -> Iterator[Segment]:
        """Plan ``records`` (motion records in execution order); yields timed segments.  #MOVE positionings
        run alongside on their axes' own interpolators (:mod:`.independent`: ``self.independent`` holds
        them and their notes)."""
        self.independent = axes = IndependentAxes(self)
        return axes.run(self.timed(axes.general(records)))

    def timed(self, records: Iterable) -> Iterator[Segment]:
        """The general interpolator: ``records`` timed one after the other; yields timed segments."""
        queue: list[Group] = []
        self._known = []
        after: dict[int, list[Event]] = {}   # events that follow a span without a stop
        clock = [0.0]
        v = 0.0
        group: Group | None = None
        last: Span | None = None
        solver, keep = self.solver, self.keep
        for item in self._corners(self._spans(records)):
            if isinstance(item, Event):
                if last is not None and not last.stop_after:
                    after.setdefault(id(last), []).append(item)
                    continue
                if group is not None:
                    queue.append(group)
                    group = None
                v = yield from self._commit(queue, len(queue), v, clock, after)
                yield Segment(item.kind, clock[0], item.duration, item.line, item.record)
                clock[0] += item.duration
                continue
            if item.stale:   # settled in _corners: a guard, so that no span is timed without its limits
                item.settle()
            last = item
            if group is None and item.stop_after and not queue and v == 0.0 and not item.piece.curved:
                # a line alone between two stops (G50, G07, a rapid): what _commit would make of a
                # queue of its group alone (from rest to rest), without the group and the look-ahead
                try:
                    duration, profile = solver.rest_to_rest(item, keep)
                except ProfileError:
                    pass   # the general path says why (PlanningError)
                else:
                    yield Segment("motion", clock[0], duration, item.line, item.record, item.piece, 0.0, 0.0,
                                  profile, item.blend)
                    clock[0] += duration
                    if after:
                        yield from self._after(item, after, clock)
                    continue
            if group is not None and _joins(group, item):
                group.add(item)
            else:
                if group is not None:
                    queue.append(group)
                group = Group(item)
            if item.stop_after:
                queue.append(group)
                group = None
                v = yield from self._commit(queue, len(queue), v, clock, after)
            elif len(queue) >= self.window:
                v = yield from self._commit(queue, self.window // 2, v, clock, after)
        if group is not None:
            queue.append(group)
        yield from self._commit(queue, len(queue), v, clock, after)

    def _commit(self, queue: list[Group], k: int, v: float, clock: list, after: dict) -> Iterator[Segment]:
        """Time the first ``k`` groups of the queue starting at speed ``v``; returns the speed after them."""
        if not queue:
            return v
        limit = backward(queue, 0.0, self._known)
        self._known = limit[k:]
        n = len(queue)
        solver = self.solver
        for i in range(k):
            g = queue[i]
            if g.stop_after:
                # min(reach, 0): a reachable speed is never below 0, nor raises where the backward pass
                # (which asked this group already) did not
                v1 = 0.0
            else:
                nxt = limit[i + 1] if i + 1 < n else 0.0
                if v >= nxt and (g.jerk != math.inf or not g.curves):
                    # min(reach(v), nxt) is nxt without the reach: the backward pass keeps nxt within the
                    # group's cap, and a reach is never below min(v, cap) but on curves without a jerk
                    # limit (whose exact reach, Group._reach_without_jerk, can be below v)
                    v1 = nxt
                else:
                    v1 = g.reach(v)
                    if nxt < v1:
                        v1 = nxt
            members = g.members
            # a group of several members needs its profile to cut their segments from: as lists of phases
            # unless the profiles are kept (no arrays made)
            keep = True if self.keep else PHASES if len(members) > 1 else False
            if not g.curves and g.length >= MICRO:   # lines: their single cap, without _time's general steps
                first = 0
                try:
                    duration, profile = solver.line(g, v, v1, keep)
                except ProfileError:
                    duration = None
            else:   # _time's first step (its end speed v1 * (1 - 0.0) is v1) without its loop
                first = 1
                try:
                    duration, _vc, profile = solver.time(g, v, v1, keep)
                except ProfileError:
                    duration = None
            if duration is None:   # or the general steps, which also lower the end speed if ruckig needs it
                duration, profile, v1 = self._time(g, v, v1, keep, first)
            if len(members) == 1:
                s = members[0]
                yield Segment("motion", clock[0], duration, s.line, s.record, s.piece, v, v1,
                              profile if self.keep else None, s.blend)
                clock[0] += duration
                if after:
                    yield from self._after(s, after, clock)
            else:
                yield from self._split(g, profile, v1, clock, after)
            v = v1
        del queue[:k]
        return v

    def _split(self, group: Group, profile: Profile, v1: float, clock: list, after: dict) -> list[Segment]:
        """The members' segments of a group, each followed by the events after it: the times where the
        group profile crosses each member's start.  A list (at most :data:`GROUP_MEMBERS` segments and
        their events), handed on by the caller's ``yield from``: no generator of its own to resume for
        every segment."""
        members = group.members
        bounds = list(accumulate(map(_LENGTH, members[:-1]), initial=0.0))
        times, speeds = profile.crossings(bounds[1:])
        t = [0.0, *times, profile.duration]
        speeds = [float(profile.v[0]), *speeds, v1]
        bounds.append(group.length)
        start = clock[0]
        keep = self.keep
        out = []
        for i, m in enumerate(members):
            duration = t[i + 1] - t[i]
            # the member's window of the group profile only when profiles are kept (no object per member else)
            window = ProfileWindow(profile, t[i], bounds[i], duration) if keep else None
            out.append(Segment("motion", start + t[i], duration, m.line, m.record, m.piece, speeds[i], speeds[i + 1],
                               window, m.blend))
            clock[0] = start + t[i + 1]
            if after:
                out += self._after(m, after, clock)
        return out

    @staticmethod
    def _after(span: Span, after: dict, clock: list) -> Iterator[Segment]:
        for ev in after.pop(id(span), ()):
            yield Segment(ev.kind, clock[0], ev.duration, ev.line, ev.record)
            clock[0] += ev.duration

    def _time(self, span, v0: float, v1: float, keep: bool | str,
              first: int = 0) -> tuple[float, Profile | None, float]:
        """(duration, profile, end speed) of ``span`` from ``v0``: at ``v1``, or the end speed a little
        lower when ruckig needs it (the :data:`SHRINKS` from the ``first``-th on)."""
        for shrink in SHRINKS[first:]:
            target = v1 * (1.0 - shrink)
            try:
                duration, _vc, profile = self.solver.time(span, v0, target, keep)
                return duration, profile, target
            except ProfileError:
                continue
        raise PlanningError(f"no jerk-limited profile for a {span.length:.6g} mm move from {v0:.6g} to "
                            f"{v1:.6g} mm/s", span.line, span.record)


def _read_ahead(records: Iterable) -> Iterable[list]:
    """``records`` in runs of :data:`READ_AHEAD`, taken from a streamed source a run at a time."""
    if isinstance(records, (list, tuple)):
        return (records[i:i + READ_AHEAD] for i in range(0, len(records), READ_AHEAD))
    return _chunks(iter(records))


def _chunks(source: Iterator) -> Iterator[list]:
    while chunk := list(islice(source, READ_AHEAD)):
        yield chunk


def _joins(group: Group, span: Span) -> bool:
    """Whether ``span`` continues ``group`` as one motion: short spans with caps within 30 %."""
    members = group.members
    if members[-1].stop_after or len(members) >= GROUP_MEMBERS or group.length + span.length > GROUP_LENGTH:
        return False
    vc = span.vc
    # both the span and the group's first member short: crossed (at its cap) faster than its acceleration
    # can rise and fall again, returning to zero acceleration at both of its ends would dominate its
    # motion (inline: this runs for every span planned after another)
    length = span.length
    if not (vc <= 1.3 * group.vc and length <= GROUP_SPAN and length < vc * span.acc / span.jerk):
        return False
    first = members[0]
    if not (first.length <= GROUP_SPAN and first.length < first.vc * first.acc / first.jerk):
        return False
    top = vc * 1.3
    for m in members[-4:]:  # noqa: SIM110 (top >= the highest of the last four caps; no generator per span)
        if m.vc > top:
            return False
    return True


def plan(records: Iterable, machine: Machine | dict | str | None = None, *, jerk: bool = True,
         keep_profiles: bool = False) -> Iterator[Segment]:
    """Plan motion records; a generator of :class:`Segment` (see :class:`Planner`)."""
    return Planner(machine, jerk=jerk, keep_profiles=keep_profiles).segments(records)
