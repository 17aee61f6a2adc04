"""The status server at the end of a run and against odd requests (issues 25.5, 30.16, 30.18).

A PLC polling every 20 ms must see how the run ended: the server lingers with the final state and
the end reason (30035, [CONSTRUCTION]: a register of the gap the seed's table leaves) and line
(30036).  A refused request changes nothing; functions outside the table are refused; malformed
frames leave nothing on the run's standard error.
"""

from __future__ import annotations

import os
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest

pytest.importorskip("pymodbus")

from pymodbus.client import ModbusTcpClient

import fagorcnc
from fagorcnc.backends import SimulatorBackend, Status
from fagorcnc.cli import main
from fagorcnc.plc import status_server
from fagorcnc.plc.status_server import END_REASONS, MainState, StatusServer, decode_long, hr_address, ir_address

FIVE = "G90 G1 X1 F6000\nX2\nX3\nX4\nX5\nM30\n"


class Idle:
    name = "idle"

    def __init__(self) -> None:
        self.stops = 0

    def status(self) -> Status:
        return Status(state="idle")

    def stop(self) -> None:
        self.stops += 1


def client_for(server: StatusServer) -> ModbusTcpClient:
    client = ModbusTcpClient("127.0.0.1", port=server.port, timeout=2, retries=0)
    assert client.connect()
    return client


def ir(client, reference: int, count: int = 1) -> list[int]:
    reply = client.read_input_registers(ir_address(reference), count=count)
    assert not reply.isError(), reply
    return reply.registers


class AlarmAfter(SimulatorBackend):
    def send(self, segment) -> None:
        super().send(segment)
        if segment.line == 2:
            self.raise_alarm(9001, "PLC custom alarm 1")


@pytest.mark.parametrize(("backend", "reason", "line", "state", "bits"), [
    (SimulatorBackend, "M30", 0, MainState.IDLE, 0b11),        # b1: ended successfully
    (AlarmAfter, "alarm", 2, MainState.ALARM, 0b01),           # stopped at line 2 (see test_run_summary)
])
def test_the_final_state_and_end_reason_stay_readable_while_it_lingers(backend, reason, line, state, bits):
    machine = fagorcnc.load_machine(None)
    be = backend(machine)
    server = StatusServer(be, machine, port=0, linger=0.6).start()
    try:
        report = fagorcnc.run(text=FIVE, machine=machine, backend=be, progress=server.progress_callback())
        server.finished(report.ok, report.ending)
        lingering = threading.Thread(target=server.linger)
        lingering.start()
        client = client_for(server)
        try:
            assert ir(client, 30071) == [state]
            assert ir(client, 30072) == [bits]
            assert ir(client, 30035) == [END_REASONS[reason]]
            assert decode_long(ir(client, 30036, 2)) == line
        finally:
            client.close()
        lingering.join(5)
        assert not lingering.is_alive() and not server.running   # then it closes
    finally:
        server.stop()


def test_the_end_reason_is_cleared_when_the_next_run_starts():
    server = StatusServer(Idle(), None, port=0)
    server.finished(False, fagorcnc.summary.Ending("error", 12))
    assert server.input_registers()[ir_address(30035)] == END_REASONS["error"] == 4
    assert decode_long(server.input_registers()[ir_address(30036):ir_address(30036) + 2]) == 12
    server.update(None, Status(state="run", line=1))
    time.sleep(0.01)   # the image is rebuilt at most every 5 ms
    server.update(None, Status(state="run", line=1))
    assert server.input_registers()[ir_address(30035)] == 0


def test_the_command_lingers_as_asked(tmp_path, monkeypatch, capsys):
    seen = []

    def linger(self, seconds=None):
        seen.append((self.linger_seconds, self.input_registers()[ir_address(30035)]))
        self.stop()

    monkeypatch.setattr(status_server.StatusServer, "linger", linger)
    f = tmp_path / "five.nc"
    f.write_text(FIVE)
    assert main(["run", str(f), "--status-server", "127.0.0.1:0", "--status-linger", "0:02"]) == 0
    assert seen == [(2.0, END_REASONS["M30"])]
    assert "stays up 2 s" in capsys.readouterr().err
    assert status_server.DEFAULT_LINGER == 3.0


