"""fagorcnc: interpreter and motion kernel for Fagor CNC 8060/8065 part programs.

::

    import fagorcnc
    result = fagorcnc.simulate("G1 X10 F100\nM30\n")     # dry run: records, state, planned time
    result.ok, result.diagnostics, result.moves, result.cycle_time, result.trajectory(0.001)
    report = fagorcnc.run("part.nc", backend="sim")      # stream to a back-end
"""

import logging as _logging

from .commands.run import RunReport, run
from .config.machine import Machine, load_machine
from .diagnostics import CODES, Diagnostic
from .simulate import DryRun, Result, Run, dry_run, interpret, simulate
from .syntax import Program, iter_lines, parse_file, parse_text
from .version import __version__

# a library logs, the application decides what is shown (the fagorcnc command: nothing unless --log-level)
_logging.getLogger(__name__).addHandler(_logging.NullHandler())


def parse(source: str, file: str = "<string>") -> Program:
    """Parse program text (not a path) into a :class:`~fagorcnc.syntax.ast.Program`."""
    return parse_text(source, file)


__all__ = [
    "CODES", "Diagnostic", "DryRun", "Machine", "Program", "Result", "Run", "RunReport", "__version__", "dry_run",
    "interpret", "iter_lines", "load_machine", "parse", "parse_file", "parse_text", "run", "simulate",
]
