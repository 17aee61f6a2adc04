"""`fagorcnc check`: the dry-run verifier for CI (text, JSON, SARIF 2.1.0, GitHub annotations)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

import fagorcnc
from fagorcnc.cli import main
from fagorcnc.commands.check import FileReport, check_file, github_report
from fagorcnc.diagnostics import Diagnostic

DEMO = Path(__file__).resolve().parents[1] / "programs" / "demo.nc"

# one program, three kinds of error: the control stops at the first, the checker reports all three
THREE_ERRORS = (
    "G1 X10 F100\n"
    "G1000\n"          # line 2: INT010 unknown G function
    "G1 X2000\n"       # line 3: INT100 beyond the soft limit (+1000 on the default machine)
    "G1 X[1\n"         # line 4: SYN003 syntax error
    "M30\n"
)
EXPECTED = [(2, 1, "INT010"), (3, 4, "INT100"), (4, 7, "SYN003")]


@pytest.fixture
def bad(tmp_path) -> Path:
    f = tmp_path / "bad.nc"
    f.write_text(THREE_ERRORS)
    return f


def _run(capsys, *argv) -> tuple[int, str]:
    status = main(["check", *map(str, argv)])
    return status, capsys.readouterr().out


# --------------------------------------------------------------------------- the three errors, every format
def test_text_reports_syntax_unknown_g_and_soft_limit_errors(bad, capsys):
    status, out = _run(capsys, "--brief", bad)
    assert status == 1
    for line, col, code in EXPECTED:
        assert f"{bad}:{line}:{col}: {code} " in out
    assert f"{bad}: FAIL: 3 errors" in out
    assert "skipping the failing blocks" in out   # the recovered errors are explained


def test_json_reports_all_three_with_file_and_line(bad, capsys):
    status, out = _run(capsys, "--format", "json", bad)
    assert status == 1
    doc = json.loads(out)
    assert doc["schema"] == "fagorcnc-check/1" and doc["ok"] is False
    assert doc["summary"] == {"files": 1, "passed": 0, "failed": 1, "errors": 3, "warnings": 0}
    (f,) = doc["files"]
    assert f["file"] == str(bad) and f["verdict"] == "fail" and f["executed"] is False
    got = [(d["file"], d["line"], d["col"], d["code"], d["severity"]) for d in f["diagnostics"]]
    assert got == [(str(bad), line, col, code, "error") for line, col, code in EXPECTED]
    # the syntax error is what the control reports; the others were found by skipping failing blocks
    assert [d["recovered"] for d in f["diagnostics"]] == [True, True, False]
    assert f["diagnostics"][1]["source"] == "G1 X2000"


def test_github_annotations_for_all_three(bad, capsys):
    status, out = _run(capsys, "--format", "github", bad)
    assert status == 1
    lines = out.splitlines()
    for line, col, code in EXPECTED:
        assert any(s.startswith(f"::error file={bad},line={line},col={col},title={code}::") for s in lines), code
    assert lines[-1].startswith(f"{bad}: FAIL")


def test_sarif_reports_all_three_and_is_valid_sarif_2_1_0(bad, capsys):
    status, out = _run(capsys, "--format", "sarif", bad)
    assert status == 1
    log = json.loads(out)
    validate_sarif(log)
    run = log["runs"][0]
    got = [(r["ruleId"], r["level"], r["locations"][0]["physicalLocation"]["region"]["startLine"],
            r["locations"][0]["physicalLocation"]["region"]["startColumn"]) for r in run["results"]]
    assert got == [(code, "error", line, col) for line, col, code in EXPECTED]
    uris = {r["locations"][0]["physicalLocation"]["artifactLocation"]["uri"] for r in run["results"]}
    assert uris == {bad.as_uri()}
    assert {r["id"] for r in run["tool"]["driver"]["rules"]} == {"INT010", "INT100", "SYN003"}
    assert run["properties"]["files"][0]["verdict"] == "fail"


# --------------------------------------------------------------------------- a minimal SARIF 2.1.0 validator
_LEVELS = {"none", "note", "warning", "error"}


def _obj(value, where: str) -> dict:
    assert isinstance(value, dict), f"{where} must be an object"
    return value


def _message(value, where: str) -> None:
    _obj(value, where)
    assert isinstance(value.get("text"), str) or isinstance(value.get("id"), str), f"{where}: text or id"


def _location(loc: dict, where: str) -> None:
    _obj(loc, where)
    phys = loc.get("physicalLocation")
    if phys is None:
        return
    _obj(phys, f"{where}.physicalLocation")
    assert "artifactLocation" in phys or "address" in phys, f"{where}: artifactLocation or address required"
    art = _obj(phys["artifactLocation"], f"{where}.artifactLocation")
    assert isinstance(art.get("uri"), str) and art["uri"], f"{where}.artifactLocation.uri"
    region = phys.get("region")
    if region is not None:
        _obj(region, f"{where}.region")
        for key in ("startLine", "startColumn", "endLine", "endColumn"):
            if key in region:
                assert isinstance(region[key], int) and region[key] >= 1, f"{where}.region.{key} >= 1"


def validate_sarif(log: dict) -> None:
    """Required properties and types of SARIF 2.1.0 (OASIS standard, §3.13-§3.28) used by a log."""
    _obj(log, "sarifLog")
    assert log.get("version") == "2.1.0"
    assert isinstance(log.get("$schema", ""), str)
    assert isinstance(log.get("runs"), list)
    for i, run in enumerate(log["runs"]):
        _obj(run, f"runs[{i}]")
        driver = _obj(_obj(run.get("tool"), "tool").get("driver"), "tool.driver")
        assert isinstance(driver.get("name"), str) and driver["name"], "tool.driver.name"
        rules = driver.get("rules", [])
        assert isinstance(rules, list)
        for rule in rules:
            assert isinstance(_obj(rule, "rule").get("id"), str)
            if "shortDescription" in rule:
                _message(rule["shortDescription"], "rule.shortDescription")
            if "defaultConfiguration" in rule:
                assert rule["defaultConfiguration"].get("level", "warning") in _LEVELS
        for inv in run.get("invocations", []):
            assert isinstance(_obj(inv, "invocation").get("executionSuccessful"), bool)
            for note in inv.get("toolExecutionNotifications", []):
                _message(_obj(note, "notification").get("message"), "notification.message")
        results = run.get("results", [])
        assert isinstance(results, list)
        for j, res in enumerate(results):
            where = f"results[{j}]"
            _obj(res, where)
            _message(res.get("message"), f"{where}.message")
            assert res.get("level", "warning") in _LEVELS
            if "ruleId" in res:
                assert isinstance(res["ruleId"], str)
            if "ruleIndex" in res:
                k = res["ruleIndex"]
                assert isinstance(k, int) and 0 <= k < len(rules) and rules[k]["id"] == res["ruleId"]
            assert isinstance(res.get("locations", []), list)
            for loc in res.get("locations", []):
                _location(loc, f"{where}.locations")
        assert isinstance(run.get("properties", {}), dict)


# --------------------------------------------------------------------------- verdicts and exit status
def test_clean_program_passes_with_its_summary(capsys):
    status, out = _run(capsys, "--format", "json", DEMO)
    assert status == 0
    (f,) = json.loads(out)["files"]
    assert f["verdict"] == "pass" and f["complete"] and f["ended_by"] == "M30"
    assert f["tools"] == [{"tool": 1, "loaded": True, "offsets": [1], "lines": [8]}]
    assert [o["origin"] for o in f["offsets"]] == ["G54"]
    (box,) = f["bbox"]
    # demo.nc: tool-centre path 80 x 50 mm around part zero plus the 0.5 mm stock of the roughing passes
    assert box["tool"] == 1
    assert box["feed"]["part"]["min"] == {"X": -60.0, "Y": -25.5, "Z": -6.0}
    assert box["feed"]["part"]["max"] == {"X": 40.5, "Y": 25.5, "Z": 5.0}
    assert box["machine"]["max"]["Z"] == 50.0
    assert f["cycle_time"] == pytest.approx(fagorcnc.simulate(DEMO).cycle_time, abs=0.05)


def test_fail_on_warning(tmp_path, capsys):
    f = tmp_path / "warn.nc"
    f.write_text("#CD ON [5]\nG1 X10 F1000\nM30\n")
    status, out = _run(capsys, "--format", "json", f)
    doc = json.loads(out)
    assert status == 0 and doc["files"][0]["verdict"] == "pass"
    assert doc["files"][0]["unsupported"][0]["code"] == "INT078"
    assert doc["files"][0]["unsupported"][0]["lines"] == [1]
    status, out = _run(capsys, "--fail-on", "warning", "--brief", f)
    assert status == 1
    assert f"{f}:1:1: INT078 warning:" in out and "FAIL: 0 errors, 1 warnings" in out


def test_max_cycle_time(capsys):
    status, out = _run(capsys, "--brief", "--max-cycle-time", "60", DEMO)
    assert status == 1
    assert f"{DEMO}:1:1: PLN101 planned cycle time {_demo_time()}" in out and "OVER the limit of 60 s" in out
    status, out = _run(capsys, "--format", "json", "--max-cycle-time", "600", DEMO)
    f = json.loads(out)["files"][0]
    assert status == 0 and f["max_cycle_time"] == 600.0 and f["cycle_time_exceeded"] is False


def test_arc_beyond_the_soft_limit_between_its_end_points_is_pln100(tmp_path, capsys):
    f = tmp_path / "arc.nc"
    # both end points at X990, the arc bulges to X1010 (limit +1000): the interpreter's end-point check passes
    f.write_text("G0 X990 Y-20\nG3 X990 Y20 I0 J20 F1000\nM30\n")
    status, out = _run(capsys, "--brief", "-q", f)
    assert status == 1
    assert (f"{f}:2:1: PLN100 the arc of this block reaches X 1010.0000 (machine), beyond its upper soft "
            f"limit 1000") in out


def test_many_files_in_parallel_keep_the_input_order(tmp_path, capsys):
    files = []
    for i in range(6):
        f = tmp_path / f"p{i}.nc"
        # the first files are the longest: with two workers the later ones finish first
        body = "".join(f"G1 X{(k % 7) * 10} Y{k % 5} F{2000 + i}\n" for k in range(200 - 30 * i))
        f.write_text(body + ("G1000\n" if i == 3 else "") + "M30\n")
        files.append(f)
    status, out = _run(capsys, "--jobs", "2", "--format", "json", *files)
    assert status == 1
    doc = json.loads(out)
    assert [f["file"] for f in doc["files"]] == [str(f) for f in files]
    assert [f["verdict"] for f in doc["files"]] == ["pass", "pass", "pass", "fail", "pass", "pass"]
    status, out = _run(capsys, "-j", "2", "-q", "--brief", *files)
    verdicts = [s.split(":")[0] for s in out.splitlines() if ": PASS" in s or ": FAIL" in s]
    assert verdicts == [str(f) for f in files]
    status1, out1 = _run(capsys, "--jobs", "1", "--format", "json", *files)
    assert status1 == 1 and json.loads(out1)["files"] == doc["files"]


def test_usage_errors_exit_2(tmp_path, bad, capsys):
    assert main(["check", str(tmp_path / "missing.nc"), str(bad)]) == 2
    captured = capsys.readouterr()
    assert "missing.nc: cannot read the file" in captured.err
    assert f"{bad}: FAIL" in captured.out   # the other files are still checked
    machine = tmp_path / "m.toml"
    machine.write_text("[axes.X]\nmax_velocity = -1\n")
    assert main(["check", "--machine", str(machine), str(bad)]) == 2
    assert "max_velocity" in capsys.readouterr().err
    assert main(["check", "--jobs", "0", str(bad)]) == 2
    with pytest.raises(SystemExit) as exc:
        main(["check", "--format", "xml", str(bad)])
    assert exc.value.code == 2


def test_unreadable_file_is_a_sarif_tool_notification(tmp_path, capsys):
    status, out = _run(capsys, "--format", "sarif", tmp_path / "missing.nc")
    assert status == 2
    log = json.loads(out)
    validate_sarif(log)
    inv = log["runs"][0]["invocations"][0]
    assert inv["executionSuccessful"] is False and "cannot read" in inv["toolExecutionNotifications"][0]["message"][
        "text"]


def test_report_written_to_a_file(tmp_path, bad, capsys):
    out = tmp_path / "report.sarif"
    assert main(["check", "--format", "sarif", "-o", str(out), str(bad)]) == 1
    assert capsys.readouterr().out == ""
    validate_sarif(json.loads(out.read_text()))


# --------------------------------------------------------------------------- GitHub workflow-command escaping
def test_github_escapes_data_and_properties():
    d = Diagnostic("dir,a:b/x%.nc", 3, 2, "INT070", "error", "100% done\r\nnext, line: two")
    report = FileReport("dir,a:b/x%.nc", diagnostics=[d], recovered=[False], executed=True, complete=False)
    first = github_report(report).splitlines()[0]
    assert first == ("::error file=dir%2Ca%3Ab/x%25.nc,line=3,col=2,title=INT070::100%25 done%0D%0Anext, line: two")


def test_check_file_api_never_raises(tmp_path):
    r = check_file(tmp_path / "nope.nc")
    assert r.verdict() == "unreadable" and r.usage_error
    r = check_file(DEMO, {"axes": {"X": {}, "Y": {}, "Z": {"max_limit": 10.0}}})
    assert r.verdict() == "fail" and r.diagnostics[0].code == "INT100"


def _demo_time() -> str:
    """The demo's planned cycle time as the reports print it (m:ss.s)."""
    minutes, seconds = divmod(fagorcnc.simulate(DEMO).cycle_time, 60.0)
    return f"{int(minutes)}:{seconds:04.1f}"


