"""The channel's axis configuration and coupled axes (seed 002 ch. 21.1.6-21.1.8, L14515-L15048; generic
axes ``?n`` L1206-L1241).

The configuration is a list of *slots*: slot 1 is the abscissa with G17, slot 2 the ordinate, slot 3 the
axis perpendicular to the plane, slot 4 the first auxiliary axis (L14730-L14732); a slot may be a *hole*
(``#SET AX [Y, 0, 0, Z]``).  Every slot holds a machine axis by its machine-file name; ``#RENAME AX`` gives
it another name in the program (L14943).  Positions stay keyed by machine names throughout fagorcnc: an
axis that leaves the channel stays where it is (it is still in every record, it just cannot be
programmed).  ``#PARK`` takes an axis or spindle out of the machine (L14587): it may not be referenced.

``#LINK [master, slave]`` couples a slave to its master: slave = slave at coupling + (master - master at
coupling) (1:1, the manual gives no ratio).  The interpreter does not move the slave itself: the stage
:func:`follow_links`, after the joint-space stage, writes each slave's position into every record made
under the coupling (the records carry it in their planning context, ``Dynamics.links``), so the slave
follows the master's real path (radius compensation, corner aids and transformations included); the
planner then sees the slave with its own velocity, acceleration and jerk limits, and its soft limits are
checked there.
"""

from __future__ import annotations

import dataclasses
import math
import re
from collections.abc import Iterator
from dataclasses import dataclass

from ..syntax.ast import ItemList, Keyed, Name, Num
from .expressions import InterpError, whole
from .mpvars import name_code
from .renaming import Renaming, item_name, rename
from .spindle import targets
from .spindle_config import cancel_renames, rename_cancel, spindle_busy

#: The offsets #SET AX / #CALL AX may apply to the axes they add (L14806-L14815).
OFFSET_KEYWORDS = frozenset({"ALL", "LOCOF", "FIXOF", "ORGOF", "MEASOF", "MANOF"})
#: [CONSTRUCTION] the most slots a configuration may have: one bit per axis of V.G.AXISCH (32 bits, L32941).
MAX_SLOTS = 32
_AXIS_NAME = re.compile(r"[XYZUVWABC][1-9]?")
_SPINDLE_NAME = re.compile(r"S[1-9]?")


@dataclass(frozen=True, slots=True)
class Link:
    """One coupling of ``#LINK``: ``slave = master + offset`` in machine coordinates (offset = slave minus
    master when the coupling was made); ``maxdiff`` the following-error difference allowed (None: no check,
    a hardware check offline, L14560)."""

    master: str
    slave: str
    offset: float
    maxdiff: float | None = None


