"""Line parser: one Fagor block (one line) -> AST node + diagnostics.

The grammar ``fagor.lark`` is compiled once per process (LALR, contextual
lexer, the AST built by :class:`~fagorcnc.syntax.builder.AstBuilder` during
the reductions) and its analysis is cached on disk by Lark.

Speed: most blocks of a CAM program are a plain run of literal words
(``N1230 G1 X12.5 Y-3.25 F800``).  Such a line is a single ``WORDS`` token
(after an optional ``N..:``) whose parse is known in advance, so
:meth:`LineParser.parse` recognises it with the grammar's own terminal
patterns and calls the same builder callbacks the LALR parser would — the
result is identical (``tests/test_fast_path.py`` checks this against the full
parser on random input).  Every other line goes through the LALR parser.
"""

from __future__ import annotations

import re
from functools import lru_cache
from importlib import resources
from pathlib import Path

from lark import Lark
from lark.exceptions import UnexpectedCharacters, UnexpectedEOF, UnexpectedInput, UnexpectedToken, VisitError

from ..diagnostics import Diagnostic, error
from .ast import Binary, Block, Call, ItemList, Param, ProgramHeader, SubroutineHeader, Unary, Var
from .builder import AstBuilder, split_plain, split_words
from .hints import hint
from .macros import macro_block

#: Levels of operators, functions, parameter and variable indexes and bracket lists one inside the
#: other in a block, at most.  The manual gives no limit; the interpreter evaluates expressions
#: recursively, so a deeper one (``P1 = 1+1+1...`` with 1000 terms, 1000 nested ``SIN[``) is
#: refused here, by the parser, with SYN040 rather than failing later (issue 30).  [CONSTRUCTION]
MAX_EXPRESSION_DEPTH = 250
_NESTING = (Binary, Unary, Call, Param, Var, ItemList)
_new = tuple.__new__   # a NamedTuple made from its field values, as split_words makes its words


def grammar_path() -> Path:
    """Location of ``fagor.lark``: packaged copy, else the repository's ``grammar/``."""
    packaged = resources.files("fagorcnc") / "grammar" / "fagor.lark"
    if packaged.is_file():
        return Path(str(packaged))
    return Path(__file__).resolve().parents[2] / "grammar" / "fagor.lark"


@lru_cache(maxsize=1)
def _compiled() -> tuple:
    builder = AstBuilder()
    text = grammar_path().read_text(encoding="utf-8")
    try:
        lark = Lark(text, parser="lalr", lexer="contextual", transformer=builder,
                    cache=True, maybe_placeholders=False)
    except OSError:  # read-only temp dir: compile without the cache
        lark = Lark(text, parser="lalr", lexer="contextual", transformer=builder,
                    maybe_placeholders=False)
    return lark, builder


# Tokens whose unexpected appearance has a specific explanation.
_SENTENCE_TOKENS = {"SHARP_KW", "CALL_KW", "RPT_KW", "AXIS_CALL_KW"}
_FLOW_TOKENS = {"IF", "ELSEIF", "ELSE", "ENDIF", "SWITCH", "CASE", "DEFAULT", "ENDSWITCH", "FOR",
                "ENDFOR", "WHILE", "ENDWHILE", "DO", "ENDDO", "BREAK", "CONTINUE", "GOTO"}
_OPERATOR_TOKENS = {"PLUS", "MINUS", "STAR", "MOD", "RELOP", "VBAR", "AMPERSAND",
                    "CIRCUMFLEX", "__ANON_0", "__ANON_1", "MORETHAN", "LESSTHAN"}
_TOKEN_WORDS = {"$END": "end of block", "LSQB": "'['", "RSQB": "']'", "COMMA": "','", "EQUAL": "'='",
                "COLON": "':'", "NUMBER": "a number", "NAME": "a keyword", "WORDS": "ISO words",
                "ADDRESS": "an ISO address", "PARAM": "a parameter", "VARNAME": "a V. variable",
                "STRING": "a \"string\"", "LABEL": "a [LABEL]", "BLOCKID": "a block number N..:"}


