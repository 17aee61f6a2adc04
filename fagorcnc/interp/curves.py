"""Curves: #POLY polynomial interpolation and #SPLINE / #ASPLINE Akima splines (seed 002 ch. 21.1.13-21.1.14).

Both become chords (:class:`~fagorcnc.interp.records.CurveLine`) within
:data:`~fagorcnc.path.spline.CHORD_TOLERANCE` of the curve, one ``curve`` object per curve so that
the planner joins them without a corner (plan/links.py), each tied to the block it comes from.

* ``#POLY [X[a,b,c,d,e] Y[...] ... SP sp EP ep]``: every axis follows ``a + b p + c p² + d p³ + e p⁴``
  for ``p`` from sp to ep (L15830-L15857), at the active feed.  [CONSTRUCTION] the manual calls p
  the arc length (L15832) but its own example (L15862-L15870: X = 60p over p 0..60) is not, so the
  polynomials are evaluated literally; coefficients are in the programmed units and coordinates
  (absolute); the curve must start where the tool stands.
* ``#SPLINE ON`` ... ``#SPLINE OFF``: the straight moves between them are replaced by the Akima spline
  through their end points, the point before ``#SPLINE ON`` first (L15690-L15722, example L15777).
  The sentences put a :class:`SplineMark` in the record stream; :func:`splines` (a stage right after
  the block loop) collects the moves and hands on the chords, so a tangent "to the next block"
  (``#ASPLINE MODE [.., 2]``) is that of the move after ``#SPLINE OFF``.  An arc interrupts the
  spline, with tangent transitions at both its ends (L15694-L15697).
  [CONSTRUCTION] the manual does not give the spline's parameter: the cumulative chord length over
  the axes that move, Akima's slopes per coordinate (path/spline.py), in machine coordinates; given
  tangents are unit vectors.  The "3 points" of L15721 count the start point.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..kinematics.stage import StageError
from ..syntax.ast import ItemList, Keyed
from .expressions import InterpError
from .records import Arc, CurveLine, IndependentMove, Line, Source, _AtPosition

#: Tangent types of #ASPLINE MODE (L15740-L15770): automatic, tangent to the block before / after, given.
TANGENT_TYPES = (1, 2, 3)


@dataclass
class CurveSettings:
    """#ASPLINE state of the channel: tangent types and the tangents given (programmed axes)."""

    start_mode: int = 1
    end_mode: int = 1
    start_tangent: dict | None = None
    end_tangent: dict | None = None
    active: bool = False
    #: axes a #MOVE moved since the last #SYNC POS -> the line of that #MOVE: the general interpolator does
    #: not count those moves until #SYNC POS (interp/independent.py, seed 002 L16657-L16665)
    independent: dict = field(default_factory=dict)


@dataclass(frozen=True, slots=True)
class SplineMark(_AtPosition):
    """#SPLINE ON (``on``) or OFF in the record stream: the tangent type of that end and its
    tangent (machine axes, unit) for type 3; consumed by :func:`splines`, never handed on."""

    kind: str
    on: bool
    mode: int
    tangent: tuple | None
    position: dict
    src: Source

    @property
    def length(self) -> float:
        return 0.0


def _items(node) -> list:
    """The items of a sentence's bracketed arguments, in order (commas or spaces between them)."""
    out = []
    for a in node.args:
        if type(a) is ItemList:
            for seq in a.items:
                out.extend(seq)
        else:
            out.append(a)
    return out


