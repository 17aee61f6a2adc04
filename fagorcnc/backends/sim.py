"""The embedded simulator back-end: executes the planned segments on a virtual machine.

It keeps the segment log (what a real back-end would have sent), the
auxiliary-function log and the cycle time; on request it samples the
trajectory.  With ``realtime`` it paces itself against the wall clock (a
factor of 2 runs twice as fast) so that a person, a PLC or a test can watch a
dry run live through :meth:`status`.
"""

from __future__ import annotations

import threading
import time

import numpy as np

from ..config.machine import Machine
from ..plan import Segment
from ..plan.trajectory import Trajectory, sample
from .base import BackendError, Status


class SimulatorBackend:
    """Back-end ``sim`` (the default)."""

    name = "sim"

    def __init__(self, machine: Machine, *, realtime: float | None = None, keep_segments: bool = True) -> None:
        self.machine = machine
        self.axes = machine.axis_names
        self.realtime = realtime
        self.keep = keep_segments
        self.segments: list[Segment] = []
        self.aux_log: list[tuple[float, int, str, float]] = []   # (time, line, function, value)
        self.cycle_time = 0.0
        self._status = Status(state="closed")
        self._position = np.zeros(len(self.axes))
        self._lock = threading.Lock()
        self._resume = threading.Event()
        self._resume.set()
        self._stopped = False
        self._t_wall = 0.0

    # ------------------------------------------------------------ protocol
    def open(self) -> None:
        self._status = Status(state="idle", position=self._pos_dict())
        self._stopped = False
        self.cycle_time = 0.0
        self._t_wall = time.monotonic()

    def send(self, segment: Segment) -> None:
        st = self._status
        if st.state == "alarm":
            raise BackendError(f"alarm {st.alarm}: {st.alarm_message}", self.status())
        if st.state == "closed" or self._stopped:
            raise BackendError(f"the simulator is {'stopped' if self._stopped else st.state}: segment refused",
                               self.status())
        if self.keep:
            self.segments.append(segment)
        st.sent += 1
        axis = getattr(segment, "axis", None)   # a #MOVE's segment, alongside the general ones (plan/independent.py)
        with self._lock:
            if st.state != "pause":      # a pause that came while the last segment ended stays a pause
                st.state = "run"
            if segment.kind == "motion" and axis is None:   # where the move now running goes (a PLC's target)
                st.target = dict(zip(self.axes, segment.piece.end.tolist(), strict=True))
        if self.realtime and axis is None:   # an independent axis is paced by the general segments it runs beside
            self._pace(segment)
            if self._stopped:
                with self._lock:
                    why = f"alarm {st.alarm}: {st.alarm_message}" if st.alarm else "stopped by the operator"
                raise BackendError(why, self.status())
        with self._lock:
            if segment.kind == "aux" and segment.record is not None:
                rec = segment.record
                self.aux_log.append((segment.t0, segment.line, rec.function, rec.value))
            if segment.kind == "motion" and axis is None:
                self._position = np.array(segment.piece.end, dtype=float)
            elif segment.kind == "motion":   # only its axis: the others are the general interpolator's
                i = self.axes.index(axis)
                self._position[i] = segment.piece.end[i]
            self.cycle_time = max(self.cycle_time, segment.t0 + segment.duration)   # independent ones overlap
            st.executed += 1
            st.line = segment.line
            st.position = self._pos_dict()
            if st.alarm:
                st.state = "alarm"
                raise BackendError(st.alarm_message or f"alarm {st.alarm}", self._copy())

    def finish(self) -> Status:
        with self._lock:
            if self._status.state == "run":
                self._status.state = "idle"
            self._status.velocity = dict.fromkeys(self.axes, 0.0)
        return self.status()

    def pause(self) -> None:
        self._resume.clear()
        with self._lock:
            if self._status.state == "run":
                self._status.state = "pause"

    def resume(self) -> None:
        with self._lock:
            if self._status.state == "alarm":
                self._status.alarm, self._status.alarm_message = 0, ""
            if self._status.state in ("pause", "alarm"):
                self._status.state = "run"
        self._resume.set()

    def stop(self) -> None:
        self._stopped = True
        self._resume.set()
        with self._lock:
            if self._status.state in ("run", "pause"):
                self._status.state = "idle"

    def raise_alarm(self, code: int, message: str) -> None:
        """An alarm from outside (a PLC through the status server): motion stops at once."""
        with self._lock:
            self._status.alarm, self._status.alarm_message = code, message
            self._status.state = "alarm"
            self._status.velocity = dict.fromkeys(self.axes, 0.0)
        self._stopped = True
        self._resume.set()

    def status(self) -> Status:
        with self._lock:
            return self._copy()

    def _copy(self) -> Status:
        """A copy of the status (call with the lock held)."""
        s = self._status
        return Status(s.state, s.alarm, s.alarm_message, s.line, s.executed, s.sent, dict(s.position), 0.0,
                      dict(s.velocity), dict(s.target))

    def close(self) -> None:
        with self._lock:
            self._status.state = "closed"

    # ------------------------------------------------------------ extras
    def trajectory(self, period: float | None = None) -> Trajectory:
        """The executed motion sampled every ``period`` seconds (needs profiles in the segments)."""
        return sample(self.segments, self.axes, period or self.machine.planner.servo_period)

    def _pos_dict(self) -> dict[str, float]:
        return {a: float(v) for a, v in zip(self.axes, self._position, strict=True)}

    def _pace(self, segment: Segment) -> None:
        """Wait until the wall clock reaches the segment's end, updating position and speed as it goes."""
        end = segment.t0 + segment.duration
        while True:
            self._resume.wait()
            if self._stopped:
                return
            now = (time.monotonic() - self._t_wall) * self.realtime
            if now >= end:
                return
            if segment.kind == "motion" and segment.profile is not None and now >= segment.t0:
                s, v, _a, _j = segment.profile.at(np.array([now - segment.t0]))
                q, d1, _, _ = segment.piece.derivatives(s)
                with self._lock:
                    self._position = q[0]
                    self._status.position = self._pos_dict()
                    self._status.velocity = {a: float(x) for a, x in zip(self.axes, d1[0] * v[0], strict=True)}
                    self._status.line = segment.line
            paused = not self._resume.is_set()
            time.sleep(min(0.01, max(0.0, (end - now) / self.realtime)))
            if paused:   # time spent paused does not count
                self._t_wall = time.monotonic() - now / self.realtime
