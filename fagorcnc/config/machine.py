"""Machine configuration: axes, limits, power-on defaults, origin and tool tables.

A :class:`Machine` is built from a TOML file or an equivalent ``dict``;
whatever it leaves out comes from the shipped default machine (three linear
axes X Y Z).  The power-on modal defaults use the manual's machine-parameter
names (``INCHES``, ``ISYSTEM``, ``IPLANE``, ``IMOVE``, ``IFEED``, ``ICORNER``,
``IRCOMP``...; spec 07 §B.3.3, seed 002 L18497, L20013-L20175).

Units: lengths in mm, linear speeds in mm/min, rotary in degrees and deg/min,
accelerations in mm/s², jerks in mm/s³, times in s.
"""

from __future__ import annotations

import copy
import math
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from .compat import Compat, parse_compat
from .errors import MachineError

#: Power-on / reset defaults: parameter -> (default value, allowed values, meaning).
DEFAULTS_SCHEMA: dict[str, tuple[int, tuple, str]] = {
    "INCHES": (0, (0, 1), "0 = G71 millimetres, 1 = G70 inches (seed 002 L2434)"),
    "ISYSTEM": (0, (0, 1), "0 = G90 absolute, 1 = G91 incremental (L2482)"),
    "IPLANE": (0, (0, 1), "0 = G17, 1 = G18 (L2995)"),
    "IMOVE": (0, (0, 1), "0 = G00, 1 = G01 (L6022)"),
    "IFEED": (0, (0, 1), "0 = G94, 1 = G95 (L4182)"),
    "ICORNER": (0, (0, 1, 2), "0 = G50, 1 = G05, 2 = G07 (L20157; spec 07 §B.11 default 0)"),
    "IRCOMP": (0, (0, 1), "0 = G136, 1 = G137 (L9591)"),
    "MIRRORCANCEL": (1, (0, 1), "1 = M30/reset cancel mirror images (L8779)"),
    "SPDLSTOP": (1, (0, 1), "1 = M02/M30 stop the spindle (L867)"),
    "DEFAULTFEED": (0, (0, 1), "1 = G1/G2/G3 without F use MAXFEED (L4062)"),
    "SREVM05": (0, (0, 1), "1 = with G84 the spindle stops (M05) before it reverses (L21990-L21997)"),
}


@dataclass
class Axis:
    """One axis of the channel (spec 07 §B.4-B.5)."""

    name: str
    type: str = "linear"            # "linear" or "rotary"
    max_velocity: float = 10000.0   # mm/min or deg/min (G00FEED)
    max_feed: float = 0.0           # MAXFEED of the axis; 0 = max_velocity
    max_acceleration: float = 1000.0  # mm/s²
    max_jerk: float = 20000.0       # mm/s³
    min_limit: float = -1000.0      # soft limits, machine coordinates
    max_limit: float = 1000.0
    diameter: bool = False          # DIAMPROG: G151 programs diameters
    rotary_mode: str = "linearlike"  # linearlike | normal | unidirectional | positioning
    module: float = 360.0           # rotary module (MODUPLIM - MODLOWLIM)
    direction: int = 1              # unidirectional rotary: +1 or -1
    home: float = 0.0               # machine coordinate of the reference point (G74)
    exchange: int = 1               # AXISEXCH: 0 may not change channel, 1 temporary, 2 permanent (L14694)
    #: parameter sets 2.. (G112, seed 002 L9307-L9360: up to 4 per axis): each a dict of the dynamic fields
    #: it changes (SET_FIELDS); set 1 is the axis's own values
    sets: tuple = ()
    default_set: int = 1            # DEFAULTSET: the set assumed at power-on, M02/M30 and reset; 0 keeps G112's

    @property
    def rotary(self) -> bool:
        return self.type == "rotary"

    @property
    def nsets(self) -> int:
        """NPARSETS: how many parameter sets the axis has."""
        return 1 + len(self.sets)

    def dynamics(self, number: int = 1) -> tuple[float, float, float, float]:
        """``(max_velocity, max_feed, max_acceleration, max_jerk)`` of parameter set ``number`` (1-based)."""
        own = (self.max_velocity, self.max_feed, self.max_acceleration, self.max_jerk)
        if number <= 1 or number > self.nsets:
            return own
        extra = self.sets[number - 2]
        return tuple(extra.get(k, v) for k, v in zip(SET_FIELDS, own, strict=True))   # type: ignore[return-value]


#: The dynamic fields of an axis a parameter set may change (G00FEED, MAXFEED, ACCEL, ACCJERK).
SET_FIELDS = ("max_velocity", "max_feed", "max_acceleration", "max_jerk")
#: G112 selects one of at most this many parameter sets per axis (seed 002 L9309).
MAX_SETS = 4


