"""The canned cycles inside the ISO block executor.

:class:`CycleRunner` is the one object :class:`~fagorcnc.interp.iso.IsoExecutor` talks to:

* :meth:`split` takes a cycle's parameter letters out of a definition or
  multiple-machining block before the ordinary word classification, so that
  ``Z``, ``D``, ``H``, ``M``, ``B``... are read as parameters, not as an axis,
  a tool offset or an H/M function (digest §1.2);
* :meth:`applies` says whether a block is the cycle's business (a definition,
  a G160-G165 block, or an influence-zone block that positions the plane axes);
* :meth:`execute` machines the hole(s) of the block and yields the ordinary
  motion records (rapid, linear, arc, dwell, spindle M) they expand into, each
  tied to the block's source line.

Every hole is computed completely, soft limits included, before its first record
is handed on: an error leaves the tool where the previous hole left it.
"""

from __future__ import annotations

import math
from dataclasses import replace
from typing import TYPE_CHECKING

from ..._lazy import LazyModule
from ..dynamics import build as _dynamics
from ..expressions import InterpError
from ..records import Arc, Dwell, Line, Source, feed_mode
from . import choices
from .model import CYCLE_CODES, PATTERN_CODES, ActiveCycle

if TYPE_CHECKING:
    from . import drilling, milling, patterns, pockets, threads
else:   # the families are imported when a program first runs a cycle (a plain program never does)
    drilling, milling, patterns, pockets, threads = (
        LazyModule(f"{__package__}.{family}") for family in ("drilling", "milling", "patterns", "pockets", "threads"))

INCH = 25.4

#: Parameter letters of each cycle (digest §2; the plane axes may also position).
LETTERS: dict[int, str] = {
    81: "ZIK", 82: "ZIBCDHJKLR", 83: "ZIJ", 84: "ZIKRB", 85: "ZIK", 86: "ZIK",
    87: "ZIDAJKMQBCLHV", 88: "ZIDJBCLHV", 210: "ZIDJKBCH",
    211: "ZIDJKBCH", 212: "ZIDJKBCH",   # H: read so that it is refused as a parameter (threads.prepare)
    160: "AXIKPQRSTUV", 161: "ABXIKYJDPQRSTUV", 162: "ABXIKYJDPQRSTUV",
    163: "XYIKCFPQRSTUV", 164: "XYBIKCFPQRSTUV", 165: "XYAICF",
}

#: The moves of one hole are computed before the first is handed on (limits included): a hole whose
#: parameters ask for more (tiny pecks or levels over a deep hole) is refused rather than held in memory.
MAX_MOVES_PER_HOLE = 100_000

FAMILIES = {81: drilling, 82: drilling, 83: drilling, 84: drilling, 85: drilling, 86: drilling,
            87: pockets, 88: pockets, 210: milling, 211: threads, 212: threads}


