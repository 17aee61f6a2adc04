"""The rest of the variable catalogue (issue 26 item 10): the tool table's other data read from the machine file
(seed 002 §22.49-§22.51), tool life, V.G.DYNOVR, V.G.ENDREP/SPDLREP, V.G.HSC/CONTERROR."""

from __future__ import annotations

import pytest

import fagorcnc
from fagorcnc.config.errors import MachineError
from fagorcnc.config.machine import load_machine

# a lathe: X in diameters (G151 active at power-on), Z; tool 3 a rhombic turning insert, tool 4 a milling cutter
LATHE = {
    "axes": {"X": {"diameter": True}, "Z": {}},
    "spindles": ["S"],
    "tools": {
        "3": {"family": 7, "status": 2, "custom": [1.5, 2],
              "1": {"type": 8, "subtype": 11, "turn_config": 2, "location_code": 3, "holder_orientation": 1,
                    "spindle_direction": 1, "plunge_angle": 60, "tip_radius": 0.8, "tip_radius_wear": 0.02,
                    "cutting_length": 12.7, "nose_angle": 35, "nose_width": 4, "cutting_angle": 93,
                    "life_monitoring": 1, "nominal_life": 120, "real_life": 45},
              "2": {"type": 8, "axis_offsets": {"X": 30, "Z": 50}, "axis_offsets_wear": {"Z": -0.1}}},
        "4": {"1": {"length": 100, "radius": 5, "type": 1, "subtype": 1}, "2": {"radius": 4}},
    },
}
DYN = {"axes": {"X": {"max_velocity": 6000, "max_acceleration": 500, "max_jerk": 1e9}, "Y": {}, "Z": {}},
       "machine_parameters": {"MPG.MINDYNOVR": 10, "MPG.MAXDYNOVR": 150, "MPG.STEPDYNOVR": 5}}


def values(text: str, n: int, machine=LATHE) -> list[float]:
    r = fagorcnc.simulate(text + "\nM30\n", machine=machine)
    assert r.ok, [str(d) for d in r.diagnostics]
    return [r.state.param(i) for i in range(1, n + 1)]


def first_error(text: str, machine=LATHE) -> str:
    r = fagorcnc.simulate(text + "\nM30\n", machine=machine)
    errors = [d for d in r.diagnostics if d.is_error]
    assert errors, "expected an error"
    return errors[0].code


# ---------------------------------------------------------------- the tool table's data (L37501-L38880)

def test_active_tool_turning_data_from_the_tool_file():
    # L37710 DTYPE 8 turning, L37726 DSUBTYPE 11 rhombic insert, L37773 TURNCONFIG 2, L37815 LOCODE 3,
    # L37864 FIXORI 1 longitudinal, L37880 SPDLTURDIR 1, L37981 TOAN 60°, L38044 NOSEA 35°, L38087 CUTA 93°,
    # L38075 NOSEW 4 mm, L38008 TOTIPR 0.8, L38020 TOWTIPR 0.02, L38032 TOCUTL 12.7: as written in the file
    assert values("T3 D1 M6\nP1=V.TM.DTYPE P2=V.TM.DSUBTYPE P3=V.TM.TURNCONFIG P4=V.TM.LOCODE P5=V.TM.FIXORI "
                  "P6=V.TM.SPDLTURDIR P7=V.TM.TOAN P8=V.TM.NOSEA P9=V.TM.CUTA P10=V.TM.NOSEW P11=V.TM.TOTIPR "
                  "P12=V.TM.TOWTIPR P13=V.TM.TOCUTL P14=V.TM.LOCODE[1]", 14) == \
        [8, 11, 2, 3, 1, 1, 60, 35, 93, 4, 0.8, 0.02, 12.7, 3]


