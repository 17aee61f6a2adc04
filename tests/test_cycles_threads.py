"""Thread milling G211/G212 (spec 09 §2.9, provisional) and the tapping PLC marks TAPPING/RIGID (§1.4).

Spec 09 gives no worked example for G211/G212 ("do not build tests until the cycles manual is found");
these tests pin the digest's recommended meanings and the [CONSTRUCTION] path of ``choices`` with
numbers worked out by hand:  path radius rho = |J| - r (G211) or |J| + r (G212), clearance radius
rho_c = rho - K (G211) or rho + K (G212), one turn per pitch |B|, a right-hand thread (B > 0) milled
top-down turns G02 (a right-hand helix turns G03 while it rises along +l).
"""

from __future__ import annotations

import json

import pytest
from cycles_helpers import channel, codes, moves, run, split

from fagorcnc.cli import main

TOOLS = {"tools": {"1": {"1": {"radius": 3.0}}}}
HEAD = "T1 D1 M6\nS1000 M3\n"


def _helices(program: str, line: int) -> list[tuple[float, float]]:
    """(sweep in degrees, change of Z) of the full-turn helices of ``line`` (G17)."""
    return [(round(r.sweep, 6), round(r.end["Z"] - r.start["Z"], 6)) for r in run(program, TOOLS).moves
            if r.line == line and r.kind == "arc" and abs(abs(r.sweep) - 360.0) < 1e-6]


# ------------------------------------------------------------------ G211 inside
def test_g211_right_hand_top_down_g98():
    # r = 3: rho = 8 - 3 = 5, rho_c = 5 - K1 = 4.  Zr = 2, Zb = -4: depth 6 = 4 turns of 1.5.
    # B+ right-hand, top-down (towards -Z) -> G02.  Entry semicircle (4,0) -> (5,0), centre (4.5,0),
    # turning with the helix (inside); exit back to (4,0); to the axis at Zb, then G98 up to Zs = 20.
    program = HEAD + "G00 G90 X0 Y0 Z20\nG98 G211 Z2 I-4 J8 K1 B1.5 F300\nM30\n"
    assert moves(program, 4, TOOLS, ok=False) == split(
        "R(0,0,2) R(4,0,2) CW(5,0,2; 4.5,0)@300 "
        "CW(5,0,0.5; 0,0)@300 CW(5,0,-1; 0,0)@300 CW(5,0,-2.5; 0,0)@300 CW(5,0,-4; 0,0)@300 "
        "CW(4,0,-4; 4.5,0)@300 R(0,0,-4) R(0,0,20)")
    # the helix pitch: each full turn (-360 degrees, clockwise) goes down by |B| = 1.5
    assert _helices(program, 4) == [(-360.0, -1.5)] * 4
    result = run(program, TOOLS)
    assert [(d.line, d.code) for d in result.diagnostics] == [(4, "CYC020")]   # provisional, a warning
    assert result.ok


def test_g211_partial_last_turn_exits_where_the_helix_ends():
    # rho = 5, rho_c = 4; Zr = 0, Zb = -2.5: 2 full turns of 1 and half a turn (angle -180 degrees,
    # clockwise) ending at (-5, 0); the exit semicircle goes from there to (-4, 0), centre (-4.5, 0).
    program = HEAD + "G00 G90 X0 Y0 Z20\nG99 G211 Z0 I-2.5 J8 K1 B1 F250\nM30\n"
    assert moves(program, 4, TOOLS, ok=False) == split(
        "R(0,0,0) R(4,0,0) CW(5,0,0; 4.5,0)@250 CW(5,0,-1; 0,0)@250 CW(5,0,-2; 0,0)@250 "
        "CW(-5,0,-2.5; 0,0)@250 CW(-4,0,-2.5; -4.5,0)@250 R(0,0,-2.5) R(0,0,0)")


def test_g211_left_hand_bottom_up():
    # B-1.5 left-hand, C1 bottom-up: rapid to (4,0) at Zr = 2, rapid down to Zb = -4 at the clearance
    # radius; the helix rises, and a left-hand helix rising turns G02 (clockwise); 4 turns up to Zr.
    program = HEAD + "G00 G90 X0 Y0 Z20\nG98 G211 Z2 I-4 J8 K1 B-1.5 C1 F300\nM30\n"
    assert moves(program, 4, TOOLS, ok=False) == split(
        "R(0,0,2) R(4,0,2) R(4,0,-4) CW(5,0,-4; 4.5,0)@300 "
        "CW(5,0,-2.5; 0,0)@300 CW(5,0,-1; 0,0)@300 CW(5,0,0.5; 0,0)@300 CW(5,0,2; 0,0)@300 "
        "CW(4,0,2; 4.5,0)@300 R(0,0,2) R(0,0,20)")
    # right-hand bottom-up turns the other way (G03) for the same path
    right = moves(program.replace("B-1.5", "B1.5"), 4, TOOLS, ok=False)
    assert right[3:9] == split("CCW(5,0,-4; 4.5,0)@300 CCW(5,0,-2.5; 0,0)@300 CCW(5,0,-1; 0,0)@300 "
                               "CCW(5,0,0.5; 0,0)@300 CCW(5,0,2; 0,0)@300 CCW(4,0,2; 4.5,0)@300")


