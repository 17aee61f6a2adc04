"""Nearest-segment queries on a polyline in 3D, and the directed
Hausdorff distance between two polylines that :mod:`fagorcnc.commands.diff` is built on.

The segments of the target polyline are cut into pieces no longer than ``c`` (about the median
segment length).  With scipy installed (the optional extra ``fagorcnc[diff]``: its k-d tree is
compiled code, about ten times faster), the 4 nearest piece midpoints of a point are asked: when the
4th is farther than the best distance found plus half a piece no other piece can be closer; else
(a path passing over itself) every piece whose midpoint lies within that radius is examined.
Without scipy a uniform grid of cell ``c`` (numpy only) files each piece under the cell of its
midpoint.  A query looks in its cell and the 26 around it: every
piece whose midpoint lies within ``c`` of the point is seen, so a found distance ``d <= c/2`` is exact
(a closer piece would have its midpoint within ``d + c/2 <= c``).  Points farther away are asked again
on grids four times coarser until the same argument holds.  All the work is vectorised, in chunks
whose size keeps the candidate pairs to a few million.

The directed distance from polyline A to polyline B is bounded on each segment of A from the
distances of its ends: distance to one straight segment is convex along a line, so when both ends'
distances to the same segment of B are known the segment's maximum is at most the larger of them; the
distance to B is also 1-Lipschitz.  Segments whose bounds leave the verdict (beyond the tolerance or
not) or the maximum undecided are halved and asked again, so the result is exact to ``eps``, not
limited by a sampling step.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass

import numpy as np

#: Candidate (point, piece) pairs examined at once.
PAIRS_PER_CHUNK = 2_000_000
#: Halvings of a segment of A at most (a segment 1 m long halved 40 times is 1 nm long).
MAX_HALVINGS = 40

_OFFSETS = np.array([(i, j, k) for i in (-1, 0, 1) for j in (-1, 0, 1) for k in (-1, 0, 1)], dtype=np.int64)


def point_segment_distance(p: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Distance from points ``p`` to segments ``a``-``b`` (arrays of shape (n, 3))."""
    ab = b - a
    den = np.einsum("ij,ij->i", ab, ab)
    t = np.einsum("ij,ij->i", p - a, ab) / np.where(den > 0, den, 1.0)
    t = np.clip(np.where(den > 0, t, 0.0), 0.0, 1.0)
    return np.linalg.norm(p - (a + t[:, None] * ab), axis=1)