@dataclass
class ToolOffset:
    """One offset D of a tool: length, radius and their wear (mm)."""

    length: float = 0.0
    radius: float = 0.0
    length_wear: float = 0.0
    radius_wear: float = 0.0
    # the manual's other fields of an offset (fagorcnc.config.tooldata; seed 002 L37710-L38130)
    type: int = 1                    # DTYPE: 1 milling .. 8 turning .. 10 probe
    subtype: int = 0                 # DSUBTYPE
    turn_config: int = 0             # TURNCONFIG (turning tools)
    location_code: int = 0           # LOCODE (turning tools)
    holder_orientation: int = 0      # FIXORI
    spindle_direction: int = 0       # SPDLTURDIR
    plunge_angle: float = 0.0        # TOAN, degrees
    tip_radius: float = 0.0          # TOTIPR, mm
    tip_radius_wear: float = 0.0     # TOWTIPR, mm
    cutting_length: float = 0.0      # TOCUTL, mm
    nose_angle: float = 0.0          # NOSEA, degrees
    nose_width: float = 0.0          # NOSEW, mm
    cutting_angle: float = 0.0       # CUTA, degrees
    life_monitoring: int = 0         # TOMON: 0 none, 1 machining time, 2 operations
    nominal_life: float = 0.0        # TLFN
    real_life: float = 0.0           # TLFR
    axis_offsets: dict = field(default_factory=dict)        # TOFL: axis -> mm
    axis_offsets_wear: dict = field(default_factory=dict)   # TOFLW: axis -> mm
    #: False for the default machine's zero-size placeholder of an offset the machine's own tool table
    #: leaves out: radius or length compensation with it is an error (the control has no such offset)
    declared: bool = field(default=True, compare=False)

    def __deepcopy__(self, memo: dict) -> ToolOffset:
        """What ``copy.deepcopy`` makes (the numbers shared, the axis tables copied), quicker: every
        channel state copies the machine's tool table, a hundred offsets for the default machine."""
        new = object.__new__(type(self))
        new.__dict__.update({k: v if type(v) in _ATOMIC else copy.deepcopy(v, memo) for k, v in self.__dict__.items()})
        return new


#: Types ``copy.deepcopy`` returns as they are.
_ATOMIC = frozenset({int, float, bool, str, type(None)})


@dataclass
class Limits:
    """Guards against runaway programs, ``[limits]`` in TOML (README "Runaway guards")."""

    max_loop_iterations: int = 1_000_000   # per loop instance; also the largest NR and #RPT count
    max_blocks: int = 100_000_000          # executed blocks per run (NR repetitions included)
    max_call_depth: int = 20               # subroutine nesting (seed 002 L10207)
    max_parameter_levels: int = 7          # local parameter levels (seed 002 L10503)
    # Seconds of interpretation per run, in CPU time of the interpreting process (the time the
    # planner or a machine holds the records does not count, nor time spent waiting for a busy
    # CPU); 0 = none.  None by default: the machine file also drives real runs,
    # where a long program is legitimate and must not be cut by a timer.  `fagorcnc check`
    # applies its own default when this is 0 (check.CHECK_MAX_SECONDS).
    max_seconds: float = 0.0
    # Warnings and notes kept per run (a #MSG in an endless $GOTO loop would otherwise fill
    # the memory); errors are always kept; 0 = no limit.
    max_messages: int = 10_000


@dataclass
class PlannerConfig:
    """Channel parameters the planner uses (spec 07 §B.3, §B.12); ``[planner]`` in TOML."""

    servo_period: float = 0.001     # s, sampling period of the trajectory
    slope_type: int = 1             # SLOPETYPE: 0 linear (no jerk limit), 1 trapezoidal, 2 square sine (L19967)
    round_type: int = 0             # ROUNDTYPE: 0 chordal error MAXROUND, 1 feed percentage ROUNDFEED (L20276)
    max_round: float = 0.01         # mm, MAXROUND: G05 rounding error (L20276)
    round_feed: float = 100.0       # %, ROUNDFEED (L20286)
    hsc_default_mode: int = 1       # HSCDEFAULTMODE: 0 SURFACE, 1 CONTERROR, 2 FAST (L19804)
    hsc_round: float = 0.01         # mm, HSCROUND: default HSC tolerance (L19784)
    corner: float = 150.0           # degrees, CORNER: sharp-edge angle in HSC (L19668)
    fast_factor: float = 100.0      # %, FASTFACTOR (L19688)
    min_corner_feed: float = 0.0    # mm/min, MINCORFEED (L19723); informative
    feed_override: float = 100.0    # %, feed override applied to G01/G02/G03 (0-200)
    rapid_override: float = 100.0   # %, override of G00 (never above 100, L20355)
    inposition_time: float = 0.0    # s, settle time after a G07/G60 stop (INPOSW wait)
    max_path_acceleration: float = 0.0   # mm/s², MAXACCEL on the path; 0 = none (L20873)
    max_path_jerk: float = 0.0           # mm/s³, MAXJERK on the path; 0 = none (L20883)
    lookahead: int = 2000           # segments kept in the look-ahead window at most


