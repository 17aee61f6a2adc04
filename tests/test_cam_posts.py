"""Real CAM output (issue 23): what the Autodesk Fagor 8065 posts, the DMS router post and LIGNOCAM
write, as they write it; the machine's [compat] policy (default and strict) and the machinist's lint."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

import fagorcnc
from fagorcnc.cli import main
from fagorcnc.config.compat import CONSTRUCTS, Compat, parse_compat
from fagorcnc.config.machine import MachineError, load_machine

ROOT = Path(__file__).resolve().parents[1]
STRICT = {"compat": {"strict": True}}


def diags(text: str, machine=None, **kw) -> list[tuple]:
    """(code, severity, line) of every diagnostic of a simulated program."""
    return [(d.code, d.severity, d.line) for d in fagorcnc.simulate(text, machine, **kw).diagnostics]


def moves(result) -> list:
    """The motion records (no auxiliary functions)."""
    return [m for m in result.moves if m.kind in ("rapid", "linear", "arc")]


def only(result, code: str):
    (d,) = [d for d in result.diagnostics if d.code == code]
    return d


# ------------------------------------------------------------------------------------------- the policy
def test_policy_defaults_warn_and_strict_makes_every_construct_an_error():
    c = Compat()
    assert {k: c.action(k) for k in CONSTRUCTS} == dict.fromkeys(CONSTRUCTS, "warn")
    s = c.strictly()
    assert {k: s.action(k) for k in CONSTRUCTS} == dict.fromkeys(CONSTRUCTS, "error")
    # the lint is the manual's letter: strict leaves it alone
    assert s.action("g58_after_offset") == "warn" and s.action("feed_spindle_stopped") == "warn"


def test_machine_file_compat_table(tmp_path):
    m = tmp_path / "m.toml"
    m.write_text('[compat]\ng51 = "accept"\nlone_g61 = "error"\n')
    c = load_machine(m).compat
    assert (c.action("g51"), c.action("lone_g61"), c.action("bare_name"), c.strict) == \
        ("accept", "error", "warn", False)
    m.write_text("[compat]\nstrict = true\n")
    assert load_machine(m).compat.action("program_name") == "error"
    for bad, says in (('g51 = "ignore"', 'compat.g51 = \'ignore\': must be "accept", "warn" or "error"'),
                      ('g52 = "warn"', "compat.g52: unknown key"), ("strict = 1", "compat.strict: expected true")):
        m.write_text(f"[compat]\n{bad}\n")
        with pytest.raises(MachineError, match=says.replace("(", r"\(").replace(")", r"\)")):
            load_machine(m)
    with pytest.raises(MachineError, match="expected a table"):
        parse_compat("strict")


# ------------------------------------------------------------------------------------------- G51
def test_g51_a45_e0002_has_no_effect_with_a_warning():
    # the generic post's header line: the 8055 look-ahead, not in the 8060/8065 G list (seed 002 L1354)
    text = "G51 A45 E0.002\nG1 X10 F1000\nG1 Y10\nM30\n"
    r = fagorcnc.simulate(text)
    assert r.ok and [(d.code, d.severity, d.line, d.col) for d in r.diagnostics] == [("CAM001", "warning", 1, 1)]
    assert "G51 A45 E0.002 is the 8055's look-ahead" in r.diagnostics[0].message
    same = fagorcnc.simulate("G1 X10 F1000\nG1 Y10\nM30\n")
    # no effect at all: the same moves, the same corner mode (G50 at power-on), the same cycle time
    assert [(m.end, m.dyn) for m in moves(r)] == [(m.end, m.dyn) for m in moves(same)]
    assert r.cycle_time == same.cycle_time and moves(r)[0].dyn.corner == "G50"


def test_g51_strict_and_per_construct_actions():
    assert diags("G51 A45 E0.002\nM30\n", STRICT) == [("CAM001", "error", 1)]
    assert diags("G51 A45 E0.002\nM30\n", {"compat": {"g51": "error"}}) == [("CAM001", "error", 1)]
    assert diags("G51 A45 E0.002\nM30\n", {"compat": {"g51": "accept"}}) == [("CAM001", "info", 1)]
    # with anything else in the block G51 stays an unknown G function
    assert diags("G51 A45 E0.002 X1\nM30\n") == [("INT010", "error", 1)]


# ------------------------------------------------------------------------------------------- lone G61
def test_lone_g61_in_the_closing_block_has_no_effect():
    # G61 acts only on the move of its own block (seed 002 L8088-L8107); the posts write it alone at the end
    r = fagorcnc.simulate("G1 X10 F1000\nG61\nG1 Y10\nM30\n")
    assert r.ok and diags("G1 X10 F1000\nG61\nG1 Y10\nM30\n") == [("CAM002", "warning", 2)]
    assert [m.dyn.corner for m in moves(r)] == ["G50", "G50"]   # nothing rounded, nothing cancelled
    assert diags("G1 X10 F1000\nG61\nM30\n", STRICT) == [("CAM002", "error", 2)]
    # G61 with a move is the manual's: no diagnostic
    assert diags("G1 X10 F1000\nG61 G1 Y10\nG1 X0\nM30\n") == []


# ------------------------------------------------------------------------------------------- G500 / G501
def test_g501_builtin_smoothing_on_and_g500_off():
    # generic post: "G501 A60 E0.0024 J100 M1" ... "G500"; A = acceleration %, E = tolerance (post's docs);
    # Fagor's own G501 is HSC on for roughing, G500 HSC off (seed 002 L11084-L11086)
    text = "G1 X1 F1000\nG501 A60 E0.0024 J100 M1\nG1 X10\nG1 Y10\nG500\nG1 X0\nM30\n"
    r = fagorcnc.simulate(text)
    assert r.ok, r.diagnostics
    assert [(d.code, d.severity, d.line) for d in r.diagnostics] == [("CAM003", "warning", 2), ("CAM003", "warning", 5)]
    assert "#HSC ON [CONTERROR 0.0024, CORNER 150] and 60 % acceleration (A60); J100 M1 not used" in \
        r.diagnostics[0].message
    before, on1, on2, off = moves(r)
    assert before.dyn.hsc is None and off.dyn.hsc is None and off.dyn.acceleration == ()
    assert on1.dyn.corner == "HSC" and on1.dyn.hsc.mode == "CONTERROR" and on1.dyn.hsc.tolerance == 0.0024
    assert on1.dyn.hsc.corner == 150.0 and on1.dyn.acceleration == (("X", 60.0), ("Y", 60.0), ("Z", 60.0))
    assert on2.dyn == on1.dyn
    # M1 after G501 is the subroutine's parameter P12 (A=P0 ... Z=P25, L11007), not an optional stop
    assert [m.value for m in r.moves if m.kind == "aux"] == [30.0]


def test_g501_dms_form_and_inches():
    # DMS post: "G501 A100 E0.001 M2": M2 is P12, the program goes on
    r = fagorcnc.simulate("G501 A100 E0.001 M2\nG1 X10 F1000\nG500\nM30\n")
    assert r.ok and r.ended_by == "M30"
    (m,) = [m for m in r.moves if m.kind == "linear"]
    assert m.dyn.hsc.tolerance == 0.001 and m.dyn.acceleration == ()   # 100 %: unchanged
    # in G70 E is in inches: 0.0001 in = 0.00254 mm
    (m,) = moves(fagorcnc.simulate("G70\nG501 E0.0001\nG1 X1 F10\nM30\n"))
    assert m.dyn.hsc.tolerance == pytest.approx(0.00254)
    # no E: the machine's HSCROUND; A above 100 stays at the machine's acceleration
    (m,) = moves(fagorcnc.simulate("G501 A150\nG1 X1 F100\nM30\n"))
    assert m.dyn.hsc.tolerance == 0.01 and m.dyn.acceleration == ()
    assert diags("G501 E0\nM30\n") == [("CAM021", "error", 1)]


def test_g500_g501_strict_mapping_and_file(tmp_path):
    assert diags("G501 A60 E0.0024 J100 M1\nG500\nM30\n", STRICT) == [("CAM003", "error", 1)]
    # mapped in the machine file: the machine builder said so, a note only (strict too)
    mapped = {"oem_subroutines": {"501": {"builtin": "smoothing_on"}, "500": {"builtin": "smoothing_off"}},
              "compat": {"strict": True}}
    r = fagorcnc.simulate("G501 A60 E0.0024 J100 M1\nG1 X1 F100\nG500\nM30\n", mapped)
    assert r.ok and [(d.code, d.severity) for d in r.diagnostics] == [("CAM003", "info"), ("CAM003", "info")]
    assert moves(r)[0].dyn.hsc.tolerance == 0.0024
    # a file G501 in the search path is the machine's own: it runs (its P0 = A60)
    (tmp_path / "G501").write_text("P100=P0\nG1 X[P0] F100\nM17\n")
    r = fagorcnc.simulate("G501 A60 E0.0024 J100 M1\nM30\n", {"subroutine_paths": [str(tmp_path)]})
    assert r.ok and not r.diagnostics and moves(r)[0].end["X"] == 60.0


def test_other_g5xx_without_file_says_how_to_provide_it():
    r = fagorcnc.simulate("G502 A1\nM30\n")
    d = only(r, "CAM020")
    assert d.is_error and "subroutine_paths" in d.message and 'oem_subroutines = {502 = "file.nc"}' in d.message
    with pytest.raises(MachineError, match=r"built-in behaviours are for G500\.\.G599"):
        load_machine({"oem_subroutines": {"180": {"builtin": "smoothing_on"}}})
    with pytest.raises(MachineError, match="expected a file name or"):
        load_machine({"oem_subroutines": {"501": {"builtin": "smooth"}}})


def test_mg501_modal_form_runs_the_builtin_once():
    r = fagorcnc.simulate("MG501 E0.005\nG1 X1 F100\nG1 X2\nG500\nM30\n")
    assert r.ok and [m.dyn.hsc.tolerance for m in moves(r)] == [0.005, 0.005]


# ------------------------------------------------------------------------------------------- program start
def test_program_name_as_lignocam_writes_it():
    # "% Pfette_.nc" (LIGNOCAM): L843 allows letters and digits only
    p = fagorcnc.parse_text("% Pfette_.nc\nG1 X1 F100\nM30\n")
    assert p.ok and p.name == "Pfette_.nc"
    assert [(d.code, d.severity, d.col) for d in p.diagnostics] == [("CAM004", "warning", 2)]
    assert diags("% Pfette_.nc\nM30\n", STRICT) == [("CAM004", "error", 1)]
    # blanks inside the name, up to a comment
    assert fagorcnc.parse_text("%PART 12 ; roughing\nM30\n").name == "PART 12"
    assert [d.code for d in fagorcnc.parse_text("%A*B\nM30\n").diagnostics] == ["SYN010"]


def test_bare_name_line_as_the_dms_post_writes_it():
    r = fagorcnc.simulate("DMS_PART1\nG1 X1 F100\nM30\n")
    assert r.ok and r.program.name == "DMS_PART1"
    assert [(d.code, d.severity, d.line) for d in r.diagnostics] == [("STR011", "warning", 1)]
    assert diags("FINISH01\nM30\n", STRICT) == [("STR011", "error", 1)]
    assert diags("FINISH01\nM30\n", {"compat": {"bare_name": "accept"}}) == [("STR011", "info", 1)]


def test_strict_front_end_error_stops_dry_run_and_check_before_anything_moves():
    out = fagorcnc.dry_run("FINISH01\nG1 X1 F100\nM30\n", STRICT)
    assert not out.ok and out.moves == 0 and [d.code for d in out.diagnostics] == ["STR011"]


# ------------------------------------------------------------------------------------------- #COMMENT, T LM06, case
def test_comment_begin_end_with_block_numbers():
    # LIGNOCAM numbers every block, #COMMENT BEGIN and END too (seed 002 L1786-L1804)
    text = "N10 G1 X1 F100\nN20 #COMMENT BEGIN\nN30 free text: G1 X500 (not a block\nN40 #COMMENT END\nN50 M30\n"
    r = fagorcnc.simulate(text)
    assert r.ok and not r.diagnostics and [m.end["X"] for m in r.moves if m.kind == "linear"] == [1.0]
    assert [d.code for d in fagorcnc.parse_text("N10 #COMMENT BEGIN\nx\n").diagnostics] == ["SYN017"]


def test_t202_lm06_is_the_tool_and_the_tool_change_subroutine(tmp_path):
    # L M06 calls the machine builder's global subroutine M06 (seed 002 L10417), glued to T202 by LIGNOCAM
    machine = {"tools": {"202": {"1": {"length": 50.0, "radius": 4.0}}}}
    r = fagorcnc.simulate("T202 LM06\nS1000 M3\nG1 X1 F100\nM30\n", machine)
    assert r.ok and [(d.code, d.severity) for d in r.diagnostics] == [("CAM006", "warning")]
    assert r.state.tool == 202 and r.state.offset == 1          # run as T202 M06
    assert [m.value for m in r.moves if m.kind == "aux" and m.function == "M"][:1] == [6.0]
    assert diags("T202 LM06\nM30\n", {**machine, **STRICT}) == [("CAM006", "error", 1)]
    # with the machine's M06 file it is called, after T202 is selected
    (tmp_path / "M06").write_text("G0 Z100\nM6\nM17\n")
    r = fagorcnc.simulate("T202 LM06\nM30\n", {**machine, "subroutine_paths": [str(tmp_path)]})
    assert r.ok and not r.diagnostics and r.state.tool == 202 and moves(r)[0].end["Z"] == 100.0
    # a glued call of another name without its file is an error
    assert diags("T2 LTOOLCH\nM30\n") == [("INT093", "error", 1)]


def test_keywords_in_brackets_in_lower_case_are_read_in_capitals():
    # "#HSC ON [conterror 0.02]" reads as #HSC ON [CONTERROR 0.02], with a warning
    r = fagorcnc.simulate("#HSC ON [conterror 0.02, Corner 120]\nG1 X1 F100\nM30\n")
    assert r.ok and [(d.code, d.severity, d.col) for d in r.diagnostics] == [("CAM007", "warning", 10)]
    assert "'conterror' as CONTERROR, 'Corner' as CORNER" in r.diagnostics[0].message
    assert moves(r)[0].dyn.hsc.tolerance == 0.02 and moves(r)[0].dyn.hsc.corner == 120.0
    # Autodesk's "#CS ON [1] [Mode 1, ...]": the front end reads it (what #CS does is the kinematics' business)
    p = fagorcnc.parse_text("#CS ON [1] [Mode 1, 0, 0, 0, 0, 0, 30]\nM30\n")
    assert p.ok and [(d.code, d.col) for d in p.diagnostics] == [("CAM007", 13)]
    # strings and V. variables keep their case; strict refuses
    assert fagorcnc.parse_text('#MSG ["Mode"]\nV.P.my_var = 1\nM30\n').diagnostics == ()
    assert diags("#HSC ON [conterror 0.02]\nM30\n", STRICT) == [("CAM007", "error", 1)]


# ------------------------------------------------------------------------------------------- lint
def test_g011_reads_as_g11_with_a_warning():
    r = fagorcnc.simulate("G011\nG1 X10 F100\nM30\n")
    assert [(d.code, d.severity) for d in r.diagnostics] == [("CAM010", "warning")]
    assert "G011 reads as G11" in r.diagnostics[0].message
    assert moves(r)[0].end["X"] == -10.0   # G11: mirror image in X (seed 002 ch. 9)
    assert diags("G01 X1 F100\nG00 X0\nG090 X0\nM30\n") == [("CAM010", "warning", 3)]   # G01, G00 are fine


@pytest.mark.parametrize("text,hint", [
    ("GO1 X10 F100", "did you mean G01"),
    ("G1 X1O F100", "did you mean X10"),
    ("G21", "on the 8065 it is G71"),
    ("G20", "inches are G70"),
    ("G43 H1 Z10", "the tool offset D applies the length"),
    ("G49", "on the 8065 it is D0"),
    ("G28 Z0", "G74 (home search) or a move in machine coordinates: #MCS G0 Z0"),
    ("G54.1 P1", "G159=n"),
    ("G64 P0.01", "G05 with #ROUNDPAR, or #HSC ON"),
])
def test_hints_for_letter_o_and_fanuc_codes(text, hint):
    (d,) = fagorcnc.simulate(text + "\nM30\n").diagnostics
    assert d.is_error and hint in d.message, d.message


def test_g58_after_g54_warns_that_it_replaces_the_offset():
    # on the 8065 G58 is absolute origin 5 (seed 002 L3531), not an additive offset
    m = {"origins": {"G54": {"X": 100.0}, "G58": {"X": 0.0}}}
    r = fagorcnc.simulate("G54\nG58\nG1 X10 F100\nM30\n", m)
    d = only(r, "CAM013")
    assert d.severity == "warning" and d.line == 2 and "replaces G54" in d.message and "X0 Y0 Z0" in d.message
    assert moves(r)[0].end["X"] == 10.0   # 0 + 10: entry 5, not 100 + 10
    assert diags("G58\nG1 X10 F100\nM30\n", m) == []          # G58 alone is fine
    assert diags("G58\nG54\nG58\nM30\n", m) == [("CAM013", "warning", 3)]
    assert diags("G54\nG58\nM30\n", {**m, **STRICT}) == [("CAM013", "warning", 2)]   # lint: strict leaves it


def test_feed_move_with_the_spindle_stopped():
    # M05 at power-on (seed 002 L5729): a tool cutting at feed without rotation, once per stop
    text = "T1 M6\nG1 X1 F100\nG1 X2\nS1000 M3\nG1 X3\nM5\nG1 X4\nG0 X0\nM30\n"
    assert diags(text) == [("CAM014", "warning", 2), ("CAM014", "warning", 7)]
    assert diags("T1 M6\nS1000 M3\nG1 X1 F100\nM30\n") == []
    assert diags("G1 X1 F100\nM30\n") == []                      # T0: no tool, nothing cut
    assert diags("T1 M6\nM3\nG1 X1 F100\nM30\n") == [("CAM014", "warning", 3)]   # M3 without a speed (L5467)
    assert diags(text, {"compat": {"feed_spindle_stopped": "accept"}})[0][1] == "info"


# ------------------------------------------------------------------------------------------- the shipped programs
@pytest.mark.parametrize("name", ["post_autodesk_generic.nc", "post_dms_router.nc"])
def test_shipped_cam_programs_pass_check_with_warnings_only(name, capsys):
    path = ROOT / "programs" / name
    assert main(["check", "--format", "json", str(path)]) == 0
    doc = json.loads(capsys.readouterr().out)
    (f,) = doc["files"]
    assert f["verdict"] == "pass" and f["executed"] is True
    assert {d["severity"] for d in f["diagnostics"]} - {"info"} == {"warning"}
    assert main(["check", "--strict", "--brief", str(path)]) == 1
    assert "[refused: strict compatibility]" in capsys.readouterr().out


def test_hints_on_syntax_errors_and_where_they_do_not_belong():
    # the front end's errors get the same hints (X-O5: the O of X-05 read as a word of its own)
    (d,) = fagorcnc.parse_text("X-O5\n").diagnostics[-1:]
    assert d.code == "SYN002" and "did you mean X-05" in d.message
    # no hint where the code means something else on the 8065 and the error is elsewhere
    (d,) = fagorcnc.simulate("G30 I10\nM30\n").diagnostics
    assert d.code == "INT018" and "Fanuc" not in d.message
    # a comment is not read for hints
    assert fagorcnc.simulate("G1 X10 F100 ; GO1\nM30\n").diagnostics == []


def test_g501_mapped_to_a_file(tmp_path):
    (tmp_path / "smooth.nc").write_text("#HSC ON [CONTERROR [P4]]\nM17\n")
    machine = {"subroutine_paths": [str(tmp_path)], "oem_subroutines": {"501": "smooth.nc"}}
    r = fagorcnc.simulate("G501 A60 E0.004 J100 M1\nG1 X1 F100\nM30\n", machine)
    assert r.ok and not r.diagnostics and moves(r)[0].dyn.hsc.tolerance == 0.004
