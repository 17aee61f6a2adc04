"""The RosettaCNC-style Modbus status server (seed 004) watching a run.

Every test starts its own server on a free port of 127.0.0.1 (``port=0``),
talks to it with pymodbus' ``ModbusTcpClient`` and stops it; the ``no_leaks``
fixture checks that every thread started during a test has ended.
"""

from __future__ import annotations

import threading
import time
from dataclasses import replace
from pathlib import Path

import pytest

pytest.importorskip("pymodbus")

from pymodbus.client import ModbusTcpClient

import fagorcnc
from fagorcnc.backends import SimulatorBackend, Status
from fagorcnc.plc.status_server import (
    CUSTOM_ALARM_CODE,
    MainState,
    PlcSignal,
    StatusServer,
    StatusServerError,
    decode_long,
    encode_long,
    hr_address,
    ir_address,
    parse_address,
)

DEMO = Path(__file__).resolve().parent.parent / "programs" / "demo.nc"
REALTIME = 60.0          # demo.nc plans ~92 s of motion: ~1.5 s of wall clock
TIMEOUT = 10.0           # s, for every wait on a run


# ---------------------------------------------------------------- helpers
@pytest.fixture(autouse=True)
def no_leaks():
    """Every thread a test starts (server, poller, run, hammer) must be joined by its end."""
    before = set(threading.enumerate())
    yield
    deadline = time.monotonic() + 5.0
    while time.monotonic() < deadline:
        extra = [t for t in threading.enumerate() if t not in before and t.is_alive()]
        if not extra:
            return
        time.sleep(0.02)
    pytest.fail(f"threads left running: {extra}")


def client_for(server: StatusServer) -> ModbusTcpClient:
    client = ModbusTcpClient("127.0.0.1", port=server.port, timeout=2, retries=1)
    assert client.connect()
    return client


def ir(client: ModbusTcpClient, reference: int, count: int = 1) -> list[int]:
    """Read input registers by their seed reference numbers (30001 = address 0)."""
    reply = client.read_input_registers(ir_address(reference), count=count)
    assert not reply.isError(), reply
    return reply.registers


def ir_long(client: ModbusTcpClient, reference: int, signed: bool = True) -> int:
    return decode_long(ir(client, reference, 2), "big", signed=signed)


def wait_for(predicate, timeout: float = TIMEOUT, period: float = 0.01):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        value = predicate()
        if value:
            return value
        time.sleep(period)
    raise AssertionError("condition not met in time")


class RunThread:
    """``fagorcnc.run`` in a thread (as the CLI runs it, with the server's progress callback)."""

    def __init__(self, **kwargs) -> None:
        self.report = None
        self.thread = threading.Thread(target=self._run, kwargs=kwargs, name="test-run")
        self.thread.start()

    def _run(self, **kwargs) -> None:
        self.report = fagorcnc.run(**kwargs)

    def join(self) -> fagorcnc.RunReport:
        self.thread.join(TIMEOUT)
        assert not self.thread.is_alive(), "the run did not end"
        assert self.report is not None
        return self.report


class FakeBackend:
    """A back-end reduced to what the server uses: ``status()`` and ``stop()`` (no ``raise_alarm``)."""

    name = "fake"

    def __init__(self, status: Status) -> None:
        self._status = status
        self.stops = 0

    def status(self) -> Status:
        return self._status

    def stop(self) -> None:
        self.stops += 1
        self._status = replace(self._status, state="idle")


def g54_machine():
    return fagorcnc.load_machine({"origins": {"G54": {"X": 100.0, "Y": -20.0}}})


