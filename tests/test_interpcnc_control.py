"""The interpcnc back-end's immediate commands, status and checks, against the emulator over Modbus TCP.

Each test starts its own emulator on a free port (127.0.0.1) and stops it; every wait has a timeout.
"""

from __future__ import annotations

import threading
import time

import pytest
from interpcnc_helpers import assert_exactly_once, plan
from pymodbus.client import ModbusTcpClient

import fagorcnc
from fagorcnc.backends.base import BackendError
from fagorcnc.backends.interpcnc import InterpCncBackend, InterpCncError
from fagorcnc.backends.interpcnc import backend as backend_module
from fagorcnc.backends.interpcnc import protocol as proto
from fagorcnc.backends.interpcnc.card import Card
from fagorcnc.backends.interpcnc.emulator import Emulator, main

M3 = {"type": 1, "output": 0, "value": 1}
M5 = [{"type": 1, "output": 0, "value": 0}, {"type": 2, "output": 0, "value": 0}]     # two actions



def test_status_reports_the_block_running_and_the_position():
    machine, segments = plan("G90 G1 X5 F600\nG1 X5 Y5\nG1 X0 Y5\nG1 X0 Y0\n")
    with Emulator(port=0, speed=1.0, resolution=400) as emu:
        backend = InterpCncBackend(machine, port=emu.port, resolution=400)
        backend.open()
        for seg in segments:
            backend.send(seg)
        time.sleep(0.3)                                       # F600 = 10 mm/s: about 3 mm along X
        st = backend.status()
        assert st.state == "run" and st.line == 1 and st.executed == 0 and st.sent == 4
        assert 1.0 < st.position["X"] < 5.0 and st.position["Y"] == 0.0
        assert st.target == {"X": 5.0, "Y": 0.0, "Z": 0.0}        # the end of the move it is running
        assert 0.0 < st.buffer_level < 1.0
        backend.set_override(400)                             # 4x: the rest takes 1.2 s at most
        st = backend.finish()
        assert st.executed == 4 and st.line == 4 and st.position == {"X": 0.0, "Y": 0.0, "Z": 0.0}
        backend.close()


def test_pause_resume_override_home_and_jog_are_immediate():
    machine, segments = plan("G90 G1 X20 F600\n")
    with Emulator(port=0, speed=1.0, resolution=1000) as emu:
        backend = InterpCncBackend(machine, port=emu.port, resolution=1000)
        backend.open()
        backend.jog({"X": 2.0}, 6000.0)                       # 6000 mm/min = 6 m/min on the wire (L1195)
        assert emu.wait_idle(5)
        jog = [e for e in emu.executed() if e.kind == "jog"]
        assert jog and jog[0].end[0] == pytest.approx(2.0) and jog[0].args["speed_m_per_min"] == 6.0
        backend.home("X")
        assert emu.executed()[-1].kind == "home" and backend.status().position["X"] == 0.0
        backend.send(segments[0])
        time.sleep(0.1)
        backend.pause()
        assert backend.status().state == "pause" and emu.inspect(lambda c: c.paused)
        x = backend.status().position["X"]
        time.sleep(0.1)
        assert backend.status().position["X"] == x            # feed hold: nothing moves
        backend.set_override(150, 50)
        assert emu.inspect(lambda c: (c.feed_override, c.rapid_override)) == (150, 50)
        backend.resume()
        assert backend.status().state == "run"
        backend.stop()                                        # 1200/255: stop and purge
        assert emu.wait_idle(2)
        assert emu.inspect(lambda c: len(c.aborted)) == 1
        with pytest.raises(InterpCncError, match="stopped by the operator") as err:
            backend.send(segments[0])
        assert err.value.accepted is False
        backend.close()


