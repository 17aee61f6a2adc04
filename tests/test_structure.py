"""Program structure: headers, local subroutines, labels, $ nesting (seed 002 L708-L953, ch. 12, ch. 21.2)."""

from __future__ import annotations

from pathlib import Path

from helpers import codes

from fagorcnc.syntax import parse_file, parse_text

PROGRAMS = Path(__file__).resolve().parents[1] / "programs"


def test_manual_layout_local_subroutines_then_header_then_body():
    # seed 002 L931-L952 (coordinates filled in)
    program = parse_text("""%L CORNER
G91 G01 X10
Y10
#RET
%L SQUARE
LL CORNER
LL CORNER
M17
%DEMO
G90 G00 X0 Y0
LL SQUARE
M30
""")
    assert program.ok, [str(d) for d in program.diagnostics]
    assert program.name == "DEMO"
    assert list(program.subroutines) == ["CORNER", "SQUARE"]
    assert [b.line for b in program.subroutines["CORNER"].blocks] == [2, 3, 4]
    assert [b.line for b in program.blocks] == [10, 11, 12]
    assert program.main.kind == "program" and program.subroutines["SQUARE"].kind == "local"


def test_local_subroutines_need_a_program_header():
    # seed 002 L846-L848
    # without a header the body cannot be told from the subroutine: both are reported
    assert codes("%L SUB\nG1 X1\nM17\nG1 X2\n") == [(1, 1, "STR001"), (4, 1, "STR003")]


def test_local_subroutine_after_the_body_is_an_error():
    # seed 002 L917-L918
    assert codes("%MAIN\nG1 X1\n%L SUB\nG1 X2\nM17\n") == [(3, 1, "STR002")]
    assert sorted(codes("G1 X1\n%L SUB\nM17\n")) == [(2, 1, "STR001"), (2, 1, "STR002")]


def test_local_subroutine_must_end_with_m17_m29_or_ret():
    # seed 002 L10299-L10300: M17, M29 or #RET, mandatory
    for end in ("M17", "M29", "#RET", "G0 X0 M29", "#RETDSBLK"):
        assert parse_text(f"%L S\nG1 X1\n{end}\n%P\nLL S\n").ok, end
    assert codes("%L S\nG1 X1\n%P\nLL S\n") == [(2, 1, "STR003")]
    assert codes("%L S\n%P\nLL S\n") == [(1, 1, "STR003")]


def test_subroutine_name_rules():
    # seed 002 L10276: %L + blank + 1-14 letters/digits
    assert parse_text("%L 0123456789\nM17\n%P\nM30\n").ok
    assert [c for _, _, c in codes("%L\nM17\n%P\nM30\n")] == ["SYN010"]
    assert [c for _, _, c in codes("%L ABCDEFGHIJKLMNOP\nM17\n%P\nM30\n")] == ["SYN010"]


def test_duplicate_subroutine_and_second_header():
    assert [c for _, _, c in codes("%L A\nM17\n%L A\nM17\n%P\nM30\n")] == ["STR008"]
    assert [c for _, _, c in codes("%P\nG1\n%Q\nM30\n")] == ["STR010"]


def test_jump_labels_are_indexed_per_routine():
    program = parse_text("""%L S
N5: G1 X1
[LOOP]
M17
%P
N10: G1 X2
[LOOP] G0 X0
M30
""")
    assert program.ok
    assert program.subroutines["S"].numbers == {5: 0} and program.subroutines["S"].labels == {"LOOP": 1}
    assert program.main.numbers == {10: 0} and program.main.labels == {"LOOP": 1}


def test_duplicate_jump_targets_in_one_routine():
    assert codes("N10: G1\nN10: G2\n") == [(2, 1, "STR004")]
    assert codes("[A] G1\n[A] G2\n") == [(2, 1, "STR004")]
    # a plain N10 (no colon) is not a jump target and may repeat
    assert codes("N10 G1\nN10 G2\n") == []


def test_if_elseif_else_chain_is_linked():
    program = parse_text("$IF P1==1\nG1\n$ELSEIF P1==2\nG2\n$ELSE\nG3\n$ENDIF\n")
    assert program.ok
    s = program.main.structure
    assert s[0] == 2 and s[2] == 4 and s[4] == 6 and s[6] == 0


def test_switch_cases_are_linked_and_need_break():
    ok = parse_text("$SWITCH P1\n$CASE 1\nG1\n$BREAK\n$CASE 2\n$BREAK\n$DEFAULT\nG0\n$ENDSWITCH\n")
    assert ok.ok
    s = ok.main.structure
    assert s[0] == 1 and s[1] == 4 and s[4] == 6 and s[6] == 8 and s[8] == 0
    assert s[3] == 0  # $BREAK -> its $SWITCH
    # seed 002 L17225-L17228: each $CASE ends with $BREAK
    assert codes("$SWITCH P1\n$CASE 1\nG1\n$CASE 2\n$BREAK\n$ENDSWITCH\n") == [(4, 1, "STR007")]


