"""The # statements of coordinate transformations and kinematics (seed 002 ch. 17, L12393-L13431):
#KIN ID, #CS, #ACS, #RTCP, #TLC, #TOOL ORI.  Called from :mod:`fagorcnc.interp.sentences`."""

from __future__ import annotations

import numpy as np

from ..interp.expressions import InterpError, whole
from ..syntax.ast import ItemList, Keyed, Name
from . import angax, caxis, frames, tangential
from .rotation import wrap
from .solve import KinematicsError, orientations, tool_direction_part
from .state import MAX_ACTIVE, KinState

#: Statements handled here (the keyword after #, and #TOOL followed by ORI).
KEYWORDS = frozenset({"KIN", "CS", "ACS", "RTCP", "TLC", "FACE", "CYL", "ANGAX", "TANGCTRL", "CAX"})


def handles(kw: str, sub: str | None) -> bool:
    return kw in KEYWORDS or (kw == "TOOL" and sub == "ORI")


def execute(interp, node, src=None) -> list:
    """Run one statement of these chapters; the motion records it makes (#CAX references its axis)."""
    st = interp.state
    kin: KinState = st.kin
    kw = node.keyword
    if kw == "CAX":
        return caxis.cax_statement(interp, node, src)
    tokens = list(_flat(node.args))
    if kw == "KIN":
        _kin_id(interp, kin, tokens, node.col)
    elif kw in ("CS", "ACS"):
        _coordinate_system(interp, kin, kw, tokens, node.col)
    elif kw == "RTCP":
        _rtcp(interp, kin, tokens, node.col)
    elif kw == "TLC":
        _tlc(interp, kin, tokens, node.col)
    elif kw in ("FACE", "CYL"):
        caxis.statement(interp, node, list(node.args))
    elif kw == "ANGAX":
        angax.statement(interp, node)
    elif kw == "TANGCTRL":
        tangential.statement(interp, node)
    else:
        _tool_ori(interp, kin, node.col)
    return []


def _flat(args):
    """The statement's items in order, a keyword with a value written as the keyword then the value."""
    for a in args:
        if type(a) is Keyed:
            yield Name(a.name, a.col)
            yield a.value
        else:
            yield a


def _name(t) -> str | None:
    return t.name if type(t) is Name else None


def _number(interp, t, col: int) -> float:
    if type(t) in (Name, ItemList) or t is None:
        raise InterpError("KIN005", "a number is missing here", col)
    return interp.evaluator.value(t)


# ---------------------------------------------------------------------- #KIN ID
def _kin_id(interp, kin: KinState, tokens, col: int) -> None:
    # seed 002 L12525-L12555: #KIN ID [n]; not while RTCP or TLC is active
    if len(tokens) != 2 or _name(tokens[0]) != "ID":
        raise InterpError("KIN005", "write #KIN ID [n] (n = the kinematics, 1..6)", col)
    n = whole(_number(interp, tokens[1], col))
    if n is None or not 1 <= n <= 6:
        raise InterpError("KIN001", "#KIN ID: the kinematics number is 1..6 (L12527)", col)
    if _identity(interp, kin, "#KIN ID", col):
        return
    if n > len(kin.kinematics):
        raise InterpError("KIN001", f"#KIN ID [{n}]: the machine defines {len(kin.kinematics)} kinematics "
                          "([[kinematics]] in the machine file)", col)
    if kin.rtcp or kin.tlc is not None:
        raise InterpError("KIN002", "#KIN ID cannot change the kinematics while #RTCP or #TLC is active "
                          "(L12545)", col)
    kin.kinid = n
    kin.rebuild(interp.state)


# ---------------------------------------------------------------------- #RTCP / #TLC / #TOOL ORI
def _identity(interp, kin: KinState, what: str, col: int) -> bool:
    """A machine with neither kinematics nor rotary axes (a 3-axis mill running a 3+2 CAM post): the
    tool is always along Z, so the kinematics is the identity and the path is exact.  Told once."""
    st = interp.state
    if kin.kinematics or any(st.machine.axes[a].rotary for a in st.axes):
        return False
    if not kin.identity_told:
        kin.identity_told = True
        interp.message("KIN024", "info", f"{what}: the machine has no rotary axes and no [[kinematics]]; the tool "
                       "stays along Z, the tool tip is the programmed point", col)
    return True


def _needs_kinematics(kin: KinState, what: str, col: int):
    k = kin.current
    if k is None:
        raise InterpError("KIN003", f"{what} needs a kinematics: none is selected (#KIN ID, or [[kinematics]] "
                          "and kinid in the machine file)", col)
    if k.c_axis:
        raise InterpError("KIN003", f"{what} needs a spindle-head or table kinematics; kinematics {k.number} is "
                          f"a {k.family}", col)
    return k


