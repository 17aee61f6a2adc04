"""fagorcnc init and the machine templates of examples/machines."""

from __future__ import annotations

from pathlib import Path

import pytest

from fagorcnc.cli import main
from fagorcnc.commands.init import KINDS, template, template_dir
from fagorcnc.config.machine import load_machine
from fagorcnc.simulate import simulate

EXAMPLES = Path(__file__).resolve().parents[1] / "examples" / "machines"

PROGRAMS = {
    "mill3": "G54 T1 D1 M06\nG0 X0 Y0 Z10\nG1 Z-2 F300\nG2 X20 Y0 I10 J0 F800\nM30\n",
    "router": "G54 T1 D1 M06\nG0 X0 Y0 Z10\nG1 Z-2 F3000\nG1 X1000 Y500\nM30\n",
    "mill5-ac": "G54 T1 D1 M06\nG0 X0 Y0 Z50\nG1 A-30 C90 F2000\nG1 X10 Y10 Z20\nM30\n",
    "interpcnc": "G54 T1 D1 M06\nS1000 M3\nG0 X0 Y0 Z10\nG1 Z-1 F200\nG1 X100\nM5\nM30\n",
    "lathe": "G54 T1 D1\nG0 X40 Z5\nG1 Z-20 F200\nG2 X60 Z-30 R10\nM30\n",
}


@pytest.mark.parametrize("kind", sorted(KINDS))
def test_every_template_loads_and_runs_a_program(kind):
    path = EXAMPLES / f"{kind}.toml"
    assert path.is_file() and template(kind) == path.read_text(encoding="utf-8")
    machine = load_machine(path)
    result = simulate(PROGRAMS[kind], machine)
    assert result.ok, [str(d) for d in result.diagnostics]
    assert template_dir().is_dir()


def test_the_lathe_works_in_g18(tmp_path):
    machine = load_machine(EXAMPLES / "lathe.toml")
    assert machine.axis_names == ["X", "Z"] and machine.axes["X"].diameter
    arc = next(m for m in simulate(PROGRAMS["lathe"], machine).moves if m.kind == "arc")
    # seed 002 L3013-L3043: a two-axis lathe works in G18 formed by Z (abscissa) and X (ordinate).
    # G2 X60 Z-30 R10 from X40 Z-20 (diameters: radius 20 to 30): in the plane (Z, X) the chord goes
    # from (-20, 20) to (-30, 30); the clockwise arc of radius 10 has its centre at (-20, 30)
    assert arc.plane[:2] == ("Z", "X")
    assert arc.center_part["Z"] == pytest.approx(-20.0) and arc.center_part["X"] == pytest.approx(30.0)


def test_init_writes_a_template_and_keeps_an_existing_file(tmp_path, capsys):
    out = tmp_path / "m.toml"
    assert main(["init", "--kind", "router", "-o", str(out)]) == 0
    assert out.read_text() == (EXAMPLES / "router.toml").read_text()
    assert main(["init", "--kind", "lathe", "-o", str(out)]) == 2
    assert "exists" in capsys.readouterr().err
    assert main(["init", "--kind", "lathe", "-o", str(out), "--force"]) == 0
    assert load_machine(out).axis_names == ["X", "Z"]
