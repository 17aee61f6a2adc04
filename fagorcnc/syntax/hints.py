"""Hints for a machinist, appended to an error: the letter O written for a zero, and the codes of
other controls (Fanuc, LinuxCNC/RS274NGC) with what the 8060/8065 uses instead.

Text only (no state): the parser and the interpreter both call :func:`hint` with the block's text
and the error's column.
"""

from __future__ import annotations

import re

_FOREIGN: list[tuple[re.Pattern, str]] = [(re.compile(p), h) for p, h in (
    (r"G0*20(?![0-9.])", "G20 is inch programming on Fanuc/LinuxCNC; on the 8065 inches are G70 (G20 defines a "
                         "plane by two directions)"),
    (r"G0*21(?![0-9.])", "G21 is millimetre programming on Fanuc/LinuxCNC; on the 8065 it is G71"),
    (r"G0*43(?![0-9])", "G43 H.. is tool length compensation on Fanuc/LinuxCNC; on the 8065 the tool offset D "
                        "applies the length (T.. D..)"),
    (r"G0*49(?![0-9])", "G49 cancels tool length compensation on Fanuc/LinuxCNC; on the 8065 it is D0"),
    (r"G0*28(?![0-9])", "G28 is the return to the reference point on Fanuc/LinuxCNC; on the 8065 use G74 (home "
                        "search) or a move in machine coordinates: #MCS G0 Z0"),
    (r"G54\.1", "G54.1 P.. is an extended work offset on Fanuc/LinuxCNC; on the 8065 it is G159=n"),
    (r"G64(?![0-9])", "G64 P.. is path blending on LinuxCNC; on the 8065 use G05 with #ROUNDPAR, or #HSC ON"),
    (r"G0*52(?![0-9])", "G52 is a local offset on Fanuc/LinuxCNC; on the 8065 it is G158"),
    (r"G68(?![0-9])", "G68 is a rotation on Fanuc/LinuxCNC; on the 8065 it is G73"),
    (r"G69(?![0-9])", "G69 cancels the rotation on Fanuc/LinuxCNC; on the 8065 it is G73 with no angle"),
    (r"G1[56](?![0-9])", "G15/G16 are polar coordinates on Fanuc; on the 8065 program R and Q (G30 sets the pole)"),
    (r"G10(?![0-9])", "G10 L.. writes offsets on Fanuc/LinuxCNC; on the 8065 G10 cancels mirror images: write "
                      "the table with V.A.ORGT[n].X = .."),
    (r"G9[01]\.1", "G90.1/G91.1 set the arc centre mode on LinuxCNC; on the 8065 it is G261/G262"),
    (r"G0*4[ \t]*P", "G4 P.. is a dwell in Fanuc/LinuxCNC form; on the 8065 the time is K in seconds: G04 K0.5"),
    (r"M98(?![0-9])", "M98 P.. calls a subprogram on Fanuc; on the 8065 use #CALL name or LL name"),
    (r"M99(?![0-9])", "M99 ends a subprogram on Fanuc; on the 8065 it is M17 or M29"),
)]
# a word with the letter O written for a zero: GO1, X1O, X-O5
_LETTER_O = re.compile(r"(?<![A-Z#.])([A-NQ-Z])([ \t]*[+-]?[ \t]*[0-9.]*)O([0-9.]*)(?![A-Z])")
#: codes that are also 8060/8065 functions (with another meaning): hinted only at the error's own word
_ALSO_HERE = ("G0*20", "G10")


def hint(text: str, col: int) -> str:
    """A hint for the error at ``col`` (1-based) of ``text``, or ``""``: the letter O written for
    a zero (``GO1`` -> G01, ``X1O`` -> X10), a Fanuc/LinuxCNC code with its 8065 equivalent."""
    code = text.split(";", 1)[0]
    for m in _LETTER_O.finditer(code):
        if m.start() < col <= m.end():
            digits = re.sub(r"[ \t]", "", m.group(2))
            return f"letter O where a zero is meant? did you mean {m.group(1)}{digits}0{m.group(3)}"
    at = text[col - 1:] if 0 < col <= len(text) else ""
    for pattern, h in _FOREIGN:
        if pattern.match(at):
            lead = "if this is Fanuc/LinuxCNC code" if pattern.pattern.startswith(_ALSO_HERE) else \
                "this is a Fanuc/LinuxCNC code"
            return f"{lead}: {h}"
    for pattern, h in _FOREIGN:   # the error may be at a word the foreign code made meaningless (G64 P0.01)
        if not pattern.pattern.startswith(_ALSO_HERE) and _word_search(pattern, code):
            return f"this is a Fanuc/LinuxCNC code: {h}"
    return ""


def _word_search(pattern: re.Pattern, text: str) -> bool:
    """Whether ``pattern`` matches at the start of a word of ``text`` (not inside G164 or X20.1)."""
    return any(pattern.match(text, i) and (i == 0 or not (text[i - 1].isalnum() or text[i - 1] == "."))
               for i in range(len(text)) if text[i] in "GM")
