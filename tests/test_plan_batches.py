"""The planner's batched computations give what the one-by-one ones give (to round-off)."""

from __future__ import annotations

import pickle
from itertools import pairwise

import numpy as np
import pytest

from fagorcnc.plan.blend import BlendPiece, BlendRow, arc_tables, blend_rows, blends, corner_deviations, curve_bounds
from fagorcnc.plan.corners import SHAPE, deviation, line_corners
from fagorcnc.plan.geometry import ArcPiece, LinePiece
from fagorcnc.plan.limits import (
    AxisLimits,
    Terms,
    axis_terms,
    curve_limits,
    line_limits,
    piece_cap,
    tangential,
    tangential_arrays,
)
from fagorcnc.plan.profile import Profile, Solver, micro_profile

TOL = 1e-12


def unit_rows(rng: np.random.Generator, n: int, spread: float) -> np.ndarray:
    """n + 1 unit directions, each turning from the one before by about ``spread`` radians."""
    u = np.cumsum(rng.normal(scale=spread, size=(n + 1, 3)), axis=0) + np.array([1.0, 0.2, -0.1])
    return u / np.linalg.norm(u, axis=1)[:, None]


def close(a, b, tol: float = TOL) -> bool:
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    return bool(np.all(np.abs(a - b) <= tol * np.maximum(1.0, np.abs(b))))


def _record_calls(monkeypatch, cls, name: str) -> list:
    """Wrap the method ``cls.name`` for the test: the list it returns receives what each call returns."""
    original = getattr(cls, name)
    results: list = []

    def recorded(self, *args):
        result = original(self, *args)
        results.append(result)
        return result

    monkeypatch.setattr(cls, name, recorded)
    return results


@pytest.mark.parametrize("spread", [0.002, 0.05, 0.6])
def test_line_corners_in_a_batch_equal_one_by_one(spread):
    u = unit_rows(np.random.default_rng(1), 40, spread)
    batch = line_corners(u[:-1], u[1:])
    for i, got in enumerate(batch):
        alone = line_corners(u[i:i + 1], u[i + 1:i + 2])[0]
        assert (got is None) == (alone is None)
        if got is not None:
            assert all(close(x, y) for x, y in zip(got, alone, strict=True))


def test_line_corner_table_is_the_arc_length_of_its_curve():
    # the closed form |B'|² = 25 (A² + C² + 2 A C cos) against the curve's own integral
    u = unit_rows(np.random.default_rng(2), 30, 0.4)
    for shape, a, b in zip(line_corners(u[:-1], u[1:]), u[:-1], u[1:], strict=True):
        if shape is not None:
            curve = BlendPiece(-a, a, np.zeros(3), SHAPE, b, b, np.zeros(3), SHAPE)
            assert close(shape.table, arc_tables(curve.controls[None])[0])
            assert close(shape.controls, curve.controls)


def _random_corners(rng, n: int):
    """n random corner curves' data: unit directions (n + 1 rows), start and end points, curvatures
    and the end parameters, as the batches take them."""
    u = unit_rows(rng, n, 0.3)
    p0 = rng.uniform(-50.0, 50.0, (n, 3))
    p5 = p0 + rng.uniform(0.1, 2.0, (n, 1)) * u[1:]
    k0, k5 = rng.normal(scale=0.3, size=(n, 3)), rng.normal(scale=0.3, size=(n, 3))
    a, b = rng.uniform(0.05, 0.5, n), rng.uniform(0.05, 0.5, n)
    return u, p0, p5, k0, k5, a, b


def test_blends_in_a_batch_equal_one_by_one():
    rng = np.random.default_rng(3)
    n = 25
    u, p0, p5, k0, k5, a, b = _random_corners(rng, n)
    curves, samples = blends(p0, u[:-1], k0, a, p5, u[1:], k5, b)
    for i, got in enumerate(curves):
        alone = BlendPiece(p0[i], u[i], k0[i], a[i], p5[i], u[i + 1], k5[i], b[i])
        assert got.valid == alone.valid
        assert close(got.controls, alone.controls) and close(got.length, alone.length)
        if alone.valid:
            assert all(close(x, y) for x, y in ((got.d1, alone.d1), (got.d2, alone.d2), (got.d3, alone.d3)))
            assert close(samples[:, :, i], alone.points(97))


def test_blend_rows_give_each_curves_own_validity_and_bounds():
    # what an HSC spline batch reads from the arrays (which curves are valid, their bounds) is each
    # curve's own valid and d1, d2, d3, a degenerate one (a curve folding back on itself) included
    rng = np.random.default_rng(5)
    n = 12
    u, p0, p5, k0, k5, a, b = _random_corners(rng, n)
    t0, t5 = u[:-1].copy(), u[1:].copy()
    p5[3], t0[3], t5[3], k0[3], k5[3], a[3], b[3] = p0[3], (1.0, 0.0, 0.0), (-1.0, 0.0, 0.0), 0.0, 0.0, 1.0, 1.0
    curves, samples, valid, (d1, d2, d3) = blend_rows(p0, t0, k0, a, p5, t5, k5, b)
    plain, plain_samples = blends(p0, t0, k0, a, p5, t5, k5, b)
    assert valid.tolist() == [c.valid for c in curves] == [c.valid for c in plain]
    assert not valid[3] and valid.sum() == n - 1
    assert np.array_equal(samples, plain_samples, equal_nan=True)
    for i, c in enumerate(curves):
        assert np.array_equal(d1[i], c.d1) and np.array_equal(d2[i], c.d2) and np.array_equal(d3[i], c.d3)
        assert np.array_equal(c.controls, plain[i].controls) and c.length == plain[i].length



