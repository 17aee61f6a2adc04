"""Canned cycles end to end: a program in the Autodesk FAGOR 8065 post's form through `fagorcnc check`,
the shipped drilling-and-pocket demo through run/check/plot, and cycles on the emulated InterpCNC card."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from fagorcnc.backends.interpcnc.emulator import Emulator
from fagorcnc.cli import main

DEMO = Path(__file__).resolve().parents[1] / "programs" / "drilling_pocket.nc"

#: What the Autodesk "FAGOR 8058/8060/8065/8070" post writes for drilling, peck drilling, chip breaking,
#: rigid tapping (with and without pecks), reaming and boring: G98 G8x X Y Z I [..] F, then bare X Y
#: points, G80 at the end of each cycle, G17 G94 before it, #MSG[""] between operations.
AUTODESK = """%DRILL01
; POST: FAGOR 8058/8060/8065/8070
N10 G71 G90 G17 G94
N15 G40
N20 T3 D1 M06
N25 S1200 M03
N30 G54
N35 G0 X10. Y10.
N40 G0 Z50.
N45 M08
N50 G17 G94
N55 G98 G81 X10. Y10. Z5. I-12. K0.5 F150.
N60 X30. Y10.
N65 X50. Y10.
N70 G80
N75 G17 G94
N80 G98 G83 X10.Y30. Z5. I-4.25 J4 F120.
N85 X30. Y30.
N90 G80
N95 G17 G94
N100 G98 G82 X50. Y30. Z5. I-20. B5. D2. H1. J3 K0.2 L1.5 R0.8 F100.
N105 G80
N110 M09
#MSG[""]
N120 T4 D1 M06
N125 S500 M03
N130 G0 X10. Y50.
N135 G0 Z50.
N140 G17 G94
N145 G98 G84 X10. Y50. Z5. I-10. R1 F750.
N150 X30. Y50.
N155 G80
N160 G98 G84 X50. Y50. Z5. I-10. B3. R1 F750.
N165 G80
#MSG[""]
N170 T5 D1 M06
N175 S800 M03
N180 G0 X70. Y10.
N185 G0 Z50.
N190 G98 G85 X70. Y10. Z5. I-15. F80.
N195 G80
N200 G98 G86 X70. Y30. Z5. I-15. K1. F60.
N205 G80
N210 G98 G86 X70. Y50. Z5. I-15. F60.
N215 G80
N220 M05
N225 G0 Z100.
N230 M30
"""


def test_autodesk_post_form_checks_clean(tmp_path, capsys):
    path = tmp_path / "drill01.nc"
    path.write_text(AUTODESK)
    assert main(["check", "--format", "json", str(path)]) == 0
    report = json.loads(capsys.readouterr().out)["files"][0]
    assert report["verdict"] == "pass" and report["counts"]["error"] == 0 and report["counts"]["warning"] == 0
    assert {d["code"] for d in report["diagnostics"]} == {"INT077"}   # the post's empty #MSG[""], as a note
    assert report["ended_by"] == "M30"
    got = [(c["code"], c["line"], c["holes"]) for c in report["cycles"]]
    assert got == [("G81", 12, 3), ("G83", 17, 2), ("G82", 21, 1), ("G84", 30, 2), ("G84", 33, 1), ("G85", 40, 1),
                   ("G86", 42, 1), ("G86", 44, 1)]
    # the deepest point: G82 I-20; the G83 bottom is Zr + I*J = 5 - 4.25*4 = -12
    part = report["bbox"][0]["feed"]["part"]
    assert part["min"]["Z"] == -20.0 and part["max"]["X"] == 50.0


def test_check_text_report_lists_the_cycles(tmp_path, capsys):
    path = tmp_path / "drill01.nc"
    path.write_text(AUTODESK)
    assert main(["check", str(path)]) == 0
    assert "canned cycles: G81 line 12 (3 holes), G83 line 17 (2 holes)" in capsys.readouterr().out


def test_demo_runs_checks_and_plots(tmp_path, capsys):
    assert main(["check", "--format", "json", str(DEMO)]) == 0
    report = json.loads(capsys.readouterr().out)["files"][0]
    # the one warning: G211's provisional semantics (CYC020)
    assert report["verdict"] == "pass" and report["counts"]["warning"] == 1
    assert [d["code"] for d in report["diagnostics"]] == ["CYC020"]
    # G81 + G160 K4: 4 holes; G83: 1; G81 + G163 K6: 6; G84 + G160: 4; one pocket each; one thread
    assert [(c["code"], c["holes"]) for c in report["cycles"]] == [
        ("G81", 4), ("G83", 1), ("G81", 6), ("G84", 4), ("G87", 1), ("G88", 1), ("G211", 1)]
    assert main(["run", str(DEMO)]) == 0
    assert "ended by M30" in capsys.readouterr().out


def test_demo_plot_shows_the_holes(tmp_path):
    pytest.importorskip("matplotlib")
    svg = tmp_path / "demo.svg"
    assert main(["plot", str(DEMO), "-o", str(svg)]) == 0
    assert "plunge / hole" in svg.read_text()


def test_cycles_reach_the_card_as_plain_moves_dwells_and_spindle_outputs(tmp_path, capsys):
    machine = tmp_path / "m.toml"
    machine.write_text('[backends.interpcnc]\nresolution = { X = 1000, Y = 1000, Z = 1000 }\n'
                       'outputs = { M3 = { type = 1, output = 0, value = 1 }, '
                       'M5 = { type = 1, output = 0, value = 0 } }\n')
    program = tmp_path / "holes.nc"
    program.write_text("S800 M3\nG0 X0 Y0 Z10\nG98 G81 X5 Z2 I-3 K0.2 F600\nX10\nG86 X15 Z2 I-3 F600\nG80\nM30\n")
    with Emulator(port=0, speed=200.0, resolution=1000) as emu:
        code = main(["run", "--machine", str(machine), "--backend", "interpcnc", "--port", str(emu.port),
                     str(program)])
        out = capsys.readouterr().out
        executed = emu.executed()
    assert code == 0, out
    kinds = [e.kind for e in executed]
    # 2 G81 holes (rapid, rapid, feed, dwell K0.2, rapid) and G86 (rapid, rapid, feed, M5, rapid, M3)
    assert kinds.count("line") == 3 and kinds.count("dwell") == 2, kinds
    assert [e.args["ms"] for e in executed if e.kind == "dwell"] == [200, 200]
    spindle = [e.args["b"] for e in executed if e.kind == "action" and e.args["type"] == 1]
    assert spindle[:3] == [1, 0, 1]   # M3 of the program, then G86's M5 at the bottom and M3 after the rapid out
