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

import numpy as np

from .geometry import _BOUND_U, BlendPiece, LinePiece, Piece
from .limits import CENTRIPETAL, CURVE_JERK

#: Control-point spacing of a blend as a fraction of its length on each side.
SHAPE = 0.375
#: Tangent / curvature differences below these run through without a blend.
TANGENT_EPS = 1e-10
CURVATURE_EPS = 1e-10


def smooth(t0: np.ndarray, k0: np.ndarray, t1: np.ndarray, k1: np.ndarray) -> bool:
    """True when the path is tangent- and curvature-continuous at the junction."""
    return float(np.linalg.norm(t1 - t0)) <= TANGENT_EPS and float(np.linalg.norm(k1 - k0)) <= CURVATURE_EPS


def included_angle(t0: np.ndarray, t1: np.ndarray) -> float:
    """Angle between the incoming and outgoing paths at a corner, degrees: 180 straight on."""
    c = max(-1.0, min(1.0, float(np.dot(t0, t1))))
    return 180.0 - math.degrees(math.acos(c))


def _blend(p: Piece, q: Piece, d1: float, d2: float) -> BlendPiece:
    p0, t0, k0 = p.frame(p.length - d1)
    p5, t5, k5 = q.frame(d2)
    return BlendPiece(p0, t0, k0, SHAPE * d1, p5, t5, k5, SHAPE * d2)


def _replaced(piece: Piece, s0: float, s1: float) -> np.ndarray:
    """Points of the programmed path between s0 and s1 (its two ends for a line)."""
    if isinstance(piece, LinePiece):
        return piece.start + np.outer([s0, s1], piece.u)
    return piece.derivatives(np.linspace(s0, s1, 17))[0]


def deviation(blend: BlendPiece, p: Piece, q: Piece, d1: float, d2: float, corner: bool) -> float:
    """Largest distance from the blend to the stretch of programmed path it replaces
    (HSC), or with ``corner`` the distance from the programmed corner point to the
    curve (#ROUNDPAR e, L8124)."""
    pts = blend.points(97)
    if corner:
        return float(np.sqrt(((pts - p.end) ** 2).sum(axis=1)).min())
    ref = np.concatenate([_replaced(p, p.length - d1, p.length), _replaced(q, 0.0, d2)[1:]])
    a, b = ref[:-1], ref[1:]
    ab = b - a
    den = np.maximum((ab * ab).sum(axis=1), 1e-300)
    rel = pts[:, None, :] - a[None, :, :]
    t = np.clip((rel * ab[None]).sum(axis=2) / den[None], 0.0, 1.0)
    gap = rel - t[..., None] * ab[None]
    return float(np.sqrt((gap * gap).sum(axis=2).min(axis=1).max()))


def _dynamic_scale(blend: BlendPiece, speed: float, acc: float, jerk: float) -> float:
    """Factor by which the blend must grow so that ``speed`` fits its curvature limits."""
    k = float(np.linalg.norm(blend.d2))
    dk = float(np.linalg.norm(blend.d3))
    need = k * speed * speed / (CENTRIPETAL * acc)
    if jerk != math.inf:
        need = max(need, math.sqrt(dk * speed ** 3 / (CURVE_JERK * jerk)))
    return need


#: Line-line corners: unit curves (size 1) sampled in the corner's plane, per 0.25 degree of turn.
_STEP = 0.25
_UNIT: dict[int, tuple | None] = {}


def _unit_2d(k: int) -> tuple | None:
    """(tangents, curvatures, curvature derivatives, corner deviation, path deviation) of the
    unit blend turning by ``k * _STEP`` degrees, in plane coordinates (x along the incoming line)."""
    if k not in _UNIT:
        turn = math.radians(k * _STEP)
        t0, t1, z = np.array([1.0, 0.0]), np.array([math.cos(turn), math.sin(turn)]), np.zeros(2)
        b = BlendPiece(-t0, t0, z, SHAPE, t1, t1, z, SHAPE)
        if not b.valid:
            _UNIT[k] = None
        else:
            _, t, kv, dk = b._geometric(_BOUND_U)
            pts = b.points(65)
            on_in = pts - np.outer(np.clip(pts @ t0, None, 0.0), t0)    # distance to the incoming ray
            on_out = pts - np.outer(np.clip(pts @ t1, 0.0, None), t1)   # ... and to the outgoing one
            dev_path = float(np.sqrt(np.minimum((on_in ** 2).sum(axis=1), (on_out ** 2).sum(axis=1))).max())
            dev_corner = float(np.sqrt((pts ** 2).sum(axis=1)).min())
            _UNIT[k] = (t, kv, dk, dev_corner, dev_path)
    return _UNIT[k]


