"""Every syntax form of seed 002 chapter 1 and chapter 21, with the AST it must give.

Test names follow the manual rule they check; the seed line is in the docstring
or the comment.
"""

from __future__ import annotations

import pytest
from helpers import block, codes, error_codes, items, words

from fagorcnc.syntax import parse_text
from fagorcnc.syntax.ast import (
    Binary,
    Call,
    Definition,
    Direction,
    Flow,
    Goto,
    ItemList,
    Keyed,
    Name,
    Num,
    Param,
    Repeat,
    RepeatRef,
    Sentence,
    Setting,
    Str,
    SubroutineCall,
    Unary,
    Var,
    Word,
)

# --------------------------------------------------------------------- ISO words


def test_iso_block_words_keep_source_order_and_columns():
    # seed 002 L1070: / N- G- G- X..C- F- S- T- D- M- H- NR-, no fixed order (L1021)
    b = block("N10 G90 G01 X23.45 F100 S200 M3")
    assert [(w.address, w.value, w.col) for w in b.items] == [
        ("N", 10.0, 1), ("G", 90.0, 5), ("G", 1.0, 9), ("X", 23.45, 13),
        ("F", 100.0, 20), ("S", 200.0, 25), ("M", 3.0, 30)]


def test_number_formats_sign_and_decimal_point():
    # seed 002 L1011-L1017: digits, optional sign and decimal point
    assert words("X12 Y12. Z12.5 A.5 B+12.5 C-0.5") == [
        ("X", 12.0), ("Y", 12.0), ("Z", 12.5), ("A", 0.5), ("B", 12.5), ("C", -0.5)]


def test_blanks_between_letter_sign_and_number():
    # seed 002 L1016: "G 1 X - 10.5" is "G1 X-10.5"
    assert words("G 1 X - 10.5") == [("G", 1.0), ("X", -10.5)]


def test_words_without_blanks():
    assert words("G1X10Y-2.5F800") == [("G", 1.0), ("X", 10.0), ("Y", -2.5), ("F", 800.0)]


def test_leading_zeros_are_insignificant():
    # seed 002 L6026: G0 == G00
    assert words("G00 G01 M03") == [("G", 0.0), ("G", 1.0), ("M", 3.0)]


def test_n_without_colon_may_stand_anywhere():
    # seed 002 L1045-L1047, L1075: "X34 N10 S100 M3" is legal
    assert words("X34 N10 S100 M3") == [("X", 34.0), ("N", 10.0), ("S", 100.0), ("M", 3.0)]


def test_all_iso_letters_including_function_parameters():
    assert [w[0] for w in words("G2 X1 Y2 I3 J4 K5 R6 Q7 E8 L9 H1 D2 T3 U1 V2 W3")] == list(
        "GXYIJKRQELHDTUVW")


def test_several_g_and_m_in_one_block():
    assert words("G0 G90 G17 M3 M8") == [("G", 0.0), ("G", 90.0), ("G", 17.0), ("M", 3.0), ("M", 8.0)]


def test_nr_repetition():
    # seed 002 L1129: G91 G01 X34.678 F150 NR4
    assert words("G91 G01 X34.678 F150 NR4") == [
        ("G", 91.0), ("G", 1.0), ("X", 34.678), ("F", 150.0), ("NR", 4.0)]


def test_numbered_axes_need_equals():
    # seed 002 L1218-L1221: X100, Z34.54, X2=123.4, A5=78.532
    assert words("X100 Z34.54 X2=123.4 A5 = 78.532") == [
        ("X", 100.0), ("Z", 34.54), ("X2", 123.4), ("A5", 78.532)]


def test_generic_axis_characters():
    # seed 002 L1222-L1241: ?1 = 12345.1234, ?2 = 50.34
    assert words("?1 = 12345.1234 ?2=50.34") == [("?1", 12345.1234), ("?2", 50.34)]


def test_spindle_names_with_equals():
    # seed 002 L1088-L1090, L1125: S1000, S1=334
    assert words("S1000 S1=334 S2=1000") == [("S", 1000.0), ("S1", 334.0), ("S2", 1000.0)]