def test_unmapped_auxiliary_functions_are_reported_not_dropped():
    machine, segments = plan("G90 G0 X1\nM3\nM8\nT2 M6\nG1 X2 F100\nM30\n")
    with Emulator(port=0, speed=20.0) as emu:
        backend = InterpCncBackend(machine, port=emu.port, outputs={"M3": M3})
        # M8; T2 and M6 of line 4 (not its implicit D1: an offset, already in the path, nothing for the card)
        problems = backend.check(segments)
        assert [w.split(":")[0] for w in problems] == ["line 3", "line 4", "line 4"]
        assert [w.split(": ")[1].split()[0] for w in problems] == ["M8", "T2", "M6"]
        backend.open()
        for seg in segments:
            backend.send(seg)
        backend.finish()
        assert backend.warnings == problems
        assert emu.card.outputs[0] is True                    # M3 did reach the card
        backend.close()
        strict = InterpCncBackend(machine, port=emu.port, strict_outputs=True, outputs={"M3": M3})
        strict.open()
        with pytest.raises(InterpCncError, match="M8") as err:
            for seg in segments:
                strict.send(seg)
        assert err.value.accepted is False
        strict.close()


def test_open_refuses_a_card_that_is_already_running():
    machine, segments = plan("G90 G1 X50 F600\n")
    with Emulator(port=0, speed=1.0) as emu:
        first = InterpCncBackend(machine, port=emu.port)
        first.open()
        first.send(segments[0])
        second = InterpCncBackend(machine, port=emu.port)
        with pytest.raises(BackendError, match="busy"):
            second.open()
        first.stop()
        first.close()
    with pytest.raises(BackendError, match="cannot connect"):
        InterpCncBackend(machine, port=emu.port, timeout=0.2).open()     # nobody listens any more


def test_emulator_serves_the_registers_a_client_reads():
    with Emulator(port=0, speed=1.0) as emu:
        client = ModbusTcpClient("127.0.0.1", port=emu.port, timeout=1, retries=0)
        assert client.connect()
        sizes = client.read_input_registers(2990, count=3, device_id=1).registers
        poll = client.read_input_registers(3000, count=5, device_id=1).registers
        assert sizes == [4096, 1024, 35] and poll == [4096, 1024, 35, 0, 0]
        # a 1005 "override" (the table's misprint, L1133) is refused; 1100 works
        assert client.write_registers(2000, [1005, 50, 50], device_id=1).isError()
        assert not client.write_registers(2000, proto.encode_override(50, 50), device_id=1).isError()
        assert client.read_holding_registers(2430, count=2, device_id=1).registers == [50, 50]
        assert not client.write_registers(2000, proto.encode_gcode("G01 X12.2 F3000"), device_id=1).isError()
        assert emu.card.gcode == ["G01 X12.2 F3000"]
        # function 06: the write of 2000 triggers the command whose arguments were written before (L490)
        assert not client.write_registers(2001, proto.encode_digital_output(5, True)[1:], device_id=1).isError()
        assert not client.write_register(2000, 1010, device_id=1).isError()
        assert client.read_coils(0, count=8, device_id=1).bits[5] is True
        client.close()
    with pytest.raises(SystemExit):
        main(["--speed", "0"])


def test_an_output_and_a_dwell_run_behind_a_gate_the_back_end_opens_once_all_are_accepted():
    """Their exact words: 1012 type 3 "above" (kind 2) on holding 3992 as extended address 103992 (seed 000 L1115)
    with threshold token - 1, timeout 65535 ms and alarm 18 on timeout; then the actions and the sequence marker
    (3990, the default marker_register), or for a dwell 0 into 3991, the marker, the dwell and 1 into 3991; then a
    plain write of the token into 3992.  The card holds them until then: a fault before it leaves nothing run
    (tests/test_fault_campaign.py injects one at each write)."""
    machine, segments = plan("M3\nG4 K0.25\n")
    with Emulator(port=0, speed=1.0) as emu:   # start_lead 0: these words open the stream, no 1012 start wait first
        backend = InterpCncBackend(machine, port=emu.port, outputs={"M3": M3}, start_lead=0)
        backend.open()
        wait = [1012, 3, 65535, 1, 2]
        gate = [103992 & 0xFFFF, 103992 >> 16]
        assert backend._prepare(backend_module._Sent(1, segments[0])) == [
            [*wait, 0, *gate], [1010, 1, 0, 1], [1010, 3, 3990, 1], backend_module._OpenGate(1)]
        assert backend._prepare(backend_module._Sent(2, segments[1])) == [
            [*wait, 1, *gate], [1010, 3, 3991, 0], [1010, 3, 3990, 2], [1011, 250], [1010, 3, 3991, 1],
            backend_module._OpenGate(2)]
        backend._reset_stream()
        backend.send(segments[0])
        backend.send(segments[1])
        assert emu.inspect(lambda card: (card.hr[3992], card.outputs[0])) == (2, True)
        st = backend.status()
        assert st.line == 2 and st.executed == 1              # M3 has run, the dwell is under way
        st = backend.finish()
        assert st.executed == 2 and st.line == 2
        backend.close()


