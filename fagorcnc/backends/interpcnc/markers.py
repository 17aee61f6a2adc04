"""Coalesced sequence markers: which motion segments may share one marker, and where a resume restarts in a group.

A marker (a 1010 type 3 action writing the segment's number into the user
register M) costs one Modbus write, as much as the move itself (seed 000
L484-L492: one command per write).  So consecutive straight moves share one:
the first segment of a **group** carries the marker, the others (at most
``marker_every`` segments in all) go out bare.  M = n then means "segment n,
the group's head, has started; the segments before it are complete".

A resume must still know exactly which move of the group was under way when
the card stopped.  The position counters tell, provided the group's path
never comes back near itself.  A segment therefore joins the open group only
when (see :meth:`Coalescer.place`):

* it is one straight move (1002), as the segments already in the group;
* its bounding box, widened by the resume's path tolerance, does not meet
  the widened box of any member but the last one: a position within the
  tolerance of a move is then within the tolerance of at most two
  consecutive members;
* no axis reverses at the joint with the last member (each axis keeps its
  direction of travel or stops).  Then the joint is decided exactly from the
  position counters (:func:`locate`).

Arcs (1003), segments sent as several moves (which write a move index into
M+1), dwells and auxiliary functions carry their own marker and close the
group, so their resume rules are unchanged.
"""

from __future__ import annotations

from array import array
from bisect import bisect_right

import numpy as np

from .translate import Move, path_distance


class Coalescer:
    """The open group of straight moves sharing one marker (see the module docstring)."""

    def __init__(self, every: int, tolerance: float, axes: int) -> None:
        self.every = every
        self.tolerance = tolerance
        self._lo = np.empty((max(every, 1), axes))
        self._hi = np.empty((max(every, 1), axes))
        self._count = 0
        self._last_delta: np.ndarray | None = None

    def close(self) -> None:
        """The next segment starts a new group."""
        self._count = 0
        self._last_delta = None

    def place(self, moves: list[Move]) -> bool:
        """Whether a segment of ``moves`` needs a marker of its own (a new group's head, or a segment that never
        shares one); False: it joins the open group, sent without a marker."""
        if len(moves) != 1 or moves[0].is_arc or self.every <= 1:
            self.close()
            return True
        m = moves[0]
        delta = m.end - m.start
        lo = np.minimum(m.start, m.end) - self.tolerance
        hi = np.maximum(m.start, m.end) + self.tolerance
        n = self._count
        last = self._last_delta
        joins = (0 < n < self.every and last is not None and bool(np.any(delta))
                 and not bool(np.any(delta * last < 0))
                 and not (n > 1 and bool(np.any(np.all((lo <= self._hi[:n - 1]) & (hi >= self._lo[:n - 1]), axis=1)))))
        if not joins:
            n = 0
        self._lo[n], self._hi[n] = lo, hi
        self._count = n + 1
        self._last_delta = delta
        return not joins


def path_tolerance(resolution: dict[str, float], chordal_tolerance: float) -> float:
    """How far (mm) a read-back position may be from the path of the move it is on (3 pulses, or the chordal
    tolerance when larger): the resume's tolerance, and the margin between the members of a group."""
    return max(3.0 / min(resolution.values()), chordal_tolerance) if resolution else chordal_tolerance


def locate(moves: list[Move], position: np.ndarray, counts: np.ndarray, resolution: np.ndarray,
           tolerance: float) -> int | None:
    """Index of the move of a group under way for a machine at ``position`` (mm, read from the position counters
    ``counts``, pulses; the moves before it are complete, it may be at its end); None when the position is on
    none of them, or on two that are not consecutive (a group built by :class:`Coalescer` never has such).

    Two consecutive candidates share the end point B of the first: its counters equal the machine's -> it is
    complete (as the card counts a move stopped on its end's counters); else an axis whose counter differs from
    B's tells the side of B the machine is on.  Exact because no axis reverses at B, and a counter is the
    position rounded to a pulse, so it lies on the same side of B as the position itself.
    """
    near = [i for i, m in enumerate(moves) if path_distance(m, position) <= tolerance]
    if not near:
        return None
    if len(near) > 2 or near[-1] - near[0] != len(near) - 1:
        return None
    i = near[0]
    if len(near) == 1:
        return i
    joint = moves[i].end
    b = np.rint(joint * resolution)
    if np.array_equal(b, counts):
        return i + 1
    after = moves[i + 1].end - joint
    differ = counts != b
    past = np.sign(position - joint)[differ] == np.sign(after)[differ]
    return i + 1 if bool(np.any(past & (np.sign(after)[differ] != 0))) else i


class MarkerLog:
    """The sequence numbers that carried a marker, in order (8 bytes each): what the card's marker register held
    while a segment ran, for :func:`~.verify.expected_events`.  A resynchronisation forgets the heads purged."""

    def __init__(self) -> None:
        self._heads = array("Q")

    def add(self, seq: int) -> None:
        if not self._heads or self._heads[-1] < seq:
            self._heads.append(seq)

    def forget_after(self, seq: int) -> None:
        """Heads above ``seq`` were purged before they ran (the stream is sent again from ``seq``)."""
        while self._heads and self._heads[-1] > seq:
            self._heads.pop()

    def clear(self) -> None:
        self._heads = array("Q")

    @property
    def last(self) -> int:
        return self._heads[-1] if self._heads else 0

    def tag(self, seq: int) -> int:
        """The marker a segment ran under: its group's head (the last head at or before it)."""
        k = bisect_right(self._heads, seq)
        return self._heads[k - 1] if k else 0

    def __len__(self) -> int:
        return len(self._heads)

