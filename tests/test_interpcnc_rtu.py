"""The same back-end over Modbus RTU (the card's RS485 and USB links, seed 000 L79-L81).

Without serial hardware: the emulator serves RTU framing on a TCP socket and the back-end's serial client
reaches it through pyserial's ``socket://127.0.0.1:PORT`` URL - RTU frames with CRC, byte for byte.
"""

from __future__ import annotations

import pytest

import fagorcnc
from fagorcnc.backends.interpcnc import InterpCncBackend, InterpCncError
from fagorcnc.backends.interpcnc.emulator import Emulator
from fagorcnc.backends.interpcnc.verify import executed_events, expected_events, first_difference

pytest.importorskip("serial")

OUTPUTS = {"M3": {"type": 1, "output": 0, "value": 1}, "M5": {"type": 1, "output": 0, "value": 0},
           "S": {"type": 2, "output": 1, "scale": 0.5}}


def test_short_stream_over_rtu_runs_exactly_as_planned():
    text = "G90 G0 X0 Y0 Z2\nM3 S4000\nG1 Z0 F1000\n" + "".join(
        f"G1 X{(k % 2) * 0.5:.1f} Y{0.1 * k:.1f} F2000\n" for k in range(1, 13)) + \
        "G2 X0 Y3.8 I0 J1.3\nG4 K0.1\nM5\nG0 Z2\n"
    result = fagorcnc.simulate(text)
    assert result.ok, result.diagnostics
    segments = list(result.segments(keep_profiles=False))
    with Emulator(port=0, speed=20.0, framer="rtu", resolution=500) as emu:
        backend = InterpCncBackend(result.machine, serial=f"socket://127.0.0.1:{emu.port}", baudrate=115200,
                                   outputs=OUTPUTS, resolution=500, timeout=2.0)
        backend.open()
        for seg in segments:
            backend.send(seg)
        status = backend.finish()
        assert status.executed == len(segments) and status.position == {"X": 0.0, "Y": 3.8, "Z": 2.0}
        assert first_difference(expected_events(segments, backend), executed_events(emu.executed())) is None
        assert emu.card.analog[1] == 2000 and emu.card.outputs[0] is False      # S4000 x 0.5 mV, then M5
        backend.close()


def test_rtu_link_loss_is_reported_and_recovered():
    result = fagorcnc.simulate("G90 G1 X10 F3000\nG1 Y10\nG1 X0\nG1 Y0\n")
    segments = list(result.segments(keep_profiles=False))
    with Emulator(port=0, speed=20.0, framer="rtu", resolution=500) as emu:
        backend = InterpCncBackend(result.machine, serial=f"socket://127.0.0.1:{emu.port}", resolution=500,
                                   timeout=1.0)
        backend.open()
        backend.send(segments[0])
        emu.fail_next(1)
        with pytest.raises(InterpCncError, match="Modbus exception 4"):
            backend.send(segments[1])
        backend.reconnect_and_continue()
        for seg in segments[2:]:
            backend.send(seg)
        backend.finish()
        assert first_difference(expected_events(segments, backend), executed_events(emu.executed())) is None
        backend.close()
