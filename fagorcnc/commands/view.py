"""``fagorcnc view FILE -o out.html``: an interactive preview in one self-contained HTML file.

The page needs no server and no network: the planned path, the program text and a small viewer
(``view.js`` next to this module, written for fagorcnc, no third-party code) are inlined.  It shows
the 3D tool path in machine coordinates (drag to turn, shift-drag to move, wheel to zoom) coloured by
motion (rapids red and dashed, feeds blue), by feed or by tool; the program text beside it: a click
on the path highlights the line that made it and a click on a line highlights its path; the block
where the program stops with an error is marked in the text and on the path; the soft-limit box is
drawn; play and a slider scrub along the planned (jerk-limited) time.

The path is the planner's, sampled with chords of at most :data:`CHORD` mm (at most
:data:`MAX_POINTS` points per piece) and written with 4 decimals.
"""

from __future__ import annotations

import argparse
import html
import json
import math
import sys
from pathlib import Path
from typing import Any

import numpy as np

from ..config.machine import Machine, MachineError, load_machine
from ._shared import not_a_file

#: Chord error of the curves drawn (mm) and points per piece at most.
CHORD = 0.01
MAX_POINTS = 64
_SCRIPT = Path(__file__).with_name("view.js")

_PAGE = """<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8">
<meta http-equiv="Content-Security-Policy" content="default-src 'none'; style-src 'unsafe-inline'; \
script-src 'unsafe-inline'">
<title>{title}</title>
<style>
body {{ margin: 0; font: 13px sans-serif; display: flex; flex-direction: column; height: 100vh; }}
header {{ padding: 4px 8px; background: #eee; display: flex; gap: 8px; align-items: center; flex-wrap: wrap; }}
main {{ flex: 1; display: flex; min-height: 0; }}
#text {{ width: 38%; overflow: auto; font: 12px monospace; border-right: 1px solid #ccc; }}
.line {{ white-space: pre; cursor: pointer; padding: 0 4px; }}
.line .no {{ display: inline-block; width: 4em; color: #999; }}
.line.hl {{ background: #ffe08a; }}
.line.failing {{ background: #f8c0c0; }}
.line.failing.hl {{ background: #f0a040; }}
#path {{ flex: 1; width: 62%; height: 100%; cursor: crosshair; }}
#diagnostics {{ max-height: 7em; overflow: auto; font: 12px monospace; padding: 2px 8px; color: #a00; }}
#time {{ flex: 1; min-width: 200px; }}
</style></head><body>
<header><b>{title}</b>
<button id="play">play / pause</button>
<select id="speed"><option value="1">1x</option><option value="10" selected>10x</option>
<option value="100">100x</option></select>
<input id="time" type="range" min="0" value="0"><span id="clock"></span>
<label>colour <select id="colour"><option value="motion">rapid / feed</option><option value="feed">feed</option>
<option value="tool">tool</option></select></label>
<button id="reset">reset view</button><span id="selected"></span></header>
<div id="diagnostics">{diagnostics}</div>
<main><div id="text"></div><canvas id="path"></canvas></main>
<script id="fagorcnc-data" type="application/json">{data}</script>
<script>{script}</script>
</body></html>
"""


def _points(piece, index: list[int]) -> np.ndarray:
    if not getattr(piece, "curved", False):
        return np.vstack([piece.start, piece.end])[:, index]
    kappa = float(np.linalg.norm(piece.d2)) / max(piece.speed_factor(), 1e-9) ** 2
    step = math.sqrt(8.0 * CHORD / kappa) if kappa > 0 else piece.length
    n = int(min(MAX_POINTS, max(3, math.ceil(piece.length / max(step, 1e-9)) + 1)))
    pts = piece.points(n) if hasattr(piece, "points") else piece.derivatives(np.linspace(0.0, piece.length, n))[0]
    return pts[:, index]


