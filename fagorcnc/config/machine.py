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
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

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

    @property
    def rotary(self) -> bool:
        return self.type == "rotary"


@dataclass
class ToolOffset:
    """One offset D of a tool: length, radius and their wear (mm)."""

    length: float = 0.0
    radius: float = 0.0
    length_wear: float = 0.0
    radius_wear: float = 0.0
    #: False for the default machine's zero-size placeholder of an offset the machine's own tool table
    #: leaves out: radius or length compensation with it is an error (the control has no such offset)
    declared: bool = field(default=True, compare=False)


@dataclass
class Limits:
    """Guards against runaway programs, ``[limits]`` in TOML (README "Runaway guards")."""

    max_loop_iterations: int = 1_000_000   # per loop instance; also the largest NR and #RPT count
    max_blocks: int = 100_000_000          # executed blocks per run (NR repetitions included)
    max_call_depth: int = 20               # subroutine nesting (seed 002 L10207)
    max_parameter_levels: int = 7          # local parameter levels (seed 002 L10503)
    # Seconds of interpretation per run (the time the planner or a machine holds the records
    # does not count); 0 = none.  None by default: the machine file also drives real runs,
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
    max_feed: float = 0.0        # channel MAXFEED, 0 = not limited (L20762)
    rapid_feed: float = 0.0      # channel rapid; 0 = from the axes' max_velocity
    servo_period: float = 0.001  # s
    cirinerr: float = 0.01       # mm, arc radius tolerance (L20298)
    cirinfact: float = 0.1       # %, relative arc radius tolerance (L20308)
    subroutine_paths: list[Path] = field(default_factory=list)
    oem_subroutines: dict[int, str] = field(default_factory=dict)  # G180.. -> file name
    m_functions: dict[int, str] = field(default_factory=dict)  # M table: number -> "before" | "after"
    limits: Limits = field(default_factory=Limits)
    planner: PlannerConfig = field(default_factory=PlannerConfig)
    backends: dict[str, dict] = field(default_factory=dict)   # [backends.<name>] tables, read by each back-end
    parameter_file: Path | None = None   # global/common parameters kept between runs (fagorcnc.config.parameter_file)

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


def _axis_table(where: str, table: Any) -> dict[str, float]:
    if not isinstance(table, dict):
        raise MachineError(f"{where}: expected a table of axis values")
    return {str(k): _number(f"{where}.{k}", v) for k, v in table.items()}


