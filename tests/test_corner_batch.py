"""Corner curves at arcs made many at once (fagorcnc.plan.corner_batch) give what the one-by-one
construction (corners.make_blend) gives, and the planner plans the same with them."""

from __future__ import annotations

import math
import re
from functools import partial

import numpy as np
import pytest
from test_plan_batches import close as close_to

from fagorcnc.plan.corner_batch import PieceRows, make_blends
from fagorcnc.plan.corners import make_blend
from fagorcnc.plan.geometry import ArcPiece, LinePiece

#: batched and one-by-one corners agree up to rounding: within 1e-9 relative (1e-13 seen)
close = partial(close_to, tol=1e-9)


def _arc(rng: np.random.Generator, at: np.ndarray, starts_there: bool) -> ArcPiece:
    """An arc (sometimes a helix or a spiral, in any of the three planes) that starts or ends at ``at``."""
    ia, io = [(0, 1), (2, 0), (1, 2)][int(rng.integers(3))]
    r = rng.uniform(0.5, 20.0)
    th = rng.uniform(0.0, 2.0 * math.pi)
    sweep = rng.uniform(0.1, 2.5) * rng.choice([-1.0, 1.0])
    centre = (at[ia] - r * math.cos(th), at[io] - r * math.sin(th))
    r1 = r * (1.0 + rng.uniform(-0.002, 0.002) * (rng.random() < 0.3))   # a spiral within CIRINERR
    other = 3 - ia - io
    rise = rng.uniform(-1.0, 1.0) * (rng.random() < 0.3)                 # a helix
    far = at.copy()
    th1 = th + (sweep if starts_there else -sweep)
    far[ia], far[io] = centre[0] + r1 * math.cos(th1), centre[1] + r1 * math.sin(th1)
    far[other] += rise if starts_there else -rise
    if starts_there:
        return ArcPiece(at.copy(), far, ia, io, centre, sweep)
    # ending at ``at``: the radius goes from r1 at ``far`` to r at ``at``
    return ArcPiece(far, at.copy(), ia, io, centre, sweep)


def _corners(seed: int, n: int) -> tuple[list, list]:
    """``n`` corners at a vertex: arc -> arc, line -> arc, arc -> line, in every plane."""
    rng = np.random.default_rng(seed)
    ps, qs = [], []
    for i in range(n):
        at = rng.uniform(-50.0, 50.0, 3)
        kind = i % 3
        ps.append(LinePiece(at - rng.uniform(-5.0, 5.0, 3), at.copy()) if kind == 1 else _arc(rng, at, False))
        qs.append(LinePiece(at.copy(), at + rng.uniform(-5.0, 5.0, 3)) if kind == 2 else _arc(rng, at, True))
    return ps, qs


def test_piece_rows_evaluate_as_the_pieces():
    """Points at many parameters and frames at one, over rows of lines (a plunge along Z among them)
    and arcs (helices and spirals in the three planes), against each piece's own evaluation."""
    ps, qs = _corners(3, 30)
    plunge = LinePiece(np.array([1.0, 2.0, 5.0]), np.array([1.0, 2.0, -3.0]))   # along Z alone: no plane direction
    pieces = [*ps, *qs, plunge]
    rows = PieceRows(pieces)
    every = np.arange(len(pieces))
    s = np.array([np.linspace(0.0, p.length, 7) for p in pieces])
    points = rows.points(s, every)
    for i, p in enumerate(pieces):
        assert close(points[i], p.derivatives(s[i])[0])
    at = np.array([0.37 * p.length for p in pieces])
    q, t, k = rows.frames(at, every)
    for i, p in enumerate(pieces):
        for got, want in zip((q[i], t[i], k[i]), p.frame(float(at[i])), strict=True):
            assert close(got, want)
    some = np.array([3, 17, 31, 44])   # a subset of the rows
    q, t, k = rows.frames(at[some], some)
    assert close(t, np.array([pieces[i].frame(float(at[i]))[1] for i in some]))
    assert close(rows.points(s[some], some), points[some])


