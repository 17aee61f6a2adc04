"""Macros: ``#DEF``, ``#INIT MACROTAB`` and blocks that use them (seed 002 ch. 21.1.16, L16113-L16202)."""

from __future__ import annotations

import math

import pytest

import fagorcnc

MANUAL_EXAMPLE = (   # seed 002 L16153-L16166, as printed
    '#DEF "READY"="G0 X0 Y0 Z10"\n'
    '#DEF "START"="SP1 M3 M41" "STOP"="M05"\n'
    '"READY"\n'
    'P1=800 "START" F450\n'
    "G01 Z0\n"
    "X40 Y40\n"
    '"STOP"\n'
    "M30\n"
)


def _errors(result) -> list[str]:
    return [d.code for d in result.diagnostics if d.is_error]


def _aux(result, line: int) -> list[tuple[str, float]]:
    return [(m.function, m.value) for m in result.moves if m.kind == "aux" and m.line == line]


def test_the_manuals_example_runs_as_the_blocks_it_stands_for():
    r = fagorcnc.simulate(MANUAL_EXAMPLE)
    assert r.ok, r.diagnostics
    ready = [m for m in r.moves if m.line == 3]
    # "READY" is G0 X0 Y0 Z10: one rapid to (0, 0, 10)
    assert [m.kind for m in ready] == ["rapid"] and ready[0].end == {"X": 0.0, "Y": 0.0, "Z": 10.0}
    # P1=800 "START" F450 is P1=800, then S800 M3 M41 F450 (L16162): the spindle at 800, M3, M41
    assert r.state.param(1) == 800.0
    assert [v for _, v in _aux(r, 4)] == [800.0, 3.0, 41.0]
    # ... and F450 is the feed of the next G01 blocks
    assert [(m.kind, m.feed, m.end["Z"]) for m in r.moves if m.line == 5] == [("linear", 450.0, 0.0)]
    assert [m.end for m in r.moves if m.line == 6] == [{"X": 40.0, "Y": 40.0, "Z": 0.0}]
    assert [v for _, v in _aux(r, 7)] == [5.0]   # "STOP" is M05


def test_parse_accepts_blocks_that_use_macros():
    program = fagorcnc.parse(MANUAL_EXAMPLE)
    assert [d for d in program.diagnostics if d.is_error] == []


def test_a_complete_expression_is_an_operand_inside_another_macro():
    # seed 002 L16168-L16170: "MACRO1"="P1*3", "MACRO2"="SIN [\"MACRO1\"]"
    r = fagorcnc.simulate('#DEF "MACRO1"="P1*3"\n#DEF "MACRO2"="SIN [\\"MACRO1\\"]"\n'
                          'P1=10\nG1 X["MACRO2"] F100\nG1 X[2*"MACRO1"]\nM30\n')
    assert r.ok, r.diagnostics
    # SIN[P1*3] = sin 30 degrees = 0.5; inside brackets a macro is one operand: 2*[P1*3] = 60, not 2*P1*3
    assert [round(m.end["X"], 9) for m in r.moves if m.kind == "linear"] == [0.5, 60.0]


@pytest.mark.parametrize("body", ["56+", "SIN[", "45]"])
def test_an_arithmetic_operation_must_be_complete_inside_one_macro(body):
    # seed 002 L16172-L16181: "56+" then "12", "SIN[" then "45]" are wrong definitions
    r = fagorcnc.simulate(f'#DEF "MACRO1"="{body}"\nG1 X10 F100\nM30\n')
    assert _errors(r) == ["MAC005"]
    assert r.moves == []   # the #DEF stops the program: nothing after it moves


def test_macros_inside_macros_chain():
    # seed 002 L16199-L16202, example 2
    r = fagorcnc.simulate('#DEF "POS"="G1 X0 Y0 Z0"\n#DEF "START"="S750 F450 M03"\n'
                          '#DEF "MACRO"="\\"POS\\" \\"START\\""\nG0 X5 Y5 Z5\n"MACRO"\nM30\n')
    assert r.ok, r.diagnostics
    line5 = [m for m in r.moves if m.line == 5]
    assert [m.kind for m in line5 if m.kind != "aux"] == ["linear"]
    assert line5[-1].end == {"X": 0.0, "Y": 0.0, "Z": 0.0} and line5[-1].feed == 450.0
    assert [v for _, v in _aux(r, 5)] == [750.0, 3.0]


def test_the_manuals_example_1_names_macros_it_never_defined():
    # seed 002 L16193-L16197: "MACRO3" names \"MA1\" and \"MA2\" (meant MACRO1, MACRO2): an error where it runs
    r = fagorcnc.simulate('#DEF "MACRO1"="X20 Y35"\n#DEF "MACRO2"="S1000 M03"\n'
                          '#DEF "MACRO3"="G01 \\"MA1\\" F100 \\"MA2\\""\n"MACRO3"\nM30\n')
    assert _errors(r) == ["MAC001"]
    assert r.diagnostics[0].line == 4 and '"MA1"' in r.diagnostics[0].message


