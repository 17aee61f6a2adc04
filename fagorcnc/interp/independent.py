"""#MOVE: positioning of one axis by its independent interpolator (seed 002 ch. 21.1.19, L16615-L16747).

``#MOVE [X50, F500, PRESENT]`` (absolute, also ``#MOVE ABS``), ``#MOVE ADD [X10 ...]`` (incremental) and
``#MOVE INF [X+ ...]`` (endless, up to the travel limit) become one
:class:`~fagorcnc.interp.records.IndependentMove` each, at the positioning feed F, with the link that
says how it ends: PRESENT at its own feed, NEXT at the feed of the next #MOVE, NULL at rest,
WAITINPOS at rest and in position (L16722-L16740).  Without a link, ICORNER decides: G05 -> PRESENT,
G50 -> NULL, G07 -> WAITINPOS (L16741-L16747).  The planner runs them on the axis's own timeline,
alongside the general blocks after them (plan/independent.py; the links in plan/links.py).

Each axis's independent interpolator has its own position count (L16618-L16620) and the machine
adds both interpolators (L16622-L16623): the general interpolator does not count a #MOVE until
``#SYNC POS`` synchronises it with the real position (L16657-L16665, "only needed when instructions
of both interpolators are mixed").  A general block that programs an axis a #MOVE moved before
that synchronisation would run on a count that misses the positioning, to another place than the
one written: it is refused (INT232) before anything moves.  ``#SYNC POS`` after #MOVEs is an
:class:`~fagorcnc.interp.records.IndependentSync` in the record stream, where the general motion
waits for the independent axes to stop (plan/independent.py).
"""

from __future__ import annotations

from dataclasses import replace

from ..syntax.ast import Direction, ItemList, Keyed, Name, Param
from .expressions import InterpError
from .records import IndependentMove, IndependentSync, Source

LINKS = ("PRESENT", "NEXT", "NULL", "WAITINPOS")
#: The link a #MOVE takes without one, from ICORNER (0 = G50, 1 = G05, 2 = G07) (L16741-L16747).
ICORNER_LINK = {0: "NULL", 1: "PRESENT", 2: "WAITINPOS"}
#: Planning context of each link: the corner mode (G07: the in-position wait) and the feed adaptation
#: giving the speed at the end (G108: the next block starts at this one's feed; G109: this block
#: reaches the next one's feed at its end).
_LINK_DYNAMICS = {"PRESENT": ("G05", "G108"), "NEXT": ("G05", "G109"), "NULL": ("G50", None),
                  "WAITINPOS": ("G07", None)}


def _fail(message: str, col: int):
    return InterpError("INT227", message, col)


def move_statement(interp, node, sub, src: Source):
    """``#MOVE <ABS|ADD|INF> [axis target <, F feed> <, link>]`` -> one :class:`IndependentMove`."""
    st = interp.state
    kind = sub if sub in ("ABS", "ADD", "INF") else "ABS"
    arg = node.args[0] if len(node.args) == 1 else None
    value = arg.value if type(arg) is Keyed and sub in ("ABS", "ADD", "INF") else arg
    if type(value) is not ItemList:
        raise _fail("#MOVE takes the axis, the feed and the link in brackets: #MOVE [X50, F500, PRESENT] (L16692)",
                    node.col)
    items = [i for seq in value.items for i in seq]
    axis, target, feed, link = None, None, None, None
    for item in items:
        t = type(item)
        col = getattr(item, "col", node.col)
        if t is Name and item.name in LINKS:
            if link is not None:
                raise _fail("#MOVE: one link (PRESENT, NEXT, NULL or WAITINPOS)", col)
            link = item.name
        elif t is Keyed and item.name[0] == "F" and item.name[1:] in ("", "P"):
            expr = item.value if item.name == "F" else Param(int(interp.evaluator.value(item.value)), col)
            feed = interp.evaluator.value(expr)   # "FP100": the feed is P100 (example L16806)
        elif (t is Keyed and kind != "INF") or (t is Direction and kind == "INF"):
            if axis is not None:
                raise _fail("#MOVE moves one axis: one #MOVE per axis (L16692)", col)
            axis = st.channel.movable(item.name, col)   # the axis configuration, #PARK, #LINK (interp/axes.py)
            if axis is None:
                raise InterpError("INT229", f"#MOVE: {item.name} is not an axis of the channel (a spindle moves "
                                  "independently only in #CAX mode, L16649)", col)
            target = item.sign if t is Direction else interp.evaluator.value(item.value)
        else:
            form = "X+ or X-" if kind == "INF" else "X50"
            raise _fail(f"#MOVE {kind}: the items are the axis ({form}), F and the link (L16692)", col)
    if axis is None:
        raise _fail("#MOVE needs the axis and its position: #MOVE [X50] (L16692)", node.col)
    if feed is None:   # L16714-L16720: without F the axis moves at its POSFEED, a machine parameter
        given = interp.machine.machine_parameters
        feed = given.get(("POSFEED", (), axis), given.get(("POSFEED", (1,), axis)))
        if feed is None:
            raise InterpError("INT228", f"#MOVE without F: the positioning feed POSFEED of {axis} is a machine "
                              f"parameter the machine file does not give ([machine_parameters] "
                              f"\"MPA.POSFEED.{axis}\" = mm/min); program F (L16714-L16720)", node.col)
    if feed <= 0:
        raise _fail(f"#MOVE: the feed F{feed:g} must be positive", node.col)
    if link is None:
        link = ICORNER_LINK[interp.machine.default("ICORNER")]
    yield _record(interp, node, src, kind, axis, target, feed, link)