class ChannelAxes:
    """Which machine axes are in the channel, in which slot and under which name; parked axes and
    spindles; the active couplings."""

    def __init__(self, machine) -> None:
        self.machine = machine
        self.original: list[str] = list(getattr(machine, "channel_axes", None) or machine.axis_names)
        self.slots: list[str | None] = list(self.original)
        self.names: dict[str, str] = {}      # machine axis -> its name after #RENAME AX (renamed ones only)
        self.parked: set[str] = set()        # parked axes and spindles (machine names)
        self.links: tuple[Link, ...] = ()
        self.by_name: dict[str, str] = {}    # program name -> machine axis, for the axes of the channel
        self._index()

    # ------------------------------------------------------------ queries
    def _index(self) -> None:
        self.by_name = {self.name_of(a): a for a in self.slots if a is not None}

    @property
    def busy(self) -> bool:
        """Something a block's words must be checked against (a coupling or a parked element)."""
        return bool(self.links or self.parked)

    def name_of(self, axis: str) -> str:
        """The program's name of machine axis ``axis``."""
        return self.names.get(axis, axis)

    def in_channel(self, axis: str) -> bool:
        return axis in self.by_name.values()

    def main_axes(self) -> list[str | None]:
        """The first three slots (None: a hole, or a channel of fewer axes)."""
        return [*self.slots, None, None, None][:3]

    def slaves(self) -> dict[str, Link]:
        return {k.slave: k for k in self.links}

    def word_axis(self, name: str, col: int) -> str | None:
        """The machine axis an axis word ``name`` programs; None when ``name`` is no axis name at all
        (a parameter letter...).  INT200 for an axis of the machine that is not in the channel under that
        name, INT203 for a parked one."""
        axis = self.by_name.get(name)
        if axis is None:
            if name in self.machine.axes:
                renamed = self.names.get(name)
                why = (f"it is called {renamed} since #RENAME AX" if renamed and self.in_channel(name)
                       else "#FREE AX, #SET AX or the machine's channel configuration left it out")
                raise InterpError("INT200", f"axis {name} is not in the channel's axis configuration ({why}; "
                                  "L14744)", col)
            return None
        if axis in self.parked:
            raise InterpError("INT203", f"axis {name} is parked (#PARK): it cannot be programmed (L14641)", col)
        return axis

    def movable(self, name: str, col: int) -> str | None:
        """The machine axis a statement that moves axis ``name`` moves (#MOVE): :meth:`word_axis`, and not a
        coupled slave (INT210, L14549)."""
        axis = self.word_axis(name, col)
        link = next((k for k in self.links if k.slave == axis), None) if axis is not None else None
        if link is not None:
            raise InterpError("INT210", f"axis {name} is coupled to {self.name_of(link.master)} (#LINK): it cannot "
                              "be programmed until #UNLINK (L14549)", col)
        return axis

    def generic(self, k: int, col: int, parked_ok: bool = False) -> str:
        """The axis of generic name ``?k``: slot k, holes counted (seed 002 L1207-L1211)."""
        slot = self.slots[k - 1] if 1 <= k <= len(self.slots) else None
        if slot is None:
            what = "a hole of the axis configuration" if 1 <= k <= len(self.slots) else "beyond the channel's axes"
            raise InterpError("INT022", f"generic axis ?{k} designates no axis: position {k} is {what} (L1211)",
                              col)
        if slot in self.parked and not parked_ok:
            raise InterpError("INT203", f"?{k} is axis {self.name_of(slot)}, which is parked (#PARK) (L14641)", col)
        return slot

    def check_block(self, bw, gs: frozenset, master: str | None) -> None:
        """The block's words against the couplings and the parked spindles (``master``: the master spindle,
        which an M3/M4/M5/M19 without a spindle suffix is for)."""
        if self.links and bw.axes and not gs & {130, 131, 132, 133, 134, 135}:
            slaves = self.slaves()
            for axis, (_v, col) in bw.axes.items():
                if axis in slaves:
                    raise InterpError("INT210", f"axis {self.name_of(axis)} is coupled to "
                                      f"{self.name_of(slaves[axis].master)} (#LINK): it cannot be programmed "
                                      "until #UNLINK (L14549)", col)
        if self.parked:
            used = [(s, c) for s, (_v, c) in bw.speeds.items()]
            used += [(sp, c) for i, (m, c) in enumerate(bw.m) if m in (3, 4, 5, 19) or i in bw.m_target
                     for sp in targets(bw, i, master)]
            for spindle, col in used:
                if spindle in self.parked:
                    raise InterpError("INT213", f"spindle {spindle} is parked (#PARK): it cannot be programmed "
                                      "(L14641)", col)

    # ------------------------------------------------------------ changes
    def _free_slot_after_last(self) -> int:
        """0-based slot of an axis called without a slot: after the last axis of the configuration
        ([CONSTRUCTION] "after the last existing axis", L14887: after the highest occupied slot)."""
        occupied = [i for i, a in enumerate(self.slots) if a is not None]
        return occupied[-1] + 1 if occupied else 0

    def _put(self, axis: str, slot: int, col: int) -> None:
        if slot >= MAX_SLOTS:
            raise InterpError("INT204", f"position {slot + 1} is beyond the {MAX_SLOTS} positions of a channel", col)
        while len(self.slots) <= slot:
            self.slots.append(None)
        self.slots[slot] = axis

    def _trim(self) -> None:
        while self.slots and self.slots[-1] is None:
            self.slots.pop()

    def _release(self, axis: str) -> None:
        self.slots[self.slots.index(axis)] = None
        self.names.pop(axis, None)   # a released axis gets its own name back (L15014)


def _exchange(machine, axis: str) -> int:
    return int(getattr(machine.axes[axis], "exchange", 1))