def test_a_macro_used_before_its_definition_is_an_error():
    r = fagorcnc.simulate('G0 X0\n"READY"\n#DEF "READY"="G0 X10"\nM30\n')
    assert _errors(r) == ["MAC001"] and r.diagnostics[0].line == 2
    assert [m.line for m in r.moves] == [1]   # nothing from line 2 on


def test_init_macrotab_empties_the_table():
    # seed 002 L16186-L16188
    r = fagorcnc.simulate('#DEF "READY"="G0 X10"\n"READY"\n#INIT MACROTAB\n"READY"\nM30\n')
    assert _errors(r) == ["MAC001"] and r.diagnostics[0].line == 4
    assert [m.end["X"] for m in r.moves if m.kind == "rapid"] == [10.0]


def test_fifty_macros_at_most_and_a_redefinition_takes_no_new_place():
    # seed 002 L16127-L16131: 50 macros; defining more is an error
    fifty = "".join(f'#DEF "M{i}"="G0 X{i}"\n' for i in range(50))
    again = fagorcnc.simulate(fifty + '#DEF "M7"="G0 X77"\n"M7"\nM30\n')
    assert again.ok, again.diagnostics
    assert [m.end["X"] for m in again.moves if m.kind == "rapid"] == [77.0]
    more = fagorcnc.simulate(fifty + '#DEF "M50"="G0 X50"\nM30\n')
    assert _errors(more) == ["MAC002"] and more.diagnostics[0].line == 51


def test_name_and_text_lengths():
    # seed 002 L16146-L16152: names up to 30 letters and digits, texts up to 140 characters
    name30, text140 = "A" * 30, "G0 X1" + " " * 135
    ok = fagorcnc.simulate(f'#DEF "{name30}"="{text140}"\n"{name30}"\nM30\n')
    assert ok.ok, ok.diagnostics
    assert _errors(fagorcnc.simulate(f'#DEF "{"A" * 31}"="G0 X1"\nM30\n')) == ["MAC003"]
    assert _errors(fagorcnc.simulate('#DEF "A_B"="G0 X1"\nM30\n')) == ["MAC003"]
    assert _errors(fagorcnc.simulate(f'#DEF "LONG"="{text140} "\nM30\n')) == ["MAC004"]


def test_a_macro_that_names_itself_is_refused():
    r = fagorcnc.simulate('#DEF "LOOP"="G0 \\"LOOP\\""\n"LOOP"\nM30\n')
    assert _errors(r) == ["MAC007"]


def test_an_expanded_block_that_does_not_read_is_reported_with_its_text():
    r = fagorcnc.simulate('#DEF "BAD"="G1 X"\n"BAD" Y+*2\nM30\n')
    assert _errors(r) == ["MAC006"]
    assert "G1 X Y+*2" in r.diagnostics[0].message


def test_def_must_be_alone_in_its_block():
    # seed 002 L16134: the definition is programmed alone in the block
    program = fagorcnc.parse('G1 X10 #DEF "A"="G0 X1"\n')
    assert [d.code for d in program.diagnostics] == ["SYN014"]


def test_a_macro_block_keeps_its_jump_target_and_block_skip():
    r = fagorcnc.simulate('#DEF "STEP"="G91 G1 X1 F100"\nP1=0\nN10: "STEP"\nP1=P1+1\n$IF P1<3 $GOTO N10\n'
                          '/"STEP"\nG90\nM30\n', None)
    moves = [m for m in r.moves if m.kind == "linear"]
    assert r.ok and [m.end["X"] for m in moves] == [1.0, 2.0, 3.0, 4.0]   # block skip off: line 6 runs
    skipped = fagorcnc.simulate('#DEF "STEP"="G91 G1 X1 F100"\n"STEP"\n/"STEP"\nM30\n', None)
    assert len([m for m in skipped.moves if m.kind == "linear"]) == 2
    from fagorcnc.simulate import simulate

    on = simulate('#DEF "STEP"="G91 G1 X1 F100"\n"STEP"\n/"STEP"\nM30\n', block_skip=True)
    assert len([m for m in on.moves if m.kind == "linear"]) == 1


def test_a_message_string_is_not_a_macro():
    r = fagorcnc.simulate('#DEF "READY"="G0 X5"\n#MSG "READY"\nG0 X1\nM30\n')
    assert r.ok, r.diagnostics
    assert [d.message for d in r.diagnostics if d.code == "INT077"] == ["#MSG: READY"]
    assert [math.isclose(m.end["X"], 1.0) for m in r.moves if m.kind == "rapid"] == [True]
