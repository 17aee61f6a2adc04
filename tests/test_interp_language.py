"""Interpreter tests for the language: parameters, operators, functions, flow
control, subroutines and the F S T D M H words.

Every expected value is worked by hand from the French manual (seed 002, cited
by line) or from the specification in ``/work/shared/spec/fagor`` where the
manual is silent (marked "[rec]": a recommendation of the spec).
"""

from __future__ import annotations

import math

import pytest

import fagorcnc
from fagorcnc.diagnostics import CODES

MOTION = ("rapid", "linear", "arc")


# ----------------------------------------------------------------------------- helpers
def run(text: str, machine=None, **kw):
    r = fagorcnc.simulate(text, machine, **kw)
    for d in r.diagnostics:
        assert d.code in CODES, d
    return r


def value(expr: str) -> float:
    """Value of ``expr`` assigned to P1 (``P1 = expr``)."""
    r = run(f"P1 = {expr}\nM30\n")
    assert r.ok, [str(d) for d in r.diagnostics]
    return r.state.param(1)


def motions(r) -> list:
    return [m for m in r.moves if m.kind in MOTION]


def aux(r, function: str | None = None) -> list:
    return [m for m in r.moves if m.kind == "aux" and (function is None or m.function == function)]


def errors(r) -> list[tuple[str, int]]:
    return [(d.code, d.line) for d in r.diagnostics if d.is_error]


def codes(r) -> list[str]:
    return [d.code for d in r.diagnostics]


def ok(r):
    assert r.ok, [str(d) for d in r.diagnostics]
    return r


# ============================================================================ 1. operators
@pytest.mark.parametrize(
    ("expr", "expected"),
    [
        ("3+4", 7),            # L1959: P1 = 3+4 -> 7
        ("5-2", 3),            # L1964/L1967: P2 = 5-2 -> 3
        ("-[3+4]", -7),        # L1965/L1968: unary minus -> -7
        ("2*3", 6),            # L1970
        ("9/2", 4.5),          # L1972: real division
        ("5 MOD 2", 1),        # L1974: 5 = 2*2 + 1
        ("2**3", 8),           # L1976: 2*2*2
    ],
)
def test_arithmetic_operators_follow_the_manual_examples_l1959_l1976(expr, expected):
    assert value(expr) == pytest.approx(expected)


@pytest.mark.parametrize(
    ("expr", "expected"),
    [
        ("2**3**2", 64),       # L2147 ** left to right: (2**3)**2 = 8**2 = 64
        ("-2**2", 4),          # L2145 unary minus above **: (-2)**2 = 4
        ("2*7 MOD 4", 6),      # L2147 MOD above *: 2*(7 MOD 4) = 2*3 = 6
        ("7 MOD 4 * 2", 6),    # (7 MOD 4)*2 = 6
        ("2+3*4", 14),         # L2149/L2151: 2 + 12
        ("10-4-3", 3),         # left to right: (10-4)-3
        ("8/4/2", 1),          # left to right: (8/4)/2
        ("4 | 2 == 2", 5),     # L2153/L2157: relational above |: 4 | (2==2) = 4|1 = 5
        ("6 & 3 ^ 1", 3),      # L2155 & and ^ share a level: (6&3)^1 = 2^1 = 3
        ("1 | 6 & 4", 5),      # L2157 | lowest: 1 | (6&4) = 1|4 = 5
        ("2 == 1+1", 1),       # + above ==: 2 == 2
    ],
)
def test_precedence_and_associativity_table_l2143_l2157(expr, expected):
    assert value(expr) == pytest.approx(expected)


def test_manual_bracketing_example_gives_the_same_value_l2111():
    # L2111-L2112: P4/P5 - P6*P7 - P8/P9 == [P4/P5] - [P6*P7] - [P8/P9]
    # 9/3 - 2*4 - 10/5 = 3 - 8 - 2 = -7
    r = ok(run("P4=9 P5=3 P6=2 P7=4 P8=10 P9=5\nP3 = P4/P5 - P6 * P7 - P8/P9\n"
               "P10 = [P4/P5] - [P6 * P7] - [P8/P9]\nM30\n"))
    assert r.state.param(3) == pytest.approx(-7)
    assert r.state.param(10) == pytest.approx(-7)


@pytest.mark.parametrize(
    ("expr", "expected"),
    [
        ("4 == 4", 1), ("4 == 5", 0),      # L1986
        ("2 != 5", 1), ("5 != 5", 0),      # L1988
        ("10 >= 10", 1), ("9 >= 10", 0),   # L1990
        ("7 <= 7", 1), ("8 <= 7", 0),      # L1992
        ("6 > 5", 1), ("5 > 5", 0),        # L1994
        ("4 < 5", 1), ("5 < 5", 0),        # L1996
    ],
)
def test_relational_operators_give_1_or_0_l1986_l1996(expr, expected):
    # [rec] spec 01 §11.2: true = 1, false = 0
    assert value(expr) == expected


@pytest.mark.parametrize(
    ("expr", "expected"),
    [
        ("[1 == 1] * [7 >= 5]", 1),   # L2006 logical AND: 1*1
        ("[1 == 1] * [2 >= 5]", 0),   # 1*0
        ("[0 != 0] + [8 == 8]", 1),   # L2008 logical OR: 0+1
        ("[0 != 0] + [2 == 8]", 0),   # 0+0
        ("TRUE", 1),                  # L2034
        ("FALSE", 0),                 # L2036
        ("[3 > 2] == TRUE", 1),
    ],
)
def test_logical_operators_and_boolean_constants_l2006_l2036(expr, expected):
    assert value(expr) == expected


@pytest.mark.parametrize(
    ("expr", "expected"),
    [
        ("12 & 10", 8),            # L1998: 1100 & 1010 = 1000
        ("12 | 10", 14),           # L2000: 1100 | 1010 = 1110
        ("12 ^ 10", 6),            # L2002: 1100 ^ 1010 = 0110
        ("12.7 & 10.9", 8),        # L1949: the decimal part is ignored -> 12 & 10
        ("$4A | 1", 75),           # L1814 hex constant $4A = 74; 74 | 1 = 75
        ("INV[0]", 4294967295),    # L2004, [rec] 32-bit: 0xFFFFFFFF - 0
        ("INV[4294967295]", 0),
        ("INV[$FFFF0000]", 65535),  # 0xFFFFFFFF - 0xFFFF0000
    ],
)
def test_bitwise_operators_on_integers_l1998_l2004(expr, expected):
    assert value(expr) == expected


@pytest.mark.parametrize(
    ("expr", "code"),
    [
        ("0 ** -1", "INT032"),        # [rec] spec 01 §11.1: power results that are not real -> error
        ("[-8] ** [1/3]", "INT032"),
        ("-1 & 3", "INT031"),         # [rec] spec 01 §11.3: negative operands rejected
        ("INV[-1]", "INT031"),
        ("EXP[1000]", "INT030"),      # e**1000 overflows a double
    ],
)
def test_power_bitwise_and_overflow_errors(expr, code):
    r = run(f"P1 = {expr}\nM30\n")
    assert errors(r) == [(code, 1)]


def test_mod_takes_the_sign_of_the_dividend():
    # [rec] spec 01 §11.1: a MOD b = a - b*trunc(a/b): -7 - 3*(-2) = -1; 7 - (-3)*(-2) = 1
    assert value("-7 MOD 3") == -1
    assert value("7 MOD -3") == 1


def test_relational_operators_sit_below_multiplication_l1956_l1957():
    # L1956-L1957: without brackets "P11 == 1 * P12 >= 5" is [P11 == [1*P12]] >= 5;
    # P11 = 1, P12 = 7: [1 == 7] = 0, 0 >= 5 -> 0 (the bracketed form gives 1)
    r = ok(run("P11=1\nP12=7\nP1 = P11 == 1 * P12 >= 5\nP2 = [P11 == 1] * [P12 >= 5]\nM30\n"))
    assert (r.state.param(1), r.state.param(2)) == (0, 1)


def test_comparisons_are_exact_l2133():
    # L2133: [P8==12.6]; [rec] spec 01 §11.2: no tolerance, so 0.1+0.2 == 0.3 is false in doubles
    r = ok(run("P8=12.6\nP1 = [P8==12.6]\nP2 = [0.1+0.2 == 0.3]\nM30\n"))
    assert (r.state.param(1), r.state.param(2)) == (1, 0)


def test_unary_plus_and_minus_after_an_operator():
    # [rec] spec 01 §12.2: unary plus accepted; 3 + -2 = 1
    assert value("+5") == 5
    assert value("3 + -2") == 1


def test_common_parameters_are_readable_and_writable_l1897_l1904():
    r = ok(run("P10000 = 3\nP1 = P10000 + 1\nM30\n"))
    assert r.state.param(1) == 4