# ------------------------------------------------------------------ #POLY
def poly_statement(interp, node, src: Source):
    """``#POLY [X[a,b,c,d,e] Y[...] SP sp EP ep]`` (seed 002 L15822-L15870): the chords of the curve."""
    from ..path.spline import CHORD_TOLERANCE, CurveError, poly_points  # on first use: a program without curves

    st = interp.state
    iso = interp.iso
    ev = interp.evaluator
    coeffs: dict[str, list[float]] = {}
    sp = ep = None
    args = node.args
    if len(args) != 1 or type(args[0]) is not ItemList:
        raise InterpError("INT220", "#POLY takes its axes and parameters in brackets: "
                          "#POLY [X[0,60,0,0,0] Y[1,0,3,0,0] SP0 EP60] (L15835)", node.col)
    for item in _items(node):
        if type(item) is not Keyed:
            raise InterpError("INT220", "#POLY: each item is an axis with its coefficients X[a,b,c,d,e], SP or EP "
                              "(L15835)", getattr(item, "col", node.col))
        name, value = item.name, item.value
        if name in ("SP", "EP") and type(value) is not ItemList:
            if name == "SP":
                sp = ev.value(value)
            else:
                ep = ev.value(value)
            continue
        if name not in st.axes:
            raise InterpError("INT220", f"#POLY: {name} is not an axis of the channel", item.col)
        seqs = value.items if type(value) is ItemList else ()
        if not 1 <= len(seqs) <= 5 or any(len(seq) != 1 for seq in seqs):
            raise InterpError("INT220", f"#POLY: {name} takes 1 to 5 coefficients in brackets, {name}[a,b,c,d,e] "
                              "(4th degree at most, L15831)", item.col)
        if name in coeffs:
            raise InterpError("INT220", f"#POLY: axis {name} is programmed twice", item.col)
        coeffs[name] = [ev.value(seq[0]) for seq in seqs] + [0.0] * (5 - len(seqs))
    if not coeffs:
        raise InterpError("INT220", "#POLY needs at least one axis and its coefficients (L15835)", node.col)
    if sp is None or ep is None:
        raise InterpError("INT220", "#POLY needs the start and end parameters SP and EP (L15856)", node.col)
    if sp == ep:
        raise InterpError("INT220", f"#POLY: SP and EP are both {sp:g}: no curve", node.col)
    if st.modes["motion"] == 0:
        raise InterpError("INT221", "#POLY runs at the feed: program G01 before it, not G00 (L15868)", node.col)
    if st.mcs_on or st.kin.frame is not None:
        raise InterpError("INT221", "#POLY under #MCS or a coordinate transformation (#CS, #RTCP...) is not "
                          "computed by fagorcnc", node.col)
    axes = list(coeffs)
    table = np.array([coeffs[a] for a in axes])
    cur = st.programmed_pos()
    for a, row in zip(axes, table, strict=True):
        here = iso.length(float(np.polyval(row[::-1], sp)), a)
        if abs(here - cur[a]) > CHORD_TOLERANCE:
            raise InterpError("INT221", f"#POLY starts at {a}{here:g} (p = SP {sp:g}) but the tool stands at "
                              f"{a}{cur[a]:g}: the curve must start where the tool is", node.col)
    scale = max(st.transform.scale, 1e-12) if st.transform.linear & set(axes) else 1.0
    tol = CHORD_TOLERANCE / max(scale, 1.0)
    unit = np.array([iso.length(1.0, a) for a in axes])
    try:
        params, points = poly_points(table, sp, ep, tol / float(unit.max()))
    except CurveError as exc:
        raise InterpError("INT222", f"#POLY: {exc}", node.col) from None
    points = points * unit
    yield from _poly_records(interp, src, axes, points, cur, table, params[-1], unit, 1.0 if ep > sp else -1.0)


def _poly_records(interp, src: Source, axes: list, points: np.ndarray, cur: dict, table, p_end: float,
                  unit: np.ndarray, direction: float):
    from ..path.spline import poly_tangent

    st = interp.state
    iso = interp.iso
    ends = []
    start = dict(st.machine_pos)
    for row in points[1:]:
        prog = dict(cur)
        prog.update(zip(axes, row.tolist(), strict=True))
        part = st.transform.apply(prog)
        ends.append((st.to_machine(part), part))
    for end, _part in ends:
        interp.check_limits(end, 1, start)
    path = np.array([[e[a] for a in start] for e in [start, *(end for end, _ in ends)]])
    length = float(np.linalg.norm(np.diff(path, axis=0), axis=1).sum())
    feed = iso._active_feed(length, start)   # G93: the whole curve takes F seconds
    comp = iso._compensation()
    joins = iso._joins(comp)
    dyn = st.dynamics()
    curve = object()
    mode = f"G{st.modes['feed']}"
    prev = start
    for end, part in ends:
        yield CurveLine("linear", prev, end, part, feed, mode, src, comp, dyn, joins=joins, curve=curve)
        prev = end
    st.machine_pos = dict(prev)
    a, o, _ = st.plane_axes()
    d = dict(zip(axes, (poly_tangent(table, p_end) * unit * direction).tolist(), strict=True))
    if a is not None and o is not None and (d.get(a, 0.0) or d.get(o, 0.0)):
        t = np.array([d.get(a, 0.0), d.get(o, 0.0)])
        t /= np.linalg.norm(t)
        st.tangent = (float(t[0]), float(t[1]))


