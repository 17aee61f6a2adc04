"""The planner's shortcuts for straight lines give exactly (to the bit) what its general steps give."""

from __future__ import annotations

import math

import numpy as np
import pytest

import fagorcnc
from fagorcnc.plan import Planner
from fagorcnc.plan.geometry import LinePiece
from fagorcnc.plan.limits import AxisLimits, line_limits
from fagorcnc.plan.profile import ProfileError, Solver
from fagorcnc.plan.span import Group, Span
from fagorcnc.simulate import Run


class _Src:
    line = 7


class _Rec:
    src = _Src()


LIMITS = AxisLimits((100.0, 80.0, 50.0), (1000.0, 800.0, 600.0), (20000.0, 15000.0, math.inf))


def _lines(n: int, seed: int = 3) -> list[LinePiece]:
    rng = np.random.default_rng(seed)
    out = [LinePiece(np.zeros(3), np.array([10.0, 0.0, 0.0])), LinePiece(np.zeros(3), np.array([0.0, -3.0, 0.0]))]
    for _ in range(n):
        a, b = rng.normal(size=3) * 20.0, rng.normal(size=3) * 20.0
        b[rng.integers(3)] = a[rng.integers(3)] if rng.random() < 0.3 else b[0]
        out.append(LinePiece(a, b))
    return out


@pytest.mark.parametrize("path", [(0.0, 0.0), (700.0, 9000.0)])
def test_a_line_span_has_the_limits_of_the_general_span(path):
    # e.g. the X line of 10 mm at feed 150 mm/s: cap min(150, 100 / 1) = 100, acceleration 1000 / 1 = 1000 (700
    # with a path limit of 700), jerk 20000 / 1 (9000 with a path limit); the same floats as Span.refresh
    rec = _Rec()
    for piece in _lines(200):
        general = Span(piece, rec, 150.0, LIMITS, False, None, *path)
        line = Span.of_line(piece, rec, 150.0, LIMITS, False, None, *path)
        assert (line.vc, line.acc, line.jerk) == (general.vc, general.acc, general.jerk)
        assert (line.vc, line.acc, line.jerk) == line_limits(piece.d1.tolist(), LIMITS, 150.0, *path)
        for name in Span.__slots__:
            assert getattr(line, name) == getattr(general, name), name
    x = Span.of_line(_lines(0)[0], _Rec(), 150.0, LIMITS, False, None, 700.0, 9000.0)
    assert (x.vc, x.acc, x.jerk) == (100.0, 700.0, 9000.0)


@pytest.mark.parametrize("keep", [False, True])
def test_rest_to_rest_is_the_general_solution(keep):
    """Solver.rest_to_rest asks ruckig what Solver.time asks of a line's group from 0 to 0 (the
    micro closed form below 1e-3 mm): the same duration and profile, to the bit."""
    lengths = [2e-4, 9.99e-4, 1e-3, 0.05, 0.5, 5.0, 5.0 * math.sqrt(2.0), 73.1]
    for length in lengths:
        piece = LinePiece(np.zeros(3), np.array([length, 0.0, 0.0]))
        span = Span.of_line(piece, _Rec(), 120.0, LIMITS, False, None, 0.0, 0.0)
        duration, profile = Solver().rest_to_rest(span, keep)
        d, _vc, p = Solver().time(Group(span), 0.0, 0.0, keep)
        assert duration == d
        assert (profile is None) == (p is None) == (not keep)
        if keep:
            for a, b in zip((profile.t, profile.j, profile.a, profile.v, profile.p),
                            (p.t, p.j, p.a, p.v, p.p), strict=True):
                assert np.array_equal(a, b)
    # 50 mm at 100 mm/s, A 1000, J 20000: ramps of dv/A + A/J = 0.15 s over 7.5 mm, cruise 35 mm in 0.35 s
    span = Span.of_line(LinePiece(np.zeros(3), np.array([50.0, 0.0, 0.0])), _Rec(), 150.0, LIMITS, False, None,
                        0.0, 0.0)
    assert Solver().rest_to_rest(span, keep)[0] == pytest.approx(0.65, rel=1e-12)


def test_rest_to_rest_without_limits_fails_as_time_does():
    span = Span.of_line(LinePiece(np.zeros(3), np.array([5.0, 0.0, 0.0])), _Rec(), 150.0,
                        AxisLimits((100.0,) * 3, (0.0,) * 3, (1.0,) * 3), False, None, 0.0, 0.0)
    with pytest.raises(ProfileError):
        Solver().rest_to_rest(span, False)
    with pytest.raises(ProfileError):
        Solver().time(Group(span), 0.0, 0.0, False)