# ============================================================================ functions
@pytest.mark.parametrize(
    ("expr", "expected"),
    [
        ("SIN[30]", 0.5),                     # L2038
        ("COS[30]", math.sqrt(3) / 2),        # L2040: 0.866
        ("TAN[30]", 1 / math.sqrt(3)),        # L2042: 0.5773
        ("ASIN[1]", 90),                      # L2044
        ("ACOS[1]", 0),                       # L2046
        ("ATAN[1]", 45),                      # L2048
        ("ATAN[-1]", -45),                    # L2052: result within +-90
        ("ABS[-10]", 10),                     # L2056
        ("SQR[4]", 16),                       # L2058: square, 4*4
        ("SQRT[16]", 4),                      # L2060
        ("LOG[100]", 2),                      # L2062: 10**2 = 100
        ("LN[100]", math.log(100)),           # L2064: 4.6051
        ("EXP[1]", math.e),                   # L2066: 2.7182
        ("DEXP[2]", 100),                     # L2068: 10**2
        ("INT[4.92]", 4),                     # L2070
        ("FRACT[1.56]", 0.56),                # L2072: 1.56 - 1
        ("ROUND[3.12]", 3),                   # L2077/L2080
        ("ROUND[4.89]", 5),                   # L2078/L2081
        ("FUP[3.12]", 4),                     # L2087/L2090: integer part + 1
        ("FUP[9]", 9),                        # L2088/L2091: already an integer
        ("INT[-4.92]", -4),                   # [rec] spec 01 §11.5: truncation toward zero
        ("FRACT[-1.56]", -0.56),              # [rec] x - INT[x]
        ("ROUND[2.5]", 3),                    # [rec] half away from zero
        ("ROUND[-2.5]", -3),
        ("FUP[-3.12]", -3),                   # [rec] ceiling
        ("SIN[P9 + 30]", 0.5),                # expression argument (P9 = 0 below)
    ],
)
def test_functions_follow_the_manual_examples_l2038_l2091(expr, expected):
    r = ok(run(f"P9=0\nP1 = {expr}\nM30\n"))
    assert r.state.param(1) == pytest.approx(expected, abs=1e-12)


@pytest.mark.parametrize(
    ("x", "y", "expected"),
    [
        (1, 1, 45),       # atan2(1, 1)
        (-1, 1, 135),     # second quadrant
        (-1, -1, 225),    # L2050 prints ARG[-1,1]=225; 225 is the angle of (-1,-1) (spec 01 §11.5)
        (1, -1, 315),     # negative angle -45 normalised into [0, 360)
        (0, -1, 270),
        (1, 0, 0),
        (-1, 0, 180),
    ],
)
def test_arg_is_atan2_of_y_x_in_0_360_l2050_l2054(x, y, expected):
    assert value(f"ARG[{x},{y}]") == pytest.approx(expected)


def test_exist_tells_whether_a_parameter_has_a_value_l2031_l2096():
    # L2093-L2097: EXIST[P1]; EXIST[P3] == FALSE; the argument is not evaluated
    r = ok(run("P1=5\nP10 = EXIST[P1]\nP11 = EXIST[P3]\nP12 = EXIST[P3] == FALSE\n"
               "V.P.here = 1\nP13 = EXIST[V.P.here]\nP14 = EXIST[V.P.nothere]\nM30\n"))
    assert [r.state.param(n) for n in (10, 11, 12, 13, 14)] == [1, 0, 1, 1, 0]


def test_if_exist_equals_if_exist_true_l2031():
    # "$IF EXIST[P1] == TRUE" is the same as "$IF EXIST[P1]"
    r = ok(run("P1=0\nP2=0\nP3=0\n$IF EXIST[P1]\nP2=1\n$ENDIF\n$IF EXIST[P1] == TRUE\nP3=1\n$ENDIF\n"
               "$IF EXIST[P4]\nP2=9\n$ENDIF\nM30\n"))
    assert (r.state.param(2), r.state.param(3)) == (1, 1)


def test_parameters_give_the_value_of_every_iso_word_l1916_l1926():
    # L1916-L1926: GP0 XP0 YP0 SP10 MP4 == G0 X0 Y0 S1500 M3; GP1 XP2 YP3 FP100 == G1 X20 Y50 F800;
    # MP101 == M30
    r = run("P0=0 P1=1 P2=20 P3=50 P4=3\nP10=1500 P100=800 P101=30\nGP0 XP0 YP0 SP10 MP4\n"
            "GP1 XP2 YP3 FP100\nMP101\n")
    ok(r)
    m = motions(r)
    assert [x.kind for x in m] == ["rapid", "linear"]
    assert (m[1].end_part["X"], m[1].end_part["Y"], m[1].feed) == (20, 50, 800)
    assert [(a.function, a.value) for a in aux(r)] == [("S", 1500), ("M", 3), ("M", 30)]
    assert r.ended_by == "M30"


# ============================================================================ 2. domain errors
@pytest.mark.parametrize(
    ("expr", "code"),
    [
        ("1/0", "INT033"),            # [rec] spec 01 E18: division by zero
        ("5 MOD 0", "INT033"),        # E18: MOD 0
        ("SQRT[-4]", "INT032"),       # L2027: the argument must be positive
        ("ASIN[2]", "INT032"),        # L2017: between -1 and 1
        ("ACOS[-1.5]", "INT032"),     # L2017
        ("LOG[0]", "INT032"),         # L2025: greater than zero
        ("LN[-1]", "INT032"),         # L2025
        ("TAN[90]", "INT032"),        # L2015: not ..., -90, 90, 270, ...
        ("TAN[-90]", "INT032"),
        ("TAN[270]", "INT032"),
        ("ARG[0,0]", "INT032"),       # [rec] spec 01 E18
        ("P7 + 1", "INT040"),         # [rec] E19: P7 never assigned
        ("P500", "INT041"),           # L1894: global range P100..P299 on this machine
        ("P20000", "INT041"),         # L1903: P20000 and above never exist
        ("V.A.NOSUCH.X", "INT044"),   # unknown variable
        ("V.G.NOSUCH", "INT044"),
        ("V.P.never", "INT043"),      # [rec] spec 01 §9.3: user variable read before it exists
    ],
)
def test_domain_errors_stop_the_run_on_the_block_line(expr, code):
    r = run(f"G00 X1\nP1 = {expr}\nG00 X2\nM30\n")
    assert errors(r) == [(code, 2)]
    assert not r.ok
    # the run stops at the error: the G00 X2 of line 3 and the M30 are not executed
    assert [m.end_part["X"] for m in motions(r)] == [1]
    assert aux(r) == []
    assert r.ended_by is None


@pytest.mark.parametrize(
    "block",
    [
        "P1 = 1\nP1 /= 0",                # compound division by zero
        "P1 = 2 * [3 / [P2 - P2]]",        # P2 = 0 below; nested
    ],
)
def test_division_by_zero_in_other_forms(block):
    r = run(f"P2 = 4\n{block}\nG00 X2\nM30\n")
    assert [c for c, _ in errors(r)] == ["INT033"]
    assert motions(r) == []


def test_writing_a_read_only_variable_is_an_error_l1809_l1812():
    # L1811-L1812: a read-only variable is a constant; V.A.POS.X is read-only (L35803)
    r = run("G00 X1\nV.A.POS.X = 5\nG00 X2\nM30\n")
    assert errors(r) == [("INT048", 2)]
    assert [m.end_part["X"] for m in motions(r)] == [1]


def test_writing_a_parameter_out_of_range_is_an_error_l1882_l1903():
    r = run("P1=1\nP500 = 3\nG00 X2\nM30\n")
    assert errors(r) == [("INT041", 2)]
    assert motions(r) == []


def test_undefined_parameter_in_an_iso_word_stops_before_the_move():
    # [rec] E19; the block with the error moves nothing
    r = run("G00 X1\nG00 XP3\nM30\n")
    assert errors(r) == [("INT040", 2)]
    assert len(motions(r)) == 1


def test_only_the_first_error_is_reported():
    r = run("P1 = 1/0\nP2 = SQRT[-1]\nM30\n")
    assert errors(r) == [("INT033", 1)]


# ============================================================================ 3. assignments
def test_compound_assignments_l1978_l1984():
    # 10 +3 = 13; -5 = 8; *2 = 16; /4 = 4
    r = ok(run("P1 = 10\nP1 += 3\nP2 = P1\nP1 -= 5\nP3 = P1\nP1 *= 2\nP4 = P1\nP1 /= 4\nM30\n"))
    assert [r.state.param(n) for n in (2, 3, 4, 1)] == [13, 8, 16, 4]


def test_compound_assignment_on_a_user_variable_l1933():
    # L1936-L1938: the operators work on parameters and variables; 2.5 * 4 = 10
    r = ok(run("V.P.acc = 2.5\nV.P.acc *= 4\nP1 = V.P.acc\nM30\n"))
    assert r.state.param(1) == 10


def test_compound_assignment_of_an_undefined_parameter_is_an_error():
    r = run("P1 += 3\nM30\n")
    assert errors(r) == [("INT040", 1)]


def test_indirect_parameter_addressing_l1910_l1911():
    # P1=3: P[P1] is P3; P[P1+2] is P5; P[P2+3] with P2=4 is P7
    r = ok(run("P1 = 3\nP2 = 4\nP[P1] = 42\nP[P1+2] = P3 + 1\nP[P2+3] = P[P1] * 2\nM30\n"))
    assert (r.state.param(3), r.state.param(5), r.state.param(7)) == (42, 43, 84)


def test_indirect_index_not_integer_is_an_error():
    # [rec] spec 01 §10.2: the index must evaluate to an integer
    r = run("P1 = 2.5\nP[P1] = 1\nM30\n")
    assert [c for c, _ in errors(r)] == ["INT035"]


def test_several_assignments_in_one_block_run_left_to_right_l2122():
    # L2122: "P100 = P9 P101 = P[P7] P102 = P[P8 + SIN[P8*20]]" in one block
    # P7=9 -> P101 = P9 = 2; P8=0 -> P[0 + SIN[0]] = P0 = 6; then P103 uses P100 set in the same block
    r = ok(run("P0 = 6\nP7 = 9\nP8 = 0\nP9 = 2\n"
               "P100 = P9 P101 = P[P7] P102 = P[P8 + SIN[P8*20]] P103 = P100 + 1\nM30\n"))
    assert [r.state.param(n) for n in (100, 101, 102, 103)] == [2, 2, 6, 3]


