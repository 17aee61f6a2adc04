"""Path pieces the planner moves along: lines and arcs (helices); corner blends are in :mod:`.blend`.

Every piece is a curve ``q(s)`` over a parameter ``s`` in ``[0, length]``
with positions as numpy vectors over the channel axes (machine order).  The
planner only needs, per axis ``i``, bounds of the first three derivatives
``q_i'``, ``q_i''``, ``q_i'''`` with respect to ``s``: the motion along the
piece is ``s(t)`` with speed ``v``, acceleration ``a`` and jerk ``j``, so

    velocity_i     = q_i' v
    acceleration_i = q_i' a + q_i'' v²
    jerk_i         = q_i' j + 3 q_i'' v a + q_i''' v³

which holds for any parameterisation.  Lines and blends use arc length
(``|q'| = 1``); an arc whose start and end radii differ slightly (within the
CIRINERR tolerance) is a spiral, parameterised by its angle, with ``|q'|``
within a fraction of a percent of 1 and its bounds computed exactly.
"""

from __future__ import annotations

import math
import operator
from abc import ABC, abstractmethod
from itertools import pairwise, starmap

import numpy as np


class Piece(ABC):
    """Base class: a curve over ``s`` in ``[0, length]`` with derivative bounds."""

    __slots__ = ("__dict__", "d1", "d2", "d3", "end", "start")

    length: float
    start: np.ndarray
    end: np.ndarray
    d1: np.ndarray   # per-axis max |q'|
    d2: np.ndarray   # per-axis max |q''|
    d3: np.ndarray   # per-axis max |q'''|

    curved = False

    @abstractmethod
    def derivatives(self, s: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """``q, q', q'', q'''`` at the parameters ``s`` (arrays of shape (n, axes))."""

    def bound_lists(self) -> tuple[list[float], list[float], list[float]]:
        """The bounds ``d1, d2, d3`` as lists of floats (what the limits run over)."""
        return self.d1.tolist(), self.d2.tolist(), self.d3.tolist()

    def frame(self, s: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Point, unit tangent and curvature vector (geometric, any parameterisation) at ``s``."""
        q, d1, d2, _ = self.derivatives(np.array([s]))
        t1 = d1[0]
        speed = float(np.linalg.norm(t1))
        t = t1 / speed
        k = (d2[0] - np.dot(d2[0], t) * t) / (speed * speed)
        return q[0], t, k

    def direction(self, s: float) -> tuple[np.ndarray, np.ndarray]:
        """Unit tangent and curvature vector at ``s`` (the frame without its point)."""
        return self.frame(s)[1:]

    def speed_factor(self) -> float:
        """Max of ``|q'|`` (1 for arc-length pieces): path speed = factor * v."""
        return 1.0


#: The slot ``d1`` of :class:`Piece` itself (a line makes its own on first use, see :attr:`LinePiece.d1`).
_D1_SLOT = Piece.__dict__["d1"]


class LinePiece(Piece):
    """A straight segment."""

    __slots__ = ("length", "u", "ul")

    @property
    def d1(self) -> np.ndarray:
        """Per-axis max ``|q'|``: ``|u|``, made on first use (a line's own limits run over ``ul``:
        most lines are never asked for it)."""
        try:
            return _D1_SLOT.__get__(self)
        except AttributeError:
            d1 = np.abs(self.u)
            _D1_SLOT.__set__(self, d1)
            return d1

    @d1.setter
    def d1(self, value: np.ndarray) -> None:
        _D1_SLOT.__set__(self, value)

    def __init__(self, start: np.ndarray, end: np.ndarray) -> None:
        self.start, self.end = start, end
        delta = end - start
        self.length = length = math.hypot(*delta.tolist())
        self.u = delta / length if length > 0 else delta * 0.0
        self.ul = self.u.tolist()   # the direction as floats, for the per-corner tests
        self.d2 = self.d3 = _zeros(len(delta))

    def derivatives(self, s):
        n = len(s)
        q = self.start + np.outer(s, self.u)
        zero = np.zeros((n, len(self.u)))
        return q, np.broadcast_to(self.u, (n, len(self.u))), zero, zero

    def frame(self, s):
        return self.start + s * self.u, self.u, self.d2

    def direction(self, s):
        return self.u, self.d2

    def direction_list(self, s: float) -> tuple[list[float], tuple[float, ...]]:
        return self.ul, (0.0,) * len(self.ul)

    def tangent_list(self, s: float) -> list[float]:
        return self.ul

    def sub(self, s0: float, s1: float, start: np.ndarray | None = None) -> LinePiece:
        # the same direction and derivative bounds: only the ends move (no norm, no division), and
        # an end that stays keeps its point; ``start``: the point at s0 when already computed
        out = LinePiece.__new__(LinePiece)
        if start is not None:
            out.start = start
        else:
            out.start = self.start if s0 == 0.0 else self.start + s0 * self.u
        out.end = self.end if s1 == self.length else self.start + s1 * self.u
        out.length = s1 - s0
        out.u, out.ul, out.d2, out.d3 = self.u, self.ul, self.d2, self.d3   # d1: |u| when asked
        return out


def line_pieces(starts: list[np.ndarray], ends: list[np.ndarray], start_rows: np.ndarray, end_rows: np.ndarray,
                shortest: float) -> list[LinePiece | None]:
    """``LinePiece(starts[i], ends[i])`` for each line of a run (``start_rows``, ``end_rows``: the same points as
    rows (n, D)), or None where it is not longer than ``shortest`` (dropped: nothing moves).  Made at once: the
    differences and the divisions by the lengths as arrays (the same operations element by element, so the
    same floats), each line's direction a row of those (a view), and its floats all in one call."""
    deltas = end_rows - start_rows
    lengths = list(starmap(math.hypot, deltas.tolist()))   # math.hypot(*delta) of each line, as __init__
    # a line dropped is divided by 1 (no warning; its direction is never asked)
    divisors = np.array(lengths)
    divisors[~(divisors > shortest)] = 1.0
    units = deltas / divisors[:, None]
    zeros = _zeros(deltas.shape[1])
    out: list[LinePiece | None] = []
    new = LinePiece.__new__
    for start, end, length, u, ul in zip(starts, ends, lengths, list(units), units.tolist()):  # noqa: B905 (a row a line)
        if not length > shortest:
            out.append(None)
            continue
        piece = new(LinePiece)
        piece.start, piece.end, piece.length, piece.u, piece.ul = start, end, length, u, ul
        piece.d2 = piece.d3 = zeros
        out.append(piece)
    return out


_ZEROS: dict[int, np.ndarray] = {}


def _zeros(dim: int) -> np.ndarray:
    """A shared read-only zero vector: the second and third derivative bounds of every line."""
    z = _ZEROS.get(dim)
    if z is None:
        z = _ZEROS[dim] = np.zeros(dim)
        z.flags.writeable = False
    return z


_PI = math.pi
_HALF_PI = math.pi / 2
#: The axes off an arc's plane, by (axes, plane's first axis, its second): what :meth:`ArcPiece.point` moves.
_OFF_PLANE: dict[tuple[int, int, int], tuple[int, ...]] = {}


def _range_max(theta0: float, theta1: float) -> tuple[float, float]:
    """Max of |sin| and |cos| over the angle interval between theta0 and theta1: 1 where the
    interval holds an odd multiple of pi/2 (|sin|) or a multiple of pi (|cos|), else the larger end."""
    lo, hi = (theta0, theta1) if theta0 <= theta1 else (theta1, theta0)
    # the larger end as max() takes it (the second where it is greater), without the call
    if _HALF_PI + math.ceil((lo - _HALF_PI) / _PI) * _PI <= hi:
        ms = 1.0
    else:
        ms, other = abs(math.sin(lo)), abs(math.sin(hi))
        if other > ms:
            ms = other
    if math.ceil(lo / _PI) * _PI <= hi:
        mc = 1.0
    else:
        mc, other = abs(math.cos(lo)), abs(math.cos(hi))
        if other > mc:
            mc = other
    return ms, mc


class ArcPiece(Piece):
    """A circular arc in the plane of axes ``ia``, ``io`` (indices), helical on the others.

    ``theta = theta0 + w s``, radius ``rho = r0 + dr s``, other axes linear.
    """

    __slots__ = ("_bounded", "_ends", "_lin", "center", "dr", "ia", "io", "length", "lin", "r0", "theta0", "w")

    curved = True

    # the derivative bounds, made on first use: a corner trims the start of an arc and the next
    # corner its end, and only the arc left after both is planned (as lists: what the limits run
    # over; arrays when asked)
    @property
    def d1(self) -> np.ndarray:
        return np.array(self.bound_lists()[0])

    @property
    def d2(self) -> np.ndarray:
        return np.array(self.bound_lists()[1])

    @property
    def d3(self) -> np.ndarray:
        return np.array(self.bound_lists()[2])

    def __init__(self, start: np.ndarray, end: np.ndarray, ia: int, io: int, center: tuple[float, float],
                 sweep: float) -> None:
        # on floats: an arc is made for every block and every trim of one
        self.start, self.end, self.ia, self.io = start, end, ia, io
        self.center = center
        cx, cy = center
        a, b = start.tolist(), end.tolist()
        r0 = math.hypot(a[ia] - cx, a[io] - cy)
        r1 = math.hypot(b[ia] - cx, b[io] - cy)
        self.theta0 = math.atan2(a[io] - cy, a[ia] - cx)
        other = list(map(operator.sub, b, a))   # y - x per axis (map: no comprehension's frame on every arc)
        other[ia] = other[io] = 0.0
        planar = abs(sweep) * (r0 + r1) / 2.0
        self.length = length = math.hypot(planar, math.hypot(*other))
        self.r0 = r0
        self.dr = (r1 - r0) / length
        self.w = sweep / length
        lin = [x / length for x in other]
        self.lin = np.array(lin)
        # what every part and trim of the arc (which share its ``lin``) asks of it: its floats, their
        # magnitudes (the other axes' d1), the sum of their squares (in speed_factor's order) and the
        # axes off the plane with theirs (what point moves)
        key = (len(lin), ia, io)
        off = _OFF_PLANE.get(key)
        if off is None:
            off = _OFF_PLANE[key] = tuple(i for i in range(len(lin)) if i != ia and i != io)
        self._lin = (lin, list(map(abs, lin)), sum(map(operator.mul, lin, lin)), off)
        self._ends = (r1, sweep)   # the end radius and sweep the bounds are made from
        self._bounded = None

    def __getstate__(self) -> tuple[None, dict]:
        # its slots, not the d1/d2/d3 properties (which pickle's default would try to set back)
        return None, {name: getattr(self, name) for name in ("start", "end", *ArcPiece.__slots__)}

    def bound_lists(self) -> tuple[list[float], list[float], list[float]]:
        """The bounds ``d1, d2, d3`` as lists of floats, made on first use."""
        if self._bounded is not None:
            return self._bounded
        r0, (r1, sweep), lin_abs = self.r0, self._ends, self._lin[1]
        ms, mc = _range_max(self.theta0, self.theta0 + sweep)
        rmax, dr, w = r1 if r1 > r0 else r0, abs(self.dr), abs(self.w)   # max(r0, r1)
        ia, io = self.ia, self.io
        d1 = list(lin_abs)
        d2 = [0.0] * len(d1)
        d3 = [0.0] * len(d1)
        # q_a = rho cos(th): q' = dr cos - rho w sin; q'' = -2 dr w sin - rho w² cos;
        # q''' = -3 dr w² cos + rho w³ sin
        # the products each pair shares made once: Python multiplies left to right, so ``rmax * w * ms``
        # is ``(rmax * w) * ms`` (the same numbers)
        rw, dw2 = rmax * w, 2 * dr * w
        rww, dww3, rw3 = rw * w, 3 * dr * w * w, rmax * w ** 3
        d1[ia] = dr * mc + rw * ms
        d1[io] = dr * ms + rw * mc
        d2[ia] = dw2 * ms + rww * mc
        d2[io] = dw2 * mc + rww * ms
        d3[ia] = dww3 * mc + rw3 * ms
        d3[io] = dww3 * ms + rw3 * mc
        self._bounded = bounds = (d1, d2, d3)
        return bounds

    def derivatives(self, s):
        th = self.theta0 + self.w * s
        c, sn = np.cos(th), np.sin(th)
        rho = self.r0 + self.dr * s
        w, dr = self.w, self.dr
        n, dim = len(s), len(self.start)
        q = self.start + np.outer(s, self.lin)
        d1 = np.broadcast_to(self.lin, (n, dim)).copy()
        d2 = np.zeros((n, dim))
        d3 = np.zeros((n, dim))
        ia, io = self.ia, self.io
        q[:, ia] = self.center[0] + rho * c
        q[:, io] = self.center[1] + rho * sn
        d1[:, ia] = dr * c - rho * w * sn
        d1[:, io] = dr * sn + rho * w * c
        d2[:, ia] = -2 * dr * w * sn - rho * w * w * c
        d2[:, io] = 2 * dr * w * c - rho * w * w * sn
        d3[:, ia] = -3 * dr * w * w * c + rho * w ** 3 * sn
        d3[:, io] = -3 * dr * w * w * sn - rho * w ** 3 * c
        return q, d1, d2, d3

    def point(self, s: float) -> np.ndarray:
        """The point at ``s``: :meth:`derivatives`' first row for one parameter, on floats (an
        arc's trims and corner frames ask for single points)."""
        th = self.theta0 + self.w * s
        rho = self.r0 + self.dr * s
        q = self.start.copy()
        lin, _, _, off = self._lin
        for i in off:   # start + s * lin on the axes off the plane, element by element
            q[i] = q[i] + s * lin[i]
        q[self.ia] = self.center[0] + rho * math.cos(th)
        q[self.io] = self.center[1] + rho * math.sin(th)
        return q

    def frame(self, s: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        return (self.point(s), *self.direction(s))

    def direction(self, s: float) -> tuple[np.ndarray, np.ndarray]:
        t, k = self.direction_list(s)
        return np.array(t), np.array(k)

    def _velocity(self, s: float) -> tuple[list[float], float, float, float]:
        """``q'`` at ``s`` as a list of floats, with the cosine and sine of the angle and the radius there."""
        th = self.theta0 + self.w * s
        c, sn = math.cos(th), math.sin(th)
        rho = self.r0 + self.dr * s
        w, dr = self.w, self.dr
        d1 = list(self._lin[0])   # the floats of ``lin``
        d1[self.ia] = dr * c - rho * w * sn
        d1[self.io] = dr * sn + rho * w * c
        return d1, c, sn, rho

    def tangent_list(self, s: float) -> list[float]:
        """The unit tangent at ``s`` as a list of floats: :meth:`direction_list`'s, without the
        curvature (which a corner only asks for when the tangents meet)."""
        d1 = self._velocity(s)[0]
        return list(map(math.hypot(*d1).__rtruediv__, d1))   # x / |q'|, as direction_list divides

    def direction_list(self, s: float) -> tuple[list[float], list[float]]:
        """The unit tangent and curvature vector at ``s`` as lists of floats: a corner at an arc
        whose tangents meet asks for them (smooth?)."""
        d1, c, sn, rho = self._velocity(s)
        w, dr, ia, io = self.w, self.dr, self.ia, self.io
        da = -2 * dr * w * sn - rho * w * w * c     # q'' has no other component
        do = 2 * dr * w * c - rho * w * w * sn
        speed = math.hypot(*d1)
        t = [x / speed for x in d1]
        along = da * t[ia] + do * t[io]
        square = speed * speed
        k = [-along * x / square for x in t]
        k[ia] = (da - along * t[ia]) / square
        k[io] = (do - along * t[io]) / square
        return t, k

    def speed_factor(self) -> float:
        rmax = max(self.r0, self.r0 + self.dr * self.length)
        return math.sqrt((self.dr ** 2 + (rmax * self.w) ** 2) + self._lin[2])

    def pieces(self, cuts: list[float]) -> list[ArcPiece]:
        """``[sub(cuts[i], cuts[i + 1]) ...]`` for the increasing ``cuts``: the same pieces, with the
        point at a cut inside the arc computed once for the two pieces that meet there (a long arc
        is planned in parts)."""
        length = self.length
        out = []
        shared = None   # point(s0) when the piece before made it as its end
        for s0, s1 in pairwise(cuts):
            start = self.start if s0 == 0.0 else shared if shared is not None else self.point(s0)
            end = shared = None if s1 == length else self.point(s1)
            out.append(self._between(s0, s1, start, self.end if end is None else end))
        return out

    def sub(self, s0: float, s1: float) -> ArcPiece:
        # the same curve over [s0, s1] with the same parameter (angle and radius linear in it): only
        # the ends, the start angle and radius move; an end that stays keeps its point
        return self._between(s0, s1, self.start if s0 == 0.0 else self.point(s0),
                             self.end if s1 == self.length else self.point(s1))

    def _between(self, s0: float, s1: float, start: np.ndarray, end: np.ndarray) -> ArcPiece:
        """:meth:`sub` with its end points (``point(s0)``, ``point(s1)`` or the arc's own ends)."""
        out = ArcPiece.__new__(ArcPiece)
        out.ia, out.io, out.center, out.w, out.dr, out.lin = self.ia, self.io, self.center, self.w, self.dr, self.lin
        out._lin = self._lin
        out.start, out.end = start, end
        out.theta0 = self.theta0 + self.w * s0
        out.r0 = r0 = self.r0 + self.dr * s0
        out.length = length = s1 - s0
        out._ends = (r0 + self.dr * length, self.w * length)
        out._bounded = None
        return out


def arc_bound_rows(arcs: list[ArcPiece], theta0: list[float], r0: list[float],
                   length: list[float]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:meth:`ArcPiece.bound_lists` of stretches of ``arcs`` (what :meth:`ArcPiece._between` makes:
    the start angles ``theta0``, radii ``r0`` and lengths ``length``) as rows (n, D), all at once: the
    same operations element by element, so the same floats (the sines and cosines of the ends by
    :mod:`math` and the cubes by Python's power, as the scalar form takes them; a batch of corners at
    arcs knows the arcs it trims at both ends)."""
    n = len(arcs)
    w, dr = np.array([a.w for a in arcs]), np.array([a.dr for a in arcs])
    theta0, r0, length = np.array(theta0), np.array(r0), np.array(length)
    r1, theta1 = r0 + dr * length, theta0 + w * length   # _between's ends: the end radius, start + sweep
    # _range_max of each stretch
    first = theta0 <= theta1
    lo, hi = np.where(first, theta0, theta1), np.where(first, theta1, theta0)
    ends = lo.tolist(), hi.tolist()
    sin = [np.abs([math.sin(x) for x in e]) for e in ends]
    cos = [np.abs([math.cos(x) for x in e]) for e in ends]
    ms = np.where(_HALF_PI + np.ceil((lo - _HALF_PI) / _PI) * _PI <= hi, 1.0, np.maximum(*sin))
    mc = np.where(np.ceil(lo / _PI) * _PI <= hi, 1.0, np.maximum(*cos))
    rmax, dr, w = np.where(r1 > r0, r1, r0), np.abs(dr), np.abs(w)
    rw, dw2 = rmax * w, 2 * dr * w
    rww, dww3, rw3 = rw * w, 3 * dr * w * w, rmax * np.array([x ** 3 for x in w.tolist()])
    d1 = np.array([a._lin[1] for a in arcs])
    d2, d3 = np.zeros(d1.shape), np.zeros(d1.shape)
    at = np.arange(n)
    ia, io = np.array([a.ia for a in arcs]), np.array([a.io for a in arcs])
    d1[at, ia], d1[at, io] = dr * mc + rw * ms, dr * ms + rw * mc
    d2[at, ia], d2[at, io] = dw2 * ms + rww * mc, dw2 * mc + rww * ms
    d3[at, ia], d3[at, io] = dww3 * mc + rw3 * ms, dww3 * ms + rw3 * mc
    return d1, d2, d3
