"""The no-gouge watch of radius compensation beyond its look-ahead (spec 04 §16.2; issue 21).

The stage checks each move against the moves around it; a neck between parts of the contour many
blocks apart, or a block dropped as a step whose wall the contour continues later, is seen by the
watch over the path already handed on (fagorcnc/path/clearance.py)."""

from __future__ import annotations

import fagorcnc
from fagorcnc.path.clearance import Clearance

R3 = {"tools": {"1": {"1": {"radius": 3.0, "length": 0.0}}}}


def _errors(r) -> list[tuple[int, str]]:
    return [(d.line, d.code) for d in r.diagnostics if d.is_error]


def test_a_neck_between_passes_many_blocks_apart_is_refused():
    # pass 1 runs +X along y=0 (lines 4-9, the tool on the left at y=3); pass 2 comes back -X along y=5
    # (lines 13-23, the tool on its left at y=2).  The passes are 5 mm apart, less than the tool's 6 mm:
    # the path of line 9 (y=3) is 2 mm from line 18's profile (y=5): 3 - 2 = 1 mm into it.  Nine blocks
    # lie between them, beyond the look-ahead: this ran, gouging 1 mm, before the watch.
    prog = ("G90 G17 G0 X0 Y-10\nT1 D1 M6 S1000 M3\nG1 G41 X0 Y0 F500\n" + "".join(f"X{x}\n" for x in range(10, 70, 10))
            + "Y-40\nX120\nY5\n" + "".join(f"X{x}\n" for x in range(110, -10, -10)) + "G40 X0 Y30\nM30\n")
    r = fagorcnc.simulate(prog, R3)
    assert _errors(r) == [(18, "INT086")]
    message = next(d.message for d in r.diagnostics if d.is_error)
    assert "line 9" in message and "1.0000 mm" in message
    assert not [m for m in r.moves if m.line >= 18 and m.kind == "linear"]   # nothing from the refused block on


def test_the_same_passes_far_enough_apart_run():
    # 6 mm apart: the offsets meet exactly (y=3 both ways), no gouge
    prog = ("G90 G17 G0 X0 Y-10\nT1 D1 M6 S1000 M3\nG1 G41 X0 Y0 F500\n" + "".join(f"X{x}\n" for x in range(10, 70, 10))
            + "Y-40\nX120\nY6\n" + "".join(f"X{x}\n" for x in range(110, -10, -10)) + "G40 X0 Y30\nM30\n")
    assert fagorcnc.simulate(prog, R3).ok


def test_a_step_right_after_the_activation_is_refused_not_dropped_into_a_gouge():
    # found by the no-gouge property: the spike of line 5 right after the activation was dropped as a step
    # (INT120) and the path of line 6 then came 2.17 mm into line 14, which continues line 5's wall.  The
    # first move of the contour is where the activation leads: it is never dropped.
    prog = ("G90 G17 G00 X68.402457799 Y-7.543015931\nT1 D1 M6 S1000 M3\nG136 G138\n"
            "G01 G41 X63.868520443 Y11.936291347 F500\nG01 X98.003707553 Y19.881481481\n"
            "G01 X28.938074074 Y7.911249515\nG01 X28.346278997 Y9.822854321\nG01 X27.628360165 Y11.690753381\n"
            "G01 X8.63498956 Y28.730418641\nG01 X-24.073322234 Y-17.901819924\nG01 X30 Y0\n"
            "G01 X29.933259094 Y2\nG01 X29.733333333 Y3.991101213\nG01 X63.868520443 Y11.936291347\n"
            "G40 G01 X68.402457799 Y-7.543015931\nM30\n")
    r = fagorcnc.simulate(prog, R3)
    assert _errors(r) == [(5, "INT086")]


def test_the_watch_window_is_bounded():
    # a path piece and a profile element 1 mm apart with R = 3 are found; after WINDOW newer entries the
    # oldest is forgotten (memory does not grow with the program)
    from fagorcnc.path import clearance

    watch = Clearance(3.0)
    assert watch.profile(("line", (0.0, 0.0), (10.0, 0.0), None, True), "p1") is None
    hit = watch.path(("line", (0.0, 1.0), (10.0, 1.0), None, True), "q1")
    assert hit is not None and abs(hit[0] - 2.0) < 1e-12 and hit[1] == "p1"
    far = Clearance(3.0)
    far.profile(("line", (0.0, 0.0), (10.0, 0.0), None, True), "p1")
    for k in range(clearance.WINDOW):
        far.profile(("line", (1000.0 + 10 * k, 0.0), (1005.0 + 10 * k, 0.0), None, True), "x")
    assert far.path(("line", (0.0, 1.0), (10.0, 1.0), None, True), "q1") is None
    assert len(far._order) == clearance.WINDOW
