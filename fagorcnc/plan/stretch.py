"""The stretch of programmed path a corner curve replaces, and how far the curve strays from it.

The end of the incoming piece and the start of the outgoing one, for many corners at once: the
pieces as arrays (:class:`PieceRows`), and the largest distance from a curve's points to that
stretch (:func:`stretch_deviations`): what HSC's CONTERROR bounds, the error between the programmed
path and the one run (seed 002 L13506).
The distance is exact for lines and for circular arcs (a point's nearest point on a circle lies
along its radius); spirals (an end radius within the arc tolerance of the start's) and helices
have no such form and are measured against a polyline of 17 points through them.
"""

from __future__ import annotations

import numpy as np

from .geometry import ArcPiece, Piece

#: Points per side of the polyline a spiral or a helix is measured against (16 chords).
REFERENCE = 17
#: An arc whose radius changes by less than this (mm) over its length is a circle to the distance
#: formula: the interpreter's end radius differs from the start's by rounding.
ROUND = 1e-9


class PieceRows:
    """Lines and arcs as arrays (one row each), evaluated all at once: points at many parameters,
    and the frame (point, unit tangent, curvature vector) at one parameter per row; the formulas
    of :class:`~fagorcnc.plan.geometry.ArcPiece`, a line being an arc that does not turn and whose
    radius grows along it from its start (its direction in the first two axes' plane, the rest
    linear).  The plane's two axes are picked by one-hot rows, so that every row takes the same
    array operations.

    With ``still``, the axes along which no piece moves (a contour in the XY plane: Z, and any
    axis the program leaves where it is) are left out of the rows when the first two axes are
    kept: every point of such a piece, and of a corner curve between two of them, has the piece's
    start there, so the rows' numbers on the axes kept are the same floats and the work on them
    is a fraction of it.  :attr:`keep` then lists the axes kept (None: all of them); ``still`` may
    also give those axes (another batch's, see :mod:`~fagorcnc.plan.corner_memo`)."""

    def __init__(self, pieces: list[Piece], still: bool | tuple[int, ...] = False) -> None:
        n = len(pieces)
        arc = [isinstance(p, ArcPiece) for p in pieces]
        start = np.array([p.start for p in pieces])
        direction = np.array([p.lin if a else p.u for p, a in zip(pieces, arc)])  # noqa: B905 (one flag a piece)
        shape = np.empty((n, 6))                                    # cx, cy, theta0, w, r0, dr
        axes = np.empty((n, 2), dtype=np.intp)
        arcs = np.array(arc, dtype=bool)
        if arcs.any():
            rows = np.array([(*p.center, p.theta0, p.w, p.r0, p.dr, p.length, p.ia, p.io)
                             for p, a in zip(pieces, arc) if a])  # noqa: B905
            shape[arcs] = rows[:, :6]
            axes[arcs] = rows[:, 7:]
            length = rows[:, 6]
        #: the axes the rows hold (None: every axis)
        self.keep: list[int] | None = None
        if still:
            if still is True:
                moving = (direction != 0.0).any(axis=0)
                if arcs.any():
                    moving[axes[arcs].ravel()] = True   # an arc's plane axes, whatever its radius
            else:   # the axes to keep, given (a superset of those the pieces move along)
                moving = np.zeros(start.shape[1], dtype=bool)
                moving[list(still)] = True
            if moving[:2].all() and not moving.all():
                keep = np.flatnonzero(moving)
                start, direction = start[:, keep], direction[:, keep]
                if arcs.any():   # the plane axes' places among the axes kept
                    axes[arcs] = np.searchsorted(keep, axes[arcs])
                self.keep = keep.tolist()
        dim = start.shape[1]
        lines = ~arcs
        if lines.any():   # a line: in the first two axes' plane, its angle there and its speed in it
            u, at = direction[lines], start[lines]
            shape[lines] = np.stack([at[:, 0], at[:, 1], np.arctan2(u[:, 1], u[:, 0]), np.zeros(len(u)),
                                     np.zeros(len(u)), np.hypot(u[:, 0], u[:, 1])], axis=1)
            axes[lines] = (0, 1)
        self.cx, self.cy, self.theta0, self.w, self.r0, self.dr = shape.T
        self.axes = axes                                            # the plane's two axes
        self.ea = (axes[:, :1] == np.arange(dim)).astype(float)   # one-hot: the plane's first axis
        self.eo = (axes[:, 1:] == np.arange(dim)).astype(float)   # ... and its second
        self.off = 1.0 - self.ea - self.eo                          # one-hot: the axes off the plane
        self.base, self.lin = start * self.off, direction * self.off
        #: the plane's axes when every row has the same (lines count as in the first two axes')
        same = (axes == axes[0]).all()
        self.plane = (int(axes[0, 0]), int(axes[0, 1])) if same else None
        self.straight = lines                                       # a line: an arc that does not turn
        self.circular = np.zeros(n, dtype=bool)                     # arcs in their plane of constant radius
        if arcs.any():
            self.circular[arcs] = (np.abs(self.dr[arcs]) * length <= ROUND) & ~self.lin[arcs].any(axis=1)
        #: every row's numbers side by side (its shape, then base, lin, ea and eo): a batch takes its
        #: rows with one index instead of one per array
        self.packed = np.concatenate([shape, self.base, self.lin, self.ea, self.eo], axis=1)
        #: the same by columns (6 + 4 D, n): what :meth:`frames` works on
        self.columns = np.ascontiguousarray(self.packed.T)

    def _rows(self, rows: np.ndarray) -> tuple[np.ndarray, ...]:
        """The numbers of the pieces ``rows``, as views of one indexed copy: cx, cy, theta0, w, r0,
        dr (m,) and base, lin, ea, eo (m, D)."""
        packed = self.packed[rows]
        dim = (packed.shape[1] - 6) // 4
        return (*packed[:, :6].T, *(packed[:, 6 + i * dim:6 + (i + 1) * dim] for i in range(4)))

    def points(self, s: np.ndarray, rows: np.ndarray) -> np.ndarray:
        """Points (n, m, D) at the parameters ``s`` (n, m) of the pieces ``rows``."""
        cx, cy, theta0, w, r0, dr, base, lin, ea, eo = self._rows(rows)
        th = theta0[:, None] + w[:, None] * s
        rho = r0[:, None] + dr[:, None] * s
        x = cx[:, None] + rho * np.cos(th)
        y = cy[:, None] + rho * np.sin(th)
        q = base[:, None, :] + s[:, :, None] * lin[:, None, :]
        q += x[:, :, None] * ea[:, None, :]
        q += y[:, :, None] * eo[:, None, :]
        return q

    def frames(self, s: np.ndarray, rows: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Point, unit tangent and curvature vector (each (n, D)) at one parameter per row.  Worked
        axis by axis on (D, n) arrays (views of them are returned): every operation then runs over
        whole rows of the batch rather than over the D numbers of each row; the sums over the axes
        add them in the order a sum along a row of D does, so the floats are the same."""
        packed = self.columns.take(rows, axis=1)                   # (6 + 4 D, n)
        dim = (len(packed) - 6) // 4
        cx, cy, theta0, w, r0, dr = packed[:6]
        base, lin, ea, eo = (packed[6 + i * dim:6 + (i + 1) * dim] for i in range(4))
        th = theta0 + w * s
        c, sn = np.cos(th), np.sin(th)
        rho = r0 + dr * s
        q = base + s * lin
        q += (cx + rho * c) * ea
        q += (cy + rho * sn) * eo
        # the products the formulas share, made once (the same floats: rho * w * c is (rho * w) * c,
        # and -2 dr w = -(2 dr w) to the bit, its sign included)
        rw, turn = rho * w, 2 * dr * w
        rww = rw * w
        d1 = lin + (dr * c - rw * sn) * ea
        d1 += (dr * sn + rw * c) * eo
        d2 = (-(turn * sn) - rww * c) * ea
        d2 += (turn * c - rww * sn) * eo
        square = _axis_sum(d1 * d1)
        t = d1 / np.sqrt(square)
        k = (d2 - _axis_sum(d2 * t) * t) / square
        return q.T, t.T, k.T


def _axis_sum(x: np.ndarray) -> np.ndarray:
    """The sums over the axes (axis 0) of ``x`` (D, n), added first to last: the floats of
    ``x.T.sum(axis=1)`` (a sum along a row of fewer than 8 numbers adds them in order)."""
    out = x[0].copy()
    for row in x[1:]:
        out += row
    return out


def stretch_deviations(sides: PieceRows, incoming: np.ndarray, outgoing: np.ndarray, p_len: np.ndarray,
                       d1: np.ndarray, d2: np.ndarray, samples: np.ndarray, vertex: np.ndarray,
                       corner: bool, ends: tuple[np.ndarray, np.ndarray] | None = None) -> np.ndarray:
    """Per corner (its pieces the rows ``incoming`` and ``outgoing`` of ``sides``), the deviation of
    its curve sampled at ``samples`` (97, D, m), which takes ``d1`` from the end of the incoming
    piece (of length ``p_len``) and ``d2`` from the start of the outgoing one: with ``corner`` the
    distance from the programmed corner point ``vertex`` to the curve (#ROUNDPAR e, seed 002
    L8124), otherwise the largest distance from the curve to the stretch of path it replaces.
    ``ends``: the stretches' ends when already known (a batch has them): the points (2m, D) at
    ``p_len - d1`` on the incoming pieces then at ``d2`` on the outgoing ones (the curves' own
    ends, :meth:`PieceRows.frames`), and those (2m, D) at ``p_len`` on the incoming pieces then
    at 0 on the outgoing ones (:meth:`PieceRows.points`: the same floats)."""
    pts = samples.transpose(2, 0, 1) - vertex[:, None, :]              # (m, 97, D), from the corner
    square = np.einsum("mkd,mkd->mk", pts, pts)                         # |x|², (m, 97)
    if corner:
        return np.sqrt(square.min(axis=1))
    # both sides of every corner at once: the incoming pieces' rows, then the outgoing ones'
    m = len(d1)
    both = np.concatenate([vertex, vertex])
    at = None
    if ends is not None:   # each side's (a, b): the incoming (moved, fixed), the outgoing (fixed, moved)
        moved, fixed = ends
        at = np.empty((2 * m, 2, moved.shape[1]))
        at[:m, 0], at[:m, 1], at[m:, 0], at[m:, 1] = moved[:m], fixed[:m], fixed[m:], moved[m:]
        at -= both[:, None, :]
    gap = _gaps(sides, np.concatenate([incoming, outgoing]), np.concatenate([p_len - d1, np.zeros(m)]),
                np.concatenate([p_len, d2]), np.concatenate([pts, pts]), np.concatenate([square, square]), both, at)
    return np.sqrt(np.maximum(np.minimum(gap[:m], gap[m:]).max(axis=1), 0.0))


def _gaps(sides: PieceRows, rows: np.ndarray, s0: np.ndarray, s1: np.ndarray, pts: np.ndarray,
          square: np.ndarray, vertex: np.ndarray, ends: np.ndarray | None = None) -> np.ndarray:
    """Squared distances (m, k) from the points ``pts`` (m, k, D, relative to each row's ``vertex``;
    ``square`` their squared norms) to the stretch ``[s0, s1]`` of the pieces ``rows`` (its ends
    ``ends`` (m, 2, D) relative to the vertex when known).  Circular arcs and lines side by side
    all take the arcs' formula (cheaper than splitting the arrays), and the lines' rows then the
    segments' one."""
    if ends is None:
        ends = sides.points(np.stack([s0, s1], axis=1), rows) - vertex[:, None, :]   # (m, 2, D): a, b
    dots = pts @ ends.transpose(0, 2, 1)                                # x.a, x.b (m, k, 2)
    lengths = np.einsum("mjd,mjd->mj", ends, ends)                      # |a|², |b|² (m, 2)
    to_a = square - 2.0 * dots[:, :, 0] + lengths[:, :1]                # |x - a|²
    straight, circular = sides.straight[rows], sides.circular[rows]
    if straight.all():
        return _to_segments(to_a, dots, ends)
    gap = _to_arcs(sides, rows, pts, square, vertex, ends, dots, lengths, to_a)
    if straight.any():   # the lines' rows alone (the formula is row by row: the same floats)
        gap[straight] = _to_segments(to_a[straight], dots[straight], ends[straight])
    other = ~(straight | circular)
    if other.any():
        gap[other] = _to_chords(sides, rows[other], s0[other], s1[other], pts[other], vertex[other])
    return gap


def _to_segments(to_a: np.ndarray, dots: np.ndarray, ends: np.ndarray) -> np.ndarray:
    """Squared distances from the points to the segments a + t (b - a) between ``ends`` (m, 2, D):
    |x - a|² - t (2 (x - a).(b - a) - t |b - a|²), t the clipped share (``to_a``: |x - a|²,
    ``dots``: x.a and x.b)."""
    a, ab = ends[:, 0], ends[:, 1] - ends[:, 0]
    den = np.maximum((ab * ab).sum(axis=1), 1e-300)[:, None]
    along = dots[:, :, 1] - dots[:, :, 0]
    along -= (a * ab).sum(axis=1)[:, None]                              # (x - a).(b - a)
    t = np.minimum(np.maximum(along / den, 0.0), 1.0)
    along *= 2.0
    along -= t * den
    along *= t
    return to_a - along


def _in_plane(sides: PieceRows, rows: np.ndarray, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The coordinates of ``x`` (m, ..., D) along the plane axes of each row: two (m, ...) arrays."""
    if sides.plane is not None:
        ia, io = sides.plane
        return x[..., ia], x[..., io]
    axes = sides.axes[rows].reshape(len(rows), *([1] * (x.ndim - 2)), 2)
    return tuple(np.take_along_axis(x, axes[..., i:i + 1], axis=-1)[..., 0] for i in (0, 1))


def _to_arcs(sides: PieceRows, rows: np.ndarray, pts: np.ndarray, square: np.ndarray, vertex: np.ndarray,
             ends: np.ndarray, dots: np.ndarray, lengths: np.ndarray, to_a: np.ndarray) -> np.ndarray:
    """Squared distances from the points (m, k, D) to circular arcs in their planes, between their
    ``ends`` a, b (m, 2, D; ``dots``: x.a and x.b, ``lengths``: |a|² and |b|², ``to_a``: |x - a|²):
    where a point lies within the stretch's sector round the centre, its nearest point is on its
    radius ((rho - r)² and the offset from the plane); elsewhere the distance to a point of the
    circle grows with the angle between them, so the nearest is one of the ends.  The sector is
    tested with cross products of radius vectors, not angles."""
    va, vo = _in_plane(sides, rows, vertex)
    ca, co = (sides.cx[rows] - va)[:, None], (sides.cy[rows] - vo)[:, None]   # the centre, from the vertex
    # the points' plane coordinates as arrays of their own: each is read twice below, and a strided
    # view against a column costs a few times the copy
    xa, xo = (np.ascontiguousarray(x) for x in _in_plane(sides, rows, pts))
    ea, eo = _in_plane(sides, rows, ends)                               # the ends in the plane (m, 2)
    # off the plane, every point of the arc is where a is: |x - a|² less its part in the plane
    da, do = xa - ea[:, :1], xo - eo[:, :1]
    radial = to_a - da * da
    radial -= do * do
    ra, ro = xa - ca, xo - co                                           # each point from the centre (m, k)
    ea, eo = ea - ca, eo - co                                           # the ends' radius vectors A, B
    rho = np.sqrt(ra * ra + ro * ro)
    rho -= np.sqrt(ea[:, :1] * ea[:, :1] + eo[:, :1] * eo[:, :1])
    radial += rho * rho
    # within the sector from A to B, turning the arc's way (more than half a turn: outside neither half-plane)
    # (the turn's sign on A and B, not on the (m, k) cross products: a product by -1 is exact, so the
    # signs compared are the same; a line's rows, whose sign is 0, take the segments' formula after)
    sign = np.sign(sides.w[rows])[:, None]
    sa, so = sign * ea, sign * eo
    after_a = sa[:, :1] * ro - so[:, :1] * ra >= 0.0
    before_b = ra * so[:, 1:] - ro * sa[:, 1:] >= 0.0
    wide = sign * (ea[:, :1] * eo[:, 1:] - eo[:, :1] * ea[:, 1:]) < 0.0
    inside = np.where(wide, after_a | before_b, after_a & before_b)
    to_b = square - 2.0 * dots[:, :, 1] + lengths[:, 1:]
    return np.where(inside, radial, np.minimum(to_a, to_b))


def _to_chords(sides: PieceRows, rows: np.ndarray, s0: np.ndarray, s1: np.ndarray, pts: np.ndarray,
               vertex: np.ndarray) -> np.ndarray:
    """Squared distances from the points (m, k, D) to the polylines of :data:`REFERENCE` points
    through the stretches [s0, s1] (spirals and helices)."""
    frac = np.linspace(0.0, 1.0, REFERENCE)[None, :]
    ref = sides.points(s0[:, None] + (s1 - s0)[:, None] * frac, rows) - vertex[:, None, :]   # (m, 17, D)
    a, ab = ref[:, :-1], ref[:, 1:] - ref[:, :-1]
    # |x - a|² - t (2 (x - a).(b - a) - t |b - a|²) from each point x to each segment a + t (b - a),
    # t the clipped share: (m, 16, k) arrays worked on in place, the products over the axes as
    # matrix products
    cols = np.ascontiguousarray(pts.transpose(0, 2, 1))                 # (m, D, k)
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
    return gap.min(axis=1)