# ---------------------------------------------------------------- (a) a run seen by a PLC
def test_plc_watches_a_run_state_line_positions_and_offsets():
    machine = g54_machine()
    be = SimulatorBackend(machine, realtime=REALTIME)
    with StatusServer(be, machine, port=0, program=DEMO) as server:
        client = client_for(server)
        try:
            # first thing a master reads: the interface level (seed 004 L24-L26, L49)
            assert ir(client, 30001) == [1]
            assert ir(client, 30071) == [MainState.IDLE]            # idle before the run (seed 004 L93)
            run = RunThread(source=DEMO, machine=machine, backend=be, keep_profiles=True, check_first=True,
                            progress=server.progress_callback())
            states, lines, transferred = [], [], []
            paused_checked = False
            while run.thread.is_alive():
                # 30071..30078 in one request: state, bits, alarm code/A/B, line [L], execution info
                regs = ir(client, 30071, 8)
                states.append(regs[0])
                lines.append(decode_long(regs[5:7]))
                transferred.append(regs[7] >> 8)
                if not paused_checked and regs[0] == MainState.RUN and lines[-1] >= 20:
                    paused_checked = True
                    check_positions_while_paused(client, be, server)
                time.sleep(0.01)
            report = run.join()
            assert report.ok, report.message
            server.refresh()
            # state idle -> run -> idle (seed 004 L93, L96); the test's pause (7, L97) is left out
            seen = [MainState.IDLE, *(s for s in states if s != MainState.PAUSE), *ir(client, 30071)]
            assert [s for i, s in enumerate(seen) if i == 0 or s != seen[i - 1]] == [3, 6, 3]
            assert paused_checked
            # the current line advances through the program (seed 004 L115) and ends on M30 (line 48)
            running_lines = [n for s, n in zip(states, lines, strict=True) if s == MainState.RUN]
            assert len(set(running_lines)) >= 5 and max(running_lines) >= 40
            assert ir_long(client, 30076) == report.status.line == 48
            # program transferred % (seed 004 L117) only grows
            assert transferred == sorted(transferred) and transferred[-1] >= 90
            # at rest the registers are the simulator's position in µm (seed 004 L57-L59)
            final = be.status().position
            machine_um = [ir_long(client, 30005 + 2 * i) for i in range(3)]
            assert machine_um == [round(1000 * final[a]) for a in "XYZ"] == [40000, -20000, 50000]
            assert [ir_long(client, 30011 + 2 * i) for i in range(3)] == machine_um      # target = end of last move
            assert [ir_long(client, 30023 + 2 * i) for i in range(3)] == [-60000, 0, 50000]   # part coordinates
            assert [ir_long(client, 30059 + 2 * i) for i in range(3)] == [0, 0, 0]            # at rest
            # b1: program ended successfully (seed 004 L109) once the runner says so
            assert ir(client, 30072)[0] & 0b10 == 0
            server.finished(report.ok)
            assert ir(client, 30072) == [0b11] and ir(client, 30078)[0] >> 8 == 100
        finally:
            client.close()
    assert not server.running


def check_positions_while_paused(client: ModbusTcpClient, be: SimulatorBackend, server: StatusServer) -> None:
    """Pause the simulator mid-run: the published positions are its status, in µm, within rounding."""
    be.pause()
    try:
        time.sleep(0.1)                             # the simulator's pacing loop settles (10 ms steps)
        status = be.status()
        time.sleep(3 * server.poll_interval)        # the poller publishes it
        pos = status.position
        expected_state = {"pause": MainState.PAUSE, "run": MainState.RUN}[status.state]
        assert ir(client, 30071) == [expected_state]
        # one request: machine X Y Z (30005-30010), target (30011-30022), program position (30023-30034)
        regs = ir(client, 30005, 30)
        machine_um = [decode_long(regs[2 * i:2 * i + 2]) for i in range(3)]
        program_um = [decode_long(regs[18 + 2 * i:20 + 2 * i]) for i in range(3)]
        for axis, value in zip("XYZ", machine_um, strict=True):
            assert abs(value - 1000 * pos[axis]) <= 0.5 + 1e-6
        # working offset from G54 (X100 Y-20, seed 004 L75-L77) and program = machine - offset
        offsets = [ir_long(client, 30047 + 2 * i) for i in range(3)]
        assert offsets == [100000, -20000, 0]
        assert program_um == [m - o for m, o in zip(machine_um, offsets, strict=True)]
        assert ir_long(client, 30076) == status.line
    finally:
        be.resume()


# ---------------------------------------------------------------- (b) a PLC alarm stops the run
def test_custom_alarm_written_by_the_plc_stops_the_run():
    machine = fagorcnc.load_machine(None)
    be = SimulatorBackend(machine, realtime=REALTIME)
    seen: list[PlcSignal] = []
    with StatusServer(be, machine, port=0, holding_writes=True, on_signal=seen.append,
                      alarm_texts={1: "guard door open"}) as server:
        client = client_for(server)
        try:
            t0 = time.monotonic()
            run = RunThread(source=DEMO, machine=machine, backend=be, keep_profiles=True,
                            progress=server.progress_callback())
            wait_for(lambda: ir(client, 30071) == [MainState.RUN] and ir_long(client, 30076) >= 15)
            # HR_CUSTOM_ALARM_01 = 40001: "set to non zero to sign custom alarm 01" (seed 004 L137)
            reply = client.write_register(hr_address(40001), 5)
            assert not reply.isError(), reply
            # acknowledged only once the back-end has the alarm: the next read already shows it
            assert ir(client, 30071) == [MainState.ALARM]                       # seed 004 L92
            assert ir(client, 30073, 3) == [CUSTOM_ALARM_CODE + 1, 1, 5]       # code, info A, info B (L111-L113)
            report = run.join()
            assert time.monotonic() - t0 < 1.0 * 92 / REALTIME                  # stopped well before the end
            assert report.stopped_by == "alarm" and not report.ok
            assert report.status.alarm == CUSTOM_ALARM_CODE + 1
            assert report.status.alarm_message == "guard door open (HR 40001 = 5)"
            assert report.status.line < 48
            assert [(s.kind, s.number, s.value, s.register, s.code) for s in server.alarms] == [
                ("alarm", 1, 5, 40001, CUSTOM_ALARM_CODE + 1)]
            assert seen == server.alarms
            # the run is over (back-end closed): still in alarm while the alarm stands
            server.refresh()
            assert ir(client, 30071) == [MainState.ALARM] and ir(client, 30073) == [CUSTOM_ALARM_CODE + 1]
            assert client.read_holding_registers(hr_address(40001), count=8).registers == [5] + [0] * 7
        finally:
            client.close()


