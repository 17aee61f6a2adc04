"""Corner blends: quintic Bézier curves joining two pieces with continuous tangent and curvature.

A blend is a :class:`~fagorcnc.plan.geometry.Piece` parameterised by arc length: its derivative
bounds are sampled at 97 parameters of the curve (:func:`curve_bounds`), its arc length is a table
of 32 Gauss-Legendre intervals (:func:`arc_tables`).  Batches of curves are made at once, as
arrays of control points (n, 6, D) (:func:`blends`, :func:`blend_rows`), and give one
:class:`BlendRow` per curve: a piece whose arrays are rows of the batch's.
"""

from __future__ import annotations

import math

import numpy as np

from .geometry import Piece

# Gauss-Legendre nodes and weights on [0, 1] for the blends' arc length
_GL_X, _GL_W = np.polynomial.legendre.leggauss(8)
_GL_X = (_GL_X + 1.0) / 2.0
_GL_W = _GL_W / 2.0
# Bernstein (degree 5) -> power basis: B(u) = sum_k u^k (M @ C)_k
_M5 = np.array([[(-1) ** (k - i) * math.comb(5, k) * math.comb(k, i) if k >= i else 0 for i in range(6)]
                for k in range(6)], dtype=float)


class BlendPiece(Piece):
    """A quintic Bézier joining two pieces with continuous tangent and curvature (G2).

    Built from the end points, unit tangents and curvature vectors of the
    pieces it joins; parameterised by arc length (the arc-length table is
    built on first use, so trial curves stay cheap).
    """

    __slots__ = ("_coef", "_length", "controls", "samples", "table_s", "table_u")

    curved = True

    def __init__(self, p0, t0, k0, a: float, p5, t5, k5, b: float) -> None:
        self._set(_controls(p0, t0, k0, a, p5, t5, k5, b))
        self._bounds()

    def _set(self, controls: np.ndarray) -> None:
        self.controls = controls
        self.start, self.end = controls[0].copy(), controls[-1].copy()
        self._coef = None
        self._length = None
        self.table_s = None
        self.table_u = _TABLE_NODES
        self.samples = None

    @property
    def coef(self) -> list[np.ndarray]:
        """Power-basis coefficients of B (6, D) and of its derivatives of order r = 1, 2, 3 (rows
        k >= r times k!/(k-r)!), made on first use: planning needs only bounds and length."""
        if self._coef is None:
            coef = _M5 @ self.controls
            self._coef = [coef] + [coef[r:] * _PERM[r][:, None] for r in (1, 2, 3)]
        return self._coef

    @property
    def length(self) -> float:
        if self._length is None:
            self._table()
        return self._length

    def _table(self) -> None:
        self.table_s = arc_tables(self.controls[None])[0]
        self._length = float(self.table_s[-1])

    @classmethod
    def from_controls(cls, controls: np.ndarray, d1: np.ndarray, d2: np.ndarray, d3: np.ndarray,
                      table: np.ndarray | None = None) -> BlendPiece:
        """A blend whose derivative bounds are already known (scaled from a unit curve), and its
        arc-length ``table`` if known too (also scaled: a curve's lengths scale with its size).

        Its length is integrated from the curve itself: the motion along it must
        end exactly where the curve does.
        """
        out = cls.__new__(cls)
        out._set(controls)
        out.d1, out.d2, out.d3 = d1, d2, d3
        if table is not None:
            out.table_s = table
            out._length = float(table[-1])
        return out

    @classmethod
    def made(cls, controls: np.ndarray, start: np.ndarray, end: np.ndarray, d1: np.ndarray, d2: np.ndarray,
             d3: np.ndarray, table: np.ndarray, length: float) -> BlendPiece:
        """:meth:`from_controls` with everything already computed (rows of a batch of curves made at
        once, :func:`blends`): its end points and length too."""
        out = cls.__new__(cls)
        out.controls, out.start, out.end, out.d1, out.d2, out.d3 = controls, start, end, d1, d2, d3
        out.table_s, out.table_u, out._length = table, _TABLE_NODES, length
        out._coef = out.samples = None
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

    def _geometric(self, u: np.ndarray):
        """Point, unit tangent, curvature vector and its arc-length derivative at the parameters u."""
        v = np.vander(u, 6, increasing=True)
        coef = self.coef
        q = v @ coef[0]
        b1, b2, b3 = v[:, :5] @ coef[1], v[:, :4] @ coef[2], v[:, :3] @ coef[3]
        return (q, *_frames(b1, b2, b3))

    @property
    def valid(self) -> bool:
        """False for a degenerate curve (a cusp where the control polygon folds back)."""
        return all(map(math.isfinite, self.d3.tolist()))   # plain floats: asked for every corner

    def _bounds(self) -> None:
        samples, d1, d2, d3, degenerate = _curve_bounds(self.controls[None])
        self.d1, self.d2, self.d3 = d1[0], d2[0], d3[0]
        self.samples = None if degenerate[0] else samples[:, :, 0]

    def points(self, n: int = 33) -> np.ndarray:
        """``n`` points evenly spaced in the curve's parameter (97: the ones its bounds were sampled at)."""
        if n == len(_BOUND_U) and self.samples is not None:
            return self.samples
        return np.vander(np.linspace(0.0, 1.0, n), 6, increasing=True) @ self.coef[0]


