"""``fagorcnc.simulate()``: parse, interpret and summarise a program.

The result is the public API of ``../shared/guide/architecture.md``: ``ok``,
``diagnostics``, ``moves`` (motion records in machine coordinates with the
part-coordinate end point), ``state`` (final positions, parameters, variables,
modal functions, active origin) and ``cycle_time`` from the jerk-limited
planner; ``trajectory()`` samples the planned motion.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

from .config.machine import Machine, MachineError, load_machine
from .config.parameter_file import attach_parameter_file
from .diagnostics import Diagnostic
from .interp.interpreter import Interpreter, handed_in_runs
from .interp.records import record_time
from .interp.state import ChannelState
from .plan import Planner, PlanningError, Segment, planning_code
from .plan.envelope import Envelope
from .program_files import Source, no_block, resolve, source_name
from .runtime import fewer_collections
from .summary import Ending, RunSummary, is_move, not_started, program_ending, stopping_error
from .syntax import parse_file, parse_text, source_encoding
from .syntax.ast import Block, Program
from .syntax.reader import PlainChunks, ProgramFile

if TYPE_CHECKING:   # imported where used: dry_run (fagorcnc check) needs neither
    from .interp.movestore import Moves
    from .plan.trajectory import Trajectory


class FinalState:
    """The channel state after the run."""

    def __init__(self, interp: Interpreter) -> None:
        self._interp = interp
        self._state: ChannelState = interp.state

    def position(self, frame: str = "part") -> dict[str, float]:
        """Current position: ``frame="part"`` (work coordinates) or ``"machine"``."""
        if frame == "machine":
            return self._state.joints()
        if frame == "part":
            return self._state.part_pos()
        raise ValueError("frame must be 'part' or 'machine'")

    def param(self, n: int) -> float:
        """Value of arithmetic parameter Pn (local parameters of the main level)."""
        return self._interp.params.get(n)

    def var(self, name: str) -> float:
        """Value of a V. variable, e.g. ``var("V.A.ORG.X")``, ``var("V.A.ORGT[1].X")``."""
        from .syntax.ast import Var as VarNode
        from .syntax.reader import line_parser

        node, diags = line_parser().parse(f"P0={name}", 1)
        if diags or node is None or type(node.items[0].value) is not VarNode:
            raise KeyError(name)
        v = node.items[0].value
        return self._interp.variables.get(v.name, tuple(self._interp.evaluator.value(i) for i in v.index))

    @property
    def origin(self) -> str:
        """The active absolute origin: ``"G54"``..``"G59"``, ``"G159=n"``, ``"G92"`` or ``"G53"``."""
        return self._state.origin_source

    @property
    def modes(self) -> dict[str, int | None]:
        """Active G function of every modal group (``{"motion": 1, "plane": 17, ...}``)."""
        return dict(self._state.modes)

    @property
    def g_functions(self) -> list[int]:
        """The active modal G functions, sorted."""
        return sorted(v for v in self._state.modes.values() if v is not None)

    @property
    def tool(self) -> int:
        return self._state.tool

    @property
    def offset(self) -> int:
        return self._state.offset

    @property
    def feed(self) -> float | None:
        return self._state.feed


class _ParsedOnUse:
    """The ``program`` of a :class:`Result`: a :class:`Program`, or a callable that parses it, called
    on first use (simulate() streams a clean program, so the tree of every block is not kept
    alongside the records while it runs; it is parsed again when asked for)."""

    def __set_name__(self, owner, name: str) -> None:
        self._slot = "_" + name

    def __get__(self, obj, owner=None):
        if obj is None:
            return None   # the dataclass default
        value = obj.__dict__.get(self._slot)
        if callable(value):
            value = obj.__dict__[self._slot] = value()
        return value

    def __set__(self, obj, value) -> None:
        obj.__dict__[self._slot] = value


@dataclass
class Result:
    """What :func:`simulate` returns."""

    ok: bool
    diagnostics: list[Diagnostic]
    moves: Sequence   # a Moves (records stored as columns, made on access), equal to the list of the records
    state: FinalState | None
    cycle_time: float
    program: Program | None = _ParsedOnUse()   # type: ignore[assignment]
    ended_by: str | None = None     # "M30" or "M02" when the program ended that way (see ``ending``)
    machine: Machine | None = None
    ending: Ending = field(default_factory=lambda: Ending("not started"))

    @property
    def summary(self) -> RunSummary:
        """Moves and ending, as every entry point counts and names them (:mod:`fagorcnc.summary`)."""
        return RunSummary(sum(map(is_move, self.moves)), self.ending)

    @property
    def errors(self) -> list[Diagnostic]:
        return [d for d in self.diagnostics if d.is_error]

    def segments(self, *, jerk: bool = True, keep_profiles: bool = True) -> Iterator[Segment]:
        """The planned motion as timed :class:`~fagorcnc.plan.Segment` objects; a #MOVE's are
        :class:`~fagorcnc.plan.IndependentSegment` objects, on the same clock, overlapping the general ones."""
        return Planner(self.machine, jerk=jerk, keep_profiles=keep_profiles).segments(self.moves)

    def trajectory(self, period: float | None = None) -> Trajectory:
        """The planned motion sampled every ``period`` seconds (default: the machine's
        servo period): ``.t`` and per-axis ``.position``/``.velocity``/``.acceleration``/
        ``.jerk`` arrays in machine coordinates."""
        mach = self.machine or load_machine(None)
        start = self.moves[0].start if self.moves else None
        from .plan.trajectory import sample
        return sample(self.segments(), mach.axis_names, period or mach.planner.servo_period, start)


def estimate_time(machine: Machine, moves: list) -> float:
    """Feed-rate cycle-time estimate in seconds (no acceleration)."""
    return sum(record_time(machine, m) for m in moves)


def simulate(source: str | os.PathLike | None = None, machine: Machine | dict | str | Path | None = None, *,
             text: str | None = None, block_skip: bool = False) -> Result:
    """Run a program offline.

    ``source`` is a program file (a path, or a ``str`` naming one) or the program text itself;
    ``text="..."`` is always program text (see :func:`fagorcnc.program_files.resolve`: a one-line
    string that looks like a path but names no file raises :class:`FileNotFoundError`).
    ``machine`` is a :class:`~fagorcnc.config.machine.Machine`, a dict or a TOML
    path (see :func:`~fagorcnc.config.machine.load_machine`); ``None`` is the default
    machine.  Never raises on a bad program: problems are in ``diagnostics``.
    A program without syntax errors is streamed through the interpreter (only its records are
    kept; ``Result.program`` is parsed again on first use).
    """
    program_source = resolve(source, text)
    try:
        mach = load_machine(machine)
    except MachineError as exc:
        d = Diagnostic(str(machine), 1, 1, "CFG001", "error", str(exc))
        from .interp.movestore import Moves
        return Result(False, [d], Moves(), None, 0.0, None)
    with fewer_collections():
        return _simulate(program_source, mach, block_skip)


def _is_file(source: Source) -> bool:
    """Whether a resolved ``source`` is a program file (else it is the program text)."""
    return isinstance(source, Path)


def _empty(program: Program) -> bool:
    """A program without any block (empty, or comments only) and without syntax errors."""
    return program.ok and not program.main.blocks and not program.subroutines


def _simulate(source: Source, mach: Machine, block_skip: bool) -> Result:
    file = source_name(source)
    syntax, encoding, chunks = _syntax(source, file, mach.compat)
    if not any(d.is_error for d in syntax):
        return _simulate_streamed(source, file, encoding, mach, block_skip, syntax, chunks)
    return _simulate_whole(source, mach, block_skip)


def _parse(source: Source, mach: Machine) -> Program:
    return parse_file(source, mach.compat) if _is_file(source) else parse_text(str(source), compat=mach.compat)


def _simulate_streamed(source: Source, file: str, encoding: str, mach: Machine, block_skip: bool,
                       syntax: list[Diagnostic], chunks: PlainChunks | None = None) -> Result:
    """A program without syntax errors, streamed through the interpreter as :func:`dry_run` runs it: only
    its records are kept (the program's tree is parsed again if :attr:`Result.program` is asked for);
    ``chunks``: what the syntax check found of its lines (:func:`_syntax`)."""
    from .interp.movestore import Moves
    from .interp.source import stream_program

    lines = _lines_of(source, encoding)
    try:
        head, body = stream_program(lines, file, mach.compat, chunks)
        interp = Interpreter(head, mach, block_skip=block_skip, stream=body)
        attach_parameter_file(interp)   # restore saved global/common parameters; a dry run never saves them
        moves, notes = Moves(), []
        cycle_time, planning = _planned(mach, _Kept(interp.run(), moves), file, notes)
    finally:
        getattr(lines, "close", lambda: None)()
    diagnostics = [*syntax, *interp.diagnostics, *([planning] if planning is not None else []), *notes]
    ending = program_ending(interp.ended, stopping_error(interp.diagnostics, planning), file)
    diagnostics.sort(key=lambda d: (d.file, d.line, d.col))
    ok = not any(d.is_error for d in diagnostics)
    return Result(ok, diagnostics, moves, FinalState(interp), cycle_time, lambda: _parse(source, mach),
                  ending.program_end, mach, ending)


class _Kept:
    """The interpreter's records, each kept in ``moves`` on its way to the planner (planned as they are
    made, not made again from the columns).  An iterator object, not a generator: after a planning
    error the rest is still interpreted and kept."""

    def __init__(self, records: Iterator, moves: Moves) -> None:
        self._records = records
        self.moves = moves
        self._keep = moves.append

    def __iter__(self) -> _Kept:
        return self

    def __next__(self):
        record = next(self._records)
        self._keep(record)
        return record


def _planned(mach: Machine, records: _Kept, file: str, notes: list) -> tuple[float, Diagnostic | None]:
    """The cycle time of ``records`` on the embedded simulator back-end (segments not kept), and the
    PLN001 when planning fails; every record is drawn from ``records`` (the rest after a failure).  The
    planner's own notes (#MOVE's timeline) are added to ``notes``."""
    from .backends.sim import SimulatorBackend

    sim = SimulatorBackend(mach, keep_segments=False)
    sim.open()
    planner = Planner(mach)
    planning = None
    try:
        for seg in planner.segments(records):
            sim.send(seg)
    except PlanningError as exc:
        where = exc.record.src.file if exc.record is not None else file
        planning = Diagnostic(where, exc.line, 1, planning_code(exc), "error", str(exc))
    for _ in records:   # the rest of the program still runs (its records and diagnostics are kept)
        pass
    records.moves.flush()
    notes.extend(planner.independent.diagnostics(file))   # #MOVE's notes (plan/independent.py)
    return sim.cycle_time, planning


def _simulate_whole(source: Source, mach: Machine, block_skip: bool) -> Result:
    """A program with a syntax error (not started) or without a block: parsed whole, as it always was."""
    from .interp.movestore import Moves

    program = _parse(source, mach)
    if _empty(program):
        program = program._replace(diagnostics=(*program.diagnostics, no_block(program.file)))
    interp = Interpreter(program, mach, block_skip=block_skip)
    attach_parameter_file(interp)   # restore saved global/common parameters; a dry run never saves them
    moves, notes = Moves(), []
    cycle_time, planning = _planned(mach, _Kept(interp.run(), moves), program.file, notes)
    diagnostics = [*program.diagnostics, *interp.diagnostics, *([planning] if planning is not None else []), *notes]
    if not program.ok:
        ending = not_started(program.diagnostics, program.file)
    else:
        ending = program_ending(interp.ended, stopping_error(interp.diagnostics, planning), program.file)
    diagnostics.sort(key=lambda d: (d.file, d.line, d.col))
    ok = not any(d.is_error for d in diagnostics)
    return Result(ok, diagnostics, moves, FinalState(interp), cycle_time, program, ending.program_end, mach, ending)


class Run:
    """A streaming run: iterate it for the motion records, one block at a time.

    Memory stays flat whatever the program length (the program is read lazily
    and only blocks a jump or loop can reach again are kept).  After (or
    during) the iteration, :attr:`diagnostics` and :attr:`state` describe the
    run.  A syntax error stops the run at the block before it.
    """

    def __init__(self, lines, file: str, machine: Machine, block_skip: bool = False) -> None:
        from .interp.source import stream_program

        self._close = getattr(lines, "close", None)
        self.program, self._stream = stream_program(lines, file, machine.compat)
        self.interpreter = Interpreter(self.program, machine, block_skip=block_skip, stream=self._stream)
        self.state = FinalState(self.interpreter)
        self._parameter_file = attach_parameter_file(self.interpreter)

    def __iter__(self):
        try:
            yield from self.interpreter.run()
        finally:
            if self._close is not None:
                self._close()
            if self._parameter_file is not None:   # a real run keeps its global/common parameters
                self._parameter_file.save()

    @property
    def diagnostics(self) -> list[Diagnostic]:
        seen = {id(d) for d in self.program.diagnostics}
        extra = [d for d in self._stream.diagnostics if id(d) not in seen]
        out = [*self.program.diagnostics, *extra, *self.interpreter.diagnostics]
        return sorted(out, key=lambda d: (d.file, d.line, d.col))

    @property
    def ok(self) -> bool:
        return not any(d.is_error for d in self.diagnostics)

    @property
    def run_order(self) -> list[Diagnostic]:
        """The interpreter's diagnostics in the order they arose (the first error is where it stopped),
        then the syntax errors met in the stream (one stops the run at the block before it)."""
        seen = {id(d) for d in self.program.diagnostics}
        ahead = [d for d in self._stream.diagnostics if id(d) not in seen and d.is_error]
        return [*self.interpreter.diagnostics, *ahead]


def interpret(source: str | os.PathLike | None = None, machine: Machine | dict | str | Path | None = None, *,
              text: str | None = None, block_skip: bool = False) -> Run:
    """Stream a program (a file, or ``text=``, as for :func:`simulate`) through the interpreter; see :class:`Run`."""
    source = resolve(source, text)
    mach = load_machine(machine)
    if _is_file(source):
        path = Path(source)
        # decoded as simulate() and the check decode it (UTF-8, else Latin-1)
        return Run(open(path, encoding=source_encoding(path), errors="replace"), str(path), mach, block_skip)
    return Run(str(source).split("\n"), "<string>", mach, block_skip)


# ----------------------------------------------------------------------------- the streamed dry run
@dataclass
class DryRun:
    """What :func:`dry_run` leaves of a program: no record is kept.

    ``executed``: the whole file is free of syntax and structure errors (else the control does
    not start it, and nothing ran); ``cycle_time``: planned seconds up to the first error;
    ``moves``: motion records (not auxiliary functions or dwells); ``ended_by``: ``"M30"``,
    ``"M02"``... or None (end of file, or stopped by an error).
    """

    executed: bool
    diagnostics: list[Diagnostic] = field(default_factory=list)
    cycle_time: float = 0.0
    moves: int = 0
    ended_by: str | None = None     # "M30" or "M02" when the program ended that way (see ``ending``)
    ending: Ending = field(default_factory=lambda: Ending("not started"))

    @property
    def summary(self) -> RunSummary:
        """Moves and ending, as every entry point counts and names them (:mod:`fagorcnc.summary`)."""
        return RunSummary(self.moves, self.ending)

    @property
    def ok(self) -> bool:
        return not any(d.is_error for d in self.diagnostics)


#: ``on_record(record, interpreter)``: called for every record as the interpreter makes it (its
#: state is then the one the record was made in, as far as look-ahead allows).
RecordWatcher = Callable[[object, Interpreter], None]


class _Watched:
    """The interpreter's records, each shown to a watcher and counted on its way to the planner
    (:meth:`Interpreter.run`'s ``watch``: no generator step of its own a record).  Every iteration takes
    the same stream on: after a planning error the rest is still interpreted."""

    def __init__(self, interp: Interpreter, watch: RecordWatcher | None) -> None:
        self._interp = interp
        self._stream = interp.run(watch)

    def __iter__(self) -> Iterator:
        return self._stream

    @property
    def moves(self) -> int:
        """The moves handed on (all of them once the stream has ended, or was closed)."""
        return self._interp.moves_handed


def _lines_of(source: Source, encoding: str):
    """The program's lines: an open file (read lazily), or the text itself (split as parse_text does)."""
    if _is_file(source):
        return ProgramFile(source, encoding)   # closed by the caller; read in large pieces
    return str(source)


def _syntax(source: Source, file: str, compat=None) -> tuple[list[Diagnostic], str, PlainChunks]:
    """The syntax and structure diagnostics of the whole program, read once in constant memory,
    the file's encoding: UTF-8, or Latin-1 for files written by older editors (as
    :func:`~fagorcnc.syntax.read_source` decides), and the chunks of its lines that are runs of plain
    lines (for the run's own reading: :class:`~fagorcnc.syntax.reader.PlainChunks`)."""
    from .syntax import iter_lines
    from .syntax.structure import assemble

    encoding = source_encoding(source) if _is_file(source) else "utf-8"
    lines = _lines_of(source, encoding)
    chunks = PlainChunks()
    blocks = [False]

    def noting_blocks(pairs):
        for pair in pairs:
            if type(pair[0]) is Block:
                blocks[0] = True
            yield pair

    try:
        diagnostics = list(assemble(noting_blocks(iter_lines(lines, file, compat, structure_only=True,
                                                             chunks=chunks)), file, keep_body=False).diagnostics)
    finally:
        getattr(lines, "close", lambda: None)()
    if not blocks[0] and not any(d.is_error for d in diagnostics):
        diagnostics.append(no_block(file))
    return diagnostics, encoding, chunks


def syntax_errors(source: str | os.PathLike | None = None, *, text: str | None = None,
                  compat=None) -> list[Diagnostic]:
    """The syntax and structure errors of the whole program (a file, or ``text=``, as for :func:`simulate`),
    read once in constant memory: a program with one is not started (as in :func:`simulate`); ``compat``
    is the machine's ``[compat]`` policy."""
    source = resolve(source, text)
    file = source_name(source)
    with fewer_collections():
        diagnostics, _, _ = _syntax(source, file, compat)
    return sorted((d for d in diagnostics if d.is_error), key=_place)


def dry_run(source: str | os.PathLike | None = None, machine: Machine | dict | str | Path | None = None, *,
            text: str | None = None, block_skip: bool = False, on_record: RecordWatcher | None = None,
            on_segment: Callable[[Segment], None] | None = None) -> DryRun:
    """A dry run in constant memory: :func:`simulate`'s diagnostics, cycle time and ending without
    keeping the program or its records, whatever its length (a CAM program of millions of blocks),
    and PLN100 where the planned path (an arc, a corner curve) leaves the soft limits between the
    programmed end points.

    The whole file is first read for its syntax (a program with a syntax error anywhere is not
    started, as in :func:`simulate`), then read again lazily, interpreted and planned in one
    stream.  ``on_record`` sees every motion record, ``on_segment`` every planned segment: what
    a caller wants to know of them it keeps itself.  Never raises on a bad program (a missing file
    raises :class:`FileNotFoundError`, as for :func:`simulate`).
    """
    source = resolve(source, text)
    try:
        mach = load_machine(machine)
    except MachineError as exc:
        return DryRun(False, [Diagnostic(str(machine), 1, 1, "CFG001", "error", str(exc))])
    file = source_name(source)
    with fewer_collections():
        diagnostics, encoding, chunks = _syntax(source, file, mach.compat)
        if any(d.is_error for d in diagnostics):
            return DryRun(False, sorted(diagnostics, key=_place), ending=not_started(diagnostics, file))
        return _dry_run(source, file, encoding, mach, block_skip, diagnostics, on_record, on_segment, chunks)


def _place(d: Diagnostic) -> tuple:
    return d.file, d.line, d.col


def _dry_run(source, file: str, encoding: str, mach: Machine, block_skip: bool, diagnostics: list,
             on_record: RecordWatcher | None, on_segment: Callable[[Segment], None] | None,
             chunks: PlainChunks | None = None) -> DryRun:
    from .interp.source import stream_program

    lines = _lines_of(source, encoding)
    try:
        program, body = stream_program(lines, file, mach.compat, chunks)   # the lines _syntax() read
        interp = Interpreter(program, mach, block_skip=block_skip, stream=body)
        attach_parameter_file(interp)   # the saved global/common parameters; a dry run never saves them
        records = _Watched(interp, on_record)
        envelope = Envelope(mach)   # PLN100: what lies between the programmed end points
        clock = 0.0
        planning = None
        planner = Planner(mach)
        envelope_add = envelope.add
        try:
            # the planner takes the records in runs (its read-ahead): the interpretation clock (limits.max_seconds)
            # is stopped once per run while the planner has them, not around every record
            for seg in planner.segments(handed_in_runs(interp, records)):
                end = seg.t0 + seg.duration
                if end > clock:   # max(clock, end): #MOVE's segments overlap the general ones
                    clock = end
                piece = seg.piece
                if piece is not None and getattr(piece, "curved", False):   # a straight piece: nothing (Envelope.add)
                    envelope_add(seg)
                if on_segment is not None:
                    on_segment(seg)
        except PlanningError as exc:
            planning = Diagnostic(exc.record.src.file if exc.record is not None else file, exc.line, 1,
                                  planning_code(exc), "error", str(exc))
            diagnostics = [*diagnostics, planning]
            for _ in records:   # the rest is still interpreted, for its diagnostics (as simulate() does)
                pass
        diagnostics = [*diagnostics, *planner.independent.diagnostics(file)]   # #MOVE's notes
    finally:
        getattr(lines, "close", lambda: None)()
    out = sorted([*diagnostics, *interp.diagnostics, *envelope.diagnostics(file)], key=_place)
    ending = program_ending(interp.ended, stopping_error(interp.diagnostics, planning), file)
    return DryRun(True, out, clock, records.moves, ending.program_end, ending)
