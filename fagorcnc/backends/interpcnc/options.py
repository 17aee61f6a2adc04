"""Options of the ``interpcnc`` back-end: the ``[backends.interpcnc]`` table, checked.

Keyword options given to the back-end override the machine's table.  Every
problem raises :class:`~fagorcnc.backends.base.BackendError` naming the key.

Example (TOML)::

    [backends.interpcnc]
    host = "192.168.10.147"          # Modbus TCP (port 502), or:
    # serial = "/dev/ttyACM0"        # Modbus RTU (also "socket://host:port")
    chordal_tolerance = 0.005        # mm, for arcs/blends sent as lines
    resolution = { X = 800, Y = 800, Z = 1600 }   # pulses per mm (position read-back)
    marker_every = 16                # straight moves sharing one sequence marker (1: one per segment)
    stall_timeout = 30               # s: the card consumes nothing although it holds commands -> stop (BCK001)
    stop_timeout = 10                # s: an axis still reported moving once the buffers are empty -> stop (BCK002)
    start_lead = 2                   # s of planned motion queued before the card starts (default 2; 0: at once)

    [backends.interpcnc.outputs]     # auxiliary functions -> synchronised actions (command 1010)
    M3 = { type = 1, output = 0, value = 1 }               # OUT0 on
    M5 = [{ type = 1, output = 0, value = 0 },             # several actions, in order
          { type = 2, output = 0, value = 0 }]
    M8 = { type = 1, output = 2, value = 1 }
    M9 = { type = 1, output = 2, value = 0 }
    S  = { type = 2, output = 0, scale = 1.0 }             # S1000 -> AOUT0 = 1000 mV
    T  = { type = 3, register = 3010, scale = 1 }          # tool number into user register 3010
    M30 = []                                               # explicitly nothing

Output keys are a function letter with its number (``M3``, ``T5``), looked
up first, or the bare letter (``M``, ``S``, ``T``, ``H``, ``D``) for any
value.  Action fields: ``type`` 1 digital output (``output`` 0-255,
``value`` 0/1); 2 analog output (``output`` 0-7, ``value`` mV 0-10000 or
``scale``: the function's value times ``scale``); 3 holding-register write
(``register`` 2150-65535 outside the command buffer, ``value`` 0-65535 or
``scale``); 4-8 torch-height control (``duration`` ms for type 5).  A scaled
value is rounded and clamped to the range, with a warning.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from typing import Any

from ...config.machine import Machine
from ..base import BackendError
from . import registers as regs

#: Nothing for the card to do: the end of the program, and D, which selects a tool offset whose
#: radius and length the path sent already includes.
DEFAULT_IGNORED = ("M2", "M30", "D")


@dataclass(frozen=True)
class OutputAction:
    """One synchronised action (command 1010) for an auxiliary function.

    ``address`` is the output number (types 1, 2), the register (type 3) or
    the argument (types 4-8); the value written is ``value`` or
    ``round(function value * scale)``.
    """

    type: int
    address: int = 0
    value: int | None = 0
    scale: float | None = None
    low: int = 0
    high: int = 0xFFFF

    def resolve(self, function_value: float) -> tuple[int, bool]:
        """The value to write for ``function_value`` and whether it had to be clamped."""
        raw = self.value if self.scale is None else round(function_value * self.scale)
        clamped = min(max(int(raw), self.low), self.high)
        return clamped, clamped != raw


@dataclass
class Options:
    """Checked options (see the module docstring)."""

    host: str = "127.0.0.1"
    port: int = regs.DEFAULT_TCP_PORT
    serial: str | None = None
    baudrate: int = 115200
    unit: int = 1
    timeout: float = 1.0                     # s, per Modbus request
    chordal_tolerance: float = 0.005         # mm
    resolution: dict[str, float] = field(default_factory=dict)   # machine axis -> pulses/mm
    outputs: dict[str, tuple[OutputAction, ...]] = field(default_factory=dict)
    ignore: frozenset[str] = frozenset(DEFAULT_IGNORED)
    poll_interval: float = 0.02              # s, status polling while streaming
    low_water: int = 8                       # planner entries below which the back-end stops sleeping
    marker_register: int = regs.DEFAULT_MARKER_REGISTER   # user RAM (this and the next two): markers and gate
    axis_map: dict[str, str] = field(default_factory=dict)   # machine axis -> card axis letter
    strict_outputs: bool = False             # unmapped auxiliary function -> error instead of warning
    marker_every: int = 16                   # straight moves sharing one sequence marker at most (see markers.py)
    stall_timeout: float = 30.0              # s without progress while the card holds commands -> error (BCK001)
    stop_timeout: float = 10.0               # s the axes may keep moving once the buffers are empty (BCK002)
    start_lead: float = 2.0                  # s of planned motion queued before the card may start (0: at once)


_KEYS = {
    "host", "port", "serial", "baudrate", "unit", "timeout", "chordal_tolerance", "resolution", "outputs",
    "ignore", "poll_interval", "low_water", "marker_register", "axis_map", "strict_outputs", "marker_every",
    "stall_timeout", "stop_timeout", "start_lead",
}
_FUNCTION_KEY = re.compile(r"^[MSTHD](\d+)?$")


def _err(key: str, problem: str) -> BackendError:
    return BackendError(f"[backends.interpcnc] {key}: {problem}")


def _number(key: str, value: Any, low: float, high: float, integer: bool = False) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value):
        raise _err(key, f"expected a number, got {value!r}")
    if integer and value != int(value):
        raise _err(key, f"expected an integer, got {value!r}")
    if not low <= value <= high:
        raise _err(key, f"{value!r} is outside {low:g}..{high:g}")
    return int(value) if integer else float(value)


def parse_options(machine: Machine, overrides: dict[str, Any]) -> Options:
    """The machine's ``[backends.interpcnc]`` table updated with ``overrides`` (``None`` = not given)."""
    table = dict(getattr(machine, "backends", {}).get("interpcnc", {}))
    table.update({k: v for k, v in overrides.items() if v is not None})
    unknown = sorted(set(table) - _KEYS)
    if unknown:
        raise _err(unknown[0], f"unknown option (known: {', '.join(sorted(_KEYS))})")
    opt = Options()
    if "host" in table:
        if not isinstance(table["host"], str) or not table["host"]:
            raise _err("host", "expected a host name or address")
        opt.host = table["host"]
    if "serial" in table:
        if not isinstance(table["serial"], str) or not table["serial"]:
            raise _err("serial", "expected a device path or a pyserial URL such as socket://127.0.0.1:5020")
        opt.serial = table["serial"]
    opt.port = int(_number("port", table.get("port", opt.port), 0, 65535, True))
    opt.baudrate = int(_number("baudrate", table.get("baudrate", opt.baudrate), 300, 4_000_000, True))
    opt.unit = int(_number("unit", table.get("unit", opt.unit), 0, 247, True))
    opt.timeout = _number("timeout", table.get("timeout", opt.timeout), 0.01, 60.0)
    opt.chordal_tolerance = _number("chordal_tolerance", table.get("chordal_tolerance", opt.chordal_tolerance),
                                    1e-5, 10.0)
    opt.poll_interval = _number("poll_interval", table.get("poll_interval", opt.poll_interval), 0.001, 5.0)
    opt.low_water = int(_number("low_water", table.get("low_water", opt.low_water), 0, 35, True))
    opt.marker_register = int(_number("marker_register", table.get("marker_register", opt.marker_register),
                                      regs.HR_USER_RAM, regs.HR_USER_RAM_LAST - 2, True))
    opt.marker_every = int(_number("marker_every", table.get("marker_every", opt.marker_every), 1, 64, True))
    opt.stall_timeout = _number("stall_timeout", table.get("stall_timeout", opt.stall_timeout), 0.05, 86400.0)
    opt.stop_timeout = _number("stop_timeout", table.get("stop_timeout", opt.stop_timeout), 0.05, 3600.0)
    opt.start_lead = _number("start_lead", table.get("start_lead", opt.start_lead), 0.0, 60.0)
    strict = table.get("strict_outputs", False)
    if not isinstance(strict, bool):
        raise _err("strict_outputs", "expected true or false")
    opt.strict_outputs = strict
    opt.axis_map = _axis_map(machine, table.get("axis_map", {}))
    opt.resolution = _resolution(machine, table.get("resolution", {}))
    opt.ignore = _ignore(table.get("ignore", list(DEFAULT_IGNORED)))
    opt.outputs = _outputs(table.get("outputs", {}), opt.marker_register)
    return opt


