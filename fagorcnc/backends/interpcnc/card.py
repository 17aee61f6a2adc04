"""A model of the InterpCNC V3 as seen through its registers (no I/O; the emulator serves it over Modbus).

What it models, from seed 000:

* The **CNC Modbus buffer** (commands written at holding 2000, L844-L850):
  a buffered command (1001-1012) is appended with its size in registers;
  input register 3000 is the free space.  A command that does not fit is
  refused with Modbus exception 6 (device busy) and counted in
  ``overflows`` - a correct client never causes one.
* The **planner** (at most ``planner_size`` = 35 entries, IR 3002): moves,
  dwells and waits take one entry each; a synchronised action (1010) and a
  feed change (1001) ride along in order and run when they reach the head,
  i.e. just before the next move starts (L941) - or at once when nothing is
  queued, as the document says.
* **Motion**: a move runs at its feed (1001, mm/min; power-on 1 mm/min,
  L884) times the feed override, a rapid (1002 bit 6) at ``rapid_speed``
  times the rapid override, at constant speed (no acceleration), ``speed``
  times faster than real time.  1003 arcs take I/J relative to their start
  point (the choice documented in :func:`.protocol.encode_arc_xy`).  Time
  advances lazily, whenever :meth:`Card.advance` is called, by at most
  ``max_lag`` seconds of wall clock per call: an emulator starved of CPU
  (a loaded test machine) stands still instead of jumping ahead and
  emptying its buffers in one burst, which no real card does.
* **Immediate commands**: 1100 overrides (also holding 2430/2431), 1101/1102
  and 1200/130/129 pause/resume, 1200/255 stop (the move in progress is
  abandoned and both buffers purged, L1225), 1200/88 alarm acknowledge,
  1110 homing (instantaneous), 1111 jog (m/min, only when idle or jogging,
  L1175), 1200/133 stop jog.
* **Alarms** (IR 3003 bit 0, IR 3004): :meth:`Card.raise_alarm` stops at
  once and purges both buffers.  The seed does not say an alarm purges them
  (only 1200/255 does, L1225): ``keep_buffers_on_alarm`` models the other
  reading - motion stops where it is, and after the acknowledge (1200/88)
  the card carries on with what was queued (a 1012 wait that timed out is
  over).  While the alarm stands, buffered commands are discarded (counted
  in ``discarded``).  Alarm 10 (emergency stop) cannot be acknowledged until
  :meth:`release_estop`.
* **Holds**: ``paused`` (1200/130, IR 3003 bit 4) and ``door`` (door safety,
  bit 6, L429) stop motion, buffers kept.  ``extra_moving``: axes-moving bits
  reported in IR 1016 on top of the model's own (L260) - a card whose axes
  are still stopping after its planner has emptied.
* The **executed log**: every completed command in order (moves with their
  end point as decoded, dwells, actions), each tagged with the value the
  watched register (the back-end's sequence marker) held when it ran.
* **Underruns**: the planner ran dry after a move or dwell completed, and
  another buffered command arrived later without a pause, stop or alarm in
  between - the motion stopped although the stream had not ended.
* Also: 1012 waits (digital inputs by level - edges are approximated by
  levels -, analog inputs, Modbus values; alarm 18 on timeout), soft
  limits (``limits``: alarm 2 when a move would end outside), position
  counters in IR 1030-1041 / HR 2400-2411 from ``resolution``, outputs in
  HR 2150-2165 and coils.  Command 1000 strings are only recorded
  (``gcode``): there is no G-code interpreter here.  The table's 1005
  (L1133) is refused like any unknown id.
* A card that misbehaves: ``report_full_after`` = n - once n buffered
  commands were accepted, IR 3000 reads 0 (no free space) for ever, while the
  card goes on running what it holds; ``extra_moving`` (above) set for good -
  the axes-moving bits never clear.  Against both the back-end must stop
  with an error after its timeouts, never wait for ever (issue 30 items 13, 14).
* Faults for tests: :meth:`Card.hold_full` (stops consuming for a while),
  :meth:`Card.schedule_alarm` (an alarm half-way through the n-th move).
"""

from __future__ import annotations

import math
import time
from collections import deque
from dataclasses import dataclass, field

from . import protocol as proto
from . import registers as regs

