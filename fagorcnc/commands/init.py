"""``fagorcnc init --kind KIND``: write a commented machine file to start from.

The templates are the files of ``examples/machines/`` (shipped inside the package as
``fagorcnc/templates/machines/``): ``mill3`` (3-axis vertical mill), ``mill5-ac`` (X Y Z with an A
tilting and a C rotary table), ``router`` (gantry router with HSC), ``lathe`` (X on the diameter and
Z, "plane" axis configuration, G18) and ``interpcnc`` (a 3-axis mill on an InterpCNC card, with its
``[backends.interpcnc]`` section).  Every number in them is an example to replace by the machine's
own parameter; each file loads as it is (a test loads them all).
"""

from __future__ import annotations

import argparse
import sys
from importlib import resources
from pathlib import Path

#: The machine kinds ``init`` knows, with what each template describes.
KINDS = {
    "mill3": "3-axis vertical milling machine (X Y Z)",
    "mill5-ac": "5-axis mill, A tilting and C rotary table (X Y Z A C)",
    "router": "3-axis gantry router, large travels, HSC",
    "lathe": "2-axis lathe, X on the diameter and Z (G18)",
    "interpcnc": "3-axis mill on a SOPROLEC InterpCNC card",
}


def template_dir() -> Path:
    """Where the templates are: the packaged copy, else the repository's ``examples/machines``."""
    packaged = resources.files("fagorcnc") / "templates" / "machines"
    if packaged.is_dir():
        return Path(str(packaged))
    return Path(__file__).resolve().parents[2] / "examples" / "machines"


def template(kind: str) -> str:
    """The text of the template of ``kind`` (a key of :data:`KINDS`)."""
    if kind not in KINDS:
        raise ValueError(f"unknown machine kind {kind!r}: one of {', '.join(KINDS)}")
    return (template_dir() / f"{kind}.toml").read_text(encoding="utf-8")


def command(args: argparse.Namespace) -> int:
    """Handler of ``fagorcnc init``: 0 written, 2 the file exists (without --force) or cannot be written."""
    out = Path(args.output)
    if out.exists() and not args.force:
        print(f"fagorcnc: {out} exists: give another -o FILE, or --force to replace it", file=sys.stderr)
        return 2
    try:
        out.write_text(template(args.kind), encoding="utf-8")
    except OSError as exc:
        print(f"fagorcnc: cannot write {out}: {exc.strerror or exc}", file=sys.stderr)
        return 2
    print(f"{out}: {KINDS[args.kind]}; replace the example values by your machine's parameters, then "
          f"fagorcnc check --machine {out} PROGRAM")
    return 0


def add_parser(sub) -> None:
    """The ``init`` sub-command's arguments."""
    p = sub.add_parser("init", help="write a commented machine file to start from (mill3, mill5-ac, router, "
                                    "lathe, interpcnc)")
    p.add_argument("--kind", choices=tuple(KINDS), default="mill3", help="the machine (default: mill3)")
    p.add_argument("-o", "--output", default="machine.toml", metavar="FILE",
                   help="the file to write (default: machine.toml)")
    p.add_argument("--force", action="store_true", help="replace the file if it exists")
    p.set_defaults(func=command)
