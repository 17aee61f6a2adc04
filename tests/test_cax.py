"""#CAX: a spindle working as C axis (seed 002 L11576-L11662)."""

from __future__ import annotations

import pytest

import fagorcnc
from fagorcnc.machine import MachineError, load_machine

LATHE = {"axes": {"X": {}, "Y": {}, "Z": {}, "C": {"type": "rotary", "home": 0.0, "min_limit": -9999,
                                                  "max_limit": 9999}},
         "spindles": ["S"], "c_axis": {"S": "C"}}


def codes(r):
    return [d.code for d in r.diagnostics]


def test_cax_stops_the_spindle_references_c_and_programs_it_in_degrees():
    # L11600: the turning spindle stops; L11603: the C axis is referenced (moved to its home 0);
    # then C is programmed in degrees, and M3 makes it a spindle again (as #CAX OFF, L11617)
    r = fagorcnc.simulate("S1000 M3\n#CAX\nG01 Z50 C100 F100\nM5\nS500 M3\nM30\n", LATHE)
    assert r.ok, r.diagnostics
    moves = [m for m in r.moves if m.kind in ("linear", "rapid")]
    assert moves[-1].end["C"] == 100 and moves[-1].end["Z"] == 50


def test_cax_errors():
    assert codes(fagorcnc.simulate("#CAX\nS1000\nM30\n", LATHE)) == ["KIN062"]     # L11601
    assert codes(fagorcnc.simulate("G1 C10 F100\nM30\n", LATHE)) == ["KIN061"]
    assert codes(fagorcnc.simulate("#CAX [S, B]\nM30\n", LATHE)) == ["KIN060"]
    assert codes(fagorcnc.simulate("#CAX\nM30\n")) == ["KIN060"]          # no c_axis on the default machine
    assert fagorcnc.simulate("#CAX [S, C]\nG1 C10 F100\n#CAX OFF\nM30\n", LATHE).ok
    with pytest.raises(MachineError, match="rotary"):
        load_machine({**LATHE, "c_axis": {"S": "X"}})
