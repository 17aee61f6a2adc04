"""Corner curves at arcs remembered by everything their construction reads, so that a corner the
program runs through again (the same contour at the next depth, a subroutine called again at
another height) takes its curve back instead of making it again.

CAM posts write a profile's passes one below the other as the same XY blocks with another Z, and
Fagor programs call a contour's subroutine once per depth; the corners of every pass after the
first are the first pass's to the bit.  A corner's curve is a function of its two pieces on the
axes they move along (the rest of each point is the corner's own: neither piece moves there), of
the most each side may give up, its speed, and the batch's tolerance and dynamics:
:func:`~fagorcnc.plan.corner_batch.blend_batch` makes every curve with the same floats however
many corners are worked with it (its sums add axis after axis and node after node), so a curve
taken back is the one that would be made.  The key holds those numbers as their bits (a -0.0 is
not a 0.0), and the memo keeps at most :data:`SIZE` corners (the oldest go first): memory stays
bounded on a program of any length.
"""

from __future__ import annotations

import struct

import numpy as np

from .geometry import ArcPiece, LinePiece, Piece

#: The most corners remembered (about 0.6 KiB each)
SIZE = 4096

#: What a corner not remembered gets from :meth:`CornerMemo.find`
MISSING = object()


def _bits(values: list[float]) -> bytes:
    """Floats as their bits: equal keys mean the same floats, signs of zero included."""
    return struct.pack(f"{len(values)}d", *values)


def piece_key(p: Piece) -> tuple[tuple[int, ...], bytes] | None:
    """The axes the piece moves along and the bits of every number a corner's construction reads
    of it on those axes (None: not a line or an arc, not remembered).  A line's: its start, end,
    direction and length; an arc's: those of its start and end, its centre, angles, radii, length,
    plane and the rate of its other axes (what :class:`~fagorcnc.plan.stretch.PieceRows` reads)."""
    kind = type(p)
    if kind is LinePiece:
        u = p.ul
        moving = tuple(i for i, x in enumerate(u) if x != 0.0)
        start, end = p.start.tolist(), p.end.tolist()
        return moving, _bits([*(start[i] for i in moving), *(end[i] for i in moving), *(u[i] for i in moving),
                              p.length])
    if kind is ArcPiece:
        lin = p.lin.tolist()
        moving = tuple(sorted({p.ia, p.io, *(i for i, x in enumerate(lin) if x != 0.0)}))
        start, end = p.start.tolist(), p.end.tolist()
        return moving, _bits([*(start[i] for i in moving), *(end[i] for i in moving), *(lin[i] for i in moving),
                              *p.center, p.theta0, p.w, p.r0, p.dr, p.length, p.ia, p.io])
    return None


class CornerMemo:
    """The corner curves a planner has made at arcs, by :func:`piece_key` of both pieces, what each
    side may give up, the speed and the batch's ``shared`` numbers.  Each entry: None (no curve
    fits) or the curve on its axes (the ones its pieces move along): control points (6, k), its
    three derivative bounds (k,), its arc-length table, its length and what each side gives up."""

    __slots__ = ("_made", "hits", "size")

    def __init__(self, size: int = SIZE) -> None:
        self._made: dict[tuple, tuple | None] = {}
        self.size = size
        #: the corners taken back so far
        self.hits = 0

    def keys(self, ps: list[Piece], qs: list[Piece], lim_p: list[float], lim_q: list[float],
             speed: list[float] | None, shared: tuple, dim: int) -> list[tuple | None]:
        """The key of each corner ``ps[i] -> qs[i]`` (None: not remembered).  Its first item is the
        axes the curve is worked on; a corner moving along three axes or more also holds the axes
        its batch works on (sums of three numbers or more may round by their order)."""
        pieces: dict[int, tuple | None] = {}
        for p in (*ps, *qs):
            if id(p) not in pieces:
                pieces[id(p)] = piece_key(p)
        known = [k for k in pieces.values() if k is not None]
        layout = None   # the axes the batch works on (PieceRows(still=True)'s), when the memo knows them
        if len(known) == len(pieces):
            moving = sorted({i for axes, _ in known for i in axes})
            layout = tuple(moving) if moving[:2] == [0, 1] else tuple(range(dim))
        out: list[tuple | None] = []
        for i, (p, q) in enumerate(zip(ps, qs, strict=True)):
            kp, kq = pieces[id(p)], pieces[id(q)]
            if kp is None or kq is None:
                out.append(None)
                continue
            axes = tuple(sorted({*kp[0], *kq[0]}))
            wide = None
            if len(axes) >= 3:
                if layout is None:
                    out.append(None)
                    continue
                wide = layout
            out.append((axes, kp, kq, _bits([lim_p[i], lim_q[i], speed[i] if speed is not None else 0.0]),
                        speed is None, wide, shared))
        return out

    def find(self, key: tuple | None) -> tuple | object | None:
        """The entry of the corner ``key`` (:data:`MISSING`: not remembered)."""
        if key is None:
            return MISSING
        found = self._made.get(key, MISSING)
        if found is not MISSING:
            self.hits += 1
        return found

    def keep(self, key: tuple | None, curve: tuple | None, bounds: tuple[np.ndarray, ...] | None) -> None:
        """Remember the corner ``key``'s ``curve`` = (piece, d1, d2) or None, with its derivative
        bounds' rows ``bounds`` (on every axis), on the key's axes."""
        if key is None or self.size <= 0:
            return
        made = self._made
        if len(made) >= self.size:
            del made[next(iter(made))]   # the oldest
        if curve is None:
            made[key] = None
            return
        axes = list(key[0])
        piece, g1, g2 = curve
        arrays = (piece.controls[:, axes], *(b[axes] for b in bounds), piece.table_s.copy())
        for a in arrays:   # shared by every curve taken back: nothing may write into them
            a.flags.writeable = False
        made[key] = (*arrays, piece.length, g1, g2)
