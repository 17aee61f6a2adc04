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
    and the frame (point, unit tangent, curvature vector) at one parameter per row; the same
    formulas as :class:`~fagorcnc.plan.geometry.ArcPiece` and
    :class:`~fagorcnc.plan.geometry.LinePiece`."""

    def __init__(self, pieces: list[Piece]) -> None:
        n = len(pieces)
        self.n = n
        self.start = np.array([p.start for p in pieces])
        self.lin = np.array([p.lin if isinstance(p, ArcPiece) else p.u for p in pieces])
        arcs = [i for i, p in enumerate(pieces) if isinstance(p, ArcPiece)]
        self.arc = np.array(arcs, dtype=np.intp)
        rows = [pieces[i] for i in arcs]
        self.theta0 = np.array([a.theta0 for a in rows])
        self.w = np.array([a.w for a in rows])
        self.r0 = np.array([a.r0 for a in rows])
        self.dr = np.array([a.dr for a in rows])
        self.cx = np.array([a.center[0] for a in rows])
        self.cy = np.array([a.center[1] for a in rows])
        self.ia = np.array([a.ia for a in rows], dtype=np.intp)
        self.io = np.array([a.io for a in rows], dtype=np.intp)

    def points(self, s: np.ndarray, rows: np.ndarray | None = None) -> np.ndarray:
        """Points (n, m, D) at the parameters ``s`` (n, m) of the pieces ``rows`` (all: None)."""
        start, lin = (self.start, self.lin) if rows is None else (self.start[rows], self.lin[rows])
        q = start[:, None, :] + s[:, :, None] * lin[:, None, :]
        sel, at = self._arcs(rows)
        if len(sel):
            sa = s[at]
            th = self.theta0[sel, None] + self.w[sel, None] * sa
            rho = self.r0[sel, None] + self.dr[sel, None] * sa
            cols = np.arange(s.shape[1])[None, :]
            q[at[:, None], cols, self.ia[sel, None]] = self.cx[sel, None] + rho * np.cos(th)
            q[at[:, None], cols, self.io[sel, None]] = self.cy[sel, None] + rho * np.sin(th)
        return q

    def frames(self, s: np.ndarray, rows: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Point, unit tangent and curvature vector (each (n, D)) at one parameter per row."""
        q = self.points(s[:, None], rows)[:, 0]
        d1 = (self.lin if rows is None else self.lin[rows]).copy()
        d2 = np.zeros_like(d1)
        sel, at = self._arcs(rows)
        if len(sel):
            sa = s[at]
            th = self.theta0[sel] + self.w[sel] * sa
            c, sn = np.cos(th), np.sin(th)
            rho = self.r0[sel] + self.dr[sel] * sa
            w, dr, ia, io = self.w[sel], self.dr[sel], self.ia[sel], self.io[sel]
            d1[at, ia] = dr * c - rho * w * sn
            d1[at, io] = dr * sn + rho * w * c
            d2[at, ia] = -2 * dr * w * sn - rho * w * w * c
            d2[at, io] = 2 * dr * w * c - rho * w * w * sn
        square = (d1 * d1).sum(axis=1)[:, None]
        speed = np.sqrt(square)
        t = d1 / speed
        k = (d2 - (d2 * t).sum(axis=1)[:, None] * t) / square
        return q, t, k

    def _arcs(self, rows: np.ndarray | None) -> tuple[np.ndarray, np.ndarray]:
        """The arcs among ``rows``: their indices in the arc arrays and their positions in ``rows``."""
        if rows is None:
            return np.arange(len(self.arc)), self.arc
        where = np.full(self.n, -1, dtype=np.intp)
        where[self.arc] = np.arange(len(self.arc))
        sel = where[rows]
        at = np.flatnonzero(sel >= 0)
        return sel[at], at


def make_blends(ps: list[Piece], qs: list[Piece], lim_p: np.ndarray, lim_q: np.ndarray, *,
                tolerance: float | None, speed: np.ndarray | None, acc: float, jerk: float,
                corner: bool = False) -> list[tuple[BlendPiece, float, float] | None]:
    """:func:`~fagorcnc.plan.corners.make_blend`'s general construction for the corners
    ``ps[i] -> qs[i]`` (rows), with ``lim_p``/``lim_q`` the most each side may give up (already
    the smaller of half its block and its length) and ``speed`` one per corner (or None): the
    same steps on every row at once, so the same curves up to rounding.  None where no curve fits."""
    n = len(ps)
    side_p, side_q = PieceRows(ps), PieceRows(qs)
    p_len = np.array([p.length for p in ps])
    vertex = np.array([p.end for p in ps])
    lim_p, lim_q = np.asarray(lim_p, dtype=float), np.asarray(lim_q, dtype=float)
    live = (lim_p > 1e-9) & (lim_q > 1e-9)
    longest = np.maximum(lim_p, lim_q)

    def curves(rows: np.ndarray, size: np.ndarray):
        d1, d2 = np.minimum(size, lim_p[rows]), np.minimum(size, lim_q[rows])
        p0, t0, k0 = side_p.frames(p_len[rows] - d1, rows)
        p5, t5, k5 = side_q.frames(d2, rows)
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
            dev = _deviations(side_p, side_q, rows, p_len[rows], d1, d2, samples, vertex[rows], corner)
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


def _deviations(side_p: PieceRows, side_q: PieceRows, rows: np.ndarray, p_len: np.ndarray, d1: np.ndarray,
                d2: np.ndarray, samples: np.ndarray, vertex: np.ndarray, corner: bool) -> np.ndarray:
    """Per row, :func:`~fagorcnc.plan.corners.deviation` of the curve sampled at ``samples``
    (97, D, n): with ``corner`` the distance from the programmed corner point to the curve,
    otherwise the largest distance from the curve to the stretch of path it replaces."""
    pts = samples.transpose(2, 0, 1) - vertex[:, None, :]              # (n, 97, D), from the corner
    if corner:
        return np.sqrt((pts * pts).sum(axis=2).min(axis=1))
    frac = np.linspace(0.0, 1.0, REFERENCE)[None, :]
    ref_p = side_p.points(p_len[:, None] - d1[:, None] * (1.0 - frac), rows)
    ref_q = side_q.points(d2[:, None] * frac[:, 1:], rows)
    ref = np.concatenate([ref_p, ref_q], axis=1) - vertex[:, None, :]   # (n, 33, D)
    a, ab = ref[:, :-1], ref[:, 1:] - ref[:, :-1]
    den = np.maximum((ab * ab).sum(axis=2), 1e-300)[:, None, :]
    # the squared distance from each point x to each segment a + t (b - a) as
    # |x - a|² - t (2 (x - a).(b - a) - t |b - a|²), t the clipped share: four (n, 97, 32) arrays
    # worked on in place
    along = pts @ ab.transpose(0, 2, 1)                                  # (x - a).(b - a)
    along -= (a * ab).sum(axis=2)[:, None, :]
    gap = pts @ a.transpose(0, 2, 1)                                     # becomes |x - a|²
    gap *= -2.0
    gap += (pts * pts).sum(axis=2)[:, :, None]
    gap += (a * a).sum(axis=2)[:, None, :]
    t = np.divide(along, den)
    np.maximum(t, 0.0, out=t)
    np.minimum(t, 1.0, out=t)
    along *= 2.0
    den = t * den
    along -= den
    along *= t
    gap -= along
    return np.sqrt(np.maximum(gap.min(axis=2).max(axis=1), 0.0))
