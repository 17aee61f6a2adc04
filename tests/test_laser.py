"""Laser functions: #SWTOUT and #PWMOUT, their state and V.G variables (seed 002 ch. 19, L13670-L13965)."""

from __future__ import annotations

import pytest

import fagorcnc
from fagorcnc.interp.laser import Laser


def _params(program: str, *numbers: int) -> list[float]:
    r = fagorcnc.simulate(program)
    assert r.ok, r.diagnostics
    return [r.state.param(n) for n in numbers]


def _errors(program: str) -> list[str]:
    return [d.code for d in fagorcnc.simulate(program).diagnostics if d.is_error]


READ_SWT = "P1=V.G.TON P2=V.G.TOF P3=V.G.PON P4=V.G.POF\nM30\n"
READ_PWM = "P1=V.G.PWMON P2=V.G.PWMFREQ P3=V.G.PWMDUTY\nM30\n"


@pytest.mark.parametrize("statement", ["#SWTOUT ON [TON=50 TOF=40]", "#SWTOUT ON [TON50 TOF40]",
                                       "#SWTOUT ON [TON=50, TOF=40]"])
def test_swtout_offsets_are_the_variables(statement):
    # L13758-L13764: the manual's forms, "=" optional; L13785: the statement's values become the variables'
    assert _params(f"{statement}\n{READ_SWT}", 1, 2, 3, 4) == [50.0, 40.0, 0.0, 0.0]


def test_swtout_without_values_keeps_the_variables_values():
    # L13787-L13790: #SWTOUT ON alone takes the variables' current values
    assert _params(f"V.G.TON=20 V.G.POF=-0.5\n#SWTOUT ON\n{READ_SWT}", 1, 2, 3, 4) == [20.0, 0.0, 0.0, -0.5]


def test_distance_offsets_are_in_the_programs_units():
    # PON/POF in mm or inch (L13751): 0.3 in = 7.62 mm
    assert _params(f"G70\n#SWTOUT ON [PON=0.3]\nG71\n{READ_SWT}", 3) == pytest.approx([7.62])
    assert _params(f"G70\nV.G.POF=1\nG71\n{READ_SWT}", 4) == pytest.approx([25.4])


def test_swtout_off_and_the_end_of_the_program_stop_switching_and_keep_the_offsets():
    # L13767-L13769: #SWTOUT OFF, M30 and reset switch it off; L13727-L13729: the offsets are kept
    laser = Laser(switching=True, ton=50.0, pof=0.2)
    laser.end_of_program()
    assert (laser.switching, laser.ton, laser.pof) == (False, 50.0, 0.2)
    assert _params(f"#SWTOUT ON [TON 5]\n#SWTOUT OFF\n{READ_SWT}", 1) == [5.0]


@pytest.mark.parametrize("statement", ["#PWMOUT ON [FREQ 200, DUTY 50]", "#PWMOUT ON [F200, D50]"])
def test_pwmout_frequency_and_duty(statement):
    # L13886-L13887: the manual's two spellings of the same statement
    assert _params(f"{statement}\n{READ_PWM}", 1, 2, 3) == [1.0, 200.0, 50.0]


def test_pwmout_defaults_and_last_values():
    # L13871: FREQ the last value, else 0; L13877: DUTY the last value, else 50
    assert _params(f"#PWMOUT ON\n{READ_PWM}", 1, 2, 3) == [1.0, 0.0, 50.0]
    assert _params(f"#PWMOUT ON [FREQ 200, DUTY 25]\n#PWMOUT OFF\nP4=V.G.PWMON\n#PWMOUT ON [D 30]\n{READ_PWM}",
                   4, 1, 2, 3) == [0.0, 1.0, 200.0, 30.0]


def test_pwmout_burst_mode_is_accepted():
    # L13888: #PWMOUT ON [FREQ 200, DUTY 25, PWMBTIME 50, PWMBEND 1]
    assert _params(f"#PWMOUT ON [FREQ 200, DUTY 25, PWMBTIME 50, PWMBEND 1]\n{READ_PWM}", 2, 3) == [200.0, 25.0]


@pytest.mark.parametrize("args", ["FREQ 1", "FREQ 5001", "DUTY 0", "DUTY 100.5", "PWMBEND 2", "PWMBTIME 0",
                                  "POWER 5", "FREQ 200, FREQ 300"])
def test_pwmout_values_outside_the_manuals_ranges_are_errors(args):
    # L13869: 2-5000 Hz; L13875: 0.1-100 %; L13907: PWMBEND 0 or 1
    assert _errors(f"#PWMOUT ON [{args}]\nM30\n") == ["INT117"]


def test_swtout_takes_only_its_four_offsets():
    assert _errors("#SWTOUT ON [TON=1 XON=2]\nM30\n") == ["INT117"]


def test_the_pwm_variables_are_read_only():
    assert _errors("V.G.PWMON=1\nM30\n") == ["INT048"]


def test_the_statements_and_variables_stop_block_preparation():
    # L13844 (#PWMOUT ON), L13795-L13799 (the #SWTOUT variables): the motion before them ends there,
    # a synchronisation point (a dwell of no time) between the two moves
    for middle in ("#PWMOUT ON [F100]", "#SWTOUT ON", "P1=V.G.TON", "V.G.TOF=3"):
        r = fagorcnc.simulate(f"G1 X10 F1000\n{middle}\nG1 X20\nM30\n")
        assert r.ok, r.diagnostics
        kinds = [(m.kind, m.line) for m in r.moves if m.kind != "aux"]
        assert kinds == [("linear", 1), ("dwell", 2), ("linear", 3)], middle