def test_a_custom_alarm_held_set_stops_the_next_run_at_once():
    machine = fagorcnc.load_machine(None)
    be = SimulatorBackend(machine, realtime=REALTIME)
    with StatusServer(be, machine, port=0, holding_writes=True) as server:
        client = client_for(server)
        try:
            assert not client.write_register(hr_address(40003), 1).isError()
            assert ir(client, 30071) == [MainState.ALARM] and ir(client, 30073) == [CUSTOM_ALARM_CODE + 3]
            t0 = time.monotonic()
            report = RunThread(source=DEMO, machine=machine, backend=be, keep_profiles=True).join()
            assert report.stopped_by == "alarm" and report.status.alarm == CUSTOM_ALARM_CODE + 3
            assert time.monotonic() - t0 < 0.8
        finally:
            client.close()


def test_custom_alarm_without_raise_alarm_stops_the_backend_and_clears_with_the_register():
    be = FakeBackend(Status(state="run", line=7, position={"X": 1.0, "Y": 2.0, "Z": 3.0}))
    with StatusServer(be, None, port=0, holding_writes=True) as server:
        client = client_for(server)
        try:
            assert ir(client, 30071) == [MainState.RUN]
            assert not client.write_register(hr_address(40002), 9).isError()
            assert be.stops >= 1
            assert ir(client, 30071) == [MainState.ALARM] and ir(client, 30073, 3) == [CUSTOM_ALARM_CODE + 2, 2, 9]
            assert not client.write_register(hr_address(40002), 0).isError()
            assert ir(client, 30071) == [MainState.IDLE] and ir(client, 30073) == [0]
            assert [s.value for s in server.alarms] == [9, 0]
        finally:
            client.close()


def test_custom_warnings_are_recorded_and_visible():
    be = FakeBackend(Status(state="run"))
    seen: list[PlcSignal] = []
    with StatusServer(be, None, port=0, holding_writes=True, on_signal=seen.append) as server:
        client = client_for(server)
        try:
            # HR_CUSTOM_WARNING_01..02 = 40009..40010 (seed 004 L146-L147), one function 16 write
            assert not client.write_registers(hr_address(40009), [3, 0]).isError()
            assert server.active_warnings() == {1: 3}
            assert not client.write_register(hr_address(40009), 0).isError()
            assert server.active_warnings() == {}
            assert [(s.kind, s.number, s.value, s.register) for s in server.warnings] == [
                ("warning", 1, 3, 40009), ("warning", 1, 0, 40009)]
            assert seen == server.warnings and server.alarms == []
            assert ir(client, 30071) == [MainState.RUN] and be.stops == 0     # a warning does not stop
            # shared memory written by the PLC (seed 004 L155) is stored, [L] high word first
            assert not client.write_registers(hr_address(40018), [*encode_long(-123456), *encode_long(7)]).isError()
            assert server.shared_memory()[:3] == [-123456, 7, 0]
        finally:
            client.close()


