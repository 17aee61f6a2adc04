"""The run summary every entry point gives: how many moves, and what ended the run.

One model for :func:`fagorcnc.run`, ``fagorcnc check``, :func:`fagorcnc.simulate` and
:func:`fagorcnc.dry_run` (issue 25.6), so that they agree on a program:

* **moves**: the motion blocks executed (the interpreter's motion records: linear, rapid,
  arc...; not auxiliary functions or dwells), a move of zero length included.  A run stopped
  by the back-end counts the moves up to the last one the back-end was given
  (:class:`MoveCounter`);
* **ending** (:class:`Ending`): the real cause -- ``M30``, ``M02``, ``end of file``,
  ``error at line L``, ``alarm N at line L``, ``link lost at line L``, ``stopped by the user
  at line L``, or ``not started`` (syntax errors, or a run refused by its check).

Back-ends tell an alarm from a lost link through the :class:`~fagorcnc.backends.BackendError`
they raise (see :func:`backend_ending`): an ``alarm`` attribute (the alarm code, 0 for a
link failure) or else the status' ``alarm``; ``fault = "link"`` on the exception, or a status
``alarm_message`` starting with ``"link lost"``, says the link was lost; ``line`` on the
exception (else the status' ``line``) is the last block the machine started.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Callable, Iterable, Iterator
from dataclasses import dataclass

from .diagnostics import Diagnostic

#: The causes an :class:`Ending` may name.
CAUSES = ("M30", "M02", "end of file", "error", "alarm", "link lost", "stopped by the user", "not started")
#: Record kinds that are not moves.
NOT_MOVES = frozenset({"aux", "dwell"})


@dataclass(frozen=True)
class Ending:
    """What ended a run: ``cause`` (one of :data:`CAUSES`), the ``line`` it happened at (0 when it does not
    apply), the ``alarm`` code for an alarm, the ``file`` of the line when it is not the program's own."""

    cause: str
    line: int = 0
    alarm: int = 0
    file: str = ""

    @property
    def program_end(self) -> str | None:
        """``"M30"`` or ``"M02"`` when the program ended itself that way, else None."""
        return self.cause if self.cause in ("M30", "M02") else None

    def __str__(self) -> str:
        where = f" at line {self.line}" if self.line else ""
        if not self.line and self.cause in ("alarm", "link lost", "stopped by the user"):
            where = " before the first block ran"   # the machine reported no executed block yet
        if self.file:
            where += f" of {self.file}"
        if self.cause == "alarm":
            return f"alarm {self.alarm}{where}"
        if self.cause in ("error", "link lost", "stopped by the user"):
            return f"{self.cause}{where}"
        if self.cause == "not started":
            return f"not started (error{where})" if self.line else "not started"
        return self.cause

    def to_dict(self) -> dict:
        return {"cause": self.cause, "line": self.line, "alarm": self.alarm, "file": self.file or None,
                "text": str(self)}


@dataclass(frozen=True)
class RunSummary:
    """Moves executed and the ending (see the module docstring)."""

    moves: int
    ending: Ending

    def __str__(self) -> str:
        return f"{self.moves} moves, ended by {self.ending}"


def is_move(record) -> bool:
    """Whether a record counts as a move."""
    return record.kind not in NOT_MOVES


def _at(d: Diagnostic, main_file: str, cause: str = "error") -> Ending:
    return Ending(cause, d.line, file="" if d.file == main_file else d.file)


def stopping_error(run_order: Iterable[Diagnostic], planning: Diagnostic | None = None) -> Diagnostic | None:
    """The error a run stopped at: a planning error (PLN001: the planner stops there, the interpreter had
    gone on), else the first error in the order the interpreter reported them (it stops at its first)."""
    if planning is not None:
        return planning
    return next((d for d in run_order if d.is_error), None)


def program_ending(ended: str | None, stop: Diagnostic | None, main_file: str) -> Ending:
    """The ending of an interpreted run: at its stopping error, else its ``M30``/``M02``, else the end of file."""
    if stop is not None:
        return _at(stop, main_file)
    if ended in ("M30", "M02"):
        return Ending(ended)
    return Ending("end of file")


def not_started(errors: Iterable[Diagnostic], main_file: str) -> Ending:
    """A run that did not start: its first error in file order (a syntax error, or what its check found)."""
    first = min((d for d in errors if d.is_error), key=lambda d: (d.file != main_file, d.file, d.line, d.col),
                default=None)
    return _at(first, main_file, "not started") if first is not None else Ending("not started")


def backend_ending(exc: BaseException, status) -> Ending:
    """The ending of a run the back-end stopped (see the module docstring for what it reads)."""
    alarm = getattr(exc, "alarm", None)
    if alarm is None:
        alarm = getattr(status, "alarm", 0) or 0
    line = getattr(exc, "line", 0) or getattr(status, "line", 0) or 0
    message = getattr(status, "alarm_message", "") or ""
    if getattr(exc, "fault", None) == "link" or (not alarm and message.startswith("link lost")):
        return Ending("link lost", line)
    if alarm:
        return Ending("alarm", line, int(alarm))
    return Ending("error", line)


def interrupted(status) -> Ending:
    """The ending of a run the operator stopped (Ctrl-C)."""
    return Ending("stopped by the user", getattr(status, "line", 0) or 0)


class MoveCounter:
    """Counts the moves of a record stream on its way to the planner, and tells how many of them a
    back-end was given: :meth:`sent` with the record of each segment sent (records in the planner's
    look-ahead are not counted until a segment of theirs, or of a record after them, is sent)."""

    def __init__(self, records: Iterable, on_move: Callable[[object], None] | None = None) -> None:
        self._records = iter(records)
        self._on_move = on_move        # called with each move as it counts as given to the back-end
        self.moves = 0                 # moves that entered the planner
        self.sent_moves = 0            # moves up to the last record a segment was sent for
        self._pending: deque = deque()

    def __iter__(self) -> Iterator:
        return self

    def __next__(self):
        rec = next(self._records)
        if is_move(rec):
            self.moves += 1
        self._pending.append((rec, self.moves))
        return rec

    def sent(self, record) -> None:
        """A segment of ``record`` was sent: every move up to it counts as given to the back-end."""
        if record is None:
            return
        pending = self._pending
        while pending:
            rec, n = pending[0]
            self._count(n, rec)
            if rec is record:
                return
            pending.popleft()

    def _count(self, n: int, rec) -> None:
        if n > self.sent_moves:
            self.sent_moves = n
            if self._on_move is not None:
                self._on_move(rec)

    def finished(self) -> None:
        """Everything planned was sent (the run ended normally)."""
        for rec, n in self._pending:
            self._count(n, rec)
        self.sent_moves = self.moves
        self._pending.clear()