def test_g_function_with_equals_value():
    # G159=5 (L3470), G263=30 (L6418); CAM posts write "G159 =5"
    b = items("G159=5")
    assert b == (Word("G", 159.0, 1, 5.0),)
    assert items("G159 =5") == (Word("G", 159.0, 1, 5.0),)
    assert items("G263=[P1*2]")[0].eq == Binary("*", Param(1, 7), Num(2.0, 10), 7)


def test_values_given_by_parameters():
    # seed 002 L1916-L1926: GP0 XP0 YP0 SP10 MP4
    b = items("GP0 XP0 YP0 SP10 MP4")
    assert [(w.address, w.value) for w in b] == [
        ("G", Param(0, 2)), ("X", Param(0, 6)), ("Y", Param(0, 10)), ("S", Param(10, 14)), ("M", Param(4, 19))]


def test_values_given_by_bracketed_expressions_and_variables():
    # seed 002 L17103 X[P0*10]; L9185 K[P1+7]; XV.A.PPOS.X
    x, k, y = items("X[P0*10] K[P1+7] YV.A.PPOS.X")
    assert x.value == Binary("*", Param(0, 3), Num(10.0, 6), 3)
    assert k.value == Binary("+", Param(1, 12), Num(7.0, 15), 12)
    assert y.value == Var("V.A.PPOS.X", (), 19)


def test_sign_in_front_of_parameter_or_bracket_negates():
    x, y = items("X-P1 Y-[P1+2]")
    assert x.value == Unary("-", Param(1, 3), 3)
    assert y.value == Unary("-", Binary("+", Param(1, 9), Num(2.0, 12), 9), 9)


def test_indirect_parameter_as_value():
    (x,) = items("XP[P2+3]")
    assert x.value == Param(Binary("+", Param(2, 4), Num(3.0, 7), 4), 2)


def test_function_as_value():
    (x,) = items("XSQRT[16]")
    assert x.value == Call("SQRT", (Num(16.0, 7),), 2)


def test_modal_oem_call_and_arguments_keep_order():
    # seed 002 L10723: words after G180 are its arguments, in order
    assert words("G01 X50 F450 G180 P0=15 P1=20") == [
        ("G", 1.0), ("X", 50.0), ("F", 450.0), ("G", 180.0), ("P0", 15.0), ("P1", 20.0)]
    assert words("MG180 A1") == [("MG", 180.0), ("A", 1.0)]


def test_tool_change_block():
    assert words("T1 D1 M06") == [("T", 1.0), ("D", 1.0), ("M", 6.0)]


def test_dwell_with_k():
    assert words("G4 K1.5") == [("G", 4.0), ("K", 1.5)]


def test_operator_outside_brackets_is_a_diagnostic():
    # spec 01 §3.6: an expression with an operator must be in [ ] as a word value
    assert codes("X P1*2") == [(1, 5, "SYN006")]


# --------------------------------------------------------------------- block layout


def test_block_skip_and_jump_target_and_label():
    # seed 002 L1052: "N20: [START] G00 X0"; L17040 "/N120 G01 X100"
    b = block("N20: [START] G00 X0")
    assert (b.skip, b.number, b.label) == (False, 20, "START")
    assert words("N20: [START] G00 X0") == [("G", 0.0), ("X", 0.0)]
    s = block("/N120 G01 X100")
    assert s.skip and s.number is None and words("/N120 G01 X100")[0] == ("N", 120.0)


def test_label_alone_and_with_plain_number():
    # seed 002 L1038: label alone on its block; L17099 "N40 [LABEL]"
    b = block("[CYCLE]")
    assert b.label == "CYCLE" and b.items == ()
    b = block("N40 [LABEL] G1 X1")
    assert b.label == "LABEL" and b.items[0] == Word("N", 40.0, 1)


def test_jump_target_may_have_blank_before_colon():
    assert block("N40 :").number == 40


def test_block_number_range():
    # seed 002 L1041: 0 ... 4294967295
    assert block("N4294967295: G1").number == 4294967295
    assert error_codes("N4294967296: G1") == ["SYN011"]


