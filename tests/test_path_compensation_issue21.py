"""Issue 21: radius compensation that never gouges (spec 04 §16-§20; seed 002 L9427-L10071).

Join, activation and cancellation types read at each block; cusps classified by whether the offsets cross;
G264 arcs on one offset circle; blocks the tool cannot machine dropped with a warning (L9455-L9459); a tool
offset missing from the tool table is an error.  Expected points are worked by hand in the comments.
"""

from __future__ import annotations

import itertools
import math

import pytest

import fagorcnc

INCH = 25.4


def tools(radius: float) -> dict:
    return {"tools": {"1": {"1": {"radius": radius}}}}


def moves(text: str, machine: dict, a: str = "X", o: str = "Y", unit: float = 1.0):
    r = fagorcnc.simulate(text, machine)
    out = [m for m in r.moves if m.kind in ("rapid", "linear", "arc")
           and math.dist((m.start[a], m.start[o]), (m.end[a], m.end[o])) > 1e-9]
    return r, out


def end(m, a="X", o="Y", unit=1.0):
    return (m.end[a] / unit, m.end[o] / unit)


def close(p, q, tol=1e-5):
    return math.dist(p, q) <= tol


def continuous(path, a="X", o="Y"):
    return all(math.dist((p.end[a], p.end[o]), (q.start[a], q.start[o])) < 1e-6 for p, q in itertools.pairwise(path))


# ------------------------------------------------------------------ 1. modal join / start types

ARC_EXIT = """G90 G17 G00 X-91.603217 Y-110
T1 D1 M6
G01 G41 X-91.603217 Y-98.436193 F500
G3 I-1.365837 J-2.212349 X-90.369054 Y-100.648542
{mode}
G40
G1 X-80.369054 Y-95.648542
M30
"""


def test_g138_programmed_before_g40_cancels_directly():
    # arc: centre = start + (I, J) = (-92.969054, -100.648542), radius sqrt(1.365837^2 + 2.212349^2) = 2.6; it
    # ends at angle 0 heading +Y; the exit heads (10, 5)/|.|: a right turn under G41, an outside corner.
    # G41, R 0.25: A = end + 0.25 (-1, 0) = (-90.619054, -100.648542).  G138: A -> target directly (L9605).
    r, path = moves(ARC_EXIT.format(mode="G138"), tools(0.25))
    assert r.ok, [str(d) for d in r.diagnostics]
    arc, leave = path[-2], path[-1]
    assert arc.kind == "arc" and arc.line == 4 and close(end(arc), (-90.619054, -100.648542))
    assert leave.kind == "linear" and leave.line == 7 and close((leave.start["X"], leave.start["Y"]), end(arc))
    # G139 (the default) goes round the end point: arc about it to B = end + 0.25 (-1, 2)/sqrt(5)
    # = (-90.369054 - 0.111803, -100.648542 + 0.223607) = (-90.480857, -100.424935), then to the target
    r, path = moves(ARC_EXIT.format(mode="G139"), tools(0.25))
    join = path[-2]
    assert join.kind == "arc" and join.direction == "cw" and close(end(join), (-90.480857, -100.424935))
    assert close((join.center["X"], join.center["Y"]), (-90.369054, -100.648542))


def test_g137_programmed_mid_contour_makes_linear_joins():
    # spec 04 §26 square under G42 (outside corners), R 3: G136 at the start, G137 before Y40, G136 before X10.
    # corner (40,10) under G137: (40,7) -> (43,7) -> (43,10); corner (40,40) under G136: arc about (40,40)
    # from (43,40) to (40,43)
    text = ("G90 G17 G00 X-10 Y-10\nT1 D1 M6\nG136\nG01 G42 X10 Y10 F500\nX40\nG137\nY40\nG136\nX10\n"
            "G40 X-10 Y60\nM30\n")
    r, path = moves(text, tools(3.0))
    assert r.ok, [str(d) for d in r.diagnostics]
    pts = [tuple(round(v, 6) for v in end(m)) for m in path]
    i = pts.index((40.0, 7.0))
    assert pts[i:i + 4] == [(40.0, 7.0), (43.0, 7.0), (43.0, 10.0), (43.0, 40.0)]
    assert path[i + 1].kind == path[i + 2].kind == "linear"
    assert path[i + 4].kind == "arc" and close(end(path[i + 4]), (40.0, 43.0))
    assert close((path[i + 4].center["X"], path[i + 4].center["Y"]), (40.0, 40.0))


# ------------------------------------------------------------------ 2. cusps (tangent reversals)

