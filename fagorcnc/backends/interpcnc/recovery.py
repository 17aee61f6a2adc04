"""Faults and recovery of the InterpCNC back-end: the link lost, an alarm, the operator's resume (see
:mod:`.backend` for the rules: purge, read the markers and the position, send again from the move under way).

A mixin of :class:`~.backend.InterpCncBackend`: it uses the back-end's link, window and encoder.
"""

from __future__ import annotations

import math

import numpy as np

from . import protocol as proto
from . import registers as regs
from .link import LinkError
from .markers import locate, path_tolerance
from .records import Command, InterpCncError, _Sent
from .translate import remaining_moves


class Recovery:
    """Faults and recovery (mixed into :class:`~.backend.InterpCncBackend`)."""

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
        first = len(entry.moves) - len(rest)
        if len(entry.moves) == 1:     # what the card gets: a later resume, and its group's rules, see only that
            entry.moves = rest
        return self._prepare(entry, rest, first=first)
