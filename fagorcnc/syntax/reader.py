"""Reading a file: the line pre-pass, streaming, and whole-program parsing.

:func:`iter_lines` streams ``(node, diagnostics)`` for every line of a source
in constant memory (a generator over the lines).  It removes
``#COMMENT BEGIN ... #COMMENT END`` ranges, whose content is free text
(seed 002 L1786-L1804), and accepts the bare program-name first line that CAM
posts emit (``FINISH01`` alone on line 1) as a program header.

:func:`parse_text` and :func:`parse_file` build a whole :class:`Program`.
"""

from __future__ import annotations

import codecs
import gc
import re
from collections.abc import Iterable, Iterator
from itertools import chain, count, islice, repeat
from pathlib import Path
from typing import Protocol, Union

from ..diagnostics import Diagnostic, error
from .ast import Block, Program, ProgramHeader
from .builder import split_plain, split_plain_lines
from .parser import PLAIN_LINE, PLAIN_RUN, LineParser
from .structure import assemble

# "#COMMENT BEGIN" may follow a block number, as on the N-numbered blocks of CAM posts (N10 #COMMENT BEGIN)
_COMMENT_BEGIN = re.compile(r"[ \t]*(?:/[ \t]*)?(?:N[0-9]+[ \t]*:?[ \t]*)?#COMMENT[ \t]+BEGIN(?![A-Za-z0-9_])").match
_COMMENT_END = re.compile(r"[ \t]*(?:/[ \t]*)?(?:N[0-9]+[ \t]*:?[ \t]*)?#COMMENT[ \t]+END(?![A-Za-z0-9_])").match
_BARE_NAME = re.compile(r"[ \t]*([A-Za-z0-9_][A-Za-z0-9_.]*)[ \t]*").fullmatch

_parser: Union[LineParser, None] = None
_new = tuple.__new__   # a Block made from its field values, as LineParser.parse makes it


class Compat(Protocol):
    """The machine's ``[compat]`` policy as the front end sees it (``fagorcnc.config.compat.Compat``):
    the severity of the CAM posts' constructs.  Without one, they are warnings (the default policy)."""

    def adjust(self, diag: Diagnostic) -> Diagnostic: ...


def line_parser() -> LineParser:
    """The process-wide :class:`LineParser` (the grammar is compiled once)."""
    global _parser
    if _parser is None:
        _parser = LineParser()
    return _parser


#: The byte-order mark, as it reads in a text decoded as UTF-8.
BOM = "\ufeff"


#: Longest line read, in characters.  The manual gives no block length; a line longer than this
#: is not held in memory: it is one SYN041 error and reading resumes at the next line (a file of
#: gigabytes without a line end is read in constant memory).  [CONSTRUCTION]
MAX_LINE_LENGTH = 16384


class _Overlong(str):
    """The start of a line longer than :data:`MAX_LINE_LENGTH`; ``length`` is its full length."""

    length: int


def _overlong(start: str, length: int) -> _Overlong:
    line = _Overlong(start[:80])
    line.length = length
    return line


def bounded_lines(file) -> Iterator[str]:
    """The lines of an open text file without their line ends, each read with at most
    :data:`MAX_LINE_LENGTH` characters in memory; a longer one comes as an :class:`_Overlong`
    (its start and length) and the rest of it is skipped, read in chunks."""
    limit = MAX_LINE_LENGTH
    readline = file.readline
    while True:
        line = readline(limit + 1)
        if not line:
            return
        if len(line) > limit and not line.endswith(("\n", "\r")):
            length, start = len(line), line
            while True:
                rest = readline(1 << 16)
                if not rest:
                    break
                length += len(rest.rstrip("\r\n"))
                if rest.endswith(("\n", "\r")):
                    break
            yield _overlong(start, length)
            continue
        yield line.rstrip("\r\n")


#: Characters :func:`universal_lines` reads at a time.
READ_SIZE = 1 << 16


