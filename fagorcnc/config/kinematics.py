"""Kinematics in the machine file: ``[[kinematics]]`` tables (seed 002 L28769-L28870, spec 07 §B.8).

The manual's kinematics are machine parameters ``MPK.TYPE`` and ``TDATA``/``TDATA_I`` values whose
meaning is installation data seed 002 does not give.  fagorcnc names each geometric datum after what
it means instead (README "Kinematics")::

    kinid = 1                          # KINID: the kinematics in force at power-on (#KIN ID)
    [[kinematics]]                     # kinematics 1
    type = 10                          # MPK.TYPE: rotary table AC
    axes = ["A", "C"]                  # the rotary axes, main (nearest the machine bed or ram) first
    directions = [[1, 0, 0], [0, 0, 1]]   # their rotation directions at rest (right-hand rule)
    pivots = [[0, 0, -100], [0, 0, -100]] # a point on each rotation line
    tool_direction = [0, 0, 1]         # tool tip -> spindle with every rotary axis at 0

Frames.  A head joint turns the tool; its pivot is measured from the *head reference point*, the
point whose machine coordinates the linear axes show (with a zero tool length the tool tip is at the
reference point plus ``spindle_nose``).  A table joint turns the part; its pivot is in machine
coordinates.  A head's secondary joint is carried by the main one, and so is a table's secondary
joint: directions and pivots are given with every rotary axis at 0.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .errors import MachineError

_X, _Y, _Z = (1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0)


def unit(v) -> np.ndarray:
    """``v`` scaled to length 1 (ValueError for a null vector)."""
    v = np.asarray(v, dtype=float)
    n = float(np.linalg.norm(v))
    if n < 1e-9:
        raise ValueError("a direction needs a non-zero vector")
    return v / n
_DIR = {"X": _X, "Y": _Y, "Z": _Z, "A": _X, "B": _Y, "C": _Z}
_AXIS_OF = {"X": "A", "Y": "B", "Z": "C"}

#: MPK.TYPE -> (family, letters of the rotation directions, which joints turn the head "H" or the table "T")
#: (seed 002 L28779-L28846).  Letters XYZ are rotation directions (heads), ABC rotary axes (tables).
TYPES: dict[int, tuple[str, str, str]] = {
    1: ("orthogonal or spherical spindle head", "YX", "HH"),
    2: ("orthogonal or spherical spindle head", "ZX", "HH"),
    3: ("orthogonal or spherical spindle head", "XY", "HH"),
    4: ("orthogonal or spherical spindle head", "ZY", "HH"),
    5: ("angular spindle head", "XZ", "HH"),
    6: ("angular spindle head", "YZ", "HH"),
    7: ("angular spindle head", "ZX", "HH"),
    8: ("angular spindle head", "ZY", "HH"),
    9: ("rotary table", "AB", "TT"),
    10: ("rotary table", "AC", "TT"),
    11: ("rotary table", "BA", "TT"),
    12: ("rotary table", "BC", "TT"),
    13: ("spindle-table", "AB", "HT"),
    14: ("spindle-table", "AC", "HT"),
    15: ("spindle-table", "BA", "HT"),
    16: ("spindle-table", "BC", "HT"),
    17: ("three-rotary orthogonal head", "ABA", "HHH"),
    18: ("three-rotary orthogonal head", "ACA", "HHH"),
    19: ("three-rotary orthogonal head", "ACB", "HHH"),
    20: ("three-rotary orthogonal head", "BAB", "HHH"),
    21: ("three-rotary orthogonal head", "BCA", "HHH"),
    22: ("three-rotary orthogonal head", "BCB", "HHH"),
    23: ("three-rotary orthogonal head", "CAB", "HHH"),
    24: ("three-rotary orthogonal head", "CBA", "HHH"),
    41: ("C axis, face machining (ALIGNC = yes)", "C", "T"),
    42: ("C axis, face machining (ALIGNC = no)", "C", "T"),
    43: ("C axis, cylindrical surface", "C", "T"),
}

#: The largest number of kinematics a machine may define (#KIN ID [1..6], seed 002 L12527).
MAX_KINEMATICS = 6


@dataclass(frozen=True)
class Joint:
    """One rotary joint: its machine axis, its direction at rest, a point on its line, head or table."""

    axis: str
    direction: tuple[float, float, float]
    pivot: tuple[float, float, float]
    head: bool


@dataclass(frozen=True)
class Kinematics:
    """One kinematics of the machine (``MPK.TYPE`` and the named geometry replacing its TDATA)."""

    number: int
    type: int
    joints: tuple[Joint, ...]
    tool_direction: tuple[float, float, float] = _Z
    spindle_nose: tuple[float, float, float] = (0.0, 0.0, 0.0)
    tolerance: float = 0.001   # mm: the tool tip's largest deviation between joint-space points (RTCP)
    extra: dict = field(default_factory=dict)

    @property
    def family(self) -> str:
        return TYPES[self.type][0]

    @property
    def head_joints(self) -> tuple[Joint, ...]:
        return tuple(j for j in self.joints if j.head)

    @property
    def table_joints(self) -> tuple[Joint, ...]:
        return tuple(j for j in self.joints if not j.head)

    @property
    def axes(self) -> tuple[str, ...]:
        return tuple(j.axis for j in self.joints)

    @property
    def c_axis(self) -> bool:
        return self.type in (41, 42, 43)


def _vector(where: str, value: Any) -> tuple[float, float, float]:
    if (not isinstance(value, list | tuple) or len(value) != 3
            or not all(isinstance(v, int | float) and not isinstance(v, bool) for v in value)):
        raise MachineError(f"{where}: expected three numbers [x, y, z], got {value!r}")
    return float(value[0]), float(value[1]), float(value[2])


_KEYS = {"type", "axes", "directions", "pivots", "tool_direction", "spindle_nose", "tolerance"}


def parse_kinematics(tables: Any, axes: dict) -> list[Kinematics]:
    """The ``[[kinematics]]`` array of a machine file, checked against the machine's axes."""
    if tables is None:
        return []
    if not isinstance(tables, list) or not all(isinstance(t, dict) for t in tables):
        raise MachineError("kinematics: expected an array of tables [[kinematics]]")
    if len(tables) > MAX_KINEMATICS:
        raise MachineError(f"kinematics: at most {MAX_KINEMATICS} kinematics (seed 002 L12527), got {len(tables)}")
    return [_one(n, t, axes) for n, t in enumerate(tables, 1)]


