"""The timing stage's shortcuts give exactly what the general forms give: the solver's rungs of a group
of curves (Solver._curved) as its general ladder (Solver.time over span.rungs), and a profile's phases
as lists (Phases) as its arrays (Profile), on the groups and speeds the planner asks for on a contour
of arcs under G05 and HSC; a group's reach (Group.reach, its rungs made as it goes down) as the rungs
of Group.rungs give it."""

from __future__ import annotations

import importlib
import sys
from pathlib import Path

import numpy as np
import pytest

import fagorcnc
from fagorcnc.plan import Planner
from fagorcnc.plan.limits import Terms, tangential
from fagorcnc.plan.lookahead import reachable
from fagorcnc.plan.profile import PHASES, Phases, Profile, ProfileError, Solver
from fagorcnc.plan.span import LADDER, Group
from fagorcnc.simulate import Run

_BENCH = Path(__file__).resolve().parents[1] / "benchmarks"
if str(_BENCH) not in sys.path:
    sys.path.insert(0, str(_BENCH))
plan_speed = importlib.import_module("plan_speed")


class _Recording(Solver):
    """A solver that keeps every (group, v0, v1) it is asked to time."""

    def __init__(self) -> None:
        super().__init__()
        self.asked: list[tuple] = []

    def time(self, span, v0: float, v1: float, keep: bool):
        self.asked.append((span, v0, v1))
        return super().time(span, v0, v1, keep)


class _Ladder(Solver):
    """A solver that takes the general ladder (span.rungs, Solver._ladder) for groups of curves too."""

    def _curved(self, span, v0: float, v1: float, top: float, keep: bool):
        return self._ladder(span, v0, v1, top, keep)


def _asked(mode: str) -> list[tuple]:
    machine = fagorcnc.load_machine(None)
    text = ["G90 G1 X40 Y0 Z0 F3000", {"G05": "G05", "HSC": "#HSC ON [CONTERROR 0.01]"}[mode],
            *plan_speed.contour_pass(), "M30"]
    planner = Planner(machine)
    planner.solver = solver = _Recording()
    assert sum(1 for _ in planner.segments(Run(iter(text), "<contour>", machine))) > 120
    return solver.asked


def _timed(group, v0: float, v1: float, keep: bool, solver: type[Solver] = Solver) -> tuple | None:
    """A fresh solver's (duration, cap, profile) of the request, None when it finds no profile."""
    try:
        return solver().time(group, v0, v1, keep)
    except ProfileError:
        return None


def _same(a: tuple | None, b: tuple | None) -> None:
    if a is None:
        assert b is None
        return
    assert a[:2] == b[:2]
    if a[2] is None:
        assert b[2] is None
        return
    for x, y in zip((a[2].t, a[2].j, a[2].a, a[2].v, a[2].p), (b[2].t, b[2].j, b[2].a, b[2].v, b[2].p), strict=True):
        assert np.array_equal(x, y)
    assert a[2].duration == b[2].duration


@pytest.mark.parametrize("mode", ["G05", "HSC"])
@pytest.mark.parametrize("keep", [False, True])
def test_the_rungs_of_a_group_of_curves_as_its_general_ladder(mode, keep):
    asked = [(g, v0, v1) for g, v0, v1 in _asked(mode) if g.curves]
    assert len(asked) > 60
    lower = 0
    for group, v0, v1 in asked:
        for w0, w1 in ((v0, v1), (v1, v0), (0.0, v1), (v0, 0.0), (0.5 * v0, v1)):
            fast = _timed(group, w0, w1, keep)
            lower += fast is not None and fast[1] < group.vc
            _same(fast, _timed(group, w0, w1, keep, _Ladder))
    assert lower > 0   # some below the top cap: the lower rungs were compared too


@pytest.mark.parametrize("mode", ["G05", "HSC"])
def test_the_phases_as_lists_are_the_profile_s_arrays(mode):
    asked = [(g, v0, v1) for g, v0, v1 in _asked(mode) if len(g.members) > 1]
    assert len(asked) > 10
    lists = 0
    for group, v0, v1 in asked:
        d, vc, phases = Solver().time(group, v0, v1, PHASES)
        d2, vc2, profile = Solver().time(group, v0, v1, True)
        assert (d, vc) == (d2, vc2)
        if type(profile) is Profile:   # a micro profile is made as arrays either way
            lists += type(phases) is Phases
        rows = (phases.t, phases.j, phases.a, phases.v, phases.p)
        assert [list(x) for x in rows] == [x.tolist() for x in (profile.t, profile.j, profile.a, profile.v, profile.p)]
        assert phases.duration == profile.duration
        bounds = np.linspace(0.0, group.length, 7)[1:-1].tolist()
        assert phases.crossings(bounds) == profile.crossings(bounds)
        tau = np.linspace(0.0, profile.duration, 9)
        for x, y in zip(phases.at(tau), profile.at(tau), strict=True):
            assert np.array_equal(x, y)
    assert lists > 10


