"""LinuxCNC INI import: a LinuxCNC machine configuration as a fagorcnc machine.

``load_machine("machine.ini")`` (any path ending in ``.ini``) and the TOML key
``linuxcnc_ini = "machine.ini"`` (TOML keys then override the INI) both go
through :func:`load_ini`, which returns a dict in the machine-file schema of
:mod:`fagorcnc.config.machine`; the default machine fills in what it leaves out.

What is read (seed 003 = LinuxCNC integrator manual, French; spec
``rosettacnc-linuxcnc.md``):

* ``[TRAJ]`` ``COORDINATES`` (the axis letters, a letter written twice counted
  once, seed 003 L896-L900), ``LINEAR_UNITS`` (``mm``/``metric``, ``in``/``inch``/
  ``imperial``, L916) and ``ANGULAR_UNITS`` (``deg``/``degree``, ``rad``/
  ``radian``, ``grad``/``gon``, L919), ``MAX_LINEAR_VELOCITY`` (older
  ``MAX_VELOCITY``, L929) caps rapids and feeds (``rapid_feed``, ``max_feed``),
  ``MAX_LINEAR_ACCELERATION`` (older ``MAX_ACCELERATION``, L932) limits the
  acceleration on the path (``[planner] max_path_acceleration``) and, with the
  angular ``MAX_ANGULAR_*``, is the fallback of axes that give none;
* ``[AXIS_X]``... (LinuxCNC 2.8+) or ``[AXIS_0]``... (older, numbered in
  ``XYZABCUVW`` order, L950-L966), and ``[JOINT_n]``: ``TYPE`` (``LINEAR`` /
  ``ANGULAR``, L968), ``WRAPPED_ROTARY`` (L969: 0..360 with the sign giving the
  direction, fagorcnc's ``rotary_mode = "normal"``), ``UNITS`` (per-axis unit
  override, L977), ``MAX_VELOCITY`` and ``MAX_ACCELERATION`` (L979-L980),
  ``MAX_JERK`` when present (jerk-limited LinuxCNC forks), ``MIN_LIMIT`` /
  ``MAX_LIMIT`` (soft limits, L1000-L1003), ``HOME`` (L1028).  Joints map to
  axes through ``[KINS] KINEMATICS = trivkins coordinates=XYYZ`` (a letter
  written twice: a gantry) or else by trivial kinematics, X joint 0 ... A
  joint 3 ... W joint 8 (L896-L900: ``[TRAJ] COORDINATES`` names the axes, its
  order does not number the joints); where an axis and its joints both give a
  value the more restrictive one is taken;
* ``[EMCMOT] SERVO_PERIOD`` in ns (L844) -> ``[planner] servo_period`` in s;
* ``[RS274NGC] SUBROUTINE_PATH`` (``:``-separated, relative to the INI file,
  L812) -> ``subroutine_paths``.  ``PARAMETER_FILE`` (L802) is *not* imported:
  LinuxCNC's own ``.var`` file holds LinuxCNC's numbered parameters; set
  fagorcnc's ``parameter_file`` in a TOML file that includes the INI instead.

Units: LinuxCNC INI values are machine units **per second** (L929, L979);
fagorcnc speeds are per **minute** and lengths in mm, so a linear speed is
multiplied by 60 and by 25.4 for inch machines, accelerations and jerks by
25.4, limits by 25.4.  Rotary axes stay in degrees.

Defaults: an axis without a jerk gets ``DEFAULT_JERK_RATE x MAX_ACCELERATION``
(jerk in units/s³ = 20/s times the acceleration: full acceleration in 50 ms, the
ratio of fagorcnc's default machine; LinuxCNC's classic planner has no jerk
limit); an axis without soft limits gets +-1e9 (no limit, like LinuxCNC);
speeds and accelerations missing everywhere keep fagorcnc's axis defaults.

Unknown sections and keys are ignored (a LinuxCNC INI holds many HAL and GUI
settings); a key fagorcnc reads with a bad value raises
:class:`~fagorcnc.config.machine.MachineError` naming the file, line, section and key.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from .errors import MachineError

#: Jerk given to an axis whose INI section has no MAX_JERK: this many times its
#: acceleration (1/s).  20/s = full acceleration in 50 ms (fagorcnc's default machine ratio).
DEFAULT_JERK_RATE = 20.0
#: Soft limit given to an axis without MIN_LIMIT / MAX_LIMIT (mm or degrees): none in practice.
NO_LIMIT = 1e9
#: LinuxCNC axis letters in joint order of trivial kinematics (seed 003 L958-L966).
AXIS_LETTERS = "XYZABCUVW"

_LINEAR_UNITS = {"mm": 1.0, "metric": 1.0, "in": 25.4, "inch": 25.4, "imperial": 25.4}
_ANGULAR_UNITS = {"deg": 1.0, "degree": 1.0, "rad": 180.0 / math.pi, "radian": 180.0 / math.pi,
                  "grad": 0.9, "gon": 0.9}


@dataclass
class IniFile:
    """A parsed INI file: ``sections[NAME][KEY]`` is a list of ``(value, line)``.

    LinuxCNC rules: ``#`` and ``;`` start comment lines, ``KEY = VALUE`` entries,
    a key may repeat (``HALFILE``), the first occurrence wins for a single value.
    Section and key names are compared in upper case.
    """

    path: Path
    sections: dict[str, dict[str, list[tuple[str, int]]]] = field(default_factory=dict)

    def get(self, section: str, key: str) -> tuple[str, int] | None:
        """First ``(value, line)`` of ``[section] key``, or None."""
        values = self.sections.get(section, {}).get(key)
        return values[0] if values else None

    def where(self, section: str, key: str, line: int | None = None) -> str:
        """``file:line: [SECTION] KEY`` for messages."""
        at = f"{self.path}:{line}" if line else str(self.path)
        return f"{at}: [{section}] {key}"

    def number(self, section: str, key: str) -> float | None:
        """``[section] key`` as a finite float (None when absent); a trailing ``# comment`` is allowed."""
        found = self.get(section, key)
        if found is None:
            return None
        text, line = found
        value = _float(text)
        if value is None:
            raise MachineError(f"{self.where(section, key, line)}: expected a number, got {text!r}")
        return value

    def text(self, section: str, key: str) -> str | None:
        found = self.get(section, key)
        return None if found is None else _strip_comment(found[0])


