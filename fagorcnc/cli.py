"""The ``fagorcnc`` command.

``fagorcnc run FILE`` interprets a program on the embedded simulator and
prints its diagnostics and a summary (moves, final position, estimated cycle
time).  ``fagorcnc parse FILE...`` (alias ``lint``) reads programs and prints every
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


def _run_command(args: argparse.Namespace) -> int:
    from .machine import MachineError, load_machine
    from .simulate import simulate

    try:
        machine = load_machine(args.machine)
    except MachineError as exc:
        print(f"fagorcnc: {exc}", file=sys.stderr)
        return 2
    try:
        result = simulate(Path(args.file), machine, block_skip=args.block_skip)
    except OSError as exc:
        print(f"{args.file}: cannot read the file: {exc.strerror or exc}", file=sys.stderr)
        return 2
    for d in result.diagnostics:
        if d.severity != "info" or args.verbose:
            print(d.render())
    moves = [m for m in result.moves if m.kind in ("rapid", "linear", "arc")]
    if args.verbose:
        for m in result.moves:
            if m.kind in ("rapid", "linear", "arc"):
                end = " ".join(f"{a}{v:.4f}" for a, v in m.end.items())
                feed = "" if m.feed is None else f" F{m.feed:g}"
                print(f"  line {m.line:>5}  {m.kind:<6} -> {end}{feed}")
    pos = result.state.position("part") if result.state else {}
    where = " ".join(f"{a}{v:.4f}" for a, v in pos.items())
    minutes, seconds = divmod(result.cycle_time, 60.0)
    errors = len(result.errors)
    print(f"{args.file}: {'OK' if result.ok else 'STOPPED'} on the embedded simulator: {len(moves)} moves, "
          f"ended by {result.ended_by or 'end of file'}, final position {where}, "
          f"estimated cycle time {int(minutes)} min {seconds:04.1f} s (feed rates, no acceleration yet), "
          f"{errors} errors")
    return 1 if errors else 0


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
    run = sub.add_parser("run", help="run a program on the embedded simulator and print a summary")
    run.add_argument("file", metavar="FILE", help="part program file")
    run.add_argument("--machine", metavar="M", help="machine configuration (TOML); default: built-in machine")
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
