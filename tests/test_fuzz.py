"""Fuzzing the front end: :func:`parse_text` never raises and reports well-formed diagnostics.

Inputs: arbitrary text, random sequences of Fagor-ish tokens, deeply nested
brackets, lines and whole programs of ``programs/*.nc`` with random edits,
and programs assembled from valid and invalid lines with ``$`` structures,
subroutine headers and ``#COMMENT`` ranges in random order.  For every
input, :func:`check` verifies the invariants of :class:`Program` and of each
:class:`Diagnostic`.

Budgets come from the Hypothesis profile (``tests/conftest.py``);
``FAGORCNC_HYPOTHESIS_PROFILE=fuzz`` runs 20000 examples per property.
"""

from __future__ import annotations

import io
from pathlib import Path

import pytest
from helpers import edit_text
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

from fagorcnc.diagnostics import CODES, Diagnostic
from fagorcnc.syntax import Block, Program, iter_lines, parse_file, parse_text

PROGRAMS = Path(__file__).resolve().parents[1] / "programs"
PROGRAM_PATHS = sorted(PROGRAMS.glob("*.nc"))
PROGRAM_TEXTS = [p.read_text(encoding="utf-8") for p in PROGRAM_PATHS]
PROGRAM_LINES = [line for text in PROGRAM_TEXTS for line in text.splitlines()]
SEVERITIES = {"error", "warning", "info"}


def check(text: str, file: str = "<fuzz>") -> Program:
    """Parse ``text`` and verify the invariants of the result."""
    program = parse_text(text, file)
    assert isinstance(program, Program)
    assert isinstance(program.diagnostics, tuple)
    assert isinstance(program.ok, bool)
    n_lines = len(text.splitlines())
    for d in program.diagnostics:
        assert isinstance(d, Diagnostic)
        assert d.code in CODES, d
        assert d.severity in SEVERITIES, d
        assert d.file == file, d
        assert isinstance(d.line, int) and 1 <= d.line <= n_lines + 1, d
        assert isinstance(d.col, int) and d.col >= 1, d
        assert isinstance(d.message, str) and d.message.strip(), d
        assert isinstance(d.source, str), d
        assert str(d).startswith(f"{file}:{d.line}:{d.col}: {d.code} ")
        assert d.render().startswith(str(d))
    assert program.ok == (not any(d.severity == "error" for d in program.diagnostics))
    for block in program.blocks:
        assert type(block) is Block
        assert 1 <= block.line <= n_lines
    for routine in program.subroutines.values():
        for block in routine.blocks:
            assert type(block) is Block
            assert 1 <= block.line <= n_lines
    return program


# ---------------------------------------------------------------- raw text
raw_text = st.one_of(
    st.text(),  # any unicode, control characters, \r, \t, \x85, \u2028 ...
    st.text(alphabet=st.characters(codec="latin-1")),
    st.text(alphabet=st.sampled_from(list(" \t\r\n\x00\x0c;()[]{}#$%:=<>!+-*/,.\"'?&|^_~0123456789"
                                          "ABCDEFGHIJKLMNOPQRSTUVWXYZ"))),
)


@given(raw_text)
@example("")
@example("\r\n\r\n")
@example("\x00")
@example("%")
@example("%L")
@example("#")
@example("$")
@example("[")
@example('"')
@example("(")
def test_random_text(text: str) -> None:
    check(text)