def test_user_variables_local_and_global_l1821_l1860():
    r = ok(run("V.P.mylocalvar = 3\nV.S.myglobalvar = V.P.mylocalvar * 2\nP1 = V.S.myglobalvar + 1\nM30\n"))
    assert r.state.param(1) == 7          # 3*2 + 1
    assert r.state.var("V.P.mylocalvar") == 3
    assert r.state.var("V.S.myglobalvar") == 6


def test_delete_removes_user_variables_l1839_l1860():
    # L1860: #DELETE V.S.globalvar1 V.S.globalvar2 (several variables separated by blanks)
    r = ok(run("V.S.globalvar1 = 1\nV.S.globalvar2 = 2\nV.P.loc = 3\n#DELETE V.S.globalvar1 V.S.globalvar2\n"
               "P1 = EXIST[V.S.globalvar1] + EXIST[V.S.globalvar2]\nP2 = EXIST[V.P.loc]\n#DELETE V.P.loc\n"
               "P3 = EXIST[V.P.loc]\nM30\n"))
    assert (r.state.param(1), r.state.param(2), r.state.param(3)) == (0, 1, 0)


def test_reading_a_deleted_user_variable_is_an_error():
    r = run("V.S.gone = 1\n#DELETE V.S.gone\nP1 = V.S.gone\nM30\n")
    assert errors(r) == [("INT043", 3)]


def test_delete_of_a_parameter_is_an_error():
    r = run("P1 = 1\n#DELETE V.A.POS.X\nM30\n")
    assert [c for c, _ in errors(r)] == ["INT049"]


# ============================================================================ 4. NR
def test_nr_repeats_an_incremental_move_l1129():
    # L1129: G91 G01 X34.678 F150 NR4 -> 4 moves of 34.678: 4 * 34.678 = 138.712
    r = ok(run("G00 X10\nG91 G01 X34.678 F150 NR4\nM30\n"))
    lin = [m for m in motions(r) if m.kind == "linear"]
    assert len(lin) == 4
    assert [round(m.end_part["X"], 4) for m in lin] == [44.678, 79.356, 114.034, 148.712]
    assert r.state.position("part")["X"] == pytest.approx(10 + 138.712)


def test_nr_under_g90_repeats_to_the_same_point():
    # spec 01 §3.5: under G90 the repetitions go to the same absolute point
    r = ok(run("G90 G01 X20 F100 NR3\nM30\n"))
    assert [m.end_part["X"] for m in motions(r)] == [20, 20, 20]


@pytest.mark.parametrize("block", ["G01 F100 NR3", "P1 = 1\nM3 NR2", "G04 K1 NR2"])
def test_nr_in_a_block_without_motion_is_an_error_l1111(block):
    # L1111-L1112: NR only in blocks with a movement
    r = run(f"{block}\nG00 X1\nM30\n")
    assert [c for c, _ in errors(r)] == ["INT028"]
    assert motions(r) == []


def test_nr0_without_a_modal_subroutine_moves_once():
    # [rec] spec 01 §3.5: NR0 without a modal cycle/subroutine behaves as one execution
    r = ok(run("G91 G01 X5 F100 NR0\nM30\n"))
    assert [m.end_part["X"] for m in motions(r)] == [5]


def test_nr_must_be_a_whole_number():
    # [rec] spec 01 E20
    r = run("G91 G01 X5 F100 NR2.5\nM30\n")
    assert errors(r) == [("INT036", 1)]
    assert motions(r) == []


# ============================================================================ 5. flow control
def test_while_goto_manual_example_l17101_l17108():
    # L17101-L17108: P0 = 10, 9, ... 2 -> G01 to X100, X90, ... X20 (9 moves); when P0 becomes 1
    # $GOTO N100 -> G00 Y30
    r = ok(run("N10 P0=10\nN20 $WHILE P0<=10\nN30 G01 X[P0*10] F400\nN40 P0=P0-1\n"
               "N50 $IF P0==1 $GOTO N100\nN60 $ENDWHILE\nN100: G00 Y30\nM30\n"))
    m = motions(r)
    assert [x.kind for x in m] == ["linear"] * 9 + ["rapid"]
    assert [x.end_part["X"] for x in m[:9]] == [100, 90, 80, 70, 60, 50, 40, 30, 20]
    assert m[9].end_part == {"X": 20, "Y": 30, "Z": 0}
    assert r.state.param(0) == 1


@pytest.mark.parametrize(
    ("p1", "p2", "branch"),
    [(1, -5, 1), (0, -5, 2), (0, 3, 3), (1, 3, 1)],
)
def test_if_elseif_else_manual_example_l17197_l17213(p1, p2, branch):
    # L17207-L17213: P1==1 -> first branch; else P2==-5 -> $ELSEIF; else $ELSE; then N100
    r = ok(run(f"P1={p1}\nP2={p2}\nN20 $IF P1==1\nN30 P10=1\nN50 $ELSEIF P2==[-5]\nN60 P10=2\n"
               "N70 $ELSE\nN80 P10=3\nN90 $ENDIF\nN100 P11=1\nM30\n"))
    assert r.state.param(10) == branch
    assert r.state.param(11) == 1


def test_if_without_else_false_continues_after_endif_l17120():
    r = ok(run("P1=0\nP10=0\n$IF P1==1\nP10=1\n$ENDIF\nP11=2\nM30\n"))
    assert (r.state.param(10), r.state.param(11)) == (0, 2)


def test_first_true_elseif_wins():
    r = ok(run("P1=5\n$IF P1==1\nP10=1\n$ELSEIF P1>2\nP10=2\n$ELSEIF P1>3\nP10=3\n$ENDIF\nM30\n"))
    assert r.state.param(10) == 2


@pytest.mark.parametrize(
    ("p1", "p5", "expected"),
    [
        (4, 0, 1),   # [P1+P2/P4] = 4 + 12/2 = 10 -> $CASE 10
        (2, 8, 2),   # 2 + 6 = 8 = [P5+P6] = 8 + 0 -> $CASE [P5+P6]
        (2, 1, 3),   # 8: neither 10 nor 1 -> $DEFAULT
    ],
)
def test_switch_case_default_manual_example_l17237_l17257(p1, p5, expected):
    r = ok(run(f"P1={p1}\nP2=12\nP4=2\nP5={p5}\nP6=0\nN20 $SWITCH [P1+P2/P4]\nN30 $CASE 10\nN40 P10=1\n"
               "N60 $BREAK\nN70 $CASE [P5+P6]\nN80 P10=2\nN100 $BREAK\nN110 $DEFAULT\nN120 P10=3\n"
               "N140 $ENDSWITCH\nN150 P11=1\nM30\n"))
    assert r.state.param(10) == expected
    assert r.state.param(11) == 1


def test_switch_without_match_or_default_continues_after_endswitch_l17216():
    r = ok(run("P1=7\nP10=0\n$SWITCH P1\n$CASE 1\nP10=1\n$BREAK\n$ENDSWITCH\nP11=1\nM30\n"))
    assert (r.state.param(10), r.state.param(11)) == (0, 1)


def test_switch_has_no_fall_through():
    # each $CASE ends with its $BREAK (L17227): only the matching section runs
    r = ok(run("P1=1\nP10=0\n$SWITCH P1\n$CASE 1\nP10=P10+1\n$BREAK\n$CASE 2\nP10=P10+10\n$BREAK\n"
               "$DEFAULT\nP10=P10+100\n$ENDSWITCH\nM30\n"))
    assert r.state.param(10) == 1


def test_for_end_value_is_inclusive_l17281_l17288():
    # L17288: P1 = 0, 2, 4, 6, 8, 10 -> 6 times; [rec] spec 06 §5.4: P1 ends on the first failing value 12
    r = ok(run("P100=0\nN20 $FOR P1=0,10,2\nN30 P100=P100+1\nN60 $ENDFOR\nM30\n"))
    assert r.state.param(100) == 6
    assert r.state.param(1) == 12


def test_for_moves_once_per_value():
    r = ok(run("G01 F100\n$FOR P1=1,3,1\nG01 X[P1*10]\n$ENDFOR\nM30\n"))
    assert [m.end_part["X"] for m in motions(r)] == [10, 20, 30]


def test_for_negative_step_runs_down_to_the_end_value_inclusive_l17291():
    # L17291: $FOR V.P.VAR_NAME=20,15,-1; values 20,19,18,17,16,15 -> 6 runs ([rec] spec 06 §5.4:
    # the manual's "5 fois" contradicts its own inclusive rule); ends on 14
    r = ok(run("P100=0\nN12 $FOR V.P.VAR_NAME=20,15,-1\nN22 P100=P100+1\nN42 $ENDFOR\nM30\n"))
    assert r.state.param(100) == 6
    assert r.state.var("V.P.VAR_NAME") == 14


def test_for_already_past_the_end_does_not_run():
    # [rec] spec 06 §5.4
    r = ok(run("P100=0\n$FOR P1=5,1,1\nP100=P100+1\n$ENDFOR\nM30\n"))
    assert r.state.param(100) == 0


def test_for_step_zero_is_an_error():
    r = run("$FOR P1=0,10,0\nP2=1\n$ENDFOR\nM30\n")
    assert errors(r) == [("INT072", 1)]