NAXES = len(regs.CARD_AXES)
BUSY, ILLEGAL_VALUE = 6, 3          # Modbus exception codes returned by write()
_KINDS = {regs.CMD_SYNC_ACTION: "action", regs.CMD_FEED: "feed", regs.CMD_DWELL: "dwell", regs.CMD_WAIT: "wait",
          regs.CMD_ARC_XY: "arc"}


@dataclass
class Executed:
    """One completed command of the executed log.

    ``kind``: "rapid", "line", "arc", "dwell", "action", "feed", "wait", "jog" or "home";
    ``end``: positions of the card axes X..C after a move (as decoded: single
    precision values); ``tag``: the watched register's value when it ran;
    ``t``: machine time (s) at completion.
    """

    cid: int
    kind: str
    end: tuple[float, ...] | None
    args: dict
    tag: int
    t: float


@dataclass
class _Entry:
    """A command in the planner (or the jog in progress)."""

    cmd: proto.Command
    kind: str
    started: bool = False
    start: list[float] = field(default_factory=list)
    end: list[float] = field(default_factory=list)
    length: float = 0.0
    s: float = 0.0                    # progress: mm for moves, s for dwells/waits
    arc: tuple | None = None          # (cx, cy, r0, r1, theta0, sweep)
    speed: float = 0.0                # mm/min for jogs


