"""Runaway and resource guards (README "Runaway guards", the machine's ``[limits]``).

Every runaway program ends promptly with a diagnostic, with the default limits where
they can do it at once: an ``NR`` or ``#RPT`` count above ``max_loop_iterations`` is
refused up front (INT081), interpretation time is bounded by ``max_seconds`` (INT082),
and the warnings a loop can pile up by ``max_messages`` (INT083).  The manual gives no
upper bound for NR (seed 002 L1109-L1111) or #RPT (L16223-L16237); these are fagorcnc's.
No test asserts on timing beyond "stopped with the code".
"""

from __future__ import annotations

import itertools
from collections import Counter

import pytest

import fagorcnc
from fagorcnc.cli import main
from fagorcnc.commands.check import check_file
from fagorcnc.interp import interpreter

WHILE_FOREVER = "P1=0\n$WHILE 1==1\nP1=P1+1\n$ENDWHILE\nM30\n"
GOTO_FOREVER = "N10: G91 G1 X0.001 F1000\nG1 X-0.001\n$GOTO N10\nM30\n"


def errors(result) -> list[tuple[int, int, str]]:
    return [(d.line, d.col, d.code) for d in result.diagnostics if d.is_error]


def moves(result) -> int:
    return sum(m.kind == "linear" for m in result.moves)


# ----------------------------------------------------------------------------- NR and #RPT counts
def test_nr_of_a_billion_is_refused_at_once_with_the_defaults():
    r = fagorcnc.simulate("G91 G1 X0.001 F1000 NR1000000000\nM30\n")
    assert errors(r) == [(1, 21, "INT081")]   # at the NR word
    assert moves(r) == 0
    (d,) = r.errors
    assert d.message == ("NR1000000000 repeats the block more than limits.max_loop_iterations = 1000000 times: "
                         "runaway program stopped")


def test_rpt_of_a_billion_is_refused_at_once_with_the_defaults():
    r = fagorcnc.simulate("N10: G91 G1 X0.001 F1000\nN20: G1 X-0.001\n  #RPT [N10, N20, 1000000000]\nM30\n")
    assert errors(r) == [(3, 3, "INT081")]    # at the #RPT
    assert moves(r) == 2                      # the range ran once before the #RPT, as written
    assert "limits.max_loop_iterations = 1000000" in r.errors[0].message


@pytest.mark.parametrize("count", [5, 6])
def test_nr_up_to_the_iteration_limit_runs(count):
    r = fagorcnc.simulate(f"G91 G1 X1 F1000 NR{count}\nM30\n", {"limits": {"max_loop_iterations": 5}})
    assert (errors(r), moves(r)) == (([], 5) if count == 5 else ([(1, 17, "INT081")], 0))


@pytest.mark.parametrize("count", [5, 6])
def test_rpt_up_to_the_iteration_limit_runs(count):
    r = fagorcnc.simulate(f"#RPT [N10, N20, {count}]\nM30\nN10: G91 G1 X1 F1000\nN20:\n",
                          {"limits": {"max_loop_iterations": 5}})
    assert (errors(r), moves(r)) == (([], 5) if count == 5 else ([(1, 1, "INT081")], 0))


# ----------------------------------------------------------------------------- time
def test_endless_while_stops_at_the_time_limit():
    r = fagorcnc.simulate(WHILE_FOREVER, {"limits": {"max_seconds": 0.05}})
    assert [c for _, _, c in errors(r)] == ["INT082"]
    assert "limits.max_seconds" in r.errors[0].message


def test_endless_streamed_program_stops_at_the_time_limit():
    lines = (f"G90 G1 X{k % 100} F3000" for k in itertools.count())
    run = fagorcnc.Run(lines, "<endless>", fagorcnc.load_machine({"limits": {"max_seconds": 0.05}}))
    assert sum(1 for _ in run) > 0
    assert [d.code for d in run.diagnostics if d.is_error] == ["INT082"]


