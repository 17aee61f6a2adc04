"""fagorcnc view: the self-contained HTML preview, and its behaviour in a real headless Chromium."""

from __future__ import annotations

import os
import re
from pathlib import Path

import pytest
from chromium import Chromium

from fagorcnc.cli import main
from fagorcnc.commands.view import view_data, write_view

DEMO = Path(__file__).resolve().parents[1] / "programs" / "demo.nc"
BAD = "G0 X0 Y0 Z0\nG1 X10 F100\nG1 Y20\nG1 X2000\nM30\n"


def test_the_data_follows_the_plan(tmp_path):
    data = view_data(DEMO)
    assert data["ok"] and data["failing"] is None
    assert data["segments"] and data["lines"][0] == "%DEMO"
    assert {s["line"] for s in data["segments"]} >= {11, 12, 13, 19, 22}
    assert data["limits"] == {"min": [-1000.0, -1000.0, -1000.0], "max": [1000.0, 1000.0, 1000.0]}
    for before, after in zip(data["segments"], data["segments"][1:], strict=False):
        assert after["t0"] == pytest.approx(before["t0"] + before["duration"], abs=2e-4)


def test_the_failing_block_is_marked(tmp_path):
    bad = tmp_path / "bad.nc"
    bad.write_text(BAD)
    data = view_data(bad)
    assert data["failing"]["line"] == 4 and data["failing"]["code"] == "INT100"
    assert data["failing"]["point"] == [10.0, 20.0, 0.0]   # where the tool stands: the end of line 3
    assert main(["view", str(bad), "-o", str(tmp_path / "bad.html")]) == 1


def test_the_page_is_self_contained(tmp_path):
    out = tmp_path / "demo.html"
    assert main(["view", str(DEMO), "-o", str(out)]) == 0
    page = out.read_text()
    assert "<script src" not in page and "<link" not in page
    assert not re.search(r"""(src|href)\s*=\s*["']?(https?:)?//""", page)
    assert "default-src 'none'" in page   # the page itself forbids any request


# CI (.ci/run installs Debian's chromium) always runs it; elsewhere it is skipped, saying why, without one
@pytest.mark.skipif(Chromium.find() is None and not os.environ.get("CI"),
                    reason="chromium is not installed (apt-get install chromium): the preview's browser test needs "
                           "a real headless browser")
def test_click_a_segment_then_a_line_in_chromium(tmp_path):
    bad = tmp_path / "bad.nc"
    bad.write_text(BAD)
    out = tmp_path / "bad.html"
    data = write_view(bad, out)
    with Chromium() as browser:
        page = browser.open(out.as_uri())
        page.wait_for("window.fagorcncView")
        # the failing block is marked in the text and selected at the start
        assert page.evaluate("document.querySelector('.line.failing').dataset.line") == "4"
        # a click on the path (the middle of the segment of line 3) selects line 3
        index = next(i for i, s in enumerate(data["segments"]) if s["line"] == 3)
        x, y = page.evaluate(f"window.fagorcncView.screenPoint({index})")
        page.click(x, y)
        assert page.evaluate("window.fagorcncView.selectedLine()") == 3
        assert page.evaluate("document.querySelector('.line.hl').dataset.line") == "3"
        # a click on line 2 of the text selects it (and its path)
        box = page.evaluate("(() => { const r = document.querySelector('.line[data-line=\"2\"]')"
                            ".getBoundingClientRect(); return [r.left + 20, r.top + r.height / 2]; })()")
        page.click(*box)
        assert page.evaluate("window.fagorcncView.selectedLine()") == 2
        assert page.evaluate("document.querySelectorAll('.line.hl').length") == 1
        # scrub: at time 0 nothing is drawn yet, so a click on the path finds nothing
        page.evaluate("window.fagorcncView.setTime(0)")
        assert page.evaluate("document.getElementById('clock').textContent").startswith("0.00 s")
        page.click(x, y)
        assert page.evaluate("window.fagorcncView.selectedLine()") == 2
