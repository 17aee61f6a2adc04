"""Spindle functions per spindle: M03/M04/M05/M19 for the spindles they name, the M19 positioning
mode, its direction and speed, and the programmed spindle override (seed 002 ch. 7, L5683-L5934;
variables L37040-L37215).

* Which spindles a function acts on (spec 03 §A.9, L5950-L5966): ``Mx.Sn`` acts on Sn only; an
  unsuffixed M03/M04 on every spindle with a speed in the block that no other M of the block
  names, else on the master; an unsuffixed M19 likewise on the spindles with a value in the block,
  else on the master (to 0 degrees); an unsuffixed M05 on the master.
* M19 (L5683-L5790): the spindle leaves speed mode for positioning mode until M03/M04.  The
  value of S in an M19 block is the angle, absolute, modulo 360 (``M19 S-100`` is 260 degrees);
  without one the angle is 0.  While a spindle is positioning, an S without M19 is its new speed,
  kept for the M03/M04 that returns it to speed mode (L5705-L5707): that speed reaches the back-end
  with the M03/M04, not before, since the spindle does not turn meanwhile.
* Direction (L5795-L5880): ``M19.POS`` / ``M19.NEG`` for every spindle of the block,
  ``M19.POS.Sn`` for Sn only, the other spindles of the block positioned in their own direction
  (L5867-L5868); remembered per spindle until another is programmed, cleared by a reset.
* ``S.POS=`` / ``Sn.POS=``: the positioning speed in rpm (L5904-L5934), read as
  ``V.A.PRGSPOS.sn``; ``V.A.SPOS.sn`` is the active one (the PLC's when it set one: never
  offline).  ``V.A.PRGSSO.sn`` is the override the program sets (0 = none) and ``V.A.SSO.sn``
  the active override: the program's, else the PLC's, else the panel's 100 % (L37152-L37215).
"""

from __future__ import annotations

from dataclasses import dataclass, field

from .expressions import InterpError


@dataclass
class SpindleModes:
    """Per spindle name: positioning mode, remembered direction, positioning speed, override."""

    positioning: set[str] = field(default_factory=set)
    new_speed: set[str] = field(default_factory=set)         # an S programmed while positioning
    direction: dict[str, int] = field(default_factory=dict)     # +1 .POS, -1 .NEG
    position_speed: dict[str, float] = field(default_factory=dict)   # rpm, S.POS=
    override: dict[str, float] = field(default_factory=dict)    # %, V.A.PRGSSO; 0 = none

    def reset(self) -> None:
        """The reset set (M02, M30, reset): speed mode with M05, no remembered direction (L5793)."""
        self.positioning.clear()
        self.new_speed.clear()
        self.direction.clear()

    def variables(self, state) -> dict:
        """Spindle variables ``V.A.<name>.sn`` / ``V.SP.<name>.sn``: name -> (getter, setter)."""

        def sync(getter):
            def get(sp):
                state.sync = True   # an execution value: its reading stops preparation
                return getter(sp)
            return get

        def set_override(sp, value):
            if value < 0.0:
                raise InterpError("INT045", f"spindle override {value:g} %: 0 (none) or a percentage", 1)
            self.override[sp] = value

        return {
            "PRGSPOS": (lambda sp: self.position_speed.get(sp, 0.0), None),
            "SPOS": (sync(lambda sp: self.position_speed.get(sp, 0.0)), None),
            "PRGSSO": (lambda sp: self.override.get(sp, 0.0), set_override),
            "SSO": (sync(lambda sp: self.override.get(sp, 0.0) or 100.0), None),
        }


def parse_suffix(address: str, spindles, col: int) -> tuple[str | None, int | None]:
    """``"M.POS.S1"`` -> ("S1", +1); ``"M.S4"`` -> ("S4", None); ``"M.NEG"`` -> (None, -1).  ``spindles``: the
    channel's spindle configuration (:class:`~fagorcnc.interp.spindle_config.ChannelSpindles`), which gives the
    machine spindle of a name of the channel (INT246 for a spindle out of the channel)."""
    spindle, direction = None, None
    for part in address.split(".")[1:]:
        if part in ("POS", "NEG"):
            direction = 1 if part == "POS" else -1
        else:
            spindle = spindles.word(part, col)
    return spindle, direction


def targets(bw, index: int, master: str | None) -> list[str]:
    """The spindles the index-th M of the block acts on (spec 03 §A.9, L5950-L5966)."""
    m, _col = bw.m[index]
    named, direction = bw.m_target.get(index, (None, None))
    if named is not None and m == 19 and direction is not None:
        # L5867-L5868: "M19.NEG.S1 S1=100 S34.75": the direction is S1's; both spindles are positioned
        return [named, *(sp for sp in bw.speeds if sp != named)]
    if named is not None:
        return [named]
    if m in (3, 4, 19):
        claimed = {sp for k, (sp, _) in bw.m_target.items() if sp is not None and k != index}
        found = [sp for sp in bw.speeds if sp not in claimed]
        if found:
            return found
    return [master] if master is not None else []


def orientation(bw, master: str | None) -> dict[str, float]:
    """The M19 positions of the block: spindle -> angle in [0, 360) (L5703-L5713, L5776-L5790)."""
    out: dict[str, float] = {}
    for k, (m, _col) in enumerate(bw.m):
        if m == 19:
            for sp in targets(bw, k, master):
                value = bw.speeds[sp][0] if sp in bw.speeds else 0.0
                out[sp] = value % 360.0
    return out


def directions(bw, modes: SpindleModes, master: str | None) -> None:
    """Remember the ``.POS`` / ``.NEG`` of the block's M19s (L5843-L5880)."""
    for k, (m, _col) in enumerate(bw.m):
        named, direction = bw.m_target.get(k, (None, None))
        if m == 19 and direction is not None:
            spindles = [named] if named is not None else (list(bw.speeds) or ([master] if master else []))
            for sp in spindles:
                modes.direction[sp] = direction


def master_statement(interp, node, sub: str | None) -> None:
    """``#MASTER S2`` (seed 002 L5285-L5300): the spindle the channel's S, M3/M4/M5/M19 without a spindle,
    G95, G96 and G33 refer to; at M02/M30 and reset the channel takes its original master back (MASTERSPDL
    "temporary", L5141-L5150; [CONSTRUCTION] fagorcnc's machine file has no MASTERSPDL: temporary)."""
    from ..syntax.ast import Keyed, Name, Num

    st = interp.state
    first = node.args[0] if len(node.args) == 1 else None
    name = None
    if type(first) is Name:
        name = first.name
    elif type(first) is Keyed and type(first.value) is Num and float(first.value.value).is_integer():
        name = f"{first.name}{int(first.value.value)}"
    if name is None:
        raise InterpError("INT071", "#MASTER takes one spindle: #MASTER S2 (L5289)", node.col)
    spindle = st.spindle_config.word(name, node.col)   # by its name in the channel (INT246 out of it)
    if spindle in st.channel.parked:
        raise InterpError("INT213", f"#MASTER {name}: spindle {name} is parked (#PARK)", node.col)
    st.master = spindle