def _line_corner(p: LinePiece, q: LinePiece, lim_p: float, lim_q: float, tolerance, speed, acc, jerk,
                 corner: bool) -> tuple[BlendPiece, float, float] | None:
    """Two lines: the symmetric blend is one plane shape scaled by its size (curvature as
    1/size, its derivative as 1/size², deviation and length as size), so a table of unit
    shapes by turning angle gives its bounds without sampling each corner."""
    cos_turn = max(-1.0, min(1.0, float(p.u @ q.u)))
    f = math.degrees(math.acos(cos_turn)) / _STEP
    k = int(f)
    lo, hi = _unit_2d(k), _unit_2d(k + 1)
    if lo is None or hi is None:
        return None
    w = f - k
    t, kv, dk = ((1 - w) * a + w * b for a, b in zip(lo[:3], hi[:3], strict=True))
    dev_corner, dev_path = ((1 - w) * a + w * b for a, b in zip(lo[3:5], hi[3:5], strict=True))
    ex = p.u
    ey = q.u - cos_turn * ex
    norm = float(np.linalg.norm(ey))
    ey = ey / norm if norm > 0 else np.zeros_like(ex)
    basis = np.stack([ex, ey])                     # plane -> machine axes
    d1 = np.minimum(np.abs(t @ basis).max(axis=0) * 1.02, 1.0)
    d2 = np.abs(kv @ basis).max(axis=0) * 1.05
    d3 = np.abs(dk @ basis).max(axis=0) * 1.10
    size = min(lim_p, lim_q)
    if speed is not None:
        need = float(np.linalg.norm(d2)) * speed * speed / (CENTRIPETAL * acc)
        if jerk != math.inf:
            need = max(need, math.sqrt(float(np.linalg.norm(d3)) * speed ** 3 / (CURVE_JERK * jerk)))
        size = min(size, max(need * 1.02, 1e-9))
    if tolerance is not None:
        dev = dev_corner if corner else dev_path
        if dev > 0:
            size = min(size, 0.95 * tolerance / dev)
    if not size > 1e-9:
        return None
    vertex = p.end
    controls = vertex + size * np.array([-ex, -(1 - SHAPE) * ex, -(1 - 2 * SHAPE) * ex,
                                         (1 - 2 * SHAPE) * q.u, (1 - SHAPE) * q.u, q.u])
    return BlendPiece.from_controls(controls, d1, d2 / size, d3 / (size * size)), size, size


_ZERO = np.zeros(16)


def make_blend(p: Piece, q: Piece, half_p: float, half_q: float, *, tolerance: float | None,
               speed: float | None, acc: float, jerk: float,
               distances: tuple[float, float] | None = None,
               corner: bool = False) -> tuple[BlendPiece, float, float] | None:
    """The corner curve between ``p`` (incoming) and ``q`` (outgoing) and the lengths
    ``d1``, ``d2`` it takes from their end and start, or None when none fits.

    ``tolerance``: the largest deviation allowed; ``speed``: the speed the
    curve should allow (None: as large as the tolerance allows);
    ``distances``: fixed (a, b) of #ROUNDPAR type 3.  ``half_p``/``half_q``:
    the most each piece may give up (half of its programmed block).
    """
    lim_p, lim_q = min(half_p, p.length), min(half_q, q.length)
    if lim_p <= 1e-9 or lim_q <= 1e-9:
        return None
    if distances is not None:
        d1, d2 = min(distances[0], lim_p), min(distances[1], lim_q)
        blend = _blend(p, q, d1, d2)
        return (blend, d1, d2) if blend.valid else None
    if isinstance(p, LinePiece) and isinstance(q, LinePiece):
        made = _line_corner(p, q, lim_p, lim_q, tolerance, speed, acc, jerk, corner)
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
