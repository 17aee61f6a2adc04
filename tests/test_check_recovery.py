"""``fagorcnc check``'s error recovery (issue 25.2): one extra streamed pass, bounded report.

The control stops at the first error; the check runs the program once more, skipping every
block in error, and lists at most ``max_per_code`` diagnostics of each code ("N more not shown").
"""

from __future__ import annotations

import json

from fagorcnc.cli import main
from fagorcnc.commands import check as check_module
from fagorcnc.commands.check import check_file, text_report
from fagorcnc.interp import interpreter


def beyond(tmp_path, n: int):
    """A move, then ``n`` moves to X2000 (beyond the +1000 mm soft limit of the default machine), M30."""
    f = tmp_path / "beyond.nc"
    f.write_text("G90 G1 X10 F1000\n" + "G1 X2000\n" * n + "M30\n")
    return f


def test_every_error_is_counted_and_the_first_20_of_a_code_listed(tmp_path):
    # 1000 blocks beyond the limit: the first (line 2) stops the control, the 999 others (lines 3..1001)
    # are found by the recovery pass; 20 are listed (lines 2..21), 1000 - 20 = 980 counted
    report = check_file(beyond(tmp_path, 1000))
    assert [d.line for d in report.diagnostics] == list(range(2, 22))
    assert {d.code for d in report.diagnostics} == {"INT100"}
    assert report.recovered == [False] + [True] * 19
    assert report.count("error") == 1000
    assert report.not_shown == {("INT100", "error"): 980}
    text = text_report(report, brief=True)
    assert "980 more INT100 (position beyond a software limit) not shown" in text
    assert "FAIL: 1000 errors" in text


def test_the_number_listed_per_code_is_configurable(tmp_path, capsys):
    f = beyond(tmp_path, 30)
    few = check_file(f, max_per_code=5)   # lines 2..6 listed, 30 - 5 = 25 more
    assert [d.line for d in few.diagnostics] == [2, 3, 4, 5, 6] and few.not_shown == {("INT100", "error"): 25}
    assert main(["check", "--max-per-code", "0", "--format", "json", str(f)]) == 1
    (entry,) = json.loads(capsys.readouterr().out)["files"]
    assert len(entry["diagnostics"]) == 30 and entry["not_shown"] == [] and entry["counts"]["error"] == 30
    assert main(["check", "--max-per-code", "3", "--format", "json", str(f)]) == 1
    (entry,) = json.loads(capsys.readouterr().out)["files"]
    assert entry["not_shown"] == [{"code": "INT100", "severity": "error", "count": 27}]
    assert entry["counts"]["error"] == 30
    assert main(["check", "--max-per-code", "-1", str(f)]) == 2


def test_recovery_is_one_more_streamed_pass_whatever_the_number_of_errors(tmp_path, monkeypatch):
    # today's re-runs blanked one more line each time (up to 25 runs, each holding the whole text): now
    # the check makes two interpreters, the dry run and the recovery pass, both reading the file lazily
    made = []
    init = interpreter.Interpreter.__init__

    def counting(self, program, machine, **kwargs):
        made.append(kwargs.get("stream") is not None)
        init(self, program, machine, **kwargs)

    monkeypatch.setattr(interpreter.Interpreter, "__init__", counting)
    report = check_file(beyond(tmp_path, 200))
    assert report.count("error") == 200
    assert made == [True, True]


def test_recovery_keeps_a_bounded_number_of_diagnostics(tmp_path):
    # the recovery pass's sink keeps at most max_per_code per code: 3 kept of 400 found
    f = beyond(tmp_path, 400)
    findings = check_module.recovery_pass(f, check_module._time_limited(check_module.load_machine(None), None),
                                          False, [], per_code=3)
    assert len(findings.kept) == 3 and findings.more == {("INT100", "error"): 397}


def test_errors_of_different_codes_each_get_their_own_quota(tmp_path):
    # lines 2-4 unknown G function (INT010), lines 5-7 beyond the limit (INT100); 2 listed per code
    f = tmp_path / "mixed.nc"
    f.write_text("G1 X10 F1000\n" + "G1000\n" * 3 + "G1 X2000\n" * 3 + "M30\n")
    report = check_file(f, max_per_code=2)
    assert [(d.line, d.code) for d in report.diagnostics] == [(2, "INT010"), (3, "INT010"), (5, "INT100"),
                                                              (6, "INT100")]
    assert report.not_shown == {("INT010", "error"): 1, ("INT100", "error"): 1}
