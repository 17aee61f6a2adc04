"""Planner segments -> InterpCNC commands.

Two steps, so that a segment interrupted by a fault can be resumed:

1. :func:`segment_moves` turns a motion segment into geometry only, a list
   of :class:`Move` (straight moves, or XY arcs of at most 180 degrees), in
   machine coordinates.  It depends on nothing but the segment.
2. :class:`Encoder` turns moves into command words.  It remembers the last
   target and feed sent, because a 1002 move only carries the axes that
   change (L902), a 1003 arc's I/J are relative to its start point and 1001
   is only sent when the feed changes.

Rules (the issue's, documented once here):

* rapid -> 1002 with bit 6; linear -> 1001 when the feed changes, then 1002.
* An arc in the XY plane with no motion on other axes, not a corner blend
  and with equal start and end radii -> 1003, split into parts of at most
  180 degrees (a 360-degree arc has start = end, which I/J alone cannot tell
  from a null arc once rounded to single precision).
* Any other arc (other planes, helices, spirals) and every corner blend ->
  1002 chords within ``tolerance`` (mm) of the curve.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...plan import Segment
from . import protocol as proto

MAX_CHORDS = 20000          # per segment, a guard against absurd tolerances


@dataclass(frozen=True)
class Move:
    """One motion command's geometry (machine coordinates, machine axis order).

    ``center`` (XY, absolute) is set for arcs, with ``xy`` the indices of the
    machine axes sent as card X and Y and ``ccw`` the direction.  ``feed`` is
    mm/min, ``None`` for rapids.
    """

    start: np.ndarray
    end: np.ndarray
    rapid: bool = False
    feed: float | None = None
    center: tuple[float, float] | None = None
    ccw: bool = False
    xy: tuple[int, int] | None = None

    @property
    def is_arc(self) -> bool:
        return self.center is not None


class TranslationError(ValueError):
    """A segment cannot be expressed with the card's commands (message names the line)."""


def segment_moves(segment: Segment, xy: tuple[int, int] | None, tolerance: float,
                  rapid_feed: float | None = None) -> list[Move]:
    """The moves of one motion segment; ``xy`` = indices of the machine axes sent as card X and Y (or None).

    An arc run at rapid (one inserted before a G00, with no feed) goes as rapid chords, or as an XY
    arc at ``rapid_feed`` (mm/min): 1003 has no rapid bit and follows the feed of 1001."""
    piece, record = segment.piece, segment.record
    rapid = bool(getattr(record, "rapid", False))
    feed = None if rapid else getattr(record, "feed", None)
    if not rapid and not (feed and feed > 0):
        raise TranslationError(f"line {segment.line}: a feed move without a feed (F) cannot be sent to the card")
    start = np.asarray(piece.start, dtype=float)
    end = np.asarray(piece.end, dtype=float)
    if not piece.curved:
        return [Move(start, end, rapid, feed)]
    if not segment.blend and xy is not None and _is_xy_arc(piece, xy, tolerance) and (not rapid or rapid_feed):
        return _arc_moves(piece, xy, rapid_feed if rapid else feed)
    return [Move(a, b, rapid, feed) for a, b in _chords(piece, tolerance)]


def _is_xy_arc(piece, xy: tuple[int, int], tolerance: float) -> bool:
    if not hasattr(piece, "ia") or {piece.ia, piece.io} != set(xy):
        return False
    if float(np.abs(piece.lin).max(initial=0.0)) * piece.length > 1e-9:   # helix: other axes move
        return False
    spiral = abs(piece.dr) * piece.length
    return spiral <= min(tolerance, 1e-3)


