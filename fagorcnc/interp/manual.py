"""Manual intervention (seed 002 ch. 8.9, L7691-L7988): G200, G201/G202 with ``#AXIS``, and the
settings ``#CONTJOG``, ``#INCJOG``, ``#MPG``, ``#SET OFFSET``, ``#SYNC POS``.

Offline there is no handwheel and no jog keyboard: no manual move ever happens, so the axes are
where the program puts them.  What is kept is what a program can get wrong: which axes have the
additive intervention (G201 needs ``#AXIS`` with at least one axis, a spindle may not be one,
L7736-L7746), the jog and handwheel settings with their units, and the additive offset limits
(lower <= 0 <= upper, defined after G201 for the axis, L7847, L7918-L7920).  G200 stops the program until
[CYCLE START] (L7789-L7794): the motion stops there, as at a synchronisation point, and a note
says that the machine waits for the operator.  The settings last until the end of the program or
a reset (L7841-L7843); the offset limits until the intervention is cancelled on the axis.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from ..syntax.ast import ItemList, Keyed, Name
from .expressions import InterpError
from .iso import INCH
from .records import Dwell


@dataclass
class ManualIntervention:
    """The channel's manual-intervention state; lengths in mm, feeds in mm/min."""

    additive: set[str] = field(default_factory=set)                       # G201 axes
    contjog: dict[str, float] = field(default_factory=dict)               # #CONTJOG feed
    incjog: dict[str, tuple] = field(default_factory=dict)                # #INCJOG ((step, feed), ...)
    mpg: dict[str, tuple] = field(default_factory=dict)                   # #MPG distance per pulse
    offset_limits: dict[str, tuple[float, float]] = field(default_factory=dict)   # #SET OFFSET

    @staticmethod
    def variables() -> dict:
        """``V.A.MANOF.xn`` and ``V.A.ADDMANOF.xn`` (spec 08 B.15.8, L41015-L41043): the distance
        moved by hand, 0 offline; execution values, so reading them stops preparation."""

        def none_moved(st, index, axis):
            st.sync = True
            return 0.0

        return {"V.A.MANOF": (none_moved, None), "V.A.ADDMANOF": (none_moved, None)}

    def g_functions(self, interp, gs: dict, src):
        """G200, G201, G202 of a block, with the block's ``#AXIS`` (``interp.axis_sentence``)."""
        state = self
        node = interp.axis_sentence
        used = [n for n in (200, 201, 202) if n in gs]
        col = gs[used[0]][0]
        if len(used) > 1:   # L7726: G201, G202 and G200 are incompatible with one another
            raise InterpError("INT012", f"G{used[0]} and G{used[1]} are incompatible in one block (L7726)",
                              gs[used[1]][0])
        n = used[0]
        axes = axis_list(interp, node, f"G{n}") if node is not None else []
        if n == 201:
            if not axes:   # L7745: G201 always with #AXIS and at least one axis
                raise InterpError("INT171", "G201 needs the axes: G201 #AXIS [X, Z] (L7745)", col)
            state.additive.update(axes)
            return
        if n == 202:
            for axis in axes or list(state.additive):   # G202 alone: every axis (L7754)
                state.additive.discard(axis)
                state.offset_limits.pop(axis, None)
            return
        # G200: the program stops; the operator moves the axes (all without #AXIS, L7806) and presses
        # [CYCLE START] (L7793)
        shown = ", ".join(axes) if axes else "every axis"
        interp.message("INT170", "info", f"G200: the program stops for manual intervention on {shown} until [CYCLE "
                       "START]; offline the axes stay where the program left them", col)
        yield Dwell("dwell", 0.0, dict(interp.state.machine_pos), src)

    def reset(self) -> None:
        """M02, M30, reset: G202 (L7728-L7729) and the settings gone (L7841-L7843)."""
        self.additive.clear()
        self.contjog.clear()
        self.incjog.clear()
        self.mpg.clear()
        self.offset_limits.clear()


def _unit(interp) -> float:
    return INCH if interp.state.modes["units"] == 70 else 1.0


def _axis(interp, name: str, col: int, what: str) -> str:
    st = interp.state
    if name in interp.machine.spindles or name in st.speeds:
        raise InterpError("INT171", f"{what}: {name} is a spindle; manual intervention is for axes only, even a "
                          "spindle in positioning mode (L7736)", col)
    if name not in st.axes:
        raise InterpError("INT024", f"{what}: axis {name} does not exist in this channel", col)
    return name


def axis_list(interp, node, what: str) -> list[str]:
    """The axes of ``#AXIS [X, Z]`` (L7743)."""
    arg = node.args[0] if len(node.args) == 1 else None
    seqs = arg.items if type(arg) is ItemList else ((arg,),) if type(arg) is Name else ()
    names = []
    for seq in seqs:
        if len(seq) != 1 or type(seq[0]) is not Name:
            raise InterpError("INT171", f"{what}: #AXIS lists axis names in brackets, e.g. #AXIS [X, Z] (L7743)",
                              node.col)
        names.append(_axis(interp, seq[0].name, seq[0].col, what))
    return names