@pytest.mark.parametrize(("tolerance", "speed", "corner"), [(0.01, 50.0, False), (None, 80.0, True),
                                                            (0.005, None, True), (0.02, 30.0, True)])
def test_corners_at_arcs_in_a_batch_equal_one_by_one(tolerance, speed, corner):
    """The HSC construction (tolerance on the replaced path, the feed's speed), G05 #ROUNDPAR
    types 1, 2 and 4 (distance from the corner point, with or without a speed): the same curves,
    the same sizes, the same bounds, including the corners where none fits."""
    ps, qs = _corners(11, 90)
    lim_p = np.array([p.length / 2.0 for p in ps])
    lim_q = np.array([q.length / 2.0 for q in qs])
    lim_p[5] = 0.0                                   # nothing left to round with: no curve
    lim_q[6] = 1e-10
    speeds = None if speed is None else np.full(len(ps), speed)
    if speeds is not None:
        speeds[::7] *= 3.0                           # each corner has its own speed
    got = make_blends(ps, qs, lim_p, lim_q, tolerance=tolerance, speed=speeds, acc=1000.0, jerk=20000.0,
                      corner=corner)
    made = 0
    for i, (p, q) in enumerate(zip(ps, qs, strict=True)):
        want = make_blend(p, q, lim_p[i], lim_q[i], tolerance=tolerance,
                          speed=None if speeds is None else float(speeds[i]), acc=1000.0, jerk=20000.0, corner=corner)
        assert (got[i] is None) == (want is None), i
        if want is None:
            continue
        made += 1
        (b, d1, d2), (w, e1, e2) = got[i], want
        assert close([d1, d2], [e1, e2]) and close(b.controls, w.controls)
        assert close(b.d1, w.d1) and close(b.d2, w.d2) and close(b.d3, w.d3) and close(b.length, w.length)
        assert close(b.derivatives(np.array([0.5 * b.length]))[0], w.derivatives(np.array([0.5 * w.length]))[0])
    assert got[5] is None and got[6] is None
    assert made >= 80


def _contour(mode: str, plane: str = "G17") -> list[str]:
    """A CAM-like contour in ``plane``: lines and arcs that meet at corners (not tangent), some
    arcs long enough to be planned in parts, a helix, a feed change."""
    rows, z = [], 0.0
    n = 48
    for i in range(n):
        a0, a1 = 2 * math.pi * i / n, 2 * math.pi * (i + 1) / n
        r = 40.0 + 1.0 * (i % 3)
        x, y = r * math.cos(a1), r * math.sin(a1)
        if i % 2:
            # the centre off the chord's middle: the arc meets its neighbours at a corner
            px, py = (40.0 + (i - 1) % 3) * math.cos(a0), (40.0 + (i - 1) % 3) * math.sin(a0)
            mx, my = (px + x) / 2.0, (py + y) / 2.0
            cx, cy = mx - 2.0 * (y - py), my + 2.0 * (x - px)
            z += 0.2 if i % 4 == 1 else 0.0
            rows.append(f"G3 X{x:.4f} Y{y:.4f} Z{z:.4f} I{cx - px:.4f} J{cy - py:.4f}")
        else:
            if i % 6 == 0:   # a line in two with a kink: an HSC spline (slight) or a corner curve (0.3 mm)
                am, kink = (a0 + a1) / 2.0, 0.3 if i % 12 else 0.004
                mid = (40.0 + (i - 1) % 3 + r) / 2.0 * math.cos(math.pi / n) + kink   # off the chord's middle
                rows.append(f"G1 X{mid * math.cos(am):.4f} Y{mid * math.sin(am):.4f}")
            rows.append(f"G1 X{x:.4f} Y{y:.4f}" + (" F2500" if i == 24 else ""))
    rows.append("G2 X46 Y-20 I-6 J-10")   # a long arc: planned in parts, no corner between them
    head = ["#HSC ON [CONTERROR 0.01]"] if mode == "HSC" else [mode, "G05"]
    program = ["G90 G1 X40 Y0 Z0 F4000", *head, *rows, "M30"]
    if plane == "G17":
        return program
    # the same contour in the ZX (G18) or YZ (G19) plane: abscissa and ordinate keep their order
    letters = {"G18": {"X": "Z", "Y": "X", "Z": "Y", "I": "K", "J": "I"},
               "G19": {"X": "Y", "Y": "Z", "Z": "X", "I": "J", "J": "K"}}[plane]
    moved = [re.sub(r"\b([XYZIJ])(?=-?[\d.])", lambda m: letters[m.group(1)], line) for line in program]
    return [moved[0], plane, *moved[1:]]


