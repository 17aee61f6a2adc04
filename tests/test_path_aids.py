"""Corner aids G36, G39, G37, G38 with hand-computed geometry (seed 002 L8393-L8703, spec 04 §3-§7)."""

from __future__ import annotations

import math

import pytest

import fagorcnc
from fagorcnc.simulate import estimate_time

A = pytest.approx


def moves(text: str, machine=None):
    r = fagorcnc.simulate(text, machine)
    assert r.ok, [str(d) for d in r.diagnostics]
    # moves of length 0 (the first "G01 X0 Y0" from the origin) are left out
    return [m for m in r.moves if m.kind in ("rapid", "linear", "arc") and m.length > 1e-12], r


def xy(p):
    return (A(p["X"], abs=1e-4), A(p["Y"], abs=1e-4))


def test_g36_rounds_a_line_line_corner():
    # (0,0)->(50,0) then up to (50,50), r 10: tangent distance r*tan(45) = 10
    # T1 (40,0), T2 (50,10), centre (40,10), left turn -> CCW fillet
    (l1, fillet, l2), r = moves("G90 G01 X0 Y0 F100\nX50\nG36 I10\nY50\nM30\n")
    assert l1.end == A({"X": 40.0, "Y": 0.0, "Z": 0.0})
    assert fillet.center == A({"X": 40.0, "Y": 10.0}) and fillet.direction == "ccw" and fillet.radius == A(10.0)
    assert fillet.sweep == A(90.0)
    assert l2.start == A({"X": 50.0, "Y": 10.0, "Z": 0.0}) and l2.end == A({"X": 50.0, "Y": 50.0, "Z": 0.0})
    # the path is shorter by 2*10 - the quarter circle: 100 - 20 + 5*pi at F100 -> 60 s per 100 mm
    assert estimate_time(r.machine, r.moves) == A((80 + 5 * math.pi) / 100 * 60)


def test_g36_rounds_a_line_arc_corner():
    # line (0,0)->(50,0), then G02 from (50,0) to (80,30) about (80,0) (start tangent +Y): left turn, psi 90
    # offsets toward the turn: y = 10 and the circle about (80,0) of radius 30 + 10 = 40
    # centre: x = 80 - sqrt(1600 - 100) = 41.2702; T1 (41.2702, 0); T2 = (80,0) + 30*(C-(80,0))/40
    (l1, fillet, arc), _ = moves("G90 G01 X0 Y0 F100\nX50\nG36 I10\nG02 X80 Y30 I30 J0\nM30\n")
    cx = 80 - math.sqrt(1500)
    assert fillet.center == A({"X": cx, "Y": 10.0}) and fillet.direction == "ccw"
    assert xy(l1.end) == (A(cx), A(0.0))
    t2 = (80 + 30 * (cx - 80) / 40, 30 * 10 / 40)
    assert xy(arc.start) == (A(t2[0]), A(t2[1])) and arc.center == A({"X": 80.0, "Y": 0.0})
    assert xy(fillet.end) == (A(t2[0]), A(t2[1]))


def test_g39_chamfer_between_two_lines():
    # I5: C1 = P - 5 t1 = (45,0), C2 = P + 5 t2 = (50,5)
    (l1, cut, l2), _ = moves("G90 G01 X0 Y0 F100\nX50\nG39 I5\nY50\nM30\n")
    assert xy(l1.end) == (45.0, 0.0) and xy(cut.start) == (45.0, 0.0) and xy(cut.end) == (50.0, 5.0)
    assert cut.kind == "linear" and xy(l2.start) == (50.0, 5.0)


def test_the_i_register_is_shared_by_g36_to_g39():
    # seed 002 L8432-L8456: a G39 without I takes the last I (here from G36)
    (_, _, _, cut, _), _ = moves("G01 X0 Y0 F100\nX50\nG36 I5\nY50\nG39\nX0\nM30\n")
    assert math.dist((cut.start["X"], cut.start["Y"]), (cut.end["X"], cut.end["Y"])) == A(5 * math.sqrt(2))


def test_g37_tangential_entry():
    # approach (0,-30)->(0,0), profile along +X: right turn, entry circle about (0,-5) r 5 (cw)
    # tangent point from (0,-30): angle -90 - acos(5/25) -> T = (-4.8990, -6.0)
    (_, approach, entry, profile), _ = moves("G90 G00 X0 Y-30\nG01 Y0 F100\nG37 I5\nX50\nM30\n")
    assert xy(approach.end) == (A(-math.sqrt(24)), A(-6.0))
    assert entry.center == A({"X": 0.0, "Y": -5.0}) and entry.direction == "cw"
    assert xy(entry.end) == (0.0, 0.0) and entry.radius == A(5.0)
    assert xy(profile.start) == (0.0, 0.0)


def test_g38_tangential_exit():
    # last move (0,0)->(50,0), exit down to (50,-30): exit circle about (50,-5) r 5 (cw), T = (54.8990, -6.0)
    (profile, out_arc, leave), _ = moves("G90 G01 X0 Y0 F100\nX50\nG38 I5\nY-30\nM30\n")
    assert xy(profile.end) == (50.0, 0.0)
    assert out_arc.center == A({"X": 50.0, "Y": -5.0}) and out_arc.direction == "cw"
    assert xy(out_arc.end) == (A(50 + math.sqrt(24)), A(-6.0)) and xy(leave.start) == xy(out_arc.end)
    assert xy(leave.end) == (50.0, -30.0)


