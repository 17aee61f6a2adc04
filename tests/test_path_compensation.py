"""Tool radius compensation G41/G42, G136/G137, G138/G139 (seed 002 L9427-L10071; spec 04 §16-§26).

Tool T1 D1 has radius 3 (wear 0) unless said otherwise; expected points are worked by hand.
"""

from __future__ import annotations

import math

import pytest

import fagorcnc

TOOL = {"tools": {"1": {"1": {"radius": 3.0}, "2": {"radius": 2.5, "radius_wear": 0.5}}}}
S = math.sqrt(0.5) * 3   # 3 * cos 45 = 2.1213


def path(text: str, machine=TOOL):
    r = fagorcnc.simulate(text, machine)
    assert r.ok, [str(d) for d in r.diagnostics]
    out = []
    for m in r.moves:
        if m.kind in ("rapid", "linear", "arc") and math.dist((m.start["X"], m.start["Y"]),
                                                              (m.end["X"], m.end["Y"])) > 1e-9:
            out.append((m.kind, round(m.end["X"], 4), round(m.end["Y"], 4), getattr(m, "direction", None)))
    return out, r


def pt(x, y):
    return (round(x, 4), round(y, 4))


def test_g41_square_inside_corners_and_circular_activation():
    # spec 04 §26: CCW square with G41, every corner is inside: offsets Y=13, X=37, Y=37 meet at
    # (37,13) and (37,37).  The activation from (-10,-10) to (10,10) turns right (outside, 225 deg):
    # G139 + G136 go to A = (10,10) + 3 n1 = (7.8787, 12.1213) then round (10,10) to B = (10,13).
    moves, _ = path("G90 G17 G00 X-10 Y-10\nT1 D1 M6\nG01 G41 X10 Y10 F500\nX40\nY40\nX10\nG40 X-10 Y60\nM30\n")
    assert [m[1:3] for m in moves] == [pt(-10, -10), pt(10 - S, 10 + S), pt(10, 13), pt(37, 13), pt(37, 37),
                                       pt(10, 37), pt(10 - S, 40 - S), pt(-10, 60)]
    assert [m[3] for m in moves if m[0] == "arc"] == ["cw", "cw"]   # G41 joins turn clockwise


def test_g42_square_outside_corners_g136():
    # spec 04 §26: with G42 the corners are outside: G136 arc about (40,10) r 3 CCW from (40,7) to (43,10).
    # Activation is an inside corner: line through (10,10) + 3*(0.7071,-0.7071) along (1,1) meets y = 7 at
    # x = 12.1213 - 0.8787 = 11.2426
    moves, _ = path("G90 G17 G00 X-10 Y-10\nT1 D1 M6\nG136\nG01 G42 X10 Y10 F500\nX40\nY40\nX10\n"
                    "G40 X-10 Y60\nM30\n")
    assert [m[1:3] for m in moves] == [pt(-10, -10), pt(10 + 2 * S - 3, 7), pt(40, 7), pt(43, 10), pt(43, 40),
                                       pt(40, 43), pt(10 + 2 * S - 3, 43), pt(-10, 60)]
    assert [m[3] for m in moves if m[0] == "arc"] == ["ccw", "ccw"]


def test_g137_joins_outside_corners_with_lines():
    # spec 04 §26: with G137 the corner at (40,10) goes (40,7) -> (43,7) -> (43,10)
    moves, _ = path("G90 G17 G00 X0 Y0\nT1 D1 M6\nG137\nG01 G42 X0 Y10 F500\nX40\nY40\nM30\n")
    points = [m[1:3] for m in moves]
    assert (pt(40, 7) in points) and (pt(43, 7) in points) and (pt(43, 10) in points)
    assert all(m[0] != "arc" for m in moves[1:])


