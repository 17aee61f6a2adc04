"""The channel's spindle configuration: ``#SET SP``, ``#CALL SP``, ``#FREE SP``, ``#RENAME SP`` (seed 002
ch. 21.1.9, L15049-L15233), the master spindle after a change (L5174-L5192, L5270-L5283) and RENAMECANCEL
(L14955-L14962, L15191-L15208, L19222-L19260) for the names of the axes and the spindles.

* The channel starts with the spindles of the machine file's ``channel_spindles`` (CHSPDLNAME), all the
  machine's spindles when it gives none; the others are free for ``#CALL SP`` (a channel may have one,
  several or no spindle, L15051-L15055).  Their order is the spindle's index in the channel
  (``V.G.SPDLNAMEn``); "the position of the spindles in the channel does not matter" (L15124-L15125).
* Speeds, states and records stay keyed by the machine's spindle names throughout fagorcnc, as the axes do:
  a spindle that leaves the channel keeps its state; it just cannot be programmed (S, M3.Sn, Sn.POS,
  #MASTER, #PARK: INT246).  ``#RENAME SP`` gives a spindle of the channel another name in the program
  (L15144-L15154); its variables are then read by the new name (L15211-L15213).
* AXISEXCH of a spindle (L15056-L15062, values L15104-L15106): the machine file's ``[machine_parameters]``
  ``"MPA.AXISEXCH.S1"``, else 1 (temporary, an axis's default in fagorcnc).  0: it may not change channel;
  1: M02, M30 and reset take the change back; 2: it is kept.
"""

from __future__ import annotations

import re

from ..syntax.ast import ItemList, Keyed, Name
from .expressions import InterpError
from .mpvars import name_code
from .renaming import Renaming, item_name, rename

_SPINDLE_NAME = re.compile(r"S[1-9]?")
_NAME_MSG = "a spindle is named S or S1 ... S9"
_RENAME_SP = Renaming("SP", "spindle", "spindles", "INT249", _SPINDLE_NAME, _NAME_MSG, "[S, S1] [S3, S]", "[S3]")


def parameter(machine, name: str, target: str | None = None, default: float = 0.0) -> float:
    """A machine parameter fagorcnc uses that its machine file gives in ``[machine_parameters]`` (the manual's
    spelling, ``"MPG.RENAMECANCEL" = 1``), or ``default``."""
    return machine.machine_parameters.get((name, (), target), default)


def exchange(machine, spindle: str) -> int:
    """AXISEXCH of a spindle (L15056-L15062): ``"MPA.AXISEXCH.S1"``, else 1 (temporary)."""
    return int(parameter(machine, "AXISEXCH", spindle, 1.0))


def rename_cancel(machine) -> bool:
    """RENAMECANCEL (L19222-L19260: 0 no, 1 yes): M02, M30, a reset and the start of a new program cancel
    the #RENAME of the axes and spindles (L14955-L14958, L15191-L15194).  [CONSTRUCTION] the manual gives no
    default: 0, the renames are kept (what fagorcnc did before it read the parameter)."""
    return parameter(machine, "RENAMECANCEL") != 0


class ChannelSpindles:
    """Which machine spindles are in the channel, in which order, and under which name."""

    def __init__(self, machine) -> None:
        self.machine = machine
        self.original: list[str] = list(getattr(machine, "channel_spindles", None) or machine.spindles)
        self.current: list[str] = list(self.original)
        self.names: dict[str, str] = {}      # machine spindle -> its name after #RENAME SP (renamed ones only)
        self.by_name: dict[str, str] = {}    # program name -> machine spindle, for the spindles of the channel
        self._index()

    def _index(self) -> None:
        self.by_name = {self.name_of(s): s for s in self.current}
        self.changed = self.current != self.original or bool(self.names)

    def name_of(self, spindle: str) -> str:
        """The program's name of machine spindle ``spindle``."""
        return self.names.get(spindle, spindle)

    def in_channel(self, spindle: str) -> bool:
        return spindle in self.current

    def word(self, name: str, col: int) -> str:
        """The machine spindle a spindle name of a block designates (``S1=``, ``M3.S1``, ``S1.POS=``,
        ``#MASTER S1``, ``#PARK S1``): one of the channel, by its name in the channel.  INT246 for a spindle
        of the machine that is not in the channel under that name, INT020 for a name the machine does not
        have."""
        spindle = self.by_name.get(name)
        if spindle is not None:
            return spindle
        if name in self.machine.spindles:
            renamed = self.names.get(name)
            why = (f"it is called {renamed} since #RENAME SP" if renamed and self.in_channel(name)
                   else "#FREE SP, #SET SP or the machine's channel configuration left it out")
            raise InterpError("INT246", f"spindle {name} is not in the channel's spindle configuration ({why}; "
                              "L15089-L15142)", col)
        raise InterpError("INT020", f"spindle {name} does not exist on this machine", col)

    def variable(self, name: str) -> str | None:
        """The machine spindle a variable's spindle name reads: one of the channel by its name in the channel
        (L15211-L15213), else a spindle out of the channel by its own name (it got it back, L15200-L15201)."""
        spindle = self.by_name.get(name)
        if spindle is None and name in self.machine.spindles and not self.in_channel(name):
            return name
        return spindle

    def master_order(self) -> list[str]:
        """The candidates for master, in the manual's order (L5174-L5192, L5270-L5283): the spindles of the original
        configuration still in the channel, in the machine file's order, then the others of the current
        configuration."""
        current = self.current
        return [s for s in self.original if s in current] + [s for s in current if s not in self.original]


