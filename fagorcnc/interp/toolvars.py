"""Tool-table variables (seed 002 §22.49-§22.51, L37501-L39447; spec 08 B.11-B.13; issue 26 item 10).

Three views of the same data (:mod:`fagorcnc.config.tooldata`):

* ``V.TM.<name>[ofd]``: the active tool, ``[ofd]`` its offset (the active one when left out); execution
  values, a read stops block preparation (L37503);
* ``V.TM.<name>T[tl][ofd]``: any tool of the table (L38312); execution values;
* ``V.G.<name>``, ``V.A.TOFL.xn``: the tool in preparation (L38884): preparation values; a write changes only
  the values the next blocks are prepared with, never the table, and the next tool or offset change
  reloads them (L38890-L38895).

Turning tools are sized by their per-axis offsets TOFL and their tip radius TOTIPR (L39363, L38008):
fagorcnc applies neither, so an active offset with TOFL/TOFLW values (INT253) and radius compensation
with a turning tool (INT254) are refused before anything moves; TOR/TOI/TOL/TOK "are not valid for
turning tools" (L37896) and TURNCONFIG/LOCODE are "only for turning tools" (L37773, L37815): INT255.
"""

from __future__ import annotations

import copy
from dataclasses import dataclass

from ..config.tooldata import CODE_FIELDS, ToolData, is_turning
from .expressions import InterpError, whole

#: manual name -> (offset field, kind): "code" (a whole-number code), "length" (mm, inch under G70),
#: "number" (degrees, life: no unit conversion)
OFFSET_FIELDS: dict[str, tuple[str, str]] = {
    "DTYPE": ("type", "code"), "DSUBTYPE": ("subtype", "code"), "TURNCONFIG": ("turn_config", "code"),
    "LOCODE": ("location_code", "code"), "FIXORI": ("holder_orientation", "code"),
    "SPDLTURDIR": ("spindle_direction", "code"), "TOAN": ("plunge_angle", "number"),
    "TOTIPR": ("tip_radius", "length"), "TOWTIPR": ("tip_radius_wear", "length"),
    "TOCUTL": ("cutting_length", "length"), "NOSEA": ("nose_angle", "number"), "NOSEW": ("nose_width", "length"),
    "CUTA": ("cutting_angle", "number"), "TOMON": ("life_monitoring", "code"), "TLFN": ("nominal_life", "number"),
    "TLFR": ("real_life", "number"),
}
#: the active tool's offset fields a program may write (L37710-L38130); TOMON/TLFN/TLFR are read-only (L37594)
_ACTIVE_WRITABLE = frozenset(OFFSET_FIELDS) - {"TOMON", "TLFN", "TLFR"}
#: the tool in preparation: these are read-only (L39081, L39186, L39013-L39023), the others read and written
_PREP = ("DSUBTYPE", "LOCODE", "TOMON", "TLFN", "TLFR", "TOAN", "TOTIPR", "TOWTIPR", "TOCUTL", "NOSEA", "NOSEW",
         "CUTA")
_PREP_READ_ONLY = frozenset({"DSUBTYPE", "LOCODE", "TLFN", "TLFR"})
_TURNING_ONLY = frozenset({"TURNCONFIG", "LOCODE"})
_NOT_TURNING = ("TOR", "TOI", "TOL", "TOK")
_NOT_NEGATIVE = frozenset({"tip_radius", "cutting_length", "nose_width", "nominal_life", "real_life"})


def _active_offset(st):
    off = st.tools.get(st.tool, {}).get(st.offset) if st.tool and st.offset else None
    return st.prep_offset if st.prep_offset is not None else off


def refuse_uncomputed_offset(st, col: int) -> None:
    """INT253 when the active offset has per-axis offsets (TOFL/TOFLW, L38099-L38130): fagorcnc compensates the
    tool length on the longitudinal axis only, so every move with that offset would be wrong."""
    off = _active_offset(st)
    if off is None:
        return
    values = {a: v for a, v in {**off.axis_offsets}.items() if v} | {a: v for a, v in off.axis_offsets_wear.items()
                                                                     if v}
    if values:
        listed = " ".join(f"{a}" for a in sorted(values))
        raise InterpError("INT253", f"offset D{st.offset} of tool T{st.tool} has per-axis tool offsets (TOFL/TOFLW "
                          f"on {listed}, seed 002 L38099): fagorcnc does not apply them, so the moves with this "
                          "offset cannot be computed", col)


