"""The ``fagorcnc`` command.

``fagorcnc run FILE`` runs a program on the embedded simulator (or, with
``--backend interpcnc``, on an InterpCNC card) and prints its diagnostics and a
summary (segments, last block, final position, planned cycle time).
``fagorcnc parse FILE...`` (alias ``lint``) reads programs and prints every
diagnostic as ``file:line:col: CODE message`` with the source line and a
caret.  Exit status: 0 clean, 1 when any error was found, 2 on bad usage
(unreadable file, unknown option).
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence
from pathlib import Path

from . import __version__
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


def _clock(seconds: float) -> str:
    minutes, sec = divmod(max(seconds, 0.0), 60.0)
    hours, minutes = divmod(int(minutes), 60)
    return f"{hours}:{minutes:02d}:{sec:04.1f}" if hours else f"{minutes}:{sec:04.1f}"


def _run_command(args: argparse.Namespace) -> int:
    from .backends import BackendError
    from .machine import MachineError, load_machine
    from .runner import run

    try:
        machine = load_machine(args.machine)
    except MachineError as exc:
        print(f"fagorcnc: {exc}", file=sys.stderr)
        return 2
    if not Path(args.file).is_file():
        print(f"{args.file}: cannot read the file: no such file", file=sys.stderr)
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
    bar = _ProgressBar(sys.stderr, Path(args.file).name) if sys.stderr.isatty() and not args.verbose else None
    try:
        report = run(Path(args.file), machine, backend=args.backend, block_skip=args.block_skip, progress=bar,
                     **options)
    except BackendError as exc:
        print(f"fagorcnc: {exc}", file=sys.stderr)
        return 2
    finally:
        if bar is not None:
            bar.close()
    for d in report.diagnostics:
        if d.severity != "info" or args.verbose:
            print(d.render())
    status = report.status
    pos = report.state.position("part") if report.state is not None else status.position
    where = " ".join(f"{a}{v:.4f}" for a, v in pos.items())
    errors = sum(d.is_error for d in report.diagnostics)
    target = "the embedded simulator" if args.backend == "sim" else f"back-end {args.backend}"
    verdict = "OK" if report.ok else f"STOPPED ({report.message})"
    print(f"{args.file}: {verdict} on {target}: {report.moves} moves, ended by {report.ended_by or 'end of file'}, "
          f"last block executed: line {status.line}, final position {where}, cycle time "
          f"{_clock(report.cycle_time)} (jerk-limited plan), {errors} errors")
    if report.stopped_by == "interrupt":
        return 130
    return 0 if report.ok else 1


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
    run.add_argument("--block-skip", action="store_true", help="skip blocks that start with '/'")
    run.add_argument("-v", "--verbose", action="store_true", help="list every move and informational notes")
    run.set_defaults(func=_run_command)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``fagorcnc`` console script; returns the exit status."""
    parser = build_parser()
    args = parser.parse_args(argv)
    if not getattr(args, "func", None):
        parser.print_help()
        return 2
    try:
        return args.func(args)
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:
        return 1


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