def _strip_comment(text: str) -> str:
    for mark in (" #", "\t#", " ;", "\t;"):
        if mark in text:
            text = text.split(mark, 1)[0]
    return text.strip()


def _float(text: str) -> float | None:
    try:
        value = float(_strip_comment(text))
    except ValueError:
        return None
    return value if math.isfinite(value) else None


def read_ini(path: str | Path) -> IniFile:
    """Read a LinuxCNC INI file (raises :class:`MachineError` when it cannot be read)."""
    path = Path(path)
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise MachineError(f"{path}: cannot read the INI file ({exc.strerror or exc})") from None
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError:
        text = data.decode("latin-1")
    ini = IniFile(path)
    section: dict[str, list[tuple[str, int]]] | None = None
    for number, raw in enumerate(text.splitlines(), start=1):
        line = raw.strip()
        if not line or line[0] in "#;":
            continue
        if line.startswith("[") and "]" in line:
            name = line[1:line.index("]")].strip().upper()
            section = ini.sections.setdefault(name, {})
            continue
        if "=" not in line or section is None:
            continue   # LinuxCNC ignores such lines too
        key, value = line.split("=", 1)
        section.setdefault(key.strip().upper(), []).append((value.strip(), number))
    return ini


def load_ini(path: str | Path) -> dict[str, Any]:
    """A LinuxCNC INI file as a machine dict (see the module docstring for the mapping).

    The result is meant for :func:`fagorcnc.config.machine.load_machine`, which merges
    it over the default machine; its ``axes`` table replaces the default axes.
    """
    ini = read_ini(path)
    traj = "TRAJ"
    linear = _units(ini, traj, "LINEAR_UNITS", _LINEAR_UNITS, "mm")
    angular = _units(ini, traj, "ANGULAR_UNITS", _ANGULAR_UNITS, "deg")

    letters, joints = _axis_letters(ini)
    axes: dict[str, dict[str, Any]] = {}
    for letter in letters:
        axes[letter] = _axis(ini, letter, joints.get(letter, []), linear, angular)

    out: dict[str, Any] = {"axes": axes}
    vmax = _first(ini, traj, ("MAX_LINEAR_VELOCITY", "MAX_VELOCITY"))
    if vmax is not None:
        value, key = vmax
        _positive(ini, traj, key, value)
        out["rapid_feed"] = out["max_feed"] = value * (60.0 * linear)
    amax = _first(ini, traj, ("MAX_LINEAR_ACCELERATION", "MAX_ACCELERATION"))
    if amax is not None:   # the trajectory's own limit (L932), on the path as well as each axis' fallback
        value, key = amax
        _positive(ini, traj, key, value)
        out["planner"] = {"max_path_acceleration": value * linear}
    period = ini.number("EMCMOT", "SERVO_PERIOD")
    if period is not None:
        seconds = period * 1e-9
        if not 1e-5 <= seconds <= 1.0:
            line = ini.get("EMCMOT", "SERVO_PERIOD")[1]
            raise MachineError(f"{ini.where('EMCMOT', 'SERVO_PERIOD', line)}: {period:g} ns is not a servo period "
                               f"(10000 ns to 1 s)")
        out.setdefault("planner", {})["servo_period"] = seconds
    paths = ini.text("RS274NGC", "SUBROUTINE_PATH")
    if paths:
        base = ini.path.resolve().parent
        out["subroutine_paths"] = [str(base / p) for p in paths.split(":") if p]
    return out


