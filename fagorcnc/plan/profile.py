"""Jerk-limited motion along one span, computed by ruckig (1 degree of freedom:
the path parameter), and its evaluation at any time.

ruckig's community edition computes state-to-state profiles; it is only ever
asked for reachable boundary speeds (the look-ahead guarantees them) and with
``min_velocity = 0`` so that no profile runs backwards.  A profile is kept as
its phases: start times, jerk, and the acceleration, speed and position at
each phase start (at most 7 phases).
"""

from __future__ import annotations

import math

import numpy as np
from ruckig import InputParameter, Result, Ruckig, RuckigError, Trajectory


class ProfileError(RuntimeError):
    """ruckig found no profile for a request the look-ahead considered feasible."""


class Profile:
    """Path motion ``s(t)`` over ``[0, duration]``: phases of constant jerk."""

    __slots__ = ("a", "duration", "j", "p", "t", "v")

    def __init__(self, t, j, a, v, p, duration: float) -> None:
        self.t, self.j, self.a, self.v, self.p = t, j, a, v, p
        self.duration = duration

    def at(self, tau: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Position, speed, acceleration and jerk along the path at times ``tau``."""
        k = np.clip(np.searchsorted(self.t, tau, side="right") - 1, 0, len(self.j) - 1)
        dt = tau - self.t[k]
        j = self.j[k]
        a0, v0, p0 = self.a[k], self.v[k], self.p[k]
        a = a0 + j * dt
        v = v0 + a0 * dt + j * dt * dt / 2.0
        s = p0 + v0 * dt + a0 * dt * dt / 2.0 + j * dt ** 3 / 6.0
        return s, v, a, j

    @property
    def peak_speed(self) -> float:
        return float(np.max(self.v))


def _equal_speeds(span, v: float, keep: bool) -> tuple[float, float, Profile | None]:
    """A micro-span between equal speeds, where ruckig's numerics give up: constant speed,
    or from rest to rest four jerk phases of ``tau = (L / 2J)^(1/3)`` (distance 2 J tau³)."""
    length, jerk = span.length, span.jerk
    if v > 0:
        duration = length / v
        prof = Profile(np.array([0.0]), np.array([0.0]), np.array([0.0]), np.array([v]), np.array([0.0]), duration)
        return duration, span.vc, prof if keep else None
    jerk = min(jerk, span.acc ** 1.5 * math.sqrt(2.0 / length))   # peak acceleration J tau stays <= A
    tau = (length / (2.0 * jerk)) ** (1.0 / 3.0)
    t = np.arange(4) * tau
    j = np.array([jerk, -jerk, -jerk, jerk])
    a = np.array([0.0, jerk * tau, 0.0, -jerk * tau])
    vel = np.array([0.0, jerk * tau ** 2 / 2, jerk * tau ** 2, jerk * tau ** 2 / 2])
    pos = np.array([0.0, jerk * tau ** 3 / 6, jerk * tau ** 3, 11 * jerk * tau ** 3 / 6])
    return 4 * tau, span.vc, Profile(t, j, a, vel, pos, 4 * tau) if keep else None


class Solver:
    """A reusable ruckig 1-DOF solver."""

    def __init__(self) -> None:
        self.otg = Ruckig(1)
        self.inp = InputParameter(1)
        self.traj = Trajectory(1)
        self.inp.current_position = [0.0]
        self.inp.current_acceleration = [0.0]
        self.inp.target_acceleration = [0.0]
        self.inp.min_velocity = [0.0]

    def duration(self, length: float, v0: float, v1: float, vc: float, acc: float, jerk: float) -> float:
        """Duration of the time-optimal profile, or ``inf`` when ruckig finds none."""
        inp = self.inp
        inp.current_velocity = [v0]
        inp.target_position = [length]
        inp.target_velocity = [v1]
        inp.max_velocity = [vc]
        inp.max_acceleration = [acc]
        inp.max_jerk = [jerk]
        try:
            result = self.otg.calculate(inp, self.traj)
        except (RuckigError, RuntimeError):
            return math.inf
        if result not in (Result.Working, Result.Finished):
            return math.inf
        return self.traj.duration

    def profile(self) -> Profile:
        """The profile of the last successful :meth:`duration` call."""
        pr = self.traj.profiles[0][0]
        t = np.concatenate([[0.0], np.cumsum(pr.t)])
        return Profile(t[:-1], np.array(pr.j), np.array(pr.a[:-1]), np.array(pr.v[:-1]), np.array(pr.p[:-1]),
                       self.traj.duration)

    def time(self, span, v0: float, v1: float, keep: bool) -> tuple[float, float, Profile | None]:
        """(duration, cap used, profile) of a span from v0 to v1.

        Curved spans try a few lower caps: below its cap a curve leaves more of
        the axes' acceleration for speeding up and slowing down.
        """
        top = max(v0, v1)
        caps = [span.vc]
        if span.piece.curved and span.vc > top * 1.0001:
            caps += [c for c in (span.vc * f for f in (0.9, 0.8, 0.65, 0.5, 0.35)) if c > top * 1.0001]
            caps.append(top * 1.0001 if top > 0 else span.vc * 0.2)
        best = (math.inf, span.vc)
        for vc in caps:
            acc, jerk = span.limits_at(vc)
            if acc <= 0 or jerk <= 0:
                continue
            d = self.duration(span.length, min(v0, vc), min(v1, vc), vc, acc, jerk)
            if d < best[0]:
                best = (d, vc)
        if best[0] == math.inf and abs(v1 - v0) <= 1e-9 * (1.0 + v0):
            return _equal_speeds(span, v0, keep)
        if best[0] == math.inf:
            raise ProfileError(f"no profile for a {span.length:.6g} mm span from {v0:.6g} to {v1:.6g} mm/s")
        if not keep:
            return best[0], best[1], None
        acc, jerk = span.limits_at(best[1])   # solve the best again so that the trajectory holds it
        self.duration(span.length, min(v0, best[1]), min(v1, best[1]), best[1], acc, jerk)
        return best[0], best[1], self.profile()
