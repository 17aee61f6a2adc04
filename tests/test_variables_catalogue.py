"""The variable catalogue (issue 26 item 10): machine-parameter variables V.MPG / MPA / SP / MPMAN / MPM / TM /
MTB read from the machine file (seed 002 §22.4-§22.12), and the manual's names fagorcnc does not implement."""

from __future__ import annotations

import pytest

import fagorcnc
from fagorcnc.config.errors import MachineError
from fagorcnc.config.machine import load_machine
from fagorcnc.config.mpcatalogue import entries

# a machine of two linear axes, a rotary one and two spindles: logical numbers X=1 Z=2 C=3, S=4 S1=5 (L17640)
MACHINE = {
    "axes": {
        "X": {"max_velocity": 12000.0, "max_feed": 5000.0, "max_acceleration": 800.0, "max_jerk": 9000.0,
              "min_limit": -10.0, "max_limit": 450.0, "diameter": True, "home": 20.0},
        "Z": {"max_velocity": 15000.0, "min_limit": -900.0, "max_limit": 5.0},
        "C": {"type": "rotary", "rotary_mode": "positioning", "max_velocity": 3600.0},
    },
    "spindles": ["S", "S1"],
    "max_feed": 8000.0,
    "cirinerr": 0.02,
    "local_params": [0, 49],
    "defaults": {"IPLANE": 1, "DEFAULTFEED": 1},
    "m_functions": {"8": "before", "50": "after"},
    "machine_parameters": {"MPA.FFGAIN.X": 80.25, "MPA.FFGAIN[1].Z": 60, "MPG.PRB1MIN": -12.5,
                           "MPMAN.JOGKEY2DEF[3]": -2, "MPA.G00FEED.S": 3000, "MTB.P": [54.9876, -34.1234]},
}


def run(text: str, machine=MACHINE):
    return fagorcnc.simulate(text + "\nM30\n", machine=machine)


def values(text: str, n: int, machine=MACHINE) -> list[float]:
    r = run(text, machine)
    assert r.ok, [str(d) for d in r.diagnostics]
    return [r.state.param(i) for i in range(1, n + 1)]


def first_error(text: str, machine=MACHINE) -> str:
    r = run(text, machine)
    errors = [d for d in r.diagnostics if d.is_error]
    assert errors, "expected an error"
    return errors[0].code


def test_general_parameters_from_the_machine_file():
    # seed 002 L17979 NCHANNEL (1 channel offline), L17987 NAXIS = 3 axes, L18304 NSPDL = 2 spindles,
    # L18328 LOOPTIME in ms (servo period 0.001 s -> 1 ms), L18509 MAXLOCP 49, L18527 MINGLBP 100,
    # L18497 INCHES 0 (mm); the channel form V.[1].MPG.NAXIS is accepted (L17761)
    assert values("P1=V.MPG.NCHANNEL P2=V.MPG.NAXIS P3=V.[1].MPG.NAXIS P4=V.MPG.NSPDL P5=V.MPG.LOOPTIME "
                  "P6=V.MPG.MAXLOCP P7=V.MPG.MINGLBP P8=V.MPG.INCHES", 8) == [1, 3, 3, 2, 1.0, 49, 100, 0]


def test_channel_parameters_from_the_machine_file():
    # L20762 MAXFEED 8000; L20776 DEFAULTFEED 1 (MAXFEED is not 0); L20013 IPLANE 1 (G18); L20298 CIRINERR 0.02;
    # L20157 ICORNER 0 (G50); L19375 CHNAXIS 3; L19400 GEOCONFIG 1 (trihedron: three axes); L19871 KINID 255
    # (no kinematics at power-on)
    assert values("P1=V.MPG.MAXFEED P2=V.MPG.DEFAULTFEED P3=V.MPG.IPLANE P4=V.MPG.CIRINERR P5=V.MPG.ICORNER "
                  "P6=V.MPG.CHNAXIS P7=V.MPG.GEOCONFIG P8=V.MPG.KINID", 8) == [8000, 1, 1, 0.02, 0, 3, 1, 255]


