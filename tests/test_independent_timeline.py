"""#MOVE alongside the general motion: each axis's own interpolator, the sum of both, the two stored
instructions, and what makes the program wait (seed 002 ch. 21.1.19, L16615-L16678; plan/independent.py).

The machine of these tests: every axis at max_acceleration 500 mm/s² with a jerk so high (1e9 mm/s³) that the
profiles are trapezoids to within microseconds.  A move of L mm from rest to rest at v mm/s then takes
``L / v + v / a`` (the two ramps of ``v / a`` each cover ``v² / 2a``, half the distance cruising takes in that time).
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import fagorcnc
from fagorcnc.backends.interpcnc.backend import InterpCncBackend
from fagorcnc.backends.sim import SimulatorBackend
from fagorcnc.plan import Planner
from fagorcnc.plan.independent import IndependentAxisError, IndependentSegment

AXIS = {"max_acceleration": 500.0, "max_jerk": 1e9, "max_velocity": 10000.0}
MACHINE = {"axes": {a: dict(AXIS) for a in ("X", "Y", "Z", "U")}}
A = 500.0


def _time(length: float, feed: float) -> float:
    """Rest-to-rest time of a trapezoid: ``L / v + v / a`` (v in mm/s from F in mm/min)."""
    v = feed / 60.0
    return length / v + v / A


def _run(program: str, machine=MACHINE):
    r = fagorcnc.simulate(text=program, machine=machine)
    assert r.ok, r.diagnostics
    return r


def _codes(program: str, machine=MACHINE) -> list[str]:
    return [d.code for d in fagorcnc.simulate(text=program, machine=machine).diagnostics]


CONCURRENT = "G0 X0 Y0 U0\n#MOVE [U100, F1000]\nG1 X50 F600\nM30\n"


def test_the_cycle_time_is_the_longer_of_both_not_their_sum():
    # L16622-L16623: the independent U move and the general X move run at the same time.
    # U: 100 mm at 1000 mm/min = 16.667 mm/s: 100 / 16.667 + 16.667 / 500 = 6 + 0.0333 = 6.0333 s
    # X: 50 mm at 600 mm/min = 10 mm/s:        50 / 10 + 10 / 500     = 5 + 0.02   = 5.02 s
    # cycle = max(6.0333, 5.02) = 6.0333 s (one after the other, as before: 11.0533 s)
    r = _run(CONCURRENT)
    assert _time(100, 1000) == pytest.approx(6.03333, abs=1e-5) and _time(50, 600) == pytest.approx(5.02)
    assert r.cycle_time == pytest.approx(6.03333, abs=1e-3)
    segs = list(r.segments(keep_profiles=False))
    u = next(s for s in segs if isinstance(s, IndependentSegment))
    x = next(s for s in segs if s.kind == "motion" and not isinstance(s, IndependentSegment))
    assert (u.axis, u.t0, x.t0) == ("U", 0.0, 0.0)   # both start when the program reaches the #MOVE
    assert x.duration == pytest.approx(5.02, abs=1e-3)


def test_the_sampled_trajectory_moves_both_axes_at_once():
    # at t (s), from rest at a = 500: a ramp of v / a, then cruising: pos = v t - v² / (2a)
    # U (v = 16.667): t=1: 16.667 - 0.2778 = 16.389; t=3: 50 - 0.2778 = 49.722; t=5.5: 91.667 - 0.2778 = 91.389
    # X (v = 10):     t=1: 10 - 0.1 = 9.9;          t=3: 29.9;                   t=5.5: at rest at 50
    tr = _run(CONCURRENT).trajectory(0.001)
    for t, u, x in ((1.0, 16.3889, 9.9), (3.0, 49.7222, 29.9), (5.5, 91.3889, 50.0)):
        k = round(t / 0.001)
        assert tr.t[k] == pytest.approx(t)
        assert tr.position["U"][k] == pytest.approx(u, abs=1e-3)
        assert tr.position["X"][k] == pytest.approx(x, abs=1e-3)
    k = round(3.0 / 0.001)
    assert tr.velocity["U"][k] * 60 == pytest.approx(1000.0) and tr.velocity["X"][k] * 60 == pytest.approx(600.0)
    assert tr.position["U"][-1] == 100.0 and tr.position["X"][-1] == 50.0
    assert tr.t[-1] == pytest.approx(6.0333, abs=2e-3)
    # the limits hold for the sum: U's speed and acceleration never beyond F1000 and 500 mm/s²
    assert np.max(np.abs(tr.velocity["U"])) <= 1000.0 / 60 + 1e-9
    assert np.max(np.abs(tr.acceleration["U"])) <= A * (1 + 1e-6)


def test_the_manual_example_is_one_axis_so_it_still_takes_42_seconds():
    # L16806-L16817: the three #MOVEs all position X, one interpolator: they run one after the other on it
    # (PRESENT: X50 reached at F500; NEXT: X100 at the next feed, F125; NULL: X150 at rest), concurrently
    # with nothing.  Without the ramps 50/500 + 50/250 + 50/125 min = 0.1 + 0.2 + 0.4 min = 42 s; the ramps:
    #   X0-50   from 0 to 8.333 mm/s:            50/8.333 + 8.333/(2*500)                      = 6.00833 s
    #   X50-100 8.333 -> 4.1667, cruise, -> 2.0833: 0.00833 + 0.00417 + (50 - 0.05208 - 0.01302)/4.1667 = 11.99688 s
    #   X100-150 2.0833, cruise, -> 0:           0.00417 + (50 - 0.00434)/2.0833                = 24.00208 s
    # total 42.0073 s.  The program itself is done much earlier: the third #MOVE finds two stored (L16625) and
    # waits until X reaches 50 (6.0083 s); M30 comes then, and the cycle ends when X stops at 150 (INT233).
    program = ("P100=500\nG0 X0 Y0\n#MOVE [X50, FP100, PRESENT]\n#MOVE [X100, F[P100/2], NEXT]\n"
               "#MOVE [X150, F[P100/4], NULL]\nM30\n")
    r = _run(program)
    assert r.cycle_time == pytest.approx(42.0073, abs=2e-3)
    segs = list(r.segments(keep_profiles=False))
    waits = [s for s in segs if s.kind == "dwell" and not isinstance(s, IndependentSegment) and s.line in (3, 4, 5)]
    assert [round(w.duration, 3) for w in waits] == [0.0, 0.0, pytest.approx(6.008, abs=1e-3)]
    m30 = next(s for s in segs if s.kind == "aux")
    assert m30.t0 == pytest.approx(6.0083, abs=1e-3)
    assert [d.code for d in r.diagnostics] == ["INT233"]


def test_a_third_instruction_makes_the_program_wait_for_the_first():
    # L16625-L16627: at most two independent instructions stored per axis (the one running counts).
    # U0->100, U100->0, U0->100 at F1000, NULL: 6.0333 s each.  The third waits until the first ends (6.0333 s),
    # so G1 X50 starts at 6.0333 and ends at 6.0333 + 5.02 = 11.0533; U ends at 3 x 6.0333 = 18.1 s = the cycle.
    # At t = 8 s: X = 10 (8 - 6.0333) - 0.1 = 19.567; U, 1.9667 s into U100->0: 100 - (16.667 x 1.9667 - 0.2778)
    # = 67.5
    program = ("G0 X0 U0\n#MOVE [U100, F1000, NULL]\n#MOVE [U0, F1000, NULL]\n#MOVE [U100, F1000, NULL]\n"
               "G1 X50 F600\nM30\n")
    r = _run(program)
    assert r.cycle_time == pytest.approx(18.1, abs=2e-3)
    x = next(s for s in r.segments(keep_profiles=False) if s.line == 5 and s.kind == "motion")
    assert x.t0 == pytest.approx(6.0333, abs=1e-3)
    tr = r.trajectory(0.001)
    k = 8000
    assert tr.position["X"][k] == pytest.approx(19.567, abs=2e-3)
    assert tr.position["U"][k] == pytest.approx(67.5, abs=2e-3)


def test_a_move_reached_while_its_axis_runs_waits_for_it_from_rest():
    # U0->100 (6.0333 s) runs while G1 X10 F600 (10/10 + 0.02 = 1.02 s); the second #MOVE of U is reached at
    # 1.02 s, while U still moves: it starts when the first has stopped, at 6.0333, and ends at 12.0667 s (INT230:
    # the machine may join the two)
    r = _run("G0 X0 U0\n#MOVE [U100, F1000, NULL]\nG1 X10 F600\n#MOVE [U0, F1000, NULL]\nM30\n")
    assert r.cycle_time == pytest.approx(12.0667, abs=2e-3)
    second = [s for s in r.segments(keep_profiles=False) if isinstance(s, IndependentSegment) and s.line == 4]
    assert second[0].t0 == pytest.approx(6.0333, abs=1e-3)
    assert sorted({d.code for d in r.diagnostics}) == ["INT230", "INT233"]


def test_a_general_move_of_the_axis_before_sync_pos_is_refused():
    # L16618-L16623, L16657-L16665: the general interpolator does not count the #MOVE until #SYNC POS; the machine
    # adds both, so G1 X60 would take X to 50 + 60 = 110, not 60: refused (INT232), also when X seems to be there
    assert "INT232" in _codes("#MOVE [X50, F500]\nG1 X60 F500\nM30\n")
    assert "INT232" in _codes("#MOVE [X50, F500]\nG1 X50 F500\nM30\n")
    assert "INT232" not in _codes("#MOVE [X50, F500]\nG1 Y60 F500\nM30\n")


def test_the_planner_refuses_a_general_record_moving_the_axis():
    # what moves an axis without a G1 of it (a cycle, a homing) is refused by the planner as well (INT232)
    r = _run("G0 X0 Y0\n#MOVE [X50, F500]\nG1 Y10 F500\nM30\n")
    moves = list(r.moves)
    i = next(k for k, m in enumerate(moves) if m.line == 3)
    moves[i] = dataclasses.replace(moves[i], end={**moves[i].end, "X": 60.0})
    with pytest.raises(IndependentAxisError) as err:
        list(Planner(r.machine).segments(moves))
    assert err.value.code == "INT232" and err.value.line == 3


def test_sync_pos_waits_for_the_positioning_then_the_axis_moves_again():
    # X 50 mm at F500 (8.333 mm/s): 6 + 8.333/500 = 6.0167 s; meanwhile G1 Y10 F500: 1.2 + 0.0167 = 1.2167 s.
    # #SYNC POS waits 6.0167 - 1.2167 = 4.8 s (INT234), then G1 X60 (10 mm: 1.2167 s): cycle 6.0167 + 1.2167
    # = 7.2333 s (one after the other: 8.45 s)
    program = "G0 X0 Y0\n#MOVE [X50, F500]\nG1 Y10 F500\n#SYNC POS\nG1 X60\nM30\n"
    r = _run(program)
    assert r.cycle_time == pytest.approx(7.2333, abs=2e-3)
    wait = next(s for s in r.segments(keep_profiles=False) if s.line == 4 and s.duration > 0)
    assert wait.kind == "dwell" and wait.duration == pytest.approx(4.8, abs=1e-3)
    assert [d.code for d in r.diagnostics] == ["INT234"]
    assert r.moves[-2].end["X"] == 60.0


def test_check_dry_run_and_the_simulator_time_it_alike():
    # every entry point takes the cycle time from the same timeline: max of both, 6.0333 s
    dry = fagorcnc.dry_run(text=CONCURRENT, machine=MACHINE)
    assert dry.ok and dry.cycle_time == pytest.approx(6.0333, abs=1e-3)
    r = _run(CONCURRENT)
    sim = SimulatorBackend(r.machine)
    sim.open()
    for seg in r.segments(keep_profiles=False):
        sim.send(seg)
    assert sim.cycle_time == pytest.approx(r.cycle_time)
    assert sim.status().position["U"] == 100.0 and sim.status().position["X"] == 50.0


class _Card:
    name = "interpcnc"


def test_the_interpcnc_card_refuses_independent_motion_before_the_start():
    # the card has one interpolator: a #MOVE beside the program cannot be sent as it was planned (refused in its
    # preflight, which the check before a real run asks of every segment)
    r = _run(CONCURRENT)
    segs = list(r.segments(keep_profiles=False))
    u = next(s for s in segs if isinstance(s, IndependentSegment))
    why = InterpCncBackend.preflight(_Card(), u)
    assert why is not None and "#MOVE of U" in why and "nothing was sent" in why


def test_waitinpos_holds_the_axis_in_position_on_its_own_timeline():
    # L16741: WAITINPOS stops at the position and waits in position before the axis's next block (inposition_time
    # 0.5 s here).  X0-50 at F500: 50 / 8.333 + 8.333 / 500 = 6.0167 s, the wait to 6.5167 s, then X50-100 to
    # 12.5333 s.  At t = 6.3 s X stands at 50 (the general records already carry it at 100, its last target).
    machine = {**MACHINE, "planner": {"inposition_time": 0.5}}
    r = _run("G0 X0\n#MOVE [X50, F500, WAITINPOS]\n#MOVE [X100, F500, NULL]\nM30\n", machine)
    assert r.cycle_time == pytest.approx(12.5333, abs=2e-3)
    tr = r.trajectory(0.001)
    assert tr.position["X"][6300] == pytest.approx(50.0) and tr.velocity["X"][6300] == 0.0
    assert tr.position["X"][9000] == pytest.approx(50 + 8.3333 * (9.0 - 6.5167) - 8.3333 ** 2 / 1000, abs=2e-3)


def test_an_execution_read_of_an_axis_a_move_may_still_position_is_warned():
    # L16615-L16623: U has its own interpolator; the general motion stops for V.A.POS.U (an execution read) while
    # U may still be moving, so the machine reads it mid-way; offline the end, 100, with warning INT235.  After
    # #SYNC POS the general interpolator has U again: no warning.
    r = _run("#MOVE ABS [U100, F1000]\nG1 X50 F600\nP1=V.A.POS.U\n#SYNC POS\nP2=V.A.POS.U\nM30\n")
    warned = [(d.line, d.col, d.severity) for d in r.diagnostics if d.code == "INT235"]
    assert warned == [(3, 4, "warning")]
    assert r.state.param(1) == 100.0 and r.state.param(2) == 100.0
