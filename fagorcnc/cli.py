"""The ``fagorcnc`` command.

``fagorcnc run FILE`` runs a program on the embedded simulator (or, with
``--backend interpcnc``, on an InterpCNC card) and prints its diagnostics and a
summary (segments, last block, final position, planned cycle time).
``fagorcnc parse FILE...`` (alias ``lint``) reads programs and prints every
diagnostic as ``file:line:col: CODE message`` with the source line and a
caret.  ``fagorcnc check FILE...`` verifies programs for CI (see
:mod:`fagorcnc.commands.check`; text, JSON, SARIF or GitHub annotations) and
``fagorcnc plot FILE -o out.png`` draws the planned tool path
(:mod:`fagorcnc.commands.plot`).  Exit status: 0 clean, 1 when any error was found, 2
on bad usage (unreadable file, unknown option).
"""

from __future__ import annotations

import argparse
import importlib
import sys
from collections.abc import Callable, Sequence

from .commands import check as check_command
from .commands import ci as ci_options
from .commands import diff as diff_command
from .commands import expand as expand_command
from .commands import init as init_command
from .commands import view as view_command
from .commands._shared import configure_logging, duration
from .program_files import PROGRAM_EXTENSIONS
from .runtime import keep_freed_memory, spare_collector
from .version import __version__


