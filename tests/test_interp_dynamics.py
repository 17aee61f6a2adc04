"""Planning context handed by the interpreter to the planner (fagorcnc/interp/dynamics.py).

Corner modes G05/G07/G50/G60/G61 and HSC (spec 04 §1, spec 06 §1), #ROUNDPAR (spec 04 §2),
#SLOPE, G130-G135 percentages (spec 02 §14-§15), G108/G109/G193/G266 (spec 02 §11, §13)
and the [planner] machine configuration.  Seed references are to the French manual 002.
"""

from __future__ import annotations

import pytest

import fagorcnc
from fagorcnc.config.machine import MachineError, load_machine
from fagorcnc.interp.dynamics import Hsc

MOTION = ("linear", "arc", "rapid")


def dyns(text: str, machine=None) -> list:
    """The Dynamics of every motion record of a program that must run without error."""
    r = fagorcnc.simulate(text, machine)
    assert not r.errors, [str(d) for d in r.diagnostics]
    return [m.dyn for m in r.moves if m.kind in MOTION]


def last(text: str, machine=None):
    """The Dynamics of the last motion record."""
    return dyns(text, machine)[-1]


def errors(text: str, machine=None) -> list:
    """(code, line) of every error diagnostic."""
    return [(d.code, d.line) for d in fagorcnc.simulate(text, machine).errors]


def hsc(statement: str, machine=None) -> Hsc:
    """The Hsc recorded on a move after ``statement``."""
    d = last(f"{statement}\nG1 X1 F100\nM30\n", machine)
    assert d.corner == "HSC"
    return d.hsc


def final_state(text: str, machine=None):
    """The channel state after the run (private, read-only here)."""
    r = fagorcnc.simulate(text, machine)
    assert not r.errors, [str(d) for d in r.diagnostics]
    return r.state._state


# ---------------------------------------------------------------- 1. corner modes

def test_default_corner_mode_is_g50():
    # ICORNER 0 = G50 (seed 002 L8021-L8023, L20157)
    d = last("G1 X10 F100\nM30\n")
    assert (d.corner, d.hsc) == ("G50", None)


def test_g05_g07_g50_are_modal_per_record():
    ds = dyns("G1 X10 F100\nG05 X20\nX25\nG07 X30\nX35\nG50 X40\nM30\n")
    assert [d.corner for d in ds] == ["G50", "G05", "G05", "G07", "G07", "G50"]


@pytest.mark.parametrize(("icorner", "mode"), [(1, "G05"), (2, "G07")])
def test_icorner_chooses_the_power_on_corner_mode(icorner, mode):
    # seed 002 L8021-L8023: G05, G07 or G50 according to ICORNER
    assert last("G1 X10 F100\nM30\n", {"defaults": {"ICORNER": icorner}}).corner == mode


def test_g60_is_a_square_corner_for_its_own_block_only():
    # seed 002 L8018: after the G60 block the previous mode (here G05) comes back
    ds = dyns("G05 G1 X10 F100\nG60 X20\nX30\nM30\n")
    assert [d.corner for d in ds] == ["G05", "G07", "G05"]


def test_g61_is_a_rounded_corner_for_its_own_block_only():
    # seed 002 L8107
    ds = dyns("G07 G1 X10 F100\nG61 X20\nX30\nM30\n")
    assert [d.corner for d in ds] == ["G07", "G05", "G07"]


def test_g60_and_g61_apply_to_arcs_and_rapids():
    ds = dyns("G0 X1\nG60 G2 X3 Y2 R2 F100\nG0 G61 X0\nX5\nM30\n")
    assert [d.corner for d in ds] == ["G50", "G07", "G05", "G50"]


def test_g60_inside_hsc_is_g07_for_its_block_then_hsc_again():
    # seed 002 L8018-L8019 (previous mode may be HSC), L13659-L13660 (G60 does not cancel HSC)
    ds = dyns("#HSC ON [CONTERROR 0.02]\nG1 X10 F100\nG60 X20\nX30\nM30\n")
    assert [d.corner for d in ds] == ["HSC", "G07", "HSC"]
    assert ds[1].hsc is None
    assert ds[2].hsc == Hsc("CONTERROR", 0.02, 150.0, 100.0)


