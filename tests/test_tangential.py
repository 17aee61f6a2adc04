"""Tangential control G45, G145, #TANGCTRL (seed 002 ch. 16; spec 05 §5)."""

from __future__ import annotations

import pytest

import fagorcnc

MACHINE = {"axes": {"X": {}, "Y": {}, "Z": {},
                    "C": {"type": "rotary", "rotary_mode": "normal", "max_velocity": 3600.0}}}


def moves(r):
    return [m for m in r.moves if m.kind in ("linear", "rapid", "arc")]


def codes(r):
    return [d.code for d in r.diagnostics]


def test_the_axis_follows_the_path():
    # G45 C0: C = direction of the path.  X10: 0 deg (C already there).  Y10: the axis turns alone to
    # 90, then the line.  X0 Y20: direction atan2(10, -10) = 135.  G3 X-10 Y10 about (0, 10) from
    # (0, 20): the tangent at the start is 180, C turns to it alone, then rises with the arc's +90 sweep
    text = "G0 X0 Y0\nG45 C0\nG1 X10 F100\nY10\nX0 Y20\nG3 X-10 Y10 I0 J-10\nG45\nM30\n"
    r = fagorcnc.simulate(text, MACHINE)
    assert r.ok, r.diagnostics
    ms = moves(r)[1:]
    kinds = [(m.src.line, m.kind, round(m.start["C"], 6), round(m.end["C"], 6)) for m in ms]
    assert kinds == [
        (3, "linear", 0, 0),
        (4, "linear", 0, 90), (4, "linear", 90, 90),
        (5, "linear", 90, 135), (5, "linear", 135, 135),
        (6, "linear", 135, 180), (6, "arc", 180, 270),
    ]
    # a turn alone moves C only, at the axis' own maximum feed (no #TANGCTRL F programmed)
    turn = ms[1]
    assert turn.start["X"] == turn.end["X"] == 10 and turn.start["Y"] == turn.end["Y"] == 0
    assert turn.feed == 3600.0


def test_angle_to_the_path_and_the_shortest_way():
    # G45 C90 with the path along -X (180 deg): C = 270, reached from 0 the short way (-90)
    r = fagorcnc.simulate("G0 X10 Y0\n#TANGCTRL ON [C90, F300]\nG1 X0 F100\nP1=V.A.TANGAN.C\nP2=V.G.TANGFEED\n"
                          "P3=V.G.TGCTRLST\nM30\n", MACHINE)
    assert r.ok, r.diagnostics
    turn = moves(r)[1]
    assert turn.end["C"] == pytest.approx(-90) and turn.feed == 300
    assert [r.state.param(i) for i in (1, 2, 3)] == [90, 300, 1]


def test_suspend_and_resume():
    # G145 K0: C stays at 0 on the Y move; G145 K1: the next move (along +X... -Y here) realigns it
    r = fagorcnc.simulate("G45 C0\nG1 X10 F100\nG145 K0\nP1=V.G.TGCTRLST\nY10\nG145 K1\nY0\nM30\n", MACHINE)
    assert r.ok, r.diagnostics
    ms = moves(r)
    assert ms[-3].src.line == 5 and ms[-3].end["C"] == pytest.approx(0)      # suspended: no turn
    assert ms[-2].src.line == 7 and ms[-2].end["C"] == pytest.approx(-90)    # resumed: -Y is -90
    assert r.state.param(1) == 2


def test_cancelled_by_m30_and_g45_alone():
    r = fagorcnc.simulate("G45 C0\nG45\nG1 C10 F100\nM30\n", MACHINE)
    assert r.ok, r.diagnostics


@pytest.mark.parametrize(("text", "code"), [
    ("G45 X90\n", "KIN050"),
    ("G45 C400\n", "KIN051"),
    ("G45 C0\nG1 C10 F100\n", "KIN053"),
    ("G145 K2\n", "KIN051"),
    ("#TANGCTRL ON\n", "KIN051"),
    ("T1 D1 M6 S1000 M3\nG45 C0\nG42 G1 X10 F100\n", "KIN052"),
])
def test_tangential_errors(text, code):
    assert codes(fagorcnc.simulate(text + "M30\n", MACHINE)) == [code]


def test_needs_a_modulo_axis():
    m = {"axes": {"X": {}, "Y": {}, "Z": {}, "C": {"type": "rotary"}}}   # linearlike
    assert codes(fagorcnc.simulate("G45 C0\nM30\n", m)) == ["KIN050"]
