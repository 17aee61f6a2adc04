"""Limits along a piece from the per-axis limits (spec 07 §B.12).

For a piece with per-axis derivative bounds ``d1, d2, d3`` (see
:mod:`.geometry`), a path motion with speed ``v <= vc``, acceleration
``|a| <= A_s`` and jerk ``|j| <= J_s`` keeps every axis within its limits when

    v  * d1_i                            <= V_i
    A_s * d1_i + vc² d2_i                 <= A_i
    J_s * d1_i + 3 vc A_s d2_i + vc³ d3_i <= J_i

On a curved piece the centripetal terms use part of the axis budget; the cap
``vc`` leaves at least ``1 - CENTRIPETAL`` of the tangential acceleration a line
with the same tangent bounds would get (see :func:`piece_cap`), and the planner
may pick a lower ``vc`` (more tangential budget) where the piece never reaches
its cap anyway.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np

#: Share of an axis' acceleration / jerk the curvature terms may use at the cap.
CENTRIPETAL = 0.9
CURVE_JERK = 0.8

# _AXES: the per-piece functions below zip vectors that have one entry per machine axis by
# construction (a piece's bounds, the axis limits), without ``strict=True``: a keyword argument
# costs about a quarter of a microsecond per call, and these run for every piece planned.


@dataclass(frozen=True, slots=True)
class AxisLimits:
    """Velocity (mm/s), acceleration (mm/s²) and jerk (mm/s³) per axis, machine order."""

    velocity: tuple[float, ...]
    acceleration: tuple[float, ...]
    jerk: tuple[float, ...]
    #: The tightest axis' acceleration and jerk (what a corner curve of unknown direction gets).
    least_acceleration: float = field(init=False)
    least_jerk: float = field(init=False)
    #: (velocity, acceleration, jerk) of each axis: what a line's limits run over
    rows: tuple[tuple[float, float, float], ...] = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "least_acceleration", min(self.acceleration))
        object.__setattr__(self, "least_jerk", min(self.jerk))
        object.__setattr__(self, "rows", tuple(zip(self.velocity, self.acceleration, self.jerk, strict=True)))


def piece_cap(d1, d2, d3, lim: AxisLimits, feed: float) -> float:
    """Highest speed cap ``vc`` on a piece: feed, axis velocities and curvature terms.

    The centripetal terms leave the piece a tangential acceleration of at least ``1 - CENTRIPETAL``
    of what a line with the same tangent bounds gets, ``reserve = (1 - CENTRIPETAL) min_i A_i / d1_i``:
    ``vc² d2_i <= A_i - reserve d1_i``.  An axis mostly across the tangent (small ``d1_i``, as on the
    part of an arc where that axis takes the centripetal acceleration) may then give nearly all of
    its budget to the curvature; every axis keeps at least ``CENTRIPETAL`` of it (``reserve d1_i <=
    (1 - CENTRIPETAL) A_i``), so the cap is never below ``sqrt(CENTRIPETAL A_i / d2_i)``.
    """
    # plain comparisons over zipped tuples, no min() calls, constants bound once: this runs for every
    # piece planned
    vc = feed
    base = _INF
    for g, a in zip(d1, lim.acceleration):  # noqa: B905 (_AXES)
        if g > 0 and (x := a / g) < base:
            base = x
    reserve = _RESERVE * base if base != _INF else 0.0
    sqrt = math.sqrt
    for g, k, k3, v, a, j in zip(d1, d2, d3, lim.velocity, lim.acceleration, lim.jerk):  # noqa: B905 (_AXES)
        if g > 0 and (x := v / g) < vc:
            vc = x
        if k > 0 and (x := sqrt((a - reserve * g) / k)) < vc:
            vc = x
        if k3 > 0 and j != _INF and (x := (CURVE_JERK * j / k3) ** (1.0 / 3.0)) < vc:
            vc = x
    return vc


_INF = math.inf
#: The share of the acceleration a curve's cap keeps for speed changes (``1 - CENTRIPETAL``, made once).
_RESERVE = 1.0 - CENTRIPETAL


class Terms(NamedTuple):
    """The axes' terms of the formulas of :func:`tangential`, sorted by what they limit (axes
    that limit nothing left out): ``(A, d2, d1)`` of the acceleration (``d1 > 0``), ``(J, d3, d2)``
    of the cross term (``d2 > 0``, finite J) and ``(J, d2, d3, d1)`` of the jerk (``d1 > 0``, finite
    J).  The terms of several pieces together give the limits of a motion along all of them."""

    acc: list[tuple[float, float, float]]
    cross: list[tuple[float, float, float]]
    jerk: list[tuple[float, float, float, float]]

    @staticmethod
    def joined(parts: Iterable[Terms]) -> Terms:
        """The terms of several pieces as one, without the cross terms another bounds (see
        :func:`_cross_kept`: what :func:`tangential` gives of them is the same)."""
        acc: list = []
        cross: list = []
        jerk: list = []
        for part in parts:
            acc += part.acc
            cross += part.cross
            jerk += part.jerk
        return Terms(acc, _cross_kept(cross), jerk)

    def total(self) -> int:
        """How many terms in all."""
        return len(self.acc) + len(self.cross) + len(self.jerk)

    def arrays(self) -> TermArrays:
        """The same terms as arrays (columns), for :func:`tangential_arrays`."""
        def cols(rows: list, width: int) -> tuple:
            table = np.array(rows, dtype=float).reshape(-1, width)
            return tuple(table[:, i] for i in range(width))
        return TermArrays(cols(self.acc, 3), cols(self.cross, 3), cols(self.jerk, 4))


def _cross_kept(cross: list[tuple[float, float, float]]) -> list[tuple[float, float, float]]:
    """The cross terms ``(J, d3, d2)`` of :func:`tangential` that no other bounds: a term with the same
    ``J`` and both bounds at least this one's gives, at every cap ``vc > 0``, at most what this one gives
    when that is positive (``vc³ d3`` and ``3 vc d2`` round monotonically, so its numerator is at most this
    one's and its denominator at least) and at most 0 when this one is: the least term, and with it the
    tangential acceleration, is the same wherever it is positive, and at most 0 where it is not (where
    the planner tries no rung: the jerk made from it is never used).  The terms sorted from the highest:
    a term is bounded when one before it with its ``J`` has a ``d2`` at least its own (the ones before
    have a ``d3`` at least its own); the ones kept in that order (:func:`tangential` takes the least,
    which the order does not change but for the sign of a zero, where no rung is tried either)."""
    kept = []
    limit, top = None, 0.0
    for term in sorted(cross, reverse=True):
        j, _k3, k = term
        if j != limit:
            limit, top = j, k
            kept.append(term)
        elif k > top:
            top = k
            kept.append(term)
    return kept


class TermArrays(NamedTuple):
    """:class:`Terms` as columns: ``acc = (A, d2, d1)``, ``cross = (J, d3, d2)``, ``jerk = (J, d2, d3, d1)``."""

    acc: tuple
    cross: tuple
    jerk: tuple


def term_arrays(d1: np.ndarray, d2: np.ndarray, d3: np.ndarray, lim: AxisLimits) -> TermArrays:
    """The terms of :func:`axis_terms` of many pieces with the same limits (bounds as rows (n, D))
    together, as arrays: the same terms, in another order (:func:`tangential_arrays` takes
    their least, which the order does not change)."""
    acc = np.broadcast_to(np.array(lim.acceleration), d1.shape)
    jerk = np.broadcast_to(np.array(lim.jerk), d1.shape)
    moves = d1 > 0
    finite = np.isfinite(jerk)
    both = moves & finite
    cross = (d2 > 0) & finite
    return TermArrays((acc[moves], d2[moves], d1[moves]), (jerk[cross], d3[cross], d2[cross]),
                      (jerk[both], d2[both], d3[both], d1[both]))


def axis_terms(d1, d2, d3, lim: AxisLimits) -> Terms:
    """The :class:`Terms` of a piece with derivative bounds ``d1, d2, d3``."""
    acc: list = []   # the lists as locals, the Terms made of them at the end (no attribute per term)
    cross: list = []
    jerk: list = []
    for g, k, k3, a, j in zip(d1, d2, d3, lim.acceleration, lim.jerk):  # noqa: B905 (_AXES)
        if g > 0:
            acc.append((a, k, g))
            if j != math.inf:
                jerk.append((j, k, k3, g))
        if k > 0 and j != math.inf:
            cross.append((j, k3, k))
    return Terms(acc, cross, jerk)


def tangential(terms: Terms, vc: float, path_acc: float = 0.0, path_jerk: float = 0.0) -> tuple[float, float]:
    """Tangential acceleration and jerk allowed on a piece (or pieces: their :func:`axis_terms`
    together) whose speed stays below ``vc``.

    On a curve the jerk left after the ``vc³ d3`` term is shared half and half
    between the tangential jerk and the ``3 vc A_s d2`` cross term, which caps
    the tangential acceleration: a tight curve is run at low speed *and* with
    gentle speed changes, never at a speed that leaves no jerk at all.
    """
    # plain comparisons, no min() calls: this runs for every piece planned
    vc2, vc3 = vc * vc, vc ** 3
    acc = path_acc if path_acc > 0 else math.inf
    for a, k, g in terms.acc:
        if (x := (a - vc2 * k) / g) < acc:
            acc = x
    # ``3.0 * vc * k`` is ``(3.0 * vc) * k`` and ``3.0 * vc * acc * k`` is ``(3.0 * vc * acc) * k`` (Python
    # multiplies left to right): the products without k made once, the same numbers
    triple = 3.0 * vc
    if vc > 0:
        for j, k3, k in terms.cross:
            if (x := 0.5 * (j - vc3 * k3) / (triple * k)) < acc:
                acc = x
    jerk = path_jerk if path_jerk > 0 else math.inf
    triple *= acc
    for j, k, k3, g in terms.jerk:
        if (x := (j - triple * k - vc3 * k3) / g) < jerk:
            jerk = x
    return acc, jerk


#: Terms above which :func:`tangential_arrays` is faster than :func:`tangential` (a group of
#: many short curves asks for its limits below several lower caps).
ARRAY_TERMS = 96


def tangential_arrays(terms: TermArrays, vc: float, path_acc: float = 0.0,
                      path_jerk: float = 0.0) -> tuple[float, float]:
    """:func:`tangential` over the terms as arrays: the same expressions, element by element
    and in the same order, so the same numbers."""
    vc2, vc3 = vc * vc, vc ** 3
    acc = path_acc if path_acc > 0 else math.inf
    a, k, g = terms.acc
    if len(a) and (x := float(((a - vc2 * k) / g).min())) < acc:
        acc = x
    j, k3, k = terms.cross
    if vc > 0 and len(j) and (x := float((0.5 * (j - vc3 * k3) / (3.0 * vc * k)).min())) < acc:
        acc = x
    jerk = path_jerk if path_jerk > 0 else math.inf
    j, k, k3, g = terms.jerk
    if len(j) and (x := float(((j - 3.0 * vc * acc * k - vc3 * k3) / g).min())) < jerk:
        jerk = x
    return acc, jerk


def reach_without_jerk(terms: Terms | TermArrays, v: float, length: float, path_acc: float) -> float:
    """Highest speed ``c`` at one end of curved pieces of total ``length`` (their :func:`axis_terms`
    together) from the speed ``v`` at the other, with no jerk limit: the constant tangential
    acceleration allowed below the cap ``c`` is ``a(c) = min_i (A_i - c² d2_i) / d1_i`` (and
    ``path_acc``), and the trapezoid needs ``c² = v² + 2 L a(c)``.  Each term is affine in ``c²``, so
    each gives its own root ``c² = (v² + 2 L A_i / d1_i) / (1 + 2 L d2_i / d1_i)``; ``v² + 2 L a(c) - c²``
    decreases with ``c``, so the least root is where the least term is met: the exact speed, where
    a ladder of lower caps only comes within a rung of it (the caller applies its cap and margins).
    """
    two_l, v2 = 2.0 * length, v * v
    best = v2 + two_l * path_acc if 0.0 < path_acc < math.inf else math.inf
    if isinstance(terms, Terms):
        for a, k, g in terms.acc:
            if (x := (v2 + two_l * a / g) / (1.0 + two_l * k / g)) < best:
                best = x
    else:
        a, k, g = terms.acc
        if len(a) and (x := float(((v2 + two_l * a / g) / (1.0 + two_l * k / g)).min())) < best:
            best = x
    return math.sqrt(best)


def line_limits(d1, lim: AxisLimits, feed: float, path_acc: float = 0.0,
                path_jerk: float = 0.0) -> tuple[float, float, float]:
    """``(vc, A_s, J_s)`` of a line, its cap (:func:`piece_cap`) and :func:`tangential` limits
    with ``d2 = d3 = 0``: without curvature terms every axis bounds the cap, the acceleration and
    the jerk by its own limit over its share ``d1``."""
    # plain comparisons, no min() calls: this runs for every line planned (an axis without a jerk
    # limit gives inf / g = inf, which lowers nothing)
    vc = feed
    acc = path_acc if path_acc > 0 else math.inf
    jerk = path_jerk if path_jerk > 0 else math.inf
    for g, (v, a, j) in zip(d1, lim.rows):  # noqa: B905 (_AXES)
        if g > 0:
            if (x := v / g) < vc:
                vc = x
            if (x := a / g) < acc:
                acc = x
            if (x := j / g) < jerk:
                jerk = x
    return vc, acc, jerk


def curve_limits(d1, d2, d3, lim: AxisLimits, feed: float, path_acc: float = 0.0,
                 path_jerk: float = 0.0) -> tuple[float, float, float]:
    """``(vc, A_s, J_s)`` of a curved piece: :func:`piece_cap`, then :func:`tangential` of its
    :func:`axis_terms` below that cap, without building the terms (the same operations, so the
    same numbers; a corner curve is made for every corner rounded)."""
    vc = piece_cap(d1, d2, d3, lim, feed)
    vc2, vc3 = vc * vc, vc ** 3
    rows = list(zip(d1, d2, d3, lim.acceleration, lim.jerk))  # noqa: B905 (_AXES)
    acc = path_acc if path_acc > 0 else _INF
    turning = vc > 0
    for g, k, k3, a, j in rows:
        if g > 0 and (x := (a - vc2 * k) / g) < acc:
            acc = x
        if turning and k > 0 and j != _INF and (x := 0.5 * (j - vc3 * k3) / (3.0 * vc * k)) < acc:
            acc = x
    jerk = path_jerk if path_jerk > 0 else _INF
    for g, k, k3, _a, j in rows:
        if g > 0 and j != _INF and (x := (j - 3.0 * vc * acc * k - vc3 * k3) / g) < jerk:
            jerk = x
    return vc, acc, jerk


def curve_limits_rows(d1: np.ndarray, d2: np.ndarray, d3: np.ndarray, lim: AxisLimits, feed: float | np.ndarray,
                      path_acc: float = 0.0, path_jerk: float = 0.0) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`curve_limits` of many curves at once (bounds as rows (n, D), ``feed`` one or (n,)): the same
    operations element by element, so the same numbers.  A term the scalar form skips (an axis
    that does not move, has no curvature or no jerk limit) is infinite here, which no least
    changes; ``fmin`` skips a NaN as the scalar comparison does."""
    inf = math.inf
    vel, acc_lim, jerk_lim = np.array(lim.velocity), np.array(lim.acceleration), np.array(lim.jerk)
    finite = np.isfinite(jerk_lim)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        base = np.fmin.reduce(np.where(d1 > 0, acc_lim / d1, inf), axis=1)
        reserve = np.where(np.isfinite(base), (1.0 - CENTRIPETAL) * base, 0.0)[:, None]
        caps = np.fmin(np.where(d1 > 0, vel / d1, inf), np.where(d2 > 0, np.sqrt((acc_lim - reserve * d1) / d2), inf))
        caps = np.fmin(caps, np.where((d3 > 0) & finite, (CURVE_JERK * jerk_lim / d3) ** (1.0 / 3.0), inf))
        vc = np.fmin(np.fmin.reduce(caps, axis=1), feed)
        vc2, vc3 = (vc * vc)[:, None], (vc ** 3)[:, None]
        col = vc[:, None]
        terms = np.fmin(np.where(d1 > 0, (acc_lim - vc2 * d2) / d1, inf),
                        np.where((col > 0) & (d2 > 0) & finite, 0.5 * (jerk_lim - vc3 * d3) / (3.0 * col * d2), inf))
        acc = np.fmin(np.fmin.reduce(terms, axis=1), path_acc if path_acc > 0 else inf)
        terms = np.where((d1 > 0) & finite, (jerk_lim - 3.0 * col * acc[:, None] * d2 - vc3 * d3) / d1, inf)
        jerk = np.fmin(np.fmin.reduce(terms, axis=1), path_jerk if path_jerk > 0 else inf)
    return vc, acc, jerk
