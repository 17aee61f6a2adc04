"""Moves synchronised with the spindle: G33 electronic threading and G63 rigid tapping (seed 002 ch. 8.7-8.8).

A G33 block is a straight move whose feed follows the master spindle: the axis named by the pitch
letter (I, J or K) advances one pitch per revolution, ``v_axis = S x pitch`` (L7381-L7382), and the
other axes of the block scale with it; the thread always runs at 100 % of that feed (L7382-L7384,
feed override locked); the spindle override acts where THREADOVR allows it, and the feed follows the
spindle (L7387-L7391, :meth:`Synchroniser.thread_override`).  The spindle is the channel's master
(after #SET SP / #FREE SP / #MASTER, interp/spindle_config.py): a thread on another spindle needs the
PLC's V.PLC.SYNC and its synchronisation with the master (L7294-L7296, L31443-L31447), which an
offline run does not have; the master's home search before the first G33 is automatic (L7374-L7376),
nothing to do offline.  ``Q1`` is the spindle angle at the thread start (L7358-L7362); only the first
G33 after G33 is activated synchronises on it, the blocks that follow are joined to it (L7366-L7370).

A G63 block is a rigid tap: the CNC interpolates the spindle with the axes, the pitch is F / S
(L7563-L7565), G63 starts the spindle itself in the sense of the sign of S (L7567-L7569: a negative S
only under G63), and the S of a G63 block stays the active speed (L7637-L7639); the feed override
applies (L7647-L7649); M3, M4, M5 or M19 cancel G63 (L7642-L7643).

Both make :class:`~fagorcnc.interp.records.Line` records of kind ``"linear"`` with ``feed_mode``
``"G33"``/``"G63"`` and a :class:`~fagorcnc.interp.records.Thread`: no corner of a thread is rounded
(the planning context is G50's: each block ends at its programmed point) and what fagorcnc cannot
make exact is refused before anything moves: a feed the axes or MAXFEED would cut down (the pitch
would be wrong), a spindle that does not turn at a known speed, G96 (the speed would change along the
thread), radius compensation, #MCS and the transformations of chapters 14-17.
"""

from __future__ import annotations

import math
from dataclasses import replace

from .expressions import InterpError
from .records import Line, Source, Thread
from .words import BlockWords

#: The entry angle's range (seed 002 L7358: ±359.9999 degrees).
MAX_ENTRY = 359.9999


