"""G112 parameter sets (seed 002 L9307-L9360) and the machine file's ``axes.X.sets``."""

from __future__ import annotations

import pytest

import fagorcnc
from fagorcnc.config.machine import MachineError, load_machine

#: X: set 1 G00FEED 10 000 mm/min, ACCEL 1 000 mm/s²; set 2 G00FEED 6 000, ACCEL 500.
SETS = {"axes": {"X": {"max_velocity": 10000.0, "max_acceleration": 1000.0,
                       "sets": [{"max_velocity": 6000.0, "max_acceleration": 500.0}]},
                 "Y": {}, "Z": {}}}


def _rapid_time(program: str, machine=SETS) -> float:
    """Planned time of the program without a jerk limit (trapezoids: times in closed form)."""
    r = fagorcnc.simulate(text=program, machine=machine)
    assert r.ok, [str(d) for d in r.diagnostics]
    return sum(s.duration for s in r.segments(jerk=False))


def test_g112_selects_the_dynamics_of_the_set():
    # G00 X1000 from rest to rest, no jerk limit: t = L / v + v / a.
    # set 1: v = 10000/60 = 166.667 mm/s, a = 1000: 1000/166.667 + 0.166667 = 6.16667 s
    # set 2: v = 6000/60 = 100 mm/s, a = 500: 1000/100 + 100/500 = 10.2 s
    assert _rapid_time("G0 X1000\nM30\n") == pytest.approx(6.166667, abs=1e-4)
    assert _rapid_time("G112 X2\nG0 X1000\nM30\n") == pytest.approx(10.2, abs=1e-4)
    # G112 X1 goes back to the axis's own values
    assert _rapid_time("G112 X2\nG112 X1\nG0 X1000\nM30\n") == pytest.approx(6.166667, abs=1e-4)


def test_g112_words_are_set_numbers_not_targets():
    r = fagorcnc.simulate(text="G112 X2\nM30\n", machine=SETS)
    assert r.ok and not [m for m in r.moves if m.kind in ("rapid", "linear")]   # X2 moves nothing (L9324)


def test_active_set_variable_and_defaultset_at_m30():
    # V.A.ACTIVSET.X after G112 X2 is 2 (L32845); M30 brings back DEFAULTSET 1 (L9343-L9349)
    text = "G112 X2\nP1 = V.A.ACTIVSET.X\nM30\n"
    r = fagorcnc.simulate(text=text, machine=SETS)
    assert r.ok and r.state.param(1) == 2.0
    keep = {"axes": {**SETS["axes"], "X": {**SETS["axes"]["X"], "default_set": 0}}}
    m = load_machine(keep)
    from fagorcnc.interp.state import ChannelState

    st = ChannelState(m)
    st.param_sets["X"] = 2
    st.reset("M30")
    assert st.param_sets == {"X": 2}       # DEFAULTSET 0: the set of G112 is kept
    st2 = ChannelState(load_machine(SETS))
    st2.param_sets["X"] = 2
    st2.reset("M30")
    assert st2.param_sets == {}            # DEFAULTSET 1


def test_defaultset_two_is_the_power_on_set():
    machine = {"axes": {**SETS["axes"], "X": {**SETS["axes"]["X"], "default_set": 2}}}
    assert _rapid_time("G0 X1000\nM30\n", machine) == pytest.approx(10.2, abs=1e-4)


def test_per_set_machine_parameters_read_their_set():
    # V.MPA.G00FEED[2].X = 6000, V.MPA.ACCEL[2].X = 500, [1] the axis's own; NPARSETS.X = 2
    text = ("P1 = V.MPA.G00FEED[1].X\nP2 = V.MPA.G00FEED[2].X\nP3 = V.MPA.ACCEL[2].X\nP4 = V.MPA.NPARSETS.X\n"
            "P5 = V.MPA.ACCJERK[2].X\nM30\n")
    r = fagorcnc.simulate(text=text, machine=SETS)
    assert r.ok, [str(d) for d in r.diagnostics]
    assert [r.state.param(i) for i in range(1, 6)] == [10000.0, 6000.0, 500.0, 2.0, 20000.0]   # jerk: set 1's


@pytest.mark.parametrize(("program", "code"), [
    ("G112 X3\n", "INT214"),        # the machine file gives X two sets
    ("G112 Y2\n", "INT214"),        # Y has one
    ("G112 X5\n", "INT214"),        # at most 4 (L9309)
    ("G112 X1.5\n", "INT214"),
    ("G112\n", "INT214"),           # no axis named
    ("P1 = V.MPA.G00FEED[3].X\n", "INT242"),
    ("P1 = V.MPA.G00FEED[2].Y\n", "INT242"),
])
def test_g112_errors(program, code):
    r = fagorcnc.simulate(text=program + "M30\n", machine=SETS)
    assert code in [d.code for d in r.diagnostics if d.severity == "error"], [str(d) for d in r.diagnostics]


def test_a_spindle_set_is_kept_with_a_warning():
    r = fagorcnc.simulate(text="G112 S2\nP1 = V.SP.ACTIVSET\nM30\n", machine=SETS)
    assert r.ok and r.state.param(1) == 2.0
    assert "INT215" in [d.code for d in r.diagnostics]


@pytest.mark.parametrize("sets", [
    [{"max_velocity": 1000.0}] * 4,      # 5 sets in all
    [{"max_speed": 1000.0}],             # unknown key
    [{"max_acceleration": 0.0}],
])
def test_machine_file_sets_are_checked(sets):
    with pytest.raises(MachineError):
        load_machine({"axes": {"X": {"sets": sets}, "Y": {}, "Z": {}}})
