"""``fagorcnc parse FILE...`` (alias ``lint``): read programs and print every diagnostic as
``file:line:col: CODE message`` with the source line and a caret."""

from __future__ import annotations

import argparse
import sys

from ..program_files import no_block
from ..syntax import parse_file, parse_text
from ._shared import STDIN_NAME


def command(args: argparse.Namespace) -> int:
    """Handler of ``fagorcnc parse``: exit 0 clean, 1 with errors, 2 for an unreadable file."""
    status = 0
    for path in args.files:
        try:
            program = parse_text(sys.stdin.read(), STDIN_NAME) if path == "-" else parse_file(path)
        except OSError as exc:
            print(f"{path}: cannot read the file: {exc.strerror or exc}", file=sys.stderr)
            status = 2
            continue
        if program.ok and not program.main.blocks and not program.subroutines:
            # the verdict run and check give too
            program = program._replace(diagnostics=(*program.diagnostics, no_block(program.file)))
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
            print(f"{program.file}{name}: {blocks} blocks, {len(program.subroutines)} local subroutines, "
                  f"{errors} errors, {warnings} warnings")
    return status