# ---------------------------------------------------------------- token soup
TOKENS = [
    # ISO words and addresses
    "G", "G1", "G0", "G159", "X", "Y", "Z", "F", "S", "T", "D", "M", "M17", "M30", "N", "NR", "MG", "?", "X1=",
    # parameters and variables
    "P", "P1", "P100", "P[", "V.A.POS.X", "V.P.NAME", "V.[2].G.FIX", "V.G.FIXT[1].X", "V.", ".X",
    # brackets and separators
    "[", "]", "[", "]", "(", ")", "(comment)", ",", ";", ";comment", '"', '"text"', ":", "/",
    # operators
    "=", "==", "!=", "<", ">=", "+=", "-=", "*=", "/=", "+", "-", "*", "**", "MOD", "&", "|", "^", "!",
    # functions and constants
    "SIN", "SQRT", "ARG", "EXIST", "ROUND", "TRUE", "FALSE", "$FF", "$",
    # sentences
    "#HSC", "ON", "OFF", "CONTERROR", "#CALL", "#PCALL", "#MCALL", "#RPT", "#MCS", "#KIN", "ID", "#RET",
    "#MSG", "#DEF", "#CALL AX", "#COMMENT", "BEGIN", "END", "#SLOPE", "#", "#FOO",
    # flow
    "$IF", "$ELSEIF", "$ELSE", "$ENDIF", "$FOR", "$ENDFOR", "$WHILE", "$ENDWHILE", "$DO", "$ENDDO",
    "$SWITCH", "$CASE", "$DEFAULT", "$BREAK", "$CONTINUE", "$ENDSWITCH", "$GOTO",
    # headers, calls, block numbers, labels
    "%L", "%", "%L SUB", "%PROG", "LL", "L", "L SUB.NC", "N10:", "N10", "N4294967296:", "[LABEL]", "[DONE]",
    "[" + "A" * 40 + "]", "[A B]", "[]",
    # numbers
    "0", "1", "-0", "1.5", ".5", "12.", "0012.3400", "1e300", "1E300", "NaN", "inf", "-", "9" * 40, "1" * 40,
    "0." + "0" * 40 + "1",
    # odd characters
    "\t", "\r", "\x00", "é", "\u2028", "x", "g1",
]
tokens = st.sampled_from(TOKENS)
separators = st.sampled_from(["", " ", " ", "\t"])
token_lines = st.lists(st.tuples(tokens, separators), max_size=16).map(lambda ts: "".join(t + s for t, s in ts))
token_programs = st.lists(token_lines, min_size=1, max_size=12).map("\n".join)


@given(token_programs)
@example("#MCS X" + "1" * 40 + "=1")
def test_token_soup(text: str) -> None:
    check(text)


# ---------------------------------------------------------------- deep nesting
NESTING_TEMPLATES = [
    "X{open}1{close}",
    "G1 X{open}P1+2{close} Y0",
    "P1={open}1{close}",
    "P1={open}1,2{close}",
    "P{open}1{close}=2",
    "$IF {open}P1==1{close}",
    "$IF {open}P1{close} $GOTO N10",
    "#HSC ON{open}CONTERROR 0.01{close}",
    "#MSG {open}\"A\"{close}",
    "{open}LABEL{close}",
    "X{open}{close}",
    "X{open}1",          # never closed
    "X1{close}",         # never opened
    "P1=SIN{open}1{close}",
]
NESTINGS = {
    "[": ("[", "]"),
    "-[": ("-[", "]"),
    "SIN[": ("SIN[", "]"),
    "P[": ("P[", "]"),
    "[[": ("[1,[", "]]"),
    "(": ("(", ")"),
}


def nested(template: str, kind: str, depth: int) -> str:
    opener, closer = NESTINGS[kind]
    return template.format(open=opener * depth, close=closer * depth)


@given(st.sampled_from(NESTING_TEMPLATES), st.sampled_from(sorted(NESTINGS)), st.integers(0, 200))
def test_deep_nesting_random(template: str, kind: str, depth: int) -> None:
    check(nested(template, kind, depth))


@pytest.mark.parametrize("depth", [200, 2000])
@pytest.mark.parametrize("kind", sorted(NESTINGS))
def test_deep_nesting(kind: str, depth: int) -> None:
    """No RecursionError however deep the brackets are."""
    for template in NESTING_TEMPLATES:
        check(nested(template, kind, depth))


def test_deep_nesting_value() -> None:
    program = check("X" + "[" * 200 + "1" + "]" * 200)
    assert program.ok
    assert program.blocks[0].items[0].value == 1.0


# ---------------------------------------------------------------- mutations
EDIT_CHARS = st.one_of(
    st.sampled_from(list(" \t\r\n:;=()[]+-.,*/$#%\"0123456789GLMNPXYZV")),
    st.characters(),
)


def _edit(draw, text: str) -> str:
    return edit_text(draw, text, EDIT_CHARS)


