"""The channel's axis configuration (#SET AX, #CALL AX, #FREE AX, #RENAME AX, #PARK/#UNPARK, ?n) and
coupled axes #LINK/#UNLINK (seed 002 ch. 21.1.6-21.1.8, L14515-L15048; generic axes L1206-L1241)."""

from __future__ import annotations

import math

import pytest

import fagorcnc
from fagorcnc.config.machine import MachineError, load_machine
from fagorcnc.plan.planner import Planner

#: the manual's five-axis machine X-Y-Z-A-W (L14818) with U, V, B, C for the other examples
AXES = {"X": {}, "Y": {}, "Z": {}, "A": {"type": "rotary"}, "W": {}, "U": {"max_limit": 100.0}, "V": {},
        "B": {"type": "rotary"}, "C": {"type": "rotary"}}
MACHINE = {"axes": AXES}


def _run(program: str, machine=None):
    return fagorcnc.simulate(program, machine or MACHINE)


def _errors(program: str, machine=None) -> list[tuple[int, int, str]]:
    return [(d.line, d.col, d.code) for d in _run(program, machine).diagnostics if d.is_error]


def _params(program: str, *numbers: int, machine=None) -> list[float]:
    r = _run(program, machine)
    assert r.ok, [str(d) for d in r.diagnostics]
    return [r.state.param(n) for n in numbers]


def _names(program: str, n: int, machine=None) -> list[float]:
    """V.G.AXISNAME1..n after ``program`` (name codes: X=10, Y=20 ... C=90, 0 for a hole)."""
    reads = "".join(f"P{k}=V.G.AXISNAME{k}\n" for k in range(1, n + 1))
    return _params(program + reads + "M30\n", *range(1, n + 1), machine=machine)


def _moves(program: str, machine=None) -> list:
    r = _run(program, machine)
    assert r.ok, [str(d) for d in r.diagnostics]
    return [m for m in r.moves if m.kind in ("linear", "rapid", "arc")]


# ---------------------------------------------------------------------- #SET AX
def test_set_ax_with_holes_the_manuals_screen():
    # L14818-L14834, machine X-Y-Z-A-W: #SET AX [Y, 0, 0, Z, A] shows Y ? ? Z A
    five = {"axes": {a: AXES[a] for a in "XYZAW"}}
    assert _names("#SET AX [Y, 0, 0, Z, A]\n", 5, five) == [20, 0, 0, 30, 70]
    # ... and #SET AX [X, Y, Z] FIXOF ORGOF shows X Y Z ? ?: A and W have left
    assert _names("#SET AX [Y, 0, 0, Z, A]\n#SET AX [X, Y, Z] FIXOF ORGOF\n", 5, five) == [10, 20, 30, 0, 0]


def test_an_axis_left_out_cannot_be_programmed():
    # X is not in [Y, 0, 0, Z, A]: "X10" is an error at its column
    assert _errors("#SET AX [Y, 0, 0, Z, A]\nG1 Y5 X10 F100\nM30\n") == [(2, 7, "INT200")]


def test_set_ax_errors():
    assert _errors("#SET AX [X, Y, X]\nM30\n") == [(1, 16, "INT204")]        # listed twice
    assert _errors("#SET AX [X, Y, Q]\nM30\n") == [(1, 16, "INT204")]        # not an axis name
    assert _errors("#SET AX [X, Y, U2]\nM30\n") == [(1, 16, "INT204")]       # the machine has no U2
    assert _errors("#SET AX [X, Y, Z] ORGOF XOF\nM30\n") == [(1, 25, "INT204")]   # unknown offset keyword
    assert _errors("#SET AX X\nM30\n") == [(1, 1, "INT204")]                 # no brackets


def test_generic_axes_count_the_holes():
    # L1222-L1241: channel Y, X, (hole), Z: ?1 is Y, ?2 is X, ?3 an error, ?4 is Z
    end = _moves("#SET AX [Y, X, 0, Z]\nG1 ?1=12.5 ?2=50.34 ?4=-3 F1000\nM30\n")[-1].end
    assert (end["Y"], end["X"], end["Z"]) == (12.5, 50.34, -3.0)
    assert _errors("#SET AX [Y, X, 0, Z]\nG1 ?3=5 F1000\nM30\n") == [(2, 4, "INT022")]
    assert _errors("#SET AX [Y, X, 0, Z]\nG1 ?5=5 F1000\nM30\n") == [(2, 4, "INT022")]   # beyond the channel


