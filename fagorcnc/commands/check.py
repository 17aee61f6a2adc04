"""``fagorcnc check``: the dry-run verifier for CI.

Every program is parsed, interpreted and planned offline on a machine configuration, in
one stream (:func:`fagorcnc.simulate.dry_run`: interpreted once, planned once, in memory
that does not grow with the program) and reported on:

* **diagnostics** (syntax, structure, interpreter, planner), including the
  soft-limit check of every programmed end point (``INT100``) and an envelope
  check of the *planned* path: an arc or a corner blend whose interior goes
  beyond a soft limit although its end points do not is ``PLN100``;
* **error recovery**: the control stops at the first error, so a check would
  show one error at a time.  After an error the verifier runs the program once
  more, streamed, skipping every block in error as if its line were blank
  (:mod:`fagorcnc.commands.recovery`), to report the errors further on; those
  are marked ``recovered`` (they may be consequences of a skipped block).  At
  most ``--max-per-code`` diagnostics of each code are listed, the others are
  counted (``not_shown``).  Everything else in the report (tools, boxes, cycle
  time) describes the program as the control would run it: up to its first error;
* **unsupported features**: the warnings that say fagorcnc does not compute
  something (``INT011``, ``INT078``, ``INT079``, ``INT115``), grouped;
* **tools** (T selected, loaded by M06, D offsets used) and **work offsets**
  (G54..G59, G159=n, G92, G53 active while the moves ran);
* the **bounding box per tool**: extent of the motion (rapids and feeds, and
  feeds alone) while each tool was in the spindle, in machine and in part
  coordinates (arc extremes included; T0 = no tool);
* the **planned cycle time** and, with ``--max-cycle-time``, whether it is over
  the limit (``PLN101``);
* a **time limit** on the interpretation of each run (``--max-seconds``, else
  the machine's ``limits.max_seconds``, else :data:`CHECK_MAX_SECONDS`): a
  runaway program fails with ``INT082`` at the block it was running instead of
  holding the CI job until the block limit;
* a **verdict** per file: ``pass``, ``fail`` (an error; a warning too with
  ``--fail-on warning``), ``unreadable`` (usage error) or ``crashed`` (internal
  error of fagorcnc).

Exit status of the command: 0 all files pass, 1 some file fails (or crashed),
2 usage error (unreadable file, bad option, bad machine file).  Files are
checked in parallel (``--jobs``, one process each) and reported in input order.

JSON report (``--format json``), schema ``fagorcnc-check/1``; keys are stable,
new keys may be added::

    {"schema": "fagorcnc-check/1", "tool": "fagorcnc", "version": "0.1.0",
     "machine": "m.toml" | null, "fail_on": "error" | "warning",
     "ok": true,                      # every file passed
     "summary": {"files": 3, "passed": 2, "failed": 1, "errors": 4, "warnings": 1},
     "files": [{
        "file": "part.nc", "verdict": "pass" | "fail" | "unreadable" | "crashed",
        "failure": null | "why the file could not be checked",
        "executed": true,             # false: syntax errors, the control would not start it
        "complete": true,             # ran to its end without error (else: stopped at its first error)
        "ended_by": "M30" | null, "moves": 63,
        "ending": {"cause": "M30" | "M02" | "end of file" | "error" | "not started" | ..., "line": 0,
                   "alarm": 0, "file": null, "text": "error at line 12"},   # fagorcnc.summary.Ending
        "cycle_time": 91.777,         # s, planned (jerk-limited), up to the first error
        "max_cycle_time": 60.0 | null, "cycle_time_exceeded": false,
        "counts": {"error": 0, "warning": 1, "info": 0},   # found, listed or not
        "not_shown": [{"code": "INT100", "severity": "error", "count": 99980}],   # beyond --max-per-code
        "diagnostics": [{"file": "part.nc", "line": 3, "col": 1, "code": "INT010",
                         "severity": "error" | "warning" | "info", "message": "...",
                         "source": "G1000", "recovered": false}],
        "unsupported": [{"code": "INT078", "description": "...", "message": "...", "lines": [17, 40]}],
        "tools": [{"tool": 1, "loaded": true, "offsets": [1], "lines": [8]}],
        "offsets": [{"origin": "G54", "first_line": 11, "moves": 57}],
        "cycles": [{"code": "G81", "line": 14, "holes": 12}],   # canned cycles run, per definition
        "bbox": [{"tool": 1,
                  "machine": {"min": {"X": -60.0, ...}, "max": {...}},
                  "part": {"min": {...}, "max": {...}},
                  "feed": {"machine": {...}, "part": {...}} | null}]}]}

SARIF 2.1.0 (``--format sarif``): one run, ``tool.driver`` = fagorcnc with one
rule per code reported, one result per diagnostic (``ruleId``, ``ruleIndex``,
``level`` error/warning/note, ``message.text``, a physical location with
``startLine``/``startColumn``); files that could not be checked are
``invocations[0].toolExecutionNotifications``; the per-file summaries (tools,
boxes, cycle time, verdict: the JSON ``files`` entries without diagnostics)
are in ``runs[0].properties.files``.  GitHub Actions (``--format github``):
one workflow command per diagnostic (``::error file=F,line=L,col=C,title=CODE::message``,
``::warning``, ``::notice`` for notes with ``-v``) then one summary line per file.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import os
import sys
import tempfile
from collections.abc import Iterable, Iterator, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ..config.machine import Machine, MachineError, load_machine
from ..diagnostics import CODES, Diagnostic
from ..program_files import PROGRAM_EXTENSIONS, program_files
from ..summary import Ending, RunSummary
from ._shared import STDIN_NAME, clock, command_machine, stdin_copy
from .extents import Box, OriginUse, ToolBox, ToolUse, _round, arc_points  # noqa: F401 - public names
from .extents import MoveSummary as _Summary
from .recovery import BUDGET_CODES, MAX_PER_CODE, recovery_pass  # noqa: F401 - BUDGET_CODES: public name

#: Codes of the warnings that say fagorcnc does not model something.
UNSUPPORTED = ("INT011", "INT078", "INT079", "INT115")
#: Seconds of interpretation (CPU time of the checking process, so a busy runner does not bring
#: the limit closer) per run when neither --max-seconds nor the machine's limits.max_seconds sets
#: a limit.  A CI job wants a verdict in minutes: 120 s of CPU interpret about 3 million blocks
#: (the check streams in constant memory, so a longer CAM program only needs a larger
#: --max-seconds), while an endless $GOTO loop of moves stops there instead of running on to
#: limits.max_blocks (an hour or more).
CHECK_MAX_SECONDS = 120.0
SCHEMA = "fagorcnc-check/1"
SARIF_SCHEMA = "https://json.schemastore.org/sarif-2.1.0.json"



@dataclass
class FileReport:
    """The verification of one program (see the module docstring for the meaning of each part)."""

    file: str
    diagnostics: list[Diagnostic] = field(default_factory=list)
    recovered: list[bool] = field(default_factory=list)     # parallel to diagnostics
    tools: list[ToolUse] = field(default_factory=list)
    origins: list[OriginUse] = field(default_factory=list)
    boxes: list[ToolBox] = field(default_factory=list)
    cycles: list[dict[str, Any]] = field(default_factory=list)   # canned cycles: code, file, line, holes
    cycle_time: float = 0.0
    max_cycle_time: float | None = None
    moves: int = 0
    ended_by: str | None = None
    executed: bool = False
    complete: bool = False          # ran to its end without error (cycle time of the whole program)
    failure: str | None = None      # the file could not be checked
    usage_error: bool = False       # ... because it cannot be read (exit status 2)
    ending: Ending = field(default_factory=lambda: Ending("not started"))   # what ended the run (fagorcnc.summary)
    #: diagnostics found but not listed (beyond ``max_per_code`` of their code): (code, severity) -> how many
    not_shown: dict[tuple[str, str], int] = field(default_factory=dict)

    def count(self, severity: str) -> int:
        """Diagnostics of ``severity`` found, listed or not."""
        return sum(d.severity == severity for d in self.diagnostics) + sum(
            n for (_, sev), n in self.not_shown.items() if sev == severity)

    def not_shown_lines(self) -> list[str]:
        """One line per code with diagnostics not listed: "N more CODE (description) not shown"."""
        return [f"{n} more {code} ({CODES.get(code, severity)}) not shown (--max-per-code)"
                for (code, severity), n in sorted(self.not_shown.items())]

    @property
    def cycle_time_exceeded(self) -> bool:
        return self.max_cycle_time is not None and self.cycle_time > self.max_cycle_time

    def verdict(self, fail_on: str = "error") -> str:
        """``"pass"``, ``"fail"``, ``"unreadable"`` or ``"crashed"``."""
        if self.failure is not None:
            return "unreadable" if self.usage_error else "crashed"
        bad = ("error", "warning") if fail_on == "warning" else ("error",)
        return "fail" if any(d.severity in bad for d in self.diagnostics) else "pass"

    def unsupported(self) -> list[dict[str, Any]]:
        """The unsupported-feature warnings grouped by code and message."""
        groups: dict[tuple[str, str], list[int]] = {}
        for d in self.diagnostics:
            if d.code in UNSUPPORTED:
                groups.setdefault((d.code, d.message), []).append(d.line)
        return [{"code": c, "description": CODES.get(c, ""), "message": m, "lines": sorted(set(lines))}
                for (c, m), lines in groups.items()]

    def to_dict(self, fail_on: str = "error", diagnostics: bool = True) -> dict[str, Any]:
        """The JSON form (schema ``fagorcnc-check/1``)."""
        out: dict[str, Any] = {
            "file": self.file, "verdict": self.verdict(fail_on), "failure": self.failure,
            "executed": self.executed, "complete": self.complete, "ended_by": self.ended_by,
            "ending": self.ending.to_dict(), "moves": self.moves,
            "cycle_time": round(self.cycle_time, 3), "max_cycle_time": self.max_cycle_time,
            "cycle_time_exceeded": self.cycle_time_exceeded,
            "counts": {s: self.count(s) for s in ("error", "warning", "info")},
        }
        if diagnostics:
            out["diagnostics"] = [_diagnostic_dict(d, r) for d, r in zip(self.diagnostics, self.recovered,
                                                                          strict=True)]
        out["not_shown"] = [{"code": c, "severity": sev, "count": n} for (c, sev), n in sorted(self.not_shown.items())]
        out["unsupported"] = self.unsupported()
        out["tools"] = [{"tool": t.tool, "loaded": t.loaded, "offsets": t.offsets, "lines": t.lines}
                        for t in self.tools]
        out["offsets"] = [{"origin": o.origin, "first_line": o.first_line, "moves": o.moves} for o in self.origins]
        out["bbox"] = [b.to_dict() for b in self.boxes]
        out["cycles"] = self.cycles
        return out


def _diagnostic_dict(d: Diagnostic, recovered: bool) -> dict[str, Any]:
    return {"file": d.file, "line": d.line, "col": d.col, "code": d.code, "severity": d.severity,
            "message": d.message, "source": d.source.rstrip("\r\n"), "recovered": recovered}



# ----------------------------------------------------------------------------- checking one file
def check_file(path: str | Path, machine: Machine | dict | str | Path | None = None, *, block_skip: bool = False,
               max_cycle_time: float | None = None, recover: bool = True,
               max_seconds: float | None = None, max_per_code: int = MAX_PER_CODE) -> FileReport:
    """Verify one program file; never raises (problems are in the report).

    ``machine`` as for :func:`fagorcnc.load_machine`; ``max_cycle_time`` in
    seconds; ``recover`` runs the program once more after an error to report the errors
    further on (:mod:`~fagorcnc.commands.recovery`); ``max_per_code``: diagnostics listed per
    code, the others counted in ``not_shown`` (0 = all);
    ``max_seconds``: interpretation time limit per run (0 = none; None = the
    machine's ``limits.max_seconds`` or :data:`CHECK_MAX_SECONDS`).
    """
    report = FileReport(str(path), max_cycle_time=max_cycle_time)
    try:
        with open(path, "rb"):
            pass
    except OSError as exc:
        report.failure, report.usage_error = f"cannot read the file: {exc.strerror or exc}", True
        return report
    try:
        mach = _time_limited(load_machine(machine), max_seconds)
    except MachineError as exc:
        report.failure, report.usage_error = f"bad machine configuration: {exc}", True
        return report
    try:
        _check(report, Path(path), mach, block_skip, recover, max_per_code)
    except Exception as exc:   # a bug in fagorcnc must not hide the other files' results
        report.failure = f"internal error of fagorcnc: {type(exc).__name__}: {exc}"
    return report


def _time_limited(machine: Machine, seconds: float | None) -> Machine:
    """The machine with the check's time limit (see :func:`check_file`)."""
    if seconds is None:
        seconds = machine.limits.max_seconds or CHECK_MAX_SECONDS
    return dataclasses.replace(machine, limits=dataclasses.replace(machine.limits, max_seconds=seconds))


def _check(report: FileReport, path: Path, machine: Machine, block_skip: bool, recover: bool,
           max_per_code: int) -> None:
    from ..simulate import dry_run

    # one streamed pass: interpreted and planned once, in constant memory whatever the program's
    # length; what the report says of the moves is gathered as they pass
    summary = _Summary()
    result = dry_run(path, machine, block_skip=block_skip, on_record=summary.add)
    found: list[tuple[Diagnostic, bool]] = [(d, False) for d in result.diagnostics]
    report.executed = result.executed
    report.complete = result.ok
    report.cycle_time = result.cycle_time
    report.moves = result.moves
    report.ended_by = result.ended_by
    report.ending = result.ending
    if recover and not result.ok:   # one more streamed pass for the errors beyond the first (see .recovery)
        findings = recovery_pass(path, machine, block_skip, result.diagnostics, max_per_code)
        found += [(d, True) for d in findings.kept]
        for slot, n in findings.more.items():
            report.not_shown[slot] = report.not_shown.get(slot, 0) + n
    report.tools, report.origins, report.boxes = summary.tools(), summary.origins(), summary.boxes()
    report.cycles = summary.cycles()
    if report.cycle_time_exceeded:
        found.append((Diagnostic(str(path), 1, 1, "PLN101", "error",
                                 f"planned cycle time {clock(report.cycle_time)} ({report.cycle_time:.1f} s) is over "
                                 f"the limit of {report.max_cycle_time:g} s (--max-cycle-time)"), False))
    found.sort(key=lambda x: (x[0].file != str(path), x[0].file, x[0].line, x[0].col))
    listed: dict[str, int] = {}
    for d, recovered in found:   # the first max_per_code of each code, in file order; the control's error always
        n = listed.get(d.code, 0)
        if max_per_code and n >= max_per_code and (recovered or not d.is_error):
            slot = (d.code, d.severity)
            report.not_shown[slot] = report.not_shown.get(slot, 0) + 1
            continue
        listed[d.code] = n + 1
        report.diagnostics.append(d)
        report.recovered.append(recovered)


# ----------------------------------------------------------------------------- many files
_WORKER: dict[str, Any] = {}


def _init_worker(machine: Machine, options: dict) -> None:
    _WORKER["machine"], _WORKER["options"] = machine, options


def _work(path: str) -> FileReport:
    return check_file(path, _WORKER["machine"], **_WORKER["options"])


def check_files(paths: Sequence[str | Path], machine: Machine | dict | str | Path | None = None, *,
                jobs: int | None = None, block_skip: bool = False, max_cycle_time: float | None = None,
                recover: bool = True, max_seconds: float | None = None,
                max_per_code: int = MAX_PER_CODE) -> Iterator[FileReport]:
    """Verify many files, ``jobs`` processes at a time (default: one per CPU);
    yields the reports in input order as they become available.

    Raises :class:`~fagorcnc.config.machine.MachineError` for a bad machine configuration.
    """
    mach = load_machine(machine)
    options = {"block_skip": block_skip, "max_cycle_time": max_cycle_time, "recover": recover,
               "max_seconds": max_seconds, "max_per_code": max_per_code}
    names = [str(p) for p in paths]
    jobs = min(jobs or os.cpu_count() or 1, len(names))
    if jobs <= 1:
        for name in names:
            yield check_file(name, mach, **options)
        return
    from concurrent.futures import ProcessPoolExecutor  # on first use: one file is checked in this process

    with ProcessPoolExecutor(max_workers=jobs, initializer=_init_worker, initargs=(mach, options)) as pool:
        yield from pool.map(_work, names)


# ----------------------------------------------------------------------------- output formats
def exit_status(reports: Iterable[FileReport], fail_on: str = "error") -> int:
    """0 all pass, 1 some file fails or crashed, 2 some file could not be read."""
    status = 0
    for r in reports:
        v = r.verdict(fail_on)
        if v == "unreadable":
            status = 2
        elif v in ("fail", "crashed"):
            status = max(status, 1)
    return status


def text_report(report: FileReport, *, fail_on: str = "error", brief: bool = False, verbose: bool = False,
                quiet: bool = False) -> str:
    """Human-readable report of one file: diagnostics, then a summary."""
    lines = []
    for d in report.diagnostics:
        if d.severity == "info" and not verbose:
            continue
        lines.append(str(d) if brief else d.render())
    lines += [f"{report.file}: {text}" for text in report.not_shown_lines()]
    verdict = report.verdict(fail_on)
    if report.failure is not None:
        lines.append(f"{report.file}: {verdict.upper()}: {report.failure}")
        return "\n".join(lines)
    errors, warnings = report.count("error"), report.count("warning")
    time = f"cycle time {clock(report.cycle_time)} (planned"
    time += ")" if report.complete else ", up to the first error)"
    if report.cycle_time_exceeded:
        time += f" OVER the limit of {report.max_cycle_time:g} s"
    run = str(RunSummary(report.moves, report.ending)) if report.executed else \
        f"not executed (syntax errors): {report.ending}"
    lines.append(f"{report.file}: {verdict.upper()}: {errors} errors, {warnings} warnings; {time}; {run}")
    if quiet:
        return "\n".join(lines)
    if any(report.recovered):
        lines.append("  note: the control stops at the first error; the diagnostics after it were found by "
                     "skipping the failing blocks and may be consequences of them")
    if report.tools:
        lines.append("  tools: " + ", ".join(
            f"T{t.tool}" + (f" D{'/D'.join(map(str, t.offsets))}" if t.offsets else "")
            + ("" if t.loaded or t.tool == 0 else " (selected, not loaded)")
            + (f" line {', '.join(map(str, t.lines))}" if t.lines else "") for t in report.tools))
    if report.origins:
        lines.append("  work offsets: " + ", ".join(f"{o.origin} (from line {o.first_line}, {o.moves} moves)"
                                                   for o in report.origins))
    for b in report.boxes:
        lines.append(f"  T{b.tool} machine: {b.machine.text()}")
        lines.append(f"  T{b.tool} part:    {b.part.text()}")
        if b.feed_part:
            lines.append(f"  T{b.tool} feeds (part): {b.feed_part.text()}")
    if report.cycles:
        lines.append("  canned cycles: " + ", ".join(f"{c['code']} line {c['line']} ({c['holes']} "
                                                    f"hole{'s' if c['holes'] != 1 else ''})" for c in report.cycles))
    for u in report.unsupported():
        where = ", ".join(map(str, u["lines"]))
        lines.append(f"  unsupported: {u['code']} {u['message']} (line{'s' if len(u['lines']) > 1 else ''} {where})")
    return "\n".join(lines)


def json_report(reports: Sequence[FileReport], *, fail_on: str = "error", machine: str | None = None) -> dict:
    """The JSON document (schema ``fagorcnc-check/1``) of a set of reports."""
    from ..version import __version__

    files = [r.to_dict(fail_on) for r in reports]
    verdicts = [f["verdict"] for f in files]
    return {
        "schema": SCHEMA, "tool": "fagorcnc", "version": __version__, "machine": machine, "fail_on": fail_on,
        "ok": all(v == "pass" for v in verdicts),
        "summary": {"files": len(files), "passed": verdicts.count("pass"),
                    "failed": len(files) - verdicts.count("pass"),
                    "errors": sum(f["counts"]["error"] for f in files),
                    "warnings": sum(f["counts"]["warning"] for f in files)},
        "files": files,
    }


_SARIF_LEVEL = {"error": "error", "warning": "warning", "info": "note"}


def _uri(file: str) -> str:
    """A file's SARIF URI: relative to the working directory (the repository a CI job checks out)
    when it lies within it, without '..'; otherwise absolute (code scanning maps no '../' path)."""
    from urllib.parse import quote

    path = Path(file)
    if not path.is_absolute() and ".." not in path.parts:
        return quote(path.as_posix(), safe="/")
    try:
        resolved = path.resolve()
        return quote(resolved.relative_to(Path.cwd().resolve()).as_posix(), safe="/")
    except (OSError, ValueError):
        return path.resolve().as_uri() if not path.is_absolute() else path.as_uri()


def sarif_report(reports: Sequence[FileReport], *, fail_on: str = "error") -> dict:
    """A SARIF 2.1.0 log of a set of reports."""
    from ..version import __version__

    rules: list[dict] = []
    index: dict[str, int] = {}
    results = []
    notifications = []
    for r in reports:
        if r.failure is not None:
            notifications.append({
                "level": "error", "message": {"text": f"{r.file}: {r.failure}"},
                "locations": [{"physicalLocation": {"artifactLocation": {"uri": _uri(r.file)}}}]})
        for d, recovered in zip(r.diagnostics, r.recovered, strict=True):
            if d.code not in index:
                index[d.code] = len(rules)
                rules.append({"id": d.code, "name": d.code,
                              "shortDescription": {"text": CODES.get(d.code, d.code)},
                              "defaultConfiguration": {"level": _SARIF_LEVEL.get(d.severity, "warning")}})
            result: dict[str, Any] = {
                "ruleId": d.code, "ruleIndex": index[d.code], "level": _SARIF_LEVEL.get(d.severity, "warning"),
                "message": {"text": d.message},
                "locations": [{"physicalLocation": {
                    "artifactLocation": {"uri": _uri(d.file)},
                    "region": {"startLine": max(1, d.line), "startColumn": max(1, d.col)}}}]}
            if d.source:
                result["locations"][0]["physicalLocation"]["region"]["snippet"] = {"text": d.source.rstrip("\r\n")}
            if recovered:
                result["properties"] = {"recovered": True}
            results.append(result)
    return {
        "version": "2.1.0",
        "$schema": SARIF_SCHEMA,
        "runs": [{
            "tool": {"driver": {"name": "fagorcnc", "version": __version__, "rules": rules}},
            "invocations": [{"executionSuccessful": not notifications,
                             "toolExecutionNotifications": notifications}],
            "results": results,
            "properties": {"files": [r.to_dict(fail_on, diagnostics=False) for r in reports]},
        }],
    }


def _escape_data(text: str) -> str:
    return text.replace("%", "%25").replace("\r", "%0D").replace("\n", "%0A")


def _escape_property(text: str) -> str:
    return _escape_data(text).replace(":", "%3A").replace(",", "%2C")


_GITHUB_COMMAND = {"error": "error", "warning": "warning", "info": "notice"}


def github_report(report: FileReport, *, fail_on: str = "error", verbose: bool = False) -> str:
    """GitHub Actions workflow commands (annotations) for one file, then a summary line."""
    lines = []
    for d in report.diagnostics:
        if d.severity == "info" and not verbose:
            continue
        props = ",".join(f"{k}={_escape_property(str(v))}" for k, v in
                         (("file", d.file), ("line", d.line), ("col", d.col), ("title", d.code)))
        lines.append(f"::{_GITHUB_COMMAND.get(d.severity, 'warning')} {props}::{_escape_data(d.message)}")
    if report.failure is not None:
        props = f"file={_escape_property(report.file)},title=fagorcnc check"
        lines.append(f"::error {props}::{_escape_data(report.failure)}")
    lines.append(text_report(report, fail_on=fail_on, quiet=True).splitlines()[-1])
    return "\n".join(lines)


def dumps(document: dict) -> str:
    """JSON text of a report document (stable key order, 2-space indent)."""
    return json.dumps(document, indent=2, ensure_ascii=False, allow_nan=False)


# --- the ``fagorcnc check`` command ----------------------------------------------------

def command(args: argparse.Namespace) -> int:
    """Handler of ``fagorcnc check``: the exit status of :func:`exit_status`, 2 on bad usage."""
    from . import ci

    if ci.prepare(args) is not None:   # [tool.fagorcnc], --select/--ignore (commands/ci.py)
        return 2
    if args.jobs is not None and args.jobs < 1:
        print("fagorcnc: --jobs must be 1 or more", file=sys.stderr)
        return 2
    if args.max_per_code is not None and args.max_per_code < 0:
        print("fagorcnc: --max-per-code must be 0 (all) or more", file=sys.stderr)
        return 2
    if args.max_cycle_time is not None and not args.max_cycle_time > 0:
        print("fagorcnc: --max-cycle-time must be a positive number of seconds", file=sys.stderr)
        return 2
    machine = command_machine(args)
    if machine is None:
        return 2
    try:
        machine = ci.with_compat(args, machine)   # [tool.fagorcnc] compat over the machine's [compat]
    except ci.ConfigError as exc:
        print(f"fagorcnc: CLI011 {exc}", file=sys.stderr)
        return 2
    if args.strict:   # the manual's letter: every CAM posts' construct of [compat] is an error
        machine = dataclasses.replace(machine, compat=machine.compat.strictly())
    with tempfile.TemporaryDirectory(prefix="fagorcnc-check-") as scratch:
        files = _program_files(args, scratch)
        if files is None:
            return 2
        if not args.output:
            return _check_report(args, machine, sys.stdout, files)
        try:
            with open(args.output, "w", encoding="utf-8") as out:
                return _check_report(args, machine, out, files)
        except OSError as exc:
            print(f"fagorcnc: cannot write {args.output}: {exc.strerror or exc}", file=sys.stderr)
            return 2


def _program_files(args: argparse.Namespace, scratch: str) -> list[tuple[str, str]] | None:
    """(name in the report, file to read) for every FILE argument: a directory stands for its program files
    (recursively, ``--extensions``), ``-`` for standard input (copied to ``scratch``); None after a usage error."""
    extensions = PROGRAM_EXTENSIONS
    if args.extensions is not None:
        extensions = tuple("." + e.strip().lstrip(".") if e.strip() else "" for e in args.extensions.split(","))
    files: list[tuple[str, str]] = []
    for name in args.files:
        if name == "-":
            if any(shown == STDIN_NAME for shown, _ in files):
                print("fagorcnc: '-' (standard input) given twice", file=sys.stderr)
                return None
            files.append((STDIN_NAME, str(stdin_copy(scratch))))
        elif Path(name).is_dir():
            found = [str(p) for p in program_files(name, extensions)]
            if not found:
                print(f"fagorcnc: {name}: no program files in this directory (extensions "
                      f"{', '.join(e or '(none)' for e in extensions)}; see --extensions)", file=sys.stderr)
                return None
            files += [(p, p) for p in found]
        else:
            files.append((name, name))
    return files


def _shown_as(report: FileReport, name: str) -> FileReport:
    """The report of a file read from a copy (standard input) under the name the user gave."""
    if report.file == name:
        return report
    copy = report.file
    report.diagnostics = [dataclasses.replace(d, file=name) if d.file == copy else d for d in report.diagnostics]
    report.file = name
    return report


def _check_report(args: argparse.Namespace, machine, out, files: list[tuple[str, str]]) -> int:
    from . import ci

    reports = []
    names = [shown for shown, _ in files]
    for shown, report in zip(names, check_files(
            [path for _, path in files], machine, jobs=args.jobs, block_skip=args.block_skip,
            max_cycle_time=args.max_cycle_time, max_seconds=args.max_seconds,
            max_per_code=MAX_PER_CODE if args.max_per_code is None else args.max_per_code), strict=True):
        report = _shown_as(report, shown)
        ci.apply(report, args.selection)   # selection and suppression comments (commands/ci.py)
        reports.append(report)
        if report.usage_error:
            print(f"{report.file}: {report.failure}", file=sys.stderr)
        if args.statistics:
            continue
        if args.format == "text":
            print(text_report(report, fail_on=args.fail_on, brief=args.brief, verbose=args.verbose,
                              quiet=args.quiet), file=out, flush=True)
            if getattr(report, "suppressed", 0) and not args.quiet:
                print(f"  {report.suppressed} diagnostics not reported (select/ignore, suppression comments)",
                      file=out, flush=True)
        elif args.format == "github":
            print(github_report(report, fail_on=args.fail_on, verbose=args.verbose), file=out, flush=True)
    if args.format == "json":
        print(dumps(json_report(reports, fail_on=args.fail_on, machine=args.machine)), file=out)
    elif args.format == "sarif":
        print(dumps(sarif_report(reports, fail_on=args.fail_on)), file=out)
    elif args.format == "junit":
        print(ci.junit_report(reports, fail_on=args.fail_on, verbose=args.verbose), file=out)
    elif args.statistics:
        print(ci.statistics(reports, verbose=args.verbose) or "no diagnostics", file=out)
    elif len(reports) > 1 and not args.quiet:
        passed = sum(r.verdict(args.fail_on) == "pass" for r in reports)
        print(f"checked {len(reports)} files: {passed} passed, {len(reports) - passed} failed", file=out)
    return exit_status(reports, args.fail_on)