def test_a_batch_curve_is_the_blend_piece_made_of_its_rows():
    # a BlendRow (its end, control points and table made when first asked) is BlendPiece.made of the
    # batch's rows: the same arrays, the same length, points and derivatives along it
    rng = np.random.default_rng(11)
    u, p0, p5, k0, k5, a, b = _random_corners(rng, 6)
    curves, _, _, (d1, d2, d3) = blend_rows(p0, u[:-1], k0, a, p5, u[1:], k5, b)
    s = np.array([0.0, 0.1, 0.3])
    for i, got in enumerate(curves):
        assert type(got) is BlendRow and isinstance(got, BlendPiece)
        controls = got._batch[0][i]
        made = BlendPiece.made(controls, controls[0], controls[-1], d1[i], d2[i], d3[i], got._batch[1][i],
                               float(got._batch[1][i][-1]))
        end = got.end
        assert got.end is end and got.controls is got.controls and got.table_s is got.table_s   # made once
        for name in ("start", "end", "controls", "d1", "d2", "d3", "table_s", "table_u"):
            assert np.array_equal(getattr(got, name), getattr(made, name)), name
        assert got.length == made.length and got.valid == made.valid
        ss = s * got.length
        assert all(np.array_equal(x, y) for x, y in zip(got.derivatives(ss), made.derivatives(ss), strict=True))
    back = pickle.loads(pickle.dumps(curves[1]))   # its own rows alone, as a BlendPiece
    assert type(back) is BlendPiece and back.length == curves[1].length
    assert all(np.array_equal(getattr(back, name), getattr(curves[1], name))
               for name in ("start", "end", "controls", "d1", "d2", "d3", "table_s", "table_u"))
    got = curves[0]
    got.end = np.zeros(3)   # set as any piece's
    assert np.array_equal(got.end, np.zeros(3))
    assert not hasattr(got, "no_such_array") and getattr(got, "no_such_array", None) is None



@pytest.mark.parametrize("dim", [1, 2, 3, 5, 8])
def test_dot_products_over_rows_of_curves_are_einsums_floats(dim):
    # blend._dot and corner_deviations sum the axes' products over whole rows of curves: to the bit
    # (signed zeros, infinities and cancellations included) einsum's sums, which they replace
    from fagorcnc.plan.blend import _axis_sums, _dot

    def bits(a):
        return np.ascontiguousarray(a).view(np.int64)

    rng = np.random.default_rng(dim)
    for n in (2, 3, 8, 63):
        x = rng.standard_normal((97, dim, n)) * 10.0 ** rng.uniform(-8, 8, (97, dim, n))
        y = rng.standard_normal((97, dim, n)) * 10.0 ** rng.uniform(-8, 8, (97, dim, n))
        x[rng.random(x.shape) < 0.3], y[rng.random(y.shape) < 0.3] = 0.0, -0.0
        x[rng.random(x.shape) < 0.02] = np.inf
        y[:, :, 0] = -x[:, ::-1, 0]   # sums that cancel
        w = y[5]
        with np.errstate(all="ignore"):
            assert np.array_equal(bits(_dot(x, y)), bits(np.einsum("id...,id...->i...", x, y)[:, None]))
            assert np.array_equal(bits(_axis_sums(x * w)), bits(np.einsum("idn,dn->in", x, w)))
    # one curve: einsum's own on two axes or fewer; on more, the floats it has in a batch (einsum adds a
    # single curve's axes in another order; the corner memo needs a curve's floats whatever its batch)
    x = rng.standard_normal((97, dim, 1))
    two = np.repeat(x, 2, axis=2)
    want = np.einsum("id...,id...->i...", x, x) if dim <= 2 else np.einsum("id...,id...->i...", two, two)[:, :1]
    assert np.array_equal(bits(_dot(x, x)), bits(want[:, None]))


def test_corner_deviations_are_the_einsum_deviations():
    rng = np.random.default_rng(8)
    for n in (1, 2, 40):
        u, p0, p5, k0, k5, a, b = _random_corners(rng, n)
        _, samples = blends(p0, u[:-1], k0, a, p5, u[1:], k5, b)
        vertex = (p0 + p5) / 2.0
        rel = samples - vertex.T
        rr = np.einsum("idn,idn->in", rel, rel)

        def to_segment(w, rel=rel, rr=rr):
            ww, rw = np.einsum("dn,dn->n", w, w), np.einsum("idn,dn->in", rel, w)
            share = np.minimum(np.maximum(rw / np.maximum(ww, 1e-300), 0.0), 1.0)
            return rr - share * (2.0 * rw - share * ww)

        gap = np.minimum(to_segment((p0 - vertex).T), to_segment((p5 - vertex).T))
        assert np.array_equal(corner_deviations(samples, p0, vertex, p5), np.sqrt(np.maximum(gap, 0.0).max(axis=0)))


def test_curve_bounds_without_the_points_are_the_same_floats():
    # the corner batches' bounds from the derivative rows alone are the full product's, to the bit,
    # for one curve, a few, and more than one matrix product holds (chunks), a degenerate one included
    from fagorcnc.plan.blend import _curve_bounds

    rng = np.random.default_rng(9)
    for n in (1, 5, 64, 130):
        controls = rng.normal(size=(n, 6, 3)) * 10.0 ** rng.uniform(-3.0, 2.0, (n, 1, 1)) + 500.0
        controls[0] = [[0, 0, 0], [1, 0, 0], [2, 0, 0], [2, 0, 0], [1, 0, 0], [0, 0, 0]]   # folds back
        _q, *full = _curve_bounds(controls)
        alone = curve_bounds(controls)
        assert all(np.array_equal(x, y) for x, y in zip(full, alone, strict=True))
        assert alone[3][0] and np.isinf(alone[2][0]).all()
        # without the tangents' bounds (a corner batch sizing its curves): the others the same
        d1, *rest = curve_bounds(controls, tangents=False)
        assert d1 is None and all(np.array_equal(x, y) for x, y in zip(full[1:], rest, strict=True))


def test_corner_deviations_equal_deviation_from_two_lines():
    rng = np.random.default_rng(4)
    n = 20
    u = unit_rows(rng, n, 0.4)
    vertex = rng.uniform(-20.0, 20.0, (n, 3))
    d1, d2 = rng.uniform(0.1, 1.0, n), rng.uniform(0.1, 1.0, n)
    p0, p5 = vertex - d1[:, None] * u[:-1], vertex + d2[:, None] * u[1:]
    curves, samples = blends(p0, u[:-1], np.zeros((n, 3)), 0.4 * d1, p5, u[1:], np.zeros((n, 3)), 0.4 * d2)
    devs = corner_deviations(samples, p0, vertex, p5)
    for i, curve in enumerate(curves):
        if curve.valid:
            p, q = LinePiece(p0[i], vertex[i]), LinePiece(vertex[i], p5[i])
            expected = deviation(BlendPiece.from_controls(curve.controls, curve.d1, curve.d2, curve.d3), p, q,
                                 d1[i], d2[i], False)
            assert devs[i] == pytest.approx(expected, rel=1e-9, abs=1e-15)


@pytest.mark.parametrize(("length", "v0", "v1"), [(5.0, 0.0, 0.0), (2.0, 30.0, 5.0), (0.3, 10.0, 13.0)])
def test_profile_crossings_reach_the_positions(length, v0, v1):
    solver = Solver()
    assert solver.duration(length, v0, v1, 60.0, 1000.0, 20000.0) < float("inf")
    profile = solver.profile()
    marks = sorted(np.random.default_rng(5).uniform(0.0, length, 30).tolist())
    times, speeds = profile.crossings(marks)
    s, v, _a, _j = profile.at(np.array(times))
    assert np.all(np.diff(times) >= 0.0)
    assert np.abs(s - marks).max() <= 1e-12 * length
    assert np.abs(v - speeds).max() <= 1e-9 * max(v0, v1, 1.0)


