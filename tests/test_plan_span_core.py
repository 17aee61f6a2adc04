"""The planner's per-span shortcuts give what the general steps give (issue 27, item 1).

- ``Solver.duration`` tests the stop-on-the-way length only when the single pulse is too long;
- ``Group._tangential`` keeps its path limits until a member is added;
- ``Planner._commit`` takes 0 as the end speed of a group that stops, without asking its reach, and the
  backward pass's limit as the end speed of a group entered at least that fast (but curves without a
  jerk limit).
"""

from __future__ import annotations

import math
import random

import numpy as np
import pytest
from plan_helpers import reference_duration as _reference
from test_plan_limits import contour_pass

import fagorcnc
from fagorcnc.plan import Planner
from fagorcnc.plan.geometry import ArcPiece, LinePiece
from fagorcnc.plan.limits import AxisLimits, tangential
from fagorcnc.plan.profile import Solver, _pulse
from fagorcnc.plan.span import Group, Span
from fagorcnc.simulate import Run

LIMITS = AxisLimits((100.0, 100.0, 50.0), (1000.0, 1000.0, 600.0), (20000.0, 20000.0, 9000.0))


class _Rec:
    class src:   # noqa: N801 (a record's source line)
        line = 7


def test_duration_between_the_stop_and_the_single_pulse():
    # one speed far below the other: a stop on the way is shorter than the single pulse, so lengths
    # between the two pass the first test and only the second one decides (both answers exercised)
    rng = random.Random(2027)
    solver = Solver()
    between = refused = 0
    for _ in range(600):
        acc, jerk = rng.uniform(200.0, 3000.0), rng.uniform(800.0, 5e4)
        v0, v1 = rng.uniform(60.0, 200.0), rng.uniform(0.5, 15.0)
        if rng.random() < 0.5:
            v0, v1 = v1, v0
        direct = _pulse(v0, v1, acc, jerk)
        stop = _pulse(v0, 0.0, acc, jerk) + _pulse(0.0, v1, acc, jerk)
        low, high = min(direct, stop), max(direct, stop)
        length = rng.uniform(low * 0.97, high * 1.01)
        between += stop < length < direct
        got = solver.duration(length, v0, v1, max(v0, v1) * 1.3, acc, jerk)
        assert got == _reference(length, v0, v1, max(v0, v1) * 1.3, acc, jerk), (length, v0, v1, acc, jerk)
        refused += got == math.inf
    assert between > 50 and 20 < refused < 580


def _arc(start: np.ndarray, sweep: float) -> ArcPiece:
    end = np.array([math.cos(sweep) * 5.0, math.sin(sweep) * 5.0, start[2] + 0.2])
    return ArcPiece(start, end, 0, 1, (0.0, 0.0), sweep)


def test_a_groups_path_limits_follow_the_members_added():
    # a curve, then a line whose axis limits are lower (Z): the group's tangential limits below a cap
    # take the line's acceleration and jerk from the moment it joins, as computed afresh
    curve = Span(_arc(np.array([5.0, 0.0, 0.0]), 0.3), _Rec(), 80.0, LIMITS, False, None, 0.0, 0.0)
    group = Group(curve)
    cap = curve.vc * 0.8
    assert group.limits_at(cap) == tangential(curve.terms, cap, math.inf, math.inf)
    line = Span.of_line(LinePiece(curve.piece.end, curve.piece.end + np.array([0.0, 0.0, 1.0])), _Rec(), 80.0,
                        LIMITS, False, None, 0.0, 0.0)
    group.add(line)
    assert line.acc == 600.0 and line.jerk == 9000.0
    cap = group.vc * 0.8   # below the line's cap too
    assert group.limits_at(cap) == tangential(curve.terms, cap, 600.0, 9000.0)
    assert group.limits_at(cap) != tangential(curve.terms, cap, math.inf, math.inf)


def _plan(program: list[str], jerk: bool) -> list[tuple]:
    machine = fagorcnc.load_machine(None)
    records = list(Run(iter(program), "<stops>", machine))
    return [(s.kind, s.line, s.t0, s.duration, s.v0, s.v1, s.blend)
            for s in Planner(machine, jerk=jerk).segments(iter(records))]


