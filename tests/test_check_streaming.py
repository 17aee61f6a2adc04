"""``fagorcnc check`` and a real machine's check-first pass stream: one interpretation and one
planning pass, in memory that does not grow with the program (CAM programs run to millions of
blocks), with the same verdicts, diagnostics, cycle time and summaries as :func:`fagorcnc.simulate`."""

from __future__ import annotations

import math
import subprocess
import sys
from pathlib import Path

import pytest

import fagorcnc
from fagorcnc.commands.check import check_file
from fagorcnc.interp.interpreter import Interpreter
from fagorcnc.plan import Planner
from fagorcnc.simulate import dry_run

PROGRAMS = sorted((Path(__file__).resolve().parents[1] / "programs").glob("*.nc"))


def _finishing(n: int, corners: str = "#HSC ON [CONTERROR 0.01]") -> str:
    """A CAM finishing program of about ``n`` blocks (under HSC by default): tool change, origin,
    rows of short lines with an arc at each row's end (arcs and corner curves go through the
    envelope check)."""
    out = ["%FINISH", "T1 M6", "D1", "G54", "G0 X0 Y0 Z5", corners, "G1 Z0 F3000"]
    row = 0
    while len(out) < n:
        y = 2.0 * row
        xs = [i * 0.5 for i in range(61)]
        for x in xs[::-1] if row % 2 else xs:
            out.append(f"X{x:.3f} Y{y:.3f} Z{0.3 * math.sin(x / 5):.4f}")
        side = 0.0 if row % 2 else 30.0
        out.append(f"G{'3' if row % 2 == 0 else '2'} X{side:.3f} Y{y + 2:.3f} I0 J1")
        out.append("G1")
        row += 1
    out += ["G0 Z50", "M30"]
    return "\n".join(out) + "\n"


@pytest.fixture(scope="module")
def programs(tmp_path_factory) -> dict[int, Path]:
    folder = tmp_path_factory.mktemp("finishing")
    out = {}
    for n in (1500, 5000, 20000):
        out[n] = folder / f"finish{n}.nc"
        out[n].write_text(_finishing(n) if n == 1500 else _finishing(n, "G05"))
    return out


#: Peak resident memory (KiB) of a fresh process that checks (or runs after checking) a program,
#: on a machine whose look-ahead window is small: the planner keeps a window of at most that many
#: motions and the program reader releases what no jump can reach in chunks of some 4000 blocks,
#: so both reach their constant size well within 5 000 blocks.
_PEAK = """
import contextlib, io, resource, sys
from fagorcnc.commands.check import check_file
from fagorcnc.cli import main
from fagorcnc.commands.run import run
machine = {"planner": {"lookahead": 50}}
if sys.argv[1] == "check":
    assert check_file(sys.argv[2], machine).verdict() == "pass"
elif sys.argv[1] == "run":
    assert run(sys.argv[2], machine, backend="sim", check_first=True, keep_segments=False).ok
else:   # the command, as a user runs it on the simulator
    with contextlib.redirect_stdout(io.StringIO()):
        assert main(["run", sys.argv[2], "--machine", sys.argv[3]]) == 0
print(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss)
"""


def _peak_kib(what: str, path: Path) -> int:
    machine = path.parent / "small_window.toml"
    machine.write_text("[planner]\nlookahead = 50\n")
    out = subprocess.run([sys.executable, "-c", _PEAK, what, str(path), str(machine)], capture_output=True,
                         text=True, check=True)
    return int(out.stdout.split()[-1])


@pytest.mark.parametrize("what", ["check", "run", "command"])
def test_check_memory_does_not_grow_with_program_size(programs, what):
    """The check (and a real machine's run, which checks the whole program first) once kept the
    program and its moves, about 1.7 KB a block: 20 000 blocks held some 25 MB more than 5 000
    did; ``fagorcnc run`` on the simulator kept every planned segment.  Streamed, four times the
    program costs no more memory."""
    small, large = _peak_kib(what, programs[5000]), _peak_kib(what, programs[20000])
    assert large < small + 4096, (small, large)