def test_for_break_leaves_the_loop_l17301_l17310():
    # L17310: stops when P2 == 2; P2 becomes 2 when P1 = 4; P1 keeps 4 after $BREAK ([rec])
    r = ok(run("P2=0\nP100=0\nN20 $FOR P1= 1,10,1\nN30 $IF P1==4\nP2=2\n$ENDIF\nN40 $IF P2==2\nN50 $BREAK\n"
               "N60 $ENDIF\nN70 P100=P100+1\nN80 $ENDFOR\nP101=1\nM30\n"))
    assert r.state.param(100) == 3      # P1 = 1, 2, 3
    assert r.state.param(1) == 4
    assert r.state.param(101) == 1


def test_for_continue_skips_the_rest_of_one_repetition_l17271_l17273():
    # P1 = 1..5: P100 counts 5, P101 skips P1 == 2 -> 4
    r = ok(run("P100=0\nP101=0\n$FOR P1=1,5,1\nP100=P100+1\n$IF P1==2\n$CONTINUE\n$ENDIF\nP101=P101+1\n"
               "$ENDFOR\nM30\n"))
    assert (r.state.param(100), r.state.param(101), r.state.param(1)) == (5, 4, 6)


def test_while_tests_at_the_start_l17317_l17338():
    # L17331-L17338: P1 = 0: runs for P1 = 0..10 -> 11 times, P1 ends at 11
    r = ok(run("P1=0\nP100=0\nN20 $WHILE P1<= 10\nN30 P1=P1+1\nP100=P100+1\nN60 $ENDWHILE\nM30\n"))
    assert (r.state.param(1), r.state.param(100)) == (11, 11)
    # false at the start: zero repetitions
    r = ok(run("P1=20\nP100=0\n$WHILE P1<= 10\nP100=P100+1\n$ENDWHILE\nM30\n"))
    assert r.state.param(100) == 0


def test_while_break_l17341_l17350():
    r = ok(run("P1=0\nP2=0\nN20 $WHILE P1<= 10\nN30 P1=P1+1\nN40 $IF P1==3\nP2=2\n$ENDIF\n"
               "$IF P2==2\nN50 $BREAK\nN60 $ENDIF\nN80 $ENDWHILE\nM30\n"))
    assert r.state.param(1) == 3


def test_while_continue_restarts_at_the_while_l17353_l17364():
    # P1 = 1..5; P101 skips P1 == 2 -> 4
    r = ok(run("P1=0\nP101=0\nN20 $WHILE P1<5\nP1=P1+1\nN40 $IF P1==2\nN50 $CONTINUE\nN60 $ENDIF\n"
               "N70 P101=P101+1\nN80 $ENDWHILE\nM30\n"))
    assert (r.state.param(1), r.state.param(101)) == (5, 4)


def test_do_runs_at_least_once_and_tests_at_the_end_l17371_l17393():
    # L17386-L17393: P1 = 0: P1 -> 1..11, the test P1<=10 fails after 11 -> 11 runs
    r = ok(run("P1=0\nP100=0\nN20 $DO\nN30 P1=P1+1\nP100=P100+1\nN60 $ENDDO P1<=10\nM30\n"))
    assert (r.state.param(1), r.state.param(100)) == (11, 11)
    r = ok(run("P1=50\nP100=0\n$DO\nP100=P100+1\n$ENDDO P1<=10\nM30\n"))
    assert r.state.param(100) == 1


def test_do_break_l17396_l17405():
    r = ok(run("P1=0\nP2=0\nN20 $DO\nP1=P1+1\n$IF P1==4\nP2=2\n$ENDIF\nN40 $IF P2==2\nN50 $BREAK\n"
               "N60 $ENDIF\nN80 $ENDDO P1<= 10\nP3=1\nM30\n"))
    assert (r.state.param(1), r.state.param(3)) == (4, 1)


def test_do_continue_tests_the_enddo_condition_l17408_l17419():
    # [rec] spec 06 §5.6: $CONTINUE goes to the $ENDDO test (else this loop would never end);
    # P1 = 1..5, P101 counts P1 = 1..4 -> 4
    r = run("P1=0\nP101=0\n$DO\nP1=P1+1\n$IF P1>=5\n$CONTINUE\n$ENDIF\nP101=P101+1\n$ENDDO P1<5\nM30\n",
            {"limits": {"max_loop_iterations": 100}})
    ok(r)
    assert (r.state.param(1), r.state.param(101)) == (5, 4)


def test_goto_to_a_label_l17095():
    # L17095/L17099: $GOTO [LABEL] ... N40 [LABEL]
    r = ok(run("G00 X1\n$GOTO [SKIP]\nG00 X5\nN40 [SKIP] G00 X7\nM30\n"))
    assert [m.end_part["X"] for m in motions(r)] == [1, 7]


def test_goto_backwards_to_a_block_number_with_colon_l17095_l17099():
    # jumps before the $GOTO are allowed; loop three times with P1
    r = ok(run("P1=0\nN10: P1=P1+1\nG00 X[P1]\n$IF P1<3 $GOTO N10\nM30\n"))
    assert [m.end_part["X"] for m in motions(r)] == [1, 2, 3]


def test_goto_with_a_computed_block_number_l17048():
    # spec 06 §5.1: $GOTO N[P1*10]; P1 = 3 -> N30
    r = ok(run("P1=3\n$GOTO N[P1*10]\nN20: G00 X2\nN30: G00 X3\nM30\n"))
    assert [m.end_part["X"] for m in motions(r)] == [3]


@pytest.mark.parametrize("target", ["[NOWHERE]", "N999"])
def test_goto_to_a_missing_target_is_an_error(target):
    # [rec] spec 06 §5.1: target not found -> error
    r = run(f"G00 X1\n$GOTO {target}\nG00 X2\nM30\n")
    assert [c for c, _ in errors(r)] == ["INT073"]
    assert [m.end_part["X"] for m in motions(r)] == [1]


def test_goto_needs_the_colon_on_the_target_block_number():
    # L17048-L17108: the target is "N<n>:"; a plain "N20" is no jump target
    r = run("$GOTO N20\nN20 G00 X2\nM30\n")
    assert [c for c, _ in errors(r)] == ["INT073"]


def test_runaway_while_is_stopped_by_the_iteration_limit():
    r = run("P1=0\n$WHILE 1\nP1=P1+1\n$ENDWHILE\nM30\n", {"limits": {"max_loop_iterations": 1000}})
    assert [c for c, _ in errors(r)] == ["INT081"]
    assert r.state.param(1) == 1000
    assert r.ended_by is None


def test_runaway_goto_loop_is_stopped_by_the_block_limit():
    r = run("N10: P1=1\n$GOTO N10\nM30\n", {"limits": {"max_blocks": 500}})
    assert [c for c, _ in errors(r)] == ["INT080"]


def test_runaway_for_is_stopped_by_the_iteration_limit():
    r = run("$FOR P1=0,100000,1\nP2=1\n$ENDFOR\nM30\n", {"limits": {"max_loop_iterations": 1000}})
    assert [c for c, _ in errors(r)] == ["INT081"]


def test_runaway_do_is_stopped_by_the_iteration_limit():
    r = run("$DO\nP2=1\n$ENDDO 1\nM30\n", {"limits": {"max_loop_iterations": 1000}})
    assert [c for c, _ in errors(r)] == ["INT081"]


def test_for_end_and_step_are_evaluated_once_and_writes_to_the_variable_count():
    # [rec] spec 06 §5.4: end P2 = 3 fixed at entry -> 3 runs although P2 becomes 10
    r = ok(run("P2=3\nP100=0\n$FOR P1=1,P2,1\nP2=10\nP100=P100+1\n$ENDFOR\nM30\n"))
    assert r.state.param(100) == 3
    # the body adds 1 to P1: values 1, 3, 5, 7, 9 -> 5 runs, ends at 11
    r = ok(run("P100=0\n$FOR P1=1,10,1\nP1=P1+1\nP100=P100+1\n$ENDFOR\nM30\n"))
    assert (r.state.param(100), r.state.param(1)) == (5, 11)


def test_break_of_a_case_inside_a_for_leaves_only_the_switch():
    # [rec] spec 06 §5.3: $BREAK leaves the innermost $SWITCH/loop; P1 = 1, 2, 3: +1, +10, +1 = 12
    r = ok(run("P100=0\n$FOR P1=1,3,1\n$SWITCH P1\n$CASE 2\nP100=P100+10\n$BREAK\n$DEFAULT\nP100=P100+1\n"
               "$ENDSWITCH\n$ENDFOR\nM30\n"))
    assert (r.state.param(100), r.state.param(1)) == (12, 4)


def test_goto_out_of_a_loop_and_back_in_restarts_it_l17074_l17078():
    # [rec] spec 06 §5.1: leaving a structure with $GOTO unwinds it; 3 passes x 2 iterations = 6
    r = ok(run("P100=0\nP3=0\n[TOP] P3=P3+1\n$FOR P1=1,5,1\nP100=P100+1\n$IF P1==2 $GOTO [OUT]\n$ENDFOR\n"
               "[OUT] $IF P3<3 $GOTO [TOP]\nM30\n"))
    assert (r.state.param(100), r.state.param(3)) == (6, 3)


def test_goto_into_the_body_of_a_loop_is_an_error_l17072_l17073():
    r = run("P1=0\n$GOTO [IN]\n$WHILE P1<3\n[IN] P1=P1+1\n$ENDWHILE\nM30\n")
    assert errors(r) == [("INT074", 2)]


# ============================================================================ 6. subroutines
def write(tmp_path, name: str, text: str) -> None:
    (tmp_path / name).write_text(text, encoding="utf-8")


def machine(tmp_path, **extra) -> dict:
    return {"subroutine_paths": [str(tmp_path)], **extra}


