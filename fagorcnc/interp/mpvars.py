"""Machine-parameter variables ``V.MPG.*``, ``V.MPA.*``/``V.SP.*``, ``V.MPMAN.*``, ``V.MPM.*``, ``V.MPK.*``,
``V.TM.*`` (magazines), ``V.MTB.*`` (seed 002 §22.4-§22.12; spec 07 part B).

The catalogue (:mod:`fagorcnc.config.mpcatalogue`) says, for each name, where its value comes from:
fagorcnc's machine file (``G00FEED`` is ``axes.X.max_velocity``), the manual's value for what the machine
does not have (no tandem pair reads 0, L18009), the ``[machine_parameters]`` table for what fagorcnc does
not use (a drive's gains), or nothing (INT240).  Every one is read-only from a program (L17422; §1.9
L1809-L1812) except ``MTB.P``/``MTB.PF``.

Axis selector (L17628-L17722, L17821-L17968): a name (``.Z``, ``.S``: the channel does not matter,
L17830), a logical number (``.4``: the axes in machine order, then the spindles), with a channel
``V.[1].MPA.x.1`` the index in the channel; ``V.SP.x.2`` the second spindle of the system, ``V.SP.x``
the master spindle.  Per-set variables take the set first: ``V.MPA.G00FEED[1].X``; fagorcnc's machine
gives each axis set 1 (its own values) and the sets 2-4 of ``axes.X.sets`` (NPARSETS; G112 selects them).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING

from .expressions import InterpError, whole

if TYPE_CHECKING:
    from ..config.mpcatalogue import Entry

_AXIS_ORDER = "XYZUVWABC"


def name_code(name: str | None) -> float:
    """Code of an axis or spindle name (L32795-L32812): X=10 .. C=90, S=100, plus the name's digit."""
    if not name:
        return 0.0
    digit = int(name[1:]) if name[1:].isdigit() else 0
    if name[0] == "S":
        return float(100 + digit)
    if name[0] not in _AXIS_ORDER:
        return 0.0
    return float(10 * (_AXIS_ORDER.index(name[0]) + 1) + digit)


def _pick(where: str, table: list, n: int) -> object:
    if not 1 <= n <= len(table):
        raise InterpError("INT045", f"{where}[{n}] does not exist (entries 1..{len(table)})", 1)
    return table[n - 1]


def _none(what: str):
    def get(ctx, target, idx):
        raise InterpError("INT045", f"{what} [{idx[0]:g}] does not exist: the machine has none (the manual's "
                          "count of them reads 0)", 1)
    return get


def _axis(field: str, scale: float = 1.0):
    """A field of an axis of the machine file; None (the [machine_parameters] table) for a spindle."""
    def get(ctx, target, idx):
        ax = ctx.machine.axes.get(target)
        return None if ax is None else float(getattr(ax, field)) * scale
    return get


def _axis_set(field: str):
    """A dynamic field of an axis in the parameter set the read names (``V.MPA.ACCEL[2].X``; machine file
    ``axes.X.sets``, seed 002 L9307); None for a spindle (the [machine_parameters] table)."""
    from ..config.machine import SET_FIELDS

    k = SET_FIELDS.index(field)

    def get(ctx, target, idx):
        ax = ctx.machine.axes.get(target)
        return None if ax is None else float(ax.dynamics(ctx.active_set)[k])
    return get


def _axis_count(what: str):
    def get(ctx, target, idx):
        ax = ctx.machine.axes.get(target)
        return None if ax is None else float(ax.nsets if what == "nsets" else ax.default_set)
    return get


def _rotary_mode(*modes: str):
    return lambda ctx, t, i: 1.0 if ctx.machine.axes[t].rotary_mode in modes else 0.0


def _m_table(ctx) -> list[tuple[int, str]]:
    return sorted(ctx.machine.m_functions.items())


def _synchtype(ctx, target, idx):
    # "before": sent and waited for before the motion (2); "after": sent and waited for after it (8), L28692
    return 2.0 if _pick("V.MPM.SYNCHTYPE", _m_table(ctx), idx[0])[1] == "before" else 8.0


def _mtb(ctx, target, idx):
    return float(_pick("V.MTB.P", ctx.state.mtb, _mtb_index(ctx, idx) + 1))


def _mtb_index(ctx, idx) -> int:
    n = idx[0]
    if not 0 <= n < len(ctx.state.mtb):   # 0 <= i < MTB.SIZE (the examples use P0, P10)
        raise InterpError("INT045", f"V.MTB.P[{n}] does not exist (MTB.SIZE = {len(ctx.state.mtb)}: P0.."
                          f"P{len(ctx.state.mtb) - 1})", 1)
    return n


Source = Callable[[object, str | None, tuple], float | None]