def test_the_first_slots_make_the_plane():
    # L14730: with G17 slot 1 is the abscissa, slot 2 the ordinate, slot 3 the perpendicular axis
    arc = _moves("#SET AX [Y, X, Z]\nG17 G2 ?1=10 ?2=0 I5 J0 F100\nM30\n")[-1]
    assert arc.plane == ("Y", "X", "Z")
    # centre = start + (I, J) on (abscissa, ordinate) = (Y 5, X 0); end Y10 X0: a half circle of radius 5
    assert (arc.center["Y"], arc.center["X"], arc.radius) == (5.0, 0.0, 5.0)


def test_reordering_only_keeps_the_offsets():
    # L14774: a new configuration that only reorders ignores the offsets; G54 X10 stays on X
    program = "V.A.ORGT[1].X=10\nG54\n#SET AX [Y, X, Z]\nG1 X1 F100\nM30\n"
    assert _moves(program)[-1].end["X"] == 11.0   # machine = part 1 + origin 10


# ---------------------------------------------------------------------- #CALL AX
def test_call_ax_the_manuals_example():
    # L14912-L14916: #SET AX [Y, 0, 0, Z] then #CALL AX [X,2, W, 3] give Y X W Z
    assert _names("#SET AX [Y, 0, 0, Z]\n#CALL AX [X,2, W, 3]\n", 5) == [20, 10, 60, 30, 0]


def test_call_ax_without_position_goes_after_the_last_axis():
    # L14895: #CALL AX [V,4,C]: V in position 4, C after the last; channel X Y Z -> X Y Z V C
    three = {"axes": AXES, "channel_axes": ["X", "Y", "Z"]}
    assert _names("#CALL AX [V,4,C]\n", 5, three) == [10, 20, 30, 50, 90]
    # an axis already there without a position stays where it is (L14790)
    assert _names("#CALL AX [X]\n", 3, three) == [10, 20, 30]
    # ... with a position it moves there: X to position 5, its old position a hole
    assert _names("#CALL AX [X, 5]\n", 5, three) == [0, 20, 30, 0, 10]


def test_call_ax_to_an_occupied_position_is_an_error():
    # L14881: "Si la position est occupée, l'erreur correspondante sera affichée"
    assert _errors("#SET AX [X, Y, Z]\n#CALL AX [W, 2]\nM30\n") == [(2, 11, "INT202")]


def test_an_axis_outside_the_channel_joins_with_call_ax():
    three = {"axes": AXES, "channel_axes": ["X", "Y", "Z"]}
    assert _errors("G1 W10 F100\nM30\n", three) == [(1, 4, "INT200")]
    assert _moves("#CALL AX [W]\nG1 W10 F100\nM30\n", three)[-1].end["W"] == 10.0


def test_offsets_of_an_axis_that_joins():
    # L14806-L14815: the offsets named are applied to the axes added; without ORGOF the origin offset is not
    three = {"axes": AXES, "channel_axes": ["X", "Y", "Z"]}
    base = "V.A.ORGT[1].W=10\nG54\n"
    assert _moves(base + "#CALL AX [W]\nG1 W5 F100\nM30\n", three)[-1].end["W"] == 5.0          # 5 + 0
    assert _moves(base + "#CALL AX [W] ORGOF\nG1 W5 F100\nM30\n", three)[-1].end["W"] == 15.0   # 5 + 10
    assert _moves(base + "#CALL AX [W] ALL\nG1 W5 F100\nM30\n", three)[-1].end["W"] == 15.0


def test_axisexch_zero_cannot_change_channel():
    # L14694: AXISEXCH decides whether an axis may change channel; 0 = it may not
    fixed = {"axes": {**AXES, "Z": {"exchange": 0}, "W": {"exchange": 0}}, "channel_axes": ["X", "Y", "Z"]}
    assert _errors("#FREE AX [Z]\nM30\n", fixed) == [(1, 11, "INT205")]
    assert _errors("#CALL AX [W]\nM30\n", fixed) == [(1, 11, "INT205")]
    assert _errors("#SET AX [Z, Y, X]\nM30\n", fixed) == []   # reordering keeps Z in its channel


