"""fagorcnc expand: the canonical dump of the executed records, its golden-file workflow."""

from __future__ import annotations

import itertools
import json
import shutil
from pathlib import Path

import pytest

from fagorcnc.cli import main
from fagorcnc.commands.expand import Expansion, check_golden, expand, expand_text, fixed
from fagorcnc.config.machine import load_machine
from fagorcnc.plan.planner import READ_AHEAD

GOLDEN = Path(__file__).parent / "golden" / "expand"
PROGRAM = GOLDEN / "square.nc"
MACHINE = GOLDEN / "machine.toml"


def test_fixed_decimals_are_stable():
    assert fixed(1.23456) == "1.2346"
    assert fixed(-0.00001) == "0.0000"   # -0 is written 0: a stored expansion does not flicker
    assert fixed(-2.5) == "-2.5000"
    assert fixed(None) == "null"


@pytest.mark.parametrize("fmt", ["jsonl", "text"])
def test_expansion_matches_the_golden_file(fmt):
    outcome = check_golden(PROGRAM, GOLDEN, MACHINE, fmt=fmt)
    assert outcome.status == "match", (outcome.line, outcome.expected, outcome.actual)


def _rows(text: str) -> list[dict]:
    return [json.loads(line) for line in text.splitlines()]


def test_positions_in_both_frames_worked_by_hand():
    part = _rows(expand_text(PROGRAM, MACHINE))
    machine = _rows(expand_text(PROGRAM, MACHINE, frame="machine"))
    assert part[0]["schema"] == "fagorcnc-expand/1" and part[0]["frame"] == "part"
    first_move = next(r for r in part if r.get("kind") == "rapid")
    # G00 X0 Y0 Z10 in G54 (X100 Y50 Z-200) with T1 D1 (length 100): machine X 0+100 = 100,
    # Y 0+50 = 50, Z 10-200+100 = -90; the offset is machine minus part: X100 Y50 Z-100
    assert first_move["end"] == {"X": 0.0, "Y": 0.0, "Z": 10.0}
    assert first_move["offset"] == {"X": 100.0, "Y": 50.0, "Z": -100.0}
    m = next(r for r in machine if r.get("kind") == "rapid")
    assert m["end"] == {"X": 100.0, "Y": 50.0, "Z": -90.0}
    arcs = [r for r in part if r.get("kind") == "arc"]
    # G02 X30 Y10 R10 from X20 Y0: the short clockwise arc has its centre at X30 Y0;
    # G03 X20 Y20 I-10 J0 from X30 Y10: centre X30-10 = 20, Y10+0 = 10
    assert arcs[0]["center"] == {"X": 30.0, "Y": 0.0} and arcs[0]["dir"] == "cw" and arcs[0]["radius"] == 10.0
    assert arcs[1]["center"] == {"X": 20.0, "Y": 10.0} and arcs[1]["dir"] == "ccw"
    assert "G02 G17" in arcs[0]["modes"] and "G03 G17" in arcs[1]["modes"]
    g91 = next(r for r in part if r.get("src") == "square.nc:11")
    assert g91["end"] == {"X": 0.0, "Y": 20.0, "Z": -1.0}   # G91 X-20 from X20
    end = part[-1]
    assert end == {"kind": "end", "moves": 7, "ended_by": "M30", "cycle_time": end["cycle_time"], "ok": True}


def test_tool_spindle_and_times_come_from_the_record_stream():
    rows = _rows(expand_text(PROGRAM, MACHINE))[1:-1]
    t1, m6, d1 = rows[0], rows[1], rows[2]
    # seed 002 L4700: T selects, M06 loads: the T1 row still has T0 in the spindle
    assert (t1["fn"], t1["T"]) == ("T", 0)
    assert (m6["fn"], m6["value"], m6["T"]) == ("M", 6.0, 1)
    assert d1["D"] == 1
    assert t1["start"] == {} and t1["offset"] == {}   # no part position before the first move
    moves = [r for r in rows if r["kind"] in ("rapid", "linear", "arc", "dwell")]
    assert all(r["S"] == 2000.0 and r["M"] == 3 for r in moves[:-1])
    for before, after in itertools.pairwise(moves):   # the planned times follow each other
        assert after["t0"] == pytest.approx(before["t0"] + before["duration"], abs=2e-4)
    dwell = next(r for r in rows if r["kind"] == "dwell")
    assert dwell["seconds"] == 0.5 and dwell["duration"] == 0.5


def test_golden_mode_prints_the_first_difference(tmp_path, capsys):
    shutil.copy(PROGRAM, tmp_path / "square.nc")
    assert main(["expand", str(tmp_path / "square.nc"), "--machine", str(MACHINE), "--golden",
                 str(tmp_path / "g")]) == 0
    stored = tmp_path / "g" / "square.nc.jsonl"
    assert stored.is_file() and "written" in capsys.readouterr().out
    text = (tmp_path / "square.nc").read_text().replace("G01 X20 F600", "G01 X20.02 F600")
    (tmp_path / "square.nc").write_text(text)
    assert main(["expand", str(tmp_path / "square.nc"), "--machine", str(MACHINE), "--golden",
                 str(tmp_path / "g")]) == 1
    out = capsys.readouterr().out
    assert "CLI002" in out and "at line 9:" in out   # header, 5 aux rows, 2 moves, then the changed line
    golden_line, now_line = out.splitlines()[1], out.splitlines()[2]
    assert '"X":20.0000' in golden_line and '"X":20.0200' in now_line


def test_csv_and_output_file(tmp_path):
    out = tmp_path / "x.csv"
    assert main(["expand", str(PROGRAM), "--machine", str(MACHINE), "--format", "csv", "-o", str(out)]) == 0
    lines = out.read_text().splitlines()
    assert lines[0].startswith("n,kind,src,start_X,start_Y,start_Z,end_X,end_Y,end_Z,center_1")
    assert lines[6].split(",")[:3] == ["6", "rapid", "square.nc:6"]


def test_an_error_is_in_the_expansion_and_the_status(tmp_path):
    bad = tmp_path / "bad.nc"
    bad.write_text("G0 X0\nG1 X10 F100\nG1 X2000\nM30\n")
    lines: list[str] = []
    result = expand(bad, lines.append)
    assert not result.ok
    assert any('"kind":"diagnostic","code":"INT100"' in line for line in lines)
    assert main(["expand", str(bad), "-o", str(tmp_path / "o.jsonl")]) == 1


def test_rows_are_written_as_they_are_timed(tmp_path):
    """Constant memory: the rows waiting for their time never pile up with the program's length."""
    prog = tmp_path / "long.nc"
    prog.write_text("G1 F1000\n" + "".join(f"X{i % 7} Y{i % 5}\n" for i in range(3000)) + "M30\n")
    expansion = Expansion(prog, load_machine({"planner": {"lookahead": 100}}))
    held = []

    def emit(row) -> None:
        held.append(len(expansion._pending))

    expansion.run(emit)
    assert len(held) == 3001   # 3000 moves and M30
    # the planner's read-ahead and look-ahead (100 spans), not the program's 3000 moves
    assert max(held) <= READ_AHEAD + 100 + 64