def test_g61_inside_hsc_is_g05_for_its_block_then_hsc_again():
    ds = dyns("#HSC ON\nG1 X10 F100\nG61 X20\nX30\nM30\n")
    assert [d.corner for d in ds] == ["HSC", "G05", "HSC"]


def test_records_share_one_dynamics_until_something_changes():
    ds = dyns("G1 X1 F100\nX2\nG130 X50\nX3\nM30\n")
    assert ds[0] is ds[1]
    assert ds[1] is not ds[2]


@pytest.mark.parametrize("code", ["G60", "G61 G60"])
def test_g60_g61_in_a_block_without_motion_is_an_error(code):
    # a lone G61 is the CAM posts' construct CAM002 (a warning by default, tests/test_cam_posts.py)
    assert [line for _code, line in errors(f"G1 X1 F100\n{code}\nX2\nM30\n")] == [2]


@pytest.mark.parametrize("pair", ["G05 G60", "G07 G61", "G60 G61"])
def test_incompatible_corner_functions_in_one_block_are_an_error(pair):
    assert [line for _code, line in errors(f"G1 X1 F100\n{pair} X2\nM30\n")] == [2]


# ---------------------------------------------------------------- 2. #HSC ON

def test_hsc_conterror_with_corner():
    # seed 002 L13501, L13541
    assert hsc("#HSC ON [CONTERROR 0.02, CORNER 140]") == Hsc("CONTERROR", 0.02, 140.0, 100.0)


def test_hsc_fast_with_percentage_and_chordal_error():
    # seed 002 L13600, L13631
    assert hsc("#HSC ON [FAST 93.5, E 0.05]") == Hsc("FAST", 0.05, 150.0, 93.5)


def test_hsc_surface_with_chordal_error():
    # seed 002 L13482 (SURFACE keeps the machine CORNER, unused)
    assert hsc("#HSC ON [SURFACE, E0.1]") == Hsc("SURFACE", 0.1, 150.0, 100.0)


def test_plain_hsc_on_is_the_default_mode_with_machine_defaults():
    # seed 002 L1653; spec 06 §1.2: HSCDEFAULTMODE 1 = CONTERROR, HSCROUND 0.01, CORNER 150
    assert hsc("#HSC ON") == Hsc("CONTERROR", 0.01, 150.0, 100.0)


def test_hsc_mode_may_be_omitted():
    # seed 002 L13471, L13542: #HSC ON [CORNER 150] is a CONTERROR statement
    assert hsc("#HSC ON [CORNER 130]") == Hsc("CONTERROR", 0.01, 130.0, 100.0)


@pytest.mark.parametrize(("statement", "expected"), [
    # seed 002 L13621-L13645: FASTFACTOR 100, "ROUNDPAR" = hsc_round 0.01, CORNER 150 when omitted
    ("#HSC ON [FAST]", Hsc("FAST", 0.01, 150.0, 100.0)),                             # L13621
    ("#HSC ON [FAST, E 0.05]", Hsc("FAST", 0.05, 150.0, 100.0)),                     # L13626
    ("#HSC ON [FAST 93.5, E 0.05]", Hsc("FAST", 0.05, 150.0, 93.5)),                 # L13631
    ("#HSC ON [FAST 93.5, E 0.01, CORNER 130]", Hsc("FAST", 0.01, 130.0, 93.5)),     # L13636
    ("#HSC ON [FAST, CORNER 130]", Hsc("FAST", 0.01, 130.0, 100.0)),                 # L13641
])
def test_hsc_fast_table_of_the_manual(statement, expected):
    assert hsc(statement) == expected