def test_line_limits_are_the_general_limits_without_curvature():
    lim = AxisLimits((100.0, 80.0, 50.0), (1000.0, 800.0, 600.0), (20000.0, 15000.0, float("inf")))
    zero = [0.0] * 3
    for d1 in ([0.6, 0.8, 0.0], [0.0, 0.0, 1.0], [0.3, 0.4, 0.866]):
        for path in ((0.0, 0.0), (500.0, 9000.0)):
            vc = piece_cap(d1, zero, zero, lim, 70.0)
            assert line_limits(d1, lim, 70.0, *path) == (vc, *tangential(axis_terms(d1, zero, zero, lim), vc, *path))


def test_curve_limits_are_the_cap_and_tangential_limits_of_the_axis_terms():
    # the fused form must give the very same numbers as the general one (no round-off allowed)
    rng = np.random.default_rng(6)
    for jerk in ((20000.0, 15000.0, 9000.0), (20000.0, float("inf"), 9000.0)):
        lim = AxisLimits((100.0, 80.0, 50.0), (1000.0, 800.0, 600.0), jerk)
        for _ in range(200):
            d1, d2, d3 = (rng.uniform(0.0, 1.0, 3) * rng.integers(0, 2, 3) for _ in range(3))
            d2, d3 = d2 * rng.choice([0.01, 1.0, 100.0]), d3 * rng.choice([0.01, 1.0, 1e4])
            d1, d2, d3 = d1.tolist(), d2.tolist(), d3.tolist()
            for path in ((0.0, 0.0), (500.0, 9000.0)):
                vc = piece_cap(d1, d2, d3, lim, 70.0)
                assert curve_limits(d1, d2, d3, lim, 70.0, *path) == (
                    vc, *tangential(axis_terms(d1, d2, d3, lim), vc, *path))


def _concatenated(parts: list[Terms]) -> Terms:
    """The terms of ``parts`` one after the other, every one kept (Terms.joined leaves out bounded cross terms)."""
    return Terms(*([t for p in parts for t in getattr(p, name)] for name in ("acc", "cross", "jerk")))


def test_tangential_over_arrays_gives_the_same_numbers():
    # a group of many short curves: the joined terms of 40 pieces, below several caps
    rng = np.random.default_rng(7)
    lim = AxisLimits((100.0, 80.0, 50.0), (1000.0, 800.0, 600.0), (20000.0, 15000.0, 9000.0))
    parts = [axis_terms(rng.uniform(0.0, 1.0, 3).tolist(), rng.uniform(0.0, 5.0, 3).tolist(),
                        rng.uniform(0.0, 500.0, 3).tolist(), lim) for _ in range(40)]
    terms = _concatenated(parts)
    assert terms.total() == 40 * 9
    joined = Terms.joined(parts)   # the cross terms another bounds left out
    assert joined.total() < terms.total()
    for vc in (0.0, 0.5, 3.0, 12.0, 40.0):
        for path in ((0.0, 0.0), (500.0, 9000.0)):
            for some in (terms, joined):
                assert tangential_arrays(some.arrays(), vc, *path) == tangential(some, vc, *path)
    empty = Terms([], [], [])
    assert tangential_arrays(empty.arrays(), 5.0, 300.0, 0.0) == tangential(empty, 5.0, 300.0, 0.0)


@pytest.mark.parametrize(("length", "v0", "v1"), [(4e-4, 20.0, 20.0), (4e-4, 20.0, 20.000001), (4e-4, 0.0, 0.0)])
def test_a_micro_profile_duration_alone_is_the_profile_duration(length, v0, v1):
    full = micro_profile(length, v0, v1, 1000.0, 20000.0)
    assert isinstance(full, Profile)
    assert micro_profile(length, v0, v1, 1000.0, 20000.0, keep=False) == full.duration


def test_an_hsc_transition_curve_is_measured_against_the_line_it_replaces():
    """Back from an HSC spline's curvature k to the straight line: the curve over [start, start + step] must stay within
    the tolerance of that stretch of line, and the longest step that does is taken (it used to be measured against
    the stretch from the step's end to the line's end, which is never closer than the step: only steps below the
    tolerance passed)."""
    from fagorcnc.plan.corners import transition_curve

    p = LinePiece(np.array([0.0, 0.0, 0.0]), np.array([8.0, 0.0, 0.0]))
    k = np.array([0.0, 0.02, 0.0])                 # curvature 0.02 /mm towards +Y at the start
    steps = [1.0, 0.5, 0.25, 0.125]
    (curve, step), made = transition_curve(p, k, steps, 0.01)
    assert made is None
    assert step == 1.0                             # far longer than the 0.01 mm tolerance
    pts = curve.points(400)
    assert np.abs(pts[:, 1]).max() <= 0.95 * 0.01 and pts[:, 0].min() >= -1e-12 and pts[:, 0].max() <= 1.0 + 1e-12
    assert np.allclose(curve.start, p.start) and np.allclose(curve.end, [1.0, 0.0, 0.0])
    tight, _ = transition_curve(p, k, steps, 1e-5)   # no step keeps 10 nm: the caller goes on with shorter ones
    assert tight is None or np.abs(tight[0].points(400)[:, 1]).max() <= 0.95e-5


def _raster_records(passes: int) -> list:
    """The records of a 3D finishing raster (0.5 mm steps) under HSC: its inflections stop some splines."""
    import fagorcnc
    from fagorcnc.simulate import Run

    rows = []
    for r in range(passes):
        xs = [i * 0.5 for i in range(101)]
        rows += [f"X{x:.4f} Y{r:.4f} Z{2 * np.sin(x / 7) * np.cos(r / 9):.4f}" for x in (xs[::-1] if r % 2 else xs)]
    program = ["G90 G1 X0 Y0 Z0 F3000", "#HSC ON [CONTERROR 0.01]", *rows, "M30"]
    return list(Run(iter(program), "<raster>", fagorcnc.load_machine(None)))


