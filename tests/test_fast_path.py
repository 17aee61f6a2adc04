"""The regex fast path of :meth:`LineParser.parse` must agree with the LALR parser.

:meth:`LineParser.parse` recognises lines made only of literal ISO words
(``N10 G1 X-1.5 Y2. F100 ; comment``) with a regular expression and builds
the AST directly; every other line goes to :meth:`LineParser.parse_full`.
Whatever the path, the ``(node, diagnostics)`` result must be the one the
full parser gives.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from hypothesis import example, given
from hypothesis import strategies as st

from fagorcnc.syntax import LineParser, line_parser
from fagorcnc.syntax.ast import Block, SubroutineCall, Word

PROGRAMS = Path(__file__).resolve().parents[1] / "programs"

# ISO addresses: every capital except P (P introduces arithmetic parameters).
ISO_LETTERS = "ABCDEFGHIJKLMNOQRSTUVWXYZ"

blanks = st.text(alphabet=" \t", max_size=3)
digits = st.text(alphabet="0123456789", min_size=1, max_size=7)
numbers = st.one_of(
    digits,                                                   # 12, 0012
    digits.map(lambda d: d + "."),                            # 12.
    digits.map(lambda d: "." + d),                            # .5
    st.tuples(digits, digits).map(lambda t: f"{t[0]}.{t[1]}"),  # 0012.3400
    st.sampled_from(["0", "00", "0012.3400", "12.", ".5", "0.0", "1" * 40, "9" * 400,
                     "4294967295", "4294967296"]),
)
signs = st.sampled_from(["", "", "+", "-"])
iso_words = st.tuples(st.sampled_from(ISO_LETTERS), blanks, signs, blanks, numbers).map("".join)
# Words separated by blanks, or glued together ("G1X10Y-2").
word_runs = st.lists(st.tuples(iso_words, blanks), max_size=8).map(lambda ws: "".join(w + b for w, b in ws))
jump_targets = st.one_of(
    st.just(""),
    st.tuples(st.just("N"), st.one_of(digits, st.just("99999999999")), blanks, st.just(":"), blanks).map("".join),
)
comment_text = st.text(alphabet=st.characters(exclude_characters="\n\r", exclude_categories=("Cs",)), max_size=12)
comments = st.one_of(st.just(""), comment_text.map(lambda c: ";" + c))
iso_lines = st.tuples(blanks, jump_targets, word_runs, comments).map("".join)


def both(text: str) -> tuple:
    parser = line_parser()
    return parser.parse(text, 1), parser.parse_full(text, 1)


@given(iso_lines)
@example("N10 G1 X-1.5 Y2. F100 ; comment")
@example("G1X10Y-2")
@example("N123: G0 X .5 Y - 12. Z+0012.3400")
@example("\tN5:\tM3\tS1000\t;spindle")
@example("X1 Y2 ;")
@example("N10:")
@example("   ; only a comment")
@example("")
@example("N4294967296: G1 X1")
@example("G1 X" + "9" * 400)
def test_fast_path_equals_full_parser(text: str) -> None:
    fast, full = both(text)
    assert fast == full


HAND_WRITTEN = [
    "N10 G1 X-1.5 Y2. F100 ; comment",
    "G1X10Y-2",
    "G01 X  -  10 Y 3",
    "N1230 G1 X12.5 Y-3.25 F800",
    "G0 Z.5",
    "X0012.3400",
    "N10: G0 X0",
    "N10 : G0 X0",
    "N0:",
    "M30",
    "T1 D1 M06",
    "S12000 M03",
    "N155 G1Z-5.F800",
    "  \t  ",
    ";",
    "; G1 X1",
    # not fast-path lines: these must still agree (they all go to the full parser)
    "G1 X1 (comment)",
    "N10 G1 X1 N20:",
    "X1.2.3",
    "X1=5",
    "G159=5",
    "P1=2",
    "/N10 G1 X1",
    "N10 P1=2",
    "g1 x1",
    "G1 X1\r",
]


@pytest.mark.parametrize("text", HAND_WRITTEN)
def test_fast_path_hand_written(text: str) -> None:
    fast, full = both(text)
    assert fast == full


def test_hand_written_values() -> None:
    node, diags = line_parser().parse("N10: G1X-1.5 Y 2. F.5 ; go", 7)
    assert diags == ()
    assert node == Block(7, "N10: G1X-1.5 Y 2. F.5 ; go", False, 10, None, (
        Word("G", 1.0, 6), Word("X", -1.5, 8), Word("Y", 2.0, 14), Word("F", 0.5, 19)))


def _no_full_parser(parser: LineParser) -> LineParser:
    def boom(*args, **kwargs):
        raise AssertionError("the fast path should have handled this line")

    parser.parse_full = boom  # instance attribute shadows the method
    return parser


@pytest.mark.parametrize("text", [
    "N10 G1 X1",
    "N10 G1 X-1.5 Y2. F100 ; comment",
    "N1230 G1 X12.5 Y-3.25 F800",
    "G1X10Y-2",
    "N20: G0 Z5.",
    "",
    "; comment only",
])
def test_fast_path_is_taken(text: str) -> None:
    expected = line_parser().parse_full(text, 3)
    assert _no_full_parser(LineParser()).parse(text, 3) == expected


# Typical CAM blocks: words separated by one blank, no blanks inside a word.
cam_words = st.tuples(st.sampled_from("GXYZIJKFSTMDABC"), signs, numbers).map("".join)
cam_lines = st.tuples(
    st.one_of(st.just(""), digits.map(lambda d: f"N{d} ")),
    st.lists(cam_words, min_size=1, max_size=6).map(" ".join),
    comments,
).map("".join)


@given(cam_lines)
def test_fast_path_is_taken_for_cam_blocks(text: str) -> None:
    expected = line_parser().parse_full(text, 1)
    assert _no_full_parser(LineParser()).parse(text, 1) == expected


# ---------------------------------------------------------------- demo lines
def _demo_lines() -> list[str]:
    lines = []
    for path in sorted(PROGRAMS.glob("*.nc")):
        lines.extend(path.read_text(encoding="utf-8").splitlines())
    return lines


DEMO_LINES = _demo_lines()
MUTATION_CHARS = st.one_of(st.sampled_from(list(" \t:;=()[]+-.*/$#%\"0123456789GLNPXYZV")), st.characters())


@st.composite
def mutated_demo_lines(draw) -> str:
    text = draw(st.sampled_from(DEMO_LINES))
    for _ in range(draw(st.integers(1, 4))):
        pos = draw(st.integers(0, len(text)))
        op = draw(st.sampled_from(["insert", "delete", "replace"]))
        if op == "insert":
            text = text[:pos] + draw(MUTATION_CHARS) + text[pos:]
        elif op == "delete":
            text = text[:pos] + text[pos + 1:]
        else:
            text = text[:pos] + draw(MUTATION_CHARS) + text[pos + 1:]
    return text


@given(mutated_demo_lines())
def test_fast_path_equals_full_parser_on_mutated_demo_lines(text: str) -> None:
    fast, full = both(text)
    assert fast == full


# ---------------------------------------------------------------- regressions
@pytest.mark.parametrize("text", ["L 5", "L 100", "N10 L 5", "N10: L 5", "N10:L\t7 ; call"])
def test_regression_global_call_with_numeric_name(text: str) -> None:
    """``L 100`` is a global subroutine call (grammar: GLOBAL_CALL before WORDS).

    The fast path reads it as the ISO word L100 instead.
    """
    fast, full = both(text)
    assert any(type(i) is SubroutineCall for i in full[0].items)
    assert fast == full


# --- the plain-line pattern tried before _fast (parser.PLAIN_LINE): a subset of _fast's lines ---------------

def _plain_taken(text: str) -> bool:
    from fagorcnc.syntax.parser import PLAIN_LINE

    return PLAIN_LINE(text) is not None


@given(st.one_of(iso_lines, cam_lines, word_runs))
@example("N10 G1 X-3.943 Y-10.455 I-13.2567 J-0.971")
@example("X0.5000 Y0.0000 Z0.1427 ")
@example("G1X10Y-2")
@example("G1 X1 ")
@example("L5 X1")
@example("N10 G1 X" + "9" * 400)
@example("N99999999999 G1 X1")
def test_plain_pattern_equals_fast_pattern(text: str) -> None:
    """Whether or not the plain pattern takes a line, parse() is _fast's result (structure_only too),
    and the full parser's; what it takes, _fast takes as one WORDS run from column 1."""
    parser = line_parser()
    for structure_only in (False, True):
        assert parser.parse(text, 4, "f", structure_only) == parser._parse_fast(text, 4, "f", structure_only)
    if _plain_taken(text):
        m = parser._fast(text)
        assert m is not None and m.group(1) is None and m.group(2) == text and m.start(2) == 0
    assert parser.parse(text, 4) == parser.parse_full(text, 4)