def test_slash_or_jump_target_inside_a_block_is_an_error():
    # seed 002 L1023-L1025
    assert codes("X34 N10: S100") == [(1, 5, "SYN009")]
    assert codes("G1 X10 / Y2") == [(1, 8, "SYN009")]


def test_label_longer_than_14_characters():
    # seed 002 L1048-L1050
    assert codes("[ABCDEFGHIJKLMNO] G1") == [(1, 1, "SYN010")]
    assert codes("[AB CD]") == [(1, 1, "SYN010")]
    assert block("[ABCDEFGHIJKLMN]").label == "ABCDEFGHIJKLMN"


def test_program_header_and_names():
    # seed 002 L840-L850, L873-L875
    for text, name in (("%0123", "0123"), ("%PROGRAM", "PROGRAM"), ("%PART923R", "PART923R"),
                       ("%LATHE1", "LATHE1"), ("% DEMO", "DEMO")):
        assert parse_text(text + "\nM30").name == name
    # over 14 characters: a CAM posts' name, warned per the machine's [compat] (tests/test_cam_posts.py)
    assert codes("%NAMETOOLONG12345\nM30") == [(1, 2, "CAM004")] and error_codes("%NAMETOOLONG12345\nM30") == []
    assert error_codes("%NAME*1\nM30") == ["SYN010"]


def test_bare_program_name_from_cam_post_is_accepted():
    program = parse_text("FINISH01\nG1 X1\nM30\n")
    assert program.name == "FINISH01" and program.ok
    assert [d.code for d in program.diagnostics] == ["STR011"]


# --------------------------------------------------------------------- comments


def test_parenthesis_comments_anywhere_in_a_block():
    # seed 002 L1791: N10 G90 X23.45 F100 (comment) S200 M3 (comment)
    assert words("N10 G90 X23.45 F100 (comment) S200 M3 (comment)") == [
        ("N", 10.0), ("G", 90.0), ("X", 23.45), ("F", 100.0), ("S", 200.0), ("M", 3.0)]


def test_semicolon_comment_to_end_of_line():
    # seed 002 L1793: N10 G90 X23.45 T1; comment
    assert words("N10 G90 X23.45 T1; comment") == [("N", 10.0), ("G", 90.0), ("X", 23.45), ("T", 1.0)]


def test_comment_only_lines_are_not_blocks():
    program = parse_text("; only a comment\n(another)\n   \n\nG1 X1\n")
    assert len(program.blocks) == 1 and program.blocks[0].line == 5


def test_comment_begin_end_section_is_not_parsed():
    # seed 002 L1795-L1804: the lines between are free text
    program = parse_text("G1 X1\n#COMMENT BEGIN\nP1 : Largeur de l'usinage.\nP2 : (profondeur\n"
                         "#COMMENT END\nG1 X2\n")
    assert program.ok and [b.line for b in program.blocks] == [1, 6]


def test_comment_begin_without_end():
    assert codes("#COMMENT BEGIN\nG1\n") == [(1, 1, "SYN017")]
    assert codes("G1\n#COMMENT END\n") == [(2, 1, "SYN018")]


def test_unclosed_parenthesis_comment():
    assert codes("G1 X1 (open") == [(1, 7, "SYN004")]


# --------------------------------------------------------------------- assignments and expressions


def test_several_assignments_in_one_block():
    # seed 002 L1916: P0=0 P1=1 P2=20 P3=50 P4=3
    b = items("P0=0 P1=1 P2=20 P3=50 P4=3")
    assert [(a.target.index, a.op, a.value.value) for a in b] == [
        (0, "=", 0.0), (1, "=", 1.0), (2, "=", 20.0), (3, "=", 50.0), (4, "=", 3.0)]


def test_compound_assignments():
    # seed 002 L1959-L1984
    assert [a.op for a in items("P1 += 3 P2 -= 5 P3 *= 2 P4 /= 9")] == ["+=", "-=", "*=", "/="]