def cusp(plane: str, side: str, line_end: float) -> str:
    """The issue's inch example: G03 ending at (1.8296, 2.8450) heading -Y, then a line heading +Y (or a
    hair off it: ``line_end`` is the abscissa of its end).  G18 writes the same contour as Z, X."""
    if plane == "G17":
        return (f"G70 G90 G17 G00 X2.2708 Y2.0\nT1 D1 M6\nG01 {side} X2.2708 Y2.845 F20\n"
                f"G03 X1.8296 Y2.8450 I-0.2206 J0\nG01 X{line_end} Y3.5600\nG40 G01 X1.0 Y3.56\nM30\n")
    return (f"G70 G90 G18 G00 Z2.2708 X2.0\nT1 D1 M6\nG01 {side} Z2.2708 X2.845 F20\n"
            f"G03 Z1.8296 X2.8450 K-0.2206 I0\nG01 Z{line_end} X3.5600\nG40 G01 Z1.0 X3.56\nM30\n")


def contour_distance(x, line_end):
    """Least distance (inch) from x to the programmed arc (centre (2.0502, 2.845), radius 0.2206, upper half
    from angle 0 to 180) and the line from (1.8296, 2.845) to (line_end, 3.56)."""
    c, rho = (2.0502, 2.845), 0.2206
    ang = math.atan2(x[1] - c[1], x[0] - c[0])
    d_arc = abs(math.dist(x, c) - rho) if 0 <= ang <= math.pi else min(math.dist(x, (2.2708, 2.845)),
                                                                        math.dist(x, (1.8296, 2.845)))
    p, q = (1.8296, 2.845), (line_end, 3.56)
    d = (q[0] - p[0], q[1] - p[1])
    k = max(0.0, min(1.0, ((x[0] - p[0]) * d[0] + (x[1] - p[1]) * d[1]) / (d[0] ** 2 + d[1] ** 2)))
    return min(d_arc, math.dist(x, (p[0] + k * d[0], p[1] + k * d[1])))


def samples(m, a, o):
    p, q = (m.start[a], m.start[o]), (m.end[a], m.end[o])
    if m.kind != "arc":
        return [(p[0] + (q[0] - p[0]) * k / 50, p[1] + (q[1] - p[1]) * k / 50) for k in range(51)]
    c = (m.center[a], m.center[o])
    a0, sw = math.atan2(p[1] - c[1], p[0] - c[0]), math.radians(m.sweep)
    return [(c[0] + m.radius * math.cos(a0 + sw * k / 50), c[1] + m.radius * math.sin(a0 + sw * k / 50))
            for k in range(51)]


@pytest.mark.parametrize("plane", ["G17", "G18"])
@pytest.mark.parametrize("line_end", [1.8296, 1.8297])
def test_cusp_with_the_tool_outside_the_arc_is_trimmed_where_the_offsets_cross(plane, line_end):
    # G42, R 0.075 in: the arc's offset circle has radius 0.2206 + 0.075 = 0.2956 about (2.0502, 2.845), the
    # line's offset is x = 1.8296 + 0.075 = 1.9046 (exact reversal).  They cross at dx = 1.9046 - 2.0502 =
    # -0.1456, dy = sqrt(0.2956^2 - 0.1456^2) = sqrt(0.06618) = 0.257254: (1.9046, 3.102254).  Going round the
    # corner instead (the old outside join) started the line inside the arc's circle: a gouge up to R.
    # line_end 1.8297 turns the line a hair away from the tool (tangents say "outside"): same crossing, within
    # 1e-4 (the line's offset moves by less than 0.0001 * 0.257 / 0.715).
    a, o = ("X", "Y") if plane == "G17" else ("Z", "X")
    r, path = moves(cusp(plane, "G42", line_end), tools(0.075 * INCH), a, o)
    assert r.ok, [str(d) for d in r.diagnostics]
    arc = next(m for m in path if m.line == 4)
    line = next(m for m in path if m.line == 5)
    assert arc.kind == "arc" and close(end(arc, a, o, INCH), (1.9046, 3.102254), 1e-4)
    assert close((line.start[a] / INCH, line.start[o] / INCH), end(arc, a, o, INCH), 1e-9)
    assert continuous(path, a, o)
    worst = min(contour_distance((x[0] / INCH, x[1] / INCH), line_end)
                for m in path if m.line in (4, 5) for x in samples(m, a, o))
    assert worst >= 0.075 - 1e-6