def test_g137_corner_sharper_than_90_degrees_uses_two_prolongations():
    # spec 04 §26: element 1 along +X ends at (0,0), element 2 towards (-10,10), G42, R 3:
    # A = (0,-3), A' = (3,-3), B' = (4.2426,0), B = (2.1213,2.1213)
    moves, _ = path("G90 G00 X-20 Y-3\nT1 D1 M6\nG137\nG01 G42 X-20 Y0 F500\nX0\nX-10 Y10\nM30\n")
    points = [m[1:3] for m in moves]
    i = points.index(pt(0, -3))
    assert points[i:i + 4] == [pt(0, -3), pt(3, -3), pt(2 * S, 0), pt(S, S)]


def test_g138_direct_activation_goes_straight_to_the_offset_point():
    # spec 04 §19.2: outside activation with G138: P0 -> B = (10,10) + 3 n2 = (10,13)
    moves, _ = path("G90 G17 G00 X-10 Y-10\nT1 D1 M6\nG138\nG01 G41 X10 Y10 F500\nX40\nM30\n")
    assert [m[1:3] for m in moves[:3]] == [pt(-10, -10), pt(10, 13), pt(40, 13)]


def test_radius_includes_the_wear_and_the_last_move_ends_on_its_perpendicular():
    # D2: radius 2.5 + wear 0.5 = 3; no G40 before the end: the last move ends at its perpendicular point
    moves, _ = path("G90 G00 X0 Y-10\nT1 D2 M6\nG01 G41 X0 Y0 F500\nX50\nM30\n")
    assert moves[-1][1:3] == pt(50, 3)


def test_inside_line_arc_corner_meets_on_the_offset_circle():
    # line along +X at y=0 to (20,0), then G03 about (20,20) r 20 (start tangent +X: tangent, no corner);
    # instead G03 X40 Y20 I0 J20 after a line heading +Y... use: line (0,0)->(20,0), then G03 from (20,0)
    # to (20,40) about (20,20): tangent at start is +X -> tangent join, offset radius 20 - 3 = 17 (G41, CCW)
    _, r = path("G90 G00 X0 Y-10\nT1 D1 M6\nG01 G41 X0 Y0 F500\nX20\nG03 X20 Y40 I0 J20\nG40 G01 X0 Y50\nM30\n")
    (arc,) = [m for m in r.moves if m.kind == "arc" and m.radius > 10]
    assert arc.radius == pytest.approx(17.0) and arc.center == pytest.approx({"X": 20.0, "Y": 20.0})
    assert (arc.start["X"], arc.start["Y"]) == pytest.approx((20.0, 3.0))


def test_plunge_between_compensated_moves_stays_at_the_joint():
    # spec 04 §21: a Z-only move between two plane moves runs at the joint point (37,13)
    _, r = path("G90 G00 X0 Y-10\nT1 D1 M6\nG01 G41 X0 Y10 F500\nX40\nZ-5\nY40\nM30\n")
    (plunge,) = [m for m in r.moves if m.kind == "linear" and m.end["Z"] == -5.0 and m.start["Z"] == 0.0]
    assert (plunge.end["X"], plunge.end["Y"]) == pytest.approx((37.0, 13.0))


def test_mirror_swaps_the_compensation_side():
    # seed 002 L8774: one mirrored plane axis turns G41 into G42 so that the part is the mirror image
    moves, _ = path("G11\nG90 G00 X0 Y-10\nT1 D1 M6\nG01 G41 X0 Y0 F500\nX40\nM30\n")
    # programmed X40 becomes X-40 moving -X; G41 with one mirror acts as G42: right of -X is +Y
    assert moves[-1][1:3] == pt(-40, 3)


@pytest.mark.parametrize(("text", "why"), [
    ("G00 X0 Y0\nT1 D1 M6\nG41 G02 X10 Y10 I10 J0 F100\nG01 X20\nM30\n", "activation with an arc"),
    ("G00 X0 Y0\nT1 D1 M6\nG41 G01 X10 F100\nX20\nG40 G02 X30 Y10 I0 J10\nM30\n", "cancellation with an arc"),
    ("G00 X0 Y0\nT1 D1 M6\nG41 G01 X10 F100\nG18 X20\nM30\n", "plane change while compensating"),
])
def test_compensation_errors(text, why):
    r = fagorcnc.simulate(text, TOOL)
    assert [d.code for d in r.errors] == ["INT086"], why