def test_any_tool_by_number_and_offset():
    # L38312: V.TM.<name>T[tl][ofd]; [tl] alone is the active offset number's (L38444): T4 active with D1,
    # V.TM.DTYPET[3] is tool 3's D1 (8); tool 4's D2 takes the defaults (DTYPE 1 milling, DSUBTYPE 0)
    assert values("T4 D1 M6\nP1=V.TM.DTYPET[3] P2=V.TM.DSUBTYPET[3][1] P3=V.TM.NOSEAT[3][1] P4=V.TM.DTYPET[4][2] "
                  "P5=V.TM.DSUBTYPET[4][2] P6=V.TM.NUMOFDT[3] P7=V.TM.DSUBTYPE", 7) == [8, 11, 35, 1, 0, 2, 1]


def test_per_axis_offsets_in_diameters_under_g151():
    # L38225-L38229: TOFL follows the active units; X is a diameter axis and G151 is active: the file's
    # 30 mm (a radius) reads 60; under G152 30; Z reads 50 and its wear -0.1
    assert values("T4 D1 M6\nP1=V.TM.TOFLT[3][2].X P2=V.TM.TOFLT[3][2].Z P3=V.TM.TOFLWT[3][2].Z\nG152\n"
                  "P4=V.TM.TOFLT[3][2].X P5=V.TM.TOFLT[3][2].1", 5) == [60, 50, -0.1, 30, 30]


def test_lengths_in_inches_under_g70():
    # L38008: TOTIPR is a length: 0.8 mm = 0.8 / 25.4 = 0.0314961 in; angles are not converted (NOSEA 35)
    p = values("T3 D1 M6\nG70\nP1=V.TM.TOTIPR P2=V.TM.NOSEA", 2)
    assert p == [pytest.approx(0.8 / 25.4), 35]


def test_any_tool_written_changes_the_table():
    # L38715-L38821: the TOxxT/NOSExT variables are written from the program; the table changes
    assert values("T3 D1 M6\nV.TM.NOSEAT[3][1]=55 P1=V.TM.NOSEA V.TM.NOSEW=3.5 P2=V.TM.NOSEWT[3][1] "
                  "V.TM.LOCODE=8 P3=V.TM.LOCODE", 3) == [55, 3.5, 8]


def test_codes_are_checked_when_written():
    assert first_error("T3 D1 M6\nV.TM.LOCODE=10") == "INT045"     # 0-9 (L37815)
    assert first_error("T3 D1 M6\nV.TM.DTYPE=0") == "INT045"       # 1-10 (L37710)
    assert first_error("T3 D1 M6\nV.TM.TLFNT[3][1]=-5") == "INT045"   # a life is not negative


def test_turning_only_and_not_for_turning_tools():
    # L37896: TOR/TOI/TOL/TOK "not valid for turning tools"; L37773/L37815: TURNCONFIG, LOCODE only for them
    assert first_error("T3 D1 M6\nP1=V.TM.TOR") == "INT255"
    assert first_error("T3 D1 M6\nP1=V.G.TOL") == "INT255"
    assert first_error("T4 D1 M6\nP1=V.TM.TORT[3][1]") == "INT255"
    assert first_error("T4 D1 M6\nP1=V.TM.LOCODE") == "INT255"
    assert first_error("T4 D1 M6\nP1=V.G.LOCODE") == "INT255"
    assert values("T4 D1 M6\nP1=V.TM.TOR P2=V.G.TOL", 2) == [5, 100]


def test_read_only_and_interface_only_tool_variables():
    # L37594-L37657: TOMON, TLFN, TLFR of the active tool are read-only, REMLIFE is PLC/interface only;
    # L38320 TSTATUST too; L39186 G.LOCODE and L39081 G.DSUBTYPE are read-only
    assert first_error("T3 D1 M6\nV.TM.TLFN=10") == "INT048"
    assert first_error("T3 D1 M6\nV.G.LOCODE=1") == "INT048"
    assert first_error("T3 D1 M6\nV.G.DSUBTYPE=1") == "INT048"
    assert first_error("T3 D1 M6\nP1=V.TM.REMLIFE") == "INT241"
    assert first_error("T3 D1 M6\nP1=V.TM.TSTATUST[3]") == "INT241"
    assert first_error("T3 D1 M6\nP1=V.TM.NOSEAT[150][1]") == "INT050"   # tool 150 is not in the table
    assert first_error("T3 D1 M6\nP1=V.TM.NOSEA[5]") == "INT051"       # tool 3 has no D5