def _program() -> list[str]:
    """Lines under G50 (a stop at every block), a rapid, a dwell, an M function and a short G05 run."""
    rng = np.random.default_rng(5)
    out = ["G90 G1 X0 Y0 Z0 F3000"]
    for i in range(60):
        x, y, z = rng.uniform(-50, 50, size=3)
        out.append(f"{'G0' if i % 17 == 3 else 'G1'} X{x:.4f} Y{y:.4f} Z{z:.4f}")
        if i % 11 == 5:
            out.append("G4 K0.1" if i % 2 else "M8")
    out += ["X0 Y0 Z0", "X0.0004", "X0.0009 Y0.0002", "G05", "X10 Y10", "X20 Y5", "X25 Y25", "G50", "X0 Y0", "M30"]
    return out


@pytest.mark.parametrize("keep", [False, True])
def test_the_planner_shortcut_plans_what_its_general_steps_plan(monkeypatch, keep):
    """With Solver.rest_to_rest failing every time the planner takes its general steps for every
    line (group, look-ahead, Solver.time): the same segments, to the bit."""
    machine = fagorcnc.load_machine(None)
    records = list(Run(iter(_program()), "<lines>", machine))

    def plan() -> list[tuple]:
        return [(s.kind, s.t0, s.duration, s.v0, s.v1, s.line, s.blend,
                 None if s.profile is None else s.profile.at(np.array([0.0, s.duration / 3]))[1].tolist())
                for s in Planner(machine, keep_profiles=keep).segments(iter(records))]

    original, used = Solver.rest_to_rest, []

    def counted(self, span, keep):
        used.append(span.length)
        return original(self, span, keep)

    monkeypatch.setattr(Solver, "rest_to_rest", counted)
    fast = plan()
    assert len(used) > 50 and min(used) < 1e-3   # the shortcut ran, the micro closed form too

    def fails(self, span, keep):
        raise ProfileError("the general path")

    monkeypatch.setattr(Solver, "rest_to_rest", fails)
    general = plan()
    assert len(fast) == len(general) > 60
    assert fast == general


@pytest.mark.parametrize("keep", [False, True])
def test_a_line_group_is_timed_as_the_general_solution(keep):
    """Solver.line asks ruckig what Solver.time asks of a group of lines (its single cap): the same
    duration and profile to the bit, for speeds the look-ahead gives (reachable) and a few it does not."""
    from fagorcnc.plan.lookahead import reachable

    rng = np.random.default_rng(11)
    pieces = _lines(40, seed=8)
    for i, piece in enumerate(pieces):
        group = Group(Span.of_line(piece, _Rec(), 120.0, LIMITS, False, None, 0.0, 0.0))
        if i % 3 == 0:   # two members (a group of short lines is timed as one motion)
            group.add(Span.of_line(pieces[i - 1], _Rec(), 90.0, LIMITS, False, None, 0.0, 0.0))
        v0 = float(rng.uniform(0.0, group.vc))
        v1 = min(group.vc, reachable(v0, group.length, group.acc, group.jerk)) * float(rng.uniform(0.2, 1.0))
        if i % 7 == 0:
            v1 = group.vc * 2.0   # above the cap: both ask ruckig with the cap
        try:
            d, _vc, p = Solver().time(group, v0, v1, keep)
        except ProfileError:
            with pytest.raises(ProfileError):
                Solver().line(group, v0, v1, keep)
            continue
        duration, profile = Solver().line(group, v0, v1, keep)
        assert duration == d
        if keep:
            assert all(np.array_equal(a, b) for a, b in zip((profile.t, profile.j, profile.a, profile.v, profile.p),
                                                          (p.t, p.j, p.a, p.v, p.p), strict=True))
        else:
            assert profile is None is p
    # a 10 mm X line from 0 to 50 mm/s at A 1000, J 20000: a ramp of dv/A + A/J = 0.1 s over 2.5 mm, the
    # remaining 7.5 mm at 50 mm/s (the cap is 100 mm/s but there is no room to reach it and come down)...
    # not needed: the time equals ruckig's, checked above; here only that a too-short request fails
    short = Group(Span.of_line(LinePiece(np.zeros(3), np.array([0.01, 0.0, 0.0])), _Rec(), 120.0, LIMITS, False,
                               None, 0.0, 0.0))
    with pytest.raises(ProfileError):   # 0 -> 100 mm/s needs (v0 + v1)/2 T = 50 x 2 sqrt(100 / 20000) = 7.07 mm
        Solver().line(short, 0.0, 100.0, keep)


