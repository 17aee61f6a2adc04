"""What the planner needs to know about each motion block: corner mode, HSC,
rounding type, acceleration and jerk percentages, feed adaptation.

The interpreter keeps this state (it is modal, reset by M02/M30) and hands the
planner one immutable :class:`Dynamics` per motion record.  Consecutive
records share the same object until something changes, so it costs nothing
per block.

Seed references (002): corner modes ch. 9 (L7989-L8112), #ROUNDPAR
L8113-L8392, #HSC ch. 18 (L13433-L13669), G130-G133 L4376-L4512, G108/G109/G193
L4193-L4270, G266 L4366, #SLOPE L15871-L16112.
"""

from __future__ import annotations

from dataclasses import dataclass

from ..syntax.ast import ItemList, Keyed, Name
from .expressions import InterpError, whole

CORNER_NAMES = {5: "G05", 7: "G07", 50: "G50"}
HSC_MODES = ("SURFACE", "CONTERROR", "FAST")   # HSCDEFAULTMODE 0, 1, 2 (L19804)


@dataclass(frozen=True, slots=True)
class Hsc:
    """An active ``#HSC ON`` (seed 002 ch. 18)."""

    mode: str            # "SURFACE" | "CONTERROR" | "FAST"
    tolerance: float     # mm: chordal error (SURFACE/FAST) or contour error (CONTERROR)
    corner: float        # degrees: included angles below it are machined sharp (L13537)
    fast: float = 100.0  # % of the reachable speed aimed for in FAST (L13605)


@dataclass(frozen=True, slots=True)
class Dynamics:
    """Planning context of one motion block.

    ``corner`` is the corner mode at the *end* of the block: ``"G05"``,
    ``"G07"``, ``"G50"`` or ``"HSC"`` (one-shot G60/G61 already resolved).
    ``roundpar`` is the #ROUNDPAR type and its parameters (used by G05/G61).
    ``acceleration``/``jerk`` are ``(axis, percent)`` pairs for axes not at 100 %.
    ``adaptation`` is G108, G109, G193 or None (default behaviour, L4260).
    """

    corner: str = "G50"
    roundpar: tuple = (1, 0.01)
    hsc: Hsc | None = None
    acceleration: tuple = ()
    jerk: tuple = ()
    adaptation: str | None = None
    override_locked: bool = False   # G266: feed override forced to 100 % (L4366)
    slope: tuple = (1, 0, 0, 0)     # #SLOPE [type, jerk, accel, move]
    contact_feed: float | None = None   # G196: F is at the tool's contact point on arcs of radius above
    # this (#TANGFEED RMIN, 0 = all; seed 002 L4298-L4325); None: G197, F at the tool centre
    plc_marks: tuple = ()   # PLC marks the channel holds on during the move: "TAPPING" (a tapping canned
    # cycle, seed 002 L29849), "RIGID" (rigid tapping, L29856); see interp.cycles.drilling.plc_marks
    path_limits: tuple | None = None   # V.G.MAXACCEL/MAXJERK of the program (mm/s², mm/s³; 0 = none), L36469
    links: tuple = ()   # the #LINK couplings (interp.axes.Link) the slaves follow in this block (L14515)
    param_sets: tuple = ()   # G112: (axis, set) of the axes not at parameter set 1 (seed 002 L9307)
    dynamic_override: float = 100.0   # V.G.DYNOVR: % of every axis's feed, acceleration and jerk (L36672)

    def param_set(self, axis: str) -> int:
        """The parameter set (1-4) whose dynamics ``axis`` moves with (G112)."""
        for a, n in self.param_sets:
            if a == axis:
                return n
        return 1

    def acceleration_factor(self, axis: str, rapid: bool = False) -> float:
        if rapid and self.slope[3] == 1:
            return 1.0          # #SLOPE [..,..,..,1]: percentages do not affect G00 (L16069)
        return dict(self.acceleration).get(axis, 100.0) / 100.0

    def jerk_factor(self, axis: str, rapid: bool = False) -> float:
        if rapid and self.slope[3] == 1:
            return 1.0
        return dict(self.jerk).get(axis, 100.0) / 100.0