# ------------------------------------------------------------------ #SPLINE / #ASPLINE
def _tangent_vector(interp, items, what: str, col: int) -> dict:
    """``X1 Y1``: a direction by its components on the programmed axes (L15755-L15770)."""
    st = interp.state
    out = {}
    for item in items:
        if type(item) is not Keyed or item.name not in st.axes or type(item.value) is ItemList:
            raise InterpError("INT223", f"#ASPLINE {what} takes the tangent by its axis components: "
                              f"#ASPLINE {what} X1 Y1 (L15755-L15770)", getattr(item, "col", col))
        out[item.name] = interp.evaluator.value(item.value)
    if not out or not any(out.values()):
        raise InterpError("INT223", f"#ASPLINE {what} needs a direction that is not zero: #ASPLINE {what} X1 Y1", col)
    return out


def aspline_statement(interp, node, sub) -> None:
    """``#ASPLINE MODE [start, end]``, ``#ASPLINE STARTTANG X.. Y..``, ``#ASPLINE ENDTANG ...``
    (seed 002 L15724-L15770)."""
    cs = interp.curves
    if sub == "MODE":
        value = node.args[0].value if type(node.args[0]) is Keyed else None
        seqs = value.items if type(value) is ItemList else ()
        if not 1 <= len(seqs) <= 2 or any(len(seq) > 1 for seq in seqs) or len(node.args) != 1:
            raise InterpError("INT223", "#ASPLINE MODE takes the start and end tangent types in brackets: "
                              "#ASPLINE MODE [1,2] (L15734)", node.col)
        modes = []
        for seq in seqs:
            m = interp.evaluator.value(seq[0]) if seq else 1.0   # not programmed: 1 (L15737)
            if m not in TANGENT_TYPES:
                raise InterpError("INT223", f"#ASPLINE MODE: tangent type {m:g}; the types are 1 (automatic), "
                                  "2 (tangent to the block before / after) and 3 (STARTTANG / ENDTANG) (L15766-L15770)",
                                  node.col)
            modes.append(int(m))
        cs.start_mode = modes[0]
        cs.end_mode = modes[1] if len(modes) > 1 else 1
        return
    if sub in ("STARTTANG", "ENDTANG"):
        vector = _tangent_vector(interp, node.args[1:], sub, node.col)
        if sub == "STARTTANG":
            cs.start_tangent = vector
        else:
            cs.end_tangent = vector
        return
    raise InterpError("INT223", "#ASPLINE is followed by MODE, STARTTANG or ENDTANG (L15724-L15770)", node.col)


def _machine_direction(interp, vector: dict) -> tuple:
    """A programmed direction as a unit vector over the machine axes (mirror and scale applied)."""
    st = interp.state
    zero = {a: 0.0 for a in st.axes}
    tip = st.transform.apply({**zero, **vector})
    base = st.transform.apply(zero)
    d = np.array([tip[a] - base[a] for a in st.axes])
    return tuple((d / np.linalg.norm(d)).tolist())


def spline_statement(interp, node, sub, src: Source):
    """``#SPLINE ON`` / ``#SPLINE OFF`` (seed 002 L15699-L15722): a :class:`SplineMark` for :func:`splines`."""
    st = interp.state
    cs = interp.curves
    if sub not in ("ON", "OFF") or len(node.args) != 1:
        raise InterpError("INT223", "#SPLINE ON or #SPLINE OFF", node.col)
    on = sub == "ON"
    if on and st.modes["compensation"] in (41, 42) and st.modes["transition"] == 137:
        raise InterpError("INT225", "#SPLINE ON with radius compensation G41/G42 and the linear transition G137: "
                          "the manual does not allow them together (L15708)", node.col)
    mode = cs.start_mode if on else cs.end_mode
    tangent = None
    if mode == 3:
        vector = cs.start_tangent if on else cs.end_tangent
        if vector is None:
            which = "STARTTANG" if on else "ENDTANG"
            raise InterpError("INT223", f"#ASPLINE MODE 3 needs the tangent: program #ASPLINE {which} X.. Y.. before "
                              f"#SPLINE {sub} (L15746-L15748)", node.col)
        tangent = _machine_direction(interp, vector)
    if on == cs.active:
        return   # ON while on / OFF while off: nothing changes
    cs.active = on
    yield SplineMark("spline", on, mode, tangent, dict(st.machine_pos), src)


