"""Corner curves at arcs made many at once: :func:`~fagorcnc.plan.corners.make_blend`'s general
construction (a curve sized for the speed, then shrunk until it keeps the tolerance) run over
arrays of corners, each corner a row that leaves the iterations when it is done.

Lines meeting lines have their own, cheaper, constructions (a table of unit curves for G05, the
HSC splines); what comes here is every corner where an arc (or one of its parts) meets a line or
another arc: CAM contours (profiles with fillets, pockets, finishing passes) are full of them.
"""

from __future__ import annotations

import math

import numpy as np

from .blend import BlendPiece, _controls, arc_tables, curve_bounds, curve_samples
from .corner_memo import MISSING, CornerMemo, distinct_pieces
from .corners import SHAPE
from .geometry import Piece
from .limits import CENTRIPETAL, CURVE_JERK
from .stretch import PieceRows, stretch_deviations


def make_blends(ps: list[Piece], qs: list[Piece], lim_p: np.ndarray, lim_q: np.ndarray, *,
                tolerance: float | None, speed: np.ndarray | None, acc: float, jerk: float,
                corner: bool = False) -> list[tuple[BlendPiece, float, float] | None]:
    """:func:`~fagorcnc.plan.corners.make_blend`'s general construction for the corners
    ``ps[i] -> qs[i]`` (rows), with ``lim_p``/``lim_q`` the most each side may give up (already
    the smaller of half its block and its length) and ``speed`` one per corner (or None): the
    same steps on every row at once, so the same curves up to rounding.  None where no curve fits."""
    return blend_batch(ps, qs, lim_p, lim_q, tolerance=tolerance, speed=speed, acc=acc, jerk=jerk,
                       corner=corner)[0]


def blend_batch(ps: list[Piece], qs: list[Piece], lim_p: np.ndarray, lim_q: np.ndarray, *,
                tolerance: float | None, speed: np.ndarray | None, acc: float, jerk: float,
                corner: bool = False, memo: CornerMemo | None = None
                ) -> tuple[list[tuple[BlendPiece, float, float] | None], tuple[np.ndarray, ...]]:
    """:func:`make_blends`' curves and their derivative bounds as arrays: ``(d1, d2, d3)``, each
    (k, D), row i that of the i-th corner that has a curve (the rows of each curve's own bounds,
    for a batch's limits: no array made again from the curves).  With a ``memo``, the corners it
    holds are taken back from it and the others made (and kept in it): the same floats."""
    if memo is None or memo.asleep:
        return _made(ps, qs, lim_p, lim_q, tolerance=tolerance, speed=speed, acc=acc, jerk=jerk, corner=corner)
    return _remembered(memo, ps, qs, lim_p, lim_q, tolerance=tolerance, speed=speed, acc=acc, jerk=jerk,
                       corner=corner)


def _remembered(memo: CornerMemo, ps: list[Piece], qs: list[Piece], lim_p: np.ndarray, lim_q: np.ndarray, *,
                tolerance: float | None, speed: np.ndarray | None, acc: float, jerk: float, corner: bool
                ) -> tuple[list[tuple[BlendPiece, float, float] | None], tuple[np.ndarray, ...]]:
    """:func:`blend_batch` through ``memo``: the corners it does not hold made in one batch."""
    n = len(ps)
    dim = len(ps[0].start) if n else 0
    lim_p, lim_q = np.asarray(lim_p, dtype=float), np.asarray(lim_q, dtype=float)
    keys, layout = memo.keys(ps, qs, lim_p, lim_q, speed, (tolerance, acc, jerk, corner))
    found = memo.find(keys)
    out: list[tuple[BlendPiece, float, float] | None] = [None] * n
    rows: list[np.ndarray | None] = [None] * n   # each curve's bound rows (d1, d2, d3)
    new = [i for i, f in enumerate(found) if f is MISSING]
    if new:
        made, bounds = _made([ps[i] for i in new], [qs[i] for i in new], lim_p[new], lim_q[new],
                             tolerance=tolerance, speed=None if speed is None else speed[new], acc=acc,
                             jerk=jerk, corner=corner, layout=layout)
        k = 0
        for i, curve in zip(new, made, strict=True):
            out[i] = curve
            if curve is None:
                memo.keep(keys[i], None, None)
                continue
            rows[i] = row = (bounds[0][k], bounds[1][k], bounds[2][k])
            memo.keep(keys[i], curve, row)
            k += 1
        if len(new) == n:   # nothing taken back: the batch's arrays as made
            return made, bounds
    back = [i for i, f in enumerate(found) if f is not MISSING and f is not None]
    for axes in {keys[i][0] for i in back}:   # the curves taken back, by the axes they are kept on
        group = [i for i in back if keys[i][0] == axes]
        entries = [found[i] for i in group]
        keep = list(axes)
        controls = np.array([e[0] for e in entries])[:, :, keep]
        b1, b2, b3 = (np.array([e[j] for e in entries])[:, keep] for j in (1, 2, 3))
        vertex = np.array([ps[i].end for i in group])
        controls, b1, b2, b3 = _all_axes(keep, vertex, controls, b1, b2, b3)
        for i, e, c, e1, e2, e3 in zip(group, entries, controls, b1, b2, b3, strict=True):
            out[i] = (BlendPiece.made(c, c[0], c[-1], e1, e2, e3, e[4], e[5]), e[6], e[7])
            rows[i] = (e1, e2, e3)
    kept = [r for r in rows if r is not None]
    if not kept:
        return out, (np.empty((0, dim)),) * 3
    return out, tuple(np.array(b) for b in zip(*kept, strict=True))


