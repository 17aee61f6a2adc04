"""Curves: #POLY (seed 002 L15822-L15870) and #SPLINE / #ASPLINE Akima splines (L15688-L15821)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import fagorcnc
from fagorcnc.cli import main
from fagorcnc.interp.records import CurveLine
from fagorcnc.path.spline import (
    CHORD_TOLERANCE,
    akima_slopes,
    cubic_points,
    hermite_coefficients,
    poly_points,
    sample_cubic,
)

#: A machine whose travel holds the manual's parabola (X to 3600, Y to 10801).
BIG = {"axes": {"X": {"min_limit": -10000, "max_limit": 10000}, "Y": {"min_limit": -20000, "max_limit": 20000},
                "Z": {}}}
PARABOLA = "G0 X0 Y1 Z0\nG1 F1000\n#POLY [X[0,60,0,0,0] Y[1,0,3,0,0] SP0 EP60]\nM30\n"   # L15862-L15870
#: The manual's spline example (L15775-L15801).
SPLINE_EXAMPLE = ("N10 G00 X0 Y20\nN20 G01 X20 Y20 F750\nN30 #ASPLINE MODE [1,2]\nN40 #SPLINE ON\nN50 X40 Y60\n"
                  "N60 X60\nN70 X50 Y40\nN80 X80\nN90 Y20\nN100 X110\nN110 Y50\nN120 #SPLINE OFF\nN130 X140\n"
                  "N140 M30\n")


def _run(program: str, machine=None):
    return fagorcnc.simulate(text=program, machine=machine)


def _codes(program: str, machine=None) -> list[str]:
    return [d.code for d in _run(program, machine).diagnostics]


def _chords(result) -> list:
    return [m for m in result.moves if isinstance(m, CurveLine)]


def _xy(points) -> np.ndarray:
    return np.array([[p["X"], p["Y"]] for p in points])


# ------------------------------------------------------------------ Akima's slopes, by hand
def test_akima_slopes_of_a_step_by_hand():
    # t 0..4, y 0 0 1 1 1: m = 0, 1, 0, 0; ends m-1 = 2*0-1 = -1, m-2 = 2*(-1)-0 = -2, m4 = m5 = 0.
    # knot 0: w_next = |m1-m0| = 1, w_prev = |m-1 - m-2| = 1 -> (1*(-1) + 1*0)/2 = -0.5
    # knot 1: w_next = |m2-m1| = 1, w_prev = |m0-m-1| = 1 -> (1*0 + 1*1)/2 = 0.5
    # knot 2: w_next = |m3-m2| = 0, w_prev = |m1-m0| = 1 -> (0*1 + 1*0)/1 = 0 (flat: no overshoot)
    # knot 3: w_next = 0, w_prev = |m2-m1| = 1 -> m3 = 0; knot 4: both weights 0 -> (m3+m4)/2 = 0
    s = akima_slopes(np.array([0.0, 1, 2, 3, 4]), np.array([0.0, 0, 1, 1, 1]))
    assert s[:, 0].tolist() == pytest.approx([-0.5, 0.5, 0.0, 0.0, 0.0])


def test_akima_slopes_on_uneven_knots_by_hand():
    # t 0 1 3, y 0 2 2: m0 = 2, m1 = 0; m-1 = 4, m-2 = 6, m2 = -2, m3 = -4
    # knot 0: w_next = |0-2| = 2, w_prev = |4-6| = 2 -> (2*4 + 2*2)/4 = 3
    # knot 1: w_next = |-2-0| = 2, w_prev = |2-4| = 2 -> (2*2 + 2*0)/4 = 1
    # knot 2: w_next = |-4+2| = 2, w_prev = |0-2| = 2 -> (2*0 + 2*(-2))/4 = -1
    s = akima_slopes(np.array([0.0, 1, 3]), np.array([0.0, 2, 2]))
    assert s[:, 0].tolist() == pytest.approx([3.0, 1.0, -1.0])


def test_given_tangents_replace_the_end_slopes():
    s = akima_slopes(np.array([0.0, 1, 3]), np.array([0.0, 2, 2]), np.array([0.5]), np.array([0.25]))
    assert s[:, 0].tolist() == pytest.approx([0.5, 1.0, 0.25])


def test_hermite_cubic_and_its_chord_bound():
    # y0 0, y1 1, slopes 0 over h 1: m = 1, c2 = 3m - 0 - 0 = 3, c3 = 0 + 0 - 2 = -2 (smoothstep)
    c = hermite_coefficients(np.array([0.0]), np.array([1.0]), np.array([0.0]), np.array([0.0]), 1.0)
    assert c[:, 0].tolist() == pytest.approx([0.0, 0.0, 3.0, -2.0])
    # c'' = 6 - 12 τ, largest |c''| = 6 at the ends: n = ceil(1 * sqrt(6 / (8 * 0.001))) = ceil(27.39) = 28
    tau = sample_cubic(c, 1.0)
    assert len(tau) == 29
    dense = np.linspace(0.0, 1.0, 20001)
    curve = cubic_points(c, dense)[:, 0]
    chords = np.interp(dense, tau, cubic_points(c, tau)[:, 0])
    assert np.abs(curve - chords).max() <= CHORD_TOLERANCE


# ------------------------------------------------------------------ #POLY
def test_poly_parabola_of_the_manual():
    r = _run(PARABOLA, BIG)
    assert r.ok, r.diagnostics
    assert "INT078" not in [d.code for d in r.diagnostics]
    chords = _chords(r)
    # X = 60p, Y = 1 + 3p²: c'' = (0, 6); 16 intervals of h = 3.75: ceil(3.75 * sqrt(6 / 0.008)) = ceil(102.7)
    # = 103 chords each, 1648 in all; from (0, 1) to (60*60, 1 + 3*3600) = (3600, 10801)
    assert len(chords) == 1648
    assert (chords[0].start["X"], chords[0].start["Y"]) == (0.0, 1.0)
    assert (chords[-1].end["X"], chords[-1].end["Y"]) == pytest.approx((3600.0, 10801.0))
    assert {c.src.line for c in chords} == {3} and {c.feed for c in chords} == {1000.0}
    # every chord end is on the curve: p = X/60, Y = 1 + 3 (X/60)²
    xy = _xy([c.end for c in chords])
    assert np.abs(xy[:, 1] - (1 + 3 * (xy[:, 0] / 60) ** 2)).max() < 1e-6
    # length ∫0^60 6 sqrt(100 + p²) dp = 6 [p/2 sqrt(100+p²) + 50 ln(p + sqrt(100+p²))]0^60 = 11696.51 mm
    assert sum(c.length for c in chords) == pytest.approx(11696.5065, abs=0.01)
    assert r.state.position()["X"] == pytest.approx(3600.0)


def test_poly_chords_run_without_a_stop_at_f():
    # G50 (the default corner) stops at corners, never between the chords of one curve: the curve takes
    # its length at F, 11696.51 mm / (1000/60 mm/s) = 701.79 s, plus the ramps at its ends
    r = _run(PARABOLA, BIG)
    segs = [s for s in r.segments() if s.line == 3]
    assert min(s.v0 for s in segs[1:]) == pytest.approx(1000 / 60)
    assert 701.79 < sum(s.duration for s in segs) < 701.79 + 0.2


def test_poly_chord_error_within_a_micrometre():
    coeffs = np.array([[0.0, 10.0, 0.0, 0.0, 0.0], [0.0, 0.0, 0.0, 1.0, -0.5]])
    p, pts = poly_points(coeffs, -2.0, 2.0)
    dense = np.linspace(-2.0, 2.0, 40001)
    exact = np.vander(dense, 5, increasing=True) @ coeffs.T
    approx = np.column_stack([np.interp(dense, p, pts[:, i]) for i in range(2)])
    assert np.linalg.norm(exact - approx, axis=1).max() <= CHORD_TOLERANCE


def test_poly_fewer_coefficients_and_decreasing_parameter():
    # X[5,-1] is X = 5 - p, p from 5 down to 0: X 0 -> 5 along a straight line (Y stays 0)
    r = _run("G1 X0 Y0 F600\n#POLY [X[5,-1] SP5 EP0]\nM30\n")
    assert r.ok, r.diagnostics
    assert r.state.position()["X"] == pytest.approx(5.0)


def test_curvature_caps_the_speed_through_the_chords():
    # X = p, Y = p², p -1..1 at F60000 (1000 mm/s): curvature at the vertex 2/(1+0)^1.5 = 2.
    # acceleration: sqrt(A / κ) = sqrt(1000 / 2) = 22.4 mm/s; jerk of the turn κ² v³ <= 20000:
    # v <= (20000 / 4)^(1/3) = 17.1 mm/s, the lower one
    r = _run("G1 X-1 Y1 F60000\n#POLY [X[0,1] Y[0,0,1] SP-1 EP1]\nM30\n")
    assert r.ok, r.diagnostics
    at_vertex = next(s for s in r.segments() if s.line == 2 and s.piece.start[:2].tolist() == [0.0, 0.0])
    assert at_vertex.v0 == pytest.approx(17.1, rel=0.03)


@pytest.mark.parametrize(("program", "code"), [
    ("G1 X0 Y1 F100\n#POLY [X[0,60,0,0,0] Y[1,0,3,0,0] SP0]\n", "INT220"),            # no EP
    ("G1 X0 Y1 F100\n#POLY [X[0,60,0,0,0,1] SP0 EP1]\n", "INT220"),                  # 5th degree
    ("G1 X0 Y1 F100\n#POLY [Q[0,60] SP0 EP1]\n", "INT220"),                          # not an axis
    ("G1 X0 Y1 F100\n#POLY [X[0,1] SP1 EP1]\n", "INT220"),                           # SP = EP
    ("G1 X0 Y1 F100\n#POLY X[0,1] SP0 EP1\n", "INT220"),                             # no brackets
    ("G0 X0 Y1\n#POLY [X[0,60] SP0 EP1]\n", "INT221"),                               # G00
    ("G1 X5 Y1 F100\n#POLY [X[0,60] SP0 EP1]\n", "INT221"),                          # starts at X0, tool at X5
    ("G1 X0 Y0 F100\n#POLY [X[0,60] SP0 EP1000]\n", "INT100"),                       # X to 60000
])
def test_poly_errors(program, code):
    assert code in _codes(program + "M30\n")


# ------------------------------------------------------------------ #SPLINE
def test_spline_through_three_points_by_hand():
    # points (0,0) (3,4) (6,0), chord lengths 5, 5: t = 0, 5, 10.  X: slopes 0.6 everywhere.
    # Y: m = 0.8, -0.8; m-1 = 2.4, m-2 = 4.0, m2 = -2.4, m3 = -4.0; all weights 1.6:
    # knot 0 (2.4 + 0.8)/2 = 1.6, knot 1 (0.8 - 0.8)/2 = 0, knot 2 (-0.8 - 2.4)/2 = -1.6.
    # Segment 0: X = 0.6τ; Y = 1.6τ + c2 τ², c2 = (3*0.8 - 2*1.6 - 0)/5 = -0.16, c3 = (1.6 + 0 - 1.6)/25 = 0,
    # so Y = (1.6/0.6) X - (0.16/0.36) X² = 8/3 X - 4/9 X²: through (1.5, 3.0), top at (3, 4)
    r = _run("G1 X0 Y0 F1000\n#SPLINE ON\nX3 Y4\nX6 Y0\n#SPLINE OFF\nM30\n")
    assert r.ok, r.diagnostics
    xy = _xy([c.end for c in _chords(r)])
    first = xy[xy[:, 0] <= 3.0]
    assert np.abs(first[:, 1] - (8 / 3 * first[:, 0] - 4 / 9 * first[:, 0] ** 2)).max() < 1e-9
    assert [3.0, 4.0] in xy.tolist() and xy[-1].tolist() == [6.0, 0.0]
    assert {c.src.line for c in _chords(r)} == {3, 4}


def test_spline_of_colinear_points_is_the_line():
    r = _run("G1 X0 Y0 F1000\n#SPLINE ON\nX10\nX30\nX35\n#SPLINE OFF\nM30\n")
    xy = _xy([c.end for c in _chords(r)])
    assert np.all(xy[:, 1] == 0.0) and np.all(np.diff(xy[:, 0]) > 0)


def test_manual_spline_example_passes_every_point_and_ends_tangent_to_the_next_block():
    r = _run(SPLINE_EXAMPLE)
    assert r.ok, r.diagnostics
    assert not {"INT078", "INT079"} & {d.code for d in r.diagnostics}
    chords = _chords(r)
    xy = _xy([c.end for c in chords]).tolist()
    for point in ([40, 60], [60, 60], [50, 40], [80, 40], [80, 20], [110, 20], [110, 50]):
        assert point in xy
    assert chords[0].start["X"] == 20.0 and chords[0].start["Y"] == 20.0   # N20: the spline's start (L15777)
    # ASPLINE MODE [1,2]: the end is tangent to N130 X140, i.e. along +X
    last = chords[-1]
    d = math.atan2(last.end["Y"] - last.start["Y"], last.end["X"] - last.start["X"])
    assert abs(math.degrees(d)) < 2.0
    assert r.moves[-2].src.line == 13 and not isinstance(r.moves[-2], CurveLine)



def test_an_independent_move_after_the_spline_is_not_the_next_block_of_its_tangent():
    # #ASPLINE MODE [1,2] ends the spline tangent to the next block (L15766-L15770).  A #MOVE is no block of the
    # path (its axis has an interpolator of its own, L16615): the tangent is that of N130 X140, along +X, and the
    # spline's chords never move U (before: the #MOVE U100 was taken as the next block, and U dipped to -3.31).
    program = SPLINE_EXAMPLE.replace("N130 X140\n", "#MOVE ABS [U100, F1000]\nN130 X140\n")
    r = _run(program, {"axes": {"X": {}, "Y": {}, "Z": {}, "U": {}}})
    assert r.ok, r.diagnostics
    chords = _chords(r)
    assert all(c.end["U"] == 0.0 for c in chords)
    last = chords[-1]
    d = math.atan2(last.end["Y"] - last.start["Y"], last.end["X"] - last.start["X"])
    assert abs(math.degrees(d)) < 2.0

def test_given_tangents_start_and_end():
    # MODE [3,3] with STARTTANG X1 Y1 and ENDTANG X0 Y1 (L15803-L15812): 2 points are enough (L15722)
    r = _run("G1 X20 Y20 F750\n#ASPLINE MODE [3,3]\n#ASPLINE STARTTANG X1 Y1\n#ASPLINE ENDTANG X0 Y1\n"
             "#SPLINE ON\nX40 Y60\n#SPLINE OFF\nM30\n")
    assert r.ok, r.diagnostics
    chords = _chords(r)
    first, last = chords[0], chords[-1]
    start = math.degrees(math.atan2(first.end["Y"] - 20, first.end["X"] - 20))
    end = math.degrees(math.atan2(60 - last.start["Y"], 40 - last.start["X"]))
    assert start == pytest.approx(45.0, abs=1.0) and end == pytest.approx(90.0, abs=1.0)


def test_an_arc_interrupts_the_spline_with_tangent_transitions():
    # the chords before G02 end along its start tangent: G02 from (20,0) about (20,-10) starts along +X
    r = _run("G1 X0 Y0 F1000\n#SPLINE ON\nX10 Y5\nX20 Y0\nG2 X30 Y-10 I0 J-10\nG1 X40 Y-5\nX50 Y-10\n"
             "#SPLINE OFF\nM30\n")
    assert r.ok, r.diagnostics
    moves = [m for m in r.moves if m.kind in ("linear", "arc")]
    k = next(i for i, m in enumerate(moves) if m.kind == "arc")
    before, after = moves[k - 1], moves[k + 1]
    assert isinstance(before, CurveLine) and isinstance(after, CurveLine)
    assert math.degrees(math.atan2(before.end["Y"] - before.start["Y"], before.end["X"] - before.start["X"])) \
        == pytest.approx(0.0, abs=2.0)
    # the arc ends at (30,-10) going -Y (clockwise about (20,-10)): the chords after it start that way
    assert math.degrees(math.atan2(after.end["Y"] - after.start["Y"], after.end["X"] - after.start["X"])) \
        == pytest.approx(-90.0, abs=2.0)


def test_an_m_function_inside_the_spline_stays_at_its_point():
    r = _run("G1 X0 Y0 F1000\n#SPLINE ON\nX3 Y4\nM8\nX6 Y0\n#SPLINE OFF\nM30\n")
    k = next(i for i, m in enumerate(r.moves) if m.kind == "aux" and m.value == 8)
    assert (r.moves[k - 1].end["X"], r.moves[k - 1].end["Y"]) == (3.0, 4.0)


@pytest.mark.parametrize(("program", "code"), [
    ("G1 X0 Y0 F100\n#SPLINE ON\nX10 Y5\n#SPLINE OFF\n", "INT224"),                     # 2 points, automatic
    ("G1 X0 Y0 F100\n#ASPLINE MODE [4,1]\n", "INT223"),                                 # no type 4
    ("#ASPLINE STARTTANG X0 Y0\n", "INT223"),                                           # zero direction
    ("#ASPLINE MODE [3,1]\n#SPLINE ON\n", "INT223"),                                    # type 3, no STARTTANG
    ("T1 D1\nG137 G41 G1 X0 Y0 F100\n#SPLINE ON\n", "INT225"),                          # L15708
    ("G1 X0 Y0 F100\n#SPLINE ON\nX10 Y5\nG137 G41 X20 Y0\nX30 Y5\n#SPLINE OFF\n", "INT225"),   # and vice versa
    ("G1 X0 Y0 F100\n#SPLINE ON\nX10 Y5\n#POLY [X[10,1] SP0 EP1]\nX20\n#SPLINE OFF\n", "INT226"),
    ("G1 X0 Y0 F100\n#SPLINE ON\nX10 Y5\n#MOVE [Z5, F100]\nX20\n#SPLINE OFF\n", "INT226"),
    ("G1 X0 Y0 F100\nG93\n#SPLINE ON\nX10 Y5 F2\nX20 F2\nX30 Y5 F2\n#SPLINE OFF\n", "INT226"),
])
def test_spline_errors(program, code):
    machine = {"tools": {"1": {"1": {"radius": 1.0}}}} if "T1" in program else None
    assert code in _codes(program + "M30\n", machine)


def test_check_reports_no_int078_for_the_curves(tmp_path, capsys):
    f = tmp_path / "curves.nc"
    f.write_text(SPLINE_EXAMPLE.replace("N140 M30\n", "") + "G1 X0 Y1\n#POLY [X[0,60] Y[1,0,3] SP0 EP1]\n"
                 "#MOVE [Z10, F500, NULL]\nM30\n")
    status = main(["check", str(f)])
    out = capsys.readouterr().out
    assert status == 0, out
    assert "INT078" not in out and "PASS" in out


def test_spline_with_radius_compensation_is_offset_by_the_radius():
    # G41 G136 with R2: every compensated point on the spline's blocks is 2 mm from the spline's chords
    machine = {"tools": {"1": {"1": {"radius": 2.0}}}}
    prog = ("T1 D1 M6\nG0 X0 Y-10\nG41 G1 X0 Y0 F1000\n#SPLINE ON\nX10 Y5\nX20 Y0\nX30 Y5\n#SPLINE OFF\nG1 X40\n"
            "G40 X50 Y-10\nM30\n")
    r = _run(prog, machine)
    assert r.ok, r.diagnostics
    plain = _xy([c.end for c in _chords(_run(prog.replace("G41 ", "").replace("G40 ", ""), machine))])
    dense = np.concatenate([np.linspace(plain[i], plain[i + 1], 50) for i in range(len(plain) - 1)])
    offset = _xy([m.end for m in r.moves if m.kind in ("linear", "arc") and m.src.line == 6])
    gaps = [np.linalg.norm(dense - q, axis=1).min() for q in offset]
    assert min(gaps) == pytest.approx(2.0, abs=1e-5) and max(gaps) == pytest.approx(2.0, abs=1e-5)


def test_tangent_to_the_block_before():
    # #ASPLINE MODE [2,1]: the spline leaves (10,0) along the G01 that reached it, +X
    r = _run("G1 X0 Y0 F1000\nX10\n#ASPLINE MODE [2,1]\n#SPLINE ON\nX20 Y10\nX30 Y0\n#SPLINE OFF\nM30\n")
    first = _chords(r)[0]
    assert math.degrees(math.atan2(first.end["Y"] - first.start["Y"], first.end["X"] - first.start["X"])) \
        == pytest.approx(0.0, abs=2.0)


def test_spline_still_on_at_the_end_of_the_program_ends_there():
    r = _run("G1 X0 Y0 F1000\n#SPLINE ON\nX3 Y4\nX6 Y0\nM30\n")
    assert r.ok, r.diagnostics
    assert _xy([c.end for c in _chords(r)])[-1].tolist() == [6.0, 0.0]