def _one(n: int, t: dict, axes: dict) -> Kinematics:
    where = f"kinematics[{n}]"
    unknown = set(t) - _KEYS
    if unknown:
        raise MachineError(f"{where}: unknown key(s) {', '.join(sorted(unknown))}")
    kind = t.get("type")
    if isinstance(kind, bool) or not isinstance(kind, int):
        raise MachineError(f"{where}.type: the kinematics type MPK.TYPE is a whole number (1-24, 41-43)")
    if 100 <= kind <= 105:
        raise MachineError(f"{where}.type = {kind}: an OEM kinematics, whose equations fagorcnc cannot know")
    if kind not in TYPES:
        raise MachineError(f"{where}.type = {kind}: unknown kinematics type (1-24, 41-43; seed 002 L28779)")
    _family, letters, roles = TYPES[kind]
    count = len(letters)
    names = t.get("axes", [_AXIS_OF.get(c, c) for c in letters])
    if not isinstance(names, list) or len(names) != count or not all(isinstance(a, str) for a in names):
        raise MachineError(f"{where}.axes: type {kind} needs {count} rotary axis name(s)")
    for a in names:
        if a not in axes:
            raise MachineError(f"{where}.axes: {a} is not an axis of the machine")
        if not axes[a].rotary:
            raise MachineError(f"{where}.axes: {a} is not a rotary axis")
    if len(set(names)) != count:
        raise MachineError(f"{where}.axes: an axis appears twice")
    if "directions" in t:
        dirs = t["directions"]
        if not isinstance(dirs, list) or len(dirs) != count:
            raise MachineError(f"{where}.directions: {count} direction(s) [x, y, z], one per rotary axis")
        directions = [_vector(f"{where}.directions[{i + 1}]", d) for i, d in enumerate(dirs)]
    elif 5 <= kind <= 8:
        raise MachineError(f"{where}: an angular head (type {kind}) needs its inclined rotation directions "
                           "(directions = [[...], [...]])")
    else:
        directions = [_DIR[c] for c in letters]
    try:
        directions = [tuple(float(x) for x in unit(d)) for d in directions]
    except ValueError:
        raise MachineError(f"{where}.directions: a rotation direction is the null vector") from None
    pivots = t.get("pivots", [[0.0, 0.0, 0.0]] * count)
    if not isinstance(pivots, list) or len(pivots) != count:
        raise MachineError(f"{where}.pivots: {count} point(s) [x, y, z], one per rotary axis")
    pivots = [_vector(f"{where}.pivots[{i + 1}]", p) for i, p in enumerate(pivots)]
    joints = tuple(Joint(a, d, p, r == "H") for a, d, p, r in zip(names, directions, pivots, roles, strict=True))
    if count >= 2 and abs(float(np.dot(directions[0], directions[1]))) > 1.0 - 1e-9:
        raise MachineError(f"{where}.directions: the main and secondary rotation directions are parallel")
    if count == 3 and abs(float(np.dot(directions[1], directions[2]))) > 1.0 - 1e-9:
        raise MachineError(f"{where}.directions: the secondary and third rotation directions are parallel")
    tool = _vector(f"{where}.tool_direction", t.get("tool_direction", list(_Z)))
    try:
        tool = tuple(float(x) for x in unit(tool))
    except ValueError:
        raise MachineError(f"{where}.tool_direction: the null vector") from None
    nose = _vector(f"{where}.spindle_nose", t.get("spindle_nose", [0.0, 0.0, 0.0]))
    tol = t.get("tolerance", 0.001)
    if isinstance(tol, bool) or not isinstance(tol, int | float) or not 1e-6 <= tol <= 1.0:
        raise MachineError(f"{where}.tolerance: mm between 0.000001 and 1, got {tol!r}")
    return Kinematics(n, kind, joints, tool, nose, float(tol))