class ProgramFile:
    """A program file fagorcnc opens itself as :func:`open` opens a text file, with universal newlines (its
    text holds no ``"\r"``: every line end is read as ``"\n"``), so that its lines can be read in large
    pieces (:func:`universal_lines`) rather than one :meth:`readline` each: the lines the reader takes
    from it are :func:`bounded_lines`' of the same open file.  A context manager; :meth:`close` closes it."""

    __slots__ = ("file",)

    def __init__(self, path: Union[str, Path], encoding: str, errors: str = "strict") -> None:
        self.file = open(path, encoding=encoding, errors=errors)  # noqa: SIM115 - closed by close(): newline=None, universal

    def close(self) -> None:
        self.file.close()

    def __enter__(self) -> ProgramFile:
        return self

    def __exit__(self, *exc) -> None:
        self.file.close()


def universal_lines(file, size: int = READ_SIZE) -> Iterator[str]:
    """:func:`bounded_lines` of a text file read with universal newlines (a :class:`ProgramFile`'s: its
    line ends are ``"\n"`` alone), read ``size`` characters at a time and split at its line ends: the
    same lines, an :class:`_Overlong` for a line longer than :data:`MAX_LINE_LENGTH` (with at most
    ``MAX_LINE_LENGTH + size`` characters of it in memory).  The lines of each piece in a list, handed on
    by ``chain`` (no generator step a line)."""
    return chain.from_iterable(_universal_pieces(file, size))


def _universal_pieces(file, size: int) -> Iterator[list]:
    """The lines of :func:`universal_lines`, in a list for each piece read."""
    limit = MAX_LINE_LENGTH
    read = file.read
    rest = ""   # the start of a line whose end is still to be read
    chunk = read(size)
    while chunk:
        lines = (rest + chunk).split("\n")
        rest = lines.pop()
        if lines:
            yield lines if max(map(len, lines)) <= limit else \
                [_overlong(line, len(line)) if len(line) > limit else line for line in lines]
        if len(rest) > limit:   # an overlong line: the rest of it is only counted, up to its end
            start, length = rest, len(rest)
            while (chunk := read(size)) and (end := chunk.find("\n")) < 0:
                length += len(chunk)
            if not chunk:   # the file ends in that line
                yield [_overlong(start, length)]
                return
            yield [_overlong(start, length + end)]
            rest, chunk = "", chunk[end + 1:]   # the lines after it, then more
            if chunk:
                continue
        chunk = read(size)
    if rest:
        yield [rest]


def _capped(lines: Iterable[str]) -> Iterator[str]:
    for line in lines:
        yield line if len(line) <= MAX_LINE_LENGTH else _overlong(line, len(line))


def _lines(source: Union[str, Iterable[str]]) -> Iterator[str]:
    if isinstance(source, str):
        if source.startswith(BOM):
            source = source[1:]   # text decoded as plain UTF-8 keeps an editor's byte-order mark
        # Only line ends separate blocks: str.splitlines() would also split on
        # \x85, \x0c, \u2028..., which can stand inside comments.
        # CR LF and a lone CR end a line too (universal newlines, like open()).
        if "\r" in source:
            source = source.replace("\r\n", "\n").replace("\r", "\n")
        if source.endswith("\n"):
            source = source[:-1]
        elif not source:
            return iter(())
        return _capped(source.split("\n"))
    if type(source) is ProgramFile:
        return universal_lines(source.file)
    if hasattr(source, "readline"):   # an open file: never a whole line of unbounded length in memory
        return bounded_lines(source)
    return _capped(s.rstrip("\r\n") for s in source)


#: Lines taken from the source at a time (:func:`iter_runs`); a run of plain lines is at most this long.
CHUNK_LINES = 128


