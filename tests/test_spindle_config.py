"""The channel's spindle configuration #SET SP, #CALL SP, #FREE SP, #RENAME SP (seed 002 ch. 21.1.9,
L15049-L15233), the master spindle after a change (L5174-L5192, L5270-L5302), RENAMECANCEL for the axes and
the spindles (L14955-L15021, L15191-L15208, L19222-L19260), and the spindle override in a G33 thread per
THREADOVR (L7382-L7391, L22355-L22414)."""

from __future__ import annotations

import pytest

import fagorcnc
from fagorcnc.config.machine import MachineError, load_machine

#: the manual's spindles of the #FREE SP / #CALL SP examples (L15156-L15172), three axes X Y Z
FOUR = {"spindles": ["S", "S1", "S2", "S4"]}
#: the spindles of the #RENAME SP examples (L15189-L15190)
RENAMED = {"spindles": ["S", "S1", "S2", "S3"]}


def _run(program: str, machine=None):
    return fagorcnc.simulate(program, FOUR if machine is None else machine)


def _errors(program: str, machine=None) -> list[tuple[int, str]]:
    return [(d.line, d.code) for d in _run(program, machine).diagnostics if d.is_error]


def _params(program: str, *numbers: int, machine=None) -> list[float]:
    r = _run(program, machine)
    assert r.ok, [str(d) for d in r.diagnostics]
    return [r.state.param(n) for n in numbers]


def _config(program: str, machine=None) -> tuple[int, list[float], float]:
    """(V.G.NSPDL, V.G.SPDLNAME1..NSPDL, V.G.MASTERSP) after ``program``: S=100, S1=101 ... (L32985);
    the spindles are numbered after the three axes: S=4, S1=5, S2=6, S4=7 (L32786-L32790)."""
    r = _run(program + "P20=V.G.NSPDL P21=V.G.MASTERSP\nM30\n", machine)
    assert r.ok, [str(d) for d in r.diagnostics]
    n = int(r.state.param(20))
    reads = "".join(f"P{k}=V.G.SPDLNAME{k}\n" for k in range(1, n + 1))
    r2 = _run(program + reads + "M30\n", machine)
    return n, [r2.state.param(k) for k in range(1, n + 1)], r.state.param(21)


def _after(program: str, machine=None) -> list[float]:
    """V.G.SPDLNAME1..V.G.NSPDL once ``program`` has ended (M30 done)."""
    r = _run(program, machine)
    assert r.ok, [str(d) for d in r.diagnostics]
    return [r.state.var(f"V.G.SPDLNAME{k}") for k in range(1, int(r.state.var("V.G.NSPDL")) + 1)]


def _speeds(program: str, machine=None) -> list[tuple[str, float]]:
    """The S records (spindle by its machine name, speed) of ``program``."""
    r = _run(program, machine)
    assert r.ok, [str(d) for d in r.diagnostics]
    return [(m.spindle, m.value) for m in r.moves if m.kind == "aux" and m.function == "S"]


# ---------------------------------------------------------------------- #FREE SP
def test_free_sp_the_manuals_examples():
    # L15156: #FREE SP [S] leaves S1 S2 S4; the master is S1, the first of the original configuration left
    # (L5276-L5278): logical 3 axes + 2 = 5
    assert _config("#FREE SP [S]\n") == (3, [101, 102, 104], 5)
    # L15159: #FREE SP [S1,S4] leaves S S2; S stays master (logical 4)
    assert _config("#FREE SP [S1,S4]\n") == (2, [100, 102], 4)
    # L15162: #FREE SP ALL: no spindle, V.G.MASTERSP 0
    assert _config("#FREE SP ALL\n") == (0, [], 0)


def test_a_spindle_out_of_the_channel_cannot_be_programmed():
    # S1 left: its speed, its M3.S1, its positioning speed, #MASTER and #PARK of it are refused (INT246)
    for block in ("S1=1000", "M3.S1", "S1.POS=50", "#MASTER S1", "#PARK S1"):
        assert _errors(f"#FREE SP [S1]\n{block}\nM30\n") == [(2, "INT246")], block
    # the master takes an S alone: with S gone it is S1 (L5133, L5276)
    assert _speeds("#FREE SP [S]\nS800 M3\nM30\n") == [("S1", 800.0)]
    # no spindle left: S, G95 and G33 say so
    assert _errors("#FREE SP ALL\nS100\nM30\n") == [(2, "INT020")]
    assert _errors("#FREE SP ALL\nG95 G1 X10 F0.1\nM30\n") == [(2, "INT065")]
    assert _errors("#FREE SP ALL\nG33 Z-10 K2\nM30\n") == [(2, "INT182")]