def _units(ini: IniFile, section: str, key: str, table: dict[str, float], default: str) -> float:
    name = ini.text(section, key)
    if name is None:
        return table[default]
    factor = table.get(name.lower())
    if factor is None:
        line = ini.get(section, key)[1]
        raise MachineError(f"{ini.where(section, key, line)}: unknown unit {name!r} (known: {', '.join(table)})")
    return factor


def _axis_letters(ini: IniFile) -> tuple[list[str], dict[str, list[str]]]:
    """The axis letters in channel order and, per letter, the joint sections that drive it."""
    coords = ini.text("TRAJ", "COORDINATES")
    joint_letters: list[str] = []
    if coords is not None:
        joint_letters = [c for c in coords.upper() if not c.isspace()]
        bad = [c for c in joint_letters if c not in AXIS_LETTERS]
        if bad:
            line = ini.get("TRAJ", "COORDINATES")[1]
            raise MachineError(f"{ini.where('TRAJ', 'COORDINATES', line)}: {bad[0]!r} is not an axis letter "
                               f"({' '.join(AXIS_LETTERS)})")
    kins = ini.text("KINS", "KINEMATICS") or ""
    kins_letters: list[str] = []   # joint n drives kins_letters[n] (trivkins coordinates=XYYZ)
    for word in kins.split():
        if word.lower().startswith("coordinates="):
            kins_letters = joint_letters = [c for c in word.split("=", 1)[1].upper() if c in AXIS_LETTERS]

    present: list[str] = []
    for name in ini.sections:
        if name.startswith("AXIS_"):
            suffix = name[5:]
            if len(suffix) == 1 and suffix in AXIS_LETTERS:
                present.append(suffix)
            elif suffix.isdigit():   # older INI: [AXIS_0] = X ... (seed 003 L950-L966)
                n = int(suffix)
                if n >= len(AXIS_LETTERS):
                    raise MachineError(f"{ini.path}: [{name}]: axis numbers go from 0 to {len(AXIS_LETTERS) - 1}")
                present.append(AXIS_LETTERS[n])
    order: list[str] = []
    for letter in joint_letters or sorted(set(present), key=AXIS_LETTERS.index):
        if letter not in order:
            order.append(letter)
    if not order:
        raise MachineError(f"{ini.path}: no axes: give [TRAJ] COORDINATES or [AXIS_X] ... sections")

    joints: dict[str, list[str]] = {}
    for name in ini.sections:
        if name.startswith("JOINT_") and name[6:].isdigit():
            n = int(name[6:])
            # without coordinates=, trivial kinematics: X is always joint 0, A joint 3, U joint 6, whatever
            # [TRAJ] COORDINATES lists (seed 003 L896-L900: it "has no effect" on the joint numbers)
            table = kins_letters or list(AXIS_LETTERS)
            if n < len(table):
                joints.setdefault(table[n], []).append(name)
    return order, joints