# ---------------------------------------------------------------- (c) addresses and units of seed 004
def test_register_addresses_and_units_follow_the_seed_table():
    machine = fagorcnc.load_machine({"axes": {"X": {}, "Y": {}, "Z": {}, "A": {"type": "rotary"}}})
    status = Status(state="pause", line=70000, position={"X": 12.3456, "Y": -6.789, "Z": 100.0, "A": 45.5},
                    velocity={"X": 10.0, "Y": -2.5, "Z": 0.0, "A": 1.0}, buffer_level=0.42)
    offsets = {"X": 10.0, "Y": -5.0, "Z": 0.0, "A": 0.25}
    with StatusServer(FakeBackend(status), machine, port=0, serial_number=123456,
                      offsets=lambda: offsets) as server:
        client = client_for(server)
        try:
            assert ir(client, 30001) == [1]                              # interface level 1 (L26, L49)
            assert ir(client, 30002) == [(0 << 8) | 1]                   # fagorcnc 0.1: version 0, release 1 (L51)
            assert ir_long(client, 30003) == 123456                      # serial number [L] (L55)
            # machine position X Y Z [mm/1000] (L57-L59): rounded to the µm
            assert [ir_long(client, r) for r in (30005, 30007, 30009)] == [12346, -6789, 100000]
            # target (L61-L66): no segment reported yet, so the machine position; A in 1/1000 degree
            assert [ir_long(client, 30011 + 2 * i) for i in range(6)] == [12346, -6789, 100000, 45500, 0, 0]
            # program position = machine - working offset (L68-L73, L75-L80)
            assert [ir_long(client, 30023 + 2 * i) for i in range(6)] == [2346, -1789, 100000, 45250, 0, 0]
            assert [ir_long(client, 30047 + 2 * i) for i in range(6)] == [10000, -5000, 0, 250, 0, 0]
            # actual velocity [mm/min], [°/min] (L82-L87): the status gives mm/s
            assert [ir_long(client, 30059 + 2 * i) for i in range(6)] == [600, -150, 0, 60, 0, 0]
            assert ir(client, 30071, 5) == [MainState.PAUSE, 0b01, 0, 0, 0]   # state 7 (L97), homed (L108)
            assert ir_long(client, 30076, signed=False) == 70000         # line [L] beyond 16 bits (L115)
            assert ir(client, 30078) == [42]                             # buffer 42 %, nothing transferred (L117)
            assert ir(client, 30079) == [0]                              # no virtual outputs (L119)
            assert ir(client, 30080, 18) == [0] * 18                     # shared memory, G-code cmd (L125-L134)
            assert ir(client, 30035, 12) == [0] * 12                     # the table's gap reads 0
            # [L] word order: high word first, the lower address holds bits 31..16
            assert ir(client, 30076, 2) == [70000 >> 16, 70000 & 0xFFFF]
            assert ir(client, 30007, 2) == [0xFFFF, (-6789) & 0xFFFF]
            assert client.read_holding_registers(hr_address(40001), count=32).registers == [0] * 32
        finally:
            client.close()


def test_low_word_first_on_request():
    status = Status(state="idle", line=70000)
    with StatusServer(FakeBackend(status), None, port=0, word_order="little") as server:
        client = client_for(server)
        try:
            assert ir(client, 30076, 2) == [70000 & 0xFFFF, 70000 >> 16]
        finally:
            client.close()


def test_main_state_mapping():
    cases = [("idle", 0, MainState.IDLE), ("run", 0, MainState.RUN), ("pause", 0, MainState.PAUSE),
             ("alarm", 0, MainState.ALARM), ("run", 12, MainState.ALARM), ("closed", 0, MainState.IDLE),
             ("something", 0, MainState.INIT)]
    for state, alarm, code in cases:
        server = StatusServer(FakeBackend(Status(state=state, alarm=alarm)), None, port=0)
        server.refresh()
        assert server.input_registers()[ir_address(30071)] == code, state
    closed = StatusServer(FakeBackend(Status(state="closed")), None, port=0, closed_state=MainState.INIT)
    closed.refresh()
    assert closed.input_registers()[ir_address(30071)] == MainState.INIT


# ---------------------------------------------------------------- (d) what the slave refuses
def test_reads_of_more_than_32_registers_and_writes_not_enabled_are_refused():
    with StatusServer(FakeBackend(Status(state="idle")), None, port=0) as server:
        client = client_for(server)
        try:
            # "a maximum of 32 registers at a time" (seed 004 L173): exception 03 illegal data value
            assert not client.read_input_registers(0, count=32).isError()
            reply = client.read_input_registers(0, count=33)
            assert reply.isError() and reply.exception_code == 3
            reply = client.read_holding_registers(0, count=33)
            assert reply.isError() and reply.exception_code == 3
            # holding writes need "Enable write operations" (seed 004 L170): exception 01 illegal function
            for reply in (client.write_register(hr_address(40001), 5),
                          client.write_registers(hr_address(40009), [1, 2])):
                assert reply.isError() and reply.exception_code == 1
            assert server.holding_registers() == [0] * 34 and server.alarms == server.warnings == []
            assert ir(client, 30071) == [MainState.IDLE]
            # beyond the table, and coils (not in the table)
            assert client.read_input_registers(ir_address(30098), count=1).isError()
            assert client.read_holding_registers(hr_address(40035), count=1).isError()
            assert client.read_coils(0, count=1).isError()
        finally:
            client.close()