class PlainChunks:
    """Which chunks of a source's lines (:data:`CHUNK_LINES` at a time, in order) :func:`iter_runs` found to be
    one run of plain lines each, on a first reading, so that a second reading of the same lines (a dry run
    after its syntax check) takes them so without :data:`~fagorcnc.syntax.parser.PLAIN_RUN`: the hash of each
    such chunk's text, None for the others.  A chunk of the second reading is taken so when the first met
    a chunk of the same text (hash) at the same place, else it is read as without.  Some 36 bytes a chunk.
    The first reading to come to the end of its lines fills it; any reading after that only reads it."""

    __slots__ = ("_hashes", "complete")

    def __init__(self) -> None:
        self._hashes: list = []
        self.complete = False

    def note(self, index: int, text: str, whole: bool) -> None:
        """Chunk ``index`` of text ``text`` (each line ended by "\\n"), one plain run (``whole``) or not, while
        the first reading goes on."""
        if not self.complete and index == len(self._hashes):
            self._hashes.append(hash(text) if whole else None)

    def whole(self, index: int, text: str) -> bool:
        """Whether chunk ``index`` of text ``text`` is one run of plain lines, as the first reading found it."""
        hashes = self._hashes
        return self.complete and index < len(hashes) and hashes[index] is not None and hashes[index] == hash(text)


def iter_lines(source: Union[str, Iterable[str]], file: str = "<string>", compat: Compat | None = None,
               *, structure_only: bool = False, chunks: PlainChunks | None = None) -> Iterator[tuple]:
    """Parse a program line by line.

    ``source`` is the program text or any iterable of lines (an open file
    streams).  Yields ``(node, diagnostics)`` per line, where ``node`` is a
    :class:`~fagorcnc.syntax.ast.Block`, a header, or ``None`` (empty,
    comment or erroneous line) and ``diagnostics`` a tuple.  ``compat`` (the
    machine's ``[compat]`` policy, :mod:`fagorcnc.config.compat`) sets the
    severity of the CAM posts' constructs: program names, the bare name line,
    keywords not in capitals.  ``structure_only=True`` (the syntax check of a whole file before
    it runs): the same diagnostics, but plain blocks of literal words (which cannot end a subroutine)
    carry no items (:meth:`~fagorcnc.syntax.parser.LineParser.parse`), and of a run of such blocks one
    after the other only the last is yielded (:func:`iter_runs`); ``chunks`` as for :func:`iter_runs`.
    """
    for item in iter_runs(source, file, compat, structure_only=structure_only, chunks=chunks):
        if type(item) is list:
            yield from zip(item, repeat(()))
        else:
            yield item


def iter_runs(source: Union[str, Iterable[str]], file: str = "<string>", compat: Compat | None = None,
              *, structure_only: bool = False, chunks: PlainChunks | None = None) -> Iterator:
    """:func:`iter_lines`' pairs, except that the blocks of a run of plain lines (:data:`PLAIN_LINE`'s, one
    after the other, outside a ``#COMMENT`` range) come as one list of :class:`Block`, without diagnostics
    (``structure_only``: a list of the run's last block only).

    Speed: the source's lines are taken :data:`CHUNK_LINES` at a time (memory stays bounded) and, when a
    chunk holds no NUL, no ``#COMMENT``, no overlong line and no open comment range, its runs of plain
    lines are found by one :data:`~fagorcnc.syntax.parser.PLAIN_RUN` call each; every other line is read
    as before, one by one (:meth:`_Reader.line`).  ``tests/test_plain_runs.py`` checks both ways.  ``chunks``
    (:class:`PlainChunks`): filled with the chunks that are one run of plain lines by the first reading of the
    source that comes to its end; a later one takes them so without the pattern.
    """
    reader = _Reader(file, compat, structure_only)
    lines = _lines(source)
    lineno = 1
    index = 0   # of the chunk
    while chunk := list(islice(lines, CHUNK_LINES)):
        text = "\n".join(chunk) + "\n"
        if (reader.comment_start is None and "\x00" not in text and "#COMMENT" not in text
                and text.count("\n") == len(chunk) and _Overlong not in set(map(type, chunk))):
            if chunks is not None and chunks.whole(index, text):
                yield reader.run(chunk, 0, len(chunk), lineno)   # what runs() makes of it, without the pattern
                reader.first = False
            else:
                reader.whole = False
                yield from reader.runs(chunk, text, lineno)
                if chunks is not None:
                    chunks.note(index, text, reader.whole)
        else:
            if chunks is not None:
                chunks.note(index, text, False)
            for n, line in enumerate(chunk, lineno):
                pair = reader.line(line, n)
                if pair is not None:
                    yield pair
                if reader.stopped:
                    return
        lineno += len(chunk)
        index += 1
    if chunks is not None:
        chunks.complete = True
    if reader.comment_start is not None:
        line, text = reader.comment_start
        yield None, (error(file, line, text.index("#") + 1, "SYN017",
                           "#COMMENT BEGIN is never closed by #COMMENT END", text),)