# ---------------------------------------------------------------------- statement helpers
def _entries(node, start: int, what: str) -> tuple[list, list[str]]:
    """The bracket list after the sentence's keywords and the blank-separated offset keywords after it."""
    args = list(node.args)
    items = None
    first = args[0] if args else None
    if start == 1 and type(first) is Keyed and type(first.value) is ItemList:   # "#SET AX [..]": AX [..]
        items, rest = first.value.items, args[1:]
    elif start == 0 and args and type(first) is ItemList:                      # "#CALL AX [..]"
        items, rest = first.items, args[1:]
    else:
        raise InterpError("INT204", f"{what} takes the axes in brackets: {what} [X, Y, Z]", node.col)
    keywords = []
    for a in rest:
        if type(a) is not Name or a.name not in OFFSET_KEYWORDS:
            raise InterpError("INT204", f"{what}: after the axes only the offsets ALL, LOCOF, FIXOF, ORGOF, MEASOF, "
                              "MANOF may follow, separated by blanks (L14806)", getattr(a, "col", node.col))
        keywords.append(a.name)
    return [seq for seq in items], keywords


def _channel_axis(ch: ChannelAxes, name: str, col: int, what: str) -> str:
    """The machine axis named ``name`` in the channel (its current name)."""
    axis = ch.by_name.get(name)
    if axis is None:
        raise InterpError("INT200", f"{what}: there is no axis {name} in the channel's configuration", col)
    return axis


def _any_axis(ch: ChannelAxes, name: str, col: int, what: str) -> str:
    """The machine axis ``name`` names: one of the channel by its current name, else one of the machine
    by its own name (an axis outside the channel has its own name, L15014)."""
    axis = ch.by_name.get(name)
    if axis is not None:
        return axis
    if name in ch.machine.axes and not ch.in_channel(name):
        return name
    if name in ch.machine.axes:
        raise InterpError("INT204", f"{what}: axis {name} is called {ch.name_of(name)} since #RENAME AX", col)
    if name and _AXIS_NAME.fullmatch(name):
        raise InterpError("INT204", f"{what}: the machine has no axis {name}", col)
    raise InterpError("INT204", f"{what}: {name or 'this'} is not an axis name (X, Y ... C, X1 ... C9)", col)


def _guard(interp, what: str, col: int) -> None:
    """[CONSTRUCTION] a configuration or a coupling does not change under radius compensation or a
    transformation: the manual does not say what they become, so fagorcnc refuses instead of guessing."""
    st = interp.state
    if st.modes.get("compensation") in (41, 42):
        raise InterpError("INT206", f"{what} with radius compensation G41/G42 active: cancel it first (G40); "
                          "fagorcnc does not compute the compensated path across a change of axes", col)
    if st.kin.frame is not None:
        raise InterpError("INT206", f"{what} with a transformation active ({st.kin.description() or '#CS/#RTCP'}): "
                          "cancel it first", col)


def _leaving(interp, axis: str, col: int, what: str) -> None:
    ch = interp.state.channel
    if _exchange(ch.machine, axis) == 0:
        raise InterpError("INT205", f"{what}: axis {ch.name_of(axis)} may not change channel (its AXISEXCH is 0, "
                          "L14694)", col)
    busy = _axis_busy(interp, axis)   # [CONSTRUCTION] what may not park may not leave either (L14603-L14613)
    if busy:
        raise InterpError("INT206", f"{what}: axis {ch.name_of(axis)} cannot leave the channel while {busy}", col)