# ---------------------------------------------------------------- the card moved outside the stream
def _stream(backend, text):
    for seg in plan(text)[1]:
        backend.send(seg)
    return backend.finish()


@pytest.mark.parametrize("outside", ["jog", "home"])
def test_a_jog_or_a_homing_between_programs_does_not_leave_a_stale_target(outside):
    """1002 omits the axes whose target did not change (seed 000 L902): after the card moved on its own, program 2's
    first move must carry Z again, or the cut runs 5 mm too deep."""
    machine, _ = plan("G90 G0 X10 Y10 Z5\n")
    with Emulator(port=0, speed=20.0, resolution=1000) as emu:
        backend = InterpCncBackend(machine, port=emu.port, resolution=1000)
        backend.open()
        assert _stream(backend, "G90 G0 X10 Y10 Z5\n").position["Z"] == 5.0
        if outside == "jog":
            backend.jog({"Z": -5.0}, 600.0)
        else:
            backend.home("Z")
        assert emu.wait_idle(5)
        assert emu.inspect(lambda c: c.position[2]) == 0.0
        st = _stream(backend, "G90 G0 X10 Y10 Z5\nG1 X30 F3000\n")
        assert st.position == {"X": 30.0, "Y": 10.0, "Z": 5.0}
        backend.close()


def test_an_arc_first_after_open_and_a_jog_goes_to_its_start_then_cuts_about_its_centre():
    """1003 takes I/J relative to where the card stands (card.py, protocol.encode_arc_xy): with the card jogged to
    X5, the arc planned from X0 must be preceded by a move to X0, or it is cut about X15 with the wrong radius."""
    machine, segments = plan("G90 G2 X20 Y0 I10 J0 F600\n")
    with Emulator(port=0, speed=20.0, resolution=1000) as emu:
        backend = InterpCncBackend(machine, port=emu.port, resolution=1000)
        backend.open()
        backend.jog({"X": 5.0}, 6000.0)
        assert emu.wait_idle(5)
        for seg in segments:
            backend.send(seg)
        st = backend.finish()
        moves = [e for e in emu.executed() if e.kind in ("jog", "line", "rapid", "arc")]
        assert [e.kind for e in moves] == ["jog", "line"] + ["arc"] * len(segments)   # the planner's pieces
        assert moves[1].end[:3] == (0.0, 0.0, 0.0)                       # to the arc's start first
        assert (moves[2].args["i"], moves[2].args["j"]) == (10.0, 0.0)   # centre X10 Y0, from X0
        assert moves[-1].end[:2] == (20.0, 0.0)
        assert emu.inspect(lambda c: c.arc_errors) == 0
        assert st.position == {"X": 20.0, "Y": 0.0, "Z": 0.0}
        backend.close()


# ---------------------------------------------------------------- alarms that forbid resuming
def _alarm_during_a_cut(emu, backend, code):
    """Stream a long cut, raise ``code`` during it; returns the error the stream reported."""
    backend.open()
    backend.send(plan("G90 G1 X20 F600\n")[1][0])
    time.sleep(0.1)
    emu.raise_alarm(code)
    with pytest.raises(InterpCncError) as err:
        backend.finish()
    return err.value


def _directs(emu):
    return emu.inspect(lambda c: [cmd.args["code"] for cmd in c.immediate if cmd.cid == 1200])


