"""Path pieces the planner moves along: lines, arcs (helices) and corner blends.

Every piece is a curve ``q(s)`` over a parameter ``s`` in ``[0, length]``
with positions as numpy vectors over the channel axes (machine order).  The
planner only needs, per axis ``i``, bounds of the first three derivatives
``q_i'``, ``q_i''``, ``q_i'''`` with respect to ``s``: the motion along the
piece is ``s(t)`` with speed ``v``, acceleration ``a`` and jerk ``j``, so

    velocity_i     = q_i' v
    acceleration_i = q_i' a + q_i'' v²
    jerk_i         = q_i' j + 3 q_i'' v a + q_i''' v³

which holds for any parameterisation.  Lines and blends use arc length
(``|q'| = 1``); an arc whose start and end radii differ slightly (within the
CIRINERR tolerance) is a spiral, parameterised by its angle, with ``|q'|``
within a fraction of a percent of 1 and its bounds computed exactly.
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod

import numpy as np

# Gauss-Legendre nodes and weights on [0, 1] for the blends' arc length
_GL_X, _GL_W = np.polynomial.legendre.leggauss(8)
_GL_X = (_GL_X + 1.0) / 2.0
_GL_W = _GL_W / 2.0
# Bernstein (degree 5) -> power basis: B(u) = sum_k u^k (M @ C)_k
_BINOM = [1, 5, 10, 10, 5, 1]
_M5 = np.array([[(-1) ** (k - i) * math.comb(5, k) * math.comb(k, i) if k >= i else 0 for i in range(6)]
                for k in range(6)], dtype=float)


class Piece(ABC):
    """Base class: a curve over ``s`` in ``[0, length]`` with derivative bounds."""

    __slots__ = ("__dict__", "d1", "d2", "d3", "end", "start")

    length: float
    start: np.ndarray
    end: np.ndarray
    d1: np.ndarray   # per-axis max |q'|
    d2: np.ndarray   # per-axis max |q''|
    d3: np.ndarray   # per-axis max |q'''|

    curved = False

    @abstractmethod
    def derivatives(self, s: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """``q, q', q'', q'''`` at the parameters ``s`` (arrays of shape (n, axes))."""


    def frame(self, s: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Point, unit tangent and curvature vector (geometric, any parameterisation) at ``s``."""
        q, d1, d2, _ = self.derivatives(np.array([s]))
        t1 = d1[0]
        speed = float(np.linalg.norm(t1))
        t = t1 / speed
        k = (d2[0] - np.dot(d2[0], t) * t) / (speed * speed)
        return q[0], t, k

    def speed_factor(self) -> float:
        """Max of ``|q'|`` (1 for arc-length pieces): path speed = factor * v."""
        return 1.0


class LinePiece(Piece):
    """A straight segment."""

    __slots__ = ("u",)

    def __init__(self, start: np.ndarray, end: np.ndarray) -> None:
        self.start, self.end = start, end
        delta = end - start
        self.length = float(np.linalg.norm(delta))
        self.u = delta / self.length if self.length > 0 else np.zeros_like(delta)
        self.d1 = np.abs(self.u)
        self.d2 = self.d3 = np.zeros_like(delta)

    def derivatives(self, s):
        n = len(s)
        q = self.start + np.outer(s, self.u)
        zero = np.zeros((n, len(self.u)))
        return q, np.broadcast_to(self.u, (n, len(self.u))), zero, zero

    def frame(self, s):
        return self.start + s * self.u, self.u, np.zeros_like(self.u)

    def sub(self, s0: float, s1: float) -> LinePiece:
        return LinePiece(self.start + s0 * self.u, self.start + s1 * self.u)


def _range_max(theta0: float, theta1: float) -> tuple[float, float]:
    """Max of |sin| and |cos| over the angle interval between theta0 and theta1."""
    lo, hi = min(theta0, theta1), max(theta0, theta1)

    def hits(offset: float) -> bool:   # does [lo, hi] contain offset + k*pi ?
        k = math.ceil((lo - offset) / math.pi)
        return offset + k * math.pi <= hi

    ms = 1.0 if hits(math.pi / 2) else max(abs(math.sin(lo)), abs(math.sin(hi)))
    mc = 1.0 if hits(0.0) else max(abs(math.cos(lo)), abs(math.cos(hi)))
    return ms, mc


