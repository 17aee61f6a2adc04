"""#MOVE: independent positioning of one axis with its end-of-move link (seed 002 L16684-L16817)."""

from __future__ import annotations

import pytest

import fagorcnc
from fagorcnc.interp.records import IndependentMove
from fagorcnc.plan.independent import IndependentSegment

#: The manual's example (L16806-L16817): feeds 500, 250, 125.
EXAMPLE = ("P100=500\nG0 X0 Y0\n#MOVE [X50, FP100, PRESENT]\n#MOVE [X100, F[P100/2], NEXT]\n"
           "#MOVE [X150, F[P100/4], NULL]\nM30\n")


def _moves(program: str, machine=None) -> list[IndependentMove]:
    r = fagorcnc.simulate(text=program, machine=machine)
    assert r.ok, r.diagnostics
    return [m for m in r.moves if isinstance(m, IndependentMove)]


def _codes(program: str, machine=None) -> list[str]:
    return [d.code for d in fagorcnc.simulate(text=program, machine=machine).diagnostics]


def test_manual_example_feeds_and_links():
    moves = _moves(EXAMPLE)
    assert [(m.end["X"], m.feed, m.link) for m in moves] == [(50.0, 500.0, "PRESENT"), (100.0, 250.0, "NEXT"),
                                                           (150.0, 125.0, "NULL")]


def test_manual_example_speeds_at_each_position():
    # the figure of L16810-L16817: X reaches 50 at 500 mm/min (PRESENT: its own feed), 100 at 125 mm/min
    # (NEXT: the next block's feed) and stops at 150 (NULL)
    r = fagorcnc.simulate(text=EXAMPLE)
    segs = [s for s in r.segments() if s.kind == "motion" and s.line in (3, 4, 5)]
    at = {}
    for s in segs:
        at.setdefault(round(float(s.piece.end[0]), 6), s.v1 * 60.0)
    assert at[50.0] == pytest.approx(500.0)
    assert at[100.0] == pytest.approx(125.0)
    assert at[150.0] == 0.0
    # times without the ramps: 50/500 + 50/250 + 50/125 min = 0.1 + 0.2 + 0.4 min = 42 s
    assert sum(s.duration for s in segs) == pytest.approx(42.0, abs=0.1)


def test_null_stops_between_two_moves():
    r = fagorcnc.simulate(text="G0 X0\n#MOVE [X50, F500, NULL]\n#MOVE [X100, F500, NULL]\nM30\n")
    first = next(s for s in r.segments() if s.line == 2)
    assert first.v1 == 0.0


def test_waitinpos_adds_the_in_position_wait():
    # on the axis's own timeline (plan/independent.py): X stops at 50, waits 0.5 s in position, goes on
    machine = {"planner": {"inposition_time": 0.5}}
    r = fagorcnc.simulate(text="G0 X0\n#MOVE [X50, F500, WAITINPOS]\n#MOVE [X100, F500, NULL]\nM30\n",
                          machine=machine)
    kinds = [(s.kind, s.line, round(s.duration, 3)) for s in r.segments() if isinstance(s, IndependentSegment)]
    k = next(i for i, x in enumerate(kinds) if x[1] == 2)
    assert kinds[k + 1][0] == "dwell" and kinds[k + 1][2] == 0.5


def test_a_move_never_blends_with_a_general_block():
    # L16672-L16674: no link across an independent move: its own motion ends at rest (nothing of its axis
    # follows), and the general G1 Y10 before it stops there instead of joining G1 Y20 after it
    r = fagorcnc.simulate(text="G0 X0 Y0\nG1 Y10 F500\n#MOVE [X50, F500, PRESENT]\nG1 Y20\nM30\n")
    move = next(s for s in r.segments() if s.line == 3 and isinstance(s, IndependentSegment))
    assert move.v1 == 0.0
    assert next(s for s in r.segments() if s.line == 2).v1 == 0.0


@pytest.mark.parametrize(("icorner", "link"), [(0, "NULL"), (1, "PRESENT"), (2, "WAITINPOS")])
def test_default_link_follows_icorner(icorner, link):
    # L16741-L16747: G50 -> NULL, G05 -> PRESENT, G07 -> WAITINPOS
    moves = _moves("#MOVE [X5, F100]\nM30\n", {"defaults": {"ICORNER": icorner}})
    assert moves[0].link == link


def test_add_abs_and_offsets():
    # G54 X shift 10: ABS X5 is part X5 = machine X15; ADD X2 then goes to part 7 = machine 17
    moves = _moves("G54\n#MOVE ABS [X5, F100]\n#MOVE ADD [X2, F100]\nM30\n", {"origins": {"G54": {"X": 10}}})
    assert [m.end["X"] for m in moves] == [15.0, 17.0]


def test_rotary_takes_the_shortest_way():
    # a normal rotary at 350 degrees to 10: +20 degrees, not -340 (L16701)
    machine = {"axes": {"X": {}, "Y": {}, "Z": {}, "C": {"type": "rotary", "rotary_mode": "normal",
                                                          "min_limit": -1e6, "max_limit": 1e6}}}
    moves = _moves("G0 C350\n#MOVE [C10, F1000]\nM30\n", machine)
    assert moves[0].end["C"] == pytest.approx(370.0)


def test_inf_runs_to_the_travel_limit_with_a_warning():
    r = fagorcnc.simulate(text="#MOVE INF [X+, F1000]\nM30\n")
    assert "INT231" in [d.code for d in r.diagnostics]
    assert next(m for m in r.moves if isinstance(m, IndependentMove)).end["X"] == 1000.0   # the default limit


def test_inch_feed_and_position():
    # G70: X1 inch = 25.4 mm at F10 in/min = 254 mm/min (L16716)
    moves = _moves("G70\n#MOVE [X1, F10]\nM30\n")
    assert (moves[0].end["X"], moves[0].feed) == pytest.approx((25.4, 254.0))


def test_without_f_the_axis_moves_at_its_posfeed():
    # L16714-L16720: #MOVE without F runs at the axis's POSFEED; [machine_parameters] "MPA.POSFEED.X" = 400
    # (mm/min, machine-file units) gives it: 50 mm at 400 mm/min
    machine = {"machine_parameters": {"MPA.POSFEED.X": 400.0}}
    moves = _moves("#MOVE [X50]\nM30\n", machine)
    assert (moves[0].end["X"], moves[0].feed) == pytest.approx((50.0, 400.0))


def test_no_sequencing_note_and_no_int078():
    # the three #MOVEs are reached at one instant and planned as one chain on X's interpolator: nothing
    # of them is a construction any more (INT230 is only for a #MOVE queued behind a running one)
    codes = _codes(EXAMPLE)
    assert "INT230" not in codes and "INT078" not in codes


@pytest.mark.parametrize(("program", "code"), [
    ("#MOVE [X50]\n", "INT228"),                      # no F, and no POSFEED in the machine file
    ("#MOVE [X50, Y10, F100]\n", "INT227"),           # one axis
    ("#MOVE [F100]\n", "INT227"),                     # no axis
    ("#MOVE [X50, F0]\n", "INT227"),
    ("#MOVE [X50, F100, NULL, NEXT]\n", "INT227"),
    ("#MOVE X50\n", "INT227"),
    ("#MOVE INF [X50, F100]\n", "INT227"),            # INF takes a direction
    ("#MOVE [Q50, F100]\n", "INT229"),                # not an axis of the channel
    ("#MOVE [X5000, F100]\n", "INT100"),              # beyond the soft limit
])
def test_move_errors(program, code):
    assert code in _codes(program + "M30\n")
