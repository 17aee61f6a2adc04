"""Laser functions (seed 002 ch. 19, L13670-L13965): synchronised switching ``#SWTOUT`` and the
PWM output ``#PWMOUT`` -- their state and variables.

Offline there is no output to drive (the PWM "is not activated in the simulation modes",
L13915); what a program can observe is kept exactly: whether each function is on, the
switching offsets TON/TOF (ms) and PON/POF (mm or inch) and the PWM frequency and duty cycle,
read and written through ``V.G.TON`` ... ``V.G.PWMDUTY``.  Both statements and every one of
these variables stop block preparation (L13844, L13795-L13799, L13942): the motion before them
ends there, as for ``#FLUSH``.

Choices where the manual leaves room (spec 06 §2.2):

* a second ``#PWMOUT ON`` while the PWM is on is an error only "from a channel" other than the
  one that activated it (L13845-L13847); offline there is one channel, so it changes the values
  at once ("modifications ... take effect without waiting", L13849-L13852);
* ``#PWMOUT OFF`` reports ``V.G.PWMON = 0``; the last programmed FREQ and DUTY are kept for the
  next ``#PWMOUT ON`` (L13869-L13879: "the last programmed value");
* M30 (and a reset) switch the synchronised switching off (L13767-L13769) and keep its offsets
  (L13727-L13729); what M30 does to the PWM depends on the machine parameter PWMCANCEL, which
  nothing can observe after M30 in an offline run.
"""

from __future__ import annotations

from dataclasses import dataclass

from ..syntax.ast import ItemList, Keyed, Name, Setting
from .expressions import InterpError
from .iso import INCH

#: The PWM frequency range, Hz (L13869) and duty-cycle range, % (L13875).
FREQ_RANGE = (2.0, 5000.0)
DUTY_RANGE = (0.1, 100.0)

_SWT_OFFSETS = ("TON", "TOF", "PON", "POF")
_PWM_NAMES = {"FREQ": "FREQ", "F": "FREQ", "DUTY": "DUTY", "D": "DUTY", "PWMBTIME": "PWMBTIME",
              "PWMBEND": "PWMBEND"}


@dataclass
class Laser:
    """The channel's laser state; lengths in mm, times in ms."""

    switching: bool = False                  # #SWTOUT ON
    ton: float = 0.0                         # L13727: 0 at power-on, kept after an error, reset or M30
    tof: float = 0.0
    pon: float = 0.0
    pof: float = 0.0
    pwm: bool = False                        # #PWMOUT ON
    freq: float = 0.0                        # L13871: the last value, else 0
    duty: float = 50.0                       # L13877: the last value, else 50
    burst_ms: float | None = None            # PWMBTIME: the PWM for this long only (L13904)
    burst_end: int = 0                       # PWMBEND: the level after the burst (L13907)

    def end_of_program(self) -> None:
        """M30, M02 or a reset: switching off, the offsets kept (L13767-L13769, L13727)."""
        self.switching = False

    def variables(self, state) -> dict:
        """``V.G.TON`` ... ``V.G.PWMDUTY`` (L13781-L13810, L13938-L13965) for the variable table:
        name -> (getter, setter or None); every access stops preparation."""

        def unit() -> float:
            return INCH if state.modes["units"] == 70 else 1.0

        def reads(getter):
            def get(index):
                state.sync = True
                return getter()
            return get

        def writes(field: str, length: bool):
            def put(index, value):
                state.sync = True
                setattr(self, field, value * unit() if length else value)
            return put

        table = {}
        for name in _SWT_OFFSETS:
            field, length = name.lower(), name.startswith("P")
            table[f"V.G.{name}"] = (reads(lambda f=field, ln=length: getattr(self, f) / (unit() if ln else 1.0)),
                                    writes(field, length))
        table["V.G.PWMON"] = (reads(lambda: 1.0 if self.pwm else 0.0), None)
        table["V.G.PWMFREQ"] = (reads(lambda: self.freq), None)
        table["V.G.PWMDUTY"] = (reads(lambda: self.duty), None)
        return table


