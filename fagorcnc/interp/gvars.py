"""Program-state variables of the catalogue (issue 26 item 10; seed 002 ch. 22; spec 08).

* ``V.G.R``, ``V.G.I``/``J``/``K``, ``V.G.CIRERR[1]``/``[2]`` (L40454-L40573): the last prepared arc;
* ``V.G.EXTORG`` (L41746): the function that set the origin offset;
* ``V.G.MIRROR1..3`` (L40586): mirror on the first three channel axes;
* ``V.G.AXISNAMEn``, ``GAXISNAMEn``, ``SPDLNAMEn``, ``GSPDLNAMEn``, ``NUMCH``, ``AXIS``, ``NAXIS``, ``NSPDL``,
  ``MASTERSP`` (§22.26, L32743-L33043): the channel's configuration;
* ``V.G.MAXACCEL``/``MAXJERK`` (L36469-L36500): the path limits, written by the program;
* ``V.G.TOR``/``TOI``/``TOL``/``TOK`` (L39204-L39265): the tool offset of the blocks in preparation;
* ``V.G.FMAN``/``MANFPR`` (L39814, L39829): the manual feeds (no effect on automatic motion);
* ``V.A.FFGAIN``/``ACFGAIN`` (L41441, L41565): the active feed-forward and AC-forward percentages.
"""

from __future__ import annotations

import copy
import math

from .axes import axis_count, logical_name, slot_name
from .expressions import InterpError, whole
from .spindle_config import index_name as spindle_index_name
from .spindle_config import logical_name as spindle_logical_name
from .spindle_config import spindle_count
from .units import INCH


def arc_data(state, start: tuple, programmed: tuple, centre: tuple, end: tuple, plane: tuple) -> None:
    """Keep the last prepared arc for V.G.R/I/J/K/CIRERR: ``start``, ``end``, the ``programmed`` and the
    (G265) ``centre`` in the plane's part coordinates (mm), ``plane`` its (abscissa, ordinate, third) axes.
    Kept as given (points are tuples): :func:`arc_values` works the variables out when one is read, not
    for every arc."""
    state.arc_data = (start, programmed, centre, end, plane)


def arc_values(data: tuple) -> tuple:
    """``(radius, centre - start, programmed - centre, plane)`` of an :func:`arc_data` entry, the last two
    as ``{axis: mm}`` of the plane's two axes."""
    start, programmed, centre, end, plane = data
    a, o = plane[0], plane[1]
    rel = {a: centre[0] - start[0], o: centre[1] - start[1]}
    err = {a: programmed[0] - centre[0], o: programmed[1] - centre[1]}   # programmed - corrected (L40483)
    # the radius: from the centre to the end point, as the manual's G264 example reads it (L40564-L40573)
    return math.dist(end, centre), rel, err, plane


