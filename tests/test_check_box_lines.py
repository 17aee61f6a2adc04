"""check's boxes per tool when a line widens them by its end alone (commands/extents.py: a line
that starts where the last move ended, in the same tool's boxes and of the same kind)."""

from __future__ import annotations

from fagorcnc.commands.check import check_file


def _boxes(tmp_path, text: str) -> dict[int, dict]:
    path = tmp_path / "p.nc"
    path.write_text(text, encoding="utf-8")
    report = check_file(path)
    assert report.verdict() == "pass", [str(d) for d in report.diagnostics]
    return {b.tool: b.to_dict() for b in report.boxes}


def test_boxes_of_lines_across_a_tool_change_and_rapid_feed_switches(tmp_path):
    # tool 0: G0 from the machine's start (0, 0, 0) to (0, 0, 10), feed lines to (10, 0, 10),
    #   (10, 5, 10), (10, 5, 2): all moves X 0..10 Y 0..5 Z 0..10; feeds from (0, 0, 10) on (the
    #   first feed line starts at the rapid's end, and its start counts in the feed box): Z 2..10
    # T2 M6, then tool 2: G0 to (-3, 5, 2)... its first move starts at (10, 5, 2), which must count
    #   in tool 2's box even though it ended the last move of tool 0: X -3..10, Y 5..5, Z 2..20
    #   (a rapid up to Z 20 at the end); feeds of tool 2: G1 from (-3, 5, 2) to (-3, 8, 2):
    #   X -3..-3 Y 5..8 Z 2..2 (the rapid before it is not a feed, its start comes in as the
    #   feed line's start), and the rapid to Z 20 adds nothing to the feed box
    boxes = _boxes(tmp_path, "G90 G0 X0 Y0 Z10\nG1 X10 F1000\nY5\nZ2\nT2 M6\nG0 X-3\nG1 Y8\nG0 Z20\nM30\n")
    assert boxes[0]["machine"] == {"min": {"X": 0.0, "Y": 0.0, "Z": 0.0}, "max": {"X": 10.0, "Y": 5.0, "Z": 10.0}}
    assert boxes[0]["feed"]["machine"] == {"min": {"X": 0.0, "Y": 0.0, "Z": 2.0},
                                           "max": {"X": 10.0, "Y": 5.0, "Z": 10.0}}
    assert boxes[2]["machine"] == {"min": {"X": -3.0, "Y": 5.0, "Z": 2.0}, "max": {"X": 10.0, "Y": 8.0, "Z": 20.0}}
    assert boxes[2]["feed"]["machine"] == {"min": {"X": -3.0, "Y": 5.0, "Z": 2.0},
                                           "max": {"X": -3.0, "Y": 8.0, "Z": 2.0}}
    assert boxes[2]["part"] == boxes[2]["machine"]   # no origin offset: part = machine


def test_a_line_after_an_arc_widens_by_both(tmp_path):
    # G0 (0, 0, 0); G2 from (0, 0) to (10, 0) about (5, 0), clockwise in G17: through (5, 5), so Y 0..5;
    # then G1 to (10, -4): Y -4..5, X 0..10
    boxes = _boxes(tmp_path, "G90 G17 G0 X0 Y0 Z0\nG2 X10 Y0 I5 J0 F1000\nG1 Y-4\nM30\n")
    assert boxes[0]["feed"]["machine"]["min"] == {"X": 0.0, "Y": -4.0, "Z": 0.0}
    assert boxes[0]["feed"]["machine"]["max"] == {"X": 10.0, "Y": 5.0, "Z": 0.0}


def test_a_feed_end_widens_both_boxes_as_two_adds():
    # points with a new axis, one below, one above and one inside the boxes so far; the feed box starts
    # narrower than the box of all moves (a rapid widened only that one): X -5..20 and X 0..10 before
    # the point X 12 (above the feed box only), etc.; Y: -1, then 0.5 above it, then -9 below
    from fagorcnc.commands.extents import Box, _add_to_both

    points = [{"X": 12.0, "Y": -1.0}, {"X": -7.0, "Z": 3.0}, {"X": 1.0, "Y": 0.5, "Z": 3.0}, {"X": 30.0, "Y": -9.0}]
    a, b = Box({"X": -5.0}, {"X": 20.0}), Box({"X": 0.0}, {"X": 10.0})
    a2, b2 = Box(dict(a.lo), dict(a.hi)), Box(dict(b.lo), dict(b.hi))
    for p in points:
        _add_to_both(a, b, p)
        a2.add(p)
        b2.add(p)
        assert (a.lo, a.hi, b.lo, b.hi) == (a2.lo, a2.hi, b2.lo, b2.hi)
    assert (a.lo, a.hi) == ({"X": -7.0, "Y": -9.0, "Z": 3.0}, {"X": 30.0, "Y": 0.5, "Z": 3.0})
    assert (b.lo["X"], b.hi["X"]) == (-7.0, 30.0)
    assert list(a.lo) == ["X", "Y", "Z"]   # the axes in the order first seen, as the report lists them


def test_a_feed_box_merges_into_both_boxes_as_two_merges():
    # an arc's box X -1..4 Y 0..2, then one with Z: into a box of all moves X -5..3 and a feed box X 0..1
    # (after a rapid): X -5..4 and -1..4; Y 0..2 new in both; then Z 7..8 new, X 2..9 widens both to 9
    from fagorcnc.commands.extents import Box, _merge_into_both

    boxes = [({"X": -1.0, "Y": 0.0}, {"X": 4.0, "Y": 2.0}), ({"X": 2.0, "Z": 7.0}, {"X": 9.0, "Z": 8.0}),
             ({"X": -6.0, "Y": 1.0, "Z": 7.5}, {"X": 0.0, "Y": 1.5, "Z": 7.6})]
    a, b = Box({"X": -5.0}, {"X": 3.0}), Box({"X": 0.0}, {"X": 1.0})
    a2, b2 = Box(dict(a.lo), dict(a.hi)), Box(dict(b.lo), dict(b.hi))
    for lo, hi in boxes:
        _merge_into_both(a, b, lo, hi)
        a2.merge(lo, hi)
        b2.merge(lo, hi)
        assert (a.lo, a.hi, b.lo, b.hi) == (a2.lo, a2.hi, b2.lo, b2.hi)
    assert (a.lo, a.hi) == ({"X": -6.0, "Y": 0.0, "Z": 7.0}, {"X": 9.0, "Y": 2.0, "Z": 8.0})
    assert (b.lo["X"], b.hi["X"]) == (-6.0, 9.0)
