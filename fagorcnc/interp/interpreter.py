"""The block executor: runs a parsed program and yields motion records.

:class:`Interpreter` walks the routines of a :class:`~fagorcnc.syntax.ast.Program`
with a call stack; ``$`` instructions jump along the links the parser recorded
in :attr:`Routine.structure`.  ISO blocks go to
:class:`~fagorcnc.interp.iso.IsoExecutor`.  Every error becomes a diagnostic
on its block and stops the run (nothing is sent to a machine after an error).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from itertools import chain, islice
from pathlib import Path
from time import process_time as cpu_time

from ..config.machine import Machine
from ..diagnostics import Diagnostic
from ..kinematics.stage import StageError
from ..path.compensation import CompensationError
from ..summary import NOT_MOVES
from ..syntax import hints
from ..syntax.ast import Assignment, Block, Flow, Param, Program, Repeat, Sentence, SubroutineCall, Word
from ..syntax.macros import MacroUse
from . import axes, compat
from .channelvars import interpreter_variables
from .curves import CurveSettings
from .exblk import exblk_block
from .expressions import Evaluator, InterpError
from .files import SubroutineFiles
from .flow import FlowMixin, _Stop
from .iso import IsoExecutor
from .laser import Laser
from .macros import expanded_blocks
from .manual import ManualIntervention
from .parameters import Parameters
from .pipeline import chained, stages
from .plain import NOT_PLAIN, PlainBlocks
from .records import Dwell, Source, record_time
from .source import RoutineSource, StreamSource
from .spindle import SpindleModes
from .state import ChannelState
from .variables import Variables

#: The runaway guards: they end a run even in recovery mode.
RUNAWAY_CODES = frozenset({"INT080", "INT081", "INT082"})


@dataclass
class Frame:
    """One level of the call stack."""

    source: RoutineSource | StreamSource
    program: Program          # file the routine belongs to (for LL lookups)
    pc: int = 0
    opened_level: bool = False
    loops: dict = field(default_factory=dict)   # opener index -> loop state
    modal: bool = False       # running the modal subroutine (#MCALL)
    repeat: list | None = None  # #RPT: [start, end, remaining, return pc]
    outer_repeats: list = field(default_factory=list)   # the #RPT ranges the running one is nested in
    close: Callable[[], None] | None = None   # a streamed subroutine file: closed when the frame ends


@dataclass
class ModalCall:
    target: str
    args: dict
    frame_program: Program


class Interpreter(FlowMixin):
    """Runs one program; iterate :meth:`run` for the records."""

    def __init__(self, program: Program, machine: Machine, *, block_skip: bool = False,
                 search_paths: list[Path] | None = None, stream: StreamSource | None = None,
                 recover: bool = False) -> None:
        self.program = program
        # recover: an error skips the block it is in and the run goes on (``fagorcnc check``'s search for
        # the errors beyond the first; the control itself stops at the first).  Runaway guards still stop.
        self.recover = recover
        self.stream = stream
        self.machine = machine
        self.state = ChannelState(machine)
        self.state.block_skip = block_skip
        self.params = Parameters(machine)
        self.variables = Variables(self.state)
        self.evaluator = Evaluator(self.params, self.variables)
        self.iso = IsoExecutor(self)
        self.diagnostics: list[Diagnostic] = []
        self.frames: list[Frame] = []
        self.modal_call: ModalCall | None = None
        self.mcs_block = False
        self._l_calls: set = set()   # "#CALL L100" calls already reported (INT116)
        self.macros: dict[str, str] = {}   # #DEF's table, name -> block text (seed 002 L16121)
        self.laser = Laser()   # #SWTOUT / #PWMOUT state (seed 002 ch. 19)
        self.variables.plain_vars.update(self.laser.variables(self.state))
        self.manual = ManualIntervention()   # G200-G202, #CONTJOG, #INCJOG, #MPG, #SET OFFSET (seed 002 ch. 8.9)
        self.axis_sentence = None   # the #AXIS of the block being executed
        self.variables.axis_vars.update(self.manual.variables())
        self.variables.plain_vars.update(interpreter_variables(self))   # V.G.PENDRPT, INTMAN (interp/channelvars.py)
        self.spindle_modes = SpindleModes()   # M19 positioning, directions, S.POS, PRGSSO (seed 002 ch. 7)
        self.variables.spindle_vars.update(self.spindle_modes.variables(self.state))
        self.variables.plain_vars.update(axes.variables(self.state))   # V.G.AXISNAMEn, V.G.LINKACTIVE
        self.variables.axis_vars.update(axes.axis_variables())          # V.A.ACTCH.Xn
        self.curves = CurveSettings()   # #ASPLINE state, #SPLINE on/off (interp/curves.py)
        self.variables.moving_alone, self.variables.warn = self.curves.independent, self.message   # INT235
        self.cam = compat.CamState()   # CAM constructs and lint (interp/compat.py)
        self.ended: str | None = None
        base = Path(program.file).resolve().parent if program.file not in ("<string>", "") else None
        self.search_paths = [p.resolve() for p in (search_paths or machine.subroutine_paths)]
        self.program_dir = base
        self.files = SubroutineFiles(self.search_paths, base, machine.compat)
        self._messages = 0   # warnings and notes reported so far (limits.max_messages)
        self.clock = _Clock(machine.limits.max_seconds)
        #: id -> (record, record_time) of the records the block loop timed, for run() to reuse when the
        #: path stages hand the same record on (most of them); bounded (see :meth:`_time`)
        self._timed: dict[int, tuple] = {}

    # ------------------------------------------------------------------ run
    def run(self, watch: Callable | None = None) -> Iterator:
        """Yield the motion records of the program, in execution order; ``watch(record, interpreter)`` sees each
        as it is handed on (``fagorcnc.simulate.RecordWatcher``), and :attr:`moves_handed` counts the moves (set
        when the run ends, or is closed)."""
        if not self.program.ok and not self.recover:
            return  # a program with syntax errors is not executed
        main = self.stream if self.stream is not None else RoutineSource(self.program.main)
        self.frames.append(Frame(main, self.program))
        machine = self.machine
        clock = self.clock
        clock.start()
        moves = 0
        try:
            # path stages with look-ahead: corner aids G36-G39 on the programmed contour, then
            # tool radius compensation G41/G42; then transformed moves in machine joints (#CS, #RTCP...)
            # (#SPLINE: the spline's chords first, interp/curves.py); coupled slaves (#LINK) follow their
            # masters' machine positions (interp/axes.py): interp/pipeline.py
            records = (stages if self.idle_stages else chained)(self._loop(0), self, _stage_error)
            timed = self._timed
            # without a time limit, or when the consumer stops the clock itself (handed_in_runs), no clock
            # to read twice per record
            limited = clock.seconds > 0 and not self.consumer_excluded
            for record in records:
                # the time _loop worked out for the same record: the entry holds its record, so no other object
                # alive has its id (the record itself, not one made later at the address of one freed)
                known = timed.pop(id(record), None)
                self.cycle_time += record_time(machine, record) if known is None else known[1]
                if record.kind not in NOT_MOVES:   # is_move(record)
                    moves += 1
                if limited:
                    handed = cpu_time()
                    if watch is not None:
                        watch(record, self)
                    yield record
                    clock.exclude(handed)   # the consumer's time is not interpretation time
                else:
                    if watch is not None:
                        watch(record, self)
                    yield record
        except CompensationError as exc:
            src = exc.record.src
            if not self.failed:
                self.diagnostics.append(Diagnostic(src.file, src.line, 1, "INT086", "error", str(exc), src.text))
        except StageError as exc:
            src = exc.record.src
            if not self.failed:
                self.diagnostics.append(Diagnostic(src.file, src.line, 1, exc.code, "error", str(exc), src.text))
        except _Stop:
            pass
        finally:
            self.moves_handed = moves
            self.files.close()

    failed = False
    #: True when the consumer of :meth:`run` takes the records in runs and stops the interpretation clock
    #: while it has them (:func:`handed_in_runs`), so that run() does not read the clock around each record.
    consumer_excluded = False
    #: Plain blocks (literal G00-G03 moves) take the fast path of :mod:`fagorcnc.interp.plain`; False runs
    #: every block through the general executor (the tests compare both).
    plain_blocks = True
    #: The path stages run as one loop while none of them has anything to do (:func:`~fagorcnc.interp.pipeline.stages`);
    #: False chains them from the start (the tests compare both).
    idle_stages = True
    cycle_time = 0.0   # seconds of the records handed on (after the corner aids)
    moves_handed = 0   # moves among them (:meth:`run`)

    def _aid_error(self, aid, message: str) -> None:
        if not self.failed:
            src = aid.src
            self.diagnostics.append(Diagnostic(src.file, src.line, 1, "INT085", "error", message, src.text))
        raise _Stop

    def _loop(self, depth: int) -> Iterator:
        """Execute blocks until the call stack is back to ``depth`` frames.  The run's own loop (``depth`` 0)
        ends normally on an error or at the end of the program, so that the stages after it can hand on the
        moves they still hold (the loop itself, not a generator around it: one step less per record)."""
        try:
            frames = self.frames
            state = self.state
            stream = self.stream
            plain_blocks = PlainBlocks(self)
            plain = plain_blocks.run if self.plain_blocks else None
            max_blocks = self.machine.limits.max_blocks
            machine = self.machine
            timed = self._timed
            while len(frames) > depth:
                frame = frames[-1]
                if frame.repeat is not None and frame.pc > frame.repeat[1]:
                    self._repeat_next(frame)
                    continue
                source = frame.source
                if type(source) is StreamSource:   # the main program, or a large subroutine file, read lazily
                    blocks = source._builder.blocks   # source.get(frame.pc) of a block read already, without the call
                    i = frame.pc - source._base
                    block = blocks[i] if 0 <= i < len(blocks) else source.get(frame.pc)
                    seen = source._seen   # has_error() has something to look at only when diagnostics came
                    if source is stream and not self.recover and (seen[2] or seen[0] is not source.diagnostics
                                                                  or len(seen[0]) != seen[1]) and stream.has_error():
                        raise _Stop  # a syntax error ahead: nothing more is executed
                    if frame.pc & 1023 == 0:
                        keep = [*frame.loops, *(r[0] for r in (frame.repeat, *frame.outer_repeats) if r)]
                        frame.source.release(frame.pc, min(keep) if keep else None)
                else:
                    block = source.get(frame.pc)
                if block is None:
                    self._end_of_routine(frame)
                    continue
                frame.pc += 1
                self._current_block = block
                executed = state.executed_blocks + 1   # count_block(1), its checks only when they can fail
                if executed > max_blocks or not executed & 1023:
                    self.count_block(1)
                else:
                    state.executed_blocks = executed
                if block.skip and state.block_skip:
                    continue
                if block.number is not None:
                    state.last_n = block.number
                if self.recover:
                    yield from self._skipping_errors(block)
                    continue
                if plain is not None:   # the commonest CAM block, without the general executor (interp/plain.py)
                    record = plain(block)
                    if record is not NOT_PLAIN:
                        if record is not None:
                            if state.sync:
                                yield self._sync(block, record.start)
                            t = plain_blocks.seconds   # self._time(record, seconds), inline
                            if t is None:
                                t = record_time(machine, record)
                            if len(timed) >= 256:
                                timed.clear()
                            timed[id(record)] = (record, t)
                            state.elapsed += t
                            yield record
                        if state.sync:
                            yield self._sync(block, None)
                        continue
                for record in self._block(block):
                    if state.sync:   # the block read an execution value: the motion before it ends first
                        yield self._sync(block, getattr(record, "start", None))
                    state.elapsed += self._time(record)   # V.G.CYTIME while running
                    yield record
                if state.sync:
                    yield self._sync(block, None)
        except InterpError as exc:
            if depth:   # a modal subroutine's loop (after_motion): the run's own loop reports it
                raise
            self._error(exc)
            self.failed = True
        except _Stop:
            if depth:
                raise

    def _time(self, record, seconds: float | None = None) -> float:
        """:func:`record_time` of a record made by the block loop (``seconds`` when it is known already), kept
        for :meth:`run` (a record is immutable, so its time is the same when a path stage hands it on
        unchanged)."""
        t = record_time(self.machine, record) if seconds is None else seconds
        timed = self._timed
        if len(timed) >= 256:   # records a stage replaced or still holds: worked out again if they come
            timed.clear()
        timed[id(record)] = (record, t)
        return t

    def _skipping_errors(self, block: Block) -> Iterator:
        """One block in recovery mode: an error is reported and the rest of the block skipped (as if its
        line were blank); the runaway guards (INT080-INT082) still end the run."""
        state = self.state
        try:
            for record in self._block(block):
                if state.sync:
                    yield self._sync(block, getattr(record, "start", None))
                state.elapsed += record_time(self.machine, record)
                yield record
            if state.sync:
                yield self._sync(block, None)
        except InterpError as exc:
            if exc.code in RUNAWAY_CODES:
                raise
            state.sync = False
            self._error(exc, block)

    def _sync(self, block: Block, where: dict | None) -> Dwell:
        """The synchronisation point of a block that reads an execution value or runs #FLUSH (seed 002
        L17437-L17450): a dwell of no time, where the machine stands, which the motion stops at."""
        self.state.sync = False
        return Dwell("dwell", 0.0, dict(where if where is not None else self.state.machine_pos), self._src(block))

    # ------------------------------------------------------------------ runaway guards
    def count_block(self, col: int) -> None:
        """One more executed block (an NR repetition too): the block limit, and the time
        limit every 1024 blocks (INT080, INT082 at ``col`` of the current block)."""
        state = self.state
        state.executed_blocks += 1
        limits = self.machine.limits
        if state.executed_blocks > limits.max_blocks:
            raise InterpError("INT080", f"more than {limits.max_blocks} blocks executed: runaway program stopped "
                              "(limits.max_blocks)", col)
        if state.executed_blocks & 1023 == 0 and self.clock.expired():
            raise InterpError("INT082", f"interpretation took more than {limits.max_seconds:g} s: runaway program "
                              "stopped (limits.max_seconds, or --max-seconds on the command line)", col)

    def guard_repetitions(self, count: int, what: str, col: int) -> None:
        """The repetitions of an NR or #RPT are a loop whose length is known up front: a count
        over limits.max_loop_iterations is refused at once (INT081 at ``col``), not after the
        limit's worth of repetitions."""
        limit = self.machine.limits.max_loop_iterations
        if count > limit:
            raise InterpError("INT081", f"{what} more than limits.max_loop_iterations = {limit} times: runaway "
                              "program stopped", col)

    # ------------------------------------------------------------------ helpers
    def _src(self, block: Block) -> Source:
        return Source(self.frames[-1].program.file, block.line, block.text)

    def _error(self, exc: InterpError, block: Block | None = None) -> None:
        block = block or self._current_block
        file = self.frames[-1].program.file if self.frames else self.program.file
        line, text = (block.line, block.text) if block is not None else (1, "")
        hint = hints.hint(text, exc.col) if text else ""
        message = f"{exc.message} ({hint})" if hint else exc.message
        self.diagnostics.append(Diagnostic(file, line, exc.col, exc.code, "error", message, text))

    def message(self, code: str, severity: str, message: str, col: int = 1) -> None:
        """A warning or note on the current block.  At most limits.max_messages are kept per run
        (a #MSG in an endless loop would fill the memory); INT083 says when the rest are left out."""
        cap = self.machine.limits.max_messages
        self._messages += 1
        if cap and self._messages > cap:
            if self._messages == cap + 1:
                self._report("INT083", "warning", f"more than {cap} warnings and notes: the rest of this run's "
                             "are not reported (limits.max_messages)", 1)
            return
        self._report(code, severity, message, col)

    def _path_warning(self, record, code: str, message: str) -> None:
        """A warning of a path stage on the block of ``record`` (the stage runs behind the block loop)."""
        cap = self.machine.limits.max_messages
        if cap and self._messages >= cap:
            self.message(code, "warning", message)   # counted; says once that the rest are left out
            return
        self._messages += 1
        src = record.src
        self.diagnostics.append(Diagnostic(src.file, src.line, 1, code, "warning", message, src.text))

    def _report(self, code: str, severity: str, message: str, col: int) -> None:
        block = self._current_block
        file = self.frames[-1].program.file if self.frames else self.program.file
        self.diagnostics.append(Diagnostic(file, block.line if block else 1, col, code, severity, message,
                                           block.text if block else ""))

    _current_block: Block | None = None

    def block_text(self) -> str:
        """The source text of the block being executed (``""`` outside a block)."""
        block = self._current_block
        return block.text if block is not None else ""

    # ------------------------------------------------------------------ blocks
    def _block(self, block: Block):
        self._current_block = block
        self.state.line = block.line
        if self.state.channel.links:   # the coupled slaves where their masters took them (interp/axes.py)
            axes.sync_slaves(self.state)
        items = block.items
        if not items:
            return
        last = items[-1]
        t = type(last)
        if t is MacroUse:   # "NAME" in the block: it runs as its text reads now (seed 002 L16115)
            for expanded in expanded_blocks(self, block, last):
                yield from self._block(expanded)
            return
        if t is Sentence and last.keyword == "EXBLK" and len(items) == 1:   # a block run here (seed 002 L11294)
            inner = exblk_block(self, last, block)
            if inner is not None:
                yield from self._block(inner)
            return
        src = self._src(block)
        if t is Flow:
            self._flow(last, block)
            return
        if t is Assignment:
            for a in items:
                if type(a) is Assignment:
                    self._assign(a)
            return
        words = [i for i in items if type(i) is Word]
        mcs_move = t is Sentence and last.keyword == "MCS" and not _is_on_off(last)
        if t is Sentence and last.keyword == "MCS" and not mcs_move and (
                any(w.address != "N" for w in words) or len(last.args) > 1):   # a block number may stand before
            # seed 002 L3212: "#MCS ON and #MCS OFF must be programmed alone in the block"
            raise InterpError("INT118", "#MCS ON and #MCS OFF must be alone in their block (L3212)", last.col)
        if mcs_move:
            words += self._mcs_words(last)
        self.mcs_block = mcs_move
        self.axis_sentence = last if t is Sentence and last.keyword == "AXIS" else None   # G200-G202 #AXIS [..]
        if self.axis_sentence is not None and not words:
            raise InterpError("INT171", "#AXIS goes with G200, G201 or G202: G201 #AXIS [X, Z] (L7743)", last.col)
        try:
            if words:
                bw = self.iso.classify(words)
                yield from self.iso.execute(bw, src)
                if bw.call is not None:
                    self._oem_call(bw.call, src)
                if bw.glued is not None:   # "T202 LM06": the global subroutine M06, after the block
                    self._enter(*bw.glued)
            if t is Sentence and not mcs_move and self.axis_sentence is None:
                yield from self._sentence(last, src)
            elif t is SubroutineCall:
                self._call(last)
            elif t is Repeat:
                self._repeat(last)
        finally:
            self.mcs_block = False
            self.axis_sentence = None

    def _mcs_words(self, node: Sentence) -> list:
        out = []
        for item in node.args:
            kind = type(item).__name__
            if kind == "Keyed" or kind == "Setting":
                out.append(Word(item.name, item.value, item.col))
            else:
                raise InterpError("INT071", "#MCS takes axis words: #MCS X.. Y.. or #MCS ON/OFF", node.col)
        return out

    def _assign(self, a: Assignment) -> None:
        ev = self.evaluator
        value = ev.value(a.value)
        target = a.target
        if a.op != "=":
            current = ev.value(target)
            value = {"+=": current + value, "-=": current - value, "*=": current * value,
                     "/=": None}[a.op] if a.op != "/=" else self._divide(current, value, a.col)
        if type(target) is Param:
            self.params.set(ev.index(target), value, target.col)
        else:
            self.variables.set(target.name, tuple(ev.value(i) for i in target.index), value, target.col)

    @staticmethod
    def _divide(a: float, b: float, col: int) -> float:
        if b == 0:
            raise InterpError("INT033", "division by zero", col)
        return a / b

    # ------------------------------------------------------------------ subroutines
    def _lookup(self, target: str, kind: str, col: int) -> tuple:
        """(source of the blocks, program, what closes a streamed file) for a call (seed 002 L10322-L10333,
        L10435; the files: :mod:`fagorcnc.interp.files`)."""
        program = self.frames[-1].program
        has_path = any(c in target for c in "/\\:")
        if kind in ("LL", "CALL", "PCALL", "MCALL") and not has_path:
            key = target.upper()
            routine = program.subroutines.get(key)
            if routine is None and key.endswith((".NC", ".FST")):
                routine = program.subroutines.get(key.rsplit(".", 1)[0])
            if routine is None and kind != "LL" and key[:1] == "L" and key[1:].isdigit() and key[1:] in \
                    program.subroutines:
                # CAM posts (Autodesk's Fagor 8065) define "%L 100" and call it "#CALL L100"; the manual's
                # call is "#CALL 100" or "LL 100" (seed 002 L10303, L10343): taken, and said
                routine = program.subroutines[key[1:]]
                block = self._current_block
                site = (self.frames[-1].program.file, block.line if block else 0, col)
                if site not in self._l_calls:   # once per call, not per pass of a loop
                    self._l_calls.add(site)
                    self.message("INT116", "info", f"#{kind} {target}: no subroutine {target}, so the local "
                                 f"subroutine {key[1:]} (%L {key[1:]}) is called, as CAM posts write it", col)
            if routine is not None:
                caller = self.frames[-1].source
                if caller.kind == "local":
                    order = list(program.subroutines)
                    if order.index(routine.name.upper()) >= order.index(caller.name.upper()):
                        raise InterpError("INT090", f"local subroutine {caller.name} may only call subroutines "
                                          f"defined before it; {routine.name} is not (L10203)", col)
                return RoutineSource(routine), program, None
            if kind == "LL":
                raise InterpError("INT091", f"local subroutine {target} is not defined in this file", col)
        path = self.files.find(target, self.state.path, col)
        return self.files.load(path, col, self.diagnostics)

    def _call(self, node: SubroutineCall) -> None:
        kind = node.kind
        if self.modal_call is not None and not self.frames[-1].modal:
            self.modal_call = None  # another call cancels the modal subroutine (L10554-L10570)
        args = self._arguments(node.args)
        if kind == "MCALL":
            self.modal_call = ModalCall(node.target, args, self.frames[-1].program)
        self._enter(node.target, kind, args, node.col, modal=kind == "MCALL")

    def _arguments(self, words) -> dict[int, float]:
        """#PCALL/#MCALL/G180 arguments: A..Z = P0..P25 or Pn=value (seed 002 L10487-L10495)."""
        out: dict[int, float] = {}
        for w in words:
            addr = w.address
            if not addr:
                raise InterpError("INT094", "a number without its letter cannot initialise a parameter", w.col)
            if addr[0] == "P" and addr[1:].isdigit():
                n = int(addr[1:])
            elif len(addr) == 1 and addr.isalpha():
                n = ord(addr) - ord("A")
            else:
                raise InterpError("INT094", f"'{addr}' cannot initialise a local parameter", w.col)
            lo, hi = self.machine.local_params
            if not lo <= n <= hi:
                raise InterpError("INT094", f"{addr} initialises P{n}, outside the local parameters "
                                  f"P{lo}..P{hi}", w.col)
            out[n] = self.evaluator.value(w.value)
        return out

    def _enter(self, target: str, kind: str, args: dict, col: int, modal: bool = False) -> None:
        if len(self.frames) > self.machine.limits.max_call_depth:
            raise InterpError("INT095", f"more than {self.machine.limits.max_call_depth} nested subroutine calls "
                              "(L10207)", col)
        source, program, close = self._lookup(target, kind, col)
        opened = kind in ("CALL", "PCALL", "MCALL", "OEM")   # L10503: these open a parameter level
        if opened:
            self.params.push(args, col)
            # V.C.PCALLP_A..Z: which letters the call passed (seed 002 L40409)
            self.state.call_letters.append(frozenset(chr(ord("A") + n) for n in args if 0 <= n <= 25))
        self.frames.append(Frame(source, program, opened_level=opened, modal=modal, close=close))

    def _oem_call(self, call: tuple, src: Source) -> None:
        n, modal, col, words = call
        if n >= 500:   # G500-G599: a file, or a built-in behaviour (interp/compat.py)
            kind, name = compat.oem_target(self, n, col)
        else:
            kind, name = "file", self.machine.oem_subroutines.get(n)
        if name is None:
            raise InterpError("INT096", f"G{n}: no OEM subroutine is configured for it", col)
        args = self._arguments(words)
        if self.modal_call is not None and not self.frames[-1].modal:
            self.modal_call = None   # another call cancels the modal subroutine (L10568, L10804)
        if kind == "builtin":   # done once: running it again after every move would change nothing
            compat.run_builtin(self, n, name, args, col, mapped=n in self.machine.oem_builtins)
            return
        if modal:
            self.modal_call = ModalCall(name, args, self.frames[-1].program)
        self._enter(name, "OEM", args, col, modal=modal)

    def return_from_subroutine(self, col: int = 1) -> None:
        if len(self.frames) == 1:
            raise InterpError("INT097", "M17/M29/#RET outside a subroutine", col)
        frame = self.frames.pop()
        if frame.close is not None:
            frame.close()
        if frame.opened_level:
            self.params.pop()
            if len(self.state.call_letters) > 1:
                self.state.call_letters.pop()

    def _end_of_routine(self, frame: Frame) -> None:
        if len(self.frames) == 1:
            self.message("INT098", "warning", "the program ends without M02 or M30 (seed 002 L860)")
            self.frames.pop()
            raise _Stop
        if frame.source.kind == "program":  # a global subroutine file without M17/#RET
            raise InterpError("INT099", f"subroutine {frame.program.file} ends without M17, M29 or #RET", 1)
        self.return_from_subroutine()

    def after_motion(self, src: Source):
        """Run the modal subroutine after a motion block (#MCALL, seed 002 L10518-L10606).

        It runs to completion before the block goes on (and before the next NR
        repetition); moves inside the modal subroutine do not trigger it again.
        """
        mc = self.modal_call
        if mc is None or any(f.modal for f in self.frames):
            return
        depth = len(self.frames)
        block = self._current_block
        self._enter(mc.target, "MCALL", mc.args, 1, modal=True)
        yield from self._loop(depth)
        self._current_block = block

    def plane_changed(self) -> None:
        self.modal_call = None  # a plane change cancels #MCALL (L10554)

    def end_program(self, m: int, src: Source) -> None:
        self.state.reset(f"M{m}")
        self.laser.end_of_program()
        self.spindle_modes.reset()
        self.manual.reset()
        self.modal_call = None
        self.ended = f"M{m:02d}"
        raise _Stop

    def check_limits(self, position: dict[str, float], col: int, start: dict[str, float] | None = None) -> None:
        """Soft limits and G198/G199 on every programmed end point (seed 002 L9201-L9240).

        An axis already outside its limits may only move back toward them.
        """
        st = self.state
        frame = st.kin.frame_for(st) if st.kin.frame is not None and not st.kin.raw else None
        if frame is not None:   # a transformed move: the joints' limits (fagorcnc.kinematics)
            position, start = frame.point(position), frame.point(start) if start is not None else None
        for a, v in position.items():
            lo, hi = st.lower_limits[a], st.upper_limits[a]
            if lo - 1e-9 <= v <= hi + 1e-9:
                continue
            if start is not None:
                s = start[a]
                if (v < lo and s < lo and v >= s - 1e-9) or (v > hi and s > hi and v <= s + 1e-9):
                    continue  # moving back toward the limits (L9226-L9228)
            bound = "lower" if v < lo else "upper"
            raise InterpError("INT100", f"axis {a} to {v:.4f} (machine) is beyond its {bound} limit "
                              f"{lo if v < lo else hi:g}", col)

    # ------------------------------------------------------------------ # sentences
    def _sentence(self, node: Sentence, src: Source):
        from .sentences import execute_sentence

        yield from execute_sentence(self, node, src)


