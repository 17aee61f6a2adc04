"""The planner's unit of work: one piece of path with its limits, and the
events (dwells, auxiliary functions) that synchronise with the motion."""

from __future__ import annotations

import numpy as np

from .geometry import Piece
from .limits import AxisLimits, curved_limits, piece_cap, tangential
from .lookahead import reachable

#: Lower caps tried on curves (fractions of the highest cap).
LADDER = (0.85, 0.7, 0.55, 0.4, 0.25, 0.12, 0.05)


class Span:
    """A piece with what the look-ahead needs: speed cap ``vc`` (mm/s),
    tangential acceleration ``acc`` and jerk ``jerk``, and whether the motion
    must stop at its end."""

    __slots__ = ("_ladder", "acc", "blend", "dyn", "feed", "jerk", "length", "lim", "line", "mid_k",
                 "orig_length", "path_acc", "path_jerk", "piece", "rapid", "record", "stop_after", "vc")

    def __init__(self, piece: Piece, record, feed: float, lim: AxisLimits, rapid: bool, dyn,
                 path_acc: float = 0.0, path_jerk: float = 0.0, blend: bool = False) -> None:
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
        self.refresh()

    def refresh(self) -> None:
        """Recompute the limits from the (possibly trimmed) piece."""
        p = self.piece
        self.length = p.length
        feed = self.feed / p.speed_factor()
        d1, d2, d3 = p.d1.tolist(), p.d2.tolist(), p.d3.tolist()
        self._ladder = None
        if p.curved:
            self.vc, self.acc, self.jerk = curved_limits(d1, d2, d3, self.lim, feed, self.path_acc, self.path_jerk)
        else:
            self.vc = piece_cap(d1, d2, d3, self.lim, feed)
            self.acc, self.jerk = tangential(d1, d2, d3, self.lim, self.vc, self.path_acc, self.path_jerk)

    def part(self, s0: float, s1: float, feed: float | None = None) -> Span:
        """The stretch ``[s0, s1]`` of this span as a new span (optionally with another feed)."""
        return Span(self.piece.sub(s0, s1), self.record, self.feed if feed is None else feed, self.lim, self.rapid,
                    self.dyn, self.path_acc, self.path_jerk, self.blend)

    @property
    def ladder(self) -> list[tuple[float, float, float]] | None:
        """Curves: (cap, tangential acceleration, tangential jerk) for descending caps: below its
        highest cap a curve leaves more of the axes' budget for speed changes.  None for lines."""
        if self._ladder is None and self.piece.curved:
            p = self.piece
            d1, d2, d3 = p.d1.tolist(), p.d2.tolist(), p.d3.tolist()
            self._ladder = [(self.vc, self.acc, self.jerk)] + [
                (self.vc * f, *tangential(d1, d2, d3, self.lim, self.vc * f, self.path_acc, self.path_jerk))
                for f in LADDER]
        return self._ladder

    def reach(self, v: float) -> float:
        """Highest speed at the other end of this span from speed ``v`` at one end (either
        direction: the profiles are symmetric), within the cap."""
        ladder = self.ladder
        if ladder is None:
            return min(self.vc, reachable(v, self.length, self.acc, self.jerk))
        best = 0.0
        for c, a, j in ladder:
            if c < v or a <= 0 or j <= 0:
                break
            best = max(best, min(c, reachable(v, self.length, a, j)))
        return best if best > 0.0 else min(self.vc, v)

    def limits_at(self, vc: float) -> tuple[float, float]:
        """Tangential acceleration and jerk when the speed stays below ``vc`` (curved pieces gain budget)."""
        if not self.piece.curved or vc >= self.vc:
            return self.acc, self.jerk
        p = self.piece
        return tangential(p.d1.tolist(), p.d2.tolist(), p.d3.tolist(), self.lim, vc, self.path_acc, self.path_jerk)


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

    __slots__ = ("_bounds", "_ladder", "acc", "jerk", "length", "line", "members", "record", "stop_after", "vc")

    def __init__(self, first: Span) -> None:
        self.members = [first]
        self.length = first.length
        self.vc, self.acc, self.jerk = first.vc, first.acc, first.jerk
        self.stop_after = first.stop_after
        self.line, self.record = first.line, first.record
        self._ladder = None
        self._bounds = None

    def add(self, span: Span) -> None:
        self.members.append(span)
        self.length += span.length
        self.vc = min(self.vc, span.vc)
        self.acc = min(self.acc, span.acc)
        self.jerk = min(self.jerk, span.jerk)
        self.stop_after = span.stop_after
        self._ladder = None
        self._bounds = None

    @property
    def ladder(self) -> list[tuple[float, float, float]] | None:
        if self._ladder is None and any(m.piece.curved for m in self.members):
            caps = self.vc * np.array(LADDER)
            acc, jerk = self._limits(caps)
            self._ladder = [(self.vc, self.acc, self.jerk), *zip(caps.tolist(), acc.tolist(), jerk.tolist(),
                                                                 strict=True)]
        return self._ladder

    reach = Span.reach

    def limits_at(self, vc: float) -> tuple[float, float]:
        """The members' tangential limits below the cap ``vc``."""
        if vc >= self.vc or self.ladder is None:
            return self.acc, self.jerk
        acc, jerk = self._limits(np.array([vc]))
        return float(acc[0]), float(jerk[0])

    def _limits(self, caps: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Tangential acceleration and jerk for each cap in ``caps``: the formulas of
        :func:`~fagorcnc.plan.limits.tangential` over all members, axes and caps at once."""
        if self._bounds is None:
            self._bounds = tuple(np.array([getattr(m.piece, name) for m in self.members])
                                 for name in ("d1", "d2", "d3"))
        d1, d2, d3 = self._bounds
        lim = self.members[0].lim
        a_max = np.asarray(lim.acceleration)
        j_max = np.asarray(lim.jerk)
        path_acc = self.members[0].path_acc or np.inf
        path_jerk = self.members[0].path_jerk or np.inf
        vc = caps[:, None, None]
        with np.errstate(divide="ignore", invalid="ignore"):
            acc = np.where(d1 > 0, (a_max - vc * vc * d2) / d1, np.inf)
            finite = np.isfinite(j_max)
            cross = np.where((d2 > 0) & finite, 0.5 * (j_max - vc ** 3 * d3) / (3.0 * vc * d2), np.inf)
            acc = np.minimum(np.minimum(acc.min(axis=(1, 2)), cross.min(axis=(1, 2))), path_acc)
            a3 = acc[:, None, None]
            jerk = np.where((d1 > 0) & finite, (j_max - 3.0 * vc * a3 * d2 - vc ** 3 * d3) / d1, np.inf)
            jerk = np.minimum(jerk.min(axis=(1, 2)), path_jerk)
        return acc, jerk