@pytest.mark.parametrize("keep", [False, True])
def test_the_planner_line_groups_plan_what_the_general_steps_plan(monkeypatch, keep):
    """With Solver.line failing every time, every group of lines takes _time's general steps: the
    same segments under G05 (lines between corner curves, groups of short lines) and G50."""
    machine = fagorcnc.load_machine(None)
    rows = []
    for r in range(3):   # a 3D finishing raster (0.5 mm steps) under G05, then a few lines under G50
        xs = [i * 0.5 for i in range(41)]
        rows += [f"X{x:.4f} Y{r:.4f} Z{2 * np.sin(x / 7) * np.cos(r / 9):.4f}" for x in (xs[::-1] if r % 2 else xs)]
    program = ["G90 G1 X0 Y0 Z0 F3000", "G05", *rows, "X30 Y10 F6000", "X31 Y10.2", "X60 Y-5", "G50", *_program()[1:]]
    records = list(Run(iter(program), "<g05>", machine))

    def plan() -> list[tuple]:
        return [(s.kind, s.t0, s.duration, s.v0, s.v1, s.line, s.blend,
                 None if s.profile is None else s.profile.at(np.array([0.0, s.duration / 3]))[1].tolist())
                for s in Planner(machine, keep_profiles=keep).segments(iter(records))]

    original, used = Solver.line, []

    def counted(self, span, v0, v1, keep):
        used.append(v0 + v1)
        return original(self, span, v0, v1, keep)

    monkeypatch.setattr(Solver, "line", counted)
    fast = plan()
    assert len(used) > 5 and max(used) > 0   # taken, also while moving (most G05 groups hold a corner curve)

    def fails(self, span, v0, v1, keep):
        raise ProfileError("the general path")

    monkeypatch.setattr(Solver, "line", fails)
    general = plan()
    assert len(fast) == len(general) > 200
    assert fast == general


@pytest.mark.parametrize("keep", [False, True])
def test_curved_groups_make_only_the_rungs_they_try(monkeypatch, keep):
    """Solver.time tries a curved group's caps from the highest down, each rung's limits made when
    tried (Group.rung): the same plan as with every rung made first (Solver._curved taking the
    general steps, Solver._ladder), on arcs under G50 and G05 corner curves; and fewer rungs made."""
    machine = fagorcnc.load_machine(None)
    rows = []
    for r in range(2):
        xs = [i * 0.5 for i in range(41)]
        rows += [f"X{x:.4f} Y{r:.4f} Z{2 * np.sin(x / 7) * np.cos(r / 9):.4f}" for x in (xs[::-1] if r % 2 else xs)]
    program = ["G90 G1 X0 Y0 Z0 F3000", "G2 X10 Y0 I5 J0", "G3 X20 Y0 I5 J0 F6000", "G2 X21 Y1 I0 J1",
               "G1 X25 Y1", "G2 X25 Y-1 I0 J-1", "G05", "G1 X0 Y0", *rows, "G3 X30 Y10 I5 J5", "G2 X40 Y0 I5 J-5",
               "M30"]
    records = list(Run(iter(program), "<arcs>", machine))
    made = []
    original_tangential = Group._tangential

    def counted(self, cap):
        made.append(cap)
        return original_tangential(self, cap)

    monkeypatch.setattr(Group, "_tangential", counted)

    def plan() -> list[tuple]:
        return [(s.kind, s.t0, s.duration, s.v0, s.v1, s.line, s.blend,
                 None if s.profile is None else s.profile.at(np.array([0.0, s.duration / 3]))[1].tolist())
                for s in Planner(machine, keep_profiles=keep).segments(iter(records))]

    lazy = plan()
    lazy_made = len(made)
    made.clear()
    monkeypatch.setattr(Solver, "_curved", lambda self, span, v0, v1, top, keep: self._ladder(span, v0, v1, top, keep))
    general = plan()
    assert len(lazy) == len(general) > 100
    assert lazy == general
    assert lazy_made < len(made)


def test_g07_waits_in_position_after_every_stop():
    # three lines under G07 with INPOSW 0.25 s: a wait after each of the two corners and after the last
    # line, 3 x 0.25 = 0.75 s more than the same lines under G50 (which stops without the wait)
    machine = {"planner": {"inposition_time": 0.25}}
    program = "G90 G{} G1 X10 F6000\nX10 Y10\nX0 Y10\nM30\n"
    g07, g50 = (fagorcnc.simulate(program.format(m), machine) for m in ("07", "50"))
    assert g07.ok and g50.ok
    assert g07.cycle_time - g50.cycle_time == pytest.approx(0.75, abs=1e-9)
    waits = [s for s in g07.segments() if s.kind == "dwell"]
    assert [w.duration for w in waits] == [0.25, 0.25, 0.25]