def _record(interp, node, src: Source, kind: str, axis: str, target, feed: float, link: str) -> IndependentMove:
    st = interp.state
    iso = interp.iso
    ax = interp.machine.axes[axis]
    start = dict(st.machine_pos)
    part = st.part_pos()
    if kind == "INF":
        if ax.rotary and ax.rotary_mode != "linearlike":
            raise InterpError("INT229", f"#MOVE INF on the rotary axis {axis}: it turns without end, the move "
                              "never finishes offline", node.col)
        end_machine = st.upper_limits[axis] if target == "+" else st.lower_limits[axis]
        interp.message("INT231", "warning", f"#MOVE INF [{axis}{target}]: offline nothing interrupts it; it runs "
                       f"to the travel limit {end_machine:g} (L16709)", node.col)
        end = dict(start)
        end[axis] = end_machine
    else:
        value = iso.length(target, axis)
        if kind == "ADD":
            if ax.rotary and ax.rotary_mode == "unidirectional" and value * ax.direction < 0:
                raise InterpError("INT026", f"{axis} only turns in one direction", node.col)
            goal = part[axis] + value
        elif ax.rotary and ax.rotary_mode != "linearlike":
            goal = _rotary_target(ax, part[axis], value)
        else:
            goal = value
        end = dict(start)
        end[axis] = st.to_machine({axis: goal})[axis]
    interp.check_limits(end, node.col, start)
    st.machine_pos = dict(end)
    corner, adaptation = _LINK_DYNAMICS[link]
    dyn = replace(st.dynamics(), corner=corner, adaptation=adaptation)
    speed = iso.length(feed, axis)   # inch/min under G70 (L16716)
    interp.curves.independent.setdefault(axis, src.line)   # not counted by the general interpolator
    return IndependentMove("linear", start, end, st.to_part(end), speed, "G94", src, dyn=dyn, link=link, axis=axis)


def _rotary_target(ax, here: float, value: float) -> float:
    """A rotary target: the shortest way (normal), or the preset direction (unidirectional) (L16698-L16701)."""
    m = ax.module
    d = (value % m - here % m) % m
    if ax.rotary_mode == "unidirectional":
        return here + (d if ax.direction > 0 else d - m if d else 0.0)
    return here + (d if d <= m / 2 else d - m)


def check_general(interp, axes, col: int) -> None:
    """Refuse a general block programming ``axes`` when one of them was moved by a #MOVE since the last
    ``#SYNC POS`` (INT232): the general interpolator's count misses that positioning (L16618-L16620), so the
    machine, adding both (L16623), would take the axis elsewhere than programmed."""
    moved = interp.curves.independent
    for axis in axes:
        line = moved.get(axis)
        if line is not None:
            raise InterpError("INT232", f"{axis} was positioned by #MOVE (line {line}): the general interpolator "
                              f"does not count that move until #SYNC POS, and the machine adds both "
                              f"interpolators (L16618-L16623, L16657-L16665), so {axis} would not go where this "
                              f"block says; program #SYNC POS before moving {axis} here", col)


def sync(interp, src: Source):
    """``#SYNC POS`` (L16657-L16665): the general interpolator takes the axes a #MOVE moved; in the record
    stream an :class:`IndependentSync`, where the general motion waits for the independent axes to stop."""
    moved = interp.curves.independent
    if moved:
        moved.clear()
        yield IndependentSync("dwell", 0.0, dict(interp.state.machine_pos), src)