def test_local_subroutine_with_ll_l10200_l10453():
    r = ok(run("%L SUB1\nG00 X[P0]\nM17\n%MAIN\nP0=4\nLL SUB1\nG00 Y1\nM30\n"))
    assert [(m.end_part["X"], m.end_part["Y"]) for m in motions(r)] == [(4, 0), (4, 1)]
    assert r.ended_by == "M30"


@pytest.mark.parametrize("end", ["M17", "M29", "#RET"])
def test_subroutine_ends_with_m17_m29_or_ret(end):
    r = ok(run(f"%L SUB1\nP100=1\n{end}\n%MAIN\nP100=0\n#CALL SUB1\nP101=2\nM30\n"))
    assert (r.state.param(100), r.state.param(101)) == (1, 2)


def test_call_opens_a_new_parameter_level_l10220_l10224():
    # #CALL changes the level: the subroutine's P0 is its own; the caller's P0 stays 5
    r = ok(run("%L SUB1\nP100 = EXIST[P0]\nP0 = 9\nM17\n%MAIN\nP0=5\n#CALL SUB1\nM30\n"))
    assert r.state.param(100) == 0     # [rec] spec 05 §1.2: the new level starts undefined
    assert r.state.param(0) == 5


def test_pcall_arguments_letters_and_pn_l10487_l10517():
    # L10517: #PCALL Sub3.nc A12.3 F45.3 P10=6 -> P0 = 12.3 (A), P5 = 45.3 (F), P10 = 6
    r = ok(run("%L SUB3\nP100=P0\nP105=P5\nP110=P10\nP111=EXIST[P1]\nP0=99\nP5=99\nM17\n"
               "%MAIN\nP0=1\nP5=2\nP10=3\n#PCALL SUB3 A12.3 F45.3 P10=6\nM30\n"))
    assert [r.state.param(n) for n in (100, 105, 110, 111)] == [12.3, 45.3, 6, 0]
    # back at the main level its locals are untouched (L10216-L10218)
    assert [r.state.param(n) for n in (0, 5, 10)] == [1, 2, 3]


def test_pcall_letter_c_is_p2_and_z_is_p25_l1884_l1886():
    # spec 01 §10.1: "except Ñ and C" is the Spanish CH; C = P2, Z = P25
    r = ok(run("%L SUBC\nP102=P2\nP125=P25\nM17\n%MAIN\n#PCALL SUBC C7 Z8\nM30\n"))
    assert (r.state.param(102), r.state.param(125)) == (7, 8)


def test_pcall_argument_expressions_use_the_caller_values():
    # values are evaluated in the caller: A[P1*2] with P1 = 4 -> P0 = 8
    r = ok(run("%L SUBE\nP100=P0\nM17\n%MAIN\nP1=4\n#PCALL SUBE A[P1*2]\nM30\n"))
    assert r.state.param(100) == 8


def test_ll_does_not_open_a_parameter_level_l10222():
    # L10222-L10224: only #CALL, #PCALL, #MCALL, G180.. change the level; LL sees and writes the
    # caller's locals ([rec] spec 05 A3)
    r = ok(run("%L SUBL\nP100=P0\nP0=7\nM17\n%MAIN\nP0=5\nLL SUBL\nM30\n"))
    assert r.state.param(100) == 5
    assert r.state.param(0) == 7


def test_global_parameters_are_shared_at_every_level_l10228_l10230():
    r = ok(run("%L SUBA\nP100 = P100 * 2\nM17\n%L SUBB\nP100 = P100 + 1\n#CALL SUBA\nM17\n"
               "%MAIN\nP100 = 3\n#PCALL SUBB A1\n#CALL SUBB\nM30\n"))
    # 3 -> +1 = 4 -> *2 = 8 -> +1 = 9 -> *2 = 18
    assert r.state.param(100) == 18


def test_local_subroutine_calling_an_earlier_one_is_allowed_l10203():
    r = ok(run("%L SUBA\nP100=P100+1\nM17\n%L SUBB\nLL SUBA\nP100=P100*10\nM17\n%MAIN\nP100=0\nLL SUBB\nM30\n"))
    assert r.state.param(100) == 10   # (0+1)*10


def test_local_subroutine_calling_a_later_one_is_an_error_l10203_l10205():
    r = run("%L SUBA\nLL SUBB\nM17\n%L SUBB\nP100=1\nM17\n%MAIN\nG00 X1\nLL SUBA\nG00 X2\nM30\n")
    assert [c for c, _ in errors(r)] == ["INT090"]
    assert [m.end_part["X"] for m in motions(r)] == [1]


def test_ll_of_an_undefined_local_subroutine_is_an_error():
    r = run("%MAIN\nLL NOSUCH\nM30\n")
    assert [c for c, _ in errors(r)] == ["INT091"]


def test_mcall_runs_after_every_motion_block_not_after_other_blocks_l10529_l10530():
    # L10529-L10530: the subroutine repeats at the end of each move.  Counted as the difference
    # between points after the #MCALL block (spec 05 A10).
    r = ok(run("%L CNT\nP100=P100+1\nM17\n%MAIN\nP100=0\nG01 F100\n#MCALL CNT\nP1=P100\n"
               "G01 X10\nP2=P100\nY5\nP3=P100\nP9=2\nM5\nF200\nP4=P100\nM30\n"))
    assert r.state.param(2) - r.state.param(1) == 1    # G01 X10: one run
    assert r.state.param(3) - r.state.param(2) == 1    # Y5 (modal G01): one run
    assert r.state.param(4) - r.state.param(3) == 0    # P9=2, M5, F200: no move, no run


@pytest.mark.parametrize("where", ["main", "modal"])
def test_an_error_ends_the_run_once_whatever_the_loop_it_is_in(where):
    # the run's block loop reports an error and ends; a modal subroutine's loop (after a move) hands it to the
    # run's: one error, the moves before it handed on (the last one was held by the corner aids), nothing after
    error = "G1 Y[P1/0]\n"
    sub = error if where == "modal" else "P100=1\n"
    r = run(f"%L SUB\n{sub}M17\n%MAIN\nG90 G1 X0 Y0 Z0 F1000\nG1 X5\n#MCALL SUB\nG1 X10\n"
            f"{error if where == 'main' else ''}G1 X20\nM30\n")
    assert [c for c, _ in errors(r)] == ["INT040"]
    assert [m.end_part["X"] for m in motions(r)] == ([0.0, 5.0] if where == "modal" else [0.0, 5.0, 10.0])


def test_mcall_nr0_moves_without_the_subroutine_l10592():
    r = ok(run("%L CNT\nP100=P100+1\nM17\n%MAIN\nP100=0\nG01 F100\n#MCALL CNT\nP1=P100\n"
               "X20 NR0\nP2=P100\nM30\n"))
    assert r.state.param(2) - r.state.param(1) == 0
    assert motions(r)[-1].end_part["X"] == 20


def test_mcall_nr_repeats_move_and_subroutine_l10594_l10596():
    # G91 X5 NR3: (move, CNT) x 3 -> +3; X ends at 15
    r = ok(run("%L CNT\nP100=P100+1\nM17\n%MAIN\nP100=0\nG01 F100\n#MCALL CNT\nP1=P100\n"
               "G91 X5 NR3\nP2=P100\nM30\n"))
    assert r.state.param(2) - r.state.param(1) == 3
    assert r.state.position("part")["X"] == 15


def test_mcall_subroutine_receives_its_arguments_at_every_run_l10537():
    # each run gets a fresh level initialised from the #MCALL arguments ([rec] spec 05 §1.9)
    r = ok(run("%L ADDA\nP100=P100+P0\nP0=1000\nM17\n%MAIN\nP100=0\nG01 F100\n#MCALL ADDA A3\nP1=P100\n"
               "X1\nX2\nP2=P100\nM30\n"))
    assert r.state.param(2) - r.state.param(1) == 6   # 3 + 3


def test_mdoff_cancels_the_modal_subroutine_l10601_l10609():
    # spec 05 §1.9 example: after #MDOFF, X5 moves without CNT
    r = ok(run("%L CNT\nP100=P100+1\nM17\n%MAIN\nP100=0\nG01 F100\n#MCALL CNT\nG01 X10\nP1=P100\n"
               "#MDOFF\nX5\nP2=P100\nM30\n"))
    assert r.state.param(2) - r.state.param(1) == 0


def test_mcall_full_example_spec05_19():
    # spec 05 §1.9 example: #MCALL (once, A10) + X10 + (X20 NR0: 0) + (G91 X5 NR3: 3) + (P1=2: 0)
    # + (#MDOFF, X5: 0) -> 1 + 1 + 0 + 3 = 5
    r = ok(run("%L CNT\nP100=P100+1\nM17\n%MAIN\nP100=0\nG01 F100\n#MCALL CNT\nG01 X10\nX20 NR0\n"
               "G91 X5 NR3\nP1=2\n#MDOFF\nX5\nM30\n"))
    assert r.state.param(100) == 5


def test_moves_inside_the_modal_subroutine_do_not_trigger_it_l10590():
    r = ok(run("%L MV\nP100=P100+1\nG91 G01 Z1\nG90\nM17\n%MAIN\nP100=0\nG01 F100\n#MCALL MV\nP1=P100\n"
               "G90 X10\nP2=P100\nM30\n"))
    assert r.state.param(2) - r.state.param(1) == 1


def test_another_call_cancels_the_modal_subroutine_l10568():
    # L10568: calling another subroutine (#PCALL, #CALL, L, LL) cancels the modal character
    r = ok(run("%L CNT\nP100=P100+1\nM17\n%L OTHER\nP101=1\nM17\n%MAIN\nP100=0\nG01 F100\n#MCALL CNT\n"
               "LL OTHER\nP1=P100\nX10\nP2=P100\nM30\n"))
    assert r.state.param(2) - r.state.param(1) == 0