def test_defaultfeed_reads_0_when_maxfeed_is_0():
    # L20776: "reads 0 whenever MAXFEED = 0"
    assert values("P1=V.MPG.DEFAULTFEED", 1, {**MACHINE, "max_feed": 0.0}) == [0]


def test_features_the_machine_does_not_have_read_the_manuals_value():
    # L18009/L18021: no tandem pair -> 0; L18157 gantry -> 0; L18249 MULNGROUP 0; L29011 NTOOLMZ 0 magazines;
    # L28329 NMPG 0 hand wheels; L21159 DRIVETYPE 16 = simulated; L18556 ROPARMIN 0 = no read-only range
    assert values("P1=V.MPG.TMASTERAXIS[1] P2=V.MPG.TSLAVEAXIS[2] P3=V.MPG.MASTERAXIS[1] P4=V.MPG.MULNGROUP "
                  "P5=V.TM.NTOOLMZ P6=V.MPMAN.NMPG P7=V.MPA.DRIVETYPE.X P8=V.MPG.ROPARMIN", 8) == \
        [0, 0, 0, 0, 0, 0, 16, 0]
    assert first_error("P1=V.TM.MZSIZE[1]") == "INT045"        # magazine 1 does not exist
    assert first_error("P1=V.MPMAN.MPGAXIS[1]") == "INT045"    # hand wheel 1 does not exist


def test_axis_parameters_by_name_and_by_logical_number():
    # L21117 AXISTYPE 1 linear / 2 rotary; L22291 POSLIMIT, L22306 NEGLIMIT; L22530 DIAMPROG; logical numbers
    # X=1 Z=2 C=3 (AXISNAME order), spindles go on: S=4 (L17640-L17650)
    assert values("P1=V.MPA.AXISTYPE.X P2=V.MPA.AXISTYPE.3 P3=V.MPA.POSLIMIT.X P4=V.MPA.NEGLIMIT.2 "
                  "P5=V.MPA.DIAMPROG.X P6=V.MPA.DIAMPROG.Z P7=V.MPA.SPDLSTOP.4", 7) == [1, 2, 450, -900, 1, 0, 1]


def test_axis_in_the_channel_by_index():
    # L17663: with a channel, a number is the index in the channel: V.[1].MPA.G00FEED[1].2 is Z's 15000
    assert values("P1=V.[1].MPA.G00FEED[1].2", 1) == [15000]


def test_per_set_parameters():
    # §22.7: G00FEED[set] = axes.X.max_velocity 12000, MAXFEED[set] 5000, ACCEL/DECEL 800, ACCJERK 9000,
    # REFVALUE 20 (the reference point); NPARSETS 1 and DEFAULTSET 1 (one set per axis, L23810, L23859)
    assert values("P1=V.MPA.G00FEED[1].X P2=V.MPA.MAXFEED[1].X P3=V.MPA.ACCEL[1].X P4=V.MPA.DECEL[1].X "
                  "P5=V.MPA.ACCJERK[1].X P6=V.MPA.REFVALUE[1].X P7=V.MPA.NPARSETS.X P8=V.MPA.DEFAULTSET.C", 8) == \
        [12000, 5000, 800, 800, 9000, 20, 1, 1]
    assert first_error("P1=V.MPA.G00FEED[2].X") == "INT242"     # set 2 > NPARSETS
    assert first_error("P1=V.MPA.G00FEED.X") == "INT244"        # the [set] is missing


def test_rotary_axis_parameters():
    # L21555 AXISMODE 0 = module (fagorcnc "positioning"), L21625 SHORTESTWAY 1 (the shortest way), L21606 UNIDIR 0,
    # L27136 MODUPLIM 360 / L27188 MODLOWLIM 0 (module 360 from 0)
    assert values("P1=V.MPA.AXISMODE.C P2=V.MPA.SHORTESTWAY.C P3=V.MPA.UNIDIR.C P4=V.MPA.MODUPLIM[1].C "
                  "P5=V.MPA.MODLOWLIM[1].C", 5) == [0, 1, 0, 360, 0]