@pytest.mark.parametrize(("text", "code", "line"), [
    ("G01 X0 Y0 F100\nX50\nG36\nY50\nM30\n", "INT017", 3),          # no I ever given
    ("G01 X0 Y0 F100\nX50\nG36 I100\nY50\nM30\n", "INT085", 3),     # radius too large for the moves
    ("G00 Y-8\nG01 Y0 F100\nG37 I5\nX50\nM30\n", "INT085", 3),      # approach shorter than 2 r
    ("G01 X0 Y0 F100\nX50\nG36 I5\nM30\n", "INT085", 3),            # no move after the aid
    ("G01 X10 F100\nG36 I2 X5\nM30\n", "INT025", 2),                # the aid stands alone
])
def test_impossible_aids_are_errors(text, code, line):
    r = fagorcnc.simulate(text)
    assert [(d.code, d.line) for d in r.errors] == [(code, line)]


def test_tangent_continuation_needs_no_rounding():
    (l1, l2), _ = moves("G01 X0 Y0 F100\nX50\nG36 I5\nX80\nM30\n")
    assert xy(l1.end) == (50.0, 0.0) and xy(l2.start) == (50.0, 0.0)


def test_aid_under_scaling_scales_the_size():
    # the aid acts on the programmed contour, before G72 scaling (spec 04 §10.1): r 10 becomes 20
    (_, fillet, _), _ = moves("G72 S2\nG01 X0 Y0 F100\nX50\nG36 I10\nY50\nM30\n")
    assert fillet.radius == A(20.0) and fillet.center == A({"X": 80.0, "Y": 20.0})


def test_records_between_the_moves_keep_their_order():
    r = fagorcnc.simulate("G01 X0 Y0 F100\nX50\nM8\nG36 I10\nY50\nM30\n")
    assert [m.kind for m in r.moves if m.kind == "aux" or m.length > 0] == ["linear", "aux", "arc", "linear", "aux"]


def test_g39_chamfer_before_a_rapid_is_a_rapid_and_is_planned():
    # seed 002 L8570, L8584-L8600 (the manual's example): "si le déplacement suivant est dans G00, le
    # chanfreinage se réalisera dans G00".  The chamfer of I5 at (10, 50) between Y+ and X+ is the
    # diagonal (10, 45) -> (15, 50), 5 sqrt(2) = 7.0711 mm, run at rapid.  With the default machine's
    # limits scaled by sqrt(2) along that diagonal its length sits exactly where two of ruckig's
    # profile types meet, where ruckig 0.19 found no profile (PLN001 on a valid program).
    text = "N10 G01 G94 X10 Y10 F600\nN20 G01 X10 Y50\nN30 G39 I5\nN40 G00 X50 Y50\nN50 M30\n"
    r = fagorcnc.simulate(text)
    assert r.ok, r.diagnostics
    cut = next(m for m in r.moves if getattr(m, "kind", "") == "rapid")
    assert (cut.start["X"], cut.start["Y"], cut.end["X"], cut.end["Y"]) == pytest.approx((10, 45, 15, 50))
    seg = [s for s in r.segments(keep_profiles=False) if s.kind == "motion" and s.piece.length == pytest.approx(
        5 * math.sqrt(2))]
    # rest to rest at 1414.2 mm/s² and 28284 mm/s³ (the limits along the diagonal): four jerk phases
    # of a/j = 0.05 s reach a²/j = 70.7 mm/s and cover exactly 7.0711 mm in 0.2 s
    assert len(seg) == 1 and seg[0].duration == pytest.approx(0.2, rel=1e-6)


def test_g36_rounding_before_a_rapid_is_run_at_rapid():
    # seed 002 L8460, the manual's example L8474-L8490: "si le déplacement suivant est dans G00,
    # l'arrondissement se réalisera dans G00".  The R5 rounding at (10, 50) between Y+ and X+.
    text = "N10 G01 G94 X10 Y10 F600\nN20 G01 X10 Y50\nN30 G36 I5\nN40 G00 X50 Y50\nN50 M30\n"
    r = fagorcnc.simulate(text)
    assert r.ok, r.diagnostics
    fillet = next(m for m in r.moves if m.kind == "arc")
    assert fillet.feed is None and fillet.rapid and fillet.radius == pytest.approx(5.0)
    assert xy(fillet.start) == (10.0, 45.0) and xy(fillet.end) == (15.0, 50.0)
    # planned at rapid: far faster than at F600 (10 mm/s would take 0.785 s for its 7.85 mm)
    seg = next(s for s in r.segments(keep_profiles=False) if s.kind == "motion" and s.piece.curved)
    assert seg.duration < 0.4
    assert estimate_time(r.machine, [fillet]) == pytest.approx(5 * math.pi / 2 / 10000 * 60)   # at 10 m/min
    # before a G01 it keeps the feed
    r = fagorcnc.simulate(text.replace("N40 G00", "N40 G01"))
    assert next(m for m in r.moves if m.kind == "arc").feed == 600.0
