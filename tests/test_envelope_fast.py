"""PLN100's cheap first test (plan.envelope.Envelope._inside): it may only say "inside" when the
exact extent of the planned curve is inside the soft limits; near a limit the exact test runs."""

from __future__ import annotations

import dataclasses
import math

import numpy as np

import fagorcnc
from fagorcnc.commands.check import check_file
from fagorcnc.plan.envelope import ENVELOPE_TOLERANCE, Envelope, piece_extent


def _curved(program: str):
    result = fagorcnc.simulate(text=program)
    assert result.ok, [str(d) for d in result.errors]
    return result.machine, [s.piece for s in result.segments() if getattr(s.piece, "curved", False)]


def _exactly_inside(envelope: Envelope, piece) -> bool:
    pmin, pmax = piece_extent(piece)
    tol = ENVELOPE_TOLERANCE
    return bool((pmin >= envelope.lo - tol).all() and (pmax <= envelope.hi + tol).all())


def test_cheap_test_never_passes_a_curve_beyond_a_limit():
    # a G05 zig-zag and arcs running along the X limit of the default machine (+-1000 mm): corner
    # blends 999.x mm out, an arc whose circle of radius 5 crosses X1000 (centre X996), one that does not
    zigzag = "".join(f"G1 X{999.2 + 0.6 * (k % 2):.1f} Y{k * 0.5:.1f}\n" for k in range(40))
    program = (f"G90 G1 X990 Y0 Z0 F3000\nG05\n{zigzag}"
               "G1 X991 Y30\nG3 X1001 Y30 I5 J0\nG1 X990 Y40\nG2 X980 Y40 I-5 J0\nM30\n")
    default = fagorcnc.load_machine(None)   # X1002 lets the arc's end pass INT100
    machine = dataclasses.replace(default, axes={**default.axes,
                                                 "X": dataclasses.replace(default.axes["X"], max_limit=1002.0)})
    result = fagorcnc.simulate(text=program, machine=machine)
    assert result.ok, [str(d) for d in result.errors]
    pieces = [s.piece for s in result.segments() if getattr(s.piece, "curved", False)]
    envelope = Envelope(fagorcnc.load_machine(None))   # the test against X1000
    verdicts = [(envelope._inside(p), _exactly_inside(envelope, p)) for p in pieces]
    assert all(exact for cheap, exact in verdicts if cheap)
    assert any(not exact for _cheap, exact in verdicts)   # the X1001 arc (and blends out there) go beyond
    assert any(cheap for cheap, _exact in verdicts)       # the arc round X975..X985 is seen at once


def test_far_from_the_limits_every_curve_is_passed_cheaply():
    _machine, pieces = _curved("G90 G1 X0 Y0 F3000\nG05\n" +
                               "".join(f"G1 X{k % 2} Y{k}\n" for k in range(20)) + "G2 X11 Y19 I5 J0\nM30\n")
    envelope = Envelope(fagorcnc.load_machine(None))
    assert pieces and all(envelope._inside(p) for p in pieces)


def test_an_arc_bulging_past_the_limit_is_still_pln100(tmp_path):
    # centre X990 Y0, radius 20: the arc from (990,-20) to (990,20) counter-clockwise reaches
    # X990 + 20 = 1010 > 1000 although both ends are at X990
    f = tmp_path / "bulge.nc"
    f.write_text("G0 X990 Y-20\nG3 X990 Y20 I0 J20 F1000\nM30\n")
    report = check_file(f)
    assert [d.code for d in report.diagnostics] == ["PLN100"]
    assert "X 1010.0000" in report.diagnostics[0].message


def test_blend_box_uses_its_length_round_its_start():
    # a blend of length L starting at x = 1000 - L/2 may reach 1000 + L/2: not cheaply inside
    _machine, pieces = _curved("G90 G1 X0 Y0 F3000\nG05\nG1 X10\nG1 Y10\nM30\n")
    blend = next(p for p in pieces if type(p).__name__ == "BlendPiece")
    envelope = Envelope(fagorcnc.load_machine(None))
    shift = np.zeros_like(blend.start)
    shift[0] = 1000.0 - blend.length / 2 - blend.start[0]
    blend.start = blend.start + shift
    assert not envelope._inside(blend)


def test_arc_box_is_the_hull_in_every_plane():
    # the cheap arc test is the hull's box (plane axes: the circle's square; the others: the end
    # points) in each of the three planes, helical or not, on either side of every limit
    from fagorcnc.plan.envelope import hull
    from fagorcnc.plan.geometry import ArcPiece

    envelope = Envelope(fagorcnc.load_machine(None))
    tol = ENVELOPE_TOLERANCE
    dim = len(envelope.lo)
    seen = set()
    for ia, io in ((0, 1), (2, 0), (1, 2)):
        for axis in range(3):
            for bound, sign in ((envelope.hi, 1.0), (envelope.lo, -1.0)):
                for gap in (-3.0, -0.5, 0.5, 3.0, 50.0):
                    for rise in (0.0, 2.0):
                        centre = np.zeros(dim)
                        centre[axis] = bound[axis] - sign * (5.0 + gap)   # radius 5: gap < 0 crosses it
                        start, end = centre.copy(), centre.copy()
                        start[ia] += 5.0
                        end[io] += 5.0
                        off = next(i for i in range(3) if i not in (ia, io))
                        end[off] += rise
                        piece = ArcPiece(start, end, ia, io, (centre[ia], centre[io]), math.pi / 2)
                        lo, hi = hull(piece)
                        boxed = bool((lo >= envelope.lo - tol).all() and (hi <= envelope.hi + tol).all())
                        assert envelope._inside(piece) is boxed
                        seen.add(boxed)
    assert seen == {True, False}