def default_roundpar(machine) -> tuple:
    """ROUNDTYPE 0: chordal error MAXROUND (type 1); 1: feed percentage ROUNDFEED (type 2) (L20276)."""
    p = machine.planner
    return (2, p.round_feed) if p.round_type == 1 else (1, p.max_round)


def _items(node) -> list:
    """The bracket list of a sentence as a flat list of items."""
    out = []
    for a in node.args:
        if type(a) is ItemList:
            out.extend(seq[0] if len(seq) == 1 else seq for seq in a.items)
        else:
            out.append(a)
    return out


def hsc_statement(interp, node, sub: str | None) -> None:
    """``#HSC ON [...]`` / ``#HSC OFF`` (seed 002 L13469-L13669)."""
    st, p = interp.state, interp.machine.planner
    if sub == "OFF":
        st.hsc = None
        st.dynamics_changed()
        return
    if sub != "ON":
        raise InterpError("INT110", "#HSC is written #HSC ON [...] or #HSC OFF", node.col)
    if st.hsc is not None:
        # L13660: a second HSC mode does not cancel the first; cancel it first
        raise InterpError("INT110", "HSC is already active: program #HSC OFF (or G05/G07/G50) before another "
                          "#HSC ON (L13660)", node.col)
    first = node.args[0] if node.args else None
    entries = []
    if type(first) is Keyed and first.value is not None:
        value = first.value
        seqs = value.items if type(value) is ItemList else ((value,),)
        for seq in seqs:
            if len(seq) != 1:
                raise InterpError("INT110", "#HSC ON: separate the elements with commas: [CONTERROR 0.01, CORNER 150]",
                                  node.col)
            entries.append(seq[0])
    mode = None
    values: dict[str, float] = {}
    for item in entries:
        if type(item) is Name:
            name, val = item.name.upper(), None
        elif type(item) is Keyed:
            name, val = item.name.upper(), interp.evaluator.value(item.value) if item.value is not None else None
        else:
            raise InterpError("INT110", "#HSC ON takes SURFACE, CONTERROR, FAST, E and CORNER", getattr(item, "col",
                                                                                                     node.col))
        col = item.col
        if name in HSC_MODES:
            if mode is not None:
                raise InterpError("INT110", f"#HSC ON: two modes ({mode} and {name}) in one statement", col)
            mode = name
            if val is not None:
                values[name] = val
        elif name in ("E", "CORNER"):
            if val is None:
                raise InterpError("INT110", f"#HSC ON: {name} needs a value", col)
            if name in values:
                raise InterpError("INT110", f"#HSC ON: {name} is written twice", col)
            values[name] = val
        else:
            raise InterpError("INT110", f"#HSC ON: '{name}' is not SURFACE, CONTERROR, FAST, E or CORNER", col)
    if mode is None:   # the mode may be omitted when it is HSCDEFAULTMODE (L13471)
        mode = HSC_MODES[p.hsc_default_mode]
    default_tol = p.hsc_round or p.max_round   # spec 07: HSCROUND, then MAXROUND
    if mode == "SURFACE":
        if "CORNER" in values:
            raise InterpError("INT110", "#HSC ON [SURFACE]: CORNER belongs to CONTERROR and FAST (L13469)", node.col)
        if "SURFACE" in values:
            raise InterpError("INT110", "#HSC ON [SURFACE]: the tolerance is written E: [SURFACE, E0.01]", node.col)
        tol = values.get("E", default_tol)
    elif mode == "CONTERROR":
        if "E" in values:
            raise InterpError("INT110", "#HSC ON [CONTERROR]: the tolerance follows the keyword: [CONTERROR 0.01] "
                              "(L13501)", node.col)
        tol = values.get("CONTERROR", default_tol)
    else:
        tol = values.get("E", default_tol)
    corner = values.get("CORNER", p.corner)
    fast = values.get("FAST", p.fast_factor)
    if not tol > 0:
        raise InterpError("INT110", f"#HSC ON: the tolerance {tol:g} must be positive", node.col)
    if not 0 <= corner <= 180:
        raise InterpError("INT110", f"#HSC ON: CORNER {corner:g} must be between 0 and 180 degrees (L13537)",
                          node.col)
    if not 0.01 <= fast <= 100:
        raise InterpError("INT110", f"#HSC ON: FAST {fast:g} must be between 0.01 and 100 % (L13605)", node.col)
    st.hsc = Hsc(mode, tol, corner, fast)
    st.dynamics_changed()


