"""The no-gouge watch of radius compensation over the whole look-back window (spec 04 §16.2).

The compensation stage checks each move against the moves around it (its look-ahead).  A gouge can
also come from farther away: a block dropped as too short for the tool whose wall another block
continues much later (a star's spike, the contour closing on the line it started with), a neck
between parts of the contour many blocks apart.  The rule is simple: the tool centre's path keeps
the tool radius R from every programmed element.  This watch holds the path already handed on and
the programmed elements of the last :data:`WINDOW` blocks in a grid of cells, and checks every new
path piece against the programmed elements near it and every new programmed element against the
path near it; anything nearer than R refuses the block (INT086), before a later stage runs it.

The window bounds the memory whatever the program's length; a neck between blocks farther apart
than the window is not seen.
"""

from __future__ import annotations

import math
from collections import deque

from .proximity import GOUGE_TOLERANCE, nearest

#: How many path pieces and programmed elements the watch keeps (the oldest go first).
WINDOW = 2048


def _box(element: tuple, margin: float) -> tuple[float, float, float, float]:
    kind, p, q, centre, _ccw = element
    if kind == "arc":   # the whole circle bounds the arc: cheap and safe
        rho = math.dist(p, centre)
        return centre[0] - rho - margin, centre[1] - rho - margin, centre[0] + rho + margin, centre[1] + rho + margin
    return (min(p[0], q[0]) - margin, min(p[1], q[1]) - margin, max(p[0], q[0]) + margin, max(p[1], q[1]) + margin)


class Clearance:
    """Path pieces and programmed elements of one compensated stretch, for :meth:`path` / :meth:`profile`."""

    def __init__(self, radius: float) -> None:
        self.radius = radius
        self.cell = max(2.0 * radius, 1.0)   # mm: a query visits a few cells
        self._cells: dict[tuple[int, int], list] = {}
        self._order: deque = deque()          # (kind, element, rec, cells) in arrival order

    def _keys(self, box: tuple) -> list[tuple[int, int]]:
        c = self.cell
        x0, y0, x1, y1 = (math.floor(box[0] / c), math.floor(box[1] / c), math.floor(box[2] / c),
                          math.floor(box[3] / c))
        if (x1 - x0 + 1) * (y1 - y0 + 1) > 4096:   # a huge element: one coarse key, checked against all
            return [(-(1 << 40), -(1 << 40))]
        return [(i, j) for i in range(x0, x1 + 1) for j in range(y0, y1 + 1)]

    def _add(self, kind: str, element: tuple, rec) -> None:
        keys = self._keys(_box(element, 0.0))
        entry = (kind, element, rec, keys)
        for k in keys:
            self._cells.setdefault(k, []).append(entry)
        self._order.append(entry)
        if len(self._order) > WINDOW:
            old = self._order.popleft()
            for k in old[3]:
                bucket = self._cells.get(k)
                if bucket is not None:
                    bucket.remove(old)
                    if not bucket:
                        del self._cells[k]

    def _near(self, element: tuple, kind: str):
        """The stored entries of ``kind`` whose cells meet the element's box grown by R."""
        seen: set[int] = set()
        keys = self._keys(_box(element, self.radius))
        coarse = self._cells.get((-(1 << 40), -(1 << 40)), [])
        for k in [*keys, None]:
            bucket = coarse if k is None else self._cells.get(k, ())
            for entry in bucket:
                if entry[0] == kind and id(entry) not in seen:
                    seen.add(id(entry))
                    yield entry

    def path(self, element: tuple, rec) -> tuple | None:
        """Add a piece of the tool centre's path; ``(depth, programmed record)`` when it comes nearer than R
        to a programmed element, else None."""
        found = self._worst(element, "profile")
        self._add("path", element, rec)
        return found

    def profile(self, element: tuple, rec) -> tuple | None:
        """Add a programmed element; ``(depth, path record)`` when the path already handed on comes nearer
        than R to it, else None."""
        found = self._worst(element, "path")
        self._add("profile", element, rec)
        return found

    def _worst(self, element: tuple, kind: str) -> tuple | None:
        limit = self.radius - GOUGE_TOLERANCE
        worst = None
        for _kind, other, rec, _keys in self._near(element, kind):
            d = nearest(element, other) if kind == "profile" else nearest(other, element)
            if d < limit and (worst is None or d < worst[0]):
                worst = (d, rec)
        return None if worst is None else (self.radius - worst[0], worst[1])