class BlendRow(BlendPiece):
    """A :class:`BlendPiece` of a batch of curves made at once: row ``_row`` of the batch's arrays
    ``_batch`` = (control points (n, 6, D), arc-length tables (n, 33)), with its start point and
    bounds (views of rows too).  Its control points, end point and arc-length table are made on
    first use (properties over slots of their own: a ``__getattr__`` would slow every attribute
    of the class): planning a corner asks for none of them (the limits come with the batch, the
    length from the table's last).  The same values as :meth:`BlendPiece.made` of the rows."""

    __slots__ = ("_batch", "_controls", "_end", "_row", "_table")

    @classmethod
    def of(cls, batch: tuple, row: int, start: np.ndarray, d1: np.ndarray, d2: np.ndarray, d3: np.ndarray,
           length: float) -> BlendRow:
        """Row ``row`` of ``batch`` (see the class), with its start point, bounds and arc length."""
        out = cls.__new__(cls)
        out._batch, out._row, out.start, out.d1, out.d2, out.d3, out._length = batch, row, start, d1, d2, d3, length
        out._controls = out._end = out._table = out._coef = out.samples = None
        out.table_u = _TABLE_NODES
        return out

    @classmethod
    def rows(cls, batch: tuple, d1: np.ndarray, d2: np.ndarray, d3: np.ndarray, lengths: list[float]) -> list[BlendRow]:
        """:meth:`of` of every row of ``batch`` (their start points the control points' first), in one
        loop: a call of :meth:`of` per curve costs about a fifth of a batch's Python work per curve."""
        new, nodes, out = cls.__new__, _TABLE_NODES, []
        for row, start, g, k, dk, length in zip(range(len(lengths)), batch[0][:, 0], d1, d2, d3, lengths, strict=True):
            c = new(cls)
            c._batch, c._row, c.start, c.d1, c.d2, c.d3, c._length = batch, row, start, g, k, dk, length
            c._controls = c._end = c._table = c._coef = c.samples = None
            c.table_u = nodes
            out.append(c)
        return out

    def __reduce__(self) -> tuple:
        """Pickled (a plan's segments, a process pool) as the :class:`BlendPiece` of its own rows alone,
        not its batch's arrays."""
        return BlendPiece.made, (self.controls, self.start, self.end, self.d1, self.d2, self.d3, self.table_s,
                                 self._length)


def _row_view(slot, make) -> property:
    """A property of :class:`BlendRow` kept in its slot ``slot``: ``make(batch, row)`` on first use."""
    def get(self: BlendRow) -> np.ndarray:
        value = slot.__get__(self)
        if value is None:
            value = make(self._batch, self._row)
            slot.__set__(self, value)
        return value
    return property(get, slot.__set__)


BlendRow.controls = _row_view(BlendRow._controls, lambda b, i: b[0][i])
BlendRow.end = _row_view(BlendRow._end, lambda b, i: b[0][i, -1])
BlendRow.table_s = _row_view(BlendRow._table, lambda b, i: b[1][i])

