"""Limits along a piece from the per-axis limits (spec 07 §B.12).

For a piece with per-axis derivative bounds ``d1, d2, d3`` (see
:mod:`.geometry`), a path motion with speed ``v <= vc``, acceleration
``|a| <= A_s`` and jerk ``|j| <= J_s`` keeps every axis within its limits when

    v  * d1_i                            <= V_i
    A_s * d1_i + vc² d2_i                 <= A_i
    J_s * d1_i + 3 vc A_s d2_i + vc³ d3_i <= J_i

On a curved piece the centripetal terms use part of the axis budget; the cap
``vc`` leaves at least ``1 - CENTRIPETAL`` of it for speeding up and slowing
down, and the planner may pick a lower ``vc`` (more tangential budget) where
the piece never reaches its cap anyway.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

#: Share of an axis' acceleration / jerk the curvature terms may use at the cap.
CENTRIPETAL = 0.9
CURVE_JERK = 0.8


@dataclass(frozen=True, slots=True)
class AxisLimits:
    """Velocity (mm/s), acceleration (mm/s²) and jerk (mm/s³) per axis, machine order."""

    velocity: tuple[float, ...]
    acceleration: tuple[float, ...]
    jerk: tuple[float, ...]


def piece_cap(d1, d2, d3, lim: AxisLimits, feed: float) -> float:
    """Highest speed cap ``vc`` on a piece: feed, axis velocities and curvature terms."""
    vc = feed
    for i, g in enumerate(d1):
        if g > 0:
            vc = min(vc, lim.velocity[i] / g)
        k = d2[i]
        if k > 0:
            vc = min(vc, math.sqrt(CENTRIPETAL * lim.acceleration[i] / k))
        k3 = d3[i]
        if k3 > 0 and lim.jerk[i] != math.inf:
            vc = min(vc, (CURVE_JERK * lim.jerk[i] / k3) ** (1.0 / 3.0))
    return vc


def tangential(d1, d2, d3, lim: AxisLimits, vc: float, path_acc: float = 0.0,
               path_jerk: float = 0.0) -> tuple[float, float]:
    """Tangential acceleration and jerk allowed on a piece whose speed stays below ``vc``.

    On a curve the jerk left after the ``vc³ d3`` term is shared half and half
    between the tangential jerk and the ``3 vc A_s d2`` cross term, which caps
    the tangential acceleration: a tight curve is run at low speed *and* with
    gentle speed changes, never at a speed that leaves no jerk at all.
    """
    acc = path_acc if path_acc > 0 else math.inf
    for i, g in enumerate(d1):
        if g > 0:
            acc = min(acc, (lim.acceleration[i] - vc * vc * d2[i]) / g)
        if d2[i] > 0 and vc > 0 and lim.jerk[i] != math.inf:
            acc = min(acc, 0.5 * (lim.jerk[i] - vc ** 3 * d3[i]) / (3.0 * vc * d2[i]))
    jerk = path_jerk if path_jerk > 0 else math.inf
    for i, g in enumerate(d1):
        if g > 0 and lim.jerk[i] != math.inf:
            jerk = min(jerk, (lim.jerk[i] - 3.0 * vc * acc * d2[i] - vc ** 3 * d3[i]) / g)
    return acc, jerk


def curved_limits(d1, d2, d3, lim: AxisLimits, feed: float, path_acc: float = 0.0,
                  path_jerk: float = 0.0) -> tuple[float, float, float]:
    """``(vc, A_s, J_s)`` for a curved piece at its highest cap."""
    vc = piece_cap(d1, d2, d3, lim, feed)
    acc, jerk = tangential(d1, d2, d3, lim, vc, path_acc, path_jerk)
    return vc, acc, jerk
