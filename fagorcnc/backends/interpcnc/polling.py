"""Polling the InterpCNC: the status words and the markers read back, what they say of the stream (segments
complete, the block under way, an alarm, a hold), the position counters (see :mod:`.backend` for the rules).

A mixin of :class:`~.backend.InterpCncBackend`.
"""

from __future__ import annotations

import time

from . import protocol as proto
from . import registers as regs
from .records import InterpCncError


class Polling:
    """Reading the card (mixed into :class:`~.backend.InterpCncBackend`)."""

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