def handed_in_runs(interp: Interpreter, records: Iterator, size: int = 1024) -> Iterator:
    """``records`` (made by ``interp.run()``, directly or through a watcher) taken ``size`` at a time:
    each run is interpreted, then handed on with the interpretation clock stopped until the consumer asks
    for more, so that limits.max_seconds still counts interpretation alone (:class:`_Clock`) with two
    clock reads per run instead of two per record (a system call each).  What runs while a run is being
    taken (a watcher of the records) counts as interpretation.  Sets ``interp.consumer_excluded``.  The
    records of each run are handed on by ``chain`` (no generator step a record): it asks for the next run,
    and so stops excluding the consumer's time, when the consumer asks for the record after the run's last."""
    interp.consumer_excluded = True
    return chain.from_iterable(_runs(interp.clock, records, size))


def _runs(clock: _Clock, records: Iterator, size: int) -> Iterator[list]:
    """The runs of :func:`handed_in_runs`, each handed with the clock stopped until the next is asked for."""
    while run := list(islice(records, size)):
        handed = cpu_time()
        yield run
        clock.exclude(handed)


class _Clock:
    """Interpretation time against limits.max_seconds: CPU time of the interpreting process since
    :meth:`start`, less the CPU time the records spent with the consumer (the planner, a
    back-end), so a long real run is not cut by a limit meant for runaway programs.  CPU time,
    not wall-clock time: a machine busy with other jobs (a loaded CI runner) slows the run down
    but does not bring the limit closer, so the verdict does not depend on the machine's load
    (issue 25.1).  Time the process spends waiting (a back-end's back-pressure, a paced
    simulator) is not CPU time either."""

    __slots__ = ("deadline", "seconds")

    def __init__(self, seconds: float) -> None:
        self.seconds = seconds
        self.deadline = math.inf

    def start(self) -> None:
        if self.seconds > 0:
            self.deadline = cpu_time() + self.seconds

    def exclude(self, since: float) -> None:
        self.deadline += cpu_time() - since

    def expired(self) -> bool:
        return cpu_time() > self.deadline


def _stage_error(record, code: str, message: str) -> None:
    raise StageError(record, code, message)


def _is_on_off(node: Sentence) -> bool:
    return bool(node.args) and type(node.args[0]).__name__ == "Name" and node.args[0].name in ("ON", "OFF")