class CycleRunner:
    """Canned cycles G80-G88, G98/G99, G160-G165, G210-G212 for one channel."""

    def __init__(self, iso) -> None:
        self.iso = iso
        self.interp = iso.interp
        self.state = iso.state
        self.machine = iso.machine

    # ------------------------------------------------------------ words
    def cycle_code(self, words) -> tuple[int, int] | None:
        """(G number, column) of the block's canned cycle or multiple machining, if any."""
        found = None
        for w in words:
            if w.address == "G" and w.value is not None:
                try:
                    n = self.iso.ev.integer(w.value, "G", w.col, 0, 9999)
                except InterpError:
                    continue
                if n in CYCLE_CODES or n in PATTERN_CODES:
                    if found is not None and found[0] != n:
                        if found[0] in PATTERN_CODES or n in PATTERN_CODES:
                            raise InterpError("CYC008", f"G{found[0]} and G{n} cannot be in one block: the "
                                              "multiple machining stands in a block of its own", w.col)
                        raise InterpError("INT012", f"G{found[0]} and G{n} are incompatible in one block", w.col)
                    found = (n, w.col)
        return found

    def split(self, words, code: int, g_col: int):
        """The block's words without the cycle parameters, and the parameters {letter: (value, col)}."""
        letters = LETTERS[code]
        ev = self.iso.ev
        rest, params = [], {}
        last = None
        for w in words:
            addr = w.address
            if addr == "" and last is not None and last[0] in "PQRSTUV" and w.value is not None:
                # "P6.007" reads as P6 then .007: a range of points to skip (digest §2.10)
                v, c = params[last[0]]
                params[last[0]] = (v + ev.value(w.value), c)
                last = None
                continue
            if len(addr) == 1 and addr in letters:
                if w.value is None:
                    raise InterpError("INT025", f"'{addr}' needs a value", w.col)
                params_value = ev.value(w.value)
            else:
                rest.append(w)
                last = None
                continue
            if addr in params:
                raise InterpError("CYC006", f"{addr} is written twice in the G{code} block: it is a parameter "
                                  f"of G{code}, so it cannot also position an axis there; position it in the "
                                  "block before", w.col)
            params[addr] = (params_value, w.col)
            last = addr
        params["G"] = (float(code), g_col)
        return rest, params

    # ------------------------------------------------------------ which blocks
    def applies(self, gs: dict, bw) -> bool:
        """Whether the block's motion is the cycles' business."""
        st = self.state
        if bw.cycle is not None:
            return True
        cyc = st.cycles.active
        if cyc is None:
            return False
        a, o, ln = cyc.plane
        in_plane = a in bw.axes or o in bw.axes or "R" in bw.params or "Q" in bw.params
        if not in_plane:
            return False
        if ln in bw.axes and choices.LONGITUDINAL_MOVE_SKIPS_CYCLE:
            # digest §1.2 [UNVERIFIED]: a plain move, the cycle does not run at its end point
            self.interp.message("CYC010", "warning", f"this block also moves the longitudinal axis {ln}: it is "
                                f"executed as a plain move, without the G{cyc.code} cycle", bw.axes[ln][1])
            return False
        return True

    def cancel_for_plane(self) -> None:
        """A change of plane or of the tool axis cancels the cycle (digest §1.1 [UNVERIFIED])."""
        if choices.CANCEL_ON_PLANE_CHANGE:
            self.state.cycles.cancel(self.state.modes)

    # ------------------------------------------------------------ execution
    def execute(self, gs: dict, bw, src: Source):
        """Machine the block's holes; returns whether anything moved."""
        if bw.cycle is not None:
            code = int(bw.cycle["G"][0])
            if code in PATTERN_CODES:
                return (yield from patterns.run(self, code, bw, src))
            self._define(code, bw, src)
        return (yield from self._points(bw, src))

    def _define(self, code: int, bw, src: Source) -> None:
        st = self.state
        params = bw.cycle
        g_col = params["G"][1]
        self._refuse_compensation(g_col)
        a, o, _n = st.plane_axes()
        ln, _direction = st.longitudinal()
        if ln is None or ln in (a, o):
            raise InterpError("CYC004", f"the tool axis {ln} lies in the plane {a}{o}: a canned cycle needs a "
                              "longitudinal axis perpendicular to the plane", g_col)
        values = {k: v for k, (v, _c) in params.items() if k != "G"}
        cols = {k: c for k, (_v, c) in params.items()}
        cyc = ActiveCycle(code, values, cols, st.modes["distance"] == 91, st.modes["units"] == 70, (a, o, ln),
                          st.programmed_pos()[ln], (src.file, src.line, code))
        cyc.plan = FAMILIES[code].prepare(cyc, self)   # every parameter error before anything moves
        self._cancel_modal_call()   # seed 002 L10570: activating a cycle cancels a modal subroutine
        cs = st.cycles
        cs.active = cyc
        cs.params = values
        cs.called = frozenset(values)
        cs.holes.setdefault(cyc.key, 0)
        st.modes["cycle"] = code
        if code == 210 and choices.G210_PROVISIONAL:
            self.interp.message("CYC009", "warning", "G210 uses provisional cycle semantics (the 8065 cycles "
                                "manual is not available): check the path in the plot", g_col)
        if code in (211, 212) and choices.THREAD_PROVISIONAL:
            self.interp.message("CYC020", "warning", f"G{code} uses provisional thread-milling semantics (the 8065 "
                                "cycles manual is not available; J thread radius at the tooth tip, K radial depth, "
                                "B pitch, B- left-hand): check the path in the plot", g_col)

    def _cancel_modal_call(self) -> None:
        interp = self.interp
        if interp.modal_call is not None and not any(f.modal for f in interp.frames):
            interp.modal_call = None

    def _refuse_compensation(self, col: int) -> None:
        if choices.RADIUS_COMP_IS_ERROR and self.state.modes["compensation"] in (41, 42):
            raise InterpError("CYC003", f"G{self.state.modes['compensation']} radius compensation is active: "
                              "cancel it with G40 before the canned cycle", col)
        if self.state.mcs_on:   # the cycle's levels are part coordinates (seed 002 L3196-L3271)
            raise InterpError("CYC004", "a canned cycle cannot run under #MCS ON (machine coordinates): "
                              "program #MCS OFF first", col)

    def _points(self, bw, src: Source):
        """The positioning of the block (NR times) and the cycle at each point reached."""
        interp = self.interp
        repeats, nr_col = bw.nr or (1, 1)
        if bw.nr is not None:
            interp.guard_repetitions(repeats, f"NR{repeats} repeats the block", nr_col)
        col = next(iter(bw.axes.values()))[1] if bw.axes else 1
        for k in range(max(repeats, 1)):
            if k:
                interp.count_block(nr_col)
            records = self.position(bw, src, col)
            if repeats != 0:   # seed 002 L1115-L1116: NR0 moves without the cycle
                records += self.hole(src, col)
            yield from records
        return True

    def position(self, bw, src: Source, col: int) -> list:
        """The rapid in the plane to the block's point, at the current longitudinal level (§1.4 step 1)."""
        st, iso = self.state, self.iso
        cyc = st.cycles.active
        self._refuse_compensation(col)
        if {"I", "J", "K", "R", "Q"} & bw.params.keys() and st.modes["motion"] in (2, 3):
            raise InterpError("CYC012", "an arc cannot position a canned cycle's point: program the point with "
                              "G00/G01 (or use G163-G165 for points on a circle)", col)
        cur = st.programmed_pos()
        end = iso.target(bw, cur)
        if "R" in bw.params or "Q" in bw.params:
            iso._polar(bw, cur, end)
        end[cyc.plane[2]] = cur[cyc.plane[2]]
        return self.emit([("R", end)], src, col)

    def hole(self, src: Source, col: int) -> list:
        """The active cycle at the current point (§1.4 steps 2-4)."""
        st = self.state
        cyc = st.cycles.active
        self._refuse_compensation(col)
        self._cancel_modal_call()   # seed 002 L10807: executing a cycle cancels a modal subroutine
        if cyc.plan is None:   # a V.C write since the last hole
            cyc.plan = FAMILIES[cyc.code].prepare(cyc, self)
        a, o, _ln = cyc.plane
        here = st.programmed_pos()
        ops = FAMILIES[cyc.code].ops(cyc, cyc.plan, self, (here[a], here[o]))
        marks = drilling.plc_marks(cyc, cyc.plan) if cyc.code == 84 else ()
        records = self.emit(ops, src, col, marks)
        st.cycles.count()
        return records

    # ------------------------------------------------------------ helpers for the families
    def length(self, value: float, cyc: ActiveCycle | None = None) -> float:
        """A cycle length in mm (the definition's G70/G71)."""
        inch = cyc.inch if cyc is not None else self.state.modes["units"] == 70
        return value * INCH if inch else value

    def guard_moves(self, count: float, cyc: ActiveCycle, letter: str) -> None:
        """Refuse (CYC004 at ``letter``) a hole that would take more than MAX_MOVES_PER_HOLE moves."""
        if not count <= MAX_MOVES_PER_HOLE:
            raise InterpError("CYC004", f"G{cyc.code}: {letter}{cyc.get(letter, 0):g} gives about {count:.3g} moves "
                              f"for one hole, more than {MAX_MOVES_PER_HOLE}", cyc.col(letter))

    def return_level(self, cyc: ActiveCycle, zr: float) -> float:
        """G98: the starting plane; G99: the reference plane."""
        return cyc.zs if self.state.modes["cycle_return"] == 98 else zr

    def feed(self, value: float | None = None, col: int = 1) -> float:
        """A cycle feed in mm/min: F (``value`` None) or a feed letter (H, V) in F's units."""
        st, iso = self.state, self.iso
        mode = st.modes["feed"]
        if mode == 93:
            raise InterpError("CYC004", "G93 (feed as a time) cannot drive a canned cycle: use G94 or G95", col)
        if value is None:
            if not st.feed and self.machine.default("DEFAULTFEED") and self.machine.max_feed > 0:
                return self.machine.max_feed   # as a G01 without F (seed 002 L4062)
            if not st.feed:
                what = "the feed is 0 (F0)" if st.feed == 0 else "no feed programmed (F)"
                raise InterpError("INT060", f"{what} for the canned cycle", col)
            f = st.feed
        else:
            f = value * INCH if st.modes["units"] == 70 else value
        if mode == 95:
            f *= iso._spindle_rpm(st.machine_pos)
        if self.machine.max_feed > 0:
            f = min(f, self.machine.max_feed)
        return f

    def tool_radius(self) -> float:
        st = self.state
        off = st.tools.get(st.tool, {}).get(st.offset) if st.offset else None
        return (off.radius + off.radius_wear) if off is not None else 0.0

    def spindle(self) -> int:
        """3, 4 or 5: the direction of the master spindle."""
        st = self.state
        return st.spindle_state.get(st.master_spindle(), 5)

    def warn(self, code: str, message: str, col: int) -> None:
        self.interp.message(code, "warning", message, col)

    # ------------------------------------------------------------ records
    def emit(self, ops: list, src: Source, col: int, marks: tuple = ()) -> list:
        """Turn cycle operations (programmed coordinates of the plane and the longitudinal axis) into
        motion records; zero-length moves are left out (digest §0.2).

        Operations: ``("R", point)`` rapid, ``("F", point, feed)`` feed move, ``("T", point, feed)``
        tapping move (feed override locked at 100 %), ``("A", point, centre, ccw, feed)`` arc in the
        plane (helix when the longitudinal level changes), ``("D", seconds)`` dwell, ``("M", n)``
        spindle function.  ``point`` is ``{axis: value}`` for some of the channel axes.  ``marks``: the PLC
        marks on during these records (``record.plc_marks``: the moves' ``Dynamics.plc_marks``, a field of the
        dwells and spindle functions; see :func:`.drilling.plc_marks`).
        """
        st, iso, interp = self.state, self.iso, self.interp
        out: list = []
        lcomp = None
        cur = None   # the programmed position: computed once, then the end of each move
        base = None  # the dynamics of the moves without modes of their own (with the PLC marks)
        for op in ops:
            kind = op[0]
            if kind == "D":
                if op[1] > 0:
                    out.append(Dwell("dwell", op[1], dict(st.machine_pos), src, marks))
                continue
            if kind == "M":
                aux = iso.aux("M", float(op[1]), "before", src)
                out.append(replace(aux, plc_marks=marks) if marks else aux)
                for s in st.spindle_state:   # the master spindle, as an M03/M04/M05 block does
                    st.spindle_state[s] = op[1]
                    break
                continue
            if cur is None:
                cur = st.programmed_pos()
            target = {**cur, **op[1]}
            if all(abs(target[x] - cur[x]) <= 1e-9 for x in op[1]) and kind != "A":
                continue
            if lcomp is None:
                lcomp = self._length_compensation(target, cur)
            cur = target
            start = dict(st.machine_pos)
            tr = st.transform
            end_part = tr.apply(target)
            end = st.to_machine(end_part)
            interp.check_limits(end, col, start)
            st.machine_pos = dict(end)
            if kind == "R":
                if base is None:
                    base = self._marked(None, marks)
                out.append(Line("rapid", start, end, end_part, None, "G94", src, None, base))
                continue
            modes = op[-1] if type(op[-1]) is dict and len(op) > (3 if kind != "A" else 5) else None
            if kind == "T":
                modes = {"G266": True}   # tapping: feed override locked at 100 % (digest §2.4)
            if modes:
                dyn = self._marked(_dynamics(st, {**st.block_modes, **modes}), marks)
            else:
                dyn = base = base if base is not None else self._marked(None, marks)
            if kind == "A":
                out.append(self._arc(op, target, start, end, end_part, src, dyn))
            else:
                out.append(Line("linear", start, end, end_part, op[2], feed_mode(st.modes["feed"]), src, None, dyn))
        return out

    def _marked(self, dyn, marks: tuple):
        """``dyn`` (the block's dynamics when None) with the PLC marks of the moves."""
        dyn = dyn if dyn is not None else self.state.dynamics()
        return replace(dyn, plc_marks=marks) if marks else dyn

    def _length_compensation(self, target: dict, cur: dict) -> bool:
        """Tool length compensation takes effect on the first move of the longitudinal axis."""
        st = self.state
        axis, _direction = st.longitudinal()
        if axis is None or abs(target[axis] - cur[axis]) <= 1e-9:
            return False
        before = dict(st.length_offset)

        self.iso._length_compensation(_LongitudinalMove(axis))
        return st.length_offset != before

    def _arc(self, op, target: dict, start: dict, end: dict, end_part: dict, src: Source, dyn) -> Arc:
        st = self.state
        (ca, co), ccw, feed = op[2], op[3], op[4]
        a, o, n = st.plane_axes()
        tr = st.transform
        center_part = tr.apply({a: ca, o: co})
        center_m = st.to_machine(center_part)
        scale = tr.scale if a in tr.linear else 1.0
        ccw_path = ccw != tr.flips(a, o)
        radius = math.hypot(target[a] - ca, target[o] - co) * scale
        return Arc("arc", start, end, end_part, center_m, center_part, "ccw" if ccw_path else "cw", (a, o, n),
                   radius, 0, feed, feed_mode(st.modes["feed"]), src, None, dyn)


class _LongitudinalMove:
    """The words of a move of the longitudinal axis, for the tool length compensation."""

    __slots__ = ("axes",)

    def __init__(self, axis: str) -> None:
        self.axes = {axis: (0.0, 1)}
