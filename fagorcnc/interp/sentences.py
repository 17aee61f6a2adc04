"""What each ``#`` sentence does offline (seed 002 ch. 21.1 and the chapters cited).

Three kinds:

* executed here: #DEF and #INIT MACROTAB (interp/macros.py), #ERROR, #WARNING, #WARNINGSTOP, #MSG, #TIME, #MCS ON/OFF,
  #PATH, #RET, #RETDSBLK, #MDOFF, #DELETE, #FLUSH;
* planning context (interp/dynamics.py): #HSC, #ROUNDPAR, #SLOPE, #TANGFEED;
* laser state (interp/laser.py): #SWTOUT, #PWMOUT and their V.G variables;
* recorded for the later stages: #ESBLK/#DSBLK ... kept in ``state.planner``;
* everything else cannot mean anything in an offline run of one channel
  (hardware, PLC, other channels) or is a transformation fagorcnc does not
  compute yet: each is reported with a warning naming it, never dropped
  silently.
"""

from __future__ import annotations

from ..syntax.ast import Direction, ItemList, Keyed, Name, Str, Var
from . import axes, curves, dynamics, independent, laser, macros, manual, spindle, spindle_config
from .expressions import InterpError
from .records import Dwell

#: Sentences kept as state for the planner / path stages.
RECORDED = frozenset({"ESBLK", "DSBLK", "ESTOP", "DSTOP", "EFHOLD", "DFHOLD"})
#: Geometric transformations the later stages will compute (issue: path / kinematics); also the
#: path treatments that change the path run, so that a user is told: #CD (loops removed, L15598).
NOT_YET = frozenset({"TOOL", "CD",
                     "VIRTAX", "FOLLOW", "TFOLLOW", "CAM", "TCAM", "RPT"})


def _text_of(args) -> str:
    """Message text of #MSG/#ERROR/#WARNING: the string and its data values."""
    parts = []
    for a in args:
        items = a.items if type(a) is ItemList else ((a,),)
        for seq in items:
            for item in seq:
                if type(item) is Str:
                    parts.append(item.text)
                elif type(item) is Name:
                    parts.append(item.name)
    return " ".join(parts)


def _values(interp, args) -> list[float]:
    out = []
    for a in args:
        items = a.items if type(a) is ItemList else ((a,),)
        for seq in items:
            for item in seq:
                if type(item) not in (Str, Name, Keyed):
                    out.append(interp.evaluator.value(item))
    return out


def _format(interp, args, col: int) -> str:
    """The text with %D/%d replaced by the data values and %% by % (seed 002 L14185-L14199)."""
    text = _text_of(args)
    values = _values(interp, args)
    out, i, k = [], 0, 0
    while i < len(text):
        ch = text[i]
        nxt = text[i + 1] if i + 1 < len(text) else ""
        if ch == "%" and nxt == "%":
            out.append("%")
            i += 2
        elif ch == "%" and nxt in "Dd" and nxt:
            if k >= len(values):
                raise InterpError("INT071", f"the text has more %D than data values ({len(values)})", col)
            out.append(f"{values[k]:g}")
            k += 1
            i += 2
        else:
            out.append(ch)
            i += 1
    if k != len(values) and _text_of(args):
        raise InterpError("INT071", f"{len(values)} data values for {k} %D in the text (L14389: as many "
                          "data as %D)", col)
    return "".join(out)


