"""Junctions the records decide themselves: the chords of one sampled curve (#POLY, #SPLINE) and the
end-of-move links of #MOVE positionings (seed 002 L16722-L16747).

* Chords of one curve (:class:`~fagorcnc.interp.records.CurveLine` with the same ``curve``) are one
  smooth path: no corner and no stop between them, whatever the corner mode.  The curvature the
  chords stand for is kept as a speed cap on both chords: with ``κ = |u₂ - u₁| / ((ℓ₁ + ℓ₂) / 2)``
  (the turn of the unit directions over the mean chord length) and the normal ``n = (u₂ - u₁) / |u₂ - u₁|``,
  an axis' centripetal acceleration ``κ v² |n_i|`` stays within its acceleration and the jerk of the
  turn ``κ² v³ |u_i|`` within its jerk.
* A #MOVE (:class:`~fagorcnc.interp.records.IndependentMove`) never blends with a general move
  (L16672-L16678): the motion stops between them.  Two #MOVEs of one axis in one direction run
  through when the first ends PRESENT or NEXT (the feed adaptation G108 / G109 its planning
  context carries gives the speed at the junction); NULL and WAITINPOS stop (WAITINPOS with the
  in-position wait of G07).
"""

from __future__ import annotations

import math

from ..interp.records import Arc, Line
from .span import Span

#: Record classes with neither ``curve`` nor ``link`` (exactly these classes: CurveLine and
#: IndependentMove derive from Line): the junctions of most blocks, told without a failed attribute
#: lookup per name.
_PLAIN = frozenset({Line, Arc})
#: Directions closer than this (unit vectors) are one direction.
SAME_DIRECTION = 1e-9


def decided(prev: Span, nxt: Span) -> bool:
    """True when the junction ``prev -> nxt`` is one of this module's (then decided here: a speed
    cap, or ``prev.stop_after``); False leaves it to the corner stage."""
    a, b = prev.record, nxt.record
    if type(a) in _PLAIN and type(b) in _PLAIN:
        return False   # neither a chord of a curve nor a #MOVE (their classes have no curve, no link)
    curve = getattr(a, "curve", None)
    if curve is not None and curve is getattr(b, "curve", None):
        _curve_cap(prev, nxt)
        return True
    link_a, link_b = getattr(a, "link", None), getattr(b, "link", None)
    if link_a is None and link_b is None:
        return False
    if link_a in ("PRESENT", "NEXT") and link_b is not None and \
            math.dist(prev.piece.ul, nxt.piece.ul) <= SAME_DIRECTION:
        return True
    prev.stop_after = True
    return True


def _curve_cap(prev: Span, nxt: Span) -> None:
    u1, u2 = prev.piece.ul, nxt.piece.ul
    turn = [q - p for p, q in zip(u1, u2, strict=True)]
    size = math.sqrt(sum(x * x for x in turn))
    if size == 0.0:
        return
    kappa = size / ((prev.orig_length + nxt.orig_length) / 2.0)
    cap = math.inf
    for lim in (prev.lim, nxt.lim):
        for (_v, acc, jerk), n, u in zip(lim.rows, turn, u2, strict=True):
            if n:
                cap = min(cap, math.sqrt(acc * size / (kappa * abs(n))))
            if u:
                cap = min(cap, (jerk / (kappa * kappa * abs(u))) ** (1.0 / 3.0))
    prev.vc = min(prev.vc, cap)
    nxt.vc = min(nxt.vc, cap)