def test_global_subroutine_found_in_subroutine_paths_l10322(tmp_path):
    # L10459-L10469: "L Sub3.nc", "#CALL Sub3.nc"
    write(tmp_path, "SUBG.nc", "%SUBG\nP100=P100+1\nG00 X[P100*10]\nM17\n")
    r = ok(run("%MAIN\nP100=0\nL SUBG.nc\n#CALL SUBG.nc\nM30\n", machine(tmp_path)))
    assert r.state.param(100) == 2
    assert [m.end_part["X"] for m in motions(r)] == [10, 20]


def test_global_pcall_with_arguments_l10517(tmp_path):
    write(tmp_path, "Sub3.nc", "P100=P0\nP105=P5\nP110=P10\n#RET\n")
    r = ok(run("P0=1\n#PCALL Sub3.nc A12.3 F45.3 P10=6\nM30\n", machine(tmp_path)))
    assert [r.state.param(n) for n in (100, 105, 110, 0)] == [12.3, 45.3, 6, 1]


def test_l_global_call_does_not_open_a_parameter_level_l10222(tmp_path):
    write(tmp_path, "SETP0.nc", "P100=P0\nP0=8\nM17\n")
    r = ok(run("P0=2\nL SETP0.nc\nM30\n", machine(tmp_path)))
    assert (r.state.param(100), r.state.param(0)) == (2, 8)


def test_global_subroutine_not_found_is_an_error(tmp_path):
    r = run("G00 X1\nL NOPE.nc\nG00 X2\nM30\n", machine(tmp_path))
    assert errors(r) == [("INT093", 2)]
    assert [m.end_part["X"] for m in motions(r)] == [1]


def test_call_of_a_missing_subroutine_is_an_error(tmp_path):
    r = run("#CALL NOPE.nc\nM30\n", machine(tmp_path))
    assert [c for c, _ in errors(r)] == ["INT093"]


def test_nesting_deeper_than_20_levels_is_an_error_l10207_l10210(tmp_path):
    # L10210: at most 20 nesting levels; a global file calling itself: calls 1..20 run, the 21st fails
    write(tmp_path, "REC.nc", "P100=P100+1\nL REC.nc\nM17\n")
    r = run("P100=0\nL REC.nc\nM30\n", machine(tmp_path))
    assert [c for c, _ in errors(r)] == ["INT095"]
    assert r.state.param(100) == 20


def test_chain_of_20_local_subroutines_is_allowed_l10207():
    # S1 ... S20: S_k calls S_(k-1) (defined before it); the main calls S20 -> depth 20, fine
    subs = "%L S1\nP100=P100+1\nM17\n" + "".join(
        f"%L S{k}\nP100=P100+1\nLL S{k - 1}\nM17\n" for k in range(2, 22))
    r = ok(run(subs + "%MAIN\nP100=0\nLL S20\nM30\n"))
    assert r.state.param(100) == 20
    # S21 -> depth 21: error
    r = run(subs + "%MAIN\nP100=0\nLL S21\nM30\n")
    assert [c for c, _ in errors(r)] == ["INT095"]


def test_g180_oem_words_before_run_first_words_after_are_arguments_l10712_l10718(tmp_path):
    # L10712-L10718: "G01 X50 F450 G180 P0=15 P1=20": move, then the subroutine with P0=15 P1=20
    write(tmp_path, "SUB180.nc", "P100=P0\nP101=P1\nP106=EXIST[P6]\nP130=V.A.PPOS.X\nM17\n")
    mach = machine(tmp_path, oem_subroutines={"180": "SUB180.nc"})
    r = ok(run("G01 X50 F450 G180 P0=15 P1=20\nM30\n", mach))
    assert [m.end_part["X"] for m in motions(r)] == [50]
    assert [r.state.param(n) for n in (100, 101, 106, 130)] == [15, 20, 0, 50]


def test_g180_every_word_after_the_code_is_an_argument_l10839_l10842(tmp_path):
    # L10839-L10842: "G180 P0=15 P1=20 G01 X50 F450" -> no move; P6 (G) = 1, P23 (X) = 50, P5 (F) = 450
    write(tmp_path, "SUB180.nc", "P100=P0\nP101=P1\nP106=P6\nP123=P23\nP105=P5\nM17\n")
    mach = machine(tmp_path, oem_subroutines={"180": "SUB180.nc"})
    r = ok(run("G180 P0=15 P1=20 G01 X50 F450\nM30\n", mach))
    assert motions(r) == []
    assert [r.state.param(n) for n in (100, 101, 106, 123, 105)] == [15, 20, 1, 50, 450]


def test_g180_opens_a_parameter_level_l10223(tmp_path):
    write(tmp_path, "SUB180.nc", "P0=77\nM17\n")
    mach = machine(tmp_path, oem_subroutines={"180": "SUB180.nc"})
    r = ok(run("P0=1\nG180 A2\nM30\n", mach))
    assert r.state.param(0) == 1


def test_g181_without_a_configured_subroutine_is_an_error(tmp_path):
    r = run("G181 A1\nM30\n", machine(tmp_path, oem_subroutines={"180": "SUB180.nc"}))
    assert [c for c, _ in errors(r)] == ["INT096"]


def test_local_parameter_levels_at_most_seven_including_the_main_program_l10220_l10221():
    # L10220-L10221: at most 7 levels of local parameters; L1879: seven groups of local parameters per
    # channel.  spec 05 §1.2 (A4): the main program's set is one of the 7, so 6 nested #CALLs are
    # allowed and the 7th (8th level) is an error.  S_k calls S_(k-1) with #CALL.
    subs = "%L S1\nP100=P100+1\nM17\n" + "".join(
        f"%L S{k}\nP100=P100+1\n#CALL S{k - 1}\nM17\n" for k in range(2, 9))
    r = ok(run(subs + "%MAIN\nP100=0\n#CALL S6\nM30\n"))       # 6 nested calls: levels 0..6
    assert r.state.param(100) == 6
    r = run(subs + "%MAIN\nP100=0\n#CALL S7\nM30\n")           # 7 nested calls: an 8th level
    assert [c for c, _ in errors(r)] == ["INT042"]


def test_pcall_p_without_equals_is_the_letter_p_l10490():
    # L10490-L10491: letters A..Z give P0..P25; spec 05 §1.8 (A5): "P<number>" without "=" is the
    # letter P -> P15; so "#PCALL SUB P3" gives P15 = 3 and leaves P3 undefined
    r = ok(run("%L SUB\nP100=P15\nP101=EXIST[P3]\nM17\n%MAIN\n#PCALL SUB P3\nM30\n"))
    assert (r.state.param(100), r.state.param(101)) == (3, 0)


def test_user_local_variable_keeps_its_value_in_called_subroutines_l42489():
    # spec 01 §9.3 [rec] (L42489-L42490): V.P.. keeps its value in the subroutines called
    r = ok(run("%L SUB\nP100=V.P.x\nM17\n%MAIN\nV.P.x=4\n#CALL SUB\nM30\n"))
    assert r.state.param(100) == 4


def test_l_finds_only_global_subroutines_l10427(tmp_path):
    # spec 05 §1.7: "L" looks for a global file only; a local S1 is not found by it
    r = run("%L S1\nP100=1\nM17\n%MAIN\nL S1\nM30\n", machine(tmp_path))
    assert [c for c, _ in errors(r)] == ["INT093"]


def test_plane_change_cancels_the_modal_subroutine_l10562():
    r = ok(run("%L CNT\nP100=P100+1\nM17\n%MAIN\nP100=0\nG01 F100\n#MCALL CNT\nP1=P100\nG18\nX10\n"
               "P2=P100\nM30\n"))
    assert r.state.param(2) - r.state.param(1) == 0


def test_new_mcall_replaces_the_modal_subroutine_l10598_l10600():
    # after "#MCALL B" only B runs after a move
    r = ok(run("%L A\nP100=P100+1\nM17\n%L B\nP101=P101+1\nM17\n%MAIN\nP100=0\nP101=0\nG01 F100\n"
               "#MCALL A\n#MCALL B\nP1=P100\nP2=P101\nX10\nP3=P100\nP4=P101\nM30\n"))
    assert (r.state.param(3) - r.state.param(1), r.state.param(4) - r.state.param(2)) == (0, 1)


def test_error_inside_a_global_subroutine_names_its_file_and_line(tmp_path):
    write(tmp_path, "ERR.nc", "P100=1\nP1=1/0\nM17\n")
    r = run("G00 X1\nL ERR.nc\nG00 X2\nM30\n", machine(tmp_path))
    assert [(d.code, d.line, d.file.endswith("ERR.nc")) for d in r.errors] == [("INT033", 2, True)]
    assert [m.end_part["X"] for m in motions(r)] == [1]


def test_error_inside_a_local_subroutine_has_the_line_of_its_block():
    r = run("%L S1\nP1=SQRT[-1]\nM17\n%MAIN\nG00 X1\nLL S1\nG00 X2\nM30\n")
    assert errors(r) == [("INT032", 2)]
    assert len(motions(r)) == 1


def test_global_subroutine_file_with_syntax_errors(tmp_path):
    write(tmp_path, "SYN.nc", "P100=1\nG00 X[\nM17\n")
    r = run("L SYN.nc\nM30\n", machine(tmp_path))
    assert "INT092" in [d.code for d in r.errors]


