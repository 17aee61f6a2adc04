"""The ``interpcnc`` back-end: streams planner segments to a SOPROLEC InterpCNC V3 over Modbus.

Translation (see :mod:`.translate`): rapids and lines -> 1002 (1001 before
a feed change), XY arcs -> 1003, other arcs, helices and corner blends ->
1002 chords, dwells -> 1011, auxiliary functions -> 1010 actions from the
``outputs`` table (see :mod:`.options`).  An auxiliary function with no
mapping is never dropped silently: it is listed in :attr:`warnings` (or
refused with ``strict_outputs``), and :meth:`InterpCncBackend.check` lists
them before streaming.

**Flow control.**  A command is written only when it fits the free space of
the CNC Modbus buffer (input register 3000).  The free space is read
(registers 3000-3004 in one request, with the status and alarm words) and
then decremented locally for every command written: the card only ever
frees space, so the local figure is a safe lower bound and no write can
overflow.  When it runs out, the back-end refills in batches of a quarter
of the buffer, or as soon as anything fits when the planner holds fewer
than ``low_water`` entries.  The status is re-read at least every
``poll_interval`` seconds while streaming, so an alarm stops the stream
within one interval.

**Sequence markers.**  Every segment gets a sequence number n (1, 2, ...)
and a synchronised action 1010 type 3 writing ``n mod 65536`` into the user
RAM holding register M = ``marker_register`` (3990 by default, see
``registers.DEFAULT_MARKER_REGISTER``; L463, L967-L971) - except the
straight moves that share the marker of the group they join, up to
``marker_every`` of them (see :mod:`.markers`: M = n then means segment n,
the group's first, has started, and a resume finds the move under way in
the group from the position counters).  The card runs
synchronised actions in order with the moves, just before the next move
(L941), so:

* motion segments and dwells: the marker is sent *before* their commands -
  M = n means segment n has **started** (segments before n are complete);
* auxiliary segments: the marker is sent *after* their actions - M = n
  means segment n has **run**;
* a motion segment sent as several moves (an arc over 180 degrees, chords)
  also writes the index j of each move into M+1 before it (the first index
  before M itself, so M is never read beside a stale index), so a resume
  knows which move was under way (a full circle ends where it starts: the
  position alone cannot tell); a dwell writes 0 into M+1 before M, and 1
  after it has ended.

**The gate.**  A move's progress can be read back (the position counters),
a dwell's or an output's cannot: if the link failed while their commands
were being written, the card may have run some of them and not the marker.
So their commands go behind a gate - a 1012 wait (L1017-L1121) until the
user register G = M+2 is above the segment's token minus one - and the
back-end opens the gate (a plain write of the token into G) only once every
command of the segment, markers included, has been accepted.  They then run
in full or not at all: a fault before the gate opens leaves nothing run
(recovery purges them), after it M and M+1 tell.  Tokens count
up, so opening a gate never shuts an earlier one still queued; before they
pass 65535 the back-end waits until the card has passed the last gate, then
sets G back to 0 (once per 65535 dwells and outputs).  The wait raises
alarm 18 if the gate stays shut for 65.535 s (a link lost for that long):
the card stops rather than run an output nobody confirmed.

**The start lead** (default 2 s of planned motion; 0 turns it off).  With ``start_lead`` > 0 the stream's
first command is
a 1012 wait until M+1 is above 0 (no alarm on its timeout); the back-end
writes 1 into M+1 once that many seconds of planned motion are queued (or
as soon as it must wait for the card), so that the card starts with a
buffer deep enough to ride out a hiccup of the PC.

**Timeouts.**  See :mod:`.watchdog`: ``stall_timeout`` (BCK001) and
``stop_timeout`` (BCK002) end waits on a card that stopped consuming or
whose axes never stop.

The back-end assumes it is the only client commanding the card (another
master acknowledging an alarm behind its back would make a purged segment
look complete).

16 bits are enough: the unacknowledged window is bounded by the buffer
(4096 registers, at least 4 per segment), far below 65536, so the value is
unwrapped unambiguously against the last one read.  ``status().line`` is
the source line of the last segment started;
``executed`` counts segments complete.

**Faults.**  On an alarm (IR 3003 bit 0 or IR 3004 != 0), a lost link, a
timeout or a Modbus exception reply, the back-end stops sending at once and
raises :class:`InterpCncError` with the alarm in words and the last block
known started.  pymodbus never retries (a retried write could run twice).
Segments given to :meth:`~InterpCncBackend.send` after that are kept, not
sent.  Recovery is the operator's: :meth:`~InterpCncBackend.resume`
(acknowledges an alarm) or :meth:`~InterpCncBackend.reconnect_and_continue`;
both resynchronise as described there.  After an alarm that means the
machine position can no longer be trusted (a limit switch, a motor fault...:
``registers.ALARMS_POSITION_LOST``) both refuse: the way out is
:meth:`~InterpCncBackend.abandon`, which discards the stream.
"""