def _axis_map(machine: Machine, table: Any) -> dict[str, str]:
    if not isinstance(table, dict):
        raise _err("axis_map", "expected a table {machine axis = card axis letter}")
    out: dict[str, str] = {}
    for axis in machine.axis_names:
        card = table.get(axis, axis)
        if card not in regs.CARD_AXES:
            raise _err(f"axis_map.{axis}",
                       f"machine axis {axis} has no InterpCNC axis (card axes: {' '.join(regs.CARD_AXES)}); "
                       f"map it, e.g. axis_map = {{ {axis} = \"A\" }}")
        out[axis] = card
    for axis in table:
        if axis not in machine.axis_names:
            raise _err(f"axis_map.{axis}", f"the machine has no axis {axis} (axes: {' '.join(machine.axis_names)})")
    if len(set(out.values())) != len(out):
        raise _err("axis_map", "two machine axes map to the same card axis")
    return out


def _resolution(machine: Machine, table: Any) -> dict[str, float]:
    if isinstance(table, int | float) and not isinstance(table, bool):
        table = dict.fromkeys(machine.axis_names, table)
    if not isinstance(table, dict):
        raise _err("resolution", "expected pulses per mm, one number or a table {axis = pulses/mm}")
    out = {}
    for axis, value in table.items():
        if axis not in machine.axis_names:
            raise _err(f"resolution.{axis}", f"the machine has no axis {axis}")
        out[axis] = _number(f"resolution.{axis}", value, 1e-6, 1e9)
    return out


