"""Programs the card must not run: a transformation fagorcnc did not compute for this machine.

The card receives machine-axis moves and has no kinematics of its own to apply (seed 000:
commands 1002 and 1003 take machine positions).  fagorcnc computes the transformations of
chapters 14-17 into machine joints (:mod:`fagorcnc.kinematics`), which the card can run like
any move; two cases remain that a real run refuses before anything is sent, with CFG030 at
the sentence's line:

* a sentence the interpreter still reports with warning INT078 ("the path ignores it");
* ``#KIN``/``#RTCP``/``#TLC``... on a machine file with no rotary axes and no ``[[kinematics]]``
  (note KIN024): offline fagorcnc runs them as the identity, which on a real machine is a guess
  about kinematics the machine file does not describe.
"""

from __future__ import annotations

import re
from collections.abc import Iterable

from ...diagnostics import Diagnostic

#: Sentences whose transformation changes where the axes must go (seed 002 ch. 14-17): kinematics and tool
#: centre point (#KIN, #RTCP, #TLC), inclined planes (#CS, #ACS), cylinder and face machining (#CYL, #FACE),
#: the angular and tangential axes (#ANGAX, #TANGCTRL), the C axis (#CAX).
REFUSED = frozenset({"KIN", "RTCP", "TLC", "CS", "ACS", "CYL", "FACE", "ANGAX", "TANGCTRL", "CAX"})
_SENTENCE = re.compile(r"#([A-Z]+)\b")


def refused_transformations(diagnostics: Iterable[Diagnostic], backend: str = "interpcnc") -> list[Diagnostic]:
    """CFG030 errors for the INT078 warnings of :data:`REFUSED` sentences (the sentence read from the message, or
    from the source at the column) and for the KIN024 notes."""
    out = []
    for d in diagnostics:
        if d.code == "KIN024":   # a kinematics statement the machine file gives no kinematics for
            m = _SENTENCE.match(d.message)
            name = m.group(1) if m else "KIN"
            out.append(Diagnostic(d.file, d.line, d.col, "CFG030", "error",
                                  f"#{name}: the machine file describes no rotary axes and no [[kinematics]], so "
                                  f"fagorcnc ran it as the identity (KIN024); on a real machine that is a guess, "
                                  f"nothing was sent - describe the machine's kinematics in the machine file",
                                  d.source))
            continue
        if d.code != "INT078":
            continue
        m = _SENTENCE.match(d.message) or _SENTENCE.match(d.source[max(d.col - 1, 0):].lstrip())
        if m is None or m.group(1) not in REFUSED:
            continue
        out.append(Diagnostic(d.file, d.line, d.col, "CFG030", "error",
                              f"#{m.group(1)} is active: the {backend} back-end sends machine-axis moves and "
                              f"fagorcnc does not compute this transformation (INT078), so the tool would not "
                              f"follow the programmed path; nothing was sent - run it on a control that computes it",
                              d.source))
    return out