def roundpar_statement(interp, node) -> None:
    """``#ROUNDPAR [type, p1, ...]`` (seed 002 L8113-L8392)."""
    st = interp.state
    items = _items(node)
    values = []
    for item in items:
        if type(item) is tuple:
            raise InterpError("INT111", "#ROUNDPAR takes numbers separated by commas: #ROUNDPAR [1, 0.05]", node.col)
        values.append(interp.evaluator.value(item))
    if not values or whole(values[0]) not in (1, 2, 3, 4, 5):
        raise InterpError("INT111", "#ROUNDPAR needs the rounding type 1 to 5 first: #ROUNDPAR [1, 0.05]", node.col)
    kind = int(values[0])
    needed = {1: 1, 2: 1, 3: 2, 4: 1, 5: 5}[kind]
    if len(values) - 1 < needed:
        raise InterpError("INT111", f"#ROUNDPAR type {kind} needs {needed} value(s) after the type", node.col)
    params = values[1:1 + needed]
    if kind in (1, 4) and not params[0] > 0:
        raise InterpError("INT111", f"#ROUNDPAR [{kind}, e]: the deviation e must be positive", node.col)
    if kind == 2 and not 0 < params[0] <= 100:
        raise InterpError("INT111", "#ROUNDPAR [2, f]: the feed percentage must be in (0, 100]", node.col)
    if kind == 3 and not (params[0] > 0 and params[1] > 0):
        raise InterpError("INT111", "#ROUNDPAR [3, a, b]: the distances must be positive", node.col)
    if kind == 5:
        interp.message("INT115", "warning", "#ROUNDPAR type 5 (laser loop around the corner) is not modelled: "
                       "corners under G05/G61 are machined sharp with a stop (same corner, longer time)", node.col)
    st.roundpar = (kind, *params)
    st.dynamics_changed()


def slope_statement(interp, node) -> None:
    """``#SLOPE [type, jerk, accel, move]``; empty fields are 0 (seed 002 L16045-L16082)."""
    st = interp.state
    out = [0, 0, 0, 0]
    first = node.args[0] if node.args else None
    fields = first.items if type(first) is ItemList else ((first,),) if first is not None else ()
    for i, a in enumerate(fields):
        if i >= 4:
            raise InterpError("INT111", "#SLOPE takes at most four values: [type, jerk, accel, move]", node.col)
        if not a:
            continue
        v = whole(interp.evaluator.value(a[0]))
        if v is None or not 0 <= v <= (1 if i == 3 else 2):
            raise InterpError("INT111", f"#SLOPE: value {i + 1} must be {'0 or 1' if i == 3 else '0, 1 or 2'}",
                              node.col)
        out[i] = int(v)
    st.slope = tuple(out)
    st.dynamics_changed()


def percentages(interp, gs: dict, axes: dict, bare) -> None:
    """G130-G135: acceleration, jerk, feed-forward and AC-forward percentages (L4376-L4623)."""
    st = interp.state
    names = list(st.axes) + list(st.speeds)
    for n, key in ((130, "acceleration"), (132, "jerk"), (131, "acceleration"), (133, "jerk")):
        if n not in gs:
            continue
        col = gs[n][0]
        if n in (130, 132):
            if not axes:
                raise InterpError("INT112", f"G{n} needs axes with their percentage: G{n} X50 Y80", col)
            pairs = {a: v for a, (v, _c) in axes.items()}
        else:
            if bare is None:
                raise InterpError("INT112", f"G{n} needs the percentage: G{n} 50", col)
            pairs = dict.fromkeys(names, bare[0])
        for v in set(pairs.values()):
            if whole(v) is None:   # L4396: whole percentages only
                raise InterpError("INT112", f"G{n}: the percentage {v:g} must be a whole number (L4396)", col)
            if not 1 <= v <= 100:
                raise InterpError("INT112", f"G{n}: the percentage {v:g} must be between 1 and 100", col)
        current = dict(getattr(st, key))
        current.update(pairs)
        setattr(st, key, {a: v for a, v in current.items() if v != 100})
        st.dynamics_changed()
    for n, limit in ((134, 2), (135, 1)):
        if n in gs:
            for a, (v, c) in axes.items():
                if not 0 <= v <= 120 or abs(round(v, limit) - v) > 1e-9:
                    raise InterpError("INT112", f"G{n} {a}{v:g}: at most 120 % with {limit} decimal(s) (L4513)", c)
            # absolute per axis, the others keep theirs (L4526-L4546)
            st.planner[f"G{n}"] = {**st.planner.get(f"G{n}", {}), **{a: v for a, (v, _c) in axes.items()}}


