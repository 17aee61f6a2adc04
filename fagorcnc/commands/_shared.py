"""Helpers the command handlers share: the ``--machine`` option, file checks, durations."""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path


def not_a_file(path: str) -> str:
    """Why ``path`` cannot be read as a program: a directory, or no such file."""
    return "it is a directory" if Path(path).is_dir() else "no such file"


def clock(seconds: float) -> str:
    """``m:ss.s`` (or ``h:mm:ss.s``) for a duration in seconds."""
    minutes, sec = divmod(max(seconds, 0.0), 60.0)
    hours, minutes = divmod(int(minutes), 60)
    return f"{hours}:{minutes:02d}:{sec:04.1f}" if hours else f"{minutes}:{sec:04.1f}"


def command_machine(args: argparse.Namespace):
    """The machine of ``--machine``, or None after saying why it cannot be used (a bad file, a
    --max-seconds that is not 0 or more)."""
    from ..config.machine import MachineError, load_machine

    if args.max_seconds is not None and not (math.isfinite(args.max_seconds) and args.max_seconds >= 0):
        print("fagorcnc: --max-seconds must be 0 (no limit) or a positive number of seconds", file=sys.stderr)
        return None
    try:
        return load_machine(args.machine)
    except MachineError as exc:
        print(f"fagorcnc: {exc}", file=sys.stderr)
        return None