@dataclass
class Machine:
    """A machine configuration.  Build with :func:`load_machine`."""

    axes: dict[str, Axis]
    spindles: list[str] = field(default_factory=lambda: ["S"])
    defaults: dict[str, int] = field(default_factory=dict)
    local_params: tuple[int, int] = (0, 25)        # MINLOCP..MAXLOCP (L1876)
    global_params: tuple[int, int] = (100, 299)    # MINGLBP..MAXGLBP (L1888)
    common_params: tuple[int, int] = (10000, 10999)  # MINCOMP..MAXCOMP (L1897)
    origins: dict[int, dict[str, float]] = field(default_factory=dict)   # G159=n table (1..99)
    fixtures: dict[int, dict[str, float]] = field(default_factory=dict)  # V.A.FIXT[n] (1..10)
    tools: dict[int, dict[int, ToolOffset]] = field(default_factory=dict)  # tool -> D -> offset
    tool_data: dict = field(default_factory=dict)   # tool -> tooldata.ToolData (TSTATUS, TLFF, TOTP1-4)
    max_feed: float = 0.0        # channel MAXFEED, 0 = not limited (L20762)
    rapid_feed: float = 0.0      # channel rapid; 0 = from the axes' max_velocity
    servo_period: float = 0.001  # s
    cirinerr: float = 0.01       # mm, arc radius tolerance (L20298)
    cirinfact: float = 0.1       # %, relative arc radius tolerance (L20308)
    subroutine_paths: list[Path] = field(default_factory=list)
    oem_subroutines: dict[int, str] = field(default_factory=dict)  # G180.., G500.. -> file name
    oem_builtins: dict[int, str] = field(default_factory=dict)  # G500..G599 -> "smoothing_on" | "smoothing_off"
    m_functions: dict[int, str] = field(default_factory=dict)  # M table: number -> "before" | "after"
    limits: Limits = field(default_factory=Limits)
    planner: PlannerConfig = field(default_factory=PlannerConfig)
    backends: dict[str, dict] = field(default_factory=dict)   # [backends.<name>] tables, read by each back-end
    parameter_file: Path | None = None   # global/common parameters kept between runs (fagorcnc.config.parameter_file)
    compat: Compat = field(default_factory=Compat)   # [compat]: CAM constructs and lint (fagorcnc.config.compat)
    kinematics: list = field(default_factory=list)   # [[kinematics]]: fagorcnc.config.kinematics.Kinematics
    kinid: int = 0               # KINID: the kinematics selected at power-on (0 = none)
    kinematics_tolerance: float = 0.001   # mm: tool-tip deviation of transformed moves cut into joint lines
    angular_axes: list = field(default_factory=list)   # [[angular_axes]]: fagorcnc.config.kinematics (#ANGAX)
    c_axes: dict[str, str] = field(default_factory=dict)   # c_axis = { S = "C" }: spindle -> its C axis (#CAX)
    #: CHAXISNAME: the axes of the channel at power-on, in order (slot 1 first); the machine's other axes
    #: are free for #CALL AX / #SET AX (seed 002 L14690).  Empty: all the axes, in the order of ``axes``.
    channel_axes: list[str] = field(default_factory=list)
    #: CHSPDLNAME: the spindles of the channel at power-on (seed 002 L15054-L15055); the machine's other
    #: spindles are free for #CALL SP / #SET SP.  Empty: all the spindles, in the order of ``spindles``.
    channel_spindles: list[str] = field(default_factory=list)
    #: [machine_parameters]: values of the manual's parameters fagorcnc does not use, for V.MPG/MPA/MPMAN
    #: reads: (name, indices, axis or spindle) -> value (fagorcnc.config.mpcatalogue)
    machine_parameters: dict[tuple, float] = field(default_factory=dict)
    mtb: list[float] = field(default_factory=list)   # "MTB.P" = [...]: the OEM parameters MTB.P[0..] (L29198)

    def default(self, name: str) -> int:
        """Value of a power-on default parameter (``INCHES``, ``IPLANE``...)."""
        return self.defaults.get(name, DEFAULTS_SCHEMA[name][0])

    @property
    def axis_names(self) -> list[str]:
        """Axis names in channel order (``?1`` is the first)."""
        return list(self.axes)

    def tool_offset(self, tool: int, offset: int) -> ToolOffset | None:
        return self.tools.get(tool, {}).get(offset)


DEFAULT_MACHINE: dict[str, Any] = {
    "axes": {
        "X": {"type": "linear", "max_velocity": 10000.0, "min_limit": -1000.0, "max_limit": 1000.0},
        "Y": {"type": "linear", "max_velocity": 10000.0, "min_limit": -1000.0, "max_limit": 1000.0},
        "Z": {"type": "linear", "max_velocity": 10000.0, "min_limit": -1000.0, "max_limit": 1000.0},
    },
    "spindles": ["S"],
    "tools": {str(t): {"1": {"length": 0.0, "radius": 0.0}} for t in range(0, 100)},
}


#: The default machine's offset of a tool a machine file's own tool table leaves out (see ToolOffset.declared).
_PLACEHOLDER = {"length": 0.0, "radius": 0.0}


def _over_default(user: dict) -> dict:
    """``user`` merged over the default machine; with a tool table of its own, the default's tools it
    does not list stay selectable but are marked as placeholders."""
    data = _merge(DEFAULT_MACHINE, user)
    own = user.get("tools")
    if isinstance(own, dict):
        listed = {(str(t), str(d)) for t, offs in own.items() if isinstance(offs, dict) for d in offs}
        for t, offs in data["tools"].items():
            if not isinstance(offs, dict):   # a wrong type: _tools says so, naming the key
                continue
            for d in offs:
                if (str(t), str(d)) not in listed:
                    offs[d] = _PLACEHOLDER
    return data


