"""Helpers the command handlers share: the ``--machine`` option, file checks, durations."""

from __future__ import annotations

import argparse
import math
import re
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


def duration(text: str) -> float:
    """A duration option: seconds (``90``, ``12.5``), ``m:ss`` (``1:30``) or ``h:mm:ss`` (``1:02:03.5``);
    an ``argparse`` type (a bad one is a usage error naming the forms accepted).  A plain negative number
    is returned as is: each option says itself what it accepts (``--max-seconds -1`` is refused naming it)."""
    parts = text.strip().split(":")
    if len(parts) == 1:
        try:
            return float(parts[0])
        except ValueError:
            pass
    try:
        if len(parts) > 3 or any(not p.strip() for p in parts):
            raise ValueError(text)
        values = [float(p) for p in parts]
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a duration: seconds (90), m:ss (1:30) or h:mm:ss") \
            from None
    if any(not math.isfinite(v) or v < 0 for v in values) or any(v >= 60 for v in values[1:]):
        raise argparse.ArgumentTypeError(f"{text!r} is not a duration: seconds (90), m:ss (1:30) or h:mm:ss")
    seconds = 0.0
    for v in values:
        seconds = seconds * 60.0 + v
    return seconds


#: The name ``-`` (standard input) has in reports.
STDIN_NAME = "<stdin>"


def stdin_copy(directory: str) -> Path:
    """Standard input copied to a file in ``directory`` (in chunks: constant memory), for ``-`` as a FILE."""
    target = Path(directory) / "stdin.nc"
    with open(target, "wb") as out:
        source = sys.stdin.buffer
        while chunk := source.read(1 << 20):
            out.write(chunk)
    return target


_LIBRARY_ADVICE = re.compile(r"[;,.]?\s*(?:[Cc]all|then call)\s+[a-z_]+\(\)[^.;]*(?:[.;]|$)")


def cli_message(message: str) -> str:
    """A back-end's message for the command line: advice to call a library method (``reconnect_and_continue()``,
    ``resume()``...) is for programs embedding fagorcnc; at the command line the way on is a new run."""
    cleaned = _LIBRARY_ADVICE.sub(".", message).strip()
    while ".." in cleaned:
        cleaned = cleaned.replace("..", ".")
    return cleaned.rstrip(" .;,")


def configure_logging(level: str | None) -> None:
    """The command's logging: quiet unless ``--log-level`` asks (fagorcnc's and pymodbus' records then go to
    standard error).  Without it no handler prints them: pymodbus' own warnings ("No response received...")
    would otherwise reach the terminal through Python's last-resort handler."""
    import logging

    for name in ("fagorcnc", "pymodbus"):
        logger = logging.getLogger(name)
        if not any(isinstance(h, logging.NullHandler) for h in logger.handlers):
            logger.addHandler(logging.NullHandler())
    if level is not None:
        logging.basicConfig(level=level.upper(), stream=sys.stderr,
                            format="%(asctime)s %(name)s %(levelname)s: %(message)s")
        for name in ("fagorcnc", "pymodbus"):
            logging.getLogger(name).setLevel(level.upper())