def test_wrong_kind_of_axis_is_refused():
    # L21117 AXISTYPE "valid for linear and rotary axes": not for the spindle S; AXISMODE rotary only;
    # SPDLSTOP spindles only
    assert first_error("P1=V.MPA.AXISTYPE.S") == "INT243"
    assert first_error("P1=V.MPA.AXISMODE.X") == "INT243"
    assert first_error("P1=V.MPA.SPDLSTOP.X") == "INT243"
    assert first_error("P1=V.MPA.AXISTYPE.9") == "INT046"       # logical numbers 1..5


def test_spindle_forms_sp_and_master():
    # L17574: MPA variables of a spindle are also SP ones; V.SP.x.2 = 2nd spindle of the system (S1),
    # V.SP.x = the master spindle (S); a spindle's G00FEED (its top speed) from [machine_parameters]
    assert values("P1=V.SP.SPDLSTOP P2=V.SP.G00FEED[1] P3=V.MPA.G00FEED[1].S P4=V.SP.G00FEED[1].S", 4) == \
        [1, 3000, 3000, 3000]
    assert first_error("P1=V.SP.G00FEED[1].2") == "INT245"      # S1's is not given


def test_parameters_fagorcnc_does_not_use_come_from_machine_parameters():
    # [machine_parameters] "MPA.FFGAIN.X" = 80.25 (FFGAIN[set], L25258; the set may be left out),
    # "MPG.PRB1MIN" = -12.5 (L20567), "MPMAN.JOGKEY2DEF[3]" = -2 (keyboard 2, key 3, - direction of axis 2,
    # L28412)
    assert values("P1=V.MPA.FFGAIN[1].X P2=V.MPA.FFGAIN[1].Z P3=V.MPG.PRB1MIN P4=V.MPMAN.JOGKEY2DEF[3]", 4) == \
        [80.25, 60, -12.5, -2]
    assert first_error("P1=V.MPA.PROGAIN[1].X") == "INT245"     # not given by the file


def test_interface_only_and_unmodelled_parameters_are_reported_distinctly():
    # L17993 MPG.AXISNAMEn and L20488 TOOLSUB are read by the interface only; L20376 FEEDND changes how
    # fagorcnc would share the feed: not implemented; a misspelt name is unknown (INT044)
    assert first_error("P1=V.MPG.AXISNAME2") == "INT241"
    assert first_error("P1=V.MPG.TOOLSUB") == "INT241"
    assert first_error("P1=V.MPG.FEEDND") == "INT240"
    assert first_error("P1=V.MPG.NAXES") == "INT044"
    assert first_error("P1=V.MPA.AXISTYP.X") == "INT044"


def test_machine_parameters_are_read_only():
    # L17422, §1.9 L1809-L1812: a program cannot write a machine parameter
    assert first_error("V.MPG.NAXIS = 2") == "INT048"
    assert first_error("V.MPA.G00FEED[1].X = 100") == "INT048"


def test_m_function_table():
    # L28673 MTABLESIZE = 2 entries (M8, M50 in number order), L28679 MNUM[pos], L28692 SYNCHTYPE:
    # "before" = sent and synchronised before the motion (2), "after" = after (8)
    assert values("P1=V.MPM.MTABLESIZE P2=V.MPM.MNUM[1] P3=V.MPM.MNUM[2] P4=V.MPM.SYNCHTYPE[1] "
                  "P5=V.MPM.SYNCHTYPE[2]", 5) == [2, 8, 50, 2, 8]
    assert first_error("P1=V.MPM.MNUM[3]") == "INT045"
    assert first_error("P1=V.MPM.MPROGNAME[1]") == "INT241"


def test_oem_parameters_read_and_written():
    # L29192 MTB.SIZE = 2; L29198 MTB.P[i], 0 <= i < SIZE: the part program reads the real value
    # (54.9876, not the PLC's truncated 54); L29219 MTB.PF reads the same datum; a write stores it
    assert values("P1=V.MTB.SIZE P2=V.MTB.P[0] P3=V.MTB.PF[1] V.MTB.P[1]=7.5 P4=V.MTB.P[1]", 4) == \
        [2, 54.9876, -34.1234, 7.5]
    assert first_error("P1=V.MTB.P[2]") == "INT045"