def build(state, block_modes: dict) -> Dynamics:
    """The :class:`Dynamics` of a motion block from the channel state."""
    corner = "HSC" if state.hsc is not None else CORNER_NAMES.get(state.modes.get("corner"), "G50")
    if "G60" in block_modes:
        corner = "G07"          # L8018: square corner for this block only
    elif "G61" in block_modes:
        corner = "G05"          # L8107: controlled rounding for this block only
    adaptation = next((g for g in ("G108", "G109", "G193") if g in block_modes), None)
    return Dynamics(corner, state.roundpar, state.hsc if corner == "HSC" else None,
                    tuple(sorted(state.acceleration.items())), tuple(sorted(state.jerk.items())),
                    adaptation, "G266" in block_modes, state.slope,
                    state.tangfeed_rmin if state.modes.get("feed_point") == 196 else None,
                    path_limits=state.path_limits, links=state.channel.links,
                    param_sets=tuple(sorted((a, n) for a, n in state.param_sets.items() if a in state.machine.axes)),
                    dynamic_override=state.dynamic_override)


def tangfeed_statement(interp, node) -> None:
    """``#TANGFEED RMIN [radius]``: G196 keeps F at the contact point only on arcs of a larger
    radius; 0 or none: on every arc; kept after G197 (seed 002 L4305-L4312)."""
    first = node.args[0] if len(node.args) == 1 else None
    if type(first) is not Keyed or first.name != "RMIN":
        raise InterpError("INT071", "#TANGFEED takes the minimum radius: #TANGFEED RMIN [5]", node.col)
    value = interp.evaluator.value(first.value) if first.value is not None else 0.0
    if value < 0:
        raise InterpError("INT071", f"#TANGFEED RMIN {value:g} is negative", node.col)
    st = interp.state
    st.tangfeed_rmin = interp.iso.length(value)
    st.dynamics_changed()


def parameter_sets(interp, col: int, bw) -> None:
    """``G112 X2 Y3`` / ``G112 S2`` (seed 002 L9307-L9360): the axes (and spindles) named move with that
    parameter set of the machine file from now on (modal, L9341); no physical change on the machine.
    The words are set numbers, not targets: the caller clears them."""
    st = interp.state
    if not bw.axes and not bw.speeds:
        raise InterpError("INT214", "G112 names the axes and their parameter set: G112 X2 Y3 (L9324)", col)
    for name, (v, c) in {**bw.axes, **bw.speeds}.items():
        n = int(v) if float(v).is_integer() else 0
        if not 1 <= n <= 4:
            raise InterpError("INT214", f"G112 {name}{v:g}: a parameter set is 1 to 4 (L9309)", c)
        ax = st.machine.axes.get(name)
        if ax is not None and n > ax.nsets:
            raise InterpError("INT214", f"G112 {name}{n}: the machine file gives axis {name} {ax.nsets} parameter "
                              f"set(s) (axes.{name}.sets = [...] adds sets 2-4)", c)
        if ax is None and n > 1:
            # a spindle's set changes its positioning dynamics (M19, L9329), which fagorcnc does not time
            interp.message("INT215", "warning", f"G112 {name}{n}: parameter set {n} of spindle {name} is kept "
                           "(V.A.ACTIVSET); fagorcnc does not time spindle positioning, so it changes nothing here",
                           c)
        if n == 1:
            st.param_sets.pop(name, None)
        else:
            st.param_sets[name] = n
    st.dynamics_changed()