def test_free_sp_errors():
    assert _errors("#FREE SP [S7]\nM30\n") == [(1, "INT247")]          # not in the channel
    assert _errors("#FREE SP [S, S]\nM30\n") == [(1, "INT247")]         # twice
    assert _errors("#FREE SP [X]\nM30\n") == [(1, "INT247")]            # not a spindle name
    # a turning spindle, and the master with G95 active, cannot leave (as for #PARK, L14615-L14626)
    assert _errors("S1=100 M3.S1\n#FREE SP [S1]\nM30\n") == [(2, "INT248")]
    assert _errors("G95\n#FREE SP [S]\nM30\n") == [(2, "INT248")]
    # AXISEXCH 0: the spindle may not change channel (L15062, L15104)
    fixed = {**FOUR, "machine_parameters": {"MPA.AXISEXCH.S2": 0}}
    assert _errors("#FREE SP [S2]\nM30\n", fixed) == [(1, "INT248")]
    assert _errors("#FREE SP ALL\nM30\n", fixed) == [(1, "INT248")]


# ---------------------------------------------------------------------- #CALL SP / #SET SP
def test_call_sp_the_manuals_examples():
    # the channel starts with S only (CHSPDLNAME); S1, S2, S4 are free
    one = {**FOUR, "channel_spindles": ["S"]}
    assert _config("", one) == (1, [100], 4)
    # L15169: #CALL SP [S1] adds S1 after S; S stays master
    assert _config("#CALL SP [S1]\n", one) == (2, [100, 101], 4)
    # L15172: #CALL SP [S,S2]: S is already there (it stays), S2 joins
    assert _config("#CALL SP [S,S2]\n", one) == (2, [100, 102], 4)
    # a spindle added to a channel with none is its master (L5182): S4 is logical 7
    assert _config("#FREE SP ALL\n#CALL SP [S4]\n", one) == (1, [104], 7)
    assert _speeds("#CALL SP [S2]\nS2=300 M3.S2\nM30\n", one) == [("S2", 300.0)]


def test_call_sp_errors():
    one = {**FOUR, "channel_spindles": ["S"]}
    assert _errors("#CALL SP [S9]\nM30\n", one) == [(1, "INT247")]     # the machine has no S9
    # S4 belongs to another channel and may not change (AXISEXCH 0, L15125-L15126)
    tied = {**one, "machine_parameters": {"MPA.AXISEXCH.S4": 0}}
    assert _errors("#CALL SP [S4]\nM30\n", tied) == [(1, "INT248")]


def test_set_sp_the_manuals_examples():
    # L15179: #SET SP [S]: one spindle
    assert _config("#SET SP [S]\n") == (1, [100], 4)
    # L15182: #SET SP [S1,S2]: S and S4 leave; the master is S1 (the first of the original configuration
    # still there, L5276)
    assert _config("#SET SP [S1,S2]\n") == (2, [101, 102], 5)
    # the order of #SET SP is the index in the channel: [S2, S] gives SPDLNAME1 = S2, the master stays S
    assert _config("#SET SP [S2, S]\n") == (2, [102, 100], 4)


def test_set_sp_keeps_a_turning_spindle_it_names_and_refuses_one_that_would_leave():
    assert _config("S100 M3\n#SET SP [S, S1]\n")[0] == 2
    assert _errors("S100 M3\n#SET SP [S1]\nM30\n") == [(2, "INT248")]
    assert _errors("#SET SP [S1, S1]\nM30\n") == [(1, "INT247")]


def test_the_master_after_a_change():
    # #MASTER S2, then S2 leaves: the channel chooses again, its original master S (L5300-L5302, L5272)
    assert _config("#MASTER S2\n#FREE SP [S2]\n")[2] == 4
    # the master leaves and one spindle remains: that one (L5184-L5185); S4 is logical 7
    assert _config("#SET SP [S, S4]\n#FREE SP [S]\n")[2] == 7
    # V.SP.x without a spindle reads the master's (L17714): after #MASTER S1 the speed of S1
    assert _params("S1=250 S100\n#MASTER S1\nP1=V.SP.SPEED\nM30\n", 1) == [250.0]


