"""Where the interpreter takes its blocks from: a parsed routine or a stream.

:class:`RoutineSource` wraps a materialised :class:`~fagorcnc.syntax.ast.Routine`.
:class:`StreamSource` reads the main program of a file lazily, one line at a
time, so that a program of millions of blocks runs in constant memory: it
keeps only the blocks that can still be reached — those after the oldest open
``$`` structure, the oldest jump label, or an active ``#RPT`` range — and
reads ahead only when a forward jump needs it.  Local subroutines (always
before the program body, seed 002 L917) are read whole first.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Iterator
from itertools import repeat

from ..syntax.ast import Block, Program, ProgramHeader, Routine, SubroutineHeader
from ..syntax.reader import iter_runs
from ..syntax.structure import RoutineBuilder, assemble

#: Blocks :meth:`StreamSource.release` lets pile up before it drops them (the interpreter asks every 1 024
#: blocks).  Few: the blocks held are net growth of the objects the cyclic collector tracks (some nine a
#: plain block), and 50 000 of it start a collection during a dry run (:mod:`fagorcnc.runtime`) that walks
#: them all; 4 096 started one in a CAM program of 4 000 blocks (30 M instructions of 4 700 M).
RELEASE_BLOCKS = 1024


class RoutineSource:
    """Random access to the blocks of a parsed routine."""

    def __init__(self, routine: Routine) -> None:
        self.routine = routine
        self.name, self.kind = routine.name, routine.kind
        self._blocks = routine.blocks
        self._spans: list | None = None

    def get(self, i: int) -> Block | None:
        return self._blocks[i] if i < len(self._blocks) else None

    def link(self, i: int) -> int:
        return self.routine.structure[i]

    def find_number(self, n: int) -> int | None:
        return self.routine.numbers.get(n)

    def find_label(self, name: str) -> int | None:
        return self.routine.labels.get(name.upper())

    def spans(self) -> list:
        """(opener, closer) index pairs of the ``$`` structures."""
        if self._spans is None:
            self._spans = _spans(self.routine.structure, self.get)
        return self._spans

    def release(self, pc: int, keep_from: int | None = None) -> None:
        """Nothing to release: the routine is in memory anyway."""


def _spans(structure: dict, get) -> list:
    out = []
    for i, j in structure.items():
        if j < i:
            b = get(i)
            if b is not None and b.items and getattr(b.items[-1], "keyword", "").startswith("END"):
                out.append((j, i))
    return out


class StreamSource:
    """The main program of a file, read lazily (see the module docstring)."""

    def __init__(self, lines: Iterator, builder: RoutineBuilder, diagnostics: list, header: bool = True) -> None:
        self._lines = lines
        self._header = header            # a program header was read (a first one may follow body blocks)
        self._builder = builder
        self.diagnostics = diagnostics   # shared with the program; grows as lines are read
        self.name, self.kind = builder.name, "program"
        self._base = 0                   # index of builder.blocks[0]
        self._done = False
        self.released = 0                # blocks dropped so far (for tests and benchmarks)
        self._seen: tuple = (None, 0, False)   # (diagnostics list, how many looked at, an error among them)

    def has_error(self) -> bool:
        """Whether a diagnostic read so far is an error (a syntax error ahead stops the run): only the
        diagnostics added since the last call are looked at, so a stream of warnings stays linear."""
        diagnostics = self.diagnostics
        listed, seen, error = self._seen
        n = len(diagnostics)
        if listed is not diagnostics or n < seen:   # the list was replaced or emptied: look again
            seen, error = 0, False
        if n > seen and not error:
            error = any(d.is_error for d in diagnostics[seen:])
        self._seen = (diagnostics, n, error)
        return error

    # -- reading
    def _read_one(self) -> bool:
        """Read the next block, or the next run of plain blocks (:func:`~fagorcnc.syntax.reader.iter_runs`);
        False at the end of the program."""
        for item in self._lines:
            if type(item) is list:
                self._builder.add_run(item)
                return True
            node, diags = item
            if diags:
                self.diagnostics.extend(diags)
            if node is None:
                continue
            if type(node) is Block:
                self._builder.add(node)
                return True
            if type(node) is ProgramHeader and not self._header:
                # the first header after blocks of the body names the program, as in assemble()
                self._header = True
                self._builder.name = self.name = node.name
                continue
            # a header inside the body: let assemble-style rules report it
            self.diagnostics.extend(_late_header(node, self._builder.file))
        if not self._done:
            self._done = True
            self._builder.finish()
            self.diagnostics.extend(self._builder.diagnostics)
            self._builder.diagnostics = []
        return False

    def _available(self) -> int:
        return self._base + len(self._builder.blocks)

    def get(self, i: int) -> Block | None:
        blocks = self._builder.blocks
        while i >= self._base + len(blocks):   # self._available(), inline (one call per block)
            if not self._read_one():
                return None
            blocks = self._builder.blocks
        if i < self._base:
            raise IndexError(f"block {i} was released from memory")
        return blocks[i - self._base]

    def link(self, i: int) -> int:
        structure = self._builder.structure
        while i not in structure:
            if not self._read_one():
                raise KeyError(i)
        return structure[i]

    def find_number(self, n: int) -> int | None:
        while n not in self._builder.numbers:
            if not self._read_one():
                return None
        return self._builder.numbers[n]

    def find_label(self, name: str) -> int | None:
        key = name.upper()
        while key not in self._builder.labels:
            if not self._read_one():
                return None
        return self._builder.labels[key]

    def spans(self) -> list:
        """As :meth:`ProgramSource.spans`, and the structures still open where the reading stands: their
        closer lies beyond every block read so far, a jump target among them included (seed 002 L17072)."""
        closed = _spans(self._builder.structure, lambda i: self.get(i) if i >= self._base else _KEPT)
        return closed + [(entry.index, math.inf) for entry in self._builder.stack]

    def release(self, pc: int, keep_from: int | None = None) -> None:
        """Drop blocks before ``pc`` that no jump or loop can reach again."""
        b = self._builder
        anchor = pc
        if keep_from is not None:
            anchor = min(anchor, keep_from)
        if b.stack:
            anchor = min(anchor, b.stack[0].index)
        for targets in (b.numbers, b.labels):   # jump targets: the first one added is the oldest
            if targets:
                anchor = min(anchor, next(iter(targets.values())))
        drop = anchor - self._base
        if drop > RELEASE_BLOCKS:  # release in chunks; the list slice is O(kept)
            del b.blocks[:drop]
            self._base += drop
            self.released += drop
            # keep the builder's own indexes valid for new blocks
            b.offset = self._base


class _Kept:
    items = ()


_KEPT = _Kept()


def _late_header(node, file: str) -> list:
    from ..diagnostics import error

    if type(node) is SubroutineHeader:
        return [error(file, node.line, 1, "STR002", f"local subroutine {node.name} must be defined before the "
                      "program header and body (seed 002 L917)", node.text)]
    if type(node) is ProgramHeader:
        return [error(file, node.line, 1, "STR010", f"second program header %{node.name} in one file", node.text)]
    return []


def stream_program(lines: Iterable[str], file: str, compat=None, chunks=None) -> tuple[Program, StreamSource]:
    """Read the local subroutines and header of a file; stream its body.

    Returns a :class:`Program` whose ``main`` routine is empty and the
    :class:`StreamSource` that yields the body.  ``chunks``: the
    :class:`~fagorcnc.syntax.reader.PlainChunks` of a reading of the same lines before (the syntax check).
    """
    it = iter_runs(lines, file, compat, chunks=chunks)   # compat: the machine's [compat] policy
    head: list = []
    body: list = []   # the first block of the body, and the rest of its run of plain blocks
    header = False
    for item in it:
        if type(item) is list:   # a run of plain blocks
            if not any(type(n) is SubroutineHeader for n, _ in head):
                body = list(zip(item, repeat(())))
                break
            head.extend(zip(item, repeat(())))
            continue
        head.append(item)
        if type(item[0]) is ProgramHeader:
            header = True
            break
        if type(item[0]) is Block and not any(type(n) is SubroutineHeader for n, _ in head):
            body = [head.pop()]
            break
    program = assemble(iter(head), file)
    builder = RoutineBuilder(program.main.name, "program", program.main.line, file)
    for block in program.main.blocks:
        builder.add(block)
    diagnostics = list(program.diagnostics)
    source = StreamSource(it, builder, diagnostics, header)
    for block, diags in body:
        diagnostics.extend(diags)
        builder.add(block)
    return program, source
