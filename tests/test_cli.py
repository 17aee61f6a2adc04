"""The `fagorcnc parse` / `lint` command and the diagnostic format."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from fagorcnc.cli import main
from fagorcnc.diagnostics import CODES, Diagnostic
from fagorcnc.syntax import parse_text

DEMO = Path(__file__).resolve().parents[1] / "programs" / "demo.nc"


def test_diagnostic_format_file_line_col_code_and_caret():
    (d,) = parse_text("G1 X10\nN20 XP1*2\n", "part.nc").diagnostics
    assert str(d) == ("part.nc:2:8: SYN006 unexpected '*2': an ISO word value with an operator must be written "
                      "in brackets, e.g. X[P1*2]")
    assert d.render().splitlines()[1:] == ["    N20 XP1*2", "           ^"]


def test_every_emitted_code_is_documented():
    assert all(code[:3] in ("SYN", "STR", "INT", "CFG", "PLN", "BCK") and len(code) == 6 for code in CODES)
    import re
    from pathlib import Path

    emitted = set()
    for path in (Path(__file__).resolve().parents[1] / "fagorcnc").rglob("*.py"):
        emitted |= set(re.findall(r'"((?:SYN|STR|INT|CFG|PLN|BCK)[0-9]{3})"', path.read_text()))
    assert emitted <= set(CODES), sorted(emitted - set(CODES))
    d = Diagnostic("f", 1, 1, "SYN001", "warning", "m")
    assert str(d) == "f:1:1: SYN001 warning: m"


def test_parse_clean_file_exit_0(capsys):
    assert main(["parse", str(DEMO)]) == 0
    out = capsys.readouterr().out
    assert "0 errors" in out and "%DEMO" in out


def test_lint_reports_every_error_and_exits_1(tmp_path, capsys):
    bad = tmp_path / "bad.nc"
    bad.write_text("G1 X[1\nG1 X1\n#FOO ON\nM30\n")
    assert main(["lint", "--brief", "-q", str(bad)]) == 1
    out = capsys.readouterr().out.splitlines()
    assert out == [f"{bad}:1:7: SYN003 the block ends before the instruction is complete",
                   f"{bad}:3:1: SYN012 unknown sentence #FOO"]


def test_missing_file_is_a_usage_error(tmp_path, capsys):
    assert main(["parse", str(tmp_path / "nope.nc")]) == 2
    assert "cannot read" in capsys.readouterr().err


def test_no_command_prints_help(capsys):
    assert main([]) == 2


def test_latin1_file_is_read(tmp_path):
    f = tmp_path / "old.nc"
    f.write_bytes("; usinage de la pièce\nG1 X1\n".encode("latin-1"))
    assert main(["parse", "-q", str(f)]) == 0


def test_console_script_runs_as_a_module():
    r = subprocess.run([sys.executable, "-m", "fagorcnc.cli", "parse", "-q", str(DEMO)],
                       capture_output=True, text=True, check=False)
    assert r.returncode == 0 and r.stdout == "" and "Traceback" not in r.stderr


def test_run_demo_on_the_embedded_simulator(capsys):
    assert main(["run", str(DEMO)]) == 0
    out = capsys.readouterr().out
    assert "OK on the embedded simulator" in out and "ended by M30" in out and "0 errors" in out


def test_run_reports_an_interpreter_error_and_exits_1(tmp_path, capsys):
    f = tmp_path / "bad.nc"
    f.write_text("G1 X10 F100\nP1 = 1/0\nG1 X20\nM30\n")
    assert main(["run", str(f)]) == 1
    out = capsys.readouterr().out
    assert f"{f}:2:" in out and "INT033" in out and "STOPPED" in out and "1 moves" in out


def test_run_does_not_start_a_program_with_a_structure_error_anywhere(tmp_path, capsys):
    # the $WHILE is never closed, after M30: the streamed run used to execute up to M30 and say OK,
    # while check, parse and simulate() report STR006 (as the CNC, which does not start it)
    f = tmp_path / "open_while.nc"
    f.write_text("P1=0\n$WHILE P1<2\nP1=P1+1\nG1 X[P1*10] F1000\nM30\n")
    assert main(["run", str(f)]) == 1
    out = capsys.readouterr().out
    assert f"{f}:2:1: STR006" in out and "nothing was run" in out and "0 moves" in out
    assert "final position" not in out and "position (machine)" not in out   # nothing moved: no position


def test_run_stopped_by_an_error_shows_where_the_machine_stands_not_where_the_program_went(tmp_path, capsys):
    # G1 X10 has no feed (INT060): the tool stays at the G0's end, X0 Z5 in machine coordinates
    f = tmp_path / "no_feed.nc"
    f.write_text("G0 X0 Y0 Z5\nG1 X10\nG1 Z-2\nM30\n")
    assert main(["run", str(f)]) == 1
    out = capsys.readouterr().out
    assert "INT060" in out and "position (machine) X0.0000 Y0.0000 Z5.0000," in out, out


def test_run_with_a_bad_machine_file_is_a_usage_error(tmp_path, capsys):
    m = tmp_path / "m.toml"
    m.write_text("[axes.X]\ntype = 'spiral'\n")
    assert main(["run", "--machine", str(m), str(DEMO)]) == 2
    assert "axes.X.type" in capsys.readouterr().err


def test_run_and_plot_say_a_directory_is_a_directory(tmp_path, capsys):
    for command in (["run"], ["plot", "-o", str(tmp_path / "x.png")]):
        assert main([*command, str(tmp_path)]) == 2
        assert f"{tmp_path}: cannot read the file: it is a directory" in capsys.readouterr().err
    assert main(["run", str(tmp_path / "nope.nc")]) == 2
    assert "cannot read the file: no such file" in capsys.readouterr().err