def test_a_rejected_hsc_spline_redoes_only_the_next_corner(monkeypatch):
    """Where an HSC spline does not fit the tolerance, the next corner's candidate (made on the
    assumption that it did) is made again alone; the plan is the one a whole new batch gives."""
    import fagorcnc
    from fagorcnc.plan import Planner

    machine = fagorcnc.load_machine(None)
    records = _raster_records(4)

    calls = _record_calls(monkeypatch, Planner, "_single")
    alone = [(s.t0, s.duration, s.v0, s.v1, s.line) for s in Planner(machine).segments(iter(records))]
    assert calls   # some corners do not take their spline

    def whole_batch(self, prev, nxt, d1, cached):   # what the planner did before: a new batch
        self._candidates.clear()
        self._batch(prev, nxt)
        return self._candidates.pop(id(nxt))

    monkeypatch.setattr(Planner, "_single", whole_batch)
    batched = [(s.t0, s.duration, s.v0, s.v1, s.line) for s in Planner(machine).segments(iter(records))]
    assert len(alone) == len(batched)
    for a, b in zip(alone, batched, strict=True):
        assert a[4] == b[4] and close(a[:4], b[:4])


def test_a_spline_candidate_made_with_the_transition_is_the_one_made_alone(monkeypatch):
    """Where an HSC spline does not fit, the transition curve after it and the next corner's candidate
    made again (:meth:`_single`) share one set of array operations: the very plan of each made alone."""
    import fagorcnc
    from fagorcnc.plan import Planner

    machine = fagorcnc.load_machine(None)
    records = _raster_records(6)
    taken = []
    single = Planner._single

    def counted(self, prev, nxt, d1, cached):
        taken.append(self._single_ahead is not None)
        return single(self, prev, nxt, d1, cached)

    monkeypatch.setattr(Planner, "_single", counted)
    shared = [(s.kind, s.line, s.t0, s.duration, s.v0, s.v1) for s in Planner(machine).segments(iter(records))]
    assert taken and all(taken)   # every corner made again was made with its transition
    monkeypatch.setattr(Planner, "_single_ahead_rows", lambda self, prev, dim: None)
    alone = [(s.kind, s.line, s.t0, s.duration, s.v0, s.v1) for s in Planner(machine).segments(iter(records))]
    assert shared == alone


@pytest.mark.parametrize("dim", [3, 4])
def test_blend_groups_are_each_group_made_alone(dim):
    """blend_groups makes several groups' curves with one set of bounds: each group's curves, bounds,
    tables and points are the very floats blends gives the group alone."""
    from fagorcnc.plan.blend import blend_groups

    rng = np.random.default_rng(dim)
    groups = []
    for n in (4, 1, 3):
        t0, t5 = (u / np.linalg.norm(u, axis=1)[:, None] for u in rng.normal(size=(2, n, dim)))
        k0, k5 = rng.normal(size=(n, dim)) * 0.1, rng.normal(size=(n, dim)) * 0.1
        p0 = rng.normal(size=(n, dim)) * 100.0
        a, b = rng.uniform(0.01, 2.0, n), rng.uniform(0.01, 2.0, n)
        groups.append((p0, t0, k0, a, p0 + rng.normal(size=(n, dim)), t5, k5, b))
    for (curves, samples), group in zip(blend_groups(groups), groups, strict=True):
        own, own_samples = blends(*group)
        assert np.array_equal(samples, own_samples, equal_nan=True)
        for c, o in zip(curves, own, strict=True):
            for name in ("controls", "start", "end", "d1", "d2", "d3", "table_s"):
                assert np.array_equal(getattr(c, name), getattr(o, name), equal_nan=True), name
            assert c.length == o.length


def test_blend_rows_made_in_one_loop_are_the_rows_of():
    """BlendRow.rows makes a batch's curves in one loop: each the curve BlendRow.of makes of its row."""
    rng = np.random.default_rng(3)
    n = 5
    p0, t0 = rng.normal(size=(n, 3)), unit_rows(rng, n - 1, 0.2)
    curves, _, _, (d1, d2, d3) = blend_rows(p0, t0, np.zeros((n, 3)), np.full(n, 0.3), p0 + 1.0, t0[::-1],
                                            np.zeros((n, 3)), np.full(n, 0.4))
    batch = curves[0]._batch
    for i, c in enumerate(curves):
        o = BlendRow.of(batch, i, batch[0][i, 0], d1[i], d2[i], d3[i], float(batch[1][i, -1]))
        for name in ("controls", "start", "end", "d1", "d2", "d3", "table_s", "table_u"):
            assert np.array_equal(getattr(c, name), getattr(o, name)), name
        assert c.length == o.length and c._row == o._row and c._coef is None and c.samples is None


def test_control_points_are_the_stacked_rows():
    """_controls writes the six control points into one array: the floats np.stack gave of the same rows,
    for one curve (spacings as floats) and for rows of curves (spacings as a column)."""
    from fagorcnc.plan.blend import _controls

    rng = np.random.default_rng(5)
    for shape, a, b in (((3,), 0.37, 1.9), ((7, 4), rng.uniform(0.1, 1.0, (7, 1)), rng.uniform(0.1, 1.0, (7, 1)))):
        p0, t0, k0, p5, t5, k5 = (rng.normal(size=shape) * 10.0 for _ in range(6))
        stacked = np.stack([p0, p0 + a * t0, p0 + 2 * a * t0 + 1.25 * a * a * k0,
                            p5 - 2 * b * t5 + 1.25 * b * b * k5, p5 - b * t5, p5], axis=-2)
        assert np.array_equal(_controls(p0, t0, k0, a, p5, t5, k5, b), stacked)


@pytest.mark.parametrize("spread", [0.002, 0.05, 0.6])
def test_line_corner_bounds_cover_the_curves_own_samples(spread):
    """The unit blends' bounds come from tabulated support functions of the curves turning by whole
    0.25 degree steps: not below the bounds the curve itself gives at its 97 samples (with the same
    margins) but for the interpolation between two steps (within 3e-3 of the largest axis, as with
    the sampled table before; the margins of 2 to 10 % cover it), and above them by at most a
    hundredth of the largest axis (directions in 1 degree)."""
    u = unit_rows(np.random.default_rng(11), 60, spread)
    for shape, a, b in zip(line_corners(u[:-1], u[1:]), u[:-1], u[1:], strict=True):
        if shape is None:
            continue
        curve = BlendPiece(-a, a, np.zeros(3), SHAPE, b, b, np.zeros(3), SHAPE)
        for got, own in ((shape.d1, curve.d1), (shape.d2, curve.d2), (shape.d3, curve.d3)):
            assert np.all(got >= own - 3e-3 * own.max())
            assert np.all(got <= own + 0.01 * own.max())