def test_global_subroutine_without_end_block_is_an_error_l10311(tmp_path):
    # spec 05 §1.4: M17, M29 or #RET is mandatory at the end of every subroutine
    write(tmp_path, "NOEND.nc", "P100=1\n")
    r = run("L NOEND.nc\nM30\n", machine(tmp_path))
    assert [d.code for d in r.errors] == ["INT099"]


@pytest.mark.parametrize("text", ["M17\nM30\n", "#RET\nM30\n"])
def test_end_of_subroutine_in_the_main_program_is_an_error(text):
    r = run(text)
    assert [c for c, _ in errors(r)] == ["INT097"]


# ============================================================================ 7. F S T D M H
def test_m3_and_s_run_before_the_motion_l5027_l5029():
    # L5027-L5029: M functions not in the M table run before the motion of their block
    r = ok(run("G00 X10 S1000 M3\nM30\n"))
    kinds = [(m.kind, getattr(m, "function", None)) for m in r.moves]
    assert kinds[:3] == [("aux", "S"), ("aux", "M"), ("rapid", None)]
    m3 = aux(r, "M")[0]
    assert (m3.value, m3.timing) == (3, "before")
    s = aux(r, "S")[0]
    assert (s.value, s.timing) == (1000, "before")


@pytest.mark.parametrize("m", [0, 1])
def test_m0_and_m1_run_after_the_motion_l5061_l5062(m):
    # L5061-L5062: M00 is recommended "at the end of the block" (spec 02 §19)
    r = ok(run(f"G00 X10 M{m}\nM30\n"))
    kinds = [m.kind for m in r.moves]
    assert kinds[:2] == ["rapid", "aux"]
    rec = aux(r, "M")[0]
    assert (rec.value, rec.timing) == (m, "after")
    assert rec.end["X"] == 10      # the stop happens at the end point


def test_h_runs_at_the_start_of_the_block_l5104():
    r = ok(run("G00 X10 H5 H7\nM30\n"))
    assert [m.kind for m in r.moves][:3] == ["aux", "aux", "rapid"]
    assert [(a.value, a.timing) for a in aux(r, "H")] == [(5, "before"), (7, "before")]


def test_m_and_h_values_are_rounded_down_l5097_l5099():
    # L5098: a computed value is rounded down to an integer: 3.9 -> 3, 7.5 -> 7
    r = ok(run("P1=3.9\nP2=7.5\nMP1 HP2\nM30\n"))
    assert [a.value for a in aux(r, "M")][:1] == [3]
    assert [a.value for a in aux(r, "H")] == [7]


def test_negative_h_is_an_error_l5099():
    r = run("H[-1]\nM30\n")
    assert not r.ok


def test_eight_m_functions_in_a_block_is_an_error():
    # spec 02 §19: up to 7 M per block
    r = run("M10 M11 M12 M13 M14 M15 M16 M18\nM30\n")
    assert [c for c, _ in errors(r)] == ["INT021"]


def test_tool_change_makes_tool_and_offset_active_l4700_l4708():
    # L4705-L4708 (mill): T preselects, M06 loads it
    r = ok(run("T5 D1 M06\nM30\n"))
    assert (r.state.tool, r.state.offset) == (5, 1)
    assert [(a.function, a.value) for a in aux(r)][:2] == [("T", 5), ("M", 6)]


def test_t_without_m06_only_preselects_l4705():
    r = ok(run("T5 D1 M06\nT7\nM30\n"))
    assert r.state.tool == 5
    assert r.state.var("V.G.NXTOOL") == 7


def test_m06_without_d_assumes_d1_l4942():
    r = ok(run("T8\nM06\nM30\n"))
    assert (r.state.tool, r.state.offset) == (8, 1)


def test_tool_offsets_come_from_the_machine_tool_table():
    mach = {"tools": {"5": {"1": {"length": 100, "radius": 4}, "2": {"length": 50, "radius": 2}}}}
    r = ok(run("T5 D2 M06\nM30\n", mach))
    assert (r.state.tool, r.state.offset) == (5, 2)
    r = run("T5 D3 M06\nM30\n", mach)
    assert [c for c, _ in errors(r)] == ["INT051"]


def test_tool_not_in_the_tool_table_is_an_error_l4685():
    # L4685: a tool must be defined in the table before it is selected; the default table has 0..99
    r = run("G00 X1\nT150\nG00 X2\nM30\n")
    assert errors(r) == [("INT050", 2)]
    assert [m.end_part["X"] for m in motions(r)] == [1]


def test_g01_without_any_feed_is_an_error_l4064_l4065():
    r = run("G00 X1\nG01 X10\nM30\n")
    assert errors(r) == [("INT060", 2)]
    assert len(motions(r)) == 1
    assert "no feed programmed (F)" in r.diagnostics[0].message
    zero = run("G01 X10 F0\nM30\n")   # F0 is a feed of 0, not a missing one: said as such
    assert errors(zero) == [("INT060", 1)] and "the feed is 0 (F0)" in zero.diagnostics[0].message


def test_g00_needs_no_feed_l4058_l4060():
    r = ok(run("G00 X10\nM30\n"))
    assert motions(r)[0].feed is None


def test_feed_is_modal_l4047():
    r = ok(run("G01 X1 F300\nX2\nG00 X3\nG01 X4\nM30\n"))
    assert [m.feed for m in motions(r)] == [300, 300, None, 300]


def test_m30_ends_the_run_l859():
    r = ok(run("G00 X1\nM30\nG00 X2\nP1=1\n"))
    assert r.ended_by == "M30"
    assert r.moves[-1].kind == "aux"
    assert (r.moves[-1].function, r.moves[-1].value) == ("M", 30)
    assert [m.end_part["X"] for m in motions(r)] == [1]
    assert not any(d.code == "INT098" for d in r.diagnostics)


def test_m02_ends_the_run_like_m30_l859():
    r = ok(run("G00 X1\nM02\nG00 X2\n"))
    assert r.ended_by == "M02"
    assert len(motions(r)) == 1


def test_program_without_m30_gives_a_warning_l860_l862():
    r = run("G00 X1\n")
    assert r.ok
    assert [(d.code, d.severity) for d in r.diagnostics] == [("INT098", "warning")]
    assert r.ended_by is None
    assert len(motions(r)) == 1


def test_g04_k_dwell_l9179_l9187():
    # L9179: G04 K0.5 -> 0.5 s; L9183 KP1 with P1=3 -> 3 s; L9185 K[P1+7] -> 10 s; G4 == G04 (L9177)
    r = ok(run("G04 K1.5\nP1=3\nG04 KP1\nG4 K[P1+7]\nM30\n"))
    assert [m.seconds for m in r.moves if m.kind == "dwell"] == [1.5, 3, 10]


def test_g04_bare_value_l9187():
    # L9187: "G04 5" is a dwell of 5 seconds
    r = ok(run("G04 5\nM30\n"))
    assert [m.seconds for m in r.moves if m.kind == "dwell"] == [5]


def test_time_sentence_dwell_l9189_l9190():
    r = ok(run("#TIME 2\n#TIME [5]\nM30\n"))
    assert [m.seconds for m in r.moves if m.kind == "dwell"] == [2, 5]


def test_error_sentence_stops_with_its_text_l14141_l14177():
    # L14141: #ERROR stops execution and shows the error
    r = run('G00 X1\n#ERROR ["tool broken"]\nG00 X2\nM30\n')
    assert errors(r) == [("INT070", 2)]
    assert "tool broken" in r.errors[0].message
    assert [m.end_part["X"] for m in motions(r)] == [1]
    assert r.ended_by is None


def test_error_sentence_with_data_placeholder_l14203_l14212():
    # %D takes the data values in order: P1 = 7
    r = run('P1=7\n#ERROR ["bad tool %D", P1]\nM30\n')
    assert [c for c, _ in errors(r)] == ["INT070"]
    assert "bad tool 7" in r.errors[0].message


def test_error_sentence_with_a_number_l14154():
    # L14156-L14157: the number may be an expression; 2 + 34 = 36
    r = run("P10=2\n#ERROR [P10+34]\nM30\n")
    assert [c for c, _ in errors(r)] == ["INT070"]
    assert "36" in r.errors[0].message


def test_warning_sentence_does_not_stop_l14283_l14331():
    r = run('#WARNING ["check coolant"]\nG00 X2\nM30\n')
    assert r.ok
    w = [d for d in r.diagnostics if d.code == "INT076"]
    assert [(d.severity, d.line) for d in w] == [("warning", 1)]
    assert "check coolant" in w[0].message
    assert len(motions(r)) == 1
    assert r.ended_by == "M30"


def test_msg_sentence_is_information_l14363_l14368():
    r = run('#MSG ["roughing"]\nG00 X2\nM30\n')
    assert r.ok
    assert [(d.code, d.severity, d.line) for d in r.diagnostics] == [("INT077", "info", 1)]
    assert "roughing" in r.diagnostics[0].message
    assert len(motions(r)) == 1


def test_t_value_is_rounded_down_l4678_l4681():
    # spec 02 §17 (L4678-L4681): T[5.7] -> T5
    r = ok(run("T[5.7]\nM06\nM30\n"))
    assert r.state.tool == 5


def test_negative_t_is_an_error_l4681():
    r = run("T[-1]\nM30\n")
    assert not r.ok


def test_d0_cancels_the_offset_l4970():
    r = ok(run("T5 D1 M06\nD0\nM30\n"))
    assert (r.state.tool, r.state.offset) == (5, 0)