def _changed(interp, before: list, added: list[str], keywords: list[str]) -> None:
    """After a change of the configuration: the polar origin, coordinate rotation, mirror image and scale
    factor are cancelled (L14727); a change of the plane's axes also does what a plane change does; the
    axes that came in take only the offsets named (L14806-L14815)."""
    st = interp.state
    ch = st.channel
    ch._trim()
    ch._index()
    if ch.slots == before:
        return   # "only an exchange of order ... the offsets are not taken into account" (L14774): nothing moved
    slaves = [k.slave for k in ch.links if k.slave in ch.main_axes()]
    if slaves:
        raise InterpError("INT209", f"axis {ch.name_of(slaves[0])} is a coupled slave (#LINK) and cannot be one of "
                          "the first three axes of the channel (L14530); #UNLINK first", 1)
    st.polar_origin = (0.0, 0.0)
    tr = st.transform
    tr.angle = 0.0
    tr.mirror = set()
    tr.scale = 1.0
    if (before + [None] * 3)[:3] != ch.main_axes():
        st.tool_axis = None
        interp.plane_changed()
        interp.iso.cycles.cancel_for_plane()
    every = "ALL" in keywords
    for axis in added:
        if not (every or "ORGOF" in keywords):   # the origin offsets (G54.., G92, G158) are not applied
            st.abs_offset[axis] = 0.0
            st.inc_offset[axis] = 0.0
        fixture = st.fixture_table.get(st.fixture, {}).get(axis, 0.0) if st.fixture else 0.0
        if fixture and not (every or "FIXOF" in keywords):
            # [CONSTRUCTION] the fixture offset is one per channel in fagorcnc: it cannot leave one axis out
            raise InterpError("INT206", f"axis {ch.name_of(axis)} joins without FIXOF while fixture {st.fixture} has "
                              f"an offset {fixture:g} for it: fagorcnc cannot leave it out; add FIXOF or select "
                              "another fixture", 1)


def set_ax(interp, node) -> None:
    """``#SET AX [X, Y, 0, Z] <offsets>``: the new configuration, 0 a hole (L14744-L14834)."""
    ch = interp.state.channel
    what = "#SET AX"
    entries, keywords = _entries(node, 1, what)
    _guard(interp, what, node.col)
    new: list[str | None] = []
    for seq in entries:
        item = seq[0] if len(seq) == 1 else None
        col = getattr(item, "col", node.col)
        if type(item) is Num and item.value == 0:
            new.append(None)
            continue
        name = item_name(item) if item is not None else None
        if name is None:
            raise InterpError("INT204", f"{what}: each position is an axis or 0 for a hole: #SET AX [X, Y, 0, Z]", col)
        axis = _any_axis(ch, name, col, what)
        if axis in new:
            raise InterpError("INT204", f"{what}: axis {name} is listed twice", col)
        if axis in ch.parked:
            raise InterpError("INT203", f"{what}: axis {name} is parked (#PARK) (L14641)", col)
        new.append(axis)
    if len(new) > MAX_SLOTS:
        raise InterpError("INT204", f"{what}: more than {MAX_SLOTS} positions", node.col)
    before = list(ch.slots)
    for axis in before:
        if axis is not None and axis not in new:
            _leaving(interp, axis, node.col, what)
    added = [a for a in new if a is not None and a not in before]
    for axis in added:
        if _exchange(ch.machine, axis) == 0 and axis not in ch.original:
            raise InterpError("INT205", f"{what}: axis {axis} may not change channel (its AXISEXCH is 0)", node.col)
    for axis in before:
        if axis is not None and axis not in new:
            ch.names.pop(axis, None)   # a released axis gets its own name back (L15014)
    ch.slots = new
    _changed(interp, before, added, keywords)


def call_ax(interp, node) -> None:
    """``#CALL AX [V, 4, C] <offsets>``: adds axes, each in the slot that follows it or after the last axis;
    an axis already in the channel moves to the slot given, or stays (L14783-L14916)."""
    ch = interp.state.channel
    what = "#CALL AX"
    entries, keywords = _entries(node, 0, what)
    _guard(interp, what, node.col)
    before = list(ch.slots)
    added: list[str] = []
    seqs = [seq[0] if len(seq) == 1 else None for seq in entries]
    i = 0
    while i < len(seqs):
        item = seqs[i]
        col = getattr(item, "col", node.col)
        name = item_name(item) if item is not None else None
        if name is None:
            raise InterpError("INT204", f"{what}: expected an axis, optionally followed by its position: "
                              "#CALL AX [V, 4, C]", col)
        axis = _any_axis(ch, name, col, what)
        if axis in ch.parked:
            raise InterpError("INT203", f"{what}: axis {name} is parked (#PARK) (L14641)", col)
        slot = None
        if i + 1 < len(seqs) and type(seqs[i + 1]) is Num:
            k = whole(seqs[i + 1].value)
            if k is None or k < 1:
                raise InterpError("INT204", f"{what}: the position of {name} must be a whole number from 1",
                                  seqs[i + 1].col)
            slot = k - 1
            i += 1
        i += 1
        present = axis in ch.slots
        if not present and _exchange(ch.machine, axis) == 0 and axis not in ch.original:
            raise InterpError("INT205", f"{what}: axis {axis} may not change channel (its AXISEXCH is 0)", col)
        if slot is None:
            if present:
                continue   # "if the axis exists and no position is programmed, it stays where it is" (L14790)
            slot = ch._free_slot_after_last()
        elif slot < len(ch.slots) and ch.slots[slot] is not None and ch.slots[slot] != axis:
            raise InterpError("INT202", f"{what}: position {slot + 1} is taken by axis "
                              f"{ch.name_of(ch.slots[slot])} (L14881)", col)
        if present:
            ch.slots[ch.slots.index(axis)] = None
        else:
            added.append(axis)
        ch._put(axis, slot, col)
        ch._index()
    _changed(interp, before, added, keywords)


