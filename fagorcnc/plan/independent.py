"""Independent axes: each #MOVE runs on its axis's own interpolator, alongside the general motion
(seed 002 ch. 21.1.19, L16615-L16678).

The manual: every axis has an independent interpolator with its own position count (L16618-L16620);
an independent and a general move may run at the same time and the axis follows the sum of both
interpolators (L16622-L16623); the CNC stores at most two independent instructions per axis, and a
further one makes the part program wait (L16625-L16627); the blocks of the independent axes stop the
interpolation, not the block preparation, so no two general blocks are joined across one
(L16672-L16674).

How the planner does it (:class:`IndependentAxes`, two small filters around the general planner):

* :meth:`IndependentAxes.general` hands the general planner each #MOVE as a dwell of no time where the
  program reaches it: the general motion stops there (L16674) and its segment gives the instant the
  instruction is issued.
* :meth:`IndependentAxes.run` passes the general segments on, and at each run of #MOVEs the program
  reaches at one instant (a *burst*) plans every axis's #MOVEs of the burst as one chain, on that
  axis's limits and with their links (PRESENT / NEXT / NULL / WAITINPOS, plan/links.py), starting at
  that instant - or, when the axis still runs an earlier positioning, when that one ends (from rest:
  the remaining construction, note INT230).  Its segments are :class:`IndependentSegment` objects on
  the same clock as the general ones: they overlap them in time.
* The program waits (a dwell segment in the general timeline, every later general segment shifted)
  where the manual says so: at a third instruction for an axis that already holds two (the one
  running counts: "stores at most two", L16625); at ``#SYNC POS`` until the independent axes have
  stopped (the position it takes must be the end of the positioning, L16657-L16665; note INT234); and
  at the end of the program until the last independent axis stops, so the cycle time is when both
  are done (note INT233: the manual does not say whether M30 waits for them).

WAITINPOS ("at rest, and in position before the next block", L16741) is read as the next block of the
axis's own interpolator, as its ICORNER counterpart G07 is for the general one (L16750, L7993): the
in-position wait is on the axis's timeline, the program does not wait for it.

The sum.  A general block that moves an axis a #MOVE moved is refused until ``#SYNC POS``
(INT232, interp/independent.py and :meth:`IndependentAxes.general`), and ``#SYNC POS`` waits for the
independent motion to end: while an axis runs independently the general interpolator holds it, so the
sum of both is the independent motion, and the axis's limits (velocity, acceleration, jerk) and soft
limits are those the independent plan keeps.  The general records after a #MOVE already carry the
axis at its target (the interpreter's position after the positioning): the sampler
(:func:`~fagorcnc.plan.trajectory.sample`) takes the axis from the independent segments over their
time, from the general ones elsewhere.
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator
from dataclasses import dataclass
from itertools import chain

from ..diagnostics import Diagnostic
from ..interp.records import Dwell, IndependentMove, IndependentSync
from .segment import PlanningError, Segment

#: Record kinds the general interpolator moves axes with.
MOTION = frozenset({"linear", "rapid", "arc"})
#: Axis changes below this (mm, degrees) are no motion.
STILL = 1e-9
#: The instructions an axis's independent interpolator stores; a further one makes the program wait (L16625).
STORED = 2


@dataclass(slots=True)
class IndependentSegment(Segment):
    """A timed part of a #MOVE positioning of ``axis`` on its own interpolator: on the general segments'
    clock, overlapping them in time (``kind`` ``"motion"``, or ``"dwell"`` for its in-position wait)."""

    axis: str = ""


class IndependentAxisError(PlanningError):
    """A general move of an axis a #MOVE moved, before ``#SYNC POS`` (diagnostic INT232)."""

    code = "INT232"