class ArcPiece(Piece):
    """A circular arc in the plane of axes ``ia``, ``io`` (indices), helical on the others.

    ``theta = theta0 + w s``, radius ``rho = r0 + dr s``, other axes linear.
    """

    __slots__ = ("center", "dr", "ia", "io", "lin", "r0", "theta0", "w")

    curved = True

    def __init__(self, start: np.ndarray, end: np.ndarray, ia: int, io: int, center: tuple[float, float],
                 sweep: float) -> None:
        self.start, self.end, self.ia, self.io = start, end, ia, io
        self.center = center
        r0 = math.hypot(start[ia] - center[0], start[io] - center[1])
        r1 = math.hypot(end[ia] - center[0], end[io] - center[1])
        self.theta0 = math.atan2(start[io] - center[1], start[ia] - center[0])
        other = end - start
        other[ia] = other[io] = 0.0
        planar = abs(sweep) * (r0 + r1) / 2.0
        self.length = length = math.hypot(planar, float(np.linalg.norm(other)))
        self.r0 = r0
        self.dr = (r1 - r0) / length
        self.w = sweep / length
        self.lin = other / length
        self._bounds(r0, r1, sweep)

    def _bounds(self, r0: float, r1: float, sweep: float) -> None:
        ms, mc = _range_max(self.theta0, self.theta0 + sweep)
        rmax, dr, w = max(r0, r1), abs(self.dr), abs(self.w)
        d1, d2, d3 = np.abs(self.lin), np.zeros_like(self.lin), np.zeros_like(self.lin)
        # q_a = rho cos(th): q' = dr cos - rho w sin; q'' = -2 dr w sin - rho w² cos;
        # q''' = -3 dr w² cos + rho w³ sin
        d1[self.ia] = dr * mc + rmax * w * ms
        d1[self.io] = dr * ms + rmax * w * mc
        d2[self.ia] = 2 * dr * w * ms + rmax * w * w * mc
        d2[self.io] = 2 * dr * w * mc + rmax * w * w * ms
        d3[self.ia] = 3 * dr * w * w * mc + rmax * w ** 3 * ms
        d3[self.io] = 3 * dr * w * w * ms + rmax * w ** 3 * mc
        self.d1, self.d2, self.d3 = d1, d2, d3

    def derivatives(self, s):
        th = self.theta0 + self.w * s
        c, sn = np.cos(th), np.sin(th)
        rho = self.r0 + self.dr * s
        w, dr = self.w, self.dr
        n, dim = len(s), len(self.start)
        q = self.start + np.outer(s, self.lin)
        d1 = np.broadcast_to(self.lin, (n, dim)).copy()
        d2 = np.zeros((n, dim))
        d3 = np.zeros((n, dim))
        ia, io = self.ia, self.io
        q[:, ia] = self.center[0] + rho * c
        q[:, io] = self.center[1] + rho * sn
        d1[:, ia] = dr * c - rho * w * sn
        d1[:, io] = dr * sn + rho * w * c
        d2[:, ia] = -2 * dr * w * sn - rho * w * w * c
        d2[:, io] = 2 * dr * w * c - rho * w * w * sn
        d3[:, ia] = -3 * dr * w * w * c + rho * w ** 3 * sn
        d3[:, io] = -3 * dr * w * w * sn - rho * w ** 3 * c
        return q, d1, d2, d3

    def speed_factor(self) -> float:
        rmax = max(self.r0, self.r0 + self.dr * self.length)
        return math.sqrt((self.dr ** 2 + (rmax * self.w) ** 2) + float(np.dot(self.lin, self.lin)))

    def sub(self, s0: float, s1: float) -> ArcPiece:
        q, _, _, _ = self.derivatives(np.array([s0, s1]))
        return ArcPiece(q[0], q[1], self.ia, self.io, self.center, self.w * (s1 - s0))