def test_indirect_parameter_assignment_and_variables():
    # seed 002 L2115-L2126
    _a, b, c = items("P100 = P9 P101 = P[P7] P102 = P[P8 + SIN[P8*20]]")
    assert b.value == Param(Param(7, 20), 18)
    assert c.value.index == Binary("+", Param(8, 33), Call("SIN", (Binary("*", Param(8, 42), Num(20.0, 45), 42),),
                                                             38), 33)
    assert items("P103 = V.G.TOOL")[0].value == Var("V.G.TOOL", (), 8)
    fx, _fy = items("V.G.FIXT[1].X=20 V.G.FIXT[1].Y=40")
    assert fx.target == Var("V.G.FIXT[].X", (Num(1.0, 10),), 1)
    assert items("P[P2] = 5")[0].target == Param(Param(2, 3), 1)


def test_channel_and_user_variables():
    (a,) = items("V.[2].G.FIX = 1")
    assert a.target == Var("V.[].G.FIX", (Num(2.0, 4),), 1)
    assert items("V.P.my_var = 3")[0].target.name == "V.P.my_var"
    assert items("V.S.GLOBAL1 = V.A.ORGT[1].Z")[0].value == Var("V.A.ORGT[].Z", (Num(1.0, 24),), 15)


def _value(expr: str):
    return items(f"P1 = {expr}")[0].value


def _fold(node):
    """Evaluate a parsed expression tree on numbers (test oracle for precedence)."""
    if type(node) is Num:
        return node.value
    if type(node) is Unary:
        return -_fold(node.operand)
    a, b = _fold(node.left), _fold(node.right)
    ops = {"+": lambda: a + b, "-": lambda: a - b, "*": lambda: a * b, "/": lambda: a / b,
           "**": lambda: a**b, "MOD": lambda: a % b,
           "&": lambda: int(a) & int(b), "|": lambda: int(a) | int(b), "^": lambda: int(a) ^ int(b),
           "==": lambda: float(a == b), "!=": lambda: float(a != b), ">": lambda: float(a > b),
           "<": lambda: float(a < b), ">=": lambda: float(a >= b), "<=": lambda: float(a <= b)}
    return ops[node.op]()


@pytest.mark.parametrize(("expr", "result"), [
    ("3+4", 7), ("5-2", 3), ("-[3+4]", -7), ("2*3", 6), ("9/2", 4.5), ("5 MOD 2", 1), ("2**3", 8),
    ("2**3**2", 64),            # ** associates left to right (seed 002 L2143-L2157)
    ("-2**2", 4),               # unary minus binds tighter than **
    ("2 * 7 MOD 4", 6),         # MOD above *
    ("6 & 3 ^ 1", 3),           # & and ^ share a level
    ("1 | 6 & 4", 5),           # | below &
    ("1 | 2 == 2", 1),          # relational between arithmetic and bitwise
    ("8/4/2", 1), ("10-4-3", 3),
    ("1 + 2 * 3", 7),
    ("[1 == 1] * [2 >= 5]", 0), ("[1 == 1] + [2 >= 5]", 1),
])
def test_operator_precedence(expr, result):
    assert _fold(_value(expr)) == result


def test_relational_operators_are_left_associative():
    # seed 002 L1956-L1957: P11 == 1 * P12 >= 5 parses as [P11 == [1*P12]] >= 5
    v = _value("P11 == 1 * P12 >= 5")
    assert v.op == ">=" and v.left.op == "==" and v.left.right.op == "*"


def test_hexadecimal_and_boolean_constants():
    # seed 002 L1814: $4A = 74; L2034: TRUE FALSE
    assert _value("$4A") == Num(74.0, 6)
    assert _value("TRUE") == Num(1.0, 6) and _value("FALSE") == Num(0.0, 6)


@pytest.mark.parametrize("name", ["SIN", "COS", "TAN", "ASIN", "ACOS", "ATAN", "ABS", "SQR", "SQRT",
                                  "LOG", "LN", "EXP", "DEXP", "INT", "FRACT", "ROUND", "FUP", "INV"])
