"""fagorcnc: interpreter and motion kernel for Fagor CNC 8060/8065 part programs.

::

    import fagorcnc
    result = fagorcnc.simulate("G1 X10 F100\nM30\n")     # dry run: records, state, planned time
    result.ok, result.diagnostics, result.moves, result.cycle_time, result.trajectory(0.001)
    report = fagorcnc.run("part.nc", backend="sim")      # stream to a back-end

:func:`run` and :class:`RunReport` (and the back-ends behind them) are imported on first use
(PEP 562, :mod:`fagorcnc._lazy`): ``fagorcnc check`` never loads them.
"""

import logging as _logging
from typing import Any as _Any

from . import _lazy
from .config.machine import Machine, load_machine
from .diagnostics import CODES, Diagnostic
from .simulate import DryRun, Result, Run, dry_run, interpret, simulate
from .syntax import Program, iter_lines, parse_file, parse_text
from .version import __version__

# a library logs, the application decides what is shown (the fagorcnc command: nothing unless --log-level)
_logging.getLogger(__name__).addHandler(_logging.NullHandler())

#: names imported on first use: name -> the module that defines it
_LAZY = {"RunReport": "fagorcnc.commands.run", "run": "fagorcnc.commands.run"}


def __getattr__(name: str) -> _Any:
    """The names of :data:`_LAZY`, imported on first use and kept (PEP 562)."""
    return _lazy.attribute(globals(), _LAZY, name)


def __dir__() -> list[str]:
    """The module's names, the lazy ones included."""
    return _lazy.names(globals(), _LAZY)


def parse(source: str, file: str = "<string>") -> Program:
    """Parse program text (not a path) into a :class:`~fagorcnc.syntax.ast.Program`."""
    return parse_text(source, file)


__all__ = [
    "CODES", "Diagnostic", "DryRun", "Machine", "Program", "Result", "Run", "RunReport", "__version__", "dry_run",
    "interpret", "iter_lines", "load_machine", "parse", "parse_file", "parse_text", "run", "simulate",
]