@pytest.mark.parametrize("text", ["N10 G1 X-1.5 Y2. F100", "G2 X-3.943 Y-10.455 I-13.2567 J-0.971",
                                  "X0.5000 Y0.0000 Z0.1427", "X.5 Y-.25 ", "N10 L5", "X+0012.3400 Y3."])
def test_plain_pattern_is_taken(text: str) -> None:
    parser = LineParser()
    parser._fast = None   # neither _fast nor the full parser is asked
    assert _plain_taken(text)
    assert _no_full_parser(parser).parse(text, 3) == line_parser().parse_full(text, 3)


@pytest.mark.parametrize("text", ["N10: G1 X1", " G1 X1", "G1 X1 ; go", "M3 S1000", "G1  X1", "G1 X 1", "X- 1",
                                  "L 5", "N10 L 5", "G1 P1", "X1 Y2 Z3 M30", "X1..2", "X1=2", "G1 X1:", "",
                                  "X1.5.5", "G1\tX1", "G1X10Y-2", "G1 X1  ", "G1 X[1]", "#HSC ON", "X+-1"])
def test_plain_pattern_steps_aside(text: str) -> None:
    """Block ids, blanks before or inside words, tabs, comments, M and P words, "L 5" calls and anything
    that is not a literal word go the way they went before."""
    assert not _plain_taken(text)
    parser = line_parser()
    assert parser.parse(text, 2) == parser._parse_fast(text, 2, "<string>", False)


