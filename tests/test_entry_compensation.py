"""Two block rules of issue 26 item 8: the G37/G38 radius under radius compensation (seed 002 L8626-L8628,
L8672-L8674) and G41/G42 started by a block without plane motion before an arc (L9684-L9717).

Tool T1 D1 has radius 3; points are worked by hand in the comments.
"""

from __future__ import annotations

import pytest

import fagorcnc

TOOL = {"tools": {"1": {"1": {"radius": 3.0}}}}
ENTRY = ("T1 D1 M6\nG90 G00 X0 Y80\nG41 G01 X0 Y50 F800\nX40 Y50\nG37 I{r}\nG02 X70 Y20 I30 J0\n"
         "G40 G01 X100 Y20\nM30\n")


def _moves(r):
    return [m for m in r.moves if m.kind in ("rapid", "linear", "arc")]


@pytest.mark.parametrize("radius", [3, 2])
def test_g37_radius_not_above_the_tool_radius_is_an_error(radius):
    # L8627-L8628: "si on travaille avec compensation de rayon, il doit être plus grand que le rayon de l'outil"
    r = fagorcnc.simulate(ENTRY.format(r=radius), TOOL)
    assert [(d.line, d.code) for d in r.errors] == [(5, "INT085")]
    assert "greater than the tool radius 3" in r.errors[0].message


def test_g37_radius_equal_to_a_tool_radius_is_fine_without_compensation():
    # the same I3 with no compensation active (G40 throughout, tool radius 3): the rule does not apply
    prog = "T1 D1 M6\nG90 G00 X0 Y50\nG01 X40 Y50 F800\nG37 I3\nG02 X70 Y20 I30 J0\nM30\n"
    r = fagorcnc.simulate(prog, TOOL)
    assert r.ok, [str(d) for d in r.diagnostics]
    # approach (0,50)->(40,50) along +X, the arc starts along +Y: entry circle centre (40,50) + 3 (-1,0) = (37,50)
    entry = next(m for m in _moves(r) if m.kind == "arc" and m.line == 3)
    assert (entry.center["X"], entry.center["Y"], entry.radius) == pytest.approx((37.0, 50.0, 3.0))


def test_g37_entry_arc_is_compensated_like_any_arc():
    # I10: entry circle centre (40,50) + 10 (-1,0) = (30,50), turning CCW into the CW arc about (70,50).
    # G41 puts the tool inside the CCW entry arc: radius 10 - 3 = 7, ending at (40,50) + 3 (-1,0) = (37,50);
    # outside the CW arc: radius 30 + 3 = 33
    r = fagorcnc.simulate(ENTRY.format(r=10), TOOL)
    assert r.ok, [str(d) for d in r.diagnostics]
    entry, main = [m for m in _moves(r) if m.kind == "arc"]
    assert (entry.center["X"], entry.center["Y"], entry.radius) == pytest.approx((30.0, 50.0, 7.0))
    assert (entry.end["X"], entry.end["Y"]) == pytest.approx((37.0, 50.0))
    assert main.radius == pytest.approx(33.0) and main.start["X"] == pytest.approx(37.0)


def test_g38_radius_not_above_the_tool_radius_is_an_error():
    # L8673-L8674: the same rule for the tangential exit
    prog = ("T1 D1 M6\nG90 G00 X0 Y80\nG41 G01 X0 Y50 F800\nX40 Y50\nG02 X70 Y20 I30 J0\nG38 I3\n"
            "G01 X100 Y20\nG40 X120 Y0\nM30\n")
    r = fagorcnc.simulate(prog, TOOL)
    assert [(d.line, d.code) for d in r.errors] == [(6, "INT085")]


def test_g41_without_plane_motion_before_an_arc():
    # L9684-L9717: the first plane move after G41 may be an arc; the block without plane motion moves the
    # tool perpendicular to that arc at its start.  (The manual's example writes "G91 G40 Y0 Z10", L9713,
    # under "Début de la compensation": read as G41.)  At (0,40) the G02 about (20,40) starts along +Y; the
    # left of +Y is -X: the block goes (0,40,0) -> (-3,40,10) and the arc, outside on the left, has radius
    # 20 + 3 = 23 about (20,40)
    r = fagorcnc.simulate("T1 D1 M6\nG90 G01 X0 Y40 Z0 F500\nG91 G41 Y0 Z10\nG02 X20 Y20 I20 J0\n"
                          "G90 G40 G01 X50 Y80\nM30\n", TOOL)
    assert r.ok, [str(d) for d in r.diagnostics]
    up = next(m for m in _moves(r) if m.line == 3)
    assert (up.start["X"], up.start["Y"], up.end["X"], up.end["Y"], up.end["Z"]) == pytest.approx((0, 40, -3, 40, 10))
    arc = next(m for m in _moves(r) if m.kind == "arc" and m.line == 4)
    assert (arc.start["X"], arc.start["Y"]) == pytest.approx((-3.0, 40.0))
    assert (arc.center["X"], arc.center["Y"], arc.radius, arc.direction) == pytest.approx((20.0, 40.0, 23.0, "cw"))


def test_g41_on_a_block_that_programs_the_same_point():
    # L9718-L9728: "G01 G41 X-30 Y30 Z10" at X-30 Y30 moves no plane axis; the next move along +X puts the
    # tool at (-30,30) + 3 (0,1) = (-30,33) in that block, and X25 runs on y = 33
    r = fagorcnc.simulate("T1 D1 M6\nG90 G01 X-30 Y30 F500\nG01 G41 X-30 Y30 Z10\nG01 X25\nG40 X40 Y0\nM30\n",
                          TOOL)
    assert r.ok, [str(d) for d in r.diagnostics]
    up = next(m for m in _moves(r) if m.line == 3)
    assert (up.end["X"], up.end["Y"], up.end["Z"]) == pytest.approx((-30.0, 33.0, 10.0))
    along = next(m for m in _moves(r) if m.line == 4)
    assert (along.start["Y"], along.end["X"], along.end["Y"]) == pytest.approx((33.0, 25.0, 33.0))
