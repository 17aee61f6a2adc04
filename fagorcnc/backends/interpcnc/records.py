"""What the InterpCNC back-end keeps of a stream: its error, its status, the segments sent and the pseudo-commands
that open and reset the gate (see :mod:`.backend`)."""

from __future__ import annotations

from dataclasses import dataclass, field

from ...plan import Segment
from ..base import BackendError, Status
from . import protocol as proto
from .translate import Move


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


@dataclass
class InterpCncStatus(Status):
    """:class:`~fagorcnc.backends.base.Status` with the streaming figures: ``segments_per_second`` sent, sustained
    since the first segment (see :meth:`InterpCncBackend.rate`), and ``underruns``, the times a poll found the
    card's buffers empty while the stream went on (a lower bound: the card does not count them itself, seed 000 has
    no such register)."""

    segments_per_second: float = 0.0
    underruns: int = 0
    #: why the stream stopped, for a run summary: "alarm" (``alarm`` N at ``line``), "link" (link lost at ``line``,
    #: ``alarm_message`` says how), "stall" (BCK001/BCK002: the card stopped consuming or never stopped), "" none
    fault: str = ""


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
