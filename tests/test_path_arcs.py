"""Every arc form with hand-computed centres, radii and end points (seed 002 ch. 8.3-8.6, spec 03 §B)."""

from __future__ import annotations

import math

import pytest

import fagorcnc

A = pytest.approx


def arcs(text: str, machine=None):
    r = fagorcnc.simulate(text, machine)
    assert r.ok, [str(d) for d in r.diagnostics]
    return [m for m in r.moves if m.kind == "arc"], r


def test_full_circle_by_centre_when_end_equals_start():
    # seed 002 L6389-L6392: G03 X30 Y30 I20 J20 from (30,30): centre (50,50), r = sqrt(800) = 28.2843
    (c,), _ = arcs("G01 X30 Y30 F100\nG03 X30 Y30 I20 J20\nM30\n")
    assert c.center == A({"X": 50.0, "Y": 50.0}) and c.radius == A(math.sqrt(800))
    assert c.sweep == A(360.0) and c.length == A(2 * math.pi * math.sqrt(800))


def test_radius_form_sign_picks_the_minor_or_major_arc():
    # spec 03 §B.5: chord (0,0)-(40,0), L=40, h=sqrt(625-400)=15
    # G02 R25 (CW minor): centre (20,-15), sweep -(180 - 2*atan(20/15))... = -106.26 deg
    # G03 R-25 back (CCW major): centre (20,15), sweep +253.74 deg
    (a, b), _ = arcs("G90 G17 G01 X0 Y0 F500\nG02 X40 Y0 R25\nG03 X0 R-25\nM30\n")
    assert a.center == A({"X": 20.0, "Y": -15.0}) and a.direction == "cw"
    assert a.sweep == A(-(2 * math.degrees(math.atan2(20, 15))))
    assert b.center == A({"X": 20.0, "Y": 15.0}) and b.sweep == A(360 - 2 * math.degrees(math.atan2(20, 15)))


def test_stored_arc_radius_r1_and_g263():
    # seed 002 L6440-L6456, L6549-L6566: "G02 R1=25" / "G02 G263=25" store the radius; the next arc uses it
    for store in ("G02 R1=25", "G02 G263=25"):
        (a,), _ = arcs(f"G01 X0 Y0 F500\n{store}\nX40 Y0\nM30\n")
        assert a.center == A({"X": 20.0, "Y": -15.0}), store


def test_radius_form_full_circle_or_too_small_radius_is_an_error():
    for text in ("G02 X0 Y0 R10 F100", "G02 X40 Y0 R10 F100"):
        r = fagorcnc.simulate(text + "\nM30\n")
        assert [d.code for d in r.errors] == ["INT064"], text


def test_polar_arc_with_centre_offset():
    # spec 03 §B.6 (L6656-L6665): G30 at (20,30); G02 R60 Q0 I30 -> E (80,30), C (50,30), r 30, -180 deg
    (a,), _ = arcs("N10 G0 G90 X20 Y30 F350\nN20 G30\nN30 G02 R60 Q0 I30\nM30\n")
    assert a.end == A({"X": 80.0, "Y": 30.0, "Z": 0.0}) and a.center == A({"X": 50.0, "Y": 30.0})
    assert a.radius == A(30.0) and a.sweep == A(-180.0)