def test_every_one_argument_function(name):
    assert _value(f"{name}[0.5]") == Call(name, (Num(0.5, 7 + len(name)),), 6)


def test_arg_and_exist_functions():
    assert _value("ARG[-1,1]") == Call("ARG", (Num(-1.0, 11), Num(1.0, 13)), 6)
    assert _value("EXIST[P1]") == Call("EXIST", (Param(1, 12),), 6)
    assert _value("EXIST[V.S.X]").args == (Var("V.S.X", (), 12),)


def test_function_argument_count_is_checked():
    assert error_codes("P1 = SIN[1, 2]") == ["SYN015"]
    assert error_codes("P1 = ARG[1]") == ["SYN015"]
    assert error_codes("P1 = EXIST[3]") == ["SYN015"]


def test_redundant_brackets_are_harmless():
    # seed 002 L2107-L2109
    assert _fold(_value("[[[2]]] * [[3]]")) == 6


# --------------------------------------------------------------------- # sentences


def test_hsc_on_with_conterror_without_space():
    (s,) = items("#HSC ON[CONTERROR 0.01]")
    assert s == Sentence("HSC", (Keyed("ON", ItemList(((Keyed("CONTERROR", Num(0.01, 19), 9),),), 9), 6),), 1)


def test_hsc_modes_and_off():
    (s,) = items("#HSC ON [FAST 80, E 0.01, CORNER 150]")
    seqs = s.args[0].value.items
    assert [x[0].name for x in seqs] == ["FAST", "E", "CORNER"]
    assert items("#HSC OFF") == (Sentence("HSC", (Name("OFF", 6),), 1),)


def test_kin_id_with_and_without_space():
    assert items("#KIN ID[1]")[0].args == (Keyed("ID", Num(1.0, 9), 6),)
    assert items("#KIN ID [1]")[0].args == (Keyed("ID", Num(1.0, 10), 6),)


def test_rtcp_and_cs():
    assert items("#RTCP ON") == (Sentence("RTCP", (Name("ON", 7),), 1),)
    (cs,) = items("#CS ON [1] [MODE 1, 0, 0, 0, 0, 30, 0]")
    assert cs.args[0] == Keyed("ON", Num(1.0, 9), 5)
    assert cs.args[1].items[0] == (Keyed("MODE", Num(1.0, 18), 13),) and len(cs.args[1].items) == 7


def test_mcs_after_and_before_iso_words():
    assert items("G0 #MCS Z0") == (Word("G", 0.0, 1), Sentence("MCS", (Keyed("Z", Num(0.0, 10), 9),), 4))
    assert items("#MCS G0 Z10")[0].args == (Keyed("G", Num(0.0, 7), 6), Keyed("Z", Num(10.0, 10), 9))


def test_messages_errors_and_strings():
    (m,) = items('#MSG["Tool %D", P1]')
    assert m.args == (ItemList(((Str("Tool %D", 6),), (Param(1, 17),)), 6),)
    assert items("#ERROR [1000]")[0].args == (Num(1000.0, 9),)


def test_time_dwell_both_forms():
    # seed 002 L9166-L9190: #TIME 5 / #TIME [5]
    assert items("#TIME 5")[0].args == (Num(5.0, 7),)
    assert items("#TIME [5]")[0].args == (Num(5.0, 8),)


def test_slope_with_omitted_arguments():
    (s,) = items("#SLOPE [2,,,1]")
    assert s.args[0].items == ((Num(2.0, 9),), (), (), (Num(1.0, 13),))


def test_swtout_settings_with_blanks():
    (s,) = items("#SWTOUT ON [TON=50 TOF=40]")
    assert s.args[0].value.items == ((Setting("TON", Num(50.0, 17), 13), Setting("TOF", Num(40.0, 24), 20)),)


def test_move_inf_direction():
    (s,) = items("#MOVE INF [X+, F100]")
    assert s.args[0].value.items[0] == (Direction("X", "+", 12),)