class ProgramVariables:
    """The program-state variables above, as ``Variables.plain_vars`` / ``axis_vars`` entries."""

    def __init__(self, variables) -> None:
        self.v = variables
        self.state = variables.state

    # ------------------------------------------------------------ tables
    def plain(self) -> dict:
        s = self.state
        out = {
            "V.G.R": (lambda i: self._arc(0), None),
            "V.G.I": (lambda i: self._arc(1), None),
            "V.G.J": (lambda i: self._arc(2), None),
            "V.G.K": (lambda i: self._arc(3), None),
            "V.G.CIRERR[]": (self._cirerr, None),
            "V.G.EXTORG": (self._extorg, None),
            "V.G.NUMCH": (lambda i: 1.0, None),
            "V.G.AXIS": (lambda i: axis_count(s, False), None),   # the axis configuration (interp/axes.py)
            "V.G.NAXIS": (lambda i: axis_count(s, True), None),
            "V.G.NSPDL": (lambda i: spindle_count(s), None),   # the spindle configuration (interp/spindle_config.py)
            "V.G.MASTERSP": (self._master, None),
            "V.G.MAXACCEL": (lambda i: self._path_limit(0), lambda i, v: self._set_path_limit(0, v)),
            "V.G.MAXJERK": (lambda i: self._path_limit(1), lambda i, v: self._set_path_limit(1, v)),
            "V.G.FMAN": (lambda i: self._manual_feed(94), lambda i, v: self._set_manual_feed(94, v)),
            "V.G.MANFPR": (lambda i: self._manual_feed(95), lambda i, v: self._set_manual_feed(95, v)),
        }
        for k in (1, 2, 3):
            out[f"V.G.MIRROR{k}"] = (lambda i, k=k: self._mirror(k), None)
        for n in range(1, 29):   # at most 28 axes (L2162)
            out[f"V.G.AXISNAME{n}"] = (lambda i, n=n: slot_name(s, n), None)   # holes, #RENAME AX, #PARK
            out[f"V.G.GAXISNAME{n}"] = (lambda i, n=n: logical_name(s, n), None)
        for n in range(1, 10):
            out[f"V.G.SPDLNAME{n}"] = (lambda i, n=n: spindle_index_name(s, n), None)
        for n in range(1, 38):
            out[f"V.G.GSPDLNAME{n}"] = (lambda i, n=n: spindle_logical_name(s, n), None)
        for name, fld in (("TOR", "radius"), ("TOI", "radius_wear"), ("TOL", "length"), ("TOK", "length_wear")):
            out[f"V.G.{name}"] = (lambda i, f=fld: self._prep_field(f), lambda i, v, f=fld: self._set_prep(f, v))
        return out

    def axis(self) -> dict:
        return {
            "V.A.FFGAIN": (lambda st, i, a: self._forward(134, "FFGAIN", a), None),
            "V.A.ACFGAIN": (lambda st, i, a: self._forward(135, "ACFGAIN", a), None),
            # the parameter set G112 or DEFAULTSET made active (L32845, L9307)
            "V.A.ACTIVSET": (lambda st, i, a: float(st.param_sets.get(a, 1)), None),
        }

    def spindle(self) -> dict:
        """``V.A.FFGAIN.S``, ``V.SP.FFGAIN`` ...: a spindle's percentages are the machine file's (L41441)."""
        return {
            "FFGAIN": lambda sp: self._forward(134, "FFGAIN", sp),
            "ACFGAIN": lambda sp: self._forward(135, "ACFGAIN", sp),
            "ACTIVSET": lambda sp: float(self.state.param_sets.get(sp, 1)),
        }

    #: execution values: their read stops block preparation (L41746, L32747, L36469, L39814, L41441)
    EXECUTION = frozenset({"V.G.EXTORG", "V.G.MAXACCEL", "V.G.MAXJERK", "V.G.FMAN", "V.G.MANFPR", "V.A.FFGAIN",
                           "V.A.ACFGAIN", *(f"V.G.GAXISNAME{n}" for n in range(1, 29))})

    # ------------------------------------------------------------ values
    def _unit(self) -> float:
        return INCH if self.state.modes["units"] == 70 else 1.0

    def _arc(self, k: int) -> float:
        data = self.state.arc_data
        if data is None:
            return 0.0
        data = arc_values(data)
        if k == 0:
            return data[0] / self._unit()
        axis = self._arc_axis(data, k - 1)
        return data[1].get(axis, 0.0) / self._unit()

    def _arc_axis(self, data, k: int) -> str | None:
        """I, J, K: the first, second and third channel axes; with G20 the abscissa, ordinate and third axis
        of the plane (L40466-L40474)."""
        if self.state.modes["plane"] == 20:
            return data[3][k]
        axes = list(self.state.axes)
        return axes[k] if k < len(axes) else None

    def _cirerr(self, index: tuple) -> float:
        n = whole(index[0])
        if n not in (1, 2):
            raise InterpError("INT045", f"V.G.CIRERR[{n}] does not exist: [1] and [2], the first two channel "
                              "axes (L40483)", 1)
        data = self.state.arc_data
        axes = list(self.state.axes)
        if data is None or len(axes) < n:
            return 0.0
        return arc_values(data)[2].get(axes[n - 1], 0.0) / self._unit()

    def _extorg(self, index: tuple) -> float:
        """0 G53, 1..6 G54..G59, n G159=n, 1000 a G92 preset (L41746-L41777)."""
        src = self.state.origin_source
        if src == "G92":
            return 1000.0
        if src.startswith("G159="):
            return float(src[5:])
        if src[1:].isdigit() and 54 <= int(src[1:]) <= 59:
            return float(int(src[1:]) - 53)
        return 0.0

    def _mirror(self, k: int) -> float:
        axes = list(self.state.axes)
        return 1.0 if k <= len(axes) and axes[k - 1] in self.state.transform.mirror else 0.0

    @staticmethod
    def _pick(table: list, n: int, what: str):
        if not 1 <= n <= len(table):
            raise InterpError("INT045", f"there is no {what} {n} (1..{len(table)})", 1)
        return table[n - 1]

    def _master(self, index: tuple) -> float:
        m = self.state.machine
        master = self.state.master_spindle()
        if master is None:   # no spindle in the channel
            return 0.0
        return float(len(m.axes) + list(m.spindles).index(master) + 1)

    def _path_limit(self, k: int) -> float:
        override = self.state.path_limits
        if override is not None:
            return override[k]
        p = self.state.machine.planner
        return p.max_path_acceleration if k == 0 else p.max_path_jerk

    def _set_path_limit(self, k: int, value: float) -> None:
        """The program's path acceleration or jerk, at once; 0 removes the path limit, the machine parameter
        included; M30 and reset restore the parameter (L36469-L36500)."""
        if not value >= 0:
            raise InterpError("INT045", f"V.G.{('MAXACCEL', 'MAXJERK')[k]} = {value:g}: a limit is 0 (none) or "
                              "positive", 1)
        current = [self._path_limit(0), self._path_limit(1)]
        current[k] = value
        self.state.path_limits = (current[0], current[1])
        self.state.dynamics_changed()

    def _manual_feed(self, mode: int) -> float:
        return self.state.manual_feeds.get(mode, 0.0)

    def _set_manual_feed(self, mode: int, value: float) -> None:
        if not value >= 0:
            raise InterpError("INT045", f"a manual feed of {value:g} is negative", 1)
        self.state.manual_feeds[mode] = value   # jog feeds: no effect on the program's moves (L39814)

    def _prep_offset(self):
        st = self.state
        if st.prep_offset is not None:
            return st.prep_offset
        off = st.tools.get(st.tool, {}).get(st.offset) if st.tool and st.offset else None
        if off is None:
            raise InterpError("INT051", f"no tool offset in preparation (T{st.tool} D{st.offset})", 1)
        return off

    def _prep_field(self, fld: str) -> float:
        return getattr(self._prep_offset(), fld) / self._unit()

    def _set_prep(self, fld: str, value: float) -> None:
        """A write changes the offset the next blocks are prepared with, never the tool table; the next tool
        or offset change reloads it from the table (L38884-L38943, L39204)."""
        st = self.state
        if st.prep_offset is None:
            st.prep_offset = copy.copy(self._prep_offset())
        setattr(st.prep_offset, fld, value * self._unit())

    def _forward(self, g: int, parameter: str, axis: str) -> float:
        """The active feed-forward (G134) or AC-forward (G135) percentage: the program's, else the machine
        parameter's (L4530-L4546, L4580-L4596); the PLC's has no value offline."""
        programmed = self.state.planner.get(f"G{g}", {})
        if axis in programmed:
            return programmed[axis]
        value = self.state.machine.machine_parameters.get((parameter, (), axis))
        if value is None:
            raise InterpError("INT245", f"V.A.{parameter}.{axis}: no G{g} programmed and the machine file gives no "
                              f"{parameter} ([machine_parameters] \"MPA.{parameter}.{axis}\" = %)", 1)
        return value
