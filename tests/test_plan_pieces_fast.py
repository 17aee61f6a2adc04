"""The planner's pieces made with less work give exactly what the general forms give: an arc's parts
made at once (ArcPiece.pieces, Span.parts) and its bounds from the data its parts share, as the
one-by-one forms (ArcPiece.sub, Span.part) and the arrays; a line's d1 made on first use; the
solver's requests as a fresh solver answers them; the planner's limits of a block as it asks them."""

from __future__ import annotations

import math
from itertools import pairwise

import numpy as np
import pytest

import fagorcnc
from fagorcnc.plan import Planner
from fagorcnc.plan.geometry import ArcPiece
from fagorcnc.plan.span import Span

#: (start, end, centre, sweep): a plane arc, a helix, a spiral (radii differ), a clockwise 3/4 turn.
ARCS = [
    ((10.0, 0.0, 0.0), (0.0, 10.0, 0.0), (0.0, 0.0), math.pi / 2),
    ((10.0, 0.0, 0.0), (0.0, 10.0, 3.0), (0.0, 0.0), math.pi / 2),
    ((10.0, 0.0, -1.0), (0.0, 10.05, 2.5), (0.0, 0.0), math.pi / 2),
    ((5.0, 0.0, 0.0), (0.0, -5.0, -0.7), (0.0, 0.0), -1.5 * math.pi),
]


def arc(case: tuple) -> ArcPiece:
    start, end, centre, sweep = case
    return ArcPiece(np.array(start), np.array(end), 0, 1, centre, sweep)


def same_piece(a: ArcPiece, b: ArcPiece) -> None:
    """Every number of the two pieces identical (their points, parameter, bounds, speed factor)."""
    assert a.start.tolist() == b.start.tolist() and a.end.tolist() == b.end.tolist()
    assert (a.theta0, a.r0, a.length, a._ends, a.w, a.dr) == (b.theta0, b.r0, b.length, b._ends, b.w, b.dr)
    assert a.bound_lists() == b.bound_lists()
    assert a.speed_factor() == b.speed_factor()


def cut_lists(length: float) -> list[list[float]]:
    """The planner's even cuts (whose last is length * n / n, not always length itself), and
    cuts with ends inside and at the arc's ends."""
    even = [[length * i / n for i in range(n + 1)] for n in (1, 2, 3, 7, 10)]
    return [*even, [0.0, 0.3 * length, length], [0.1 * length, 0.5 * length, 0.9 * length],
            [0.0, 0.0, 0.4 * length, length, length]]


@pytest.mark.parametrize("case", ARCS)
def test_pieces_are_the_subs_between_the_cuts(case):
    whole = arc(case)
    for cuts in cut_lists(whole.length):
        made = whole.pieces(cuts)
        assert len(made) == len(cuts) - 1
        for piece, (s0, s1) in zip(made, pairwise(cuts), strict=True):
            same_piece(piece, whole.sub(s0, s1))
            # the arc's own end points where a cut is at one of its ends, as sub keeps them
            assert (piece.start is whole.start) == (s0 == 0.0)
            assert (piece.end is whole.end) == (s1 == whole.length)


def test_pieces_share_the_point_at_a_cut_inside_the_arc():
    whole = arc(ARCS[1])
    made = whole.pieces([whole.length * i / 4 for i in range(5)])
    for a, b in pairwise(made):
        assert a.end is b.start


@pytest.mark.parametrize("case", ARCS)
def test_bounds_and_speed_factor_from_the_shared_data_are_those_of_the_arrays(case):
    """bound_lists, speed_factor and point read the floats the arc and its parts share (``_lin``): the
    numbers the arc's ``lin`` array gives and the axes off its plane, for the arc, its subs and theirs."""
    whole = arc(case)
    for piece in (whole, whole.sub(0.25 * whole.length, whole.length),
                  whole.sub(0.1, whole.length - 0.2).sub(0.3, 1.5)):
        lin = piece.lin.tolist()
        off = tuple(i for i in range(len(lin)) if i not in (piece.ia, piece.io))
        assert piece._lin == (lin, [abs(x) for x in lin], sum(x * x for x in lin), off)
        d1 = piece.bound_lists()[0]
        assert [d1[i] for i in range(len(lin)) if i not in (piece.ia, piece.io)] == \
            [abs(x) for i, x in enumerate(lin) if i not in (piece.ia, piece.io)]
        rmax = max(piece.r0, piece.r0 + piece.dr * piece.length)
        assert piece.speed_factor() == math.sqrt((piece.dr ** 2 + (rmax * piece.w) ** 2) +
                                                 sum(x * x for x in lin))