class _Grid:

    def __init__(self, mid: np.ndarray, cell: float, origin: np.ndarray) -> None:
        self.cell, self.origin = cell, origin
        ijk = np.floor((mid - origin) / cell).astype(np.int64)
        self.dims = ijk.max(axis=0) + 3 if len(ijk) else np.ones(3, dtype=np.int64)
        keys = self._key(ijk)
        self.order = np.argsort(keys, kind="stable")
        self.keys = keys[self.order]
        self.density = max(1.0, len(mid) / max(1, len(np.unique(self.keys))))

    def _key(self, ijk: np.ndarray) -> np.ndarray:
        d = self.dims
        return ((ijk[:, 0] + 1) * (d[1] + 2) + (ijk[:, 1] + 1)) * (d[2] + 2) + (ijk[:, 2] + 1)

    def candidates(self, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(point index, piece index) of every piece filed in the 27 cells around each point."""
        ijk = np.floor((points - self.origin) / self.cell).astype(np.int64)
        ijk = np.clip(ijk, -1, self.dims)   # far outside: the border cells (empty) keep the keys valid
        pidx, sidx = [], []
        rows = np.arange(len(points))
        for off in _OFFSETS:
            keys = self._key(ijk + off)
            lo = np.searchsorted(self.keys, keys, "left")
            hi = np.searchsorted(self.keys, keys, "right")
            count = hi - lo
            hit = count > 0
            if not hit.any():
                continue
            count, lo = count[hit], lo[hit]
            total = int(count.sum())
            starts = np.repeat(lo - np.cumsum(count) + count, count)
            pidx.append(np.repeat(rows[hit], count))
            sidx.append(self.order[starts + np.arange(total)])
        if not pidx:
            return np.empty(0, dtype=np.int64), np.empty(0, dtype=np.int64)
        return np.concatenate(pidx), np.concatenate(sidx)


class SegmentIndex:
    """Nearest segment of a polyline (segments ``a[i]``-``b[i]``, shape (n, 3)) to query points."""

    def __init__(self, a: np.ndarray, b: np.ndarray, cell: float | None = None) -> None:
        self.a, self.b = np.asarray(a, float), np.asarray(b, float)
        n = len(self.a)
        if n == 0:
            raise ValueError("no segment to compare with")
        lengths = np.linalg.norm(self.b - self.a, axis=1)
        lo = np.minimum(self.a.min(axis=0), self.b.min(axis=0))
        hi = np.maximum(self.a.max(axis=0), self.b.max(axis=0))
        extent = float(np.max(hi - lo)) or 1.0
        total = float(lengths.sum())
        if cell is None:   # about two pieces per segment, at most ~4 million pieces in all
            cell = max(float(np.median(lengths)) if n else 1.0, total / 4e6, extent * 1e-6, 1e-6)
        self.cell = cell
        cuts = np.maximum(1, np.ceil(lengths / cell)).astype(np.int64)
        parent = np.repeat(np.arange(n), cuts)
        first = np.repeat(np.cumsum(cuts) - cuts, cuts)
        k = np.arange(len(parent)) - first
        frac = (k + 0.5) / cuts[parent]
        mid = self.a[parent] + frac[:, None] * (self.b[parent] - self.a[parent])
        self.parent = parent
        self.origin = lo - cell
        self.extent = extent
        self._mid = mid
        self._grids: list[_Grid] = []
        self._tree = _kd_tree(mid)
        if self._tree is None:
            self._grids.append(_Grid(mid, cell, self.origin))


    def _keep_nearest(self, points, ids, pidx, seg, best, arg) -> None:
        """For the candidate pairs (point ``ids[pidx]``, segment ``seg``), keep in ``best``/``arg`` each
        point's nearest segment where it is nearer than what was found before."""
        d = point_segment_distance(points[ids][pidx], self.a[seg], self.b[seg])
        local = np.full(len(ids), np.inf)
        np.minimum.at(local, pidx, d)
        hit = d <= local[pidx]
        where = np.zeros(len(ids), dtype=np.int64)
        where[pidx[hit]] = seg[hit]
        better = local < best[ids]
        best[ids[better]] = local[better]
        arg[ids[better]] = where[better]

    def _grid(self, level: int) -> _Grid:
        while len(self._grids) <= level:
            self._grids.append(_Grid(self._mid, self.cell * 4 ** len(self._grids), self.origin))
        return self._grids[level]

    def distance_to(self, points: np.ndarray, seg: np.ndarray) -> np.ndarray:
        """Distance from each point to the given segment of the polyline."""
        return point_segment_distance(points, self.a[seg], self.b[seg])

    def nearest(self, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(distance, segment index) of the nearest segment to every point (exact)."""
        points = np.asarray(points, float)
        if self._tree is not None:
            return self._nearest_tree(points)
        m = len(points)
        best = np.full(m, np.inf)
        arg = np.zeros(m, dtype=np.int64)
        todo = np.arange(m)
        level = 0
        while len(todo):
            grid = self._grid(level)
            reach = grid.cell - self.cell / 2   # found d <= reach: exact (see the module docstring)
            last = grid.cell > 2 * self.extent + 4 * self.cell   # every piece within the 27 cells
            chunk = max(1, int(PAIRS_PER_CHUNK / (27 * grid.density)))
            unresolved = []
            for s in range(0, len(todo), chunk):
                ids = todo[s:s + chunk]
                pidx, sidx = grid.candidates(points[ids])
                if len(pidx):
                    self._keep_nearest(points, ids, pidx, self.parent[sidx], best, arg)
                if not last:
                    unresolved.append(ids[~(best[ids] <= reach)])
            todo = np.concatenate(unresolved) if unresolved else np.empty(0, dtype=np.int64)
            level += 1
        return best, arg


    def _nearest_tree(self, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        # the 4 nearest piece midpoints first: the answer is exact when the 4th is farther than the
        # best distance plus half a piece (a closer piece has its midpoint within that); for the
        # other points (paths that pass over themselves: many pieces about as near) every piece
        # whose midpoint lies within that radius is examined
        m = len(points)
        best = np.empty(m)
        arg = np.empty(m, dtype=np.int64)
        half = self.cell / 2
        tree = self._tree
        k = min(4, len(self._mid))
        unresolved = []
        for s in range(0, m, 100_000):
            p = points[s:s + 100_000]
            dist, idx = tree.query(p, k=k)
            dist, idx = dist.reshape(len(p), k), idx.reshape(len(p), k)
            seg = self.parent[idx]
            d = point_segment_distance(np.repeat(p, k, axis=0), self.a[seg.ravel()],
                                       self.b[seg.ravel()]).reshape(len(p), k)
            col = np.argmin(d, axis=1)
            rows = np.arange(len(p))
            best[s:s + len(p)] = d[rows, col]
            arg[s:s + len(p)] = seg[rows, col]
            if k < len(self._mid):
                unresolved.append(s + np.flatnonzero(dist[:, -1] < best[s:s + len(p)] + half))
        todo = np.concatenate(unresolved) if unresolved else np.empty(0, dtype=np.int64)
        for s in range(0, len(todo), 20_000):
            ids = todo[s:s + 20_000]
            lists = tree.query_ball_point(points[ids], r=best[ids] + half, return_sorted=False)
            counts = np.fromiter((len(x) for x in lists), dtype=np.int64, count=len(lists))
            flat = np.fromiter(itertools.chain.from_iterable(lists), dtype=np.int64, count=int(counts.sum()))
            pidx = np.repeat(np.arange(len(ids)), counts)
            self._keep_nearest(points, ids, pidx, self.parent[flat], best, arg)
        return best, arg


def _kd_tree(points: np.ndarray):
    """A scipy k-d tree of the points when scipy is installed (``pip install 'fagorcnc[diff]'``),
    else None (the numpy grid answers the same, slower)."""
    try:
        from scipy.spatial import cKDTree
    except ImportError:
        return None
    return cKDTree(points)


@dataclass
class Directed:
    """The directed distance from polyline A to polyline B, per segment of A.

    ``lower``/``upper`` bound the largest distance to B of the points of each segment of A;
    ``where`` is a point of A at distance ``lower`` and ``near`` the segment of B nearest to it.
    """

    lower: np.ndarray
    upper: np.ndarray
    where: np.ndarray
    near: np.ndarray

    @property
    def maximum(self) -> float:
        return float(self.lower.max()) if len(self.lower) else 0.0


def directed(a0: np.ndarray, a1: np.ndarray, index: SegmentIndex, tolerance: float, eps: float) -> Directed:
    """How far the segments ``a0``-``a1`` of A stray from the polyline of ``index`` (see the module
    docstring): each segment's bounds decide whether it is beyond ``tolerance`` and, to ``eps``,
    the maximum."""
    n = len(a0)
    lower = np.zeros(n)
    upper = np.zeros(n)
    where = a0.copy()
    near = np.zeros(n, dtype=np.int64)
    if n == 0:
        return Directed(lower, upper, where, near)
    owner = np.arange(n)
    s0, s1 = a0.astype(float), a1.astype(float)
    d0, j0 = index.nearest(s0)
    d1, j1 = index.nearest(s1)
    found = 0.0
    for halving in range(MAX_HALVINGS + 1):
        length = np.linalg.norm(s1 - s0, axis=1)
        c01 = index.distance_to(s1, j0)
        c10 = index.distance_to(s0, j1)
        low = np.maximum(d0, d1)
        up = np.minimum(np.minimum(np.maximum(d0, c01), np.maximum(c10, d1)), (d0 + d1 + length) / 2)
        up = np.maximum(up, low)
        found = max(found, float(low.max()))
        decided = (up <= tolerance) | (low > tolerance)
        done = decided & ((up - low <= eps) | (up <= found + eps))
        if halving == MAX_HALVINGS:
            done[:] = True
        if done.any():
            o, lw, upd = owner[done], low[done], up[done]
            first = d0[done] >= d1[done]
            pt = np.where(first[:, None], s0[done], s1[done])
            jj = np.where(first, j0[done], j1[done])
            # pieces of one owner finishing together: ascending order, so the largest is written last
            order = np.argsort(lw, kind="stable")
            o, lw, upd, pt, jj = o[order], lw[order], upd[order], pt[order], jj[order]
            better = lw >= lower[o]
            lower[o[better]] = lw[better]
            where[o[better]] = pt[better]
            near[o[better]] = jj[better]
            np.maximum.at(upper, o, upd)
        keep = ~done
        if not keep.any():
            break
        s0, s1, d0, d1, j0, j1, owner = s0[keep], s1[keep], d0[keep], d1[keep], j0[keep], j1[keep], owner[keep]
        mid = (s0 + s1) / 2
        dm, jm = index.nearest(mid)
        s0, s1 = np.concatenate([s0, mid]), np.concatenate([mid, s1])
        d0, d1 = np.concatenate([d0, dm]), np.concatenate([dm, d1])
        j0, j1 = np.concatenate([j0, jm]), np.concatenate([jm, j1])
        owner = np.concatenate([owner, owner])
    return Directed(lower, np.maximum(upper, lower), where, near)