def _handler(module: str) -> Callable[[argparse.Namespace], int]:
    """The ``command`` function of :mod:`fagorcnc.commands` ``module``, imported when the command runs
    (``fagorcnc check`` does not load the back-ends of ``run`` nor the plotting of ``plot``)."""

    def command(args: argparse.Namespace) -> int:
        return importlib.import_module(f"{__package__}.commands.{module}").command(args)

    return command


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of the ``fagorcnc`` command."""
    parser = argparse.ArgumentParser(
        prog="fagorcnc", description="Fagor CNC 8060/8065 part-program interpreter and motion kernel.")
    parser.add_argument("--version", action="version", version=f"fagorcnc {__version__}")
    parser.add_argument("--log-level", choices=("debug", "info", "warning", "error"), default=None,
                        help="print the library's log records (fagorcnc, pymodbus) of this level and above on "
                             "standard error (default: none)")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    for name in ("parse", "lint"):
        p = sub.add_parser(name, help="check the syntax of programs and list every problem")
        p.add_argument("files", nargs="+", metavar="FILE", help="part program files ('-': standard input)")
        p.add_argument("-q", "--quiet", action="store_true", help="print only diagnostics")
        p.add_argument("--brief", action="store_true", help="one line per diagnostic, no source excerpt")
        p.add_argument("-v", "--verbose", action="store_true", help="also print informational notes")
        p.set_defaults(func=_handler("parse"))
    run = sub.add_parser("run", help="run a program (embedded simulator by default, or an InterpCNC card)")
    run.add_argument("file", metavar="FILE", help="part program file ('-': standard input)")
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
    run.add_argument("--status-linger", type=duration, metavar="SECONDS",
                     help="with --status-server: keep serving the final state and the end reason this long after "
                          "the end (default 3 s; 0 = close at once)")
    run.add_argument("--block-skip", action="store_true", help="skip blocks that start with '/'")
    run.add_argument("--max-seconds", type=duration, metavar="SECONDS",
                     help="stop a program whose interpretation takes longer, in CPU seconds (INT082; 0 = no limit; "
                          "default: the machine's limits.max_seconds, none)")
    run.add_argument("-v", "--verbose", action="store_true", help="list every move and informational notes")
    run.set_defaults(func=_handler("run"))
    check = sub.add_parser("check", help="verify programs offline for CI: diagnostics, limits, tools, cycle time")
    check.add_argument("files", nargs="*", metavar="FILE",
                       help="part program files, or directories (their program files, recursively); '-': "
                            "standard input (default: [tool.fagorcnc] paths of pyproject.toml)")
    check.add_argument("--extensions", metavar="EXT,...", default=None,
                       help="program extensions looked for in a directory (default: "
                            + ",".join(e.lstrip(".") for e in PROGRAM_EXTENSIONS) + ")")
    check.add_argument("--machine", metavar="M", help="machine configuration (TOML or LinuxCNC INI)")
    check.add_argument("--format", choices=("text", "json", "sarif", "github", "junit"), default="text",
                       help="report format (default: text)")
    check.add_argument("--max-cycle-time", type=duration, metavar="DURATION",
                       help="fail a program whose planned cycle time is longer: seconds (90), m:ss (1:30) or "
                            "h:mm:ss")
    check.add_argument("--fail-on", choices=("error", "warning"), default=None,
                       help="fail on errors only (default) or on warnings too")
    check.add_argument("--max-seconds", type=duration, metavar="SECONDS",
                       help="fail a program whose interpretation takes longer, in CPU seconds (INT082; 0 = no "
                            "limit; default: the machine's limits.max_seconds, else 120)")
    check.add_argument("--max-per-code", type=int, default=None, metavar="N",
                       help="list at most N diagnostics of each code, count the others (default 20; 0 = all)")
    check.add_argument("--jobs", "-j", type=int, metavar="N", help="files checked in parallel (default: CPU count)")
    check.add_argument("--block-skip", action="store_true", help="skip blocks that start with '/'")
    check.add_argument("--strict", action="store_true",
                       help="the manual's letter: the CAM posts' constructs of the machine's [compat] table are "
                            "errors (as [compat] strict = true)")
    check.add_argument("-o", "--output", metavar="FILE", help="write the report to FILE instead of the output")
    check.add_argument("--brief", action="store_true", help="text: one line per diagnostic, no source excerpt")
    check.add_argument("-q", "--quiet", action="store_true", help="text: diagnostics and verdicts only")
    check.add_argument("-v", "--verbose", action="store_true", help="also report informational notes")
    ci_options.add_arguments(check)
    check.set_defaults(func=check_command.command)
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
    plot.add_argument("--view", choices=("joints", "tip"), default="joints",
                      help="moves under a kinematics (#RTCP, #TOOL ORI): draw the joints (default) or the tool tip "
                           "in the part frame")
    plot.add_argument("--no-tool-axis", action="store_true",
                      help="do not draw the tool-axis glyphs of the moves made under a kinematics")
    plot.set_defaults(func=_handler("plot"))
    expand_command.add_parser(sub)
    diff_command.add_parser(sub)
    view_command.add_parser(sub)
    init_command.add_parser(sub)
    sub.add_parser("emulate", help="serve an emulated InterpCNC card (Modbus TCP) for tests and dry runs; "
                   "see fagorcnc emulate --help")
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``fagorcnc`` console script; returns the exit status."""
    argv = list(sys.argv[1:] if argv is None else argv)
    if argv[:1] == ["emulate"]:   # its own options: fagorcnc emulate --help
        from .commands import emulate as emulate_command

        return emulate_command.command(argv[1:])
    parser = build_parser()
    args = parser.parse_args(argv)
    if not getattr(args, "func", None):
        parser.print_help()
        return 2
    configure_logging(args.log_level)
    keep_freed_memory()   # the planner's arrays: reused, not faulted in again (see fagorcnc.runtime)
    try:
        return args.func(args)
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:
        return 1


def command() -> int:
    """The ``fagorcnc`` process (the console script, ``python -m fagorcnc``): :func:`main`, the collector spared
    the imports' modules, classes and functions, which live until the process exits
    (:func:`~fagorcnc.runtime.spare_collector`).  What the command makes is left to the collection at exit: a
    compiled extension's objects kept past it (ruckig's, nanobind) would be reported as leaked."""
    spare_collector()
    return main()


if __name__ == "__main__":  # pragma: no cover
    sys.exit(command())
