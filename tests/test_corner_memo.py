"""Corner curves at arcs taken back from the planner's memo (fagorcnc.plan.corner_memo) are, to the
bit, the curves that would be made: a corner's curve is the same floats in any batch, the memo
keys every number the construction reads, and a contour run again at another depth plans as the
first time."""

from __future__ import annotations

import math

import numpy as np
import pytest
from test_corner_batch import _corners, _flat_corners

from fagorcnc.plan.corner_batch import blend_batch
from fagorcnc.plan.corner_memo import CornerMemo
from fagorcnc.plan.geometry import ArcPiece, LinePiece

KW = dict(acc=1000.0, jerk=20000.0)
MODES = [(0.01, 50.0, False), (0.005, None, True), (None, 80.0, True)]


def _same(a, b) -> bool:
    """Two corners' results ((curve, d1, d2) or None) are the same floats."""
    if a is None or b is None:
        return a is b
    (p, g1, g2), (q, h1, h2) = a, b
    return ((g1, g2, p.length) == (h1, h2, q.length)
            and all(np.array_equal(x, y) for x, y in ((p.controls, q.controls), (p.start, q.start), (p.end, q.end),
                                                       (p.d1, q.d1), (p.d2, q.d2), (p.d3, q.d3),
                                                       (p.table_s, q.table_s))))


def _limits(ps, qs):
    lim_p = np.array([p.length / 2.0 for p in ps])
    lim_q = np.array([q.length / 2.0 for q in qs])
    lim_p[4] = 0.0   # a corner without a curve among them
    return lim_p, lim_q


@pytest.mark.parametrize(("tolerance", "speed", "corner"), MODES)
def test_a_corners_curve_is_the_same_floats_in_any_batch(tolerance, speed, corner):
    """Each corner made alone, in the whole batch and in the batch shuffled: the same curve to the
    bit (helices, spirals, lines along three axes and corners in every plane among them)."""
    ps, qs = _corners(21, 45)
    lim_p, lim_q = _limits(ps, qs)
    speeds = None if speed is None else np.linspace(0.5, 1.5, len(ps)) * speed
    kw = dict(tolerance=tolerance, corner=corner, **KW)
    whole, bounds = blend_batch(ps, qs, lim_p, lim_q, speed=speeds, **kw)
    order = np.random.default_rng(2).permutation(len(ps))
    shuffled, _ = blend_batch([ps[i] for i in order], [qs[i] for i in order], lim_p[order], lim_q[order],
                              speed=None if speeds is None else speeds[order], **kw)
    made = 0
    for j, i in enumerate(order):
        alone, _ = blend_batch(ps[i:i + 1], qs[i:i + 1], lim_p[i:i + 1], lim_q[i:i + 1],
                               speed=None if speeds is None else speeds[i:i + 1], **kw)
        assert _same(whole[i], alone[0]) and _same(whole[i], shuffled[j]), i
        made += whole[i] is not None
    assert made >= 35 and len(bounds[0]) == made


def _shifted(pieces: list, dz: float) -> list:
    """The same pieces ``dz`` lower along Z (the next pass of a flat contour)."""
    down = np.array([0.0, 0.0, dz])
    out = []
    for p in pieces:
        if isinstance(p, ArcPiece):
            out.append(ArcPiece(p.start + down, p.end + down, p.ia, p.io, p.center, p._ends[1]))   # its sweep
        else:
            out.append(LinePiece(p.start + down, p.end + down))
    return out


@pytest.mark.parametrize(("tolerance", "speed", "corner"), MODES)
def test_a_pass_at_another_depth_takes_its_curves_back(tolerance, speed, corner):
    """An XY contour's corners, then the same corners 0.2 mm lower among new ones: the second batch
    takes the first's curves back at its own height, the very floats a batch without the memo
    makes, and its bound arrays too; a corner alone on three axes is taken back as well."""
    ps, qs = _flat_corners(4, 40, 5.0)
    lim_p, lim_q = _limits(ps, qs)
    speeds = None if speed is None else np.full(len(ps), speed)
    kw = dict(tolerance=tolerance, corner=corner, **KW)
    memo = CornerMemo()
    first, _ = blend_batch(ps, qs, lim_p, lim_q, speed=speeds, memo=memo, **kw)
    assert memo.hits == 0 and all(_same(a, b) for a, b in zip(
        first, blend_batch(ps, qs, lim_p, lim_q, speed=speeds, **kw)[0], strict=True))
    new_p, new_q = _corners(8, 12)   # corners the memo does not hold, on three axes
    ps2 = [*_shifted(ps, -0.2), *new_p]
    qs2 = [*_shifted(qs, -0.2), *new_q]
    lim_p2 = np.concatenate([lim_p, [p.length / 2.0 for p in new_p]])
    lim_q2 = np.concatenate([lim_q, [q.length / 2.0 for q in new_q]])
    speeds2 = None if speeds is None else np.full(len(ps2), speed)
    got, got_bounds = blend_batch(ps2, qs2, lim_p2, lim_q2, speed=speeds2, memo=memo, **kw)
    want, want_bounds = blend_batch(ps2, qs2, lim_p2, lim_q2, speed=speeds2, **kw)
    assert memo.hits == len(ps)
    assert all(_same(a, b) for a, b in zip(got, want, strict=True))
    assert all(np.array_equal(a, b) for a, b in zip(got_bounds, want_bounds, strict=True))
    assert all(g[0].controls[:, 2].tolist() == [4.8] * 6 for g in got[:len(ps)] if g is not None)
    again, _ = blend_batch(new_p[:1], new_q[:1], lim_p2[len(ps):len(ps) + 1], lim_q2[len(ps):len(ps) + 1],
                           speed=None if speeds is None else speeds[:1], memo=memo, **kw)
    assert memo.hits == len(ps) + 1 and _same(again[0], want[len(ps)])