def _merge(base: dict, over: dict) -> dict:
    out = copy.deepcopy(base)
    for key, value in over.items():
        if isinstance(value, dict) and isinstance(out.get(key), dict) and key != "axes":
            out[key] = _merge(out[key], value)
        else:
            out[key] = copy.deepcopy(value)
    return out


def _number(where: str, value: Any) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value):
        raise MachineError(f"{where}: expected a number, got {value!r}")
    return float(value)


def _table(where: str, value: Any) -> dict:
    """``value`` when it is a table (a dict), else a :class:`MachineError` naming ``where``."""
    if not isinstance(value, dict):
        raise MachineError(f"{where}: expected a table, got {value!r}")
    return value


def _text(where: str, value: Any) -> str:
    if not isinstance(value, str):
        raise MachineError(f"{where}: expected a text in quotes, got {value!r}")
    return value


def _flag(where: str, value: Any) -> bool:
    """true/false (0 and 1 are taken too: INI-style files write them)."""
    if isinstance(value, bool):
        return value
    if isinstance(value, int) and value in (0, 1):
        return bool(value)
    raise MachineError(f"{where}: expected true or false, got {value!r}")


def _entry(where: str, key: Any, low: int, high: int) -> int:
    """A table key that is an entry number (``tools.5``, ``fixtures.2``): a whole number in [low, high]."""
    text = str(key).strip()
    if isinstance(key, bool) or not (isinstance(key, int) or text.isdigit()):
        raise MachineError(f"{where}.{key}: the key must be a number {low}..{high}")
    n = int(text) if len(text) <= 12 else high + 1
    if not low <= n <= high:
        raise MachineError(f"{where}.{key}: the number must be {low}..{high}")
    return n


#: Axis names of the manual: X Y Z U V W A B C, optionally followed by a digit 1-9 (seed 002 L1196-L1199).
_AXIS_NAME = re.compile(r"[XYZUVWABC][1-9]?")
#: Spindle names: S, S1...S9 (seed 002 L1080-L1090).
_SPINDLE_NAME = re.compile(r"S[1-9]?")


def _axis_table(where: str, table: Any, axes: dict | None = None) -> dict[str, float]:
    if not isinstance(table, dict):
        raise MachineError(f"{where}: expected a table of axis values, e.g. {{ X = 10.0 }}, got {table!r}")
    out = {}
    for k, v in table.items():
        if axes is not None and str(k) not in axes:
            raise MachineError(f"{where}.{k}: the machine has no axis {k} (axes: {' '.join(axes)})")
        out[str(k)] = _number(f"{where}.{k}", v)
    return out


def _axis(name: Any, spec: Any) -> Axis:
    if not isinstance(name, str) or not _AXIS_NAME.fullmatch(name):
        raise MachineError(f"axes.{name}: an axis is named X Y Z U V W A B C, optionally followed by a digit "
                           "1-9 (seed 002 L1196)")
    spec = _table(f"axes.{name}", spec)
    known = set(Axis.__dataclass_fields__) - {"name"}
    unknown = set(spec) - known
    if unknown:
        raise MachineError(f"axes.{name}: unknown key(s) {', '.join(sorted(map(str, unknown)))}")
    kwargs: dict[str, Any] = {}
    for key, value in spec.items():
        where = f"axes.{name}.{key}"
        if key in ("type", "rotary_mode"):
            kwargs[key] = _text(where, value)
        elif key == "diameter":
            kwargs[key] = _flag(where, value)
        elif key == "direction":
            kwargs[key] = 1 if _number(where, value) >= 0 else -1
        elif key == "sets":
            kwargs[key] = _parameter_sets(where, value)
            continue
        elif key == "default_set":
            if isinstance(value, bool) or not isinstance(value, int) or not 0 <= value <= MAX_SETS:
                raise MachineError(f"{where} (DEFAULTSET) must be 0 (keep the set of G112) or a set 1-{MAX_SETS}, "
                                   f"got {value!r}")
            kwargs[key] = value
        elif key == "exchange":
            if isinstance(value, bool) or value not in (0, 1, 2):
                raise MachineError(f"{where} (AXISEXCH) must be 0 (no change of channel), 1 (temporary) or "
                                   f"2 (permanent), got {value!r}")
            kwargs[key] = int(value)
        else:
            kwargs[key] = _number(where, value)
    axis = Axis(name=name, **kwargs)
    if axis.type not in ("linear", "rotary"):
        raise MachineError(f"axes.{name}.type must be 'linear' or 'rotary', got {axis.type!r}")
    if axis.rotary_mode not in ("linearlike", "normal", "unidirectional", "positioning"):
        raise MachineError(f"axes.{name}.rotary_mode: unknown mode {axis.rotary_mode!r}")
    for key in ("max_velocity", "max_acceleration", "max_jerk", "module"):
        if not getattr(axis, key) > 0:
            raise MachineError(f"axes.{name}.{key} must be positive, got {getattr(axis, key):g}")
    if axis.min_limit > axis.max_limit:
        raise MachineError(f"axes.{name}: min_limit is above max_limit")
    if axis.default_set > axis.nsets:
        raise MachineError(f"axes.{name}.default_set {axis.default_set}: the axis has {axis.nsets} parameter set(s)")
    return axis