class _Reader:
    """The state of one :func:`iter_runs`: an open ``#COMMENT BEGIN``, whether the first line that says
    something is still to come (a bare program name), and a NUL met (nothing more is read)."""

    def __init__(self, file: str, compat: Compat | None, structure_only: bool) -> None:
        self.file, self.compat, self.structure_only = file, compat, structure_only
        self.parse = line_parser()._parse_fast   # LineParser.parse of a line PLAIN_LINE does not take
        self.comment_start: tuple | None = None   # (line, text) of an open #COMMENT BEGIN
        self.first = True
        self.stopped = False
        self.whole = False   # the chunk runs() read last was one run of plain lines

    def runs(self, chunk: list, text: str, lineno: int) -> Iterator:
        """The items of a chunk of lines (``text``: the lines each ended by "\\n", starting at line
        ``lineno``) that holds no NUL, ``#COMMENT`` or overlong line: its runs of plain lines as lists, each
        other line as :meth:`parsed` reads it (:attr:`whole` when it is one run)."""
        pos = i = 0
        n = len(chunk)
        while i < n:
            end = PLAIN_RUN(text, pos).end()
            if end > pos:
                k = text.count("\n", pos, end)
                yield self.run(chunk, i, k, lineno + i)
                self.first = False
                i += k
                pos = end
                if i == n:
                    self.whole = k == n
                    return
            line = chunk[i]
            yield self.parsed(line, lineno + i)
            pos += len(line) + 1
            i += 1

    def run(self, chunk: list, i: int, k: int, lineno: int) -> list:
        """The blocks of the plain lines ``chunk[i:i + k]``, the first on line ``lineno``."""
        if self.structure_only:
            return [_new(Block, (lineno + k - 1, chunk[i + k - 1], False, None, None, ()))]
        lines = chunk[i:i + k]
        return list(map(_new, repeat(Block), zip(count(lineno), lines, repeat(False), repeat(None), repeat(None),
                                                  split_plain_lines(lines))))

    def line(self, text: str, lineno: int) -> tuple | None:
        """The ``(node, diagnostics)`` of any line, or None for a line of a ``#COMMENT`` range (or its
        ends); :attr:`stopped` once a NUL is met."""
        file = self.file
        if type(text) is _Overlong:
            return None, (error(file, lineno, MAX_LINE_LENGTH + 1, "SYN041",
                                f"this line is {text.length} characters long, more than the {MAX_LINE_LENGTH} "
                                "fagorcnc reads in a block: it is not read (reading goes on at the next line)",
                                str(text)),)
        if "\x00" in text:   # no program text holds a NUL: a binary file, or UTF-16 without its mark
            self.stopped = True
            return None, (error(file, lineno, text.index("\x00") + 1, "SYN023",
                                "this is not a program text file (it holds NUL bytes: a binary file, or text "
                                "saved as UTF-16 without a byte-order mark); nothing after this point is read", ""),)
        if "#COMMENT" in text:
            if self.comment_start is None and _COMMENT_BEGIN(text):
                self.comment_start = (lineno, text)
                return None
            if _COMMENT_END(text):
                opened, self.comment_start = self.comment_start, None
                if opened is None:
                    return None, (error(file, lineno, text.index("#") + 1, "SYN018",
                                        "#COMMENT END without #COMMENT BEGIN", text),)
                return None
        if self.comment_start is not None:
            return None
        if PLAIN_LINE(text) is not None:   # LineParser.parse's first case, without its call
            self.first = False
            return _new(Block, (lineno, text, False, None, None, () if self.structure_only else split_plain(text))), ()
        return self.parsed(text, lineno)

    def parsed(self, text: str, lineno: int) -> tuple:
        """The ``(node, diagnostics)`` of a line outside a ``#COMMENT`` range, without NUL, not overlong, that
        :data:`PLAIN_LINE` does not take: :meth:`LineParser.parse`'s, a bare program name on the first line
        that says something, the diagnostics under the ``[compat]`` policy."""
        file = self.file
        node, diags = self.parse(text, lineno, file, self.structure_only)
        if self.first and (node is not None or diags):
            self.first = False
            bare = node is None or (type(node) is Block and any(getattr(i, "value", 0) is None for i in node.items))
            if bare and (m := _BARE_NAME(text)):
                # CAM posts write the program name alone on the first line.
                node = ProgramHeader(m.group(1), lineno, text)
                diags = (Diagnostic(file, lineno, m.start(1) + 1, "STR011", "warning",
                                    f"first line '{m.group(1)}' taken as the program name: the manual's header is "
                                    f"%{m.group(1)} (seed 002 L842); CAM posts write the name alone", text),)
        if diags and self.compat is not None:
            diags = tuple(self.compat.adjust(d) for d in diags)
        return node, diags