# ---------------------------------------------------------------------- #RENAME SP
def test_rename_sp_the_manuals_examples():
    # L15189: #RENAME SP [S,S1]: S is called S1, and S1, in the configuration, is called S
    assert _config("#RENAME SP [S,S1]\n", RENAMED)[1] == [101, 100, 102, 103]
    # S1=1000 now programs the machine's spindle S; S=500 ... the master's S alone is still the master (S)
    assert _speeds("#RENAME SP [S,S1]\nS1=1000\nS2=20\nM30\n", RENAMED) == [("S", 1000.0), ("S2", 20.0)]
    # L15190: #RENAME SP [S1,S2][S3,S]: S1 <-> S2, then S3 takes S and S takes S3
    assert _config("#RENAME SP [S1,S2][S3,S]\n", RENAMED)[1] == [103, 102, 101, 100]


def test_rename_sp_off_the_manuals_examples():
    # L15230: #RENAME SP OFF [S3] gives the spindle called S3 its own name back
    r = _run("#RENAME SP [S1,S3]\n#RENAME SP OFF [S3]\nP1=V.G.SPDLNAME2\nM30\n", {"spindles": ["S", "S1"]})
    assert r.ok and r.state.param(1) == 101
    # L15233: #RENAME SP OFF, every spindle (the swap of the first example too)
    assert _config("#RENAME SP [S1,S2][S3,S]\n#RENAME SP OFF\n", RENAMED)[1] == [100, 101, 102, 103]


def test_a_renamed_spindle_is_programmed_and_read_by_its_new_name():
    # L15211-L15213: the variables by the new name; the old name is no spindle of the channel any more
    assert _params("#RENAME SP [S1,S5]\nS5=700\nP1=V.A.SPEED.S5 P2=V.SP.ACTCH.S5\nM30\n", 1, 2) == [700.0, 1.0]
    assert _errors("#RENAME SP [S1,S5]\nS1=700\nM30\n") == [(2, "INT246")]
    # a spindle that leaves gets its own name back (L15200-L15201)
    assert _params("#RENAME SP [S1,S5]\n#FREE SP [S5]\nP1=V.A.ACTCH.S1\nM30\n", 1) == [0.0]
    # V.G.GSPDLNAMEn: logical spindle 5 (S1, after the three axes and S) by its name in the channel
    assert _params("#RENAME SP [S1,S5]\nP1=V.G.GSPDLNAME5\nM30\n", 1) == [105.0]


def test_rename_sp_errors():
    assert _errors("#RENAME SP [S, X1]\nM30\n") == [(1, "INT249")]     # not a spindle name
    assert _errors("#RENAME SP [S7, S1]\nM30\n") == [(1, "INT249")]    # no S7 in the channel
    assert _errors("#RENAME SP OFF [S5]\nM30\n") == [(1, "INT249")]
    # [CONSTRUCTION] cancelling one side of a swap would give two spindles the name S
    assert _errors("#RENAME SP [S,S1]\n#RENAME SP OFF [S1]\nM30\n") == [(2, "INT249")]


# ---------------------------------------------------------------------- M02/M30, AXISEXCH, RENAMECANCEL
def test_m30_takes_a_temporary_change_back_and_keeps_a_permanent_one():
    # AXISEXCH 1 (temporary, the default): after M30 the channel has S again, and not S1 (L5155-L5170)
    one = {**FOUR, "channel_spindles": ["S"]}
    assert _after("#CALL SP [S1]\n#FREE SP [S]\nM30\n", one) == [100]
    # AXISEXCH 2 (permanent): the change stays
    permanent = {**one, "machine_parameters": {"MPA.AXISEXCH.S1": 2, "MPA.AXISEXCH.S": 2}}
    assert _after("#CALL SP [S1]\n#FREE SP [S]\nM30\n", permanent) == [101]


