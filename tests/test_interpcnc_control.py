"""The interpcnc back-end's immediate commands, status and checks, against the emulator over Modbus TCP.

Each test starts its own emulator on a free port (127.0.0.1) and stops it; every wait has a timeout.
"""

from __future__ import annotations

import time

import pytest
from interpcnc_helpers import plan
from pymodbus.client import ModbusTcpClient

from fagorcnc.backends.base import BackendError
from fagorcnc.backends.interpcnc import InterpCncBackend, InterpCncError
from fagorcnc.backends.interpcnc import backend as backend_module
from fagorcnc.backends.interpcnc import protocol as proto
from fagorcnc.backends.interpcnc.emulator import Emulator, main

M3 = {"type": 1, "output": 0, "value": 1}



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
        problems = backend.check(segments)                    # M8; T2, M6 and the implicit D1 of line 4
        assert [w.split(":")[0] for w in problems] == ["line 3", "line 4", "line 4", "line 4"]
        assert [w.split(": ")[1].split()[0] for w in problems] == ["M8", "T2", "M6", "D1"]
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
    """Their exact words: 1012 type 3 "above" (kind 2) on holding 3002 as extended address 103002 (seed 000 L1115)
    with threshold token - 1, timeout 65535 ms and alarm 18 on timeout; then the actions and the sequence marker
    (3000), or for a dwell 0 into 3001, the marker, the dwell and 1 into 3001; then a plain write of the token into
    3002.  The card holds them until then: a fault before it leaves nothing run (tests/test_fault_campaign.py
    injects one at each write)."""
    machine, segments = plan("M3\nG4 K0.25\n")
    with Emulator(port=0, speed=1.0) as emu:
        backend = InterpCncBackend(machine, port=emu.port, outputs={"M3": M3})
        backend.open()
        wait = [1012, 3, 65535, 1, 2]
        gate = [103002 & 0xFFFF, 103002 >> 16]
        assert backend._prepare(backend_module._Sent(1, segments[0])) == [
            [*wait, 0, *gate], [1010, 1, 0, 1], [1010, 3, 3000, 1], backend_module._OpenGate(1)]
        assert backend._prepare(backend_module._Sent(2, segments[1])) == [
            [*wait, 1, *gate], [1010, 3, 3001, 0], [1010, 3, 3000, 2], [1011, 250], [1010, 3, 3001, 1],
            backend_module._OpenGate(2)]
        backend._reset_stream()
        backend.send(segments[0])
        backend.send(segments[1])
        assert emu.inspect(lambda card: (card.hr[3002], card.outputs[0])) == (2, True)
        st = backend.status()
        assert st.line == 2 and st.executed == 1              # M3 has run, the dwell is under way
        st = backend.finish()
        assert st.executed == 2 and st.line == 2
        backend.close()
