"""CI configuration of ``fagorcnc check``: ``[tool.fagorcnc]`` in ``pyproject.toml``, ``--select`` /
``--ignore`` codes, per-line suppression comments, the JUnit report and ``--statistics``.

``[tool.fagorcnc]`` is looked for in the ``pyproject.toml`` of the working directory or the nearest
directory above it (``--config FILE`` names another; ``--no-config`` ignores it).  Keys (``-`` or
``_`` alike)::

    [tool.fagorcnc]
    machine = "machines/mill.toml"   # --machine (relative to the pyproject.toml's directory)
    compat = { g51 = "error" }       # over the machine's [compat] table (or compat = "strict", as --strict)
    fail-on = "warning"              # --fail-on
    select = ["INT", "PLN"]          # codes or prefixes reported (default: all)
    ignore = ["INT098", "STR011"]    # codes or prefixes not reported
    max-cycle-time = 600             # --max-cycle-time, s
    paths = ["nc/", "posts/*.nc"]    # the programs checked when none is named (globs; a directory:
                                     # its *.nc, *.pim and *.mpf files, recursively)

Options on the command line win over the file; ``--select``/``--ignore`` on the command line replace
the file's lists, ``--extend-select``/``--extend-ignore`` add to them.  As in ruff, the longest
matching prefix decides: ``select = ["INT"]`` with ``ignore = ["INT09"]`` drops INT098 but
``select = ["INT098"]`` keeps it.

A suppression comment ends the line whose diagnostic it silences: ``G1 X10 ; fagorcnc:
ignore[INT100]`` (several codes separated by commas).  A comment that names a code fagorcnc does not
know is itself reported (``CLI010``), and so is a bad configuration (``CLI011``, exit 2).  Only
warnings and notes are silenced: an error stays reported whatever the selection or a comment says,
with ``CLI012`` beside it (the control stops at that block; a passing check must not hide it).  What
is dropped is counted: the text summary says how many diagnostics were not reported.
"""

from __future__ import annotations

import argparse
import re
import sys
from collections import Counter
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ..diagnostics import CODES, Diagnostic
from ..syntax.reader import ProgramFile, universal_lines

#: The keys of ``[tool.fagorcnc]``.
KEYS = ("machine", "compat", "fail-on", "select", "ignore", "max-cycle-time", "paths")
#: Suffixes of the programs a directory of ``paths`` holds.
PROGRAM_SUFFIXES = (".nc", ".pim", ".mpf")
_SUPPRESS = re.compile(r";.*?\bfagorcnc:\s*ignore\[([^\]]*)\]", re.IGNORECASE)


class ConfigError(ValueError):
    """A bad ``[tool.fagorcnc]`` table (CLI011)."""


@dataclass
class Selection:
    """Which codes are reported: the longest matching prefix of ``select`` or ``ignore`` decides."""

    select: list[str] = field(default_factory=list)
    ignore: list[str] = field(default_factory=list)

    def keeps(self, code: str) -> bool:
        """Whether ``code`` is reported (a tie between select and ignore: ignored)."""
        chosen = max((len(p) for p in self.select if code.startswith(p)), default=-1) if self.select else 0
        dropped = max((len(p) for p in self.ignore if code.startswith(p)), default=-1)
        return chosen >= 0 and chosen > dropped


@dataclass
class Config:
    """``[tool.fagorcnc]``: the values given (None when not), and where they were read."""

    file: Path | None = None
    values: dict[str, Any] = field(default_factory=dict)

    def get(self, key: str, default=None):
        return self.values.get(key, default)


def find_pyproject(start: Path) -> Path | None:
    """The nearest ``pyproject.toml`` at or above ``start``."""
    for directory in (start, *start.parents):
        candidate = directory / "pyproject.toml"
        if candidate.is_file():
            return candidate
    return None


