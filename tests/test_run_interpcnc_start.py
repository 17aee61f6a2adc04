"""`run` on the InterpCNC: what is said and refused before the start, and progress that follows the card (issue 25
items 3 and 4), and the streaming figures the run reports (issue 29)."""

from __future__ import annotations

import fagorcnc
from fagorcnc.backends.interpcnc.emulator import Emulator
from fagorcnc.backends.interpcnc.refusals import refused_transformations
from fagorcnc.cli import main
from fagorcnc.commands.run import _ProgressBar


def test_an_m_function_without_output_is_reported_before_the_first_command(tmp_path, capsys):
    prog = tmp_path / "p.nc"
    prog.write_text("G90 G1 X5 F3000\nM8\nG1 X10\nM30\n")
    seen: list = []
    with Emulator(port=0, speed=50.0) as emu:
        def before(warnings) -> None:        # called before anything is sent: the card has received nothing
            seen.append(([d.code for d in warnings], emu.requests))

        report = fagorcnc.run(prog, backend="interpcnc", port=emu.port, before_start=before)
        assert report.ok
        assert seen == [(["CFG003"], 0)]
        # the CLI prints it first, once: before the summary line, not repeated after the run
        code = main(["run", "--backend", "interpcnc", "--port", str(emu.port), str(prog)])
    out = capsys.readouterr().out
    assert code == 0
    assert out.count("CFG003") == 1 and out.index("CFG003") < out.index("OK on back-end interpcnc")
    assert "segments/s sustained" in out and "underruns seen" in out


def test_kinematics_the_card_cannot_reproduce_are_refused_before_anything_is_sent(tmp_path, capsys):
    prog = tmp_path / "k.nc"
    prog.write_text("G90 G1 X5 F3000\n#RTCP ON\nG1 X10\n#RTCP OFF\nM30\n")
    with Emulator(port=0, speed=50.0) as emu:
        report = fagorcnc.run(prog, backend="interpcnc", port=emu.port)
        assert not report.ok and report.stopped_by == "error" and "nothing was sent" in report.message
        cfg = [d for d in report.diagnostics if d.code == "CFG030"]
        assert len(cfg) == 1 and cfg[0].line == 2 and cfg[0].is_error and "#RTCP" in cfg[0].message
        code = main(["run", "--backend", "interpcnc", "--port", str(emu.port), str(prog)])
        assert emu.requests == 0 and emu.executed() == []
    out = capsys.readouterr().out
    assert code == 1 and "CFG030" in out
    # the simulator keeps the warning: offline, the moves are planned as programmed
    assert fagorcnc.run(prog).ok


def test_the_refused_sentences_are_read_from_the_interpreter_warning():
    # #KIN ID on a machine file without kinematics runs as the identity offline (KIN024): refused on a card;
    # #CD (INT078) runs as programmed; a computed #CS is sent as the machine moves it gives
    result = fagorcnc.simulate("#KIN ID [1]\n#CS ON [1] [MODE 1, 0, 0, 0, 0, 0, 0]\n#CD ON [5]\nG1 X1 F100\nM30\n")
    codes = [(d.line, d.code) for d in result.diagnostics if d.code in ("INT078", "KIN024")]
    assert codes == [(1, "KIN024"), (3, "INT078")]
    refused = refused_transformations(result.diagnostics)
    assert [d.line for d in refused][:1] == [1] and all(d.code == "CFG030" for d in refused)
    assert 3 not in [d.line for d in refused]                # #CD: the moves run as programmed (a warning)


class _Seg:
    def __init__(self, t0: float, duration: float) -> None:
        self.t0, self.duration = t0, duration


class _St:
    def __init__(self, executed: int, line: int) -> None:
        self.executed, self.line = executed, line


def test_progress_follows_what_the_card_executed_not_what_was_sent():
    class Out:
        text = ""

        def write(self, s: str) -> None:
            self.text = s

        def flush(self) -> None:
            pass

    out = Out()
    bar = _ProgressBar(out, "p.nc")
    ticks = iter(range(1, 1000))
    bar.clock = lambda: float(next(ticks))        # every call 1 s later: never throttled
    # 10 segments of 1 s planned (total 10 s) all sent, the card has executed 2: 20 %, not 100 %
    for k in range(10):
        bar(_Seg(float(k), 1.0), _St(min(k, 2), 3), 10.0)
    assert " 20%" in out.text and "line      3" in out.text
    # then, while finish() waits (no segment), the card executes up to 8: 80 %
    bar(None, _St(8, 9), 10.0)
    assert " 80%" in out.text and "line      9" in out.text


def test_run_reports_progress_while_the_card_finishes(tmp_path):
    prog = tmp_path / "p.nc"
    prog.write_text("G90 G1 X5 F600\nG1 X10\nG1 X0\nM30\n")      # 20 mm at 10 mm/s: 2 s, / 4 = 0.5 s
    calls: list = []
    with Emulator(port=0, speed=4.0) as emu:
        report = fagorcnc.run(prog, backend="interpcnc", port=emu.port,
                              progress=lambda seg, st, total: calls.append((seg is None, st.executed)))
    assert report.ok
    waiting = [executed for none, executed in calls if none]
    assert waiting, "no progress while the card ran what had been sent"
    assert waiting == sorted(waiting) and waiting[-1] >= 3