def test_check_interprets_and_plans_the_program_once(programs, monkeypatch):
    """It once interpreted the program twice (the second time to see the origin of each move) and
    planned it twice (the cycle time, then the envelope of the planned path)."""
    calls = {"run": 0, "segments": 0}
    interpret, plan = Interpreter.run, Planner.segments

    def counted_run(self, *args):
        calls["run"] += 1
        return interpret(self, *args)

    def counted_segments(self, records):
        calls["segments"] += 1
        return plan(self, records)

    monkeypatch.setattr(Interpreter, "run", counted_run)
    monkeypatch.setattr(Planner, "segments", counted_segments)
    report = check_file(programs[1500])
    assert report.verdict() == "pass"
    assert calls == {"run": 1, "segments": 1}


@pytest.mark.parametrize("path", PROGRAMS, ids=lambda p: p.name)
def test_check_agrees_with_simulate(path):
    """Verdict, cycle time, moves and ending: the streamed check says what simulate() says."""
    result = fagorcnc.simulate(path)
    report = check_file(path)
    assert report.complete == result.ok
    assert report.cycle_time == pytest.approx(result.cycle_time, rel=1e-12)
    assert report.moves == sum(m.kind not in ("aux", "dwell") for m in result.moves)
    assert report.ended_by == result.ended_by
    assert [d.code for d in report.diagnostics] == [d.code for d in result.diagnostics]


def test_finishing_program_summary(programs):
    """The summary gathered as the moves pass: the tool, its offset, the origin of every move, the
    boxes (the arcs' extremes included)."""
    report = check_file(programs[1500])
    assert [(t.tool, t.loaded, t.offsets) for t in report.tools] == [(1, True, [1])]
    result = fagorcnc.simulate(programs[1500])
    moves = sum(m.kind not in ("aux", "dwell") for m in result.moves)
    assert [(o.origin, o.moves) for o in report.origins] == [("G54", moves)]
    box = report.boxes[0]
    assert box.tool == 1
    assert box.feed_part.lo["X"] == pytest.approx(-1.0)   # the G2 arcs at X0 bulge 1 mm to the left
    assert box.feed_part.hi["X"] == pytest.approx(31.0)   # ... and the G3 arcs at X30 to the right
    assert box.part.hi["Z"] == pytest.approx(50.0)


def test_a_syntax_error_after_m30_means_the_program_is_not_started(tmp_path):
    """The whole file is read for its syntax before anything runs: an error far down (here after
    M30, which the run never reaches) still keeps the program from starting."""
    f = tmp_path / "late.nc"
    f.write_text("G1 X10 F1000\nM30\nG1 X[[\n")
    report = check_file(f)
    assert not report.executed and report.moves == 0 and report.cycle_time == 0.0
    assert [(d.code, d.line) for d in report.diagnostics if d.is_error] == [("SYN003", 3)]
    assert dry_run(f).executed is False


def test_latin1_program_is_read_as_latin1(tmp_path):
    """Files written by older editors (Latin-1) are decoded as such, as simulate() reads them: the
    report quotes the block as written."""
    f = tmp_path / "old.nc"
    f.write_bytes("; pièce\nG1 X10 F1000\nG1 X10000 ; trop loin (réglage)\nM30\n".encode("latin-1"))
    report = check_file(f)
    (d,) = [d for d in report.diagnostics if d.code == "INT100"]
    assert d.line == 3 and "réglage" in d.source


def test_duplicate_jump_target_names_the_first_one_after_its_block_was_dropped(tmp_path):
    """The syntax pass drops every block once read; STR004 still names the first target's line."""
    f = tmp_path / "dup.nc"
    f.write_text("N10: G1 X10 F1000\n" + "G1 X1\nG1 X2\n" * 40 + "N10: G1 X2\nM30\n")
    (d,) = [d for d in check_file(f).diagnostics if d.code == "STR004"]
    assert d.line == 82 and "already defined on line 1" in d.message


