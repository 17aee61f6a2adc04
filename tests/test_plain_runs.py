"""Runs of plain lines (``syntax.reader.iter_runs``): read a chunk at a time, found by one pattern call.

``iter_runs`` takes the source's lines :data:`~fagorcnc.syntax.reader.CHUNK_LINES` at a time; in a chunk
without NUL, ``#COMMENT`` or overlong line, the runs of consecutive plain lines (``parser.PLAIN_LINE``'s)
are found by ``parser.PLAIN_RUN`` and built at once; every other line is read one by one, as before.
These tests compare the runs with the same lines read one by one (``PLAIN_RUN`` switched off, and every
pattern switched off: each line by ``_fast`` or the LALR parser), and show which chunks step aside.
"""

from __future__ import annotations

import io
import re
from unittest import mock

import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from fagorcnc.interp.source import stream_program
from fagorcnc.syntax import parser, reader
from fagorcnc.syntax.ast import Block, Word
from fagorcnc.syntax.builder import split_plain, split_words
from fagorcnc.syntax.parser import PLAIN_LINE, PLAIN_RUN
from fagorcnc.syntax.structure import assemble

plain_words = st.tuples(st.sampled_from("GXYZIJKFSTNABC"), st.sampled_from(["", "-", "+"]),
                        st.sampled_from(["0", "12", "0.5", "12.", ".25", "-3", "007", "1" * 30])).map("".join)
plain_lines = st.tuples(st.lists(plain_words, min_size=1, max_size=6).map(" ".join),
                        st.sampled_from(["", "", " "])).map("".join)
other_lines = st.sampled_from([
    "", "%PRG", "%L SUB", "M17", "M30", "PRG1", "FINISH01", "N10: G1 X1", "G1 X1 ; go", " G1 X1", "G1  X1",
    "$IF P1==1", "$ENDIF", "#COMMENT BEGIN", "#COMMENT END", "N5 #COMMENT BEGIN", "G1 X[[", "X1 M3",
    "P1 = 2", "#HSC ON [CONTERROR 0.01]", "G1 X1 Y2\nG1 X3", "G1 X1\r", "G1 X1\x00", "\x00", "g1 x1",
    "G1 X" + "9" * 20000, "N10 G1 X1 N20:", "L 5"])
programs = st.lists(st.one_of(plain_lines, plain_lines, other_lines), max_size=30)


def _line_by_line(self, chunk: list, text: str, lineno: int):
    """_Reader.runs read one line at a time (every check of _Reader.line on each line, no run)."""
    for n, line in enumerate(chunk, lineno):
        if self.stopped:
            return
        pair = self.line(line, n)
        if pair is not None:
            yield pair


def _one_by_one(source, structure_only: bool = False, patterns: bool = True) -> list:
    """iter_lines without runs, every line read by _Reader.line (and, ``patterns=False``, without the plain
    pattern: by _fast or the LALR parser)."""
    with mock.patch.object(reader._Reader, "runs", _line_by_line):
        if patterns:
            return list(reader.iter_lines(source, "f", structure_only=structure_only))
        with mock.patch.object(reader, "PLAIN_LINE", lambda text: None), \
                mock.patch.object(parser, "PLAIN_LINE", lambda text: None):
            return list(reader.iter_lines(source, "f", structure_only=structure_only))


def _last_of_runs(pairs: list) -> list:
    """The pairs without the plain blocks (no items, no diagnostics) that another plain block follows."""
    out = []
    for pair in pairs:
        if out and _plain_structure(out[-1]) and _plain_structure(pair):
            out[-1] = pair
        else:
            out.append(pair)
    return out


def _within(short: list, long: list) -> bool:
    """Whether ``short`` is ``long`` with some of its items left out."""
    rest = iter(long)
    return all(any(item == other for other in rest) for item in short)


def _plain_structure(pair: tuple) -> bool:
    node, diags = pair
    return type(node) is Block and not node.items and not diags and PLAIN_LINE(node.text) is not None


@given(programs, st.sampled_from([1, 2, 3, 128]))
@example(["G1 X1"] * 300, 128)
@example(["FINISH01", "X1 Y2", "X2 Y3"], 2)
@example(["#COMMENT BEGIN", "X1", "X2", "#COMMENT END", "X3"], 2)
@example(["X1", "X2", "G1 X1\x00", "X3"], 128)
def test_runs_equal_the_lines_read_one_by_one(lines: list, chunk: int) -> None:
    """The same pairs as line by line, whatever the chunk size (runs across chunks, the bare name of a
    first line, comment ranges and NUL inside a chunk, a line with a line end inside)."""
    with mock.patch.object(reader, "CHUNK_LINES", chunk):
        fast = list(reader.iter_lines(lines, "f"))
        assert fast == _one_by_one(lines) == _one_by_one(lines, patterns=False)
        text = "\n".join(line.replace("\n", " ") for line in lines)
        assert list(reader.iter_lines(text, "f")) == _one_by_one(text)
        assert list(reader.iter_lines(io.StringIO(text, newline=None), "f")) == _one_by_one(text)
        quick = list(reader.iter_lines(lines, "f", structure_only=True))
        slow = _one_by_one(lines, structure_only=True)   # of a run read at once, only its last block
        assert _within(_last_of_runs(slow), quick) and _within(quick, slow)
        assert [p for p in quick if not _plain_structure(p)] == [p for p in slow if not _plain_structure(p)]
        assert (assemble(iter(quick), "f", keep_body=False).diagnostics
                == assemble(iter(fast), "f", keep_body=False).diagnostics)