def test_poly_nested_lists():
    (s,) = items("#POLY [X[1,2,3,4,5] Y[1,2,3,4,5] SP0 EP10]")
    first = s.args[0].items[0]
    assert [i.name for i in first] == ["X", "Y", "SP", "EP"] and len(first[0].value.items) == 5


def test_def_macro_and_delete_variables():
    assert items('#DEF "HOLE"="G81 Z-5"')[0].args == (Definition("HOLE", "G81 Z-5", 6),)
    assert items("#DELETE V.S.A V.S.B")[0].args == (Var("V.S.A", (), 9), Var("V.S.B", (), 15))
    # seed 002 L1844: #DELETE alone is an error
    assert error_codes("#DELETE") == ["SYN013"]


def test_axis_configuration_sentences():
    assert items("#CALL AX [X, Y]")[0].keyword == "CALL AX"
    assert items("#FREE AX ALL")[0].args == (Name("AX", 7), Name("ALL", 10))
    assert items("#SET AX [X, Y, Z]")[0].keyword == "SET"
    assert items("#RENAME AX [X, X1]")[0].keyword == "RENAME"


def test_every_catalogued_sentence_keyword_parses():
    from fagorcnc.syntax.sentences import NO_ARGUMENTS, SENTENCES

    for kw, allowed in SENTENCES.items():
        if kw in ("COMMENT",):
            continue
        text = f"#{kw}" + ("" if kw in NO_ARGUMENTS else f" {sorted(allowed)[0]}" if allowed else " [1]")
        if kw == "DELETE":
            text = "#DELETE V.P.A"
        assert items(text)[0].keyword == kw, text


def test_unknown_sentence_and_missing_keyword():
    assert codes("#FOO ON") == [(1, 1, "SYN012")]
    assert codes("#HSC") == [(1, 1, "SYN013")]
    assert codes("#TOOL XX") == [(1, 1, "SYN013")]


def test_two_sentences_in_one_block():
    # seed 002 L1172-L1178
    assert codes("#HSC ON #KIN ID[1]") == [(1, 9, "SYN007")]


def test_sentence_after_iso_words_must_be_mcs_or_axis():
    assert error_codes("G1 X1 #HSC OFF") == ["SYN014"]
    assert items("N110 G201 #AXIS [X, Z]")[2].keyword == "AXIS"


def test_block_number_before_sentence_and_flow():
    # seed 002 L17142 "N20 $IF ..."; L16291 "N10: $FOR P1=1,10,1"
    assert items("N45 #KIN ID[1]")[0] == Word("N", 45.0, 1)
    b = block("N10: $FOR P1=1,10,1")
    assert b.number == 10 and type(b.items[0]) is Flow
    assert items("N10 P0=10")[1].target == Param(0, 5)


# --------------------------------------------------------------------- subroutine calls


def test_local_and_global_calls():
    # seed 002 L10314-L10660
    assert items("LL POINTS") == (SubroutineCall("LL", "POINTS", (), 1),)
    assert items("L Sub3.nc") == (SubroutineCall("L", "Sub3.nc", (), 1),)
    assert items(r"L C:\Cnc8070\Users\Prg\sub1.nc")[0].target == r"C:\Cnc8070\Users\Prg\sub1.nc"


def test_call_pcall_mcall_mdoff_ret():
    assert items("#CALL L100") == (SubroutineCall("CALL", "L100", (), 1),)
    (p,) = items("#PCALL Sub3.nc A12.3 F45.3 P10=6")
    assert p == SubroutineCall("PCALL", "Sub3.nc", (Word("A", 12.3, 16), Word("F", 45.3, 22),
                                                   Word("P10", 6.0, 28)), 1)
    assert items("#MCALL CNT A[P1+1]")[0].args[0].value == Binary("+", Param(1, 14), Num(1.0, 17), 14)
    assert items("#MDOFF")[0] == Sentence("MDOFF", (), 1)
    assert items("#RET")[0] == Sentence("RET", (), 1)
    assert items('#PATH ["C:\\Cnc8070\\Users\\Prg\\"]')[0].args[0].items[0][0].text == "C:\\Cnc8070\\Users\\Prg\\"