_BOUND_U = np.linspace(0.0, 1.0, 97)
_TABLE_NODES = np.linspace(0.0, 1.0, 33)
_PERM = {r: np.array([math.perm(k, r) for k in range(r, 6)], dtype=float) for r in (1, 2, 3)}


def _basis(u: np.ndarray, order: int) -> np.ndarray:
    """Matrix (len(u), 6) taking the control points to the ``order``-th derivative at the parameters u."""
    rows = _M5[order:] * _PERM[order][:, None] if order else _M5
    return np.vander(u, 6 - order, increasing=True) @ rows


#: B and its first three derivatives at the 97 bound parameters, stacked (4 * 97, 6)
_BOUND_B = np.vstack([_basis(_BOUND_U, r) for r in range(4)])
#: The rows of the first three derivatives alone (see :func:`curve_bounds`)
_DERIVATIVE_B = np.ascontiguousarray(_BOUND_B[len(_BOUND_U):])
#: The rows of the points and the first derivative alone (see :func:`curve_samples`)
_SAMPLE_B = np.ascontiguousarray(_BOUND_B[:2 * len(_BOUND_U)])
#: The 8 Gauss-Legendre nodes of each of the 32 arc-length table intervals, and B' there (256, 6)
TABLE_GAUSS = (_TABLE_NODES[:-1, None] + _GL_X[None, :] / 32.0).ravel()
_TABLE_B1 = _basis(TABLE_GAUSS, 1)
#: Multiply-adds of a matrix product that OpenBLAS still runs on one thread (see :func:`_apply`)
_SINGLE_THREAD = 4 * 65536


def _controls(p0, t0, k0, a, p5, t5, k5, b) -> np.ndarray:
    """Control points (..., 6, D) of the blend from its end points, unit tangents, curvature vectors
    and control spacings (arrays of vectors (..., D) and spacings (..., 1) work row by row)."""
    shape = np.shape(p0)
    out = np.empty((*shape[:-1], 6, shape[-1]))   # np.stack's array of the six rows, written in place
    out[..., 0, :] = p0
    np.add(p0, a * t0, out=out[..., 1, :])
    np.add(p0 + 2 * a * t0, 1.25 * a * a * k0, out=out[..., 2, :])
    np.add(p5 - 2 * b * t5, 1.25 * b * b * k5, out=out[..., 3, :])
    np.subtract(p5, b * t5, out=out[..., 4, :])
    out[..., 5, :] = p5
    return out