@given(st.lists(st.one_of(iso_lines, cam_lines, st.sampled_from(["%PRG", "M30", "#COMMENT BEGIN", "#COMMENT END",
                                                                 "PRG1", "G1 X1 Y2", "$IF P1==1", "$ENDIF"])),
                max_size=12))
def test_iter_lines_plain_shortcut_equals_parse(lines: list) -> None:
    """iter_lines() takes PLAIN_LINE's lines without calling parse(): the same (node, diagnostics) as with
    the pattern switched off (every line by _fast or the full parser), for execution and for the
    structure pre-pass."""
    from unittest import mock

    from fagorcnc.syntax import parser, reader

    for structure_only in (False, True):
        fast = list(reader.iter_lines(lines, "f", structure_only=structure_only))
        with mock.patch.object(reader, "PLAIN_LINE", lambda text: None), \
                mock.patch.object(parser, "PLAIN_LINE", lambda text: None):
            assert list(reader.iter_lines(lines, "f", structure_only=structure_only)) == fast


@pytest.mark.parametrize("tail", [";", " ;comment", "  ", "=1", ":"])
def test_plain_pattern_no_backtracking_on_integer_words(tail: str) -> None:
    """A line of integer words that the plain pattern rejects only at its end (a comment, two blanks,
    ``=``, ``:``) is read as _fast and the full parser read it.  With a number pattern whose digits split
    two ways (``[0-9]+\\.?[0-9]*``) the rejection backtracked through every split of every word: eight
    12-digit words took 78 s, these thirty would never end."""
    text = " ".join(f"{axis}{'7' * 20}" for axis in "XYZABCUVWIJKXYZABCUVWIJKXYZABC") + tail
    assert not _plain_taken(text)
    parser = line_parser()
    assert parser.parse(text, 2) == parser._parse_fast(text, 2, "<string>", False) == parser.parse_full(text, 2)
    taken = text[: -len(tail)]
    assert _plain_taken(taken) and parser.parse(taken, 2) == parser.parse_full(taken, 2)


@pytest.mark.parametrize("word", ["X 1", "X - 1", "M 3", "X1", "X 1.5", "G 1"])
@pytest.mark.parametrize("tail", ["=", ":", "@", "X", "..", "[", '"', ";"])
def test_words_with_blanks_no_backtracking(word: str, tail: str) -> None:
    """Forty words with blanks between letter, sign and number (L1016), then a tail the WORDS run cannot
    take: read as the full parser reads it.  With "[ \\t]*[+-]?[ \\t]*" around the sign each blank could go
    before or after the missing sign, and the failing fullmatch retried 2^40 ways (18 words: 0.1 s)."""
    text = " ".join([word] * 40) + tail
    parser = line_parser()
    for structure_only in (False, True):
        assert parser.parse(text, 2, "f", structure_only) == parser._parse_fast(text, 2, "f", structure_only)
    assert parser.parse(text, 2) == parser.parse_full(text, 2)