def test_a_header_after_body_blocks_names_the_program_in_every_entry_point(tmp_path):
    """seed 002 L840-L850: the header '%name' is optional without local subroutines.  Blocks before
    it belong to the body (as the whole-file parser reads them); the streamed run used to call it a
    'second program header' and stop there."""
    f = tmp_path / "late_header.nc"
    f.write_text("G1 X10 F1000\n%PART\nG1 X20\nM30\n")
    result = fagorcnc.simulate(f)
    streamed = fagorcnc.interpret(f)
    moves = list(streamed)
    assert result.ok and streamed.ok and check_file(f).verdict() == "pass"
    ends = [[m.end["X"] for m in ms if m.kind == "linear"] for ms in (moves, result.moves)]
    assert ends == [[10.0, 20.0], [10.0, 20.0]]


def test_planning_error_still_interprets_the_rest(tmp_path, monkeypatch):
    """After a planning error the rest of the program is still interpreted, for its diagnostics
    (as simulate() does): an interpreter error further on is reported too."""
    from fagorcnc.plan import PlanningError

    f = tmp_path / "p.nc"
    f.write_text("G1 X10 F1000\nG1 X20\nG1 X30\nG1 X40 Y[1/0]\nM30\n")
    plan = Planner.segments

    def failing(self, records):
        for seg in plan(self, records):
            if seg.line == 2:
                raise PlanningError("no profile", 2, seg.record)
            yield seg

    monkeypatch.setattr(Planner, "segments", failing)
    out = dry_run(f)
    assert [(d.code, d.line) for d in out.diagnostics if d.is_error] == [("PLN001", 2), ("INT033", 4)]
    assert out.moves == 3 and not out.ok


@pytest.mark.parametrize("text", ["G1 X10 F1000\nG2 X20 Y0 I5 J0\nM30\n", "G1 X10 F1000\rG1 X20\rM30\r",
                                  "G1 X10 F1000\r\nG1 X[[\r\nM30\r\n", "%P\nT1 M6\nG1 X10 F1000\nG1 Y[1/0]\nM30\n"])
def test_dry_run_of_program_text_agrees_with_simulate(text):
    """Program text (not a file) is split into blocks as parse_text splits it (CR LF and a lone
    CR end a line too)."""
    result, out = fagorcnc.simulate(text), dry_run(text)
    assert (out.ok, out.executed, out.ended_by) == (result.ok, result.program.ok, result.ended_by)
    assert out.cycle_time == pytest.approx(result.cycle_time, rel=1e-12)
    assert out.moves == sum(m.kind not in ("aux", "dwell") for m in result.moves)
    assert [str(d) for d in out.diagnostics] == [str(d) for d in result.diagnostics]


def test_the_envelope_box_holds_every_curve(programs):
    """The PLN100 check skips the exact extent of a curve whose cheap box (a Bézier curve's control
    points, an arc's circle) lies within the soft limits: that box must hold the whole curve."""
    from fagorcnc.plan.blend import BlendPiece
    from fagorcnc.plan.envelope import hull, piece_extent

    result = fagorcnc.simulate(programs[1500])
    curved = [s.piece for s in result.segments(keep_profiles=False) if s.piece is not None and s.piece.curved]
    kinds = {"BlendPiece" if isinstance(p, BlendPiece) else type(p).__name__ for p in curved}   # BlendRow too
    assert kinds == {"ArcPiece", "BlendPiece"}
    for piece in curved:
        lo, hi = hull(piece)
        pmin, pmax = piece_extent(piece)
        assert (lo <= pmin + 1e-9).all() and (pmax <= hi + 1e-9).all(), piece


def test_the_streamed_run_decodes_latin1_as_the_check_does(tmp_path):
    """``fagorcnc run`` reads the program lazily; it decodes an old editor's Latin-1 file as the
    check and simulate() do (it used to turn every accent into U+FFFD)."""
    f = tmp_path / "old.nc"
    f.write_bytes('G1 X10 F1000\n#MSG ["réglage"]\nM30\n'.encode("latin-1"))
    streamed = fagorcnc.interpret(f)
    list(streamed)
    assert streamed.ok
    (shown,) = [d for d in streamed.diagnostics if d.code == "INT077"]   # the #MSG text, shown
    assert shown.message == "#MSG: réglage" and shown.source == '#MSG ["réglage"]'
    assert [str(d) for d in streamed.diagnostics] == [str(d) for d in fagorcnc.simulate(f).diagnostics]


