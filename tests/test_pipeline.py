"""The idle lane of the path stages (:func:`fagorcnc.interp.pipeline.stages`) must be invisible.

Every program here runs twice, through the idle lane and with :attr:`Interpreter.idle_stages` off (the
stages chained as generators from the first record), and everything must be the same: each record (its
``repr``, so every float to the last bit, and its type), the diagnostics, the ending, the cycle time, and
the planned cycle time of a dry run.  The programs start with plain moves, dwells and auxiliary functions
(the corner aids' stage then holds a move and the records after it) before what the lane hands over at:
a #SPLINE mark, a corner aid, radius compensation, tangential control, a transformation, #MCS, a coupling.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

import fagorcnc
from fagorcnc.interp import pipeline
from fagorcnc.interp.interpreter import Interpreter

ROOT = Path(__file__).resolve().parents[1]

#: Moves, a dwell and auxiliary functions: the state the idle lane holds when something comes.
HEAD = "G0 X0 Y0 Z5\nT1 D1 M6\nG1 X5 F800\nG4 K10\nM8\nX10 Y2\nM9\n"

MACHINE = {
    "axes": {"X": {}, "Y": {}, "Z": {}, "U": {"max_limit": 100.0}, "A": {"type": "rotary", "min_limit": -120,
                                                                           "max_limit": 120},
             "C": {"type": "rotary", "rotary_mode": "normal", "max_velocity": 3600.0}},
    "kinematics": [{"type": 10}, {"type": 43, "axes": ["A"], "directions": [[1, 0, 0]]}],
    "tools": {"1": {"1": {"length": 20.0, "radius": 2.0}}},
}

PROGRAMS = {
    "plain": HEAD + "X0\n",
    "ends_with_records_held": HEAD,
    "spline": HEAD + "#SPLINE ON\nX20 Y10\nX30 Y0\nX40 Y5\n#SPLINE OFF\nX50\n",
    "spline_tangent_to_the_last_move": HEAD + "#ASPLINE MODE [2,2]\n#SPLINE ON\nX20 Y10\nX30 Y0\n#SPLINE OFF\n"
                                              "X40\n",
    "spline_after_a_move": HEAD + "#ASPLINE MODE [2,1]\n#MOVE ABS [U50, F1000]\n#SPLINE ON\nX20 Y10\nX30 Y0\n"
                                  "X40 Y5\n#SPLINE OFF\nX50\n",
    "corner_aid": HEAD + "X50\nG36 I5\nY50\nX0\n",
    "corner_aid_first": "G36 I5\nG1 X10 F100\n",
    "corner_aid_last": HEAD + "G39 I5\n",
    "compensation": HEAD + "G41 X20 Y20\nX40\nY40\nG40 X50 Y50\nX0 Y0\n",
    "tangential": "G0 X0 Y0\nG1 X5 F100\nG4 K1\n#TANGCTRL ON [C90, F300]\nX10 Y10\nY20\n#TANGCTRL OFF\nX0\n",
    "transformation": HEAD + "#CS ON [1] [MODE 1, 0,0,0, 30,0,0]\n#TOOL ORI\nG0 X10\nG1 Y20 F500\n#CS OFF\nX0\n",
    "rtcp": HEAD + "#RTCP ON\nG1 X20 A10 F100\n#RTCP OFF\nG1 X0\n",
    "mcs": HEAD + "#MCS G0 X30 Y30\nG1 X0 F300\n",
    "mcs_under_a_transformation": HEAD + "#CS ON [1] [MODE 1, 0,0,0, 30,0,0]\nG1 X10 F500\n#MCS G0 X30 Y30\n"
                                         "G1 Y20\n#CS OFF\nX0\n",
    "coupling": "G0 U5\nG1 X2 F1000\nM8\n#LINK [X, U]\nG1 X10\nG4 K1\nG1 X-2\n#UNLINK\nG1 U20\nX0\n",
    "independent_move": HEAD + "#MOVE ABS [U50, F1000]\nX20\n#SYNC POS\nX30\n",
    "error_after_moves": HEAD + "G1 X5000\n",
}


def _shown(records) -> list:
    """Each record's type and ``repr``, the addresses of the objects in it (a curve's chords share one)
    numbered in the order they first appear."""
    seen: dict = {}
    return [(type(m).__name__, re.sub(r" at 0x[0-9a-f]+", lambda a: f" #{seen.setdefault(a[0], len(seen))}",
                                      repr(m))) for m in records]


def _run(text: str, idle: bool, monkeypatch) -> tuple:
    monkeypatch.setattr(Interpreter, "idle_stages", idle)
    r = fagorcnc.simulate(text=text + "M30\n", machine=MACHINE)
    dry = fagorcnc.dry_run(text=text + "M30\n", machine=MACHINE)
    return (_shown(r.moves), [repr(d) for d in r.diagnostics], r.ok,
            repr(r.ending), r.cycle_time, [repr(d) for d in dry.diagnostics], dry.cycle_time, dry.moves)


@pytest.mark.parametrize("name", sorted(PROGRAMS))
def test_programs_same_both_ways(name, monkeypatch):
    lane = _run(PROGRAMS[name], True, monkeypatch)
    chain = _run(PROGRAMS[name], False, monkeypatch)
    assert lane[1] == chain[1]   # diagnostics first: the clearest message when they differ
    assert lane == chain


@pytest.mark.parametrize("name", sorted(p.name for p in (ROOT / "programs").glob("*.nc")))
def test_example_programs_same_both_ways(name, monkeypatch):
    text = (ROOT / "programs" / name).read_text()
    assert _run(text, True, monkeypatch) == _run(text, False, monkeypatch)


@pytest.mark.parametrize("name", ["tilted_plane.nc", "rtcp_table.nc"])
def test_five_axis_programs_same_both_ways(name, monkeypatch):
    machine = ROOT / "machines" / "five_axis_ac.toml"
    runs = []
    for idle in (True, False):
        monkeypatch.setattr(Interpreter, "idle_stages", idle)
        r = fagorcnc.simulate(ROOT / "programs" / "five_axis" / name, machine)
        runs.append((_shown(r.moves), [repr(d) for d in r.diagnostics], r.cycle_time))
    assert runs[0] == runs[1]


def test_the_lane_hands_over_where_a_stage_acts(monkeypatch):
    """The idle lane takes the plain head, and hands the rest to the chained stages at the first record
    one of them acts on (here the #SPLINE mark), with the corner aids' held move and the records after it."""
    handed = []
    chained = pipeline.chained

    def watching(records, interp, on_error, last=None, held=None, after=()):
        handed.append((last, held, list(after)))
        return chained(records, interp, on_error, last, held, after)

    monkeypatch.setattr(pipeline, "chained", watching)
    r = fagorcnc.simulate(text=PROGRAMS["spline"] + "M30\n", machine=MACHINE)
    assert r.ok, r.diagnostics
    ((last, held, after),) = handed
    assert last is held and held.src.line == 6   # X10 Y2, then M9 after it
    assert [(a.kind, a.src.line) for a in after] == [("aux", 7)]
    monkeypatch.setattr(pipeline, "chained", watching)
    handed.clear()
    fagorcnc.simulate(text=PROGRAMS["plain"] + "M30\n", machine=MACHINE)
    assert handed == []   # nothing for the stages to do: the lane to the end


def test_run_shows_each_record_to_its_watcher():
    """``Interpreter.run(watch)``: the watcher sees each record handed on, in order, as it is handed on (the
    interpreter's state is the one then), and ``moves_handed`` counts the moves among them."""
    from fagorcnc.machine import load_machine
    from fagorcnc.syntax import parse_text

    interp = Interpreter(parse_text(PROGRAMS["compensation"] + "M30\n"), load_machine(MACHINE))
    seen, lines = [], []
    handed = []
    for rec in interp.run(lambda r, i: (seen.append(r), lines.append(i.state.line))):
        assert seen[-1] is rec   # shown before it is handed on
        handed.append(rec)
    assert seen == handed and interp.moves_handed == sum(r.kind not in ("aux", "dwell") for r in handed) == 10
    assert lines == sorted(lines)   # each seen after the blocks it comes after were run
