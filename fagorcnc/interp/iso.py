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

from ..kinematics import tangential
from ..path.aids import Aid
from . import compat, dynamics
from .cycles import CycleRunner
from .expressions import InterpError, whole
from .gtable import G_FUNCTIONS
from .motion import MotionMixin
from .records import Aux, Dwell, Line, Source
from .spindle import directions, orientation, targets
from .state import ChannelState
from .threading import Synchroniser
from .toolvars import refuse_uncomputed_offset
from .units import INCH
from .words import BlockWords, WordsMixin

#: M functions run after the motion by default (spec 02 §19: M00/M01 "after").
_M_AFTER = frozenset({0, 1, 2, 30, 17, 29})


class IsoExecutor(MotionMixin, WordsMixin):
    """Interprets ISO words against a :class:`ChannelState`, yielding records."""

    def __init__(self, interp) -> None:
        self.interp = interp
        self.state: ChannelState = interp.state
        self.machine = interp.machine
        self.ev = interp.evaluator
        self.cycles = CycleRunner(self)
        self.sync = Synchroniser(self)   # G33 threading, G63 rigid tapping

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
        modes = st.modes
        incremental = modes["distance"] == 91
        inch = modes["units"] == 70
        diameter = modes["diameter"] == 151
        configured = st.machine.axes
        out = dict(current_part)
        for axis, (v, col) in bw.axes.items():
            ax = configured[axis]
            if ax.rotary:
                if ax.rotary_mode != "linearlike" and axis not in st.kin.as_linear:
                    out[axis] = self._rotary(ax, current_part[axis], v, incremental, col)
                    continue
                v = self.length(v, axis)
            else:   # self.length(v, axis) of a linear axis, inline (one call per axis word)
                if inch:
                    v *= INCH
                if diameter and ax.diameter:
                    v /= 2.0
            out[axis] = current_part[axis] + v if incremental else v
        kin = st.kin
        if kin.pending_ori or kin.angax or kin.tangential or kin.c_axes:   # #TOOL ORI, #ANGAX SUSP, G45, #CAX
            from ..kinematics.statements import adjust_target  # on first use: a plain program never needs it
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
        self.sync.previous_motion = st.modes["motion"]   # G33 joins the thread of the block before (L7366)
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
        if 112 in gs:   # G112 X2 S2: parameter sets, not targets or speeds (L9324)
            dynamics.parameter_sets(self.interp, gs[112][0], bw)
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
            v = self.sync.speed_word(spindle, v, col)   # a negative S only under G63 (L7568)
            st.kin.speed_check(spindle, col)   # not for a spindle working as C axis (#CAX, L11601)
            st.speeds[spindle] = v
            if spindle in modes.positioning and st.modes["motion"] != 63:
                # L5705: kept as the speed of the M03/M04 that ends positioning; G63 starts the spindle
                # itself whatever M3/M4/M5/M19 is active (L7567-L7568)
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
            outer_nr = st.pending_nr
            for k in range(max(repeats, 1)):
                st.pending_nr = max(repeats, 1) - 1 - k   # V.G.PENDNR: n - 1 .. 0 (seed 002 L40680-L40684)
                if k:  # every repetition counts as an executed block (runaway guards)
                    interp.count_block(nr_col)
                rec = self._motion(gs, bw, src)
                if rec is not None:
                    moved = True
                    if rec.kind != "rapid" and rec.feed_mode not in ("G95", "G33", "G63"):
                        compat.spindle_lint(self.interp, rec, 1)
                    yield rec
                    if bw.nr is None or bw.nr[0] != 0:
                        yield from interp.after_motion(src)
            st.pending_nr = outer_nr
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
        if not st.length_offset and (not st.offset or not st.tool):
            return   # no offset, none applied: nothing changes (_tool_offset is None, the length 0)
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
            slots = st.channel.slots   # the first three axes of the configuration (L14730)
            if n in gs and axis < len(slots) and slots[axis] is not None:
                tr.mirror = tr.mirror | {slots[axis]}
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
        trihedron = [a for a in st.channel.slots[:3] if a is not None]
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
        st.prep_offset = None   # a new offset: V.G.TOR.. read the table again (L38884-L38943)
        st.prep_tool = None
        refuse_uncomputed_offset(st, col)   # TOFL/TOFLW: per-axis offsets fagorcnc does not apply

    def _master(self) -> str | None:
        """The master spindle: the channel's first (seed 002 L5100)."""
        return self.state.master_spindle()

    def _m_before(self, m: int, col: int, bw: BlockWords, src: Source, index: int = 0):
        st = self.state
        named = bw.m_target.get(index, (None, None))[0] if bw.m else None
        if m in (3, 4, 5, 19):
            self.sync.cancel_by_m(m, bw, col)   # M3/M4/M5/M19 cancel G63 (L7642)
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
            st.prep_offset = None   # V.G.TOR.. of the new tool come from the table (L38884-L38943)
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
            homes = {axis: self.machine.axes[axis].home for axis in groups[order]}
            if st.kin.frame is not None:
                # the reference point is a joint position: under a transformation the joints go there
                # (a joint move, as #MCS) and the position in the frame is worked out from them again
                yield st.kin.raw_move(st, lambda h=homes: self._home_group(h, src))
            else:
                yield self._home_group(homes, src)
        if st.modes["motion"] in (2, 3):
            st.modes["motion"] = 1 if self.machine.default("IMOVE") else 0

    def _home_group(self, homes: dict[str, float], src: Source) -> Line:
        """One group of G74: a rapid of its axes to their reference points (machine coordinates)."""
        st = self.state
        start = dict(st.machine_pos)
        end = {**start, **homes}
        st.machine_pos = dict(end)
        return Line("rapid", start, end, st.to_part(end), None, "G94", src, dyn=st.dynamics())

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
