"""Faults while streaming to the InterpCNC emulator: link loss, exception replies, late replies, alarms.

After each fault the back-end must stop sending, say what happened in words with the last block, and
after the operator's recovery every move and every output action must have run exactly once
(compared event by event with what was planned: see fagorcnc.backends.interpcnc.verify).
"""

from __future__ import annotations

import math

import pytest
from interpcnc_helpers import assert_exactly_once, plan, stream
from pymodbus.constants import ExcCodes

from fagorcnc.backends.interpcnc import InterpCncBackend, InterpCncError
from fagorcnc.backends.interpcnc.emulator import Emulator
from fagorcnc.backends.interpcnc.translate import segment_moves
from fagorcnc.backends.interpcnc.verify import expected_events

OUTPUTS = {
    "M3": {"type": 1, "output": 0, "value": 1},
    "M5": {"type": 1, "output": 0, "value": 0},
    "M8": {"type": 1, "output": 2, "value": 1},
    "M9": {"type": 1, "output": 2, "value": 0},
}


def program(lines: int = 600) -> str:
    """Short lines with coolant toggles, XY arcs (1003) and ZX arcs (sent as chords)."""
    out = ["G90 G0 X0 Y0 Z1", "M3", "G1 Z0 F2000"]
    for i in range(lines):
        y = 0.02 * (i + 1)
        out.append(f"G1 X{0.5 * (i % 2):.1f} Y{y:.3f} F3000")
        if i % 150 == 75:
            out += ["M8", f"G1 X0 Y{y:.3f}", f"G2 X0 Y{y:.3f} I3 J0 F2000",
                    "G18 G2 X4 Z0 I2 K0", "G17 G1 X0 F3000", "M9"]
    out += ["M5", "G0 Z5", "M30"]
    return "\n".join(out) + "\n"


def check_exactly_once(emu, segments, backend) -> None:
    assert_exactly_once(segments, backend, emu.executed())
    assert emu.card.overflows == 0 and emu.card.arc_errors == 0


def open_backend(emu, machine, **options) -> InterpCncBackend:
    # a reply timeout with room for a machine loaded by other work (1 s was seen to expire on an
    # ordinary reply with the test suite, four builds and a profiler sharing 2 cores); the tests of
    # timeouts give their own
    options.setdefault("timeout", 5.0)
    backend = InterpCncBackend(machine, port=emu.port, outputs=OUTPUTS, resolution=1000, **options)
    backend.open()
    return backend


def moves_before(segments, backend, seq: int) -> int:
    """How many moves the card runs before segment ``seq`` (1-based), as verify counts them."""
    return sum(1 for e in expected_events(segments, backend) if e[0] == "move" and e[1] < seq)


# ---------------------------------------------------------------- link faults
def test_connection_dropped_mid_stream_then_reconnect_runs_every_segment_once():
    machine, segments = plan(program())
    with Emulator(port=0, speed=10.0, resolution=1000) as emu:
        backend = open_backend(emu, machine)
        emu.drop_connection(after_commands=400)
        errors = stream(backend, segments, lambda err: backend.reconnect_and_continue())
        assert len(errors) == 1
        message = str(errors[0])
        assert "no valid reply" in message and "stopped sending" in message and "last block started: line" in message
        assert errors[0].status.state == "alarm" and errors[0].line > 0
        assert backend.stats["resyncs"] == 1
        check_exactly_once(emu, segments, backend)
        backend.close()


def test_exception_reply_stops_the_stream_and_nothing_runs_twice():
    machine, segments = plan(program())
    with Emulator(port=0, speed=10.0, resolution=1000) as emu:
        backend = open_backend(emu, machine)
        for seg in segments[:300]:
            backend.send(seg)
        emu.fail_next(1, ExcCodes.DEVICE_FAILURE)
        errors = stream(backend, segments[300:], lambda err: backend.reconnect_and_continue())
        assert len(errors) == 1 and "Modbus exception 4 (device failure)" in str(errors[0])
        assert "reconnect_and_continue()" in str(errors[0])
        check_exactly_once(emu, segments, backend)
        backend.close()


def test_late_reply_after_the_timeout_is_not_sent_again():
    machine, segments = plan(program())
    with Emulator(port=0, speed=10.0, resolution=1000) as emu:
        # a timeout with room for a loaded 2-core machine (0.2 s was seen to expire on an ordinary reply)
        backend = open_backend(emu, machine, timeout=0.5)
        for seg in segments[:250]:
            backend.send(seg)
        emu.delay_next(1, 1.5)                 # the card takes the command but its reply comes too late
        errors = stream(backend, segments[250:], lambda err: backend.reconnect_and_continue())
        assert len(errors) == 1 and "no valid reply" in str(errors[0])
        check_exactly_once(emu, segments, backend)     # the late command ran once, or was purged and re-sent
        backend.close()


def test_sends_after_a_link_failure_are_kept_not_lost():
    machine, segments = plan(program(100))
    with Emulator(port=0, speed=10.0, resolution=1000) as emu:
        backend = open_backend(emu, machine)
        for seg in segments[:40]:
            backend.send(seg)
        emu.drop_now()
        for seg in segments[40:45]:
            with pytest.raises(InterpCncError) as err:
                backend.send(seg)
            assert err.value.accepted
        assert "reconnect_and_continue" in str(err.value)
        backend.reconnect_and_continue()
        for seg in segments[45:]:
            backend.send(seg)
        backend.finish()
        check_exactly_once(emu, segments, backend)
        backend.close()