# ------------------------------------------------------------------ the stage
def _unit(v: np.ndarray) -> np.ndarray | None:
    n = float(np.linalg.norm(v))
    return v / n if n > 1e-12 else None


def _direction(rec, axes: list, at_end: bool) -> np.ndarray | None:
    """Unit direction of travel of a move at its start or end (machine axes)."""
    start = np.array([rec.start[a] for a in axes])
    end = np.array([rec.end[a] for a in axes])
    if rec.kind != "arc":
        return _unit(end - start)
    a, o = rec.plane[0], rec.plane[1]
    ia, io = axes.index(a), axes.index(o)
    p = end if at_end else start
    ra, ro = p[ia] - rec.center[a], p[io] - rec.center[o]
    r = float(np.hypot(ra, ro))
    planar = np.zeros(len(axes))
    planar[ia], planar[io] = ((-ro, ra) if rec.direction == "ccw" else (ro, -ra))
    planar *= abs(np.radians(rec.sweep)) * rec.radius / r if r > 1e-12 else 0.0
    other = end - start
    other[ia] = other[io] = 0.0
    return _unit(planar + other)


class _Spline:
    """The points of a spline being collected: ``records[i]`` programmed point ``i + 1``;
    ``events[k]`` the auxiliary records met at point k."""

    def __init__(self, start: dict, tangent, mark: SplineMark, limits: dict, total: int = 0) -> None:
        self.limits = limits
        self.axes = list(start)
        self.start = dict(start)
        self.points = [np.array([start[a] for a in self.axes])]
        self.records: list = []
        self.events: dict[int, list] = {}
        self.tangent = tangent
        self.mark = mark
        self.total = total   # points of the spline before this stretch (an arc interrupted it)
        self.last_chord = None

    def add(self, rec) -> None:
        if rec.frame is not None:
            raise StageError(rec, "INT226", "a spline under a coordinate transformation (#CS, #ACS, #RTCP...) is "
                             "not computed by fagorcnc")
        if rec.feed_mode == "G93":
            raise StageError(rec, "INT226", "a spline with G93 (time per block) is not computed by fagorcnc: "
                             "program the feed in G94 or G95")
        if rec.comp is not None and rec.comp[2] == 137:
            raise StageError(rec, "INT225", "radius compensation with the linear transition G137 inside a spline: "
                             "the manual does not allow them together (L15708)")
        p = np.array([rec.end[a] for a in self.axes])
        if float(np.linalg.norm(p - self.points[-1])) <= 1e-9:
            return   # a point where the spline already is adds nothing
        self.points.append(p)
        self.records.append(rec)

    def event(self, rec) -> None:
        self.events.setdefault(len(self.points) - 1, []).append(rec)

    def count(self) -> int:
        """Points of the spline so far (its start and the ends of the arcs that interrupted it included)."""
        return self.total + len(self.points)

    def emit(self, end_tangent):
        """The chords (and the events at their points) of the stretch collected."""
        from ..path.spline import CurveError, spline_points

        yield from self.events.get(0, ())
        if len(self.points) < 2:
            return
        pts = np.array(self.points)
        start = None if self.tangent is None else np.asarray(self.tangent)
        end = None if end_tangent is None else np.asarray(end_tangent)
        try:
            segments = spline_points(pts, start, end)
        except CurveError as exc:
            raise StageError(self.records[-1], "INT222", f"#SPLINE: {exc}") from None
        curve = object()
        prev = self.start
        for k, (rec, seg) in enumerate(zip(self.records, segments, strict=True)):
            offset = {a: rec.end[a] - rec.end_part[a] for a in rec.end_part}
            for row in seg:
                end_pos = dict(zip(self.axes, row.tolist(), strict=True))
                _check_limits(rec, end_pos, self.limits)
                part = {a: end_pos[a] - offset[a] for a in rec.end_part}
                chord = CurveLine(rec.kind, prev, end_pos, part, rec.feed, rec.feed_mode, rec.src, rec.comp, rec.dyn,
                                  None, rec.joins, curve=curve)
                self.last_chord = chord
                yield chord
                prev = end_pos
            yield from self.events.get(k + 1, ())