@pytest.mark.parametrize("plane", ["G17", "G18", "G19"])
@pytest.mark.parametrize("mode", ["HSC", "#ROUNDPAR [1, 0.01]", "#ROUNDPAR [2, 60]", "#ROUNDPAR [4, 0.005]"])
def test_corners_at_arcs_in_a_batch_plan_as_one_by_one(monkeypatch, mode, plane):
    """A contour of lines and arcs planned with the corners at arcs made in batches is planned as
    with every one made alone; every corner at an arc comes from a batch, a few batches in all."""
    from test_plan_batches import _record_calls, _record_module_calls

    import fagorcnc
    from fagorcnc.plan import Planner, junctions
    from fagorcnc.plan.junctions import _MISSING
    from fagorcnc.simulate import Run

    machine = fagorcnc.load_machine(None)
    records = list(Run(iter(_contour(mode, plane)), "<contour>", machine))
    results = _record_calls(monkeypatch, Planner, "_arc_blend")
    fast = _record_module_calls(monkeypatch, junctions, "batched_arc_corner")
    batches = _record_calls(monkeypatch, Planner, "_arc_batch")
    batched = [(s.t0, s.duration, s.v0, s.v1, s.line, s.blend) for s in Planner(machine).segments(iter(records))]
    # a corner the batch knows to hold is taken at the top of _junction, or else in _arc_blend
    taken = [found for found in fast if found is not None]
    assert len(results) + len(taken) >= 20 and all(found is not _MISSING for found in results)
    assert sum(found[0] is not None for found in [*results, *taken]) >= 20
    assert len(batches) <= 3
    monkeypatch.setattr(Planner, "_arc_blend", lambda self, *args: _MISSING)
    alone = [(s.t0, s.duration, s.v0, s.v1, s.line, s.blend) for s in Planner(machine).segments(iter(records))]
    assert len(alone) == len(batched)
    for a, b in zip(alone, batched, strict=True):
        assert a[4:] == b[4:] and close(a[:4], b[:4])


@pytest.mark.parametrize("plane", ["G17", "G18", "G19"])
@pytest.mark.parametrize("mode", ["HSC", "#HSC ON [FAST 80, E0.02, CORNER 165]", "#ROUNDPAR [1, 0.01]",
                                  "#ROUNDPAR [2, 60]", "#ROUNDPAR [4, 0.005]"])
def test_corners_at_arcs_known_to_hold_plan_as_the_general_path(monkeypatch, mode, plane):
    """The batched corners at arcs taken at the top of _junction (checks known to hold) give the very
    floats of the general path through every check and _arc_blend, on a contour with HSC splines
    between its lines, a feed change, a helix and a long arc in parts (and, with CORNER 165, sharp
    edges the estimate must leave to the test); the shortcut is taken for most corners at arcs."""
    from test_plan_batches import _plan_floats, _record_module_calls

    import fagorcnc
    from fagorcnc.plan import junctions
    from fagorcnc.simulate import Run

    machine = fagorcnc.load_machine(None)
    program = _contour(mode, plane)
    if mode.startswith("#HSC ON [FAST"):
        program = [mode if line.startswith("#HSC") else line for line in _contour("HSC", plane)]
    records = list(Run(iter(program), "<contour>", machine))
    fast = _record_module_calls(monkeypatch, junctions, "batched_arc_corner")
    quick = _plan_floats(machine, records)
    assert sum(found is not None for found in fast) >= 12
    monkeypatch.setattr(junctions, "fast_arc_corners", lambda chain, rows, *args: [False] * len(rows))
    general = _plan_floats(machine, records)
    assert quick == general


