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
from pathlib import Path
from typing import Protocol, Union

from ..diagnostics import Diagnostic, error
from .ast import Block, Program, ProgramHeader
from .parser import LineParser
from .structure import assemble

# "#COMMENT BEGIN" may follow a block number, as on the N-numbered blocks of CAM posts (N10 #COMMENT BEGIN)
_COMMENT_BEGIN = re.compile(r"[ \t]*(?:/[ \t]*)?(?:N[0-9]+[ \t]*:?[ \t]*)?#COMMENT[ \t]+BEGIN(?![A-Za-z0-9_])").match
_COMMENT_END = re.compile(r"[ \t]*(?:/[ \t]*)?(?:N[0-9]+[ \t]*:?[ \t]*)?#COMMENT[ \t]+END(?![A-Za-z0-9_])").match
_BARE_NAME = re.compile(r"[ \t]*([A-Za-z0-9_][A-Za-z0-9_.]*)[ \t]*").fullmatch

_parser: Union[LineParser, None] = None


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
        return iter(source.split("\n"))
    return (s.rstrip("\r\n") for s in source)


def iter_lines(source: Union[str, Iterable[str]], file: str = "<string>", compat: Compat | None = None
               ) -> Iterator[tuple]:
    """Parse a program line by line.

    ``source`` is the program text or any iterable of lines (an open file
    streams).  Yields ``(node, diagnostics)`` per line, where ``node`` is a
    :class:`~fagorcnc.syntax.ast.Block`, a header, or ``None`` (empty,
    comment or erroneous line) and ``diagnostics`` a tuple.  ``compat`` (the
    machine's ``[compat]`` policy, :mod:`fagorcnc.config.compat`) sets the
    severity of the CAM posts' constructs: program names, the bare name line,
    keywords not in capitals.
    """
    parse = line_parser().parse
    comment_start = None  # (line, text) of an open #COMMENT BEGIN
    first = True
    for lineno, text in enumerate(_lines(source), 1):
        if "\x00" in text:   # no program text holds a NUL: a binary file, or UTF-16 without its mark
            yield None, (error(file, lineno, text.index("\x00") + 1, "SYN023",
                               "this is not a program text file (it holds NUL bytes: a binary file, or text "
                               "saved as UTF-16 without a byte-order mark); nothing after this point is read", ""),)
            return
        if "#COMMENT" in text:
            if comment_start is None and _COMMENT_BEGIN(text):
                comment_start = (lineno, text)
                continue
            if _COMMENT_END(text):
                if comment_start is None:
                    yield None, (error(file, lineno, text.index("#") + 1, "SYN018",
                                       "#COMMENT END without #COMMENT BEGIN", text),)
                comment_start = None
                continue
        if comment_start is not None:
            continue
        node, diags = parse(text, lineno, file)
        if first and (node is not None or diags):
            first = False
            bare = node is None or (type(node) is Block and any(getattr(i, "value", 0) is None for i in node.items))
            if bare and (m := _BARE_NAME(text)):
                # CAM posts write the program name alone on the first line.
                node = ProgramHeader(m.group(1), lineno, text)
                diags = (Diagnostic(file, lineno, m.start(1) + 1, "STR011", "warning",
                                    f"first line '{m.group(1)}' taken as the program name: the manual's header is "
                                    f"%{m.group(1)} (seed 002 L842); CAM posts write the name alone", text),)
        if diags and compat is not None:
            diags = tuple(compat.adjust(d) for d in diags)
        yield node, diags
    if comment_start is not None:
        line, text = comment_start
        yield None, (error(file, line, text.index("#") + 1, "SYN017",
                           "#COMMENT BEGIN is never closed by #COMMENT END", text),)


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
    """Parse a program file into a :class:`Program`; ``compat`` as for :func:`iter_lines`."""
    return parse_text(read_source(path), str(path), compat)