@pytest.mark.parametrize("case", ARCS)
def test_span_parts_settle_to_the_limits_of_the_parts_one_by_one(case):
    planner = Planner(fagorcnc.load_machine(None))
    lim = planner._axis_limits(None, False)
    span = Span(arc(case), None, 80.0, lim, False, None, 0.0, 0.0, later=True)
    cuts = [span.length * i / 3 for i in range(4)]
    parts = span.parts(cuts)
    singles = [span.part(s0, s1, later=True) for s0, s1 in pairwise(cuts)]
    for got, want in zip(parts, singles, strict=True):
        assert got.stale and want.stale and got.length == want.length
        got.settle()
        want.settle()
        assert (got.vc, got.acc, got.jerk, got.feed, got.lim) == (want.vc, want.acc, want.jerk, want.feed, want.lim)
        same_piece(got.piece, want.piece)


def test_a_long_arc_is_planned_in_the_parts_of_its_cuts():
    """The planner's long arc: as many parts as 30 degree steps, the same segments as parts made one by
    one would give (the parts are the subs of the cuts, above), from the arc's start to its end."""
    from fagorcnc.simulate import Run

    machine = fagorcnc.load_machine(None)
    program = ["G90 G1 X10 Y0 Z0 F2000", "G3 X-10 Y0 I-10 J0", "G2 X10 Y0 Z1 I10 J0 F1500", "M30"]
    records = list(Run(program, "arc.nc", machine))
    segments = [s for s in Planner(machine).segments(records) if s.kind == "motion"]
    arcs = [s for s in segments if s.piece.curved]
    assert len(arcs) == 12   # two half turns, six 30 degree parts each
    for a, b in pairwise(arcs[:6]):
        assert a.piece.end is b.piece.start and a.t0 + a.duration == pytest.approx(b.t0)
    assert arcs[0].piece.start.tolist() == [10.0, 0.0, 0.0]
    assert arcs[5].piece.end.tolist() == pytest.approx([-10.0, 0.0, 0.0], abs=1e-12)


def reference_bounds(piece: ArcPiece) -> tuple[list[float], list[float], list[float]]:
    """An arc's derivative bounds written out as the formulas read (q_a = rho cos th, q_o = rho sin th)."""
    from fagorcnc.plan.geometry import _range_max

    r1, sweep = piece._ends
    ms, mc = _range_max(piece.theta0, piece.theta0 + sweep)
    rmax, dr, w = max(piece.r0, r1), abs(piece.dr), abs(piece.w)
    d1 = [abs(x) for x in piece.lin.tolist()]
    d2, d3 = [0.0] * len(d1), [0.0] * len(d1)
    ia, io = piece.ia, piece.io
    d1[ia] = dr * mc + rmax * w * ms
    d1[io] = dr * ms + rmax * w * mc
    d2[ia] = 2 * dr * w * ms + rmax * w * w * mc
    d2[io] = 2 * dr * w * mc + rmax * w * w * ms
    d3[ia] = 3 * dr * w * w * mc + rmax * w ** 3 * ms
    d3[io] = 3 * dr * w * w * ms + rmax * w ** 3 * mc
    return d1, d2, d3


@pytest.mark.parametrize("case", ARCS)
def test_bound_lists_are_the_formulas_to_the_last_bit(case):
    whole = arc(case)
    rng = np.random.default_rng(27)
    for s0, s1 in [(0.0, whole.length), *np.sort(rng.uniform(0.0, whole.length, (20, 2)), axis=1).tolist()]:
        piece = whole.sub(s0, s1)
        assert piece.bound_lists() == reference_bounds(piece)


def test_the_solver_sets_again_only_what_ruckig_does_not_hold():
    """Solver.duration leaves a speed or length ruckig already holds: a solver asked many requests in turn
    (repeats, the same value as another float object, 0.0 after -0.0) answers each as a fresh solver."""
    from fagorcnc.plan.profile import Solver

    rng = np.random.default_rng(5)
    shared = Solver()
    requests = []
    for _ in range(300):
        v0, v1 = (float(x) if rng.random() < 0.6 else 0.0 for x in rng.uniform(0.0, 80.0, 2))
        requests.append((float(rng.uniform(0.5, 30.0)), v0, v1))
        if rng.random() < 0.3:
            requests.append(requests[-1])                                   # the same request again
        if rng.random() < 0.2:
            length, v0, v1 = requests[-1]
            # equal speeds that are other objects, and -0.0 for 0.0
            requests.append((length, float(str(v0)), -0.0 if v1 == 0.0 else float(str(v1))))
    for length, v0, v1 in requests:
        got = shared.duration(length, v0, v1, 90.0, 1000.0, 20000.0)
        assert got == Solver().duration(length, v0, v1, 90.0, 1000.0, 20000.0)
        if got < math.inf:   # ruckig was asked (a request too short is answered before): it holds this one
            held = (*shared.inp.current_velocity, *shared.inp.target_position, *shared.inp.target_velocity)
            assert [(x, math.copysign(1.0, x)) for x in held] == [(x, math.copysign(1.0, x)) for x in (v0, length, v1)]
    span = Span.__new__(Span)
    span.length, span.vc, span.acc, span.jerk = 12.5, 60.0, 800.0, 15000.0
    fresh = Solver().rest_to_rest(span, False)
    shared.duration(12.5, 30.0, 0.0, 60.0, 800.0, 15000.0)
    assert shared.rest_to_rest(span, False) == fresh == shared.rest_to_rest(span, False)