def _arguments(interp, node, what: str, names: dict[str, str]) -> dict[str, tuple[float, int]]:
    """``#X ON [A=1, B 2 ...]``: {name: (value, col)}; blanks or commas between them (L13764)."""
    first = node.args[0]
    if len(node.args) > 1:
        raise InterpError("INT117", f"#{what} ON takes its values in one bracket: #{what} ON [...]", node.col)
    if type(first) is Name:
        return {}
    value = first.value
    seqs = value.items if type(value) is ItemList else ((value,),)
    found: dict[str, tuple[float, int]] = {}
    for seq in seqs:
        for item in seq:
            kind = type(item)
            if kind not in (Keyed, Setting) or item.value is None or item.name not in names:
                shown = getattr(item, "name", None) or "this value"
                raise InterpError("INT117", f"#{what} ON: '{shown}' is not one of {', '.join(sorted(names))}",
                                  getattr(item, "col", node.col))
            key = names[item.name]
            if key in found:
                raise InterpError("INT117", f"#{what} ON: {key} is written twice", item.col)
            found[key] = (interp.evaluator.value(item.value), item.col)
    return found


def swtout_statement(interp, node, sub: str | None) -> None:
    """``#SWTOUT ON [<TON=ms>, <TOF=ms>, <PON=len>, <POF=len>]`` / ``#SWTOUT OFF`` (L13718-L13774)."""
    laser, st = interp.laser, interp.state
    st.sync = True
    if sub == "OFF":
        if len(node.args) != 1 or type(node.args[0]) is not Name:
            raise InterpError("INT117", "#SWTOUT OFF takes nothing more (L13772)", node.col)
        laser.switching = False
        return
    unit = INCH if st.modes["units"] == 70 else 1.0
    for name, (value, _col) in _arguments(interp, node, "SWTOUT", {n: n for n in _SWT_OFFSETS}).items():
        # L13785: the statement's values become the variables'; without values, the variables' apply
        setattr(laser, name.lower(), value * unit if name.startswith("P") else value)
    laser.switching = True


def pwmout_statement(interp, node, sub: str | None) -> None:
    """``#PWMOUT ON [<FREQ/F Hz>, <DUTY/D %>, <PWMBTIME ms>, <PWMBEND 0|1>]`` / ``#PWMOUT OFF``
    (L13844-L13930)."""
    laser = interp.laser
    interp.state.sync = True   # L13844: it stops block preparation
    if sub == "OFF":
        if len(node.args) != 1 or type(node.args[0]) is not Name:
            raise InterpError("INT117", "#PWMOUT OFF takes nothing more (L13929)", node.col)
        laser.pwm = False
        return
    args = _arguments(interp, node, "PWMOUT", _PWM_NAMES)
    checks = {"FREQ": (FREQ_RANGE, "Hz", "L13869"), "DUTY": (DUTY_RANGE, "%", "L13875")}
    for key, ((lo, hi), unit, line) in checks.items():
        if key in args and not lo <= args[key][0] <= hi:
            raise InterpError("INT117", f"#PWMOUT ON: {key} {args[key][0]:g} {unit} is outside {lo:g}-{hi:g} {unit} "
                              f"({line})", args[key][1])
    if "PWMBTIME" in args and args["PWMBTIME"][0] <= 0:
        raise InterpError("INT117", f"#PWMOUT ON: PWMBTIME {args['PWMBTIME'][0]:g} ms must be a positive time "
                          "(L13904)", args["PWMBTIME"][1])
    if "PWMBEND" in args and args["PWMBEND"][0] not in (0.0, 1.0):
        raise InterpError("INT117", f"#PWMOUT ON: PWMBEND is 0 or 1, not {args['PWMBEND'][0]:g} (L13907)",
                          args["PWMBEND"][1])
    laser.freq = args["FREQ"][0] if "FREQ" in args else laser.freq
    laser.duty = args["DUTY"][0] if "DUTY" in args else laser.duty
    laser.burst_ms = args["PWMBTIME"][0] if "PWMBTIME" in args else None
    laser.burst_end = int(args["PWMBEND"][0]) if "PWMBEND" in args else 0
    laser.pwm = True
