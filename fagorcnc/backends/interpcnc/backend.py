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
``registers.DEFAULT_MARKER_REGISTER``; L463, L967-L971).  The card runs
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
from dataclasses import dataclass, field

import numpy as np

from ...config.machine import Machine
from ...diagnostics import Diagnostic
from ...plan import Segment
from ..base import BackendError, Status
from . import protocol as proto
from . import registers as regs
from .link import Link, LinkError
from .markers import Coalescer, MarkerLog, locate, path_tolerance
from .options import Options, OutputAction, parse_options
from .outputs import OutputTable
from .refusals import refused_transformations
from .translate import Encoder, Move, TranslationError, remaining_moves, segment_moves


class InterpCncError(BackendError):
    """The InterpCNC back-end stopped.

    ``alarm``: the card's alarm code (0 for a link failure); ``line``: source
    line of the last segment known started; ``accepted``: whether the segment
    given to the failing ``send`` was kept (True: recovery will deliver it,
    do not send it again); ``code``: a diagnostic code when the cause has one
    (``BCK001`` the card stopped consuming, ``BCK002`` an axis never stopped).
    """

    def __init__(self, message: str, status: Status | None = None, *, alarm: int = 0, line: int = 0,
                 accepted: bool = True, code: str = "") -> None:
        super().__init__(message, status)
        self.alarm = alarm
        self.line = line
        self.accepted = accepted
        self.code = code


#: How long the card waits at a shut gate before alarm 18 (the longest 1012 timeout, L1091).
GATE_TIMEOUT_MS = 0xFFFF
#: Gate tokens 1..GATE_TOKENS, then the gate register is set back to 0 (see the module docstring).
GATE_TOKENS = 0xFFFF


@dataclass(frozen=True)
class _OpenGate:
    """Not a card command: the direct write of ``token`` into the gate register (see the module docstring)."""

    token: int


@dataclass(frozen=True)
class _ResetGate:
    """Not a card command: once segment ``after`` (the last one gated) has run, the gate register back to 0."""

    after: int


Command = proto.Words | _OpenGate | _ResetGate


@dataclass
class _Sent:
    """A segment with its sequence number, its moves (motion) and whether all its commands went out."""

    seq: int
    segment: Segment
    moves: list[Move] = field(default_factory=list)
    transmitted: bool = False
    head: int = 0                  # the sequence number its marker carries (its group's head; its own when it has one)

    end_sub: int | None = None     # the M+1 value written when it ends (a dwell); None: M = seq says it has run

    def has_run(self, sub: int) -> bool:
        """Whether it has run, the card's M holding its number and M+1 holding ``sub`` (see the module docstring)."""
        if self.segment.kind == "motion":
            return False                 # M = seq: started; the position tells how far
        return self.end_sub is None or sub == self.end_sub