def test_exchange_in_the_machine_file():
    with pytest.raises(MachineError, match="AXISEXCH"):
        load_machine({"axes": {"X": {"exchange": 3}}})
    with pytest.raises(MachineError, match="no axis 'Q'"):
        load_machine({"axes": {"X": {}}, "channel_axes": ["Q"]})
    with pytest.raises(MachineError, match="twice"):
        load_machine({"axes": {"X": {}}, "channel_axes": ["X", "X"]})


# ---------------------------------------------------------------------- #FREE AX
def test_free_ax_leaves_holes():
    # L14975-L14992, machine X Y Z A B: #FREE AX [Y, A] shows X ? Z ? B
    xyzab = {"axes": {a: AXES[a] for a in "XYZAB"}}
    assert _names("#FREE AX [Y, A]\n", 5, xyzab) == [10, 0, 30, 0, 80]
    assert _names("#FREE AX ALL\n", 2, xyzab) == [0, 0]
    assert _errors("#FREE AX [Y, A]\nG1 Y1 F100\nM30\n", xyzab) == [(2, 4, "INT200")]
    assert _params("#FREE AX [A]\nP1=V.A.ACTCH.A P2=V.A.ACTCH.X\nM30\n", 1, 2, machine=xyzab) == [0.0, 1.0]


def test_a_configuration_change_cancels_rotation_mirror_scale_polar_origin():
    # L14727: "En changeant la configuration d'axes on annule l'origine polaire, la rotation de coordonnées,
    # l'image miroir et le facteur d'échelle actif."  G73 Q90 turns X10 Y0 into X0 Y10; after #FREE AX it is X10
    assert _moves("G73 Q90\nG1 X10 Y0 F100\nM30\n")[-1].end["X"] == pytest.approx(0.0, abs=1e-9)
    end = _moves("G73 Q90\n#FREE AX [C]\nG1 X10 Y0 F100\nM30\n")[-1].end
    assert (end["X"], end["Y"]) == pytest.approx((10.0, 0.0))
    # G11 mirrors X (X10 -> -10) and G72 S2 doubles: both gone after the change
    assert _moves("G11\nG72 S2\n#FREE AX [C]\nG1 X10 F100\nM30\n")[-1].end["X"] == 10.0
    # V.G.ORGROT-free check of the polar origin: G30 I20 J0 then polar R10 Q0 lands on X30; after it, X10
    assert _moves("G30 I20 J0\n#FREE AX [C]\nG1 R10 Q0 F100\nM30\n")[-1].end["X"] == pytest.approx(10.0)


def test_a_configuration_change_under_radius_compensation_is_refused():
    # [CONSTRUCTION] the manual does not say what G41 becomes when the plane's axes change
    program = "T1 D1 M6\nG41 G1 X10 Y0 F100\n#FREE AX [C]\nM30\n"
    tool = {"axes": AXES, "tools": {"1": {"1": {"radius": 2.0}}}}
    assert [c for _l, _c, c in _errors(program, tool)] == ["INT206"]


# ---------------------------------------------------------------------- #RENAME AX
def test_rename_gives_the_axis_its_new_name():
    # L14943-L14966: #RENAME AX [X,X1]: the axis X is called X1
    end = _moves("#RENAME AX [X, X1]\nG1 X1=10 F100\nM30\n")[-1].end
    assert end["X"] == 10.0
    assert _errors("#RENAME AX [X, X1]\nG1 X10 F100\nM30\n") == [(2, 4, "INT200")]
    assert _names("#RENAME AX [X, X1]\n", 1) == [11]


def test_rename_to_a_name_in_the_channel_swaps():
    # L14947: "Si le deuxième axe est présent dans la configuration, il prend le nom du premier axe"
    end = _moves("#RENAME AX [X, Y]\nG1 Y5 X7 F100\nM30\n")[-1].end
    assert (end["X"], end["Y"]) == (5.0, 7.0)   # the machine's X answers to Y, its Y to X
    # the manual's #RENAME AX [X1,Y][Z,V2] after [X, X1]: X (now X1) takes Y, Y takes X1; Z takes V2
    assert _names("#RENAME AX [X, X1]\n#RENAME AX [X1,Y][Z,V2]\n", 3) == [20, 11, 52]


