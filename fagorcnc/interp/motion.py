"""Motion blocks of the ISO executor: G00/G01, arcs in every form, helices, polar moves, #MCS moves, and the
record each becomes (with its compensation, joins and feed).  A mixin of
:class:`~fagorcnc.interp.iso.IsoExecutor`: the methods use its state and helpers (seed 002 ch. 8)."""

from __future__ import annotations

import math

from ..path import arcs
from .expressions import InterpError
from .gvars import arc_data
from .plain import record_maker
from .records import Arc, Line, Source, feed_mode, shared_tuple
from .toolvars import refuse_turning_compensation
from .units import INCH
from .words import BlockWords

#: Arc(...) without its dataclass __init__ (interp/plain.py: record_maker)
_arc_record = record_maker(Arc)
#: Words of a move in polar coordinates, and every word that makes a G02/G03 without axis words an arc.
_POLAR = frozenset("RQ")
_ARC_WORDS = frozenset("IJKRQ")
#: The centre letters of each plane (abscissa, ordinate) and the helix pitch letter (seed 002 ch. 8.3).
_CENTRE_LETTERS = {17: ("I", "J", "K"), 18: ("K", "I", "J"), 19: ("J", "K", "I")}


class MotionMixin:
    """G00/G01, G02/G03 and their forms, polar and #MCS moves: :meth:`_motion` and its helpers."""

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
        if not bw.axes and _POLAR.isdisjoint(bw.params) and mode not in (2, 3):
            return None
        if not bw.axes and mode in (2, 3) and _ARC_WORDS.isdisjoint(bw.params):
            return None
        if self.interp.curves.independent:   # an axis a #MOVE moved, before #SYNC POS (interp/independent.py)
            from .independent import check_general  # on first use: a program without #MOVE never needs it

            check_general(self.interp, bw.axes, next(iter(bw.axes.values()))[1] if bw.axes else 1)
        prepared = self.sync.prepare(mode, bw) if mode in (33, 63) else None   # refused before anything moves
        if st.mcs_on or self.interp.mcs_block:
            return self._mcs_move(gs, bw, src)
        cur_part = st.programmed_pos()   # computations are in programmed coordinates
        start = st.move_start()
        if mode in (8, 9) or (mode in (2, 3) and not self._null_move(bw, cur_part)):
            return self._arc(mode, gs, bw, src, cur_part, start)
        end_part = self.target(bw, cur_part)
        if "R" in bw.params or "Q" in bw.params:
            self._polar(bw, cur_part, end_part)
            st.arc_radius = None   # a polar move clears the stored arc radius (L6533)
        self._length_compensation(bw)
        end_prog = end_part
        tr = st.transform
        end_part = dict(end_prog) if tr.identity else tr.apply(end_prog)
        end = st.shared_end(st.to_machine(end_part), end_part)
        self.interp.check_limits(end, next(iter(bw.axes.values()))[1] if bw.axes else 1, start)
        st.moved_to(end)
        if a is not None and o is not None:   # a lathe in G17 or a rotary-only machine has no plane to track
            st.tangent = arcs.end_tangent((cur_part[a], cur_part[o]), (end_prog[a], end_prog[o]), None, True) \
                or st.tangent
        if prepared is not None:   # G33 thread, G63 rigid tap: the feed follows the spindle
            return self.sync.record(mode, prepared, start, end, end_part, src)
        comp = self._compensation()
        if mode == 0:
            return Line("rapid", start, end, end_part, None, "G94", src, comp, st.dynamics(), joins=self._joins(comp))
        length = math.sqrt(sum((end[a] - start[a]) ** 2 for a in end))
        return Line("linear", start, end, end_part, self._active_feed(length, start), feed_mode(st.modes["feed"]),
                    src, comp, st.dynamics(), joins=self._joins(comp), css=self._css())

    def _null_move(self, bw: BlockWords, cur_part: dict) -> bool:
        """A G02/G03 block with no centre, radius or polar word whose target is where the tool stands:
        no arc, a null move (seed 002 L9996-L10009: "G91 G40 Y0" after a G03 cancels the
        compensation where the tool stands); mode 0 or 1 handles it as such."""
        if not _ARC_WORDS.isdisjoint(bw.params):
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
        if st.prep_offset is not None:   # V.G.TOR.. written: the offset of the blocks in preparation (L39204)
            refuse_turning_compensation(st, st.prep_offset, use)
            return st.prep_offset
        off = st.tools.get(st.tool, {}).get(st.offset)
        if off is None or not off.declared:
            raise InterpError("INT123", f"{use} needs the offset D{st.offset} of tool T{st.tool}, which the "
                              "machine's tool table does not hold", 1)
        refuse_turning_compensation(st, off, use)   # G41/G42 with a turning tool: not computed (INT254)
        return off

    def _joins(self, comp: tuple | None) -> tuple | None:
        """G136/G137 and G138/G139 in force on a move without radius compensation: they may be programmed
        while compensation is active (seed 002 L9554, L9597), so a G138 written before the G40 block makes a
        direct cancellation; a compensated move carries them in ``comp``."""
        if comp is not None:
            return None
        modes = self.state.modes
        return shared_tuple((modes["transition"], modes["comp_start"]))

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
        spindle = st.master_spindle()
        if spindle is None:   # none on the machine, or none left in the channel (#FREE SP)
            raise InterpError("INT065", "G95 feed per revolution needs a spindle in the channel", 1)
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

    def _css(self) -> tuple | None:
        """What the planner needs for a G95 move under G96, whose spindle speed follows the radius along it
        (seed 002 L5406-L5464): ``(mm/rev, m/min, G192 limit or 0, radius axis, machine - part offset)``;
        None otherwise (the feed of the record is then the feed of the whole move)."""
        st = self.state
        if st.modes["feed"] != 95 or st.modes["css"] != 96 or st.master_spindle() is None or st.kin.frame is not None:
            return None
        axis = st.axes[0]
        limit = float(st.planner.get("G192", 0.0) or 0.0)
        return (st.feed, st.speeds[st.master_spindle()], limit, axis, st.axis_offset(axis))

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
        ci, cj, ck = _CENTRE_LETTERS.get(
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
        programmed = center
        if given_centre:
            center = self._radius_check(sp, ep, center, col)
        arc_data(st, sp, programmed, center, ep, (a, o, n))   # V.G.R, I, J, K, CIRERR (L40454)
        delta = arcs.sweep(sp, ep, center, ccw)
        turns = 0
        if pitch is not None:
            delta, turns, ep = self._helix(delta, pitch, cur_part, end_part, center, r0, ccw, col)
            end_part[a], end_part[o] = ep
        self._length_compensation(bw)
        tr = st.transform
        st.tangent = arcs.end_tangent(sp, ep, center, ccw)
        end_part = tr.apply(end_part)
        end = st.shared_end(st.to_machine(end_part), end_part)
        self.interp.check_limits(end, col, start)
        st.moved_to(end)
        center_part = tr.apply({a: center[0], o: center[1]})
        center_m = st.to_machine(center_part)
        scale = tr.scale if a in tr.linear else 1.0
        ccw_path = ccw != tr.flips(a, o)   # an odd mirror in the plane turns G02 into G03 (L8740)
        planar = abs(math.radians(delta)) * r0 * scale
        other = sum((end[x] - start[x]) ** 2 for x in end if x not in (a, o))
        feed = self._active_feed(math.hypot(planar, math.sqrt(other)), start)
        comp = self._compensation()
        return _arc_record(kind="arc", start=start, end=end, end_part=end_part, center=center_m,
                           center_part=center_part, direction="ccw" if ccw_path else "cw", plane=(a, o, n),
                           radius=math.dist(ep, center) * scale, turns=turns, feed=feed,
                           feed_mode=feed_mode(st.modes["feed"]), src=src, comp=comp, dyn=st.dynamics(),
                           joins=self._joins(comp), css=self._css())

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
                       radius, 0, feed, feed_mode(st.modes["feed"]), src, None, st.dynamics())
        if mode != 1:
            raise InterpError("INT063", "#MCS moves are G00, G01, G02 or G03", 1)
        length = math.sqrt(sum((end[a] - start[a]) ** 2 for a in end))
        return Line("linear", start, end, end_part, self._active_feed(length, start), feed_mode(st.modes["feed"]), src,
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
