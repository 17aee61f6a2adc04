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

import argparse
import contextlib
import dataclasses
import os
import sys
import tempfile
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

from ..backends import Backend, BackendError, Status, get_backend
from ..config.machine import Machine, MachineError, load_machine
from ..diagnostics import Diagnostic
from ..plan import Planner, PlanningError, Segment, planning_code
from ..plan.envelope import Envelope
from ..program_files import resolve, source_name
from ..runtime import fewer_collections
from ..simulate import FinalState, dry_run, interpret, syntax_errors
from ..summary import (
    Ending,
    MoveCounter,
    RunSummary,
    backend_ending,
    interrupted,
    not_started,
    program_ending,
    stopping_error,
)
from ._shared import STDIN_NAME, cli_message, clock, command_machine, not_a_file, stdin_copy


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
    ended_by: str | None = None     # "M30" or "M02" when the program ended that way (see ``ending``)
    moves: int = 0                  # moves given to the back-end (counted as check and simulate() count them)
    state: FinalState | None = field(default=None, repr=False)   # the interpreter's final state
    ending: Ending = field(default_factory=lambda: Ending("not started"))   # what really ended the run

    @property
    def summary(self) -> RunSummary:
        """Moves and ending, as every entry point counts and names them (:mod:`fagorcnc.summary`)."""
        return RunSummary(self.moves, self.ending)


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


def run(source: str | os.PathLike | None = None, machine: Machine | dict | str | Path | None = None, *,
        text: str | None = None, backend: str | Backend = "sim", block_skip: bool = False,
        check_first: bool | None = None, progress: Progress | None = None, keep_profiles: bool = False,
        on_move: Callable[[object], None] | None = None,
        before_start: Callable[[list[Diagnostic]], None] | None = None, **backend_options) -> RunReport:
    """Run a program on a back-end (``"sim"`` by default, ``"interpcnc"`` for the card).

    ``check_first`` (default: True except on the plain simulator) plans the
    whole program before sending anything and refuses to start when it has an
    error; it also gives ``progress`` the total time for an ETA.
    ``progress(segment, status, total_time)`` is called after each segment, and
    with ``segment=None`` while the back-end waits for the machine to finish.
    ``on_move(record)`` is called for each move as it is given to the back-end (the moves the report
    counts).  ``before_start(warnings)`` gets what the check found that does not stop
    the run (e.g. CFG003, an M function the card has no output for) before
    anything is sent; they are in the report's diagnostics too.
    ``backend_options`` go to the back-end (e.g. ``host``, ``port``, ``serial``).
    """
    source = resolve(source, text)   # a file or program text, as simulate() decides (FileNotFoundError)
    with fewer_collections():
        return _run(source, machine, backend, block_skip, check_first, progress, keep_profiles, backend_options,
                    on_move, before_start)