def test_rename_off():
    # L15030-L15048: #RENAME AX OFF [X] cancels the renaming of X; without a list, of all the axes
    assert _names("#RENAME AX [X, X1] [Z, V2]\n#RENAME AX OFF [X1]\n", 3) == [10, 20, 52]
    assert _names("#RENAME AX [X, X1] [Z, V2]\n#RENAME AX OFF\n", 3) == [10, 20, 30]


def test_a_freed_axis_gets_its_name_back():
    # L15014: "Lorsqu'un canal libère un axe (instructions #SET ou #FREE), celui-ci récupère toujours son nom"
    five = {"axes": {a: AXES[a] for a in "XYZAW"}}
    assert _names("#RENAME AX [W, W1]\n#FREE AX [W1]\n#CALL AX [W]\n", 5, five) == [10, 20, 30, 70, 60]
    assert _errors("#RENAME AX [W, W1]\n#FREE AX [W1]\nG1 W1=5\nM30\n", five) == [(3, 4, "INT024")]


def test_renamed_axis_variables_use_the_new_name():
    # L15025: after renaming, the program reads the axis's variables by the new name
    assert _params("#RENAME AX [X, X1]\nG1 X1=4 F100\nP1=V.A.POS.X1\nM30\n", 1) == [4.0]


def test_rename_errors():
    assert _errors("#RENAME AX [Q, X1]\nM30\n") == [(1, 13, "INT207")]
    assert _errors("#RENAME AX [X, Q1]\nM30\n") == [(1, 16, "INT207")]
    assert _errors("#RENAME AX [X]\nM30\n") == [(1, 13, "INT207")]
    assert _errors("#RENAME AX [X, X1]\n#SET AX [X, Y, Z]\nM30\n") == [(2, 10, "INT204")]   # X is X1 now


# ---------------------------------------------------------------------- #PARK / #UNPARK
def test_a_parked_axis_cannot_be_programmed():
    # L14641: "Dès qu'un axe ou une broche est stationné, on ne peut pas y faire référence dans le programme"
    assert _errors("#PARK A\nG1 A10 F100\nM30\n") == [(2, 4, "INT203")]
    assert _errors("#PARK A\n?4=10\nM30\n") == [(2, 1, "INT203")]
    assert _moves("#PARK A\n#PARK A\n#UNPARK A\n#UNPARK A\nG1 A10 F100\nM30\n")[-1].end["A"] == 10.0
    # V.G.AXISNAMEn shows a parked axis as not available (L32990)
    assert _names("#PARK A\n", 4) == [10, 20, 30, 0]


def test_generic_names_in_link_and_park():
    # L1243-L1279: #LINK, #PARK and #UNPARK take the generic names; channel X Y Z A W ...: ?4 is A, ?5 is W
    assert _errors("#PARK ?4\nG1 A10 F100\nM30\n") == [(2, 4, "INT203")]
    assert _errors("#PARK ?4\n#UNPARK ?4\nG1 A10 F100\nM30\n") == []
    end = _moves("#LINK [?3, ?5]\nG1 Z7 F100\nM30\n")[-1].end
    assert end["W"] == 7.0


def test_park_refused_while_in_use():
    # L14603-L14613: not an axis of a coupling, of an active #ANGAX, #TANGCTRL or kinematics
    assert _errors("#LINK [X, U]\n#PARK U\nM30\n") == [(2, 7, "INT208")]
    assert _errors("#PARK\nM30\n") == [(1, 1, "INT208")]
    lathe = {"axes": {"X": {}, "Y": {}, "Z": {}, "W": {}},
             "angular_axes": [{"angular_axis": "X", "orthogonal_axis": "Z", "angle": 30}]}
    assert _errors("#ANGAX ON [1]\n#PARK Z\nM30\n", lathe) == [(2, 7, "INT208")]
    assert _errors("#ANGAX ON [1]\n#PARK W\nM30\n", lathe) == []
    assert _errors("#CS ON [1] [MODE 1, 0, 0, 0, 0, 0, 30]\n#PARK Y\n#PARK W\nM30\n", lathe) == [(2, 7, "INT208")]


