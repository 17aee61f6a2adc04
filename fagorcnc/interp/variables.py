"""V. variables an offline interpreter honours (seed 002 ch. 22; spec 07, 08).

Names are matched after the parser's normalisation (``V.A.ORGT[1].X`` is
``"V.A.ORGT[].X"`` with index ``(1,)``).  The axis of ``V.A.<name>.<axis>``
may be an axis name or its logical number (1 = first channel axis).  The
channel selector ``V.[n].`` is accepted for channel 1 only (one channel
offline).  Writing a read-only variable is an error (seed 002 L1809-L1812);
an unknown variable is an error naming it.  User variables ``V.P.name``
(local) and ``V.S.name`` (global) are created by assignment (L1821-L1860).
"""

from __future__ import annotations

from collections.abc import Callable

from ..kinematics.variables import axis_variables as kinematics_axis_variables
from ..kinematics.variables import variables as kinematics_variables
from . import spindle_config
from .channelvars import ChannelVariables
from .cycles.variables import register as register_cycle_variables
from .expressions import InterpError
from .gvars import ProgramVariables
from .iso import INCH, whole
from .mpvars import MachineParameters
from .state import ChannelState
from .toolvars import ToolVariables

Getter = Callable[[ChannelState, tuple, str | None], float]
Setter = Callable[[ChannelState, tuple, str | None, float], None]


def _entry(table: dict, n: int, col: int, what: str, hi: int) -> dict:
    if not 1 <= n <= hi:
        raise InterpError("INT045", f"{what}[{n}] does not exist (entries 1..{hi})", col)
    return table.setdefault(n, {})


_AXIS_ORDER = "XYZUVWABC"


def _index(v: float) -> int:
    """A table index: a whole number (seed 002 E20)."""
    n = whole(v)
    if n is None:
        raise InterpError("INT045", f"index [{v:g}] must be a whole number", 1)
    return n


def _axis_code(name: str | None) -> int:
    """Axis code of V.G.PLANE/LONGAX: X=10, Y=20 ... C=90, plus the axis digit (X1=11)."""
    if not name or name[0] not in _AXIS_ORDER:
        return 0
    return 10 * (_AXIS_ORDER.index(name[0]) + 1) + (int(name[1:]) if name[1:].isdigit() else 0)


#: Variables whose reading "stops block preparation" (seed 002 L17437: "sa lecture arrête la préparation
#: des blocs", marked on each in ch. 22): they give the value at execution, so the motion before the
#: block that reads them ends there (a synchronisation point, as #FLUSH makes, L17446).
EXECUTION_READS = frozenset({
    "V.A.POS", "V.A.TPOS", "V.A.TIPPOS", "V.A.TIPTPOS", "V.A.APOS", "V.A.ATPOS", "V.A.ATIPPOS", "V.A.ATIPTPOS",
    "V.A.ORGT[]", "V.TM.TOOL", "V.TM.NXTOOL", "V.TM.TOD", "V.TM.NXTOD", "V.TM.NUMOFD",
    "V.TM.TOR", "V.TM.TOI", "V.TM.TOL", "V.TM.TOK", "V.TM.TOR[]", "V.TM.TOI[]", "V.TM.TOL[]", "V.TM.TOK[]",
    "V.TM.TORT[]", "V.TM.TOIT[]", "V.TM.TOLT[]", "V.TM.TOKT[]",
    "V.TM.TORT[][]", "V.TM.TOIT[][]", "V.TM.TOLT[][]", "V.TM.TOKT[][]",
    "V.G.FEED", "V.G.FPREV", "V.G.FREAL", "V.G.PATHFEED", "V.G.FRO", "V.G.CNCFRO", "V.G.RAPID",
    "V.G.CYTIME", "V.G.CLOCK", "V.G.PARTC", "V.G.STATUS", "V.G.FULLSTATUS", "V.G.FIRST", "V.G.M01STOP",
    "V.G.SBLOCK", "V.G.SBOUT",
    "V.PLC.TAPPING", "V.PLC.TAPPINGC1", "V.PLC.RIGID", "V.PLC.RIGIDC1",   # L29844-L29857 (cycles/variables.py)
})