@given(programs, st.lists(st.one_of(plain_lines, other_lines), max_size=3), st.sampled_from([1, 2, 3, 128]))
@example(["G1 X1"] * 300, [], 128)
@example(["G1 X1"] * 300, ["M3"], 128)
@example(["X1", "X2", "X3", "X4"], ["X5 Y6"], 2)
@example(["X1", "X2", "G1 X1\x00", "X3"], [], 2)
def test_chunks_a_first_reading_found_plain(lines: list, changed: list, chunk: int) -> None:
    """A reading with the PlainChunks of a reading before (the syntax check, structure only) gives what a
    reading without them gives, also when the lines changed in between (chunks of other text are read the
    usual way); the first reading fills them only when it comes to the end of its lines."""
    with mock.patch.object(reader, "CHUNK_LINES", chunk):
        chunks = reader.PlainChunks()
        assert chunks.complete is False
        list(reader.iter_lines(lines, "f", structure_only=True, chunks=chunks))
        assert chunks.complete is not any("\x00" in line for line in lines)   # a NUL ends the reading there
        taken = []
        run = reader._Reader.run

        def counting(self, *args):
            taken.append(args)
            return run(self, *args)

        with mock.patch.object(reader._Reader, "run", counting):
            assert list(reader.iter_lines(lines, "f", chunks=chunks)) == list(reader.iter_lines(lines, "f"))
            if len(lines) >= chunk and all(PLAIN_LINE(line) for line in lines[:chunk]):
                assert taken[0][1:3] == (0, chunk)   # the first chunk as one run
            middle = len(lines) // 2
            other = lines[:middle] + changed + lines[middle + 1:]
            assert list(reader.iter_lines(other, "f", chunks=chunks)) == list(reader.iter_lines(other, "f"))
        partial = reader.PlainChunks()
        next(iter(reader.iter_lines(["X1"] * 3 * chunk, "f", chunks=partial)))
        assert not partial.complete and not partial.whole(0, "X1\n" * chunk)


def test_runs_are_lists_and_other_lines_pairs() -> None:
    lines = ["%PRG", "G1 X1 Y2", "X2 Y3 ", "M3 S100", "X4", "", "X5"]
    items = list(reader.iter_runs(lines, "f"))
    assert [type(i) is list for i in items] == [False, True, False, True, False, True]
    assert items[1] == [Block(2, "G1 X1 Y2", False, None, None, (Word("G", 1.0, 1), Word("X", 1.0, 4),
                                                                Word("Y", 2.0, 7))),
                        Block(3, "X2 Y3 ", False, None, None, (Word("X", 2.0, 1), Word("Y", 3.0, 4)))]
    assert [b.line for b in items[1] + items[3] + items[5]] == [2, 3, 5, 7] and items[4] == (None, ())
    quick = list(reader.iter_runs(lines, "f", structure_only=True))
    assert quick[1] == [Block(3, "X2 Y3 ", False, None, None, ())]


@pytest.mark.parametrize("lines", [
    ["X1", "#COMMENT BEGIN", "X2", "#COMMENT END", "X3"],   # a comment range in the chunk
    ["X1", "X2\x00", "X3"],                                  # a NUL: nothing after it is read
    ["X1", "X" + "1" * 20000, "X3"],                          # an overlong line
    ["X1", "X2\nX3", "X4"],                                  # a line end inside a line of an iterable
])
def test_chunks_that_step_aside(lines: list) -> None:
    """A chunk with a NUL, a #COMMENT, an overlong line or a line end inside a line is read one line at a
    time: no run, the pairs of the lines read one by one."""
    items = list(reader.iter_runs(lines, "f"))
    assert not any(type(i) is list for i in items)
    assert items == _one_by_one(lines)


@pytest.mark.parametrize("text", ["N10 G1 X-4.6502 Y-9.9382 Z-7.8301 F2000", "X0.5000 Y0.0000 Z0.1427 ",
                                  "G1 X" + "9" * 400, "X.5 Y-.25 Z+007 A12."])
def test_split_plain_equals_split_words(text: str) -> None:
    assert PLAIN_LINE(text) is not None
    assert split_plain(text) == tuple(split_words(text, 1))


