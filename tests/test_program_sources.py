"""What users hit first with programs (issues 25.7, 30.4, 25.8): files or text, empty files,
``run -v``, ``check DIR``, ``-`` for standard input, ``m:ss`` durations, CLI wording."""

from __future__ import annotations

import io
import json
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

import fagorcnc
from fagorcnc.cli import main
from fagorcnc.commands._shared import cli_message
from fagorcnc.program_files import looks_like_path, program_files, resolve
from fagorcnc.simulate import syntax_errors

PROGRAM = "G90 G1 X10 F1000\nG1 Y10\nM30\n"


# ----------------------------------------------------------------------------- str | os.PathLike, text=
def test_a_missing_file_named_like_a_path_raises_instead_of_being_parsed(tmp_path):
    # used to be parsed as program text: SYN005 'p'
    for entry in (fagorcnc.simulate, fagorcnc.dry_run, fagorcnc.interpret, fagorcnc.run):
        with pytest.raises(FileNotFoundError):
            entry("progs/missing.nc")
        with pytest.raises(FileNotFoundError):
            entry(tmp_path / "missing.nc")


def test_files_as_str_path_or_pathlike_and_text_by_keyword(tmp_path):
    f = tmp_path / "part.nc"
    f.write_text(PROGRAM)

    class Pathish:
        def __fspath__(self) -> str:
            return str(f)

    for source in (f, str(f), Pathish()):
        r = fagorcnc.simulate(source)
        assert r.ok and r.diagnostics == [] and r.summary.moves == 2 and r.program.file == str(f)
    assert fagorcnc.simulate(text=PROGRAM).program.file == "<string>"
    assert fagorcnc.dry_run(text=PROGRAM).moves == 2
    assert sum(r.kind != "aux" for r in fagorcnc.interpret(text=PROGRAM)) == 2
    assert fagorcnc.run(text=PROGRAM).moves == 2
    # text= even when it names a file: it is the text
    assert not fagorcnc.simulate(text=str(f)).ok
    with pytest.raises(TypeError):
        fagorcnc.simulate(f, text=PROGRAM)


def test_a_long_one_line_program_is_text_not_a_file_name():
    # 30.4: 300 characters without a newline were tried as a path: OSError ENAMETOOLONG
    line = "P1=" + "+".join(["1"] * 150)           # 3 + 150 + 149 = 302 characters, P1 = 150
    assert len(line) == 302
    r = fagorcnc.simulate(line)
    assert r.ok and r.state.param(1) == 150
    assert fagorcnc.dry_run(line).ok
    assert syntax_errors(line) == []
    assert fagorcnc.simulate("G1 X" + "1" * 300 + " F100").program.file == "<string>"


def test_what_looks_like_a_path():
    assert looks_like_path("progs/missing.nc") and looks_like_path("PART.NC") and looks_like_path("a/b")
    for text in ("G1 X10", "P1=10/2", "/G1 X10", "M30", "G1 X[10/2]", "X1\nX2/3"):
        assert not looks_like_path(text), text
    assert isinstance(resolve("G1 X10"), str) and not isinstance(resolve("G1 X10"), Path)


# ----------------------------------------------------------------------------- the empty file
def test_an_empty_file_has_the_same_verdict_everywhere(tmp_path, capsys):
    # it passed run, parse and dry_run() but failed check
    for text in ("", "; only a comment\n\n"):
        f = tmp_path / "empty.nc"
        f.write_text(text)
        assert [d.code for d in fagorcnc.simulate(f).diagnostics] == ["STR012"]
        dry = fagorcnc.dry_run(f)
        assert [d.code for d in dry.diagnostics] == ["STR012"] and not dry.executed
        report = fagorcnc.run(f)
        assert not report.ok and [d.code for d in report.diagnostics] == ["STR012"]
        for command in ("run", "parse", "check"):
            assert main([command, str(f)]) == 1, command
            assert "STR012" in capsys.readouterr().out


# ----------------------------------------------------------------------------- the command line
def test_run_verbose_lists_the_moves(tmp_path, capsys):
    f = tmp_path / "part.nc"
    f.write_text(PROGRAM)
    assert main(["run", "-v", str(f)]) == 0
    out = capsys.readouterr().out
    assert "move 1: line 1 linear to X10.0000 Y0.0000 Z0.0000 F1000" in out
    assert "move 2: line 2 linear to X10.0000 Y10.0000 Z0.0000 F1000" in out
    assert "2 moves, ended by M30" in out


def test_check_a_directory_recurses_over_program_files(tmp_path, capsys):
    (tmp_path / "sub" / "deeper").mkdir(parents=True)
    (tmp_path / "a.nc").write_text(PROGRAM)
    (tmp_path / "sub" / "b.NC").write_text(PROGRAM)
    (tmp_path / "sub" / "deeper" / "c.pim").write_text("G1000\nM30\n")
    (tmp_path / "sub" / "notes.txt").write_text("not a program")
    assert [p.name for p in program_files(tmp_path)] == ["a.nc", "b.NC", "c.pim"]
    assert main(["check", "--format", "json", str(tmp_path)]) == 1   # c.pim has an error
    doc = json.loads(capsys.readouterr().out)
    assert [Path(f["file"]).name for f in doc["files"]] == ["a.nc", "b.NC", "c.pim"]
    assert main(["check", "-q", "--extensions", "nc", str(tmp_path)]) == 0   # a.nc and b.NC only
    assert "checked 2 files: 2 passed" not in capsys.readouterr().out   # -q: no total line
    empty = tmp_path / "nothing"
    empty.mkdir()
    assert main(["check", str(empty)]) == 2
    assert "no program files" in capsys.readouterr().err


