"""The interpcnc back-end streaming a long program over Modbus TCP (127.0.0.1) to the InterpCNC emulator.

Each test starts its own emulator on a free port and stops it; every wait has a timeout.
"""

from __future__ import annotations

import threading
import time

from interpcnc_helpers import plan

from fagorcnc.backends import get_backend
from fagorcnc.backends.interpcnc import InterpCncBackend
from fagorcnc.backends.interpcnc.emulator import Emulator, VirtualClock
from fagorcnc.backends.interpcnc.verify import executed_events, expected_events, first_difference

OUTPUTS = {
    "M3": {"type": 1, "output": 0, "value": 1},
    "M5": {"type": 1, "output": 0, "value": 0},
    "M8": {"type": 1, "output": 2, "value": 1},
    "M9": {"type": 1, "output": 2, "value": 0},
    "S": {"type": 2, "output": 0, "scale": 1.0},
}
SEGMENT_TIME = 0.3 / (3000 / 60)      # s: a 0.3 mm move at F3000, in real time
ROUND_TRIP = 0.0005                   # s per Modbus request in lock-step (see tests/test_interpcnc_keepup.py)


def raster_program(lines: int, arcs_every: int = 2500) -> str:
    """Short G1 moves (0.3 mm at F3000) in a raster, a few XY arcs, coolant toggled, a dwell."""
    out = ["G90 G0 X0 Y0 Z5", "M3 S2000", "M8", "G4 K0.05", "G1 Z0 F1000"]
    y = 0.0
    for i in range(lines):
        if i and i % arcs_every == 0:
            out += [f"G1 X0 Y{y:.3f}", f"G2 X0 Y{y + 2:.3f} I0 J1 F2000", f"G3 X0 Y{y + 4:.3f} I0 J1"]
            y += 4.0
            out.append("M9" if (i // arcs_every) % 2 else "M8")
        y += 0.01
        out.append(f"G1 X{0.3 * (i % 2 == 0):.1f} Y{y:.3f} F3000")
    out += ["M5", "M9", "G0 Z5", "M30"]
    return "\n".join(out) + "\n"



def test_ten_thousand_segments_execute_exactly_as_planned_without_underrun():
    # Underrun-free streaming is a claim about rates: the card must consume segments slower than the back-end
    # can send them.  Asked in lock-step (issue 25 item 9: the verdict once depended on how loaded the test
    # machine was): the card's time moves by ROUND_TRIP per Modbus request and by the back-end's sleeps, so only
    # the protocol counts.  A 0.3 mm move at F3000 takes 6 ms, 1.2 ms at x5; with markers coalesced (8 moves per
    # marker) a move costs 1 + 1/8 writes = 0.56 ms of link time plus about 0.05 ms of polls per ms: it keeps up.
    machine, segments = plan(raster_program(10_000))
    assert len(segments) >= 10_000
    speed = 5.0
    card, status, backend = stream_all(machine, segments, speed)
    assert status.state == "idle" and status.executed == status.sent == len(segments)
    assert status.line == segments[-1].line
    assert backend.warnings == []
    # polled about once per poll interval while waiting for room, never once per segment: that is
    # SEGMENT_TIME / (speed * poll_interval) polls per segment = 0.006 / (5 * 0.02) = 0.06
    expected = len(segments) * SEGMENT_TIME / (speed * backend.options.poll_interval)
    assert backend.stats["polls"] < min(1.5 * expected, len(segments) / 2)
    assert card.underruns == 0, f"{card.underruns} planner underruns at speed x{speed:.1f} in lock-step"


def stream_all(machine, segments, speed: float):
    """Stream every segment in lock-step to an emulated card at ``speed``; check the executed log against the plan."""
    clock = VirtualClock(ROUND_TRIP)
    with Emulator(port=0, speed=speed, resolution=1000, clock=clock) as emu:
        # a Modbus request timeout of 10 s, not 1: a busy test machine may hold a reply that long (the card's
        # time is the virtual clock's; this test is about the protocol, not about the link's latency)
        backend = get_backend("interpcnc", machine, port=emu.port, outputs=OUTPUTS, resolution=1000, timeout=10.0)
        assert isinstance(backend, InterpCncBackend)
        backend.clock, backend.sleep = clock, clock.sleep
        backend.open()
        for seg in segments:
            backend.send(seg)
        status = backend.finish()
        backend.close()
        card = emu.card
        log = emu.executed()
        # same order, same end points (as single floats), every M function's output at its place
        expected = expected_events(segments, backend)
        assert first_difference(expected, executed_events(log)) is None
        assert sum(1 for e in expected if e[0] == "move") >= 10_000
        assert card.overflows == 0 and card.discarded == 0 and card.arc_errors == 0
        assert card.outputs[0] is False and card.outputs[2] is False      # M5 and M9 at the end
        outs = [e for e in expected if e[0] == "out"]
        assert outs[:3] == [("out", 2, 0, 2000), ("out", 1, 0, 1), ("out", 1, 2, 1)]    # S2000, M3, M8
        assert ("out", 1, 2, 0) in outs[3:-2]                                           # M9 mid-program
    return card, status, backend


def test_back_pressure_never_overflows_the_card_buffer():
    machine, segments = plan(raster_program(400, arcs_every=1000))
    with Emulator(port=0, speed=50.0, buffer_size=64) as emu:   # a small buffer: back-pressure all along
        backend = InterpCncBackend(machine, port=emu.port, outputs=OUTPUTS)
        backend.open()
        timer = threading.Timer(0.05, emu.hold_full, args=(0.4,))
        timer.start()
        t0 = time.monotonic()
        for seg in segments:
            backend.send(seg)
        backend.finish()
        timer.join(5)
        assert time.monotonic() - t0 >= 0.4                    # the hold was waited out
        assert emu.card.overflows == 0
        assert backend.stats["waits"] > 0
        assert first_difference(expected_events(segments, backend), executed_events(emu.executed())) is None
        backend.close()