#: A subset of the lines the ``_fast`` pattern takes, tried first because it is some four times quicker
#: (no look-ahead, no atomic group) and its words split at the blanks (:func:`split_plain`): literal ISO
#: words from the first column, one blank apart (and perhaps one at the end), each a letter other than M
#: or P, a sign right after it and a number; no block id, no comment, no leading blank.  Such a line is
#: one ``WORDS`` run for ``_fast`` too, starting at column 1 with no ``N..:``: each number, a run of
#: digits and points followed by neither, is what the atomic group takes; nothing follows it but a
#: blank or the end (never ``=`` or ``:``); ``L`` is followed by its number, not a blank (no global
#: call); and there is no M, so ``structure_only`` gives it no items either.  ``tests/test_fast_path.py``
#: checks both ways.  The number is written so that a run of digits matches in one way only
#: (``[0-9]+(?:\.[0-9]*)?``, not ``[0-9]+\.?[0-9]*``, whose digits split between the two runs): with the
#: ambiguous form a line of integer words that fails at its end (``X001 Y002 ... ;``) backtracks through
#: every split of every word, exponentially in the number of words (eight 12-digit words: 78 s).
#: Every repetition and option is possessive (``?+``, ``++``, ``*+``: what it took is never given back), the
#: same language, since giving back could never help: a sign given back leaves a sign where a digit or a
#: point must stand, digits or a point a digit or a point where a blank or the end must, a word a blank
#: where the end must; each alternative starts with its own character.  The matcher keeps no place to go
#: back to, and reads a line some 1.5 times as fast (``tests/test_plain_runs.py`` checks the language
#: against the pattern without possessive quantifiers).
_PLAIN_WORD = r"[A-LN-OQ-Z][+-]?+(?:[0-9]++(?:\.[0-9]*+)?+|\.[0-9]++)"
_PLAIN = rf"{_PLAIN_WORD}(?: {_PLAIN_WORD})*+ ?+"
PLAIN_LINE = re.compile(_PLAIN).fullmatch
#: ``PLAIN_RUN(text, pos).end()``: where the run of lines from ``pos`` that :data:`PLAIN_LINE` takes ends, each
#: line ended by ``"\n"`` (a line holds no ``"\n"``, so each repetition is one whole line, taken exactly when
#: ``PLAIN_LINE`` takes it).  The first line it rejects ends the match: nothing follows the repetition, so
#: the lines before are never tried again, and that line fails in linear time as ``PLAIN_LINE`` does.
PLAIN_RUN = re.compile(rf"(?:{_PLAIN}\n)*+").match


_BRACKETED_WORD = re.compile(r'"(?:[^"\\\n]|\\.)*"|V\.[A-Za-z0-9_.]*|\b[A-Za-z][A-Za-z_]*')


def _keywords_in_capitals(text: str) -> tuple[str, list] | None:
    """The line with the words inside the brackets of its ``#`` sentence in capitals, and the
    ``(col, word)`` pairs changed; None when nothing would change.  Strings and V. variables
    (``V.P.my_var``) keep their case."""
    start = text.find("#")
    if start < 0 or ";" in text[:start]:
        return None
    out = list(text)
    words = []
    depth = 0
    i = text.find("[", start)
    while 0 <= i < len(text):
        ch = text[i]
        if ch == ";" and depth == 0:
            break
        if ch == "[":
            depth += 1
        elif ch == "]":
            depth = max(depth - 1, 0)
        elif depth and (ch == '"' or ch.isalpha()):
            m = _BRACKETED_WORD.match(text, i)
            if m is not None:
                word = m.group()
                if word[0] not in '"V' or (word[0] == "V" and not word.startswith("V.")):
                    if word != word.upper():
                        words.append((i + 1, word))
                        out[i:m.end()] = word.upper()
                i = m.end()
                continue
        i += 1
    return ("".join(out), words) if words else None


def _hinted(d: Diagnostic) -> Diagnostic:
    """``d`` with a machinist's hint (letter O for zero, another control's code) when one applies."""
    h = hint(d.source, d.col)
    return Diagnostic(d.file, d.line, d.col, d.code, d.severity, f"{d.message} ({h})", d.source) if h else d


