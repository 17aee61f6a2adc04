"""Classification of an ISO block's words by role (G functions, axes, parameters, F S T D M H, NR, calls),
and the checks of its G functions against the G table (seed 002 L1021, ch. 2).  A mixin of
:class:`~fagorcnc.interp.iso.IsoExecutor`."""

from __future__ import annotations

from dataclasses import dataclass, field

from ..syntax.ast import Word
from . import compat
from .expressions import InterpError
from .gtable import EXCLUSIVE_GROUPS, G_FUNCTIONS
from .spindle import parse_suffix as spindle_suffix

_AXIS_LETTERS = frozenset("XYZUVWABC")
#: letters that are parameters of G functions, not axes (chapters 8-12)
_PARAM_LETTERS = frozenset("IJKRQEL")


@dataclass
class BlockWords:
    """The evaluated words of one ISO block, sorted by role."""

    g: list = field(default_factory=list)            # (number, col, eq)
    axes: dict = field(default_factory=dict)         # axis name -> (value, col)
    params: dict = field(default_factory=dict)       # I J K R Q ... -> (value, col)
    feed: tuple | None = None
    speeds: dict = field(default_factory=dict)       # spindle -> (value, col)
    tool: tuple | None = None
    offset: tuple | None = None
    m: list = field(default_factory=list)            # (number, col)
    h: list = field(default_factory=list)
    nr: tuple | None = None
    call: tuple | None = None                        # (G number, modal, col, argument words)
    roles: list = field(default_factory=list)        # G20: (axis, type, col); an axis may repeat
    scale: tuple | None = None                       # G72 S<factor> (S after G72, L9010)
    percent: tuple | None = None                     # G131/G133 <percent> (L4437)
    m_target: dict = field(default_factory=dict)     # index in m -> (spindle, direction) of "M3.S2", "M19.POS"
    position_speeds: dict = field(default_factory=dict)   # spindle -> (rpm, col) of "S.POS=" (L5904)
    cycle: dict | None = None                        # canned cycle parameters: letter -> (value, col)
    glued: tuple | None = None                       # "T202 LM06": (name, "L", {}, col) of the call