def _parameter_sets(where: str, value: Any) -> tuple:
    """``sets = [{ max_velocity = 6000, max_acceleration = 500 }, ...]``: parameter sets 2.. of an axis
    (G112; seed 002 L9309: at most 4 sets in all), each giving any of :data:`SET_FIELDS`."""
    sets = _list(where, value)
    if len(sets) > MAX_SETS - 1:
        raise MachineError(f"{where}: at most {MAX_SETS - 1} sets besides the axis's own (4 in all, seed 002 L9309)")
    out = []
    for i, entry in enumerate(sets):
        at = f"{where}[{i}] (set {i + 2})"
        table = _table(at, entry)
        unknown = set(table) - set(SET_FIELDS)
        if unknown:
            raise MachineError(f"{at}: unknown key(s) {', '.join(sorted(map(str, unknown)))}; a set gives "
                               f"{', '.join(SET_FIELDS)}")
        values = {k: _number(f"{at}.{k}", v) for k, v in table.items()}
        for k, v in values.items():
            if not (v > 0 or (k == "max_feed" and v == 0)):
                raise MachineError(f"{at}.{k} must be positive, got {v:g}")
        out.append(values)
    return tuple(out)


def _origin_entry(key: Any) -> int:
    k = str(key).strip().upper()
    if k in ("G54", "G55", "G56", "G57", "G58", "G59"):
        return int(k[1:]) - 53
    number = k[5:] if k.startswith("G159.") else k
    if not number.isdigit() or len(number) > 3:
        raise MachineError(f"origins.{key}: use G54..G59, 'G159.n' or n (n = 1..99)")
    n = int(number)
    if not 1 <= n <= 99:
        raise MachineError(f"origins.{key}: entry must be 1..99")
    return n


def _tools(table: Any, axes: dict) -> dict[str, dict]:
    """``tools``: tool -> D -> :class:`ToolOffset`, and the tools' own data (``status``, ``family``, ``custom``,
    :mod:`fagorcnc.config.tooldata`)."""
    from .tooldata import TOOL_KEYS, offset_field, tool_data

    tools: dict[int, dict[int, ToolOffset]] = {}
    data: dict = {}
    for tkey, offsets in _table("tools", table).items():
        t = _entry("tools", tkey, 0, 4294967295)
        offsets = _table(f"tools.{tkey}", offsets)
        own = {k: v for k, v in offsets.items() if k in TOOL_KEYS}
        if own:
            data[t] = tool_data(f"tools.{tkey}", own)
        for dkey, spec in offsets.items():
            if dkey in TOOL_KEYS:
                continue
            d = _entry(f"tools.{tkey}", dkey, 0, 4294967295)
            declared = spec is not _PLACEHOLDER   # see ToolOffset.declared
            spec = _table(f"tools.{tkey}.{dkey}", spec)
            unknown = set(spec) - (set(ToolOffset.__dataclass_fields__) - {"declared"})
            if unknown:
                raise MachineError(f"tools.{tkey}.{dkey}: unknown key(s) {', '.join(sorted(map(str, unknown)))}")
            fields = {k: _number(f"tools.{tkey}.{dkey}.{k}", v) if k in _SIZE_FIELDS
                      else offset_field(f"tools.{tkey}.{dkey}.{k}", k, v, axes) for k, v in spec.items()}
            tools.setdefault(t, {})[d] = ToolOffset(**fields, declared=declared)
    return {"tools": tools, "tool_data": data}


_SIZE_FIELDS = ("length", "radius", "length_wear", "radius_wear")


def _prange(data: dict, key: str, default: tuple[int, int], hard: tuple[int, int]) -> tuple[int, int]:
    """A parameter range ``[low, high]`` within the manual's bounds ``hard``."""
    value = data.get(key, default)
    if not isinstance(value, list | tuple) or len(value) != 2:
        raise MachineError(f"{key}: expected a range [low, high], e.g. [{default[0]}, {default[1]}], got {value!r}")
    lo, hi = (_number(f"{key}[{i}]", v) for i, v in enumerate(value))
    if lo != int(lo) or hi != int(hi):
        raise MachineError(f"{key}: the range's ends must be whole numbers, got {value!r}")
    if not (hard[0] <= lo <= hi <= hard[1]):
        raise MachineError(f"{key}: range must lie within P{hard[0]}..P{hard[1]}")
    return int(lo), int(hi)


def _list(where: str, value: Any) -> list:
    if not isinstance(value, list | tuple):
        raise MachineError(f"{where}: expected a list, e.g. [\"...\"], got {value!r}")
    return list(value)