@st.composite
def mutated_lines(draw) -> str:
    text = draw(st.sampled_from(PROGRAM_LINES))
    for _ in range(draw(st.integers(1, 4))):
        text = _edit(draw, text)
    return text


@st.composite
def mutated_programs(draw) -> str:
    lines = draw(st.sampled_from(PROGRAM_TEXTS)).splitlines()
    for _ in range(draw(st.integers(0, 3))):  # line-level edits: structure
        i = draw(st.integers(0, len(lines) - 1))
        op = draw(st.sampled_from(["delete", "duplicate", "move"]))
        if op == "delete":
            del lines[i]
        elif op == "duplicate":
            lines.insert(i, lines[i])
        else:
            lines.insert(draw(st.integers(0, len(lines))), lines.pop(i))
        if not lines:
            lines = [""]
    text = "\n".join(lines)
    for _ in range(draw(st.integers(1, 8))):  # character-level edits
        text = _edit(draw, text)
    return text


@given(mutated_lines())
def test_mutated_lines(text: str) -> None:
    check(text)


@given(mutated_programs())
def test_mutated_programs(text: str) -> None:
    check(text)


@pytest.mark.slow
@settings(max_examples=max(3000, settings.default.max_examples),
          suppress_health_check=[HealthCheck.too_slow])
@given(mutated_programs())
def test_mutated_programs_long(text: str) -> None:
    check(text)


# ---------------------------------------------------------------- structure soup
VALID_LINES = [
    "G1 X10 Y20 F500", "N10 G0 Z5", "N20: G1 X0", "[LOOP] G0 X1", "P1 = 0", "P2 = P1 + 1", "V.P.A = 2",
    "M3 S1000", "#HSC ON", "#HSC OFF", "LL SUB", "L PART.NC", "#CALL SUB", "#PCALL SUB A1 B2", "#RET",
    "#RPT [N10, N20, 2]", "$GOTO N20", "$GOTO [LOOP]", "$IF P1==1 $GOTO N10", "; comment", "", "(comment)",
    "/G1 X1", "G159=5", "M17", "M29", "M30",
]
INVALID_LINES = [
    "G1 X10 N20:", "X1+2", "g1 x1", "#FOO", "#HSC", "#HSC ON #RTCP ON", "$IF P1==1 $ENDIF", "P1 = SIN[1,2]",
    "[" + "A" * 40 + "]", "X(", '#MSG "open', "N99999999999:", "$", "%", "=", "@", "N10: N10: G1",
]
STRUCTURE_LINES = [
    "$IF P1==1", "$ELSEIF P1==2", "$ELSE", "$ENDIF",
    "$FOR P1 = 1, 3, 1", "$ENDFOR", "$WHILE P1 < 3", "$ENDWHILE", "$DO", "$ENDDO P1 < 3",
    "$SWITCH P1", "$CASE 1", "$CASE 2", "$DEFAULT", "$BREAK", "$CONTINUE", "$ENDSWITCH",
    "%L SUB", "%L SUB2", "%L", "%PROG", "%PROG2", "M17", "#RET",
    "#COMMENT BEGIN", "#COMMENT END", "  #COMMENT BEGIN extra", "N10 #COMMENT END",
    "SUBNAME", "N10:", "N10:", "[LOOP]", "[LOOP]",
]
program_lines = st.one_of(
    st.sampled_from(VALID_LINES),
    st.sampled_from(INVALID_LINES),
    st.sampled_from(STRUCTURE_LINES),
    st.sampled_from(PROGRAM_LINES),
)
newlines = st.sampled_from(["\n", "\r\n", "\r"])
structure_programs = st.tuples(st.lists(program_lines, max_size=40), newlines, st.booleans()).map(
    lambda t: t[1].join(t[0]) + (t[1] if t[2] else ""))