def free_ax(interp, node) -> None:
    """``#FREE AX [X, A]`` / ``#FREE AX ALL``: the axes leave; their slots become holes (L14868-L14992)."""
    ch = interp.state.channel
    what = "#FREE AX"
    args = node.args
    if len(args) == 2 and type(args[1]) is Name and args[1].name == "ALL":
        axes = [(a, node.col) for a in ch.slots if a is not None]
    else:
        entries, keywords = _entries(node, 1, what)
        if keywords:
            raise InterpError("INT204", f"{what} takes no offsets", node.col)
        axes = []
        for seq in entries:
            item = seq[0] if len(seq) == 1 else None
            col = getattr(item, "col", node.col)
            name = item_name(item) if item is not None else None
            if name is None:
                raise InterpError("INT204", f"{what}: expected the axes: #FREE AX [X, A]", col)
            axes.append((_channel_axis(ch, name, col, what), col))
    _guard(interp, what, node.col)
    before = list(ch.slots)
    for axis, col in axes:
        _leaving(interp, axis, col, what)
    for axis, _col in axes:
        ch._release(axis)
    _changed(interp, before, [], [])


_RENAME_AX = Renaming("AX", "axis", "axes", "INT207", _AXIS_NAME,
                      "a new name is X, Y ... C, optionally followed by a digit 1-9 (L1196)", "[X, X1] [Z, V2]", "[X]")


def rename_ax(interp, node) -> None:
    """``#RENAME AX [X, X1][..]``: the first axis takes the second name; an axis of the channel with that
    name takes the first (L14943-L14966).  ``#RENAME AX OFF <[X, ..]>``: the own names back (L15030)."""
    rename(node, interp.state.channel, _RENAME_AX, _renamed)


def _renamed(ch: ChannelAxes, col: int) -> None:
    ch.names = {a: n for a, n in ch.names.items() if n != a}
    ch._index()
    if len(ch.by_name) != sum(a is not None for a in ch.slots):
        raise InterpError("INT207", "#RENAME AX: two axes of the channel would have the same name", col)


# ---------------------------------------------------------------------- #PARK / #UNPARK
def park(interp, node, unpark: bool) -> None:
    """``#PARK A`` / ``#UNPARK A``, one axis or spindle a statement (L14587-L14689)."""
    st = interp.state
    ch = st.channel
    what = "#UNPARK" if unpark else "#PARK"
    item = node.args[0] if len(node.args) == 1 else None
    name = item_name(item) if item is not None else None
    if name is None:
        raise InterpError("INT208", f"{what} takes one axis or spindle: {what} A, {what} S2 (L14649)", node.col)
    col = item.col
    if name[0] == "?":   # the generic names are allowed in #PARK and #UNPARK (L1243-L1279)
        element = ch.generic(int(name[1:]), col, parked_ok=True)
    elif _SPINDLE_NAME.fullmatch(name) and name not in ch.by_name:
        element = st.spindle_config.word(name, col)   # a spindle of the channel, by its name there (INT246)
    else:
        element = _any_axis(ch, name, col, what)
    if unpark or element in ch.parked:
        ch.parked.discard(element) if unpark else None   # parking a parked element is ignored (L14660, L14676)
        return
    why = spindle_busy(interp, element) if element in st.speeds else _axis_busy(interp, element)
    if why:
        raise InterpError("INT208", f"{what} {name}: not while {why} (L14603-L14625)", col)
    ch.parked.add(element)