@pytest.mark.parametrize("code", [1, 17])
def test_resume_refuses_an_alarm_after_which_the_position_is_not_trusted_and_abandon_clears_it(code):
    """Seed 000 L430: after a limit switch (1) or a motor fault (17) the step counters may not match the machine;
    resume() sends nothing (not even the acknowledge 1200/88), abandon() acknowledges and discards the stream."""
    machine, _ = plan("G90 G1 X20 F600\n")
    with Emulator(port=0, speed=5.0, resolution=1000) as emu:
        backend = InterpCncBackend(machine, port=emu.port, resolution=1000)
        err = _alarm_during_a_cut(emu, backend, code)
        assert err.alarm == code and "can no longer be trusted" in str(err) and "abandon()" in str(err)
        log, directs, where = len(emu.executed()), _directs(emu), emu.inspect(lambda c: list(c.position))
        for recover in (backend.resume, backend.reconnect_and_continue, backend.resume):
            with pytest.raises(InterpCncError, match="position can no longer be trusted") as refused:
                recover()
            assert refused.value.alarm == code and f"alarm {code} (" in str(refused.value)
            assert "abandon()" in str(refused.value) and "last block started: line 1" in str(refused.value)
            assert backend.status().state == "alarm"
        assert len(emu.executed()) == log and _directs(emu) == directs        # nothing sent, no 88
        assert emu.inspect(lambda c: (list(c.position), c.alarm)) == (where, code)
        with pytest.raises(InterpCncError, match=r"abandon\(\)"):
            backend.send(plan("G90 G1 X1 F600\n")[1][0])
        backend.abandon()
        assert _directs(emu)[len(directs):] == [255, 88, 255]   # purged before the acknowledge
        st = backend.status()
        assert (st.state, st.alarm, st.sent, st.executed) == ("idle", 0, 0, 0) and emu.inspect(lambda c: c.alarm) == 0
        st = _stream(backend, "G90 G1 X1 F3000\n")                            # a new stream, as after open()
        assert st.state == "idle" and st.executed == 1 and st.position == {"X": 1.0, "Y": 0.0, "Z": 0.0}
        backend.close()


def test_resume_still_continues_after_a_cycle_aborted_alarm():
    machine, _ = plan("G90 G1 X20 F600\n")
    with Emulator(port=0, speed=5.0, resolution=1000) as emu:
        backend = InterpCncBackend(machine, port=emu.port, resolution=1000)
        err = _alarm_during_a_cut(emu, backend, 3)
        assert err.alarm == 3 and "trusted" not in str(err)
        backend.resume()
        assert _directs(emu)[-3:] == [255, 88, 255]            # purged before the acknowledge
        st = backend.finish()
        assert st.executed == 1 and st.position == {"X": 20.0, "Y": 0.0, "Z": 0.0}
        backend.close()


# ---------------------------------------------------------------- open() on a card that is not ready
@pytest.mark.parametrize("state", ["pause", "jog"])
def test_open_refuses_a_card_that_is_paused_or_jogging(state):
    """IR 3003 (seed 000 L429): a card in feed hold would hold the stream (finish() would wait forever), a jog
    moves it from under the plan."""
    machine, _ = plan("G90 G1 X1 F600\n")
    with Emulator(port=0, speed=1.0, resolution=1000) as emu:
        first = InterpCncBackend(machine, port=emu.port, resolution=1000)
        first.open()
        if state == "pause":
            first.pause()
            words = r"not ready \(paused \(feed hold\)\)"
        else:
            first.jog({"X": 50.0}, 600.0)
            words = r"not ready \(jogging\)"
        second = InterpCncBackend(machine, port=emu.port, resolution=1000)
        with pytest.raises(BackendError, match=words):
            second.open()
        assert second.status().state == "closed"
        if state == "pause":
            first.resume()
        else:
            first.stop_jog()
        assert emu.wait_idle(5)
        first.close()
        second.open()
        assert second.status().state == "idle"
        emu.set_speed(20.0)
        st = _stream(second, "G90 G1 X1 F600\n")
        assert st.position["X"] == 1.0
        second.close()


# ---------------------------------------------------------------- recovery purges before it acknowledges
def _wait_for(emu, predicate, timeout=5.0):
    deadline = time.monotonic() + timeout
    while not emu.inspect(predicate):
        assert time.monotonic() < deadline, "the emulated card never got there"
        time.sleep(0.005)


