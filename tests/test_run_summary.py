"""One run summary for run, check, simulate() and dry_run() (issues 25.6, 30.17): the same move count,
and "ended by" naming the real cause."""

from __future__ import annotations

from pathlib import Path

import pytest

import fagorcnc
from fagorcnc.backends import BackendError, SimulatorBackend, Status
from fagorcnc.cli import main
from fagorcnc.commands.check import check_file, text_report
from fagorcnc.simulate import dry_run
from fagorcnc.summary import Ending, MoveCounter

PROGRAMS = Path(__file__).resolve().parents[1] / "programs"
# five moves on lines 1..5 (line 1: G1 X1; line k: X k), then M30 on line 6
FIVE = "G90 G1 X1 F6000\nX2\nX3\nX4\nX5\nM30\n"


def test_every_entry_point_counts_the_moves_of_cam_finish_alike():
    # 53 motion records; one of them, the rapid of line 66 (N280 G0 Z15. after G159=5 and #RTCP: the tool is
    # there already), has length zero and no planned segment: run counted segments and said 52
    path = PROGRAMS / "cam_finish.nc"
    counts = {
        "simulate": fagorcnc.simulate(path).summary.moves,
        "dry_run": dry_run(path).moves,
        "check": check_file(path).moves,
        "run": fagorcnc.run(path).moves,
        "run, checked first": fagorcnc.run(path, check_first=True).moves,
    }
    assert set(counts.values()) == {53}, counts
    assert str(fagorcnc.run(path).summary) == "53 moves, ended by M30"


def test_m30_m02_and_end_of_file():
    assert str(fagorcnc.simulate(text=FIVE).ending) == "M30"
    assert str(dry_run(text=FIVE.replace("M30", "M02")).ending) == "M02"
    assert str(fagorcnc.run(text=FIVE.replace("M30\n", "")).ending) == "end of file"


def test_an_error_ends_the_run_at_its_line_everywhere(tmp_path):
    # line 3: G1000 is no G function (INT010): the control stops there, after the moves of lines 1-2
    f = tmp_path / "bad.nc"
    f.write_text(FIVE.replace("X3", "G1000"))
    for ending in (fagorcnc.simulate(f).ending, dry_run(f).ending, fagorcnc.run(f).ending,
                   check_file(f).ending):
        assert str(ending) == "error at line 3"
    assert fagorcnc.run(f).ended_by is None
    assert "2 moves, ended by error at line 3" in text_report(check_file(f))   # was "ended by end of file"


class AlarmAfter(SimulatorBackend):
    """The simulator with a PLC raising alarm 9001 once the segment of line ``line`` has run."""

    def __init__(self, machine, line: int) -> None:
        super().__init__(machine)
        self.line = line

    def send(self, segment) -> None:
        super().send(segment)
        if segment.line == self.line:
            self.raise_alarm(9001, "PLC custom alarm 1")


def test_an_alarm_ends_the_run_at_the_line_the_machine_stopped():
    # the alarm comes once line 2's move has run; the simulator refuses the next segment (line 3), so the
    # machine stopped at line 2; the interpreter had read on to M30 (line 6): the report said "ended by M30"
    machine = fagorcnc.load_machine(None)
    report = fagorcnc.run(text=FIVE, machine=machine, backend=AlarmAfter(machine, 2))
    assert report.stopped_by == "alarm" and report.ended_by is None
    assert report.ending == Ending("alarm", 2, 9001) and report.status.line == 2
    assert str(report.summary) == "2 moves, ended by alarm 9001 at line 2"


class Failing(SimulatorBackend):
    """The simulator whose ``send`` of line ``line``'s segment raises ``exc``."""

    def __init__(self, machine, line: int, exc) -> None:
        super().__init__(machine)
        self.line, self.exc = line, exc

    def send(self, segment) -> None:
        if segment.line == self.line:
            raise self.exc(self)
        super().send(segment)


def test_a_lost_link_and_ctrl_c_name_their_cause_and_line():
    machine = fagorcnc.load_machine(None)

    def link_lost(be):   # what the InterpCNC back-end raises: alarm 0, "link lost: ..." on its status
        return BackendError("no response", Status(state="alarm", alarm_message="link lost: no response", line=3))

    report = fagorcnc.run(text=FIVE, machine=machine, backend=Failing(machine, 4, link_lost))
    assert str(report.ending) == "link lost at line 3"
    report = fagorcnc.run(text=FIVE, machine=machine, backend=Failing(machine, 4, lambda be: KeyboardInterrupt()))
    # Ctrl-C while line 4's segment was being sent: the machine had executed line 3
    assert report.stopped_by == "interrupt" and str(report.ending) == "stopped by the user at line 3"
    assert report.moves == 3


def test_the_interpcnc_error_tells_its_alarm_and_link_loss():
    from fagorcnc.backends.interpcnc.backend import InterpCncError
    from fagorcnc.summary import backend_ending

    assert str(backend_ending(InterpCncError("x", Status(alarm=18), alarm=18, line=7), None)) == "alarm 18 at line 7"
    lost = InterpCncError("x", Status(state="alarm", alarm_message="link lost: timeout"), alarm=0, line=9)
    assert str(backend_ending(lost, lost.status)) == "link lost at line 9"


def test_a_syntax_error_means_not_started(tmp_path, capsys):
    f = tmp_path / "syntax.nc"
    f.write_text("G1 X10 F100\nG1 X[1\nM30\n")
    assert str(dry_run(f).ending) == "not started (error at line 2)"
    assert str(fagorcnc.simulate(f).ending) == "not started (error at line 2)"
    assert main(["run", str(f)]) == 1
    assert "ended by not started (error at line 2)" in capsys.readouterr().out


def test_the_move_counter_counts_only_what_was_sent():
    # records a (move), b (aux), c (move), d (move): a segment of c sent -> 2 moves given to the back-end
    class R:
        def __init__(self, kind):
            self.kind = kind

    a, b, c, d = R("linear"), R("aux"), R("arc"), R("rapid")
    seen = []
    counter = MoveCounter([a, b, c, d], seen.append)
    assert list(counter) == [a, b, c, d] and counter.moves == 3
    counter.sent(c)
    assert counter.sent_moves == 2 and seen == [a, c]
    counter.finished()
    assert counter.sent_moves == 3 and seen == [a, c, d]


@pytest.mark.parametrize("program", ["cam_finish.nc", "demo.nc"])
def test_run_summary_line_of_the_command(program, capsys):
    path = PROGRAMS / program
    assert main(["run", str(path)]) == 0
    out = capsys.readouterr().out
    assert f"{fagorcnc.simulate(path).summary.moves} moves, ended by M30" in out
