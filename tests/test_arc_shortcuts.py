"""Shortcuts of the batches of corners at arcs (fagorcnc.plan.shortcuts): the arcs a batch trims at
both ends (arc_trims, cut_arc) get the very bounds and limits each trimmed arc makes itself, the turn
estimate of a corner (turn_estimate) is within far less than its margin of the angle between the
tangents _junction tests, and the planner plans the same with them."""

from __future__ import annotations

import math
import operator

import numpy as np
import pytest
from test_corner_batch import _contour, _corners
from test_plan_batches import _plan_floats

from fagorcnc.plan.geometry import ArcPiece, LinePiece, arc_bound_rows
from fagorcnc.plan.shortcuts import TURN_MARGIN, sharpest_turn, turn_estimate


def test_bound_rows_of_stretches_are_each_stretchs_bounds():
    """arc_bound_rows of stretches of arcs (helices and spirals in the three planes, both turning
    ways; stretches of stretches, an end kept, a whole arc as a stretch of itself) from their start
    angle, radius and length is what each stretch's bound_lists gives, to the bit."""
    ps, qs = _corners(17, 150)
    arcs = [p for p in (*ps, *qs) if isinstance(p, ArcPiece)]
    family, stretches = [], []
    for a in arcs:
        half = a.sub(0.25 * a.length, a.length)
        for s in (a.sub(0.0, a.length), a.sub(0.1 * a.length, 0.7 * a.length), a.sub(0.0, 0.3 * a.length),
                  half, half.sub(0.0, 0.5 * half.length)):
            family.append(a)
            stretches.append(s)
    rows = arc_bound_rows(family, [s.theta0 for s in stretches], [s.r0 for s in stretches],
                          [s.length for s in stretches])
    assert len(stretches) >= 400
    for i, s in enumerate(stretches):
        assert [r[i].tolist() for r in rows] == list(s.bound_lists())


@pytest.mark.parametrize("plane", ["G17", "G18", "G19"])
@pytest.mark.parametrize("mode", ["HSC", "#HSC ON [FAST 80, E0.02, CORNER 165]", "#ROUNDPAR [1, 0.01]",
                                  "#ROUNDPAR [4, 0.005]"])
def test_arcs_trimmed_with_a_batch_plan_as_the_general_path(monkeypatch, mode, plane):
    """Arcs given their stretch's bounds and limits by the batch that trims them (cut_arc) plan to the
    very floats of arcs that make their own (Span.refresh), on a contour with HSC splines between its
    lines, a feed change, a helix, a long arc in parts and (CORNER 165) sharp edges: most arcs take
    the batch's, and an arc whose start the batch did not trim as it took it makes its own."""
    import fagorcnc
    from fagorcnc.plan import junctions, shortcuts
    from fagorcnc.plan.span import Span
    from fagorcnc.simulate import Run

    machine = fagorcnc.load_machine(None)
    program = _contour(mode, plane)
    if mode.startswith("#HSC ON [FAST"):
        program = [mode if line.startswith("#HSC") else line for line in _contour("HSC", plane)]
    records = list(Run(iter(program), "<contour>", machine))
    refreshed, cuts = [], []
    refresh, cut_arc = Span.refresh, junctions.cut_arc

    def counted_refresh(span):
        refreshed.append(span)
        refresh(span)

    def counted_cut(span, keep, known):
        before = len(refreshed)
        cut_arc(span, keep, known)
        cuts.append(len(refreshed) == before)

    monkeypatch.setattr(Span, "refresh", counted_refresh)
    monkeypatch.setattr(junctions, "cut_arc", counted_cut)
    quick = _plan_floats(machine, records)
    if "CORNER" in mode:   # sharp edges stop most corners: the arcs after them are trimmed at one end only
        assert 1 <= sum(cuts) < len(cuts)
    else:
        assert sum(cuts) >= 8
    monkeypatch.setattr(shortcuts, "arc_trims", lambda *args: ([], [], [], [], [], []))
    cuts.clear()
    general = _plan_floats(machine, records)
    assert not cuts and quick == general


def _tangent_turn(p, q) -> float:
    """The angle between the unit tangents _junction tests (the end of p, the start of q), by a formula
    exact at every angle (acos loses digits near 0, where _junction tests the tangents' distance)."""
    pu, qu = p.tangent_list(p.length), q.tangent_list(0.0)
    return 2.0 * math.atan2(math.dist(pu, qu), math.hypot(*map(operator.add, pu, qu)))


