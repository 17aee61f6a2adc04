"""The ``fagorcnc`` command.

``fagorcnc run FILE`` runs a program on the embedded simulator (or, with
``--backend interpcnc``, on an InterpCNC card) and prints its diagnostics and a
summary (segments, last block, final position, planned cycle time).
``fagorcnc parse FILE...`` (alias ``lint``) reads programs and prints every
diagnostic as ``file:line:col: CODE message`` with the source line and a
caret.  ``fagorcnc check FILE...`` verifies programs for CI (see
:mod:`fagorcnc.check`; text, JSON, SARIF or GitHub annotations) and
``fagorcnc plot FILE -o out.png`` draws the planned tool path
(:mod:`fagorcnc.plot`).  Exit status: 0 clean, 1 when any error was found, 2
on bad usage (unreadable file, unknown option).
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import sys
from collections.abc import Sequence
from pathlib import Path

from . import __version__
from .runtime import keep_freed_memory
from .syntax import parse_file


def _parse_command(args: argparse.Namespace) -> int:
    status = 0
    for path in args.files:
        try:
            program = parse_file(path)
        except OSError as exc:
            print(f"{path}: cannot read the file: {exc.strerror or exc}", file=sys.stderr)
            status = 2
            continue
        shown = [d for d in program.diagnostics if args.verbose or d.severity != "info"]
        for d in shown:
            print(d.render() if not args.brief else str(d))
        errors = sum(d.is_error for d in program.diagnostics)
        warnings = sum(d.severity == "warning" for d in program.diagnostics)
        if errors:
            status = max(status, 1)
        if not args.quiet:
            blocks = len(program.blocks) + sum(len(r.blocks) for r in program.subroutines.values())
            name = f" %{program.name}" if program.name else ""
            print(f"{path}{name}: {blocks} blocks, {len(program.subroutines)} local subroutines, "
                  f"{errors} errors, {warnings} warnings")
    return status


class _ProgressBar:
    """A one-line progress display on a terminal: block, line, planned time and ETA."""

    def __init__(self, stream, label: str) -> None:
        import time

        self.stream, self.label, self.clock = stream, label, time.monotonic
        self.last = 0.0
        self.start = self.clock()

    def __call__(self, seg, status, total) -> None:
        now = self.clock()
        if now - self.last < 0.2:
            return
        self.last = now
        done = seg.t0 + seg.duration
        if total:
            frac = min(1.0, done / total)
            bar = "#" * int(frac * 20)
            eta = (now - self.start) * (1 - frac) / frac if frac > 0 else 0.0
            text = f"[{bar:<20}] {frac:4.0%}  line {status.line:>6}  ETA {_clock(eta)}"
        else:
            text = f"line {status.line:>6}  planned {_clock(done)}"
        self.stream.write(f"\r{self.label}: {text}")
        self.stream.flush()

    def close(self) -> None:
        if self.last:
            self.stream.write("\r\x1b[K")
            self.stream.flush()


def _not_a_file(path: str) -> str:
    return "it is a directory" if Path(path).is_dir() else "no such file"


def _where(report) -> str:
    """Where the tool ended: the program's end point (part coordinates) after a complete run; after
    an error or an alarm where the back-end last stood (machine coordinates), since the interpreter
    may have gone on past the last move the machine made; nothing when nothing moved."""
    if report.ok and report.state is not None:
        pos, label = report.state.position("part"), "final position"
    else:
        pos, label = report.status.position, "position (machine)"
    where = " ".join(f"{a}{v:.4f}" for a, v in pos.items())
    return f"{label} {where}, " if where else ""


def _clock(seconds: float) -> str:
    minutes, sec = divmod(max(seconds, 0.0), 60.0)
    hours, minutes = divmod(int(minutes), 60)
    return f"{hours}:{minutes:02d}:{sec:04.1f}" if hours else f"{minutes}:{sec:04.1f}"


def _command_machine(args: argparse.Namespace):
    """The machine of ``--machine``, or None after saying why it cannot be used (a bad file, a
    --max-seconds that is not 0 or more)."""
    from .machine import MachineError, load_machine

    if args.max_seconds is not None and not (math.isfinite(args.max_seconds) and args.max_seconds >= 0):
        print("fagorcnc: --max-seconds must be 0 (no limit) or a positive number of seconds", file=sys.stderr)
        return None
    try:
        return load_machine(args.machine)
    except MachineError as exc:
        print(f"fagorcnc: {exc}", file=sys.stderr)
        return None


def _run_command(args: argparse.Namespace) -> int:
    from .backends import BackendError
    from .runner import run

    machine = _command_machine(args)
    if machine is None:
        return 2
    if args.max_seconds is not None:
        machine = dataclasses.replace(machine, limits=dataclasses.replace(machine.limits,
                                                                          max_seconds=args.max_seconds))
    if not Path(args.file).is_file():
        print(f"{args.file}: cannot read the file: {_not_a_file(args.file)}", file=sys.stderr)
        return 2
    options = {}
    if args.backend == "interpcnc":
        options = {k: v for k, v in (("host", args.host), ("port", args.port), ("serial", args.serial))
                   if v is not None}
    if args.realtime is not None:
        if args.backend != "sim":
            print("fagorcnc: --realtime paces the simulator only", file=sys.stderr)
            return 2
        options["realtime"] = args.realtime
    if args.backend == "sim":
        options["keep_segments"] = False   # the command reads none of them: memory stays flat however long the run
    bar = _ProgressBar(sys.stderr, Path(args.file).name) if sys.stderr.isatty() and not args.verbose else None
    backend, progress, server = args.backend, bar, None
    report = None
    try:
        if args.status_server is not None:
            backend, server = _start_status_server(args, machine, options)
            if server is None:
                return 2
            options, progress = {}, server.progress_callback(bar)
        report = run(Path(args.file), machine, backend=backend, block_skip=args.block_skip, progress=progress,
                     **options)
    except BackendError as exc:
        print(f"fagorcnc: {exc}", file=sys.stderr)
        return 2
    finally:
        if bar is not None:
            bar.close()
        if server is not None:
            server.finished(report is not None and report.ok)
            server.stop()
    for d in report.diagnostics:
        if d.severity != "info" or args.verbose:
            print(d.render())
    status = report.status
    errors = sum(d.is_error for d in report.diagnostics)
    target = "the embedded simulator" if args.backend == "sim" else f"back-end {args.backend}"
    verdict = "OK" if report.ok else f"STOPPED ({report.message})"
    print(f"{args.file}: {verdict} on {target}: {report.moves} moves, ended by {report.ended_by or 'end of file'}, "
          f"last block executed: line {status.line}, {_where(report)}cycle time "
          f"{_clock(report.cycle_time)} (jerk-limited plan), {errors} errors")
    if report.stopped_by == "interrupt":
        return 130
    return 0 if report.ok else 1


def _check_command(args: argparse.Namespace) -> int:
    if args.jobs is not None and args.jobs < 1:
        print("fagorcnc: --jobs must be 1 or more", file=sys.stderr)
        return 2
    if args.max_cycle_time is not None and not args.max_cycle_time > 0:
        print("fagorcnc: --max-cycle-time must be a positive number of seconds", file=sys.stderr)
        return 2
    machine = _command_machine(args)
    if machine is None:
        return 2
    if not args.output:
        return _check_report(args, machine, sys.stdout)
    try:
        with open(args.output, "w", encoding="utf-8") as out:
            return _check_report(args, machine, out)
    except OSError as exc:
        print(f"fagorcnc: cannot write {args.output}: {exc.strerror or exc}", file=sys.stderr)
        return 2


def _check_report(args: argparse.Namespace, machine, out) -> int:
    from .check import check_files, dumps, exit_status, github_report, json_report, sarif_report, text_report

    reports = []
    for report in check_files(args.files, machine, jobs=args.jobs, block_skip=args.block_skip,
                              max_cycle_time=args.max_cycle_time, max_seconds=args.max_seconds):
        reports.append(report)
        if report.usage_error:
            print(f"{report.file}: {report.failure}", file=sys.stderr)
        if args.format == "text":
            print(text_report(report, fail_on=args.fail_on, brief=args.brief, verbose=args.verbose,
                              quiet=args.quiet), file=out, flush=True)
        elif args.format == "github":
            print(github_report(report, fail_on=args.fail_on, verbose=args.verbose), file=out, flush=True)
    if args.format == "json":
        print(dumps(json_report(reports, fail_on=args.fail_on, machine=args.machine)), file=out)
    elif args.format == "sarif":
        print(dumps(sarif_report(reports, fail_on=args.fail_on)), file=out)
    elif len(reports) > 1 and not args.quiet:
        passed = sum(r.verdict(args.fail_on) == "pass" for r in reports)
        print(f"checked {len(reports)} files: {passed} passed, {len(reports) - passed} failed", file=out)
    return exit_status(reports, args.fail_on)


def _plot_command(args: argparse.Namespace) -> int:
    from .machine import MachineError
    from .plot import MatplotlibMissingError, plot_program

    if not Path(args.file).is_file():
        print(f"{args.file}: cannot read the file: {_not_a_file(args.file)}", file=sys.stderr)
        return 2
    try:
        info = plot_program(Path(args.file), args.output, args.machine, three_d=args.three_d, plane=args.plane,
                            programmed=not args.no_programmed, limits=args.limits, block_skip=args.block_skip)
    except MatplotlibMissingError as exc:
        print(f"fagorcnc: {exc}", file=sys.stderr)
        return 2
    except (MachineError, ValueError) as exc:
        print(f"fagorcnc: {exc}", file=sys.stderr)
        return 2
    except OSError as exc:
        print(f"fagorcnc: cannot write {args.output}: {exc.strerror or exc}", file=sys.stderr)
        return 2
    for d in info.diagnostics:
        if d.severity != "info":
            print(d.render(), file=sys.stderr)
    print(f"{args.output}: {info.segments} planned segments, cycle time {_clock(info.cycle_time)}"
          + (", programmed contour drawn" if info.programmed else ""))
    return 0 if info.ok else 1


def _start_status_server(args: argparse.Namespace, machine, options: dict):
    """Build the back-end and start the Modbus status server on it: (backend, server), server None on failure."""
    from .backends import get_backend
    from .status_server import PlcSignal, StatusServer, StatusServerError, parse_address

    try:
        host, port = parse_address(args.status_server)
    except ValueError as exc:
        print(f"fagorcnc: {exc}", file=sys.stderr)
        return None, None
    backend = get_backend(args.backend, machine, **options)

    def show(signal: PlcSignal) -> None:
        what = f"= {signal.value}" if signal.value else "cleared"
        print(f"\nfagorcnc: PLC {signal.kind} {signal.number} (HR {signal.register}) {what}", file=sys.stderr)

    server = StatusServer(backend, machine, host=host, port=port, holding_writes=args.plc_writes,
                          program=Path(args.file), on_signal=show)
    try:
        server.start()
    except StatusServerError as exc:
        print(f"fagorcnc: {exc}", file=sys.stderr)
        return backend, None
    print(f"fagorcnc: status server (Modbus TCP) on {server.host}:{server.port}"
          f"{', PLC writes enabled' if args.plc_writes else ''}", file=sys.stderr)
    return backend, server


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of the ``fagorcnc`` command."""
    parser = argparse.ArgumentParser(
        prog="fagorcnc", description="Fagor CNC 8060/8065 part-program interpreter and motion kernel.")
    parser.add_argument("--version", action="version", version=f"fagorcnc {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    for name in ("parse", "lint"):
        p = sub.add_parser(name, help="check the syntax of programs and list every problem")
        p.add_argument("files", nargs="+", metavar="FILE", help="part program files")
        p.add_argument("-q", "--quiet", action="store_true", help="print only diagnostics")
        p.add_argument("--brief", action="store_true", help="one line per diagnostic, no source excerpt")
        p.add_argument("-v", "--verbose", action="store_true", help="also print informational notes")
        p.set_defaults(func=_parse_command)
    run = sub.add_parser("run", help="run a program (embedded simulator by default, or an InterpCNC card)")
    run.add_argument("file", metavar="FILE", help="part program file")
    run.add_argument("--machine", metavar="M", help="machine configuration (TOML); default: built-in machine")
    run.add_argument("--backend", default="sim", metavar="NAME",
                     help="where the motion goes: sim (default) or interpcnc")
    run.add_argument("--host", help="InterpCNC card address (Modbus TCP)")
    run.add_argument("--port", type=int, help="InterpCNC Modbus TCP port (default 502)")
    run.add_argument("--serial", metavar="DEV", help="InterpCNC serial device (Modbus RTU, e.g. /dev/ttyACM0)")
    run.add_argument("--realtime", type=float, nargs="?", const=1.0, metavar="FACTOR",
                     help="pace the simulator against the clock (FACTOR 2 = twice as fast)")
    run.add_argument("--status-server", metavar="[HOST:]PORT",
                     help="serve the CNC state to a PLC over Modbus TCP while the program runs (RosettaCNC "
                          "register table, interface level 1); HOST defaults to 127.0.0.1, e.g. 5020 or 0.0.0.0:502")
    run.add_argument("--plc-writes", action="store_true",
                     help="with --status-server: accept PLC writes (40001-40008 custom alarms stop the run, "
                          "40009-40016 custom warnings are shown)")
    run.add_argument("--block-skip", action="store_true", help="skip blocks that start with '/'")
    run.add_argument("--max-seconds", type=float, metavar="SECONDS",
                     help="stop a program whose interpretation takes longer (INT082; 0 = no limit; "
                          "default: the machine's limits.max_seconds, none)")
    run.add_argument("-v", "--verbose", action="store_true", help="list every move and informational notes")
    run.set_defaults(func=_run_command)
    check = sub.add_parser("check", help="verify programs offline for CI: diagnostics, limits, tools, cycle time")
    check.add_argument("files", nargs="+", metavar="FILE", help="part program files")
    check.add_argument("--machine", metavar="M", help="machine configuration (TOML or LinuxCNC INI)")
    check.add_argument("--format", choices=("text", "json", "sarif", "github"), default="text",
                       help="report format (default: text)")
    check.add_argument("--max-cycle-time", type=float, metavar="SECONDS",
                       help="fail a program whose planned cycle time is longer")
    check.add_argument("--fail-on", choices=("error", "warning"), default="error",
                       help="fail on errors only (default) or on warnings too")
    check.add_argument("--max-seconds", type=float, metavar="SECONDS",
                       help="fail a program whose interpretation takes longer (INT082; 0 = no limit; default: "
                            "the machine's limits.max_seconds, else 120)")
    check.add_argument("--jobs", "-j", type=int, metavar="N", help="files checked in parallel (default: CPU count)")
    check.add_argument("--block-skip", action="store_true", help="skip blocks that start with '/'")
    check.add_argument("-o", "--output", metavar="FILE", help="write the report to FILE instead of the output")
    check.add_argument("--brief", action="store_true", help="text: one line per diagnostic, no source excerpt")
    check.add_argument("-q", "--quiet", action="store_true", help="text: diagnostics and verdicts only")
    check.add_argument("-v", "--verbose", action="store_true", help="also report informational notes")
    check.set_defaults(func=_check_command)
    plot = sub.add_parser("plot", help="draw the planned tool path into a PNG, SVG or PDF (needs matplotlib)")
    plot.add_argument("file", metavar="FILE", help="part program file")
    plot.add_argument("-o", "--output", required=True, metavar="OUT", help="picture file: .png, .svg or .pdf")
    plot.add_argument("--machine", metavar="M", help="machine configuration (TOML or LinuxCNC INI)")
    plot.add_argument("--3d", dest="three_d", action="store_true", help="3D view of X, Y, Z")
    plot.add_argument("--plane", default="XY", metavar="AB", help="axes of the 2D view: XY (default), XZ, YZ, ZX ...")
    plot.add_argument("--no-programmed", action="store_true",
                      help="do not draw the programmed contour of a compensated path")
    plot.add_argument("--limits", action="store_true", help="draw the soft limits (2D view)")
    plot.add_argument("--block-skip", action="store_true", help="skip blocks that start with '/'")
    plot.set_defaults(func=_plot_command)
    sub.add_parser("emulate", help="serve an emulated InterpCNC card (Modbus TCP) for tests and dry runs; "
                   "see fagorcnc emulate --help")
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``fagorcnc`` console script; returns the exit status."""
    argv = list(sys.argv[1:] if argv is None else argv)
    if argv[:1] == ["emulate"]:   # its own options: fagorcnc emulate --help
        from .backends.interpcnc.emulator import main as emulate

        return emulate(argv[1:])
    parser = build_parser()
    args = parser.parse_args(argv)
    if not getattr(args, "func", None):
        parser.print_help()
        return 2
    keep_freed_memory()   # the planner's arrays: reused, not faulted in again (see fagorcnc.runtime)
    try:
        return args.func(args)
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:
        return 1


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