def test_execution_parameters_stop_block_preparation():
    # L17437: G00FEED (R +osc E, L24868) stops block preparation, MAXFEED[set] (R P, L24920) does not
    assert _synchronised("V.MPA.G00FEED[].X", (1,))
    assert not _synchronised("V.MPA.MAXFEED[].X", (1,))
    assert _synchronised("V.MPA.AXISTYPE.X", ())          # R +set E (L21117)
    assert not _synchronised("V.MPG.NAXIS", ())           # R P (L17987)


def _synchronised(name: str, index: tuple) -> bool:
    """Whether reading ``name`` makes the interpreter stop block preparation (ChannelState.sync)."""
    from fagorcnc.interp.state import ChannelState
    from fagorcnc.interp.variables import Variables

    v = Variables(ChannelState(load_machine(MACHINE)))
    v.get(name, index)
    return v.state.sync


def test_machine_parameters_table_is_checked():
    # a key must be a catalogue name that fagorcnc does not compute itself
    for key in ("MPA.G00FEED.X", "MPG.NAXIS", "MPG.FEEDND", "MPA.NOPE.X", "MPA.FFGAIN", "MPA.FFGAIN.Q"):
        with pytest.raises(MachineError):
            load_machine({**MACHINE, "machine_parameters": {key: 1}})


def test_the_catalogue_cites_the_seed_in_the_manuals_range():
    # every entry is a §22.4-§22.12 variable: seed 002 L17975-L29306
    for e in entries():
        assert 17975 <= int(e.seed[1:]) <= 29306, e


# ---------------------------------------------------------------- program-state variables (spec 08)

def test_arc_variables_with_g265_the_manuals_example():
    # seed 002 L40564: G00 X0 Y0 / G2 X120 Y120.001 I100 J20 under G265 (power-on): the centre moves to the
    # projection of (100, 20) on the bisector of the chord: (100.000417, 20.000417), R = 101.980881 to both
    # ends, CIRERR = programmed - corrected = -0.000417 on X and Y (start radius 101.980390, end 101.981371:
    # 0.00098 mm apart, inside CIRINERR 0.01)
    p = values("G00 X0 Y0\nG2 X120 Y120.001 I100 J20 F100\nP1=V.G.R P2=V.G.I P3=V.G.J P4=V.G.CIRERR[1] "
               "P5=V.G.CIRERR[2] P6=V.G.K", 6, None)
    assert p == pytest.approx([101.980881, 100.000417, 20.000417, -0.000417, -0.000417, 0.0], abs=5e-7)



def test_cirerr_without_its_index_says_so():
    # L40483: the variable is V.G.CIRERR[1] / [2]; without the index it is INT244 (it exists), not INT240
    r = fagorcnc.simulate(text="G0 X0\nP1=V.G.CIRERR\nM30\n")
    assert [(d.line, d.col, d.code) for d in r.diagnostics if d.is_error] == [(2, 4, "INT244")]
    assert "V.G.CIRERR[1]" in r.diagnostics[0].message

def test_arc_variables_with_g264_the_manuals_example():
    # seed 002 L40568: with G264 the centre stays (100, 20): I = 100, J = 20, CIRERR = 0; G.R = 101.981371,
    # sqrt(20² + 100.001²), the radius to the end point as the example prints it (spec 08 F.2: §8.3.6 says the
    # arc runs with the start radius 101.980390)
    p = values("G264 G00 X0 Y0\nG2 X120 Y120.001 I100 J20 F100\nP1=V.G.R P2=V.G.I P3=V.G.J P4=V.G.CIRERR[1] "
               "P5=V.G.CIRERR[2]", 5, None)
    assert p == pytest.approx([101.981371, 100.0, 20.0, 0.0, 0.0], abs=5e-7)


def test_arc_centre_components_follow_the_channel_axes():
    # L40466: I, J, K are the first, second and third channel axes: a G18 arc from X0 Z0 to X20 Z0 about the
    # centre X10 Z0 (I10 K0) gives I = 10, J = 0, K = 0; R = 10; before any arc they read 0
    assert values("P1=V.G.R\nG18 G1 X0 Z0 F100\nG2 X20 Z0 I10 K0\nP2=V.G.R P3=V.G.I P4=V.G.J P5=V.G.K", 5,
                  None) == pytest.approx([0, 10, 10, 0, 0])
    assert first_error("P1=V.G.CIRERR[3]", None) == "INT045"