def test_a_lines_d1_made_when_asked_is_the_magnitude_of_its_direction():
    from fagorcnc.plan.geometry import LinePiece

    line = LinePiece(np.array([1.0, -2.0, 0.5]), np.array([-3.0, 4.0, 0.5]))
    part = line.sub(0.5, 2.0)
    for piece in (part, line, line.sub(0.0, line.length).sub(1.0, 3.0)):
        assert piece.d1.tolist() == np.abs(piece.u).tolist() == [abs(x) for x in piece.ul]
        assert piece.d1 is piece.d1   # made once
    part.d1 = np.array([0.25, 0.5, 0.0])   # set as any piece's bounds (corner curves narrow theirs)
    assert part.d1.tolist() == [0.25, 0.5, 0.0] and line.d1.tolist() == np.abs(line.u).tolist()
    span = Span(LinePiece(np.zeros(3), np.array([3.0, 4.0, 0.0])), None, 50.0, lim(), False, None)
    assert (span.vc, span.acc, span.jerk) == (50.0, 1000.0 / 0.8, 20000.0 / 0.8)   # refresh reads d1


def lim():
    return Planner(fagorcnc.load_machine(None))._axis_limits(None, False)


def test_the_planner_takes_the_limits_of_each_block_as_it_asks_them():
    """_span reuses the limits of the block before when it has the same dynamics and rapid flag: every
    span has the limits _axis_limits gives for its own block (rapids and feeds, two dynamics)."""
    from fagorcnc.simulate import Run

    machine = fagorcnc.load_machine(None)
    program = ["G90 G1 X10 Y0 F2000", "G0 X20 Y5", "G1 X30", "G05", "G1 X40", "G0 X0", "G1 Y10",
               "G0 Y0", "M30"]
    planner = Planner(machine)
    spans = [s for s in planner._spans(Run(program, "limits.nc", machine)) if isinstance(s, Span)]
    assert len(spans) == 7 and len({id(s.dyn) for s in spans}) == 2
    fresh = Planner(machine)
    for span in spans:
        assert span.lim is planner._axis_limits(span.dyn, span.rapid)
        assert span.lim == fresh._axis_limits(span.dyn, span.rapid)


class FailingFirst:
    """A solver whose time() refuses the first request for each end speed in ``refuse`` (as ruckig
    may at an edge of its profile types), recording every request; the rest go to the real solver."""

    def __init__(self, solver, refuse: int) -> None:
        self.solver, self.refuse, self.asked = solver, refuse, []

    def __getattr__(self, name):
        return getattr(self.solver, name)

    def time(self, span, v0, v1, keep):
        from fagorcnc.plan.profile import ProfileError

        self.asked.append(v1)
        if len(self.asked) <= self.refuse:
            raise ProfileError("refused")
        return self.solver.time(span, v0, v1, keep)


@pytest.mark.parametrize("refuse", [1, 2])
def test_a_curve_refused_by_ruckig_goes_on_with_the_lower_end_speeds_in_turn(refuse):
    """_commit times a group of curves with solver.time at its end speed, then (refused) with _time's
    next end speeds in turn: v1, v1 (1 - 1e-9), v1 (1 - 1e-6), ... each asked once, as _time alone asks."""
    from fagorcnc.plan.planner import SHRINKS
    from fagorcnc.simulate import Run

    machine = fagorcnc.load_machine(None)
    program = ["G90 G1 X10 Y0 F2000", "G3 X0 Y10 I-10 J0", "M30"]
    planner = Planner(machine)
    planner.solver = FailingFirst(planner.solver, refuse)
    segments = [s for s in planner.segments(list(Run(program, "arc.nc", machine))) if s.kind == "motion"]
    asked = planner.solver.asked
    v1 = asked[0]
    assert asked[:refuse + 1] == [v1 * (1.0 - shrink) for shrink in SHRINKS[:refuse + 1]]
    first_part = next(s for s in segments if s.piece.curved)
    assert first_part.v1 == v1 * (1.0 - SHRINKS[refuse]) and first_part.v1 < v1


def test_range_max_takes_the_larger_end_as_max_does():
    """_range_max's ends compared without max(): the same floats as max() of the ends' |sin| and |cos|
    (or 1 where the interval holds the extremum), over random intervals in either order."""
    import math

    from fagorcnc.plan.geometry import _range_max

    rng = np.random.default_rng(12)
    for _ in range(2000):
        a, b = rng.uniform(-10.0, 10.0), rng.uniform(-10.0, 10.0) * rng.choice([1.0, 1e-3])
        lo, hi = min(a, a + b), max(a, a + b)
        ms = 1.0 if any(lo <= math.pi / 2 + k * math.pi <= hi for k in range(-5, 5)) else \
            max(abs(math.sin(lo)), abs(math.sin(hi)))
        mc = 1.0 if any(lo <= k * math.pi <= hi for k in range(-5, 5)) else max(abs(math.cos(lo)), abs(math.cos(hi)))
        assert _range_max(a, a + b) == (ms, mc)