@pytest.mark.parametrize("jerk", [True, False])
def test_a_stopping_group_ends_at_rest_without_its_reach(monkeypatch, jerk):
    """The end speed of a group that stops is min(reach, 0): 0, as a reach is never negative.  Every
    reach the planner asks (lines, arcs in parts, corner curves, stops at G07 corners and M functions)
    is at least 0, and every group that stops ends at 0."""
    program = ["G90 G1 X0 Y0 Z0 F3000", "G07", "G2 X10 Y0 I5 J0", "G1 X10 Y5", "M5", "G3 X0 Y5 I-5 J0 F6000",
               "G05", "G1 X0 Y10", "G2 X10 Y10 I5 J0", "G1 X20 Y10.5", "G2 X20 Y20 I0 J5", "X0 Y20", "G50",
               "G2 X0 Y30 I0 J5", "G1 X1 Y30.5", "M30"]
    fast = _plan(program, jerk)
    asked: list[tuple[float, float, bool]] = []
    base = Group.reach

    def reach(self, v):
        out = base(self, v)
        asked.append((v, out, self.stop_after))
        return out

    monkeypatch.setattr(Group, "reach", reach)
    again = _plan(program, jerk)
    assert fast == again and len(fast) > 15
    assert all(out >= 0.0 for _v, out, _stop in asked)
    assert sum(stop for *_x, stop in asked) >= 3   # stopping groups were asked (by the backward pass)
    ends = [s for s in fast if s[0] == "motion" and s[5] == 0.0]
    assert len(ends) >= 4


def test_a_reach_is_never_negative():
    # the premise of the shortcut, on random lines and arcs, limits and speeds (jerk limited or not)
    rng = random.Random(11)
    for _ in range(400):
        jerk = rng.choice([rng.uniform(500.0, 5e4), math.inf])
        lim = AxisLimits((100.0, 100.0, 50.0), (rng.uniform(50.0, 3000.0),) * 3, (jerk,) * 3)
        if rng.random() < 0.5:
            end = np.array([rng.uniform(-5, 5), rng.uniform(-5, 5), rng.uniform(-1, 1)])
            span = Span.of_line(LinePiece(np.zeros(3), end), _Rec(), rng.uniform(1.0, 200.0), lim, False, None,
                                0.0, 0.0)
        else:
            span = Span(_arc(np.array([5.0, 0.0, 0.0]), rng.uniform(0.01, 1.0)), _Rec(), rng.uniform(1.0, 200.0), lim,
                        False, None, 0.0, 0.0)
        v = rng.choice([0.0, rng.uniform(0.0, 1.5 * span.vc)])
        assert Group(span).reach(v) >= 0.0


def _random_span(rng: random.Random, jerk: float) -> Span:
    lim = AxisLimits((100.0, 100.0, 50.0), (rng.uniform(50.0, 3000.0),) * 3, (jerk,) * 3)
    if rng.random() < 0.5:
        end = np.array([rng.uniform(-5, 5), rng.uniform(-5, 5), rng.uniform(-1, 1)])
        return Span.of_line(LinePiece(np.zeros(3), end), _Rec(), rng.uniform(1.0, 200.0), lim, False, None, 0.0, 0.0)
    return Span(_arc(np.array([5.0, 0.0, 0.0]), rng.uniform(0.01, 1.0)), _Rec(), rng.uniform(1.0, 200.0), lim,
                False, None, 0.0, 0.0)


def test_a_reach_is_at_least_the_speed_within_the_cap():
    # the premise of _commit's end speed without the reach: from v a group reaches at least min(v, cap)
    # (the speed it has, or its cap), on random groups of lines and arcs, jerk-limited or lines alone
    rng = random.Random(12)
    for _ in range(600):
        jerk = rng.uniform(500.0, 5e4)
        group = Group(_random_span(rng, jerk))
        for _ in range(rng.randrange(3)):
            group.add(_random_span(rng, jerk))
        if rng.random() < 0.25:   # lines without a jerk limit
            group = Group(Span.of_line(LinePiece(np.zeros(3), np.array([rng.uniform(0.01, 5.0), 1.0, 0.0])), _Rec(),
                                       rng.uniform(1.0, 200.0), AxisLimits((100.0,) * 3, (800.0,) * 3, (math.inf,) * 3),
                                       False, None, 0.0, 0.0))
        for v in (0.0, rng.uniform(0.0, group.vc), group.vc, rng.uniform(group.vc, 2.0 * group.vc)):
            assert group.reach(v) >= min(v, group.vc), (v, group.vc)