@given(structure_programs)
@example("%L SUB\nG1 X1\n%L SUB\nM17\n%PROG\n$IF P1==1\n$FOR P1=1,2,1\n$ENDIF\n$ENDFOR\n#COMMENT BEGIN")
@example("$SWITCH P1\n$CASE 1\n$CASE 2\n$BREAK\n$DEFAULT\n$CASE 3\n$ENDSWITCH\n$BREAK\n$CONTINUE")
@example("#COMMENT END\n#COMMENT BEGIN\n#COMMENT BEGIN\n#COMMENT END\n#COMMENT END")
def test_structure_soup(text: str) -> None:
    check(text)


@given(structure_programs)
def test_streaming_equals_text(text: str) -> None:
    """Reading an open file gives the same lines as parsing the text (\\n, \\r\\n and \\r line ends)."""
    from_text = list(iter_lines(text))
    from_stream = list(iter_lines(io.StringIO(text, newline=None)))
    assert from_stream == from_text


# ---------------------------------------------------------------- demo programs
@pytest.mark.parametrize("path", PROGRAM_PATHS, ids=lambda p: p.name)
def test_demo_programs_are_valid(path: Path) -> None:
    program = check(path.read_text(encoding="utf-8"), str(path))
    assert program.ok, [str(d) for d in program.diagnostics]
    assert not [d for d in program.diagnostics if d.severity == "error"]
    assert program.blocks
    file_program = parse_file(path)
    assert file_program.diagnostics == program.diagnostics
    assert file_program.blocks == program.blocks


def test_demo_programs_exist() -> None:
    assert len(PROGRAM_PATHS) >= 4


# ---------------------------------------------------------------- regressions
@pytest.mark.parametrize("text", [
    "N" + "1" * 5000 + ":",          # jump target: int() of more than 4300 digits
    "N" + "1" * 5000 + ": G1 X1",
    "P" + "1" * 5000 + "=1",         # parameter number
    "G" + "1" * 5000 + "=1",         # G159=5 form
    "G" + "1" * 400 + "=1",          # G159=5 form: float() of an int above 1.8e308
    "#MCS X" + "1" * 400 + "=1",     # numbered axis in a sentence: int(float('inf'))
    "P1=$" + "F" * 300,              # hexadecimal constant too large for a float
])
def test_regression_huge_numbers_do_not_raise(text: str) -> None:
    check(text)


@pytest.mark.parametrize("text", ["P1=[1,2]+1", "P1=1+[1,2]", "P1=-[1,2]", "P1=[]+1", "P1=[1,2]*2", "G3 X1 I-[] J0",
                                  "X[[1,2]+1]"])
def test_regression_bracket_list_operand_has_a_column(text: str) -> None:
    """SYN016 for a bracket list used as an operand must point into the line (col >= 1)."""
    program = check(text)
    assert [d.code for d in program.diagnostics] == ["SYN016"]


@pytest.mark.parametrize("sep", ["\x85", "\x0c", "\x0b", "\x1c", "\u2028"])
def test_regression_only_line_ends_split_lines(sep: str) -> None:
    """A comment holding a character that ``str.splitlines`` treats as a line break.

    A cp1252 '…' read through the Latin-1 fallback of :func:`read_source` is
    ``\\x85``; the line must not be split there (an open file is not split there).
    """
    text = f"%P1\nG1 X1 ; caf{sep} done\nG2 X2\n"
    program = check(text)
    assert program.ok, [str(d) for d in program.diagnostics]
    assert [b.line for b in program.blocks] == [2, 3]
    assert list(iter_lines(text)) == list(iter_lines(io.StringIO(text, newline=None)))


@pytest.mark.parametrize("text", [
    "$IF [1,2] $GOTO N10",
    "$IF [1,2]\n$ENDIF",
    "$WHILE [1,2]\n$ENDWHILE",
    "$SWITCH [1,2]\n$CASE [1,2]\n$BREAK\n$ENDSWITCH",
    "$DO\n$ENDDO [1,2]",
    "$FOR P1=[1,2],3,1\n$ENDFOR",
])
def test_regression_bracket_list_in_flow_expression(text: str) -> None:
    """A bracket list is not a condition: SYN016, as for ``P1=[1,2]`` or ``$GOTO N[1,2]``.

    Today the $ instruction keeps the :class:`ItemList` in the AST without a diagnostic.
    """
    program = check(text)
    assert "SYN016" in [d.code for d in program.diagnostics]