def test_polar_arcs_about_the_polar_origin_and_with_offsets():
    # spec 03 §B.6: G30 I45 J0; G01 R20 Q110 -> (45 + 20 cos110, 20 sin110) = (38.1596, 18.7939)
    # G02 Q70: centre = polar origin, r 20, -40 deg -> (51.8404, 18.7939)
    # G03 Q110 I-6.8404 J18.7938: centre (45, 37.5877), +320 deg -> (38.1596, 18.7939)
    text = "N10 G0 G90 X0 Y0 F350\nN20 G30 I45 J0\nN30 G01 R20 Q110\nN40 G02 Q70\nN50 G03 Q110 I-6.8404 J18.7938\nM30\n"
    (b, c), _ = arcs(text)
    x110, y110 = 45 + 20 * math.cos(math.radians(110)), 20 * math.sin(math.radians(110))
    assert b.center == A({"X": 45.0, "Y": 0.0}) and b.sweep == A(-40.0)
    assert b.end["X"] == A(45 + 20 * math.cos(math.radians(70))) and b.end["Y"] == A(y110)
    assert c.center == A({"X": 45.0, "Y": 37.5877}, abs=2e-4) and c.sweep == A(320.0, abs=1e-3)
    assert c.end == A({"X": x110, "Y": y110, "Z": 0.0})


def test_g31_polar_origin_at_the_arc_centre_for_one_block():
    # spec 03 §B.7: from (50,20) G02 G31 R20 Q0 J-20: C (50,0), E (70,0), -90 deg; then the polar origin is back
    (a,), r = arcs("G90 G17 G01 X50 Y20 F500\nG02 G31 R20 Q0 J-20\nG01 R10 Q90\nM30\n")
    assert a.center == A({"X": 50.0, "Y": 0.0}) and a.end == A({"X": 70.0, "Y": 0.0, "Z": 0.0})
    assert a.sweep == A(-90.0)
    assert r.state.position() == A({"X": 0.0, "Y": 10.0, "Z": 0.0}, abs=1e-12)


def test_g264_runs_about_the_programmed_centre_within_tolerance():
    # spec 03 §B.9: CIRINERR 0.01, CIRINFACT 0.5 %; C (10.01,0): rs 10.01, re 9.99, delta 0.02 (0.2 %) -> ok
    m = {"cirinerr": 0.01, "cirinfact": 0.5}
    (a,), _ = arcs("G90 G17 G01 X0 Y0 F500\nG264\nG02 X20 Y0 I10.01 J0\nM30\n", m)
    assert a.center == A({"X": 10.01, "Y": 0.0})


def test_g265_corrects_the_centre_onto_the_bisector():
    # same arc with G265 (default): centre projected onto x = 10 -> (10, 0), exact semicircle r 10
    (a,), _ = arcs("G90 G17 G01 X0 Y0 F500\nG02 X20 Y0 I10.01 J0\nM30\n", {"cirinerr": 0.01, "cirinfact": 0.5})
    assert a.center == A({"X": 10.0, "Y": 0.0}) and a.radius == A(10.0) and a.sweep == A(-180.0)


def test_radius_mismatch_beyond_both_tolerances_is_an_error():
    r = fagorcnc.simulate("G01 X0 Y0 F500\nG02 X20 Y0 I10.01 J0\nM30\n", {"cirinerr": 0.01, "cirinfact": 0.1})
    assert [(d.code, d.line) for d in r.errors] == [("INT062", 2)]


def test_g08_tangent_arcs():
    # seed 002 L7033-L7037: from (0,40): G01 X70; G08 X90 Y60 -> C (70,60) r 20 CCW 90;
    # G08 X110 -> C (100,60) r 10 CW 180
    (a, b), r = arcs("G90 G00 X0 Y40\nG01 X70 F100\nG08 X90 Y60\nG08 X110\nP1 = V.G.GS[1]\nM30\n")
    assert a.center == A({"X": 70.0, "Y": 60.0}) and a.radius == A(20.0) and a.sweep == A(90.0)
    assert b.center == A({"X": 100.0, "Y": 60.0}) and b.radius == A(10.0) and b.sweep == A(-180.0)
    assert r.state.param(1) == 1.0   # G08 is non-modal: G01 is still the active motion


def test_g08_without_a_previous_move_or_on_the_tangent_is_an_error():
    assert [d.code for d in fagorcnc.simulate("G08 X10 Y10\nM30\n").errors] == ["INT068"]
    assert [d.code for d in fagorcnc.simulate("G01 X10 F100\nG08 X20\nM30\n").errors] == ["INT064"]