def load_config(path: Path | None) -> Config:
    """Read ``[tool.fagorcnc]`` of ``path`` (None: nothing).  Raises :class:`ConfigError`."""
    if path is None:
        return Config()
    import tomllib

    try:
        with open(path, "rb") as f:
            document = tomllib.load(f)
    except OSError as exc:
        raise ConfigError(f"{path}: cannot read the file: {exc.strerror or exc}") from exc
    except tomllib.TOMLDecodeError as exc:
        raise ConfigError(f"{path}: not valid TOML: {exc}") from exc
    table = document.get("tool", {}).get("fagorcnc", {})
    if not isinstance(table, dict):
        raise ConfigError(f"{path}: [tool.fagorcnc] must be a table")
    values: dict[str, Any] = {}
    for raw, value in table.items():
        key = raw.replace("_", "-")
        if key not in KEYS:
            raise ConfigError(f"{path}: [tool.fagorcnc] has no key {raw!r} (keys: {', '.join(KEYS)})")
        values[key] = _checked(path, key, value)
    return Config(path, values)


def _checked(path: Path, key: str, value: Any) -> Any:
    where = f"{path}: [tool.fagorcnc] {key}"
    if key in ("select", "ignore", "paths"):
        if not isinstance(value, list) or not all(isinstance(v, str) and v for v in value):
            raise ConfigError(f"{where} must be a list of strings")
        if key != "paths":
            for code in value:
                _check_prefix(code, where)
        return value
    if key == "fail-on":
        if value not in ("error", "warning"):
            raise ConfigError(f"{where} must be \"error\" or \"warning\"")
        return value
    if key == "max-cycle-time":
        if isinstance(value, str):   # "1:30", as on the command line
            from ._shared import duration

            try:
                value = duration(value)
            except Exception:
                raise ConfigError(f"{where} = {value!r}: seconds, m:ss or h:mm:ss") from None
        if isinstance(value, bool) or not isinstance(value, int | float) or not value > 0:
            raise ConfigError(f"{where} must be a positive number of seconds")
        return float(value)
    if key == "compat":
        if value != "strict" and not isinstance(value, dict):
            raise ConfigError(f"{where}: a table like the machine file's [compat] (compat = {{ g51 = \"error\" }}) "
                              "or \"strict\"")
        return value
    if not isinstance(value, str) or not value:
        raise ConfigError(f"{where} must be a string")
    return value


def _check_prefix(code: str, where: str) -> None:
    if not any(c.startswith(code) for c in CODES):
        raise ConfigError(f"{where}: {code!r} is no code or prefix of a code of fagorcnc (see README, Diagnostics)")


# ----------------------------------------------------------------------------- the command's options
def add_arguments(check: argparse.ArgumentParser) -> None:
    """The options of ``fagorcnc check`` this module reads."""
    check.add_argument("--select", metavar="CODES", help="report only these codes or prefixes (comma-separated)")
    check.add_argument("--ignore", metavar="CODES", help="do not report these codes or prefixes (comma-separated)")
    check.add_argument("--extend-select", metavar="CODES", help="add to the configuration's select")
    check.add_argument("--extend-ignore", metavar="CODES", help="add to the configuration's ignore")
    check.add_argument("--statistics", action="store_true",
                       help="text: the number of diagnostics per code instead of the diagnostics")
    check.add_argument("--config", metavar="PYPROJECT", help="read [tool.fagorcnc] from this file "
                                                            "(default: the nearest pyproject.toml)")
    check.add_argument("--no-config", action="store_true", help="ignore [tool.fagorcnc]")


def _codes(text: str | None, option: str) -> list[str]:
    if not text:
        return []
    codes = [c.strip().upper() for c in text.split(",") if c.strip()]
    for code in codes:
        _check_prefix(code, option)
    return codes