def _values(interp, arg) -> list:
    """The values of ``[a, b, c]`` (or of a single ``[a]``)."""
    if type(arg) is ItemList:
        return [seq[0] if len(seq) == 1 else None for seq in arg.items]
    return [arg]


def _setting(interp, node, what: str, form: str):
    """(values, axis) of ``#WHAT [values] axis``."""
    if len(node.args) != 2 or type(node.args[1]) is not Name:
        raise InterpError("INT171", f"#{what} is written {form}", node.col)
    axis = _axis(interp, node.args[1].name, node.args[1].col, f"#{what}")
    return node.args[0], axis


def _positive(interp, item, what: str, col: int) -> float:
    if item is None or type(item) in (ItemList, Name, Keyed):
        raise InterpError("INT171", f"{what} must be a number", col)
    value = interp.evaluator.value(item)
    if not value > 0:
        raise InterpError("INT171", f"{what} {value:g} must be positive", col)
    return value


def statement(interp, node) -> None:
    """``#CONTJOG``, ``#INCJOG``, ``#MPG``, ``#SET OFFSET``, ``#SYNC POS`` (L7839-L7988)."""
    kw, state, unit = node.keyword, interp.manual, _unit(interp)
    if kw == "SYNC":   # L7971: preparation takes the execution position (and the additive offset)
        if len(node.args) != 1 or type(node.args[0]) is not Name or node.args[0].name != "POS":
            raise InterpError("INT171", "#SYNC POS takes nothing more", node.col)
        interp.state.sync = True
        return
    if kw == "CONTJOG":   # #CONTJOG [F] X (L7857)
        arg, axis = _setting(interp, node, "CONTJOG", "#CONTJOG [feed] axis, e.g. #CONTJOG [400] X (L7857)")
        values = _values(interp, arg)
        if len(values) != 1:
            raise InterpError("INT171", "#CONTJOG takes one feed: #CONTJOG [400] X (L7857)", node.col)
        state.contjog[axis] = _positive(interp, values[0], "#CONTJOG feed", node.col) * unit
        return
    if kw == "INCJOG":   # #INCJOG [[inc1,F1]...[inc10000,F10000]] X (L7870)
        arg, axis = _setting(interp, node, "INCJOG", "#INCJOG [[step, feed][step, feed]...] axis (L7870)")
        pairs = [x for seq in arg.items for x in seq] if type(arg) is ItemList else []
        if not 1 <= len(pairs) <= 5 or any(type(p) is not ItemList or len(p.items) != 2 for p in pairs):
            raise InterpError("INT171", "#INCJOG takes up to 5 [step, feed] pairs, one per position of the "
                              "incremental jog switch (1, 10, 100, 1000, 10000): #INCJOG [[0.1,100][0.5,200]] X "
                              "(L7870)", node.col)
        state.incjog[axis] = tuple(
            (_positive(interp, p.items[0][0], "#INCJOG step", p.col) * unit,
             _positive(interp, p.items[1][0], "#INCJOG feed", p.col) * unit) for p in pairs)
        return
    if kw == "MPG":   # #MPG [pos1, pos2, pos3] X (L7906)
        arg, axis = _setting(interp, node, "MPG", "#MPG [distance, distance, distance] axis (L7906)")
        values = _values(interp, arg)
        if not 1 <= len(values) <= 3:
            raise InterpError("INT171", "#MPG takes up to 3 distances per pulse, one per handwheel switch "
                              "position: #MPG [0.1, 1, 10] X (L7906)", node.col)
        state.mpg[axis] = tuple(_positive(interp, v, "#MPG distance", node.col) * unit for v in values)
        return
    # #SET OFFSET [lower, upper] axis (L7916-L7920)
    first = node.args[0]
    if len(node.args) != 2 or type(first) is not Keyed or type(node.args[1]) is not Name:
        raise InterpError("INT171", "#SET OFFSET is written #SET OFFSET [lower, upper] axis (L7916)", node.col)
    axis = _axis(interp, node.args[1].name, node.args[1].col, "#SET OFFSET")
    values = _values(interp, first.value)
    if len(values) != 2 or any(v is None for v in values):
        raise InterpError("INT171", "#SET OFFSET takes two limits: #SET OFFSET [-20, 35] Y (L7916)", node.col)
    lower, upper = (interp.evaluator.value(v) for v in values)
    if not lower <= 0.0 <= upper:   # L7918-L7920
        raise InterpError("INT171", f"#SET OFFSET [{lower:g}, {upper:g}]: the lower limit must be 0 or less and the "
                          "upper one 0 or more (L7918)", node.col)
    if axis not in state.additive:   # L7847: defined after the intervention is activated
        raise InterpError("INT171", f"#SET OFFSET on {axis}: activate the additive intervention on {axis} first "
                          f"(G201 #AXIS [{axis}], L7847)", node.col)
    state.offset_limits[axis] = (lower * unit, upper * unit)