def _apply(basis: np.ndarray, controls: np.ndarray) -> np.ndarray:
    """``basis @ controls`` for every curve (control points (n, 6, D)), laid out (m, D, n): sums
    over the axes and maxima over the samples then run over whole rows of curves.  Relative to
    each curve's first point, so that small curves far from the origin keep their digits.  A few
    curves per matrix product: OpenBLAS runs products of more than 4 * 65536 multiply-adds on
    several threads, whose start-up costs more than it saves at these sizes (and takes a core)."""
    n, _, dim = controls.shape
    rel = (controls - controls[:, :1]).transpose(1, 2, 0)
    chunk = max(1, _SINGLE_THREAD // (len(basis) * 6 * dim))
    if n <= chunk:   # one product, laid out as it comes
        return (basis @ rel.reshape(6, -1)).reshape(len(basis), dim, n)
    out = np.empty((len(basis), dim, n))
    for i in range(0, n, chunk):
        part = rel[:, :, i:i + chunk]
        out[:, :, i:i + chunk] = (basis @ part.reshape(6, -1)).reshape(len(basis), dim, part.shape[2])
    return out


def _dot(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Dot products of the vectors along axis 1 of ``x`` and ``y``, that axis kept (length 1).  Over
    more than one curve (laid along axis 2), and over one curve of three axes or more, the products
    are added axis after axis to a sum from 0 (:func:`_axis_sums`): einsum's floats over a batch,
    and a single curve's the same as in a batch (einsum adds its axes in another order), which
    :mod:`~fagorcnc.plan.corner_memo` needs."""
    if x.ndim == 3 and (x.shape[2] > 1 or x.shape[1] > 2):
        return _axis_sums(x * y)[:, None]
    return np.einsum("id...,id...->i...", x, y)[:, None]


def _axis_sums(p: np.ndarray) -> np.ndarray:
    """The sums over the axes (axis -2) of products ``p`` of rows of more than one curve (the curves
    on the last axis): einsum's floats at a fraction of its cost (its set-up alone costs as much as a
    product over 100 curves).  Over more than one curve einsum's innermost loop runs over the curves
    and adds the axes' products in order to a sum from 0, as these sums over whole rows do; over one
    curve its loop runs over the axes, in another order (the callers then keep einsum)."""
    out = p[..., 0, :] + 0.0   # from 0, as einsum's: a sum of -0.0 terms is +0.0
    for i in range(1, p.shape[-2]):
        out += p[..., i, :]
    return out


def _frames(b1: np.ndarray, b2: np.ndarray, b3: np.ndarray, square: np.ndarray | None = None):
    """Unit tangent, curvature vector and its arc-length derivative from the first three
    derivatives of B (vectors along axis 1).  With s = |B'|, a = B'.B'', c = B'.B''' and
    e = B''.B'':  t = B'/s,  k = (B'' - (a/s²) B')/s²  and
    dk/ds = (B''' - 3 (a/s²) B'' + (4 (a/s²)² - (c + e)/s²) B')/s³,
    written with those dot products so that only a few passes run over the full arrays.
    ``square``: ``B'.B'`` when already computed."""
    inv2 = 1.0 / (_dot(b1, b1) if square is None else square)
    inv1 = np.sqrt(inv2)
    inv3 = inv2 * inv1
    ai = _dot(b1, b2) * inv2
    t = b1 * inv1
    k = (b2 - ai * b1) * inv2
    dk = b3 * inv3 - (3.0 * ai * inv3) * b2 + ((4.0 * ai * ai - (_dot(b1, b3) + _dot(b2, b2)) * inv2) * inv3) * b1
    return t, k, dk


def _frame_bounds(b1: np.ndarray, b2: np.ndarray, b3: np.ndarray, square: np.ndarray, tangents: bool = True):
    """The largest magnitudes over the samples (axis 0) of the unit tangent, the curvature vector and
    its arc-length derivative per axis, each (D, n): :func:`_frames`' formulas, operation for
    operation (the same floats), worked in two buffers instead of a new array per operation.
    Without ``tangents`` the tangent's is None (not worked)."""
    inv2 = 1.0 / square
    inv1 = np.sqrt(inv2)
    inv3 = inv2 * inv1
    ai = _dot(b1, b2) * inv2
    if tangents:
        buf = np.multiply(b1, inv1)
        top_t = np.abs(buf, out=buf).max(axis=0)
        np.multiply(ai, b1, out=buf)
    else:
        top_t, buf = None, np.multiply(ai, b1)
    np.subtract(b2, buf, out=buf)
    buf *= inv2
    top_k = np.abs(buf, out=buf).max(axis=0)
    tmp = np.multiply(3.0 * ai * inv3, b2)
    np.multiply(b3, inv3, out=buf)
    buf -= tmp
    np.multiply((4.0 * ai * ai - (_dot(b1, b3) + _dot(b2, b2)) * inv2) * inv3, b1, out=tmp)
    buf += tmp
    return top_t, top_k, np.abs(buf, out=buf).max(axis=0)


def _curve_bounds(controls: np.ndarray):
    """For control points (n, 6, D): the points at the 97 bound parameters (97, D, n), per-axis
    bounds ``d1, d2, d3`` (n, D) (sampled maxima with a margin: the curves are smooth polynomials
    of low degree; inf for a degenerate curve) and which curves are degenerate (a cusp, where the
    first derivative vanishes)."""
    m = len(_BOUND_U)
    b = _apply(_BOUND_B, controls)
    q = b[:m]
    q += controls[:, 0].T   # b is the product's own array
    return (q, *_derivative_bounds(b[m:]))


def curve_bounds(controls: np.ndarray, tangents: bool = True) -> tuple[np.ndarray | None, np.ndarray, np.ndarray,
                                                                      np.ndarray]:
    """:func:`_curve_bounds` without the points: ``d1, d2, d3`` and which curves are degenerate,
    the same floats (each row of a matrix product is its own dot products: the derivative rows
    alone give the same numbers) from three quarters of the products, for a batch that does not
    look at the curves' points.  Without ``tangents``, ``d1`` is None (a curve sized for its
    curvature does not look at it)."""
    return _derivative_bounds(_apply(_DERIVATIVE_B, controls), tangents)


def _derivative_bounds(b: np.ndarray, tangents: bool = True) -> tuple[np.ndarray | None, np.ndarray, np.ndarray,
                                                                      np.ndarray]:
    """The bounds and degeneracy of :func:`_curve_bounds` from the first three derivatives of B at
    the 97 bound parameters, stacked (3 * 97, D, n); ``d1`` None without ``tangents``."""
    m = len(_BOUND_U)
    b1, b2, b3 = b[:m], b[m:2 * m], b[2 * m:]
    square = _dot(b1, b1)
    sig = np.sqrt(square)
    degenerate = sig.min(axis=0)[0] <= 1e-6 * sig.max(axis=0)[0]
    with np.errstate(all="ignore"):   # a degenerate curve divides by zero; its bounds are set below
        top_t, top_k, top_dk = _frame_bounds(b1, b2, b3, square, tangents)
    d2 = top_k.T * 1.05
    d3 = top_dk.T * 1.10
    some = degenerate.any()   # most batches have none: three masked writes saved
    if some:
        d2[degenerate] = d3[degenerate] = np.inf
    if not tangents:
        return None, d2, d3, degenerate
    d1 = np.minimum(top_t.T * 1.02, 1.0)
    if some:
        d1[degenerate] = np.inf
    return d1, d2, d3, degenerate


def curve_samples(controls: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The points at the 97 bound parameters (97, D, n) of curves with control points (n, 6, D) and
    which curves are degenerate, as :func:`_curve_bounds` gives them (the same products, to the
    bit) without the bounds: half the products and none of the frames, for a curve whose
    deviation is tested before its bounds are asked (a corner curve shrunk to its tolerance)."""
    m = len(_BOUND_U)
    b = _apply(_SAMPLE_B, controls)
    q, b1 = b[:m], b[m:]
    q += controls[:, 0].T
    sig = np.sqrt(_dot(b1, b1))
    return q, sig.min(axis=0)[0] <= 1e-6 * sig.max(axis=0)[0]


def arc_tables(controls: np.ndarray, alone: bool = False) -> np.ndarray:
    """Arc length at the 33 table parameters (8-point Gauss-Legendre on 32 intervals) of each curve
    (control points (n, 6, D)) -> (n, 33).  The same integral gives the length and the parameter of
    every point: a single coarser rule for the length was off by 3e-5 on sharp asymmetric curves,
    which sampling at 1 ms sees.  ``alone``: see :func:`speed_tables`."""
    b1 = _apply(_TABLE_B1, controls)
    return speed_tables(np.sqrt(_dot(b1, b1))[:, 0], alone)


def speed_tables(speed: np.ndarray, alone: bool = False) -> np.ndarray:
    """Arc-length tables (n, 33) from the speeds ``|B'|`` of n curves at :data:`TABLE_GAUSS` (256, n).
    With ``alone``, each curve's table is the same floats however many curves are worked with it
    (what :mod:`~fagorcnc.plan.corner_memo` needs): one small product per curve, on a copy laid
    out curve by curve, where the weights times (8, n) columns round by the batch's width."""
    n = speed.shape[1]
    if alone:
        seg = np.ascontiguousarray(speed.T).reshape(n, 32, len(_GL_X)) @ _GL_W32   # (n, 32)
    else:
        seg = (_GL_W32 @ speed.reshape(32, len(_GL_X), -1)).T               # each interval's length
    out = np.empty((n, 33))                                              # rows: one curve each, contiguous
    out[:, 0] = 0.0
    np.cumsum(seg, axis=1, out=out[:, 1:])
    return out


_GL_W32 = _GL_W / 32.0


def blends(p0: np.ndarray, t0: np.ndarray, k0: np.ndarray, a: np.ndarray, p5: np.ndarray, t5: np.ndarray,
           k5: np.ndarray, b: np.ndarray) -> tuple[list[BlendPiece], np.ndarray]:
    """Many :class:`BlendPiece` at once (rows of the arrays): the same curves, bounds and
    arc-length tables as one by one, computed with array operations over all of them; and their
    points at the 97 bound parameters, (97, D, n) (the pieces do not keep them)."""
    curves, samples, _, _ = blend_rows(p0, t0, k0, a, p5, t5, k5, b)
    return curves, samples


def blend_rows(p0: np.ndarray, t0: np.ndarray, k0: np.ndarray, a: np.ndarray, p5: np.ndarray, t5: np.ndarray,
               k5: np.ndarray, b: np.ndarray) -> tuple[list[BlendPiece], np.ndarray, np.ndarray, tuple]:
    """:func:`blends` with what a batch asks of its curves next, as arrays: which are valid (each
    curve's :attr:`BlendPiece.valid`: all its ``d3`` finite) and the bounds ``(d1, d2, d3)`` (n, D),
    whose rows are the curves' own."""
    controls = _controls(p0, t0, k0, a[:, None], p5, t5, k5, b[:, None])
    samples, d1, d2, d3, _ = _curve_bounds(controls)
    tables = arc_tables(controls)
    curves = BlendRow.rows((controls, tables), d1, d2, d3, tables[:, -1].tolist())
    return curves, samples, np.isfinite(d3).all(axis=1), (d1, d2, d3)


def blend_groups(groups: list[tuple]) -> list[tuple[list[BlendPiece], np.ndarray]]:
    """:func:`blends` of each group of rows (its eight arrays, of three axes or more), the same curves and
    points as each group alone, with one set of bounds over all of them: a curve's bounds are those of
    its own columns (a product's row is its dot products, the frames element by element, the axes
    summed row by row for any number of curves, see :func:`_dot`), while an arc-length table rounds by
    its group's width, so each group keeps its own (:func:`speed_tables`)."""
    parts = [_controls(p0, t0, k0, a[:, None], p5, t5, k5, b[:, None]) for p0, t0, k0, a, p5, t5, k5, b in groups]
    samples, d1, d2, d3, _ = _curve_bounds(np.concatenate(parts))
    out, i = [], 0
    for controls in parts:
        j = i + len(controls)
        tables = arc_tables(controls)
        out.append((BlendRow.rows((controls, tables), d1[i:j], d2[i:j], d3[i:j], tables[:, -1].tolist()),
                     samples[:, :, i:j]))
        i = j
    return out


def corner_deviations(samples: np.ndarray, start: np.ndarray, vertex: np.ndarray, end: np.ndarray) -> np.ndarray:
    """Largest distance from the points ``samples`` (m, D, n) of each of n curves to the two segments
    ``start``-``vertex`` and ``vertex``-``end`` (rows of (n, D)) it replaces."""
    rel = samples - vertex.T
    many = rel.shape[2] > 1   # einsum's sums, made as rows (see _axis_sums)
    rr = _axis_sums(rel * rel) if many else np.einsum("idn,idn->in", rel, rel)

    def to_segment(w):   # squared distances (m, n) to the segments from the vertex to the vertex + w (D, n)
        # |rel - s w|² = |rel|² - 2 s rel.w + s² |w|², s the clipped share: passes over (m, n) only
        ww = np.einsum("dn,dn->n", w, w)   # w is a transpose: einsum's loop runs over the axes
        rw = _axis_sums(rel * w) if many else np.einsum("idn,dn->in", rel, w)
        share = np.minimum(np.maximum(rw / np.maximum(ww, 1e-300), 0.0), 1.0)
        return rr - share * (2.0 * rw - share * ww)

    gap = np.minimum(to_segment((start - vertex).T), to_segment((end - vertex).T))
    return np.sqrt(np.maximum(gap, 0.0).max(axis=0))