def _check_limits(rec, end: dict, limits: dict) -> None:
    """Soft limits on a point of the spline (it may pass beyond the programmed points)."""
    for a, v in end.items():
        lo, hi = limits.get(a, (-np.inf, np.inf))
        if v < lo - 1e-9 or v > hi + 1e-9:
            raise StageError(rec, "INT100", f"the spline takes axis {a} to {v:.4f} (machine), beyond its "
                             f"{'lower' if v < lo else 'upper'} limit {lo if v < lo else hi:g}")


MOTION = ("linear", "rapid", "arc")


def splines(records, interp, last=None):
    """The stage: the moves between #SPLINE ON and OFF become the chords of their spline (see the
    module's text); every other record passes unchanged, in order.  ``last``: the last move handed on
    before ``records`` (a stage taking over a stream from :func:`~fagorcnc.interp.pipeline.stages`' idle
    lane)."""
    st = interp.state
    spline: _Spline | None = None
    held: tuple | None = None     # (spline, end mark, events after it): waiting for the next move's tangent
    # last: the last move handed on (tangent type 2 at the start)
    for rec in records:
        kind = rec.kind
        if kind == "spline":
            if rec.on:
                if held is not None:   # ON again before any move: the block after OFF has no tangent
                    yield from _release(held, None)
                    last, held = held[0].last_chord or last, None
                axes = list(rec.position)
                tangent = _direction(last, axes, True) if rec.mode == 2 and last is not None else rec.tangent
                spline = _Spline(rec.position, tangent, rec, _limits(st))
            elif spline is not None:
                _enough(spline, rec)
                if rec.mode == 2:
                    held, spline = (spline, rec, []), None
                else:
                    yield from spline.emit(rec.tangent)
                    last, spline = spline.last_chord or last, None
            continue
        if held is not None:
            # an independent #MOVE is no block of the path: the spline ends tangent to the next general move
            if kind not in MOTION or isinstance(rec, IndependentMove):
                held[2].append(rec)
                continue
            yield from _release(held, _direction(rec, held[0].axes, False))
            held = None
        if spline is not None:
            if kind in ("linear", "rapid") and type(rec) is Line:
                spline.add(rec)
                continue
            if kind in MOTION:
                if type(rec) is not Arc:
                    raise StageError(rec, "INT226", "#POLY or #MOVE between #SPLINE ON and #SPLINE OFF: the "
                                     "spline is made of G00/G01 points (L15692)")
                # an arc interrupts the spline; tangent transitions at both its ends (L15694-L15697)
                yield from spline.emit(_direction(rec, spline.axes, False))
                yield rec
                last = rec
                spline = _Spline(dict(rec.end), _direction(rec, spline.axes, True), spline.mark, _limits(st),
                                 spline.count())
                continue
            spline.event(rec)
            continue
        if kind in MOTION and not isinstance(rec, IndependentMove):
            last = rec
        yield rec
    if held is not None:
        yield from _release(held, None)
    if spline is not None:   # the program ended with the spline on: it ends there
        yield from spline.emit(None)


def _limits(st) -> dict:
    return {a: (st.lower_limits[a], st.upper_limits[a]) for a in st.axes}


def _release(held: tuple, tangent):
    """A spline whose end is tangent to the next block (type 2): its chords, then what came after
    #SPLINE OFF.  [CONSTRUCTION] with no move after it (the program ends) the end tangent is automatic."""
    spline, _mark, events = held
    yield from spline.emit(tangent)
    yield from events


def _enough(spline: _Spline, mark: SplineMark) -> None:
    """#SPLINE OFF needs 3 points, or 2 with both tangents defined (L15721-L15722)."""
    both = spline.mark.mode != 1 and mark.mode != 1
    need = 2 if both else 3
    if spline.count() < need:
        raise StageError(mark, "INT224", f"#SPLINE OFF after {spline.count()} point(s) of the spline (the start point "
                         f"included): it needs 3, or 2 when the start and end tangents are both defined (L15721)")