def test_parked_spindle():
    # L14615-L14625 and L14641: a turning spindle is not parked (L14619 taken as "not stopped", spec 06 §4.7);
    # a parked one cannot be programmed
    two = {"axes": AXES, "spindles": ["S", "S2"]}
    assert _errors("#PARK S2\nS2=1000 M3.S2\nM30\n", two) == [(2, 1, "INT213")]
    assert _errors("S2=1000 M3.S2\n#PARK S2\nM30\n", two) == [(2, 7, "INT208")]
    assert _errors("#PARK S2\n#UNPARK S2\nS2=1000 M3.S2\nM30\n", two) == []
    # L14629-L14631: with S parked S2 is the only spindle left, so it is the master: M3 alone turns S2
    assert _errors("#PARK S\nM3\nM30\n", two) == []
    # L5262-L5283: with two or more left the original master, or when it is parked the next one: S2
    three = {"axes": AXES, "spindles": ["S", "S2", "S3"]}
    assert _errors("#PARK S\nM3\nM30\n", three) == []
    assert _errors("#PARK S\nS2=100 M3\nM30\n", two) == []            # ... here for S2, the block's spindle


def test_the_spindle_left_alone_is_the_master():
    # L14629-L14631, L5262-L5283: after #PARK S the first spindle not parked, S2, is the master: "S1000" is
    # its speed and V.G.MASTERSP its logical number (the axes, then the spindles: len(AXES) + 2); #UNPARK S makes
    # S the master again (len(AXES) + 1)
    two = {"axes": AXES, "spindles": ["S", "S2"]}
    r = fagorcnc.simulate(text="#PARK S\nS1000 M3\nP1 = V.G.MASTERSP\nM5\n#UNPARK S\nP2 = V.G.MASTERSP\nM30\n",
                          machine=two)
    assert r.ok, [str(d) for d in r.diagnostics]
    assert ("S", 1000.0, "S2") in [(m.function, m.value, m.spindle) for m in r.moves if m.kind == "aux"]
    assert (r.state.param(1), r.state.param(2)) == (len(AXES) + 2.0, len(AXES) + 1.0)


def test_master_selects_the_master_spindle_until_m30():
    # #MASTER S2 (L5287): S alone is S2's until M30 brings the original master back (MASTERSPDL temporary)
    two = {"axes": AXES, "spindles": ["S", "S2"]}
    r = fagorcnc.simulate(text="#MASTER S2\nS800\nP1 = V.G.MASTERSP\nM30\n", machine=two)
    assert r.ok, [str(d) for d in r.diagnostics]
    assert ("S", 800.0, "S2") in [(m.function, m.value, m.spindle) for m in r.moves if m.kind == "aux"]
    assert r.state.param(1) == len(AXES) + 2.0
    from fagorcnc.config.machine import load_machine
    from fagorcnc.interp.state import ChannelState

    st = ChannelState(load_machine(two))
    st.master = "S2"
    st.reset("M30")
    assert st.master_spindle() == "S"
    assert _errors("#MASTER S3\nM30\n", two) == [(1, 1, "INT020")]
    assert _errors("#PARK S2\n#MASTER S2\nM30\n", two) == [(2, 1, "INT213")]


# ---------------------------------------------------------------------- #LINK / #UNLINK
def test_the_slave_follows_its_master_in_the_records():
    # L14517: the slave's motion follows the master's; U starts at 5, X at 0: U = 5 + (X - 0)
    lines = _moves("G0 U5\n#LINK [X, U]\nG1 X10 F1000\nG1 X-2\nM30\n")
    assert [(m.start["U"], m.end["U"]) for m in lines[1:]] == [(5.0, 15.0), (15.0, 3.0)]
    # the path is now X and U: sqrt(10^2 + 10^2) = 14.1421 mm, fed at 1000 * 14.1421 / 10 so X keeps F1000
    assert lines[1].feed == pytest.approx(1000.0 * 2 ** 0.5)