def test_g09_arc_through_three_points():
    # seed 002 L7199-L7201: from (-50,0) G09 X35 Y20 I-15 J25 -> C (3.9035,-38.4649), r 66.2204, CW, -82.497 deg
    (a,), _ = arcs("G90 G00 X-50 Y0\nG09 X35 Y20 I-15 J25 F100\nM30\n")
    assert a.center == A({"X": 3.9035, "Y": -38.4649}, abs=1e-4) and a.radius == A(66.2204, abs=1e-4)
    assert a.direction == "cw" and a.sweep == A(-82.497, abs=1e-3)


def test_g09_collinear_points_are_an_error():
    r = fagorcnc.simulate("G00 X0 Y0\nG09 X20 Y0 I10 J0 F100\nM30\n")
    assert [d.code for d in r.errors] == ["INT064"]


@pytest.mark.parametrize("block", [
    "G03 X40 Y20 I20 J0 Z50",
    "G03 X40 Y20 R-20 Z50",
    "G03 R44.72136 Q26.56505 I20 J0 Z50",
    "G09 X40 Y20 I60 J0 Z50",
])
def test_helix_forms_are_equivalent(block):
    # seed 002 L7238-L7250: from (20,0,0) to (40,20,50): C (40,0), r 20, CCW 270 deg
    (a,), _ = arcs(f"G00 X20 Y0 Z0\nG01 F100\n{block}\nM30\n")
    assert a.center == A({"X": 40.0, "Y": 0.0}, abs=1e-4) and a.radius == A(20.0, abs=1e-4)
    assert a.sweep == A(270.0, abs=1e-3) and a.end["Z"] == A(50.0)
    assert a.length == A(math.hypot(1.5 * math.pi * 20, 50), abs=1e-3)


def test_multi_turn_helix_by_pitch():
    # spec 03 §B.12: G03 I15 J0 Z50 K5 from (0,0,0): 50/5 = 10 turns about (15,0), ends where it started in XY
    (a,), _ = arcs("G01 X0 Y0 Z0 F100\nG03 I15 J0 Z50 K5\nM30\n")
    assert a.sweep == A(3600.0) and a.turns == 9
    assert a.end == A({"X": 0.0, "Y": 0.0, "Z": 50.0}, abs=1e-9)


def test_arcs_in_g18_and_g19_use_the_planes_centre_letters():
    # G18: abscissa Z, ordinate X, centre words K (Z) and I (X). From (X0,Z10): G02 X10 Z0 K-10 I0
    # -> centre (Z0, X0); sweep in (Z, X): from angle 0 to 90 deg -> CW means -270
    (a,), _ = arcs("G18 G00 X0 Z10\nG02 X10 Z0 K-10 I0 F100\nM30\n")
    assert a.center == A({"Z": 0.0, "X": 0.0}) and a.plane[:2] == ("Z", "X") and a.sweep == A(-270.0)
    # G19: abscissa Y, ordinate Z, centre words J and K
    (b,), _ = arcs("G19 G00 Y10 Z0\nG03 Y0 Z10 J-10 K0 F100\nM30\n")
    assert b.center == A({"Y": 0.0, "Z": 0.0}) and b.sweep == A(90.0)


def test_g06_absolute_centre_for_one_block_and_g261():
    # spec 03 §B.8 (H03-17): start (50,50), end (50,10), centre (20,30)
    (a,), _ = arcs("G00 X50 Y50\nG02 G06 X50 Y10 I20 J30 F100\nM30\n")
    (b,), _ = arcs("G00 X50 Y50\nG261\nG02 X50 Y10 I20 J30 F100\nM30\n")
    (c,), _ = arcs("G00 X50 Y50\nG02 X50 Y10 I-30 J-20 F100\nM30\n")
    assert a.center == b.center == c.center == A({"X": 20.0, "Y": 30.0})