def test_g211_whole_turns_end_exactly_on_the_bottom():
    # depth 0.3 - (-0.7) = 1.0 = 10 turns of 0.1 (0.1 is not exact in binary: 10 x 0.1 steps would end
    # 1e-16 off); the tenth turn ends on Zb = -0.7 itself, then the exit semicircle at -0.7
    program = HEAD + "G0 X0 Y0 Z20\nG99 G211 Z0.3 I-0.7 J8 K1 B0.1 F300\nM30\n"
    arcs = [r for r in run(program, TOOLS).moves if r.line == 4 and r.kind == "arc"]
    assert len(arcs) == 12 and arcs[-2].end_part["Z"] == -0.7 and arcs[-1].end_part["Z"] == -0.7


# ------------------------------------------------------------------ G212 outside
def test_g212_outside_left_hand_bottom_up_g99():
    # r = 3: rho = 8 + 3 = 11, rho_c = 12, centre (10,10).  Zr = 2, Zb = -3: depth 5 = 2 turns of 2 and a
    # half.  C1: down to Zb at (22,10) in rapid; B-2 left-hand rising -> G02.  Outside, the entry semicircle
    # (22,10) -> (21,10), centre (21.5,10), turns against the helix (G03) to be tangent to it.  The half
    # turn (-180 degrees) ends at (10-11, 10) = (-1,10); exit to (-2,10), centre (-1.5,10), G03.
    # Retract: up at the clearance radius to the return level (G99: Zr = 2, already there), then the axis.
    program = HEAD + "G00 G90 X10 Y10 Z20\nG99 G212 Z2 I-3 J8 K1 B-2 C1 F300\nM30\n"
    assert moves(program, 4, TOOLS, ok=False) == split(
        "R(10,10,2) R(22,10,2) R(22,10,-3) CCW(21,10,-3; 21.5,10)@300 "
        "CW(21,10,-1; 10,10)@300 CW(21,10,1; 10,10)@300 CW(-1,10,2; 10,10)@300 "
        "CCW(-2,10,2; -1.5,10)@300 R(10,10,2)")


def test_g212_top_down_g98_retracts_before_crossing_the_stud():
    # rho = 11, rho_c = 12; Zr = 1, Zb = -2: 3 turns of 1, right-hand top-down -> G02; entry and exit
    # G03.  After the exit at (12,0,-2): up to Zs = 15 at the clearance radius, then over the axis.
    program = HEAD + "G00 G90 X0 Y0 Z15\nG98 G212 Z1 I-2 J8 K1 B1 F200\nM30\n"
    assert moves(program, 4, TOOLS, ok=False) == split(
        "R(0,0,1) R(12,0,1) CCW(11,0,1; 11.5,0)@200 CW(11,0,0; 0,0)@200 CW(11,0,-1; 0,0)@200 "
        "CW(11,0,-2; 0,0)@200 CCW(12,0,-2; 11.5,0)@200 R(12,0,15) R(0,0,15)")


def test_g212_with_the_starting_plane_below_zr_goes_over_the_stud_at_zr():
    # Zs = 0 lies between Zr = 1 and Zb = -2 (allowed, spec 09 §1.3): the tool leaves the clearance
    # radius at Zr, the level over the stud, and only then goes down to the return level Zs = 0.
    program = HEAD + "G00 G90 X0 Y0 Z0\nG98 G212 Z1 I-2 J8 K1 B1 F200\nM30\n"
    assert moves(program, 4, TOOLS, ok=False)[-3:] == split("R(12,0,1) R(0,0,1) R(0,0,0)")