def test_the_key_holds_every_number_bit_for_bit():
    """A corner's key changes with any of its numbers on the axes its pieces move along, the sign of
    a zero included, and not with where it stands on the axes they do not move along; a helix's
    corner also holds its batch's axes."""
    def key(start, end, helix=None):
        q = helix or ArcPiece(np.array(end), np.array([end[0] - 1.0, end[1] + 1.0, end[2]]), 0, 1,
                              (end[0] - 1.0, end[1]), math.pi / 2)
        return CornerMemo().keys([LinePiece(np.array(start), np.array(end))], [q], np.array([0.5]),
                                 np.array([0.5]), np.array([50.0]), (0.01, 1000.0, 20000.0, False))[0][0]

    base = key([1.0, 0.0, 5.0], [3.0, 2.0, 5.0])
    assert base[0] == (0, 1) and base[2] is None
    assert key([1.0, 0.0, -7.0], [3.0, 2.0, -7.0]) == base
    assert key([1.0, -0.0, 5.0], [3.0, 2.0, 5.0]) != base
    assert key([1.0, 0.0, 5.0], [3.0, 2.0 + 1e-15, 5.0]) != base
    helix = key([1.0, 0.0, 5.0], [3.0, 2.0, 5.0], ArcPiece(np.array([3.0, 2.0, 5.0]), np.array([2.0, 3.0, 5.5]), 0, 1,
                                                           (2.0, 2.0), math.pi / 2))
    assert helix[0] == (0, 1, 2) and helix[2] == (0, 1, 2)


def test_the_memo_is_bounded():
    """Past its size the memo lets its oldest corners go."""
    ps, qs = _flat_corners(5, 30, 0.0)
    lim_p, lim_q = _limits(ps, qs)
    memo = CornerMemo(size=7, patience=100)
    blend_batch(ps, qs, lim_p, lim_q, tolerance=0.01, speed=np.full(len(ps), 50.0), memo=memo, **KW)
    assert len(memo._made) == 7
    blend_batch(ps, qs, lim_p, lim_q, tolerance=0.01, speed=np.full(len(ps), 50.0), memo=memo, **KW)
    assert memo.hits == 7 and not memo.asleep


def test_the_memo_sleeps_on_corners_that_do_not_repeat():
    """After its size of corners in a row made and none taken back, the memo looks none up (and
    keeps none): the batch is made as without it, the same floats."""
    ps, qs = _flat_corners(6, 30, 0.0)
    lim_p, lim_q = _limits(ps, qs)
    kw = dict(tolerance=0.01, speed=np.full(len(ps), 50.0), **KW)
    memo = CornerMemo(patience=20)
    blend_batch(ps, qs, lim_p, lim_q, memo=memo, **kw)
    assert memo.asleep and not memo._made
    again, _ = blend_batch(ps, qs, lim_p, lim_q, memo=memo, **kw)
    assert memo.hits == 0 and not memo._made
    assert all(_same(a, b) for a, b in zip(again, blend_batch(ps, qs, lim_p, lim_q, **kw)[0], strict=True))


def _passes(mode: str, depths: int) -> list[str]:
    """A closed contour of arcs and lines at the corners, run at ``depths`` depths 0.25 mm apart."""
    rows = []
    n = 36
    for i in range(n):
        a1 = 2 * math.pi * (i + 1) / n
        r = 30.0 + 0.7 * (i % 3)
        x, y = r * math.cos(a1), r * math.sin(a1)
        rows.append(f"G3 X{x:.4f} Y{y:.4f} R{r * 0.9:.4f}" if i % 2 else f"G1 X{x:.4f} Y{y:.4f}")
    head = ["#HSC ON [CONTERROR 0.01]"] if mode == "HSC" else [mode, "G05"]
    program = ["G90 G1 X30.7 Y0 Z0 F3000", *head]
    for k in range(depths):
        program += [f"G1 Z{-0.25 * k:.4f}", *rows]
    return [*program, "M30"]


@pytest.mark.parametrize("mode", ["HSC", "#ROUNDPAR [1, 0.01]", "#ROUNDPAR [2, 60]"])
def test_a_contour_run_at_several_depths_plans_as_without_the_memo(mode):
    """Three passes of a contour: the planner takes most corners of the second and third passes back
    from its memo, and every segment is the same floats as a planner without it plans."""
    import fagorcnc
    from fagorcnc.plan import Planner
    from fagorcnc.simulate import Run

    machine = fagorcnc.load_machine(None)
    records = list(Run(iter(_passes(mode, 3)), "<passes>", machine))
    planner = Planner(machine)
    got = [(s.kind, s.line, s.t0, s.duration, s.v0, s.v1) for s in planner.segments(iter(records))]
    assert planner._corner_memo.hits >= 30
    plain = Planner(machine)
    plain._corner_memo = None
    want = [(s.kind, s.line, s.t0, s.duration, s.v0, s.v1) for s in plain.segments(iter(records))]
    assert got == want
