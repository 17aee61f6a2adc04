"""``fagorcnc.run()``: a program through interpreter and planner into a back-end.

For a real machine (any back-end but the simulator) the whole program is
checked first — parse, interpret, plan — and nothing is sent when that check
finds an error.  Then it streams: the program is read lazily, planned with
look-ahead and sent segment by segment with the back-end's back-pressure, so
memory stays flat however long the program is.  A back-end alarm, a link
failure or Ctrl-C stops the stream; the report names the last block the
machine executed.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

from .backends import Backend, BackendError, Status, get_backend
from .diagnostics import Diagnostic
from .machine import Machine, MachineError, load_machine
from .plan import Planner, PlanningError, Segment
from .plan.envelope import Envelope
from .runtime import fewer_collections
from .simulate import FinalState, dry_run, interpret, syntax_errors


@dataclass
class RunReport:
    """What :func:`run` returns.

    ``ok``: the program ran to its end without error or alarm; ``stopped_by``:
    None, ``"error"`` (program error: see ``diagnostics``), ``"alarm"`` (the
    back-end stopped: ``message``), or ``"interrupt"`` (the operator);
    ``status``: the back-end's last status (``status.line`` is the last block
    executed); ``cycle_time``: planned seconds of what was sent; ``planned_time``:
    the whole program's planned time when it was checked first.
    """

    ok: bool
    diagnostics: list[Diagnostic]
    status: Status
    cycle_time: float = 0.0
    planned_time: float | None = None
    segments: int = 0
    stopped_by: str | None = None
    message: str = ""
    backend: Backend | None = field(default=None, repr=False)
    ended_by: str | None = None     # "M30", "M02" ... or None (end of file / stopped)
    moves: int = 0                  # motion blocks (records) sent
    state: FinalState | None = field(default=None, repr=False)   # the interpreter's final state


def _unmapped(be, found: list[Diagnostic]):
    """A record watcher (see :func:`~fagorcnc.simulate.dry_run`) adding to ``found`` the auxiliary
    functions the back-end cannot execute (e.g. M8 with no InterpCNC output mapped): reported
    before anything is sent, never silently dropped."""
    check = getattr(be, "check", None)

    def watch(rec, _interp) -> None:
        if check is not None and rec.kind == "aux":
            for message in check([rec]):
                found.append(Diagnostic(rec.src.file, rec.line, 1, "CFG003", "warning", message))

    return watch


def _unsendable(be, found: list[Diagnostic]):
    """A segment watcher adding to ``found`` the planned segments the back-end could not send
    (its ``preflight``): found before the start, not half-way through the program."""
    preflight = getattr(be, "preflight", None)

    def watch(seg) -> None:
        why = preflight(seg) if preflight is not None else None
        if why:
            src = getattr(seg.record, "src", None)
            found.append(Diagnostic(src.file if src else "", seg.line, 1, "CFG004", "error", why))

    return watch


Progress = Callable[[Segment, Status, float | None], None]
#: Segments the back-end cannot send, reported at most (one cause usually repeats).
MAX_UNSENDABLE = 20


def run(source: str | Path, machine: Machine | dict | str | Path | None = None, *, backend: str | Backend = "sim",
        block_skip: bool = False, check_first: bool | None = None, progress: Progress | None = None,
        keep_profiles: bool = False, **backend_options) -> RunReport:
    """Run a program on a back-end (``"sim"`` by default, ``"interpcnc"`` for the card).

    ``check_first`` (default: True except on the plain simulator) plans the
    whole program before sending anything and refuses to start when it has an
    error; it also gives ``progress`` the total time for an ETA.
    ``progress(segment, status, total_time)`` is called after each segment.
    ``backend_options`` go to the back-end (e.g. ``host``, ``port``, ``serial``).
    """
    with fewer_collections():
        return _run(source, machine, backend, block_skip, check_first, progress, keep_profiles, backend_options)


def _run(source, machine, backend, block_skip: bool, check_first: bool | None, progress: Progress | None,
         keep_profiles: bool, backend_options: dict) -> RunReport:
    try:
        mach = load_machine(machine)
    except MachineError as exc:
        d = Diagnostic(str(machine), 1, 1, "CFG001", "error", str(exc))
        return RunReport(False, [d], Status(state="closed"), stopped_by="error", message=str(exc))
    be = backend if not isinstance(backend, str) else get_backend(backend, mach, **backend_options)
    if check_first is None:
        check_first = be.name != "sim" or bool(backend_options.get("realtime") or getattr(be, "realtime", None))
    total = None
    if check_first:   # streamed too: a program of millions of blocks is checked in constant memory
        unmapped: list[Diagnostic] = []
        unsendable: list[Diagnostic] = []
        checked = dry_run(source, mach, block_skip=block_skip, on_record=_unmapped(be, unmapped),
                          on_segment=_unsendable(be, unsendable))
        if not checked.ok or unsendable:
            return RunReport(False, [*checked.diagnostics, *unsendable[:MAX_UNSENDABLE]], be.status(),
                             stopped_by="error", message="the program has errors: nothing was sent", backend=be)
        total = checked.cycle_time
        if unmapped and getattr(getattr(be, "options", None), "strict_outputs", False):
            return RunReport(False, [*checked.diagnostics, *unmapped], be.status(), stopped_by="error",
                             message="auxiliary functions without an output mapping: nothing was sent", backend=be)
    else:   # the program streams from its file; one with a syntax or structure error anywhere is not started
        errors = syntax_errors(source)
        if errors:
            return RunReport(False, errors, be.status(), stopped_by="error",
                             message="the program has errors: nothing was run", backend=be)
    stream = interpret(source, mach, block_skip=block_skip)
    pacing = be.name == "sim" and bool(getattr(be, "realtime", None))
    planner = Planner(mach, keep_profiles=keep_profiles or pacing)
    sent, clock, moves, last = 0, 0.0, 0, None
    # PLN100 as check says it: checked before a real run (dry_run), reported after a run without that check
    envelope = None if check_first else Envelope(mach)
    stopped_by, message = None, ""
    extra: list[Diagnostic] = []
    be.open()
    try:
        for seg in planner.segments(stream):
            if envelope is not None:
                envelope.add(seg)
            be.send(seg)
            sent += 1
            if seg.kind == "motion" and not seg.blend and seg.record is not last:
                moves, last = moves + 1, seg.record
            clock = seg.t0 + seg.duration
            if progress is not None:
                progress(seg, be.status(), total)
        status = be.finish()
    except BackendError as exc:
        stopped_by, message = "alarm", str(exc)
        status = exc.status or be.status()
    except PlanningError as exc:
        stopped_by, message = "error", str(exc)
        file = exc.record.src.file if exc.record is not None else stream.program.file
        extra.append(Diagnostic(file, exc.line, 1, "PLN001", "error", str(exc)))
        status = be.finish()
    except KeyboardInterrupt:
        be.stop()
        stopped_by, message = "interrupt", "stopped by the operator (Ctrl-C)"
        status = be.status()
    finally:
        be.close()
    if check_first:
        extra += unmapped
    if envelope is not None:
        extra += envelope.diagnostics(stream.program.file)
    diagnostics = sorted([*stream.diagnostics, *extra], key=lambda d: (d.file, d.line, d.col))
    if stopped_by is None and any(d.is_error for d in diagnostics):
        beyond = all(d.code == "PLN100" for d in diagnostics if d.is_error)
        stopped_by, message = "error", ("the planned path leaves the soft limits" if beyond
                                        else "the program stopped at an error")
    return RunReport(stopped_by is None, diagnostics, status, clock, total, sent, stopped_by, message, be,
                     stream.interpreter.ended, moves, stream.state)