def _arc_moves(piece, xy: tuple[int, int], feed: float | None) -> list[Move]:
    ix, iy = xy
    sweep = piece.w * piece.length                       # signed, in the piece's (ia, io) frame
    if (piece.ia, piece.io) == (ix, iy):
        cx, cy = piece.center
    else:                                                # plane given as (Y, X): mirror the sense
        cy, cx = piece.center
        sweep = -sweep
    ccw = sweep > 0
    parts = max(1, math.ceil(abs(sweep) / math.pi - 1e-9))
    start = np.asarray(piece.start, dtype=float)
    r0 = math.hypot(start[ix] - cx, start[iy] - cy)
    r1 = math.hypot(piece.end[ix] - cx, piece.end[iy] - cy)
    th0 = math.atan2(start[iy] - cy, start[ix] - cx)
    moves, prev = [], start
    for k in range(1, parts + 1):
        if k == parts:
            q = np.asarray(piece.end, dtype=float)
        else:
            th = th0 + sweep * k / parts
            r = r0 + (r1 - r0) * k / parts
            q = prev.copy()
            q[ix], q[iy] = cx + r * math.cos(th), cy + r * math.sin(th)
        moves.append(Move(prev, q, False, feed, (cx, cy), ccw, xy))
        prev = q
    return moves


def chord_count(piece, tolerance: float) -> int:
    """Number of equal chords keeping within ``tolerance`` of the curve."""
    length = piece.length
    if length <= 0:
        return 1
    if hasattr(piece, "r0"):                             # arc or helix: sagitta r(1 - cos(dθ/2))
        r = max(piece.r0, piece.r0 + piece.dr * length)
        sweep = abs(piece.w * length)
        dtheta = 2.0 * math.acos(max(-1.0, 1.0 - tolerance / r)) if r > 0 else math.pi
        n = math.ceil(sweep / dtheta) if dtheta > 0 else MAX_CHORDS
    else:                                                # curvature bound: sagitta ~ k h^2 / 8
        kmax = float(np.linalg.norm(piece.d2))
        n = math.ceil(length / math.sqrt(8.0 * tolerance / kmax)) if 0 < kmax < math.inf else \
            math.ceil(length / max(10 * tolerance, 0.01))
    return min(max(1, n), MAX_CHORDS)


def _chords(piece, tolerance: float) -> list[tuple[np.ndarray, np.ndarray]]:
    n = chord_count(piece, tolerance)
    s = np.linspace(0.0, piece.length, n + 1)[1:]
    q, _, _, _ = piece.derivatives(s)
    q = np.array(q, dtype=float)
    q[-1] = piece.end
    out, prev = [], np.asarray(piece.start, dtype=float)
    for p in q:
        out.append((prev, p))
        prev = p
    return out