# ---------------------------------------------------------------------- statement helpers
def _list(items: ItemList, what: str, code: str = "INT247") -> list[tuple[str, int]]:
    """The spindle names of a bracket list ``[S, S1]`` with their columns (``code``: the statement's error)."""
    out = []
    for seq in items.items:
        item = seq[0] if len(seq) == 1 else None
        col = getattr(item, "col", items.col)
        name = item_name(item) if item is not None else None
        if name is None or not _SPINDLE_NAME.fullmatch(name):
            raise InterpError(code, f"{what}: expected the spindles, {_NAME_MSG}: {what} [S, S1]", col)
        if any(n == name for n, _c in out):
            raise InterpError(code, f"{what}: spindle {name} is listed twice", col)
        out.append((name, col))
    return out


def _entries(node, what: str) -> list[tuple[str, int]]:
    """``#SET SP [..]`` / ``#FREE SP [..]`` (SP [..]) and ``#CALL SP [..]`` ([..])."""
    args = node.args
    first = args[0] if len(args) == 1 else None
    if type(first) is Keyed and type(first.value) is ItemList:
        return _list(first.value, what)
    if type(first) is ItemList:
        return _list(first, what)
    raise InterpError("INT247", f"{what} takes the spindles in brackets: {what} [S, S1]", node.col)


def _any_spindle(cfg: ChannelSpindles, name: str, col: int, what: str) -> str:
    """The machine spindle ``name`` names: one of the channel by its current name, else one out of the
    channel by its own name."""
    spindle = cfg.variable(name)
    if spindle is not None:
        return spindle
    if name in cfg.machine.spindles:
        raise InterpError("INT247", f"{what}: spindle {name} is called {cfg.name_of(name)} since #RENAME SP", col)
    raise InterpError("INT247", f"{what}: the machine has no spindle {name} (its spindles: "
                      f"{' '.join(cfg.machine.spindles) or 'none'})", col)


def _leaving(interp, spindle: str, col: int, what: str) -> None:
    """What keeps a spindle in the channel: AXISEXCH 0 (L15056-L15062) and, [CONSTRUCTION] as for the axes,
    what keeps it from being parked (L14615-L14631): it turns, works as a C axis, or is the master with
    G33, G63, G95 or G96 active; synchronised spindles cannot change channel (L15368) and #SYNC is not run
    offline."""
    cfg = interp.state.spindle_config
    name = cfg.name_of(spindle)
    if exchange(cfg.machine, spindle) == 0:
        raise InterpError("INT248", f"{what}: spindle {name} may not change channel (its AXISEXCH is 0, L15062)",
                          col)
    busy = spindle_busy(interp, spindle)
    if busy:
        raise InterpError("INT248", f"{what}: spindle {name} cannot leave the channel while {busy} "
                          "(L14615-L14631)", col)


def spindle_busy(interp, spindle: str) -> str:
    """Why a spindle may not be parked (L14615-L14626), nor leave the channel; "" when it may."""
    st = interp.state
    if st.spindle_state.get(spindle) in (3, 4):
        # L14619 reads "if the spindle is stopped": taken as "not stopped" (spec 06 §4.7)
        return "it turns (M3/M4); stop it with M5 first"
    if st.kin.cax is not None and st.kin.cax[0] == spindle:
        return "it works as a C axis (#CAX)"
    master = st.master_spindle()
    if spindle == master and (st.modes.get("css") == 96 or st.modes.get("feed") == 95):
        return "it is the master spindle with G96 or G95 active"
    if spindle == master and st.modes.get("motion") in (33, 63):   # L14622-L14626: G63, G33 too
        return f"it is the master spindle with G{st.modes['motion']} active"
    return ""