def test_the_slave_keeps_its_place_after_unlink():
    # after #UNLINK U stays where X took it (15); the next U move starts there
    lines = _moves("G0 U5\n#LINK [X, U]\nG1 X10 F1000\n#UNLINK\nG1 U20\nG1 X0\nM30\n")
    assert (lines[2].start["U"], lines[2].end["U"]) == (15.0, 20.0)
    assert lines[3].end["U"] == 20.0   # X moves alone again


def test_a_slave_reads_where_its_master_took_it():
    # U = 5 + (X - 0): after G1 X10, V.A.POS.U reads 15 (no motion: the block reads it at once)
    assert _params("G0 U5\n#LINK [X, U]\nG1 X10 F1000\nP1=V.A.POS.U\nM30\n", 1) == [15.0]


def test_a_coupled_axis_cannot_leave_the_channel():
    assert _errors("#LINK [X, U]\n#FREE AX [U]\nM30\n") == [(2, 11, "INT206")]
    assert _errors("#LINK [X, U]\n#SET AX [X, Y, Z]\nM30\n") == [(2, 1, "INT206")]


def test_a_slave_cannot_become_a_main_axis():
    # L14530 holds while the coupling lasts: #SET AX may not bring the slave U into the first three positions
    assert [c for _l, _c, c in _errors("#LINK [X, U]\n#SET AX [X, U, Y, Z, A, W, V, B, C]\nM30\n")] == ["INT209"]


def test_link_ends_at_m30_and_link_active_variable():
    # L14521: a coupling still active at the end of the program ends after M02/M30; V.G.LINKACTIVE (L40690)
    assert _params("#LINK [X, U]\nP1=V.G.LINKACTIVE\n#UNLINK\nP2=V.G.LINKACTIVE\nM30\n", 1, 2) == [1.0, 0.0]


def test_several_pairs_and_the_manuals_forms():
    # L14567-L14573: #LINK [X,U][Y,V,0.5], #LINK [X,U,0.5][Z,W], #LINK [X,U][Y,V][Z,W]
    end = _moves("#LINK [X,U][Y,V][Z,W]\nG1 X1 Y2 Z3 F100\nM30\n")[-1].end
    assert (end["U"], end["V"], end["W"]) == (1.0, 2.0, 3.0)
    assert _errors("#LINK [X,U][Y,V,0.5]\n#UNLINK\n#LINK [X,U,0.5][Z,W]\nM30\n") == []


@pytest.mark.parametrize(("program", "col"), [
    ("#LINK [U, X]", 11),          # L14530: the main axes (first three of the channel) are not slaves
    ("#LINK [X, A]", 11),          # L14532: both linear or both rotary
    ("#LINK [X, U][U, V]", 17),    # L14534: a master cannot be a slave in another pair
    ("#LINK [X, U][Y, U]", 17),    # L14536: a slave has one master
    ("#LINK [X, X]", 11),
    ("#LINK [X, U, -1]", 15),
])
def test_link_restrictions(program, col):
    assert _errors(f"{program}\nM30\n") == [(1, col, "INT209")]


def test_no_new_link_while_one_is_active():
    # L14542: "on ne pourra pas activer un nouvel accouplement d'axes sans désactiver auparavant ..."
    assert _errors("#LINK [X, U]\n#LINK [Y, V]\nM30\n") == [(2, 1, "INT209")]


def test_a_coupled_slave_cannot_be_programmed():
    # L14549: "Dans ces axes esclaves on ne peut pas programmer de déplacement du temps qu'ils restent accouplés"
    assert _errors("#LINK [X, U]\nG1 X1 U5 F100\nM30\n") == [(2, 7, "INT210")]
    assert _errors("#LINK [X, U]\n#UNLINK\nG1 X1 U5 F100\nM30\n") == []


def test_move_follows_the_configuration_and_the_couplings():
    # #MOVE (seed 002 L16684) moves an axis of the channel: not a freed, parked or coupled slave one (L14549)
    assert _errors("#FREE AX [W]\n#MOVE [W10, F100]\nM30\n") == [(2, 8, "INT200")]
    assert _errors("#PARK W\n#MOVE [W10, F100]\nM30\n") == [(2, 8, "INT203")]
    assert _errors("#LINK [X, U]\n#MOVE [U10, F100]\nM30\n") == [(2, 8, "INT210")]
    # the master's independent move takes its slave along: U = 0 + (X - 0) = 10
    r = _run("#LINK [X, U]\n#MOVE [X10, F100]\nM30\n")
    assert r.ok and [m.end["U"] for m in r.moves if m.kind == "linear"] == [10.0]