# ------------------------------------------------------------------ planes
def test_g211_in_g18():
    # G18: plane ZX (abscissa Z, ordinate X), longitudinal Y (seed 002 L2991).  Z is the reference plane
    # parameter, so the point (Z0, X0) is reached before.  Zs = Y20, Zr = Y2, Zb = Y-4; rho = 5 along Z.
    # Notation (X,Y,Z; centre Z,X).  The plane (Z, X, Y) is right-handed: right-hand top-down is G02.
    program = HEAD + "G00 G90 X0 Y20 Z0\nG18 G98 G211 Z2 I-4 J8 K1 B1.5 F300\nM30\n"
    assert moves(program, 4, TOOLS, ok=False) == split(
        "R(0,2,0) R(0,2,4) CW(0,2,5; 4.5,0)@300 "
        "CW(0,0.5,5; 0,0)@300 CW(0,-1,5; 0,0)@300 CW(0,-2.5,5; 0,0)@300 CW(0,-4,5; 0,0)@300 "
        "CW(0,-4,4; 4.5,0)@300 R(0,-4,0) R(0,20,0)")


def test_g212_in_g19():
    # G19: plane YZ, longitudinal X.  Zs = X20, Zr = X2, Zb = X-3; rho = 11, rho_c = 12 along Y; depth 5 =
    # 2 turns of 2 and a half (-180 degrees: Y = -11).  Notation (X,Y,Z; centre Y,Z).
    program = HEAD + "G00 G90 X20 Y0 Z0\nG19 G99 G212 Z2 I-3 J8 K1 B2 F300\nM30\n"
    assert moves(program, 4, TOOLS, ok=False) == split(
        "R(2,0,0) R(2,12,0) CCW(2,11,0; 11.5,0)@300 CW(0,11,0; 0,0)@300 CW(-2,11,0; 0,0)@300 "
        "CW(-3,-11,0; 0,0)@300 CCW(-3,-12,0; -11.5,0)@300 R(2,-12,0) R(2,0,0)")


# ------------------------------------------------------------------ modal life, patterns, report
def test_thread_influence_zone_patterns_and_check_report(tmp_path, capsys):
    # the thread is repeated at X30 (influence zone) and by G160 A90 X20 K2 at (30,20): 3 threads
    program = (HEAD + "G00 G90 X0 Y0 Z20\nG99 G211 Z2 I-4 J8 K1 B1.5 F300\nX30\nG160 A90 X20 K2\n"
               "G80\nX50\nM30\n")
    assert moves(program, 5, TOOLS, ok=False)[:3] == split("R(30,0,2) R(34,0,2) CW(35,0,2; 34.5,0)@300")
    assert moves(program, 6, TOOLS, ok=False)[:2] == split("R(30,20,2) R(34,20,2)")
    assert moves(program, 8, TOOLS, ok=False) == ["R(50,20,2)"]   # after G80 a plain move (from (30,20))
    result = run(program, TOOLS)
    assert channel(result).cycles.report() == [{"code": "G211", "file": "<string>", "line": 4, "holes": 3}]
    part = tmp_path / "thread.nc"
    part.write_text(program)
    machine = tmp_path / "m.toml"
    machine.write_text('[tools.1.1]\nradius = 3.0\n')
    main(["check", str(part), "--machine", str(machine), "--format", "json"])
    report = json.loads(capsys.readouterr().out)
    entry = report["files"][0]
    assert [(c["code"], c["holes"]) for c in entry["cycles"]] == [("G211", 3)]


def test_thread_starts_a_stopped_spindle():
    program = "T1 D1 M6\nG00 G90 X0 Y0 Z20\nG211 Z2 I-4 J8 K1 B1.5 F300\nM30\n"
    assert moves(program, 3, TOOLS, ok=False)[0] == "M3"


# ------------------------------------------------------------------ errors (spec 09 §1.5)
@pytest.mark.parametrize(("block", "code"), [
    ("G211 Z2 J8 K1 B1", "CYC001"),              # no depth I
    ("G211 Z2 I2 J8 K1 B1", "CYC002"),           # Zb == Zr
    ("G211 Z2 I-4 K1 B1", "CYC004"),             # no J
    ("G212 Z2 I-4 J-8 K1 B1", "CYC004"),         # J <= 0 (the hand is B's sign)
    ("G211 Z2 I-4 J8 B1", "CYC004"),             # no K
    ("G211 Z2 I-4 J8 K0 B1", "CYC004"),          # K0
    ("G211 Z2 I-4 J8 K1", "CYC004"),             # no B
    ("G212 Z2 I-4 J8 K1 B0", "CYC004"),          # B0
    ("G211 Z2 I-4 J8 K1 B1 C2", "CYC004"),       # C is 0 or 1
    ("G211 Z2 I-4 J8 K1 B1 H100", "CYC004"),     # H has no meaning here
    ("G211 Z2 I-4 J8 K1 B1 D-1", "CYC004"),      # D < 0
    ("G211 Z2 I-4000 J8 K1 B0.0001", "CYC004"),  # 4e7 turns for one thread
    ("G211 Z2 I-4 J3 K1 B1", "CYC005"),          # r = 3: rho = 3 - 3 = 0
    ("G211 Z2 I-4 J4 K2 B1", "CYC005"),          # rho = 1, rho_c = 1 - 2 < 0
])
def test_thread_errors(block, code):
    program = HEAD + "G00 Z20\n" + block + " F100\nM30\n"
    result = run(program, TOOLS)
    assert (4, code) in [(d.line, d.code) for d in result.diagnostics if d.is_error]
    assert [r for r in result.moves if r.line == 4] == []   # nothing of the block moves