def _reach(group, v: float) -> float:
    """Group.reach down the ladder written over Group.rungs(v): the best speed reached, or the cap
    once one is reached within the length."""
    best = 0.0
    for c, a, j in group.rungs(v):
        if c < v or a <= 0 or j <= 0:
            break
        r = reachable(v, group.length, a, j)
        if r >= c:
            best = max(best, c)
            break
        best = max(best, r)
    return best if best > 0.0 else min(group.vc, v)


@pytest.mark.parametrize("mode", ["G05", "HSC"])
def test_the_reach_of_a_group_of_curves_as_its_rungs_give_it(mode):
    groups = [g for g, _v0, _v1 in _asked(mode) if g.curves]
    below = 0
    for group in groups:
        for f in (0.0, 0.1, 0.5, 0.8, 0.93, 0.99, 1.0):
            v = group.vc * f
            fresh = Group(group.members[0])   # no rungs made yet: reach makes them
            for m in group.members[1:]:
                fresh.add(m)
            got = fresh.reach(v)
            assert got == _reach(group, v)
            below += got < group.vc
    assert below > 0


def _tangential_both(terms: Terms, full: Terms, cap: float) -> None:
    """tangential() over ``terms`` (cross terms bounded by others left out) is tangential() over ``full``
    wherever its acceleration is positive, and at most 0 where that is not (no rung is tried there)."""
    got, want = tangential(terms, cap, 0.0, 0.0), tangential(full, cap, 0.0, 0.0)
    if want[0] > 0:
        assert got == want
    else:
        assert got[0] <= 0


@pytest.mark.parametrize("mode", ["G05", "HSC"])
def test_joined_terms_without_bounded_cross_terms_give_the_same_limits(mode):
    groups = [g for g, _v0, _v1 in _asked(mode) if len(g.curves) > 1]
    assert len(groups) > 10
    fewer = 0
    for group in groups:
        parts = [m.terms for m in group.curves]
        joined = Terms.joined(parts)
        full = Terms([t for p in parts for t in p.acc], [t for p in parts for t in p.cross],
                     [t for p in parts for t in p.jerk])
        assert joined.acc == full.acc and joined.jerk == full.jerk
        assert set(joined.cross) <= set(full.cross)
        fewer += len(joined.cross) < len(full.cross)
        for f in (1.0, *LADDER, 1.3, 0.5 * 1e-3, 1e-9):
            _tangential_both(joined, full, group.vc * f)
    assert fewer > 10   # bounded cross terms were left out


def test_cross_terms_left_out_are_bounded_by_one_kept():
    """On random terms with few distinct values (ties, equal bounds, duplicates, near-zero and negative
    numerators): the same limits at every cap, and every term left out bounded by a kept one."""
    rng = np.random.default_rng(11)
    for _ in range(400):
        n = int(rng.integers(1, 12))
        pick = lambda values: float(rng.choice(values))  # noqa: E731
        cross = [(pick([2e4, 5e4]), pick([0.0, 1e2, 3e2, 1e3, 5e5]), pick([0.01, 0.05, 0.2, 1.0])) for _ in range(n)]
        acc = [(pick([800.0, 1000.0]), pick([0.0, 0.05, 0.2]), pick([0.3, 0.7, 1.0])) for _ in range(n)]
        jerk = [(j, k, k3, pick([0.3, 1.0])) for j, k3, k in cross]
        joined = Terms.joined([Terms(acc, cross, jerk)])
        for t in cross:
            assert any(u[0] == t[0] and u[1] >= t[1] and u[2] >= t[2] for u in joined.cross)
        for cap in (*rng.uniform(0.0, 200.0, 8).tolist(), 1e-6, 1.0, 40.0):
            _tangential_both(joined, Terms(acc, cross, jerk), cap)