def test_line_corner_sizes_in_a_batch_equal_one_by_one():
    from fagorcnc.plan.corners import _line_corner, line_corner_arrays, line_corner_sizes

    rng = np.random.default_rng(12)
    u = unit_rows(rng, 30, 0.3)
    ends = rng.uniform(-20.0, 20.0, (30, 3))
    lim_p, lim_q = rng.uniform(0.01, 2.0, 30), rng.uniform(0.01, 2.0, 30)
    unit = line_corner_arrays(u[:-1], u[1:])
    for speed, tolerance, jerk in ((50.0, 0.01, 20000.0), (50.0, None, float("inf")), (None, 0.002, 9000.0),
                                   (500.0, 1e-7, 20000.0)):
        sizes = line_corner_sizes(unit, lim_p, lim_q, speed, tolerance, 800.0, jerk, corner=True)
        for i, size in enumerate(sizes.tolist()):
            p = LinePiece(ends[i] - 3.0 * u[i], ends[i])
            q = LinePiece(ends[i], ends[i] + 3.0 * u[i + 1])
            alone = _line_corner(p, q, lim_p[i], lim_q[i], tolerance, speed, 800.0, jerk, True, None)
            assert close(size, 0.0 if alone is None else alone[1])   # the lines' directions to round-off


def test_curve_limits_of_many_rows_equal_one_by_one():
    from fagorcnc.plan.limits import curve_limits_rows

    rng = np.random.default_rng(13)
    for jerk in ((20000.0, 15000.0, 9000.0), (20000.0, float("inf"), 9000.0)):
        lim = AxisLimits((100.0, 80.0, 50.0), (1000.0, 800.0, 600.0), jerk)
        d1, d2, d3 = (rng.uniform(0.0, 1.0, (200, 3)) * rng.integers(0, 2, (200, 3)) for _ in range(3))
        d2, d3 = d2 * rng.choice([0.01, 1.0, 100.0], (200, 1)), d3 * rng.choice([0.01, 1.0, 1e4], (200, 1))
        for path in ((0.0, 0.0), (500.0, 9000.0)):
            rows = curve_limits_rows(d1, d2, d3, lim, 70.0, *path)
            for i in range(200):
                alone = curve_limits(d1[i].tolist(), d2[i].tolist(), d3[i].tolist(), lim, 70.0, *path)
                np.testing.assert_allclose([r[i] for r in rows], alone, rtol=TOL, atol=0.0)


def test_term_arrays_give_the_limits_of_the_joined_terms():
    from fagorcnc.plan.limits import term_arrays

    rng = np.random.default_rng(14)
    for jerk in ((20000.0, 15000.0, 9000.0), (20000.0, float("inf"), 9000.0)):
        lim = AxisLimits((100.0, 80.0, 50.0), (1000.0, 800.0, 600.0), jerk)
        d1, d2, d3 = (rng.uniform(0.0, 1.0, (30, 3)) * rng.integers(0, 2, (30, 3)) for _ in range(3))
        d2, d3 = d2 * 5.0, d3 * 500.0
        terms = _concatenated([axis_terms(d1[i].tolist(), d2[i].tolist(), d3[i].tolist(), lim) for i in range(30)])
        arrays = term_arrays(d1, d2, d3, lim)
        assert sum(len(col[0]) for col in arrays) == terms.total()
        for vc in (0.0, 0.5, 3.0, 12.0, 40.0):
            for path in ((0.0, 0.0), (500.0, 9000.0)):
                assert tangential_arrays(arrays, vc, *path) == tangential(terms, vc, *path)


def _g05_program(roundpar: str, feeds: bool = False) -> list[str]:
    rows = []
    for r in range(4):   # a 3D raster, with ``feeds`` a feed change at every block (CAM feed optimisation)
        xs = [i * 0.5 for i in range(60)]
        for j, x in enumerate(xs[::-1] if r % 2 else xs):
            f = f" F{2000 + 1000 * (j % 3)}" if feeds else ""
            rows.append(f"X{x:.4f} Y{r:.4f} Z{2 * np.sin(x / 7) * np.cos(r / 9):.4f}{f}")
    return ["G90 G1 X0 Y0 Z0 F3000", roundpar, "G05", *rows, "G01 G108 X40 Y10", "G109 X45 Y10 F1000",
            "X50 Y12 F4000", "G193 X55 Y15 F2000", "X60 Y15", "#HSC ON [CONTERROR 0.01]", "X61 Y16", "X62 Y16.5",
            "#HSC OFF", "G05 X63 Y17.2", "X64 Y16", "M30"]


@pytest.mark.parametrize(("roundpar", "feeds"), [("#ROUNDPAR [1, 0.01]", False), ("#ROUNDPAR [2, 40]", True),
                                                 ("#ROUNDPAR [4, 0.002]", False), ("#ROUNDPAR [1, 0.05]", True)])
def test_g05_line_corners_in_a_batch_plan_as_one_by_one(monkeypatch, roundpar, feeds):
    """The G05 curves of a chain of lines made in one batch (sizes, curves, limits) give the plan
    the corners made one by one give; the batch is used for (nearly) every line corner, and a
    feed change does not end a batch (each corner has its own feed: batches of one corner each
    cost more than they save)."""
    import fagorcnc
    from fagorcnc.plan import Planner, junctions
    from fagorcnc.simulate import Run

    machine = fagorcnc.load_machine(None)
    records = list(Run(iter(_g05_program(roundpar, feeds)), "<g05>", machine))
    results = _record_calls(monkeypatch, Planner, "_line_blend")
    batches = _record_calls(monkeypatch, Planner, "_line_blend_batch")
    fast = _record_module_calls(monkeypatch, junctions, "batched_line_corner")
    batched = [(s.t0, s.duration, s.v0, s.v1, s.line, s.blend) for s in Planner(machine).segments(iter(records))]
    # a corner the batch holds is taken at the top of _junction, or else in _line_blend
    used = [found is not None for found in results] + [True for found in fast if found is not None]
    assert sum(used) >= 0.95 * len(used) > 200
    assert len(batches) <= len(used) / 16
    monkeypatch.setattr(Planner, "_line_blend", lambda self, *args: None)
    alone = [(s.t0, s.duration, s.v0, s.v1, s.line, s.blend) for s in Planner(machine).segments(iter(records))]
    assert len(alone) == len(batched)
    for a, b in zip(alone, batched, strict=True):
        assert a[4:] == b[4:] and close(a[:4], b[:4])


def _record_module_calls(monkeypatch, module, name: str) -> list:
    """Wrap the function ``module.name`` for the test: the list it returns receives what each call returns."""
    original = getattr(module, name)
    results: list = []

    def recorded(*args):
        result = original(*args)
        results.append(result)
        return result

    monkeypatch.setattr(module, name, recorded)
    return results