def test_hsc_default_mode_0_makes_the_omitted_mode_surface():
    # HSCDEFAULTMODE 0 = SURFACE (seed 002 L19804)
    assert hsc("#HSC ON [E 0.05]", {"planner": {"hsc_default_mode": 0}}) == Hsc("SURFACE", 0.05, 150.0, 100.0)


def test_hsc_defaults_come_from_the_planner_config():
    machine = {"planner": {"hsc_default_mode": 2, "fast_factor": 90, "corner": 120, "hsc_round": 0.03}}
    assert hsc("#HSC ON", machine) == Hsc("FAST", 0.03, 120.0, 90.0)


def test_hsc_round_0_falls_back_to_max_round():
    # spec 07 (HSCROUND = 0 -> MAXROUND)
    assert hsc("#HSC ON", {"planner": {"hsc_round": 0, "max_round": 0.02}}).tolerance == pytest.approx(0.02)


# ---------------------------------------------------------------- 3. #HSC errors

def test_second_hsc_on_while_active_is_an_error():
    # seed 002 L13660: a second HSC mode does not cancel the first
    assert errors("#HSC ON\nG1 X1 F100\n#HSC ON [SURFACE]\nM30\n") == [("INT110", 3)]


def test_second_hsc_on_after_g60_block_is_still_an_error():
    # G60 does not cancel HSC (L13660)
    assert errors("#HSC ON\nG1 X1 F100\nG60 X2\n#HSC ON [SURFACE]\nM30\n") == [("INT110", 4)]


@pytest.mark.parametrize("statement", [
    "#HSC ON [SURFACE, CONTERROR 0.1]",       # two modes in one statement
    "#HSC ON [SURFACE, CORNER 100]",          # CORNER is not in the SURFACE syntax (L13469)
    "#HSC ON [CONTERROR 0.02, E 0.1]",        # CONTERROR takes its tolerance after the keyword (L13501)
    "#HSC ON [CORNER 200]",                   # CORNER 0..180 (L13537)
    "#HSC ON [CORNER -1]",
    "#HSC ON [FAST 0]",                       # FAST 0.01..100 % (L13605)
    "#HSC ON [FAST 150]",
    "#HSC ON [CONTERROR 0]",                  # tolerance must be positive
    "#HSC ON [SURFACE, E-0.1]",
    "#HSC ON [FOO 3]",                        # unknown keyword
    "#HSC ON [E 0.1, E 0.2]",                 # written twice
    "#HSC ON [CORNER]",                       # keyword without value
])
def test_invalid_hsc_statement_is_int110_on_its_line(statement):
    assert errors(f"G1 X1 F100\n{statement}\nX2\nM30\n") == [("INT110", 2)]


# ---------------------------------------------------------------- 4. cancelling HSC

def test_hsc_off_cancels_hsc():
    ds = dyns("#HSC ON\nG1 X1 F100\n#HSC OFF\nX2\nM30\n")
    assert [(d.corner, d.hsc is None) for d in ds] == [("HSC", False), ("G50", True)]


@pytest.mark.parametrize("code", ["G05", "G07", "G50"])
def test_g05_g07_g50_cancel_hsc(code):
    # seed 002 L13659
    ds = dyns(f"#HSC ON\nG1 X1 F100\n{code} X2\nX3\nM30\n")
    assert [d.corner for d in ds] == ["HSC", code, code]
    assert ds[2].hsc is None


def test_after_g50_a_new_hsc_on_is_accepted():
    d = last("#HSC ON\nG1 X1 F100\nG50\n#HSC ON [SURFACE]\nX2\nM30\n")
    assert d.hsc == Hsc("SURFACE", 0.01, 150.0, 100.0)


@pytest.mark.parametrize("code", ["G60", "G61"])
def test_g60_g61_do_not_cancel_hsc(code):
    # seed 002 L13660
    assert last(f"#HSC ON\nG1 X1 F100\n{code} X2\nX3\nM30\n").corner == "HSC"


def test_m30_cancels_hsc():
    # seed 002 L13665-L13667
    assert final_state("#HSC ON\nG1 X1 F100\nM30\n").hsc is None


