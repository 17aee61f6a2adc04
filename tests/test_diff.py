"""fagorcnc diff: geometric comparison of two programs' planned tool paths."""

from __future__ import annotations

import json

import numpy as np
import pytest

from fagorcnc.cli import main
from fagorcnc.commands import geometry_index as gi
from fagorcnc.commands.diff import DiffError, diff_programs

ABSOLUTE = """G71 G90 G17 G54
T1 D1 M06
G00 X0 Y0 Z5
G01 Z-1 F500
G01 X20 F1000
G02 X30 Y10 R10
G01 Y30
G03 X20 Y40 R10
G00 Z5
M30
"""
# the same path: incremental, the first line cut in two, arcs by their centre (I J) instead of R
INCREMENTAL = """G71 G91 G17 G54
T1 D1 M06
G00 X0 Y0 Z5
G01 Z-6 F500
G01 X12.5 F1000
X7.5
G02 X10 Y10 I10 J0
G01 Y20
G03 X-10 Y10 I-10 J0
G00 Z6
M30
"""


def _write(tmp_path, name: str, text: str):
    path = tmp_path / name
    path.write_text(text)
    return path


def test_the_same_path_written_differently_deviates_by_zero(tmp_path):
    a, b = _write(tmp_path, "a.nc", ABSOLUTE), _write(tmp_path, "b.nc", INCREMENTAL)
    report = diff_programs(a, b, tolerance=0.01)
    assert report.deviation < 1e-6 and report.bound < 1e-6
    assert report.within and report.regions() == []
    assert main(["diff", str(a), str(b)]) == 0


def test_a_step_of_two_hundredths(tmp_path, capsys):
    a = _write(tmp_path, "a.nc", ABSOLUTE)
    # line 7 (G01 Y30) becomes a step of 0.02 mm in X then the same line moved by 0.02 mm:
    # every point of B's new X30.02 line is 0.02 from A's X30 line, and back
    b = _write(tmp_path, "b.nc", ABSOLUTE.replace("G01 Y30\nG03 X20 Y40 R10",
                                                  "G01 X30.02\nG01 Y30\nG01 X30\nG03 X20 Y40 R10"))
    report = diff_programs(a, b, tolerance=0.01)
    assert report.deviation == pytest.approx(0.02, abs=1e-5)
    assert not report.within
    at = report.at()
    assert at["a_line"] == 7 and at["b_line"] in (7, 8, 9)
    regions = report.regions()
    assert any(r["from"] == "b" and r["lines"][0] <= 8 <= r["lines"][1] for r in regions)
    assert main(["diff", str(a), str(b)]) == 1
    assert "BEYOND" in capsys.readouterr().out
    assert main(["diff", str(a), str(b), "--tolerance", "0.05", "--format", "json"]) == 0
    document = json.loads(capsys.readouterr().out)
    assert document["schema"] == "fagorcnc-diff/1" and document["within"] is True
    assert document["deviation"] == pytest.approx(0.02, abs=1e-5)


def test_tools_offsets_and_cycle_time_are_compared(tmp_path):
    a = _write(tmp_path, "a.nc", ABSOLUTE)
    b = _write(tmp_path, "b.nc", ABSOLUTE.replace("T1 D1", "T2 D1").replace("F1000", "F500"))
    report = diff_programs(a, b, {"tools": {"1": {"1": {"length": 0}}, "2": {"1": {"length": 0}}}})
    text = "\n".join(report.differences())
    assert "tools: T1 in A, T2 in B" in text and "cycle time" in text


def test_a_moving_rotary_axis_is_refused(tmp_path, capsys):
    machine = {"axes": {"X": {}, "Y": {}, "Z": {}, "C": {"type": "rotary"}}}
    a = _write(tmp_path, "a.nc", "G0 X0 Y0 Z0\nG1 X10 C90 F100\nM30\n")
    with pytest.raises(DiffError, match="rotary axis"):
        diff_programs(a, a, machine)


def test_point_to_segment_distance_by_hand():
    # A: X0 -> X10; B: X0 -> (X5 Y1) -> X10.  A's farthest point from B is (5, 0): its distance to
    # the segment (0,0)-(5,1) is |(5, 0) - t (5, 1)| at t = 25/26: |(5/26, -25/26)| = sqrt(650)/26
    a0, a1 = np.array([[0.0, 0, 0]]), np.array([[10.0, 0, 0]])
    b0, b1 = np.array([[0.0, 0, 0], [5, 1, 0]]), np.array([[5.0, 1, 0], [10, 0, 0]])
    forward = gi.directed(a0, a1, gi.SegmentIndex(b0, b1), 0.01, 1e-9)
    assert forward.maximum == pytest.approx(650 ** 0.5 / 26, abs=1e-8)
    assert forward.where[0] == pytest.approx([5.0, 0.0, 0.0], abs=1e-6)
    backward = gi.directed(b0, b1, gi.SegmentIndex(a0, a1), 0.01, 1e-9)
    assert backward.maximum == pytest.approx(1.0)   # B's corner (5, 1) is 1 above A
    # a line cut in two collinear pieces is the same path
    c0, c1 = np.array([[0.0, 0, 0], [5, 0, 0]]), np.array([[5.0, 0, 0], [10, 0, 0]])
    assert gi.directed(a0, a1, gi.SegmentIndex(c0, c1), 0.01, 1e-9).maximum < 1e-12


def test_the_numpy_grid_and_the_tree_agree_with_brute_force():
    rng = np.random.default_rng(7)
    pts = np.cumsum(rng.normal(0, 0.3, (3000, 3)), axis=0)
    index = gi.SegmentIndex(pts[:-1], pts[1:])
    queries = pts[::7] + rng.normal(0, 2.0, (len(pts[::7]), 3))
    brute = np.array([gi.point_segment_distance(np.repeat(q[None], len(pts) - 1, 0), pts[:-1], pts[1:]).min()
                      for q in queries])
    d_tree, _ = index.nearest(queries)
    grid = gi.SegmentIndex(pts[:-1], pts[1:])
    grid._tree = None
    d_grid, _ = grid.nearest(queries)
    assert np.allclose(d_tree, brute, atol=1e-12) and np.allclose(d_grid, brute, atol=1e-12)