def _axis_sections(ini: IniFile, letter: str) -> list[str]:
    names = [f"AXIS_{letter}", f"AXIS_{AXIS_LETTERS.index(letter)}"]
    return [n for n in names if n in ini.sections]


def _axis(ini: IniFile, letter: str, joints: list[str], linear: float, angular: float) -> dict[str, Any]:
    axis_sections = _axis_sections(ini, letter)
    sections = axis_sections + joints
    rotary = letter in "ABC"
    for sec in sections:
        kind = ini.text(sec, "TYPE")
        if kind is not None:
            if kind.upper() not in ("LINEAR", "ANGULAR"):
                line = ini.get(sec, "TYPE")[1]
                raise MachineError(f"{ini.where(sec, 'TYPE', line)}: expected LINEAR or ANGULAR, got {kind!r}")
            rotary = kind.upper() == "ANGULAR"
    scale = angular if rotary else linear
    for sec in sections:   # per-axis unit override (seed 003 L977)
        if ini.text(sec, "UNITS") is not None:
            scale = _units(ini, sec, "UNITS", _ANGULAR_UNITS if rotary else _LINEAR_UNITS, "deg")

    def values(key: str) -> list[tuple[float, str]]:
        out = []
        for sec in sections:
            v = ini.number(sec, key)
            if v is not None:
                out.append((v, sec))
        return out

    spec: dict[str, Any] = {"type": "rotary" if rotary else "linear"}
    # [TRAJ] fallbacks of an axis that gives no value itself
    velocity = ("MAX_ANGULAR_VELOCITY",) if rotary else ("MAX_LINEAR_VELOCITY", "MAX_VELOCITY")
    acceleration = ("MAX_ANGULAR_ACCELERATION",) if rotary else ("MAX_LINEAR_ACCELERATION", "MAX_ACCELERATION")
    for key, out_key, factor, fallback in (("MAX_VELOCITY", "max_velocity", 60.0, velocity),
                                           ("MAX_ACCELERATION", "max_acceleration", 1.0, acceleration),
                                           ("MAX_JERK", "max_jerk", 1.0, ())):
        found = values(key)
        for v, sec in found:
            _positive(ini, sec, key, v)
        if found:
            spec[out_key] = min(v for v, _ in found) * (factor * scale)
            continue
        traj = _first(ini, "TRAJ", fallback)
        if traj is not None:
            _positive(ini, "TRAJ", traj[1], traj[0])
            spec[out_key] = traj[0] * (factor * scale)
    if "max_jerk" not in spec and "max_acceleration" in spec:
        spec["max_jerk"] = DEFAULT_JERK_RATE * spec["max_acceleration"]

    lows, highs = values("MIN_LIMIT"), values("MAX_LIMIT")
    spec["min_limit"] = max(v for v, _ in lows) * scale if lows else -NO_LIMIT
    spec["max_limit"] = min(v for v, _ in highs) * scale if highs else NO_LIMIT
    if spec["min_limit"] > spec["max_limit"]:
        where = lows[0][1] if lows else sections[0]
        raise MachineError(f"{ini.path}: [{where}] MIN_LIMIT {spec['min_limit'] / scale:g} is above MAX_LIMIT "
                           f"{spec['max_limit'] / scale:g} (axis {letter})")
    homes = values("HOME")
    if homes:
        spec["home"] = homes[0][0] * scale
    if rotary:
        wrapped = values("WRAPPED_ROTARY")
        if wrapped and wrapped[0][0] != 0:
            spec["rotary_mode"] = "normal"   # 0..360, the sign gives the direction (seed 003 L969-L970)
    return spec


def _first(ini: IniFile, section: str, keys: tuple[str, ...]) -> tuple[float, str] | None:
    for key in keys:
        value = ini.number(section, key)
        if value is not None:
            return value, key
    return None


def _positive(ini: IniFile, section: str, key: str, value: float) -> None:
    if not value > 0:
        found = ini.get(section, key)
        raise MachineError(f"{ini.where(section, key, found[1] if found else None)}: must be positive, "
                           f"got {value:g}")
