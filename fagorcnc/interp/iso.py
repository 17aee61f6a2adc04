"""Execution of ISO blocks: G functions, axis words, F S T D M H, motion.

Order inside a block (spec 02 §8.10, seed 002 L1021 and the chapters cited):

1. values of all words are evaluated; G functions are checked against the
   G table (unknown / unsupported / two of one modal group are errors);
2. modal functions of the block take effect (units, G90/G91, plane, feed
   type ...), so the block's own coordinates use them;
3. origins: G53, then G157, then G54-G59/G159, G92, G158 (L3854, L3535);
4. F, S, T, D; H and M functions that run before the motion;
5. the motion (G00/G01/G02/G03, polar R/Q), repeated NR times; G04 dwell;
6. M functions that run after the motion (M00, M01), then end of program
   or subroutine (M02/M30, M17/M29).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from ..kinematics import tangential
from ..kinematics.statements import adjust_target
from ..path import arcs
from ..path.aids import Aid
from ..syntax.ast import Word
from . import compat, dynamics
from .cycles import CycleRunner
from .expressions import InterpError, whole
from .gtable import EXCLUSIVE_GROUPS, G_FUNCTIONS
from .records import Arc, Aux, Dwell, Line, Source
from .spindle import directions, orientation, targets
from .spindle import parse_suffix as spindle_suffix
from .state import ChannelState

INCH = 25.4
_AXIS_LETTERS = frozenset("XYZUVWABC")
#: M functions run after the motion by default (spec 02 §19: M00/M01 "after").
_M_AFTER = frozenset({0, 1, 2, 30, 17, 29})
#: letters that are parameters of G functions, not axes (chapters 8-12)
_PARAM_LETTERS = frozenset("IJKRQEL")


@dataclass
class BlockWords:
    """The evaluated words of one ISO block, sorted by role."""

    g: list = field(default_factory=list)            # (number, col, eq)
    axes: dict = field(default_factory=dict)         # axis name -> (value, col)
    params: dict = field(default_factory=dict)       # I J K R Q ... -> (value, col)
    feed: tuple | None = None
    speeds: dict = field(default_factory=dict)       # spindle -> (value, col)
    tool: tuple | None = None
    offset: tuple | None = None
    m: list = field(default_factory=list)            # (number, col)
    h: list = field(default_factory=list)
    nr: tuple | None = None
    call: tuple | None = None                        # (G number, modal, col, argument words)
    roles: list = field(default_factory=list)        # G20: (axis, type, col); an axis may repeat
    scale: tuple | None = None                       # G72 S<factor> (S after G72, L9010)
    percent: tuple | None = None                     # G131/G133 <percent> (L4437)
    m_target: dict = field(default_factory=dict)     # index in m -> (spindle, direction) of "M3.S2", "M19.POS"
    position_speeds: dict = field(default_factory=dict)   # spindle -> (rpm, col) of "S.POS=" (L5904)
    cycle: dict | None = None                        # canned cycle parameters: letter -> (value, col)
    glued: tuple | None = None                       # "T202 LM06": (name, "L", {}, col) of the call


class IsoExecutor:
    """Interprets ISO words against a :class:`ChannelState`, yielding records."""

    def __init__(self, interp) -> None:
        self.interp = interp
        self.state: ChannelState = interp.state
        self.machine = interp.machine
        self.ev = interp.evaluator
        self.cycles = CycleRunner(self)

    # ------------------------------------------------------------ words
    def classify(self, words: list[Word]) -> BlockWords:
        cycle = self.cycles.cycle_code(words)
        if cycle is not None:   # its letters are parameters, not axes, offsets or H/M functions
            words, params = self.cycles.split(words, *cycle)
            bw = self._classify(words)
            bw.cycle = params
            return bw
        return self._classify(words)

    def _classify(self, words: list[Word]) -> BlockWords:
        ev, st = self.ev, self.state
        bw = BlockWords()
        axes = st.axes
        g157 = any(w.address == "G" and w.value == 157.0 for w in words)
        g20 = any(w.address == "G" and w.value == 20.0 for w in words)
        skip = 0
        for i, w in enumerate(words):
            addr, col = w.address, w.col
            if skip and col < skip:
                continue   # the name of a glued call (T202 LM06)
            if w.value is None:
                if addr == "L" and i > 0:
                    call = compat.glued_call(self.interp, w, self.interp.block_text())
                    if call is not None:   # "T202 LM06" (LIGNOCAM): L M06 called after the block
                        bw.glued, skip = call   # (without its file: the M06 word that follows runs)
                        continue
                if not (g157 and (addr in st.machine.axes or addr[0] == "?")):
                    raise InterpError("INT025", f"'{addr}' needs a value", col)
                w = w._replace(value=1.0)  # G157 X: exclude X (L3851-L3852)
            if addr == "G" or addr == "MG":
                n = ev.integer(w.value, addr, col, 0, 9999)
                if n == 51 and compat.g51_block(self.interp, words):
                    return BlockWords()   # "G51 A45 E0.002": executed as nothing (compat.g51)
                if (180 <= n <= 189 or 380 <= n <= 399 or 500 <= n <= 599) or addr == "MG":
                    bw.call = (n, addr == "MG", col, tuple(words[i + 1:]))
                    return bw  # every word after the call is an argument (L10712-L10719)
                eq = ev.value(w.eq) if w.eq is not None else None
                bw.g.append((n, col, eq))
                if n >= 10:
                    compat.leading_zero(self.interp, n, col, self.interp.block_text())   # "G011" is G11
            elif addr == "N":
                st.last_n = ev.integer(w.value, "N", col)
            elif addr == "" and bw.percent is None and any(n in (131, 133) for n, _c, _e in bw.g):
                bw.percent = (ev.value(w.value), col)   # seed 002 L4437: G131 100 X50 Y80
            elif addr == "":
                if "K" in bw.params or not any(n == 4 for n, _c, _e in bw.g):
                    raise InterpError("INT025", "a number without its letter is only allowed as the time "
                                      "of G04 (G04 5)", col)
                bw.params["K"] = (ev.value(w.value), col)   # seed 002 L9187: G04 5
            elif addr == "F":
                bw.feed = (ev.value(w.value), col)
            elif addr == "S" and any(g[0] == 72 for g in bw.g):
                bw.scale = (ev.value(w.value), col)   # an S after G72 is the scale factor (L9010)
            elif addr == "S" or (addr[0] == "S" and addr[1:].isdigit()):
                spindle = addr if addr in st.speeds else None
                if spindle is None:
                    if addr != "S" or not st.speeds:
                        raise InterpError("INT020", f"spindle {addr} does not exist on this machine", col)
                    spindle = next(iter(st.speeds))
                bw.speeds[spindle] = (ev.value(w.value), col)
            elif addr == "T":
                bw.tool = (ev.integer(w.value, "T", col, 0, 4294967294, floor=True), col)
            elif addr == "D":
                bw.offset = (ev.integer(w.value, "D", col), col)
            elif addr == "M" or addr[:2] == "M.":
                if len(bw.m) == 7:  # spec 02 §19: up to 7 M per block
                    raise InterpError("INT021", "more than 7 M functions in one block", col)
                m = ev.integer(w.value, "M", col, 0, 65535, floor=True)
                if addr != "M":   # M3.S2, M19.POS.S1 (seed 002 L5720-L5760, L5843-L5880)
                    if m != 19 and (".POS" in addr or ".NEG" in addr):
                        raise InterpError("INT025", f"M{m}{addr[1:]}: only M19 takes a direction .POS/.NEG (L5843)",
                                          col)
                    if m not in (3, 4, 5, 19, 41, 42, 43, 44):
                        raise InterpError("INT025", f"M{m}{addr[1:]}: a spindle suffix goes with M3, M4, M5, M19 "
                                          "and M41-M44 (L5950)", col)
                    bw.m_target[len(bw.m)] = spindle_suffix(addr, st.speeds, col)
                bw.m.append((m, col))
            elif addr[0] == "S" and addr.endswith(".POS"):   # S.POS=120, S1.POS=50 (L5904-L5934)
                name = addr[:-4]
                spindle = name if name in st.speeds else (next(iter(st.speeds)) if name == "S" and st.speeds
                                                            else None)
                if spindle is None:
                    raise InterpError("INT020", f"spindle {name} does not exist on this machine", col)
                speed = ev.value(w.value)
                if speed <= 0:
                    raise InterpError("INT027", f"M19 positioning speed {speed:g} must be positive (L5904)", col)
                bw.position_speeds[spindle] = (speed, col)
            elif addr == "H":
                if len(bw.h) == 7:
                    raise InterpError("INT021", "more than 7 H functions in one block", col)
                bw.h.append((ev.integer(w.value, "H", col, 0, 65535, floor=True), col))
            elif addr == "NR":
                bw.nr = (ev.integer(w.value, "NR", col), col)
            elif addr[0] == "?":
                k = int(addr[1:])
                if not 1 <= k <= len(axes):  # seed 002 L1211: ?n on a hole or beyond the channel
                    raise InterpError("INT022", f"generic axis {addr} does not designate an axis", col)
                self._axis_word(bw, axes[k - 1], ev.value(w.value), col)
            elif addr in st.machine.axes:
                if g20:
                    bw.roles.append((addr, ev.value(w.value), col))
                    continue
                self._axis_word(bw, addr, ev.value(w.value), col)
            elif addr == "R1":   # modal arc radius R1= (seed 002 L6418)
                bw.params["R1"] = (ev.value(w.value), col)
            elif addr in _PARAM_LETTERS or (len(addr) == 1 and addr not in _AXIS_LETTERS):
                if addr in bw.params:
                    raise InterpError("INT023", f"{addr} is written twice in the block", col)
                bw.params[addr] = (ev.value(w.value), col)
            elif addr[0] in _AXIS_LETTERS:
                self._unknown_g(words)   # "G51 A45 E0.002" (another CNC's smoothing): the G is the mistake
                raise InterpError("INT024", f"axis {addr} does not exist on this machine", col)
            else:
                raise InterpError("INT025", f"'{addr}' is not meaningful here", col)
        return bw

    @staticmethod
    def _axis_word(bw: BlockWords, axis: str, value: float, col: int) -> None:
        if axis in bw.axes:
            raise InterpError("INT023", f"axis {axis} is written twice in the block", col)
        bw.axes[axis] = (value, col)

    def _unknown_g(self, words: list[Word]) -> None:
        """Raise INT010 for a G function of the block that the 8060/8065 does not have, if any: its
        other words may be meaningless only because of it."""
        for w in words:
            if w.address == "G" and w.value is not None:
                try:
                    n = self.ev.integer(w.value, "G", w.col, 0, 9999)
                except InterpError:
                    continue
                if n not in G_FUNCTIONS:
                    raise InterpError("INT010", f"G{n} is not a G function of the 8060/8065", w.col)

    def check_g(self, bw: BlockWords) -> None:
        seen: dict[str, int] = {}
        for n, col, _eq in bw.g:
            g = G_FUNCTIONS.get(n)
            if g is None:
                raise InterpError("INT010", f"G{n} is not a G function of the 8060/8065", col)
            if g.support == "no":
                raise InterpError("INT011", f"G{n} ({g.meaning}) is not supported by fagorcnc yet", col)
            if g.group in EXCLUSIVE_GROUPS:
                if g.group in seen and seen[g.group] != n:
                    raise InterpError("INT012", f"G{seen[g.group]} and G{n} are incompatible in one block", col)
                seen[g.group] = n

    # ------------------------------------------------------------ units
    def plane(self, what: str, col: int) -> tuple[str, str, str | None]:
        """(abscissa, ordinate, longitudinal) of the active plane, for ``what`` (an arc, a polar move,
        G41...) that needs both plane axes; INT150 when the machine lacks one: a lathe (X Z) in G17, a
        rotary-only machine.  The planes are made of the first three channel axes (seed 002 L2961-L2966)."""
        st = self.state
        a, o, n = st.plane_axes()
        if a is None or o is None:
            plane = st.modes["plane"]
            raise InterpError("INT150", f"{what} needs the two axes of the plane G{plane}, made of the first three "
                              f"axes of the channel, and this machine has only {' '.join(st.axes)} (seed 002 L2961)",
                              col)
        return a, o, n

    def length(self, value: float, axis: str | None = None, diameter_ok: bool = True) -> float:
        """A programmed length in mm (G70 inch, G151 diameter axes)."""
        st = self.state
        if axis is not None and st.machine.axes[axis].rotary and axis not in st.kin.as_linear:
            return value   # (a rotary axis of #FACE/#CYL is programmed as a length)
        if st.modes["units"] == 70:
            value *= INCH
        if diameter_ok and axis is not None and st.modes["diameter"] == 151 and st.machine.axes[axis].diameter:
            value /= 2.0
        return value

    def target(self, bw: BlockWords, current_part: dict[str, float]) -> dict[str, float]:
        """Part coordinates of the programmed end point (cartesian words)."""
        st = self.state
        incremental = st.modes["distance"] == 91
        out = dict(current_part)
        for axis, (v, col) in bw.axes.items():
            ax = st.machine.axes[axis]
            if ax.rotary and ax.rotary_mode != "linearlike" and axis not in st.kin.as_linear:
                out[axis] = self._rotary(ax, current_part[axis], v, incremental, col)
            elif incremental:
                out[axis] = current_part[axis] + self.length(v, axis)
            else:
                out[axis] = self.length(v, axis)
        kin = st.kin
        if kin.pending_ori or kin.angax or kin.tangential or kin.c_axes:   # #TOOL ORI, #ANGAX SUSP, G45, #CAX
            adjust_target(self.interp, bw, out)
        return out

    @staticmethod
    def _rotary(ax, cur: float, v: float, incremental: bool, col: int) -> float:
        """Rotary axis end position (spec 02 §3, seed 002 L2505-L2585); unrolled position."""
        m = ax.module
        if incremental:
            if ax.rotary_mode == "unidirectional" and v * ax.direction < 0:
                raise InterpError("INT026", f"{ax.name} only turns in one direction", col)
            return cur + v
        here = cur % m
        target = abs(v) % m
        if ax.rotary_mode == "normal":
            direction = 1 if math.copysign(1.0, v) > 0 else -1
        elif ax.rotary_mode == "unidirectional":
            direction = ax.direction
        else:  # positioning: shortest way, tie -> positive
            d = (target - here) % m
            return cur + (d if d <= m / 2 else d - m)
        d = (target - here) % m if direction > 0 else -((here - target) % m)
        return cur + d

    # ------------------------------------------------------------ execution
    def execute(self, bw: BlockWords, src: Source):
        """Interpret the classified words; yields records in execution order."""
        st, interp = self.state, self.interp
        self.check_g(bw)
        gs = {n: (col, eq) for n, col, eq in bw.g}
        # 2. modal functions take effect for this block
        previous_plane = st.modes["plane"]
        block_modes = {}
        for n, (_col, _eq) in gs.items():
            g = G_FUNCTIONS[n]
            if g.group is not None and g.group != "origin":
                st.modes[g.group] = n
                if g.group == "corner":
                    st.hsc = None          # L13659: G05/G07/G50 cancel HSC
                    st.dynamics_changed()
                elif g.group == "feed_point":
                    st.dynamics_changed()  # G196/G197: where F is measured (see path/compensation.py)
            elif g.reset == "block" and g.support == "recorded":
                block_modes[f"G{n}"] = True
        if 130 in gs or 131 in gs or 132 in gs or 133 in gs or 134 in gs or 135 in gs:
            per_axis = 130 in gs or 132 in gs or 134 in gs or 135 in gs
            words = {**bw.axes, **bw.speeds} if per_axis else bw.axes
            dynamics.percentages(self.interp, gs, words, bw.percent)
            if per_axis:   # their axis and spindle words are percentages, not targets (L4385, L4396)
                bw.axes.clear()
                bw.speeds.clear()
        corner = [n for n in (5, 7, 50, 60, 61) if n in gs]
        if len(corner) > 1:
            # L8016, L8057, L8105: G05, G07, G50, G60 and G61 are incompatible with each other
            raise InterpError("INT113", f"G{corner[0]:02d} and G{corner[1]:02d} cannot be in the same block "
                              "(L8016)", gs[corner[1]][0])
        if 192 in gs:  # spindle speed limit for G96 (seed 002 L5368-L5405): "G192 S<rpm>"
            if not bw.speeds:
                raise InterpError("INT027", "G192 needs the speed limit: G192 S<rpm>", gs[192][0])
            self.state.planner["G192"] = next(iter(bw.speeds.values()))[0]
            bw.speeds.clear()
        st.block_modes = block_modes
        if 193 in gs and st.slope[0] != 0:
            # seed 002 L4246-L4250: G193 needs linear acceleration (SLOPETYPE / #SLOPE type 0)
            raise InterpError("INT114", "G193 (feed interpolated over the block) needs linear acceleration: "
                              "#SLOPE [0] or SLOPETYPE 0 (L4246)", gs[193][0])
        if st.modes["plane"] != previous_plane:
            st.polar_origin = (0.0, 0.0)  # plane change -> polar origin at work zero (L2682)
            st.transform.angle = 0.0      # ... and cancels the rotation (L8946)
            st.tool_axis = None           # each plane brings its perpendicular tool axis (L10074)
            interp.plane_changed()
            self.cycles.cancel_for_plane()
        self._transformations(gs, bw)
        if 20 in gs:
            self._g20(gs[20][0], bw)
            st.polar_origin = (0.0, 0.0)
            interp.plane_changed()
            self.cycles.cancel_for_plane()
        # 3. origins
        self._origins(gs, bw)
        consumed = self._axis_functions(gs, bw)
        # 4. technology
        if bw.feed is not None:
            self._feed(*bw.feed)
        modes, master = self.interp.spindle_modes, self._master()
        for spindle, (v, _col) in bw.position_speeds.items():
            modes.position_speed[spindle] = v
        orient = orientation(bw, master) if any(m == 19 for m, _ in bw.m) else {}
        for spindle, angle in orient.items():
            # seed 002 L5703-L5713: with M19, S is the angular position (degrees, absolute, taken modulo
            # 360), not a speed: the speed kept for M03/M04 does not change; no S is 0 degrees
            yield self.aux("SPOS", angle, "before", src, spindle)
        directions(bw, modes, master)
        for spindle, (v, col) in bw.speeds.items():
            if spindle in orient:
                continue
            if v < 0:
                raise InterpError("INT027", f"spindle speed {v:g} is negative", col)
            st.kin.speed_check(spindle, col)   # not for a spindle working as C axis (#CAX, L11601)
            st.speeds[spindle] = v
            if spindle in modes.positioning:   # L5705: kept as the speed of the M03/M04 that ends positioning
                modes.new_speed.add(spindle)
                continue
            yield self.aux("S", v, "before", src, spindle)
        if bw.tool is not None:
            yield from self._tool(bw, src)
        if bw.offset is not None and not any(m == 6 for m, _ in bw.m):
            if bw.tool is not None:   # "T7 D2" then "M06": D2 is the offset of T7 once loaded (seed 002 L4946-L4962)
                self._next_offset(*bw.offset)
            else:
                self._offset(*bw.offset)
                yield self.aux("D", float(st.offset), "before", src)
        for h, _col in bw.h:
            yield self.aux("H", float(h), "before", src)
        after = []
        table = self.machine.m_functions
        for k, (m, col) in enumerate(bw.m):
            if m in (2, 30, 17, 29) or table.get(m, "after" if m in _M_AFTER else "before") == "after":
                after.append((m, col))
                continue
            yield from self._m_before(m, col, bw, src, k)
        if 45 in gs or 145 in gs:   # tangential control (seed 002 ch. 16): its axis words are angles
            (tangential.g45 if 45 in gs else tangential.g145)(self.interp, bw, gs[45 if 45 in gs else 145][0])
        # 5. motion
        moved = False
        if 4 in gs:
            yield self._dwell(gs[4][0], bw, src)
            consumed = True
        if 30 in gs:
            self._polar_preset(gs[30][0], bw)
            consumed = True
        if 200 in gs or 201 in gs or 202 in gs:   # manual intervention (seed 002 ch. 8.9)
            yield from self.interp.manual.g_functions(self.interp, gs, src)
        elif self.interp.axis_sentence is not None:
            raise InterpError("INT171", "#AXIS goes with G200, G201 or G202: G201 #AXIS [X, Z] (L7743)",
                              self.interp.axis_sentence.col)
        if 74 in gs:
            yield from self._home(gs[74][0], bw, src)
            consumed = True
        if 80 in gs:
            self.interp.modal_call = None   # seed 002 L10798: G80 cancels the modal subroutine
            st.cycles.cancel(st.modes)      # ... and the canned cycle (L1449)
        aids = [n for n in (36, 37, 38, 39) if n in gs]
        if aids:
            yield self._aid(aids, gs, bw, src)
            consumed = True
        if not consumed and self.cycles.applies(gs, bw):   # canned cycle: definition, G160-G165, influence zone
            moved = yield from self.cycles.execute(gs, bw, src)
        elif not consumed:
            repeats, nr_col = bw.nr or (1, 1)
            if bw.nr is not None:
                if not (bw.axes or "R" in bw.params or "Q" in bw.params):
                    raise InterpError("INT028", "NR repeats a motion: the block has none", nr_col)
                # seed 002 L1109-L1111: NR = how many times the block is executed (no upper bound given)
                interp.guard_repetitions(repeats, f"NR{repeats} repeats the block", nr_col)
            for k in range(max(repeats, 1)):
                if k:  # every repetition counts as an executed block (runaway guards)
                    interp.count_block(nr_col)
                rec = self._motion(gs, bw, src)
                if rec is not None:
                    moved = True
                    if rec.kind != "rapid" and rec.feed_mode != "G95":
                        compat.spindle_lint(self.interp, rec, 1)
                    yield rec
                    if bw.nr is None or bw.nr[0] != 0:
                        yield from interp.after_motion(src)
        elif bw.nr is not None:
            raise InterpError("INT028", "NR repeats a motion: the block has none", bw.nr[1])
        if not moved and 74 not in gs:
            if 61 in gs:
                compat.lone_g61(self.interp, gs[61][0])   # the posts' closing "G61" (compat.lone_g61)
                del gs[61]
            for n, what in ((60, "G60 (square corner for this block)"), (61, "G61 (rounded corner for this block)"),
                            (266, "G266 (override at 100 % for this block)")):
                if n in gs:   # L8008, L8090, L4374: only in a block that moves
                    raise InterpError("INT113", f"{what} needs a move in its block", gs[n][0])
        # 6. after the motion
        for m, col in after:
            yield from self._m_after(m, col, src)
        return moved

    # ------------------------------------------------------------ origins and axis functions
    def _origins(self, gs: dict, bw: BlockWords) -> None:
        st = self.state
        if st.mcs_on and any(n in gs for n in (92, 54, 55, 56, 57, 58, 59, 159, 158, 30)):
            raise InterpError("INT013", "origins cannot be changed while #MCS ON is active (L3225)", 1)
        if 53 in gs:
            st.cancel_origin()
        if 157 in gs:  # applied before the offset it qualifies, whatever the order (L3854)
            for axis, (v, col) in list(bw.axes.items()):
                if v not in (0.0, 1.0):
                    raise InterpError("INT014", f"G157 {axis}{v:g}: write 1 to exclude or 0 to include", col)
                if v == 1.0:
                    st.excluded.add(axis)
                else:
                    st.excluded.discard(axis)
        for n in range(54, 60):
            if n in gs:
                st.select_origin(n - 53, f"G{n}")
                compat.origin_lint(self.interp, f"G{n}", gs[n][0])
        if 159 in gs:
            col, eq = gs[159]
            n = whole(eq) if eq is not None else None
            if n is None or not 1 <= n <= 99:
                raise InterpError("INT015", "G159 needs an entry number 1..99: G159=n", col)
            st.select_origin(n, f"G159={n}")
            compat.origin_lint(self.interp, f"G159={n}", col)

    def _axis_functions(self, gs: dict, bw: BlockWords) -> bool:
        """G92, G158, G157, G174, G198, G199: their axis words are not a motion."""
        st = self.state
        if 157 in gs:
            return True
        if 92 in gs:
            st.preset({a: self.length(v, a) for a, (v, _c) in bw.axes.items()})
            return True
        if 158 in gs:
            if not bw.axes:
                for a in st.axes:
                    st.inc_offset[a] = 0.0
            for a, (v, _c) in bw.axes.items():
                st.inc_offset[a] = self.length(v, a)   # replaces, not cumulative (L3761)
            return True
        if 174 in gs:
            if len(bw.axes) != 1:
                raise InterpError("INT016", "G174 sets one axis at a time (L3285)", gs[174][0])
            ((a, (v, col)),) = bw.axes.items()
            value = v * INCH if self.machine.default("INCHES") and not self.machine.axes[a].rotary else v
            self.interp.check_limits({a: value}, col)   # L3303-L3305: must be inside the limits
            st.machine_pos = {**st.machine_pos, a: value}   # records keep their own positions
            return True
        if 198 in gs or 199 in gs:
            self._soft_limits(gs, bw)
            return True
        return False

    def _soft_limits(self, gs: dict, bw: BlockWords) -> None:
        """G198/G199 (seed 002 L9201-L9240): machine coordinates, G91 relative to the active
        limit, always radii; both limits 0 cancel the axis' limits (machine ones too)."""
        st = self.state
        incremental = st.modes["distance"] == 91
        for n, store in ((198, st.lower_limits), (199, st.upper_limits)):
            if n not in gs:
                continue
            for a, (v, _c) in bw.axes.items():
                value = self.length(v, a, diameter_ok=False)
                store[a] = store[a] + value if incremental and math.isfinite(store[a]) else value
        for a in bw.axes:
            if st.lower_limits[a] == 0.0 and st.upper_limits[a] == 0.0:
                st.lower_limits[a], st.upper_limits[a] = -math.inf, math.inf

    def _length_compensation(self, bw: BlockWords) -> None:
        """Tool length compensation on the longitudinal axis (seed 002 L10072-L10171).

        Active while an offset D (not 0) is selected: the controlled point is the
        tool base, ``length + length wear`` away from the tip against the tool's
        orientation.  It takes effect on the next move of the longitudinal axis.
        """
        st = self.state
        axis, direction = st.longitudinal()
        if axis is None or axis not in bw.axes:
            return
        off = self._tool_offset("length compensation")
        length = (off.length + off.length_wear) if off is not None else 0.0
        st.length_offset = {axis: -direction * length} if length else {}

    def _transformations(self, gs: dict, bw: BlockWords) -> None:
        """G10-G14 mirror, G72 scale, G73 rotation (seed 002 L8705-L9141)."""
        st = self.state
        tr = st.transform
        mirror = [n for n in (10, 11, 12, 13, 14) if n in gs]
        if (10 in mirror or 14 in mirror) and len(mirror) > 1:
            raise InterpError("INT012", "G10 and G14 are incompatible with G11, G12, G13 and each other "
                              "in one block (L8779)", gs[mirror[1]][0])
        if 10 in gs:
            tr.mirror = set()
        for n, axis in ((11, 0), (12, 1), (13, 2)):
            if n in gs and axis < len(st.axes):
                tr.mirror = tr.mirror | {st.axes[axis]}
        if 14 in gs:
            for axis, (v, c) in list(bw.axes.items()):
                if v not in (-1.0, 1.0):
                    raise InterpError("INT014", f"G14 {axis}{v:g}: write -1 to mirror the axis, 1 to cancel", c)
                tr.mirror = tr.mirror | {axis} if v < 0 else tr.mirror - {axis}
            bw.axes.clear()
        if 72 in gs:
            if st.mcs_on:
                raise InterpError("INT013", "the scale cannot be changed while #MCS ON is active (L9030)", gs[72][0])
            factor = bw.scale[0] if bw.scale is not None else 1.0
            self.set_scale(factor, gs[72][0])
        if 73 in gs:
            self._rotation(gs[73][0], bw)

    def set_scale(self, factor: float, col: int) -> None:
        """G72 S / #SCALE: 0 or 1 cancels (seed 002 L8989-L9027)."""
        if factor < 0:
            raise InterpError("INT070", f"scale factor {factor:g} must not be negative", col)
        self.state.transform.scale = 1.0 if factor in (0.0, 1.0) else factor

    def _rotation(self, col: int, bw: BlockWords) -> None:
        """G73 Q [I J]: incremental rotation of the coordinate system (seed 002 L8906-L8980)."""
        st = self.state
        tr = st.transform
        a, o, _ = self.plane("G73 (rotation)", col) if "Q" in bw.params else st.plane_axes()
        p = bw.params
        if bw.axes:
            raise InterpError("INT025", "G73 takes only Q and the centre I J in its block", col)
        if "Q" not in p:
            if "I" in p or "J" in p:
                raise InterpError("INT025", "G73 I J needs the angle Q", col)
            tr.angle, tr.centre = 0.0, (0.0, 0.0)   # G73 alone cancels the rotation
            return
        if ("I" in p) != ("J" in p):
            raise InterpError("INT018", "G73 needs both I and J, or neither", col)
        tr.angle += p.pop("Q")[0]
        tr.plane = (a, o)
        if "I" in p:
            tr.centre = (self.length(p.pop("I")[0], a), self.length(p.pop("J")[0], o))
        else:
            tr.centre = (0.0, 0.0)

    def _g20(self, col: int, bw: BlockWords) -> None:
        """G20: plane from the trihedron axes (seed 002 L3048-L3125).

        Each axis word gives a role: 1 abscissa, 2 ordinate, +3/-3 longitudinal
        axis (sign = tool orientation), 5 perpendicular axis when the
        longitudinal axis is also the abscissa or the ordinate.
        """
        st = self.state
        trihedron = st.axes[:3]
        roles: dict[int, str] = {}
        direction = -1
        for axis, v, c in bw.roles:
            if axis not in trihedron:
                raise InterpError("INT066", f"G20: {axis} is not one of the first three channel axes", c)
            kind = abs(v)
            if whole(v) is None or kind not in (1, 2, 3, 5):
                raise InterpError("INT066", f"G20 {axis}{v:g}: the type must be 1, 2, +3, -3 or 5", c)
            if kind in roles:
                raise InterpError("INT066", f"G20: two axes of type {kind:g}", c)
            roles[int(kind)] = axis
            if kind == 3:
                direction = 1 if v > 0 else -1
        if 1 not in roles or 2 not in roles or roles[1] == roles[2]:
            raise InterpError("INT066", "G20 needs an abscissa (type 1) and a different ordinate (type 2)", col)
        longitudinal = roles.get(3) or next(a for a in trihedron if a not in (roles[1], roles[2]))
        if longitudinal in (roles[1], roles[2]) and 5 not in roles:
            raise InterpError("INT066", "G20: the tool axis is in the plane, so the perpendicular axis (type 5) "
                              "is needed", col)
        st.g20_plane = (roles[1], roles[2], longitudinal)
        st.tool_direction = direction

    # ------------------------------------------------------------ F S T D M
    def _feed(self, value: float, col: int) -> None:
        st = self.state
        if value < 0 or (value == 0 and st.modes["feed"] == 93):
            raise InterpError("INT029", f"feed F{value:g} must be positive", col)
        st.feed_programmed = value
        if st.modes["feed"] == 93:
            st.feed = value
        else:
            st.feed = value * INCH if st.modes["units"] == 70 else value

    def _tool(self, bw: BlockWords, src: Source):
        st = self.state
        t, col = bw.tool
        if t != 0 and t not in st.tools:
            raise InterpError("INT050", f"tool T{t} is not in the tool table", col)
        st.next_tool = t
        yield self.aux("T", float(t), "before", src)

    def _next_offset(self, d: int, col: int) -> None:
        st = self.state
        if d != 0 and st.next_tool != 0 and st.tools.get(st.next_tool, {}).get(d) is None:
            raise InterpError("INT051", f"tool T{st.next_tool} has no offset D{d}", col)
        st.next_offset = d

    def _offset(self, d: int, col: int) -> None:
        st = self.state
        if d != 0 and st.tool != 0 and st.tools.get(st.tool, {}).get(d) is None:
            raise InterpError("INT051", f"tool T{st.tool} has no offset D{d}", col)
        st.offset = d

    def _master(self) -> str | None:
        """The master spindle: the channel's first (seed 002 L5100)."""
        return next(iter(self.state.spindle_state), None)

    def _m_before(self, m: int, col: int, bw: BlockWords, src: Source, index: int = 0):
        st = self.state
        named = bw.m_target.get(index, (None, None))[0] if bw.m else None
        if m in (3, 4, 5, 19):
            modes = self.interp.spindle_modes
            for s in targets(bw, index, self._master()) if bw.m else []:
                if m == 19:
                    modes.positioning.add(s)   # L5697: positioning mode until M03/M04
                elif s in modes.positioning:
                    modes.positioning.discard(s)
                    if m != 5 and s in modes.new_speed:   # the speed programmed meanwhile applies (L5705-L5707)
                        yield self.aux("S", st.speeds[s], "before", src, s)
                    modes.new_speed.discard(s)
                st.spindle_state[s] = m
                if m != 19:
                    st.kin.spindle_order(s)   # a spindle working as C axis is a spindle again (L11617)
        yield self.aux("M", float(m), "before", src, named)
        if m == 6:  # tool change: the preselected tool goes to the spindle (L4700-L4708)
            st.tool = st.next_tool
            # the D of this block, or the one programmed with T, or D1 (L4942, L4964-L4966)
            d = bw.offset[0] if bw.offset is not None else st.next_offset if st.next_offset is not None \
                else (1 if st.tool else 0)
            st.next_offset = None
            self._offset(d, bw.offset[1] if bw.offset else col)
            yield self.aux("D", float(st.offset), "before", src)

    def _m_after(self, m: int, col: int, src: Source):
        yield self.aux("M", float(m), "after", src)
        if m in (2, 30):
            self.state.parts += 1   # V.G.PARTC (seed 002 L43175)
            self.interp.end_program(m, src)
        elif m in (17, 29):
            self.interp.return_from_subroutine(col)

    def aux(self, function: str, value: float, timing: str, src: Source, spindle: str | None = None) -> Aux:
        return Aux("aux", function, value, timing, dict(self.state.machine_pos), src, spindle)

    # ------------------------------------------------------------ dwell, polar origin
    def _dwell(self, col: int, bw: BlockWords, src: Source) -> Dwell:
        # seed 002 L9174-L9190: G04 K<seconds> (or G04 <value>, G04 K[expr])
        if "K" in bw.params:
            t = bw.params.pop("K")[0]
        else:
            raise InterpError("INT017", "G04 needs the time: G04 K<seconds>", col)
        if t < 0:
            raise InterpError("INT017", f"dwell time {t:g} is negative", col)
        return Dwell("dwell", t, dict(self.state.machine_pos), src)

    def _aid(self, aids: list, gs: dict, bw: BlockWords, src: Source):
        """G36/G37/G38/G39 [I<size>] [F]: a marker for the corner-aid stage (seed 002 L8393-L8703).

        I is one register shared by the four functions (spec 04 §7); the aid
        stands in a block of its own between the two moves it joins.
        """
        st = self.state
        col = gs[aids[0]][0]
        if len(aids) > 1:
            raise InterpError("INT012", f"G{aids[0]} and G{aids[1]} in one block", gs[aids[1]][0])
        if bw.axes or {"R", "Q"} & bw.params.keys():
            raise InterpError("INT025", f"G{aids[0]} stands in a block of its own, between the two moves", col)
        if "I" in bw.params:
            st.aid_size = self.length(bw.params.pop("I")[0])
        if st.aid_size is None:
            raise InterpError("INT017", f"G{aids[0]} needs its size I (no earlier G36-G39 gave one)", col)
        kind = {36: "round", 37: "entry", 38: "exit", 39: "chamfer"}[aids[0]]
        feed = st.feed if bw.feed is not None and st.modes["feed"] == 94 else None
        a, o, _ = self.plane(f"G{aids[0]}", col)
        return Aid("aid", kind, st.aid_size * st.transform.scale, feed, (a, o), src)

    def _home(self, col: int, bw: BlockWords, src: Source):
        """G74: home search (seed 002 L2357-L2406).

        Each axis word gives the axis' order number; the groups run in
        increasing order, the axes of one group together (one rapid move per
        group to the reference point of the machine configuration).  Origins
        are kept (L2351).  G74 cancels G02/G03 (L6333).  A spindle word
        (``S1``) is accepted: the spindle is referenced with the first group.
        """
        st = self.state
        bw.speeds.clear()
        if not bw.axes:
            raise InterpError("INT067", "G74 needs the axes to reference with their order: G74 X1 Y2", col)
        st.kin.check_home(bw.axes, col)
        groups: dict[int, list[str]] = {}
        for axis, (v, c) in bw.axes.items():
            if whole(v) is None or v < 1:
                raise InterpError("INT067", f"G74 {axis}{v:g}: the order must be a whole number 1, 2, ...", c)
            groups.setdefault(int(v), []).append(axis)
        bw.axes.clear()
        for order in sorted(groups):
            start = dict(st.machine_pos)
            end = dict(start)
            for axis in groups[order]:
                end[axis] = self.machine.axes[axis].home
            st.machine_pos = dict(end)
            yield Line("rapid", start, end, st.to_part(end), None, "G94", src, dyn=st.dynamics())
        if st.modes["motion"] in (2, 3):
            st.modes["motion"] = 1 if self.machine.default("IMOVE") else 0

    def _polar_preset(self, col: int, bw: BlockWords) -> None:
        """G30 [I J]: polar origin (seed 002 L3945-L3967)."""
        st = self.state
        a, o, _ = self.plane("G30 (polar origin)", col)
        has_i, has_j = "I" in bw.params, "J" in bw.params
        others = [g for g, *_ in bw.g if g != 30] + list(bw.axes) + [k for k in bw.params if k not in "IJ"]
        if others or bw.feed or bw.speeds or bw.tool or bw.offset or bw.m or bw.h or bw.nr:
            # seed 002 L3953: "the polar origin preset must be programmed alone in the block"
            raise InterpError("INT118", "G30 must be alone in its block: G30 or G30 I.. J.. (L3953)", col)
        if has_i != has_j:
            raise InterpError("INT018", "G30 needs both I and J, or neither (L3960)", col)
        if has_i:
            st.polar_origin = (self.length(bw.params["I"][0], a), self.length(bw.params["J"][0], o))
        else:
            part = st.programmed_pos()
            st.polar_origin = (part[a], part[o])

    # ------------------------------------------------------------ motion
    def _motion(self, gs: dict, bw: BlockWords, src: Source):
        st = self.state
        mode = 8 if 8 in gs else 9 if 9 in gs else st.modes["motion"]   # G08/G09 act in their block only
        a, o, _ = st.plane_axes()
        if "R1" in bw.params or 263 in gs:  # modal arc radius (seed 002 L6533-L6566)
            r = bw.params.pop("R1")[0] if "R1" in bw.params else gs[263][1]
            if r is None or r == 0:
                raise InterpError("INT064", "the arc radius R1= / G263= must not be 0", 1)
            st.arc_radius = self.length(r)
            if a not in bw.axes and o not in bw.axes:
                return None   # "G02 G263=50" only stores the radius
        if not bw.axes and not ({"R", "Q"} & bw.params.keys()) and mode not in (2, 3):
            return None
        if not bw.axes and mode in (2, 3) and not ({"I", "J", "K", "R", "Q"} & bw.params.keys()):
            return None
        if st.mcs_on or self.interp.mcs_block:
            return self._mcs_move(gs, bw, src)
        cur_part = st.programmed_pos()   # computations are in programmed coordinates
        start = dict(st.machine_pos)
        if mode in (8, 9) or (mode in (2, 3) and not self._null_move(bw, cur_part)):
            return self._arc(mode, gs, bw, src, cur_part, start)
        end_part = self.target(bw, cur_part)
        if "R" in bw.params or "Q" in bw.params:
            self._polar(bw, cur_part, end_part)
            st.arc_radius = None   # a polar move clears the stored arc radius (L6533)
        self._length_compensation(bw)
        end_prog = end_part
        end_part = st.transform.apply(end_prog)
        end = st.to_machine(end_part)
        self.interp.check_limits(end, next(iter(bw.axes.values()))[1] if bw.axes else 1, start)
        st.machine_pos = dict(end)
        if a is not None and o is not None:   # a lathe in G17 or a rotary-only machine has no plane to track
            st.tangent = arcs.end_tangent((cur_part[a], cur_part[o]), (end_prog[a], end_prog[o]), None, True) \
                or st.tangent
        comp = self._compensation()
        if mode == 0:
            return Line("rapid", start, end, end_part, None, "G94", src, comp, st.dynamics(), joins=self._joins(comp))
        length = math.sqrt(sum((end[a] - start[a]) ** 2 for a in end))
        return Line("linear", start, end, end_part, self._active_feed(length, start), f"G{st.modes['feed']}", src,
                    comp, st.dynamics(), joins=self._joins(comp))

    def _null_move(self, bw: BlockWords, cur_part: dict) -> bool:
        """A G02/G03 block with no centre, radius or polar word whose target is where the tool stands:
        no arc, a null move (seed 002 L9996-L10009: "G91 G40 Y0" after a G03 cancels the
        compensation where the tool stands); mode 0 or 1 handles it as such."""
        if {"I", "J", "K", "R", "Q"} & bw.params.keys():
            return False
        end_part = self.target(bw, cur_part)
        return all(end_part[x] == cur_part[x] for x in end_part)

    def _compensation(self) -> tuple | None:
        """Radius compensation of a move: (side, R, G136/G137, G138/G139, plane) or None (seed 002 L9427).

        R is the radius plus its wear of the active offset D; an odd number of
        mirrored plane axes swaps G41 and G42 (L8774).
        """
        st = self.state
        mode = st.modes["compensation"]
        if mode not in (41, 42):
            return None
        a, o, _ = self.plane(f"G{mode} (radius compensation)", 1)
        side = 1 if mode == 41 else -1
        if st.transform.flips(a, o):
            side = -side
        off = self._tool_offset(f"radius compensation G{mode}")
        radius = (off.radius + off.radius_wear) if off is not None else 0.0
        return (side, radius, st.modes["transition"], st.modes["comp_start"], (a, o))

    def _tool_offset(self, use: str):
        """The active tool offset D for a compensation, None with D0 or no tool.  An offset the
        machine's tool table does not hold (a placeholder of the default machine) is an error: the
        control has no such offset, and running with radius or length 0 would cut the wrong part."""
        st = self.state
        if not st.offset or not st.tool:
            return None
        off = st.tools.get(st.tool, {}).get(st.offset)
        if off is None or not off.declared:
            raise InterpError("INT123", f"{use} needs the offset D{st.offset} of tool T{st.tool}, which the "
                              "machine's tool table does not hold", 1)
        return off

    def _joins(self, comp: tuple | None) -> tuple | None:
        """G136/G137 and G138/G139 in force on a move without radius compensation: they may be programmed
        while compensation is active (seed 002 L9554, L9597), so a G138 written before the G40 block makes a
        direct cancellation; a compensated move carries them in ``comp``."""
        if comp is not None:
            return None
        modes = self.state.modes
        return (modes["transition"], modes["comp_start"])

    def _active_feed(self, length: float, start: dict) -> float:
        """Feed along the path in mm/min (seed 002 L4127-L4192).

        G94: F mm/min; G95: F mm/rev times the master spindle's speed (under
        G96 the speed follows from the surface speed and the radius on the
        first channel axis, limited by G192); G93: the move takes F seconds.
        MAXFEED clamps silently (L4072).
        """
        st = self.state
        mode = st.modes["feed"]
        if st.feed is None or st.feed == 0:
            if self.machine.default("DEFAULTFEED") and self.machine.max_feed > 0:
                return self.machine.max_feed
            what = "the feed is 0 (F0)" if st.feed == 0 else "no feed programmed (F)"
            raise InterpError("INT060", f"{what} for this G01/G02/G03 move", 1)
        if mode == 93:
            feed = length / st.feed * 60.0
        elif mode == 95:
            feed = st.feed * self._spindle_rpm(start)
        else:
            feed = st.feed
        if self.machine.max_feed > 0:
            feed = min(feed, self.machine.max_feed)
        return feed

    def _spindle_rpm(self, start: dict) -> float:
        st = self.state
        if not st.speeds:
            raise InterpError("INT065", "G95 feed per revolution needs a spindle", 1)
        spindle = next(iter(st.speeds))
        s = st.speeds[spindle]
        if st.spindle_state[spindle] == 5 or s <= 0:
            raise InterpError("INT065", "G95 feed per revolution with the spindle stopped: the axes would not move "
                              "(program S and M03/M04)", 1)
        if st.modes["css"] == 96:  # seed 002 L5406-L5464: S is the cutting speed in m/min
            radius = abs(st.to_part(start)[st.axes[0]])
            limit = float(st.planner.get("G192", 0.0) or 0.0)
            rpm = s * 1000.0 / (2.0 * math.pi * radius) if radius > 1e-6 else math.inf
            if limit > 0:
                rpm = min(rpm, limit)
            if not math.isfinite(rpm):
                raise InterpError("INT065", "G96 at the spindle centre without a G192 speed limit", 1)
            return rpm
        return s

    def _polar(self, bw: BlockWords, cur_part: dict, end_part: dict, origin=None) -> None:
        """R/Q polar end point in the plane (spec 02 §6.3, seed 002 L2639-L2672).

        ``origin`` replaces the polar origin for one block (G31: the arc centre).
        """
        st = self.state
        word = bw.params.get("Q") or bw.params.get("R")
        a, o, _ = self.plane("a move in polar coordinates (R, Q)", word[1] if word else 1)
        pa, po = st.polar_origin if origin is None else origin
        dx, dy = cur_part[a] - pa, cur_part[o] - po
        r_cur = math.hypot(dx, dy)
        q_cur = math.degrees(math.atan2(dy, dx)) if r_cur > 1e-12 else st.last_polar_angle
        r_prog = self.length(bw.params["R"][0]) if "R" in bw.params else None
        q_prog = bw.params["Q"][0] if "Q" in bw.params else None
        if q_prog is not None and abs(q_prog) > 360:
            q_prog = math.fmod(q_prog, 360.0)  # Q420 == Q60, sign kept (L2670)
        if st.modes["distance"] == 91:
            r = r_cur + (r_prog or 0.0)
            q = q_cur + (q_prog or 0.0)
        else:
            r = r_prog if r_prog is not None else r_cur
            q = q_prog if q_prog is not None else q_cur
        if r < 0:
            col = bw.params["R"][1] if "R" in bw.params else 1
            raise InterpError("INT019", f"polar radius {r:g} is negative", col)
        st.last_polar_angle = q
        end_part[a] = pa + r * math.cos(math.radians(q))
        end_part[o] = po + r * math.sin(math.radians(q))

    def _arc(self, mode: int, gs: dict, bw: BlockWords, src: Source, cur_part: dict, start: dict) -> Arc:
        """G02/G03 (centre, radius or polar form), G08 tangent and G09 three-point arcs, helices.

        seed 002 ch. 8.3-8.6; the reading of R follows spec 03 §B.3: with Q it
        is the polar radius, without Q but with an in-plane end coordinate it
        is the arc radius.
        """
        st = self.state
        p = bw.params
        col = next(iter(bw.axes.values()))[1] if bw.axes else next(iter(p.values()), (0, 1))[1]
        a, o, n = self.plane(f"G0{mode} (an arc)", col)
        # centre words of the plane (G17 I J, G18 K I, G19 J K; G20 I J) and the helix pitch letter
        ci, cj, ck = {17: ("I", "J", "K"), 18: ("K", "I", "J"), 19: ("J", "K", "I")}.get(
            st.modes["plane"], ("I", "J", "K"))
        pitch = p.pop(ck)[0] if ck in p and mode != 9 else None
        in_plane = a in bw.axes or o in bw.axes
        polar = "Q" in p or ("R" in p and not in_plane)
        sp = (cur_part[a], cur_part[o])
        end_part = self.target(bw, cur_part)
        absolute = 6 in gs or st.modes["arc_centre"] == 261
        center = None
        given_centre = False
        try:
            if mode == 9:
                center, ccw = self._three_point(bw, cur_part, end_part, polar, a, o)
            elif mode == 8:
                if polar:
                    self._polar(bw, cur_part, end_part)
                if st.tangent is None:
                    raise InterpError("INT068", "G08 needs a previous move in the plane to be tangent to", col)
                center, _r, ccw = arcs.tangent_arc(sp, st.tangent, (end_part[a], end_part[o]))
            else:
                ccw = mode == 3
                if ci in p or cj in p:
                    di = self.length(p[ci][0]) if ci in p else 0.0
                    dj = self.length(p[cj][0]) if cj in p else 0.0
                    center = (di, dj) if absolute else (sp[0] + di, sp[1] + dj)
                    given_centre = True
                    st.arc_radius = None   # an arc by its centre clears the stored radius (L6533)
                elif 31 in gs:
                    raise InterpError("INT069", "G31 needs the arc centre (I, J or K) in the block", col)
                if polar:
                    origin = center if 31 in gs else None
                    self._polar(bw, cur_part, end_part, origin)
                    st.arc_radius = None
                    if center is None:   # centre = polar origin (L6622-L6625)
                        center, given_centre = st.polar_origin, True
                elif center is None:
                    r = self.length(p["R"][0]) if "R" in p else st.arc_radius
                    if r is None:
                        raise InterpError("INT061", "G02/G03 needs the centre (I J K) or the radius (R)", col)
                    center = arcs.centre_from_radius(sp, (end_part[a], end_part[o]), r, not ccw)
        except arcs.ArcError as exc:
            raise InterpError("INT064", str(exc), col) from None
        ep = (end_part[a], end_part[o])
        r0 = math.dist(sp, center)
        if r0 < 1e-9:
            raise InterpError("INT061", "the arc centre is on the start point (radius 0)", col)
        if given_centre:
            center = self._radius_check(sp, ep, center, col)
        delta = arcs.sweep(sp, ep, center, ccw)
        turns = 0
        if pitch is not None:
            delta, turns, ep = self._helix(delta, pitch, cur_part, end_part, center, r0, ccw, col)
            end_part[a], end_part[o] = ep
        self._length_compensation(bw)
        tr = st.transform
        st.tangent = arcs.end_tangent(sp, ep, center, ccw)
        end_part = tr.apply(end_part)
        end = st.to_machine(end_part)
        self.interp.check_limits(end, col, start)
        st.machine_pos = dict(end)
        center_part = tr.apply({a: center[0], o: center[1]})
        center_m = st.to_machine(center_part)
        scale = tr.scale if a in tr.linear else 1.0
        ccw_path = ccw != tr.flips(a, o)   # an odd mirror in the plane turns G02 into G03 (L8740)
        planar = abs(math.radians(delta)) * r0 * scale
        other = sum((end[x] - start[x]) ** 2 for x in end if x not in (a, o))
        feed = self._active_feed(math.hypot(planar, math.sqrt(other)), start)
        comp = self._compensation()
        return Arc("arc", start, end, end_part, center_m, center_part, "ccw" if ccw_path else "cw",
                   (a, o, n), math.dist(ep, center) * scale, turns, feed, f"G{st.modes['feed']}", src,
                   comp, st.dynamics(), joins=self._joins(comp))

    def _radius_check(self, s, e, c, col: int):
        """Start/end radius mismatch with G264/G265 (seed 002 L6969-L7018; spec 03 §B.9)."""
        rs, re = math.dist(s, c), math.dist(e, c)
        delta = abs(re - rs)
        if delta <= 1e-12:
            return c
        ok = delta <= self.machine.cirinerr or 100.0 * delta / rs <= self.machine.cirinfact
        if not ok:
            raise InterpError("INT062", f"arc start radius {rs:.4f} and end radius {re:.4f} differ by "
                              f"{delta:.4f} mm, more than CIRINERR {self.machine.cirinerr:g} mm and "
                              f"CIRINFACT {self.machine.cirinfact:g} %", col)
        if self.state.modes["centre_correction"] == 265:
            return arcs.corrected_centre(s, e, c)
        return c

    def _three_point(self, bw: BlockWords, cur_part: dict, end_part: dict, polar: bool, a: str, o: str):
        """G09: intermediate point I J (K) is cartesian and follows G90/G91 (spec 03 §B.11)."""
        st = self.state
        p = bw.params
        plane = st.modes["plane"]
        letters = {a: "I", o: "J"} if plane == 20 else {ax: lt for ax, lt in zip(st.axes[:3], "IJK", strict=False)}
        la, lo = letters.get(a), letters.get(o)
        if la not in p or lo not in p:
            raise InterpError("INT068", f"G09 needs the intermediate point {la} {lo}", 1)
        incremental = st.modes["distance"] == 91
        pa = self.length(p[la][0], a) + (cur_part[a] if incremental else 0.0)
        po = self.length(p[lo][0], o) + (cur_part[o] if incremental else 0.0)
        if polar:
            self._polar(bw, cur_part, end_part)
        c, _r, ccw = arcs.three_point_arc((cur_part[a], cur_part[o]), (pa, po), (end_part[a], end_part[o]))
        return c, ccw

    def _helix(self, delta, pitch, cur_part, end_part, center, r, ccw, col):
        """Multi-turn helix: the pitch fixes the sweep, the in-plane end follows (spec 03 §B.12)."""
        st = self.state
        a, o, _ = st.plane_axes()
        pitch = self.length(pitch)
        travel = math.sqrt(sum((end_part[x] - cur_part[x]) ** 2 for x in end_part if x not in (a, o)))
        if pitch <= 0 or travel == 0:
            raise InterpError("INT069", "a helix pitch needs a positive pitch and a move off the plane", col)
        total = 360.0 * travel / pitch
        start_angle = math.degrees(math.atan2(cur_part[o] - center[1], cur_part[a] - center[0]))
        signed = total if ccw else -total
        e = arcs.point_on(center, r, start_angle + signed)
        if not math.isfinite(total) or total > 3.6e8:
            raise InterpError("INT069", "the helix pitch gives more than a million turns", col)
        turns = int((total - 1e-9) // 360.0)
        return signed, turns, e

    def _mcs_move(self, gs: dict, bw: BlockWords, src: Source) -> Line | Arc:
        """#MCS move; under a transformation (#CS, #RTCP...) it is written in the joints and not
        transformed (seed 002 L13195: "#MCS ON ... G1 G91 Z-10" inside an inclined plane)."""
        kin = self.state.kin
        if kin.frame is None:
            return self._mcs_plain(gs, bw, src)
        return kin.raw_move(self.state, lambda: self._mcs_plain(gs, bw, src))

    def _mcs_plain(self, gs: dict, bw: BlockWords, src: Source) -> Line | Arc:
        """#MCS move: machine coordinates, INCHES units, no offsets, no polar coordinates; G00, G01 and
        G02/G03 arcs by their centre or radius (seed 002 L3196-L3271: the #MCS ON example runs G01,
        G02 and G00)."""
        st = self.state
        a, o, _ = st.plane_axes()
        mode = st.modes["motion"]
        polar = "Q" in bw.params or ("R" in bw.params and (mode not in (2, 3) or not {a, o} & bw.axes.keys()))
        if polar:
            raise InterpError("INT063", "polar coordinates are not allowed in #MCS moves (L3225)", 1)
        start = dict(st.machine_pos)
        end = dict(start)
        inch = self.machine.default("INCHES")
        for axis, (v, _c) in bw.axes.items():
            v = v * INCH if inch and not self.machine.axes[axis].rotary else v
            end[axis] = start[axis] + v if st.modes["distance"] == 91 else v
        arc = self._mcs_arc(gs, bw, start, end, inch) if mode in (2, 3) else None
        self.interp.check_limits(end, 1, start)
        st.machine_pos = dict(end)
        end_part = st.to_part(end)
        if mode == 0:
            return Line("rapid", start, end, end_part, None, "G94", src, dyn=st.dynamics())
        if arc is not None:
            center, radius, sweep = arc
            n = st.plane_axes()[2]
            planar = abs(math.radians(sweep)) * radius
            other = sum((end[x] - start[x]) ** 2 for x in end if x not in (a, o))
            feed = self._active_feed(math.hypot(planar, math.sqrt(other)), start)
            center_m = {a: center[0], o: center[1]}
            center_part = {x: v for x, v in st.to_part({**end, **center_m}).items() if x in (a, o)}
            return Arc("arc", start, end, end_part, center_m, center_part, "ccw" if mode == 3 else "cw", (a, o, n),
                       radius, 0, feed, f"G{st.modes['feed']}", src, None, st.dynamics())
        if mode != 1:
            raise InterpError("INT063", "#MCS moves are G00, G01, G02 or G03", 1)
        length = math.sqrt(sum((end[a] - start[a]) ** 2 for a in end))
        return Line("linear", start, end, end_part, self._active_feed(length, start), f"G{st.modes['feed']}", src,
                    dyn=st.dynamics())

    def _mcs_arc(self, gs: dict, bw: BlockWords, start: dict, end: dict, inch: bool) -> tuple:
        """(centre, radius, sweep in degrees) of a G02/G03 #MCS arc in the machine's plane coordinates:
        the centre from the plane's centre words (from the start point, or absolute with G06/G261) or
        from R, as :meth:`_arc` does in part coordinates."""
        st = self.state
        a, o, _ = self.plane("G02/G03 (an arc)", 1)
        p = bw.params
        ccw = st.modes["motion"] == 3
        ci, cj = {17: ("I", "J"), 18: ("K", "I"), 19: ("J", "K")}.get(st.modes["plane"], ("I", "J"))
        sp, ep = (start[a], start[o]), (end[a], end[o])
        scale = INCH if inch else 1.0
        if ci in p or cj in p:
            di = p[ci][0] * scale if ci in p else 0.0
            dj = p[cj][0] * scale if cj in p else 0.0
            absolute = 6 in gs or st.modes["arc_centre"] == 261
            center = (di, dj) if absolute else (sp[0] + di, sp[1] + dj)
            col = (p.get(ci) or p[cj])[1]
            if math.dist(sp, center) < 1e-9:
                raise InterpError("INT061", "the arc centre is on the start point (radius 0)", col)
            center = self._radius_check(sp, ep, center, col)
        elif "R" in p:
            try:
                center = arcs.centre_from_radius(sp, ep, p["R"][0] * scale, not ccw)
            except arcs.ArcError as exc:
                raise InterpError("INT064", str(exc), p["R"][1]) from None
        else:
            raise InterpError("INT061", "G02/G03 needs the centre (I J K) or the radius (R)", 1)
        return center, math.dist(ep, center), arcs.sweep(sp, ep, center, ccw)