def _axis_busy(interp, axis: str) -> str:
    st = interp.state
    kin = st.kin
    current = kin.current
    if kin.frame is not None and current is not None and axis in current.axes:
        return "it belongs to the active kinematics"
    linear = [a for a in st.axes if not st.machine.axes[a].rotary][:3]   # the axes #CS/#ACS transform
    if kin.active and (axis in linear or (current is not None and axis in current.axes)):
        return "it belongs to an active #CS/#ACS transformation"
    if any(t.number in kin.angax and axis in (t.angular, t.orthogonal) for t in kin.angular_axes):
        return "it belongs to an active angular transformation #ANGAX"
    if axis in kin.tangential:
        return "it is under tangential control #TANGCTRL"
    if any(axis in (k.master, k.slave) for k in st.channel.links):
        return "it is coupled (#LINK)"
    return ""


# ---------------------------------------------------------------------- #LINK / #UNLINK
def link(interp, node) -> None:
    """``#LINK [master, slave <, maxdiff>] [..]`` (L14515-L14562) and its restrictions (L14527-L14543)."""
    st = interp.state
    ch = st.channel
    if ch.links:
        raise InterpError("INT209", "#LINK while a coupling is active: #UNLINK first (L14542)", node.col)
    if not node.args:
        raise InterpError("INT209", "#LINK needs the pairs: #LINK [X, U] [Y, V, 0.5]", node.col)
    _guard(interp, "#LINK", node.col)
    main = {a for a in ch.main_axes() if a is not None}
    pairs: list[Link] = []
    for arg in node.args:
        if type(arg) is not ItemList or len(arg.items) not in (2, 3) or any(len(s) != 1 for s in arg.items):
            raise InterpError("INT209", "#LINK: each pair is [master, slave] or [master, slave, maximum difference]",
                              getattr(arg, "col", node.col))
        (m,), (s,), *rest = arg.items
        master = _link_axis(interp, m, "master")
        slave = _link_axis(interp, s, "slave")
        maxdiff = None
        if rest:
            maxdiff = interp.evaluator.value(rest[0][0])
            if maxdiff < 0:
                raise InterpError("INT209", f"#LINK: the maximum difference {maxdiff:g} is negative", rest[0][0].col)
        named = f"#LINK [{ch.name_of(master)}, {ch.name_of(slave)}]"
        if master == slave:
            raise InterpError("INT209", f"{named}: an axis cannot be coupled to itself", s.col)
        if slave in main:
            raise InterpError("INT209", f"{named}: the main axes (the first three of the channel) cannot be "
                              "slaves (L14530)", s.col)
        axes = ch.machine.axes
        if axes[master].rotary != axes[slave].rotary:
            raise InterpError("INT209", f"{named}: master and slave must both be linear or both rotary (L14532)",
                              s.col)
        if any(k.slave == slave for k in pairs):
            raise InterpError("INT209", f"{named}: a slave cannot be coupled to two masters (L14536)", s.col)
        if any(k.slave == master for k in pairs) or any(k.master == slave for k in pairs):
            raise InterpError("INT209", f"{named}: the master of one pair cannot be the slave of another "
                              "(L14534)", s.col)
        pairs.append(Link(master, slave, st.machine_pos[slave] - st.machine_pos[master],
                          interp.iso.length(maxdiff, master) if maxdiff is not None else None))
    ch.links = tuple(pairs)
    st.dynamics_changed()


def _link_axis(interp, item, role: str) -> str:
    ch = interp.state.channel
    col = getattr(item, "col", 1)
    name = item_name(item)
    if name is None:
        raise InterpError("INT209", f"#LINK: expected the {role} axis", col)
    if name.startswith("?") and name[1:].isdigit():
        return ch.generic(int(name[1:]), col)
    axis = ch.word_axis(name, col)
    if axis is None:
        raise InterpError("INT204", f"#LINK: the machine has no axis {name}" if _AXIS_NAME.fullmatch(name)
                          else f"#LINK: {name} is not an axis name (X, Y ... C, X1 ... C9)", col)
    return axis


