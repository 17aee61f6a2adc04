"""``fagorcnc check``'s error recovery: the errors beyond the first, in one streamed pass.

The control stops at a program's first error (seed 002: a block in error stops the
execution), so a check that stopped there too would show one error per CI round.  After the
check's own pass (what the control would do, up to its first error) *one* more pass
interprets the file again, streamed as the first, in **recovery mode**: a block in error is
reported and skipped as if its line were blank, and the run goes on to the end (lines with a
syntax error are skipped the same way).  The runaway guards (INT080-INT082) still end the pass,
so it costs at most the first pass's time again and its memory does not grow with the program.

What that pass finds is marked *recovered* in the report: it may be a consequence of a skipped
block.  :class:`Findings` keeps the report bounded: at most ``per_code`` diagnostics of each
code are listed (the first ones, in file order), the others are counted ("N more not shown").
"""

from __future__ import annotations

import logging
from collections.abc import Iterable
from dataclasses import dataclass, field
from pathlib import Path

from ..config.machine import Machine
from ..diagnostics import Diagnostic

log = logging.getLogger(__name__)

#: Diagnostics listed per code by default (``--max-per-code``; 0 = all).
MAX_PER_CODE = 20
#: Runaway guards that spent the run's budget: a recovery pass would spend it again.
BUDGET_CODES = ("INT080", "INT082")


def _key(d: Diagnostic) -> tuple:
    return d.file, d.line, d.code, d.message


class _Ignored:
    """A diagnostics list that keeps nothing: the syntax errors a recovery pass reads again were all
    reported by the check's syntax pass."""

    def append(self, _d: Diagnostic) -> None:
        return None

    def extend(self, _ds: Iterable[Diagnostic]) -> None:
        return None

    def __iter__(self):
        return iter(())


@dataclass
class Findings:
    """The diagnostics of a recovery pass, bounded (an interpreter's ``diagnostics`` sink).

    ``known``: keys of what the first pass reported (not repeated); ``per_code``: diagnostics kept
    per code, counting the first pass's (0 = no limit).  ``kept`` holds the new ones, ``more`` how
    many others there were per (code, severity): occurrences, so an error inside a loop repeated
    100 times counts 100.
    """

    known: set
    per_code: int = MAX_PER_CODE
    kept: list[Diagnostic] = field(default_factory=list)
    more: dict[tuple[str, str], int] = field(default_factory=dict)
    _per: dict[str, int] = field(default_factory=dict)
    _kept_keys: set = field(default_factory=set)

    def count_known(self, diagnostics: Iterable[Diagnostic]) -> None:
        """Count the first pass's diagnostics against the per-code limit."""
        for d in diagnostics:
            self._per[d.code] = self._per.get(d.code, 0) + 1

    def append(self, d: Diagnostic) -> None:
        key = _key(d)
        if key in self.known or key in self._kept_keys:
            return
        n = self._per.get(d.code, 0)
        if self.per_code and n >= self.per_code:
            slot = (d.code, d.severity)
            self.more[slot] = self.more.get(slot, 0) + 1
            return
        self._per[d.code] = n + 1
        self._kept_keys.add(key)
        self.kept.append(d)

    def extend(self, ds: Iterable[Diagnostic]) -> None:
        for d in ds:
            self.append(d)

    def __iter__(self):
        return iter(self.kept)


def recovery_pass(path: Path, machine: Machine, block_skip: bool, first: list[Diagnostic],
                  per_code: int = MAX_PER_CODE) -> Findings:
    """The errors (and warnings) beyond ``first`` (what the check's pass reported), from one more streamed
    pass in recovery mode (see the module docstring)."""
    from ..config.parameter_file import attach_parameter_file
    from ..interp.interpreter import Interpreter
    from ..interp.source import stream_program
    from ..runtime import fewer_collections
    from ..syntax import source_encoding

    findings = Findings({_key(d) for d in first}, per_code)
    findings.count_known(first)
    if any(d.code in BUDGET_CODES or d.code == "SYN023" or (d.code.startswith("STR") and d.is_error)
           for d in first):
        # the runaway budget is spent; a file that is not program text (SYN023) or whose structure is
        # broken ($IF without $ENDIF...) cannot be run by skipping lines
        return findings
    name = str(path)
    try:
        with fewer_collections(), open(path, encoding=source_encoding(path), errors="replace") as lines:
            program, body = stream_program(lines, name, machine.compat)
            body.diagnostics = _Ignored()
            interp = Interpreter(program, machine, block_skip=block_skip, stream=body, recover=True)
            attach_parameter_file(interp)   # the same starting parameters as the first pass; never saved
            interp.diagnostics = findings   # type: ignore[assignment]  # bounded sink, see Findings
            for _record in interp.run():
                pass
    except (RecursionError, MemoryError, OSError) as exc:
        # the pass only looks further than the control would: what it found so far stands
        log.debug("check: recovery pass of %s stopped: %s", name, exc)
    return findings
