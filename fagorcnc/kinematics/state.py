"""What the channel knows of its transformations: #KIN ID, stored and active #CS/#ACS, #RTCP, #TLC,
#TOOL ORI (seed 002 ch. 17).  One :class:`KinState` per channel, ``ChannelState.kin``.

Persistence (seed 002 L12594, L13309; spec 05 §6.3, §6.7-§6.8): #CS/#ACS, #RTCP and #TLC stay
active after M02/M30 and reset; nothing here is reset by them.
"""

from __future__ import annotations

import numpy as np

from ..config.kinematics import Kinematics
from .frame import Frame
from .frames import CoordinateSystem, compose

#: Most #ACS + #CS active at once (seed 002 L13085).
MAX_ACTIVE = 10


class KinState:
    """Transformations of a channel; :meth:`frame_for` gives the :class:`Frame` of the next record."""

    def __init__(self, machine) -> None:
        self.kinematics: list[Kinematics] = list(getattr(machine, "kinematics", []))
        self.kinid: int = getattr(machine, "kinid", 0)
        self.stored: dict[str, dict[int, CoordinateSystem]] = {"CS": {}, "ACS": {}}
        self.last_stored: dict[str, int | None] = {"CS": None, "ACS": None}
        # active systems in activation order: (kind, id or None for the unnamed one, system, saved zero)
        self.active: list[tuple[str, int | None, CoordinateSystem, tuple]] = []
        self.zero: np.ndarray | None = None   # part zero (X, Y, Z) when the first system went on
        self.rtcp = False
        self.tlc: float | None = None
        self.tool_ori = False        # #TOOL ORI given under the active plane: the kinematics is in use
        self.pending_ori = False     # the next move turns the rotary axes (seed 002 L13131)
        self.sol2 = False
        self.frame: Frame | None = None
        self.toolori: tuple[dict, dict] | None = None   # (solution 1, solution 2) of the active plane
        self.identity_told = False   # KIN024 given (no kinematics, no rotary axes)
        self.raw = False             # the record being made is in machine joints already (#MCS)
        self.cax: tuple[str, str] | None = None   # #CAX: (spindle, its C axis)
        self.c_axes = frozenset(getattr(machine, "c_axes", {}).values())   # axes that stand for spindles
        self.caxis: tuple | None = None     # ("FACE" | "CYL", its frame, the modes it replaced)
        self.as_linear: frozenset = frozenset()   # rotary axes programmed as lengths (#FACE, #CYL)
        self.angular_axes = list(getattr(machine, "angular_axes", []))   # [[angular_axes]] (#ANGAX)
        self.angax: dict[int, int] = {}   # #ANGAX: transformation number -> 1 active, 2 suspended
        self.tangential: dict[str, list] = {}   # G45/#TANGCTRL: axis -> [angle, 1 active | 2 suspended]
        self.tangfeed: float | None = None      # #TANGCTRL F (kept after cancellation, L12170)

    @property
    def current(self) -> Kinematics | None:
        """The selected kinematics (#KIN ID), or None."""
        return self.kinematics[self.kinid - 1] if 1 <= self.kinid <= len(self.kinematics) else None

    def active_kinds(self) -> list[str]:
        return [k for k, *_ in self.active]

    def description(self) -> str:
        parts = []
        if any(k == "ACS" for k, *_ in self.active):
            parts.append("#ACS")
        if any(k == "CS" for k, *_ in self.active):
            parts.append("#CS")
        if self.rtcp:
            parts.append("#RTCP")
        if self.tlc is not None:
            parts.append("#TLC")
        if self.tool_ori:
            parts.append("#TOOL ORI")
        return "+".join(parts)

    def plane(self) -> tuple[np.ndarray, np.ndarray]:
        """(R, V) of the active systems: every #ACS before every #CS, each kind in activation order
        (seed 002 L13085-L13110)."""
        acs = [cs for k, _n, cs, _z in self.active if k == "ACS"]
        css = [cs for k, _n, cs, _z in self.active if k == "CS"]
        return compose(acs + css)

    # ------------------------------------------------------------------ the frame
    def _linear(self, st) -> tuple[str, str, str] | None:
        names = [a for a in st.axes if not st.machine.axes[a].rotary][:3]
        return tuple(names) if len(names) == 3 else None

    def _length(self, st, linear) -> np.ndarray:
        return np.array([st.length_offset.get(a, 0.0) for a in linear], dtype=float)

    def rebuild(self, st) -> None:
        """Work the frame out again after a change; the joints stay where they are (the virtual
        position is recomputed from them)."""
        real = self.frame.point(st.machine_pos) if self.frame is not None else dict(st.machine_pos)
        self.frame = self._build(st)
        st.machine_pos = self.frame.inverse(real) if self.frame is not None else real

    def _build(self, st) -> Frame | None:
        if self.caxis is not None:
            return self.caxis[1]
        if self.angax:
            from .angax import frame_of

            return frame_of(self)
        if not self.active:
            self.zero = None
            self.tool_ori = False
            self.pending_ori = False
        kin = self.current
        if not self.active and not (self.rtcp and kin is not None) and self.tlc is None:
            return None   # (#RTCP without a kinematics: the identity, see statements._identity)
        linear = self._linear(st)
        if linear is None:
            return None
        r, v = self.plane()
        zero = self.zero if self.zero is not None else np.zeros(3)
        shift = zero + v - r @ zero
        engaged = kin is not None and (self.rtcp or self.tool_ori)
        return Frame(self.description(), r, shift, linear, self._length(st, linear), kin, engaged, self.tlc or 0.0)

    def reset(self) -> None:
        """M02/M30 and reset: a suspended #ANGAX is active again (seed 002 L11950), tangential control is
        cancelled (L12056); #CS/#ACS, #RTCP, #TLC and #ANGAX are kept (L12594, L13309, L11903)."""
        for n, v in self.angax.items():
            if v == 2:
                self.angax[n] = 1
        self.tangential = {}   # tangential control is cancelled by M02/M30 and reset (L12056)

    def check_home(self, axes, col: int) -> None:
        """G74: refused with an angular transformation active (L11867) and under #RTCP for axes that are
        not the RTCP's (L13320).  Under any other transformation (a plane, #TLC, #TOOL ORI, #FACE/#CYL,
        the RTCP's own axes) the manual does not forbid it: the interpreter moves the joints to the
        reference point (``raw_move``); only the C axis of #FACE is refused (not computed, KIN073)."""
        from ..interp.expressions import InterpError

        if self.angax:
            raise InterpError("KIN042", "G74 homing is not allowed with an angular transformation (#ANGAX) active "
                              "(L11867)", col)
        if self.rtcp and self.current is not None:
            mine = set(self.current.axes) | {"X", "Y", "Z"}
            other = [a for a in axes if a not in mine]
            if other:
                raise InterpError("KIN042", f"G74 of {', '.join(other)} while #RTCP is active: only the RTCP's "
                                  "axes may be homed (L13320)", col)
        wrapped = getattr(self.frame, "wrapped", ())
        homed = [a for a in axes if a in wrapped]
        if homed:
            # the C axis of #FACE is followed over whole turns by the joint-space stage: its reference
            # point would be reached on a turn fagorcnc does not know here
            raise InterpError("KIN073", f"G74 of {', '.join(homed)}, the C axis of #FACE, is not computed by "
                              "fagorcnc (the axis stands whole turns from the angle the program knows): "
                              "#FACE OFF first", col)

    def spindle_order(self, spindle: str | None) -> None:
        """M3/M4/M5 on the spindle working as C axis: it is a spindle again, as #CAX OFF (L11617)."""
        if self.cax is not None and spindle == self.cax[0]:
            self.cax = None

    def speed_check(self, spindle: str, col: int) -> None:
        from ..interp.expressions import InterpError

        if self.cax is not None and spindle == self.cax[0]:
            raise InterpError("KIN062", f"spindle {spindle} works as C axis {self.cax[1]}: no speed may be "
                              "programmed for it (L11601)", col)

    def raw_move(self, st, make):
        """A move written in machine joints while a transformation is active (#MCS): made with the
        channel's position in joints, handed on untransformed; the position goes back to the frame's
        coordinates afterwards."""
        frame = self.frame
        st.machine_pos = frame.point(st.machine_pos)
        self.raw = True
        try:
            return make()
        finally:
            st.machine_pos = frame.inverse(st.machine_pos)

    def frame_for(self, st) -> Frame | None:
        """The frame of a record made now (rebuilt when the tool length offset changed with the move,
        which the interpreter applies with it)."""
        f = self.frame
        if type(f) is Frame and not np.array_equal(f.length, self._length(st, f.linear)):
            f = self.frame = self._build(st)
        return f