def _flat_arc(rng: np.random.Generator, at: np.ndarray, starts_there: bool, plane: tuple[int, int]) -> ArcPiece:
    """An arc (sometimes a spiral, either way round) in ``plane`` that starts or ends at ``at``."""
    ia, io = plane
    r, th = rng.uniform(0.5, 30.0), rng.uniform(-math.pi, math.pi)
    sweep = rng.uniform(0.01, 2.0) * rng.choice([-1.0, 1.0])
    centre = (at[ia] - r * math.cos(th), at[io] - r * math.sin(th))
    r1 = r * (1.0 + rng.uniform(-0.002, 0.002) * (rng.random() < 0.3))
    far = at.copy()
    th1 = th + (sweep if starts_there else -sweep)
    far[ia], far[io] = centre[0] + r1 * math.cos(th1), centre[1] + r1 * math.sin(th1)
    return ArcPiece(at.copy(), far, ia, io, centre, sweep) if starts_there else ArcPiece(far, at.copy(), ia, io,
                                                                                          centre, sweep)


def test_the_turn_estimate_is_the_angle_between_the_tangents():
    """Over lines and arcs (spirals among them, trimmed ones, both ways round) meeting in each plane at
    every turn from almost none to almost a reversal, the estimate is within 1e-12 rad of the angle
    between the unit tangents (a hundredth of its margin and more); NaN where a piece leaves the
    plane (a helix, a line along another axis) or two arcs lie in different planes."""
    rng = np.random.default_rng(23)
    seen = 0
    for plane in ((0, 1), (2, 0), (1, 2)):
        off = 3 - plane[0] - plane[1]
        for i in range(300):
            at = rng.uniform(-50.0, 50.0, 3)
            p = _flat_arc(rng, at, False, plane)
            if i % 3 == 1:
                p = LinePiece(at - rng.uniform(0.5, 5.0) * np.array(p.tangent_list(p.length)), at.copy())
            elif i % 3 == 2:
                p = p.sub(0.2 * p.length, p.length)
            turn = rng.choice([rng.uniform(1e-7, 1e-4), rng.uniform(0.0, math.pi - 1e-3)])
            a = math.atan2(*reversed([p.tangent_list(p.length)[k] for k in plane])) + turn * rng.choice([-1, 1])
            if i % 2:   # an arc after p that leaves at that angle
                q = _flat_arc(rng, at, True, plane)
                q = q.sub(0.0, q.length)   # its start angle moved by the one it had
                q.theta0 += a - math.atan2(*reversed([q.tangent_list(0.0)[k] for k in plane]))
            else:
                u = np.zeros(3)
                u[plane[0]], u[plane[1]] = math.cos(a), math.sin(a)
                q = LinePiece(at.copy(), at + rng.uniform(0.5, 5.0) * u)
            if type(p) is ArcPiece or type(q) is ArcPiece:
                assert abs(turn_estimate(p, q) - _tangent_turn(p, q)) <= 1e-12
                seen += 1
            up = at.copy()
            up[off] += 1.0
            assert math.isnan(turn_estimate(_flat_arc(rng, at, False, plane), LinePiece(at.copy(), up)))
    assert seen >= 600
    helix = _corners(3, 30)[0]
    helices = [h for h in helix if isinstance(h, ArcPiece) and h._lin[2] > 0.0]
    assert helices and all(math.isnan(turn_estimate(h, LinePiece(h.end, h.end + 1.0))) for h in helices)
    at = np.zeros(3)
    assert math.isnan(turn_estimate(_flat_arc(rng, at, False, (0, 1)), _flat_arc(rng, at, True, (2, 0))))
    assert TURN_MARGIN >= 1e4 * 1e-12


def test_the_sharpest_turn_rounded_leaves_the_margin():
    """sharpest_turn: the turn of the least included angle rounded less the margin, and no turn at all
    (every corner tested on its tangents) where that turn is too small for acos to be known to 1e-12."""
    assert sharpest_turn(1.0) == math.radians(179.0) - TURN_MARGIN
    assert sharpest_turn(150.0) == math.radians(30.0) - TURN_MARGIN
    assert sharpest_turn(180.0) <= 0.0 and sharpest_turn(179.99999) <= 0.0