class Card:
    """The card's state; every method takes the wall-clock time implicitly (``clock``)."""

    def __init__(self, *, speed: float = 1.0, buffer_size: int = 4096, planner_size: int = 35,
                 rapid_speed: float = 10000.0, resolution: float | dict[str, float] = 1000.0,
                 limits: dict[str, tuple[float, float]] | None = None,
                 watch_register: int = regs.DEFAULT_MARKER_REGISTER, max_lag: float = 0.02,
                 keep_buffers_on_alarm: bool = False, clock=time.monotonic,
                 report_full_after: int | None = None) -> None:
        if speed <= 0:
            raise ValueError("speed factor must be positive")
        self.speed = speed
        self.buffer_size = buffer_size
        self.planner_size = planner_size
        self.rapid_speed = rapid_speed
        res = resolution if isinstance(resolution, dict) else dict.fromkeys(regs.CARD_AXES, resolution)
        self.resolution = [float(res.get(a, 1000.0)) for a in regs.CARD_AXES]
        self.limits = {regs.CARD_AXES.index(a): v for a, v in (limits or {}).items()}
        self.watch = watch_register
        self.clock = clock
        self.max_lag = max_lag
        self.lag_events = 0                           # updates where wall time beyond max_lag was dropped
        self.hr = [0] * 65536
        self.ir = [0] * 65536
        self.position = [0.0] * NAXES
        self.feed = 1.0                               # mm/min at power-on (L884)
        self.feed_override = self.rapid_override = self.spindle_override = 100
        self.hr[regs.HR_FEED_OVERRIDE] = self.hr[regs.HR_RAPID_OVERRIDE] = 100
        self.paused = False
        self.door = False                             # door safety active (IR 3003 bit 6): holds motion
        self.extra_moving = 0                         # IR 1016 low byte bits reported on top of the model's
        self.keep_buffers_on_alarm = keep_buffers_on_alarm
        self.alarm = 0
        self.estop = False
        self.queue: deque[proto.Command] = deque()       # CNC Modbus buffer
        self.used = 0                                 # registers in it
        self.planner: deque[_Entry] = deque()
        self.entries = 0                              # planner entries in use (moves, dwells, waits)
        self.jog: _Entry | None = None
        self.outputs = [False] * 256
        self.analog = [0] * 8
        self.inputs = [False] * 256
        self.analog_inputs = [0] * 8
        self.thc: list[int] = []
        self.log: list[Executed] = []
        self.aborted: list[Executed] = []
        self.gcode: list[str] = []
        self.immediate: list[proto.Command] = []
        self.time = 0.0                               # machine time, s
        self.underruns = 0
        self.overflows = 0
        self.report_full_after = report_full_after
        self.buffered = 0                             # buffered commands accepted
        self.discarded = 0
        self.arc_errors = 0
        self.moves_started = 0
        self._starved = False
        self._alarm_at: list[tuple[int, int]] = []    # (move number, code)
        self._hold_until = 0.0
        self._wall = clock()
        self.clients = 0
        self.refresh()

    # ------------------------------------------------------------ time
    def advance(self) -> None:
        """Run the machine up to now."""
        now = self.clock()
        if now < self._hold_until:
            self._wall = now
            return
        wall = now - self._wall
        if wall > self.max_lag:
            wall = self.max_lag
            self.lag_events += 1
        dt = wall * self.speed
        self._wall = now
        self._run(max(dt, 0.0))

    def hold_full(self, seconds: float) -> None:
        """Fault: stop consuming for ``seconds`` (wall clock) - nothing moves, nothing leaves the buffer,
        so a streaming client fills it and must wait.  The free space reported stays true."""
        self.advance()
        self._hold_until = self.clock() + seconds

    @property
    def holding(self) -> bool:
        return self.clock() < self._hold_until

    def _run(self, dt: float) -> None:
        if self.holding:
            return
        t_end = self.time + dt
        try:
            self._steps(dt, t_end)
        finally:
            self.time = t_end

    def _steps(self, dt: float, t_end: float) -> None:
        while True:
            self.time = t_end - dt
            self._refill()
            if self.alarm or self.paused or self.door:
                return
            if self.jog is not None and not self.planner:
                dt = self._step_move(self.jog, dt)
                if self.jog.s < self.jog.length:
                    return
                self.time = t_end - dt
                self._complete(self.jog)
                self.jog = None
                continue
            if not self.planner:
                return
            e = self.planner[0]
            if e.kind in ("action", "feed"):
                self._instant(e)
                self.planner.popleft()
                continue
            if dt <= 0 or (not e.started and not self._start(e)):
                return
            dt = self._step_timed(e, dt) if e.kind in ("dwell", "wait") else self._step_move(e, dt)
            if self.alarm and self.planner and self.planner[0] is e and e.kind == "wait" and e.s >= e.length:
                self._drop_timed_out(e)                  # buffers kept: the wait that raised alarm 18 is over
            if self.alarm or e.s < e.length:
                return
            self.time = t_end - dt
            self.planner.popleft()
            self.entries -= 1
            self._complete(e)
            if not self.planner and not self.queue:
                self._starved = True

    def _drop_timed_out(self, e: _Entry) -> None:
        self.planner.popleft()
        self.entries -= 1
        self.aborted.append(Executed(e.cmd.cid, e.kind, None, dict(e.cmd.args), self.hr[self.watch], self.time))

    def _refill(self) -> None:
        while self.queue and (self.entries < self.planner_size or self.queue[0].cid in
                              (regs.CMD_SYNC_ACTION, regs.CMD_FEED)):
            cmd = self.queue.popleft()
            self.used -= cmd.size
            kind = _KINDS.get(cmd.cid)
            if kind is None:
                kind = "rapid" if cmd.args["rapid"] else "line"
            if kind not in ("action", "feed"):
                self.entries += 1
            self.planner.append(_Entry(cmd, kind))

    # ------------------------------------------------------------ execution
    def _start(self, e: _Entry) -> bool:
        e.started = True
        e.start = list(self.position)
        if e.kind == "dwell":
            e.length = e.cmd.args["ms"] / 1000.0
            return True
        if e.kind == "wait":
            e.length = e.cmd.args["timeout_ms"] / 1000.0
            return True
        e.end = list(self.position)
        if e.kind == "arc":
            a = e.cmd.args
            e.end[0], e.end[1] = a["x"], a["y"]
            cx, cy = e.start[0] + a["i"], e.start[1] + a["j"]
            r0 = math.hypot(e.start[0] - cx, e.start[1] - cy)
            r1 = math.hypot(e.end[0] - cx, e.end[1] - cy)
            if abs(r1 - r0) > 0.005 and abs(r1 - r0) > 0.001 * r0:   # Grbl's arc-radius rule
                self.arc_errors += 1
            t0 = math.atan2(e.start[1] - cy, e.start[0] - cx)
            t1 = math.atan2(e.end[1] - cy, e.end[0] - cx)
            full = math.hypot(e.end[0] - e.start[0], e.end[1] - e.start[1]) < 1e-9
            if a["ccw"]:
                sweep = (t1 - t0) % (2 * math.pi) or (2 * math.pi if full else 0.0)
            else:
                sweep = -((t0 - t1) % (2 * math.pi) or (2 * math.pi if full else 0.0))
            e.arc = (cx, cy, r0, r1, t0, sweep)
            e.length = abs(sweep) * (r0 + r1) / 2.0
        else:
            for axis, v in e.cmd.args["targets"].items():
                e.end[regs.CARD_AXES.index(axis)] = v
            e.length = math.dist(e.start, e.end)
        for k, (lo, hi) in self.limits.items():
            if not lo <= e.end[k] <= hi:
                self.raise_alarm(regs.ALARM_SOFT_LIMIT)
                return False
        self.moves_started += 1
        return True

    def _speed(self, e: _Entry) -> float:
        """Path speed in mm/s (machine time)."""
        if e.kind == "jog":
            return e.speed / 60.0
        if e.kind == "rapid":
            return self.rapid_speed * self.rapid_override / 100.0 / 60.0
        return self.feed * self.feed_override / 100.0 / 60.0

    def _step_move(self, e: _Entry, dt: float) -> float:
        """Advance along a move for ``dt`` s; returns the time left over."""
        v = self._speed(e)
        due = [c for n, c in self._alarm_at if n == self.moves_started] if e is not self.jog else []
        stop = max(e.s, e.length / 2.0) if due else e.length
        if v <= 0:
            return 0.0
        need = (stop - e.s) / v
        if dt >= need:
            e.s = stop
            dt -= need
        else:
            e.s += v * dt
            dt = 0.0
        self._place(e)
        if due and e.s >= stop:
            self._alarm_at = [(n, c) for n, c in self._alarm_at if n != self.moves_started]
            self.raise_alarm(due[0])
            return 0.0
        return dt

    def _step_timed(self, e: _Entry, dt: float) -> float:
        if e.kind == "wait" and self._wait_met(e.cmd.args):
            e.s = e.length
            return dt
        need = e.length - e.s
        if dt >= need:
            e.s = e.length
            if e.kind == "wait" and e.cmd.args["alarm"]:
                self.raise_alarm(regs.ALARM_WAIT_TIMEOUT)
            return dt - need
        e.s += dt
        return 0.0

    def _wait_met(self, a: dict) -> bool:
        if a["type"] == 1:
            state = self.inputs[a["input"]]
            return state if a["wait"] in (1, 3) else not state    # edges approximated by levels
        if a["type"] == 2:
            v, t = self.analog_inputs[a["input"]], a["threshold"]
        else:
            addr = a["address"]
            v = self.ir[addr] if addr < 100000 else self.hr[addr - 100000]
            t = a["threshold"]
        return v < t if a["wait"] == 1 else v > t if a["wait"] == 2 else v == t

    def _place(self, e: _Entry) -> None:
        f = 1.0 if e.length <= 0 else min(1.0, e.s / e.length)
        if e.arc is not None:
            cx, cy, r0, r1, t0, sweep = e.arc
            th, r = t0 + sweep * f, r0 + (r1 - r0) * f
            pos = list(e.start)
            pos[0], pos[1] = (cx + r * math.cos(th), cy + r * math.sin(th)) if f < 1.0 else (e.end[0], e.end[1])
            self.position = pos
        else:
            self.position = [a + (b - a) * f for a, b in zip(e.start, e.end, strict=True)]

    def _instant(self, e: _Entry) -> None:
        a = e.cmd.args
        if e.kind == "feed":
            self.feed = a["feed"]
        elif a["type"] == regs.ACTION_DIGITAL:
            self.outputs[a["a"]] = bool(a["b"])
        elif a["type"] == regs.ACTION_ANALOG:
            self.analog[a["a"]] = a["b"]
        elif a["type"] == regs.ACTION_REGISTER:
            self.hr[a["a"]] = a["b"]
            self._hr_written(a["a"])
        else:
            self.thc.append(a["type"])
        self.log.append(Executed(e.cmd.cid, e.kind, None, dict(a), self.hr[self.watch], self.time))

    def _complete(self, e: _Entry) -> None:
        end = tuple(e.end) if e.end else None
        self.log.append(Executed(e.cmd.cid, e.kind, end, dict(e.cmd.args), self.hr[self.watch], self.time))

    # ------------------------------------------------------------ immediate actions
    def raise_alarm(self, code: int) -> None:
        """Alarm ``code``: motion stops where it is, both buffers are purged unless ``keep_buffers_on_alarm``
        (alarm 10 latches the e-stop)."""
        if not self.keep_buffers_on_alarm:
            self._abort()
        self.alarm = code
        if code == regs.ALARM_ESTOP:
            self.estop = True

    def release_estop(self) -> None:
        """The emergency-stop button is released (the alarm still needs an acknowledge)."""
        self.estop = False

    def schedule_alarm(self, code: int, move: int) -> None:
        """Fault: raise ``code`` half-way through the ``move``-th move started from now (1 = the next)."""
        self._alarm_at.append((self.moves_started + move, code))

    def _abort(self) -> None:
        for e in [*(list(self.planner)[:1]), self.jog]:
            if e is not None and e.started:
                if e is not self.jog and e.end and self._counts(e.end) == self._counts(self.position):
                    self._complete(e)   # stopped where its position counters already read its end: done
                    continue
                self.aborted.append(Executed(e.cmd.cid, e.kind, tuple(self.position), dict(e.cmd.args),
                                             self.hr[self.watch], self.time))
        self.queue.clear()
        self.planner.clear()
        self.used = self.entries = 0
        self.jog = None
        self.paused = False
        self._starved = False

    # ------------------------------------------------------------ Modbus side
    def write(self, address: int, values: list[int]) -> int | None:
        """A write of holding registers; returns a Modbus exception code to refuse it."""
        self.advance()
        end = address + len(values)
        old = self.hr[address:end]
        self.hr[address:end] = values
        if address <= regs.HR_COMMAND < end:
            code = self._command(self.hr[regs.HR_COMMAND:regs.HR_COMMAND + regs.HR_COMMAND_SIZE])
            if code is not None:
                self.hr[address:end] = old
            return code
        for reg in range(address, end):
            self._hr_written(reg)
        return None

    def _hr_written(self, reg: int) -> None:
        if reg == regs.HR_FEED_OVERRIDE:
            self.feed_override = self.hr[reg]
        elif reg == regs.HR_RAPID_OVERRIDE:
            self.rapid_override = min(self.hr[reg], 100)
        elif regs.HR_ANALOG_OUTPUTS <= reg < regs.HR_ANALOG_OUTPUTS + 8:
            self.analog[reg - regs.HR_ANALOG_OUTPUTS] = self.hr[reg]
        elif regs.HR_DIGITAL_OUTPUTS <= reg < regs.HR_DIGITAL_OUTPUTS + 6:
            base = (reg - regs.HR_DIGITAL_OUTPUTS) * 16
            for k in range(16):
                self.outputs[base + k] = bool(self.hr[reg] >> k & 1)

    def _command(self, words: list[int]) -> int | None:
        try:
            cmd = proto.parse_command(words)
        except proto.ProtocolError:
            return ILLEGAL_VALUE
        if cmd.cid in regs.BUFFERED_COMMANDS:
            return self._buffer(cmd)
        if cmd.cid == regs.CMD_GCODE:
            self.gcode.append(cmd.args["text"])
            return None
        self.immediate.append(cmd)
        if cmd.cid == regs.CMD_OVERRIDE:
            self.feed_override, self.rapid_override = cmd.args["feed"], min(cmd.args["rapid"], 100)
        elif cmd.cid in (regs.CMD_PAUSE, regs.CMD_RESUME):
            self._direct(regs.DIRECT_PAUSE if cmd.cid == regs.CMD_PAUSE else regs.DIRECT_RESUME)
        elif cmd.cid == regs.CMD_DIRECT:
            self._direct(cmd.args["code"])
        elif cmd.cid == regs.CMD_HOME:
            self._home(cmd)
        elif cmd.cid == regs.CMD_JOG:
            self._start_jog(cmd)
        return None

    def _buffer(self, cmd: proto.Command) -> int | None:
        if self.alarm:
            self.discarded += 1
            return None
        if cmd.size > self.buffer_size - self.used:
            self.overflows += 1
            return BUSY
        if self._starved:
            self.underruns += 1
            self._starved = False
        self.queue.append(cmd)
        self.used += cmd.size
        self.buffered += 1
        self._run(0.0)            # an action with nothing queued runs at once (L941)
        return None

    def _direct(self, code: int) -> None:
        if code == regs.DIRECT_ACK_ALARM:
            if not self.estop:
                self.alarm = 0
        elif code == regs.DIRECT_RESUME:
            self.paused = False
        elif code == regs.DIRECT_PAUSE:
            self.paused = True
            self._starved = False
        elif code == regs.DIRECT_STOP_JOG:
            if self.jog is not None:
                self.aborted.append(Executed(regs.CMD_JOG, "jog", tuple(self.position), {}, self.hr[self.watch],
                                             self.time))
                self.jog = None
        elif code == regs.DIRECT_FEED_OVERRIDE_100:
            self.feed_override = 100
        elif code == regs.DIRECT_RAPID_OVERRIDE_100:
            self.rapid_override = 100
        elif code == regs.DIRECT_SPINDLE_OVERRIDE_100:
            self.spindle_override = 100
        elif code == regs.DIRECT_STOP:
            self._abort()

    def _idle(self) -> bool:
        return not self.alarm and not self.queue and not self.planner

    def _home(self, cmd: proto.Command) -> None:
        if not self._idle() or self.jog is not None:
            return
        axis = cmd.args["axis"]
        for k in range(NAXES) if axis == 0 else [axis - 1]:
            self.position[k] = 0.0
        self.log.append(Executed(cmd.cid, "home", tuple(self.position), dict(cmd.args), self.hr[self.watch],
                                 self.time))

    def _start_jog(self, cmd: proto.Command) -> None:
        if not self._idle():                                   # only idle or jogging (L1175)
            return
        e = _Entry(cmd, "jog", started=True, start=list(self.position), end=list(self.position))
        for axis, v in cmd.args["targets"].items():
            k = regs.CARD_AXES.index(axis)
            e.end[k] = e.start[k] + v if cmd.args["relative"] else v
        e.length = math.dist(e.start, e.end)
        e.speed = cmd.args["speed_m_per_min"] * 1000.0         # m/min (L1195) -> mm/min
        self.jog = e

    # ------------------------------------------------------------ registers
    def status_word(self) -> int:
        w = 0
        if self.alarm:
            w |= regs.STATUS_ALARM
        if self.queue or self.planner:
            w |= regs.STATUS_CYCLE
        if self.paused:
            w |= regs.STATUS_PAUSED
        if self.door:
            w |= regs.STATUS_DOOR
        if self.jog is not None:
            w |= regs.STATUS_JOG
        if self.estop:
            w |= regs.STATUS_ESTOP
        return w

    def pulses(self) -> list[int]:
        return self._counts(self.position)

    def _counts(self, position) -> list[int]:
        """Position counters (pulses) of a position."""
        return [round(p * r) for p, r in zip(position, self.resolution, strict=True)]

    def refresh(self) -> None:
        """Write the live values into the register images (input and holding)."""
        ir, hr = self.ir, self.hr
        ir[regs.IR_CNC_BUFFER_SIZE], ir[regs.IR_GRBL_BUFFER_SIZE], ir[regs.IR_PLANNER_SIZE] = \
            self.buffer_size, 1024, self.planner_size
        ir[regs.IR_CNC_BUFFER_FREE] = self.buffer_size - self.used
        if self.report_full_after is not None and self.buffered >= self.report_full_after:
            ir[regs.IR_CNC_BUFFER_FREE] = 0
        ir[regs.IR_GRBL_BUFFER_FREE] = 1024
        ir[regs.IR_PLANNER_FREE] = self.planner_size - self.entries
        ir[regs.IR_CNC_STATUS] = self.status_word()
        ir[regs.IR_ALARM_CODE] = self.alarm
        ir[regs.IR_FIRMWARE_VERSION], ir[regs.IR_FIRMWARE_VERSION + 1] = 3, 0
        ir[regs.IR_TCP_CLIENTS] = self.clients
        pos = [w for p in self.pulses() for w in proto.i32_words(p)]
        ir[regs.IR_AXIS_POSITION:regs.IR_AXIS_POSITION + 12] = pos
        hr[regs.HR_AXIS_POSITION:regs.HR_AXIS_POSITION + 12] = pos
        active = self.planner[0] if self.planner and self.planner[0].started else self.jog
        moving = 0
        if active is not None and active.end and not self.paused and not self.alarm:
            moving = sum(1 << k for k in range(NAXES) if active.start[k] != active.end[k])
        ir[regs.IR_STATUS_BITS] = moving | self.extra_moving
        feed = self._speed(active) * 60.0 if moving else 0.0
        ir[regs.IR_CNC_FEED:regs.IR_CNC_FEED + 2] = proto.u32_words(min(round(feed), 0xFFFFFFFF))
        hr[regs.HR_FEED_OVERRIDE], hr[regs.HR_RAPID_OVERRIDE] = self.feed_override, self.rapid_override
        hr[regs.HR_ANALOG_OUTPUTS:regs.HR_ANALOG_OUTPUTS + 8] = self.analog
        for reg in range(6):
            hr[regs.HR_DIGITAL_OUTPUTS + reg] = sum(1 << k for k in range(16) if self.outputs[reg * 16 + k])