def _on_off(tokens, what: str, col: int) -> str:
    word = _name(tokens[0]) if tokens else None
    if word not in ("ON", "OFF"):
        raise InterpError("KIN005", f"write {what} ON or {what} OFF", col)
    return word


def _rtcp(interp, kin: KinState, tokens, col: int) -> None:
    # seed 002 L13215-L13341
    word = _on_off(tokens, "#RTCP", col)
    if len(tokens) != 1:
        raise InterpError("KIN005", f"#RTCP {word} takes nothing more", col)
    if word == "ON":
        if kin.tlc is not None:
            raise InterpError("KIN004", "#RTCP ON while #TLC is active (L13229): switch #TLC OFF first", col)
        if not _identity(interp, kin, "#RTCP", col):
            _needs_kinematics(kin, "#RTCP", col)
        kin.rtcp = True
    else:
        kin.rtcp = False
    kin.rebuild(interp.state)


def _tlc(interp, kin: KinState, tokens, col: int) -> None:
    # seed 002 L13343-L13373: #TLC ON [d] / #TLC OFF; d = real minus theoretical tool length
    word = _on_off(tokens, "#TLC", col)
    if word == "ON":
        if len(tokens) != 2:
            raise InterpError("KIN005", "write #TLC ON [d], d = real minus theoretical tool length", col)
        if kin.rtcp:
            raise InterpError("KIN004", "#TLC ON while #RTCP is active (L13359): switch #RTCP OFF first", col)
        kin.tlc = interp.iso.length(_number(interp, tokens[1], col))
    else:
        if len(tokens) != 1:
            raise InterpError("KIN005", "#TLC OFF takes nothing more", col)
        kin.tlc = None
    kin.rebuild(interp.state)


def _tool_ori(interp, kin: KinState, col: int) -> None:
    # seed 002 L13131-L13213: the tool perpendicular to the active plane, during the next move
    st = interp.state
    if _identity(interp, kin, "#TOOL ORI", col):
        r, _v = kin.plane()
        if abs(r[2, 2] - 1.0) > 1e-9:
            raise InterpError("KIN013", "#TOOL ORI: the machine has no rotary axes to put the tool perpendicular "
                              "to the inclined plane", col)
        return
    _needs_kinematics(kin, "#TOOL ORI", col)
    kin.tool_ori = bool(kin.active) or kin.rtcp
    kin.pending_ori = True
    kin.rebuild(st)
    solution_angles(kin, st, col)   # refused now when no position of the rotary axes gives it


def solution_angles(kin: KinState, st, col: int) -> dict:
    """The rotary positions of #TOOL ORI: the tool along Z' of the active plane (SOL2: solution 2)."""
    k = kin.current
    r, _v = kin.plane()
    current = {a: st.machine_pos[a] for a in k.axes}
    try:
        sols = orientations(k, r[:, 2], current)
    except KinematicsError as exc:
        raise InterpError("KIN013", f"#TOOL ORI: {exc}", col) from None
    sol = sols[1] if kin.sol2 and len(sols) > 1 else sols[0]
    return {a: _nearest(st, a, v) for a, v in sol.items()}


def _nearest(st, axis: str, angle: float) -> float:
    """``angle`` or a turn away from it, nearest the axis' present position within its limits."""
    cur = st.machine_pos[axis]
    ax = st.machine.axes[axis]
    if ax.rotary_mode != "linearlike":
        return wrap(angle) % 360.0 if ax.rotary_mode != "positioning" else angle
    best = None
    for k in range(-3, 4):
        v = angle + 360.0 * k
        if st.lower_limits[axis] - 1e-9 <= v <= st.upper_limits[axis] + 1e-9:
            if best is None or abs(v - cur) < abs(best - cur):
                best = v
    return angle if best is None else best


def adjust_target(interp, bw, end: dict) -> None:
    """The end point of a move as this chapter changes it: #TOOL ORI's rotary positions, a suspended
    #ANGAX; a tangential axis may not be programmed."""
    kin: KinState = interp.state.kin
    if kin.c_axes:
        caxis.cax_check(interp.state, bw)
    if kin.tangential:
        tangential.programmed(interp.state, bw)
    if kin.pending_ori:
        orient_target(interp, end)
    if kin.angax:
        angax.suspended_target(interp, bw, end)


def orient_target(interp, end: dict) -> None:
    """#TOOL ORI pending: the move's end point gets the rotary positions (programmed coordinates)."""
    st = interp.state
    kin: KinState = st.kin
    angles = solution_angles(kin, st, 1)
    for a, v in angles.items():
        end[a] = v - st.chain(a)