def test_activation_without_plane_motion_moves_to_the_first_offset_point():
    # spec 04 §19.3: "G41 Z-1" moves no plane axis: that block goes from (0,0) to (0,0) + 3 n2 of the next
    # move along +X: (0,3), together with Z
    _, r = path("G90 G00 X0 Y0 Z5\nT1 D1 M6\nG01 G41 Z-1 F100\nX30\nM30\n")
    plunge = next(m for m in r.moves if m.kind == "linear" and m.end["Z"] == -1.0)
    assert (plunge.start["X"], plunge.start["Y"], plunge.end["X"], plunge.end["Y"]) == pytest.approx((0, 0, 0, 3))


def test_side_change_on_a_collinear_continuation_inserts_a_segment():
    # spec 04 §26 / §22 case B: G41 along +X on y=+3, G42 on y=-3: segment (30,3) -> (30,-3)
    moves, _ = path("G90 G00 X0 Y-10\nT1 D1 M6\nG01 G41 X0 Y0 F100\nX30\nG42 X60\nG40 X70 Y-10\nM30\n")
    points = [m[1:3] for m in moves]
    i = points.index(pt(30, 3))
    assert points[i + 1] == pt(30, -3)


def test_side_change_where_the_offsets_meet_trims_both():
    # spec 04 §22 case A: G41 along +X (y = 3), then G42 along +Y from (30,0) (x = 33): they meet at (33,3)
    moves, _ = path("G90 G00 X0 Y-10\nT1 D1 M6\nG01 G41 X0 Y0 F100\nX30\nG42 Y30\nG40 X40 Y40\nM30\n")
    points = [m[1:3] for m in moves]
    assert pt(33, 3) in points and pt(30, 3) not in points


NECK = ("G00 X-20 Y5\nT1 D1 M6\nG41 G01 X-20 Y0 F500\nG01 X{w} Y0\nG01 X-4 Y-40\nG01 X4 Y-40\n"
        "G01 X{e} Y0\nG01 X20 Y0\nG40 G01 X20 Y5\nM30\n")


def test_a_gap_narrower_than_the_tool_two_blocks_apart_is_bridged():
    """A channel 8 mm wide at the bottom, 5.8 mm at its mouth, tool radius 3: the corner trims alone
    see nothing wrong (the bottom is wide enough), but the tool cannot pass the mouth.  The left wall's
    offset starts at its perpendicular point (-2.9, 0) + 3 n, n = (0.999622, -0.027488) the wall's left
    normal: (0.098866, -0.082464); the right wall runs at 2.9 + 1.1 * (-y / 40) = 2.902268 there, so the
    tool's edge would cross it by 3 - (2.902268 - 0.098866) * 0.999622 = 0.1977 mm.  The CNC does not execute
    such blocks (seed 002 L9455-L9459): the right wall (line 7) and the bottom (line 6) are gaps (INT122); the
    left wall re-joined with line 8 (offset y = 3) would run back up: a step (INT120).  Lines 4 and 8 share the
    offset y = 3: the tool passes over the channel, 3 above its mouth; line 8 ends at (20 - 3, 3) = (17, 3),
    where its offset meets the cancellation's x = 17."""
    r = fagorcnc.simulate(NECK.format(w=-2.9, e=2.9), TOOL)
    assert r.ok, [str(d) for d in r.diagnostics]
    assert sorted((d.code, d.line) for d in r.diagnostics if d.code.startswith("INT")) == [
        ("INT120", 5), ("INT122", 6), ("INT122", 7)]
    assert all("narrower than the tool diameter 6" in d.message for d in r.diagnostics if d.code == "INT122")
    lines = [(m.line, round(m.start["X"], 4), round(m.start["Y"], 4), round(m.end["X"], 4), round(m.end["Y"], 4))
             for m in r.moves if m.kind == "linear" and m.line in (4, 8)]
    assert lines == [(4, -17.0, 3.0, -2.9, 3.0), (8, -2.9, 3.0, 17.0, 3.0)]