def test_resume_purges_before_acknowledging_so_a_card_that_kept_its_buffers_runs_no_unconfirmed_body():
    """Seed 000: only 1200/255 purges (L1225), nothing says an alarm does.  The link drops after M5's gate and first
    action were accepted; the gate never opens, alarm 18 (L1099).  A card keeping its buffers holds that half of M5:
    acknowledged before a purge, it would run it, and the resynchronisation would send M5 again in full."""
    machine, segments = plan("G90 G1 X1 F3000\nM5\nG1 X2\nM30\n")
    with Emulator(port=0, speed=1000.0, resolution=1000, keep_buffers_on_alarm=True) as emu:
        backend = InterpCncBackend(machine, port=emu.port, resolution=1000, outputs={"M5": M5}, timeout=0.5)
        backend.open()
        backend.send(segments[0])
        emu.drop_connection(after_commands=2)                 # the gate wait and OUT0 off accepted, AOUT0 lost
        with pytest.raises(InterpCncError, match="no valid reply") as lost:
            backend.send(segments[1])
        assert lost.value.accepted
        _wait_for(emu, lambda c: c.alarm == 18)               # 65.5 s at the shut gate (x1000)
        assert emu.inspect(lambda c: [e.kind for e in c.planner]) == ["action"]    # half of M5, kept
        with pytest.raises(InterpCncError, match="alarm 18"):
            backend.reconnect_and_continue()
        backend.resume()
        for seg in segments[2:]:
            backend.send(seg)
        backend.finish()
        log = emu.executed()
        backend.close()
    assert_exactly_once(segments, backend, log)           # (was: OUT0 off, OUT0 off, AOUT0 0)


def test_abandon_purges_before_acknowledging_so_nothing_of_the_old_stream_moves():
    machine, _ = plan("G90 G1 X20 F600\n")
    with Emulator(port=0, speed=5.0, resolution=1000, keep_buffers_on_alarm=True) as emu:
        backend = InterpCncBackend(machine, port=emu.port, resolution=1000)
        err = _alarm_during_a_cut(emu, backend, 3)
        assert err.alarm == 3
        where, log = emu.inspect(lambda c: (list(c.position), len(c.log)))
        assert emu.inspect(lambda c: len(c.planner)) == 1     # the cut, stopped half-way and kept
        backend.abandon()
        assert emu.inspect(lambda c: (list(c.position), len(c.log), len(c.planner))) == (where, log, 0)
        backend.close()


# ---------------------------------------------------------------- the gate's register convention
class InputRegisterConvention(Card):
    """A card reading 1012's address 100000 + r as *input* register r (seed 000 L250, L775-L791, L1291), where the
    back-end follows L1113-L1115 (holding register r)."""

    def _wait_met(self, a: dict) -> bool:
        if a["type"] == 3 and a["address"] >= 100000:
            self.refresh()
            a = dict(a, address=a["address"] - 100000)    # the model reads addresses below 100000 as input registers
        return super()._wait_met(a)


def test_with_the_default_marker_register_a_card_reading_the_gate_the_other_way_stops_at_the_first_gate():
    """Audit B1: with the gate on holding 3002 (the old default 3000), such a card watched IR 3002, the planner free
    space, and opened the gate by itself: M3 ran although nobody had confirmed it.  On 3992 the input register is not
    documented (map L259-L435) and reads 0: the gate stays shut, alarm 18, and the message names the cause."""
    machine, segments = plan("M3\nG1 X1 F600\n")
    emu = Emulator(port=0, speed=1000.0)
    emu.card = InputRegisterConvention(speed=1000.0)
    with emu:
        backend = InterpCncBackend(machine, port=emu.port, outputs={"M3": M3}, timeout=0.5)
        assert backend.options.marker_register == 3990
        backend.open()
        emu.hold_full(0.2)                                    # M3 is all accepted (its gate opened) before it runs
        for seg in segments:
            backend.send(seg)
        with pytest.raises(InterpCncError) as err:
            backend.finish()
        assert err.value.alarm == 18 and "input register 3992" in str(err.value)
        assert "option marker_register, now 3990" in str(err.value)
        assert emu.inspect(lambda c: c.outputs[0]) is False   # M3 did not run
        backend.close()