# ---------------------------------------------------------------------- #CS / #ACS
def _coordinate_system(interp, kin: KinState, kind: str, tokens, col: int) -> None:
    """seed 002 L12640-L12700: DEF, ON, OFF, NEW (spec 05 §6.3)."""
    what = f"#{kind}"
    if not tokens or _name(tokens[0]) not in ("DEF", "ON", "OFF", "NEW"):
        raise InterpError("KIN005", f"{what} is followed by DEF, ON, OFF or NEW", col)
    verb = _name(tokens[0])
    rest = tokens[1:]
    keep = all_ = act = False
    while rest and _name(rest[0]) in ("KEEP", "ALL", "ACT"):
        w = _name(rest.pop(0))
        keep, all_, act = keep or w == "KEEP", all_ or w == "ALL", act or w == "ACT"
    if keep and verb not in ("OFF", "NEW"):
        raise InterpError("KIN010", f"KEEP is allowed only where {what} deactivates (OFF, NEW; L12631)", col)
    if (act and verb != "DEF") or (all_ and verb != "OFF"):
        raise InterpError("KIN005", f"{what} {verb}: {'ACT' if act else 'ALL'} does not go with {verb}", col)
    n = None
    if (rest and type(rest[0]) is not ItemList) or (rest and len(rest) >= 1 and _is_index(rest[0])):
        n = _id(interp, rest.pop(0), what, col)
    definition = rest.pop(0) if rest and type(rest[0]) is ItemList else None
    if rest:
        raise InterpError("KIN005", f"{what} {verb}: unexpected item after the definition", col)
    if verb == "OFF":
        if n is not None or definition is not None:
            raise InterpError("KIN005", f"write {what} OFF, {what} OFF KEEP or {what} OFF ALL", col)
        _deactivate(interp, kin, kind, all_, keep, col)
        return
    if verb == "DEF" and act:
        if n is None or definition is not None:
            raise InterpError("KIN005", f"write {what} DEF ACT [n]", col)
        r, v = kin.plane()
        kin.stored[kind][n] = frames.make(1, v, r)
        kin.last_stored[kind] = n
        return
    cs = _definition(interp, kin, definition, col) if definition is not None else None
    if verb == "DEF":
        if n is None or cs is None:
            raise InterpError("KIN005", f"write {what} DEF [n] [MODE m, ...]", col)
        kin.stored[kind][n] = cs
        kin.last_stored[kind] = n
        return
    if verb == "NEW":
        if cs is None:
            raise InterpError("KIN005", f"write {what} NEW <KEEP> <[n]> [MODE m, ...]", col)
        _deactivate(interp, kin, kind, True, keep, col, quiet=True)
    if cs is None:   # #CS ON [n] / #CS ON
        if n is None:
            n = kin.last_stored[kind]
            if n is None:
                raise InterpError("KIN008", f"{what} ON: no {kind} has been stored yet", col)
        if n not in kin.stored[kind]:
            raise InterpError("KIN008", f"{what} ON [{n}]: {kind} {n} is not defined ({what} DEF [{n}] ...)", col)
        cs = kin.stored[kind][n]
    elif n is not None:
        kin.stored[kind][n] = cs
        kin.last_stored[kind] = n
    elif any(k == kind and i is None for k, i, *_ in kin.active):
        raise InterpError("KIN009", f"{what} ON [MODE ...]: an unnamed {kind} is already active; switch it off "
                          "before defining another (L12658)", col)
    _activate(interp, kin, kind, n, cs, col)


def _is_index(t) -> bool:
    return type(t) is ItemList and len(t.items) == 1 and len(t.items[0]) == 1 and type(t.items[0][0]) is not Keyed


def _id(interp, t, what: str, col: int) -> int:
    if type(t) is ItemList:
        t = t.items[0][0]
    n = whole(_number(interp, t, col))
    if n is None or not 1 <= n <= 5:
        raise InterpError("KIN006", f"{what}: the system number is 1..5 (L12610)", col)
    return n


def _activate(interp, kin: KinState, kind: str, n, cs, col: int) -> None:
    st = interp.state
    if len(kin.active) >= MAX_ACTIVE:
        raise InterpError("KIN011", f"more than {MAX_ACTIVE} #ACS and #CS active at once (L13085)", col)
    if not kin.active:
        kin.zero = np.array([st.chain(a) for a in kin._linear(st)], dtype=float) if kin._linear(st) else None
    saved = (dict(st.abs_offset), dict(st.inc_offset), st.fixture, st.origin_source)
    kin.active.append((kind, n, cs, saved))
    kin.sol2 = cs.sol2
    kin.rebuild(st)
    if kin.current is not None and len(kin.current.joints) >= 2:   # (a three-rotary head: main, secondary)
        _toolori_values(kin, st)