def _spindles(value: Any) -> list[str]:
    out = []
    for i, s in enumerate(_list("spindles", value)):
        if not isinstance(s, str) or not _SPINDLE_NAME.fullmatch(s):
            raise MachineError(f"spindles[{i}]: a spindle is named S or S1..S9, got {s!r}")
        if s in out:
            raise MachineError(f"spindles[{i}]: spindle {s} is listed twice")
        out.append(s)
    if len(out) > 4:   # seed 002 L15051: "a maximum of four spindles" in the system
        raise MachineError(f"spindles: {len(out)} spindles; the CNC has at most four (seed 002 L15051)")
    return out


def _paths(value: Any) -> list[Path]:
    out = []
    for i, p in enumerate(_list("subroutine_paths", value)):
        if not isinstance(p, str | Path) or not str(p) or "\0" in str(p):
            raise MachineError(f"subroutine_paths[{i}]: expected a directory name, got {p!r}")
        out.append(Path(p))
    return out


def _defaults(table: Any) -> dict[str, int]:
    defaults = {}
    for key, value in _table("defaults", table).items():
        if key not in DEFAULTS_SCHEMA:
            raise MachineError(f"defaults.{key}: unknown parameter (known: {', '.join(DEFAULTS_SCHEMA)})")
        if isinstance(value, bool) or not isinstance(value, int | float) or value not in DEFAULTS_SCHEMA[key][1]:
            raise MachineError(f"defaults.{key} = {value!r}: {DEFAULTS_SCHEMA[key][2]}")
        defaults[key] = int(value)
    return defaults


def _build(data: dict) -> Machine:
    axes = {}
    for name, spec in _table("axes", data.get("axes", {})).items():
        axes[name] = _axis(name, spec)
    if not axes:
        raise MachineError("axes: the machine needs at least one axis")
    origins = {_origin_entry(key): _axis_table(f"origins.{key}", table)
               for key, table in _table("origins", data.get("origins", {})).items()}
    fixtures = {_entry("fixtures", key, 1, 10): _axis_table(f"fixtures.{key}", table)
                for key, table in _table("fixtures", data.get("fixtures", {})).items()}
    limits = _limits(data.get("limits", {}))
    planner = _planner(data.get("planner", {}), data.get("servo_period"))
    return Machine(
        axes=axes,
        spindles=_spindles(data.get("spindles", ["S"])),
        defaults=_defaults(data.get("defaults", {})),
        local_params=_prange(data, "local_params", (0, 25), (0, 99)),
        global_params=_prange(data, "global_params", (100, 299), (100, 9999)),
        common_params=_prange(data, "common_params", (10000, 10999), (10000, 19999)),
        origins=origins,
        fixtures=fixtures,
        **_tools(data.get("tools", {}), axes),
        max_feed=_number("max_feed", data.get("max_feed", 0.0)),
        rapid_feed=_number("rapid_feed", data.get("rapid_feed", 0.0)),
        servo_period=planner.servo_period,
        cirinerr=_number("cirinerr", data.get("cirinerr", 0.01)),
        cirinfact=_number("cirinfact", data.get("cirinfact", 0.1)),
        subroutine_paths=_paths(data.get("subroutine_paths", [])),
        **_oem_table(data.get("oem_subroutines", {})),
        m_functions=_m_table(data.get("m_functions", {})),
        limits=limits,
        planner=planner,
        backends=_backends(data.get("backends", {})),
        parameter_file=_parameter_file(data.get("parameter_file")),
        compat=parse_compat(data.get("compat", {})),
        **_kinematics(data, axes),
        **_machine_parameters(data.get("machine_parameters", {}), axes, data.get("spindles", ["S"])),
        channel_axes=_channel_axes(data.get("channel_axes", []), axes),
        channel_spindles=_channel_spindles(data.get("channel_spindles", []), data.get("spindles", ["S"])),
    )


def _machine_parameters(table: Any, axes: dict, spindles: Any) -> dict:
    """``[machine_parameters]``: ``"MPA.FFGAIN.X" = 100``, ``"MPG.PRB1MIN" = -10``, ``"MTB.P" = [1.5, 2]``
    (the manual's names; fagorcnc.config.mpcatalogue)."""
    values: dict[tuple, float] = {}
    mtb: list[float] = []
    for key, value in _table("machine_parameters", table).items():
        where = f"machine_parameters.{key}"
        if key == "MTB.P":
            mtb = [_number(f"{where}[{i}]", v) for i, v in enumerate(_list(where, value))]
            continue
        from .mpcatalogue import parse_key  # on first use: the default machine has no such table

        parsed = parse_key(str(key))
        if isinstance(parsed, str):
            raise MachineError(f"{where}: {parsed}")
        entry, idx, target = parsed
        if target is not None and target not in axes and target not in [str(x) for x in spindles]:
            raise MachineError(f"{where}: the machine has no axis or spindle {target}")
        values[(entry.name, idx, target)] = _number(where, value)
    return {"machine_parameters": values, "mtb": mtb}


def _channel_axes(value: Any, axes: dict) -> list[str]:
    """``channel_axes = ["X", "Y", "Z"]``: the channel's axes at power-on (CHAXISNAME)."""
    out = []
    for i, a in enumerate(_list("channel_axes", value)):
        if not isinstance(a, str) or a not in axes:
            raise MachineError(f"channel_axes[{i}]: the machine has no axis {a!r} (axes: {' '.join(axes)})")
        if a in out:
            raise MachineError(f"channel_axes[{i}]: axis {a} is listed twice")
        out.append(a)
    return out