def parse_kinid(value: Any, kinematics: list[Kinematics]) -> int:
    """KINID: the kinematics in force at power-on; 0 = none (seed 002 L12532)."""
    if value is None:
        return 1 if kinematics else 0
    if isinstance(value, bool) or not isinstance(value, int) or not 0 <= value <= len(kinematics):
        raise MachineError(f"kinid: 0 (none) or a kinematics number 1..{len(kinematics)}, got {value!r}")
    return value


# ---------------------------------------------------------------------- #ANGAX (seed 002 ch. 15)
@dataclass(frozen=True)
class AngularAxis:
    """One angular transformation: ``angular`` (X') inclined by ``angle`` degrees from its Cartesian
    direction toward the ``orthogonal`` axis (Z)."""

    number: int
    angular: str
    orthogonal: str
    angle: float
    sense: int = 1
    offset: float = 0.0


def parse_angular_axes(tables: Any, axes: dict) -> list[AngularAxis]:
    """The ``[[angular_axes]]`` array of a machine file."""
    if tables is None:
        return []
    if not isinstance(tables, list) or not all(isinstance(t, dict) for t in tables):
        raise MachineError("angular_axes: expected an array of tables [[angular_axes]]")
    out = []
    for n, t in enumerate(tables, 1):
        where = f"angular_axes[{n}]"
        unknown = set(t) - {"angular_axis", "orthogonal_axis", "angle", "sense", "offset"}
        if unknown:
            raise MachineError(f"{where}: unknown key(s) {', '.join(sorted(unknown))}")
        ang, ort = t.get("angular_axis"), t.get("orthogonal_axis")
        for key, a in (("angular_axis", ang), ("orthogonal_axis", ort)):
            if not isinstance(a, str) or a not in axes:
                raise MachineError(f"{where}.{key}: an axis of the machine, got {a!r}")
            if axes[a].rotary:
                raise MachineError(f"{where}.{key}: {a} is rotary; both axes must be linear (L11858)")
        if ang == ort:
            raise MachineError(f"{where}: the angular and the orthogonal axis are the same")
        angle = t.get("angle")
        if isinstance(angle, bool) or not isinstance(angle, int | float) or not -89.0 <= angle <= 89.0:
            raise MachineError(f"{where}.angle: degrees between -89 and 89 (ANGANTR), got {angle!r}")
        sense = t.get("sense", 1)
        if sense not in (1, -1):
            raise MachineError(f"{where}.sense: 1 or -1, got {sense!r}")
        offset = t.get("offset", 0.0)
        if isinstance(offset, bool) or not isinstance(offset, int | float):
            raise MachineError(f"{where}.offset: a length (OFFANGAX), got {offset!r}")
        if offset != 0:
            raise MachineError(f"{where}.offset: a non-zero OFFANGAX is not computed by fagorcnc (how the CNC "
                               "uses it is in a figure the manual's text lost)")
        out.append(AngularAxis(n, ang, ort, float(angle), int(sense), float(offset)))
    return out



# ---------------------------------------------------------------------- #CAX (seed 002 ch. 14.1)
def parse_c_axes(table: Any, axes: dict, spindles: list[str]) -> dict[str, str]:
    """``c_axis = { S = "C" }``: the spindles that may work as a C axis (CAXIS) and the machine's rotary
    axis that then stands for them (CAXNAME, the name the program uses)."""
    if table is None:
        return {}
    if not isinstance(table, dict):
        raise MachineError('c_axis: expected a table { spindle = "axis" }, e.g. c_axis = { S = "C" }')
    out = {}
    for spindle, axis in table.items():
        if spindle not in spindles:
            raise MachineError(f"c_axis.{spindle}: not a spindle of the machine")
        if not isinstance(axis, str) or axis not in axes or not axes[axis].rotary:
            raise MachineError(f"c_axis.{spindle}: the C axis is a rotary axis of the machine, got {axis!r}")
        out[str(spindle)] = axis
    if len(set(out.values())) != len(out):
        raise MachineError("c_axis: two spindles share one C axis")
    return out
