"""The back-end interface, the embedded simulator back-end and fagorcnc.run()."""

from __future__ import annotations

import threading
import time

import pytest

import fagorcnc
from fagorcnc.backends import Backend, BackendError, SimulatorBackend, available, get_backend
from fagorcnc.cli import main
from fagorcnc.config.machine import load_machine

PROGRAM = "G90 G1 X10 F6000\nM8\nG4 K0.5\nX20 Y5\nG2 X30 Y5 I5 J0\nM9\nM30\n"


def test_registry_knows_the_builtin_backends():
    names = available()
    assert "sim" in names and "interpcnc" in names
    be = get_backend("sim", load_machine(None))
    assert isinstance(be, Backend) and be.name == "sim"
    with pytest.raises(BackendError, match="unknown back-end 'plasma'"):
        get_backend("plasma", load_machine(None))


def test_run_on_the_simulator_matches_the_dry_run():
    dry = fagorcnc.simulate(PROGRAM)
    report = fagorcnc.run(PROGRAM)
    assert report.ok and report.ended_by == "M30" and report.stopped_by is None
    assert report.cycle_time == pytest.approx(dry.cycle_time, rel=1e-12)
    be = report.backend
    planned = list(dry.segments(keep_profiles=False))
    assert [(s.kind, s.line) for s in be.segments] == [(s.kind, s.line) for s in planned]
    assert [(line, f, v) for _t, line, f, v in be.aux_log] == [(2, "M", 8.0), (6, "M", 9.0), (7, "M", 30.0)]
    assert report.status.position == pytest.approx({"X": 30.0, "Y": 5.0, "Z": 0.0})
    assert report.status.line == 7 and report.status.executed == len(planned)


def test_run_stops_at_a_program_error_and_reports_it():
    report = fagorcnc.run("G1 X10 F600\nP1 = 1/0\nG1 X20\nM30\n")
    assert not report.ok and report.stopped_by == "error"
    assert [d.code for d in report.diagnostics if d.is_error] == ["INT033"]
    assert report.status.position["X"] == pytest.approx(10.0)   # nothing after the error moved


def test_check_first_sends_nothing_when_the_program_has_an_error():
    be = SimulatorBackend(load_machine(None))
    report = fagorcnc.run("G1 X10 F600\nP1 = 1/0\nG1 X20\nM30\n", backend=be, check_first=True)
    assert report.stopped_by == "error" and report.segments == 0 and be.segments == []


def test_an_alarm_stops_the_stream_with_the_last_block():
    class Failing(SimulatorBackend):
        def send(self, segment):
            if segment.line == 4:
                self.raise_alarm(10, "emergency stop")
            super().send(segment)

    be = Failing(load_machine(None))
    report = fagorcnc.run(PROGRAM, backend=be)
    assert report.stopped_by == "alarm" and report.message == "alarm 10: emergency stop"
    assert report.status.line <= 3 and all(s.line < 4 for s in be.segments)


def test_realtime_pacing_and_status_while_running():
    m = load_machine(None)
    be = SimulatorBackend(m, realtime=4.0)
    seen = []
    done = threading.Event()

    def watch():
        while not done.is_set():
            seen.append(be.status().state)
            time.sleep(0.01)

    th = threading.Thread(target=watch)
    th.start()
    t0 = time.monotonic()
    report = fagorcnc.run("G1 X50 F6000\nM30\n", backend=be, keep_profiles=True)
    elapsed = time.monotonic() - t0
    done.set()
    th.join()
    # 50 mm at 100 mm/s from rest to rest: 0.3 s of ramps + 0.35 s cruise = 0.65 s, at 4x: ~0.16 s
    assert report.ok and 0.14 <= elapsed < 2.0
    assert "run" in seen


def test_cli_run_backend_options(capsys):
    assert main(["run", "--backend", "plasma", "programs/demo.nc"]) == 2
    assert "unknown back-end" in capsys.readouterr().err
    assert main(["run", "--realtime", "2", "--backend", "interpcnc", "programs/demo.nc"]) == 2