def _function_key(name: Any) -> str | None:
    """``"m03"`` -> ``"M3"``; None when not a function name."""
    key = str(name).strip().upper()
    m = _FUNCTION_KEY.match(key)
    if not m:
        return None
    return key[0] + (str(int(m.group(1))) if m.group(1) else "")


def _forbidden_register(addr: int) -> str:
    """Why a holding register may not be an action's target ('' if it may): the position counters
    (seed 000 L564: never to be changed during a move, and an action runs with the motion), the
    card's parameters (L476) and its memory pointers (L477-L483)."""
    if regs.HR_AXIS_POSITION <= addr < regs.HR_AXIS_POSITION + 12:
        return "a position counter (seed 000 L564: never changed during a move)"
    if regs.HR_PARAMETERS <= addr < regs.HR_PARAMETERS + 4000:
        return "one of the card's parameters (32000-35999)"
    if addr >= 62000:
        return "a pointer into the card's memory (62000 and above)"
    return ""


def _ignore(value: Any) -> frozenset[str]:
    if not isinstance(value, list | tuple) or not all(isinstance(v, str) for v in value):
        raise _err("ignore", "expected a list of function names such as [\"M30\"]")
    out = set()
    for v in value:
        key = _function_key(v)
        if key is None:
            raise _err("ignore", f"{v!r} is not a function name like M30 or T")
        out.add(key)
    return frozenset(out)


def _outputs(table: Any, marker: int) -> dict[str, tuple[OutputAction, ...]]:
    if not isinstance(table, dict):
        raise _err("outputs", "expected a table {function = action or [actions]}")
    out = {}
    for name, spec in table.items():
        key = _function_key(name)
        if key is None:
            raise _err(f"outputs.{name}", "keys are a function letter M S T H D, optionally with a number (M3)")
        if key in out:
            raise _err(f"outputs.{name}", f"{key} is given twice")
        specs = spec if isinstance(spec, list) else [spec]
        out[key] = tuple(_action(f"outputs.{name}[{k}]" if isinstance(spec, list) else f"outputs.{name}", s, marker)
                         for k, s in enumerate(specs))
    return out


_FIELDS = {1: {"output", "value"}, 2: {"output", "value", "scale"}, 3: {"register", "value", "scale"},
           4: set(), 5: {"duration"}, 6: set(), 7: set(), 8: set()}


def _action(key: str, spec: Any, marker: int) -> OutputAction:
    if not isinstance(spec, dict):
        raise _err(key, "expected a table such as { type = 1, output = 0, value = 1 }")
    kind = int(_number(f"{key}.type", spec.get("type"), 1, 8, True)) if "type" in spec else None
    if kind is None:
        raise _err(key, "missing 'type' (1 digital output, 2 analog output, 3 register, 4-8 THC)")
    extra = sorted(set(spec) - _FIELDS[kind] - {"type"})
    if extra:
        raise _err(f"{key}.{extra[0]}", f"not a field of action type {kind} (fields: {sorted(_FIELDS[kind])})")
    if kind == regs.ACTION_DIGITAL:
        out = int(_number(f"{key}.output", spec.get("output"), 0, 255, True))
        value = int(_number(f"{key}.value", spec.get("value"), 0, 1, True))
        return OutputAction(kind, out, value, None, 0, 1)
    if kind in (regs.ACTION_ANALOG, regs.ACTION_REGISTER):
        if kind == regs.ACTION_ANALOG:
            addr = int(_number(f"{key}.output", spec.get("output"), 0, 7, True))
            high = 10000
        else:
            addr = int(_number(f"{key}.register", spec.get("register"), 2150, 65535, True))
            if marker <= addr <= marker + 2:
                raise _err(f"{key}.register", f"{addr} holds the sequence markers and the gate (marker_register "
                           "and the next two)")
            forbidden = _forbidden_register(addr)
            if forbidden:
                raise _err(f"{key}.register", f"{addr} is {forbidden}: an auxiliary function must not write it")
            high = 0xFFFF
        if ("value" in spec) == ("scale" in spec):
            raise _err(key, "give exactly one of 'value' (fixed) or 'scale' (times the function's value)")
        if "scale" in spec:
            return OutputAction(kind, addr, None, _number(f"{key}.scale", spec["scale"], -1e9, 1e9), 0, high)
        return OutputAction(kind, addr, int(_number(f"{key}.value", spec["value"], 0, high, True)), None, 0, high)
    duration = int(_number(f"{key}.duration", spec.get("duration", 0), 0, 65535, True))
    return OutputAction(kind, duration, 0, None, 0, 0xFFFF)