def test_a_refused_read_write_request_changes_nothing():
    # function 23 with a bad read part: answered with an exception, and the write must not happen (HR 40001 = 5
    # would stop the run with alarm 9001)
    backend = Idle()
    with StatusServer(backend, None, port=0, holding_writes=True) as server:
        client = client_for(server)
        try:
            for read_address, read_count, code in ((0, 40, 2), (200, 2, 2), (0, 33, 3)):
                reply = client.readwrite_registers(read_address=read_address, read_count=read_count,
                                                   write_address=hr_address(40001), values=[5])
                assert reply.isError() and reply.exception_code == code
            assert server.holding_registers() == [0] * 34 and server.alarms == [] and backend.stops == 0
            # a valid one writes, then reads what it wrote (Modbus: the write first)
            reply = client.readwrite_registers(read_address=hr_address(40009), read_count=2,
                                               write_address=hr_address(40009), values=[7])
            assert not reply.isError() and reply.registers == [7, 0]
            assert server.active_warnings() == {1: 7}
        finally:
            client.close()


def test_read_fifo_and_file_records_are_refused():
    with StatusServer(Idle(), None, port=0) as server:
        client = client_for(server)
        try:
            reply = client.read_fifo_queue(address=0)   # pymodbus answered dummy values 0, 1, 2, 3
            assert reply.isError() and reply.exception_code == 1
            assert ir(client, 30001) == [1]              # the server goes on answering
        finally:
            client.close()


SCRIPT = """
import socket, struct, sys, time
from fagorcnc.backends import Status
from fagorcnc.plc.status_server import StatusServer

class Idle:
    name = "idle"
    def status(self):
        return Status(state="idle")

with StatusServer(Idle(), None, port=0) as server:
    for payload in (b"", b"\\x00", b"\\x00\\x01\\x02\\x03\\x04", b"\\xff" * 20):
        s = socket.create_connection(("127.0.0.1", server.port))
        s.settimeout(2)
        s.sendall(struct.pack(">HHHB", 1, 0, 2 + len(payload), 1) + b"\\x84" + payload)
        try:
            s.recv(100)
        except OSError:
            pass
        s.close()
    time.sleep(0.2)
print("done")
"""


def test_function_0x84_frames_print_nothing_on_standard_error():
    env = {**os.environ, "PYTHONPATH": str(Path(__file__).resolve().parents[1])}
    out = subprocess.run([sys.executable, "-c", SCRIPT], capture_output=True, text=True, env=env, timeout=60)
    assert out.stdout.strip() == "done"
    assert out.stderr == "", out.stderr


def test_a_plc_alarm_is_the_ending_of_the_run_not_m30():
    # issue 30.17: HR 40001 = 5 stops the run with alarm 9001; the summary said "ended by M30"
    demo = Path(__file__).resolve().parents[1] / "programs" / "demo.nc"
    machine = fagorcnc.load_machine(None)
    be = SimulatorBackend(machine, realtime=20.0)   # demo.nc plans ~92 s: ~4.6 s of wall clock, a wide window
    with StatusServer(be, machine, port=0, holding_writes=True) as server:
        client = client_for(server)
        result: list = []
        thread = threading.Thread(target=lambda: result.append(fagorcnc.run(
            demo, machine, backend=be, keep_profiles=True, progress=server.progress_callback())))
        thread.start()
        try:
            deadline = time.monotonic() + 10
            while not (ir(client, 30071) == [MainState.RUN] and decode_long(ir(client, 30076, 2)) >= 15):
                assert time.monotonic() < deadline, "the run did not reach line 15"
                time.sleep(0.01)
            assert not client.write_register(hr_address(40001), 5).isError()
        finally:
            thread.join(10)
            client.close()
        (report,) = result
        assert report.stopped_by == "alarm" and report.ended_by is None
        assert report.ending.cause == "alarm" and report.ending.alarm == 9001
        assert report.ending.line == report.status.line < 48
        assert str(report.summary).endswith(f"ended by alarm 9001 at line {report.status.line}")
