"""The one interface every back-end implements (the registry that picks one by name is
:mod:`.registry`, so this protocol module imports no implementation).

A back-end receives the planner's :class:`~fagorcnc.plan.Segment` stream in
order.  ``send`` applies back-pressure: it blocks while the back-end cannot
take more (a card's buffer is full) and raises :class:`BackendError` when the
machine reports an alarm or the link fails; after that nothing more is sent
until the operator asks (``resume`` after acknowledging, or a new ``open``).

"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Protocol, runtime_checkable

from ..plan import Segment

#: Main states of a back-end (also what the status server publishes).
STATES = ("idle", "run", "pause", "alarm", "closed")


@dataclass
class Status:
    """What a back-end reports.

    ``state``: one of :data:`STATES`; ``alarm``/``alarm_message``: the alarm
    code and its text (0 / "" when none); ``line``: source line of the last
    segment the machine executed (0 before the first); ``executed``/``sent``:
    segments executed and sent so far; ``position``: machine coordinates;
    ``buffer_level``: fraction 0..1 of the back-end's buffer in use;
    ``velocity``: per axis (mm/s) where the back-end knows it; ``target``: the end
    (machine coordinates) of the motion segment the machine is executing, where known.
    """

    state: str = "idle"
    alarm: int = 0
    alarm_message: str = ""
    line: int = 0
    executed: int = 0
    sent: int = 0
    position: dict[str, float] = field(default_factory=dict)
    buffer_level: float = 0.0
    velocity: dict[str, float] = field(default_factory=dict)
    target: dict[str, float] = field(default_factory=dict)


class BackendError(RuntimeError):
    """The back-end stopped: alarm, link failure or refused command.

    ``status`` is the back-end's status at that moment (its ``line`` names the
    last block the machine executed).
    """

    def __init__(self, message: str, status: Status | None = None) -> None:
        super().__init__(message)
        self.status = status


@runtime_checkable
class Backend(Protocol):
    """The back-end protocol (see the module docstring)."""

    name: str

    def open(self) -> None: ...

    def send(self, segment: Segment) -> None: ...

    def finish(self) -> Status: ...

    def pause(self) -> None: ...

    def resume(self) -> None: ...

    def stop(self) -> None: ...

    def status(self) -> Status: ...

    def close(self) -> None: ...