def refuse_turning_compensation(st, off, use: str) -> None:
    """INT254: radius compensation of a turning tool uses its tip radius TOTIPR and its shape factor LOCODE
    (L37815: the calibrated tip is the controlled point), which fagorcnc does not compute."""
    if off is not None and use.startswith("radius") and is_turning(off):
        raise InterpError("INT254", f"{use} with tool T{st.tool} D{st.offset}, a turning tool (DTYPE {off.type}, "
                          f"DSUBTYPE {off.subtype}): fagorcnc does not compute tip-radius compensation from the "
                          "shape factor LOCODE (seed 002 L37815)", 1)


@dataclass
class PrepTool(ToolData):
    """The tool in preparation's own data once the program writes V.G.TOTPn, REMLIFE or SPDLTURDIR (L38890)."""

    remaining: float | None = None   # V.G.REMLIFE written
    no_direction: bool = False       # V.G.SPDLTURDIR = 0 written


def _prep_record(data: ToolData) -> PrepTool:
    return PrepTool(status=data.status, family=data.family, custom=list(data.custom))


class ToolVariables:
    """The tool variables above, as ``Variables.plain_vars`` / ``axis_vars`` entries."""

    def __init__(self, variables) -> None:
        self.v = variables
        self.state = variables.state

    # ------------------------------------------------------------ tables
    def plain(self, existing: dict) -> dict:
        out: dict = {}
        for name, (fld, kind) in OFFSET_FIELDS.items():
            rw = name in _ACTIVE_WRITABLE
            get, put = self._field(name, fld, kind, self._active)
            out[f"V.TM.{name}"] = out[f"V.TM.{name}[]"] = (get, put if rw else None)
            get, put = self._field(name, fld, kind, self._any)
            out[f"V.TM.{name}T[]"] = out[f"V.TM.{name}T[][]"] = (get, put)   # all written (L38347-L38821)
        for name in _PREP:
            fld, kind = OFFSET_FIELDS[name]
            get, put = self._field(name, fld, kind, self._prep)
            out[f"V.G.{name}"] = (get, None if name in _PREP_READ_ONLY else put)
        # the preset spindle direction of the active tool; the program cancels it with 0 (L38289-L38299)
        out["V.G.SPDLTURDIR"] = (self._spdlturdir, self._cancel_spdlturdir)
        # the tool's own data
        out["V.TM.TSTATUS"] = (lambda i: float(self._data(self.state.tool).status), None)   # L37566
        out["V.TM.TLFF"] = (lambda i: float(self._data(self.state.tool).family), None)      # L37582
        out["V.G.TSTATUS"] = (lambda i: float(self._prep_data().status), None)              # L38956
        out["V.G.TLFF"] = (lambda i: float(self._prep_data().family), None)                 # L38972
        out["V.TM.TLFFT[]"] = (lambda i: float(self._data(self._tool(i)).family), self._set_family)   # L38335
        out["V.TM.NUMOFDT[]"] = (self._numofd, self._refuse_numofd)                          # L38415
        out["V.G.REMLIFE"] = (self._remlife, self._set_remlife)                              # L39033
        for n in range(1, 5):   # TOTP1-TOTP4 (L37668, L38400, L39045)
            out[f"V.TM.TOTP{n}"] = (lambda i, n=n: self._data(self.state.tool).custom[n - 1],
                                    lambda i, v, n=n: self._set_custom(self.state.tool, n, v))
            out[f"V.TM.TOTP{n}T[]"] = (lambda i, n=n: self._data(self._tool(i)).custom[n - 1],
                                       lambda i, v, n=n: self._set_custom(self._tool(i), n, v))
            out[f"V.G.TOTP{n}"] = (lambda i, n=n: self._prep_data().custom[n - 1],
                                   lambda i, v, n=n: self._set_prep_custom(n, v))
        for name in ("V.TM.REMLIFE", "V.TM.TSTATUST[]"):   # read by the PLC and the interface only (L37657, L38320)
            out[name] = (lambda i, name=name: self._interface_only(name), None)
        # per-axis offsets of the first three channel axes (L38231-L38248, L39395-L39412)
        for k in (1, 2, 3):
            for wear, label in ((False, "TOFL"), (True, "TOFLW")):
                out[f"V.TM.{label}{k}"] = (
                    lambda i, k=k, w=wear: self._axis_get(self._active(()), self._slot(k), w, plain=True),
                    lambda i, v, k=k, w=wear: self._axis_put(self._active(()), self._slot(k), w, v, True, plain=True))
                out[f"V.G.{label}{k}"] = (
                    lambda i, k=k, w=wear: self._axis_get(self._prep(()), self._slot(k), w, plain=True),
                    lambda i, v, k=k, w=wear: self._axis_put(self._prep_copy(), self._slot(k), w, v, True, plain=True))
        # TOR/TOI/TOL/TOK are not valid for turning tools (L37896-L37980, L38632-L38701, L39204-L39265)
        for name in _NOT_TURNING:
            for key, where in ((f"V.TM.{name}", self._active), (f"V.TM.{name}[]", self._active),
                               (f"V.TM.{name}T[]", self._any), (f"V.TM.{name}T[][]", self._any),
                               (f"V.G.{name}", self._prep)):
                if key in existing:
                    out[key] = self._not_turning(name, existing[key], where)
        return out

    def axis(self) -> dict:
        """``V.TM.TOFL[ofd].X``, ``V.TM.TOFLT[tl][ofd].X``, ``V.A.TOFL.X`` (the tool in preparation) and wears."""
        out: dict = {}
        for wear, label in ((False, "TOFL"), (True, "TOFLW")):
            entry = (lambda st, i, a, w=wear: self._axis_get(self._active(i), a, w),
                     lambda st, i, a, v, w=wear: self._axis_put(self._active(i), a, w, v, self._is_active(i)))
            out[f"V.TM.{label}"] = out[f"V.TM.{label}[]"] = entry
            entry = (lambda st, i, a, w=wear: self._axis_get(self._any(i), a, w),
                     lambda st, i, a, v, w=wear: self._axis_put(self._any(i), a, w, v, self._any_is_active(i)))
            out[f"V.TM.{label}T[]"] = out[f"V.TM.{label}T[][]"] = entry
            out[f"V.A.{label}"] = (lambda st, i, a, w=wear: self._axis_get(self._prep(()), a, w),
                                   lambda st, i, a, v, w=wear: self._axis_put(self._prep_copy(), a, w, v, True))
        return out

    @staticmethod
    def execution(names) -> frozenset:
        """Those of ``names`` whose read (and write) stops block preparation: every V.TM. one (L37503, L38314),
        and G.TLFF, G.SPDLTURDIR (L38972, L38291)."""
        return frozenset(k for k in names if k.startswith("V.TM.") or k in ("V.G.TLFF", "V.G.SPDLTURDIR"))

    # ------------------------------------------------------------ offsets
    def _offset(self, tool: int, d: int):
        off = self.state.tools.get(tool, {}).get(d)
        if off is None:
            raise InterpError("INT051", f"tool T{tool} has no offset D{d}", 1)
        return off

    def _active(self, index: tuple):
        st = self.state
        return self._offset(st.tool, _whole(index[0]) if index else st.offset)

    def _is_active(self, index: tuple) -> bool:
        return not index or _whole(index[0]) == self.state.offset

    def _tool(self, index: tuple) -> int:
        t = _whole(index[0])
        if t not in self.state.tools:
            raise InterpError("INT050", f"tool T{t} is not in the tool table", 1)
        return t

    def _any(self, index: tuple):
        return self._offset(self._tool(index), _whole(index[1]) if len(index) > 1 else self.state.offset)

    def _any_is_active(self, index: tuple) -> bool:
        st = self.state
        return _whole(index[0]) == st.tool and (len(index) < 2 or _whole(index[1]) == st.offset)

    def _prep(self, index: tuple):
        st = self.state
        off = _active_offset(st)
        if off is None:
            raise InterpError("INT051", f"no tool offset in preparation (T{st.tool} D{st.offset})", 1)
        return off

    def _prep_copy(self):
        """The offset of the blocks in preparation, made the channel's own copy before a write (L38890)."""
        st = self.state
        if st.prep_offset is None:
            st.prep_offset = copy.deepcopy(self._prep(()))
        return st.prep_offset

    # ------------------------------------------------------------ fields
    def _unit(self) -> float:
        return self.v._unit()

    def _field(self, name: str, fld: str, kind: str, where):
        prep = where == self._prep

        def get(index: tuple) -> float:
            off = where(index)
            self._check_kind(name, off)
            value = getattr(off, fld)
            return float(value) / self._unit() if kind == "length" else float(value)

        def put(index: tuple, value: float) -> None:
            off = self._prep_copy() if prep else where(index)
            self._check_kind(name, off)
            if kind == "code":
                allowed = CODE_FIELDS[fld][1]
                n = whole(value)
                if n not in allowed:
                    raise InterpError("INT045", f"{name} = {value:g}: the values are {allowed[0]}..{allowed[-1]} "
                                      "(seed 002 ch. 22.49)", 1)
                setattr(off, fld, n)
            else:
                if fld in _NOT_NEGATIVE and value < 0:
                    raise InterpError("INT045", f"{name} = {value:g}: a size or a life is not negative", 1)
                setattr(off, fld, value * self._unit() if kind == "length" else value)

        return get, put

    def _check_kind(self, name: str, off) -> None:
        turning = is_turning(off)
        if name in _TURNING_ONLY and not turning:
            raise InterpError("INT255", f"{name} is only for turning tools (seed 002 L37773, L37815); this offset "
                              f"is DTYPE {off.type} DSUBTYPE {off.subtype} (tools.T.D.type = 8 in the machine file)",
                              1)

    def _not_turning(self, name: str, entry: tuple, where):
        get, put = entry

        def checked(index: tuple):
            off = where(index)
            if is_turning(off):
                raise InterpError("INT255", f"{name} is not valid for turning tools (seed 002 L37896): this offset is "
                                  f"DTYPE {off.type} DSUBTYPE {off.subtype}; a turning tool is sized by TOFL and "
                                  "TOTIPR", 1)

        def read(index: tuple) -> float:
            checked(index)
            return get(index)

        def write(index: tuple, value: float) -> None:
            checked(index)
            put(index, value)

        return read, (write if put is not None else None)

    # ------------------------------------------------------------ per-axis offsets
    def _slot(self, k: int) -> str:
        axes = list(self.state.axes)
        if k > len(axes):
            raise InterpError("INT046", f"the channel has no axis {k} ({len(axes)} axes)", 1)
        return axes[k - 1]

    def _diameter(self, axis: str) -> float:
        """Diameters under G151 on a diameter axis (L38225-L38229)."""
        st = self.state
        return 2.0 if st.machine.axes[axis].diameter and st.modes["diameter"] == 151 else 1.0

    def _axis_get(self, off, axis: str, wear: bool, plain: bool = False) -> float:
        """In mm (Variables.get divides an axis variable by the unit itself), in the unit with ``plain``."""
        table = off.axis_offsets_wear if wear else off.axis_offsets
        value = table.get(axis, 0.0) * self._diameter(axis)
        return value / self.v._unit(axis) if plain else value

    def _axis_put(self, off, axis: str, wear: bool, value: float, active: bool, plain: bool = False) -> None:
        """A write (mm, in the unit with ``plain``); on the active offset or the one in preparation a value
        fagorcnc would not apply is refused (INT253) before it takes effect."""
        mm = (value * self.v._unit(axis) if plain else value) / self._diameter(axis)
        attr = "axis_offsets_wear" if wear else "axis_offsets"
        table = dict(getattr(off, attr))
        table[axis] = mm
        if active and mm:
            raise InterpError("INT253", f"{'TOFLW' if wear else 'TOFL'} on {axis} = {value:g} for the active offset "
                              f"D{self.state.offset}: fagorcnc does not apply per-axis tool offsets (seed 002 "
                              "L38099), so the next moves could not be computed", 1)
        setattr(off, attr, table)

    # ------------------------------------------------------------ the tool's own data
    def _data(self, tool: int) -> ToolData:
        return self.state.tool_data.get(tool) or ToolData()

    def _own(self, tool: int) -> ToolData:
        if tool not in self.state.tools:
            raise InterpError("INT050", f"tool T{tool} is not in the tool table", 1)
        return self.state.tool_data.setdefault(tool, ToolData())

    def _set_custom(self, tool: int, n: int, value: float) -> None:
        self._own(tool).custom[n - 1] = value

    def _set_family(self, index: tuple, value: float) -> None:
        n = whole(value)
        if n is None or n < 0:
            raise InterpError("INT045", f"V.TM.TLFFT = {value:g}: a family code is a whole number", 1)
        self._own(self._tool(index)).family = n

    def _prep_data(self) -> ToolData:
        st = self.state
        if st.prep_tool is not None:
            return st.prep_tool
        return self._data(st.tool)

    def _set_prep_custom(self, n: int, value: float) -> None:
        st = self.state
        if st.prep_tool is None:
            st.prep_tool = _prep_record(self._data(st.tool))
        st.prep_tool.custom[n - 1] = value

    def _remlife(self, index: tuple) -> float:
        """The remaining life of the offset in preparation: nominal minus real life (TLFN - TLFR, L39013-L39037),
        unless the program wrote it."""
        prep = self.state.prep_tool
        if prep is not None and prep.remaining is not None:
            return prep.remaining
        off = self._prep(())
        return max(0.0, off.nominal_life - off.real_life)

    def _set_remlife(self, index: tuple, value: float) -> None:
        st = self.state
        if not value >= 0:
            raise InterpError("INT045", f"V.G.REMLIFE = {value:g}: a remaining life is not negative", 1)
        if st.prep_tool is None:
            st.prep_tool = _prep_record(self._data(st.tool))
        st.prep_tool.remaining = value   # the preparation's value only (L38890)

    def _numofd(self, index: tuple) -> float:
        return float(len(self.state.tools[self._tool(index)]))

    def _refuse_numofd(self, index: tuple, value: float) -> None:
        raise InterpError("INT258", "V.TM.NUMOFDT: writing the number of offsets of a tool (seed 002 L38415) adds or "
                          "removes offsets whose data fagorcnc would have to invent; give them in the machine file's "
                          "tool table", 1)

    def _spdlturdir(self, index: tuple) -> float:
        st = self.state
        if st.prep_tool is not None and st.prep_tool.no_direction:
            return 0.0
        off = _active_offset(st)
        return float(off.spindle_direction) if off is not None else 0.0

    def _cancel_spdlturdir(self, index: tuple, value: float) -> None:
        """Only 0: the program cancels the preset direction for now, the table keeps it, the next tool change
        reloads it (L38293-L38299)."""
        if value != 0:
            raise InterpError("INT045", f"V.G.SPDLTURDIR = {value:g}: the program can only cancel the tool's preset "
                              "spindle direction, with 0 (seed 002 L38293)", 1)
        st = self.state
        if st.prep_tool is None:
            st.prep_tool = _prep_record(self._data(st.tool))
        st.prep_tool.no_direction = True

    @staticmethod
    def _interface_only(name: str) -> float:
        raise InterpError("INT241", f"{name.replace('[]', '[..]')} is read by the PLC and the interface only, not by a "
                          "part program (seed 002 L37657, L38320)", 1)


def _whole(v: float) -> int:
    n = whole(v)
    if n is None:
        raise InterpError("INT045", f"index [{v:g}] must be a whole number", 1)
    return n