#: catalogue source word -> getter(ctx, axis or spindle, indices) (None: look in [machine_parameters])
SOURCES: dict[str, Source] = {
    "naxis": lambda ctx, t, i: float(len(ctx.machine.axes)),
    "nspdl": lambda ctx, t, i: float(len(ctx.machine.spindles)),
    "chnaxis": lambda ctx, t, i: float(sum(a is not None for a in ctx.state.channel.slots)),   # #SET AX changes it
    "chnspdl": lambda ctx, t, i: float(len(ctx.state.spindle_config.current)),   # #SET SP, #FREE SP (L19444)
    # AXISEXCH (L21089): axes.X.exchange; a spindle's "MPA.AXISEXCH.S" of [machine_parameters], else 1
    "axisexch": lambda ctx, t, i: float(ctx.machine.axes[t].exchange if t in ctx.machine.axes else
                                        ctx.machine.machine_parameters.get(("AXISEXCH", (), t), 1.0)),
    # [machine_parameters], else fagorcnc's value (interp/spindle_config.py, interp/threading.py)
    "renamecancel": lambda ctx, t, i: ctx.machine.machine_parameters.get(("RENAMECANCEL", (), None), 0.0),
    "threadovr": lambda ctx, t, i: ctx.machine.machine_parameters.get(("THREADOVR", (), t), 0.0),
    # two channel axes make a "plane" configuration (0), more a trihedron (1), L19400-L19500
    "geoconfig": lambda ctx, t, i: 0.0 if len(ctx.state.axes) == 2 else 1.0,
    "nogroup": _none("multi-axis group"),
    "nompg": _none("hand wheel"),
    "nomz": _none("magazine"),
    "looptime": lambda ctx, t, i: ctx.machine.planner.servo_period * 1000.0,   # ms
    "inches": lambda ctx, t, i: float(ctx.machine.default("INCHES")),
    "minlocp": lambda ctx, t, i: float(ctx.machine.local_params[0]),
    "maxlocp": lambda ctx, t, i: float(ctx.machine.local_params[1]),
    "minglbp": lambda ctx, t, i: float(ctx.machine.global_params[0]),
    "maxglbp": lambda ctx, t, i: float(ctx.machine.global_params[1]),
    "mincomp": lambda ctx, t, i: float(ctx.machine.common_params[0]),
    "maxcomp": lambda ctx, t, i: float(ctx.machine.common_params[1]),
    "corner": lambda ctx, t, i: ctx.machine.planner.corner,
    "fastfactor": lambda ctx, t, i: ctx.machine.planner.fast_factor,
    "mincorfeed": lambda ctx, t, i: ctx.machine.planner.min_corner_feed,
    "hscround": lambda ctx, t, i: ctx.machine.planner.hsc_round,
    "hscmode": lambda ctx, t, i: float(ctx.machine.planner.hsc_default_mode),
    # KINID 255 = no kinematics at power-on (L19871); fagorcnc's kinid 0 is that
    "kinid": lambda ctx, t, i: float(ctx.machine.kinid or 255),
    "slopetype": lambda ctx, t, i: float(ctx.machine.planner.slope_type),
    "roundtype": lambda ctx, t, i: float(ctx.machine.planner.round_type),
    "maxround": lambda ctx, t, i: ctx.machine.planner.max_round,
    "roundfeed": lambda ctx, t, i: ctx.machine.planner.round_feed,
    "cirinerr": lambda ctx, t, i: ctx.machine.cirinerr,
    "cirinfact": lambda ctx, t, i: ctx.machine.cirinfact,
    "maxfeed": lambda ctx, t, i: ctx.machine.max_feed,
    # DEFAULTFEED reads 0 whenever MAXFEED is 0 (L20776)
    "defaultfeed": lambda ctx, t, i: float(ctx.machine.default("DEFAULTFEED")) if ctx.machine.max_feed else 0.0,
    "maxaccel": lambda ctx, t, i: ctx.machine.planner.max_path_acceleration,
    "maxjerk": lambda ctx, t, i: ctx.machine.planner.max_path_jerk,
    "axistype": lambda ctx, t, i: 2.0 if ctx.machine.axes[t].rotary else 1.0,   # L21117
    # AXISMODE 0 module (rollover), 1 linearlike (L21555); UNIDIR, SHORTESTWAY (L21606, L21625)
    "axismode": _rotary_mode("linearlike"),
    "unidir": _rotary_mode("unidirectional"),
    "shortestway": _rotary_mode("positioning"),   # the shortest way (fagorcnc "positioning", spec 02 §3)
    "caxis": lambda ctx, t, i: 1.0 if t in ctx.machine.c_axes or t in ctx.machine.c_axes.values() else 0.0,
    "spdlstop": lambda ctx, t, i: float(ctx.machine.default("SPDLSTOP")),
    "srevm05": lambda ctx, t, i: float(ctx.machine.default("SREVM05")),
    "poslimit": _axis("max_limit"),
    "neglimit": _axis("min_limit"),
    "diamprog": lambda ctx, t, i: 1.0 if ctx.machine.axes[t].diameter else 0.0,
    "g00feed": _axis_set("max_velocity"),
    # 0 = not limited: G00FEED is then the maximum of every move (L24920); fagorcnc's max_feed 0 is that
    "axismaxfeed": _axis_set("max_feed"),
    "accel": _axis_set("max_acceleration"),
    "jerk": _axis_set("max_jerk"),
    "nparsets": _axis_count("nsets"),        # NPARSETS (L23810): 1 + the machine file's axes.X.sets
    "defaultset": _axis_count("default"),    # DEFAULTSET (L23860)
    "refvalue": _axis("home"),
    "moduplim": _axis("module"),
    "modlowlim": lambda ctx, t, i: 0.0,   # fagorcnc's rotary module runs from 0 (MODLOWLIM 0, MODUPLIM module)
    "mirrorcancel": lambda ctx, t, i: float(ctx.machine.default("MIRRORCANCEL")),
    "iplane": lambda ctx, t, i: float(ctx.machine.default("IPLANE")),
    "isystem": lambda ctx, t, i: float(ctx.machine.default("ISYSTEM")),
    "imove": lambda ctx, t, i: float(ctx.machine.default("IMOVE")),
    "ifeed": lambda ctx, t, i: float(ctx.machine.default("IFEED")),
    "icorner": lambda ctx, t, i: float(ctx.machine.default("ICORNER")),
    "ircomp": lambda ctx, t, i: float(ctx.machine.default("IRCOMP")),
    "mtablesize": lambda ctx, t, i: float(len(ctx.machine.m_functions)),
    "mnum": lambda ctx, t, i: float(_pick("V.MPM.MNUM", _m_table(ctx), i[0])[0]),
    "synchtype": _synchtype,
    "mtbsize": lambda ctx, t, i: float(len(ctx.state.mtb)),
    "mtb": _mtb,
}