def test_extorg_names_the_origin_function():
    # L41746: 0 G53, 1..6 G54..G59 (G56 = 3, spec 08 E.2), n for G159=n, 1000 for a G92 preset
    assert values("G56\nP1=V.G.EXTORG\nG159=12\nP2=V.G.EXTORG\nG92 X0\nP3=V.G.EXTORG\nG53\nP4=V.G.EXTORG", 4,
                  None) == [3, 12, 1000, 0]
    assert _synchronised("V.G.EXTORG", ())   # an execution value (L41746)


def test_mirror_variables():
    # L40543 G.MIRROR bit 0 = first channel axis; L40586 MIRROR1..3: G11 mirrors X: 1, 0, 0; G11 G13: mask 5
    assert values("G11\nP1=V.G.MIRROR1 P2=V.G.MIRROR2 P3=V.G.MIRROR3\nG13\nP4=V.G.MIRROR", 4, None) == [1, 0, 0, 5]


def test_axis_and_spindle_names_of_the_configuration():
    # §22.26 L32747-L33043 with X Z C and spindles S S1: AXISNAME2 = Z = 30 (index 2 in the channel),
    # GAXISNAME3 = C = 90 (logical 3), SPDLNAME2 = S1 = 101, GSPDLNAME4 = S = 100 (spindles numbered after the
    # 3 axes, L32786), MASTERSP = 4 (S's logical number), NUMCH 1, G.AXIS 3, G.NSPDL 2
    assert values("P1=V.G.AXISNAME2 P2=V.G.GAXISNAME3 P3=V.G.SPDLNAME2 P4=V.G.GSPDLNAME4 P5=V.G.MASTERSP "
                  "P6=V.G.NUMCH P7=V.G.AXIS P8=V.G.NSPDL", 8) == [30, 90, 101, 100, 4, 1, 3, 2]
    assert first_error("P1=V.G.GSPDLNAME2") == "INT045"   # logical 2 is the axis Z
    assert first_error("P1=V.G.AXISNAME4") == "INT045"
    assert first_error("V.G.AXISNAME1 = 10") == "INT048"


def test_path_acceleration_written_by_the_program_reaches_the_planner():
    # L36469: V.G.MAXACCEL = 500 limits the path acceleration (the axis' is 1000): 100 mm at F6000 with
    # J = 20000: ramps dv/A + A/J = 0.2 + 0.025 = 0.225 s over 11.25 mm, cruise 77.5 mm: 0.45 + 0.775 = 1.225 s
    # (1.15 s without it); 0 removes the path limit, the machine parameter's included
    r = fagorcnc.simulate("P1=V.G.MAXACCEL\nV.G.MAXACCEL=500\nP2=V.G.MAXACCEL\nG1 X100 F6000\nM30\n")
    assert r.ok and [r.state.param(1), r.state.param(2)] == [0, 500]
    list(r.segments())
    assert r.cycle_time == pytest.approx(1.225, rel=1e-9)
    limited = {"planner": {"max_path_acceleration": 500.0}}
    r = fagorcnc.simulate("P1=V.G.MAXACCEL\nV.G.MAXACCEL=0\nG1 X100 F6000\nM30\n", limited)
    assert r.ok and r.state.param(1) == 500
    list(r.segments())
    assert r.cycle_time == pytest.approx(1.15, rel=1e-9)
    assert first_error("V.G.MAXJERK = -1", None) == "INT045"


def test_path_limits_return_to_the_machine_parameters_at_m30_not_m02():
    # L36478: M30 and reset restore MAXACCEL/MAXJERK; M02 is not named
    from fagorcnc.interp.state import ChannelState

    st = ChannelState(load_machine(None))
    st.path_limits = (500.0, 0.0)
    st.reset("M02")
    assert st.path_limits == (500.0, 0.0)
    st.reset("M30")
    assert st.path_limits is None