class IndependentAxes:
    """The independent interpolators of one planned run (see the module's docstring).

    ``end`` is when the last independent motion ends (s); :meth:`diagnostics` the notes of the run.
    """

    def __init__(self, planner) -> None:
        self._planner = planner
        self._chains = None                       # the planner of the independent chains, made on first use
        self._markers: dict[int, tuple] = {}      # id(dwell standing for a #MOVE) -> (that dwell, the #MOVE)
        self._moved: dict[str, IndependentMove] = {}   # axes a #MOVE moved since #SYNC POS (record order)
        self._issued: dict[str, list[list]] = {}  # axis -> [start, end, #MOVE] of its instructions, in time order
        self.end = 0.0
        self._last: IndependentMove | None = None   # the #MOVE that ends at ``end``
        self._notes: list[tuple[str, str, object]] = []
        self._noted: set[str] = set()

    # ------------------------------------------------------------ records
    def general(self, records: Iterable) -> Iterator:
        """The records for the general interpolator: each #MOVE as a dwell of no time where the program reaches
        it; a general move of an axis a #MOVE moved, before ``#SYNC POS``, raises INT232."""
        markers, moved = self._markers, self._moved
        for rec in records:
            t = type(rec)
            if t is IndependentMove:
                marker = Dwell("dwell", 0.0, rec.start, rec.src)
                markers[id(marker)] = (marker, rec)
                moved[rec.axis] = rec
                yield marker
                continue
            if moved:
                if t is IndependentSync:
                    moved.clear()
                elif rec.kind in MOTION:
                    self._check(rec)
            yield rec

    def _check(self, rec) -> None:
        for axis, move in self._moved.items():
            s, e = rec.start.get(axis), rec.end.get(axis)
            if s is None or e is None:
                continue
            if abs(e - s) > STILL or (rec.kind == "arc" and axis in rec.plane[:2]):
                raise IndependentAxisError(
                    f"this block moves {axis}, which the #MOVE of line {move.src.line} positioned: the general "
                    f"interpolator does not count that move until #SYNC POS and the machine adds both "
                    f"(seed 002 L16618-L16623, L16657-L16665); program #SYNC POS before moving {axis}",
                    rec.src.line, rec)

    # ------------------------------------------------------------ segments
    def run(self, segments: Iterable[Segment]) -> Iterator[Segment]:
        """The general segments with the independent ones among them, and the program's waits."""
        markers = self._markers
        source = iter(segments)
        for seg in source:   # until a #MOVE is read, the general segments as they are
            if markers:
                yield from self._alongside(chain((seg,), source))
                return
            yield seg

    def _alongside(self, segments: Iterator[Segment]) -> Iterator[Segment]:
        markers = self._markers
        shift = 0.0            # the program's waits so far: added to every later general segment
        burst: list[tuple[Segment, IndependentMove]] = []
        clock = 0.0            # the end of the general timeline so far
        line = 0
        for seg in segments:
            if markers and seg.kind == "dwell":
                hit = markers.pop(id(seg.record), None)
                if hit is not None:
                    burst.append((seg, hit[1]))
                    continue
            if burst:
                shift, clock = yield from self._burst(burst, shift)
                burst = []
            if shift:
                seg.t0 += shift
            if type(seg.record) is IndependentSync and self.end > seg.t0:
                wait = self.end - seg.t0
                yield Segment("dwell", seg.t0, wait, seg.line, seg.record)
                self._note("INT234", f"#SYNC POS: the program waits {wait:.3f} s here until the independent "
                           f"axes stop (the #MOVE of line {self._last.src.line} ends last), so that the position "
                           "the general interpolator takes is the end of the positioning (L16657-L16665; the "
                           "manual does not say what it takes on a moving axis)", seg.record, once=False)
                shift += wait
                seg.t0 += wait
            clock = seg.t0 + seg.duration
            line = seg.line
            yield seg
        if burst:
            shift, clock = yield from self._burst(burst, shift)
            line = burst[-1][0].line
        if self.end > clock and self._last is not None:
            self._note("INT233", f"the program's blocks end at {clock:.3f} s and the #MOVE of "
                       f"{self._last.axis} (line {self._last.src.line}) runs until {self.end:.3f} s: the cycle time "
                       "counts until it stops (the manual does not say whether the program end waits for an "
                       "independent axis, L16615-L16678)", self._last)
            yield Segment("dwell", clock, self.end - clock, line, None)

    def _burst(self, burst: list, shift: float):
        """The #MOVEs the program reaches at one instant: each axis's moves planned and yielded, and the
        program's wait at each #MOVE (a dwell segment, of no time when it does not wait); returns the new shift
        and the end of the general timeline."""
        t = burst[0][0].t0 + shift
        chains: dict[str, list[IndependentMove]] = {}
        for _seg, move in burst:
            chains.setdefault(move.axis, []).append(move)
        planned: dict[int, list[IndependentSegment]] = {id(m): [] for _s, m in burst}   # by #MOVE
        where: dict[int, int] = {}   # id(#MOVE) -> its index in its axis's instructions
        for axis, moves in chains.items():
            issued = self._issued.setdefault(axis, [])
            while len(issued) > 1 and issued[0][1] <= t:   # ended: no longer stored (the last one is kept)
                del issued[0]
            begin = t
            if issued and issued[-1][1] > t:   # the axis still runs an earlier positioning
                begin = issued[-1][1]
                self._note("INT230", f"#MOVE of {axis} reached while the axis still runs the positioning of "
                           f"line {issued[-1][2].src.line}: offline it starts when that one has stopped; the "
                           "machine may join the two without stopping (L16625, L16722-L16740)", moves[0])
            first = len(issued)
            times = {id(m): [None, None] for m in moves}
            current = moves[0]
            for seg in self._chain_planner().timed(moves):
                rec = seg.record
                if id(rec) in times:
                    current = rec
                span = times[id(current)]
                t0 = seg.t0 + begin
                if span[0] is None:
                    span[0] = t0
                span[1] = t0 + seg.duration
                planned[id(current)].append(IndependentSegment(seg.kind, t0, seg.duration, seg.line, rec, seg.piece,
                                                               seg.v0, seg.v1, seg.profile, seg.blend, axis))
            at = begin
            for i, move in enumerate(moves):   # a positioning of no length takes no time
                start, end = times[id(move)]
                start = at if start is None else start
                at = start if end is None else end
                issued.append([start, at, move])
                where[id(move)] = first + i
            if at >= self.end:
                self.end, self._last = at, moves[-1]
        g = t
        for seg, move in burst:
            issued = self._issued[move.axis]
            stored = [e for _s, e, _m in issued[:where[id(move)]] if e > g]
            wait = stored[-2] - g if len(stored) >= STORED else 0.0   # L16625: the program waits
            yield Segment("dwell", g, wait, seg.line, move)
            g += wait
        for _seg, move in burst:   # in the program's order, each #MOVE's segments in time order
            yield from planned[id(move)]
        return shift + (g - t), g

    def _chain_planner(self):
        if self._chains is None:
            p = self._planner
            self._chains = type(p)(p.machine, jerk=p.jerk, keep_profiles=p.keep)
        return self._chains

    # ------------------------------------------------------------ notes
    def _note(self, code: str, message: str, record, once: bool = True) -> None:
        if once:
            if code in self._noted:
                return
            self._noted.add(code)
        self._notes.append((code, message, record))

    def diagnostics(self, file: str) -> list[Diagnostic]:
        """The notes of the run (INT230, INT233, INT234), at the blocks they concern."""
        out = []
        for code, message, rec in self._notes:
            src = getattr(rec, "src", None)
            out.append(Diagnostic(src.file if src is not None else file, src.line if src is not None else 1, 1,
                                  code, "info", message))
        return out