def test_the_time_the_consumer_holds_the_records_does_not_count(monkeypatch):
    # a fake clock that only the consumer advances: 10 s per record would be 30 000 s of
    # CPU time, yet the interpretation itself took no time at all
    now = [0.0]
    monkeypatch.setattr(interpreter, "cpu_time", lambda: now[0])
    run = fagorcnc.interpret("G90 G1 X1 F1000\nG1 X0\n" * 1500 + "M30\n", {"limits": {"max_seconds": 1}})
    for _ in run:
        now[0] += 10.0
    assert run.ok, [str(d) for d in run.diagnostics]


def test_a_dry_runs_planner_time_does_not_count(monkeypatch):
    # dry_run (fagorcnc check) hands the records to the planner in runs and stops the clock while the
    # planner has them: a fake clock advanced 10 s per planned segment (30 000 s) never reaches the
    # 1 s limit, and the clock is read twice per run of 1024 records, not twice per record
    now = [0.0]
    reads = [0]

    def clock():
        reads[0] += 1
        return now[0]

    def planner_busy(_segment):
        now[0] += 10.0

    monkeypatch.setattr(interpreter, "cpu_time", clock)
    r = fagorcnc.dry_run(text="G90 G1 X1 F1000\nG1 X0\n" * 1500 + "M30\n",
                         machine={"limits": {"max_seconds": 1}}, on_segment=planner_busy)
    assert r.ok and not r.diagnostics, [str(d) for d in r.diagnostics]
    assert r.moves == 3000
    assert reads[0] <= 12   # start, 2 per run of 1024 (3 runs), the limit's checks every 1024 blocks


def test_a_dry_runs_interpretation_time_still_counts(monkeypatch):
    # what runs as the records are made (here a watcher of them, 10 s each) is interpretation time:
    # the limit stops the run at the first check (block 1024) with INT082
    now = [0.0]

    def watcher(_record, _interp):
        now[0] += 10.0

    monkeypatch.setattr(interpreter, "cpu_time", lambda: now[0])
    r = fagorcnc.dry_run(text="G90 G1 X1 F1000\nG1 X0\n" * 1500 + "M30\n",
                         machine={"limits": {"max_seconds": 1}}, on_record=watcher)
    assert [d.code for d in r.diagnostics if d.is_error] == ["INT082"]


def test_the_time_limit_counts_cpu_time_not_a_busy_machines_wall_clock(monkeypatch):
    # issue 25.1: a loaded CI runner leaves the interpreter off the CPU; simulated by a 0.4 s sleep
    # (wall-clock time, no CPU time) at block 1000 of 1500.  The limit (0.25 s) is checked every
    # 1024 blocks: on a wall clock the check at block 1024 sees 0.4 s > 0.25 s and stops a legitimate
    # program (INT082); in CPU time 1024 short blocks take a few hundredths of a second.
    import time

    count_block = interpreter.Interpreter.count_block

    def descheduled(self, col):
        count_block(self, col)
        if self.state.executed_blocks == 1000:
            time.sleep(0.4)

    monkeypatch.setattr(interpreter.Interpreter, "count_block", descheduled)
    r = fagorcnc.simulate("G90 G1 X1 F1000\nG1 X0\n" * 750 + "M30\n", {"limits": {"max_seconds": 0.25}})
    assert r.ok, [str(d) for d in r.diagnostics]
    assert moves(r) == 1500


# ----------------------------------------------------------------------------- memory
def test_warnings_of_an_endless_loop_are_bounded():
    r = fagorcnc.simulate('N10: #MSG ["pass"]\n$GOTO N10\nM30\n', {"limits": {"max_messages": 10, "max_blocks": 100}})
    assert Counter(d.code for d in r.diagnostics) == {"INT077": 10, "INT083": 1, "INT080": 1}