# ---------------------------------------------------------------- alarms
def test_soft_limit_alarm_is_reported_in_words_with_the_block_then_resume_finishes_exactly_once():
    machine, segments = plan(program())
    with Emulator(port=0, speed=10.0, resolution=1000) as emu:
        backend = open_backend(emu, machine)
        emu.schedule_alarm(2, move=300)
        seen = []

        def recover(err: InterpCncError) -> None:
            seen.append((err, backend.status()))
            backend.resume()                    # the operator acknowledges: 1200/88, then resynchronise

        errors = stream(backend, segments, recover)
        assert len(errors) == 1
        err, status = seen[0]
        assert err.alarm == 2 and "alarm 2 (soft limit" in str(err) and "stopped sending" in str(err)
        aborted = emu.card.aborted[0]
        assert err.line == segments[aborted.tag - 1].line                 # the block that was running
        assert f"line {err.line}" in str(err)
        assert status.state == "alarm" and status.alarm == 2 and "soft limit" in status.alarm_message
        assert 1200 in [c.cid for c in emu.card.immediate]
        check_exactly_once(emu, segments, backend)
        assert backend.status().state == "idle" and backend.status().alarm == 0
        backend.close()


def test_emergency_stop_cannot_be_resumed_until_released():
    machine, segments = plan(program())
    with Emulator(port=0, speed=10.0, resolution=1000) as emu:
        backend = open_backend(emu, machine)
        for seg in segments[:200]:
            backend.send(seg)
        emu.raise_alarm(10)
        attempts = []

        def recover(err: InterpCncError) -> None:
            assert err.alarm == 10 and "emergency stop" in str(err)
            with pytest.raises(InterpCncError, match=r"still active .*; last block started: line \d+") as again:
                backend.resume()
            assert again.value.line == err.line > 0
            attempts.append(backend.status().state)
            emu.release_estop()
            backend.resume()

        errors = stream(backend, segments[200:], recover)
        assert len(errors) == 1 and attempts == ["alarm"]
        check_exactly_once(emu, segments, backend)
        backend.close()


def test_alarm_inside_an_xy_arc_resumes_about_the_same_centre():
    machine, segments = plan("G90 G0 X10 Y0\nG1 Z0 F500\nG3 X-10 Y0 I-10 J0 F1200\nG1 X-12\n")
    with Emulator(port=0, speed=4.0, resolution=1000) as emu:
        backend = open_backend(emu, machine)
        arc_seq = next(k for k, s in enumerate(segments, 1) if s.kind == "motion" and s.record.kind == "arc")
        emu.schedule_alarm(2, move=moves_before(segments, backend, arc_seq) + 1)
        stream(backend, segments, lambda err: backend.resume())
        check_exactly_once(emu, segments, backend)
        stop = emu.card.aborted[0]
        assert stop.kind == "arc" and stop.tag == arc_seq
        resumed = next(e for e in emu.executed() if e.kind == "arc" and e.tag == arc_seq)
        cx, cy = stop.end[0] + resumed.args["i"], stop.end[1] + resumed.args["j"]
        assert math.hypot(cx, cy) < 2e-3                        # the centre is still (0, 0)
        assert math.hypot(stop.end[0], stop.end[1]) == pytest.approx(10.0, abs=1e-3)
        backend.close()


def test_alarm_inside_chords_resumes_from_the_chord_in_progress():
    machine, segments = plan("G90 G0 X0 Y0 Z0\nG1 X2 F1000\nG18 G2 X6 Z0 I2 K0\nG17 G1 X8\n")
    with Emulator(port=0, speed=4.0, resolution=1000) as emu:
        backend = open_backend(emu, machine)
        seq = next(k for k, s in enumerate(segments, 1) if s.kind == "motion" and s.record.kind == "arc")
        chords = len(segment_moves(segments[seq - 1], backend.xy, backend.options.chordal_tolerance))
        assert chords > 3
        emu.schedule_alarm(2, move=moves_before(segments, backend, seq) + 3)     # half-way through chord 3
        stream(backend, segments, lambda err: backend.resume())
        check_exactly_once(emu, segments, backend)
        moves = [e for e in emu.executed() if e.kind in ("line", "rapid") and e.tag == seq]
        assert len(moves) == chords                                # chords 1-2, the rest of 3, then 4...
        sub = [e.args["b"] for e in emu.executed() if e.kind == "action" and e.args["a"] == 3991]
        assert sub[:3] == [0, 1, 2] and sub[3:5] == [2, 3]        # the move register said chord index 2 ran
        backend.close()


def test_resume_refuses_to_guess_when_the_machine_was_moved():
    machine, segments = plan("G90 G1 X20 F600\nG1 X0\n")
    with Emulator(port=0, speed=4.0, resolution=1000) as emu:
        backend = open_backend(emu, machine)
        emu.schedule_alarm(2, move=1)
        with pytest.raises(InterpCncError, match="soft limit"):
            for seg in segments:
                backend.send(seg)
            backend.finish()
        emu.inspect(lambda card: card.position.__setitem__(1, 5.0))       # someone moved Y by hand
        with pytest.raises(InterpCncError, match="not on the path"):
            backend.resume()
        assert [e for e in emu.executed() if e.kind == "line"] == []   # nothing was sent
        backend.close()


def test_resume_of_a_move_needs_the_resolution():
    machine, segments = plan("G90 G1 X20 F600\n")
    with Emulator(port=0, speed=4.0) as emu:
        backend = InterpCncBackend(machine, port=emu.port)
        backend.open()
        emu.schedule_alarm(2, move=1)
        with pytest.raises(InterpCncError, match="soft limit"):
            backend.send(segments[0])
            backend.finish()
        with pytest.raises(InterpCncError, match="resolution"):
            backend.resume()
        backend.close()