def test_number_of_offsets_is_not_written():
    assert first_error("T3 D1 M6\nV.TM.NUMOFDT[3]=4") == "INT258"


# ---------------------------------------------------------------- what fagorcnc does not compute is refused

def test_an_offset_with_per_axis_offsets_is_refused_before_anything_moves():
    # L38099: a turning tool is sized by TOFL on each axis; fagorcnc compensates the length on the
    # longitudinal axis only: selecting T3 D2 (TOFL X30 Z50) is refused at the M6 block
    r = fagorcnc.simulate("G0 X10\nT3 D2 M6\nG1 X20 F100\nM30\n", machine=LATHE)
    codes = [d.code for d in r.diagnostics if d.is_error]
    assert codes[0] == "INT253" and r.diagnostics[0].line == 2
    assert first_error("T3 D1 M6\nV.TM.TOFL.Z=3") == "INT253"       # written on the active offset
    assert first_error("T3 D1 M6\nV.A.TOFL.X=2") == "INT253"        # on the offset in preparation (L39356)
    assert first_error("T3 D1 M6\nV.G.TOFLW2=0.5") == "INT253"      # the second channel axis, Z
    # another tool's per-axis offsets may be written, and a zero on the active one changes nothing
    assert values("T3 D1 M6\nV.TM.TOFLT[4][1].Z=7 P1=V.TM.TOFLT[4][1].Z V.TM.TOFL1=0 P2=V.TM.TOFL1", 2) == [7, 0]


def test_radius_compensation_with_a_turning_tool_is_refused():
    # L37815: the shape factor sets the controlled point of the tip-radius compensation: not computed
    assert first_error("T3 D1 M6\nG1 G42 X10 Z10 F100") == "INT254"
    r = fagorcnc.simulate("T4 D1 M6\nG17\nG1 G42 X10 F100\nG40 X0\nM30\n",
                          machine={**LATHE, "axes": {"X": {}, "Y": {}, "Z": {}}})
    assert r.ok, [str(d) for d in r.diagnostics]


# ---------------------------------------------------------------- tool life and the tool's own data

def test_tool_life_and_family_of_the_active_tool():
    # L37566 TSTATUS 2 worn, L37582 TLFF 7, L37594 TOMON 1 (machining time), L37633 TLFN 120, L37645 TLFR 45;
    # L38335 TLFFT written; L38347 TLFNT/TLFRT written
    assert values("T3 D1 M6\nP1=V.TM.TSTATUS P2=V.TM.TLFF P3=V.TM.TOMON P4=V.TM.TLFN P5=V.TM.TLFR "
                  "V.TM.TLFFT[4]=12 P6=V.TM.TLFFT[4] V.TM.TLFRT[3][1]=50 P7=V.TM.TLFR P8=V.TM.TOMONT[4][1]", 8) == \
        [2, 7, 1, 120, 45, 12, 50, 0]


def test_remaining_life_in_preparation():
    # L39033: G.REMLIFE = TLFN - TLFR = 120 - 45 = 75; a write is the preparation's value only (L38890):
    # V.G.REMLIFE=10 reads 10, the table's TLFN/TLFR are unchanged; the next tool change reloads 75
    assert values("T3 D1 M6\nP1=V.G.REMLIFE V.G.REMLIFE=10 P2=V.G.REMLIFE P3=V.TM.TLFN P4=V.G.TLFN "
                  "P5=V.G.TLFR\nT3 D1 M6\nP6=V.G.REMLIFE", 6) == [75, 10, 120, 120, 45, 75]