def test_a_tangent_alone_is_the_direction_lists_floats():
    """tangent_list, which a corner asks for first (the curvature only where the tangents meet), is
    the tangent of direction_list to the bit at the ends and inside lines and arcs (helices and
    spirals in the three planes), trimmed arcs among them."""
    ps, qs = _corners(11, 60)
    pieces = [*ps, *qs]
    pieces += [p.sub(0.3 * p.length, p.length) for p in pieces]
    for p in pieces:
        for s in (0.0, 0.37 * p.length, p.length):
            assert p.tangent_list(s) == p.direction_list(s)[0]


def test_deviations_with_the_ends_known_are_the_same_floats():
    """A batch hands stretch_deviations the ends of the stretches it already has (the curves' own
    ends from the frames, the pieces' end and start once per batch): the same deviations, to the
    bit, as from the ends it evaluates itself, over lines, arcs, spirals and helices, every corner
    or a few; and the lines' rows of a mixed batch take the segments' formula as they do alone."""
    from fagorcnc.plan.blend import _controls, curve_samples
    from fagorcnc.plan.stretch import _gaps, stretch_deviations

    ps, qs = _corners(5, 60)
    rows = PieceRows([*ps, *qs])
    n = len(ps)
    p_len = np.array([p.length for p in ps])
    vertex = np.array([p.end for p in ps])
    incoming, outgoing = np.arange(n), np.arange(n, 2 * n)
    fixed = rows.points(np.concatenate([p_len, np.zeros(n)])[:, None], np.concatenate([incoming, outgoing]))[:, 0]
    for some in (np.arange(n), np.array([1, 2, 7]), np.array([4])):
        d1 = np.minimum(p_len[some] / 3.0, 0.8)
        d2 = np.array([min(qs[i].length / 3.0, 0.6) for i in some])
        q, t, k = rows.frames(np.concatenate([p_len[some] - d1, d2]), np.concatenate([incoming[some], outgoing[some]]))
        m = len(some)
        controls = _controls(q[:m], t[:m], k[:m], 0.3 * d1[:, None], q[m:], t[m:], k[m:], 0.3 * d2[:, None])
        samples, _ = curve_samples(controls)
        args = (rows, incoming[some], outgoing[some], p_len[some], d1, d2, samples, vertex[some], False)
        alone = stretch_deviations(*args)
        known = stretch_deviations(*args, (q, fixed[np.concatenate([some, some + n])]))
        assert np.array_equal(alone, known)
    # the lines' rows among arcs (rows of lines: kind 1's incoming, kind 2's outgoing) row by row
    sides = np.concatenate([incoming, outgoing])
    assert rows.straight[sides].any() and not rows.straight[sides].all()
    s0 = np.concatenate([p_len - 0.5, np.zeros(n)])
    s1 = np.concatenate([p_len, np.full(n, 0.5)])
    at = np.concatenate([vertex, vertex])
    pts = np.random.default_rng(2).normal(size=(2 * n, 9, 3))
    square = (pts * pts).sum(axis=2)
    together = _gaps(rows, sides, s0, s1, pts, square, at)
    for i in range(2 * n):
        one = slice(i, i + 1)
        assert np.array_equal(together[i], _gaps(rows, sides[one], s0[one], s1[one], pts[one], square[one], at[one])[0])