def test_loops_are_linked_and_break_continue_point_to_their_loop():
    program = parse_text("$FOR P1=1,3,1\n$WHILE P2<3\n$CONTINUE\n$ENDWHILE\n$BREAK\n$ENDFOR\n$DO\n$ENDDO P3<1\n")
    assert program.ok
    s = program.main.structure
    assert s[0] == 5 and s[5] == 0 and s[1] == 3 and s[3] == 1 and s[2] == 1 and s[4] == 0 and s[6] == 7


def test_unbalanced_structures():
    assert codes("$ENDIF\n") == [(1, 1, "STR005")]
    assert codes("$ELSE\n") == [(1, 1, "STR005")]
    assert codes("$CASE 1\n") == [(1, 1, "STR005")]
    assert codes("$IF P1\n") == [(1, 1, "STR006")]
    assert codes("$WHILE P1\nG1\n") == [(1, 1, "STR006")]
    assert codes("$IF P1\n$ELSE\n$ELSE\n$ENDIF\n") == [(3, 1, "STR007")]
    assert codes("$IF P1\n$ELSE\n$ELSEIF P2\n$ENDIF\n") == [(3, 1, "STR007")]


def test_crossing_structures():
    # $FOR opened inside $IF and closed after $ENDIF
    assert codes("$IF P1\n$FOR P2=1,2,1\n$ENDIF\n$ENDFOR\n") == [(2, 1, "STR006"), (4, 1, "STR005")]


def test_break_and_continue_outside_loops():
    assert codes("$BREAK\n") == [(1, 1, "STR009")]
    assert codes("$SWITCH P1\n$CASE 1\n$CONTINUE\n$BREAK\n$ENDSWITCH\n") == [(3, 1, "STR009")]


def test_if_goto_has_no_endif():
    # seed 002 L17122-L17123
    assert parse_text("$IF P1==1 $GOTO N10\nN10: G1\n").ok


def test_structure_is_checked_per_routine():
    assert codes("%L S\n$IF P1\nM17\n%P\n$ENDIF\nM30\n") == [(2, 1, "STR006"), (5, 1, "STR005")]


def test_syntax_errors_do_not_stop_the_parse_every_error_is_reported():
    text = "G1 X[1\nG1 X1\n#FOO\nP1 = SIN[1,2]\nG1 Y2\n$ENDFOR\n"
    program = parse_text(text)
    assert [(d.line, d.code) for d in program.diagnostics] == [
        (1, "SYN003"), (3, "SYN012"), (4, "SYN015"), (6, "STR005")]
    assert [b.line for b in program.blocks] == [2, 3, 4, 5, 6]


def test_crlf_line_endings():
    program = parse_text("%P\r\nG1 X1\r\nM30\r\n")
    assert program.ok and program.blocks[0].text == "G1 X1"


def test_demo_programs_parse_clean():
    files = sorted(PROGRAMS.glob("*.nc"))
    assert len(files) >= 3
    for path in files:
        program = parse_file(path)
        assert program.ok, [d.render() for d in program.diagnostics]
        if path.name.startswith("post_"):   # real CAM posts' output: their name lines warn by design
            continue
        assert not program.diagnostics, [d.render() for d in program.diagnostics]


def test_cam_style_program_parses_clean():
    # guide/implementer-notes: what CAM posts emit for a Fagor 8065
    text = """FINISH01
; FAGOR 8065 - FINISHING
N10 G71 G90 G17
N15 G159=5
N20 G159 =5
N25 #KIN ID[1]
N30 #KIN ID [1]
N35 #RTCP ON
N40 #HSC ON[CONTERROR 0.01]
N45 T1 D1 M06
N50 T5 D1 M6
N55 S12000 M03
N60 P101=600
N65 G0 X10.123456 Y-5. Z50.
N70 G1 Z-1.5 FP101
N75 G2 X20 Y0 I5 J2.5
N80 G03X10Y-5I-5J0F800
N85 G4 K1.5
N90 #MSG["FINISH DONE"]
N95 #CS ON [1] [MODE 1, 0, 0, 0, 0, 30, 0]
N100 #MCS G0 Z0
N105 G0 #MCS Z0
N110 #CS OFF
N115 #CALL L100
N120 G500
N125 G501 A60 E0.0024 J100 M1
N130 #HSC OFF
N135 #RTCP OFF
N140 M30
"""
    program = parse_text(text)
    assert program.ok, [d.render() for d in program.diagnostics]
    assert program.name == "FINISH01"
    assert len(program.blocks) == 27