def prepare(args: argparse.Namespace) -> int | None:
    """Merge ``[tool.fagorcnc]`` into the check's arguments (the command line wins) and set
    ``args.selection``; returns 2 after saying why on a bad configuration, else None."""
    try:
        config = Config() if args.no_config else load_config(
            Path(args.config) if args.config else find_pyproject(Path.cwd()))
        if args.config and config.file is None:
            raise ConfigError(f"{args.config}: no such file")
        base = config.file.parent if config.file is not None else Path.cwd()
        if args.machine is None and config.get("machine") is not None:
            args.machine = str(base / config.get("machine"))
        if args.fail_on is None:
            args.fail_on = config.get("fail-on", "error")
        if args.max_cycle_time is None:
            args.max_cycle_time = config.get("max-cycle-time")
        args.compat_table, args.compat_file = config.get("compat"), config.file
        select = _codes(args.select, "--select") if args.select is not None else list(config.get("select", []))
        ignore = _codes(args.ignore, "--ignore") if args.ignore is not None else list(config.get("ignore", []))
        select += _codes(args.extend_select, "--extend-select")
        ignore += _codes(args.extend_ignore, "--extend-ignore")
        args.selection = Selection(select, ignore)
        if not args.files:
            args.files = expand_paths(config.get("paths", []), base)
            if not args.files:
                raise ConfigError("no program to check: name files, or give paths in [tool.fagorcnc]")
        if args.statistics and args.format != "text":
            raise ConfigError("--statistics goes with --format text")
    except ConfigError as exc:
        print(f"fagorcnc: CLI011 {exc}", file=sys.stderr)
        return 2
    return None


def expand_paths(patterns: Sequence[str], base: Path) -> list[str]:
    """The program files of ``paths`` patterns (globs relative to ``base``; a directory: its programs)."""
    out: list[str] = []
    for pattern in patterns:
        matches = sorted(base.glob(pattern)) if any(ch in pattern for ch in "*?[") else [base / pattern]
        for match in matches:
            if match.is_dir():
                out += sorted(str(p) for p in match.rglob("*") if p.suffix.lower() in PROGRAM_SUFFIXES and p.is_file())
            elif match.exists():
                out.append(str(match))
            else:
                raise ConfigError(f"[tool.fagorcnc] paths: {pattern!r} matches no file")
    return list(dict.fromkeys(out))


# ----------------------------------------------------------------------------- filtering a report
def suppressions(path: str | Path) -> dict[int, list[str]]:
    """Line -> the codes its ``; fagorcnc: ignore[...]`` comment names (the file read line by line)."""
    found: dict[int, list[str]] = {}
    try:
        with ProgramFile(path, "utf-8", "replace") as f:
            for number, line in enumerate(universal_lines(f.file), start=1):   # no line of unbounded length in memory
                if "fagorcnc" not in line:
                    continue
                match = _SUPPRESS.search(line)
                if match:
                    found[number] = [c.strip().upper() for c in match.group(1).split(",") if c.strip()]
    except OSError:
        return {}
    return found


def apply(report, selection: Selection) -> int:
    """Drop the diagnostics of a :class:`~fagorcnc.commands.check.FileReport` that the selection or a
    suppression comment silences; adds CLI010 for a comment naming an unknown code.  Returns how
    many were dropped (also kept as ``report.suppressed``)."""
    comments = suppressions(report.file) if report.failure is None else {}
    kept: list[tuple[Diagnostic, bool]] = []
    dropped = 0
    for d, recovered in zip(report.diagnostics, report.recovered, strict=True):
        codes = comments.get(d.line, ()) if d.file == report.file else ()
        if d.is_error:   # never silenced: the control stops at it, whatever the check says
            kept.append((d, recovered))
            if d.code in codes or not selection.keeps(d.code):
                kept.append((Diagnostic(d.file, d.line, 1, "CLI012", "warning",
                                        f"{d.code} is an error and stays reported: the control stops at this "
                                        "block (select/ignore and suppression comments silence warnings and notes "
                                        "only)"), False))
            continue
        if not selection.keeps(d.code) or d.code in codes:
            dropped += 1
            continue
        kept.append((d, recovered))
    for line, codes in sorted(comments.items()):
        for code in codes:
            if code not in CODES and selection.keeps("CLI010"):
                kept.append((Diagnostic(report.file, line, 1, "CLI010", "warning",
                                        f"the suppression comment names {code!r}, which is no code of fagorcnc"),
                             False))
    kept.sort(key=lambda x: (x[0].file != report.file, x[0].file, x[0].line, x[0].col))
    report.diagnostics = [d for d, _ in kept]
    report.recovered = [r for _, r in kept]
    report.suppressed = dropped
    return dropped