def test_feed_forward_percentages_g134_g135():
    # L4513-L4546: G134 X50.75 Y80 Z10 -> V.A.FFGAIN.X = 50.75 (L41441); G135 X55.8 -> V.A.ACFGAIN.X = 55.8
    # (L41565); an axis G134 does not name keeps the machine's FFGAIN ([machine_parameters] 60 for Z here)
    assert values("G134 X50.75\nG135 X55.8\nP1=V.A.FFGAIN.X P2=V.A.ACFGAIN.X P3=V.A.FFGAIN.Z", 3) == \
        [50.75, 55.8, 60]
    assert first_error("P1=V.A.ACFGAIN.Z") == "INT245"   # no G135 on Z and no ACFGAIN in the file
    assert _synchronised("V.A.FFGAIN.X", ())


def test_tool_radius_in_preparation_changes_the_compensation_not_the_table():
    # spec 08 E.5 / L39204: V.G.TOR = V.G.TOR + 0.5 with T1 D1 of radius 3: the G41 square is compensated
    # with 3.5 (corner (40 - 3.5, 10 + 3.5) = (36.5, 13.5)) while V.TM.TOR, the table, still reads 3
    tool = {"tools": {"1": {"1": {"radius": 3.0}}}}
    r = fagorcnc.simulate("G90 G17 G00 X-10 Y-10\nT1 D1 M6\nV.G.TOR = V.G.TOR + 0.5\nP1=V.G.TOR P2=V.TM.TOR\n"
                          "G01 G41 X10 Y10 F500\nX40\nY40\nX10\nG40 X-10 Y60\nM30\n", tool)
    assert r.ok, [str(d) for d in r.diagnostics]
    assert [r.state.param(1), r.state.param(2)] == [3.5, 3.0]
    ends = [(round(m.end["X"], 4), round(m.end["Y"], 4)) for m in r.moves]
    assert (36.5, 13.5) in ends and (37.0, 13.0) not in ends


def test_tool_radius_in_preparation_is_reloaded_at_the_next_offset():
    # L38884-L38943: the next tool or offset change reloads the values from the table
    tool = {"tools": {"1": {"1": {"radius": 3.0}, "2": {"radius": 2.0}}}}
    assert values("T1 D1 M6\nV.G.TOR = 9\nP1=V.G.TOR\nD2\nP2=V.G.TOR\nD1\nP3=V.G.TOR", 3, tool) == [9, 2, 3]


def test_manual_feeds_are_kept():
    # L39814 G.FMAN (G94) and L39829 G.MANFPR (G95): read/written by the program, no effect on its moves
    assert values("V.G.FMAN = 1500\nV.G.MANFPR = 0.2\nP1=V.G.FMAN P2=V.G.MANFPR", 2, None) == [1500, 0.2]


def test_a_variable_the_manual_defines_is_not_an_unknown_one():
    # L36518 G.PERFRATE, L41781 G.CAMST, L35936 A.FLWACT, PLC signals: defined, not implemented (INT240);
    # a name the manual does not have stays INT044
    for text in ("P1=V.G.PERFRATE", "P1=V.G.CAMST[1]", "P1=V.A.FLWACT.X", "P1=V.PLC.READYC2", "P1=V.TM.MZWAIT"):
        assert first_error(text, None) == "INT240", text
    for text in ("P1=V.G.DYNOVER", "P1=V.A.FLWACTS.X", "P1=V.PLC.NOPE"):
        assert first_error(text, None) == "INT044", text


def test_spindle_feed_forward_and_active_set():
    # L41441: V.A.FFGAIN.S / V.SP.FFGAIN (master) of a spindle: the machine file's FFGAIN; L32845 ACTIVSET 1
    machine = {**MACHINE, "machine_parameters": {"MPA.FFGAIN.S": 90}}
    assert values("P1=V.A.FFGAIN.S P2=V.SP.FFGAIN P3=V.A.ACTIVSET.X P4=V.SP.ACTIVSET", 4, machine) == [90, 90, 1, 1]


def test_every_catalogue_source_is_computed():
    # a catalogue line names a machine-file field the variable layer knows, or the manual's value, or
    # [machine_parameters] / not implemented / interface only
    from fagorcnc.interp.mpvars import SOURCES

    for e in entries():
        assert e.source in SOURCES or e.source[0] == "=" or e.source in ("free", "none", "-"), e
        assert (e.source == "-") == (e.access == "IF"), e