def test_dash_reads_the_program_from_standard_input(monkeypatch, capsys):
    for command in (["check", "--brief"], ["run"], ["parse"]):
        # line 2: a syntax error (an open bracket), which parse finds too
        monkeypatch.setattr(sys, "stdin", io.TextIOWrapper(io.BytesIO(b"G1 X10 F1000\nG1 X[1\nM30\n")))
        assert main([*command, "-"]) == 1, command
        out = capsys.readouterr().out
        assert "<stdin>:2:" in out and "SYN" in out, (command, out)


def test_durations_accept_minutes_and_seconds(tmp_path, capsys):
    # the program plans 10 mm at 1000 mm/min + 10 mm = 1.2 s and a bit of acceleration: over 0:01, under 1:30
    f = tmp_path / "part.nc"
    f.write_text(PROGRAM)
    assert main(["check", "-q", "--max-cycle-time", "1:30", str(f)]) == 0
    assert main(["check", "-q", "--max-cycle-time", "0:01", str(f)]) == 1
    assert "PLN101" in capsys.readouterr().out
    assert main(["check", "--max-seconds", "2:00", str(f)]) == 0
    capsys.readouterr()
    for bad in ("1:75", "x", "1::2", "1:-5"):
        with pytest.raises(SystemExit):
            main(["check", "--max-cycle-time", bad, str(f)])
        assert "is not a duration" in capsys.readouterr().err
    assert main(["check", "--max-cycle-time", "-5", str(f)]) == 2   # a number, but not a positive one
    assert "--max-cycle-time must be a positive" in capsys.readouterr().err


def test_cli_messages_name_no_library_method():
    message = ("no response from 127.0.0.1:5020; stopped sending. last block started: line 40 (39 segments "
               "complete) (as last read). Call reconnect_and_continue() when the link is back.")
    assert "reconnect_and_continue" not in cli_message(message)
    assert cli_message(message).endswith("(as last read)")
    assert "resume()" not in cli_message("the InterpCNC back-end is stopped (alarm 3): sending; call resume() to "
                                         "acknowledge the alarm first")


def test_the_command_prints_no_log_record_of_the_library(tmp_path):
    # a library warning (pymodbus: "No response received...") must not reach the terminal by default
    script = ("import logging, sys\nfrom fagorcnc.cli import main\n"
              "logging.getLogger('pymodbus.logging').warning('No response received, expected at least 8 bytes')\n"
              "logging.getLogger('fagorcnc.x').warning('library detail')\n"
              "sys.exit(main(['parse', '-q', sys.argv[1]]))\n")
    f = tmp_path / "part.nc"
    f.write_text(PROGRAM)
    env = {**os.environ, "PYTHONPATH": str(Path(__file__).resolve().parents[1])}
    # the records are made before main() configures logging: only the package's NullHandler keeps fagorcnc's
    # quiet; pymodbus' is kept quiet from main() on -- so emit them again after main() set things up
    script = script.replace("sys.exit(main(['parse', '-q', sys.argv[1]]))\n",
                            "status = main(['parse', '-q', sys.argv[1]])\n"
                            "logging.getLogger('pymodbus.logging').warning('No response received')\n"
                            "logging.getLogger('fagorcnc.x').warning('library detail')\n"
                            "sys.exit(status)\n")
    script = script.replace("logging.getLogger('pymodbus.logging').warning('No response received, expected at "
                            "least 8 bytes')\n", "")
    out = subprocess.run([sys.executable, "-c", script, str(f)], capture_output=True, text=True, env=env)
    assert out.returncode == 0 and out.stderr == "", out.stderr


def test_a_lost_link_at_the_command_line_says_what_to_do_there(tmp_path, capsys):
    # issue 25.8: after a link fault the command said "Call reconnect_and_continue() when the link is back"
    from fagorcnc.backends.interpcnc.emulator import Emulator

    f = tmp_path / "part.nc"
    f.write_text("G90 G1 X0 Y0 F3000\n" + "".join(f"G1 X{k % 20} Y{k % 7}\n" for k in range(1, 60)) + "M30\n")
    machine = tmp_path / "m.toml"
    machine.write_text("[backends.interpcnc]\ntimeout = 0.2\n")
    with Emulator(port=0, speed=50.0) as emu:
        emu.drop_connection(after_commands=20)   # the 21st command write closes the connection
        code = main(["run", "--machine", str(machine), "--backend", "interpcnc", "--port", str(emu.port), str(f)])
    captured = capsys.readouterr()
    assert code == 1, captured.out
    text = captured.out + captured.err
    assert "reconnect_and_continue" not in text and "()" not in text
    # where the card stood when the link went (the last block it reported executing) depends on timing
    assert re.search(r"ended by link lost (at line [0-9]+|before the first block ran)", captured.out), captured.out
    assert "run the program again (fagorcnc run)" in captured.out