def parse_text(text: str, file: str = "<string>", compat: Compat | None = None) -> Program:
    """Parse program text into a :class:`Program` (never raises on bad input); ``compat`` as
    for :func:`iter_lines`."""
    # The AST is millions of small immutable tuples that can never form a
    # reference cycle; the cyclic collector would rescan them over and over
    # while they accumulate, so it is paused for the duration.
    enabled = gc.isenabled()
    gc.disable()
    try:
        return assemble(iter_lines(text, file, compat), file)
    finally:
        if enabled:
            gc.enable()


def read_source(path: Union[str, Path]) -> str:
    """Read a program file: UTF-8, or Latin-1 for files written by older editors (see
    :func:`source_encoding`, the one place that rule is made)."""
    return Path(path).read_bytes().decode(source_encoding(path))


def source_encoding(path: Union[str, Path]) -> str:
    """The encoding of a program file: ``"utf-16"`` when it starts with a UTF-16 byte-order mark,
    ``"utf-8-sig"`` (UTF-8, without the byte-order mark some Windows editors write first, which
    would stand before the header), or ``"latin-1"`` (files written by older editors) when it is
    not valid UTF-8; found by reading it in chunks, in constant memory, so a program read lazily
    line by line is decoded as :func:`read_source` decodes it whole."""
    decoder = codecs.getincrementaldecoder("utf-8")()
    with open(path, "rb") as f:
        if f.read(2) in (codecs.BOM_UTF16_LE, codecs.BOM_UTF16_BE):
            return "utf-16"   # Windows Notepad's "Unicode": its byte-order mark says which
        f.seek(0)
        try:
            while chunk := f.read(1 << 20):
                decoder.decode(chunk)
            decoder.decode(b"", final=True)
        except UnicodeDecodeError:
            return "latin-1"
    return "utf-8-sig"


def parse_file(path: Union[str, Path], compat: Compat | None = None) -> Program:
    """Parse a program file into a :class:`Program`, read line by line (:func:`universal_lines`:
    the text is never held whole, and a line longer than :data:`MAX_LINE_LENGTH` is SYN041);
    ``compat`` as for :func:`iter_lines`."""
    enabled = gc.isenabled()
    gc.disable()   # as in parse_text
    try:
        with ProgramFile(path, source_encoding(path), "replace") as f:
            return assemble(iter_lines(f, str(path), compat), str(path))
    finally:
        if enabled:
            gc.enable()