def test_renamecancel_keeps_or_cancels_the_renames_of_axes_and_spindles():
    program = "#RENAME SP [S,S5]\n#RENAME AX [X,X1]\nP1=V.MPG.RENAMECANCEL\nM30\n"
    # [CONSTRUCTION] no RENAMECANCEL in the machine file: 0 (L19256-L19260: 0 no, 1 yes), the names are kept
    kept = _run(program)
    assert kept.ok and kept.state.param(1) == 0
    assert (kept.state.var("V.G.SPDLNAME1"), kept.state.var("V.G.AXISNAME1")) == (105, 11)
    # RENAMECANCEL 1: M30 cancels both (L14955-L14958, L15191-L15194)
    cancel = _run(program, {**FOUR, "machine_parameters": {"MPG.RENAMECANCEL": 1}})
    assert cancel.ok and cancel.state.param(1) == 1
    assert (cancel.state.var("V.G.SPDLNAME1"), cancel.state.var("V.G.AXISNAME1")) == (100, 10)


def test_a_kept_rename_is_cancelled_when_the_channel_gets_its_name_back():
    # L15203-L15208: S1 left (temporarily), S took its name; at M30 S1 returns: the rename of S is cancelled
    assert _after("#FREE SP [S1]\n#RENAME SP [S,S1]\nM30\n") == [100, 102, 104, 101]
    # the same for the axes (L15017-L15021): W left, Z took its name; W returns to slot 4 and Z is Z again
    axes = {"axes": {"X": {}, "Y": {}, "Z": {}, "W": {}}}
    r = _run("#FREE AX [W]\n#RENAME AX [Z,W]\nM30\n", axes)
    assert r.ok and [r.state.var(f"V.G.AXISNAME{k}") for k in (3, 4)] == [30, 60]


def test_the_machine_parameter_variables_of_the_spindle_configuration():
    one = {**FOUR, "channel_spindles": ["S"], "machine_parameters": {"MPA.AXISEXCH.S1": 2}}
    # CHNSPDL follows #CALL SP (L19444-L19452); AXISEXCH: the machine file's, 1 without it, axes.X.exchange
    assert _params("#CALL SP [S1]\nP1=V.MPG.CHNSPDL P2=V.MPA.AXISEXCH.S1 P3=V.MPA.AXISEXCH.S2 "
                   "P4=V.MPA.AXISEXCH.X\nM30\n", 1, 2, 3, 4, machine=one) == [2.0, 2.0, 1.0, 1.0]
    # V.A.ACTCH.Sn / V.SP.ACTCH: 1 in the channel, 0 in none (L32821-L32864)
    assert _params("#FREE SP [S2]\nP1=V.A.ACTCH.S2 P2=V.SP.ACTCH P3=V.A.ACTCH.S\nM30\n", 1, 2, 3) == [0.0, 1.0, 1.0]


def test_channel_spindles_in_the_machine_file():
    assert load_machine({"spindles": ["S", "S1"], "channel_spindles": ["S1"]}).channel_spindles == ["S1"]
    with pytest.raises(MachineError, match="no spindle 'S2'"):
        load_machine({"spindles": ["S", "S1"], "channel_spindles": ["S2"]})
    with pytest.raises(MachineError, match="twice"):
        load_machine({"spindles": ["S", "S1"], "channel_spindles": ["S", "S"]})
    # L15051: at most four spindles in the system; a name once
    with pytest.raises(MachineError, match="at most four"):
        load_machine({"spindles": ["S", "S1", "S2", "S3", "S4"]})
    with pytest.raises(MachineError, match="twice"):
        load_machine({"spindles": ["S", "S"]})


def test_park_refuses_the_master_spindle_with_g33_active():
    # L14625: not with G33 active, being the master; the spindle stopped (M5) after the thread, G33 still modal
    assert _errors("S500 M3\nG33 Z-10 K2\nM5\n#PARK S\nM30\n") == [(4, "INT208")]


# ---------------------------------------------------------------------- G33: its spindle and THREADOVR
THREAD = "G0 X0 Y0 Z0\nS500 M3\nV.A.PRGSSO.S=80\nG33 Z-20 K2\nM30\n"


def _thread(program: str, parameters: dict | None = None, machine=None):
    m = dict(machine or {})
    if parameters:
        m["machine_parameters"] = parameters
    r = fagorcnc.simulate(program, m)
    assert r.ok, [str(d) for d in r.diagnostics]
    line = next(x for x in r.moves if x.kind == "linear")
    return line.feed, line.thread.speed, [d.code for d in r.diagnostics]


