"""`fagorcnc plot`: the planned tool path as a picture (matplotlib is optional)."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

import fagorcnc
from fagorcnc.cli import main

DEMO = Path(__file__).resolve().parents[1] / "programs" / "demo.nc"


def test_without_matplotlib_plot_says_so_and_exits_2(tmp_path, monkeypatch, capsys):
    for name in [m for m in sys.modules if m == "matplotlib" or m.startswith("matplotlib.")]:
        monkeypatch.delitem(sys.modules, name)
    monkeypatch.setitem(sys.modules, "matplotlib", None)   # import matplotlib -> ImportError
    out = tmp_path / "demo.png"
    assert main(["plot", str(DEMO), "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert "needs matplotlib" in err and "fagorcnc[plot]" in err
    assert not out.exists()


def test_demo_png(tmp_path, capsys):
    pytest.importorskip("matplotlib")
    out = tmp_path / "demo.png"
    assert main(["plot", str(DEMO), "-o", str(out)]) == 0
    data = out.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 10_000
    assert f"planned segments, cycle time {_demo_time()}" in capsys.readouterr().out


def test_demo_svg_and_3d(tmp_path):
    pytest.importorskip("matplotlib")
    svg = tmp_path / "demo.svg"
    assert main(["plot", str(DEMO), "-o", str(svg)]) == 0
    text = svg.read_text()
    assert "<svg" in text and "demo.nc" in text and f"cycle time {_demo_time()}" in text
    png = tmp_path / "demo3d.png"
    assert main(["plot", str(DEMO), "-o", str(png), "--3d"]) == 0
    assert png.stat().st_size > 10_000


def test_compensated_path_draws_the_programmed_contour(tmp_path):
    pytest.importorskip("matplotlib")
    from fagorcnc.commands.plot import plot_program

    prog = tmp_path / "comp.nc"
    prog.write_text("T1 D1 M6\nG0 X0 Y0\nG1 G41 X10 Y10 F500\nG1 X50\nG2 X60 Y0 R10\nG1 Y-20\nG1 X10\n"
                    "G1 Y10\nG1 G40 X0 Y0\nM30\n")
    info = plot_program(prog, tmp_path / "comp.svg", {"tools": {"1": {"1": {"radius": 5.0}}}}, plane="XY")
    assert info.ok and info.programmed and info.segments > 6
    info = plot_program(prog, tmp_path / "nocomp.svg", {"tools": {"1": {"1": {"radius": 5.0}}}}, programmed=False)
    assert not info.programmed


def test_plot_usage_errors(tmp_path, capsys):
    pytest.importorskip("matplotlib")
    assert main(["plot", str(DEMO), "-o", str(tmp_path / "demo.jpeg")]) == 2
    assert "must be .png, .svg, .pdf" in capsys.readouterr().err
    assert main(["plot", str(DEMO), "-o", str(tmp_path / "x.png"), "--plane", "XQ"]) == 2
    assert main(["plot", str(tmp_path / "missing.nc"), "-o", str(tmp_path / "x.png")]) == 2


def test_program_with_errors_is_drawn_up_to_the_error_and_exits_1(tmp_path, capsys):
    pytest.importorskip("matplotlib")
    prog = tmp_path / "bad.nc"
    prog.write_text("G1 X10 Y10 F1000\nG1 X2000\nM30\n")
    out = tmp_path / "bad.png"
    assert main(["plot", str(prog), "-o", str(out)]) == 1
    assert out.stat().st_size > 0 and "INT100" in capsys.readouterr().err


def _demo_time() -> str:
    """The demo's planned cycle time as the plot title prints it (m:ss.s)."""
    minutes, seconds = divmod(fagorcnc.simulate(DEMO).cycle_time, 60.0)
    return f"{int(minutes)}:{seconds:04.1f}"