def test_custom_parameters_active_any_and_in_preparation():
    # L37668 TOTP1-4 of the active tool (the file's [1.5, 2], the rest 0); L38400 TOTPnT[tl] of any tool;
    # L39045 G.TOTPn: the preparation's copy, the table keeps 1.5
    assert values("T3 D1 M6\nP1=V.TM.TOTP1 P2=V.TM.TOTP2 P3=V.TM.TOTP3 V.G.TOTP1=9 P4=V.G.TOTP1 P5=V.TM.TOTP1 "
                  "V.TM.TOTP4T[4]=-3 P6=V.TM.TOTP4T[4] V.TM.TOTP2=6 P7=V.TM.TOTP2T[3]", 7) == [1.5, 2, 0, 9, 1.5, -3, 6]


def test_tool_in_preparation_writes_do_not_change_the_table():
    # L38890-L38895: V.G.NOSEA=40 is used for the blocks in preparation; V.TM.NOSEA reads the table (35);
    # the next tool change reloads the table's value
    assert values("T3 D1 M6\nV.G.NOSEA=40 P1=V.G.NOSEA P2=V.TM.NOSEA P3=V.G.DSUBTYPE P4=V.G.TOMON "
                  "V.G.TOTIPR=1.2 P5=V.G.TOTIPR P6=V.TM.TOTIPR\nT3 D1 M6\nP7=V.G.NOSEA", 7) == \
        [40, 35, 11, 1, 1.2, 0.8, 35]


def test_preset_spindle_direction_is_cancelled_with_0():
    # L38289-L38299: V.G.SPDLTURDIR reads the tool's preset direction (1 = M03); the program cancels it with
    # 0, the table keeps it and the next tool change reloads it; only 0 may be written
    assert values("T3 D1 M6\nP1=V.G.SPDLTURDIR V.G.SPDLTURDIR=0 P2=V.G.SPDLTURDIR P3=V.TM.SPDLTURDIR "
                  "\nT3 D1 M6\nP4=V.G.SPDLTURDIR", 4) == [1, 0, 1, 1]
    assert first_error("T3 D1 M6\nV.G.SPDLTURDIR=2") == "INT045"


def test_tool_file_fields_are_checked():
    bad = [{"type": 11}, {"location_code": 1.5}, {"axis_offsets": {"Y": 1}}, {"axis_offsets": 3},
           {"tip_radius": -1}, {"nose_angle": "35"}]
    for spec in bad:
        with pytest.raises(MachineError):
            load_machine({**LATHE, "tools": {"5": {"1": spec}}})
    for spec in ({"status": 3}, {"family": 1.5}, {"custom": [1, 2, 3, 4, 5]}, {"custom": ["x"]}):
        with pytest.raises(MachineError):
            load_machine({**LATHE, "tools": {"5": spec}})
    m = load_machine(LATHE)
    assert m.tool_data[3].custom == [1.5, 2.0, 0.0, 0.0] and m.tools[3][2].axis_offsets == {"X": 30.0, "Z": 50.0}


def test_tool_variables_stop_block_preparation_or_not():
    # L37503: the active tool's V.TM. variables are execution values; L38884: the V.G. ones of the tool in
    # preparation are not, except G.TLFF (L38972) and G.SPDLTURDIR (L38291)
    from fagorcnc.interp.state import ChannelState
    from fagorcnc.interp.variables import Variables

    def synced(name: str, index: tuple = ()) -> bool:
        st = ChannelState(load_machine(LATHE))
        st.tool, st.offset = 3, 1
        v = Variables(st)
        v.get(name, index)
        return st.sync

    assert synced("V.TM.NOSEA") and synced("V.TM.TLFNT[][]", (3, 1)) and synced("V.G.TLFF")
    assert synced("V.G.SPDLTURDIR")
    assert not synced("V.G.NOSEA") and not synced("V.G.TLFN") and not synced("V.G.REMLIFE")


# ---------------------------------------------------------------- V.G.DYNOVR (L36672, L20408-L20428)