def _build(data: dict) -> Machine:
    axes = {}
    for name, spec in data.get("axes", {}).items():
        if not isinstance(spec, dict):
            raise MachineError(f"axes.{name}: expected a table")
        known = set(Axis.__dataclass_fields__) - {"name"}
        unknown = set(spec) - known
        if unknown:
            raise MachineError(f"axes.{name}: unknown key(s) {', '.join(sorted(unknown))}")
        kwargs = {}
        for key, value in spec.items():
            if key in ("type", "rotary_mode"):
                kwargs[key] = str(value)
            elif key == "diameter":
                kwargs[key] = bool(value)
            elif key == "direction":
                kwargs[key] = 1 if int(value) >= 0 else -1
            else:
                kwargs[key] = _number(f"axes.{name}.{key}", value)
        axis = Axis(name=str(name), **kwargs)
        if axis.type not in ("linear", "rotary"):
            raise MachineError(f"axes.{name}.type must be 'linear' or 'rotary'")
        if axis.rotary_mode not in ("linearlike", "normal", "unidirectional", "positioning"):
            raise MachineError(f"axes.{name}.rotary_mode: unknown mode {axis.rotary_mode!r}")
        for key in ("max_velocity", "max_acceleration", "max_jerk"):
            if not getattr(axis, key) > 0:
                raise MachineError(f"axes.{name}.{key} must be positive, got {getattr(axis, key):g}")
        if axis.min_limit > axis.max_limit:
            raise MachineError(f"axes.{name}: min_limit is above max_limit")
        axes[str(name)] = axis
    if not axes:
        raise MachineError("axes: the machine needs at least one axis")

    defaults = {}
    for key, value in data.get("defaults", {}).items():
        if key not in DEFAULTS_SCHEMA:
            raise MachineError(f"defaults.{key}: unknown parameter (known: {', '.join(DEFAULTS_SCHEMA)})")
        if value not in DEFAULTS_SCHEMA[key][1]:
            raise MachineError(f"defaults.{key} = {value!r}: {DEFAULTS_SCHEMA[key][2]}")
        defaults[key] = int(value)

    origins = {}
    for key, table in data.get("origins", {}).items():
        k = str(key).upper()
        if k in ("G54", "G55", "G56", "G57", "G58", "G59"):
            n = int(k[1:]) - 53
        elif k.startswith("G159."):
            n = int(k[5:])
        else:
            try:
                n = int(k)
            except ValueError:
                raise MachineError(f"origins.{key}: use G54..G59, 'G159.n' or n") from None
        if not 1 <= n <= 99:
            raise MachineError(f"origins.{key}: entry must be 1..99")
        origins[n] = _axis_table(f"origins.{key}", table)

    fixtures = {}
    for key, table in data.get("fixtures", {}).items():
        n = int(key)
        if not 1 <= n <= 10:
            raise MachineError(f"fixtures.{key}: entry must be 1..10")
        fixtures[n] = _axis_table(f"fixtures.{key}", table)

    tools: dict[int, dict[int, ToolOffset]] = {}
    for tkey, offsets in data.get("tools", {}).items():
        for dkey, spec in offsets.items():
            declared = spec is not _PLACEHOLDER
            fields = {k: _number(f"tools.{tkey}.{dkey}.{k}", v) for k, v in spec.items()}
            unknown = set(fields) - (set(ToolOffset.__dataclass_fields__) - {"declared"})
            if unknown:
                raise MachineError(f"tools.{tkey}.{dkey}: unknown key(s) {', '.join(sorted(unknown))}")
            tools.setdefault(int(tkey), {})[int(dkey)] = ToolOffset(**fields, declared=declared)

    def prange(key: str, default: tuple[int, int], hard: tuple[int, int]) -> tuple[int, int]:
        lo, hi = data.get(key, default)
        if not (hard[0] <= lo <= hi <= hard[1]):
            raise MachineError(f"{key}: range must lie within P{hard[0]}..P{hard[1]}")
        return int(lo), int(hi)

    limits = _limits(data.get("limits", {}))
    planner = _planner(data.get("planner", {}), data.get("servo_period"))
    return Machine(
        axes=axes,
        spindles=[str(s) for s in data.get("spindles", ["S"])],
        defaults=defaults,
        local_params=prange("local_params", (0, 25), (0, 99)),
        global_params=prange("global_params", (100, 299), (100, 9999)),
        common_params=prange("common_params", (10000, 10999), (10000, 19999)),
        origins=origins,
        fixtures=fixtures,
        tools=tools,
        max_feed=_number("max_feed", data.get("max_feed", 0.0)),
        rapid_feed=_number("rapid_feed", data.get("rapid_feed", 0.0)),
        servo_period=planner.servo_period,
        cirinerr=_number("cirinerr", data.get("cirinerr", 0.01)),
        cirinfact=_number("cirinfact", data.get("cirinfact", 0.1)),
        subroutine_paths=[Path(p) for p in data.get("subroutine_paths", [])],
        oem_subroutines={int(k): str(v) for k, v in data.get("oem_subroutines", {}).items()},
        m_functions=_m_table(data.get("m_functions", {})),
        limits=limits,
        planner=planner,
        backends=_backends(data.get("backends", {})),
        parameter_file=_parameter_file(data.get("parameter_file")),
    )


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


def _m_table(table: dict) -> dict[int, str]:
    """The OEM M table's timing (seed 002 L5020-L5029): {m: "before" | "after"}."""
    out = {}
    for key, value in table.items():
        m = int(key)
        if not 0 <= m <= 65535 or value not in ("before", "after"):
            raise MachineError(f"m_functions.{key}: M0..M65535 = \"before\" or \"after\"")
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
        for name, spec in data.get("axes", {}).items():   # an [axes.X] table overrides single keys of the INI's X
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