# ---------------------------------------------------------------- a card holding the stream
@pytest.mark.parametrize("hold", ["paused", "door"])
def test_a_feed_hold_or_the_door_on_the_card_shows_as_pause_and_finish_waits_for_it(hold):
    """IR 3003 bit 4 (feed hold: the card's panel, its pause input L1141, another client) or bit 6 (door safety), L429:
    the state says "pause" while it lasts, "run" after; finish() waits, the hold is the operator's."""
    machine, segments = plan("G90 G1 X5 F600\n")              # 0.5 s
    with Emulator(port=0, speed=1.0, resolution=1000) as emu:
        backend = InterpCncBackend(machine, port=emu.port, resolution=1000)
        backend.open()
        backend.send(segments[0])
        time.sleep(0.05)
        for _ in range(2):
            emu.inspect(lambda c: setattr(c, hold, True))
            time.sleep(0.03)                                  # status() reads the card again after poll_interval
            assert backend.status().state == "pause"
            emu.inspect(lambda c: setattr(c, hold, False))
            time.sleep(0.03)
            assert backend.status().state == "run"
        emu.inspect(lambda c: setattr(c, hold, True))
        done: list = []
        waiter = threading.Thread(target=lambda: done.append(backend.finish()), daemon=True)
        waiter.start()
        time.sleep(0.6)                                       # the cut would be over without the hold
        assert waiter.is_alive() and backend.status().state == "pause"
        assert emu.inspect(lambda c: c.position[0]) < 5.0
        emu.inspect(lambda c: setattr(c, hold, False))
        waiter.join(5.0)
        assert not waiter.is_alive() and done[0].state == "idle" and done[0].position["X"] == 5.0
        backend.close()


# ---------------------------------------------------------------- empty buffers, axes still moving
@pytest.mark.parametrize("call", ["finish", "abandon"])
def test_motion_ends_when_the_axes_have_stopped_not_only_when_the_buffers_are_empty(call):
    """Seed 000 L260, L512: IR 1016's low byte says which axes are still moving.  A card whose planner has freed its
    last entry while X is still stopping: finish() (and the wait after a 1200/255) must go on until the bit clears."""
    machine, segments = plan("G90 G1 X1 F3000\n")
    with Emulator(port=0, speed=20.0, resolution=1000) as emu:
        backend = InterpCncBackend(machine, port=emu.port, resolution=1000)
        backend.open()
        backend.send(segments[0])
        assert emu.wait_idle(5)
        emu.inspect(lambda c: setattr(c, "extra_moving", 0b1))    # X still moving, buffers empty
        done: list = []
        waiter = threading.Thread(target=lambda: done.append(getattr(backend, call)()), daemon=True)
        waiter.start()
        time.sleep(0.3)
        assert waiter.is_alive()
        emu.inspect(lambda c: setattr(c, "extra_moving", 0))
        waiter.join(5.0)
        assert not waiter.is_alive() and len(done) == 1 and backend.status().state == "idle"
        backend.close()


def test_an_arc_run_at_rapid_before_a_g00_is_sent_at_the_rapid_feed():
    # G41 round an outside corner into a G00: the compensation's transition arc about (30, 30) from
    # (27, 30) to (30, 33) has no feed (it runs at rapid).  The card was refused it mid-program ("a feed
    # move without a feed"); 1003 has no rapid bit, so it goes at the channel's rapid feed (1001).
    text = ("G90 G00 X0 Y-10\nT1 D1 M6\nG01 G41 X0 Y0 F500\nX30\nY30\nG00 X60 Y30\n"
            "G40 G00 X80 Y50\nM30\n")
    result = fagorcnc.simulate(text, {"tools": {"1": {"1": {"radius": 3.0}}}})
    assert result.ok, result.diagnostics
    segments = list(result.segments(keep_profiles=False))
    with Emulator(port=0, speed=50.0, resolution=1000) as emu:
        backend = InterpCncBackend(result.machine, port=emu.port, resolution=1000)
        backend.open()
        for seg in segments:
            backend.send(seg)
        st = backend.finish()
        backend.close()
        executed = emu.executed()
    arcs = [e for e in executed if e.kind == "arc"]
    assert [tuple(round(v, 3) for v in e.end[:2]) for e in arcs][-1] == (30.0, 33.0)
    assert st.position == {"X": 80.0, "Y": 50.0, "Z": 0.0}
    assert backend.rapid_feed == 10000.0   # the default machine: no channel rapid, X and Y at 10 m/min
