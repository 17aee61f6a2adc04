"""V.C variables of the canned cycles (seed 002 L40298-L40443).

* ``V.C.A`` ... ``V.C.Z``: the call parameters of the last canned cycle, read and written from the
  program (L40310-L40330); a write changes the active cycle from its next hole on (the levels
  are recomputed with the G90/G91 of the definition, digest §1.2).  Values are as programmed.
* ``V.C.CALLP_A`` ... ``V.C.CALLP_Z``: 1 when the letter was programmed in the call (L40341-L40386).
* ``V.C.P_A`` ... ``V.C.P_Z`` and ``V.C.P_CALLP_A`` ...: the same for the last multiple machining
  block G160-G165 (L40391-L40443).
* ``V.G.CYCLETYPEON`` (the active cycle type) is read by the PLC and the interface only
  ("Variable de lecture depuis le programme PLC et l'Interface", L40300): a part program that
  reads it is refused (spec 09 §1.2 reads it as program-visible; the seed wins).  Its value, for
  the other readers: the G number, 0 when none ([UNVERIFIED] value table, ``choices``).

* ``V.PLC.TAPPING`` / ``V.PLC.RIGID`` (and ``...C1`` ... ``...C4`` per channel), the PLC marks "the channel
  executes a tapping canned cycle" / "a rigid tapping" (seed 002 L29844-L29857), are readable from the
  program, but each read "returns the execution value; its read stops block preparation": the block that
  reads waits until the motion before it has ended, and then the channel executes that block, not a
  tapping cycle (a canned cycle runs no program block inside it).  From a part program they therefore
  always read 0; the marks themselves are carried by the cycle's records
  (``record.plc_marks``, :func:`.drilling.plc_marks`) for the PLC-side readers.  Channels 2-4 do not
  exist offline (INT047).
* ``V.SP.SREVM05`` / ``V.MPA.SREVM05`` (with G84 the spindle stops before it reverses, the machine file's
  ``SREVM05``) are read by the PLC and the interface only (L21990-L21992): a program read is refused.

A letter never programmed reads 0.
"""

from __future__ import annotations

from ..expressions import InterpError
from . import choices
from .model import LETTERS


def register(plain_vars: dict, state) -> None:
    """Add the cycle variables to a :class:`~fagorcnc.interp.variables.Variables` table."""
    cs = state.cycles

    def write(letter: str, pattern: bool):
        def put(index: tuple, value: float) -> None:
            if pattern:
                cs.pattern_params[letter] = value
                return
            cs.params[letter] = value
            if cs.active is not None and letter != "G":
                cs.active.params = cs.params
                cs.active.plan = None   # rebuilt (and checked) at the next hole
        return put

    for letter in LETTERS:
        plain_vars[f"V.C.{letter}"] = (lambda i, x=letter: cs.params.get(x, 0.0), write(letter, False))
        plain_vars[f"V.C.CALLP_{letter}"] = (lambda i, x=letter: 1.0 if x in cs.called else 0.0, None)
        plain_vars[f"V.C.P_{letter}"] = (lambda i, x=letter: cs.pattern_params.get(x, 0.0), write(letter, True))
        plain_vars[f"V.C.P_CALLP_{letter}"] = (lambda i, x=letter: 1.0 if x in cs.pattern_called else 0.0, None)
    plain_vars["V.G.CYCLETYPEON"] = (_plc_only, None)
    # SREVM05 (G84 stops the spindle before reversing it) is the PLC's and the interface's (L21990-L21992)
    for group in ("SP", "MPA"):
        for suffix in ("", *(f".{sp}" for sp in state.machine.spindles)):
            plain_vars[f"V.{group}.SREVM05{suffix}"] = (_plc_only_of(f"V.{group}.SREVM05", "L21990-L21992"), None)
    for mark in PLC_MARKS:
        for suffix in ("", "C1"):
            plain_vars[f"V.PLC.{mark}{suffix}"] = (lambda i: 0.0, None)   # seed 002 L29844-L29857 (above)
        for n in (2, 3, 4):
            plain_vars[f"V.PLC.{mark}C{n}"] = (lambda i, n=n: _no_channel(n), None)


#: The PLC marks of the tapping cycles (seed 002 L29844 TAPPING, L29851 RIGID).
PLC_MARKS = ("TAPPING", "RIGID")


def _no_channel(n: int) -> float:
    raise InterpError("INT047", f"channel {n} does not exist (one channel offline)")


def cycle_type(state) -> float:
    """V.G.CYCLETYPEON for the PLC and the interface: the active cycle's G number, 0 when none."""
    active = state.cycles.active
    return float(active.code) if active is not None else float(choices.NO_CYCLE_TYPE)


def _plc_only_of(name: str, seed: str):
    def read(index: tuple) -> float:
        raise InterpError("INT044", f"{name} is read by the PLC and the interface, not by a part program "
                          f"(seed 002 {seed})")
    return read


_plc_only = _plc_only_of("V.G.CYCLETYPEON", "L40300")