def test_m30_restores_the_machine_roundpar_and_corner_mode():
    # seed 002 L8021-L8023 (ICORNER), spec 04 §2 (ROUNDTYPE re-applied at M02/M30)
    machine = {"planner": {"round_type": 1, "round_feed": 80}, "defaults": {"ICORNER": 2}}
    st = final_state("#ROUNDPAR [3, 1, 2]\nG05 G1 X1 F100\nM30\n", machine)
    assert st.roundpar == (2, 80.0)
    assert st.dynamics().corner == "G07"


# ---------------------------------------------------------------- 5. #ROUNDPAR

@pytest.mark.parametrize(("statement", "expected"), [
    ("#ROUNDPAR [1, 0.05]", (1, 0.05)),     # seed 002 L8125
    ("#ROUNDPAR [2, 40]", (2, 40.0)),       # L8215
    ("#ROUNDPAR [3, 2, 3]", (3, 2.0, 3.0)),  # L8186
    ("#ROUNDPAR [4, 0.02]", (4, 0.02)),     # L8196
])
def test_roundpar_types(statement, expected):
    assert last(f"{statement}\nG05 G1 X1 F100\nM30\n").roundpar == expected


def test_roundpar_default_from_round_type_1():
    # ROUNDTYPE 1: feed percentage ROUNDFEED (seed 002 L20236, L20286)
    assert last("G1 X1 F100\nM30\n", {"planner": {"round_type": 1, "round_feed": 80}}).roundpar == (2, 80.0)


def test_roundpar_default_machine_is_type_1_maxround():
    assert last("G1 X1 F100\nM30\n").roundpar == (1, 0.01)


@pytest.mark.parametrize("statement", [
    "#ROUNDPAR [6, 1]",        # type 1..5 only
    "#ROUNDPAR [1]",           # missing parameter
    "#ROUNDPAR [3, 2]",
    "#ROUNDPAR [1, 0]",        # e > 0
    "#ROUNDPAR [4, -1]",
    "#ROUNDPAR [2, 101]",      # f <= 100 %
    "#ROUNDPAR [2, 0]",
    "#ROUNDPAR [3, 0, 2]",
])
def test_invalid_roundpar_is_int111(statement):
    assert errors(f"G1 X1 F100\n{statement}\nM30\n") == [("INT111", 2)]


def test_roundpar_type_5_is_a_warning_not_an_error():
    # seed 002 L8258-L8259, L8328 (negative a and b allowed)
    r = fagorcnc.simulate("#ROUNDPAR [5, -30, -30, 55, -5, 0]\nG1 X1 F100\nM30\n")
    assert r.ok
    assert [(d.code, d.line, d.severity) for d in r.diagnostics] == [("INT115", 1, "warning")]
    (m,) = [m for m in r.moves if m.kind in MOTION]
    assert m.dyn.roundpar == (5, -30.0, -30.0, 55.0, -5.0, 0.0)


# ---------------------------------------------------------------- 6. #SLOPE

def test_slope_four_values():
    # seed 002 L16080
    assert last("#SLOPE [1,1,0,0]\nG1 X1 F100\nM30\n").slope == (1, 1, 0, 0)


def test_slope_empty_fields_are_zero():
    # seed 002 L16082
    assert last("#SLOPE [2,,,1]\nG1 X1 F100\nM30\n").slope == (2, 0, 0, 1)


def test_slope_default_comes_from_slope_type():
    assert last("G1 X1 F100\nM30\n", {"planner": {"slope_type": 2}}).slope == (2, 0, 0, 0)


def test_slope_type_alone():
    assert last("#SLOPE [1]\nG1 X1 F100\nM30\n").slope == (1, 0, 0, 0)


@pytest.mark.parametrize("statement", ["#SLOPE [1,1,0,2]", "#SLOPE [1,3]", "#SLOPE [1,1,0,0,0]", "#SLOPE [1,0.5]"])
def test_invalid_slope_is_int111(statement):
    assert errors(f"G1 X1 F100\n{statement}\nM30\n") == [("INT111", 2)]


