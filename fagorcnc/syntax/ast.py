"""Typed, immutable syntax tree of a Fagor 8060/8065 program.

Every node is a :class:`typing.NamedTuple` (immutable, cheap to build: a CAM
program has millions of them).  Positions: a :class:`Block` knows its source
line (1-based) and text; nodes inside a block carry ``col``, the 1-based column
where they start.  The file name lives on :class:`Program`.

The parser knows syntax only.  Values are kept as written: a literal is a
``float``, anything else an expression node (:data:`Expr`).  Which G function
consumes which letters, which axes exist, value ranges and modal rules are the
interpreter's business.
"""

from __future__ import annotations

from typing import NamedTuple, Union

# --------------------------------------------------------------------------
# Expressions (seed 002 L1927-L2157)
# --------------------------------------------------------------------------


class Num(NamedTuple):
    """A numeric constant (decimal, ``$`` hexadecimal, TRUE=1, FALSE=0)."""

    value: float
    col: int


class Param(NamedTuple):
    """Arithmetic parameter ``P<n>`` or ``P[<expr>]`` (seed 002 L1861-L1911).

    ``index`` is an ``int`` for ``P12`` and an expression for ``P[P1+2]``.
    """

    index: Union[int, Expr]
    col: int


class Var(NamedTuple):
    """A ``V.`` variable reference (seed 002 L17555).

    ``name`` is the spelling with every bracketed index replaced by ``[]``
    (``V.G.FIXT[1].X`` -> ``"V.G.FIXT[].X"``, ``V.[2].G.FIX`` ->
    ``"V.[].G.FIX"``); ``index`` holds the index expressions in order.
    """

    name: str
    index: tuple
    col: int


class Unary(NamedTuple):
    """``-x`` (``op`` is ``"-"``)."""

    op: str
    operand: Expr
    col: int


class Binary(NamedTuple):
    """``left op right``; ``op`` is one of ``| & ^ == != >= <= > < + - * / ** MOD``."""

    op: str
    left: Expr
    right: Expr
    col: int


class Call(NamedTuple):
    """Function call ``SIN[30]``, ``ARG[x, y]``, ``EXIST[P1]`` (seed 002 L2010-L2097)."""

    func: str
    args: tuple
    col: int


Expr = Union[Num, Param, Var, Unary, Binary, Call]

#: Number of arguments of every function of the manual's list.
FUNCTION_ARITY: dict[str, int] = {
    "SIN": 1, "COS": 1, "TAN": 1, "ASIN": 1, "ACOS": 1, "ATAN": 1, "ARG": 2,
    "ABS": 1, "SQR": 1, "SQRT": 1, "LOG": 1, "LN": 1, "EXP": 1, "DEXP": 1,
    "INT": 1, "FRACT": 1, "ROUND": 1, "FUP": 1, "EXIST": 1, "INV": 1,
}

# --------------------------------------------------------------------------
# Generic items of # sentences
# --------------------------------------------------------------------------


class Name(NamedTuple):
    """A bare keyword or name: ``ON``, ``FAST``, ``AX``, ``X``."""

    name: str
    col: int


class Keyed(NamedTuple):
    """A keyword followed by a value: ``CONTERROR 0.01``, ``ID[1]``, ``X20``.

    ``value`` is an expression or an :class:`ItemList`.
    """

    name: str
    value: object
    col: int


class Setting(NamedTuple):
    """``NAME = expr``: ``TON=50``; with a numbered name ``X1=20`` -> name ``"X1"``."""

    name: str
    value: Expr
    col: int


class Direction(NamedTuple):
    """An axis and a direction sign: ``X+`` in ``#MOVE INF [X+]``."""

    name: str
    sign: str
    col: int


class Str(NamedTuple):
    """A double-quoted string (quotes removed)."""

    text: str
    col: int


class Definition(NamedTuple):
    """``"NAME"="text"`` (``#DEF``, seed 002 L16113)."""

    name: str
    text: str
    col: int


class ItemList(NamedTuple):
    """A bracketed list ``[a, b c, , d]``: ``items`` holds one tuple of items per
    comma-separated position (an empty tuple for an omitted argument)."""

    items: tuple
    col: int


# --------------------------------------------------------------------------
# Block contents
# --------------------------------------------------------------------------


class Word(NamedTuple):
    """An ISO word (seed 002 L1006-L1129).

    ``address`` is the letter(s) as written: ``"G"``, ``"X"``, ``"NR"``,
    ``"MG"``, numbered names ``"X1"``, ``"S2"``, generic axes ``"?3"``, call
    arguments ``"P10"``.  ``value`` is a ``float`` for a literal or an
    expression, ``None`` for an address written without a value (the axes
    of ``G157 X Z``, seed 002 L3851).  A number without a letter (``G04 5``)
    has the address ``""``.  For ``G159=5`` and ``G263=30`` the address is ``"G"``, the
    value the function number and ``eq`` the value after ``=``.
    """

    address: str
    value: Union[float, Expr]
    col: int
    eq: Union[float, Expr, None] = None