def _coming(cfg: ChannelSpindles, spindle: str, col: int, what: str) -> None:
    """A spindle may join only if it is free: one out of every channel, or of another channel whose
    AXISEXCH lets it change (L15125-L15126); offline a spindle out of the channel is in no channel unless
    AXISEXCH 0 ties it to one."""
    if exchange(cfg.machine, spindle) == 0 and spindle not in cfg.original:
        raise InterpError("INT248", f"{what}: spindle {spindle} may not change channel (its AXISEXCH is 0, "
                          "L15062)", col)


def _release(interp, spindle: str) -> None:
    st = interp.state
    cfg = st.spindle_config
    cfg.current.remove(spindle)
    cfg.names.pop(spindle, None)   # a released spindle gets its own name back (L15200-L15201)
    if st.master == spindle:
        st.master = None           # the master leaves: the channel chooses another (L5300-L5302)


def free_sp(interp, node) -> None:
    """``#FREE SP [S, S1]`` / ``#FREE SP ALL`` (L15089-L15097, L15156-L15162): the spindles leave the channel."""
    cfg = interp.state.spindle_config
    what = "#FREE SP"
    args = node.args
    if len(args) == 2 and type(args[0]) is Name and type(args[1]) is Name and args[1].name == "ALL":
        spindles = [(s, args[1].col) for s in cfg.current]
    else:
        spindles = []
        for name, col in _entries(node, what):
            spindle = cfg.by_name.get(name)
            if spindle is None:
                raise InterpError("INT247", f"{what}: there is no spindle {name} in the channel's configuration", col)
            spindles.append((spindle, col))
    for spindle, col in spindles:
        _leaving(interp, spindle, col, what)
    for spindle, _col in spindles:
        _release(interp, spindle)
    cfg._index()


def call_sp(interp, node) -> None:
    """``#CALL SP [S1, S2]`` (L15121-L15130, L15169-L15172): free spindles join the channel, after its last
    one; one already in the channel stays ([CONSTRUCTION] as ``#CALL AX`` of an axis already there, L14790)."""
    cfg = interp.state.spindle_config
    what = "#CALL SP"
    for name, col in _entries(node, what):
        spindle = _any_spindle(cfg, name, col, what)
        if cfg.in_channel(spindle):
            continue
        _coming(cfg, spindle, col, what)
        cfg.current.append(spindle)
        cfg._index()


def set_sp(interp, node) -> None:
    """``#SET SP [S1, S2]`` (L15132-L15142, L15179-L15182): the channel's new spindles, in this order.  "The
    spindles of the channel not programmed are removed and the programmed ones that were not there are added"
    (L15135-L15137); [CONSTRUCTION] a spindle in both stays where it is, with its name and without the checks of
    one that leaves (the manual also calls it "equivalent to #FREE SP of all, then #CALL SP", L15139-L15140,
    which would refuse a turning spindle that stays)."""
    cfg = interp.state.spindle_config
    what = "#SET SP"
    new: list[str] = []
    cols: dict[str, int] = {}
    for name, col in _entries(node, what):
        spindle = _any_spindle(cfg, name, col, what)
        if spindle in new:
            raise InterpError("INT247", f"{what}: spindle {name} is listed twice", col)
        new.append(spindle)
        cols[spindle] = col
    leaving = [s for s in cfg.current if s not in new]
    for spindle in leaving:
        _leaving(interp, spindle, node.col, what)
    for spindle in new:
        if not cfg.in_channel(spindle):
            _coming(cfg, spindle, cols[spindle], what)
    for spindle in leaving:
        _release(interp, spindle)
    cfg.current = new
    cfg._index()


def rename_sp(interp, node) -> None:
    """``#RENAME SP [S, S1] [..]``: each pair's first spindle takes the second name; a spindle of the channel
    with that name takes the first (L15144-L15154, L15189-L15190).  ``#RENAME SP OFF <[S3, ..]>``: the own
    names back, whatever RENAMECANCEL says (L15214-L15233)."""
    rename(node, interp.state.spindle_config, _RENAME_SP, _renamed)