@pytest.mark.parametrize("statement", ["#SLOPE [3]", "#SLOPE [1.5]", "#SLOPE [-1]"])
def test_invalid_single_slope_type_is_int111(statement):
    assert errors(f"G1 X1 F100\n{statement}\nM30\n") == [("INT111", 2)]


# ---------------------------------------------------------------- 7. G130-G135

def test_g130_axis_words_are_percentages_not_targets():
    # seed 002 L4430-L4433: G130 X50 Y20 then G01 X0
    r = fagorcnc.simulate("G1 X5 Y5 F100\nG130 X50 Y20\nG1 X10\nM30\n")
    assert r.ok
    moves = [m for m in r.moves if m.kind in MOTION]
    assert [m.src.line for m in moves] == [1, 3]
    assert moves[1].end == pytest.approx({"X": 10.0, "Y": 5.0, "Z": 0.0})
    assert moves[0].dyn.acceleration == ()
    assert moves[1].dyn.acceleration == (("X", 50.0), ("Y", 20.0))


def test_g131_100_restores_all_and_moves():
    # seed 002 L4437: G131 100 X50 Y80 -> 100 % on every axis, move to X50 Y80
    r = fagorcnc.simulate("G1 X5 F100\nG130 X50 Y20\nG131 100 X50 Y80\nM30\n")
    assert r.ok
    m = [m for m in r.moves if m.kind in MOTION][-1]
    assert m.src.line == 3 and m.end == pytest.approx({"X": 50.0, "Y": 80.0, "Z": 0.0})
    assert m.dyn.acceleration == ()


def test_g133_sets_jerk_of_every_axis_and_spindle():
    # seed 002 L4459-L4468, L4511: all axes and spindles
    d = last("G133 30\nG1 X10 F100\nM30\n")
    assert d.jerk == (("S", 30.0), ("X", 30.0), ("Y", 30.0), ("Z", 30.0))
    assert d.acceleration == ()


def test_percentages_are_absolute_per_axis():
    # seed 002 L4490: 50 % twice is 50 %; a later G132 on Y keeps X
    d = last("G132 X50\nG132 X50\nG132 Y20\nG1 X1 F100\nM30\n")
    assert d.jerk == (("X", 50.0), ("Y", 20.0))


def test_g130_accepts_a_spindle():
    assert last("G130 S50\nG1 X1 F100\nM30\n").acceleration == (("S", 50.0),)


@pytest.mark.parametrize("statement", [
    "G130 X50.5",     # whole numbers only (L4396)
    "G132 Y20.5",     # L4470
    "G131 0",         # 1..100 (spec 02 §14 decision)
    "G131 150",
    "G130 X0",
    "G130",           # no axes
    "G131",           # no value
    "G133 12.5",
])
def test_invalid_acceleration_jerk_percentage_is_int112(statement):
    assert errors(f"G1 X1 F100\n{statement}\nM30\n") == [("INT112", 2)]


@pytest.mark.parametrize("statement", [
    "G134 X120.5",     # at most 120 % (seed 002 L4535)
    "G134 X100.123",   # two decimals at most (L4530)
    "G134 X-5",
    "G135 X99.55",     # one decimal at most (L4587)
    "G135 X121",
])
def test_invalid_feed_forward_is_int112(statement):
    assert errors(f"G1 X1 F100\n{statement}\nM30\n") == [("INT112", 2)]


def test_feed_forward_values_are_stored_not_moved():
    # seed 002 L4561, L4617: G134 X50.75 Y80 Z10 / G135 X55.8 Y75 Z110
    r = fagorcnc.simulate("G1 X1 F100\nG134 X50.75 Y80 Z10\nG135 X55.8 Y75 Z110\nX2\n")
    assert not r.errors
    assert [m.src.line for m in r.moves if m.kind in MOTION] == [1, 4]
    assert r.state._state.planner == {"G134": {"X": 50.75, "Y": 80.0, "Z": 10.0},
                                      "G135": {"X": 55.8, "Y": 75.0, "Z": 110.0}}


