"""The channel state: modal functions, positions, the origin chain, tools, feed.

The origin chain (spec 02 §8.0, seed 002 L3167-L3195), per axis::

    machine = part + FIX[active fixture] + ABS + INC

``ABS`` is the absolute origin offset loaded by G54-G59 / G159=n (table
entry), by a G92 preset, or zero after G53; ``INC`` is the G158 incremental
offset.  G174 redefines the machine coordinate of the current point.  The PLC
offset is a hardware input and is zero offline.
"""

from __future__ import annotations

import copy

from ..config.machine import Machine
from ..kinematics.state import KinState
from ..path.transform import Transform
from . import axes as channel_axes
from . import spindle_config
from .cycles.model import CycleState
from .dynamics import Dynamics, build, default_roundpar
from .gtable import power_on_modes


class ChannelState:
    """Everything the interpreter knows about the channel between blocks."""

    def __init__(self, machine: Machine) -> None:
        self.machine = machine
        self.axes = machine.axis_names
        self.modes: dict[str, int | None] = power_on_modes(machine)
        self.machine_pos: dict[str, float] = dict.fromkeys(self.axes, 0.0)
        # origin chain
        self.origin_table: dict[int, dict[str, float]] = copy.deepcopy(machine.origins)
        self.fixture_table: dict[int, dict[str, float]] = copy.deepcopy(machine.fixtures)
        self.fixture = 0                       # V.G.FIX
        self.abs_offset: dict[str, float] = dict.fromkeys(self.axes, 0.0)
        self.inc_offset: dict[str, float] = dict.fromkeys(self.axes, 0.0)
        self.origin_source: str = "G53"        # "G54".."G59", "G159=n", "G92", "G53"
        self.excluded: set[str] = set()        # pending G157 exclusion
        # polar origin in work coordinates of the plane (abscissa, ordinate)
        self.transform = Transform(linear=frozenset(a for a, ax in machine.axes.items() if not ax.rotary))
        self.length_offset: dict[str, float] = {}   # applied tool length compensation (axis -> mm)
        self.tool_axis: tuple[str, int] | None = None   # #TOOL AX [Z+]: (axis, orientation)
        self.aid_size: float | None = None     # shared I register of G36-G39
        self.polar_origin = (0.0, 0.0)
        self.last_polar_angle = 0.0
        self.arc_radius: float | None = None   # R1= / G263= (modal arc radius)
        self.tangent: tuple[float, float] | None = None   # end direction of the last move in the plane (G08)
        # technology
        self.feed: float | None = None         # mm/min (G94), mm/rev (G95), s (G93)
        self.feed_programmed: float | None = None  # as written, in the active unit
        self.speeds: dict[str, float] = dict.fromkeys(machine.spindles, 0.0)
        self.spindle_state: dict[str, int] = dict.fromkeys(machine.spindles, 5)  # M3 / M4 / M5
        self.tools = copy.deepcopy(machine.tools)   # V.TM.TOR... may write it
        self.tool_data = copy.deepcopy(machine.tool_data)   # V.TM.TOTP1T.. may write it (config/tooldata.py)
        self.prep_tool = None   # V.G.TOTPn/REMLIFE written: (tool, values) of the tool in preparation (toolvars)
        self.g20_plane: tuple[str, str, str] | None = None   # G20 (abscissa, ordinate, longitudinal)
        self.tool_direction = -1               # V.G.TOOLDIR: the tool points along -longitudinal
        self.tool = 0
        self.next_tool = 0
        self.next_offset: int | None = None   # a D programmed with T: the offset the next M6 selects
        self.sync = False   # a read of an execution value or #FLUSH: the motion stops before the block goes on
        self.offset = 0                        # active D
        self.lower_limits: dict[str, float] = {a: ax.min_limit for a, ax in machine.axes.items()}
        self.upper_limits: dict[str, float] = {a: ax.max_limit for a, ax in machine.axes.items()}
        self.block_modes: dict[str, object] = {}  # G108/G109/G193/G60/G61/G266 of the last block
        self.planner: dict[str, object] = {}      # recorded sentences and G134/G135 for later stages
        # planning context (see interp/dynamics.py)
        self.hsc = None                          # Hsc of an active #HSC ON
        self.roundpar: tuple = default_roundpar(machine)
        self.slope: tuple = (machine.planner.slope_type, 0, 0, 0)
        self.tangfeed_rmin = 0.0   # #TANGFEED RMIN: G196 keeps F at the contact on arcs above it (L4305)
        self.acceleration: dict[str, float] = {}   # G130/G131 percentages not at 100
        #: G112 parameter sets of the axes and spindles not at set 1 (seed 002 L9307-L9360); power-on: DEFAULTSET
        self.param_sets: dict[str, int] = {}
        self.master: str | None = None   # #MASTER's spindle (None: the configuration's, master_spindle())
        self.reset_param_sets(power_on=True)
        self.jerk: dict[str, float] = {}           # G132/G133
        self._dynamics: Dynamics | None = None
        self.path: str | None = None           # #PATH directory
        self.user_vars: dict[str, float] = {}  # V.P.* and V.S.*
        self.mcs_on = False                    # #MCS ON
        self.block_skip = False
        self.executed_blocks = 0
        self.line = 0
        self.last_n = -1                       # V.G.BLKN: last N number executed (-1: none)
        self.elapsed = 0.0                     # estimated seconds of motion so far (V.G.CYTIME)
        self.parts = 0                         # V.G.PARTC: +1 at every M02/M30
        self.feed_override = 100.0             # V.G.PRGFRO (0 = none set by the program)
        self.programmed_override = 0.0
        self.call_letters: list[frozenset] = [frozenset()]  # V.C.PCALLP_x per call level
        self.cycles = CycleState()             # the active canned cycle, V.C.x (interp/cycles)
        self.arc_data: tuple | None = None     # the last prepared arc: V.G.R/I/J/K/CIRERR (interp/gvars.py)
        self.path_limits: tuple[float, float] | None = None   # V.G.MAXACCEL/MAXJERK written by the program
        self.manual_feeds: dict[int, float] = {}   # V.G.FMAN (94), V.G.MANFPR (95)
        self.dynamic_override = 100.0          # V.G.DYNOVR: % of every axis's dynamics (interp/channelvars.py)
        self.repositioning = (1.0, 0.0)        # V.G.ENDREP, V.G.SPDLREP (no tool inspection offline)
        self.pending_nr = 0                    # V.G.PENDNR: repetitions of the NR block still to run
        self.prep_offset = None                # V.G.TOR..TOK written: the offset of the blocks in preparation
        self.mtb: list[float] = list(machine.mtb)   # V.MTB.P[i] (written by the program, L29198)
        self.kin = KinState(machine)           # #KIN ID, #CS/#ACS, #RTCP, #TLC (kept by M30 and reset)
        self.channel = channel_axes.ChannelAxes(machine)   # #SET AX, #RENAME AX, #PARK, #LINK (interp/axes.py)
        self.spindle_config = spindle_config.ChannelSpindles(machine)   # #SET SP, #RENAME SP (interp/spindle_config.py)

    # ------------------------------------------------------------ planning context
    def dynamics_changed(self) -> None:
        """Something the planner depends on changed: rebuild :meth:`dynamics` on next use."""
        self._dynamics = None

    def dynamics(self) -> Dynamics:
        """The planning context of a motion in the current block (shared while unchanged)."""
        if self.block_modes:
            return build(self, self.block_modes)
        d = self._dynamics
        if d is None:
            d = self._dynamics = build(self, {})
        return d

    # ------------------------------------------------------------ coordinates
    def chain(self, axis: str) -> float:
        """Total offset between part and machine coordinates on ``axis``."""
        fix = self.fixture_table.get(self.fixture, {}).get(axis, 0.0) if self.fixture else 0.0
        return fix + self.abs_offset[axis] + self.inc_offset[axis]

    def axis_offset(self, axis: str) -> float:
        """Machine minus part coordinate on ``axis``: origin chain plus tool length compensation."""
        return self.chain(axis) + self.length_offset.get(axis, 0.0)

    def offsets(self) -> dict[str, float]:
        """:meth:`axis_offset` of every axis of the machine, in one pass (the same sums, in the same order)."""
        fix = self.fixture_table.get(self.fixture, {}) if self.fixture else None
        ab, inc, lo = self.abs_offset, self.inc_offset, self.length_offset
        if fix is None and not lo:
            return {a: 0.0 + ab[a] + inc[a] + 0.0 for a in self.axes}
        if fix is None:
            fix = {}
        return {a: fix.get(a, 0.0) + ab[a] + inc[a] + lo.get(a, 0.0) for a in self.axes}

    def joints(self) -> dict[str, float]:
        """The machine axes' positions: ``machine_pos`` is in the programmed plane's coordinates while
        a transformation is active (#CS, #RTCP, #FACE...; fagorcnc.kinematics.frame)."""
        frame = self.kin.frame
        return frame.point(self.machine_pos) if frame is not None else dict(self.machine_pos)

    def part_pos(self) -> dict[str, float]:
        """Tool tip in (transformed) part coordinates."""
        off = self.offsets()
        pos = self.machine_pos
        return {a: pos[a] - off[a] for a in self.axes}

    def programmed_pos(self) -> dict[str, float]:
        """Tool tip in programmed coordinates (before scaling, mirror and rotation)."""
        part = self.part_pos()
        return part if self.transform.identity else self.transform.invert(part)   # part is a new dict

    def to_machine(self, part: dict[str, float]) -> dict[str, float]:
        off = self.offsets()
        return {a: v + off[a] for a, v in part.items()}

    # the points of consecutive records are shared where they are equal (a record never changes
    # its points): simulate() keeps every record, and three dicts per move were most of its memory
    _last_end: dict[str, float] | None = None

    def move_start(self) -> dict[str, float]:
        """The start point of a new move: the end point of the last move when the tool is still
        there (the same dict, key order included), else a copy of ``machine_pos``."""
        last = self._last_end
        pos = self.machine_pos
        if last is not None and last == pos and tuple(last) == tuple(pos):
            return last
        return dict(pos)

    def moved_to(self, end: dict[str, float]) -> None:
        """The tool is at ``end``, the end point of the move just made."""
        self.machine_pos = dict(end)
        self._last_end = end

    @staticmethod
    def shared_end(end: dict[str, float], end_part: dict[str, float]) -> dict[str, float]:
        """``end_part`` itself when the machine point is the same (no offset): one dict for both."""
        return end_part if end == end_part and tuple(end) == tuple(end_part) else end

    def to_part(self, machine: dict[str, float]) -> dict[str, float]:
        off = self.offsets()
        return {a: v - off[a] for a, v in machine.items()}

    def longitudinal(self) -> tuple[str | None, int]:
        """The tool's longitudinal axis and the tool orientation (-1: the tool points to -axis)."""
        if self.tool_axis is not None:
            return self.tool_axis
        return self.plane_axes()[2], self.tool_direction

    # ------------------------------------------------------------ plane
    def plane_axes(self) -> tuple[str, str, str]:
        """(abscissa, ordinate, longitudinal) of the active plane (seed 002 L2961-L3012).

        Planes are defined by the first three slots of the channel's axis configuration (L14730).
        """
        slots = self.channel.slots
        plane = self.modes["plane"]
        if plane == 20 and self.g20_plane is not None:
            return self.g20_plane
        a = slots[:3] if len(slots) >= 3 else slots[:3] + [None] * (3 - len(slots))
        if len(slots) == 2 and None not in slots:
            # seed 002 L3013-L3016, L3043: a lathe with a "plane" axis configuration (two axes) always
            # works in G18, formed by the second axis (abscissa) and the first (X, Z: the plane ZX)
            return a[1], a[0], None
        if plane == 18:
            return a[2], a[0], a[1]
        if plane == 19:
            return a[1], a[2], a[0]
        return a[0], a[1], a[2]

    # ------------------------------------------------------------ origins
    def select_origin(self, n: int, label: str) -> None:
        """G54-G59 / G159=n: load table entry n on all non-excluded axes (L3531-L3545)."""
        entry = self.origin_table.get(n, {})
        for a in self.axes:
            if a not in self.excluded:
                self.abs_offset[a] = entry.get(a, 0.0)
        self.excluded.clear()
        self.origin_source = label

    def cancel_origin(self) -> None:
        """G53: ABS and INC to zero, pending exclusion cleared; fixture stays (L3897-L3902)."""
        for a in self.axes:
            self.abs_offset[a] = 0.0
            self.inc_offset[a] = 0.0
        self.excluded.clear()
        self.origin_source = "G53"

    def preset(self, values: dict[str, float]) -> None:
        """G92: the current point gets the given part coordinates (L3400-L3440)."""
        for a, v in values.items():
            self.abs_offset[a] = self.machine_pos[a] - (self.chain(a) - self.abs_offset[a]) - v
        self.origin_source = "G92"

    def master_spindle(self) -> str | None:
        """The channel's master spindle (seed 002 L5131-L5283): the one ``#MASTER`` chose while it is in the
        channel and not parked, else the first spindle of the channel's original configuration (the machine
        file's order) that is in the channel and not parked, else the first of the current configuration not
        parked (L5147-L5153, L5262-L5283, L14629-L14631); None when the channel has no spindle."""
        parked = self.channel.parked
        cfg = self.spindle_config
        if not cfg.changed and not parked:
            return self.master if self.master is not None else next(iter(cfg.current), None)
        if self.master is not None and self.master not in parked and cfg.in_channel(self.master):
            return self.master
        order = cfg.master_order()
        return next((s for s in order if s not in parked), next(iter(order), None))

    def reset_param_sets(self, power_on: bool = False) -> None:
        """DEFAULTSET (seed 002 L9343-L9349): each axis goes back to its default set at power-on, M02, M30 and
        reset; with DEFAULTSET 0 the set G112 chose is kept (at power-on: set 1)."""
        for name, ax in self.machine.axes.items():
            if ax.default_set != 0:
                self.param_sets.pop(name, None)
                if ax.default_set > 1:
                    self.param_sets[name] = ax.default_set
            elif power_on:
                self.param_sets.pop(name, None)

    def reset(self, event: str) -> None:
        """M02/M30/reset: groups flagged 'default' return to their power-on value."""
        from .gtable import G_FUNCTIONS

        defaults = power_on_modes(self.machine)
        for group, value in defaults.items():
            current = self.modes.get(group)
            g = G_FUNCTIONS.get(current) if current is not None else None
            if g is None or g.reset == "default":
                if group != "origin":
                    self.modes[group] = value
        self.polar_origin = (0.0, 0.0)
        self.excluded.clear()
        self.block_modes = {}
        # transformations (spec 04 §25): scale and rotation always, mirror per MIRRORCANCEL (L8786)
        self.transform.scale = 1.0
        self.transform.angle = 0.0
        if self.machine.default("MIRRORCANCEL"):
            self.transform.mirror = set()
        self.tool_axis = None
        self.cycles.reset()           # M02/M30/reset cancel the canned cycle (digest 09 §1.1)
        channel_axes.reset(self)      # #LINK ends, temporary changes of the axis configuration go back
        spindle_config.reset(self)    # and of the spindle configuration; RENAMECANCEL (L14955, L15191)
        self.kin.reset()              # a suspended #ANGAX is active again (L11950)
        self.aid_size = None
        self.planner = {}
        self.hsc = None               # L13665: HSC is cancelled by M02/M30 and reset
        self.roundpar = default_roundpar(self.machine)
        self.slope = (self.machine.planner.slope_type, 0, 0, 0)
        self.acceleration = {}        # L4447, L4495: 100 % after reset
        self.reset_param_sets()       # DEFAULTSET at M02/M30 and reset (L9343-L9349)
        self.master = None            # MASTERSPDL temporary: the original master again (L5141-L5150)
        if event != "M02":
            self.path_limits = None   # V.G.MAXACCEL/MAXJERK: the machine parameters again at M30 and reset (L36478)
        self.jerk = {}
        self._dynamics = None
        self.path = None
        self.mcs_on = False
        if self.machine.default("SPDLSTOP"):
            for s in self.spindle_state:
                self.spindle_state[s] = 5
        for s in self.speeds:  # S is 0 after M02/M30 (spec 02 §16)
            self.speeds[s] = 0.0