def test_frames_worked_axis_by_axis_are_the_row_formulas_floats():
    """PieceRows.frames works on (D, n) arrays: the same floats, to the bit, as the formulas row by
    row on (n, D) arrays (each piece's numbers gathered, the sums over a row's axes), over lines,
    arcs, spirals and helices in every plane, all rows or a few; and its sums over the axes are a
    row sum's."""
    from fagorcnc.plan.stretch import _axis_sum

    ps, qs = _corners(8, 45)
    rows = PieceRows([*ps, *qs])
    x = np.random.default_rng(4).normal(size=(500, 3)) * 10.0 ** np.random.default_rng(5).uniform(-6, 6, (500, 3))
    assert np.array_equal(_axis_sum(np.ascontiguousarray(x.T)), x.sum(axis=1))
    for some in (np.arange(90), np.array([0, 44, 45, 89]), np.array([7])):
        s = np.array([0.41 * ([*ps, *qs][i]).length for i in some])
        cx, cy, theta0, w, r0, dr = (a[some] for a in (rows.cx, rows.cy, rows.theta0, rows.w, rows.r0, rows.dr))
        base, lin, ea, eo = rows.base[some], rows.lin[some], rows.ea[some], rows.eo[some]
        th = theta0 + w * s
        c, sn = np.cos(th), np.sin(th)
        rho = r0 + dr * s
        q = base + s[:, None] * lin
        q += (cx + rho * c)[:, None] * ea
        q += (cy + rho * sn)[:, None] * eo
        d1 = lin + (dr * c - rho * w * sn)[:, None] * ea
        d1 += (dr * sn + rho * w * c)[:, None] * eo
        d2 = (-2 * dr * w * sn - rho * w * w * c)[:, None] * ea
        d2 += (2 * dr * w * c - rho * w * w * sn)[:, None] * eo
        square = (d1 * d1).sum(axis=1)[:, None]
        t = d1 / np.sqrt(square)
        k = (d2 - (d2 * t).sum(axis=1)[:, None] * t) / square
        got = rows.frames(s, some)
        assert all(np.array_equal(a, b) for a, b in zip(got, (q, t, k), strict=True))


def _flat_corners(seed: int, n: int, z: float) -> tuple[list, list]:
    """``n`` corners of an XY contour at the height ``z``: arcs in G17 and lines in the plane."""
    rng = np.random.default_rng(seed)
    ps, qs = [], []
    for i in range(n):
        at = np.array([*rng.uniform(-50.0, 50.0, 2), z])
        kind = i % 3
        back, ahead = (np.array([*rng.uniform(-5.0, 5.0, 2), 0.0]) for _ in range(2))
        ps.append(LinePiece(at - back, at.copy()) if kind == 1 else _plane_arc(rng, at, False))
        qs.append(LinePiece(at.copy(), at + ahead) if kind == 2 else _plane_arc(rng, at, True))
    return ps, qs


def _plane_arc(rng: np.random.Generator, at: np.ndarray, starts_there: bool) -> ArcPiece:
    """An arc in the XY plane that starts or ends at ``at``."""
    r = rng.uniform(0.5, 20.0)
    th = rng.uniform(0.0, 2.0 * math.pi)
    sweep = rng.uniform(0.1, 2.5) * rng.choice([-1.0, 1.0])
    centre = (at[0] - r * math.cos(th), at[1] - r * math.sin(th))
    far = at.copy()
    th1 = th + (sweep if starts_there else -sweep)
    far[0], far[1] = centre[0] + r * math.cos(th1), centre[1] + r * math.sin(th1)
    start, end = (at.copy(), far) if starts_there else (far, at.copy())
    return ArcPiece(start, end, 0, 1, centre, sweep)