from __future__ import annotations

import math
import threading
import time
from collections import deque
from collections.abc import Iterable

from ...config.machine import Machine
from ...diagnostics import Diagnostic
from ...plan import Segment
from ...plan.independent import IndependentSegment
from ..base import BackendError, Status
from . import protocol as proto
from . import registers as regs
from .link import Link, LinkError
from .markers import Coalescer, MarkerLog, path_tolerance
from .options import Options, OutputAction, parse_options
from .outputs import OutputTable
from .polling import Polling
from .records import Command, InterpCncError, InterpCncStatus, _OpenGate, _ResetGate, _Sent
from .recovery import Recovery
from .refusals import refused_transformations
from .translate import Encoder, Move, TranslationError, segment_moves
from .watchdog import Watchdog

#: How long the card waits at a shut gate before alarm 18 (the longest 1012 timeout, L1091).
GATE_TIMEOUT_MS = 0xFFFF
#: Gate tokens 1..GATE_TOKENS, then the gate register is set back to 0 (see the module docstring).
GATE_TOKENS = 0xFFFF



class InterpCncBackend(Polling, Recovery, Watchdog):
    """Back-end ``interpcnc`` (options: see :mod:`.options`)."""

    name = "interpcnc"

    def __init__(self, machine: Machine, **options) -> None:
        self.machine = machine
        self.options: Options = parse_options(machine, options)
        opt = self.options
        self.axes = list(machine.axis_names)
        self.card_axes = [opt.axis_map[a] for a in self.axes]
        self.xy = ((self.card_axes.index("X"), self.card_axes.index("Y"))
                   if "X" in self.card_axes and "Y" in self.card_axes else None)
        #: mm/min of an XY arc run at rapid (1003 follows the 1001 feed): the channel's rapid, or the
        #: slower of the axes sent as X and Y (see translate.segment_moves)
        self.rapid_feed = machine.rapid_feed or min((machine.axes[self.axes[i]].max_velocity for i in self.xy or ()),
                                                    default=0.0)
        self.encoder = Encoder(self.axes, opt.axis_map)
        self.outputs = OutputTable(opt)
        self.link = Link(host=opt.host, port=opt.port, serial=opt.serial, baudrate=opt.baudrate, unit=opt.unit,
                         timeout=opt.timeout)
        self.warnings: list[str] = []
        self.stats = {"polls": 0, "commands": 0, "registers": 0, "waits": 0, "low_water": 0, "resyncs": 0,
                      "markers": 0, "underruns": 0, "t_encode": 0.0, "t_write": 0.0, "t_poll": 0.0, "t_wait": 0.0}
        #: the clock and the sleep of every wait and timeout (a test may give the emulator's virtual clock)
        self.clock = time.monotonic
        self.sleep = time.sleep
        #: called with the status while :meth:`finish` waits for the card (progress after the last segment sent)
        self.on_wait = None
        # boxes widened by the resume's path tolerance each: members not consecutive stay 2 tolerances apart
        self.coalescer = Coalescer(self.options.marker_every,
                                   path_tolerance(self.options.resolution, self.options.chordal_tolerance),
                                   len(self.axes))
        #: the segments that carried a marker (see markers.MarkerLog; verify.expected_events reads it)
        self.marker_log = MarkerLog()
        self._dry = False                            # a poll found the card's buffers empty while streaming
        self._stall_mark: tuple | None = None        # what the card reported when progress was last seen
        self._stall_since = 0.0
        self._stall_pulses: list[int] | None = None
        self._first_sent = self._last_sent = 0.0     # clock of the first and the last segment transmitted
        self._stall_code = ""                        # BCK001/BCK002 once the watchdog stopped the stream
        self._lead: float | None = None              # planned s queued behind the start wait, None: no wait shut
        self._lock = threading.Lock()
        self._status = Status(state="closed")
        self._window: deque[_Sent] = deque()        # sent, not known complete (seq order)
        self._pending: deque[Segment] = deque()     # accepted, not yet sent (after a fault)
        self._lines: dict[int, int] = {}             # seq -> source line, from the oldest unconfirmed
        self._seq = 0                                # last sequence number given
        self._marker = 0                             # last marker read, unwrapped
        self._sub = 0                                # last move index read (register M+1)
        self._done = 0                               # highest sequence number known complete
        self._gate = 0                               # last gate token used
        self._gated_seq = 0                          # sequence number of the last segment gated
        self._free = 0                               # free registers in the card buffer (lower bound)
        self._planner_free = 0
        self._card_status = 0
        self._alarm_code = 0
        self._buffer_size = 4096
        self._planner_size = 35
        self._last_poll = -math.inf
        self._last_status = -math.inf                # last refresh by status()
        self._fault: str | None = None               # "alarm" or "link" while stopped by a fault
        self._untrusted_alarm = 0                    # an ALARMS_POSITION_LOST code seen: until abandon()/open()
        self._hold_seen = False                      # the card reported a feed hold or the door since "pause" began
        self._stopped = False

    # ------------------------------------------------------------ protocol
    def open(self) -> None:
        """Connect, check the card is idle and ready (not paused, homing, jogging...), clear the marker registers."""
        try:
            self.link.connect()
            sizes = self.link.read_input(regs.IR_CNC_BUFFER_SIZE, 3, "reading the buffer sizes")
            self._buffer_size = sizes[0] or self._buffer_size
            self._planner_size = sizes[2] or self._planner_size
            self._reset_stream()
            self._read_card()
            self._check_ready()
            if not self._card_alarm() and not self._card_idle():
                self.link.close()
                raise BackendError(f"the InterpCNC at {self.link.where} is busy "
                                   f"({', '.join(proto.decode_status(self._card_status)) or 'buffer not empty'}): "
                                   "stop it before streaming")
            self.link.write(self.options.marker_register, [0, 0, 0], "clearing the sequence and gate registers")
        except LinkError as exc:
            self._set(state="closed")
            raise BackendError(str(exc), self._snapshot()) from exc
        if self._card_alarm():
            self._fault = "alarm"
            self._set(state="alarm", alarm=self._alarm_code, alarm_message=proto.alarm_message(self._alarm_code))
        else:
            self._set(state="idle", alarm=0, alarm_message="")

    def _check_ready(self) -> None:
        """Refuse a card in a state where a stream would hang or start from an unplanned position (L429)."""
        not_ready = self._card_status & regs.STATUS_NOT_READY
        if not_ready:
            self.link.close()
            raise BackendError(f"the InterpCNC at {self.link.where} is not ready "
                               f"({', '.join(proto.decode_status(not_ready))}): end that on the card "
                               "(resume or stop the feed hold, let the homing, jog or tool change finish, "
                               "close the door, wake the card, leave test mode) before streaming")

    def send(self, segment: Segment) -> None:
        """Queue ``segment`` on the card; blocks while its buffer is full (see the module docstring)."""
        if self._status.state == "closed":
            raise InterpCncError("the InterpCNC back-end is not open: segment refused", self._snapshot(),
                                 accepted=False)
        if self._stopped:
            raise InterpCncError("stopped by the operator: segment refused", self._snapshot(), accepted=False)
        if isinstance(segment, IndependentSegment):   # never sent one after the other (see preflight)
            raise InterpCncError(self.preflight(segment), self._snapshot(), accepted=False)
        if segment.kind == "aux" and self.options.strict_outputs:    # refused before it is accepted
            rec = segment.record
            if self.outputs.unmapped(rec.function, rec.value):
                raise InterpCncError(self.outputs.unmapped_message(segment.line, rec.function, rec.value),
                                     self._snapshot(), accepted=False)
        self._pending.append(segment)
        if self._fault:
            raise self._fault_error("segment kept, not sent")
        self._flush()

    def finish(self) -> Status:
        """Block until everything sent has executed and the axes have stopped; returns the status (raises on an
        alarm or link loss).  A feed hold or the door safety on the card (state "pause") keeps it waiting."""
        if self._status.state == "closed":
            raise InterpCncError("the InterpCNC back-end is not open", self._snapshot())
        moving_since = None
        self._stall_reset()
        while True:
            if self._fault:
                raise self._fault_error("cannot finish")
            if self._pending:
                self._flush()
            if self._lead is not None:
                self._io(self._start)
            if self._stopped:
                break
            self._io(self._poll)
            # a feed hold or the door (state "pause") keeps it waiting: ending the hold is the operator's; IR 1016
            # is read only once the buffers look empty, not on every poll
            if self._card_idle() and self._marker == self.marker_log.last:
                if not self._io(self._axes_moving):
                    break
                moving_since = self.clock() if moving_since is None else moving_since
                if self.clock() - moving_since > self.options.stop_timeout:
                    raise self._stalled("BCK002", f"the axes-moving bits (input register {regs.IR_STATUS_BITS}) "
                                        f"stayed set {self.options.stop_timeout:g} s after the card's buffers had "
                                        "emptied")
            else:
                moving_since = None
                self._io(lambda: self._watch("the end of the program"))
            if self.on_wait is not None:
                self.on_wait(self._snapshot())
            self.sleep(self.options.poll_interval)
        self._set(state="idle")
        status = self.status()
        if self.on_wait is not None:
            self.on_wait(status)              # the end: 100 % executed
        return status

    def pause(self) -> None:
        """Feed hold (1200/130; the card also stops the spindle, buffers kept)."""
        self._immediate(proto.encode_pause(), "pause")
        if self._status.state in ("run", "idle"):
            self._hold_seen = False              # "pause" until the card has reported the hold and ended it
            self._set(state="pause")

    def resume(self) -> None:
        """Continue: after a pause 1200/129; after an alarm stop and purge (1200/255), acknowledge (1200/88) and
        resynchronise (see :meth:`reconnect_and_continue`); after a link loss, reconnect first.

        Refused after an alarm that means the machine position can no longer be trusted
        (``registers.ALARMS_POSITION_LOST``: limit switch, homing errors, homing required, tool setter
        triggered, master/slave gap, internal error, motor fault; seed 000 L430): the step counters may
        not match the machine, and after a limit switch continuing drives further toward it.  It then
        raises :class:`InterpCncError` and sends nothing, not even the acknowledge; the state stays
        "alarm".  Call :meth:`abandon`, home the machine and start the program again.  Other alarms
        (soft limit, cycle aborted, probe errors, emergency stop, spindle ready, 1012 timeout) resume.
        """
        if self._fault:
            self._recover(acknowledge=True)
            return
        self._immediate(proto.encode_resume(), "resume")
        if self._status.state == "pause":
            self._hold_seen = False
            self._set(state="run")

    def abandon(self) -> None:
        """Give up the interrupted stream: stop and purge (1200/255), acknowledge the alarm (1200/88), purge again,
        forget every segment sent or kept and clear the fault; the state becomes "idle" and a new stream can be
        sent, as after :meth:`open`.  Nothing of the old stream runs again (see :meth:`_purge_and_acknowledge`).

        The way out of an alarm :meth:`resume` refuses (the machine position can no longer be trusted):
        home the machine before starting the program again.  Raises if the alarm is still active after the
        acknowledge (emergency stop still engaged?); reconnects first after a link loss.
        """
        try:
            self._reconnect()
            self._read_card()              # the status words only: the old stream's markers no longer matter
            if self._card_alarm():
                self._purge_and_acknowledge()
                self._read_card()
                if self._card_alarm():
                    self._raise_alarm_state("still active after the acknowledge (emergency stop still engaged?)")
            # (again after an alarm: in case the card ignored the first one while in alarm, the seed does not say)
            self.link.command(proto.encode_stop(), "stop and purge, abandoning the stream")
            self._await_rest(self._read_card)
            self._reset_stream()
            self.link.write(self.options.marker_register, [0, 0, 0], "clearing the sequence and gate registers")
        except LinkError as exc:
            raise self._link_lost(exc) from exc
        self._set(state="idle", alarm=0, alarm_message="")

    def stop(self) -> None:
        """Immediate stop with deceleration; the card purges its buffers (1200/255).  Nothing more is sent."""
        self._last_status = -math.inf
        with self.link.lock:
            self._stopped = True
            if not self.link.failed:
                try:
                    self.link.command(proto.encode_stop(), "stop")
                except LinkError as exc:
                    self._fault = "link"
                    self._set(state="alarm", alarm_message=f"link lost: {exc}")
            self._pending.clear()
            self._window.clear()
        if self._status.state in ("run", "pause"):
            self._set(state="idle")

    def status(self) -> Status:
        """The card's status, read again when older than ``poll_interval`` (so that calling it after every
        segment costs nothing); the last known one when the link is down.  The position needs ``resolution``."""
        now = self.clock()
        if self._status.state != "closed" and not self.link.failed and now - self._last_status >= \
                self.options.poll_interval:
            self._last_status = now
            try:
                self._read_poll()
                position = self._position()
                if position:
                    self._set(position=position)
            except (LinkError, InterpCncError):
                pass
        return self._snapshot()

    def rate(self) -> float:
        """Segments per second sustained so far: segments sent over the time from the first to the last one
        (0 before two were sent)."""
        span = self._last_sent - self._first_sent
        return (self._status.sent - 1) / span if span > 0 and self._status.sent > 1 else 0.0

    def close(self) -> None:
        self.link.close()
        self._set(state="closed")

    # ------------------------------------------------------------ extras
    def check(self, items: Iterable) -> list[str]:
        """Messages for the auxiliary functions of ``items`` (segments or interpreter records) that the
        ``outputs`` table does not map; run it before streaming."""
        out = []
        for it in items:
            rec = it.record if hasattr(getattr(it, "record", None), "function") else it
            if getattr(rec, "function", None) is None:
                continue
            if self.outputs.unmapped(rec.function, rec.value):
                out.append(self.outputs.unmapped_message(rec.line, rec.function, rec.value))
        return out

    def refusals(self, diagnostics: Iterable[Diagnostic]) -> list[Diagnostic]:
        """Errors (CFG030) for what the check found that this card cannot reproduce (see :mod:`.refusals`):
        :func:`fagorcnc.run` asks before anything is sent."""
        return refused_transformations(diagnostics, self.name)

    def preflight(self, segment: Segment) -> str | None:
        """Why ``segment`` could not be sent to the card (None when it can): the check before a real
        run asks it of every planned segment, so that a stream never stops half-way on one."""
        if isinstance(segment, IndependentSegment):   # a #MOVE running alongside the program (plan/independent.py)
            return (f"the #MOVE of {segment.axis} runs on its own interpolator alongside the program's blocks "
                    f"(seed 002 L16622: the axis follows the sum of both); the {self.name} card has one "
                    f"interpolator and runs its moves one after another, so the axes would not move as "
                    f"planned - nothing was sent")
        if segment.kind != "motion":
            return None
        thread = getattr(segment.record, "thread", None)
        if thread is not None:   # seed 000: the card moves axes only, it has no spindle-synchronised motion
            what = "G63 rigid tap" if thread.rigid else "G33 thread"
            return (f"a {what} needs the axes synchronised with the spindle encoder; the {self.name} card has "
                    f"no spindle-synchronised motion, so the pitch would not be kept")
        try:
            segment_moves(segment, self.xy, self.options.chordal_tolerance, self.rapid_feed)
        except TranslationError as exc:
            return str(exc)
        return None

    def set_override(self, feed: int, rapid: int = 100) -> None:
        """Feed and rapid overrides in % (holding 2430/2431, L455-L456; avoids the 1100/1005 ambiguity)."""
        for name, v in (("feed", feed), ("rapid", rapid)):
            if isinstance(v, bool) or not isinstance(v, int) or not 0 <= v <= 0xFFFF:
                raise BackendError(f"{name} override must be an integer percentage, got {v!r}")
        self._io(lambda: self.link.write(regs.HR_FEED_OVERRIDE, [feed, rapid], "override"))

    def home(self, axis: int | str = 0) -> None:
        """Homing sequence (1110): 0 = all per the card's parameters, or one axis (card index 1-6 or name)."""
        if isinstance(axis, str):
            if axis not in self.options.axis_map:
                raise BackendError(f"home: the machine has no axis {axis}")
            axis = regs.CARD_AXES.index(self.options.axis_map[axis]) + 1
        self._immediate(proto.encode_home(axis), "home")
        self.encoder.reset()   # the card moved without the stream: the next move carries every axis

    def jog(self, targets: dict[str, float], speed: float, *, relative: bool = True) -> None:
        """Jog machine axes by (or to) ``targets`` mm at ``speed`` mm/min (sent in m/min, L1195)."""
        unknown = [a for a in targets if a not in self.options.axis_map]
        if unknown:
            raise BackendError(f"jog: the machine has no axis {unknown[0]}")
        words = proto.encode_jog({self.options.axis_map[a]: v for a, v in targets.items()}, speed, relative=relative)
        self._immediate(words, "jog")
        self.encoder.reset()   # see home()

    def stop_jog(self) -> None:
        self._immediate(proto.encode_direct(regs.DIRECT_STOP_JOG), "stop jog")
        self.encoder.reset()

    def reconnect_and_continue(self) -> None:
        """Operator-initiated recovery after a link failure, a timeout or an exception reply.

        Reconnects, then resynchronises:

        1. if the card is in alarm, raise (acknowledging is the operator's call: :meth:`resume`, or
           :meth:`abandon` after an alarm meaning the position can no longer be trusted, see :meth:`resume`);
        2. 1200/255: stop and purge the card's buffers - whatever was still
           queued there is discarded, so nothing sent twice can run twice;
        3. wait until the card is idle, read the sequence registers (segment n,
           move j) and the position;
        4. segments up to n are complete and are never sent again - except a
           motion segment n, which resumes from the current position: move j
           is completed as a line to the same end, or an XY arc about the
           same centre with I/J recomputed from the current position - or
           skipped when the position is at its end (its position counters
           read it) - then its later moves follow; an output segment n has
           run (its marker follows its actions), a dwell n has if M+1 = 1,
           else it runs again in full (one whose gate had not opened has
           not run at all: it comes next);
        5. every later segment is sent again, in order, with its own sequence
           number (and a fresh gate token), then those ``send`` kept meanwhile.

        Guarantee: every move, every dwell and every synchronised action of the
        stream runs exactly once, except a dwell under way at the fault, which
        runs again in full (the card cannot tell how much of it ran; dwelling
        longer is safe).  Resuming a move needs ``resolution`` for every axis;
        if the machine is not on the interrupted move's path (it was jogged),
        this raises and sends nothing.
        """
        self._recover(acknowledge=False)

    # ------------------------------------------------------------ streaming
    def _reset_stream(self) -> None:
        self._window.clear()
        self._pending.clear()
        self._lines.clear()
        self._seq = self._marker = self._sub = self._done = self._gate = self._gated_seq = 0
        self.coalescer.close()
        self.marker_log.clear()
        self._dry = False
        self._first_sent = self._last_sent = 0.0
        self._lead = None
        self._stall_code = ""
        self.stats["underruns"] = 0
        self._fault = None
        self._untrusted_alarm = 0
        self._hold_seen = False
        self._stopped = False
        self.encoder.reset()
        self._set(line=0, executed=0, sent=0, alarm=0, alarm_message="")

    def _flush(self) -> None:
        while self._pending:
            segment = self._pending[0]
            entry = _Sent(self._seq + 1, segment)
            t0 = time.perf_counter()
            try:
                words = self._prepare(entry)
            except TranslationError as exc:
                self._pending.popleft()
                raise InterpCncError(str(exc), self._snapshot(), accepted=False) from exc
            self.stats["t_encode"] += time.perf_counter() - t0
            if entry.seq == 1 and self.options.start_lead > 0:
                words = [self._start_wait(), *words]
            with self.link.lock:
                self._pending.popleft()
                self._seq = entry.seq
                self._window.append(entry)
                self._lines[entry.seq] = segment.line
            self._transmit(entry, words)
            if self._lead is not None:
                self._lead += float(segment.duration)
                if self._lead >= self.options.start_lead:
                    self._start()

    def _start_wait(self) -> proto.Words:
        """The start lead: a 1012 wait before the stream's first command until the move register M+1 is above 0,
        so that ``start_lead`` s of planned motion are queued before the card moves and a hiccup of the PC
        early in the stream cannot run the card dry.  M+1 is 0 (cleared by open()) and nothing of the stream
        writes it before the wait is over; :meth:`_start` writes 1 into it.  On timeout the card goes on (no
        alarm): the wait holds back nothing that must not run."""
        self._lead = 0.0
        return proto.encode_wait_value(regs.EXTENDED_HOLDING + self.options.marker_register + 1, regs.WAIT_ABOVE, 0,
                                       GATE_TIMEOUT_MS, alarm_on_timeout=False)

    def _start(self) -> None:
        """Let the card start (see :meth:`_start_wait`): once the lead is queued, when the back-end must wait for
        the card (room, a gate, the end), never later."""
        if self._lead is None:
            return
        self._lead = None
        with self.link.lock:
            self._check_stopped()
            self.link.write(self.options.marker_register + 1, [1], "starting the stream (the start lead is queued)")

    def _prepare(self, entry: _Sent, moves: list[Move] | None = None, first: int = 0) -> list[Command]:
        """The commands of a segment with its markers (order: see the module docstring).

        ``moves``/``first``: for a resumed segment, the moves left and the index of the first one.
        """
        seg = entry.segment
        reg = self.options.marker_register
        marker = proto.encode_register_write(reg, entry.seq & 0xFFFF)
        if seg.kind == "motion":
            if moves is None:
                entry.moves = moves = segment_moves(seg, self.xy, self.options.chordal_tolerance, self.rapid_feed)
            if len(entry.moves) == 1:
                if not self.coalescer.place(moves):      # joins the open group: no marker of its own
                    entry.head = self.marker_log.last
                    return self.encoder.encode(moves)
                self._headed(entry)
                return [marker, *self.encoder.encode(moves)]
            self.coalescer.close()
            self._headed(entry)
            out = []
            for j, m in enumerate(moves, start=first):
                out.append(proto.encode_register_write(reg + 1, j))
                if j == first:                   # the move index first: never read beside a stale one
                    out.append(marker)
                out += self.encoder.encode([m])
            return out
        self.coalescer.close()
        self._headed(entry)
        if seg.kind == "dwell":
            dwell = proto.encode_dwell(float(getattr(seg.record, "seconds", seg.duration)))
            if not dwell:
                return [marker]
            entry.end_sub = 1
            return self._gated(entry, [proto.encode_register_write(reg + 1, 0), marker, *dwell,
                                       proto.encode_register_write(reg + 1, entry.end_sub)])
        if seg.kind == "aux":
            actions = self._aux_words(seg)
            return self._gated(entry, [*actions, marker]) if actions else [marker]
        return [marker]

    def _headed(self, entry: _Sent) -> None:
        """``entry`` carries its own marker."""
        entry.head = entry.seq
        self.marker_log.add(entry.seq)
        self.stats["markers"] += 1

    def _gated(self, entry: _Sent, body: list[proto.Words]) -> list[Command]:
        """``body`` held behind a wait until the gate opens (see the module docstring)."""
        out: list[Command] = []
        if self._gate == GATE_TOKENS:
            out.append(_ResetGate(self._gated_seq))
            self._gate = 0
        self._gate += 1
        self._gated_seq = entry.seq
        # seed 000 L1113-L1115: 1012 addresses holding register r as 100000 + r; "above" is strict (L1105)
        out.append(proto.encode_wait_value(regs.EXTENDED_HOLDING + self.options.marker_register + 2,
                                           regs.WAIT_ABOVE, self._gate - 1, GATE_TIMEOUT_MS, alarm_on_timeout=True))
        return [*out, *body, _OpenGate(self._gate)]

    def _transmit(self, entry: _Sent, commands: list[Command]) -> None:
        try:
            for words in commands:
                if isinstance(words, _ResetGate):
                    self._await_done(words.after)
                if isinstance(words, (_OpenGate, _ResetGate)):
                    token = words.token if isinstance(words, _OpenGate) else 0
                    with self.link.lock:
                        self._check_stopped()
                        self.link.write(self.options.marker_register + 2, [token], "writing the gate register")
                    continue
                self._room(len(words))
                with self.link.lock:             # a poll from another thread sees the write and the count
                    self._check_stopped()
                    t0 = time.perf_counter()
                    self.link.command(words)
                    self.stats["t_write"] += time.perf_counter() - t0
                    self._free -= len(words)
                self.stats["commands"] += 1
                self.stats["registers"] += len(words)
        except LinkError as exc:
            raise self._link_lost(exc) from exc
        entry.transmitted = True
        if self._dry:                            # the card had run dry, and the stream goes on: an underrun
            self._dry = False
            self.stats["underruns"] += 1
        now = self.clock()
        with self._lock:
            if not self._status.sent:
                self._first_sent = now
            self._last_sent = now
            self._status.sent += 1
            if self._status.state == "idle":
                self._status.state = "run"

    def _await_done(self, seq: int) -> None:
        """Poll until segment ``seq`` has run (raises on an alarm or a stop)."""
        self._stall_reset()
        self._start()
        while True:
            self._poll()
            if self._done >= seq:
                return
            self._check_stopped()
            self._watch(f"the card to pass the gate of segment {seq}")
            self.stats["waits"] += 1
            self._pause(self.options.poll_interval)

    def _check_stopped(self) -> None:
        if self._stopped:
            raise InterpCncError("stopped by the operator", self._snapshot())

    def _room(self, size: int) -> None:
        """Wait until ``size`` registers fit the card's buffer; polls the status every poll_interval.

        Once the local estimate runs out, the buffer is refilled in batches:
        the back-end waits for a quarter of it to be free (fewer polls) unless
        the planner holds fewer than ``low_water`` entries, when any room will do.
        """
        opt = self.options
        if size > self._buffer_size:
            raise InterpCncError(f"a command of {size} registers cannot fit the card's "
                                 f"{self._buffer_size}-register buffer", self._snapshot())
        batch = max(size, self._buffer_size // 4)
        waited = False
        while True:
            if self._free >= size:
                if self.clock() - self._last_poll < opt.poll_interval:
                    return
                self._poll()                     # the periodic check for an alarm while the estimate has room
                if self._free >= size:
                    return
            self._start()                        # the card must consume: the lead is as long as the buffer allows
            self._poll()
            low = self._planner_size - self._planner_free < opt.low_water
            if self._free >= (size if low else batch):
                return
            self._check_stopped()
            if not waited:
                waited = True
                self._stall_reset()
            self._watch(f"room for {size} registers in the card's buffer")
            self.stats["waits"] += 1
            if low:
                self.stats["low_water"] += 1
                self._pause(0.001)
            else:
                self._pause(opt.poll_interval)

    def _pause(self, seconds: float) -> None:
        t0 = time.perf_counter()
        self.sleep(seconds)
        self.stats["t_wait"] += time.perf_counter() - t0

    def _immediate(self, words: list[int], what: str) -> None:
        self._io(lambda: self.link.command(words, what))

    def _io(self, fn):
        self._last_status = -math.inf            # the next status() reads the card again
        try:
            return fn()
        except LinkError as exc:
            raise self._link_lost(exc) from exc

    # ------------------------------------------------------------ auxiliary functions
    def actions_for(self, function: str, value: float) -> tuple[OutputAction, ...] | None:
        """The ``outputs`` entry for an auxiliary function (``M3`` first, then ``M``); None when unmapped."""
        return self.outputs.actions(function, value)

    def _aux_words(self, seg: Segment) -> list[proto.Words]:
        rec = seg.record
        tr = self.outputs.translate(seg.line, rec.function, rec.value)
        if not tr.mapped and self.options.strict_outputs:
            raise InterpCncError(tr.warnings[0], self._snapshot(), accepted=False)
        self.warnings += tr.warnings
        return tr.commands

    def _set(self, **fields) -> None:
        with self._lock:
            for k, v in fields.items():
                setattr(self._status, k, v)

    def _snapshot(self) -> Status:
        with self._lock:
            s = self._status
            return InterpCncStatus(s.state, s.alarm, s.alarm_message, s.line, s.executed, s.sent, dict(s.position),
                                   s.buffer_level, dict(s.velocity), dict(s.target), self.rate(),
                                   self.stats["underruns"], "stall" if self._stall_code else (self._fault or ""))

