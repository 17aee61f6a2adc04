"""Global and common parameters kept between runs in a parameter file (LinuxCNC `.var` format)."""

from __future__ import annotations

import fagorcnc
from fagorcnc.commands.check import check_file
from fagorcnc.config.parameter_file import read_parameter_file, write_parameter_file

COUNTER = (
    "$IF EXIST[P100] == 0\n"
    "P100 = 0\n"
    "$ENDIF\n"
    "P100 = P100 + 1\n"        # global: counts the runs
    "P10001 = P100 * 2.5\n"    # common
    "P1 = 99\n"                # local: never kept
    "M30\n"
)


def _machine(tmp_path):
    return {"parameter_file": str(tmp_path / "params.var")}


def test_round_trip_over_two_runs(tmp_path):
    prog = tmp_path / "count.nc"
    prog.write_text(COUNTER)
    var = tmp_path / "params.var"
    assert fagorcnc.run(prog, _machine(tmp_path)).ok
    assert var.read_text() == "100\t1.0\n10001\t2.5\n"
    assert fagorcnc.run(prog, _machine(tmp_path)).ok
    assert read_parameter_file(var) == {100: 2.0, 10001: 5.0}


def test_a_dry_run_reads_the_file_but_never_writes_it(tmp_path):
    var = tmp_path / "params.var"
    write_parameter_file(var, {100: 41.0, 10500: 0.125})
    before = var.read_text()
    r = fagorcnc.simulate("P100 = P100 + 1\nP101 = P10500\nM30\n", _machine(tmp_path))
    assert r.ok and r.state.param(100) == 42.0 and r.state.param(101) == 0.125
    assert var.read_text() == before
    prog = tmp_path / "p.nc"
    prog.write_text("P100 = P100 + 1\nM30\n")
    assert check_file(prog, _machine(tmp_path)).verdict() == "pass"
    assert var.read_text() == before


def test_entries_outside_the_ranges_are_kept(tmp_path):
    var = tmp_path / "params.var"
    var.write_text("; written by hand\n5161\t1.5\n100\t3\n\n")
    prog = tmp_path / "p.nc"
    prog.write_text("P100 = P100 * 2\nM30\n")
    assert fagorcnc.run(prog, _machine(tmp_path)).ok
    assert read_parameter_file(var) == {100: 6.0, 5161: 1.5}


def test_a_malformed_file_is_an_error_and_is_left_alone(tmp_path):
    var = tmp_path / "params.var"
    var.write_text("100 1.0\n101 one\n")
    prog = tmp_path / "p.nc"
    prog.write_text("P100 = 1\nM30\n")
    r = fagorcnc.simulate(prog, _machine(tmp_path))
    (d,) = r.errors
    assert (d.code, d.file, d.line) == ("CFG002", str(var), 2) and "'101 one'" in d.message
    report = fagorcnc.run(prog, _machine(tmp_path))
    assert not report.ok and report.diagnostics[0].code == "CFG002"
    assert var.read_text() == "100 1.0\n101 one\n"


def test_parameter_file_in_a_toml_is_relative_to_it(tmp_path):
    (tmp_path / "cfg").mkdir()
    toml = tmp_path / "cfg" / "machine.toml"
    toml.write_text('parameter_file = "state/params.var"\n')
    prog = tmp_path / "p.nc"
    prog.write_text("P10000 = 7\nM30\n")
    assert fagorcnc.run(prog, str(toml)).ok
    assert read_parameter_file(tmp_path / "cfg" / "state" / "params.var") == {10000: 7.0}