# ----------------------------------------------------------------------------- reports
def statistics(reports: Sequence, *, verbose: bool = False) -> str:
    """Diagnostics per code over all reports, most frequent first (``--statistics``)."""
    counts: Counter[tuple[str, str]] = Counter()
    for r in reports:
        for d in r.diagnostics:
            if d.severity != "info" or verbose:
                counts[(d.code, d.severity)] += 1
    rows = sorted(counts.items(), key=lambda kv: (-kv[1], kv[0][0]))
    return "\n".join(f"{n:>6}  {code}  {severity:<7}  {CODES.get(code, '')}" for (code, severity), n in rows)


def junit_report(reports: Sequence, *, fail_on: str = "error", verbose: bool = False) -> str:
    """A JUnit XML document: one test suite per program, one test case per diagnostic (a failure
    when it fails the check, else passed with the message in ``system-out``), one passing case
    ``check`` for a clean program; a program that could not be checked is an ``error``."""
    from xml.etree import ElementTree

    failing = ("error", "warning") if fail_on == "warning" else ("error",)
    root = ElementTree.Element("testsuites", name="fagorcnc check")
    totals = Counter()
    for r in reports:
        suite = ElementTree.SubElement(root, "testsuite", name=r.file)
        counts = Counter()
        if r.failure is not None:
            case = ElementTree.SubElement(suite, "testcase", name="check", classname=r.file)
            ElementTree.SubElement(case, "error", message=r.failure).text = r.failure
            counts["tests"] += 1
            counts["errors"] += 1
        shown = [d for d in r.diagnostics if d.severity != "info" or verbose]
        for d in shown:
            case = ElementTree.SubElement(suite, "testcase", name=f"{d.code} line {d.line}",
                                          classname=r.file, file=d.file, line=str(d.line))
            counts["tests"] += 1
            if d.severity in failing:
                ElementTree.SubElement(case, "failure", message=f"{d.code} {d.message}",
                                       type=d.severity).text = str(d)
                counts["failures"] += 1
            else:
                ElementTree.SubElement(case, "system-out").text = str(d)
        if not shown and r.failure is None:
            ElementTree.SubElement(suite, "testcase", name="check", classname=r.file)
            counts["tests"] += 1
        for key in ("tests", "failures", "errors"):
            suite.set(key, str(counts[key]))
            totals[key] += counts[key]
        properties = ElementTree.Element("properties")
        suite.insert(0, properties)
        ElementTree.SubElement(properties, "property", name="cycle_time", value=f"{r.cycle_time:.3f}")
        ElementTree.SubElement(properties, "property", name="verdict", value=r.verdict(fail_on))
    for key in ("tests", "failures", "errors"):
        root.set(key, str(totals[key]))
    ElementTree.indent(root)
    return '<?xml version="1.0" encoding="UTF-8"?>\n' + ElementTree.tostring(root, encoding="unicode")


def with_compat(args: argparse.Namespace, machine):
    """The machine with ``[tool.fagorcnc] compat`` laid over its ``[compat]`` policy (the file's keys win;
    ``"strict"`` is ``--strict``); raises :class:`ConfigError` naming the bad key."""
    from dataclasses import replace

    from ..config.compat import parse_compat
    from ..config.errors import MachineError

    table = getattr(args, "compat_table", None)
    if table is None:
        return machine
    if table == "strict":
        return replace(machine, compat=machine.compat.strictly())
    try:
        parsed = parse_compat(table)   # validates the keys and actions
    except MachineError as exc:
        raise ConfigError(f"{args.compat_file}: [tool.fagorcnc] {exc}") from None
    actions = {**machine.compat.actions, **{k: parsed.actions[k] for k in table if k != "strict"}}
    return replace(machine, compat=replace(machine.compat, actions=actions,
                                           strict=machine.compat.strict or parsed.strict))