class Variables:
    """Reads and writes ``V.`` variables against a :class:`ChannelState`."""

    def __init__(self, state: ChannelState) -> None:
        self.state = state
        s = state
        #: the axes a #MOVE positioned since the last #SYNC POS, and the interpreter's warning hook: an
        #: execution read of such an axis gets a warning (the interpreter sets both; see :meth:`get`)
        self.moving_alone: dict = {}
        self.warn: Callable | None = None
        self.machine_parameters = MachineParameters(state)   # V.MPG, V.MPA, V.SP, V.MPMAN, V.MPM, V.TM, V.MTB
        # name -> (getter, setter or None); axis variables take the axis as 3rd argument
        self.axis_vars: dict[str, tuple[Getter, Setter | None]] = {
            "V.A.PPOS": (lambda st, i, a: st.part_pos()[a], None),          # L35650
            "V.A.POS": (lambda st, i, a: st.joints()[a], None),             # L35803
            "V.A.TPOS": (lambda st, i, a: st.joints()[a], None),            # L35816
            # the controlled point is the tool base (POS, L35803): the tip is the tool length away from it
            # in machine coordinates (TIPPOS, L35846), the base in part coordinates leaves the tool
            # length out (APOS, L35734)
            "V.A.TIPPOS": (lambda st, i, a: st.machine_pos[a] - st.length_offset.get(a, 0.0), None),
            "V.A.TIPTPOS": (lambda st, i, a: st.machine_pos[a] - st.length_offset.get(a, 0.0), None),
            "V.A.APOS": (lambda st, i, a: st.machine_pos[a] - st.chain(a), None),
            "V.A.ATPOS": (lambda st, i, a: st.machine_pos[a] - st.chain(a), None),
            "V.A.ATIPPOS": (lambda st, i, a: st.part_pos()[a], None),
            "V.A.ATIPTPOS": (lambda st, i, a: st.part_pos()[a], None),
            "V.A.ORG": (lambda st, i, a: st.abs_offset[a] + st.inc_offset[a], None),  # L35123
            "V.A.ADDORG": (lambda st, i, a: st.inc_offset[a], None),         # L35159
            "V.A.FIX": (lambda st, i, a: st.fixture_table.get(st.fixture, {}).get(a, 0.0)
                        if st.fixture else 0.0, None),                        # L35384
            "V.A.ORGT[]": (lambda st, i, a: _entry(st.origin_table, i[0], 1, "V.A.ORGT", 99).get(a, 0.0),
                           lambda st, i, a, v: _entry(st.origin_table, i[0], 1, "V.A.ORGT", 99).__setitem__(a, v)),
            "V.A.FIXT[]": (lambda st, i, a: _entry(st.fixture_table, i[0], 1, "V.A.FIXT", 10).get(a, 0.0),
                           lambda st, i, a, v: _entry(st.fixture_table, i[0], 1, "V.A.FIXT", 10).__setitem__(a, v)),
            "V.A.LOLIM": (lambda st, i, a: st.lower_limits[a], None),
            "V.A.UPLIM": (lambda st, i, a: st.upper_limits[a], None),
            # the software limits (L33066-L33080): read and written from the program, a write makes them
            # the limits from there on
            "V.A.POSLIMIT": (lambda st, i, a: st.upper_limits[a],
                             lambda st, i, a, v: st.upper_limits.__setitem__(a, v)),
            "V.A.NEGLIMIT": (lambda st, i, a: st.lower_limits[a],
                             lambda st, i, a, v: st.lower_limits.__setitem__(a, v)),
        }
        # the manual also writes the fixture table V.G.FIXT[n].X (L2126, spec 01 §18.8)
        self.axis_vars["V.G.FIXT[]"] = self.axis_vars["V.A.FIXT[]"]
        self.plain_vars: dict[str, tuple[Callable[[tuple], float], Callable[[tuple, float], None] | None]] = {
            "V.G.FIX": (lambda i: float(s.fixture), self._set_fix),          # L35373
            "V.G.TOOL": (lambda i: float(s.tool), None),                     # L37501
            "V.G.NXTOOL": (lambda i: float(s.next_tool), None),
            "V.G.TOD": (lambda i: float(s.offset), None),
            "V.G.PRGS": (lambda i: s.speeds.get(s.machine.spindles[0], 0.0) if s.machine.spindles else 0.0, None),
            "V.G.BLKSKIP": (lambda i: 1.0 if s.block_skip else 0.0, None),
            "V.G.NUMORG": (lambda i: 99.0, None),
            "V.G.FORG": (lambda i: 1.0, None),
            "V.G.NUMFIX": (lambda i: 10.0, None),
            "V.G.FFIX": (lambda i: 1.0, None),
            "V.G.PORGF": (lambda i: s.polar_origin[0], None),                # L40519
            "V.G.PORGS": (lambda i: s.polar_origin[1], None),
        }
        # active and next tool (seed 002 L37501-L38290); [ofd] optional: the active D
        self.plain_vars.update({
            "V.TM.TOOL": (lambda i: float(s.tool), None),
            "V.TM.TOD": (lambda i: float(s.offset), None),
            "V.TM.NXTOOL": (lambda i: float(s.next_tool), None),
            "V.TM.NXTOD": (lambda i: float(s.next_offset or 0), None),   # L37547: the next offset
            "V.G.NXTOD": (lambda i: float(s.next_offset or 0), None),    # L38931
            "V.TM.NUMOFD": (lambda i: float(len(s.tools.get(s.tool, {}))), None),
        })
        for name, fld in (("TOR", "radius"), ("TOI", "radius_wear"), ("TOL", "length"), ("TOK", "length_wear")):
            get, put = self._tool_field(fld)
            self.plain_vars[f"V.TM.{name}"] = (get, put)
            self.plain_vars[f"V.TM.{name}[]"] = (get, put)
            # any tool of the table: V.TM.TORT[tl][ofd], [tl] alone its active offset (L38632-L38725)
            self.plain_vars[f"V.TM.{name}T[]"] = self.plain_vars[f"V.TM.{name}T[][]"] = \
                self._tool_field(fld, any_tool=True)
        # programmed functions (seed 002 L40015-L40258)
        self.plain_vars.update({
            "V.G.GS[]": (self._g_state, None),
            "V.G.MS[]": (self._m_state, None),
            "V.G.PLANE": (self._plane_code, None),
            # the longitudinal axis and the tool's orientation, #TOOL AX's when given (L3126-L3166):
            # TOOLDIR 1 positive, 2 negative (L40029; the example L40073-L40078 contradicts itself)
            "V.G.LONGAX": (lambda i: float(_axis_code(s.longitudinal()[0])), None),
            "V.G.TOOLDIR": (lambda i: 1.0 if s.longitudinal()[1] > 0 else 2.0, None),
        })
        for k in range(1, 11):
            self.plain_vars[f"V.G.HGS{k}"] = (lambda i, k=k: float(self._hgs(k)), None)
        # transformations (seed 002 L40543-L40650)
        self.plain_vars.update({
            "V.G.MIRROR": (lambda i: float(sum(1 << k for k, a in enumerate(s.axes) if a in s.transform.mirror)),
                           None),
            "V.G.SCALE": (lambda i: s.transform.scale, None),
            "V.G.ORGROT": (lambda i: s.transform.angle, None),
            "V.G.ROTPF": (lambda i: s.transform.centre[0], None),
            "V.G.ROTPS": (lambda i: s.transform.centre[1], None),
        })
        # feeds (seed 002 L36129-L36460); offline no PLC value and no panel override
        self.plain_vars.update({
            "V.G.FEED": (lambda i: self._feed(94), None),
            "V.G.PRGF": (lambda i: self._feed(94), None),
            "V.G.PATHFEED": (lambda i: self._feed(s.modes["feed"]), None),
            "V.G.FREAL": (lambda i: self._feed(s.modes["feed"]), None),
            "V.G.FPREV": (lambda i: self._feed(95), None),
            "V.G.PRGFPR": (lambda i: self._feed(95), None),
            "V.G.FTIME": (lambda i: self._feed(93), None),
            "V.G.FRO": (lambda i: s.programmed_override or 100.0, None),
            "V.G.PRGFRO": (lambda i: s.programmed_override, self._set_override),
            "V.G.CNCFRO": (lambda i: 100.0, None),
        })
        # general and program state (seed 002 L42513-L43300)
        self.plain_vars.update({
            "V.G.HARDTYPE": (lambda i: 0.0, None),          # 0 = simulator
            "V.G.CNCHANNEL": (lambda i: 1.0, None),
            "V.G.STATUS": (lambda i: 2.0, None),            # executing
            "V.G.FULLSTATUS": (lambda i: 525.0, None),      # $20D: executing, simulation
            "V.G.BLKN": (lambda i: float(s.last_n), None),
            "V.G.LINEN": (lambda i: float(s.executed_blocks), None),
            "V.G.FIRST": (lambda i: 1.0, None),
            "V.G.PARTC": (lambda i: float(s.parts), self._set_parts),
            "V.G.CYTIME": (lambda i: float(round(s.elapsed * 100.0)), None),
            "V.G.CLOCK": (lambda i: float(int(s.elapsed)), None),
            "V.G.SBOUT": (lambda i: 0.0, None),
            "V.G.SBLOCK": (lambda i: 0.0, None),
            "V.G.M01STOP": (lambda i: 0.0, None),
            "V.G.RAPID": (lambda i: 0.0, None),
        })
        program = ProgramVariables(self)   # V.G.R/I/J/K/CIRERR, EXTORG, MIRRORn, AXISNAMEn, MAXACCEL, TOR...
        self.plain_vars.update(program.plain())
        self.axis_vars.update(program.axis())
        self.plain_vars.update(kinematics_variables(s))   # V.MPK.*, V.G.POSROT*, V.G.TOOLORI*, V.G.TANGFEED
        self.axis_vars.update(kinematics_axis_variables())   # V.A.TANGAN, V.A.TGCTRLST
        for letter in "ABCDEFGHIJKLMNOPQRSTUVWXYZ":
            self.plain_vars[f"V.C.PCALLP_{letter}"] = (
                lambda i, x=letter: 1.0 if x in s.call_letters[-1] else 0.0, None)
        register_cycle_variables(self.plain_vars, s)   # V.C.A..Z, V.C.CALLP_x, V.G.CYCLETYPEON
        # spindle speeds (seed 002 L36721-L37300): V.A.<name>.<spindle> or V.SP.<name>[.<spindle>]
        self.spindle_vars: dict[str, Callable[[str], float]] = {
            "SPEED": lambda sp: s.speeds[sp] if s.modes["css"] != 96 else 0.0,
            "PRGS": lambda sp: s.speeds[sp] if s.modes["css"] != 96 else 0.0,
            "SREAL": lambda sp: s.speeds[sp] if s.spindle_state[sp] in (3, 4) and s.modes["css"] != 96 else 0.0,
            "CSS": lambda sp: s.speeds[sp] if s.modes["css"] == 96 else 0.0,
            "PRGCSS": lambda sp: s.speeds[sp] if s.modes["css"] == 96 else 0.0,
            "SLIMIT": lambda sp: float(s.planner.get("G192", 0.0) or 0.0),
            "PRGSL": lambda sp: float(s.planner.get("G192", 0.0) or 0.0),
        }
        self.spindle_vars.update(program.spindle())
        self.spindle_vars.update(spindle_config.variables(s))   # V.A.ACTCH.S (interp/spindle_config.py)
        # the tool table's other data: V.TM.DTYPE.., V.TM.*T[tl][ofd], V.G.NOSEA.., tool life (interp/toolvars.py)
        channel_vars = ChannelVariables(self)   # V.G.DYNOVR, ENDREP, SPDLREP, HSC, CONTERROR, A.INPOS...
        self.plain_vars.update(channel_vars.plain())
        self.axis_vars.update(channel_vars.axis())
        self.spindle_vars.update(channel_vars.spindle())
        before = set(self.plain_vars) | set(self.axis_vars)
        tools = ToolVariables(self)
        self.plain_vars.update(tools.plain(self.plain_vars))
        self.axis_vars.update(tools.axis())
        added = (set(self.plain_vars) | set(self.axis_vars)) - before
        #: the names whose read stops block preparation, and the ones whose write does too (L17437)
        channel = ChannelVariables.EXECUTION
        self.execution = EXECUTION_READS | ProgramVariables.EXECUTION | channel | ToolVariables.execution(added)
        self.write_sync = ProgramVariables.EXECUTION | channel | ToolVariables.execution(added)

    # ------------------------------------------------------------------
    def _tool_field(self, fld: str, any_tool: bool = False):
        """Getter and setter of an offset's field: of the active tool's offset ``[ofd]`` (the active one
        without an index), or with ``any_tool`` of the offset ``[tl][ofd]`` of any tool of the table."""
        st = self.state

        def offset_of(index: tuple):
            if any_tool:
                tool = _index(index[0])
                d = _index(index[1]) if len(index) > 1 else st.offset
            else:
                tool, d = st.tool, _index(index[0]) if index else st.offset
            off = st.tools.get(tool, {}).get(d)
            if off is None:
                raise InterpError("INT051", f"tool T{tool} has no offset D{d}", 1)
            return off

        def get(index: tuple) -> float:
            return getattr(offset_of(index), fld) / self._unit()

        def put(index: tuple, value: float) -> None:
            off = offset_of(index)
            setattr(off, fld, value * self._unit())
            off.declared = True   # written by the program: the offset now exists

        return get, put

    def _unit(self, axis: str | None = None) -> float:
        """mm per unit of the program's lengths: 25.4 under G70 (inch), 1 under G71 or for a rotary axis.
        A program reads and writes positions, origins and tool sizes in the units it is written in, so
        that 'G1 X[V.A.PPOS.X]' stays where it is (the interpreter keeps millimetres)."""
        st = self.state
        if st.modes["units"] != 70 or (axis is not None and st.machine.axes[axis].rotary):
            return 1.0
        return INCH

    def _feed(self, mode: int) -> float:
        """Programmed feed of a feed mode, in the active unit (0 if that mode is not active)."""
        st = self.state
        if st.modes["feed"] != mode or st.feed_programmed is None:
            return 0.0
        return st.feed_programmed

    def _set_override(self, index: tuple, value: float) -> None:
        if not 0 <= value <= 200:
            raise InterpError("INT045", f"feed override {value:g} % must be 0..200", 1)
        self.state.programmed_override = value

    def _set_parts(self, index: tuple, value: float) -> None:
        n = whole(value)
        if n is None or n < 0:
            raise InterpError("INT045", f"V.G.PARTC = {value:g}: the part count is a whole number", 1)
        self.state.parts = n

    def _spindle(self, token: str | None, col: int) -> str:
        spindles = list(self.state.speeds)
        if token is None:   # V.SP.x: the master spindle (L17714, L22408)
            master = self.state.master_spindle()
            if master is None:
                raise InterpError("INT046", "this channel has no spindle" if spindles else "this machine has no "
                                  "spindle", col)
            return master
        named = self.state.spindle_config.variable(token)   # after #RENAME SP the program uses the new name (L15209)
        if named is not None:
            return named
        if token.isdigit() and 1 <= int(token) <= len(spindles):
            return spindles[int(token) - 1]
        raise InterpError("INT046", f"spindle {token} does not exist on this machine", col)

    def _plane_code(self, index: tuple) -> float:
        a, o, _ = self.state.plane_axes()
        return float(100 * _axis_code(a) + _axis_code(o))

    def _active_g(self) -> set[int]:
        st = self.state
        active = {v for v in st.modes.values() if v is not None}
        origin = st.origin_source
        if origin.startswith("G159="):
            active.add(159)
        elif origin[1:].isdigit():
            active.add(int(origin[1:]))
        # functions without a modal group that stay active while their effect lasts (L40147)
        tr = st.transform
        if any(st.inc_offset.values()):
            active.add(158)
        if tr.angle:
            active.add(73)
        if tr.scale != 1.0:
            active.add(72)
        active.update(n for n, axis in ((11, "X"), (12, "Y"), (13, "Z")) if axis in tr.mirror)
        return active

    def _g_state(self, index: tuple) -> float:
        return 1.0 if _index(index[0]) in self._active_g() else 0.0

    def _m_state(self, index: tuple) -> float:
        m = _index(index[0])
        spindle = self.state.spindle_state.get(self.state.master_spindle(), 5)
        return 1.0 if m in (3, 4, 5) and m == spindle else 0.0

    def _hgs(self, k: int) -> int:
        """V.G.HGSk: bit b is G(32(k-1)+b) (seed 002 L40179-L40258)."""
        word = 0
        for g in self._active_g():
            if 32 * (k - 1) <= g < 32 * k:
                word |= 1 << (g - 32 * (k - 1))
        return word

    def _set_fix(self, index: tuple, value: float) -> None:
        n = whole(value)
        if n is None or not 0 <= n <= 10:
            raise InterpError("INT045", f"V.G.FIX = {value:g}: the fixture number must be 0..10", 1)
        self.state.fixture = n

    def _axis(self, token: str, col: int) -> str:
        axes = self.state.axes
        renamed = self.state.channel.by_name.get(token)   # after #RENAME AX the program uses the new name (L15025)
        if renamed is not None:
            return renamed
        if token in axes:
            return token
        if token.isdigit() and 1 <= int(token) <= len(axes):
            return axes[int(token) - 1]
        raise InterpError("INT046", f"axis {token} does not exist in this channel", col)

    def _resolve(self, name: str, index: tuple, col: int):
        channel = name.startswith("V.[].")
        if channel:
            if index and index[0] != 1:
                raise InterpError("INT047", f"channel {index[0]:g} does not exist (one channel offline)", col)
            name, index = "V." + name[5:], index[1:]
        if name.startswith(("V.P.", "V.S.")):
            return ("user", name, index)
        if name in self.plain_vars:
            return ("plain", name, index)
        head, _, tail = name.rpartition(".")
        if head in self.axis_vars and tail and tail[0] != "S":   # V.A.x.S: a spindle's, below
            return ("axis", head, (index, self._axis(tail, col)))
        parts = name.split(".")
        if len(parts) in (3, 4) and parts[1] in ("A", "SP") and parts[2] in self.spindle_vars:
            if parts[1] == "A" and len(parts) == 3:
                raise InterpError("INT044", f"{name} needs the spindle: {name}.S", col)
            spindle = self._spindle(parts[3] if len(parts) == 4 else None, col)
            return ("spindle", parts[2], spindle)
        found = self.machine_parameters.find(name, index, channel, col)
        if found is not None:
            return ("mp", found[0], found[1:])
        if "[" not in name and (f"{name}[]" in self.plain_vars or f"{name}[]" in self.axis_vars):
            # V.G.CIRERR is V.G.CIRERR[1] or [2] (L40483): a missing index, not a variable fagorcnc lacks
            raise InterpError("INT244", f"{name} needs its index: {name}[1]", col)
        from .vcatalogue import interface_only, manual_defined  # on first use: the error path of an unknown name
        only = interface_only(name)
        if only is not None:
            raise InterpError("INT241", f"{name.replace('[]', '[..]')} is read by the PLC or the interface only, not "
                              f"by a part program (seed 002 {only})", col)
        defined = manual_defined(name)
        if defined is not None:
            raise InterpError("INT240", f"{name.replace('[]', '[..]')} is a variable of the manual (seed 002 "
                              f"{defined}) that fagorcnc does not implement", col)
        raise InterpError("INT044", f"unknown variable {name.replace('[]', '[..]')}", col)

    def get(self, name: str, index: tuple, col: int = 1) -> float:
        kind, key, extra = self._resolve(name, index, col)
        if key in self.execution:
            self.state.sync = True   # the interpreter stops the motion before this block (see EXECUTION_READS)
        if kind == "user":
            try:
                return self.state.user_vars[key]
            except KeyError:
                raise InterpError("INT043", f"variable {key} has no value yet (use EXIST[{key}])", col) from None
        if kind == "plain":
            try:
                return self.plain_vars[key][0](extra)
            except InterpError as exc:
                exc.col = col
                raise
        if kind == "mp":
            return self.machine_parameters.read(key, extra[0], extra[1], col)
        if kind == "spindle":
            entry = self.spindle_vars[key]
            return entry[0](extra) if type(entry) is tuple else entry(extra)
        idx, axis = extra
        if axis in self.moving_alone and key in self.execution and self.warn is not None:
            # L16615-L16623: the axis's own interpolator may still be positioning it when the general motion
            # stops for this read; offline its #MOVE has no instant to be read at, so the end is given
            self.warn("INT235", "warning", f"{key}.{axis} is read while the #MOVE of line {self.moving_alone[axis]} "
                      f"may still be positioning {axis} (its own interpolator, L16615): fagorcnc gives the end of "
                      f"that positioning, the machine the position at that moment; program #SYNC POS before "
                      f"reading it", col)
        try:
            return self.axis_vars[key][0](self.state, tuple(_index(x) for x in idx), axis) / self._unit(axis)
        except InterpError as exc:
            exc.col = col
            raise

    def set(self, name: str, index: tuple, value: float, col: int = 1) -> None:
        kind, key, extra = self._resolve(name, index, col)
        if kind == "user":
            self.state.user_vars[key] = value
            return
        if kind == "plain":
            setter = self.plain_vars[key][1]
            if setter is None:
                raise InterpError("INT048", f"{key} is read-only", col)
            if key in self.write_sync:
                self.state.sync = True   # the write of an execution variable stops block preparation (L17437)
            try:
                setter(extra, value)
            except InterpError as exc:
                exc.col = col
                raise
            return
        if kind == "mp":
            self.machine_parameters.write(key, extra[0], extra[1], value, col)
            return
        if kind == "spindle":
            entry = self.spindle_vars[key]
            if type(entry) is not tuple or entry[1] is None:
                raise InterpError("INT048", f"{name} is read-only", col)
            entry[1](extra, value)   # V.A.PRGSSO.S (seed 002 L37200)
            return
        idx, axis = extra
        setter = self.axis_vars[key][1]
        if setter is None:
            raise InterpError("INT048", f"{key}.{axis} is read-only", col)
        if key in self.write_sync:
            self.state.sync = True   # V.TM.TOFL[..].X: an execution variable (L37503)
        try:
            setter(self.state, tuple(_index(x) for x in idx), axis, value * self._unit(axis))
        except InterpError as exc:
            exc.col = col
            raise

    def exists(self, name: str, index: tuple) -> bool:
        try:
            kind, key, _ = self._resolve(name, index, 1)
        except InterpError:
            return False
        return key in self.state.user_vars if kind == "user" else True

    def delete(self, name: str, index: tuple, col: int) -> None:
        """#DELETE of a user variable (seed 002 L1839-L1845)."""
        kind, key, _ = self._resolve(name, index, col)
        if kind != "user":
            raise InterpError("INT049", f"#DELETE only deletes user variables V.P.. and V.S.., not {key}", col)
        self.state.user_vars.pop(key, None)
