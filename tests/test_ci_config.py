"""fagorcnc check in CI: [tool.fagorcnc], --select/--ignore, suppression comments, JUnit, --statistics."""

from __future__ import annotations

from xml.etree import ElementTree

import pytest

from fagorcnc.cli import main
from fagorcnc.commands.ci import ConfigError, Selection, load_config, suppressions

NO_END = "G0 X0 Y0 Z0\nG1 X10 F100\n"            # INT098 (warning): no M02/M30
BEYOND = "G0 X0 Y0 Z0\nG1 X2000 F100\nM30\n"     # INT100 (error) on line 2


def test_the_longest_prefix_decides():
    assert Selection().keeps("INT098")
    assert not Selection(ignore=["INT09"]).keeps("INT098")
    assert Selection(ignore=["INT09"]).keeps("INT100")
    assert not Selection(select=["PLN"]).keeps("INT098")
    assert Selection(select=["INT098"], ignore=["INT"]).keeps("INT098")   # 6 characters beat 3
    assert not Selection(select=["INT"], ignore=["INT"]).keeps("INT098")  # a tie: ignored


def test_config_is_read_and_checked(tmp_path):
    path = tmp_path / "pyproject.toml"
    path.write_text('[tool.fagorcnc]\nfail_on = "warning"\nignore = ["INT098"]\nmax-cycle-time = 60\n')
    config = load_config(path)
    assert config.get("fail-on") == "warning" and config.get("ignore") == ["INT098"]
    assert config.get("max-cycle-time") == 60.0
    for bad in ('colour = "red"', 'select = "INT"', 'ignore = ["XYZ1"]', 'fail-on = "info"', "max-cycle-time = -1"):
        path.write_text(f"[tool.fagorcnc]\n{bad}\n")
        with pytest.raises(ConfigError):
            load_config(path)


def test_suppression_comments_are_found(tmp_path):
    p = tmp_path / "p.nc"
    p.write_text("G0 X0\nG1 X10 F100 ; fagorcnc: ignore[INT098, int100]\n(fagorcnc: ignore[INT098])\n")
    assert suppressions(p) == {2: ["INT098", "INT100"]}   # only in a ';' comment


def test_pyproject_paths_ignore_and_fail_on(tmp_path, monkeypatch, capsys):
    (tmp_path / "nc").mkdir()
    (tmp_path / "nc" / "a.nc").write_text(NO_END)
    (tmp_path / "pyproject.toml").write_text('[tool.fagorcnc]\nfail-on = "warning"\npaths = ["nc"]\n')
    monkeypatch.chdir(tmp_path)
    assert main(["check", "-q"]) == 1             # INT098 fails with fail-on = warning
    assert "INT098" in capsys.readouterr().out
    assert main(["check", "-q", "--ignore", "INT098"]) == 0
    assert main(["check", "-q", "--fail-on", "error"]) == 0   # the command line wins
    assert main(["check", "-q", "--no-config", "nc/a.nc"]) == 0
    (tmp_path / "pyproject.toml").write_text('[tool.fagorcnc]\npaths = ["missing/*.nc"]\n')
    assert main(["check"]) == 2
    assert "CLI011" in capsys.readouterr().err


def test_a_comment_silences_a_warning_not_an_error(tmp_path, capsys):
    p = tmp_path / "p.nc"
    p.write_text("G0 X0 Y0 Z0\nG1 X10 F100 ; fagorcnc: ignore[INT098, NOPE1]\n")
    assert main(["check", "--no-config", "--fail-on", "warning", "--brief", str(p)]) == 1
    out = capsys.readouterr().out
    assert "INT098" not in out and "CLI010" in out   # the unknown code is reported (a warning)
    p.write_text("G0 X0 Y0 Z0\nG1 X2000 F100 ; fagorcnc: ignore[INT100]\nM30\n")
    assert main(["check", "--no-config", "--brief", str(p)]) == 1
    out = capsys.readouterr().out
    assert "INT100" in out and "CLI012" in out       # an error stays: the control stops there


def test_junit_and_statistics(tmp_path, capsys):
    a, b = tmp_path / "a.nc", tmp_path / "b.nc"
    a.write_text(NO_END)
    b.write_text(BEYOND)
    assert main(["check", "--no-config", "--format", "junit", "-j", "1", str(a), str(b)]) == 1
    root = ElementTree.fromstring(capsys.readouterr().out)
    suites = root.findall("testsuite")
    assert [s.get("name") for s in suites] == [str(a), str(b)]
    assert suites[0].get("failures") == "0" and suites[1].get("failures") == "1"   # the warning passes
    failure = suites[1].find("testcase/failure")
    assert failure.get("type") == "error" and "INT100" in failure.get("message")
    assert root.get("tests") == "2" and root.get("failures") == "1"
    assert main(["check", "--no-config", "--statistics", "-j", "1", str(a), str(b), str(a)]) == 1
    rows = [line.split() for line in capsys.readouterr().out.splitlines() if line.strip()]
    assert rows[0][:3] == ["2", "INT098", "warning"] and rows[1][:3] == ["1", "INT100", "error"]


def test_pyproject_compat_lays_over_the_machines_policy(tmp_path, monkeypatch, capsys):
    # issue 28: [tool.fagorcnc] compat sets the [compat] policy of the check (the README "CAM posts"):
    # G51 A45 E0.002 is a warning by default (CAM001), an error with compat = { g51 = "error" } or "strict"
    prog = tmp_path / "p.nc"
    prog.write_text("G51 A45 E0.002\nG1 X10 F100\nM30\n")
    monkeypatch.chdir(tmp_path)
    assert main(["check", "--no-config", str(prog)]) == 0
    for table in ('compat = { g51 = "error" }', 'compat = "strict"'):
        (tmp_path / "pyproject.toml").write_text(f"[tool.fagorcnc]\n{table}\n")
        capsys.readouterr()
        assert main(["check", str(prog)]) == 1, table
        assert "CAM001" in capsys.readouterr().out
    (tmp_path / "pyproject.toml").write_text('[tool.fagorcnc]\ncompat = { g51 = "maybe" }\n')
    assert main(["check", str(prog)]) == 2
    assert "CLI011" in capsys.readouterr().err


def test_pyproject_max_cycle_time_in_minutes(tmp_path):
    path = tmp_path / "pyproject.toml"
    path.write_text('[tool.fagorcnc]\nmax-cycle-time = "1:30"\n')
    assert load_config(path).get("max-cycle-time") == 90.0   # 1 min 30 s
