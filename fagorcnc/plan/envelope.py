"""PLN100: the planned path against the soft limits between the programmed end points.

The interpreter checks every programmed end point against the soft limits (INT100); what lies
between them is known once the path is planned: an arc bulging past a limit, a corner curve of
G05 or HSC.  :class:`Envelope` watches the planned segments of a run for that, so that a check,
a dry run and the check before a real run all say the same.
"""

from __future__ import annotations

import math

import numpy as np

from ..config.machine import Machine
from ..diagnostics import Diagnostic
from .blend import BlendPiece, BlendRow
from .geometry import ArcPiece

#: Tolerance of the envelope check (mm, degrees).
ENVELOPE_TOLERANCE = 1e-6


class Envelope:
    """PLN100: arcs and corner blends of the planned path whose interior leaves the soft limits,
    from the segments as they are planned (:meth:`add`), the farthest point per block and axis."""

    def __init__(self, machine: Machine) -> None:
        axes = self.axes = machine.axis_names
        self.lo = np.array([machine.axes[a].min_limit for a in axes])
        self.hi = np.array([machine.axes[a].max_limit for a in axes])
        self.worst: dict[tuple[int, bool, str, str], tuple[float, float, object]] = {}
        self._limits = list(zip(self.lo.tolist(), self.hi.tolist(), strict=True))
        self._off: dict[tuple[int, int], tuple[int, ...]] = {}   # the axes off each arc plane

    def add(self, seg) -> None:
        piece = seg.piece
        if piece is None or not getattr(piece, "curved", False):
            return   # straight pieces: their end points are the interpreter's INT100 check
        if self._inside(piece):
            return
        axes, lo, hi, worst, tol = self.axes, self.lo, self.hi, self.worst, ENVELOPE_TOLERANCE
        box = hull(piece)
        if box is not None and (box[0] >= lo - tol).all() and (box[1] <= hi + tol).all():
            return   # a box round the whole curve lies within the soft limits: nothing can pass them
        pmin, pmax = piece_extent(piece)
        # only what goes beyond the block's own end points (those are the interpreter's check, which
        # lets an axis already beyond its limit move back); a blend joins two blocks inside them
        rec = seg.record
        if not seg.blend and hasattr(rec, "start") and hasattr(rec, "end"):
            ends = np.array([[rec.start.get(a, 0.0) for a in axes], [rec.end.get(a, 0.0) for a in axes]])
        else:
            ends = np.vstack([piece.start, piece.end])
        ends_lo, ends_hi = ends.min(axis=0), ends.max(axis=0)
        for i, axis in enumerate(axes):
            if pmax[i] > hi[i] + tol and pmax[i] > ends_hi[i] + tol:
                key = (seg.line, seg.blend, axis, "upper")
                if key not in worst or pmax[i] > worst[key][0]:
                    worst[key] = (pmax[i], hi[i], rec)
            if pmin[i] < lo[i] - tol and pmin[i] < ends_lo[i] - tol:
                key = (seg.line, seg.blend, axis, "lower")
                if key not in worst or pmin[i] < worst[key][0]:
                    worst[key] = (pmin[i], lo[i], rec)

    def _inside(self, piece) -> bool:
        """Whether a cheap box round ``piece`` (floats, no array) lies within the soft limits: most
        curves are far from them, and only the others need :func:`hull` and :func:`piece_extent`.

        An arc: its circle's square of the largest radius in its plane, its end points on the other
        axes (as :func:`hull`).  A corner blend (arc-length parameterised): no point of a curve is
        farther from its start than its length, so the cube of that half-size round its start holds
        it (the length is integrated to far better than the 1e-6 margin).
        """
        tol, limits = ENVELOPE_TOLERANCE, self._limits
        kind = type(piece)
        if kind is BlendPiece or kind is BlendRow:   # a curve of a batch (blend.BlendRow) too
            reach = piece.length * (1.0 + 1e-6) + tol
            for v, (lo, hi) in zip(piece.start.tolist(), limits, strict=True):   # a loop: no generator per piece
                if not (lo <= v - reach and v + reach <= hi):
                    return False
            return True
        if kind is ArcPiece:
            r0 = piece.r0
            r1 = r0 + piece.dr * piece.length
            radius = (r1 if r1 > r0 else r0) + tol   # max(r0, r1), without the call
            ia, io = piece.ia, piece.io
            cx, cy = piece.center
            lo, hi = limits[ia]
            if cx - radius < lo or cx + radius > hi:
                return False
            lo, hi = limits[io]
            if cy - radius < lo or cy + radius > hi:
                return False
            others = self._off.get((ia, io))
            if others is None:
                others = self._off[ia, io] = tuple(i for i in range(len(limits)) if i not in (ia, io))
            if others:
                start, end = piece.start.tolist(), piece.end.tolist()
                for i in others:
                    lo, hi = limits[i]
                    s, e = start[i], end[i]
                    if (e if e < s else s) < lo - tol or (e if e > s else s) > hi + tol:   # min(s, e), max(s, e)
                        return False
            return True
        return False

    def diagnostics(self, file: str) -> list[Diagnostic]:
        out = []
        for (line, blend, axis, bound), (value, limit, rec) in self.worst.items():
            src = getattr(rec, "src", None)
            what = "the corner blend after this block" if blend else "the arc of this block"
            out.append(Diagnostic(src.file if src else file, line, 1, "PLN100", "error",
                                  f"{what} reaches {axis} {value:.4f} (machine), beyond its {bound} soft limit "
                                  f"{limit:g}", src.text if src else ""))
        return out


def hull(piece) -> tuple[np.ndarray, np.ndarray] | None:
    """A box round a curved piece, cheaper than its extent: a Bézier curve lies within its control
    points' box; an arc (helix, spiral) within its circle's square of the largest radius and, on
    the other axes, between its end points.  None for another kind of piece."""
    controls = getattr(piece, "controls", None)
    if controls is not None:
        return controls.min(axis=0), controls.max(axis=0)
    if not hasattr(piece, "center"):
        return None
    lo, hi = np.minimum(piece.start, piece.end), np.maximum(piece.start, piece.end)
    radius = max(piece.r0, piece.r0 + piece.dr * piece.length)
    for axis, centre in zip((piece.ia, piece.io), piece.center, strict=True):
        lo[axis], hi[axis] = centre - radius, centre + radius
    return lo, hi


def piece_extent(piece) -> tuple[np.ndarray, np.ndarray]:
    """Per-axis min and max of a planned piece (machine coordinates).

    Arcs (helices, spirals) are exact: their planar extremes lie where the
    angle crosses a quarter turn.  Other curves are sampled (65 points).
    """
    length = piece.length
    if hasattr(piece, "theta0") and hasattr(piece, "w") and piece.w != 0.0:
        th0, th1 = piece.theta0, piece.theta0 + piece.w * length
        k0, k1 = math.ceil(min(th0, th1) / (math.pi / 2)), math.floor(max(th0, th1) / (math.pi / 2))
        ks = range(k0, min(k1, k0 + 4000) + 1)
        s = np.clip(np.array([0.0, length, *((k * math.pi / 2 - th0) / piece.w for k in ks)]), 0.0, length)
        q = piece.derivatives(s)[0]
    elif hasattr(piece, "points"):
        q = piece.points(65)
    else:
        q = piece.derivatives(np.linspace(0.0, length, 65))[0]
    q = np.vstack([q, piece.start, piece.end])
    return q.min(axis=0), q.max(axis=0)
