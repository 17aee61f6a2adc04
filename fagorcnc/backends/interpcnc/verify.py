"""Dry-run verification: does what a card executed match what was planned?

:func:`expected_events` lists, for the segments streamed in one session of
an :class:`~.backend.InterpCncBackend`, what the card must execute, in
order: every move's end point as the card receives it (single precision),
tagged with the marker it ran under (its segment's sequence number, or its
group's head when markers are coalesced: ``backend.marker_log``), every
synchronised action of the
``outputs`` table and every dwell.  :func:`executed_events` reads the same
events from the emulator's executed log (:class:`~.card.Executed`), leaving
out the back-end's own marker writes and feed changes.  Equal lists mean
every move and action ran exactly once, in order, to the right place - a
move interrupted and resumed counts once, since the card logs a move when it
completes.
"""

from __future__ import annotations

from collections.abc import Iterable

from ...plan import Segment
from . import protocol as proto
from . import registers as regs
from .card import Executed
from .translate import segment_moves

Event = tuple


def expected_events(segments: Iterable[Segment], backend) -> list[Event]:
    """``("move", seq, end)``, ``("out", type, address, value)`` and ``("dwell", ms)`` in streaming order."""
    out: list[Event] = []
    card_index = [regs.CARD_AXES.index(c) for c in backend.card_axes]
    position = [0.0] * len(regs.CARD_AXES)
    last: tuple | None = None
    log = getattr(backend, "marker_log", None)
    for seq, seg in enumerate(segments, start=1):
        if seg.kind == "motion":
            tag = log.tag(seq) if log is not None and len(log) else seq
            for m in segment_moves(seg, backend.xy, backend.options.chordal_tolerance, backend.rapid_feed):
                for k, v in zip(card_index, m.end, strict=True):
                    position[k] = proto.float32(float(v))
                end = tuple(position)
                if end != last:
                    out.append(("move", tag, end))
                last = end
        elif seg.kind == "dwell":
            seconds = float(getattr(seg.record, "seconds", seg.duration))
            out += [("dwell", w[1]) for w in proto.encode_dwell(seconds)]
        elif seg.kind == "aux":
            for a in backend.actions_for(seg.record.function, seg.record.value) or ():
                out.append(("out", a.type, a.address, a.resolve(seg.record.value)[0]))
    return out


def executed_events(log: Iterable[Executed], marker_register: int = regs.DEFAULT_MARKER_REGISTER) -> list[Event]:
    """The same events read from an emulator's executed log."""
    out: list[Event] = []
    for e in log:
        if e.kind in ("rapid", "line", "arc"):
            out.append(("move", e.tag, tuple(e.end)))
        elif e.kind == "dwell":
            out.append(("dwell", e.args["ms"]))
        elif e.kind == "action":
            if e.args["type"] == regs.ACTION_REGISTER and e.args["a"] in (marker_register, marker_register + 1):
                continue
            out.append(("out", e.args["type"], e.args["a"], e.args["b"]))
    return out


def first_difference(expected: list[Event], actual: list[Event], tolerance: float = 0.0) -> str | None:
    """A sentence about the first place the two lists differ, or None when they agree."""
    for k, (a, b) in enumerate(zip(expected, actual, strict=False)):
        if a == b:
            continue
        if a[0] == b[0] == "move" and a[1] == b[1] and max(abs(x - y) for x, y in zip(a[2], b[2], strict=True)) \
                <= tolerance:
            continue
        return f"event {k}: expected {a}, executed {b}"
    if len(expected) != len(actual):
        k = min(len(expected), len(actual))
        more = expected[k] if len(expected) > k else actual[k]
        return (f"{len(expected)} events expected, {len(actual)} executed; first unmatched: {more}")
    return None
