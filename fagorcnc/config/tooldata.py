"""The tool table's data beyond length and radius (seed 002 §22.49-§22.51, L37501-L39447; spec 08 B.11-B.13).

A machine file's tool table gives, per offset ``tools.T.D``, the manual's fields by a descriptive key:

=====================  ============  ==========================================================  ========
key                    manual        values                                                      seed
=====================  ============  ==========================================================  ========
``type``               DTYPE         1 milling, 2 drilling, 3 facing, 4 reaming, 5 boring bar,   L37710
                                     6 threading, 7 grooving/parting, 8 turning, 9 other,
                                     10 probe (default 1: fagorcnc sizes a tool by L and R)
``subtype``            DSUBTYPE      0 none .. 15 (the manual's table, L37726)                   L37726
``turn_config``        TURNCONFIG    0-7, axis orientation of a turning tool                     L37773
``location_code``      LOCODE        0-9, shape factor (calibrated tip) of a turning tool        L37815
``holder_orientation`` FIXORI        0 frontal axis, 1 longitudinal axis                         L37864
``spindle_direction``  SPDLTURDIR    0 none, 1 M03 / right, 2 M04 / left                         L37880
``plunge_angle``       TOAN          degrees                                                     L37981
``tip_radius``         TOTIPR        mm                                                          L38008
``tip_radius_wear``    TOWTIPR       mm                                                          L38020
``cutting_length``     TOCUTL        mm                                                          L38032
``nose_angle``         NOSEA         degrees                                                     L38044
``nose_width``         NOSEW         mm                                                          L38075
``cutting_angle``      CUTA          degrees                                                     L38087
``life_monitoring``    TOMON         0 none, 1 machining time, 2 number of operations            L37594
``nominal_life``       TLFN          the monitoring's unit                                       L37633
``real_life``          TLFR          the monitoring's unit                                       L37645
``axis_offsets``       TOFL          { X = 30, Z = 50 }: offset (length) of the tool per axis    L38099
``axis_offsets_wear``  TOFLW         the same, its wear                                          L38123
=====================  ============  ==========================================================  ========

and, per tool, ``tools.T.status`` (TSTATUS 0 available, 1 rejected, 2 worn, L37566), ``tools.T.family``
(TLFF, the family code, L37582) and ``tools.T.custom`` (TOTP1-TOTP4, up to four numbers, L37668).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

from .errors import MachineError

#: per-offset whole-number codes: key -> (manual name, allowed values)
CODE_FIELDS: dict[str, tuple[str, tuple[int, ...]]] = {
    "type": ("DTYPE", tuple(range(1, 11))),
    "subtype": ("DSUBTYPE", tuple(range(0, 16))),
    "turn_config": ("TURNCONFIG", tuple(range(0, 8))),
    "location_code": ("LOCODE", tuple(range(0, 10))),
    "holder_orientation": ("FIXORI", (0, 1)),
    "spindle_direction": ("SPDLTURDIR", (0, 1, 2)),
    "life_monitoring": ("TOMON", (0, 1, 2)),
}
#: per-offset real numbers: key -> manual name
REAL_FIELDS: dict[str, str] = {
    "plunge_angle": "TOAN", "tip_radius": "TOTIPR", "tip_radius_wear": "TOWTIPR", "cutting_length": "TOCUTL",
    "nose_angle": "NOSEA", "nose_width": "NOSEW", "cutting_angle": "CUTA", "nominal_life": "TLFN",
    "real_life": "TLFR",
}
#: per-offset tables of axis values: key -> manual name
AXIS_FIELDS: dict[str, str] = {"axis_offsets": "TOFL", "axis_offsets_wear": "TOFLW"}
#: the keys of ``tools.T`` that are the tool's own data, not an offset
TOOL_KEYS = ("status", "family", "custom")

#: DTYPE 8 "outil à tourner" and the inserts of DSUBTYPE 5 (threading), 11-13 (turning, grooving, parting)
#: are turning tools: the manual sizes them by TOFL and TOTIPR, and TOR/TOI/TOL/TOK "are not valid" for them
#: (L37896); TURNCONFIG and LOCODE are "only for turning tools" (L37773, L37815).
TURNING_SUBTYPES = (5, 11, 12, 13)


@dataclass
class ToolData:
    """The data of a tool (not of one of its offsets): TSTATUS, TLFF, TOTP1-TOTP4."""

    status: int = 0                          # 0 available, 1 rejected, 2 worn (L37566)
    family: int = 0                          # TLFF (L37582)
    custom: list[float] = field(default_factory=lambda: [0.0, 0.0, 0.0, 0.0])   # TOTP1-TOTP4 (L37668)


def is_turning(off) -> bool:
    """Whether an offset describes a turning tool (see TURNING_SUBTYPES)."""
    return off.type == 8 or off.subtype in TURNING_SUBTYPES


def _finite(where: str, value: Any) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value):
        raise MachineError(f"{where}: expected a number, got {value!r}")
    return float(value)


def offset_field(where: str, key: str, value: Any, axes: dict) -> object:
    """The value of an extended offset key (CODE_FIELDS, REAL_FIELDS, AXIS_FIELDS), checked."""
    if key in CODE_FIELDS:
        name, allowed = CODE_FIELDS[key]
        if isinstance(value, bool) or not isinstance(value, int | float) or value not in allowed:
            raise MachineError(f"{where} ({name}) must be one of {allowed[0]}..{allowed[-1]}, got {value!r}")
        return int(value)
    if key in REAL_FIELDS:
        v = _finite(where, value)
        if key in ("tip_radius", "cutting_length", "nose_width", "nominal_life", "real_life") and v < 0:
            raise MachineError(f"{where} ({REAL_FIELDS[key]}) must not be negative, got {v:g}")
        return v
    if not isinstance(value, dict):
        raise MachineError(f"{where} ({AXIS_FIELDS[key]}): expected a table of axis values, e.g. {{ X = 30.0 }}, "
                           f"got {value!r}")
    out = {}
    for a, v in value.items():
        if str(a) not in axes:
            raise MachineError(f"{where}.{a}: the machine has no axis {a} (axes: {' '.join(map(str, axes))})")
        out[str(a)] = _finite(f"{where}.{a}", v)
    return out


def tool_data(where: str, spec: dict) -> ToolData:
    """``tools.T.status``, ``.family``, ``.custom`` of one tool, checked."""
    data = ToolData()
    if "status" in spec:
        v = spec["status"]
        if isinstance(v, bool) or v not in (0, 1, 2):
            raise MachineError(f"{where}.status (TSTATUS) must be 0 (available), 1 (rejected) or 2 (worn), "
                               f"got {v!r}")
        data.status = int(v)
    if "family" in spec:
        v = spec["family"]
        if isinstance(v, bool) or not isinstance(v, int | float) or v != int(v) or not 0 <= v <= 4294967295:
            raise MachineError(f"{where}.family (TLFF) must be a whole number, got {v!r}")
        data.family = int(v)
    if "custom" in spec:
        v = spec["custom"]
        if not isinstance(v, list | tuple) or len(v) > 4:
            raise MachineError(f"{where}.custom (TOTP1-TOTP4): expected a list of at most 4 numbers, got {v!r}")
        values = [_finite(f"{where}.custom[{i}]", x) for i, x in enumerate(v)]
        data.custom = values + [0.0] * (4 - len(values))
    return data