def test_piece_rows_leave_out_the_axes_no_piece_moves_along():
    """An XY contour at Z -2.5: the rows hold X and Y alone, and their points and frames there are
    the floats of the rows on every axis; a piece that moves in Z, or a YZ arc (the first two axes
    must stay), keeps every axis."""
    ps, qs = _flat_corners(4, 30, -2.5)
    pieces = [*ps, *qs]
    every = np.arange(len(pieces))
    full, flat = PieceRows(pieces), PieceRows(pieces, still=True)
    assert full.keep is None and flat.keep == [0, 1]
    s = np.array([np.linspace(0.0, p.length, 7) for p in pieces])
    assert np.array_equal(flat.points(s, every), full.points(s, every)[:, :, :2])
    at = np.array([0.37 * p.length for p in pieces])
    for got, want in zip(flat.frames(at, every), full.frames(at, every), strict=True):
        assert np.array_equal(got, want[:, :2])
        assert not want[:, 2].any() or np.all(want[:, 2] == -2.5)   # Z: the height (points), 0 (t, k)
    rising = LinePiece(np.array([0.0, 0.0, -2.5]), np.array([1.0, 1.0, -2.0]))
    assert PieceRows([*pieces, rising], still=True).keep is None
    yz = ArcPiece(np.array([0.0, 1.0, -2.5]), np.array([0.0, 0.0, -1.5]), 1, 2, (0.0, -2.5), -math.pi / 2)
    assert PieceRows([yz, yz], still=True).keep is None   # X still, but lines take their plane in X, Y


@pytest.mark.parametrize(("tolerance", "speed", "corner"), [(0.01, 50.0, False), (0.005, None, True)])
def test_corners_of_a_flat_contour_are_the_curves_worked_on_every_axis(monkeypatch, tolerance, speed, corner):
    """The corner curves of an XY contour worked on X and Y alone are, to the bit, those worked on
    X, Y and Z: the same control points (Z the contour's height), sizes and bounds (0 along Z)."""
    import fagorcnc.plan.corner_batch as batch

    ps, qs = _flat_corners(9, 60, 7.25)
    lim_p = np.array([p.length / 2.0 for p in ps])
    lim_q = np.array([q.length / 2.0 for q in qs])
    speeds = None if speed is None else np.full(len(ps), speed)
    kw = dict(tolerance=tolerance, speed=speeds, acc=1000.0, jerk=20000.0, corner=corner)
    got = make_blends(ps, qs, lim_p, lim_q, **kw)
    monkeypatch.setattr(batch, "PieceRows", lambda pieces, still=False: PieceRows(pieces))
    want = make_blends(ps, qs, lim_p, lim_q, **kw)
    made = 0
    for g, w in zip(got, want, strict=True):
        assert (g is None) == (w is None)
        if w is None:
            continue
        made += 1
        (b, d1, d2), (c, e1, e2) = g, w
        assert (d1, d2) == (e1, e2)
        assert np.array_equal(b.controls, c.controls) and np.all(b.controls[:, 2] == 7.25)
        for x, y in ((b.d1, c.d1), (b.d2, c.d2), (b.d3, c.d3), (b.table_s, c.table_s)):
            assert np.array_equal(x, y)
        assert b.d2[2] == 0.0 and b.length == c.length
    assert made >= 50


def test_a_batch_gives_its_curves_bounds_as_arrays():
    """blend_batch's bound arrays: row i the bounds of the i-th corner that has a curve, the same
    floats as the curve's own (a batch's limits are made from them), on corners in 3D and on a flat
    contour (worked on X and Y alone)."""
    from fagorcnc.plan.corner_batch import blend_batch

    for ps, qs in (_corners(5, 40), _flat_corners(6, 40, 1.5)):
        lim_p = np.array([p.length / 2.0 for p in ps])
        lim_q = np.array([q.length / 2.0 for q in qs])
        lim_p[3] = 0.0                                   # a corner without a curve among them
        found, bounds = blend_batch(ps, qs, lim_p, lim_q, tolerance=0.01, speed=np.full(len(ps), 50.0),
                                    acc=1000.0, jerk=20000.0)
        curves = [f[0] for f in found if f is not None]
        assert found[3] is None and len(curves) == len(bounds[0]) >= 30
        for k, name in enumerate(("d1", "d2", "d3")):
            assert np.array_equal(bounds[k], np.array([getattr(c, name) for c in curves]))