def _channel_spindles(value: Any, spindles: Any) -> list[str]:
    """``channel_spindles = ["S"]``: the channel's spindles at power-on (CHSPDLNAME); ``[]`` is all of them."""
    names = [str(x) for x in spindles] if isinstance(spindles, list | tuple) else []
    out = []
    for i, s in enumerate(_list("channel_spindles", value)):
        if not isinstance(s, str) or s not in names:
            raise MachineError(f"channel_spindles[{i}]: the machine has no spindle {s!r} (spindles: "
                               f"{' '.join(names) or 'none'})")
        if s in out:
            raise MachineError(f"channel_spindles[{i}]: spindle {s} is listed twice")
        out.append(s)
    return out


#: the built-in behaviours a G500..G599 may be mapped to (fagorcnc.interp.compat)
OEM_BUILTINS = ("smoothing_on", "smoothing_off")


def _oem_table(table: Any) -> dict[str, dict[int, str]]:
    """``oem_subroutines``: G180-G189, G380-G399 and G500-G599 -> a file name, or (G500-G599)
    ``{ builtin = "smoothing_on" }`` / ``{ builtin = "smoothing_off" }``."""
    if not isinstance(table, dict):
        raise MachineError('oem_subroutines: expected a table, e.g. {180 = "file.nc", '
                           '501 = { builtin = "smoothing_on" }}')
    files: dict[int, str] = {}
    builtins: dict[int, str] = {}
    for key, value in table.items():
        try:
            n = int(str(key).upper().removeprefix("G"))
        except ValueError:
            raise MachineError(f"oem_subroutines.{key}: expected a G number (180..189, 380..399, 500..599)") from None
        if not (180 <= n <= 189 or 380 <= n <= 399 or 500 <= n <= 599):
            raise MachineError(f"oem_subroutines.{key}: G{n} is not an OEM function (180..189, 380..399, 500..599)")
        if isinstance(value, dict):
            behaviour = value.get("builtin")
            if set(value) != {"builtin"} or behaviour not in OEM_BUILTINS:
                raise MachineError(f"oem_subroutines.{key}: expected a file name or "
                                   f"{{ builtin = \"{OEM_BUILTINS[0]}\" }} / {{ builtin = \"{OEM_BUILTINS[1]}\" }}")
            if n < 500:
                raise MachineError(f"oem_subroutines.{key}: built-in behaviours are for G500..G599 only")
            builtins[n] = behaviour
        elif isinstance(value, str) and value and "\0" not in value:
            files[n] = value
        else:
            raise MachineError(f"oem_subroutines.{key}: expected a file name, got {value!r}")
    return {"oem_subroutines": files, "oem_builtins": builtins}


def _kinematics(data: dict, axes: dict) -> dict:
    """``[[kinematics]]``, ``kinid`` and ``kinematics_tolerance`` (fagorcnc.config.kinematics)."""
    from .kinematics import parse_angular_axes, parse_c_axes, parse_kinematics, parse_kinid

    kins = parse_kinematics(data.get("kinematics"), axes)
    tol = _number("kinematics_tolerance", data.get("kinematics_tolerance", 0.001))
    if not 1e-6 <= tol <= 1.0:
        raise MachineError(f"kinematics_tolerance = {tol:g}: mm between 0.000001 and 1")
    return {"kinematics": kins, "kinid": parse_kinid(data.get("kinid"), kins), "kinematics_tolerance": tol,
            "angular_axes": parse_angular_axes(data.get("angular_axes"), axes),
            "c_axes": parse_c_axes(data.get("c_axis"), axes, [str(x) for x in data.get("spindles", ["S"])])}


def _parameter_file(value: Any) -> Path | None:
    if value is None or value == "":
        return None
    if not isinstance(value, str | Path):
        raise MachineError(f"parameter_file: expected a file name, got {value!r}")
    return Path(value)


def _backends(table: Any) -> dict[str, dict]:
    if not isinstance(table, dict) or not all(isinstance(v, dict) for v in table.values()):
        raise MachineError("backends: expected one table per back-end, e.g. [backends.interpcnc]")
    return {str(k): dict(v) for k, v in table.items()}


#: Allowed ranges of the [limits] keys: (low, high, integer?)
_LIMIT_RANGES = {
    "max_loop_iterations": (1, 1e12, True), "max_blocks": (1, 1e15, True), "max_call_depth": (1, 10_000, True),
    "max_parameter_levels": (1, 10_000, True), "max_seconds": (0.0, 1e7, False), "max_messages": (0, 1e9, True),
}


def _limits(table: Any) -> Limits:
    return Limits(**_checked("limits", table, _LIMIT_RANGES))