def _renamed(cfg: ChannelSpindles, col: int) -> None:
    cfg.names = {s: n for s, n in cfg.names.items() if n != s}
    cfg._index()
    if len(cfg.by_name) != len(cfg.current):
        # [CONSTRUCTION] e.g. #RENAME SP OFF of one spindle of a swap: the manual does not say what the other is
        raise InterpError("INT249", "#RENAME SP: two spindles of the channel would have the same name; cancel "
                          "both renames (#RENAME SP OFF [..] of both)", col)


def cancel_renames(names: dict[str, str], returned: list, cancel: bool) -> None:
    """At M02/M30 and reset: RENAMECANCEL (``cancel``) cancels every rename of the channel (L14955-L14958);
    without it a rename is still cancelled when the channel gets back an element (``returned``) of the same
    name (L15017-L15021, L15203-L15208), and so on for a rename whose name the cancelled one's element takes
    back.  ``names`` (element -> new name) is changed in place."""
    if cancel:
        names.clear()
        return
    taken = set(returned)   # the own names of the elements the channel got back
    while taken:
        clash = [e for e, n in names.items() if n in taken]
        for e in clash:
            del names[e]
        taken = set(clash)      # these take their own names back: a rename to one of them clashes in turn


def reset(st) -> None:
    """M02/M30/reset: the spindles whose change of channel is temporary (AXISEXCH 1) go back (L5155-L5170):
    those that came in leave, those that left return; then RENAMECANCEL.  [CONSTRUCTION] the manual undoes a
    temporary exchange at the start of the next program rather than at M30 (L5163-L5170): offline every
    program starts from the machine file, so the two cannot be told apart in a run."""
    cfg = st.spindle_config
    machine = cfg.machine
    for spindle in list(cfg.current):
        if spindle not in cfg.original and exchange(machine, spindle) == 1:
            cfg.current.remove(spindle)
            cfg.names.pop(spindle, None)
    returned = [s for s in cfg.original if s not in cfg.current and exchange(machine, s) == 1]
    cfg.current.extend(returned)
    cancel_renames(cfg.names, returned, rename_cancel(machine))
    cfg._index()


# ---------------------------------------------------------------------- the sentences
def handles(kw: str, sub: str | None) -> bool:
    """A sentence of this module: #SET SP, #CALL SP, #FREE SP, #RENAME SP."""
    return kw == "CALL SP" or (sub == "SP" and kw in ("SET", "FREE", "RENAME"))


def statement(interp, node) -> None:
    kw = node.keyword
    if kw == "SET":
        set_sp(interp, node)
    elif kw == "CALL SP":
        call_sp(interp, node)
    elif kw == "FREE":
        free_sp(interp, node)
    else:
        rename_sp(interp, node)


# ---------------------------------------------------------------------- variables
def spindle_count(st) -> float:
    """``V.G.NSPDL``, ``MPG.CHNSPDL``: the spindles of the channel (L32930, L19444)."""
    return float(len(st.spindle_config.current))


def index_name(st, n: int) -> float:
    """``V.G.SPDLNAMEn``: the name code of the spindle with index n in the channel (L32985), its name after
    #RENAME SP; 0 when parked ([CONSTRUCTION] as V.G.AXISNAMEn shows a parked axis as "?", L32976)."""
    cfg = st.spindle_config
    if not 1 <= n <= len(cfg.current):
        raise InterpError("INT045", f"there is no spindle index {n} in the channel (1..{len(cfg.current)})", 1)
    spindle = cfg.current[n - 1]
    return 0.0 if spindle in st.channel.parked else name_code(cfg.name_of(spindle))


def logical_name(st, n: int) -> float:
    """``V.G.GSPDLNAMEn``: the name code of logical spindle n, numbered after the axes (L32771-L32790), its
    name in the channel if renamed."""
    m = st.machine
    k = n - len(m.axes)
    if not 1 <= k <= len(m.spindles):
        raise InterpError("INT045", f"no spindle has the logical number {n} (the spindles are "
                          f"{len(m.axes) + 1}..{len(m.axes) + len(m.spindles)}, numbered after the axes)", 1)
    return name_code(st.spindle_config.name_of(m.spindles[k - 1]))


def variables(st) -> dict:
    """``V.A.ACTCH.Sn`` / ``V.SP.ACTCH.Sn``: the channel the spindle is in, 1, or 0 in none (L32821-L32864)."""
    return {"ACTCH": lambda sp: 1.0 if st.spindle_config.in_channel(sp) else 0.0}