def test_dynamic_override_scales_every_axis_dynamics():
    # G0 X100 on X (6000 mm/min = 100 mm/s, A = 500 mm/s², jerk 1e9: a trapezoid): L/v + v/A = 1 + 0.2
    # = 1.2 s; with V.G.DYNOVR = 50 v = 50 mm/s, A = 250 mm/s²: 100/50 + 50/250 = 2 + 0.2 = 2.2 s
    r = fagorcnc.simulate("G0 X100\nM30\n", machine=DYN)
    assert r.ok and r.cycle_time == pytest.approx(1.2, abs=1e-5)
    r = fagorcnc.simulate("V.G.DYNOVR=50\nG0 X100\nM30\n", machine=DYN)
    assert r.ok and r.cycle_time == pytest.approx(2.2, abs=1e-5)


def test_dynamic_override_bounds_come_from_the_machine_parameters():
    # L20408-L20428: MINDYNOVR 10, MAXDYNOVR 150, STEPDYNOVR 5 from [machine_parameters]; DYNOVR 100 at start
    assert values("P1=V.G.DYNOVR P2=V.MPG.MINDYNOVR P3=V.MPG.MAXDYNOVR P4=V.MPG.STEPDYNOVR V.G.DYNOVR=120 "
                  "P5=V.G.DYNOVR", 5, DYN) == [100, 10, 150, 5, 120]
    assert first_error("V.G.DYNOVR=200", DYN) == "INT256"
    assert first_error("V.G.DYNOVR=5", DYN) == "INT256"
    assert first_error("V.G.DYNOVR=50", None) == "INT257"     # the default machine gives no MINDYNOVR/MAXDYNOVR
    assert values("P1=V.G.DYNOVR", 1, None) == [100]


def test_dynamic_override_stops_block_preparation():
    from fagorcnc.interp.state import ChannelState
    from fagorcnc.interp.variables import Variables

    st = ChannelState(load_machine(DYN))
    Variables(st).get("V.G.DYNOVR", ())
    assert st.sync


# ---------------------------------------------------------------- repositioning, HSC

def test_repositioning_variables():
    # L41724: offline there is no tool inspection: the axes are where the program left them, ENDREP 1;
    # L41734 SPDLREP: the M function of the spindle's repositioning, 0 until the program writes one
    assert values("P1=V.G.ENDREP P2=V.G.SPDLREP V.G.SPDLREP=3 P3=V.G.SPDLREP V.G.ENDREP=0 P4=V.G.ENDREP", 4,
                  None) == [1, 0, 3, 0]
    assert first_error("V.G.ENDREP=2", None) == "INT045"
    assert first_error("V.G.SPDLREP=3.5", None) == "INT045"


def test_hsc_state_and_its_programmed_error():
    # L40709 G.HSC 1 while #HSC ON is active; L36584 G.CONTERROR the error programmed with it (0.02 mm,
    # 0.02 / 25.4 = 0.000787 in under G70); 0 and 0 after #HSC OFF
    p = values("#HSC ON [CONTERROR 0.02]\nP1=V.G.HSC P2=V.G.CONTERROR\nG70\nP3=V.G.CONTERROR\nG71\n#HSC OFF\n"
               "P4=V.G.HSC P5=V.G.CONTERROR", 5, None)
    assert p == [1, 0.02, pytest.approx(0.02 / 25.4), 0, 0]


# ---------------------------------------------------------------- repetitions, manual moves, offline states

def test_pending_repetitions_of_rpt():
    # L40664-L40668: n - 1 on the first repetition, 0 on the last: the range N10-N20 runs once as written
    # (no #RPT yet: 0), then #RPT repeats it 3 times: 2, 1, 0; after it 0 again; P2 counts 1 + 3 = 4 passes
    r = fagorcnc.simulate("P2=0\nN10: P2=P2+1\nP[10+P2]=V.G.PENDRPT\nN20:\n#RPT [N10, N20, 3]\nP9=V.G.PENDRPT\n"
                          "M30\n")
    assert r.ok and [r.state.param(n) for n in (2, 11, 12, 13, 14, 9)] == [4, 0, 2, 1, 0, 0]