def test_call_sentences_stand_alone():
    assert error_codes("G1 X1 #CALL SUB") == ["SYN014"]
    assert error_codes("#CALL SUB A1") == ["SYN002"]  # #CALL passes no parameters


def test_rpt_with_numbers_and_labels():
    # seed 002 L16203: #RPT [N10, N20, 2]
    assert items("#RPT [N10, N20, 2]")[0] == Repeat(RepeatRef(10.0, None, 7), RepeatRef(20.0, None, 12),
                                                    Num(2.0, 17), 1)
    r = items("#RPT [[START], [END]]")[0]
    assert (r.start.label, r.end.label, r.count) == ("START", "END", None)


# --------------------------------------------------------------------- $ flow control


def test_flow_instructions():
    text = """$IF P1==1
$ELSEIF P1 > 2
$ELSE
$ENDIF
$SWITCH P2
$CASE 1
$BREAK
$DEFAULT
$ENDSWITCH
$FOR P1 = 0, 10, 2
$CONTINUE
$ENDFOR
$WHILE P0<=10
$BREAK
$ENDWHILE
$DO
$ENDDO P3 < 4
$GOTO N10
N10:
$GOTO [END]
[END]
"""
    program = parse_text(text)
    assert program.ok, [str(d) for d in program.diagnostics]
    kws = [b.items[0].keyword for b in program.blocks if b.items]
    assert kws == ["IF", "ELSEIF", "ELSE", "ENDIF", "SWITCH", "CASE", "BREAK", "DEFAULT", "ENDSWITCH", "FOR",
                   "CONTINUE", "ENDFOR", "WHILE", "BREAK", "ENDWHILE", "DO", "ENDDO", "GOTO", "GOTO"]
    f = program.blocks[9].items[0]
    assert f.args == (Param(1, 6), Num(0.0, 11), Num(10.0, 14), Num(2.0, 18))


def test_if_goto_on_one_line():
    # seed 002 L17075-L17078: N50 $IF P0==1 $GOTO N100
    (f,) = items("$IF P0==1 $GOTO N100")[0:1]
    assert f.args[1] == Goto(100.0, None, 17)
    assert items("$IF P0==1 $GOTO [DONE]")[0].args[1] == Goto(None, "DONE", 17)


def test_goto_number_forms():
    # seed 002 L17048: $GOTO N{expr}, also with colon, parameter or expression
    assert items("$GOTO N40:")[0].args == (Goto(40.0, None, 7),)
    assert items("$GOTO NP1")[0].args == (Goto(Param(1, 8), None, 7),)
    assert items("$GOTO N[P1*10]")[0].args[0].number == Binary("*", Param(1, 9), Num(10.0, 12), 9)


def test_flow_keyword_followed_by_letter_is_not_a_keyword():
    # spec 01 §7.4: $DEFAULTX is not $DEFAULT
    assert codes("$DEFAULTX") == [(1, 1, "SYN022")]
    assert codes("N10 $ENDIFF") == [(1, 5, "SYN022")]


def test_flow_instruction_must_be_alone():
    assert codes("$IF P1 $ELSE") == [(1, 8, "SYN008")]
    assert error_codes("G1 X1 $ENDIF") == ["SYN008"]


def test_for_with_variable_and_negative_step():
    # seed 002 L17291: $FOR V.P.VAR_NAME=20,15,-1
    f = items("$FOR V.P.VAR_NAME=20,15,-1")[0]
    assert f.args[0] == Var("V.P.VAR_NAME", (), 6) and f.args[3] == Num(-1.0, 26)


def test_manual_while_goto_example_parses():
    # seed 002 L17099-L17107
    program = parse_text("""N10 P0=10
N20 $WHILE P0<=10
N30 G01 X[P0*10] F400
N40 P0=P0-1
N50 $IF P0==1 $GOTO N100
N60 $ENDWHILE
N100: G00 Y30
M30
""")
    assert program.ok
    assert program.main.numbers == {100: 6}
    assert program.main.structure[1] == 5 and program.main.structure[5] == 1