def _plan_floats(machine, records) -> list[tuple]:
    from fagorcnc.plan import Planner

    return [(s.t0, s.duration, s.v0, s.v1, s.line, s.blend, *(() if s.piece is None else (
        s.piece.length, *s.piece.start.tolist(), *s.piece.end.tolist())))
        for s in Planner(machine).segments(iter(records))]


@pytest.mark.parametrize(("roundpar", "feeds"), [("#ROUNDPAR [1, 0.01]", False), ("#ROUNDPAR [2, 40]", True),
                                                 ("#ROUNDPAR [4, 0.002]", False)])
def test_g05_line_corners_known_to_hold_plan_as_the_general_path(monkeypatch, roundpar, feeds):
    """The batched G05 line corners taken at the top of _junction (checks known to hold, prev's end
    point made with the batch) give the very floats of the general path through every check and
    Span.trim, on a raster with feed changes, adaptation and HSC after it; the shortcut is taken
    for most corners and refused where a line no longer stands as the batch took it."""
    import fagorcnc
    from fagorcnc.plan import junctions
    from fagorcnc.simulate import Run

    machine = fagorcnc.load_machine(None)
    records = list(Run(iter(_g05_program(roundpar, feeds)), "<g05>", machine))
    fast = _record_module_calls(monkeypatch, junctions, "batched_line_corner")
    cuts = _record_module_calls(monkeypatch, junctions, "cut_line")
    quick = _plan_floats(machine, records)
    assert sum(found is not None for found in fast) >= 0.9 * len(fast) > 200
    assert len(cuts) >= 0.9 * len(fast)
    monkeypatch.setattr(junctions, "fast_corners", lambda chain, *args: [False] * (len(chain) - 1))
    general = _plan_floats(machine, records)
    assert quick == general


@pytest.mark.parametrize("hsc", ["#HSC ON [CONTERROR 0.01]", "#HSC ON [FAST 80, E0.02, CORNER 120]",
                                 "#HSC ON [CONTERROR 0.002]"])
def test_hsc_splines_known_to_hold_plan_as_the_general_path(monkeypatch, hsc):
    """The batched HSC splines taken at the top of _junction (checks known to hold, the next line's
    start made with the batch) give the very floats of the general path through _junction and
    _spline, on a raster whose inflections stop some splines (a candidate made again alone) and
    with feed changes, a sharp edge and G05 after it; the shortcut is taken for most corners."""
    import fagorcnc
    from fagorcnc.plan import junctions
    from fagorcnc.simulate import Run

    machine = fagorcnc.load_machine(None)
    rows = []
    for r in range(4):   # a 3D finishing raster (0.5 mm steps)
        xs = [i * 0.5 for i in range(101)]
        rows += [f"X{x:.4f} Y{r:.4f} Z{2 * np.sin(x / 7) * np.cos(r / 9):.4f}" + (" F2500" if i % 37 == 5 else "")
                 for i, x in enumerate(xs[::-1] if r % 2 else xs)]
    program = ["G90 G1 X0 Y0 Z0 F3000", hsc, *rows, "X20 Y20 F3000", "X20.5 Y20", "X0 Y20.4", "X-1 Y21",
               "#HSC OFF", "G05 X-2 Y22", "X-3 Y21", "M30"]
    records = list(Run(iter(program), "<raster>", machine))
    fast = _record_calls(monkeypatch, junctions.CornerMixin, "_batched_spline")
    quick = _plan_floats(machine, records)
    taken = [found is not junctions._MISSING for found in fast]
    assert sum(taken) >= 0.8 * len(rows) and not all(taken)
    monkeypatch.setattr(junctions, "fast_splines", lambda chain, *args: [False] * (len(chain) - 1))
    general = _plan_floats(machine, records)
    assert quick == general


def test_a_line_cut_with_its_end_known_is_the_trimmed_line():
    """cut_line gives the piece Span.trim(0.0, keep) gives: the same start (object), end, length,
    direction and bounds."""
    from fagorcnc.plan.limits import AxisLimits
    from fagorcnc.plan.shortcuts import cut_line
    from fagorcnc.plan.span import Span

    rng = np.random.default_rng(5)
    lim = AxisLimits.__new__(AxisLimits)
    for _ in range(50):
        a, b = rng.normal(size=3), rng.normal(size=3)
        piece = LinePiece(a, b).sub(float(rng.uniform(0.0, 0.1)), LinePiece(a, b).length)
        keep = float(piece.length * rng.uniform(0.2, 1.0))
        one, two = Span.__new__(Span), Span.__new__(Span)
        one.piece = two.piece = piece
        one.lim = two.lim = lim
        one.trim(0.0, keep)
        cut_line(two, keep, piece.start + keep * piece.u)
        assert two.piece.start is one.piece.start and two.length == one.length == two.piece.length
        assert np.array_equal(two.piece.end, one.piece.end) and two.piece.length == one.piece.length
        assert two.piece.u is one.piece.u and two.piece.ul is one.piece.ul and two.piece.d2 is one.piece.d2
        assert np.array_equal(two.piece.d1, one.piece.d1)


def test_an_arcs_frame_and_trim_on_floats_equal_its_derivatives():
    """An arc's single-point frame and trim (on floats) give what the general evaluation over
    arrays gives: point, unit tangent and curvature vector (helix and spiral included)."""
    from fagorcnc.plan.geometry import Piece

    start, end = np.array([10.0, 0.0, 0.0]), np.array([0.0, 10.05, 3.0])   # radius 10 -> 10.05, 3 mm of helix
    arc = ArcPiece(start, end, 0, 1, (0.0, 0.0), np.pi / 2)
    for s in (0.0, 0.3 * arc.length, arc.length):
        for got, general in zip(arc.frame(s), Piece.frame(arc, s), strict=True):
            assert close(got, general)
        assert close(arc.point(s), arc.derivatives(np.array([s]))[0][0])
    part = arc.sub(0.25 * arc.length, 0.75 * arc.length)
    q = arc.derivatives(np.array([0.25 * arc.length, 0.75 * arc.length]))[0]
    assert close(part.start, q[0]) and close(part.end, q[1])
    assert close(part.length, 0.5 * arc.length)


