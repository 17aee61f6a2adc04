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
from itertools import accumulate

import numpy as np
from ruckig import InputParameter, Result, Ruckig, RuckigError, Trajectory

from .span import LADDER


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

    def crossings(self, positions: list[float]) -> tuple[list[float], list[float]]:
        """Times at which the motion reaches the increasing ``positions`` (inside ``[0, length]``)
        and its speeds there (see :func:`_crossings`)."""
        return _crossings(self.t.tolist(), self.j.tolist(), self.a.tolist(), self.v.tolist(), self.p.tolist(),
                          self.duration, positions)

    @property
    def peak_speed(self) -> float:
        return float(np.max(self.v))


class Phases(Profile):
    """A :class:`Profile` whose phases are lists of floats, as ruckig gives them: what a group's
    members' segments are cut from (:meth:`crossings`, the start speed ``v[0]``, the duration) when
    the profiles are not kept; its arrays (the same numbers) are made only when it is sampled."""

    __slots__ = ()

    def at(self, tau: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        rows = (np.array(x) for x in (self.t, self.j, self.a, self.v, self.p))
        return Profile(*rows, self.duration).at(tau)

    def crossings(self, positions: list[float]) -> tuple[list[float], list[float]]:
        return _crossings(self.t, self.j, self.a, self.v, self.p, self.duration, positions)


def _crossings(starts: list[float], jerks: list[float], accs: list[float], speeds: list[float], places: list[float],
               duration: float, positions: list[float]) -> tuple[list[float], list[float]]:
    """Times at which a motion of the phases (their start times, jerks, and acceleration, speed and
    position at each start) reaches the increasing ``positions`` and its speeds there.  Per
    constant-jerk phase the position is a cubic in time, increasing (the speed stays >= 0): its root
    in the phase, ``p0 + v0 t + a0 t²/2 + j t³/6 = 0`` from ``p0 <= 0``, by Newton from the linear
    guess, kept inside the bracket by bisection, to full precision (inline: a root per member of a
    group planned)."""
    ends = [*starts[1:], duration]
    times, at_speed = [], []
    k = 0
    last = len(places) - 1
    for b in positions:
        while k < last and places[k + 1] <= b:
            k += 1
        p0, v0, a0, j, t0 = places[k] - b, speeds[k], accs[k], jerks[k], starts[k]
        span = ends[k] - t0
        lo, hi = 0.0, span
        half = a0 / 2.0   # the loop's invariants made once (the same numbers)
        close = 4e-16 * span
        rise = span * (v0 + span * (half + span * j / 6.0))
        # span * min(1.0, -p0 / rise) by a comparison (no call), or the middle
        tau = span * (x if (x := -p0 / rise) < 1.0 else 1.0) if rise > 0.0 else span / 2.0
        for _ in range(100):
            tj = tau * j   # ``tau * j / 6.0`` is ``(tau * j) / 6.0``: the product both expressions begin with
            f = p0 + tau * (v0 + tau * (half + tj / 6.0))
            if f == 0.0:
                break
            if f > 0.0:
                hi = tau
            else:
                lo = tau
            slope = v0 + tau * (a0 + tj / 2.0)
            nxt = tau - f / slope if slope > 0.0 else (lo + hi) / 2.0
            if not lo <= nxt <= hi:
                nxt = (lo + hi) / 2.0
            if -close <= nxt - tau <= close:   # abs(nxt - tau) <= close, without a call
                tau = nxt
                break
            tau = nxt
        times.append(t0 + tau)
        at_speed.append(v0 + a0 * tau + j * tau * tau / 2.0)
    return times, at_speed


#: Spans shorter than this (mm) get exact closed-form profiles: ruckig's end position is only
#: good to ~1e-9 mm there, which a servo sampling at 1 ms would see as a jerk spike.
MICRO = 1e-3
#: Acceleration and jerk scale of a second try when ruckig finds no profile with the limits as
#: they are: a span whose length is exactly where two of its profile types meet (for example
#: 5 mm x sqrt(2) at 1000 x sqrt(2) mm/s² and 20000 x sqrt(2) mm/s³: the diagonal of a G39
#: chamfer run at rapid) makes ruckig 0.19 fail with "error in step 1"; limits a billionth
#: lower move the span off that edge and are still within the machine's.
EDGE_SCALE = 1.0 - 1e-9


def micro_profile(length: float, v0: float, v1: float, acc: float, jerk: float,
                  keep: bool = True) -> Profile | float | None:
    """Exact short profile with zero acceleration at both ends, or None when it would need more
    than ``acc`` (then ruckig plans it); with ``keep=False`` only its duration.

    Moving (v0 + v1 > 0): two jerk phases of ``tau = L / (v0 + v1)`` with ``j = (v1 - v0) / tau²``;
    at the speeds the look-ahead allows, ``|j|`` never exceeds J (the reachable-speed relation
    ``L² = dv (v0 + v1)² / J``).  From rest to rest: four phases of ``tau = (L / 2J)^(1/3)``.
    """
    if v0 + v1 > 0 and abs(v1 - v0) <= 1e-12 * (v0 + v1):
        v = (v0 + v1) / 2   # equal up to rounding: constant speed
        if not keep:
            return length / v
        return Profile(np.array([0.0]), np.array([0.0]), np.array([0.0]), np.array([v]), np.array([0.0]), length / v)
    if v0 + v1 > 0:
        tau = length / (v0 + v1)
        j = (v1 - v0) / (tau * tau)
        if abs(j) > jerk * (1 + 1e-6) or abs(j) * tau > acc:   # rounding of the reachable speed
            return None
        if not keep:
            return 2 * tau
        t = np.array([0.0, tau])
        return Profile(t, np.array([j, -j]), np.array([0.0, j * tau]), np.array([v0, v0 + j * tau * tau / 2]),
                       np.array([0.0, v0 * tau + j * tau ** 3 / 6]), 2 * tau)
    j = min(jerk, acc ** 1.5 * math.sqrt(2.0 / length))   # peak acceleration J tau stays <= A
    tau = (length / (2.0 * j)) ** (1.0 / 3.0)
    if not keep:
        return 4 * tau
    return Profile(np.arange(4) * tau, np.array([j, -j, -j, j]), np.array([0.0, j * tau, 0.0, -j * tau]),
                   np.array([0.0, j * tau ** 2 / 2, j * tau ** 2, j * tau ** 2 / 2]),
                   np.array([0.0, j * tau ** 3 / 6, j * tau ** 3, 11 * j * tau ** 3 / 6]), 4 * tau)


class ProfileWindow:
    """The part of a profile between ``t0`` and ``t0 + duration``, positions from ``s0``:
    a member's motion inside a group's profile (same interface as :class:`Profile`)."""

    __slots__ = ("duration", "profile", "s0", "t0")

    def __init__(self, profile: Profile, t0: float, s0: float, duration: float) -> None:
        self.profile, self.t0, self.s0, self.duration = profile, t0, s0, duration

    def at(self, tau: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        s, v, a, j = self.profile.at(np.asarray(tau) + self.t0)
        return s - self.s0, v, a, j


#: Margins of :func:`too_short` (relative, and mm): a span within them of the shortest length is
#: left to ruckig, which works to a tolerance (the look-ahead asks for reachable speeds computed by
#: the same formula, so spans exactly at the shortest length are common: a 2.05e-5 mm span whose
#: length was 1.0e-6 short of it relatively has a ruckig profile).
SHORT_MARGIN = 1e-4
SHORT_MARGIN_MM = 1e-7
#: ``1 - SHORT_MARGIN``, made once (a name in an expression is not folded as a literal is).
_SHORT_KEPT = 1.0 - SHORT_MARGIN


def _pulse(v0: float, v1: float, acc: float, jerk: float) -> float:
    """Length run by the fastest monotone change of speed from ``v0`` to ``v1``: one acceleration
    pulse, a jerk triangle (``T = 2 sqrt(dv / J)``) while ``dv <= A²/J``, else a trapezoid
    (``T = dv / A + A / J``); symmetric, so the speed is symmetric about its middle and the length
    is ``(v0 + v1) / 2 T``."""
    dv = abs(v1 - v0)
    t = 2.0 * math.sqrt(dv / jerk) if dv * jerk <= acc * acc else dv / acc + acc / jerk
    return (v0 + v1) / 2.0 * t


def shortest_length(v0: float, v1: float, acc: float, jerk: float) -> float:
    """The shortest path length (mm) over which the speed can change from ``v0`` to ``v1`` (mm/s),
    at zero acceleration at both ends, within ``acc`` and ``jerk`` (speeds never negative).

    A motion that does not change speed monotonically dips to some ``w`` below both speeds (where
    its acceleration crosses zero): two pulses, ``P(v0, w) + P(w, v1)``.  Each pulse length is
    concave in ``w`` (``(2x - d)/2 T(d)`` with ``d = x - w``, ``T`` increasing and concave), so the
    sum is least at an end of ``[0, min(v0, v1)]``: the single pulse, or a stop on the way (up to a
    few per cent shorter when one speed is far below the other; ruckig finds it).  Any longer span is
    met by cruising.
    """
    if v0 == v1:
        return 0.0
    return min(_pulse(v0, v1, acc, jerk), _pulse(v0, 0.0, acc, jerk) + _pulse(0.0, v1, acc, jerk))


def too_short(length: float, v0: float, v1: float, acc: float, jerk: float) -> bool:
    """Whether no profile goes from ``v0`` to ``v1`` over ``length`` (shorter than
    :func:`shortest_length` by more than the margins; borderline cases go to ruckig)."""
    return length < shortest_length(v0, v1, acc, jerk) * _SHORT_KEPT - SHORT_MARGIN_MM


#: A lower cap is not solved when the best duration found, times this, is at most the length over
#: the cap (no motion within it is faster): the margin keeps ruckig's rounding out of the decision.
RUNG_MARGIN = 1.0 + 1e-9


#: ``keep`` of a request whose profile is wanted as :class:`Phases` (lists), not as arrays.
PHASES = "phases"
#: The speed at rest (one object: see Solver.duration).
_REST = 0.0
#: ruckig's results of a request it solved.
_SOLVED = (Result.Working, Result.Finished)


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
        # the start speed, length and end speed ruckig holds (see duration)
        self._v0 = self._length = self._v1 = None

    def duration(self, length: float, v0: float, v1: float, vc: float, acc: float, jerk: float) -> float:
        """Duration of the time-optimal profile, or ``inf`` when ruckig finds none.

        A request that cannot be met (:func:`too_short`) is answered without ruckig, whose
        failures go through an exception and cost five times a success.
        """
        if v0 != v1:
            # too_short(length, v0, v1, acc, jerk) inline, operation for operation (every request to
            # ruckig passes here; at equal speeds the shortest length is 0: never too short)
            # ``length < min(direct, stop) * (1 - m) - mm`` as two tests: rounded products and
            # differences are monotone, so the least of the two sides is the side of the least (the
            # same answer), and a span long enough for the single pulse needs no stop computed
            lim = acc * acc
            dv = abs(v1 - v0)
            t = 2.0 * math.sqrt(dv / jerk) if dv * jerk <= lim else dv / acc + acc / jerk
            direct = (v0 + v1) / 2.0 * t
            if length < direct * _SHORT_KEPT - SHORT_MARGIN_MM:
                dv = abs(0.0 - v0)
                t = 2.0 * math.sqrt(dv / jerk) if dv * jerk <= lim else dv / acc + acc / jerk
                stop = (v0 + 0.0) / 2.0 * t
                dv = abs(v1 - 0.0)
                t = 2.0 * math.sqrt(dv / jerk) if dv * jerk <= lim else dv / acc + acc / jerk
                stop += (0.0 + v1) / 2.0 * t
                if length < stop * _SHORT_KEPT - SHORT_MARGIN_MM:
                    return math.inf
        # ruckig is given the start speed, length and end speed each only when it differs from the one
        # it holds (a setter converts its argument; the rungs of a span and the G50 blocks from rest to
        # rest ask the same ones again).  A float equal to the one held and not zero is the same number;
        # a zero is set again unless it is the very object held (0.0 and -0.0 are equal).  The setters
        # take one-element tuples: a tuple converts with fewer instructions than a list.
        inp = self.inp
        if not (v0 is (held := self._v0) or (v0 == held and v0 != 0.0)):
            inp.current_velocity = (v0,)
            self._v0 = v0
        if not (length is (held := self._length) or (length == held and length != 0.0)):
            inp.target_position = (length,)
            self._length = length
        if not (v1 is (held := self._v1) or (v1 == held and v1 != 0.0)):
            inp.target_velocity = (v1,)
            self._v1 = v1
        inp.max_velocity = (vc,)
        inp.max_acceleration = (acc,)
        inp.max_jerk = (jerk,)
        try:
            result = self.otg.calculate(inp, self.traj)
        except (RuckigError, RuntimeError):
            return math.inf
        if result not in _SOLVED:
            return math.inf
        return self.traj.duration

    def profile(self) -> Profile:
        """The profile of the last successful :meth:`duration` call: its 7 phases' start times (the
        running sum of their durations, added in turn as ``np.cumsum`` adds them), jerks, and the
        acceleration, speed and position at each start, made as the rows of one array."""
        return Profile(*np.array(self._phases()), self.traj.duration)

    def _phases(self) -> list[list[float]]:
        """The rows of :meth:`profile` as lists of floats."""
        pr = self.traj.profiles[0][0]
        return [list(accumulate(pr.t[:-1], initial=0.0)), pr.j, pr.a[:-1], pr.v[:-1], pr.p[:-1]]

    def _kept(self, keep: bool | str) -> Profile | None:
        """What a request gives of the last successful :meth:`duration` call: nothing (``keep`` false),
        its :class:`Phases` (``keep`` :data:`PHASES`: no arrays made) or its :class:`Profile`."""
        if not keep:
            return None
        if keep is PHASES:
            return Phases(*self._phases(), self.traj.duration)
        return self.profile()

    def line(self, span, v0: float, v1: float, keep: bool | str) -> tuple[float, Profile | None]:
        """(duration, profile) of a ``span`` of straight lines at least :data:`MICRO` long: :meth:`time`
        for its single cap (no lower caps: a line's limits do not depend on its speed), without its
        general steps (the same requests, so the same numbers).  Raises :class:`ProfileError` as
        :meth:`time` does."""
        length, vc, acc, jerk = span.length, span.vc, span.acc, span.jerk
        if acc > 0 and jerk > 0:
            a, b = (v0 if v0 <= vc else vc), (v1 if v1 <= vc else vc)   # min(v0, vc), min(v1, vc)
            for scale in (1.0, EDGE_SCALE):
                d = self.duration(length, a, b, vc, acc * scale, jerk * scale)
                if d < math.inf:
                    return d, self._kept(keep)
        raise ProfileError(f"no profile for a {length:.6g} mm span from {v0:.6g} to {v1:.6g} mm/s")

    def rest_to_rest(self, span, keep: bool | str) -> tuple[float, Profile | None]:
        """(duration, profile) of a straight ``span`` from rest to rest: :meth:`time` for a line's
        single cap with both speeds 0, without its general steps (the same requests to ruckig, so
        the same numbers; a G50 program stops at every block).  Raises :class:`ProfileError` as
        :meth:`time` does."""
        length, vc = span.length, span.vc
        if length < MICRO:
            prof = micro_profile(length, 0.0, 0.0, span.acc, span.jerk, keep)
            if isinstance(prof, Profile):
                return prof.duration, prof
            return prof, None
        acc, jerk = span.acc, span.jerk
        if not (acc <= 0 or jerk <= 0):   # as time() tests them (a NaN limit goes to ruckig)
            for scale in (1.0, EDGE_SCALE):   # as time(): the limits a billionth lower on a second try
                d = self.duration(length, _REST, _REST, vc, acc * scale, jerk * scale)
                if d < math.inf:
                    return d, self._kept(keep)
        raise ProfileError(f"no profile for a {length:.6g} mm span from rest to rest")

    def time(self, span, v0: float, v1: float, keep: bool | str) -> tuple[float, float, Profile | None]:
        """(duration, cap used, profile) of a span from v0 to v1 (the profile as :meth:`_kept` gives it).

        Curved spans try a few lower caps: below its cap a curve leaves more of
        the axes' acceleration for speeding up and slowing down.
        """
        if span.length < MICRO:
            prof = micro_profile(span.length, v0, v1, span.acc, span.jerk, keep)
            if isinstance(prof, Profile):
                return prof.duration, span.vc, prof
            if prof is not None:
                return prof, span.vc, None
        top = v0 if v0 >= v1 else v1   # max(v0, v1) (the first of equal ones), without a call
        if span.curves and span.vc >= top:   # its caps from the top one down to top: walked as made
            return self._curved(span, v0, v1, top, keep)
        return self._ladder(span, v0, v1, top, keep)

    def _ladder(self, span, v0: float, v1: float, top: float,
                keep: bool | str) -> tuple[float, float, Profile | None]:
        """:meth:`time`'s general steps: the rungs of ``span.rungs`` at least ``top`` (and a cap just
        above ``top``) made first, then tried from the highest down."""
        rungs = span.rungs(top)
        if span.curved:
            rungs = [r for r in rungs if r[0] >= top]
            if top > 0 and top * (1 + 1e-9) < rungs[-1][0]:
                cap = top * (1 + 1e-9)
                rungs.append((cap, *span.limits_at(cap)))
        best = (math.inf, span.vc, 0.0, 0.0)
        held = False   # whether the trajectory holds the best profile (the last one solved)
        length = span.length
        for scale in (1.0, EDGE_SCALE):
            for vc, acc, jerk in rungs:
                if best[0] * RUNG_MARGIN <= length / vc:
                    # no motion below this cap (nor below the lower caps after it) is shorter than
                    # length / vc: the best found stands, and ruckig is not asked
                    break
                if acc <= 0 or jerk <= 0:
                    continue
                acc, jerk = acc * scale, jerk * scale
                d = self.duration(span.length, min(v0, vc), min(v1, vc), vc, acc, jerk)
                held = d < best[0]
                if held:
                    best = (d, vc, acc, jerk)
            if best[0] < math.inf:
                break
        if best[0] == math.inf:
            raise ProfileError(f"no profile for a {span.length:.6g} mm span from {v0:.6g} to {v1:.6g} mm/s")
        if not keep:
            return best[0], best[1], None
        if not held:
            _d, vc, acc, jerk = best   # solve the best again so that the trajectory holds it
            self.duration(span.length, min(v0, vc), min(v1, vc), vc, acc, jerk)
        return best[0], best[1], self._kept(keep)

    def _curved(self, span, v0: float, v1: float, top: float,
                keep: bool | str) -> tuple[float, float, Profile | None]:
        """:meth:`_ladder` of a group with curves whose cap is at least ``top``: the same caps tried in
        the same order (the group's cap, the ladder's while at least ``top``, then a cap just above
        ``top`` when it is lower than the last), each made as the walk reaches it and each rung's
        limits only when the rung is tried (``span.rung``: the group's own list, as ``span.rungs``
        makes it), so the same profile."""
        cap = span.vc
        last = len(LADDER)   # the index of the lowest rung; the cap above top is tried as index last + 1
        extra_limits = None
        best, best_vc, best_acc, best_jerk = math.inf, cap, 0.0, 0.0
        bound = math.inf   # best * RUNG_MARGIN, made when best changes
        held = False
        length = span.length
        rungs = span._rungs   # the rungs the look-ahead made already (read here, made by span.rung)
        made = 0 if rungs is None else len(rungs)
        for scale in (1.0, EDGE_SCALE):
            i, vc = 0, cap
            while True:
                if bound <= length / vc:
                    break   # as in _ladder(): no motion below this cap is shorter than length / vc
                if i < made:
                    _cap, acc, jerk = rungs[i]
                elif i <= last:
                    _cap, acc, jerk = span.rung(i)
                else:
                    if extra_limits is None:
                        extra_limits = span.limits_at(vc)
                    acc, jerk = extra_limits
                if not (acc <= 0 or jerk <= 0):
                    if scale != 1.0:   # x * 1.0 is x: the first pass asks with the limits as they are
                        acc, jerk = acc * scale, jerk * scale
                    # min(v0, vc), min(v1, vc) as comparisons (the same objects, no call per rung)
                    d = self.duration(length, v0 if v0 <= vc else vc, v1 if v1 <= vc else vc, vc, acc, jerk)
                    held = d < best
                    if held:
                        best, best_vc, best_acc, best_jerk = d, vc, acc, jerk
                        bound = d * RUNG_MARGIN
                # the next cap: the ladder's while at least top, then once the cap just above top
                if i < last and (nxt := cap * LADDER[i]) >= top:
                    i, vc = i + 1, nxt
                elif i <= last and top > 0 and (nxt := top * (1 + 1e-9)) < vc:
                    i, vc = last + 1, nxt
                else:
                    break
            if best < math.inf:
                break
        if best == math.inf:
            raise ProfileError(f"no profile for a {length:.6g} mm span from {v0:.6g} to {v1:.6g} mm/s")
        if not keep:
            return best, best_vc, None
        if not held:   # solve the best again so that the trajectory holds it
            vc = best_vc
            self.duration(length, min(v0, vc), min(v1, vc), vc, best_acc, best_jerk)
        return best, best_vc, self._kept(keep)