class Encoder:
    """Moves -> command words, remembering the last target and feed sent.

    ``axes`` are the machine axis names (the order of the move arrays) and
    ``card_axes`` the card letter each is sent as.  After a stop, a jog or a
    homing the card's state is not known: :meth:`reset` makes the next move
    carry every axis and the next feed move repeat 1001.
    """

    def __init__(self, axes: list[str], card_axes: dict[str, str]) -> None:
        self.axes = list(axes)
        self.card = [card_axes[a] for a in self.axes]
        self.last: list[float] | None = None     # single-precision targets last sent, machine order
        self.feed: float | None = None
        self.at_start = False                    # after a reset: the card stands at the next move's start

    def reset(self, at_start: bool = False) -> None:
        """Forget what the card was sent.  ``at_start``: the card is known to stand where the next move
        starts (a resumed move starts at the position read back); otherwise an arc coming first is
        preceded by a line to its start, since 1003 takes its centre relative to where the card is."""
        self.last = None
        self.feed = None
        self.at_start = at_start

    def encode(self, moves: list[Move]) -> list[proto.Words]:
        out: list[proto.Words] = []
        for m in moves:
            out += self._arc(m) if m.is_arc else self._line(m)
        return out

    def _changed(self, end: np.ndarray) -> dict[int, float]:
        target = [proto.float32(float(v)) for v in end]
        if self.last is None:
            return dict(enumerate(target))
        return {i: v for i, v in enumerate(target) if v != self.last[i]}

    def _commit(self, changed: dict[int, float], end: np.ndarray) -> None:
        if self.last is None:
            self.last = [proto.float32(float(v)) for v in end]
        for i, v in changed.items():
            self.last[i] = v

    def _feed(self, feed: float | None) -> list[proto.Words]:
        if feed is None or proto.float32(feed) == self.feed:
            return []
        self.feed = proto.float32(feed)
        return [proto.encode_feed(feed)]

    def _line(self, m: Move) -> list[proto.Words]:
        changed = self._changed(m.end)
        if not changed:
            return []
        out = [] if m.rapid else self._feed(m.feed)
        out.append(proto.encode_line({self.card[i]: v for i, v in changed.items()}, rapid=m.rapid))
        self._commit(changed, m.end)
        return out

    def _arc(self, m: Move) -> list[proto.Words]:
        ix, iy = self.card.index("X"), self.card.index("Y")
        out = self._feed(m.feed)
        if self.last is None:
            if self.at_start:            # resumed: the card stands at the move's start (read back)
                self.last = [proto.float32(float(v)) for v in m.start]
            else:                        # position unknown (a new stream, a jog, a homing): go there first
                start = self._changed(m.start)
                out.append(proto.encode_line({self.card[i]: v for i, v in start.items()}))
                self._commit(start, m.start)
        other = {i: v for i, v in self._changed(m.start).items() if i not in (ix, iy)}
        if other:                        # the card's arc moves X and Y only: bring other axes there first
            out.append(proto.encode_line({self.card[i]: v for i, v in other.items()}))
            self._commit(other, m.start)
        changed = self._changed(m.end)
        if not changed:
            return out
        # I/J relative to the start as the card knows it: the last target sent
        sx, sy = self.last[ix], self.last[iy]
        cx, cy = m.center
        x, y = proto.float32(float(m.end[ix])), proto.float32(float(m.end[iy]))
        out.append(proto.encode_arc_xy(x, y, cx - sx, cy - sy, ccw=m.ccw))
        self._commit(changed, m.end)
        return out


def remaining_moves(moves: list[Move], pos: np.ndarray, end_tol: np.ndarray, path_tol: float) -> list[Move] | None:
    """What is left of ``moves`` (the first one under way) for a machine at ``pos``.

    [] when ``pos`` is at the end of the first move and no other follows;
    None when ``pos`` is not on the first move's path.
    """
    first = moves[0]
    if np.all(np.abs(pos - first.end) <= end_tol):
        return list(moves[1:])
    if path_distance(first, pos) > path_tol:
        return None
    return [Move(pos.copy(), first.end, first.rapid, first.feed, first.center, first.ccw, first.xy), *moves[1:]]


def path_distance(m: Move, p: np.ndarray) -> float:
    """Distance (mm) from ``p`` to the path of move ``m``: its segment, or its XY arc."""
    if m.center is None:
        d = m.end - m.start
        n2 = float(d @ d)
        t = 0.0 if n2 == 0 else min(1.0, max(0.0, float((p - m.start) @ d) / n2))
        return float(np.linalg.norm(p - (m.start + t * d)))
    ix, iy = m.xy
    cx, cy = m.center
    others = [k for k in range(len(p)) if k not in (ix, iy)]
    off = float(np.max(np.abs(p[others] - m.start[others]), initial=0.0))
    a0 = math.atan2(m.start[iy] - cy, m.start[ix] - cx)
    a1 = math.atan2(m.end[iy] - cy, m.end[ix] - cx)
    ap = math.atan2(p[iy] - cy, p[ix] - cx)
    sign = 1.0 if m.ccw else -1.0
    sweep = (sign * (a1 - a0)) % (2 * math.pi)
    along = (sign * (ap - a0)) % (2 * math.pi)
    if along > sweep + 1e-9:                      # outside the arc's angular range
        return float(min(np.linalg.norm(p - m.start), np.linalg.norm(p - m.end)))
    r0 = math.hypot(m.start[ix] - cx, m.start[iy] - cy)
    return max(abs(math.hypot(p[ix] - cx, p[iy] - cy) - r0), off)
