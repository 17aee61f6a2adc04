"""Look-ahead: junction speeds over a window of spans.

Each span starts and ends with zero path acceleration; between two speeds
``v0`` and ``v1`` it needs at least the distance of a jerk-limited S-curve

    T(dv) = dv/A + A/J      if dv >= A²/J   (the acceleration reaches A)
          = 2 sqrt(dv/J)    otherwise
    D     = (v0 + v1) / 2 * T(|v1 - v0|)     (the speed curve is point-symmetric)

The backward pass starts from a stop at the end of the window (so the tool can
always stop within what it has seen), the forward pass from the committed
speed; both use the closed-form inverses below (checked against ruckig in the
tests), not a solver per segment.
"""

from __future__ import annotations

import math

#: Relative margin on the reachable speed change so that ruckig always finds the profile.
MARGIN = 1e-7
#: The share of the reachable speed change kept (``1 - MARGIN``, made once: a name in an expression is not
#: folded as a literal is).
_KEPT = 1.0 - MARGIN


def distance(v0: float, v1: float, acc: float, jerk: float) -> float:
    """Shortest distance to go from speed v0 to v1 (zero acceleration at both ends)."""
    dv = abs(v1 - v0)
    if dv == 0.0:
        return 0.0
    if jerk == math.inf or dv >= acc * acc / jerk:
        t = dv / acc + (0.0 if jerk == math.inf else acc / jerk)
    else:
        t = 2.0 * math.sqrt(dv / jerk)
    return 0.5 * (v0 + v1) * t


def reachable(v0: float, length: float, acc: float, jerk: float) -> float:
    """Highest speed reachable from v0 (or from which v0 is reachable) within ``length``."""
    if length <= 0.0:
        return v0
    if jerk == math.inf:
        dv = 2.0 * length * acc / (v0 + math.sqrt(v0 * v0 + 2.0 * length * acc))
        return v0 + dv * _KEPT
    dc = acc * acc / jerk
    twice = 2.0 * v0   # what ``2.0 * v0 ...`` begins with below (Python multiplies left to right)
    if length >= (twice + dc) * acc / jerk:
        # (2 v0 + dv)(dv/A + A/J) = 2 L  ->  dv² + dv (A²/J + 2 v0) + 2 v0 A²/J - 2 L A = 0
        b = dc + twice
        c = twice * dc - 2.0 * length * acc
        dv = 0.5 * (-b + math.sqrt(b * b - 4.0 * c))
    else:
        # (2 v0 + x²) x = L sqrt(J) with x = sqrt(dv): the real root of x³ + p x - r = 0 (p = 2 v0),
        # Cardano's x = A - B with A = cbrt(r/2 + sqrt(r²/4 + p³/27)) and A B = p/3, written as
        # r / (A² + A B + B²) (as A³ - B³ = r): a sum of positive terms, no cancellation
        rhs = length * math.sqrt(jerk)
        third = twice / 3.0
        a = (0.5 * rhs + math.sqrt(0.25 * rhs * rhs + third * third * third)) ** (1.0 / 3.0)
        b = third / a
        x = rhs / (a * a + third + b * b)
        dv = x * x
    return v0 + dv * _KEPT


def backward(spans, end_speed: float, known: list[float] | None = None) -> list[float]:
    """Highest start speed of each span so that every later limit (and ``end_speed``) holds.

    ``spans[i].reach(v)`` gives the span's reachable speed within its cap; the
    junction between i and i+1 is also capped by both sides and by a stop
    (``stop_after``).  The forward pass runs as the spans are committed.
    ``known``: what an earlier pass gave for the first spans (with fewer spans after them):
    the pass stops where it finds one of those again, as every limit before follows from it.
    """
    known = known or []
    n = len(spans)
    start = known + [0.0] * (n - len(known))
    v = end_speed
    for i in range(n - 1, -1, -1):
        s = spans[i]
        if s.stop_after:
            v = 0.0
        v = s.reach(v if v < s.vc else s.vc)
        if i > 0 and spans[i - 1].vc < v:
            v = spans[i - 1].vc
        if i < len(known) and v == known[i]:
            break
        start[i] = v
    return start
