"""What happens where two pieces meet: stop, run through, or blend (seed 002 ch. 9, ch. 18).

* G07/G60 (square corner, WAITINPOS) and G50 (semi-rounded, NULL): the
  commanded motion reaches every block end at zero speed (seed 002 L7991-L8070,
  link types L16730-L16751); G07 then waits the in-position time.
* G05/G61 (controlled rounding, PRESENT): every junction that is not already
  tangent- and curvature-continuous is replaced by a curve (not an arc,
  L8096) whose size follows #ROUNDPAR: type 1 the smallest curve that keeps
  F within the deviation e, type 2 the one that can be run at f % of F, type 3
  the given distances, type 4 the deviation e (F lowered as needed); each
  distance at most half of its block (L8133).
* HSC (all modes): corners whose included angle is below CORNER are sharp
  (stop, L13537); the others are blended within the tolerance, so the path
  never leaves the programmed one by more than E.

A blend is a quintic Bézier with the tangent *and curvature* of both pieces
at its ends, so the axes' accelerations stay continuous through it.
Rapid moves always stop at their ends.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from .blend import _BOUND_U, TABLE_GAUSS, BlendPiece, blend_groups, blends, corner_deviations, speed_tables
from .geometry import LinePiece, Piece
from .limits import CENTRIPETAL, CURVE_JERK
from .stretch import PieceRows, stretch_deviations

#: Control-point spacing of a blend as a fraction of its length on each side.
SHAPE = 0.375
#: Tangent / curvature differences below these run through without a blend.
TANGENT_EPS = 1e-10
CURVATURE_EPS = 1e-10


#: Parts a corner curve is planned in when the planner has no jerk limit (see :func:`split_blend`).
#: G05 zig-zag of 0.05 mm steps, jerk off, planned ÷ time-optimal bound: 1.089 in 16 parts with the
#: whole curve's margins, 1.066 in 32; with :data:`PART_MARGIN` 1.066 in 16 and 1.04 in 32.
BLEND_PARTS = 32
#: A part's bounds of ``|q'|`` and ``|q''|`` per axis: the largest of its 97 samples times
#: ``1 + PART_MARGIN`` plus :data:`PART_CURVE` times the samples' largest second difference (see
#: :func:`part_bounds`), never above the whole curve's margins (2 % and 5 %).
PART_MARGIN = 0.005
PART_CURVE = 2.0


def split_blend(blend: BlendPiece, parts: int) -> list[BlendPiece]:
    """The corner curve as ``parts`` curves of equal parameter range (de Casteljau subdivision of its
    control points: the same curve, point for point), each with the derivative bounds of its own
    stretch.  A corner curve's curvature runs from the pieces' at its ends to its largest in the
    middle; in parts, the ends get caps from their own (lower) curvature instead of the middle's.
    The first two bounds of each part are :func:`part_bounds` (the third, which only a jerk limit
    uses, keeps its margin)."""
    out = []
    rest = blend.controls
    for i in range(parts, 1, -1):
        left, rest = _subdivide(rest, 1.0 / i)
        out.append(left)
    out.append(rest)
    pieces = []
    for controls in out:
        piece = BlendPiece.__new__(BlendPiece)
        piece._set(controls)
        piece._bounds()
        if piece.samples is not None:   # not degenerate (a degenerate part's bounds are infinite)
            _, t, k, _ = piece._geometric(_BOUND_U)
            piece.d1 = np.minimum(np.minimum(part_bounds(t), piece.d1), 1.0)
            piece.d2 = np.minimum(part_bounds(k), piece.d2)
        pieces.append(piece)
    return pieces


def part_bounds(samples: np.ndarray) -> np.ndarray:
    """Per-axis bound of ``|f|`` over a part from ``f`` at its 97 bound parameters (97, D): the largest
    ``|f_i|`` sampled, times ``1 + PART_MARGIN``, plus ``PART_CURVE`` times the largest second
    difference of ``|f_i|``.  Between two samples ``h`` apart a smooth ``|f_i|`` exceeds the larger
    by at most ``h² max|f_i''| / 8``, about an eighth of a second difference: the rule keeps 16
    times that, and a kink (``|f_i|`` through 0) only widens it.  A part is a 32nd of a corner curve,
    sampled as finely as 3 000 points over the whole: its tangent and curvature vary little between
    samples, where the whole curve's 5 % on ``q''`` stood for 97 samples over the whole turn
    (dense check, 4 001 points on 2 400 random curves and turns in 16 and 32 parts: never above)."""
    a = np.abs(samples)
    second = np.abs(a[2:] - 2.0 * a[1:-1] + a[:-2]).max(axis=0)
    return a.max(axis=0) * (1.0 + PART_MARGIN) + PART_CURVE * second


def _subdivide(controls: np.ndarray, u: float) -> tuple[np.ndarray, np.ndarray]:
    """Control points of the Bézier curve over ``[0, u]`` and over ``[u, 1]``."""
    rows = [controls]
    while len(rows[-1]) > 1:
        c = rows[-1]
        rows.append((1.0 - u) * c[:-1] + u * c[1:])
    left = np.array([r[0] for r in rows])
    right = np.array([r[-1] for r in rows[::-1]])
    return left, right


def transition_curve(p: LinePiece, k: np.ndarray, steps: list[float], tol: float,
                     other: tuple | None = None) -> tuple[tuple | None, tuple | None]:
    """The first of the transition curves over ``steps`` from the start of ``p`` back to its line from
    the curvature ``k`` that keeps the tolerance, and its step (None: none does), all computed at
    once; with ``other`` (the eight rows of :func:`~fagorcnc.plan.blend.blends` of one more curve, of
    three axes or more) that curve made with them (:func:`~fagorcnc.plan.blend.blend_groups`): its
    curves and points, as blends gives them (else None)."""
    size = np.array(steps)
    n = len(steps)
    # the rows repeated (copies: np.broadcast_to costs as much as a few array operations)
    start, u = p.start[None].repeat(n, 0), p.u[None].repeat(n, 0)
    ends = p.start + size[:, None] * p.u
    rows = (start, u, k[None].repeat(n, 0), SHAPE * size, ends, u, np.zeros((n, len(k))), SHAPE * size)
    if other is None:
        (curves, samples), made = blends(*rows), None
    else:
        (curves, samples), made = blend_groups([rows, other])
    # the deviation from the stretch of line the curve replaces: from its start to the curve's end
    for curve, step, dev in zip(curves, steps, corner_deviations(samples, start, start, ends).tolist(), strict=True):
        if curve.valid and dev <= 0.95 * tol:
            return (curve, step), made
    return None, made


def _blend(p: Piece, q: Piece, d1: float, d2: float) -> BlendPiece:
    p0, t0, k0 = p.frame(p.length - d1)
    p5, t5, k5 = q.frame(d2)
    return BlendPiece(p0, t0, k0, SHAPE * d1, p5, t5, k5, SHAPE * d2)


def deviation(blend: BlendPiece, p: Piece, q: Piece, d1: float, d2: float, corner: bool) -> float:
    """Largest distance from the blend to the stretch of programmed path it replaces
    (HSC), or with ``corner`` the distance from the programmed corner point to the
    curve (#ROUNDPAR e, L8124): :func:`~fagorcnc.plan.stretch.stretch_deviations` of one corner."""
    pts = blend.points(97)
    if corner:
        return float(np.sqrt(((pts - p.end) ** 2).sum(axis=1)).min())
    return float(stretch_deviations(PieceRows([p, q]), _FIRST, _SECOND, np.array([p.length]), np.array([d1]),
                                    np.array([d2]), pts[:, :, None], p.end[None], False)[0])


_FIRST, _SECOND = np.array([0]), np.array([1])


def _dynamic_scale(blend: BlendPiece, speed: float, acc: float, jerk: float) -> float:
    """Factor by which the blend must grow so that ``speed`` fits its curvature limits."""
    k = float(np.linalg.norm(blend.d2))
    dk = float(np.linalg.norm(blend.d3))
    need = k * speed * speed / (CENTRIPETAL * acc)
    if jerk != math.inf:
        need = max(need, math.sqrt(dk * speed ** 3 / (CURVE_JERK * jerk)))
    return need


#: Line-line corners: unit curves (size 1) in the corner's plane (x along the incoming line), one
#: per 0.25 degree of turn k, filled in on first use: the support functions of their tangents,
#: curvatures and curvature derivatives at the 97 bound parameters (for each direction in the
#: plane, every 1 degree round, the largest of the samples' components along it),
#: their deviations from the corner point and from the path, and whether the curve is valid (1),
#: has none (-1) or is not computed yet (0).
_STEP = 0.25
_TURNS = int(180 / _STEP) + 2
_PHI = math.radians(1.0)
_PHIS = 360
_UNIT_H = np.zeros((_TURNS, 3, _PHIS + 2))
_UNIT_DEV = np.zeros((_TURNS, 2))
_UNIT_STATE = np.zeros(_TURNS, dtype=np.int8)


def _unit(k: int) -> None:
    """Fill in the unit curve turning by ``k * _STEP`` degrees."""
    turn = math.radians(k * _STEP)
    t0, t1, z = np.array([1.0, 0.0]), np.array([math.cos(turn), math.sin(turn)]), np.zeros(2)
    b = BlendPiece(-t0, t0, z, SHAPE, t1, t1, z, SHAPE)
    if not b.valid:
        _UNIT_STATE[k] = -1
        return
    _, t, kv, dk = b._geometric(_BOUND_U)
    pts = b.points(65)
    on_in = pts - np.outer(np.clip(pts @ t0, None, 0.0), t0)    # distance to the incoming ray
    on_out = pts - np.outer(np.clip(pts @ t1, 0.0, None), t1)   # ... and to the outgoing one
    dev_path = float(np.sqrt(np.minimum((on_in ** 2).sum(axis=1), (on_out ** 2).sum(axis=1))).max())
    dev_corner = float(np.sqrt((pts ** 2).sum(axis=1)).min())
    phi = np.arange(_PHIS + 2) * _PHI
    along = np.stack([np.cos(phi), np.sin(phi)], axis=1)                 # (362, 2)
    samples = np.stack([t, kv, dk])                                      # (3, 97, 2)
    _UNIT_H[k] = (samples @ along.T).max(axis=1)                         # (3, 362)
    _UNIT_DEV[k] = dev_corner, dev_path
    _UNIT_STATE[k] = 1


def _bounds(k: np.ndarray, w: np.ndarray, x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Upper bounds (n, D, 3) of the magnitude of the components along the plane vectors
    ``(x, y)`` (n, D) of the samples (tangent, curvature and its derivative) of the unit curves
    turning by ``k + w`` steps (rows): the larger of the support functions towards (x, y) and
    away from it, interpolated between the turns k and k + 1 (the largest of a sum is at most the
    sum of the largest).  Between two tabulated directions a and b, a unit vector is
    e = (sin(b - phi) e_a + sin(phi - a) e_b) / sin(b - a), both weights >= 0, so the largest p.e is
    at most the same combination of the support values at a and b: a bound, never below the
    samples' largest component, above it by about 1 - cos(1/2 degree) in direction."""
    tau = 2.0 * math.pi
    phi = np.empty((2, *x.shape))                                         # towards, away (2, n, D)
    np.remainder(np.arctan2(y, x), tau, out=phi[0])
    np.remainder(phi[0] + math.pi, tau, out=phi[1])
    j = np.minimum((phi / _PHI).astype(np.intp), _PHIS - 1)
    wa = np.sin((j + 1) * _PHI - phi)
    wb = np.sin(phi - j * _PHI)
    turns = np.stack([k, k + 1])[:, None, :, None, None]                 # (2, 1, n, 1, 1)
    h = _UNIT_H[turns, :, j[None, ..., None] + np.arange(2)]             # (2, 2, n, D, 2, 3)
    sup = wa[..., None] * h[..., 0, :]
    sup += wb[..., None] * h[..., 1, :]
    sup = np.maximum(sup[:, 0], sup[:, 1])                               # (2, n, D, 3)
    scale = (np.hypot(x, y) / math.sin(_PHI))[..., None]
    return ((1 - w)[:, None, None] * sup[0] + w[:, None, None] * sup[1]) * scale


def _units(ks: np.ndarray) -> np.ndarray:
    """Which of the unit curves ``ks`` and ``ks + 1`` are both valid, filling in those not computed yet."""
    state = _UNIT_STATE[ks], _UNIT_STATE[ks + 1]
    if not (state[0].all() and state[1].all()):
        # a set of ints, not np.unique: that imports numpy.ma on first use (46 M instructions)
        for k in sorted({*ks[state[0] == 0].tolist(), *(ks[state[1] == 0] + 1).tolist()}):
            _unit(k)
        state = _UNIT_STATE[ks], _UNIT_STATE[ks + 1]
    return (state[0] == 1) & (state[1] == 1)


def _speed_squares() -> tuple[np.ndarray, np.ndarray]:
    """The unit blend's ``B' = 5 (A(u) u_in + C(u) u_out)`` (its control points' differences are
    S u_in, S u_in, (1 - 2S)(u_in + u_out), S u_out, S u_out): ``|B'|² / 25 = A² + C² + 2 A C cos``
    of the turn; ``A² + C²`` and ``2 A C`` at the arc-length table's nodes."""
    u = TABLE_GAUSS
    b = [math.comb(4, i) * u ** i * (1 - u) ** (4 - i) for i in range(5)]
    a = SHAPE * (b[0] + b[1]) + (1 - 2 * SHAPE) * b[2]
    c = (1 - 2 * SHAPE) * b[2] + SHAPE * (b[3] + b[4])
    return a * a + c * c, 2 * a * c


_SPEED_SQUARES = _speed_squares()


class LineCorner(NamedTuple):
    """The symmetric blend between two lines at size 1, from which every size follows: bounds of
    ``q'`` (the same at any size), ``q''`` (scale as 1/size) and ``q'''`` (as 1/size²), the norms
    of the last two, the deviations, the control points relative to the vertex and the arc-length
    table (all three scale as size)."""

    d1: np.ndarray
    d2: np.ndarray
    d3: np.ndarray
    k_norm: float
    dk_norm: float
    dev_corner: float
    dev_path: float
    controls: np.ndarray
    table: np.ndarray


class LineCorners(NamedTuple):
    """The unit blends of many line-line corners as arrays (rows: corners), see :class:`LineCorner`;
    ``valid`` is False where the table has no curve for the turn."""

    valid: np.ndarray
    d1: np.ndarray
    d2: np.ndarray
    d3: np.ndarray
    k_norm: np.ndarray
    dk_norm: np.ndarray
    dev_corner: np.ndarray
    dev_path: np.ndarray
    controls: np.ndarray
    table: np.ndarray


def line_corner_arrays(u_in: np.ndarray, u_out: np.ndarray) -> LineCorners:
    """The unit blends of the corners turning from the unit directions ``u_in`` to ``u_out``
    (rows), all at once: the unit curves of the table interpolated by turning angle, turned into
    each corner's plane, and each curve's arc length."""
    cos_turn = np.minimum(np.maximum((u_in * u_out).sum(axis=1), -1.0), 1.0)
    f = np.degrees(np.arccos(cos_turn)) / _STEP
    k = f.astype(np.intp)
    valid = _units(k)
    w = f - k
    devs = (1 - w[:, None]) * _UNIT_DEV[k] + w[:, None] * _UNIT_DEV[k + 1]
    ey = u_out - cos_turn[:, None] * u_in
    norm = np.sqrt((ey * ey).sum(axis=1))[:, None]
    ey = np.divide(ey, norm, out=np.zeros_like(ey), where=norm > 0)
    # per machine axis i, the plane vector (u_in_i, ey_i) takes the plane's samples to axis i
    bounds = _bounds(k, w, u_in, ey)
    d1 = np.minimum(bounds[:, :, 0] * 1.02, 1.0)
    d2 = bounds[:, :, 1] * 1.05
    d3 = bounds[:, :, 2] * 1.10
    k_norm = np.sqrt((d2 * d2).sum(axis=1))
    dk_norm = np.sqrt((d3 * d3).sum(axis=1))
    controls = np.stack([-u_in, -(1 - SHAPE) * u_in, -(1 - 2 * SHAPE) * u_in,
                         (1 - 2 * SHAPE) * u_out, (1 - SHAPE) * u_out, u_out], axis=1)
    speed = np.multiply.outer(_SPEED_SQUARES[1], cos_turn)              # |B'|² / 25 at the table's nodes
    speed += _SPEED_SQUARES[0][:, None]
    tables = speed_tables(np.sqrt(speed, out=speed))
    tables *= 5.0
    return LineCorners(valid, d1, d2, d3, k_norm, dk_norm, devs[:, 0], devs[:, 1], controls, tables)


def line_corners(u_in: np.ndarray, u_out: np.ndarray) -> list[LineCorner | None]:
    """:func:`line_corner_arrays` as one :class:`LineCorner` per corner (None where the table has
    no valid curve)."""
    c = line_corner_arrays(u_in, u_out)
    k_norm, dk_norm = c.k_norm.tolist(), c.dk_norm.tolist()
    devs = np.stack([c.dev_corner, c.dev_path], axis=1).tolist()
    return [LineCorner(c.d1[i], c.d2[i], c.d3[i], k_norm[i], dk_norm[i], *devs[i], c.controls[i], c.table[i])
            if ok else None for i, ok in enumerate(c.valid.tolist())]


def line_corner_sizes(c: LineCorners, lim_p: np.ndarray, lim_q: np.ndarray, speed: float | np.ndarray | None,
                      tolerance: float | None, acc: float, jerk: float, corner: bool) -> np.ndarray:
    """The sizes :func:`_line_corner` gives the corners ``c`` (rows), all at once and with the same
    operations (so the same numbers); ``speed`` one for all or one per corner; 0 where no curve
    fits."""
    size = np.minimum(lim_p, lim_q)
    with np.errstate(divide="ignore", invalid="ignore"):
        if speed is not None:
            need = c.k_norm * speed * speed / (CENTRIPETAL * acc)
            if jerk != math.inf:
                need = np.maximum(need, np.sqrt(c.dk_norm * speed ** 3 / (CURVE_JERK * jerk)))
            size = np.minimum(size, np.maximum(need * 1.02, 1e-9))
        if tolerance is not None:
            dev = c.dev_corner if corner else c.dev_path
            size = np.where(dev > 0, np.minimum(size, 0.95 * tolerance / dev), size)
    return np.where(c.valid & (size > 1e-9), size, 0.0)


def _line_corner(p: LinePiece, q: LinePiece, lim_p: float, lim_q: float, tolerance, speed, acc, jerk,
                 corner: bool, shape: LineCorner | None) -> tuple[BlendPiece, float, float] | None:
    """Two lines: the symmetric blend is one plane shape scaled by its size (curvature as
    1/size, its derivative as 1/size², deviation and length as size), so a table of unit
    shapes by turning angle gives its bounds without sampling each corner.  ``shape``: the
    corner's unit blend when already computed with others (:func:`line_corners`)."""
    if shape is None:
        shape = line_corners(p.u[None, :], q.u[None, :])[0]
        if shape is None:
            return None
    size = min(lim_p, lim_q)
    if speed is not None:
        need = shape.k_norm * speed * speed / (CENTRIPETAL * acc)
        if jerk != math.inf:
            need = max(need, math.sqrt(shape.dk_norm * speed ** 3 / (CURVE_JERK * jerk)))
        size = min(size, max(need * 1.02, 1e-9))
    if tolerance is not None:
        dev = shape.dev_corner if corner else shape.dev_path
        if dev > 0:
            size = min(size, 0.95 * tolerance / dev)
    if not size > 1e-9:
        return None
    blend = BlendPiece.from_controls(p.end + size * shape.controls, shape.d1, shape.d2 / size,
                                     shape.d3 / (size * size), size * shape.table)
    return blend, size, size


def make_blend(p: Piece, q: Piece, half_p: float, half_q: float, *, tolerance: float | None,
               speed: float | None, acc: float, jerk: float,
               distances: tuple[float, float] | None = None, corner: bool = False,
               shape: LineCorner | None = None) -> tuple[BlendPiece, float, float] | None:
    """The corner curve between ``p`` (incoming) and ``q`` (outgoing) and the lengths
    ``d1``, ``d2`` it takes from their end and start, or None when none fits.

    ``tolerance``: the largest deviation allowed; ``speed``: the speed the
    curve should allow (None: as large as the tolerance allows);
    ``distances``: fixed (a, b) of #ROUNDPAR type 3.  ``half_p``/``half_q``:
    the most each piece may give up (half of its programmed block).  ``shape``: the unit
    blend of a corner between two lines, when already computed (:func:`line_corners`).
    """
    lim_p, lim_q = min(half_p, p.length), min(half_q, q.length)
    if lim_p <= 1e-9 or lim_q <= 1e-9:
        return None
    if distances is not None:
        d1, d2 = min(distances[0], lim_p), min(distances[1], lim_q)
        blend = _blend(p, q, d1, d2)
        return (blend, d1, d2) if blend.valid else None
    if isinstance(p, LinePiece) and isinstance(q, LinePiece):
        made = _line_corner(p, q, lim_p, lim_q, tolerance, speed, acc, jerk, corner, shape)
        if made is not None:
            return made
    size = max(lim_p, lim_q)
    if speed is not None:
        size = min(lim_p, lim_q)
        for _ in range(2):   # the curvature scales as 1/size, its derivative as 1/size²
            trial = _blend(p, q, min(size, lim_p), min(size, lim_q))
            if not trial.valid:
                return None
            size *= max(_dynamic_scale(trial, speed, acc, jerk), 1e-3) * 1.02
            if size >= max(lim_p, lim_q):
                size = max(lim_p, lim_q)
                break
    for _ in range(12):
        d1, d2 = min(size, lim_p), min(size, lim_q)
        blend = _blend(p, q, d1, d2)
        if not blend.valid:
            return None
        if tolerance is None:
            return blend, d1, d2
        dev = deviation(blend, p, q, d1, d2, corner)
        if dev <= 0.95 * tolerance:
            return blend, d1, d2
        size *= max(0.1, 0.9 * tolerance / dev)
    return None


def _roundpar(params: tuple, feed: float) -> tuple[float, float | None, float | None, tuple | None]:
    """``(feed, speed, tolerance, distances)`` of a G05 corner under #ROUNDPAR ``params`` (seed 002
    L8096-L8133): type 1 keeps F within the deviation e, type 2 runs at f % of F, type 3 takes
    the distances a, b, type 4 keeps the deviation e and lowers F as needed."""
    kind = params[0]
    if kind == 1:
        return feed, feed, params[1], None
    if kind == 2:
        feed *= params[1] / 100.0
        return feed, feed, None, None
    if kind == 3:
        return feed, None, None, (params[1], params[2])
    if kind == 4:
        return feed, None, params[1], None
    return feed, feed, None, None


def _roundpar_rows(params: tuple, feed: np.ndarray) -> tuple[np.ndarray, np.ndarray | None, float | None]:
    """:func:`_roundpar` of many G05 corners between lines at once (``feed``: each corner's lower
    feed): (feeds, speeds or None, tolerance).  The types batched (1, 2 and 4; 3 and 5 are made
    alone) scale the feed, so _roundpar of a unit feed gives the factor, and ``feed * factor``
    is the very product it makes for each corner."""
    factor, speed, tolerance, _ = _roundpar(params, 1.0)
    if factor != 1.0:
        feed = feed * factor
    return feed, (None if speed is None else feed), tolerance