def test_a_busy_port_is_reported():
    with StatusServer(FakeBackend(Status()), None, port=0) as first:
        second = StatusServer(FakeBackend(Status()), None, port=first.port)
        with pytest.raises(StatusServerError, match="cannot listen"):
            second.start(timeout=5.0)
        assert not second.running


# ---------------------------------------------------------------- (e) no torn 32-bit values
class FlippingBackend:
    """Every status() flips the line between 65535 and 65536 and X between -0.001 and 0 mm.

    Both cross a 16-bit boundary, so a read that took one word from each
    value would decode as 0 or 131071 (line) and -65536 or 65535 (X, µm).
    """

    name = "flip"

    def __init__(self) -> None:
        self.calls = 0

    def status(self) -> Status:
        self.calls += 1
        odd = self.calls % 2
        return Status(state="run", line=65535 + odd, position={"X": -0.001 * (1 - odd), "Y": 0.0, "Z": 0.0})


def test_32_bit_values_are_never_torn_while_they_change():
    backend = FlippingBackend()
    with StatusServer(backend, None, port=0, poll_interval=0.001) as server:
        stop = threading.Event()

        def hammer() -> None:            # publish as fast as possible, besides the 1 ms poller
            while not stop.is_set():
                server.refresh()

        writer = threading.Thread(target=hammer, name="test-hammer")
        writer.start()
        client = client_for(server)
        lines, xs = set(), set()
        try:
            deadline = time.monotonic() + 1.0
            while time.monotonic() < deadline:
                lines.add(ir_long(client, 30076, signed=False))
                xs.add(ir_long(client, 30005))
                # both in one request too: X (30005) .. line (30076) is too far apart, so X and Z
                regs = ir(client, 30005, 6)
                xs.add(decode_long(regs[0:2]))
        finally:
            stop.set()
            writer.join(TIMEOUT)
            client.close()
        assert not writer.is_alive()
    assert lines == {65535, 65536}, lines         # a torn read would add 0 or 131071
    assert xs == {-1, 0}, xs                       # ... or -65536 or 65535
    assert backend.calls > 100


# ---------------------------------------------------------------- helpers of the module
def test_long_encoding_and_address_helpers():
    assert encode_long(70000) == (1, 4464) and decode_long([1, 4464]) == 70000
    assert encode_long(70000, "little") == (4464, 1) and decode_long([4464, 1], "little") == 70000
    assert encode_long(-1) == (0xFFFF, 0xFFFF) and decode_long([0xFFFF, 0xFFFF]) == -1
    assert decode_long([0xFFFF, 0xFFFF], signed=False) == 0xFFFFFFFF
    assert encode_long(-(1 << 40)) == (0x8000, 0)                       # saturates
    assert ir_address(30001) == 0 and ir_address(30076) == 75 and hr_address(40001) == 0
    assert parse_address("5020") == ("127.0.0.1", 5020)
    assert parse_address("0.0.0.0:502") == ("0.0.0.0", 502)
    with pytest.raises(ValueError):
        parse_address("host:port")


def test_the_target_position_is_the_end_of_the_move_the_machine_is_running(tmp_path):
    # seed 004 L61-L66 IR_TARGET_POSITION: the runner reports a segment after the back-end has run it, so the
    # target read one move behind (where the tool came from); the back-end now says where it is going
    program = tmp_path / "two.nc"
    program.write_text("G90 G1 X100 F600\nG1 Y50\nM30\n")   # 10 s along X at y = 0, then 5 s along Y at x = 100
    machine = fagorcnc.load_machine(None)
    be = SimulatorBackend(machine, realtime=25.0)
    with StatusServer(be, machine, port=0) as server:
        client = client_for(server)
        try:
            run = threading.Thread(target=fagorcnc.run, args=(program, machine),
                                   kwargs={"backend": be, "progress": server.progress_callback()})
            run.start()
            rows = []
            while run.is_alive():
                rows.append([ir_long(client, 30005 + 2 * i) for i in range(2)] +
                            [ir_long(client, 30011 + 2 * i) for i in range(2)])
                time.sleep(0.02)
            run.join()
        finally:
            client.close()
    along_x = [r for r in rows if r[1] == 0 and 0 < r[0] < 100000]
    along_y = [r for r in rows if r[0] == 100000 and 0 < r[1] < 50000]
    assert along_x and along_y, rows
    assert all(r[2:] == [100000, 0] for r in along_x), along_x
    assert all(r[2:] == [100000, 50000] for r in along_y), along_y