def test_an_arcs_point_moves_the_axes_off_its_plane_as_the_array_product():
    """ArcPiece.point, which moves only the axes off the plane (element by element), gives the floats
    of ``start + s * lin`` with the plane's two axes set: helices, planar arcs whose start has a -0.0
    off the plane (0.0 once moved), and arcs in the three planes of four axes."""
    import math

    for dim, (ia, io) in ((3, (0, 1)), (3, (2, 0)), (3, (1, 2)), (4, (0, 1)), (4, (1, 2))):
        for rise in (0.0, -0.0, 2.5, -1e-9):
            start = np.zeros(dim)
            start[ia], start[io] = 10.0, 0.0
            start[[i for i in range(dim) if i not in (ia, io)]] = -0.0
            end = start.copy()
            end[ia], end[io] = 0.0, 10.05
            end[[i for i in range(dim) if i not in (ia, io)]] = rise
            arc = ArcPiece(start, end, ia, io, (0.0, 0.0), np.pi / 2)
            for s in (0.3 * arc.length, arc.length, 1e-300):
                want = arc.start + s * arc.lin
                th, rho = arc.theta0 + arc.w * s, arc.r0 + arc.dr * s
                want[ia], want[io] = arc.center[0] + rho * math.cos(th), arc.center[1] + rho * math.sin(th)
                assert arc.point(s).tobytes() == want.tobytes()


def test_distances_to_an_arc_and_a_line_worked_by_hand():
    """The distance from a point to the stretch of an arc in XY of radius 5 about the origin from
    0 to 90 degrees: along the radius where the point's angle is within the stretch ((6, 0, 0): 1;
    (3, 4, 2): on the circle's radius, 2 above its plane), else to the nearer end ((0, -6, 0):
    sqrt(5² + 6²) to (5, 0); (-1, -1, 0): sqrt(37) to either end).  The same arc run clockwise
    from 90 to 0 degrees gives the same; a line from (0, 0, 0) to (4, 0, 0) gives sqrt(2² + 3²)
    at (6, 3, 0), 3 at (2, -3, 0)."""
    from fagorcnc.plan.stretch import PieceRows, _gaps

    ccw = ArcPiece(np.array([5.0, 0.0, 0.0]), np.array([0.0, 5.0, 0.0]), 0, 1, (0.0, 0.0), np.pi / 2)
    cw = ArcPiece(np.array([0.0, 5.0, 0.0]), np.array([5.0, 0.0, 0.0]), 0, 1, (0.0, 0.0), -np.pi / 2)
    line = LinePiece(np.array([0.0, 0.0, 0.0]), np.array([4.0, 0.0, 0.0]))
    sides = PieceRows([ccw, cw, line])
    assert sides.circular.tolist() == [True, True, False] and sides.straight.tolist() == [False, False, True]

    def distances(row, s1, pts, vertex):
        rel = (np.array(pts) - vertex)[None]   # the distances do not depend on the point they are taken from
        square = (rel * rel).sum(axis=2)
        return np.sqrt(_gaps(sides, np.array([row]), np.array([0.0]), np.array([s1]), rel, square, vertex[None])[0])

    pts = [[6.0, 0.0, 0.0], [3.0, 4.0, 2.0], [0.0, -6.0, 0.0], [-1.0, -1.0, 0.0]]
    for row, arc in ((0, ccw), (1, cw)):
        got = distances(row, arc.length, pts, np.array([0.0, 5.0, 0.0]))
        assert got == pytest.approx([1.0, 2.0, np.sqrt(61.0), np.sqrt(37.0)], abs=1e-12)
    # half the stretch: (6, 0, 0) is then beyond its end at 45 degrees (clockwise: 90 down to 45)
    half = distances(1, cw.length / 2, pts[:1], np.array([5.0, 0.0, 0.0]))
    assert half[0] == pytest.approx(np.hypot(6.0 - 5.0 / np.sqrt(2.0), 5.0 / np.sqrt(2.0)), abs=1e-12)
    # three quarters of a turn (0 to 270 degrees): (0, -6, 0) at its end, 1 from it; (-1, -1, 0) at
    # 225 degrees now inside, 5 - sqrt(2) from the circle
    big = ArcPiece(np.array([5.0, 0.0, 0.0]), np.array([0.0, -5.0, 0.0]), 0, 1, (0.0, 0.0), 1.5 * np.pi)
    sides = PieceRows([big])
    assert distances(0, big.length, pts[2:], np.zeros(3)) == pytest.approx([1.0, 5.0 - np.sqrt(2.0)], abs=1e-12)
    sides = PieceRows([line])
    assert distances(0, 4.0, [[6.0, 3.0, 0.0], [2.0, -3.0, 0.0]], np.zeros(3)) == pytest.approx(
        [np.sqrt(13.0), 3.0], abs=1e-12)


def test_deviation_from_arcs_is_the_distance_to_the_arcs():
    """HSC's deviation of corner curves at circular arcs (line -> arc, arc -> arc, in XY) is the
    distance to the arcs themselves: against the distance to 20 001 points of the replaced stretch
    (whose spacing overstates it by less than 1e-6)."""
    from fagorcnc.plan.corners import make_blend

    rng = np.random.default_rng(6)

    def arc_at(at, starts_there):
        r, th = rng.uniform(0.5, 10.0), rng.uniform(0.0, 2.0 * np.pi)
        sweep = rng.uniform(0.2, 2.5) * rng.choice([-1.0, 1.0])
        centre = (at[0] - r * np.cos(th), at[1] - r * np.sin(th))
        far = at.copy()
        th1 = th + (sweep if starts_there else -sweep)
        far[0], far[1] = centre[0] + r * np.cos(th1), centre[1] + r * np.sin(th1)
        return ArcPiece(at.copy(), far, 0, 1, centre, sweep) if starts_there else ArcPiece(far, at.copy(), 0, 1,
                                                                                            centre, sweep)
    checked = 0
    for i in range(40):
        at = rng.uniform(-20.0, 20.0, 3)
        p = LinePiece(at - rng.uniform(-5.0, 5.0, 3) * [1.0, 1.0, 0.0], at.copy()) if i % 2 else arc_at(at, False)
        q = arc_at(at, True)
        made = make_blend(p, q, p.length / 2, q.length / 2, tolerance=0.01, speed=None, acc=1000.0, jerk=20000.0)
        if made is None:
            continue
        blend, d1, d2 = made
        ref = np.concatenate([p.derivatives(np.linspace(p.length - d1, p.length, 20001))[0],
                              q.derivatives(np.linspace(0.0, d2, 20001))[0]])
        pts = blend.points(97)
        dense = max(float(np.sqrt(((ref - x) ** 2).sum(axis=1)).min()) for x in pts)
        assert deviation(blend, p, q, d1, d2, False) == pytest.approx(dense, abs=1e-6)
        checked += 1
    assert checked >= 30