def _graphics_zone(interp, node) -> None:
    """``#DGWZ [Xmin, Xmax, Ymin, Ymax, Zmin, Zmax]`` (a lathe: ``[Zmin, Zmax, Xmin, Xmax]``), the
    graphics zone (seed 002 L14408-L14440): each lower limit below its upper one (L14424)."""
    arg = node.args[0] if len(node.args) == 1 else None
    seqs = arg.items if type(arg) is ItemList else ()
    if len(seqs) not in (4, 6) or any(len(seq) != 1 for seq in seqs):
        raise InterpError("INT071", "#DGWZ takes the limits in brackets: #DGWZ [Xmin, Xmax, Ymin, Ymax, Zmin, Zmax] "
                          "(a lathe: [Zmin, Zmax, Xmin, Xmax]) (L14419)", node.col)
    values = [interp.evaluator.value(seq[0]) for seq in seqs]
    for k in range(0, len(values), 2):
        if not values[k] < values[k + 1]:
            raise InterpError("INT071", f"#DGWZ: limit {k + 1} ({values[k]:g}) must be below limit {k + 2} "
                              f"({values[k + 1]:g}): lower limits are always below upper ones (L14424)", node.col)
    interp.state.planner["DGWZ"] = tuple(values)


def _without_sub(statement):
    return lambda interp, node, sub: statement(interp, node)


#: Sentences a module of their own executes: keyword -> handler(interp, node, first keyword).
_HANDLERS = {
    "DEF": _without_sub(macros.define_statement),          # macros (interp/macros.py)
    "INIT": _without_sub(macros.init_statement),
    "DGWZ": _without_sub(_graphics_zone),                  # the graphics zone (above)
    "SWTOUT": laser.swtout_statement,                      # laser (interp/laser.py)
    "PWMOUT": laser.pwmout_statement,
    "HSC": dynamics.hsc_statement,                         # planning context (interp/dynamics.py)
    "ROUNDPAR": _without_sub(dynamics.roundpar_statement),
    "SLOPE": _without_sub(dynamics.slope_statement),
    "TANGFEED": _without_sub(dynamics.tangfeed_statement),
    "MASTER": spindle.master_statement,                    # the master spindle (interp/spindle.py)
}

#: Curves and independent moves: keyword -> handler(interp, node, first keyword, source), records or None.
_CURVES = {
    "POLY": lambda interp, node, sub, src: curves.poly_statement(interp, node, src),
    "SPLINE": curves.spline_statement,
    "ASPLINE": lambda interp, node, sub, src: curves.aspline_statement(interp, node, sub),
    "MOVE": independent.move_statement,
}