def unlink(interp, node) -> None:
    """``#UNLINK``: every coupling ends (L14545); the slaves stay where they followed their masters to."""
    if node.args:
        raise InterpError("INT209", "#UNLINK takes nothing after it", node.col)
    if interp.state.channel.links:
        _guard(interp, "#UNLINK", node.col)
    end_links(interp.state)


def sync_slaves(st) -> None:
    """The interpreter's own position of each coupled slave, where its master took it (what V.A.POS of a
    slave reads; the records get the slaves' positions from :func:`follow_links`).  Not under a
    transformation, where the interpreter's positions are in the programmed frame."""
    if st.kin.frame is None:
        pos = st.machine_pos
        for k in st.channel.links:
            pos[k.slave] = pos[k.master] + k.offset


def end_links(st) -> None:
    """End the couplings (#UNLINK, M02/M30 L14521): each slave's position is where its master took it."""
    ch = st.channel
    if not ch.links:
        return
    sync_slaves(st)
    ch.links = ()
    st.dynamics_changed()


def reset(st) -> None:
    """M02/M30: the couplings end (L14521); the axes whose change of channel is temporary (AXISEXCH 1) go
    back: those that came in leave, those that left return to their slot (or after the last) (L14694)."""
    end_links(st)
    ch = st.channel
    for axis in list(ch.slots):
        if axis is not None and axis not in ch.original and _exchange(ch.machine, axis) == 1:
            ch._release(axis)
    returned = []
    for i, axis in enumerate(ch.original):
        if axis not in ch.slots and _exchange(ch.machine, axis) == 1:
            free = i < len(ch.slots) and ch.slots[i] is None
            ch._put(axis, i if free or i >= len(ch.slots) else ch._free_slot_after_last(), 1)
            returned.append(axis)
    # RENAMECANCEL, and a rename to the name of an axis the channel gets back (L14955-L14962, L15017-L15021)
    cancel_renames(ch.names, returned, rename_cancel(ch.machine))
    ch._trim()
    ch._index()


# ---------------------------------------------------------------------- the sentences
def handles(kw: str, sub: str | None) -> bool:
    """A sentence of this module: #SET AX, #CALL AX, #FREE AX, #RENAME AX, #PARK, #UNPARK, #LINK, #UNLINK."""
    return (kw in ("PARK", "UNPARK", "LINK", "UNLINK", "CALL AX")
            or (sub == "AX" and kw in ("SET", "FREE", "RENAME")))


def statement(interp, node) -> None:
    kw = node.keyword
    if kw == "SET":
        set_ax(interp, node)
    elif kw == "CALL AX":
        call_ax(interp, node)
    elif kw == "FREE":
        free_ax(interp, node)
    elif kw == "RENAME":
        rename_ax(interp, node)
    elif kw in ("PARK", "UNPARK"):
        park(interp, node, kw == "UNPARK")
    elif kw == "LINK":
        link(interp, node)
    else:
        unlink(interp, node)


# ---------------------------------------------------------------------- variables
def slot_name(st, n: int) -> float:
    """``V.G.AXISNAMEn``: the name code of the axis in slot n, holes counted (L32964); 0 for a hole or a
    parked axis ([CONSTRUCTION]: the manual shows them as "?", L32990, and gives no number for it), also for
    the free positions up to the machine's number of axes (the manual's screens show as many, L14818)."""
    ch = st.channel
    top = max(len(ch.slots), len(ch.machine.axes))
    if not 1 <= n <= top:
        raise InterpError("INT045", f"there is no axis index {n} (1..{top})", 1)
    axis = ch.slots[n - 1] if n <= len(ch.slots) else None
    return 0.0 if axis is None or axis in ch.parked else name_code(ch.name_of(axis))


def logical_name(st, n: int) -> float:
    """``V.G.GAXISNAMEn``: the name code of logical axis n (the machine file's order, L32747), its name in
    the channel if renamed; 0 when parked (L32762)."""
    ch = st.channel
    names = ch.machine.axis_names
    if not 1 <= n <= len(names):
        raise InterpError("INT045", f"there is no logical axis {n} (1..{len(names)})", 1)
    axis = names[n - 1]
    return 0.0 if axis in ch.parked else name_code(ch.name_of(axis))