class LineParser:
    """Parses single lines; reusable, not thread-safe (one per thread/process)."""

    def __init__(self) -> None:
        self._lark, self._builder = _compiled()
        words = self._lark.get_terminal("WORDS").pattern.to_regexp()
        blockid = self._lark.get_terminal("BLOCKID").pattern.to_regexp()
        # [N..:] WORDS [; comment] -- exactly the token sequence the LALR
        # parser would see for the commonest CAM block.
        # "L 100" / "N10 L 100" are global calls (GLOBAL_CALL outranks WORDS there).
        self._fast = re.compile(
            rf"[ \t]*(?:({blockid})[ \t]*)?(?!(?:N[0-9]+[ \t]*)?L[ \t])({words})?(?:;.*)?").fullmatch

    def parse(self, text: str, line: int, file: str = "<string>", structure_only: bool = False) -> tuple:
        """Parse one line.

        Returns ``(node, diagnostics)``; ``node`` is a :class:`Block`,
        :class:`ProgramHeader`, :class:`SubroutineHeader`, or ``None`` for an
        empty line, a comment-only line or a line with a syntax error.
        ``structure_only``: for a check of the whole file's syntax and structure, a plain run of
        literal words without an M (which cannot end a subroutine) gets no items (same diagnostics).
        """
        if PLAIN_LINE(text) is not None:   # the commonest CAM line: what _fast makes of it, sooner
            items = () if structure_only else split_plain(text)
            return _new(Block, (line, text, False, None, None, items)), ()
        return self._parse_fast(text, line, file, structure_only)

    def _parse_fast(self, text: str, line: int, file: str, structure_only: bool) -> tuple:
        """:meth:`parse` by the ``_fast`` pattern, else by the LALR parser."""
        m = self._fast(text)
        if m is not None:
            bid, words = m.group(1), m.group(2)
            if words is None and bid is None:
                return None, ()
            if structure_only and (not words or "M" not in words):
                items = ()
            else:
                items = tuple(split_words(words, m.start(2) + 1)) if words else ()
            number = None
            if bid is not None:
                digits = bid[1:].rstrip(" \t:").lstrip("0") or "0"
                if len(digits) > 10 or int(digits) > 4294967295:
                    return self.parse_full(text, line, file)
                number = int(digits)
            return _new(Block, (line, text, False, number, None, items)), ()   # Block(...) without its __new__
        return self.parse_full(text, line, file)

    def parse_full(self, text: str, line: int, file: str = "<string>") -> tuple:
        """Parse one line with the LALR parser (no fast path)."""
        stripped = text.strip()
        if not stripped or stripped[0] == ";":
            return None, ()
        builder = self._builder
        builder.problems = []
        try:
            result = self._lark.parse(text)
        except UnexpectedInput as exc:
            macro = self._macro_block(text, line)
            if macro is not None:
                return macro
            capitals = _keywords_in_capitals(text) if "#" in text and "[" in text else None
            if capitals is None:
                return None, (_hinted(self._syntax_error(exc, text, line, file)),)
            # "#CS ON [1] [Mode 1, ...]" (Autodesk): read in capitals, and said (the [compat] construct keyword_case)
            fixed, words = capitals
            builder.problems = []
            try:
                result = self._lark.parse(fixed)
            except (UnexpectedInput, VisitError):
                return None, (self._syntax_error(exc, text, line, file),)
            shown = ", ".join(f"'{w}' as {w.upper()}" for _c, w in words)
            builder.problems.insert(0, (words[0][0], "CAM007", f"{shown}: the manual writes the keywords of a # "
                                        "sentence in capitals; read in capitals"))
        except VisitError as exc:  # a builder bug must not escape as a traceback
            return None, (error(file, line, 1, "SYN002", f"cannot read this block ({exc.orig_exc})", text),)
        diags = tuple(Diagnostic(file, line, col, code, "warning" if code[:3] == "CAM" else "error", msg, text)
                      for col, code, msg in builder.problems)
        if len(text) > MAX_EXPRESSION_DEPTH // 2:   # each level takes at least a character or two
            col = _too_deep(result)
            if col is not None:
                return None, (*diags, error(file, line, col, "SYN040", f"this expression is nested more than "
                                            f"{MAX_EXPRESSION_DEPTH} levels deep (operators, functions, indexes, "
                                            "bracket lists): split it over several parameters", text))
        if any(d.is_error for d in diags) and (macro := self._macro_block(text, line)) is not None:
            return macro   # X["NAME"]: a string as a value
        kind = result[0]
        if kind == "block":
            _, skip, number, label, items = result
            if not items and not skip and number is None and label is None:
                return None, diags  # comment-only line
            return Block(line, text, skip, number, label, items), diags
        if kind == "program":
            return ProgramHeader(result[1], line, text), diags
        return SubroutineHeader(result[1], line, text), diags

    @staticmethod
    def _macro_block(text: str, line: int) -> tuple | None:
        """A line that does not read as a block but uses macros ("NAME" where its words are):
        a block of one :class:`~fagorcnc.syntax.macros.MacroUse`, read when it runs, once its
        macros are defined (seed 002 L16115)."""
        macro = macro_block(text) if '"' in text else None
        if macro is None:
            return None
        skip, number, label, use = macro
        return Block(line, text, skip, number, label, (use,)), ()

    # ------------------------------------------------------------------
    def _syntax_error(self, exc: UnexpectedInput, text: str, line: int, file: str) -> Diagnostic:
        col = getattr(exc, "column", None) or 1
        if isinstance(exc, UnexpectedCharacters):
            pos = exc.pos_in_stream
            ch = text[pos] if 0 <= pos < len(text) else ""
            col = pos + 1
            if ch == "(":
                return error(file, line, col, "SYN004",
                             "comment '(' is not closed with ')' on this line", text)
            if ch.islower():
                return error(file, line, col, "SYN005",
                             f"'{ch}': addresses and keywords are written in capitals", text)
            if ch == "#":
                return error(file, line, col, "SYN002",
                             "'#' must be followed by a sentence name in capitals, e.g. #HSC", text)
            return error(file, line, col, "SYN001", f"unexpected character {ch!r}", text)
        if isinstance(exc, UnexpectedEOF):
            return error(file, line, len(text.rstrip()) + 1, "SYN003",
                         "the block ends before the instruction is complete", text)
        assert isinstance(exc, UnexpectedToken)
        tok = exc.token
        ttype = tok.type
        col = tok.column if isinstance(tok.column, int) else len(text.rstrip()) + 1
        if ttype == "$END":
            return error(file, line, len(text.rstrip()) + 1, "SYN003",
                         "the block ends before the instruction is complete", text)
        if ttype in _SENTENCE_TOKENS:
            return error(file, line, col, "SYN007",
                         f"{tok.value.split()[0]}: only one # sentence is allowed in a block", text)
        if ttype in _FLOW_TOKENS:
            return error(file, line, col, "SYN008",
                         f"{tok.value}: a $ instruction must be alone in its block "
                         "(only $IF ... $GOTO may share a line)", text)
        if ttype == "BLOCKID":
            return error(file, line, col, "SYN009",
                         f"'{tok.value.strip()}' (jump target) must be at the start of the block", text)
        if ttype == "SKIP":
            return error(file, line, col, "SYN009",
                         "'/' (block skip) must be the first character of the block; "
                         "for a division write the value in brackets, e.g. X[P1/2]", text)
        if ttype == "COLON" and re.search(r"N[ \t]*[0-9]+[ \t]*$", text[:col - 1]):
            return error(file, line, text[:col - 1].rstrip().rindex("N") + 1, "SYN009",
                         "'N..:' (jump target) must be at the start of the block", text)
        first = tok.value[:1]
        if ttype not in _TOKEN_WORDS and first.islower():
            return error(file, line, col, "SYN005",
                         f"'{first}': addresses and keywords are written in capitals", text)
        if first == "$" and ttype not in _FLOW_TOKENS and ttype != "HEXNUM":
            name = re.match(r"\$[A-Za-z0-9_]*", tok.value)[0]
            return error(file, line, col, "SYN022",
                         f"unknown $ instruction '{name}' (see the list in seed 002 ch. 21.2)", text)
        if first == '"' and tok.value.count('"') == 1:
            return error(file, line, col, "SYN021", 'text string "... is not closed with " on this line', text)
        if ttype in _OPERATOR_TOKENS or (ttype not in _TOKEN_WORDS and first in "*/+-&|^<>=!"):
            return error(file, line, col, "SYN006",
                         f"unexpected '{tok.value}': an ISO word value with an operator must be "
                         "written in brackets, e.g. X[P1*2]", text)
        shown = _TOKEN_WORDS.get(ttype, repr(tok.value))
        return error(file, line, col, "SYN002", f"unexpected {shown} '{tok.value}'"
                     if shown[0] != "'" else f"unexpected {shown}", text)


def _too_deep(tree) -> int | None:
    """The column of an expression nested deeper than :data:`MAX_EXPRESSION_DEPTH`, or None
    (walked with an explicit stack: no recursion however deep the tree)."""
    stack = [(tree, 0)]
    while stack:
        node, depth = stack.pop()
        if isinstance(node, _NESTING):
            depth += 1
            if depth > MAX_EXPRESSION_DEPTH:
                return max(int(getattr(node, "col", 1) or 1), 1)
        stack.extend((child, depth) for child in node if isinstance(child, tuple))
    return None
