"""Builds AST nodes while Lark's LALR parser reduces (no intermediate tree).

Each method is the callback of the grammar rule (or alias) of the same name in
``grammar/fagor.lark``.  Problems that the grammar cannot express (a label of
15 characters, ``SIN`` with two arguments ...) are collected in
:attr:`AstBuilder.problems` as ``(col, code, message)`` for the caller to turn
into diagnostics; parsing goes on.
"""

from __future__ import annotations

import re
from collections.abc import Iterable

from lark import Token, Transformer

from .ast import (
    FUNCTION_ARITY,
    Assignment,
    Binary,
    Call,
    Definition,
    Direction,
    Flow,
    Goto,
    ItemList,
    Keyed,
    Name,
    Num,
    Param,
    PlainWords,
    Repeat,
    RepeatRef,
    Sentence,
    Setting,
    Str,
    SubroutineCall,
    Unary,
    Var,
    Word,
)
from .sentences import check_sentence

_EXPR_TYPES = (Num, Param, Var, Unary, Binary, Call)

# One literal ISO word inside a WORDS run (the run's own pattern guarantees
# the shape; this only splits it): letter, sign, number.
_WORD = re.compile(r"([A-OQ-Z])[ \t]*([+-]?)[ \t]*([0-9]+\.?[0-9]*|\.[0-9]+)")
_NAME14 = re.compile(r"[A-Za-z0-9]{1,14}")
_CHANNEL = re.compile(r"V\.\[([0-9]+)\]\.")


#: a program name as CAM posts write them: letters, digits, "_", ".", "-" and blanks (CAM004)
_POST_NAME = re.compile(r"[A-Za-z0-9_][A-Za-z0-9_.\- ]*")


def valid_name(name: str) -> bool:
    """Label, program and subroutine names: 1-14 letters and digits (seed 002 L843, L1048)."""
    return _NAME14.fullmatch(name) is not None


#: One float object per number text met lately in :func:`split_words` (``"-1.5"`` -> -1.5): CAM programs
#: repeat their coordinates (a raster's X values every row, its Y along a row) and the records keep the words'
#: values, so sharing them saves a float object (24 bytes) per repeated word.  Bounded (512 numbers, some
#: 50 kB: emptied before a block whose words could fill it; a single block longer than 1 024 characters may
#: hold more, its own words at most).
_NUMBERS: dict[str, float] = {}
_NUMBERS_MAX = 512


def split_words(text: str, col: int, _new=tuple.__new__, _finditer=_WORD.finditer, _known=_NUMBERS.get,
                _put=_NUMBERS.setdefault) -> list:
    """Split a WORDS run starting at column ``col`` into :class:`Word` nodes.

    Hot path (one call per CAM block): builds the tuples directly, the values of the numbers met
    lately from :data:`_NUMBERS` by their signed text (a ``0.0`` found there is looked for again:
    ``or``; a new one is put there by ``setdefault``, no Python call).  :data:`_NUMBERS` is emptied
    before the run when its words could fill it beyond :data:`_NUMBERS_MAX` (a word takes two
    characters at least).
    """
    if len(_NUMBERS) + len(text) // 2 >= _NUMBERS_MAX:
        _NUMBERS.clear()
    return [_new(Word, (m[1], _known(key := m[2] + m[3]) or _put(key, float(key)), col + m.start(), None))
            for m in _finditer(text)]


def split_plain(text: str) -> PlainWords:
    """:func:`split_words` (as a :class:`PlainWords` tuple: a block's items) of a run from column 1 whose
    words are each a letter, a sign right after it and a number, one blank apart (``parser.PLAIN_LINE``'s
    lines): the same :class:`Word` nodes, split at the blanks (no regular expression)."""
    return split_plain_lines((text,))[0]


def split_plain_lines(lines: Iterable[str], _new=tuple.__new__, _word=Word, _plain=PlainWords) -> list:
    """:func:`split_plain` of each of ``lines``, in one call (a run of plain lines).

    Hot path (some six words a plain CAM block): a new float per word, not one from :data:`_NUMBERS` (a
    dictionary look-up and insertion cost more than the float; ``simulate()`` keeps the coordinates of
    plain moves as doubles in columns, so sharing their floats saves little)."""
    out = []
    for text in lines:
        words = []
        col = 1
        for w in text.split():   # PLAIN_LINE's blanks are single spaces, and perhaps one at the end
            words.append(_new(_word, (w[0], float(w[1:]), col, None)))
            col += len(w) + 1
        out.append(_new(_plain, words))
    return out