def test_manual_moves_allowed_with_g201():
    # L39465: manual moves are allowed while G201 is active (G202 ends it); offline no manual mode, TEACH-IN
    # or tool inspection
    assert values("P1=V.G.INTMAN\nG201 #AXIS [X]\nP2=V.G.INTMAN\nG202\nP3=V.G.INTMAN", 3, None) == [0, 1, 0]


def test_states_a_running_program_reads_offline():
    # L33055 SOFTLIMIT 0 (fagorcnc refuses a move beyond a limit before it runs), L41915 IBUSY 0, L41658 CNCERR
    # 0, L39865 INPOS 1 (its read stops preparation: the axes are at the position, in inches as in mm),
    # L37274 CNCSSO 100 (no panel offline, as V.G.CNCFRO)
    assert values("G70\nP1=V.A.INPOS.X P2=V.G.SOFTLIMIT P3=V.G.IBUSY P4=V.G.CNCERR P5=V.A.CNCSSO.S P6=V.SP.CNCSSO",
                  6, None) == [1, 0, 0, 0, 100, 100]
    assert first_error("P1=V.A.INPOS.S", None) == "INT240"   # a spindle's: not computed


def test_interface_only_variables_are_refused():
    # spec 08 D.2: "Variable de lecture depuis l'interface" (L42992 FILENAME, L40283 HMS2, L43316 V.E.*) and
    # "... depuis le PLC et l'interface" (L35454 LUP1, L37310 MZSTATUS): not readable by a part program;
    # V.E.PROGSELECT is written with 0 only (L43316)
    for text in ("P1=V.G.FILENAME", "P1=V.G.HMS2", "P1=V.E.NERRORS", "P1=V.G.LUP1[3]", "P1=V.TM.MZSTATUS",
                 "P1=V.G.PLAXNAME2", "P1=V.E.PROGSELECT"):
        assert first_error(text, None) == "INT241", text
    assert values("V.E.PROGSELECT=0\nP1=1", 1, None) == [1]
    assert first_error("V.E.PROGSELECT=1", None) == "INT045"


def test_coarse_and_fine_origin_parts_without_fine_adjustment():
    # L35243-L35340 with MPG.FINEORG 0 (L19265, no fine adjustment): the coarse part is the whole offset, the
    # fine part 0; ORG = coarse + fine + G158 = 12.5 + 0 + 1 = 13.5 (L35203); COARSEORGT writes the table
    # like ORGT; a fine part other than 0 cannot be written (INT258); L42433 VIRTAXST 0 (#VIRTAX is refused)
    p = values("V.A.ORGT[2].X=12.5\nG55\nG158 X1\nP1=V.A.COARSEORG.X P2=V.A.FINEORG.X P3=V.A.ORG.X "
               "P4=V.A.COARSEORGT[2].X P5=V.A.FINEORGT[2].X\nV.A.COARSEORGT[3].Y=4\nP6=V.A.ORGT[3].Y\n"
               "V.A.FINEORGT[3].Y=0\nP7=V.G.VIRTAXST", 7, None)
    assert p == [12.5, 0, 13.5, 12.5, 0, 4, 0]
    assert first_error("V.A.FINEORGT[3].Y=0.01", None) == "INT258"


def test_pending_repetitions_of_nr_in_the_modal_subroutine():
    # L40680-L40684: n - 1 during the first repetition, 0 during the last; #MCALL runs SUB at the #MCALL
    # (no NR: 0, P120) and after each of the 3 repetitions of the NR3 block (2, 1, 0: P121-P123); after: 0
    r = fagorcnc.simulate("%L SUB\nP[120+P100]=V.G.PENDNR\nP100=P100+1\nM17\n%MAIN\nP100=0\n#MCALL SUB\n"
                          "G91 G1 X1 F100 NR3\n#MDOFF\nP109=V.G.PENDNR\nM30\n")
    assert r.ok and [r.state.param(n) for n in (100, 120, 121, 122, 123, 109)] == [4, 0, 2, 1, 0, 0]