def test_a_gap_wider_than_the_tool_is_compensated():
    moves, r = path(NECK.format(w=-3.1, e=3.1))
    assert not r.errors
    # down the left wall 3 mm inside it, then along the bottom 3 mm above it
    assert any(m[0] == "linear" and abs(m[2] - (-37.0)) < 0.2 for m in moves)


def test_a_null_incremental_move_under_g03_cancels_where_the_tool_stands():
    # seed 002 L9996-L10009, the manual's example: "G03 X-20 Y-20 I0 J-20 / G91 G40 Y0 / G01 X-20".  A
    # null move under modal G03 is no arc (no centre needed): the compensation ends at the tool's point.
    # G41 on the line to (0, 0) along -X: the tool 3 below it, (0, -3), on the arc about (0, -20) at
    # radius 17; it ends at (-17, -20), then goes to the programmed end (-20, -20), then 20 along -X.
    moves, _ = path("G90 G00 X10 Y0\nT1 D1 M6\nG01 G41 X0 Y0 F500\nG03 X-20 Y-20 I0 J-20\nG91 G40 Y0\n"
                    "G01 X-20\nM30\n")
    assert moves == [("rapid", 10.0, 0.0, None), ("linear", 0.0, -3.0, None), ("arc", -17.0, -20.0, "ccw"),
                     ("linear", -20.0, -20.0, None), ("linear", -40.0, -20.0, None)]
    # without compensation the null G03 block is a null move too, and a full circle still needs its centre
    assert fagorcnc.simulate("G90 G01 X0 Y0 F500\nG03 X-20 Y-20 I0 J-20\nG91 Y0\nG01 X-20\nM30\n").ok
    bad = fagorcnc.simulate("G90 G01 X0 Y0 F500\nG03 X-20 Y-20 I0 J-20\nG91 Y5\nM30\n")
    assert [d.code for d in bad.diagnostics if d.severity == "error"] == ["INT061"]


@pytest.mark.parametrize(("setup", "side", "radius", "feed"), [
    ("G196", "G41", 13.0, 780.0),                        # outside: the centre runs F (10 + 3) / 10
    ("G196", "G42", 7.0, 420.0),                         # inside: F (10 - 3) / 10
    ("G197", "G41", 13.0, 600.0),                        # F at the tool centre (the default)
    ("#TANGFEED RMIN [15]\nG196", "G41", 13.0, 600.0),   # only arcs of a radius above 15
    ("#TANGFEED RMIN [10]\nG196", "G41", 13.0, 600.0),   # "plus grand que le minimum": 10 is not
    ("#TANGFEED RMIN [5]\nG196", "G41", 13.0, 780.0),
    ("#TANGFEED RMIN [15]\nG196\n#TANGFEED RMIN [0]", "G41", 13.0, 780.0),   # 0: every arc
])
def test_g196_keeps_the_programmed_feed_at_the_contact_point_on_arcs(setup, side, radius, feed):
    # seed 002 L4298-L4325: under G196 F is the feed at the tool's contact point; the contact runs at
    # F R / (R + r) when the centre runs at F, so the centre runs at F (R + r) / R.  The half circle about
    # (10, 0) from (0, 0) to (20, 0), clockwise, R 10, tool radius 3.
    _, r = path(f"G90 G00 X0 Y-10\nT1 D1 M6\nS1000 M3\n{setup}\nG01 {side} X0 Y0 F600\nG02 X20 Y0 R10\nG01 X20 Y-10\n"
                "G40 G01 X30 Y-10\nM30\n")
    arc = next(m for m in r.moves if m.kind == "arc" and m.radius > 5)
    assert arc.radius == pytest.approx(radius) and arc.feed == pytest.approx(feed)
    assert not r.diagnostics   # computed, nothing to warn about
    # without compensation the tool centre is on the path: G196 changes nothing
    plain = fagorcnc.simulate("G90 G196 G01 X0 Y0 F600\nG02 X20 Y0 R10\nM30\n")
    assert [m.feed for m in plain.moves if m.kind == "arc"] == [600.0]