@pytest.mark.parametrize("plane", ["G17", "G18"])
@pytest.mark.parametrize("line_end", [1.8296, 1.8297])
def test_cusp_with_the_tool_inside_the_arc_goes_round_the_corner(plane, line_end):
    # G41, R 0.075 in: offset circle radius 0.2206 - 0.075 = 0.1456 about (2.0502, 2.845); the line's offset
    # x = 1.8296 - 0.075 = 1.7546 is 0.2956 from the centre: no crossing.  So the tool goes round the corner:
    # arc of radius R about (1.8296, 2.845), clockwise under G41, from A = (1.9046, 2.845) to B = (1.7546,
    # 2.845) passing below it.  line_end 1.8297 turns the line a hair toward the tool: tangents say "inside",
    # which used to stop with INT086 "do not meet".
    a, o = ("X", "Y") if plane == "G17" else ("Z", "X")
    r, path = moves(cusp(plane, "G41", line_end), tools(0.075 * INCH), a, o)
    assert r.ok, [str(d) for d in r.diagnostics]
    join = [m for m in path if m.line == 4 and m.kind == "arc"][1]
    assert join.direction == "cw" and abs(join.radius - 0.075 * INCH) < 1e-6
    assert close((join.center[a] / INCH, join.center[o] / INCH), (1.8296, 2.845))
    assert close((join.start[a] / INCH, join.start[o] / INCH), (1.9046, 2.845))
    # B = P + R L(t2); with line_end 1.8297, t2 = (0.0001, 0.715)/|.| and L(t2) = (-1, 0.00014): B.y = 2.845 +
    # 0.075 * 0.00014 = 2.845010
    assert close(end(join, a, o, INCH), (1.7546, 2.845 if line_end == 1.8296 else 2.845010), 2e-6)
    assert abs(abs(join.sweep) - 180.0) < 0.02
    assert continuous(path, a, o)
    worst = min(contour_distance((x[0] / INCH, x[1] / INCH), line_end)
                for m in path if m.line in (4, 5) for x in samples(m, a, o))
    assert worst >= 0.075 - 1e-6


# ------------------------------------------------------------------ 3. G264 arcs

G264_ARCS = """G70 G90 G17 G00 X0.336 Y-0.5583
T1 D1 M6
{mode}
G01 G41 X0.336 Y0.4417 F20
G03 X1.2281 Y1.3456 I0.2921 J0.6039
G02 X0.1253 Y0.9881 I-0.6093
G40 G01 X0 Y0
M30
"""


@pytest.mark.parametrize("mode", ["G264", "G265"])
@pytest.mark.parametrize("radius", [0.0, 0.01])
def test_g264_arc_keeps_one_offset_circle(mode, radius):
    # start (0.336, 0.4417), centre (0.6281, 1.0456): start radius sqrt(0.2921^2 + 0.6039^2) = 0.670834, end
    # radius |(0.6, 0.3)| = 0.670820 (within CIRINERR).  G264 runs the arc on its start radius (L6996): its
    # offset is the circle of radius 0.670834 - R, and the offset arc starts and ends on it.  It used to stop
    # with INT086 even with R = 0.  With R = 0 the arc ends on that circle at the angle of the programmed end:
    # centre + 0.670834 (0.894427, 0.447214) = (1.228113, 1.345606), within 1e-4 of the programmed end.
    r, path = moves(G264_ARCS.format(mode=mode), tools(radius * INCH))
    assert r.ok, [str(d) for d in r.diagnostics]
    first = next(m for m in path if m.line == 5)
    c = (first.center["X"], first.center["Y"])
    rs, re = math.dist((first.start["X"], first.start["Y"]), c), math.dist((first.end["X"], first.end["Y"]), c)
    assert abs(rs - re) < 1e-9 and abs(first.radius - re) < 1e-9
    if mode == "G264":
        assert abs(rs / INCH - (0.670834 - radius)) < 2e-6
        if radius == 0.0:
            assert close(end(first, unit=INCH), (1.228113, 1.345606), 1e-4)
    assert continuous(path)


# ------------------------------------------------------------------ 4. blocks the tool cannot machine

def codes(r):
    """The interpreter's diagnostics (the CAM lint may add notes of its own)."""
    return [(d.code, d.line, d.severity) for d in r.diagnostics if d.code.startswith("INT")]


def test_step_is_dropped_with_a_warning_and_the_neighbours_rejoined():
    # R 3, G41: line 5 (X50 -> X40 Y2) turns back 169 degrees: the inside corners at both its ends trim it
    # past its start (a step).  Dropped (INT120, L9455), lines 4 and 6 are re-joined where their offsets meet:
    # y = 3 and x = 40 - 3 = 37 -> (37, 3).  The dropped move stays >= 3 from the path: (37,3) to its end (40,2)
    # is sqrt(9 + 1) = 3.16.
    text = "G90 G17 G00 X0 Y-10\nT1 D1 M6\nG01 G41 X0 Y0 F500\nX50\nX40 Y2\nX40 Y30\nG40 X60 Y30\nM30\n"
    r, path = moves(text, tools(3.0))
    assert r.ok and codes(r) == [("INT120", 5, "warning")], [str(d) for d in r.diagnostics]
    assert all(m.line != 5 for m in path)
    four, six = [m for m in path if m.line == 4][-1], next(m for m in path if m.line == 6)
    assert close(end(four), (37.0, 3.0)) and close((six.start["X"], six.start["Y"]), (37.0, 3.0))
    assert continuous(path)


