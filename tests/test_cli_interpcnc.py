"""`fagorcnc run --backend interpcnc` end to end against the emulator, and `fagorcnc emulate`."""

from __future__ import annotations

import subprocess
import sys
import time
from pathlib import Path

from fagorcnc.backends.interpcnc.emulator import Emulator
from fagorcnc.cli import main

DEMO = Path(__file__).resolve().parents[1] / "programs" / "demo.nc"


def test_run_demo_on_the_emulated_card(tmp_path, capsys):
    machine = tmp_path / "m.toml"
    machine.write_text('[backends.interpcnc]\nresolution = { X = 1000, Y = 1000, Z = 1000 }\n'
                       'outputs = { M3 = { type = 1, output = 0, value = 1 }, '
                       'M5 = { type = 1, output = 0, value = 0 } }\n')
    with Emulator(port=0, speed=200.0, resolution=1000) as emu:
        code = main(["run", "--machine", str(machine), "--backend", "interpcnc", "--port", str(emu.port), str(DEMO)])
        out = capsys.readouterr().out
        executed = emu.executed()
    assert code == 0, out
    assert "OK on back-end interpcnc" in out and "ended by M30" in out
    moves = [e for e in executed if e.kind in ("line", "arc", "rapid")]
    assert len(moves) > 20


def _run_on_the_card(path: Path, capsys) -> tuple[int, str, list, int]:
    """``fagorcnc run --backend interpcnc`` of ``path`` on an emulated card: exit code, output, what the
    card executed and how many Modbus requests it served."""
    with Emulator(port=0, speed=50.0) as emu:
        code = main(["run", "--backend", "interpcnc", "--port", str(emu.port), str(path)])
        out = capsys.readouterr().out
        return code, out, emu.executed(), emu.requests


def test_run_refuses_to_start_on_a_program_with_errors(tmp_path, capsys):
    bad = tmp_path / "bad.nc"
    bad.write_text("G1 X10 F100\nP1 = 1/0\nM30\n")
    code, out, executed, requests = _run_on_the_card(bad, capsys)
    assert code == 1 and "INT033" in out and "nothing was sent" in out
    assert executed == [] and requests == 0


def test_run_sends_nothing_when_an_arc_leaves_the_soft_limits_between_its_end_points(tmp_path, capsys):
    # both end points at X990, the arc bulges to X1010 (default limit +1000): the end-point check (INT100)
    # passes, the planned path does not (PLN100, what check says): nothing may reach the machine
    arc = tmp_path / "arc.nc"
    arc.write_text("G0 X990 Y-20\nG3 X990 Y20 I0 J20 F1000\nM30\n")
    code, out, executed, requests = _run_on_the_card(arc, capsys)
    assert code == 1 and "PLN100" in out and "X 1010.0000" in out and "nothing was sent" in out, out
    assert executed == [] and requests == 0
    # on the simulator the dry run goes through and says so too
    code = main(["run", str(arc)])
    out = capsys.readouterr().out
    assert code == 1 and "PLN100" in out and "leaves the soft limits" in out, out


def test_emulate_command_serves_until_interrupted():
    proc = subprocess.Popen([sys.executable, "-m", "fagorcnc.cli", "emulate", "--port", "0"], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)
    try:
        line = proc.stdout.readline()
        assert "InterpCNC emulator listening on 127.0.0.1:" in line
    finally:
        proc.terminate()
        proc.wait(timeout=10)
    time.sleep(0.1)


def test_a_move_the_card_could_not_take_stops_the_run_before_anything_is_sent(tmp_path, capsys, monkeypatch):
    # the check before a real run asks the back-end about every planned segment (preflight): a stream
    # that would stop half-way on a move the card refuses does not start.  Stand-in: arcs refused.
    from fagorcnc.backends.interpcnc import backend as backend_module
    from fagorcnc.backends.interpcnc.translate import TranslationError

    real = backend_module.segment_moves

    def no_arcs(segment, *args):
        if segment.piece.curved:
            raise TranslationError(f"line {segment.line}: no arcs on this card")
        return real(segment, *args)

    monkeypatch.setattr(backend_module, "segment_moves", no_arcs)
    program = tmp_path / "arc.nc"
    program.write_text("G0 X0 Y0\nG1 X10 F1000\nG2 X20 Y0 I5 J0\nG1 X30\nM30\n")
    code, out, executed, requests = _run_on_the_card(program, capsys)
    assert code == 1 and f"{program}:3:1: CFG004 line 3: no arcs on this card" in out and "nothing was sent" in out
    assert executed == [] and requests == 0