def _run(source, machine, backend, block_skip: bool, check_first: bool | None, progress: Progress | None,
         keep_profiles: bool, backend_options: dict, on_move: Callable[[object], None] | None = None,
         before_start=None) -> RunReport:
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
            found = [*checked.diagnostics, *unsendable[:MAX_UNSENDABLE]]
            return RunReport(False, found, be.status(), stopped_by="error",
                             message="the program has errors: nothing was sent", backend=be,
                             ending=not_started(found, source_name(source)))
        total = checked.cycle_time
        if unmapped and getattr(getattr(be, "options", None), "strict_outputs", False):
            found = [*checked.diagnostics, *unmapped]
            return RunReport(False, found, be.status(), stopped_by="error",
                             message="auxiliary functions without an output mapping: nothing was sent", backend=be,
                             ending=Ending("not started", unmapped[0].line))
        refusals = getattr(be, "refusals", None)          # what the path ignores and the machine would not
        refused = refusals(checked.diagnostics) if refusals is not None else []
        if refused:
            return RunReport(False, [*checked.diagnostics, *refused], be.status(), stopped_by="error",
                             message="a transformation the back-end cannot reproduce is active: nothing was sent",
                             backend=be, ending=Ending("not started", refused[0].line))
        if before_start is not None and unmapped:
            before_start(list(unmapped))
    else:   # the program streams from its file; one with a syntax or structure error anywhere is not started
        errors = syntax_errors(source, compat=mach.compat)
        if errors:
            return RunReport(False, errors, be.status(), stopped_by="error",
                             message="the program has errors: nothing was run", backend=be,
                             ending=not_started(errors, source_name(source)))
    stream = interpret(source, mach, block_skip=block_skip)
    pacing = be.name == "sim" and bool(getattr(be, "realtime", None))
    planner = Planner(mach, keep_profiles=keep_profiles or pacing)
    sent, clock = 0, 0.0
    counted = MoveCounter(stream, on_move)
    ending: Ending | None = None
    planning: Diagnostic | None = None
    # PLN100 as check says it: checked before a real run (dry_run), reported after a run without that check
    envelope = None if check_first else Envelope(mach)
    stopped_by, message = None, ""
    extra: list[Diagnostic] = []
    be.open()
    try:
        for seg in planner.segments(counted):
            if envelope is not None:
                envelope.add(seg)
            be.send(seg)
            sent += 1
            counted.sent(seg.record)
            clock = max(clock, seg.t0 + seg.duration)   # #MOVE's segments overlap the general ones
            if progress is not None:
                progress(seg, be.status(), total)
        counted.finished()
        if progress is not None and hasattr(be, "on_wait"):   # the machine still runs what was sent
            be.on_wait = lambda st: progress(None, st, total)
        status = be.finish()
    except BackendError as exc:
        stopped_by, message = "alarm", str(exc)
        status = exc.status or be.status()
        ending = backend_ending(exc, status)
    except PlanningError as exc:
        stopped_by, message = "error", str(exc)
        file = exc.record.src.file if exc.record is not None else stream.program.file
        planning = Diagnostic(file, exc.line, 1, planning_code(exc), "error", str(exc))
        extra.append(planning)
        status = be.finish()
    except KeyboardInterrupt:
        be.stop()
        stopped_by, message = "interrupt", "stopped by the operator (Ctrl-C)"
        status = be.status()
        ending = interrupted(status)
    finally:
        be.close()
    if check_first:
        extra += unmapped
    if envelope is not None:
        extra += envelope.diagnostics(stream.program.file)
    if planner.independent is not None:   # #MOVE's notes (plan/independent.py)
        extra += planner.independent.diagnostics(stream.program.file)
    diagnostics = sorted([*stream.diagnostics, *extra], key=lambda d: (d.file, d.line, d.col))
    if stopped_by is None and any(d.is_error for d in diagnostics):
        beyond = all(d.code == "PLN100" for d in diagnostics if d.is_error)
        stopped_by, message = "error", ("the planned path leaves the soft limits" if beyond
                                        else "the program stopped at an error")
    if ending is None:
        ending = program_ending(stream.interpreter.ended, stopping_error(stream.run_order, planning),
                                stream.program.file)
    return RunReport(stopped_by is None, diagnostics, status, clock, total, sent, stopped_by, message, be,
                     ending.program_end, counted.sent_moves, stream.state, ending)



# --- the ``fagorcnc run`` command ------------------------------------------------------