@pytest.mark.parametrize("tail", [";", " ;comment", "  ", "=1", ":", " X 1", "X"])
def test_plain_run_rejects_a_failing_line_in_linear_time(tail: str) -> None:
    """Plain lines, then one of thirty integer words (or forty "X 1" words) that fails only at its end: the
    run ends before it (a pattern that retried the lines before, or the splits of the digits, would never
    end), and the lines read as one by one."""
    for bad in (" ".join(f"{a}{'7' * 20}" for a in "XYZABCUVWIJKXYZABCUVWIJKXYZABC") + tail,
                " ".join(["X 1"] * 40) + tail):
        text = "X1 Y2\n" * 50 + bad + "\n" + "X3\n"
        assert PLAIN_RUN(text, 0).end() == 6 * 50
        lines = text[:-1].split("\n")
        assert list(reader.iter_lines(lines, "f")) == _one_by_one(lines)


def test_streamed_blocks_equal_the_parsed_program() -> None:
    """StreamSource takes a run at once: the blocks it gives are the parsed program's, local subroutines
    (plain blocks among them) and diagnostics included."""
    text = ("%L SUB\nG1 X1 Y2\nX3 Y4\nM17\n%MAIN\nG1 X1 F100\nX2\nX3\nN10: G1 X4\nX5 ;c\n"
            + "".join(f"X{i} Y{i % 7}\n" for i in range(700)) + "M30\n")
    whole = reader.parse_text(text, "f")
    for chunk in (2, 128):
        with mock.patch.object(reader, "CHUNK_LINES", chunk):
            program, source = stream_program(text, "f")
            blocks = []
            while (block := source.get(len(blocks))) is not None:
                blocks.append(block)
        assert tuple(blocks) == whole.main.blocks and program.subroutines == whole.subroutines
        assert source.find_number(10) == whole.main.numbers[10]
    program, source = stream_program("G1 X1\nX2\nX3\n", "f")   # a body without header: its first run
    assert [source.get(i).line for i in range(3)] == [1, 2, 3] and source.get(3) is None


# The plain pattern as it was written before its quantifiers were made possessive: the same language.
_WORD_BEFORE = r"[A-LN-OQ-Z][+-]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)"
_LINE_BEFORE = re.compile(rf"{_WORD_BEFORE}(?: {_WORD_BEFORE})* ?").fullmatch
_RUN_BEFORE = re.compile(rf"(?:{_WORD_BEFORE}(?: {_WORD_BEFORE})* ?\n)*").match


@given(st.text(alphabet="XYZGNMPL+-.0123 \n;:=", max_size=40))
@example("X1. Y.5 Z-0 ")
@example("X+.5")
@example("X1.2.3")
@example("X. Y1")
@example("X1  Y2")
@example("X1 \nY2\n\nX3\n")
def test_possessive_plain_pattern_is_the_same_language(text: str) -> None:
    """PLAIN_LINE takes what the pattern without possessive quantifiers took, PLAIN_RUN ends where it ended."""
    assert (PLAIN_LINE(text) is None) == (_LINE_BEFORE(text) is None)
    for pos in range(len(text) + 1):
        assert PLAIN_RUN(text, pos).end() == _RUN_BEFORE(text, pos).end()


_LONG = reader.MAX_LINE_LENGTH
_PIECES = ["", "\n", "X\r\nY", "Z\r", "\r", "X1", "X1\n", "G1 X2 Y3\n", "\n\n", "A" * _LONG, "B" * (_LONG + 1),
           "C" * (_LONG - 1), "D" * (3 * _LONG + 5)]


@settings(max_examples=150, deadline=None)
@given(parts=st.lists(st.sampled_from(_PIECES), max_size=7),
       size=st.sampled_from([1, 2, 7, 64, reader.MAX_LINE_LENGTH - 1, reader.MAX_LINE_LENGTH,
                             reader.MAX_LINE_LENGTH + 1, reader.READ_SIZE]))
def test_universal_lines_are_the_bounded_lines(parts: list, size: int) -> None:
    """A file with universal newlines read in pieces of ``size`` characters: the lines readline() gives, the
    overlong ones (one longer than a piece, or than several) as the same _Overlong start and length."""
    text = "".join(parts)

    def shown(lines) -> list:
        return [(type(x).__name__, str(x), getattr(x, "length", None)) for x in lines]

    assert shown(reader.universal_lines(io.StringIO(text, newline=None), size)) == \
        shown(reader.bounded_lines(io.StringIO(text, newline=None)))


def test_program_files_read_as_open_files(tmp_path) -> None:
    """A ProgramFile's lines (what simulate(), dry_run(), parse_file() and check read) are those of the
    same file opened by open(): CR LF, a lone CR, an overlong line, no line end at the end."""
    path = tmp_path / "p.nc"
    path.write_bytes(b"%P\r\nG1 X1 F100\rG1 X2\n" + b"X" * (reader.MAX_LINE_LENGTH + 10) + b"\nG1 X3\nM30")
    with open(path, encoding="utf-8") as f:
        expected = [(type(x).__name__, str(x)) for x in reader.bounded_lines(f)]
    with reader.ProgramFile(path, "utf-8") as f:
        assert [(type(x).__name__, str(x)) for x in reader._lines(f)] == expected
    assert len(expected) == 6 and expected[3][0] == "_Overlong"
