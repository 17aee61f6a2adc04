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

import numpy as np

from .geometry import ArcPiece, LinePiece, Piece

#: The most corners remembered (each holds views of its batch's arrays: a few MiB at most)
SIZE = 4096
#: Corners made in a row, none taken back, after which the memo sleeps (a pass of a profile
#: within that many corners of the same pass above is taken back)
PATIENCE = 1024

#: What a corner not remembered gets from :meth:`CornerMemo.find`
MISSING = object()

#: The axes of each mask of moving axes (bit i: axis i), made once
_AXES: dict[int, tuple[int, ...]] = {}


def _axes(code: int) -> tuple[int, ...]:
    axes = _AXES.get(code)
    if axes is None:
        axes = _AXES[code] = tuple(i for i in range(code.bit_length()) if code >> i & 1)
    return axes


def distinct_pieces(ps: list[Piece], qs: list[Piece]) -> tuple[list[Piece], np.ndarray, np.ndarray]:
    """Each piece of the corners ``ps[i] -> qs[i]`` once (a chain's outgoing piece is the next
    corner's incoming one), and the rows of each corner's incoming piece and of its outgoing one."""
    pieces: list[Piece] = []
    at: dict[int, int] = {}
    for p in (*ps, *qs):
        if id(p) not in at:
            at[id(p)] = len(pieces)
            pieces.append(p)
    return (pieces, np.array([at[id(p)] for p in ps], dtype=np.intp),
            np.array([at[id(q)] for q in qs], dtype=np.intp))


def piece_rows(pieces: list[Piece]) -> tuple[np.ndarray, np.ndarray] | None:
    """For lines and arcs (None if any is neither): which axes each moves along (k, D) and a row of
    every number a corner's construction reads of it, those on the axes it does not move along
    set to 0 (they are the corner's own): its start, end and direction (an arc's rate on its other
    axes), then its length, centre, angles, radii and plane (what
    :class:`~fagorcnc.plan.stretch.PieceRows` reads), then its moving axes as 0/1."""
    kinds = [type(p) for p in pieces]
    if any(k is not LinePiece and k is not ArcPiece for k in kinds):
        return None
    arc = [k is ArcPiece for k in kinds]
    start = np.array([p.start for p in pieces])
    end = np.array([p.end for p in pieces])
    direction = np.array([p.lin if a else p.u for p, a in zip(pieces, arc, strict=True)])
    moving = direction != 0.0
    shape = np.zeros((len(pieces), 9))
    shape[:, 0] = [p.length for p in pieces]
    if any(arc):
        at = np.flatnonzero(arc)
        rows = np.array([(*p.center, p.theta0, p.w, p.r0, p.dr, p.ia, p.io) for p, a in zip(pieces, arc, strict=True)
                         if a])
        shape[at, 1:] = rows
        plane = rows[:, 6:].astype(np.intp)
        moving[at, plane[:, 0]] = moving[at, plane[:, 1]] = True
    return moving, np.concatenate([np.where(moving, start, 0.0), np.where(moving, end, 0.0),
                                   np.where(moving, direction, 0.0), shape, moving], axis=1)


class CornerMemo:
    """The corner curves a planner has made at arcs, by the bits of both pieces' rows
    (:func:`piece_rows`), what each side may give up and the speed, and the batch's ``shared``
    numbers.  Each entry: None (no curve fits) or the curve as its batch made it (views of the
    batch's arrays: control points (6, D), its three derivative bounds (D,), its arc-length table,
    its length and what each side gives up); the axes no piece of the corner moves along are
    taken from the corner taking it back."""

    __slots__ = ("_made", "_since", "asleep", "hits", "patience", "size")

    def __init__(self, size: int = SIZE, patience: int = PATIENCE) -> None:
        self._made: dict[tuple, tuple | None] = {}
        self.size = size
        self.patience = patience
        #: the corners taken back so far
        self.hits = 0
        #: no corner looked up any more: :attr:`patience` corners in a row were made, none taken
        #: back (a program that does not repeat its corners pays for the keys no further)
        self.asleep = size <= 0 or patience <= 0
        self._since = 0

    def keys(self, ps: list[Piece], qs: list[Piece], lim_p: np.ndarray, lim_q: np.ndarray,
             speed: np.ndarray | None, shared: tuple) -> tuple[list[tuple | None], tuple[int, ...] | bool]:
        """The key of each corner ``ps[i] -> qs[i]`` (None: not remembered): the axes its curve is
        worked on, then the bits of its numbers; a corner moving along three axes or more also
        holds the axes its batch works on (sums of three numbers or more may round by their order).
        And those axes (what PieceRows(still=True) keeps of the whole batch; True: not known), on
        which the corners not held are then made."""
        pieces, ip, iq = distinct_pieces(ps, qs)
        made = piece_rows(pieces)
        if made is None:
            return [None] * len(ps), True
        moving, rows = made
        n, dim = len(ps), moving.shape[1]
        axes = moving[ip] | moving[iq]
        codes = (axes @ (1 << np.arange(dim))).tolist()
        every = moving.any(axis=0)   # the batch's axes (PieceRows(still=True)'s)
        layout = tuple(np.flatnonzero(every).tolist()) if every[:2].all() else tuple(range(dim))
        numbers = np.concatenate([rows[ip], rows[iq], lim_p[:, None], lim_q[:, None],
                                  (np.zeros(n) if speed is None else speed)[:, None]], axis=1)
        wide = (axes.sum(axis=1) >= 3).tolist()
        raw, width = numbers.tobytes(), numbers.shape[1] * 8   # each corner's row: a slice of the bytes
        alone = speed is None
        return [(_axes(code), raw[i:i + width], layout if w else None, alone, shared)
                for code, i, w in zip(codes, range(0, n * width, width), wide, strict=True)], layout

    def find(self, keys: list[tuple | None]) -> list[tuple | object | None]:
        """The entry of each corner of ``keys`` (:data:`MISSING`: not remembered)."""
        get = self._made.get
        found = [MISSING if key is None else get(key, MISSING) for key in keys]
        for entry in found:
            if entry is MISSING:
                self._since += 1
            else:
                self.hits += 1
                self._since = 0
        if self._since >= self.patience:
            self.asleep = True
            self._made.clear()
        return found

    def keep(self, key: tuple | None, curve: tuple | None, bounds: tuple[np.ndarray, ...] | None) -> None:
        """Remember the corner ``key``'s ``curve`` = (piece, d1, d2) or None, with its derivative
        bounds' rows ``bounds``.  Nothing writes into a made curve's arrays: they are kept as they are."""
        if key is None or self.asleep:
            return
        made = self._made
        if len(made) >= self.size:
            del made[next(iter(made))]   # the oldest
        if curve is None:
            made[key] = None
            return
        piece, g1, g2 = curve
        made[key] = (piece.controls, *bounds, piece.table_s, piece.length, g1, g2)