def test_dry_run_reports_an_arc_that_leaves_the_soft_limits_as_check_does(tmp_path):
    # PLN100 is part of the dry run's verdict: the check, the check before a real run and the dry run agree
    arc = tmp_path / "arc.nc"
    arc.write_text("G0 X990 Y-20\nG3 X990 Y20 I0 J20 F1000\nM30\n")
    result = fagorcnc.dry_run(arc)
    assert not result.ok and [(d.code, d.line) for d in result.diagnostics] == [("PLN100", 2)]
    assert [d.code for d in check_file(arc).diagnostics] == ["PLN100"]   # reported once, not twice


def test_a_utf8_byte_order_mark_is_not_part_of_the_header(tmp_path):
    # Windows editors may write a UTF-8 byte-order mark first: it used to stand before '%PART' (SYN002)
    f = tmp_path / "bom.nc"
    f.write_bytes(b"\xef\xbb\xbf%PART\nG1 X10 F1000\nM30\n")
    assert fagorcnc.simulate(f).ok and fagorcnc.simulate(f).program.name == "PART"
    assert fagorcnc.simulate(f.read_text(encoding="utf-8")).program.name == "PART"   # text decoded without -sig
    assert fagorcnc.dry_run(f).ok and check_file(f).diagnostics == []
    streamed = fagorcnc.interpret(f)
    assert [m.end["X"] for m in streamed if m.kind == "linear"] == [10.0] and streamed.ok


def test_utf16_files_are_read_and_binary_files_are_one_diagnostic(tmp_path):
    # Windows Notepad's "Unicode" is UTF-16 with a byte-order mark: read as such, in every entry point
    f = tmp_path / "u16.nc"
    f.write_bytes("%U16\nG1 X10 F1000 ; réglage\nM30\n".encode("utf-16"))
    assert fagorcnc.simulate(f).ok and fagorcnc.dry_run(f).ok and check_file(f).diagnostics == []
    assert [m.end["X"] for m in fagorcnc.interpret(f) if m.kind == "linear"] == [10.0]
    # a binary file (or UTF-16 without its mark) holds NUL bytes: one error, not a page of syntax errors
    for data in (bytes(range(256)) * 8, "G1 X10 F1000\nM30\n".encode("utf-16-le")):
        f.write_bytes(data)
        found = check_file(f).diagnostics
        assert [d.code for d in found] == ["SYN023"] and "not a program text file" in found[0].message


def test_a_forward_goto_into_a_structure_is_refused_in_the_streamed_run_too(tmp_path):
    # seed 002 L17072: no jump into the body of another instruction.  simulate() said INT074; the streamed
    # run (check, run) had not yet read the $ENDIF when it jumped, and ran the body
    f = tmp_path / "goto_in.nc"
    f.write_text("P1=0\n$GOTO [IN]\n$IF P1==1\n[IN] P100=1\n$ENDIF\nM30\n")
    assert [(d.code, d.line) for d in fagorcnc.simulate(f).diagnostics] == [("INT074", 2)]
    assert [(d.code, d.line) for d in fagorcnc.dry_run(f).diagnostics] == [("INT074", 2)]
    streamed = fagorcnc.interpret(f)
    list(streamed)
    assert [(d.code, d.line) for d in streamed.diagnostics] == [("INT074", 2)]
    # a forward jump over a whole structure, or within the one it stands in, is still allowed
    f.write_text("P1=0\n$GOTO [OUT]\n$IF P1==1\nP100=1\n$ENDIF\n[OUT] P101=1\n$WHILE P1<2\nP1=P1+1\n"
                 "$GOTO [NEXT]\nP102=1\n[NEXT] P103=P1\n$ENDWHILE\nM30\n")
    assert fagorcnc.dry_run(f).ok and fagorcnc.simulate(f).state.param(103) == 2
