"""Forward and inverse kinematics of a :class:`~fagorcnc.config.kinematics.Kinematics`.

Model (product of rotations about the joints' lines at rest, main joint last):

* the head turns points of the tool about the head joints: ``H(x) = H1(H2(x))`` with ``x`` measured
  from the head reference point ``m`` (the linear axes' position);
* the table turns points of the part about the table joints: ``W(x) = T1(T2(x))`` in machine
  coordinates; the *part frame* is the table's frame with every table axis at 0.

With tool length ``L`` and the tool direction ``t0`` (tip -> spindle at rest), the tool tip is
``tip_machine = m + H(nose - L t0)`` and, in the part frame, ``tip = W^-1(tip_machine)``; the tool
direction in the part frame is ``W_rot^-1 H_rot t0``.
"""

from __future__ import annotations

import math
from collections.abc import Mapping

import numpy as np

from ..config.kinematics import Joint, Kinematics
from .rotation import rot, two_angles, wrap


class KinematicsError(ValueError):
    """A pose the kinematics cannot reach or compute; the message says why."""


def _turn(joints: tuple[Joint, ...], angles: Mapping[str, float], x: np.ndarray, *, points: bool,
          inverse: bool = False) -> np.ndarray:
    """``x`` moved by the joints (main last: the main joint carries the secondary one)."""
    order = joints if inverse else tuple(reversed(joints))
    for j in order:
        r = rot(j.direction, -angles[j.axis] if inverse else angles[j.axis])
        if points:
            p = np.asarray(j.pivot)
            x = p + r @ (x - p)
        else:
            x = r @ x
    return x


def head_offset(kin: Kinematics, angles: Mapping[str, float], length: float) -> np.ndarray:
    """Tool tip minus head reference point, in machine coordinates, for tool length ``length``."""
    rest = np.asarray(kin.spindle_nose) - length * np.asarray(kin.tool_direction)
    return _turn(kin.head_joints, angles, rest, points=True)


def tool_direction_machine(kin: Kinematics, angles: Mapping[str, float]) -> np.ndarray:
    """The tool direction (tip -> spindle) in machine coordinates."""
    return _turn(kin.head_joints, angles, np.asarray(kin.tool_direction, dtype=float), points=False)


def tool_direction_part(kin: Kinematics, angles: Mapping[str, float]) -> np.ndarray:
    """The tool direction (tip -> spindle) in the part frame."""
    return _turn(kin.table_joints, angles, tool_direction_machine(kin, angles), points=False, inverse=True)


def to_part(kin: Kinematics, angles: Mapping[str, float], point) -> np.ndarray:
    """A machine-frame point in the part frame (the table turned back to 0)."""
    return _turn(kin.table_joints, angles, np.asarray(point, dtype=float), points=True, inverse=True)


def to_machine(kin: Kinematics, angles: Mapping[str, float], point) -> np.ndarray:
    """A part-frame point where the table's present angles put it in machine coordinates."""
    return _turn(kin.table_joints, angles, np.asarray(point, dtype=float), points=True)