class Sentence(NamedTuple):
    """A ``#`` programming statement (seed 002 ch. 21.1).

    ``keyword`` is the name after ``#`` (``"HSC"``, ``"CALL AX"``); ``args``
    are the generic items that follow (:class:`Name`, :class:`Keyed`, ...,
    or expressions) in source order.
    """

    keyword: str
    args: tuple
    col: int


class SubroutineCall(NamedTuple):
    """``LL name``, ``L [path]name``, ``#CALL``, ``#PCALL``, ``#MCALL`` (seed 002 L10314).

    ``kind`` is ``"LL"``, ``"L"``, ``"CALL"``, ``"PCALL"`` or ``"MCALL"``;
    ``target`` the name as written (possibly with a path); ``args`` the
    parameter initialisations as :class:`Word` (``A12.3`` -> address ``"A"``,
    ``P10=6`` -> address ``"P10"``).
    """

    kind: str
    target: str
    args: tuple
    col: int


class RepeatRef(NamedTuple):
    """One end of a ``#RPT`` range: ``N10`` (``number``) or ``[NAME]`` (``label``)."""

    number: Union[float, Expr, None]
    label: Union[str, None]
    col: int


class Repeat(NamedTuple):
    """``#RPT [start, end, n]`` (seed 002 L16203); ``count`` is ``None`` when omitted."""

    start: RepeatRef
    end: RepeatRef
    count: Union[Expr, None]
    col: int


class Goto(NamedTuple):
    """Destination of ``$GOTO``: ``N<expr>`` (``number``) or ``[label]``."""

    number: Union[float, Expr, None]
    label: Union[str, None]
    col: int


class Flow(NamedTuple):
    """A ``$`` flow-control instruction (seed 002 ch. 21.2).

    ``keyword`` without the ``$`` (``"IF"``, ``"ENDFOR"`` ...).  ``args``:
    ``IF``/``ELSEIF``/``WHILE``/``ENDDO``/``SWITCH``/``CASE`` -> ``(expr,)``;
    ``IF`` with ``$GOTO`` -> ``(expr, Goto)``; ``GOTO`` -> ``(Goto,)``;
    ``FOR`` -> ``(target, start, end, step)``; others ``()``.
    """

    keyword: str
    args: tuple
    col: int


class Assignment(NamedTuple):
    """``target op expr`` with ``op`` in ``= += -= *= /=`` (seed 002 L1959)."""

    target: Union[Param, Var]
    op: str
    value: Expr
    col: int


class PlainWords(tuple):
    """The items of a block read from a plain line (``parser.PLAIN_LINE``'s): :class:`Word` nodes only, each
    of a letter other than M and P, a literal float and no ``eq``.  A tuple like any other (it compares,
    hashes and prints as one); its type tells :meth:`~fagorcnc.interp.plain.PlainBlocks.run` that no word
    needs checking."""

    __slots__ = ()


class Block(NamedTuple):
    """One block (one line) of a program.

    ``items`` holds the block's content in source order: :class:`Word`,
    :class:`Sentence`, :class:`SubroutineCall`, :class:`Repeat`,
    :class:`Flow` or :class:`Assignment` nodes.  ``number`` is the jump-target
    number of ``N40:`` (a plain ``N40`` is an ordinary :class:`Word`).
    """

    line: int
    text: str
    skip: bool
    number: Union[int, None]
    label: Union[str, None]
    items: tuple

    @property
    def words(self) -> tuple:
        """The ISO words of the block, in order."""
        return tuple(i for i in self.items if type(i) is Word)

    @property
    def statement(self):
        """The block's ``#`` sentence, call or ``$`` instruction, if any."""
        for i in self.items:
            if type(i) is not Word and type(i) is not Assignment:
                return i
        return None


class ProgramHeader(NamedTuple):
    """``%NAME`` (seed 002 L840)."""

    name: str
    line: int
    text: str


class SubroutineHeader(NamedTuple):
    """``%L NAME``: start of a local subroutine (seed 002 L10276)."""

    name: str
    line: int
    text: str


Line = Union[Block, ProgramHeader, SubroutineHeader]


class Routine(NamedTuple):
    """The main program or one local subroutine of a file.

    ``numbers`` maps jump-target block numbers (``N40:``) and ``labels`` maps
    ``[NAME]`` labels to indexes into ``blocks``.  ``structure`` maps the
    index of every ``$`` instruction that opens or continues a structure
    (``$IF``, ``$ELSEIF``, ``$ELSE``, ``$FOR``, ``$WHILE``, ``$DO``,
    ``$SWITCH``, ``$CASE``, ``$DEFAULT``) to the index of the next instruction
    of the same structure, and each closing one (``$ENDIF`` ...) to its
    opening one.
    """

    name: str
    kind: str  # "program" or "local"
    line: int
    blocks: tuple
    numbers: dict
    labels: dict
    structure: dict


class Program(NamedTuple):
    """A parsed file: its main program, its local subroutines and diagnostics."""

    file: str
    name: Union[str, None]
    main: Routine
    subroutines: dict  # name (upper-case) -> Routine, in definition order
    diagnostics: tuple

    @property
    def ok(self) -> bool:
        """True when no diagnostic is an error."""
        return not any(d.severity == "error" for d in self.diagnostics)

    @property
    def blocks(self) -> tuple:
        """The blocks of the main program."""
        return self.main.blocks
