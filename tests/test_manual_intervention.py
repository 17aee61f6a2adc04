"""Manual intervention: G200, G201/G202 with #AXIS, #CONTJOG, #INCJOG, #MPG, #SET OFFSET, #SYNC POS
(seed 002 ch. 8.9, L7691-L7988).  Offline nothing moves by hand: the path is the programmed one."""

from __future__ import annotations

import pytest

import fagorcnc
from fagorcnc.interp.interpreter import Interpreter
from fagorcnc.machine import load_machine
from fagorcnc.syntax import parse_text


def _interp(program: str) -> Interpreter:
    interp = Interpreter(parse_text(program), load_machine(None))
    list(interp.run())
    return interp


def _errors(program: str) -> list[str]:
    return [d.code for d in fagorcnc.simulate(program).diagnostics if d.is_error]


def test_the_manuals_additive_example():
    # seed 002 L7760-L7772: G201 on X-Z, G202 on X, then on Z
    program = ("N100 G71 G90 X0 Y0 F400\nN110 G201 #AXIS [X, Z]\nN120 G01 X100 Y50\nN130 G202 #AXIS [X]\n"
               "N140 G01 X50 Y150\nN150 G202 #AXIS [Z]\n")
    r = fagorcnc.simulate(program + "M30\n")
    assert r.ok, r.diagnostics
    # the path is the programmed one: nothing moves by hand offline
    assert [(m.end["X"], m.end["Y"]) for m in r.moves if m.kind == "linear"] == [(100.0, 50.0), (50.0, 150.0)]
    states = []
    for stop in ("N110", "N130", "N150"):
        text = program[:program.index(stop)] + program[program.index(stop):].split("\n", 1)[0] + "\n"
        states.append(sorted(_interp(text).manual.additive))
    assert states == [["X", "Z"], ["Z"], []]


def test_g202_alone_cancels_every_axis_and_the_end_of_the_program_resets():
    # L7754: G202 alone cancels the intervention on every axis; L7728-L7729: M30 -> G202
    assert _interp("G201 #AXIS [X, Y, Z]\nG202\n").manual.additive == set()
    assert _interp("G201 #AXIS [X, Y]\nM30\n").manual.additive == set()


def test_g200_stops_the_motion_and_says_the_machine_waits():
    # L7789-L7806: G200 interrupts the program until [CYCLE START], on the listed axes or all
    r = fagorcnc.simulate("G1 X10 F400\nG200 #AXIS [X, Z]\nG1 X100 Y100\nG200\nM30\n")
    assert r.ok, r.diagnostics
    assert [(m.kind, m.line) for m in r.moves if m.kind != "aux"] == [("linear", 1), ("dwell", 2), ("linear", 3),
                                                                      ("dwell", 4)]
    notes = [d.message for d in r.diagnostics if d.code == "INT170"]
    assert "on X, Z" in notes[0] and "every axis" in notes[1]


@pytest.mark.parametrize("program, code", [
    ("G201\n", "INT171"),                      # L7745: G201 always with #AXIS, at least one axis
    ("G201 #AXIS [S]\n", "INT171"),            # L7736: not on a spindle
    ("G201 #AXIS [Q]\n", "INT024"),            # not an axis of the channel
    ("G200 G201 #AXIS [X]\n", "INT012"),       # L7726: incompatible with one another
    ("G201 G202 #AXIS [X]\n", "INT012"),
    ("#AXIS [X]\n", "INT171"),                 # #AXIS belongs to G200-G202
    ("G1 X1 F100 #AXIS [X]\n", "INT171"),
])
def test_intervention_errors(program, code):
    assert _errors(program + "M30\n") == [code]


def test_jog_and_handwheel_settings_in_the_programs_units():
    # L7857-L7912, the manual's examples: #CONTJOG [400] X, #INCJOG [[0.1,100]...[10,500]] X, #MPG [0.1,1,10] X
    manual = _interp("#CONTJOG [400] X\n#INCJOG [[0.1,100][0.5,200][1,300][5,400][10,500]] X\n"
                     "#MPG [0.1,1,10] X\n#MPG [0.5] Y\nG70\n#CONTJOG [10] Y\n").manual
    assert manual.contjog == {"X": 400.0, "Y": 254.0}   # 10 in/min = 254 mm/min
    assert manual.incjog["X"] == ((0.1, 100.0), (0.5, 200.0), (1.0, 300.0), (5.0, 400.0), (10.0, 500.0))
    assert manual.mpg == {"X": (0.1, 1.0, 10.0), "Y": (0.5,)}


@pytest.mark.parametrize("statement", ["#CONTJOG [0] X", "#CONTJOG [400]", "#CONTJOG [400] S",
                                       "#INCJOG [[0.1,100][0.5,200][1,300][5,400][10,500][20,600]] X",
                                       "#INCJOG [[0.1][0.5,200]] X", "#MPG [0.1,1,10,100] X", "#MPG [-1] X"])
def test_jog_setting_errors(statement):
    assert _errors(statement + "\nM30\n") == ["INT171"]


def test_set_offset_limits():
    # L7916-L7920, the manual's example N100-N120; lower <= 0 <= upper; after G201 (L7847)
    manual = _interp("G01 X30 Y30 F550\nN100 G201 #AXIS [Y]\nN110 #SET OFFSET [-20,35] Y\nN120 G01 X100 Y45 F400\n"
                     "#SYNC POS\n").manual
    assert manual.offset_limits == {"Y": (-20.0, 35.0)}
    assert _interp("G201 #AXIS [Y]\n#SET OFFSET [-20,35] Y\nG202 #AXIS [Y]\n").manual.offset_limits == {}
    assert _errors("#SET OFFSET [-20,35] Y\nM30\n") == ["INT171"]           # before G201 on Y
    assert _errors("G201 #AXIS [Y]\n#SET OFFSET [5,35] Y\nM30\n") == ["INT171"]
    assert _errors("G201 #AXIS [Y]\n#SET OFFSET [-5,-1] Y\nM30\n") == ["INT171"]


def test_sync_pos_and_the_manual_offset_variables_stop_preparation():
    # L7971: #SYNC POS takes the execution position; V.A.ADDMANOF (L41028) is 0: nothing moved by hand
    r = fagorcnc.simulate("G1 X10 F400\n#SYNC POS\nG1 X20\nP1=V.A.ADDMANOF.X P2=V.A.MANOF.Y\nG1 X30\nM30\n")
    assert r.ok, r.diagnostics
    assert [(m.kind, m.line) for m in r.moves if m.kind != "aux"] == [
        ("linear", 1), ("dwell", 2), ("linear", 3), ("dwell", 4), ("linear", 5)]
    assert (r.state.param(1), r.state.param(2)) == (0.0, 0.0)
    assert not [d for d in r.diagnostics if d.code in ("INT078", "INT079")]