def forward(kin: Kinematics, linear, angles: Mapping[str, float], length: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """(tool tip, tool direction) in the part frame from the joint positions: ``linear`` is the head
    reference point (X, Y, Z machine), ``angles`` the rotary axes in degrees."""
    tip_m = np.asarray(linear, dtype=float) + head_offset(kin, angles, length)
    return to_part(kin, angles, tip_m), tool_direction_part(kin, angles)


def linear_for_tip(kin: Kinematics, tip, angles: Mapping[str, float], length: float = 0.0) -> np.ndarray:
    """The linear axes (head reference point) that put the tool tip on ``tip`` (part frame) at ``angles``."""
    return to_machine(kin, angles, tip) - head_offset(kin, angles, length)


def orientations(kin: Kinematics, direction, current: Mapping[str, float] | None = None) -> list[dict[str, float]]:
    """The rotary positions that point the tool along ``direction`` (part frame, tip -> spindle), best
    first: solution 1 turns the main axis least from 0, solution 2 most (seed 002 L13030-L13040, L13389);
    where both turn it as far (a table's two solutions A, -A), the one whose secondary axis moves least
    comes first [CONSTRUCTION].

    An axis left free by a singular pose (the tool along a rotary axis) keeps its ``current`` value.
    Angles are in (-180, 180].  Raises :class:`KinematicsError` when no position of the rotary axes
    gives that direction.
    """
    current = current or {}
    js = kin.joints
    v = np.asarray(direction, dtype=float)
    v = v / np.linalg.norm(v)
    if len(js) == 3 and all(j.head for j in js):
        return _three(kin, v, current)
    if len(js) != 2:
        raise KinematicsError(f"the tool orientation of a {kin.family} (type {kin.type}) is not solved by "
                              "fagorcnc: program the rotary axes themselves")
    t0 = np.asarray(kin.tool_direction, dtype=float)
    first, second = js
    # v = Rt2^-1 Rt1^-1 Rh1 Rh2 t0, written as rot(a, f1) rot(b, f2) t0 = v
    if first.head and second.head:
        a, sa, ja = first.direction, 1.0, first
        b, sb, jb = second.direction, 1.0, second
    elif not first.head and not second.head:
        a, sa, ja = second.direction, -1.0, second
        b, sb, jb = first.direction, -1.0, first
    else:
        head, table = (first, second) if first.head else (second, first)
        a, sa, ja = table.direction, -1.0, table
        b, sb, jb = head.direction, 1.0, head
    sols = []
    for f1, f2 in two_angles(a, b, t0, v):
        sol = {ja.axis: wrap(sa * f1) if f1 is not None else current.get(ja.axis, 0.0),
               jb.axis: wrap(sb * f2) if f2 is not None else current.get(jb.axis, 0.0)}
        if sol not in sols:
            sols.append(sol)
    if not sols:
        raise KinematicsError(f"no position of {first.axis} and {second.axis} points the tool along "
                              f"({v[0]:.4f}, {v[1]:.4f}, {v[2]:.4f})")
    main, other = first.axis, second.axis
    # solution 1: the main axis least far from 0; between equals, the secondary axis nearest where it is
    sols.sort(key=lambda s: (round(abs(s[main]), 9), round(abs(wrap(s[other] - current.get(other, 0.0))), 9),
                             s[main] < 0))
    return sols


def _three(kin: Kinematics, v: np.ndarray, current: Mapping[str, float]) -> list[dict[str, float]]:
    """The orientations of a three-rotary head (types 17-24): ``rot(d1, t1) rot(d2, t2) rot(d3, t3) t0 = v``.

    One angle is more than a direction needs.  The manual's rule for the two solutions (the main axis
    least / most far from 0, seed 002 L13030-L13040) is carried over one axis further [CONSTRUCTION,
    seed 002 says nothing of these heads but their names, L28831-L28845]: the main axis turns as
    little from 0 as the direction allows (``t1 = 0`` whenever the last two axes reach ``v`` alone),
    then solution 1 is the one whose secondary axis turns least from 0, solution 2 the one that
    turns it most.  An axis left free by a singular pose keeps its ``current`` value.
    """
    j1, j2, j3 = kin.joints
    d1, d2, d3 = (np.asarray(j.direction, dtype=float) for j in (j1, j2, j3))
    t0 = np.asarray(kin.tool_direction, dtype=float)
    # z = rot(d3, t3) t0 runs over a cone about d3, and rot(d2, t2) keeps z.d2: the last two axes reach
    # q when q.d2 lies within the cone's range of .d2, [m - r, m + r]
    along = d3 * float(d3 @ t0)
    m = float(d2 @ along)
    r = float(np.linalg.norm(t0 - along)) * float(np.linalg.norm(d2 - d3 * float(d3 @ d2)))
    lo, hi = m - r, m + r
    # q(t1) = rot(d1, -t1) v, so q.d2 = a + b cos t1 + c sin t1 (Rodrigues)
    par = d1 * float(d1 @ v)
    a, b, c = float(d2 @ par), float(d2 @ (v - par)), -float(d2 @ np.cross(d1, v))
    eps = 1e-12
    if lo - eps <= a + b <= hi + eps:
        mains = [0.0]
    else:
        bound = hi if a + b > hi else lo
        amp = math.hypot(b, c)
        ratio = (bound - a) / amp if amp > eps else math.inf
        if abs(ratio) > 1.0 + 1e-12:
            raise KinematicsError(f"no position of {j1.axis}, {j2.axis} and {j3.axis} points the tool along "
                                  f"({v[0]:.4f}, {v[1]:.4f}, {v[2]:.4f})")
        phi, half = math.atan2(c, b), math.acos(max(-1.0, min(1.0, ratio)))
        cands = [wrap(math.degrees(phi + half)), wrap(math.degrees(phi - half))]
        least = min(abs(t) for t in cands)
        mains = sorted({round(t, 12) for t in cands if abs(t) - least < 1e-9})
    sols: list[dict[str, float]] = []
    for t1 in mains:
        q = rot(d1, -t1) @ v
        for f2, f3 in two_angles(d2, d3, t0, q):
            sol = {j1.axis: wrap(t1),
                   j2.axis: wrap(f2) if f2 is not None else current.get(j2.axis, 0.0),
                   j3.axis: wrap(f3) if f3 is not None else current.get(j3.axis, 0.0)}
            if sol not in sols:
                sols.append(sol)
    if not sols:   # (the boundary of the reach, lost to rounding)
        raise KinematicsError(f"no position of {j1.axis}, {j2.axis} and {j3.axis} points the tool along "
                              f"({v[0]:.4f}, {v[1]:.4f}, {v[2]:.4f})")
    sols.sort(key=lambda s: (round(abs(s[j1.axis]), 9), round(abs(s[j2.axis]), 9),
                             round(abs(wrap(s[j3.axis] - current.get(j3.axis, 0.0))), 9),
                             s[j1.axis] < 0, s[j2.axis] < 0))
    return sols