def _made(ps: list[Piece], qs: list[Piece], lim_p: np.ndarray, lim_q: np.ndarray, *,
          tolerance: float | None, speed: np.ndarray | None, acc: float, jerk: float,
          corner: bool = False, layout: tuple[int, ...] | bool = True
          ) -> tuple[list[tuple[BlendPiece, float, float] | None], tuple[np.ndarray, ...]]:
    """:func:`blend_batch` without a memo: every corner's curve made, on the axes ``layout`` (True:
    those some piece moves along; a memo gives its whole batch's, so that a corner is worked on
    the axes it would be without the memo)."""
    n = len(ps)
    pieces, incoming, outgoing = distinct_pieces(ps, qs)
    # on the axes some piece moves along (the others' numbers are each corner's vertex's)
    sides = PieceRows(pieces, still=layout)
    p_len = np.array([p.length for p in ps])
    whole = np.array([p.end for p in ps])
    vertex = whole if sides.keep is None else whole[:, sides.keep]
    lim_p, lim_q = np.asarray(lim_p, dtype=float), np.asarray(lim_q, dtype=float)
    live = (lim_p > 1e-9) & (lim_q > 1e-9)
    longest = np.maximum(lim_p, lim_q)
    # where the stretch a curve replaces ends on the programmed path, whatever its size: the end of
    # each corner's incoming piece, then the start of its outgoing one
    fixed = None
    if tolerance is not None and not corner:
        fixed = sides.points(np.concatenate([p_len, np.zeros(n)])[:, None], np.concatenate([incoming, outgoing]))[:, 0]

    def made(rows: np.ndarray, size: np.ndarray, points: bool = False):
        d1, d2 = np.minimum(size, lim_p[rows]), np.minimum(size, lim_q[rows])
        q, t, k = sides.frames(np.concatenate([p_len[rows] - d1, d2]), np.concatenate([incoming[rows], outgoing[rows]]))
        m = len(rows)
        p0, t0, k0, p5, t5, k5 = q[:m], t[:m], k[:m], q[m:], t[m:], k[m:]
        controls = _controls(p0, t0, k0, (SHAPE * d1)[:, None], p5, t5, k5, (SHAPE * d2)[:, None])
        return (d1, d2, controls, q) if points else (d1, d2, controls)

    def curves(rows: np.ndarray, size: np.ndarray):
        # the points are not looked at, nor the tangents' bounds (the bounds kept are made at the end)
        d1, d2, controls = made(rows, size)
        _, b2, b3, _ = curve_bounds(controls, tangents=False)
        return d1, d2, controls, b2, b3, np.isfinite(b3).all(axis=1)

    def sampled(rows: np.ndarray, size: np.ndarray):
        # the curves' points alone: their bounds once they keep the tolerance (below).  A curve
        # that is not degenerate has finite bounds (its speed |B'| stays above 1e-6 of its
        # largest), so ``valid`` is the same as from the bounds
        d1, d2, controls, ends = made(rows, size, True)
        samples, degenerate = curve_samples(controls)
        return d1, d2, controls, ends, samples, ~degenerate & np.isfinite(samples).all(axis=(0, 1))

    size = longest.copy()
    if speed is not None:
        size = np.minimum(lim_p, lim_q)
        sizing = live.copy()
        for _ in range(2):   # the curvature scales as 1/size, its derivative as 1/size²
            rows = np.flatnonzero(sizing)
            if not len(rows):
                break
            *_, b2, b3, valid = curves(rows, size[rows])
            live[rows[~valid]] = sizing[rows[~valid]] = False
            v = speed[rows]
            with np.errstate(invalid="ignore", over="ignore"):
                need = np.sqrt((b2 * b2).sum(axis=1)) * v * v / (CENTRIPETAL * acc)
                if jerk != math.inf:
                    need = np.maximum(need, np.sqrt(np.sqrt((b3 * b3).sum(axis=1)) * v ** 3 / (CURVE_JERK * jerk)))
            grown = size[rows] * (np.maximum(need, 1e-3) * 1.02)
            full = grown >= longest[rows]
            size[rows] = np.where(full, longest[rows], grown)
            sizing[rows[full]] = False
            sizing &= live
    out: list[tuple[BlendPiece, float, float] | None] = [None] * n
    done_rows, done = [], []
    active = live
    for _ in range(12):
        rows = np.flatnonzero(active)
        if not len(rows):
            break
        if tolerance is None:
            d1, d2, controls, _, _, valid = curves(rows, size[rows])
            ok = valid
        else:
            d1, d2, controls, ends, samples, valid = sampled(rows, size[rows])
            known = None if fixed is None else (ends, fixed[np.concatenate([rows, rows + n])])
            dev = stretch_deviations(sides, incoming[rows], outgoing[rows], p_len[rows], d1, d2, samples,
                                     vertex[rows], corner, known)
            ok = valid & (dev <= 0.95 * tolerance)
            shrink = valid & ~ok
            size[rows[shrink]] *= np.maximum(0.1, 0.9 * tolerance / dev[shrink])
        active[rows[~valid]] = False
        active[rows[ok]] = False
        if ok.any():
            done_rows.append(rows[ok])
            done.append((d1[ok], d2[ok], controls[ok]))
    if done:
        rows = np.concatenate(done_rows)
        d1, d2, controls = (np.concatenate(x) for x in zip(*done, strict=True))
        # the bounds of the curves kept, all at once (the same products row by row as in the loop)
        b1, b2, b3, _ = curve_bounds(controls)
        tables = arc_tables(controls, alone=True)   # the same floats in any batch: see corner_memo
        if sides.keep is not None:
            controls, b1, b2, b3 = _all_axes(sides.keep, whole[rows], controls, b1, b2, b3)
        # row by row on lists and iterated rows (views, as indexing gives them): no index per array
        for row, c, first, last, e1, e2, e3, table, length, g1, g2 in zip(
                rows.tolist(), controls, controls[:, 0], controls[:, -1], b1, b2, b3, tables, tables[:, -1].tolist(),
                d1.tolist(), d2.tolist(), strict=True):
            out[row] = (BlendPiece.made(c, first, last, e1, e2, e3, table, length), g1, g2)
        order = np.argsort(rows)   # the corners' order
        return out, (b1[order], b2[order], b3[order])
    dim = len(ps[0].start) if n else 0
    return out, (np.empty((0, dim)),) * 3


def _all_axes(keep: list[int], vertex: np.ndarray, controls: np.ndarray, *bounds: np.ndarray) -> tuple[np.ndarray, ...]:
    """Curves worked on the axes ``keep`` alone back on every axis: their control points (n, 6, D')
    with each curve's ``vertex`` (n, D) on the axes left out (none of its pieces moves there), and
    their derivative bounds (n, D'), 0 on those axes (what the frames' formulas give there)."""
    full = np.repeat(vertex[:, None, :], 6, axis=1)
    full[:, :, keep] = controls
    out = [full]
    for b in bounds:
        wide = np.zeros(vertex.shape)
        wide[:, keep] = b
        out.append(wide)
    return tuple(out)