def _checked(name: str, table: Any, ranges: dict[str, tuple[float, float, bool]]) -> dict[str, Any]:
    """The keys of table ``[name]``, each checked against ``ranges`` (unknown key, type, whole number, range)."""
    if not isinstance(table, dict):
        raise MachineError(f"{name}: expected a table")
    unknown = set(table) - set(ranges)
    if unknown:
        raise MachineError(f"{name}: unknown key(s) {', '.join(sorted(unknown))}")
    out: dict[str, Any] = {}
    for key, value in table.items():
        lo, hi, integer = ranges[key]
        v = _number(f"{name}.{key}", value)
        if integer and v != int(v):
            raise MachineError(f"{name}.{key}: expected a whole number, got {value!r}")
        if not lo <= v <= hi:
            raise MachineError(f"{name}.{key} = {value!r}: must be between {lo:g} and {hi:g}")
        out[key] = int(v) if integer else v
    return out


#: Allowed ranges of the [planner] keys: (low, high, integer?)
_PLANNER_RANGES = {
    "servo_period": (1e-5, 1.0, False), "slope_type": (0, 2, True), "round_type": (0, 1, True),
    "max_round": (1e-6, 1000.0, False), "round_feed": (1e-3, 100.0, False), "hsc_default_mode": (0, 2, True),
    "hsc_round": (0.0, 1000.0, False), "corner": (0.0, 180.0, False), "fast_factor": (0.01, 100.0, False),
    "min_corner_feed": (0.0, 1e9, False), "feed_override": (0.0, 200.0, False), "rapid_override": (0.0, 100.0, False),
    "inposition_time": (0.0, 60.0, False), "max_path_acceleration": (0.0, 1e12, False),
    "max_path_jerk": (0.0, 1e15, False), "lookahead": (16, 1_000_000, True),
}


def _planner(table: Any, servo_period: Any) -> PlannerConfig:
    values = dict(table) if isinstance(table, dict) else table
    if isinstance(values, dict) and servo_period is not None and "servo_period" not in values:
        values["servo_period"] = servo_period   # older top-level key
    return PlannerConfig(**_checked("planner", values, _PLANNER_RANGES))


def _m_table(table: Any) -> dict[int, str]:
    """The OEM M table's timing (seed 002 L5020-L5029): {m: "before" | "after"}."""
    out = {}
    for key, value in _table("m_functions", table).items():
        m = _entry("m_functions", key, 0, 65535)
        if value not in ("before", "after"):
            raise MachineError(f"m_functions.{key}: M0..M65535 = \"before\" or \"after\", got {value!r}")
        out[m] = value
    return out


def _file_relative(path: Path, data: dict) -> dict:
    """Keys of a machine file that name other files, resolved against its directory:
    ``parameter_file`` and ``linuxcnc_ini`` (a LinuxCNC INI the file's own keys override)."""
    base = path.resolve().parent
    data = dict(data)
    if isinstance(data.get("parameter_file"), str) and data["parameter_file"]:
        data["parameter_file"] = str(base / data["parameter_file"])
    ini = data.pop("linuxcnc_ini", None)
    if ini is not None:
        if not isinstance(ini, str):
            raise MachineError(f"{path}: linuxcnc_ini: expected a file name, got {ini!r}")
        from .linuxcnc import load_ini

        ini_data = load_ini(base / ini)
        axes = dict(ini_data.get("axes", {}))
        for name, spec in _table("axes", data.get("axes", {})).items():   # [axes.X] overrides keys of the INI's X
            axes[name] = {**axes.get(name, {}), **spec} if isinstance(spec, dict) else spec
        data = _merge(ini_data, data)
        data["axes"] = axes
    return data


def _in_file(path: Path, exc: MachineError) -> str:
    """The error message with the file named in front (once)."""
    text = str(exc)
    return text if text.startswith(str(path)) else f"{path}: {text}"


def load_machine(machine: Machine | dict | str | Path | None = None) -> Machine:
    """A :class:`Machine` from ``None`` (the default machine), a dict, a TOML path or a
    LinuxCNC INI path (``*.ini``, see :mod:`fagorcnc.config.linuxcnc`).

    A dict or file is merged over the default machine; its ``axes`` table, when
    given, replaces the default axes entirely.  In a TOML file, ``parameter_file``
    and ``linuxcnc_ini`` are relative to the file's directory.
    """
    if isinstance(machine, Machine):
        return machine
    if machine is None:
        return _build(DEFAULT_MACHINE)
    if isinstance(machine, str | Path):
        path = Path(machine)
        if path.suffix.lower() == ".ini":   # a LinuxCNC configuration (fagorcnc.config.linuxcnc)
            from .linuxcnc import load_ini

            try:
                return _build(_over_default(load_ini(path)))
            except MachineError as exc:
                raise MachineError(_in_file(path, exc)) from None
        import tomllib  # on first use: the default machine is a dict

        try:
            data = tomllib.loads(path.read_text(encoding="utf-8"))
        except OSError as exc:
            raise MachineError(f"{path}: cannot read the machine file ({exc.strerror or exc})") from None
        except tomllib.TOMLDecodeError as exc:
            raise MachineError(f"{path}: {exc}") from None
        try:
            return _build(_over_default(_file_relative(path, data)))
        except MachineError as exc:
            raise MachineError(_in_file(path, exc)) from None
    if isinstance(machine, dict):
        return _build(_over_default(machine))
    raise MachineError(f"machine: expected a path, a dict or a Machine, not {type(machine).__name__}")