class Synchroniser:
    """The G33/G63 part of the ISO executor ``iso``: the checks before a synchronised move and its record."""

    def __init__(self, iso) -> None:
        self.iso = iso
        self.previous_motion: int | None = None   # the motion mode before the current block
        self.tap_speed: dict[str, float] = {}     # signed S of the last G63 block per spindle (L7637)
        self._dyn: tuple = (None, None, None)     # (base dynamics, rigid, thread dynamics)
        self._direction: tuple | None = None      # unit direction of the last G33 block
        self._passes: dict[tuple, float] = {}     # (pitch axis, its start, pitch) -> speed of the first pass
        self._held: set[tuple] = set()            # the INT189 warnings given (once per override and reason)

    # ------------------------------------------------------------ spindle words of the block
    def speed_word(self, spindle: str, value: float, col: int) -> float:
        """An S word of the block: the speed to store (positive).  A negative S is only allowed while G63 is
        active (seed 002 L7568-L7569); under G63 its sign is the sense of rotation for the tap."""
        st = self.iso.state
        rigid = st.modes["motion"] == 63
        if value < 0 and not rigid:
            raise InterpError("INT027", f"spindle speed {value:g} is negative: a negative S (reverse tapping) is "
                              "only allowed with G63 (L7568)", col)
        if rigid:
            self.tap_speed[spindle] = value
        else:
            self.tap_speed.pop(spindle, None)
        return abs(value)

    def cancel_by_m(self, m: int, bw: BlockWords, col: int) -> None:
        """M3, M4, M5 or M19 cancel G63 (seed 002 L7642-L7643); the motion mode becomes the power-on one
        (G00 or G01 per IMOVE) [CONSTRUCTION: the manual does not say which mode follows, spec 03 §F.14].
        In the G63 block itself it is an error: the tap would be cancelled before it runs."""
        st = self.iso.state
        if any(n == 63 for n, _c, _e in bw.g):
            raise InterpError("INT185", f"M{m} cancels G63 (L7642): program it in a block of its own, after the "
                              "tap", col)
        if st.modes["motion"] == 63:
            st.modes["motion"] = 1 if self.iso.machine.default("IMOVE") else 0

    # ------------------------------------------------------------ the move
    def prepare(self, mode: int, bw: BlockWords) -> tuple:
        """Checks that need no geometry, done before the block moves anything: what the manual refuses and
        what fagorcnc does not combine with a synchronised move.  Returns ``(spindle, speed, pitch, letter,
        entry)``: ``speed`` signed rpm, ``pitch`` mm/rev (None for G63: F / S, known with the feed),
        ``letter`` the pitch letter of G33."""
        iso, st = self.iso, self.iso.state
        col = next(iter(bw.axes.values()))[1] if bw.axes else 1
        name = "G33 (threading)" if mode == 33 else "G63 (rigid tapping)"
        if st.mcs_on or iso.interp.mcs_block or st.kin.frame is not None:
            raise InterpError("INT186", f"{name} under #MCS or a transformation (#CS, #ACS, #RTCP, #TLC, #FACE, "
                              "#CYL, #ANGAX...) is not computed by fagorcnc: cancel it before the thread", col)
        if st.modes["compensation"] in (41, 42):
            raise InterpError("INT186", f"{name} under radius compensation G{st.modes['compensation']} is not "
                              "computed by fagorcnc: program G40 before the thread", col)
        spindle = st.master_spindle()
        if spindle is None:
            where = "the channel has none left (#FREE SP, #SET SP); #CALL SP first" if st.speeds else \
                "the machine has none"
            raise InterpError("INT182", f"{name} needs a spindle: {where}", col)
        if st.modes["css"] == 96:
            raise InterpError("INT182", f"{name} under G96: the spindle speed would change with the diameter "
                              "along the thread; program G97 S<rpm>", col)
        if mode == 33:
            return self._prepare_thread(bw, spindle, col)
        return self._prepare_tap(bw, spindle, col)

    def _prepare_thread(self, bw: BlockWords, spindle: str, col: int) -> tuple:
        iso, st = self.iso, self.iso.state
        letters = [k for k in ("I", "J", "K") if k in bw.params]
        if not letters:
            raise InterpError("INT180", "G33 needs the thread pitch: I, J or K of the axis it is measured on "
                              "(G33 Z-30 K1.5, L7315)", col)
        if len(letters) > 1:
            raise InterpError("INT180", f"G33 takes one pitch letter, not {' and '.join(letters)}: the pitch is "
                              "measured on one axis (L7324-L7325)", bw.params[letters[1]][1])
        letter = letters[0]
        value, pcol = bw.params.pop(letter)
        if not value > 0:
            raise InterpError("INT180", f"G33 pitch {letter}{value:g} must be positive", pcol)
        pitch = iso.length(value)
        entry = None
        if "Q1" in bw.params:
            q, qcol = bw.params.pop("Q1")
            if abs(q) > MAX_ENTRY:
                raise InterpError("INT184", f"G33 entry angle Q1={q:g} is outside +-359.9999 degrees (L7358)", qcol)
            entry = q
        # seed 002 L7366-L7370: Q1 counts only in the first G33 after G33 is activated
        # no Q1 synchronises on 0 degrees (L7361-L7362); a joined thread does not synchronise
        entry = None if self.previous_motion == 33 else (entry if entry is not None else 0.0)
        state = st.spindle_state.get(spindle)
        speed = st.speeds.get(spindle, 0.0)
        if spindle in iso.interp.spindle_modes.positioning or state == 19:
            raise InterpError("INT182", f"G33 with the spindle {spindle} in M19 positioning: program S and M03/M04 "
                              "before the thread (L7431-L7435)", col)
        if state not in (3, 4) or not speed > 0:
            what = "stopped (M05)" if state not in (3, 4) else "at speed 0"
            raise InterpError("INT182", f"G33 with the spindle {spindle} {what}: the feed is speed x pitch "
                              "(L7381); program S and M03/M04 before the thread", col)
        return spindle, (speed if state == 3 else -speed), pitch, letter, entry

    def _prepare_tap(self, bw: BlockWords, spindle: str, col: int) -> tuple:
        st = self.iso.state
        for k in ("I", "J", "K", "Q1"):
            if k in bw.params:
                raise InterpError("INT185", f"G63 takes no {k}: the pitch of a rigid tap is F / S (L7563-L7565)",
                                  bw.params[k][1])
        speed = st.speeds.get(spindle, 0.0)
        signed = self.tap_speed.get(spindle)
        if signed is None or abs(signed) != speed:
            signed = speed   # L7637-L7638: the active speed, in the sense of M03 (L7567)
        if not speed > 0:
            raise InterpError("INT182", f"G63 with the spindle {spindle} at speed 0: program S in the G63 block "
                              "(G63 Z-30 S100) or before it (L7637)", col)
        if st.modes["feed"] == 93:
            raise InterpError("INT185", "G63 under G93 (feed as a time): the pitch is F / S, program G94 or G95",
                              col)
        if st.feed is None or st.feed == 0:
            raise InterpError("INT185", "G63 needs the feed F: the pitch is F / S (L7563-L7565)", col)
        return spindle, signed, None, None, None

    def record(self, mode: int, prepared: tuple, start: dict, end: dict, end_part: dict, src: Source) -> Line:
        """The synchronised move from ``start`` to ``end`` (machine coordinates)."""
        iso, st = self.iso, self.iso.state
        spindle, speed, pitch, letter, entry = prepared
        rpm = abs(speed)
        length = math.sqrt(sum((end[a] - start[a]) ** 2 for a in end))
        if mode == 33:
            axis = self.pitch_axis(letter)
            advance = abs(end[axis] - start[axis])
            if advance < 1e-9:
                raise InterpError("INT181", f"G33: the thread does not advance on {axis}, the axis of its pitch "
                                  f"letter {letter} (L7330-L7333)", 1)
            # seed 002 L7387-L7389: where THREADOVR lets the spindle override act, the spindle turns at S x override
            # and the feed follows it; seed 002 L7381-L7382: feed = speed x pitch on the pitch axis, and the path
            # runs faster by length / advance
            rpm = rpm * self.thread_override(spindle, start, end) / 100.0
            speed = rpm if speed > 0 else -rpm
            feed = rpm * pitch * length / advance
        else:
            axis = max(end, key=lambda a: abs(end[a] - start[a]))
            if st.modes["feed"] == 95:   # F is already per revolution: the pitch [CONSTRUCTION, spec 03 §F.13]
                pitch, feed = st.feed, st.feed * rpm
            else:                        # L7563-L7565: pitch = F / S
                pitch, feed = st.feed / rpm, st.feed
        self._check_feed(mode, feed, length, start, end)
        if mode == 33:
            self.previous_motion = 33   # a repetition (NR) of the block is joined to it
            direction = tuple((end[a] - start[a]) / length for a in sorted(end))
            if entry is None and self._direction is not None and math.dist(direction, self._direction) > 1e-9:
                # [CONSTRUCTION] the manual joins threads (L7542-L7552) without saying how the axes turn the
                # corner while following the spindle; fagorcnc stops them there (no rounding inside a thread)
                iso.interp.message("INT187", "warning", "joined threads meet at a corner: the axes stop there "
                                   "within their acceleration while the spindle turns, so the pitch is not kept "
                                   "over the slow-down and the start again", 1)
            self._direction = direction
            if entry is not None:
                self._same_speed(axis, start[axis], pitch, rpm)
        thread = Thread(mode == 63, spindle, speed, pitch, axis, entry)
        return Line("linear", start, end, end_part, feed, f"G{mode}", src, None, self._dynamics(mode == 63),
                    joins=iso._joins(None), thread=thread)

    def thread_override(self, spindle: str, start: dict, end: dict) -> float:
        """The spindle override (%) a G33 thread runs at (seed 002 L7382-L7391, L22355-L22414).

        Offline the spindle override is the program's, ``V.A.PRGSSO`` (0 = none: 100 %), there is no panel.
        The feed override never acts in a thread (L7382-L7384); the spindle override does only if the OEM lets
        it: THREADOVR, "the maximum variation allowed for the override while threading" (L22363), from the
        machine file's ``[machine_parameters]`` ``"MPA.THREADOVR.S"`` (0 without it: none, 100 %), and only
        if the active feed forward of every axis of the thread is above 90 % (L7389-L7391; G134's, else
        ``"MPA.FFGAIN.X"``; [CONSTRUCTION] one the machine file does not give is taken as allowing it).
        [CONSTRUCTION] an override beyond 100 +- THREADOVR runs at the nearest of the two (INT189)."""
        from .spindle_config import parameter

        iso = self.iso
        override = iso.interp.spindle_modes.override.get(spindle, 0.0) or 100.0
        if override == 100.0:
            return override
        limit = parameter(iso.machine, "THREADOVR", spindle, 0.0)
        allowed = min(max(override, 100.0 - limit), 100.0 + limit)
        why = f"THREADOVR of {spindle} is {limit:g} % (L22355)"
        programmed = iso.state.planner.get("G134", {})
        for a in end:
            if abs(end[a] - start[a]) < 1e-12:
                continue
            ff = programmed.get(a, iso.machine.machine_parameters.get(("FFGAIN", (), a)))
            if ff is not None and not ff > 90.0:
                allowed, why = 100.0, f"the feed forward of axis {a} is {ff:g} %, not above 90 % (L7389-L7391)"
                break
        if allowed != override and (spindle, override, allowed, why) not in self._held:
            self._held.add((spindle, override, allowed, why))
            iso.interp.message("INT189", "warning", f"the spindle override {override:g} % acts as {allowed:g} % in "
                               f"this thread: {why}", 1)
        return allowed

    def _same_speed(self, axis: str, begin: float, pitch: float, rpm: float) -> None:
        """Every pass of a thread, and every start of a multi-start thread, must begin at the same spindle speed
        (seed 002 L7392-L7400), or the entry points or the angles between the starts do not match; the CNC does
        not check it.  A synchronised G33 that begins where an earlier one began on its pitch axis, with the
        same pitch, at another speed is warned about (INT188) [CONSTRUCTION: how a pass is recognised]."""
        key = (axis, round(begin, 6), round(pitch, 9))
        first = self._passes.setdefault(key, rpm)
        if abs(first - rpm) > 1e-9:
            self.iso.interp.message("INT188", "warning", f"this pass of the thread begins at {rpm:g} rpm, an "
                                    f"earlier one at {first:g} rpm: the passes (and the starts) of one thread must "
                                    "begin at the same speed (L7392-L7400)", 1)

    def pitch_axis(self, letter: str) -> str:
        """The axis of a pitch letter (seed 002 L7330-L7333): G17/G18/G19 I, J, K are the channel's first,
        second and third axes; G20 the abscissa, ordinate and perpendicular of its plane.  A two-axis lathe
        channel (X, Z) takes I for its first axis and K for its second [CONSTRUCTION: the manual's lathe
        examples, L7497-L7552, write K for the pitch along Z]."""
        st = self.iso.state
        axes = list(st.axes)
        if st.modes["plane"] == 20 and st.g20_plane is not None:
            names = dict(zip("IJK", st.g20_plane, strict=True))
        elif len(axes) == 2:
            names = {"I": axes[0], "K": axes[1]}
        else:
            names = dict(zip("IJK", axes[:3], strict=False))
        axis = names.get(letter)
        if axis is None:
            raise InterpError("INT180", f"G33 pitch letter {letter}: the channel has no axis for it (L7330)", 1)
        return axis

    def _check_feed(self, mode: int, feed: float, length: float, start: dict, end: dict) -> None:
        """A synchronised feed is never cut down: MAXFEED or an axis's maximum feed below it would change the
        pitch cut, so that is an error (the manual clamps an ordinary F silently, L4072)."""
        machine, name = self.iso.machine, f"G{mode}"
        if machine.max_feed > 0 and feed > machine.max_feed * (1 + 1e-9):
            raise InterpError("INT183", f"{name}: the feed {feed:.6g} mm/min (speed x pitch) is above MAXFEED "
                              f"{machine.max_feed:g}: the pitch cannot be kept; lower S", 1)
        for a in end:
            d = abs(end[a] - start[a])
            if d < 1e-12 or length <= 0:
                continue
            ax = machine.axes[a]
            limit = min(ax.max_feed, ax.max_velocity) if ax.max_feed > 0 else ax.max_velocity
            v = feed * d / length
            if v > limit * (1 + 1e-9):
                raise InterpError("INT183", f"{name}: axis {a} would run at {v:.6g} mm/min, above its maximum "
                                  f"{limit:g}: the pitch cannot be kept; lower S", 1)

    def _dynamics(self, rigid: bool):
        """The planning context of a synchronised move: the block's, with no corner rounding (G50: the block
        ends at its programmed point, no G05/HSC curve cuts into the thread), no feed adaptation, and for G33
        the feed override locked at 100 % (L7382-L7384)."""
        base = self.iso.state.dynamics()
        cached = self._dyn
        if cached[0] is base and cached[1] is rigid:
            return cached[2]
        dyn = replace(base, corner="G50", hsc=None, adaptation=None, override_locked=not rigid)
        self._dyn = (base, rigid, dyn)
        return dyn