def axis_count(st, holes: bool) -> float:
    """``V.G.AXIS`` (the channel's axes) and ``V.G.NAXIS`` (counting the holes of the axes given away), L32908-L32925;
    also ``MPG.CHNAXIS``, which #SET AX, #FREE AX and #CALL AX change (L19375)."""
    slots = st.channel.slots
    return float(len(slots) if holes else sum(a is not None for a in slots))


def variables(st) -> dict:
    """``V.G.LINKACTIVE``: 1 while a coupling is active (L40690)."""
    return {"V.G.LINKACTIVE": (lambda _index: 1.0 if st.channel.links else 0.0, None)}


def axis_variables() -> dict:
    """``V.A.ACTCH.Xn``: the channel the axis is in, 1, or 0 when in none (L14715, L32821)."""
    return {"V.A.ACTCH": (lambda st, _index, axis: 1.0 if st.channel.in_channel(axis) else 0.0, None)}


# ---------------------------------------------------------------------- the slaves in the records
def follow_links(records, st, on_error) -> Iterator:
    """Write each coupled slave's position into the records made under a coupling (``dyn.links``): the
    slave's start and end follow its master's; the feed is scaled so that the path over the other axes
    keeps its programmed speed (the slave follows, it does not share the feed); each slave end point is
    checked against the slave's soft limits (those of ``st``, the channel state).  ``on_error(record, code,
    message)`` raises."""
    links: tuple = ()
    for rec in records:
        kind = rec.kind
        if kind in ("linear", "rapid", "arc"):
            dyn = rec.dyn
            if dyn is not None:
                links = dyn.links
            if links:
                rec = _follow(rec, links, on_error)
                check_slave_limits(rec, links, st.lower_limits, st.upper_limits, on_error)
        elif links and kind in ("dwell", "aux"):
            position = dict(rec.position)
            for k in links:
                position[k.slave] = position[k.master] + k.offset
            rec = dataclasses.replace(rec, position=position)
        yield rec


def _follow(rec, links, on_error):
    start, end = dict(rec.start), dict(rec.end)
    if rec.kind == "arc":
        plane = rec.plane[:2]
        for k in links:
            if k.master in plane:
                on_error(rec, "INT211", f"coupled axis {k.slave} cannot follow {k.master} along an arc of the plane: "
                         "fagorcnc's arcs move only the plane's two axes on the circle (the slave would cut a "
                         "chord); program the arc with #UNLINK, or couple axes outside the plane")
    for k in links:
        start[k.slave] = start[k.master] + k.offset
        end[k.slave] = end[k.master] + k.offset
    part = dict(rec.end_part)
    for k in links:
        if k.slave in part and k.slave in rec.end:
            part[k.slave] += end[k.slave] - rec.end[k.slave]
    feed = rec.feed
    if feed and rec.kind != "arc":   # a line's length over all its axes, the slaves now included
        before = rec.length
        after = math.sqrt(sum((end[a] - start[a]) ** 2 for a in end))
        if before > 0.0 and after > before:
            feed *= after / before
        return dataclasses.replace(rec, start=start, end=end, end_part=part, feed=feed)
    new = dataclasses.replace(rec, start=start, end=end, end_part=part)
    if feed:
        before, after = rec.length, new.length   # an arc: its plane's sweep and the helix axes
        if before > 0.0 and after > before:
            new = dataclasses.replace(new, feed=feed * after / before)
    return new


def check_slave_limits(rec, links, lower: dict, upper: dict, on_error) -> None:
    """Each slave's end point within its soft limits (seed 002 L9201; an axis already outside may only
    move back toward them, L9226)."""
    for k in links:
        s = k.slave
        v, a = rec.end[s], rec.start[s]
        lo, hi = lower[s], upper[s]
        if lo - 1e-9 <= v <= hi + 1e-9:
            continue
        if (v < lo and a < lo and v >= a - 1e-9) or (v > hi and a > hi and v <= a + 1e-9):
            continue
        bound = "lower" if v < lo else "upper"
        on_error(rec, "INT100", f"coupled axis {s} to {v:.4f} (machine) is beyond its {bound} limit "
                 f"{lo if v < lo else hi:g} (it follows {k.master}, #LINK)")