def test_the_slaves_soft_limits_count():
    # U's upper limit is 100: U at 95 follows X +10 to 105
    assert [c for _l, _c, c in _errors("G0 U95\n#LINK [X, U]\nG1 X10 F100\nM30\n")] == ["INT100"]


def test_a_slave_of_a_plane_axis_on_an_arc_is_refused():
    # the slave would have to turn a circle; fagorcnc's arcs move only the plane's two axes on it
    assert [c for _l, _c, c in _errors("#LINK [X, U]\nG2 X10 Y0 I5 J0 F100\nM30\n")] == ["INT211"]
    # a slave of the helix axis follows linearly: Z 0 -> 4, W 0 -> 4
    arc = _moves("#LINK [Z, W]\nG2 X10 Y0 Z4 I5 J0 F100\nM30\n")[-1]
    assert (arc.start["W"], arc.end["W"]) == (0.0, 4.0)
    # half circle of radius 5: 5 pi = 15.708 mm in the plane; helix Z 4: hypot(15.708, 4) = 16.209 mm; with W
    # hypot(15.708, 4, 4) = 16.700 mm: F100 * 16.700 / 16.209 keeps the programmed path at 100 mm/min
    assert arc.feed == pytest.approx(100.0 * math.hypot(5 * math.pi, 4, 4) / math.hypot(5 * math.pi, 4))


def test_the_planner_sees_the_slave_limits():
    # U slow (600 mm/min): G0 X100 coupled to U cannot take less than 100 / 600 * 60 = 10 s;
    # X alone at 10000 mm/min needs 100 / 10000 * 60 = 0.6 s plus its acceleration
    slow = {"axes": {**AXES, "U": {"max_velocity": 600.0, "max_limit": 1000.0}}}
    planner = Planner(slow)

    def planned(program: str) -> float:
        r = _run(program, slow)
        assert r.ok, [str(d) for d in r.diagnostics]
        return sum(s.duration for s in planner.segments(r.moves))

    assert planned("#LINK [X, U]\nG0 X100\nM30\n") >= 10.0
    assert planned("G0 X100\nM30\n") < 2.0


def test_link_under_radius_compensation_is_refused():
    tool = {"axes": AXES, "tools": {"1": {"1": {"radius": 2.0}}}}
    program = "T1 D1 M6\nG41 G1 X10 Y0 F100\n#LINK [X, U]\nM30\n"
    assert [c for _l, _c, c in _errors(program, tool)] == ["INT206"]


def test_no_sentence_of_this_section_is_left_unsupported():
    # issue 26: "fagorcnc check gives no INT011/INT078/INT044 for any function named here"
    program = ("#SET AX [X, Y, Z, A, U]\n#CALL AX [W, 6]\n#FREE AX [W]\n#RENAME AX [X, X1]\n#RENAME AX OFF\n"
               "#PARK B\n#UNPARK B\n#LINK [X, U]\n#UNLINK\nM30\n")
    r = _run(program)
    assert r.ok and not [d for d in r.diagnostics if d.code in ("INT011", "INT078", "INT079", "INT044")]


def test_m30_ends_the_coupling_and_undoes_temporary_changes():
    # L14521: the coupling ends at M02/M30; L14694-L14700: a temporary change of channel (AXISEXCH 1) does not
    # outlast the program, a permanent one (2) does
    from fagorcnc.interp import axes
    from fagorcnc.interp.state import ChannelState

    machine = load_machine({"axes": {**AXES, "V": {"exchange": 2}}, "channel_axes": ["X", "Y", "Z", "W"]})
    st = ChannelState(machine)
    ch = st.channel
    ch.slots = ["X", "Y", "Z", None, "U", "V"]   # W left (temporary), U came (temporary), V came (permanent)
    ch.links = (axes.Link("X", "U", 5.0),)
    st.machine_pos["X"] = 10.0
    axes.reset(st)
    assert ch.links == () and st.machine_pos["U"] == 15.0   # U where X took it: 10 + 5
    assert ch.slots == ["X", "Y", "Z", "W", None, "V"]