def test_concave_arc_smaller_than_the_tool_is_dropped():
    # pocket corner rounded with radius 2, tool R 3 inside (G41 on a CCW contour): the fillet's offset radius
    # 2 - 3 < 0 cannot be followed (INT121).  Lines X58 (offset y = 3) and X60 (offset x = 57) meet at (57,3),
    # which keeps sqrt(1 + 9) = 3.16 from the fillet's ends (58,0) and (60,2) (outside its quarter).
    text = ("G90 G17 G00 X20 Y-10\nT1 D1 M6\nG01 G41 X20 Y0 F500\nX58\nG03 X60 Y2 I0 J2\nG01 X60 Y40\n"
            "G40 X80 Y40\nM30\n")
    r, path = moves(text, tools(3.0))
    assert r.ok and codes(r) == [("INT121", 5, "warning")], [str(d) for d in r.diagnostics]
    four = [m for m in path if m.line == 4][-1]
    assert close(end(four), (57.0, 3.0)) and all(m.line != 5 for m in path)
    assert continuous(path)


def test_slot_narrower_than_the_tool_is_bridged():
    # a slot 2 wide and 10 deep under a line milled from above (G41), R 3.  Bottom (line 6): trimmed from
    # (13,-7) back to (9,-7), a step (INT120).  Walls x = 13 (down) and x = 9 (up) never meet: the up wall
    # (line 7) is a gap narrower than the tool (INT122).  The down wall (line 5) re-joined with the line after
    # the slot (y = 3) at (13,3) runs backwards from (13,0): a step (INT120).  Lines 4 and 8 share the offset
    # y = 3: the tool runs straight over the slot, 3 above its edges.
    text = ("G90 G17 G00 X-10 Y-10\nT1 D1 M6\nG01 G41 X-10 Y0 F500\nX10\nY-10\nX12\nY0\nX30\n"
            "G40 X40 Y-10\nM30\n")
    r, path = moves(text, tools(3.0))
    assert r.ok, [str(d) for d in r.diagnostics]
    assert sorted(codes(r)) == [("INT120", 5, "warning"), ("INT120", 6, "warning"), ("INT122", 7, "warning")]
    assert [m.line for m in path if m.line in (5, 6, 7)] == []
    four, eight = [m for m in path if m.line == 4], next(m for m in path if m.line == 8)
    assert close(end(four[-1]), (10.0, 3.0)) and close((eight.start["X"], eight.start["Y"]), (10.0, 3.0))
    assert all(abs(m.end["Y"] - 3.0) < 1e-9 for m in four) and close(end(eight), (30.0, 3.0), 3.0 + 1e-6)
    assert continuous(path)


def test_a_dropped_block_that_moves_z_is_an_error():
    # the step of the first test, with a Z move in it: dropping it would lose the Z move
    text = "G90 G17 G00 X0 Y-10\nT1 D1 M6\nG01 G41 X0 Y0 F500\nX50\nX40 Y2 Z-1\nX40 Y30\nG40 X60 Y30\nM30\n"
    r, _path = moves(text, tools(3.0))
    assert [(d.code, d.line) for d in r.errors] == [("INT086", 5)], [str(d) for d in r.diagnostics]


# ------------------------------------------------------------------ 5. missing tool offsets

SQUARE = "G90 G17 G00 X0 Y-10\n{tool}\nG01 G42 X0 Y0 F500\nX10\nG40 X20 Y-10\nM30\n"


def test_offset_not_in_the_tool_table_is_an_error_naming_tool_and_offset():
    r = fagorcnc.simulate(SQUARE.format(tool="T10 D1 M6"), tools(3.0))
    errors = [d for d in r.diagnostics if d.is_error]
    assert [(d.code, d.line) for d in errors] == [("INT123", 3)]
    assert "T10" in errors[0].message and "D1" in errors[0].message
    assert not [m for m in r.moves if m.kind == "linear"]    # nothing moved with a made-up radius


def test_length_compensation_with_an_offset_not_in_the_table_is_an_error():
    r = fagorcnc.simulate("G90 G00 X0 Y0\nT10 D1 M6\nG01 Z-5 F100\nM30\n", tools(3.0))
    assert [(d.code, d.line) for d in r.errors] == [("INT123", 3)]


def test_declared_offsets_and_the_default_machine_still_run():
    assert fagorcnc.simulate(SQUARE.format(tool="T1 D1 M6"), tools(3.0)).ok
    assert fagorcnc.simulate(SQUARE.format(tool="T10 D1 M6")).ok       # default machine: T0-T99, radius 0
    assert fagorcnc.simulate("G90 G00 X0 Y0\nT10 D0 M6\nG01 Z-5 F100\nM30\n", tools(3.0)).ok   # D0: none