class MachineParameters:
    """Reads of the machine-parameter families against the interpreter's machine and channel."""

    def __init__(self, state) -> None:
        self.state = state
        self.machine = state.machine
        self.active_set = 1   # the [set] of the per-set read being answered (V.MPA.ACCEL[2].X)

    # ------------------------------------------------------------ name
    def find(self, name: str, index: tuple, channel: bool, col: int):
        """``(entry, indices, target)`` for ``name`` (the parser's ``V.MPA.G00FEED[].X``), None when the
        catalogue has no such name."""
        parts = name.split(".")
        if len(parts) not in (3, 4) or parts[0] != "V":
            return None
        prefix, word = parts[1], parts[2]
        base = word.replace("[]", "")
        from ..config.mpcatalogue import lookup  # on first use: a program that reads no V.MP variable never needs it

        found = lookup(prefix, base)
        if found is None:
            return None
        entry, number = found
        if prefix == "SP" and not entry.on:
            return None
        wanted = max(entry.indices, 0) + (1 if entry.per_set else 0)
        given = word.count("[]")
        if given != wanted and not (entry.indices == -1 and given == wanted + 1):
            what = "the parameter set [set]" if entry.per_set and given < wanted else f"{wanted} index(es)"
            raise InterpError("INT244", f"{name.replace('[]', '[..]')} needs {what}, e.g. "
                              f"V.{prefix}.{base}{'[1]' * max(wanted, 1)}{'.X' if entry.on else ''}", col)
        idx = tuple(_integer(v, col) for v in index)
        set_no = 1
        if entry.per_set:
            set_no = idx[0]
            if not 1 <= set_no <= 4:
                raise InterpError("INT242", f"parameter set [{set_no}] does not exist: an axis has sets 1 to 4 "
                                  "(seed 002 L9309)", col)
            idx = idx[1:]
        if "#" in entry.name or "?" in entry.name:
            idx = (number if number is not None else 1, *idx)   # JOGKEYDEF is keyboard 1 (L28412)
        target = self._target(entry, prefix, parts[3] if len(parts) == 4 else None, channel, name, col)
        ax = self.machine.axes.get(target) if target is not None else None
        if set_no > (ax.nsets if ax is not None else 1):
            raise InterpError("INT242", f"parameter set [{set_no}] does not exist: the machine file gives "
                              f"{target} {ax.nsets if ax is not None else 1} set(s) (NPARSETS; axes.{target}.sets)",
                              col)
        self.active_set = set_no
        return entry, idx, target

    def _target(self, entry: Entry, prefix: str, token: str | None, channel: bool, name: str, col: int):
        if not entry.on:
            if token is not None:
                raise InterpError("INT044", f"unknown variable {name.replace('[]', '[..]')}: "
                                  f"V.{prefix}.{name.split('.')[2]} takes no axis", col)
            return None
        m = self.machine
        if prefix == "SP":
            spindles = m.spindles
            if token is None:   # the master spindle of the channel (L17714)
                target = self.state.master_spindle()
                if target is None:
                    raise InterpError("INT046", "this channel has no spindle" if spindles else "this machine has no "
                                      "spindle", col)
            elif self.state.spindle_config.variable(token) is not None:   # its name in the channel (L15209)
                target = self.state.spindle_config.variable(token)
            elif token.isdigit() and 1 <= int(token) <= len(spindles):
                target = spindles[int(token) - 1]   # index in the system (L17652)
            else:
                raise InterpError("INT046", f"spindle {token} does not exist on this machine", col)
        elif token is None:
            raise InterpError("INT244", f"{name.replace('[]', '[..]')} needs the axis or spindle: "
                              f"{name.replace('[]', '[1]')}.X", col)
        elif token[0] == "S" and self.state.spindle_config.variable(token) is not None:
            target = self.state.spindle_config.variable(token)   # a spindle by its name in the channel (L15209)
        elif token in m.axes or token in m.spindles:
            target = token
        elif token.isdigit():
            n = int(token)
            table = list(self.state.axes) if channel else list(m.axes) + list(m.spindles)
            if not 1 <= n <= len(table):
                what = "index in the channel" if channel else "logical number"
                raise InterpError("INT046", f"no axis or spindle with {what} {n} (1..{len(table)})", col)
            target = table[n - 1]
        else:
            raise InterpError("INT046", f"axis {token} does not exist on this machine", col)
        kind = "s" if target in m.spindles else "r" if m.axes[target].rotary else "l"
        if kind not in entry.on:
            valid = {"l": "linear axes", "r": "rotary axes", "s": "spindles"}
            raise InterpError("INT243", f"V.{prefix}.{entry.name} is for " +
                              " and ".join(valid[k] for k in entry.on) + f" only, not {target} (L{entry.seed[1:]})",
                              col)
        return target

    # ------------------------------------------------------------ value
    def read(self, entry: Entry, idx: tuple, target: str | None, col: int) -> float:
        label = _label(entry, idx, target)
        if entry.access == "IF":
            raise InterpError("INT241", f"{label} is read by the interface only, not by a part program "
                              f"(seed 002 {entry.seed})", col)
        if entry.source == "none":
            raise InterpError("INT240", f"{label} is a machine parameter of the manual (seed 002 {entry.seed}) "
                              "that fagorcnc does not implement: what it changes is not computed", col)
        if entry.execution:
            self.state.sync = True   # the read stops block preparation (L17437)
        value = None
        if entry.source.startswith("="):
            value = float(entry.source[1:])
        elif entry.source != "free":
            try:
                value = SOURCES[entry.source](self, target, idx)
            except InterpError as exc:
                exc.col = col
                raise
        if value is None:
            value = self.machine.machine_parameters.get((entry.name, idx, target))
            if value is None:
                raise InterpError("INT245", f"{label}: this machine file does not give it (fagorcnc does not use "
                                  f"it; [machine_parameters] \"{_key(entry, idx, target)}\" = value, "
                                  f"seed 002 {entry.seed})", col)
        return value

    def write(self, entry: Entry, idx: tuple, target: str | None, value: float, col: int) -> None:
        if entry.access != "RWE":
            raise InterpError("INT048", f"{_label(entry, idx, target)} is a machine parameter: read-only from a "
                              "program (seed 002 L1809-L1812)", col)
        self.state.sync = True   # writing MTB.P stops block preparation (L29210)
        try:
            self.state.mtb[_mtb_index(self, idx)] = value
        except InterpError as exc:
            exc.col = col
            raise


def _integer(v: float, col: int) -> int:
    n = whole(v)
    if n is None:
        raise InterpError("INT045", f"index [{v:g}] must be a whole number", col)
    return n


def _key(entry: Entry, idx: tuple, target: str | None) -> str:
    from ..config.mpcatalogue import PREFIX

    name = entry.name
    if "#" in name or "?" in name:
        name = name.replace("#", str(idx[0])).replace("?", str(idx[0]) if idx[0] != 1 else "")
        idx = idx[1:]
    return f"{PREFIX[entry.family]}.{name}" + "".join(f"[{i}]" for i in idx) + (f".{target}" if target else "")


def _label(entry: Entry, idx: tuple, target: str | None) -> str:
    return "V." + _key(entry, idx, target)
