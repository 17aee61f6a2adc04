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

from .corners import SHAPE
from .geometry import ArcPiece, BlendPiece, Piece, _controls, _curve_bounds, arc_tables
from .limits import CENTRIPETAL, CURVE_JERK

#: Points of the programmed path per side that a curve's deviation is measured against (as
#: :func:`~fagorcnc.plan.corners.deviation`: a line's points are collinear, the same distance).
REFERENCE = 17
#: Corners whose deviations are measured at once: a few (rows, 97, 32) arrays of about 200 kB each.
CHUNK = 64


class PieceRows:
    """Lines and arcs as arrays (one row each), evaluated all at once: points at many parameters,
    and the frame (point, unit tangent, curvature vector) at one parameter per row; the formulas
    of :class:`~fagorcnc.plan.geometry.ArcPiece`, a line being an arc that does not turn and whose
    radius grows along it from its start (its direction in the first two axes' plane, the rest
    linear).  The plane's two axes are picked by one-hot rows, so that every row takes the same
    array operations."""

    def __init__(self, pieces: list[Piece]) -> None:
        dim = len(pieces[0].start)
        base, lin, plane, shape = [], [], [], []
        for p in pieces:
            if isinstance(p, ArcPiece):
                ia, io = p.ia, p.io
                shape.append((*p.center, p.theta0, p.w, p.r0, p.dr))
                direction = p.lin.tolist()
            else:
                ia, io = 0, 1
                direction = p.u.tolist()
                start = p.start.tolist()
                shape.append((start[0], start[1], math.atan2(direction[1], direction[0]), 0.0, 0.0,
                               math.hypot(direction[0], direction[1])))
            row = p.start.tolist()
            row[ia] = row[io] = direction[ia] = direction[io] = 0.0
            base.append(row)
            lin.append(direction)
            plane.append((ia, io))
        self.base, self.lin = np.array(base), np.array(lin)
        self.cx, self.cy, self.theta0, self.w, self.r0, self.dr = np.array(shape).T
        axes = np.array(plane)
        self.ea = (axes[:, :1] == np.arange(dim)).astype(float)   # one-hot: the plane's first axis
        self.eo = (axes[:, 1:] == np.arange(dim)).astype(float)   # ... and its second

    def points(self, s: np.ndarray, rows: np.ndarray) -> np.ndarray:
        """Points (n, m, D) at the parameters ``s`` (n, m) of the pieces ``rows``."""
        th = self.theta0[rows, None] + self.w[rows, None] * s
        rho = self.r0[rows, None] + self.dr[rows, None] * s
        x = self.cx[rows, None] + rho * np.cos(th)
        y = self.cy[rows, None] + rho * np.sin(th)
        q = self.base[rows, None, :] + s[:, :, None] * self.lin[rows, None, :]
        q += x[:, :, None] * self.ea[rows, None, :]
        q += y[:, :, None] * self.eo[rows, None, :]
        return q

    def frames(self, s: np.ndarray, rows: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Point, unit tangent and curvature vector (each (n, D)) at one parameter per row."""
        th = self.theta0[rows] + self.w[rows] * s
        c, sn = np.cos(th), np.sin(th)
        rho = self.r0[rows] + self.dr[rows] * s
        w, dr = self.w[rows], self.dr[rows]
        ea, eo = self.ea[rows], self.eo[rows]
        q = self.base[rows] + s[:, None] * self.lin[rows]
        q += (self.cx[rows] + rho * c)[:, None] * ea
        q += (self.cy[rows] + rho * sn)[:, None] * eo
        d1 = self.lin[rows] + (dr * c - rho * w * sn)[:, None] * ea
        d1 += (dr * sn + rho * w * c)[:, None] * eo
        d2 = (-2 * dr * w * sn - rho * w * w * c)[:, None] * ea
        d2 += (2 * dr * w * c - rho * w * w * sn)[:, None] * eo
        square = (d1 * d1).sum(axis=1)[:, None]
        t = d1 / np.sqrt(square)
        k = (d2 - (d2 * t).sum(axis=1)[:, None] * t) / square
        return q, t, k


def make_blends(ps: list[Piece], qs: list[Piece], lim_p: np.ndarray, lim_q: np.ndarray, *,
                tolerance: float | None, speed: np.ndarray | None, acc: float, jerk: float,
                corner: bool = False) -> list[tuple[BlendPiece, float, float] | None]:
    """:func:`~fagorcnc.plan.corners.make_blend`'s general construction for the corners
    ``ps[i] -> qs[i]`` (rows), with ``lim_p``/``lim_q`` the most each side may give up (already
    the smaller of half its block and its length) and ``speed`` one per corner (or None): the
    same steps on every row at once, so the same curves up to rounding.  None where no curve fits."""
    n = len(ps)
    sides = PieceRows(ps + qs)   # rows 0 .. n - 1 the incoming pieces, n .. 2n - 1 the outgoing ones
    p_len = np.array([p.length for p in ps])
    vertex = np.array([p.end for p in ps])
    lim_p, lim_q = np.asarray(lim_p, dtype=float), np.asarray(lim_q, dtype=float)
    live = (lim_p > 1e-9) & (lim_q > 1e-9)
    longest = np.maximum(lim_p, lim_q)

    def curves(rows: np.ndarray, size: np.ndarray):
        d1, d2 = np.minimum(size, lim_p[rows]), np.minimum(size, lim_q[rows])
        q, t, k = sides.frames(np.concatenate([p_len[rows] - d1, d2]), np.concatenate([rows, rows + n]))
        m = len(rows)
        p0, t0, k0, p5, t5, k5 = q[:m], t[:m], k[:m], q[m:], t[m:], k[m:]
        controls = _controls(p0, t0, k0, (SHAPE * d1)[:, None], p5, t5, k5, (SHAPE * d2)[:, None])
        samples, b1, b2, b3, _ = _curve_bounds(controls)
        return d1, d2, controls, samples, b1, b2, b3, np.isfinite(b3).all(axis=1)

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
        d1, d2, controls, samples, b1, b2, b3, valid = curves(rows, size[rows])
        active[rows[~valid]] = False
        if tolerance is None:
            ok = valid
        else:
            dev = _deviations(sides, n, rows, p_len[rows], d1, d2, samples, vertex[rows], corner)
            ok = valid & (dev <= 0.95 * tolerance)
            shrink = valid & ~ok
            size[rows[shrink]] *= np.maximum(0.1, 0.9 * tolerance / dev[shrink])
        active[rows[ok]] = False
        if ok.any():
            done_rows.append(rows[ok])
            done.append((d1[ok], d2[ok], controls[ok], b1[ok], b2[ok], b3[ok]))
    if done:
        rows = np.concatenate(done_rows)
        d1, d2, controls, b1, b2, b3 = (np.concatenate(x) for x in zip(*done, strict=True))
        tables = arc_tables(controls)
        for i, row in enumerate(rows.tolist()):
            c = controls[i]
            out[row] = (BlendPiece.made(c, c[0], c[-1], b1[i], b2[i], b3[i], tables[i], float(tables[i, -1])),
                        float(d1[i]), float(d2[i]))
    return out


def _deviations(sides: PieceRows, n: int, rows: np.ndarray, p_len: np.ndarray, d1: np.ndarray,
                d2: np.ndarray, samples: np.ndarray, vertex: np.ndarray, corner: bool) -> np.ndarray:
    """Per row, :func:`~fagorcnc.plan.corners.deviation` of the curve sampled at ``samples``
    (97, D, n): with ``corner`` the distance from the programmed corner point to the curve,
    otherwise the largest distance from the curve to the stretch of path it replaces (corner i's
    pieces are the rows i and n + i of ``sides``)."""
    pts = samples.transpose(2, 0, 1) - vertex[:, None, :]              # (n, 97, D), from the corner
    if corner:
        return np.sqrt((pts * pts).sum(axis=2).min(axis=1))
    frac = np.linspace(0.0, 1.0, REFERENCE)[None, :]
    m = len(rows)
    both = sides.points(np.concatenate([p_len[:, None] - d1[:, None] * (1.0 - frac), d2[:, None] * frac]),
                        np.concatenate([rows, rows + n]))   # each side's points (the vertex twice)
    ref = np.concatenate([both[:m], both[m:, 1:]], axis=1) - vertex[:, None, :]   # (n, 33, D)
    a, ab = ref[:, :-1], ref[:, 1:] - ref[:, :-1]
    # the squared distance from each point x to each segment a + t (b - a) as
    # |x - a|² - t (2 (x - a).(b - a) - t |b - a|²), t the clipped share: four (n, 32, 97) arrays
    # worked on in place, segments before points so that the least over the segments runs
    # across whole rows of points
    cols = np.ascontiguousarray(pts.transpose(0, 2, 1))                 # (n, D, 97)
    den = np.maximum((ab * ab).sum(axis=2), 1e-300)[:, :, None]
    along = ab @ cols                                                    # (x - a).(b - a)
    along -= (a * ab).sum(axis=2)[:, :, None]
    gap = a @ cols                                                       # becomes |x - a|²
    gap *= -2.0
    gap += (pts * pts).sum(axis=2)[:, None, :]
    gap += (a * a).sum(axis=2)[:, :, None]
    t = np.divide(along, den)
    np.maximum(t, 0.0, out=t)
    np.minimum(t, 1.0, out=t)
    along *= 2.0
    den = t * den
    along -= den
    along *= t
    gap -= along
    return np.sqrt(np.maximum(gap.min(axis=1).max(axis=1), 0.0))