class InterpCncBackend:
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
        if segment.kind != "motion":
            return None
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

    # ------------------------------------------------------------ the watchdog (issue 30 items 13, 14)
    def _stall_reset(self) -> None:
        self._stall_mark, self._stall_pulses, self._stall_since = None, None, self.clock()

    def _watch(self, waiting_for: str) -> None:
        """After a poll in a wait: raise BCK001 when the card has shown no progress for ``stall_timeout`` s
        (plus the dwell it is running) although it holds commands.

        Progress is any change of the free space (IR 3000, 3002), of the marker registers or, read only once the
        rest has stood still, of the position counters (a long slow move); a feed hold or the door (the
        operator's, IR 3003 bits 4 and 6) is never a stall.
        """
        if self._card_status & regs.STATUS_HELD:
            self._stall_reset()
            return
        mark = (self._free, self._planner_free, self._marker, self._sub)
        now = self.clock()
        if mark != self._stall_mark:
            self._stall_mark, self._stall_pulses, self._stall_since = mark, None, now
            return
        if self._stall_pulses is None:          # standing still since the last poll: note where the axes are
            self._stall_pulses = self._pulses()
            return
        limit = self.options.stall_timeout
        head = self._window[0] if self._window else None
        if head is not None and head.seq == self._marker and head.segment.kind == "dwell":
            limit += float(head.segment.duration)
        if now - self._stall_since <= limit:
            return
        pulses = self._pulses()
        if pulses != self._stall_pulses:
            self._stall_pulses, self._stall_since = pulses, now
            return
        raise self._stalled("BCK001", f"the card has consumed nothing for {limit:g} s while the back-end waited "
                            f"for {waiting_for}: input register {regs.IR_CNC_BUFFER_FREE} (free space in the CNC "
                            f"buffer) reads {self._free} of {self._buffer_size}, {regs.IR_PLANNER_FREE} (planner) "
                            f"{self._planner_free} of {self._planner_size}, the sequence register "
                            f"{self.options.marker_register} and the position counters have not changed")

    def _pulses(self) -> list[int]:
        return self.link.read_input(regs.IR_AXIS_POSITION, 12, "reading the position counters")

    def _stalled(self, code: str, what: str) -> InterpCncError:
        """Stop (1200/255, nothing more is sent) and the error: what the card reports, the last block."""
        sent = self._lines.get(self._seq, 0)
        message = (f"InterpCNC: {what}; stopped the card (1200/255) and the stream (timeout set by "
                   f"{'stall_timeout' if code == 'BCK001' else 'stop_timeout'}); {self._where_text()}"
                   f"{f', last block sent: line {sent}' if sent else ''}")
        self.stop()
        self._set(state="alarm", alarm_message=message)
        return InterpCncError(message, self._snapshot(), line=self._status.line, code=code)

    # ------------------------------------------------------------ polling
    def _read_card(self) -> None:
        """IR 3000-3004 in one request: free registers, Grbl free, planner free, status, alarm."""
        with self.link.lock:
            t0 = time.perf_counter()
            free, _grbl, pfree, status, alarm = self.link.read_input(regs.POLL_FIRST, regs.POLL_COUNT, "status poll")
            self.stats["t_poll"] += time.perf_counter() - t0
            self._free, self._planner_free, self._card_status, self._alarm_code = free, pfree, status, alarm
            self._last_poll = self.clock()
            self.stats["polls"] += 1

    def _read_poll(self, *, purged: bool = False) -> None:
        """The card's status words and the marker registers; updates the window and the status.

        An idle card with empty buffers has run everything sent - unless it purged them (an alarm, a
        stop): ``purged`` (or an alarm, a fault, a stop) forbids that inference, a motion segment whose
        marker was read last is then only known to have started (a dwell's or an output's marker says
        it has run).
        """
        with self.link.lock:                     # one consistent view, whichever thread polls
            self._read_poll_locked(purged)

    def _read_poll_locked(self, purged: bool) -> None:
        self._read_card()
        t0 = time.perf_counter()
        raw, self._sub = self.link.read_holding(self.options.marker_register, 2, "reading the sequence registers")
        self.stats["t_poll"] += time.perf_counter() - t0
        marker = self._marker + ((raw - self._marker) & 0xFFFF)
        if marker > self._seq:
            self._fault = "alarm"
            msg = (f"the sequence register {self.options.marker_register} holds {raw}, which this stream never "
                   "sent: another client wrote it or the card was reset")
            self._set(state="alarm", alarm_message=msg)
            raise InterpCncError(msg, self._snapshot())
        for seq in range(self._marker, marker):
            self._lines.pop(seq, None)
        self._marker = marker
        purged = purged or self._card_alarm() or self._fault is not None or self._stopped
        complete = not purged and self._card_idle() and all(e.transmitted for e in self._window)
        window = self._window
        while window and window[0].seq < marker:
            window.popleft()
        if window and window[0].seq == marker and window[0].segment.kind == "motion":
            # the move the card is running (its marker went out first): where it goes, for a PLC
            self._set(target=dict(zip(self.axes, window[0].segment.piece.end.tolist(), strict=True)))
        if window and window[0].seq == marker:
            if complete and marker == self.marker_log.last:     # idle: the whole group has run
                self._done = window[-1].seq
                window.clear()
            elif window[0].has_run(self._sub):
                window.popleft()
                self._done = marker
        self._done = max(self._done, marker - 1)
        # buffers empty mid-stream (not after a stop or an alarm): the card ran dry - an underrun if more follows
        self._dry = not purged and self._card_idle() and self._status.state == "run" and self._seq > 0
        line = self._lines.get(marker, self._status.line) if marker else 0
        level = max(1.0 - self._free / self._buffer_size, 1.0 - self._planner_free / self._planner_size)
        self._set(executed=self._done, line=line, buffer_level=level)
        self._follow_hold()

    def _follow_hold(self) -> None:
        """A stream held by the card (feed hold, also from a hardware input L1141, or the door safety: IR 3003 bits
        4, 6, L429) shows as state "pause", and as "run" again when the card lets it go: the progress line and a PLC
        then see why nothing moves."""
        held = bool(self._card_status & regs.STATUS_HELD)
        with self._lock:
            state = self._status.state
            if held and state in ("run", "pause"):
                self._hold_seen = True
                self._status.state = "pause"
            elif not held and state == "pause" and self._hold_seen:
                self._hold_seen = False
                self._status.state = "run" if self._window else "idle"

    def _poll(self) -> None:
        """Read the card's status words and the markers (raises on an alarm).  The markers are read on every poll,
        the periodic ones included: the line an error names (the last block started) is then at most one poll
        interval old, which the fault campaign holds the back-end to."""
        self._read_poll()
        if self._card_alarm():
            self._fault = "alarm"
            code = self._alarm_code
            self._note_alarm(code)
            self._set(state="alarm", alarm=code, alarm_message=proto.alarm_message(code))
            advice = (" the machine position can no longer be trusted: call abandon(), home the machine and start "
                      "the program again;" if self._untrusted_alarm else self._gate_advice(code))
            raise InterpCncError(f"InterpCNC {proto.describe_alarm(code)}: stopped sending;{advice} "
                                 f"{self._where_text()}", self._snapshot(), alarm=code, line=self._status.line)

    def _gate_advice(self, code: int) -> str:
        """For alarm 18 in a stream with gates: the gate's 1012 address convention may be wrong (audit B1).

        Raised here, with the link up all along, the back-end had opened the gate (it writes the token as soon as the
        segment's commands are accepted).  The seed gives two readings of 1012's address 100000 + r (holding r:
        L460, L1113-L1115, which the back-end follows; input register r: L250, L775-L791, L1291).
        """
        if code != regs.ALARM_WAIT_TIMEOUT or not self._gated_seq:
            return ""
        gate = self.options.marker_register + 2
        return (" an output or a dwell waited 65 s at its gate, which the back-end had opened (holding register "
                f"{gate}; the card watches it as address {regs.EXTENDED_HOLDING + gate}): this card probably reads "
                f"that address as input register {gate} instead (the protocol document gives both meanings), so no "
                "gate can ever open - almost certainly so if it stopped at the first output or dwell of the program; "
                "ask the card's maker which one it uses (the gate registers come from the option marker_register, "
                f"now {self.options.marker_register});")

    def _note_alarm(self, code: int) -> None:
        """Remember an alarm after which the position is not trusted, even if someone acknowledges it on
        the card: only abandon() forgets it."""
        if code in regs.ALARMS_POSITION_LOST:
            self._untrusted_alarm = code

    def _card_alarm(self) -> bool:
        return bool(self._card_status & regs.STATUS_ALARM or self._alarm_code)

    def _card_idle(self) -> bool:
        # Exact: empty means free space = size (IR 3000 vs 2990, 3002 vs 2992; L423-L428, L848-L850).  Nothing in the
        # seed says an empty buffer can report less; a card that did would make finish() wait forever (audit B5).
        return (self._free >= self._buffer_size and self._planner_free >= self._planner_size
                and not self._card_status & regs.STATUS_CYCLE)

    def _axes_moving(self) -> bool:
        """IR 1016's low byte: an axis still moving (L260; L512 "check that the axes have really stopped").

        The planner may free its last entry before the axes have stopped.  Read only where the back-end decides
        that motion has ended (finish(), after a stop), so the status poll on the streaming path stays one request.
        """
        bits = self.link.read_input(regs.IR_STATUS_BITS, 1, "reading the axes-moving bits")[0]
        return bool(bits & regs.AXES_MOVING_MASK)

    def _where_text(self) -> str:
        s = self._status
        if not s.line:
            return "no block had started"
        return f"last block started: line {s.line} ({s.executed} segments complete)"

    def _position(self) -> dict[str, float]:
        res = self.options.resolution
        if not res:
            return {}
        pulses = proto.decode_i32_list(self.link.read_input(regs.IR_AXIS_POSITION, 12, "reading the position"))
        return {a: pulses[regs.CARD_AXES.index(c)] / res[a] for a, c in zip(self.axes, self.card_axes, strict=True)
                if a in res}

    # ------------------------------------------------------------ faults and recovery
    def _link_lost(self, exc: LinkError) -> InterpCncError:
        self._fault = "link"
        self._set(state="alarm", alarm=0, alarm_message=f"link lost: {exc}")
        return InterpCncError(f"{exc}; stopped sending. {self._where_text()} (as last read). "
                              "Call reconnect_and_continue() when the link is back.", self._snapshot(),
                              line=self._status.line)

    def _fault_error(self, what: str) -> InterpCncError:
        s = self._status
        how = "resume() to acknowledge the alarm" if self._fault == "alarm" else "reconnect_and_continue()"
        if self._untrusted_alarm:
            how = "abandon() to acknowledge the alarm and discard the stream"
        return InterpCncError(f"the InterpCNC back-end is stopped ({s.alarm_message}): {what}; call {how} first",
                              self._snapshot(), alarm=s.alarm, line=s.line)

    def _immediate(self, words: list[int], what: str) -> None:
        self._io(lambda: self.link.command(words, what))

    def _io(self, fn):
        self._last_status = -math.inf            # the next status() reads the card again
        try:
            return fn()
        except LinkError as exc:
            raise self._link_lost(exc) from exc

    def _recover(self, *, acknowledge: bool) -> None:
        """Reconnect if needed, acknowledge an alarm if allowed, then resynchronise."""
        try:
            self._reconnect()
            self._read_poll(purged=True)
            if self._card_alarm():
                self._note_alarm(self._alarm_code)
            if self._untrusted_alarm:
                self._refuse_untrusted()
            if self._card_alarm():
                if not acknowledge:
                    self._raise_alarm_state("acknowledge it with resume()")
                self._purge_and_acknowledge()
                self._read_poll(purged=True)
                if self._card_alarm():
                    self._raise_alarm_state("still active after the acknowledge (emergency stop still engaged?)")
            self._resync()
        except LinkError as exc:
            raise self._link_lost(exc) from exc

    def _reconnect(self) -> None:
        """The start of a recovery: the back-end must be open; the link is connected again if it failed
        (raises LinkError for the caller to report)."""
        self._last_status = -math.inf
        if self._status.state == "closed":
            raise InterpCncError("the InterpCNC back-end is not open", self._snapshot())
        if self.link.failed:
            self.link.connect()

    def _purge_and_acknowledge(self) -> None:
        """1200/255 (stop, purge both buffers), then 1200/88 (acknowledge the alarm).

        The seed says only 255 purges the buffers (L1225) and that a pause keeps them (L1139); nothing says an
        alarm empties them.  A card that kept them would, once acknowledged, carry on with what was queued - after
        alarm 18 the body behind a gate nobody opened (half an M function), after a limit switch more travel
        toward it - for the round trips until the resynchronisation's own 255.  Purged first, nothing is left to run.
        """
        self.link.command(proto.encode_stop(), "stop and purge before acknowledging the alarm")
        self.link.command(proto.encode_ack_alarm(), "acknowledging the alarm")

    def _refuse_untrusted(self) -> None:
        """Raise (nothing sent) for an alarm of regs.ALARMS_POSITION_LOST: see resume()."""
        # the card's alarm, or the one that stopped the stream if someone acknowledged it behind our back
        code = self._alarm_code if self._alarm_code in regs.ALARMS_POSITION_LOST else self._untrusted_alarm
        self._raise_alarm_state("the machine position can no longer be trusted, so the interrupted program is "
                                "not continued; call abandon() to acknowledge the alarm and discard the stream, "
                                "then home the machine and start the program again", code)

    def _raise_alarm_state(self, advice: str, code: int | None = None) -> None:
        code = self._alarm_code if code is None else code
        self._fault = "alarm"
        self._set(state="alarm", alarm=code, alarm_message=proto.alarm_message(code))
        raise InterpCncError(f"InterpCNC {proto.describe_alarm(code)}: {advice}; {self._where_text()}",
                             self._snapshot(), alarm=code, line=self._status.line)

    def _resync(self) -> None:
        # after a link fault the only stop; after an alarm a second one, in case the card ignored the first (sent
        # in alarm, _purge_and_acknowledge): the seed does not say it honours 255 then.  At rest it costs nothing.
        self.link.command(proto.encode_stop(), "stop and purge before resuming")
        self._await_rest()
        marker = self._marker
        redo = [e for e in self._window if e.seq >= marker]
        # the segments under the marker read: its own, and those sent without a marker of their own after it
        group = [e for e in redo if e.head == marker] if marker else []
        plans: list[tuple[_Sent, list[Command]]] = []
        self.encoder.reset(at_start=True)   # the interrupted move resumes from the position read back
        self.coalescer.close()              # the first segment sent again carries its own marker
        self.marker_log.forget_after(marker)
        if len(group) > 1:
            plans = self._resume_group(group)
            redo = redo[len(group):]
        for e in redo:
            fresh = _Sent(e.seq, e.segment, e.moves, end_sub=e.end_sub)
            words = self._resume_words(fresh) if e.seq == marker else self._prepare(fresh)
            if words is not None:
                plans.append((fresh, words))
        self._fault = None
        self.stats["resyncs"] += 1
        with self.link.lock:
            # every segment to send again is in the window before the first write: a fault half-way through
            # leaves the rest there (not transmitted) for the next resynchronisation, nothing is forgotten
            self._window.clear()
            self._window.extend(fresh for fresh, _ in plans)
        self._set(state="run", alarm=0, alarm_message="")
        sent = self._status.sent
        for fresh, words in plans:
            self._transmit(fresh, words)
        with self._lock:
            self._status.sent = sent        # segments sent again were counted the first time
        self._flush()

    def _await_rest(self, read=None) -> None:
        """After a 1200/255: poll (``read``, by default the status and markers) until the card is idle with
        empty buffers and no axis moving (the position read next must be where it stopped, not mid-deceleration)."""
        deadline = self.clock() + max(10.0, 20 * self.options.timeout)
        while True:
            if read is None:
                self._read_poll(purged=True)
            else:
                read()
            if self._card_idle() and not self._axes_moving():
                return
            if self.clock() > deadline:
                raise InterpCncError(f"the InterpCNC did not come to rest after stop (1200/255): input registers "
                                     f"{regs.IR_CNC_BUFFER_FREE}-{regs.IR_CNC_STATUS} (buffers, status) or "
                                     f"{regs.IR_STATUS_BITS} (axes moving) still report motion; "
                                     f"{self._where_text()}", self._snapshot(), code="BCK002")
            self.sleep(self.options.poll_interval)

    def _resume_group(self, group: list[_Sent]) -> list[tuple[_Sent, list[Command]]]:
        """The commands finishing a group of straight moves sharing one marker (see :mod:`.markers`): the move
        under way is found from the position counters (:func:`.markers.locate`), the moves before it are complete,
        it is finished from where the machine stands (or skipped at its end), the later ones are sent again."""
        res = self.options.resolution
        missing = [a for a in self.axes if a not in res]
        first = group[0].segment.line
        if missing:
            raise InterpCncError(f"cannot resume line {first}: the position of axis {missing[0]} cannot be read "
                                 "back without 'resolution' (pulses per mm)", self._snapshot())
        pulses = proto.decode_i32_list(self.link.read_input(regs.IR_AXIS_POSITION, 12, "reading the position"))
        counts = np.array([float(pulses[regs.CARD_AXES.index(c)]) for c in self.card_axes])
        scale = np.array([res[a] for a in self.axes])
        pos = counts / scale
        tol = path_tolerance(res, self.options.chordal_tolerance)
        moves = [e.moves[0] for e in group]
        i = locate(moves, pos, counts, scale, tol)
        rest = None if i is None else remaining_moves(moves[i:i + 1], pos, 0.5 / scale, tol)
        if rest is None:
            raise InterpCncError(f"cannot resume line {first}: the machine is not on the path of the interrupted "
                                 "moves (was it moved?); nothing was sent", self._snapshot())
        self._done = max(self._done, group[i].seq - 1)
        plans: list[tuple[_Sent, list[Command]]] = []
        if rest:                                       # the move under way, from where the machine stands
            e = group[i]
            fresh = _Sent(e.seq, e.segment, rest)
            plans.append((fresh, self._prepare(fresh, rest)))
        for e in group[i + 1:]:
            fresh = _Sent(e.seq, e.segment, e.moves)
            plans.append((fresh, self._prepare(fresh)))
        return plans

    def _resume_words(self, entry: _Sent) -> list[Command] | None:
        """Commands finishing the segment that had started (marker = its number); None when nothing is left."""
        if entry.has_run(self._sub):
            return None
        if not entry.moves:
            return self._prepare(entry)                   # a dwell cut short runs again in full
        res = self.options.resolution
        missing = [a for a in self.axes if a not in res]
        if missing:
            raise InterpCncError(f"cannot resume line {entry.segment.line}: the position of axis {missing[0]} "
                                 "cannot be read back without 'resolution' (pulses per mm)", self._snapshot())
        position = self._position()
        pos = np.array([position[a] for a in self.axes])
        j = self._sub if len(entry.moves) > 1 else 0
        if not 0 <= j < len(entry.moves):
            raise InterpCncError(f"cannot resume line {entry.segment.line}: move register holds {j}, the block has "
                                 f"{len(entry.moves)} moves", self._snapshot())
        # at its end = the position counters read its end (the card then counts it as done)
        end_tol = np.array([0.5 / res[a] for a in self.axes])
        path_tol = max(3.0 / min(res.values()), self.options.chordal_tolerance)
        rest = remaining_moves(entry.moves[j:], pos, end_tol, path_tol)
        if rest is None:
            raise InterpCncError(f"cannot resume line {entry.segment.line}: the machine is not on the path of the "
                                 "interrupted move (was it moved?); nothing was sent", self._snapshot())
        if not rest:
            return None
        return self._prepare(entry, rest, first=len(entry.moves) - len(rest))

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
            return Status(s.state, s.alarm, s.alarm_message, s.line, s.executed, s.sent, dict(s.position),
                          s.buffer_level, dict(s.velocity), dict(s.target))