def test_deviation_from_a_helix_is_the_distance_to_its_polyline():
    """A helix has no closed-form distance: deviation() measures it against 17 points through the
    replaced stretch (the line before it exactly): against the plain distance from each of the
    curve's 97 points to each segment of that polyline."""
    from fagorcnc.plan.corners import make_blend

    p = LinePiece(np.array([100.0, 50.0, 0.0]), np.array([110.0, 50.0, 0.0]))
    q = ArcPiece(np.array([110.0, 50.0, 0.0]), np.array([115.0, 55.0, 1.0]), 0, 1, (110.0, 55.0), np.pi / 2)
    blend, d1, d2 = make_blend(p, q, 5.0, q.length / 2, tolerance=0.01, speed=50.0, acc=1000.0, jerk=20000.0)
    ref = np.concatenate([[p.start + (p.length - d1) * p.u], q.derivatives(np.linspace(0.0, d2, 17))[0]])
    worst = 0.0
    for x in blend.points(97):
        best = np.inf
        for a, b in pairwise(ref):
            t = min(max(float(np.dot(x - a, b - a) / np.dot(b - a, b - a)), 0.0), 1.0)
            best = min(best, float(np.linalg.norm(x - a - t * (b - a))))
        worst = max(worst, best)
    assert 0.0 < worst <= 0.95 * 0.01
    assert deviation(blend, p, q, d1, d2, False) == pytest.approx(worst, rel=1e-9, abs=1e-12)


def test_an_arcs_trim_is_the_same_curve_over_the_same_parameter():
    """ArcPiece.sub restricts the curve: at every parameter the trimmed arc is where the whole one is
    at s0 + s (helix and spiral included), its length is s1 - s0, and its derivative bounds (made on
    first use) are those of the arc rebuilt from its end points, within rounding."""
    from fagorcnc.plan.geometry import ArcPiece

    start, end = np.array([10.0, 0.0, 0.0]), np.array([0.0, 10.05, 3.0])
    arc = ArcPiece(start, end, 0, 1, (0.0, 0.0), np.pi / 2)
    s0, s1 = 0.2 * arc.length, 0.7 * arc.length
    part = arc.sub(s0, s1)
    assert part.length == s1 - s0
    s = np.linspace(0.0, part.length, 9)
    for got, whole in zip(part.derivatives(s), arc.derivatives(s0 + s), strict=True):
        assert close(got, whole)
    rebuilt = ArcPiece(part.start, part.end, 0, 1, (0.0, 0.0), part.w * part.length)
    for got, want in zip((part.d1, part.d2, part.d3), (rebuilt.d1, rebuilt.d2, rebuilt.d3), strict=True):
        assert np.allclose(got, want, rtol=1e-3)   # the rebuilt spiral's parameter runs 0.1 % faster
    assert arc.sub(0.0, arc.length).end is arc.end and arc.sub(0.0, s1).start is arc.start


def test_a_span_made_later_settles_to_the_limits_made_at_once():
    """A curved span made or trimmed with ``later`` has no limits until settled; then it has those a
    span made (or trimmed) at once has."""
    import fagorcnc
    from fagorcnc.plan import Planner
    from fagorcnc.plan.geometry import ArcPiece
    from fagorcnc.plan.span import Span

    planner = Planner(fagorcnc.load_machine(None))
    lim = planner._axis_limits(None, False)
    arc = ArcPiece(np.array([10.0, 0.0, 0.0]), np.array([0.0, 10.0, 1.0]), 0, 1, (0.0, 0.0), np.pi / 2)
    at_once = Span(arc, None, 80.0, lim, False, None, 0.0, 0.0)
    later = Span(arc, None, 80.0, lim, False, None, 0.0, 0.0, later=True)
    assert later.stale and not hasattr(later, "vc")
    later.settle()
    assert not later.stale and (later.vc, later.acc, later.jerk) == (at_once.vc, at_once.acc, at_once.jerk)
    at_once.trim(1.0, arc.length)
    later.trim(1.0, arc.length, later=True)
    assert later.stale and later.length == at_once.length
    later.settle()
    assert (later.vc, later.acc, later.jerk) == (at_once.vc, at_once.acc, at_once.jerk)


@pytest.mark.parametrize("params", [(1, 0.01), (2, 37.0), (2, 100.0), (4, 0.002)])
def test_roundpar_of_a_line_batch_is_roundpar_of_each_corner(params):
    """The G05 line batch takes #ROUNDPAR's feed, speed and tolerance for all its corners at once:
    the very numbers _roundpar gives each corner (its entries are matched against them)."""
    from fagorcnc.plan.corners import _roundpar, _roundpar_rows

    feeds = np.array([50.0, 100.0 / 3.0, 17.1, 0.123456789])
    f, speeds, tolerance = _roundpar_rows(params, feeds)
    for i, feed in enumerate(feeds.tolist()):
        one = _roundpar(params, feed)
        assert f[i] == one[0] and tolerance == one[2]
        assert (speeds is None and one[1] is None) or speeds[i] == one[1]


def test_a_crawl_told_without_the_jerk_term_is_the_whole_test():
    """_crawls skips the jerk term of the rest-to-rest time where the rest without it already covers
    the time at the cap: the same answer as the whole formula, on random and edge values."""
    import math

    from fagorcnc.plan.junctions import _crawls
    from fagorcnc.plan.span import Span

    def whole(length, vc, acc, jerk):
        at_cap = length / vc if vc > 0 else math.inf
        if jerk == math.inf:
            return at_cap > 2.0 * math.sqrt(length / acc)
        return at_cap > 4.0 * (length / (2.0 * jerk)) ** (1.0 / 3.0) + 2.0 * math.sqrt(length / acc)

    rng = np.random.default_rng(7)
    cases = [(float(10 ** rng.uniform(-6, 1)), float(10 ** rng.uniform(-3, 3)), float(10 ** rng.uniform(1, 5)),
              float(10 ** rng.uniform(2, 7)) if rng.random() < 0.8 else math.inf) for _ in range(3000)]
    cases += [(0.1, 0.0, 1000.0, 1e5), (0.1, 50.0, 1000.0, math.nan), (0.0, 50.0, 1000.0, 1e5), (1e-9, 1e-3, 1e4, 1e6)]
    answers = set()
    for length, vc, acc, jerk in cases:
        span = Span.__new__(Span)
        span.length, span.vc, span.acc, span.jerk = length, vc, acc, jerk
        assert _crawls(span) == whole(length, vc, acc, jerk)
        answers.add(_crawls(span))
    assert answers == {True, False}