def small_int(digits: str, limit: int = 4294967295) -> int | None:
    """``int(digits)`` when it is at most ``limit``, else None (no huge-int work)."""
    digits = digits.strip().lstrip("0") or "0"
    if len(digits) > len(str(limit)):
        return None
    n = int(digits)
    return n if n <= limit else None


def _float(text: str) -> float:
    """float() of a literal; an out-of-range literal becomes inf (reported later as a value error)."""
    try:
        return float(text)
    except OverflowError:
        return float("inf")


def _unquote(text: str) -> str:
    """Text of a STRING token: quotes removed, \\" -> " (seed 002 L14194)."""
    return text[1:-1].replace('\\"', '"')


def _neg(x):
    if type(x) is Num:
        return Num(-x.value, x.col)
    if type(x) is float:
        return -x
    return Unary("-", x, x.col)


def _literal(value):
    """ISO word values: a literal number is kept as a plain float."""
    return value.value if type(value) is Num else value


class AstBuilder(Transformer):
    """Inline transformer for the LALR parser; see the module docstring."""

    def __init__(self) -> None:
        super().__init__(visit_tokens=False)
        self.problems: list = []

    def _problem(self, col: int, code: str, message: str) -> None:
        self.problems.append((col, code, message))

    def _expr(self, value, col: int):
        if type(value) is ItemList:
            col = value.col or max(col, 1)
            self._problem(col, "SYN016", "a bracket list [a, b] cannot stand where a single value is expected")
            return Num(0.0, col)
        return value

    # ------------------------------------------------------------ blocks
    def start(self, c):
        return c[0]

    def block(self, c):
        skip = False
        number = label = plain_number = None
        items = ()
        for x in c:
            if type(x) is Token:
                t = x.type
                if t == "SKIP":
                    skip = True
                elif t == "BLOCKID":
                    digits = x.value[1:].rstrip(" \t:")
                    number = small_int(digits)
                    if number is None:
                        self._problem(x.column, "SYN011",
                                      f"block number N{digits[:12]}{'...' if len(digits) > 12 else ''} is out "
                                      "of range 0..4294967295")
                        number = 0
                elif t == "BLOCKNUM":
                    plain_number = Word("N", _float(x.value[1:]), x.column)
                elif t == "LABEL":
                    label = x.value[1:-1].strip()
                    if not valid_name(label):
                        self._problem(x.column, "SYN010",
                                      f"label [{label}] must be 1 to 14 letters and digits, without blanks")
            else:
                items = x
        if plain_number is not None:
            items = (plain_number, *items)
        return ("block", skip, number, label, items)

    def program_header(self, c):
        tok = c[0]
        name = tok.value[1:].strip()
        if not valid_name(name):
            if _POST_NAME.fullmatch(name):   # "% Pfette_.nc" (LIGNOCAM): the [compat] construct program_name
                self._problem(tok.column + 1, "CAM004",
                              f"program name '{name}': the manual's names are 1 to 14 letters and digits, without "
                              "blanks (seed 002 L843); CAM posts write others and the control accepts them: taken "
                              "as the name (it only names the program, L849)")
            else:
                self._problem(tok.column + 1, "SYN010",
                              f"program name '{name}' must be 1 to 14 letters and digits, without blanks")
        return ("program", name)

    def subroutine_header(self, c):
        tok = c[0]
        name = tok.value[2:].strip()
        if not valid_name(name):
            shown = name or "(missing)"
            self._problem(tok.column + 3, "SYN010",
                          f"subroutine name '{shown}' after %L must be 1 to 14 letters and digits")
        return ("subroutine", name)

    def iso_block(self, c):
        items = []
        for x in c:
            if type(x) is list:
                items.extend(x)
            else:
                items.append(x)
        last = items[-1]
        if type(last) is Sentence and last.keyword not in ("MCS", "AXIS"):
            self._problem(last.col, "SYN014",
                          f"#{last.keyword} must be alone in its block (only #MCS and #AXIS follow ISO words)")
        elif type(last) in (SubroutineCall, Repeat):
            kw = "RPT" if type(last) is Repeat else last.kind
            self._problem(last.col, "SYN014", f"#{kw} must be alone in its block")
        return tuple(items)

    def sentence_block(self, c):
        return (c[0],)

    def flow_block(self, c):
        return (c[0],)

    def assignment_block(self, c):
        return tuple(c)

    def local_call(self, c):
        tok = c[0]
        return (SubroutineCall("LL", tok.value[2:].strip(), (), tok.column),)

    def global_call(self, c):
        tok = c[0]
        return (SubroutineCall("L", tok.value[1:].strip(), (), tok.column),)

    # ------------------------------------------------------------ ISO words
    def words(self, c):
        tok = c[0]
        return split_words(tok.value, tok.column)

    def word(self, c):
        tok, value = c
        return Word(tok.value, _literal(self._expr(value, tok.column)), tok.column)

    def spindle_m(self, c):
        """``M3.S2`` -> Word("M.S2", 3); ``M19.POS`` -> Word("M.POS", 19); ``M19.NEG.S1`` -> Word("M.NEG.S1", 19)."""
        tok = c[0]
        text = tok.value.replace(" ", "").replace("\t", "")
        number, _, suffix = text[1:].partition(".")
        return Word(f"M.{suffix}", float(number), tok.column)

    def spindle_pos_speed(self, c):
        """``S.POS=120`` -> Word("S.POS", 120); ``S1.POS=50`` -> Word("S1.POS", 50)."""
        tok, value = c
        return Word(tok.value.rstrip("= \t"), _literal(self._expr(value, tok.column)), tok.column)

    def param_letter(self, c):
        tok = c[0]
        return Word("P", _float(tok.value[1:]), tok.column)

    def bare_value(self, c):
        tok = c[0]
        return Word("", _float(tok.value), tok.column)

    def bare_word(self, c):
        tok = c[0]
        return Word(tok.value, None, tok.column)

    def word_eq(self, c):
        tok, value = c
        head = tok.value.rstrip("= \t")
        letter = head[0]
        number = small_int(head[1:], 99999)
        if number is None:
            self._problem(tok.column, "SYN011", f"'{head[:12]}...' is not a valid name or G function number")
            number = 0
        value = _literal(self._expr(value, tok.column))
        if letter == "G":  # G159=5, G263=30: function number and its value
            return Word("G", float(number), tok.column, value)
        return Word(f"{letter}{number}", value, tok.column)

    def _plain_eq(self, op) -> None:
        if op.value != "=":
            self._problem(op.column, "SYN002", f"'{op.value}' is only allowed in assignments; write '='")

    def param_word(self, c):
        tok, op, value = c
        self._plain_eq(op)
        return Word(f"P{self.param([tok]).index}", _literal(self._expr(value, tok.column)), tok.column)

    # ------------------------------------------------------------ sentences
    def call_sentence(self, c):
        kw, target = c[0], c[1]
        args = []
        for x in c[2:]:
            if type(x) is list:
                args.extend(x)
            else:
                args.append(x)
        kind = kw.value[1:]
        if kind == "CALL" and args:
            self._problem(args[0].col, "SYN002",
                          "#CALL passes no parameters: use #PCALL to initialise local parameters")
        return SubroutineCall(kind, target.value, tuple(args), kw.column)

    def rpt_sentence(self, c):
        kw = c[0]
        count = self._expr(c[3], kw.column) if len(c) > 3 else None
        return Repeat(c[1], c[2], count, kw.column)

    def rpt_number(self, c):
        tok, value = c
        return RepeatRef(_literal(self._expr(value, tok.column)), None, tok.column)

    def rpt_label(self, c):
        tok = c[0]
        name = tok.value[1:-1].strip()
        if not valid_name(name):
            self._problem(tok.column, "SYN010", f"label [{name}] must be 1 to 14 letters and digits")
        return RepeatRef(None, name, tok.column)

    def sentence(self, c):
        kw = c[0]
        keyword = " ".join(kw.value[1:].split())
        if keyword == "MOVE ABS":
            keyword = "MOVE"   # "#MOVE ABS [X50]" is "#MOVE [X50]": ABS is the default form (L16690)
        node = Sentence(keyword, tuple(c[1:]), kw.column)
        for col, code, message in check_sentence(node):
            self._problem(col, code, message)
        return node

    def s_name(self, c):
        return Name(c[0].value, c[0].column)

    def s_keyed(self, c):
        return Keyed(c[0].value, c[1], c[0].column)

    def s_setting(self, c):
        self._plain_eq(c[1])
        return Setting(c[0].value, self._expr(c[2], c[0].column), c[0].column)

    def s_setting_n(self, c):
        name, number, op, value = c
        self._plain_eq(op)
        n = small_int(number.value.split(".")[0], 99999)
        if n is None or "." in number.value:
            self._problem(number.column, "SYN010", f"'{name.value}{number.value[:12]}' is not a valid name")
            n = 0
        return Setting(f"{name.value}{n}", self._expr(value, name.column), name.column)

    def s_direction(self, c):
        return Direction(c[0].value, c[1].value, c[0].column)

    def s_string(self, c):
        return Str(_unquote(c[0].value), c[0].column)

    def s_define(self, c):
        self._plain_eq(c[1])
        return Definition(_unquote(c[0].value), _unquote(c[2].value), c[0].column)

    # ------------------------------------------------------------ flow
    def _flow(self, c, args=()):
        tok = c[0]
        return Flow(tok.type, args, tok.column)

    def f_if(self, c):
        return self._flow(c, (self._expr(c[1], c[0].column),))

    def f_if_goto(self, c):
        return self._flow(c, (self._expr(c[1], c[0].column), c[3]))

    f_elseif = f_while = f_enddo = f_switch = f_case = f_if

    def f_else(self, c):
        return self._flow(c)

    f_endif = f_default = f_endswitch = f_endfor = f_endwhile = f_do = f_break = f_continue = f_else

    def f_for(self, c):
        self._plain_eq(c[2])
        return self._flow(c, (c[1], *(self._expr(x, c[0].column) for x in c[3:])))

    def f_goto(self, c):
        return self._flow(c, (c[1],))

    def goto_number(self, c):
        tok, value = c[0], c[1]
        return Goto(_literal(self._expr(value, tok.column)), None, tok.column)

    def goto_label(self, c):
        tok = c[0]
        name = tok.value[1:-1].strip()
        if not valid_name(name):
            self._problem(tok.column, "SYN010", f"label [{name}] must be 1 to 14 letters and digits")
        return Goto(None, name, tok.column)

    # ------------------------------------------------------------ assignments
    def assignment(self, c):
        target, op, value = c
        return Assignment(target, op.value, self._expr(value, op.column), target.col)

    # ------------------------------------------------------------ expressions
    def _binary(op):  # noqa: N805 - builds the callbacks below
        def build(self, c):
            left, right = c[0], c[-1]
            return Binary(op, self._expr(left, 0), self._expr(right, 0), left.col)
        return build

    bor = _binary("|")
    band = _binary("&")
    bxor = _binary("^")
    add = _binary("+")
    sub = _binary("-")
    mul = _binary("*")
    div = _binary("/")
    pow = _binary("**")
    mod = _binary("MOD")
    del _binary

    def rel(self, c):
        left, op, right = c
        return Binary(op.value, self._expr(left, op.column), self._expr(right, op.column), left.col)

    def neg(self, c):
        return _neg(self._expr(c[0], 0))

    def number(self, c):
        return Num(_float(c[0].value), c[0].column)

    def hexnum(self, c):
        digits = c[0].value[1:].lstrip("0") or "0"
        value = float(int(digits, 16)) if len(digits) <= 200 else float("inf")
        return Num(value, c[0].column)

    def true(self, c):
        return Num(1.0, c[0].column)

    def false(self, c):
        return Num(0.0, c[0].column)

    def param(self, c):
        tok = c[0]
        n = small_int(tok.value[1:], 99999)
        if n is None:
            self._problem(tok.column, "SYN011", f"parameter {tok.value[:12]}... does not exist (P0..P19999)")
            n = 99999
        return Param(n, tok.column)

    def param_indexed(self, c):
        tok, index = c
        return Param(self._expr(index, tok.column), tok.column)

    def var(self, c):
        tok = c[0]
        name = tok.value
        index = []
        m = _CHANNEL.match(name)
        if m:
            index.append(Num(float(m.group(1)), tok.column + 3))
            name = "V.[]." + name[m.end():]
        for tail in c[1:]:
            if type(tail) is Token:
                name += tail.value
            else:
                name += "[]"
                index.append(self._expr(tail, tok.column))
        return Var(name, tuple(index), tok.column)

    def func(self, c):
        tok, arg = c
        name = tok.value
        if type(arg) is ItemList:
            args = []
            for seq in arg.items:
                if len(seq) == 1 and type(seq[0]) in _EXPR_TYPES:
                    args.append(seq[0])
                else:
                    self._problem(tok.column, "SYN015", f"{name}[...] takes numbers separated by commas")
                    args.append(Num(0.0, tok.column))
            args = tuple(args)
        else:
            args = (arg,)
        arity = FUNCTION_ARITY[name]
        if len(args) != arity:
            self._problem(tok.column, "SYN015",
                          f"{name} takes {arity} argument{'s' if arity > 1 else ''}, not {len(args)}")
        if name == "EXIST" and args and type(args[0]) not in (Param, Var):
            self._problem(tok.column, "SYN015", "EXIST[...] takes a parameter or a variable, e.g. EXIST[P1]")
        return Call(name, args, tok.column)

    def bracket(self, c):
        if len(c) == 1:
            seq = c[0]
            if len(seq) == 1 and type(seq[0]) in _EXPR_TYPES:
                return seq[0]  # plain grouping: [P1*2]
        col = 0
        for seq in c:
            if seq:
                col = seq[0].col
                break
        return ItemList(tuple(c), col)

    def bseq(self, c):
        return tuple(c)
