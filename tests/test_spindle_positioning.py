"""Spindle functions per spindle and M19 positioning (seed 002 ch. 7, L5683-L5934; variables L36977-L37215)."""

from __future__ import annotations

import pytest

import fagorcnc

TWO_SPINDLES = {"spindles": ["S", "S1", "S2", "S4"]}


def _aux(r, *functions):
    return [(m.line, m.function, m.value, m.spindle) for m in r.moves
            if m.kind == "aux" and (not functions or m.function in functions)]


def _ok(program, machine=None):
    r = fagorcnc.simulate(program, machine)
    assert r.ok, [str(d) for d in r.diagnostics]
    return r


def test_the_manuals_example_keeps_the_speed_programmed_while_positioning():
    # seed 002 L5776-L5790: N40 S1000 while in M19 is the new speed, used by the M03 of N60
    r = _ok("N10 G97 S2500 M03\nN20 M19 S50\nN30 M19 S150\nN40 S1000\nN50 M19 S-100\nN60 M03\n"
            "P1=V.A.SPEED.S\nN70 M30\n")
    assert _aux(r, "S", "SPOS") == [(1, "S", 2500.0, "S"), (2, "SPOS", 50.0, "S"), (3, "SPOS", 150.0, "S"),
                                    (5, "SPOS", 260.0, "S"), (6, "S", 1000.0, "S")]
    assert r.state.param(1) == 1000.0


def test_m19_without_s_positions_the_master_at_zero():
    # L5722: M19 alone takes the master spindle to 0 degrees
    r = _ok("S500 M3\nM19\nM30\n")
    assert _aux(r, "SPOS") == [(2, "SPOS", 0.0, "S")]


def test_a_suffix_names_the_spindle():
    # L5735-L5742: M19.S4 takes S4 to 0 degrees; M3.S2 starts S2 only, S2=800 its speed
    r = _ok("S2=800 M3.S2\nM19.S4\nM19 S2=120.78 S1=10\nM30\n", TWO_SPINDLES)
    assert _aux(r, "S", "SPOS") == [(1, "S", 800.0, "S2"), (2, "SPOS", 0.0, "S4"),
                                    (3, "SPOS", 120.78, "S2"), (3, "SPOS", 10.0, "S1")]
    m = [(line, value, spindle) for line, f, value, spindle in _aux(r, "M")]
    assert m[:2] == [(1, 3.0, "S2"), (2, 19.0, "S4")]


def test_m3_dot_s2_is_not_a_speed_of_2_rpm():
    # before the suffix was read, "M3.S2" was M3 and S=2: the spindle would have turned at 2 rpm
    r = _ok("S2=900 M3.S2\nM30\n", TWO_SPINDLES)
    assert [a for a in _aux(r, "S") if a[2] == 2.0] == []


def test_unsuffixed_m3_acts_on_the_spindles_with_a_speed_and_m5_on_the_master():
    # spec 03 A.9 (L5950-L5966)
    text = "S1=100 S2=200 M3 M4.S2\nP1=V.A.SREAL.S1 P2=V.A.SREAL.S2 P3=V.A.SREAL.S\nM30\n"
    r = _ok(text, TWO_SPINDLES)
    # S1 turns (M3), S2 turns (M4.S2), the master S has no M: its real speed is 0
    assert [r.state.param(n) for n in (1, 2, 3)] == [100.0, 200.0, 0.0]


def test_direction_suffixes_are_m19_only():
    r = fagorcnc.simulate("M3.POS\nM30\n")
    assert [d.code for d in r.diagnostics if d.is_error] == ["INT025"]
    r = fagorcnc.simulate("M8.S1\nM30\n", TWO_SPINDLES)
    assert [d.code for d in r.diagnostics if d.is_error] == ["INT025"]
    r = fagorcnc.simulate("M3.S9\nM30\n")
    assert [d.code for d in r.diagnostics if d.is_error] == ["INT020"]


def test_m19_pos_and_neg_position_the_spindles_of_the_block():
    # L5843-L5880: M19.POS / M19.NEG for every spindle of the block, M19.POS.S1 for S1 only
    # L5867-L5868: "M19.NEG.S1 S1=100 S34.75": negative for S1, both spindles positioned
    r = _ok("M19.POS S90\nM19.NEG.S1 S1=100 S34.75\nM19.NEG\nM30\n", TWO_SPINDLES)
    assert sorted(_aux(r, "SPOS")) == [(1, "SPOS", 90.0, "S"), (2, "SPOS", 34.75, "S"), (2, "SPOS", 100.0, "S1"),
                                       (3, "SPOS", 0.0, "S")]


def test_positioning_speed_and_override_variables():
    # L5904-L5934: S.POS= / Sn.POS= positioning speeds; PRGSSO read/write, 0 = none; SSO the active one
    r = _ok("M19 S.POS=120 S1.POS=50\nP1=V.A.PRGSPOS.S P2=V.A.SPOS.S1 P3=V.SP.PRGSPOS.S1\n"
            "P4=V.A.SSO.S\nV.A.PRGSSO.S=80\nP5=V.A.SSO.S P6=V.A.PRGSSO.S\nM30\n", TWO_SPINDLES)
    assert [r.state.param(n) for n in range(1, 7)] == [120.0, 50.0, 50.0, 100.0, 80.0, 80.0]
    bad = fagorcnc.simulate("M19 S.POS=0\nM30\n")
    assert [d.code for d in bad.diagnostics if d.is_error] == ["INT027"]
    assert [d.code for d in fagorcnc.simulate("V.A.SSO.S=50\nM30\n").diagnostics] == ["INT048"]


@pytest.mark.parametrize("text", ["M3. S100", "G1 X3.Y4 F100 M3"])
def test_a_plain_m_with_a_trailing_dot_and_words_run_together_still_read(text):
    r = _ok(f"{text}\nM30\n")
    assert ("M", 3.0) in [(f, v) for _, f, v, _ in _aux(r, "M")]