def _toolori_values(kin: KinState, st) -> None:
    """V.G.TOOLORIF1/S1/F2/S2 worked out for the new plane (seed 002 L13389-L13413)."""
    k = kin.current
    r, _v = kin.plane()
    try:
        sols = orientations(k, r[:, 2], {a: st.machine_pos[a] for a in k.axes})
    except KinematicsError:
        kin.toolori = None
        return
    kin.toolori = (sols[0], sols[1] if len(sols) > 1 else sols[0])


def _deactivate(interp, kin: KinState, kind: str, everything: bool, keep: bool, col: int,
                quiet: bool = False) -> None:
    st = interp.state
    mine = [i for i, (k, *_r) in enumerate(kin.active) if k == kind]
    if not mine:
        if not quiet:
            # the manual does not say (spec 05 §6.3 chose an error): nothing changes, the user is told
            interp.message("KIN012", "warning", f"#{kind} OFF: no {kind} is active, nothing changes", col)
        return
    drop = mine if everything else mine[-1:]
    first_saved = kin.active[drop[0]][3]
    for i in reversed(drop):
        del kin.active[i]
    if not keep:   # the part zero in force before the activation comes back (L12586)
        abs_o, inc_o, fixture, source = first_saved
        st.abs_offset.update(abs_o)
        st.inc_offset.update(inc_o)
        st.fixture, st.origin_source = fixture, source
    kin.rebuild(st)
    kin.toolori = None if not kin.active else kin.toolori


def _definition(interp, kin: KinState, lst: ItemList, col: int):
    """``[MODE m, V1, V2, V3, a1, a2, a3 <,0/1>] <SOL2>`` -> a CoordinateSystem (spec 05 §6.4)."""
    items = [seq for seq in lst.items]
    if not items or len(items[0]) != 1 or type(items[0][0]) is not Keyed or items[0][0].name != "MODE":
        raise InterpError("KIN007", "the definition starts with MODE m: [MODE 1, V1, V2, V3, a1, a2, a3]", col)
    mode = whole(_number(interp, items[0][0].value, col))
    if mode not in frames.MODE_VALUES:
        raise InterpError("KIN007", f"MODE {mode}: the modes are 1..6 (L12612)", col)
    words = []
    values = []
    for seq in items[1:]:
        if len(seq) != 1:
            raise InterpError("KIN005", "one value between commas in the definition", col)
        t = seq[0]
        if type(t) is Name and t.name in ("FIRST", "SECOND", "SOL2"):
            words.append(t.name)
        else:
            if words:
                raise InterpError("KIN005", f"{words[-1]} goes at the end of the definition", col)
            values.append(_number(interp, t, col))
    need = frames.MODE_VALUES[mode]
    flag = 0
    if mode in (3, 4, 5) and len(values) == need + 1:
        flag = values.pop()
        if flag not in (0.0, 1.0):
            raise InterpError("KIN010", f"the alignment value of MODE {mode} is 0 or 1, not {flag:g}", col)
    if len(values) != need:
        raise InterpError("KIN007", f"MODE {mode} takes {need} values (origin and angles), got {len(values)}", col)
    if any(w in ("FIRST", "SECOND") for w in words) and mode != 6:
        raise InterpError("KIN010", "FIRST and SECOND are for MODE 6 only (L12636)", col)
    sol2 = "SOL2" in words
    origin = values[:3]
    try:
        if mode == 1:
            r = frames.mode_1(*values[3:6])
        elif mode == 2:
            r = frames.mode_2(*values[3:6])
        elif mode in (3, 4, 5):
            r = frames.mode_345(mode, values[3], values[4], values[5], int(flag))
        else:
            r = _mode_6(interp, kin, values[3], next((w for w in words if w != "SOL2"), None), col)
    except ValueError as exc:
        raise InterpError("KIN007", f"MODE {mode}: {exc}", col) from None
    return frames.make(mode, origin, r, tuple(values), sol2)


def _mode_6(interp, kin: KinState, psi: float, which: str | None, col: int) -> np.ndarray:
    """MODE 6: Z' along the tool now, seen in the present plane (seed 002 L12965)."""
    st = interp.state
    k = _needs_kinematics(kin, "MODE 6", col)
    angles = {a: (kin.frame.point(st.machine_pos) if kin.frame else st.machine_pos)[a] for a in k.axes}
    tool = tool_direction_part(k, angles)
    r, _v = kin.plane()
    return frames.mode_6(r.T @ tool, psi, which)