class BlendPiece(Piece):
    """A quintic Bézier joining two pieces with continuous tangent and curvature (G2).

    Built from the end points, unit tangents and curvature vectors of the
    pieces it joins; parameterised by arc length (the arc-length table is
    built on first use, so trial curves stay cheap).
    """

    __slots__ = ("_length", "coef", "samples", "table_s", "table_u")

    curved = True

    def __init__(self, p0, t0, k0, a: float, p5, t5, k5, b: float) -> None:
        c = np.array([p0, p0 + a * t0, p0 + 2 * a * t0 + 1.25 * a * a * k0,
                      p5 - 2 * b * t5 + 1.25 * b * b * k5, p5 - b * t5, p5])
        self._set(_M5 @ c)
        self._bounds()

    def _set(self, coef: np.ndarray) -> None:
        # power basis (6, D); derivative of order r: rows k >= r times k!/(k-r)!
        self.coef = [coef] + [coef[r:] * _PERM[r][:, None] for r in (1, 2, 3)]
        self.start, self.end = coef[0].copy(), coef.sum(axis=0)
        self._length = None
        self.table_s = None

    @property
    def length(self) -> float:
        if self._length is None:
            self._table()
        return self._length

    def _table(self) -> None:
        """Arc length at 33 parameters (8-point Gauss-Legendre on 32 intervals).  The same
        integral gives the length and the parameter of every point: a single coarser rule for
        the length was off by 3e-5 on sharp asymmetric curves, which sampling at 1 ms sees."""
        sig = np.sqrt(((_TABLE_V @ self.coef[1]) ** 2).sum(axis=1)).reshape(32, len(_GL_X))
        seg = (sig * _GL_W[None, :]).sum(axis=1) / 32.0
        self.table_u = _TABLE_NODES
        self.table_s = np.concatenate([[0.0], np.cumsum(seg)])
        self._length = float(self.table_s[-1])

    @classmethod
    def from_controls(cls, controls: np.ndarray, d1: np.ndarray, d2: np.ndarray, d3: np.ndarray) -> BlendPiece:
        """A blend whose derivative bounds are already known (scaled from a unit curve).

        Its length is integrated from the curve itself: the motion along it must
        end exactly where the curve does.
        """
        out = cls.__new__(cls)
        out._set(_M5 @ controls)
        out.d1, out.d2, out.d3 = d1, d2, d3
        return out

    def _d(self, u: np.ndarray, order: int) -> np.ndarray:
        """``order``-th derivative of B at the parameters u, shape (n, D)."""
        c = self.coef[order]
        return np.vander(u, len(c), increasing=True) @ c

    def _u_of_s(self, s: np.ndarray) -> np.ndarray:
        """Invert the arc length: Newton from the table."""
        if self.table_s is None:
            self._table()
        s = np.clip(s, 0.0, self.table_s[-1])
        u = np.interp(s, self.table_s, self.table_u)
        n = len(_GL_X)
        for _ in range(4):
            k = np.clip(np.searchsorted(self.table_u, u, side="right") - 1, 0, 31)
            u0 = self.table_u[k]
            x = (u0[:, None] + (u - u0)[:, None] * _GL_X[None, :]).ravel()
            sig = np.sqrt((self._d(x, 1) ** 2).sum(axis=1)).reshape(len(u), n)
            s_u = self.table_s[k] + (u - u0) * (sig * _GL_W[None, :]).sum(axis=1)
            speed = np.sqrt((self._d(u, 1) ** 2).sum(axis=1))
            u = np.clip(u - (s_u - s) / speed, 0.0, 1.0)
        return u

    def derivatives(self, s):
        return self._geometric(self._u_of_s(np.asarray(s, dtype=float)))

    def _geometric(self, u: np.ndarray, v: np.ndarray | None = None):
        if v is None:
            v = np.vander(u, 6, increasing=True)
        q = v @ self.coef[0]
        b1, b2, b3 = v[:, :5] @ self.coef[1], v[:, :4] @ self.coef[2], v[:, :3] @ self.coef[3]
        sig = np.sqrt((b1 * b1).sum(axis=1))[:, None]
        t = b1 / sig
        b2t = (b2 * t).sum(axis=1)[:, None]
        p = b2 - b2t * t                            # B'' without its tangential part
        k = p / sig ** 2                            # curvature vector
        t_u = p / sig
        dp = b3 - ((b3 * t).sum(axis=1)[:, None] + (b2 * t_u).sum(axis=1)[:, None]) * t - b2t * t_u
        dk = (dp / sig ** 2 - 2 * p * b2t / sig ** 3) / sig
        return q, t, k, dk

    @property
    def valid(self) -> bool:
        """False for a degenerate curve (a cusp where the control polygon folds back)."""
        return bool(np.isfinite(self.d3).all())

    def _bounds(self) -> None:
        sig = np.sqrt(((_BOUND_V[:, :5] @ self.coef[1]) ** 2).sum(axis=1))
        if sig.min() <= 1e-6 * sig.max():
            self.d1 = self.d2 = self.d3 = np.full(self.coef[0].shape[1], np.inf)
            self.samples = None
            return
        self.samples, t, k, dk = self._geometric(_BOUND_U, _BOUND_V)
        # sampled maxima with a margin: the curves are smooth polynomials of low degree
        self.d1 = np.minimum(np.abs(t).max(axis=0) * 1.02, 1.0)
        self.d2 = np.abs(k).max(axis=0) * 1.05
        self.d3 = np.abs(dk).max(axis=0) * 1.10

    def points(self, n: int = 33) -> np.ndarray:
        """``n`` points evenly spaced in the curve's parameter (97: the ones its bounds were sampled at)."""
        if n == len(_BOUND_U) and getattr(self, "samples", None) is not None:
            return self.samples
        return np.vander(np.linspace(0.0, 1.0, n), 6, increasing=True) @ self.coef[0]


