"""Macros (seed 002 ch. 21.1.16, L16113-L16202): ``#DEF "NAME"="block text"`` and their use.

A macro is named block text.  ``#DEF "START"="SP1 M3 M41"`` stores it; a later block that
writes ``"START"`` is executed as if the text stood there: ``P1=800 "START" F450`` is
``S800 M3 M41 F450`` (L16115-L16118, L16160-L16166).  The table is filled while the program
runs (a ``#DEF`` inside a ``$IF`` may or may not define), so a block that uses a macro is
read in two steps:

* here, at parse time, the line is recognised as a *macro block* (a ``"string"`` standing
  where the block's words are, before any ``#`` sentence) and kept as a :class:`MacroUse`
  with its text; its block number, label and block-skip mark are read as usual so jumps
  reach it;
* when the block executes, :func:`expand` replaces each ``"NAME"`` by its text (macros in a
  macro's text are written ``\\"NAME\\"``, L16182-L16202) and the interpreter parses the
  expanded line like any other.

Rules of the text (L16146-L16181): names of 1 to 30 letters and digits, texts of at most 140
characters, at most 50 macros; an arithmetic operation must be complete inside one macro
(``"56+"`` then ``"12"`` is wrong, ``"SIN["`` then ``"45]"`` too), a complete expression may be
an operand: ``"MACRO2"="SIN [\\"MACRO1\\"]"`` with ``"MACRO1"="P1*3"``.  A macro used inside
brackets is expanded as a bracketed sub-expression, so ``P1*3`` stays one operand there (the
digest's recommendation, spec 06 §4.16).
"""

from __future__ import annotations

import re
from typing import NamedTuple

#: The table holds at most this many macros (seed 002 L16127).
MAX_MACROS = 50
#: A macro name: up to 30 letters and digits (L16147).
MAX_NAME = 30
#: A macro text: up to 140 characters (L16151).
MAX_TEXT = 140
#: Macros inside macros are expanded to this depth at most: deeper is a macro that names itself.
MAX_DEPTH = 20

_NAME = re.compile(r"[A-Za-z0-9]{1,30}")
#: ``[/] [N10:] [N10] [[LABEL]]`` before the body of a block (as in the grammar's block rule).
_PREFIX = re.compile(r"[ \t]*(/)?[ \t]*(?:N[ \t]*([0-9]+)[ \t]*:)?[ \t]*(?:N[0-9]+(?![0-9:])[ \t]*)?(\[[^\]\n]*\])?")
_OPERATORS = "+-*/^&|=<>!"


class MacroUse(NamedTuple):
    """A block that uses macros: the whole line, expanded when it executes (seed 002 L16115);
    ``col`` is where its body starts."""

    text: str
    col: int


class MacroError(ValueError):
    """A macro that cannot be defined or expanded; ``col`` is 1-based in the block."""

    def __init__(self, code: str, message: str, col: int = 1) -> None:
        super().__init__(message)
        self.code, self.message, self.col = code, message, col


def _code_spans(text: str):
    """``(start, end)`` spans of ``text`` outside comments: ``( ... )`` and ``; ...``."""
    i, start, n = 0, 0, len(text)
    in_string = False
    while i < n:
        ch = text[i]
        if ch == '"':
            in_string = not in_string
        elif not in_string and ch == "(":
            yield start, i
            close = text.find(")", i)
            if close < 0:
                return
            i = start = close + 1
            continue
        elif not in_string and ch == ";":
            yield start, i
            return
        i += 1
    yield start, n


def macro_block(text: str) -> tuple[bool, int | None, str | None, MacroUse] | None:
    """``(skip, number, label, use)`` when ``text`` is a block that uses macros, else ``None``.

    A block uses macros when a ``"NAME"`` (a valid macro name in quotes) stands in its body
    before any ``#`` sentence: a ``#MSG "..."`` or ``#DEF "..."`` is a sentence's string.  A
    line whose quotes do not pair up into names is not a macro block (its syntax error is
    reported as it is)."""
    prefix = _PREFIX.match(text)
    body_start = prefix.end()
    found = False
    for start, end in _code_spans(text):
        part = text[max(start, body_start):end]
        hash_at = part.find("#")
        if hash_at >= 0:
            part = part[:hash_at]
        if part.count('"') % 2:
            return None
        names = part.split('"')[1::2]
        if any(not _NAME.fullmatch(n) for n in names):
            return None
        found = found or bool(names)
        if hash_at >= 0:
            break
    if not found:
        return None
    skip, number, label = prefix.group(1), prefix.group(2), prefix.group(3)
    return (skip is not None, int(number) if number is not None else None,
            label[1:-1].strip() if label else None, MacroUse(text, body_start + 1))


def check_definition(name: str, body: str, col: int) -> None:
    """A ``#DEF "name"="body"`` the manual allows, else :class:`MacroError` (L16146-L16181)."""
    if not _NAME.fullmatch(name):
        raise MacroError("MAC003", f"macro name '{name}': 1 to {MAX_NAME} letters and digits (L16147)", col)
    if len(body) > MAX_TEXT:
        raise MacroError("MAC004", f"the text of macro '{name}' has {len(body)} characters; at most {MAX_TEXT} "
                         "(L16151)", col)
    bare = re.sub(r'"[^"]*"', "0", body).strip()   # the macros it names are complete operands
    depth = 0
    for ch in bare:
        depth += (ch == "[") - (ch == "]")
        if depth < 0:
            break
    ends = bare[-1:] in _OPERATORS or bare[:1] in "*/^&|=<>!"
    if depth != 0 or ends:
        raise MacroError("MAC005", f"macro '{name}' = \"{body}\": an arithmetic operation must be complete inside "
                         "one macro (L16173: \"56+\" or \"SIN[\" are not macros)", col)


def expand(text: str, table: dict[str, str], col: int = 1, depth: int = 0) -> str:
    """``text`` with every ``"NAME"`` replaced by the text of macro NAME of ``table``; inside
    brackets the text is bracketed, so a macro is one operand of an expression."""
    if depth > MAX_DEPTH:
        raise MacroError("MAC007", f"macros nested more than {MAX_DEPTH} deep: a macro that names itself?", col)
    out: list[str] = []
    last = 0
    for start, end in _code_spans(text):
        i = start
        while i < end:
            q = text.find('"', i, end)
            if q < 0:
                break
            close = text.find('"', q + 1, end)
            if close < 0:
                raise MacroError("SYN021", 'text string "... is not closed with " on this line', col + q)
            name = text[q + 1:close]
            if name not in table:
                raise MacroError("MAC001", f"macro \"{name}\" is not defined (#DEF \"{name}\"=\"...\" first, "
                                 "L16113)", col + q)
            inner = expand(table[name], table, col + q, depth + 1)
            brackets = text.count("[", 0, q) - text.count("]", 0, q)
            out.append(text[last:q])
            out.append(f"[{inner}]" if brackets > 0 else inner)
            last = i = close + 1
    out.append(text[last:])
    return "".join(out)