@pytest.mark.parametrize("jerk", [True, False])
def test_the_end_speed_without_the_reach_is_the_general_one(monkeypatch, jerk):
    """Every end speed _commit times a group with is min(reach(v), limit) of its start speed v and the
    backward pass's limit at its end (0 for a group that stops), also where it takes the limit
    without asking the reach; and that limit is within the cap of the group before the junction."""
    from fagorcnc.plan import planner as planner_module
    from fagorcnc.plan.profile import Solver

    # the benchmarks' contour (arcs and lines at small kinks) in G05, then in HSC, and a raster of lines
    program = ["G90 G1 X40 Y0 Z0 F3000", "G05", *contour_pass(60), "#HSC ON [CONTERROR 0.01]", *contour_pass(60),
               "G1 Z1", *(f"X{40 + 0.5 * (k % 20):.1f} Y{0.4 * (k // 20):.1f} Z{1 + 0.1 * (k % 3):.1f}"
                          for k in range(60)), "M30"]
    base = planner_module.backward
    after: dict[int, float] = {}   # the limit after each group (by id) of the last backward pass

    def backward(queue, end_speed, known):
        out = base(queue, end_speed, known)
        for i, g in enumerate(queue):
            after[id(g)] = out[i + 1] if i + 1 < len(queue) else 0.0
            assert i + 1 == len(queue) or out[i + 1] <= g.vc
        return out

    timed: list[tuple[float, float, float]] = []   # (general end speed, end speed timed with, start speed)

    def check(group, v0, v1):
        general = 0.0 if group.stop_after else min(base_reach(group, v0), after[id(group)])
        timed.append((general, v1, v0))

    base_reach, line, time = Group.reach, Solver.line, Solver.time
    monkeypatch.setattr(planner_module, "backward", backward)
    monkeypatch.setattr(Solver, "line", lambda self, g, v0, v1, k: (check(g, v0, v1), line(self, g, v0, v1, k))[1])
    monkeypatch.setattr(Solver, "time", lambda self, g, v0, v1, k: (check(g, v0, v1), time(self, g, v0, v1, k))[1])
    _plan(program, jerk)
    assert len(timed) > 100
    assert all(general == v1 for general, v1, _v0 in timed)
    assert sum(v0 >= v1 > 0.0 for _g, v1, v0 in timed) > 30   # groups the shortcut times (entered fast enough)


def test_a_profile_has_the_phases_of_the_general_arrays():
    # Solver.profile's start times (a running sum in turn) and phase values, as the rows of one array, are
    # those of np.cumsum and one array per row, to the bit, on random requests
    rng = random.Random(13)
    solver = Solver()
    made = 0
    for _ in range(300):
        v0, v1 = rng.uniform(0.0, 80.0), rng.uniform(0.0, 80.0)
        if solver.duration(rng.uniform(0.5, 20.0), v0, v1, 100.0, rng.uniform(200.0, 3000.0),
                           rng.uniform(1e3, 5e4)) == math.inf:
            continue
        made += 1
        pr = solver.traj.profiles[0][0]
        got = solver.profile()
        assert got.t.tolist() == np.concatenate([[0.0], np.cumsum(pr.t)])[:-1].tolist()
        for mine, theirs in ((got.j, pr.j), (got.a, pr.a[:-1]), (got.v, pr.v[:-1]), (got.p, pr.p[:-1])):
            assert mine.tolist() == np.array(theirs).tolist()
        assert got.duration == solver.traj.duration and got.at(np.array([got.duration / 2]))[0].shape == (1,)
    assert made > 200