def test_threadovr_lets_the_spindle_override_change_the_thread():
    # L7387-L7389: THREADOVR 20 allows 80 %: the spindle turns at 500 x 0.8 = 400 rpm and the feed follows
    # the pitch: 400 rpm x 2 mm = 800 mm/min
    assert _thread(THREAD, {"MPA.THREADOVR.S": 20}) == (800.0, 400.0, [])
    # no THREADOVR (0): the thread runs at 100 %: 500 x 2 = 1000 mm/min (INT189 says the override is held)
    assert _thread(THREAD) == (1000.0, 500.0, ["INT189"])
    # THREADOVR 10 % is the most the override may vary: 80 % acts as 90 %: 450 rpm x 2 = 900 mm/min
    assert _thread(THREAD, {"MPA.THREADOVR.S": 10}) == (900.0, 450.0, ["INT189"])
    # L7389-L7391: the feed forward of the thread's axes must be above 90 %: Z at 80 % holds it at 100 %
    assert _thread(THREAD, {"MPA.THREADOVR.S": 20, "MPA.FFGAIN.Z": 80}) == (1000.0, 500.0, ["INT189"])
    # ... G134 Z95 makes it 95 %: 800 mm/min again
    program = THREAD.replace("G33", "G134 Z95\nG33")
    assert _thread(program, {"MPA.THREADOVR.S": 20, "MPA.FFGAIN.Z": 80}) == (800.0, 400.0, [])
    # the warning once, not for every block of the thread
    r = fagorcnc.simulate(THREAD.replace("M30", "G33 Z-40 K2\nG33 Z-60 K2\nM30"), {})
    assert [d.code for d in r.diagnostics] == ["INT189"]
    assert [x.feed for x in r.moves if x.kind == "linear"] == [1000.0] * 3
    # the feed override never acts (L7382-L7384): the panel's 50 % leaves 800 mm/min
    r = fagorcnc.simulate(THREAD, {"machine_parameters": {"MPA.THREADOVR.S": 20}, "planner": {"feed_override": 50}})
    assert r.ok and next(x for x in r.moves if x.kind == "linear").feed == 800.0


def test_threadovr_is_read_as_the_machine_file_gives_it():
    program = "P1=V.MPA.THREADOVR.S P2=V.SP.THREADOVR\nM30\n"
    assert _params(program, 1, 2, machine={"machine_parameters": {"MPA.THREADOVR.S": 20}}) == [20.0, 20.0]
    assert _params(program, 1, 2, machine={}) == [0.0, 0.0]
    # after #RENAME SP [S,S5] the program reads S's parameter as V.MPA.THREADOVR.S5 (L15211-L15213)
    assert _params("#RENAME SP [S,S5]\nP1=V.MPA.THREADOVR.S5\nM30\n", 1,
                   machine={"machine_parameters": {"MPA.THREADOVR.S": 20}}) == [20.0]


def test_the_thread_follows_the_master_of_the_new_configuration():
    # S leaves; S1 is the master, S250 M3 turns it; G33 Z-20 K2 synchronises on S1: 250 x 2 = 500 mm/min
    two = {"spindles": ["S", "S1"]}
    r = fagorcnc.simulate("#FREE SP [S]\nG0 X0 Y0 Z0\nS250 M3\nG33 Z-20 K2\nM30\n", two)
    assert r.ok, [str(d) for d in r.diagnostics]
    line = next(x for x in r.moves if x.kind == "linear")
    assert (line.feed, line.thread.spindle) == (500.0, "S1")


def test_cax_alone_is_the_master_and_a_named_spindle_must_be_in_the_channel():
    # L11635: "#CAX" is the master spindle's; with S gone (#FREE SP [S]) the master is S1, C axis of the file
    lathe = {"axes": {"X": {}, "Z": {}, "C": {"type": "rotary"}}, "spindles": ["S", "S1"], "c_axis": {"S1": "C"}}
    r = fagorcnc.simulate("#FREE SP [S]\n#CAX\nG1 C90 F1000\nM30\n", lathe)
    assert r.ok, [str(d) for d in r.diagnostics]
    # L11630: "#CAX [S1]" names the spindle (S1 read as S with the value 1, not a KIN005 syntax error)
    assert fagorcnc.simulate("#CAX [S1]\nG1 C45 F1000\nM30\n", lathe).ok
    # #CAX [S1] once S1 has left: not a spindle of the channel (INT246)
    assert [d.code for d in fagorcnc.simulate("#FREE SP [S1]\n#CAX [S1]\nM30\n", lathe).diagnostics] == ["INT246"]