class _ProgressBar:
    """A one-line progress display on a terminal: block, line, planned time and ETA."""

    def __init__(self, stream, label: str) -> None:
        import time
        from collections import deque

        self.stream, self.label, self.clock = stream, label, time.monotonic
        self.last = 0.0
        self.start = self.clock()
        self.sent: deque[tuple[int, float]] = deque()    # (segments sent, planned end) not known executed yet
        self.count = 0
        self.done = 0.0

    def __call__(self, seg, status, total) -> None:
        # what the machine has executed, not what was sent (a card buffers seconds of motion): the planned end of
        # the last segment the back-end reports executed (status.executed, from the card's sequence markers)
        if seg is not None:
            self.count += 1
            self.sent.append((self.count, seg.t0 + seg.duration))
        while self.sent and self.sent[0][0] <= status.executed:
            self.done = self.sent.popleft()[1]
        now = self.clock()
        if now - self.last < 0.2:
            return
        self.last = now
        done = self.done
        if total:
            frac = min(1.0, done / total)
            bar = "#" * int(frac * 20)
            eta = (now - self.start) * (1 - frac) / frac if frac > 0 else 0.0
            text = f"[{bar:<20}] {frac:4.0%}  line {status.line:>6}  ETA {clock(eta)}"
        else:
            text = f"line {status.line:>6}  planned {clock(done)}"
        self.stream.write(f"\r{self.label}: {text}")
        self.stream.flush()

    def close(self) -> None:
        if self.last:
            self.stream.write("\r\x1b[K")
            self.stream.flush()


def _where(report) -> str:
    """Where the tool ended: the program's end point (part coordinates) after a complete run; after
    an error or an alarm where the back-end last stood (machine coordinates), since the interpreter
    may have gone on past the last move the machine made; nothing when nothing moved."""
    if report.ok and report.state is not None:
        pos, label = report.state.position("part"), "final position"
    else:
        pos, label = report.status.position, "position (machine)"
    where = " ".join(f"{a}{v:.4f}" for a, v in pos.items())
    return f"{label} {where}, " if where else ""


def command(args: argparse.Namespace) -> int:
    """Handler of ``fagorcnc run``: exit 0 when the program ran to its end, 1 when it stopped,
    2 on bad usage, 130 when interrupted."""
    machine = command_machine(args)
    if machine is None:
        return 2
    if args.max_seconds is not None:
        machine = dataclasses.replace(machine, limits=dataclasses.replace(machine.limits,
                                                                          max_seconds=args.max_seconds))
    if args.file == "-":   # standard input: copied to a file first (the run reads the program twice)
        with tempfile.TemporaryDirectory(prefix="fagorcnc-run-") as scratch:
            return _command(args, machine, stdin_copy(scratch), STDIN_NAME)
    if not Path(args.file).is_file():
        print(f"{args.file}: cannot read the file: {not_a_file(args.file)}", file=sys.stderr)
        return 2
    return _command(args, machine, Path(args.file), args.file)