def execute_sentence(interp, node, src):
    kw = node.keyword
    st = interp.state
    first = node.args[0] if node.args else None
    sub = first.name if type(first) in (Name, Keyed) else None
    curve = _CURVES.get(kw)
    if curve is not None:   # #POLY, #SPLINE, #ASPLINE (interp/curves.py), #MOVE (interp/independent.py)
        yield from curve(interp, node, sub, src) or ()
        return
    handler = _HANDLERS.get(kw)
    if handler is not None:
        handler(interp, node, sub)
        return
    if axes.handles(kw, sub):   # the axis configuration, #PARK, #LINK (interp/axes.py)
        axes.statement(interp, node)
        return
    if spindle_config.handles(kw, sub):   # the spindle configuration (interp/spindle_config.py)
        spindle_config.statement(interp, node)
        return
    if kw == "REPOS":
        # seed 002 L11114: "#REPOS is only allowed in interrupt subroutines", which the PLC starts
        raise InterpError("INT119", "#REPOS is allowed only in an interrupt subroutine, which the PLC starts "
                          "(L11114); a program or subroutine run here cannot use it", node.col)
    if kw in ("CONTJOG", "INCJOG", "MPG") or (kw == "SET" and sub == "OFFSET") or (kw == "SYNC" and sub == "POS"):
        manual.statement(interp, node)
        if kw == "SYNC":   # after #MOVEs: the general interpolator takes their axes (interp/independent.py)
            yield from independent.sync(interp, src)
        return
    if kw == "ERROR":
        # seed 002 L14139-L14212: stops the program with the error
        values = _values(interp, node.args)
        text = (_format(interp, node.args, node.col) if _text_of(node.args)
                else f"error {values[0]:g}" if values else "#ERROR")
        raise InterpError("INT070", f"#ERROR: {text}", node.col)
    if kw in ("WARNING", "WARNINGSTOP"):
        text = _format(interp, node.args, node.col)
        stop = " (the CNC stops here until cycle start)" if kw == "WARNINGSTOP" else ""
        interp.message("INT076", "warning", f"#{kw}: {text}{stop}", node.col)
        return
    if kw == "MSG":
        interp.message("INT077", "info", f"#MSG: {_format(interp, node.args, node.col)}", node.col)
        return
    if kw == "TIME":
        # seed 002 L9166-L9190: #TIME <seconds>
        if not node.args:
            raise InterpError("INT017", "#TIME needs the time in seconds", node.col)
        arg = node.args[0]
        t = interp.evaluator.value(arg)
        if t < 0:
            raise InterpError("INT017", f"dwell time {t:g} is negative", node.col)
        yield Dwell("dwell", t, dict(st.machine_pos), src)
        return
    if kw == "MCS":
        st.mcs_on = sub == "ON"
        return
    if kw == "PATH":
        texts = [i.text for a in node.args if type(a) is ItemList for seq in a.items for i in seq if type(i) is Str]
        if not texts:
            raise InterpError("INT071", '#PATH needs a directory in brackets and quotes: #PATH ["dir"]', node.col)
        st.path = texts[0]
        return
    if kw in ("RET", "RETDSBLK"):
        interp.return_from_subroutine(node.col)
        return
    if kw == "MDOFF":
        interp.modal_call = None
        return
    if kw == "DELETE":
        for a in node.args:
            if type(a) is not Var:
                raise InterpError("INT049", "#DELETE takes user variables: #DELETE V.S.name V.P.name", node.col)
            interp.variables.delete(a.name, tuple(interp.evaluator.value(i) for i in a.index), a.col)
        return
    if kw == "SCALE":
        # seed 002 L8981-L9035: #SCALE [factor]; the brackets are mandatory
        arg = node.args[0] if len(node.args) == 1 else None
        if arg is None or type(arg) is ItemList:
            raise InterpError("INT071", "#SCALE takes one factor in brackets: #SCALE [2]", node.col)
        if st.mcs_on:
            raise InterpError("INT013", "the scale cannot be changed while #MCS ON is active (L9030)", node.col)
        interp.iso.set_scale(interp.evaluator.value(arg), node.col)
        return
    if kw == "TOOL" and sub == "AX":
        # seed 002 L3126-L3166: #TOOL AX [Z+] selects the longitudinal axis and the tool orientation
        value = first.value if type(first) is Keyed else None
        items = value.items if type(value) is ItemList else ()
        item = items[0][0] if len(items) == 1 and len(items[0]) == 1 else None
        if type(item) is not Direction or item.name not in st.axes:
            raise InterpError("INT071", "#TOOL AX needs one axis and its direction: #TOOL AX [Z+]", node.col)
        st.tool_axis = (item.name, 1 if item.sign == "+" else -1)
        interp.iso.cycles.cancel_for_plane()   # a new tool axis cancels the canned cycle (spec 09 §1.1)
        return
    from ..kinematics import statements as kinematics  # on first use: a program without sentences never needs it
    if kinematics.handles(kw, sub):   # seed 002 ch. 14-17: #KIN ID, #CS, #ACS, #RTCP, #TLC, #TOOL ORI...
        yield from kinematics.execute(interp, node, src)
        return
    if kw == "FLUSH":
        st.sync = True   # seed 002 L17446: preparation waits for execution, the motion stops here
        return
    if kw in RECORDED:
        st.planner[kw if sub is None else f"{kw} {sub}"] = node.args
        return
    if kw in NOT_YET and sub == "OFF":
        st.planner[f"{kw} OFF"] = node.args   # cancelling what was never computed changes nothing
        return
    if kw in NOT_YET:
        interp.message("INT078", "warning", f"#{kw} is not computed by fagorcnc yet; the path ignores it",
                       node.col)
        return
    interp.message("INT079", "warning", f"#{kw} has no effect in an offline run (hardware, PLC or other "
                   "channels)", node.col)
    return
