"""`fagorcnc plot` under a kinematics: tool-axis glyphs and the tool-tip view (fagorcnc.commands.plot_tool),
checked on the SVG/PNG produced and on the glyphs it reports, numbers worked out by hand."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

from fagorcnc.cli import main
from fagorcnc.commands.plot import plot_program

pytest.importorskip("matplotlib")

AXES3 = {a: {"min_limit": -1000, "max_limit": 1000} for a in "XYZ"}
HEAD_B = {   # type 1: B about Y (main), A about X; tool 100 mm
    "axes": AXES3 | {"A": {"type": "rotary", "min_limit": -120, "max_limit": 120},
                     "B": {"type": "rotary", "min_limit": -120, "max_limit": 120}},
    "kinematics": [{"type": 1}],
    "tools": {"1": {"1": {"length": 100.0}}},
}
TABLE_AC = {   # type 10, both lines through (0, 0, -100); no tool length
    "axes": AXES3 | {"A": {"type": "rotary", "min_limit": -120, "max_limit": 120},
                     "C": {"type": "rotary", "min_limit": -9999, "max_limit": 9999}},
    "kinematics": [{"type": 10, "pivots": [[0, 0, -100], [0, 0, -100]]}],
}
# the manual's RTCP example 3 (seed 002 L13280): tip (40,0) -> (100,0), B-35 about the tip, ... -> (340, 0)
RTCP = ("T1 D1 M6\nG90 G17\n#RTCP ON\nG01 X40 Z0 B0 F1000\nX100\nB-35\nX200 Z70\nB90\n"
        "G18 G02 X270 Z0 R70 B0\nG01 X340\n#RTCP OFF\nM30\n")
S35, C35 = math.sin(math.radians(35)), math.cos(math.radians(35))


def has_glyph(segments, foot, direction, tol=1e-6) -> bool:
    foot, direction = np.asarray(foot, dtype=float), np.asarray(direction, dtype=float)
    for s in segments:
        d = s[1] - s[0]
        if np.allclose(s[0], foot, atol=tol) and np.allclose(d / np.linalg.norm(d), direction, atol=tol):
            return True
    return False


def svg_glyphs(path) -> int:
    """The number of glyphs in the SVG's "tool-axis" group: one move-to (M) per glyph."""
    text = path.read_text()
    group = re.search(r'<g id="tool-axis">(.*?)</g>', text, re.S)
    return 0 if group is None else len(re.findall(r"\bM ", group.group(1)))


def test_tip_view_of_the_rtcp_example(tmp_path):
    prog = tmp_path / "rtcp.nc"
    prog.write_text(RTCP)
    out = tmp_path / "tip.svg"
    info = plot_program(prog, out, HEAD_B, plane="XZ", view="tip")
    assert info.ok and info.view == "tip" and info.tool_axes > 10
    assert svg_glyphs(out) == info.tool_axes
    g = info.tool_axis_segments
    # extent: X 0..340, Z 0..170 (tip + the 100 mm length offset on Z: 100..170) -> 340; glyphs 6 %
    lengths = np.linalg.norm(g[:, 1] - g[:, 0], axis=1)
    assert np.allclose(lengths, 0.06 * 340)
    # the tip of B-35 stays at X100 (drawn at Z 0 + 100): the tool leans Ry(-35) Z = (-sin35, cos35)
    assert has_glyph(g, (100, 100), (-S35, C35))
    assert has_glyph(g, (340, 100), (0, 1))   # the last move, tool along Z
    # every foot on the programmed tip path: the arc's feet 70 mm from (270, 70 + 100)
    arc = [s for s in g if 200 + 1e-6 < s[0][0] < 270 - 1e-6]
    assert arc and all(abs(math.dist(s[0], (270, 170)) - 70) < 1e-6 for s in arc)


def test_joint_view_of_the_rtcp_example(tmp_path):
    prog = tmp_path / "rtcp.nc"
    prog.write_text(RTCP)
    out = tmp_path / "joints.svg"
    info = plot_program(prog, out, HEAD_B, plane="XZ")
    assert info.view == "joints" and svg_glyphs(out) == info.tool_axes > 10
    # B-35 about the tip (100, 0): the head reference point ends at (100 - 100 sin35, 100 cos35); the glyph
    # is the tool from there toward the tip: -(-sin35, cos35)
    assert has_glyph(info.tool_axis_segments, (100 - 100 * S35, 100 * C35), (S35, -C35))


def test_table_turning_about_the_tip(tmp_path):
    # RTCP on a table AC: C90 with the tip on the part point (50, 0, 0).  The table turns it about the
    # C line (through X0 Y0) to machine (0, 50): the joints arc from (50, 0) to (0, 50) while in the
    # part frame the tip stays at (50, 0) (every glyph there, the tool along Z)
    prog = tmp_path / "table.nc"
    prog.write_text("#RTCP ON\nG1 X50 Y0 Z0 A0 C0 F1000\nC90\n#RTCP OFF\nM30\n")
    tip = plot_program(prog, tmp_path / "tip.png", TABLE_AC, view="tip")
    feet = tip.tool_axis_segments[:, 0]
    assert tip.ok and len(feet) >= 1 and np.allclose(feet[-1], (50, 0), atol=1e-6)
    joints = plot_program(prog, tmp_path / "joints.png", TABLE_AC)
    feet = joints.tool_axis_segments[:, 0]
    assert len(feet) > 3 and np.allclose(feet[-1], (0, 50), atol=1e-6)
    assert all(abs(math.hypot(*f) - 50) < 1e-6 for f in feet[1:])   # on the circle of radius 50
    assert (tmp_path / "tip.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_no_glyphs_without_a_kinematics_or_when_asked(tmp_path):
    prog = tmp_path / "plain.nc"
    prog.write_text("G1 X10 Y10 F1000\nX20\nM30\n")
    out = tmp_path / "plain.svg"
    info = plot_program(prog, out, None, view="tip")
    assert info.tool_axes == 0 and svg_glyphs(out) == 0
    rtcp = tmp_path / "rtcp.nc"
    rtcp.write_text(RTCP)
    info = plot_program(rtcp, out, HEAD_B, plane="XZ", tool_axis=False)
    assert info.tool_axes == 0 and svg_glyphs(out) == 0


def test_cli_view_option(tmp_path, capsys):
    prog = tmp_path / "rtcp.nc"
    prog.write_text(RTCP)
    machine = tmp_path / "head.toml"
    machine.write_text('[axes.X]\n[axes.Y]\n[axes.Z]\n[axes.A]\ntype = "rotary"\n[axes.B]\ntype = "rotary"\n'
                       "[[kinematics]]\ntype = 1\n"
                       "[tools.1.1]\nlength = 100.0\n")
    out = tmp_path / "x.png"
    assert main(["plot", str(prog), "-o", str(out), "--machine", str(machine), "--3d", "--view", "tip"]) == 0
    assert "tool-axis glyphs (tip view)" in capsys.readouterr().out
    with pytest.raises(SystemExit):
        main(["plot", str(prog), "-o", str(out), "--view", "part"])
    with pytest.raises(ValueError, match="view"):
        plot_program(prog, out, HEAD_B, view="part")