def view_data(source: str | Path, machine: Machine | dict | str | Path | None = None, *,
              block_skip: bool = False) -> dict[str, Any]:
    """What the page shows: the planned path, the program text, diagnostics, the soft limits."""
    from ..simulate import dry_run
    from ..syntax import read_source

    mach = load_machine(machine)
    axes = [a for a in mach.axis_names if not mach.axes[a].rotary][:3]
    index = [mach.axis_names.index(a) for a in axes]
    tools: dict[int, tuple[object, int]] = {}
    state = {"tool": 0, "next": 0}

    def on_record(rec, _interp) -> None:
        if rec.kind == "aux":
            if rec.function == "T":
                state["next"] = int(rec.value)
            elif rec.function == "M" and rec.value == 6:   # M06 loads the tool T selected (seed 002 L4700)
                state["tool"] = state["next"]
        tools[id(rec)] = (rec, state["tool"])

    segments: list[dict[str, Any]] = []

    def on_segment(seg) -> None:
        if seg.kind != "motion" or seg.piece is None:
            return
        rec = seg.record
        pts = _points(seg.piece, index)
        if len(axes) < 3:
            pts = np.hstack([pts, np.zeros((len(pts), 3 - len(axes)))])
        segments.append({"points": np.round(pts, 4).tolist(), "line": seg.line, "file": rec.src.file,
                         "rapid": bool(getattr(rec, "rapid", False)), "feed": getattr(rec, "feed", None) or 0.0,
                         "tool": tools.get(id(rec), (None, state["tool"]))[1],
                         "t0": round(seg.t0, 4), "duration": round(seg.duration, 4)})

    result = dry_run(source, mach, block_skip=block_skip, on_record=on_record, on_segment=on_segment)
    file = str(source)
    try:
        lines = read_source(Path(source)).replace("\r\n", "\n").replace("\r", "\n").split("\n")
    except OSError:
        lines = []
    if segments:
        allpts = np.array([p for s in segments for p in s["points"]])
        lo, hi = allpts.min(axis=0).tolist(), allpts.max(axis=0).tolist()
    else:
        lo, hi = [0.0, 0.0, 0.0], [1.0, 1.0, 1.0]
    limits = None
    if len(axes) == 3 and all(math.isfinite(mach.axes[a].min_limit) and math.isfinite(mach.axes[a].max_limit)
                              for a in axes):
        limits = {"min": [mach.axes[a].min_limit for a in axes], "max": [mach.axes[a].max_limit for a in axes]}
    failing = None
    errors = [d for d in result.diagnostics if d.is_error]
    if errors:
        first = errors[0]
        point = segments[-1]["points"][-1] if segments else None
        failing = {"line": first.line if first.file == file else None, "code": first.code,
                   "message": first.message, "point": point}
    feeds = [s["feed"] for s in segments if not s["rapid"]]
    return {"file": file, "axes": axes, "lines": lines, "segments": segments, "bounds": {"min": lo, "max": hi},
            "limits": limits, "failing": failing, "cycle_time": round(result.cycle_time, 4),
            "max_feed": max(feeds, default=1.0), "ok": result.ok,
            "diagnostics": [str(d) for d in result.diagnostics if d.severity != "info"]}


def render_page(data: dict[str, Any]) -> str:
    """The self-contained HTML page of :func:`view_data`'s data."""
    payload = json.dumps(data, separators=(",", ":"), allow_nan=False).replace("</", "<\\/")
    diagnostics = "<br>".join(html.escape(d) for d in data["diagnostics"])
    return _PAGE.format(title=html.escape(Path(data["file"]).name), diagnostics=diagnostics, data=payload,
                        script=_SCRIPT.read_text(encoding="utf-8"))


def write_view(source: str | Path, output: str | Path, machine: Machine | dict | str | Path | None = None, *,
               block_skip: bool = False) -> dict[str, Any]:
    """Write the preview page of a program; returns its data."""
    data = view_data(source, machine, block_skip=block_skip)
    Path(output).write_text(render_page(data), encoding="utf-8")
    return data


def command(args: argparse.Namespace) -> int:
    """Handler of ``fagorcnc view``: 0 the program has no error, 1 it has (the page marks where), 2 bad usage."""
    if not Path(args.file).is_file():
        print(f"{args.file}: cannot read the file: {not_a_file(args.file)}", file=sys.stderr)
        return 2
    try:
        data = write_view(args.file, args.output, args.machine, block_skip=args.block_skip)
    except MachineError as exc:
        print(f"fagorcnc: {exc}", file=sys.stderr)
        return 2
    except OSError as exc:
        print(f"fagorcnc: cannot write {args.output}: {exc.strerror or exc}", file=sys.stderr)
        return 2
    for d in data["diagnostics"]:
        print(d, file=sys.stderr)
    print(f"{args.output}: {len(data['segments'])} planned segments, cycle time {data['cycle_time']:.1f} s"
          + ("" if data["ok"] else f", stops at line {data['failing']['line']} ({data['failing']['code']})"))
    return 0 if data["ok"] else 1


def add_parser(sub) -> None:
    """The ``view`` sub-command's arguments."""
    p = sub.add_parser("view", help="write an interactive preview (one HTML file: 3D path, program text, "
                                    "click path <-> line, play along the planned time)")
    p.add_argument("file", metavar="FILE", help="part program file")
    p.add_argument("-o", "--output", required=True, metavar="OUT", help="the HTML file to write")
    p.add_argument("--machine", metavar="M", help="machine configuration (TOML or LinuxCNC INI)")
    p.add_argument("--block-skip", action="store_true", help="skip blocks that start with '/'")
    p.set_defaults(func=command)
