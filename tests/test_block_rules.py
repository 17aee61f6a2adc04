"""Block rules the manual states: what must be alone in its block, #RPT ranges and loops, #EXBLK in the
program's own channel, #REPOS outside interrupt subroutines, #DGWZ limits (seed 002; issue "the rest of
the manual", item 8)."""

from __future__ import annotations

import pytest

import fagorcnc


def _codes(program: str) -> list[str]:
    return [d.code for d in fagorcnc.simulate(program).diagnostics if d.severity != "info"]


@pytest.mark.parametrize("block", ["G30 X10", "G30 I1 J2 F100", "G1 G30 X5", "G30 M3"])
def test_g30_must_be_alone_in_its_block(block):
    # seed 002 L3953: "the polar origin preset must be programmed alone in the block"
    assert _codes(f"{block}\nM30\n") == ["INT118"]


def test_g30_alone_or_with_i_and_j_presets_the_polar_origin():
    r = fagorcnc.simulate("G0 X4 Y3\nG30\nG1 R5 Q90 F100\nN5 G30 I10 J0\nG1 R2 Q0\nM30\n")
    assert r.ok, r.diagnostics
    lines = [m for m in r.moves if m.kind == "linear"]
    # G30 alone: the origin at (4, 3); R5 Q90 is 5 up from it: (4, 8); G30 I10 J0: R2 Q0 is (12, 0)
    assert [(round(m.end["X"], 9), round(m.end["Y"], 9)) for m in lines] == [(4.0, 8.0), (12.0, 0.0)]


@pytest.mark.parametrize("block", ["#MCS ON X10", "G1 X10 F100 #MCS ON", "G0 Z0 #MCS OFF"])
def test_mcs_on_and_off_must_be_alone(block):
    # seed 002 L3212: "#MCS ON and #MCS OFF must be programmed alone in the block"
    assert _codes(f"{block}\nM30\n") == ["INT118"]


def test_mcs_with_axes_is_one_move_in_machine_coordinates():
    r = fagorcnc.simulate("#MCS X30 Y30\nN20 #MCS ON\nG0 X1\nN40 #MCS OFF\nM30\n")   # N: a block number
    assert r.ok, r.diagnostics


def test_rpt_may_not_close_a_loop_opened_before_its_range():
    # seed 002 L16278-L16280: a repeated range that closes a $ loop must hold its opening too
    program = ("P1=0\n$WHILE P1<2\nN20: P1=P1+1\nG91 G1 X1 F100\n$ENDWHILE\nN30:\n#RPT [N20, N30]\nM30\n")
    r = fagorcnc.simulate(program)
    assert [d.code for d in r.diagnostics if d.is_error] == ["INT075"]
    assert "line 2" in next(d.message for d in r.diagnostics if d.code == "INT075")


def test_rpt_of_a_range_that_holds_the_whole_loop_runs():
    program = ("N10: P1=0\n$WHILE P1<2\nP1=P1+1\nG91 G1 X1 F100\n$ENDWHILE\nN20:\n#RPT [N10, N20, 2]\nG90\nM30\n")
    r = fagorcnc.simulate(program)
    assert r.ok, r.diagnostics
    # the loop moves 2 mm; run once, then twice more by #RPT: X6
    assert round(r.state.position("part")["X"], 9) == 6.0


def test_exblk_without_channel_runs_the_block_here():
    # seed 002 L11294-L11296: in a program, without a channel, the block runs in the program's own channel
    r = fagorcnc.simulate("P1=0\n#EXBLK [G01 X100 F550]\n#EXBLK [G01 X[P1+10] Y5, 1]\nM30\n")
    assert r.ok, r.diagnostics
    lines = [m for m in r.moves if m.kind == "linear"]
    assert [(m.end["X"], m.end["Y"], m.feed) for m in lines] == [(100.0, 0.0, 550.0), (10.0, 5.0, 550.0)]


def test_exblk_to_another_channel_says_it_is_not_simulated():
    # seed 002 L11304: #EXBLK [G01 X100 F550, 2] runs in channel 2, which fagorcnc does not run
    r = fagorcnc.simulate("#EXBLK [G01 X100 F550, 2]\nM30\n")
    assert r.ok and [d.code for d in r.diagnostics if d.severity == "warning"] == ["INT119"]
    assert [m for m in r.moves if m.kind == "linear"] == []


def test_exblk_with_a_bad_block_is_an_error():
    assert _codes("#EXBLK [G01 X+*3]\nM30\n")[0].startswith("SYN")
    assert _codes("#EXBLK G01\nM30\n") in (["INT071"], ["SYN002"])


def test_repos_is_only_for_interrupt_subroutines():
    # seed 002 L11114: "#REPOS is only allowed in interrupt subroutines"
    assert _codes("#REPOS X Y Z\nM30\n") == ["INT119"]


@pytest.mark.parametrize("zone, codes", [("[0, 100, 0, 50, -20, 10]", []), ("[10, 0, 0, 50, -20, 10]", ["INT071"]),
                                         ("[0, 100, 50, 50, -20, 10]", ["INT071"]), ("[0, 100, 0, 50]", []),
                                         ("[0, 100, 0]", ["INT071"])])
def test_dgwz_lower_limits_below_upper_limits(zone, codes):
    # seed 002 L14419-L14424: each lower limit of an axis is always below its upper one
    assert _codes(f"#DGWZ {zone}\nM30\n") == codes