def test_feed_forward_is_modal_per_axis():
    r = fagorcnc.simulate("G134 X90\nG134 Y80\nG1 X1 F100\n")
    assert r.state._state.planner["G134"] == {"X": 90.0, "Y": 80.0}


def test_m30_resets_percentages():
    # seed 002 L4449-L4450, L4497-L4498, L4548-L4550 (M30 resets)
    st = final_state("G130 X50\nG133 40\nG134 X90\nG1 X1 F100\nM30\n")
    assert (st.acceleration, st.jerk, st.planner) == ({}, {}, {})
    assert (st.dynamics().acceleration, st.dynamics().jerk) == ((), ())


# ---------------------------------------------------------------- 8. G108/G109/G193/G266

def test_g108_g109_are_recorded_on_their_block_only():
    # seed 002 L4258: not modal
    ds = dyns("G1 X1 F100\nG108 X2\nX3\nG109 X4\nX5\nM30\n")
    assert [d.adaptation for d in ds] == [None, "G108", None, "G109", None]


def test_g266_is_recorded_on_its_block_only():
    # seed 002 L4374
    ds = dyns("G1 X1 F100\nG266 X2\nX3\nM30\n")
    assert [d.override_locked for d in ds] == [False, True, False]


def test_g266_without_motion_is_an_error():
    assert [line for _code, line in errors("G1 X1 F100\nG266\nX2\nM30\n")] == [2]


def test_g193_needs_linear_acceleration():
    # seed 002 L4246-L4250: default SLOPETYPE 1 (trapezoidal)
    assert errors("G1 X1 F100\nG193 X2\nM30\n") == [("INT114", 2)]


def test_g193_after_slope_0_is_recorded_on_its_block_only():
    ds = dyns("#SLOPE [0]\nG1 X1 F100\nG193 X2\nX3\nM30\n")
    assert [d.adaptation for d in ds] == [None, "G193", None]


def test_g193_with_slope_type_0_machine():
    assert last("G1 X1 F100\nG193 X2\nM30\n", {"planner": {"slope_type": 0}}).adaptation == "G193"


def test_g193_after_slope_1_is_an_error():
    assert errors("#SLOPE [1]\nG1 X1 F100\nG193 X2\nM30\n") == [("INT114", 3)]


# ---------------------------------------------------------------- 9. machine config

@pytest.mark.parametrize(("machine", "names"), [
    ({"planner": {"foo": 1}}, ("planner", "foo")),
    ({"planner": {"corner": 200}}, ("planner.corner",)),
    ({"planner": {"hsc_default_mode": 3}}, ("planner.hsc_default_mode",)),
    ({"planner": {"slope_type": 1.5}}, ("planner.slope_type",)),
    ({"planner": {"corner": "150"}}, ("planner.corner",)),
    ({"planner": {"round_type": True}}, ("planner.round_type",)),
    ({"axes": {"X": {"max_jerk": -5}}}, ("axes.X.max_jerk",)),
    ({"axes": {"X": {"max_acceleration": "fast"}}}, ("axes.X.max_acceleration",)),
])
def test_machine_config_errors_name_the_key(machine, names):
    with pytest.raises(MachineError) as exc:
        load_machine(machine)
    assert all(n in str(exc.value) for n in names), str(exc.value)


def test_machine_config_error_is_cfg001_from_simulate():
    r = fagorcnc.simulate("G1 X1 F100\nM30\n", {"planner": {"corner": 200}})
    assert not r.ok
    assert [d.code for d in r.diagnostics] == ["CFG001"]
    assert "planner.corner" in r.diagnostics[0].message


def test_planner_config_values_are_read():
    p = load_machine({"planner": {"slope_type": 2.0, "corner": 120, "round_type": 1}}).planner
    assert (p.slope_type, p.corner, p.round_type) == (2, 120.0, 1)
    assert type(p.slope_type) is int
