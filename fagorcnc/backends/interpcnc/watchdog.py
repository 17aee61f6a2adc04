"""The InterpCNC back-end's watchdog (issue 30 items 13, 14): a card that consumes nothing although it holds commands
(``stall_timeout``, BCK001), or whose axes-moving bits stay set once its buffers are empty (``stop_timeout``, BCK002,
checked in ``finish()``), stops the stream with an error naming the register and the last block, never a hang.

A mixin of :class:`~.backend.InterpCncBackend`.
"""

from __future__ import annotations

from . import registers as regs
from .records import InterpCncError


class Watchdog:
    """Progress watch while the back-end waits for the card (mixed into :class:`~.backend.InterpCncBackend`)."""

    def _stall_reset(self) -> None:
        self._stall_mark, self._stall_pulses, self._stall_since = None, None, self.clock()

    def _watch(self, waiting_for: str) -> None:
        """After a poll in a wait: raise BCK001 when the card has shown no progress for ``stall_timeout`` s
        (plus the dwell it is running) although it holds commands.

        Progress is any change of the free space (IR 3000, 3002), of the marker registers or, read only once the
        rest has stood still, of the position counters (a long slow move); a feed hold or the door (the
        operator's, IR 3003 bits 4 and 6) or an override at 0 % (HR 2430/2431, read at the deadline) is never a
        stall.
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
        feed, rapid = self.link.read_holding(regs.HR_FEED_OVERRIDE, 2, "reading the overrides")
        if feed == 0 or rapid == 0:             # an override at 0 % holds the motion: the operator's, like a hold
            self._stall_reset()
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
        message = (f"InterpCNC {code}: {what}; stopped the card (1200/255) and the stream (timeout set by "
                   f"{'stall_timeout' if code == 'BCK001' else 'stop_timeout'}); {self._where_text()}"
                   f"{f', last block sent: line {sent}' if sent else ''}")
        self.stop()
        self._stall_code = code
        self._set(state="alarm", alarm_message=message)
        return InterpCncError(message, self._snapshot(), line=self._status.line, code=code)