def test_outside_thread_is_never_too_big_for_the_tool():
    # G212 J4 K2, r = 3: rho = 7, rho_c = 9 -- nothing to refuse
    assert "CYC005" not in [c for _l, c in codes(HEAD + "G00 Z20\nG212 Z2 I-4 J4 K2 B1 F100\nM30\n", TOOLS)]


def test_thread_under_radius_compensation_is_refused():
    assert (4, "CYC003") in codes(HEAD + "G00 Z20\nG41 G211 Z2 I-4 J8 K1 B1 F100\nM30\n", TOOLS)


# ------------------------------------------------------------------ PLC marks TAPPING / RIGID
TAP = "S500 M03\nG00 G90 X0 Y0 Z20\n"


def test_tapping_marks_on_the_records_of_the_tapping_cycle():
    # seed 002 L29849: TAPPING while a tapping canned cycle runs; L29856: RIGID during rigid tapping
    # (G63; G84 R1 too, spec 09 §1.4 [UNVERIFIED]).  The plane positioning is not part of the cycle; the
    # approach to Zr, the tapping in, the dwell, the spindle reversal, the tapping out, the restored M03
    # and the G98 return are.
    normal = run(TAP + "G98 G84 X15 Y15 Z3 I-12 K0.5 R0 F750\nX30\nG81 Z3 I-5\nM30\n")
    t = ("TAPPING",)
    hole = [(r.kind, r.plc_marks) for r in normal.moves if r.line == 3]
    assert hole == [("rapid", ()), ("rapid", t), ("linear", t), ("dwell", t), ("aux", t), ("linear", t),
                    ("aux", t), ("rapid", t)]
    assert [r.plc_marks for r in normal.moves if r.line == 4] == [(), t, t, t, t, t, t, t]
    assert {r.plc_marks for r in normal.moves if r.line == 5} == {()}   # G81 drills without the marks
    assert {r.dyn.plc_marks for r in normal.moves if r.line == 3 and r.kind == "linear"} == {t}
    rigid = run(TAP + "G98 G84 X15 Y15 Z3 I-12 R1 B5 F750\nM30\n")
    assert {r.plc_marks for r in rigid.moves if r.line == 3 and r.kind == "linear"} == {("TAPPING", "RIGID")}


def test_plc_marks_read_from_the_program_are_off_and_synchronise():
    # "sa lecture arrête la préparation des blocs" (L29846): the read waits for the tapping to end, then
    # the channel executes the reading block, not a tapping cycle: 0 + 0 + 0 + 0 + 7 = 7
    program = (TAP + "G98 G84 X15 Y15 Z3 I-12 R1 F750\nG80\nP1=V.PLC.TAPPING + V.PLC.RIGID + V.PLC.TAPPINGC1"
               " + V.PLC.RIGIDC1 + 7\nM30\n")
    result = run(program)
    assert result.ok and result.state.param(1) == 7
    # the synchronisation point: a dwell of no time at line 5, where the tapping ended (X15 Y15 Z20)
    sync = [r for r in result.moves if r.line == 5]
    assert [(r.kind, r.seconds, r.position["Z"]) for r in sync] == [("dwell", 0.0, 20.0)]
    # one channel offline
    assert (3, "INT047") in codes(TAP + "P1=V.PLC.RIGIDC2\nM30\n")


@pytest.mark.parametrize("name", ["V.SP.SREVM05", "V.SP.SREVM05.S", "V.MPA.SREVM05.S"])
def test_srevm05_is_the_plcs_variable(name):
    # seed 002 L21990-L21992: "Variable de lecture depuis le programme PLC et l'Interface" -- not a part
    # program's (the machine file's SREVM05 drives G84, see test_cycles_drilling)
    result = run(TAP + f"P1={name}\nM30\n")
    errors = [d for d in result.diagnostics if d.is_error]
    assert [(d.line, d.code) for d in errors] == [(3, "INT044")] and "PLC" in errors[0].message