class WordsMixin:
    """:meth:`classify` (words by role into a :class:`BlockWords`) and :meth:`check_g`."""

    # ------------------------------------------------------------ words
    def classify(self, words: list[Word]) -> BlockWords:
        cycle = self.cycles.cycle_code(words)
        if cycle is not None:   # its letters are parameters, not axes, offsets or H/M functions
            words, params = self.cycles.split(words, *cycle)
            bw = self._classify(words)
            bw.cycle = params
            return bw
        return self._classify(words)

    def _classify(self, words: list[Word]) -> BlockWords:
        ev, st = self.ev, self.state
        bw = BlockWords()
        channel = st.channel
        by_name = channel.by_name
        g157 = any(w.address == "G" and w.value == 157.0 for w in words)
        g20 = any(w.address == "G" and w.value == 20.0 for w in words)
        skip = 0
        for i, w in enumerate(words):
            addr, col = w.address, w.col
            if skip and col < skip:
                continue   # the name of a glued call (T202 LM06)
            if w.value is None:
                if addr == "L" and i > 0:
                    call = compat.glued_call(self.interp, w, self.interp.block_text())
                    if call is not None:   # "T202 LM06" (LIGNOCAM): L M06 called after the block
                        bw.glued, skip = call   # (without its file: the M06 word that follows runs)
                        continue
                if not (g157 and (addr in st.machine.axes or addr[0] == "?")):
                    raise InterpError("INT025", f"'{addr}' needs a value", col)
                w = w._replace(value=1.0)  # G157 X: exclude X (L3851-L3852)
            if addr == "G" or addr == "MG":
                n = ev.integer(w.value, addr, col, 0, 9999)
                if n == 51 and compat.g51_block(self.interp, words):
                    return BlockWords()   # "G51 A45 E0.002": executed as nothing (compat.g51)
                if (180 <= n <= 189 or 380 <= n <= 399 or 500 <= n <= 599) or addr == "MG":
                    bw.call = (n, addr == "MG", col, tuple(words[i + 1:]))
                    return bw  # every word after the call is an argument (L10712-L10719)
                eq = ev.value(w.eq) if w.eq is not None else None
                bw.g.append((n, col, eq))
                if n >= 10:
                    compat.leading_zero(self.interp, n, col, self.interp.block_text())   # "G011" is G11
            elif addr == "N":
                st.last_n = ev.integer(w.value, "N", col)
            elif addr == "" and bw.percent is None and any(n in (131, 133) for n, _c, _e in bw.g):
                bw.percent = (ev.value(w.value), col)   # seed 002 L4437: G131 100 X50 Y80
            elif addr == "":
                if "K" in bw.params or not any(n == 4 for n, _c, _e in bw.g):
                    raise InterpError("INT025", "a number without its letter is only allowed as the time "
                                      "of G04 (G04 5)", col)
                bw.params["K"] = (ev.value(w.value), col)   # seed 002 L9187: G04 5
            elif addr == "F":
                bw.feed = (ev.value(w.value), col)
            elif addr == "S" and any(g[0] == 72 for g in bw.g):
                bw.scale = (ev.value(w.value), col)   # an S after G72 is the scale factor (L9010)
            elif addr == "S" or (addr[0] == "S" and addr[1:].isdigit()):
                # S alone is the master spindle's (L5133: orders go to it when no spindle is named)
                # a named one by its name in the channel's spindle configuration (INT246, interp/spindle_config.py)
                spindle = st.master_spindle() if addr == "S" else st.spindle_config.word(addr, col)
                if spindle is None:
                    raise InterpError("INT020", f"{addr}: the channel has no spindle", col)
                bw.speeds[spindle] = (ev.value(w.value), col)
            elif addr == "T":
                bw.tool = (ev.integer(w.value, "T", col, 0, 4294967294, floor=True), col)
            elif addr == "D":
                bw.offset = (ev.integer(w.value, "D", col), col)
            elif addr == "M" or addr[:2] == "M.":
                if len(bw.m) == 7:  # spec 02 §19: up to 7 M per block
                    raise InterpError("INT021", "more than 7 M functions in one block", col)
                m = ev.integer(w.value, "M", col, 0, 65535, floor=True)
                if addr != "M":   # M3.S2, M19.POS.S1 (seed 002 L5720-L5760, L5843-L5880)
                    if m != 19 and (".POS" in addr or ".NEG" in addr):
                        raise InterpError("INT025", f"M{m}{addr[1:]}: only M19 takes a direction .POS/.NEG (L5843)",
                                          col)
                    if m not in (3, 4, 5, 19, 41, 42, 43, 44):
                        raise InterpError("INT025", f"M{m}{addr[1:]}: a spindle suffix goes with M3, M4, M5, M19 "
                                          "and M41-M44 (L5950)", col)
                    bw.m_target[len(bw.m)] = spindle_suffix(addr, st.spindle_config, col)
                bw.m.append((m, col))
            elif addr[0] == "S" and addr.endswith(".POS"):   # S.POS=120, S1.POS=50 (L5904-L5934)
                name = addr[:-4]
                spindle = st.master_spindle() if name == "S" else st.spindle_config.word(name, col)
                if spindle is None:
                    raise InterpError("INT020", f"{addr}: the channel has no spindle", col)
                speed = ev.value(w.value)
                if speed <= 0:
                    raise InterpError("INT027", f"M19 positioning speed {speed:g} must be positive (L5904)", col)
                bw.position_speeds[spindle] = (speed, col)
            elif addr == "H":
                if len(bw.h) == 7:
                    raise InterpError("INT021", "more than 7 H functions in one block", col)
                bw.h.append((ev.integer(w.value, "H", col, 0, 65535, floor=True), col))
            elif addr == "NR":
                bw.nr = (ev.integer(w.value, "NR", col), col)
            elif addr[0] == "?":   # seed 002 L1211: ?n on a hole or beyond the channel is an error
                self._axis_word(bw, channel.generic(int(addr[1:]), col), ev.value(w.value), col)
            elif (axis := by_name.get(addr)) is not None or addr in st.machine.axes:   # its name in the channel
                if axis is None or channel.parked:
                    axis = channel.word_axis(addr, col)   # not in the channel, or parked: the error (interp/axes.py)
                if g20:
                    bw.roles.append((axis, ev.value(w.value), col))
                    continue
                self._axis_word(bw, axis, ev.value(w.value), col)
            elif addr == "Q1" and (st.modes["motion"] in (33, 63) or any(
                    x.address == "G" and x.value in (33.0, 63.0) for x in words)):
                bw.params["Q1"] = (ev.value(w.value), col)   # G33 entry angle (seed 002 L7358)
            elif addr == "R1":   # modal arc radius R1= (seed 002 L6418)
                bw.params["R1"] = (ev.value(w.value), col)
            elif addr in _PARAM_LETTERS or (len(addr) == 1 and addr not in _AXIS_LETTERS):
                if addr in bw.params:
                    raise InterpError("INT023", f"{addr} is written twice in the block", col)
                bw.params[addr] = (ev.value(w.value), col)
            elif addr[0] in _AXIS_LETTERS:
                self._unknown_g(words)   # "G51 A45 E0.002" (another CNC's smoothing): the G is the mistake
                raise InterpError("INT024", f"axis {addr} does not exist on this machine", col)
            else:
                raise InterpError("INT025", f"'{addr}' is not meaningful here", col)
        if channel.busy:   # a coupled slave programmed, a parked spindle (interp/axes.py)
            channel.check_block(bw, frozenset(n for n, _c, _e in bw.g), st.master_spindle())
        return bw

    @staticmethod
    def _axis_word(bw: BlockWords, axis: str, value: float, col: int) -> None:
        if axis in bw.axes:
            raise InterpError("INT023", f"axis {axis} is written twice in the block", col)
        bw.axes[axis] = (value, col)

    def _unknown_g(self, words: list[Word]) -> None:
        """Raise INT010 for a G function of the block that the 8060/8065 does not have, if any: its
        other words may be meaningless only because of it."""
        for w in words:
            if w.address == "G" and w.value is not None:
                try:
                    n = self.ev.integer(w.value, "G", w.col, 0, 9999)
                except InterpError:
                    continue
                if n not in G_FUNCTIONS:
                    raise InterpError("INT010", f"G{n} is not a G function of the 8060/8065", w.col)

    def check_g(self, bw: BlockWords) -> None:
        seen: dict[str, int] = {}
        for n, col, _eq in bw.g:
            g = G_FUNCTIONS.get(n)
            if g is None:
                raise InterpError("INT010", f"G{n} is not a G function of the 8060/8065", col)
            if g.support == "no":
                raise InterpError("INT011", f"G{n} ({g.meaning}) is not supported by fagorcnc yet", col)
            if g.group in EXCLUSIVE_GROUPS:
                if g.group in seen and seen[g.group] != n:
                    raise InterpError("INT012", f"G{seen[g.group]} and G{n} are incompatible in one block", col)
                seen[g.group] = n