def _command(args: argparse.Namespace, machine, path: Path, shown: str) -> int:
    options = {}
    if args.backend == "interpcnc":
        options = {k: v for k, v in (("host", args.host), ("port", args.port), ("serial", args.serial))
                   if v is not None}
    if args.realtime is not None:
        if args.backend != "sim":
            print("fagorcnc: --realtime paces the simulator only", file=sys.stderr)
            return 2
        options["realtime"] = args.realtime
    if args.backend == "sim":
        options["keep_segments"] = False   # the command reads none of them: memory stays flat however long the run
    bar = _ProgressBar(sys.stderr, Path(shown).name) if sys.stderr.isatty() and not args.verbose else None
    backend, progress, server = args.backend, bar, None
    report = None
    on_move = _MoveList(sys.stdout) if args.verbose else None
    announced: set[int] = set()

    def announce(warnings) -> None:
        """The check's warnings (CFG003...) before anything moves, not after the run."""
        for d in warnings:
            announced.add(id(d))
            print(d.render().replace(str(path), shown) if shown != str(path) else d.render(), flush=True)

    try:
        if args.status_server is not None:
            backend, server = _start_status_server(args, machine, options, path)
            if server is None:
                return 2
            options, progress = {}, server.progress_callback(bar)
        report = run(path, machine, backend=backend, block_skip=args.block_skip, progress=progress,
                     on_move=on_move, before_start=announce, **options)
    except BackendError as exc:
        print(f"fagorcnc: {cli_message(str(exc))}", file=sys.stderr)
        if server is not None:
            server.stop()
        return 2
    finally:
        if bar is not None:
            bar.close()
        if server is not None and report is None:
            server.stop()
    for d in report.diagnostics:
        if (d.severity != "info" or args.verbose) and id(d) not in announced:
            print(d.render().replace(str(path), shown) if shown != str(path) else d.render())
    status = report.status
    errors = sum(d.is_error for d in report.diagnostics)
    target = "the embedded simulator" if args.backend == "sim" else f"back-end {args.backend}"
    verdict = "OK" if report.ok else f"STOPPED ({cli_message(report.message)}{_way_on(report)})"
    print(f"{shown}: {verdict} on {target}: {report.summary}, "
          f"last block executed: line {status.line}, {_where(report)}cycle time "
          f"{clock(report.cycle_time)} (jerk-limited plan), {errors} errors", flush=True)
    streamed = getattr(report.backend, "rate", None)
    if callable(streamed) and report.status.sent:
        stats = getattr(report.backend, "stats", {})
        print(f"{shown}: streamed {report.status.sent} segments at {streamed():.0f} segments/s sustained, "
              f"{stats.get('underruns', 0)} underruns seen (the card's buffers found empty mid-program)", flush=True)
    if server is not None:   # the PLC reads how the run ended before the port closes
        server.finished(report.ok, report.ending)
        if server.linger_seconds > 0:
            print(f"fagorcnc: status server stays up {server.linger_seconds:g} s with the final state "
                  "(--status-linger)", file=sys.stderr)
        with contextlib.suppress(KeyboardInterrupt):   # Ctrl-C cuts the wait short
            server.linger()
    if report.stopped_by == "interrupt":
        return 130
    return 0 if report.ok else 1


def _way_on(report: RunReport) -> str:
    """What to do at the command line after a stop by the back-end (the library's advice names its methods)."""
    cause = report.ending.cause
    if cause == "link lost":
        return "; restore the connection to the card, then run the program again (fagorcnc run)"
    if cause == "alarm":
        return "; clear the alarm on the machine, then run the program again (fagorcnc run)"
    return ""


class _MoveList:
    """``run -v``: one line per move given to the back-end (the moves the summary counts)."""

    def __init__(self, out) -> None:
        self.out, self.n = out, 0

    def __call__(self, record) -> None:
        self.n += 1
        end = getattr(record, "end_part", None) or getattr(record, "end", {}) or {}
        where = " ".join(f"{a}{v:.4f}" for a, v in end.items())
        feed = getattr(record, "feed", None)
        speed = f" F{feed:g}" if feed and not getattr(record, "rapid", False) else ""
        self.out.write(f"  move {self.n}: line {record.line} {record.kind} to {where}{speed}\n")


def _start_status_server(args: argparse.Namespace, machine, options: dict, path: Path):
    """Build the back-end and start the Modbus status server on it: (backend, server), server None on failure."""
    from ..plc.status_server import DEFAULT_LINGER, PlcSignal, StatusServer, StatusServerError, parse_address

    try:
        host, port = parse_address(args.status_server)
    except ValueError as exc:
        print(f"fagorcnc: {exc}", file=sys.stderr)
        return None, None
    backend = get_backend(args.backend, machine, **options)

    def show(signal: PlcSignal) -> None:
        what = f"= {signal.value}" if signal.value else "cleared"
        print(f"\nfagorcnc: PLC {signal.kind} {signal.number} (HR {signal.register}) {what}", file=sys.stderr)

    server = StatusServer(backend, machine, host=host, port=port, holding_writes=args.plc_writes,
                          program=path, on_signal=show,
                          linger=DEFAULT_LINGER if args.status_linger is None else args.status_linger)
    try:
        server.start()
    except StatusServerError as exc:
        print(f"fagorcnc: {exc}", file=sys.stderr)
        return backend, None
    print(f"fagorcnc: status server (Modbus TCP) on {server.host}:{server.port}"
          f"{', PLC writes enabled' if args.plc_writes else ''}", file=sys.stderr)
    return backend, server