_BOUND_U = np.linspace(0.0, 1.0, 97)
_BOUND_V = np.vander(_BOUND_U, 6, increasing=True)
_TABLE_NODES = np.linspace(0.0, 1.0, 33)
_TABLE_V = np.vander((_TABLE_NODES[:-1, None] + _GL_X[None, :] / 32.0).ravel(), 5, increasing=True)
_PERM = {r: np.array([math.perm(k, r) for k in range(r, 6)], dtype=float) for r in (1, 2, 3)}


def blends(p0: np.ndarray, t0: np.ndarray, k0: np.ndarray, a: np.ndarray, p5: np.ndarray, t5: np.ndarray,
           k5: np.ndarray, b: np.ndarray) -> list[BlendPiece]:
    """Many :class:`BlendPiece` at once (rows of the arrays): the same curves, bounds and
    arc-length tables as one by one, computed with array operations over all of them."""
    a2, b2 = a[:, None], b[:, None]
    c = np.stack([p0, p0 + a2 * t0, p0 + 2 * a2 * t0 + 1.25 * a2 * a2 * k0,
                  p5 - 2 * b2 * t5 + 1.25 * b2 * b2 * k5, p5 - b2 * t5, p5], axis=1)      # (n, 6, D)
    coef = _M5 @ c
    c1, c2, c3 = (coef[:, r:] * _PERM[r][None, :, None] for r in (1, 2, 3))
    # bounds at the 97 parameters (the formulas of BlendPiece._geometric, batched)
    q = _BOUND_V @ coef
    d1 = _BOUND_V[:, :5] @ c1
    d2 = _BOUND_V[:, :4] @ c2
    d3 = _BOUND_V[:, :3] @ c3
    sig = np.sqrt((d1 * d1).sum(axis=2))[..., None]
    with np.errstate(divide="ignore", invalid="ignore"):
        t = d1 / sig
        b2t = (d2 * t).sum(axis=2)[..., None]
        pv = d2 - b2t * t
        k = pv / sig ** 2
        t_u = pv / sig
        dp = d3 - ((d3 * t).sum(axis=2)[..., None] + (d2 * t_u).sum(axis=2)[..., None]) * t - b2t * t_u
        dk = (dp / sig ** 2 - 2 * pv * b2t / sig ** 3) / sig
    degenerate = sig[..., 0].min(axis=1) <= 1e-6 * sig[..., 0].max(axis=1)
    # arc-length tables
    tsig = np.sqrt(((_TABLE_V @ c1) ** 2).sum(axis=2)).reshape(len(a), 32, len(_GL_X))
    seg = (tsig * _GL_W[None, None, :]).sum(axis=2) / 32.0
    tables = np.concatenate([np.zeros((len(a), 1)), np.cumsum(seg, axis=1)], axis=1)
    b_d1 = np.minimum(np.abs(t).max(axis=1) * 1.02, 1.0)
    b_d2 = np.abs(k).max(axis=1) * 1.05
    b_d3 = np.abs(dk).max(axis=1) * 1.10
    ends = coef.sum(axis=1)
    lengths = tables[:, -1].tolist()
    out = []
    for i in range(len(a)):
        bp = BlendPiece.__new__(BlendPiece)
        bp.coef = [coef[i], c1[i], c2[i], c3[i]]
        bp.start, bp.end = coef[i, 0].copy(), ends[i]
        if degenerate[i]:
            bp.d1 = bp.d2 = bp.d3 = np.full(coef.shape[2], np.inf)
            bp.samples = None
        else:
            bp.d1, bp.d2, bp.d3 = b_d1[i], b_d2[i], b_d3[i]
            bp.samples = q[i]
        bp.table_u = _TABLE_NODES
        bp.table_s = tables[i]
        bp._length = lengths[i]
        out.append(bp)
    return out


def corner_deviations(samples: np.ndarray, start: np.ndarray, vertex: np.ndarray, end: np.ndarray) -> np.ndarray:
    """Largest distance from each row's curve points ``samples`` (n, m, D) to the two segments
    ``start``-``vertex`` and ``vertex``-``end`` (n, D) it replaces."""
    def to_segment(a, b):
        ab = (b - a)[:, None, :]
        rel = samples - a[:, None, :]
        den = np.maximum((ab * ab).sum(axis=2), 1e-300)
        s = np.clip((rel * ab).sum(axis=2) / den, 0.0, 1.0)
        gap = rel - s[..., None] * ab
        return (gap * gap).sum(axis=2)
    return np.sqrt(np.minimum(to_segment(start, vertex), to_segment(vertex, end)).max(axis=1))