def test_an_empty_file_or_one_of_comments_only_fails_the_check(tmp_path, capsys):
    # a post-processor that crashed leaves an empty or truncated file: CI must not pass it
    for name, text in (("empty.nc", ""), ("comments.nc", "; T1 D=6 FLAT END MILL\n\n(nothing else)\n")):
        f = tmp_path / name
        f.write_text(text)
        status, out = _run(capsys, "--brief", "-q", f)
        assert status == 1 and f"{f}:1:1: STR012" in out, out
    # a program of blocks without motion is a program: only the missing M30 is said
    f = tmp_path / "params.nc"
    f.write_text("P1=2\n")
    status, out = _run(capsys, "--brief", "-q", f)
    assert status == 0 and "STR012" not in out and "INT098" in out


def test_sarif_uris_have_no_dot_dot(tmp_path, capsys, monkeypatch):
    # code scanning maps a result to a file of the repository by a path relative to its root: '../' maps nowhere
    (tmp_path / "sub").mkdir()
    f = tmp_path / "x.nc"
    f.write_text("G1 X10\nM30\n")   # INT060: no feed

    def uris(name: str) -> set[str]:
        _, out = _run(capsys, "--format", "sarif", name)
        return {loc["physicalLocation"]["artifactLocation"]["uri"]
                for run in json.loads(out)["runs"] for res in run["results"] for loc in res["locations"]}

    monkeypatch.chdir(tmp_path)
    assert uris("sub/../x.nc") == {"x.nc"}
    monkeypatch.chdir(tmp_path / "sub")   # outside the working directory: absolute
    assert uris("../x.nc") == {f.resolve().as_uri()}