# ----------------------------------------------------------------------------- the other guards still hold
@pytest.mark.parametrize(("text", "limits", "code"), [
    ("N10: P1=1\n$GOTO N10\nM30\n", {"max_blocks": 500}, "INT080"),
    (WHILE_FOREVER, {"max_loop_iterations": 1000}, "INT081"),
    ("L REC.nc\nM30\n", {}, "INT095"),
])
def test_block_loop_and_nesting_guards_with_the_time_limit_on(tmp_path, text, limits, code):
    (tmp_path / "REC.nc").write_text("L REC.nc\nM17\n")
    machine = {"subroutine_paths": [str(tmp_path)], "limits": {**limits, "max_seconds": 60}}
    assert [c for _, _, c in errors(fagorcnc.simulate(text, machine))] == [code]


# ----------------------------------------------------------------------------- configuration and command line
@pytest.mark.parametrize(("body", "key"), [
    ("max_seconds = 'x'", "limits.max_seconds"),
    ("max_seconds = -1", "limits.max_seconds"),
    ("max_blocks = 0", "limits.max_blocks"),
    ("max_messages = 2.5", "limits.max_messages"),
    ("max_secs = 5", "max_secs"),
])
def test_bad_limits_name_the_key(tmp_path, body, key):
    f = tmp_path / "mill.toml"
    f.write_text(f"[limits]\n{body}\n")
    with pytest.raises(fagorcnc.config.machine.MachineError) as err:
        fagorcnc.load_machine(f)
    assert str(err.value).startswith(f"{f}: ") and key in str(err.value)


def test_limits_from_toml(tmp_path):
    f = tmp_path / "mill.toml"
    f.write_text("[limits]\nmax_seconds = 2.5\nmax_messages = 0\nmax_blocks = 1e6\n")
    limits = fagorcnc.load_machine(f).limits
    assert (limits.max_seconds, limits.max_messages, limits.max_blocks) == (2.5, 0, 1_000_000)


def test_check_stops_a_runaway_at_its_time_limit_without_running_it_again(tmp_path, capsys):
    f = tmp_path / "loop.nc"
    f.write_text(GOTO_FOREVER)
    report = check_file(f, max_seconds=0.05)
    assert [d.code for d in report.diagnostics] == ["INT082"]   # no recovery re-runs after it
    assert main(["check", "--max-seconds", "0.05", "--brief", str(f)]) == 1
    assert "INT082" in capsys.readouterr().out


def test_check_takes_the_machines_time_limit(tmp_path):
    f = tmp_path / "loop.nc"
    f.write_text(GOTO_FOREVER)
    report = check_file(f, {"limits": {"max_seconds": 0.05}})
    assert [d.code for d in report.diagnostics] == ["INT082"]


def test_run_stops_a_runaway_at_its_time_limit(tmp_path, capsys):
    f = tmp_path / "loop.nc"
    f.write_text(WHILE_FOREVER)
    assert main(["run", "--max-seconds", "0.05", str(f)]) == 1
    assert "INT082" in capsys.readouterr().out


@pytest.mark.parametrize("command", ["run", "check"])
def test_a_negative_max_seconds_is_a_usage_error(tmp_path, capsys, command):
    f = tmp_path / "p.nc"
    f.write_text("G1 X1 F100\nM30\n")
    assert main([command, "--max-seconds", "-1", str(f)]) == 2
    assert "--max-seconds" in capsys.readouterr().err


def test_handed_in_runs_stop_the_clock_while_the_consumer_holds_a_run(monkeypatch):
    # each run of records is taken with the clock running, then the clock is stopped until the consumer asks for
    # the record after the run's last: the consumer's 10 s a record move the deadline on once a run, after it
    from types import SimpleNamespace
    now = [0.0]
    monkeypatch.setattr(interpreter, "cpu_time", lambda: now[0])
    interp = SimpleNamespace(clock=interpreter._Clock(100.0), consumer_excluded=False)
    interp.clock.start()
    seen = []
    for rec in interpreter.handed_in_runs(interp, iter(range(5)), 2):
        assert interp.consumer_excluded
        seen.append((rec, interp.clock.deadline))
        now[0] += 10.0
    assert seen == [(0, 100.0), (1, 100.0), (2, 120.0), (3, 120.0), (4, 140.0)]
    assert interp.clock.deadline == 150.0