@pytest.mark.parametrize(
    ("block", "code"),
    [("G04", "INT017"), ("G04 K-1", "INT017"), ("S[-100]", "INT027"), ("G01 X1 F[-10]", "INT029")],
)
def test_invalid_dwell_speed_and_feed(block, code):
    r = run(f"{block}\nM30\n")
    assert errors(r) == [(code, 1)]


def test_error_sentence_manual_examples_with_data_l14210_l14212():
    # L14212: #ERROR ["Valeurs %D - %D incorrects",18,P21] with P21 = 5
    r = run('P21=5\n#ERROR ["Valeurs %D - %D incorrects",18,P21]\nM30\n')
    assert errors(r) == [("INT070", 2)]
    assert "Valeurs 18 - 5 incorrects" in r.errors[0].message


def test_msg_manual_example_with_two_data_l14407():
    r = ok(run('P21=800\n#MSG ["Fini F=%D mm/min. et S=%D RPM", P21, 1200]\nM30\n'))
    assert "Fini F=800 mm/min. et S=1200 RPM" in r.diagnostics[0].message


def test_backslash_quote_puts_a_quote_in_the_text_l14194_l14199():
    # L14194: \" puts a double quote in the text; L14199 and L14401 are the manual's examples
    r = run('#ERROR ["Le paramètre \\"P100\\" est incorrect"]\nM30\n')
    assert errors(r) == [("INT070", 1)]
    assert 'Le paramètre "P100" est incorrect' in r.errors[0].message
    r = ok(run('#MSG ["L\'outil \\"T1\\" est de finition"]\nM30\n'))
    assert 'L\'outil "T1" est de finition' in r.diagnostics[0].message


def test_double_percent_puts_a_percent_in_the_text_l14196_l14398():
    # L14196 / L14398: "%%" puts the character % in the text
    r = ok(run('#MSG ["100%% done"]\nM30\n'))
    assert r.diagnostics[0].message.endswith("100% done")


def test_lone_percent_is_printed_as_is_l14402():
    # L14402: #MSG ["On utilise 80% de l'avance"] ([rec] spec 06 §4.1)
    r = ok(run('#MSG ["On utilise 80% de l\'avance"]\nM30\n'))
    assert r.diagnostics[0].message.endswith("On utilise 80% de l'avance")


def test_msg_needs_as_many_data_as_placeholders_l14389_l14390():
    # L14389-L14390: "il devra y avoir autant de données que d'identificateurs"; two %D, one datum
    # -> error ([rec] spec 06 §4.1: mismatch -> error)
    r = run('P1=3\n#MSG ["%D parts of %D", P1]\nM30\n')
    assert not r.ok
    assert [line for _, line in errors(r)] == [2]


# ============================================================================ 8. block skip
def test_block_skip_l1026_l1029():
    # L1028-L1029: with the skip mark active the CNC does not execute "/" blocks
    text = "G01 F100\n/G01 X5\nG01 X7\nM30\n"
    r = ok(run(text, block_skip=True))
    assert [m.end_part["X"] for m in motions(r)] == [7]
    r = ok(run(text, block_skip=False))
    assert [m.end_part["X"] for m in motions(r)] == [5, 7]


def test_block_skip_of_an_assignment():
    r = ok(run("P1=1\n/P1=2\nM30\n", block_skip=True))
    assert r.state.param(1) == 1


@pytest.mark.parametrize(("text", "what"), [
    ("#CD ON [5]\nG01 X10 F500\nX0 Y5\n#CD OFF\nM30\n", "#CD"),                            # L15598: loops removed
])
def test_path_treatments_not_computed_are_reported_not_dropped(text, what):
    # these change the path the CNC runs: a run that ignores them must say so (INT078),
    # once, at the statement; the moves are still planned as programmed
    r = fagorcnc.simulate(text)
    found = [d for d in r.diagnostics if d.code == "INT078"]
    assert r.ok and len(found) == 1 and what in found[0].message and found[0].line == 1, r.diagnostics


def test_tangfeed_takes_its_minimum_radius():
    # seed 002 L4305: #TANGFEED RMIN [<radius>]
    for bad in ("#TANGFEED RMIN [-1]\nM30\n", "P1=-2\n#TANGFEED RMIN [P1]\nM30\n"):
        assert [d.code for d in fagorcnc.simulate(bad).diagnostics] == ["INT071"], bad
    assert fagorcnc.simulate("P1=2\n#TANGFEED RMIN [P1*3]\nG196\nG01 X10 F100\nM30\n").ok


def test_call_l_and_the_number_of_a_local_subroutine_as_cam_posts_write_it():
    # Autodesk's Fagor 8065 post defines "%L 100" and calls "#CALL L100" (the manual writes "#CALL 100" or
    # "LL 100", seed 002 L10303, L10343): the local subroutine 100 runs, and a note says so once per call
    text = ("%L 100\nG91 G1 X10 F1000\nG90\nM17\n%MAIN\nG0 X0 Y0\nP1=0\n$WHILE P1<3\nP1=P1+1\n#CALL L100\n"
            "$ENDWHILE\nM30\n")
    r = fagorcnc.simulate(text)
    assert r.ok, r.diagnostics
    assert [m.end["X"] for m in r.moves if m.kind == "linear"] == [10.0, 20.0, 30.0]
    assert [(d.code, d.line, d.severity) for d in r.diagnostics] == [("INT116", 10, "info")]
    # a subroutine really named L100 is still the one called; LL keeps the manual's meaning
    named = fagorcnc.simulate("%L L100\nG1 X5 F1000\nM17\n%L 100\nG1 X7 F1000\nM17\n%MAIN\n#CALL L100\nM30\n")
    assert [m.end["X"] for m in named.moves if m.kind == "linear"] == [5.0] and not named.diagnostics
    assert [d.code for d in fagorcnc.simulate("%L 100\nG1 X5 F1000\nM17\n%MAIN\nLL L100\nM30\n").diagnostics] \
        == ["INT091"]


def test_for_with_a_decimal_step_reaches_its_end_value_l17264_l17288():
    # "De P1=0 à P1=10, en incréments de 2 (6 fois)": the end value is included; 0.1 + 0.1 + 0.1 is
    # 0.30000000000000004 in floating point, which must still count as -0.3 / 0.3 reached
    r = ok(run("P100=0\n$FOR P1=-0.1,-0.3,-0.1\nP100=P100+1\n$ENDFOR\nP101=0\n$FOR P2=0,0.6,0.2\n"
               "P101=P101+1\n$ENDFOR\nP102=0\n$FOR P3=0,10,2\nP102=P102+1\n$ENDFOR\nM30\n"))
    assert [r.state.param(n) for n in (100, 101, 102)] == [3, 4, 6]


def test_another_call_or_g80_cancels_the_modal_subroutine_l10568_l10798(tmp_path):
    # L10568: the modal character is cancelled by calling another subroutine (#PCALL, #CALL, L, LL, G180-G189);
    # L10798: or by G80.  #MCALL runs CNT on its own block and after each motion block while modal.
    write(tmp_path, "SUB180.nc", "M17\n")
    mach = machine(tmp_path, oem_subroutines={"180": "SUB180.nc"})
    subs = "%L CNT\nP100=P100+1\nM17\n%MAIN\nP100=0\n#MCALL CNT\nG1 X10 F100\n"
    assert ok(run(subs + "G180\nG1 X20\nM30\n", mach)).state.param(100) == 2
    assert ok(run(subs + "G80\nG1 X20\nG1 X30\nM30\n", mach)).state.param(100) == 2
    assert ok(run(subs + "G1 X20\nM30\n", mach)).state.param(100) == 3   # still modal


def test_rpt_range_rules_l16206_l16241():
    # L16206: "l'étiquette du bloc final doit être programmée seule"; L16241: the labels must differ
    assert ok(run("P100=0\nN10: P100=P100+1\nN20:\n#RPT [N10,N20,2]\nM30\n")).state.param(100) == 3
    for text in ("P100=0\nN10: P100=P100+1\n#RPT [N10,N10,2]\nM30\n",
                 "P100=0\nN10: P100=P100+1\nN20: P100=P100+10\n#RPT [N10,N20]\nM30\n"):
        r = run(text)
        assert [c for c, _ in errors(r)] == ["INT075"], r.diagnostics


def test_rpt_ranges_nest_up_to_20_levels_l16216():
    # "20 niveaux d'imbrication sont permis": an #RPT inside a repeated range, the manual's layout with the
    # ranges after M30 (L16209) and one written inside the other
    r = ok(run("P100=0\nP101=0\n#RPT [[A],[B],2]\nM30\n[A] P100=P100+1\n#RPT [[C],[D],3]\n[B]\n"
               "[C] P101=P101+1\n[D]\n"))
    assert (r.state.param(100), r.state.param(101)) == (2, 6)   # 2 outer passes, 3 inner each
    # N10 runs once, twice more by the inner #RPT, then 3 outer passes of (1 + 2)
    r = ok(run("P100=0\nN10: P100=P100+1\nN20:\nN30: #RPT [N10,N20,2]\nN40:\n#RPT [N10,N40,3]\nM30\n"))
    assert r.state.param(100) == 12
    # each range [Lk] repeats the next one: 20 levels run, 21 are refused

    def chain(n: int) -> str:
        levels = "".join(f"[L{k}] #RPT [[L{k + 1}],[E{k + 1}],1]\n[E{k}]\n" for k in range(1, n))
        return f"#RPT [[L1],[E1],1]\nM30\n{levels}[L{n}] P1=1\n[E{n}]\n"

    assert ok(run(chain(20))).state.param(1) == 1
    r = run(chain(21))
    assert [c for c, _ in errors(r)] == ["INT075"] and "20 deep" in r.diagnostics[0].message
