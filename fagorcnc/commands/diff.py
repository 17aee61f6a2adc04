"""``fagorcnc diff A B``: compare the planned tool paths of two programs geometrically.

Both programs are interpreted and planned (:func:`fagorcnc.simulate.dry_run`); every planned piece
of motion (rapids, feeds, arcs, corner curves) becomes a polyline of the **tool tip in part
coordinates** (machine coordinates minus each record's own translation, see
:meth:`ChannelState.part_pos <fagorcnc.interp.state.ChannelState.part_pos>`) over the linear axes;
curved pieces are cut into chords whose sagitta is at most :data:`CHORD_ERROR` (or a twentieth of the
tolerance when that is smaller).  The deviation is the symmetric Hausdorff distance of the two
polylines, computed exactly to a thousandth of the tolerance by :mod:`.geometry_index` (nearest
segments through a spatial index, no sampling step): how far a point of one path is from the other
path at worst.  Two programs written differently that cut the same path (G90 and G91, arcs by R and
by I/J/K) differ by 0; the report says where the largest deviation is (source lines in both
programs) and lists the regions beyond the tolerance.

It also compares what a re-post may change silently: tools used, work offsets, bounding boxes (part
coordinates, per tool) and the planned cycle time.  Exit status: 0 the paths are within the
tolerance, 1 beyond it (or a program stopped by an error: its path is only compared up to there),
2 bad usage (unreadable file, bad machine, a rotary axis that moves: 5-axis paths are not compared).

JSON report (``--format json``), schema ``fagorcnc-diff/1``::

    {"schema": "fagorcnc-diff/1", "a": "old.nc", "b": "new.nc", "tolerance": 0.01, "within": false,
     "deviation": 0.02, "bound": 0.02,            # mm: exact to eps; bound >= deviation
     "eps": 1e-05, "chord_error": 0.0005,
     "at": {"from": "a" | "b", "point": {"X": ..}, "a_line": 12, "b_line": 12},
     "a_to_b": 0.02, "b_to_a": 0.02,
     "regions": [{"from": "a", "lines": [20, 35], "other_lines": [20, 35], "max": 0.02}],
     "segments": {"a": 812, "b": 812},
     "programs": {"a": {"ok": true, "cycle_time": 89.88, "tools": [1], "offsets": ["G54"],
                        "bbox": {"1": {"min": {...}, "max": {...}}}, "diagnostics": [...]}, "b": {...}},
     "differences": ["tools: ...", "cycle time: ..."]}
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ..config.machine import Machine, MachineError, load_machine
from ._shared import clock, not_a_file

if TYPE_CHECKING:
    from .geometry_index import Directed

SCHEMA = "fagorcnc-diff/1"
#: Largest chord sagitta of a curved piece (mm).
CHORD_ERROR = 0.0005
#: Chords per curved piece at most.
MAX_CHORDS = 20000
#: Regions beyond the tolerance listed at most.
MAX_REGIONS = 50


class DiffError(ValueError):
    """What ``diff`` cannot compare (a rotary axis that moves, a program with no motion)."""


@dataclass
class ProgramPath:
    """One program's planned tool-tip path and what the comparison reports of it."""

    file: str
    a: np.ndarray               # segment starts (n, 3): part coordinates of the linear axes
    b: np.ndarray               # segment ends
    lines: np.ndarray           # source line of each segment
    ok: bool
    cycle_time: float
    diagnostics: list
    tools: list[int] = field(default_factory=list)
    offsets: list[str] = field(default_factory=list)
    boxes: dict[int, Any] = field(default_factory=dict)


class _Collector:
    """Turns planned segments into chords of the tool tip in part coordinates."""

    def __init__(self, machine: Machine, chord: float) -> None:
        names = machine.axis_names
        self.linear = [i for i, a in enumerate(names) if not machine.axes[a].rotary][:3]
        self.rotary = [i for i, a in enumerate(names) if machine.axes[a].rotary]
        self.names = [names[i] for i in self.linear]
        self.chord = chord
        self.starts: list[np.ndarray] = []
        self.ends: list[np.ndarray] = []
        self.lines: list[np.ndarray] = []
        self._single_a: list = []
        self._single_b: list = []
        self._single_l: list[int] = []
        self.rotary_line: int | None = None

    def __call__(self, seg) -> None:
        piece = seg.piece
        if seg.kind != "motion" or piece is None:
            return
        rec = seg.record
        linear = self.linear
        end_part = getattr(rec, "end_part", None)
        off = np.zeros(len(linear))
        if end_part is not None:
            off = np.array([rec.end[self.names[k]] - end_part[self.names[k]] for k in range(len(linear))])
        if self.rotary and self.rotary_line is None:
            if any(abs(float(piece.end[i]) - float(piece.start[i])) > 1e-9 for i in self.rotary):
                self.rotary_line = seg.line
        if not piece.curved:
            self._single_a.append(piece.start[linear] - off)
            self._single_b.append(piece.end[linear] - off)
            self._single_l.append(seg.line)
            if len(self._single_l) >= 65536:
                self._flush()
            return
        self._flush()
        pts = _curve_points(piece, self.chord)[:, linear] - off
        self.starts.append(pts[:-1])
        self.ends.append(pts[1:])
        self.lines.append(np.full(len(pts) - 1, seg.line, dtype=np.int64))

    def _flush(self) -> None:
        if self._single_l:
            self.starts.append(np.array(self._single_a, dtype=float).reshape(-1, len(self.linear)))
            self.ends.append(np.array(self._single_b, dtype=float).reshape(-1, len(self.linear)))
            self.lines.append(np.array(self._single_l, dtype=np.int64))
            self._single_a, self._single_b, self._single_l = [], [], []

    def arrays(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        self._flush()
        dim = len(self.linear)
        if not self.starts:
            return np.empty((0, 3)), np.empty((0, 3)), np.empty(0, dtype=np.int64)
        a, b = np.concatenate(self.starts), np.concatenate(self.ends)
        if dim < 3:   # a machine of fewer linear axes: the others are 0
            a = np.hstack([a, np.zeros((len(a), 3 - dim))])
            b = np.hstack([b, np.zeros((len(b), 3 - dim))])
        return a, b, np.concatenate(self.lines)


def _curve_points(piece, chord: float) -> np.ndarray:
    """Points along a curved piece whose chords stray at most ``chord`` from it: the sagitta of a
    chord h on a curve of curvature k is about k h^2 / 8 (the curvature bounded by |q''|).
    [CONSTRUCTION] for the planner's corner curves, whose parameter is not the arc length, the bound
    |q''| is taken as the curvature; their speed factor is near 1."""
    kappa = float(np.linalg.norm(piece.d2)) / max(piece.speed_factor(), 1e-9) ** 2
    step = math.sqrt(8.0 * chord / kappa) if kappa > 0 else piece.length
    n = int(min(MAX_CHORDS, max(2, math.ceil(piece.length / max(step, 1e-9)) + 1)))
    if hasattr(piece, "points"):
        return piece.points(n)
    return piece.derivatives(np.linspace(0.0, piece.length, n))[0]


def program_path(source: str | Path, machine: Machine, chord: float, *, block_skip: bool = False) -> ProgramPath:
    """Plan one program and collect its path; raises :class:`DiffError` for a moving rotary axis."""
    from ..simulate import dry_run
    from .extents import MoveSummary as _Summary

    collector = _Collector(machine, chord)
    summary = _Summary()
    result = dry_run(source, machine, block_skip=block_skip, on_record=summary.add, on_segment=collector)
    if collector.rotary_line is not None:
        raise DiffError(f"{source}: a rotary axis moves (line {collector.rotary_line}): fagorcnc diff compares "
                        "the tool tip over the linear axes only, 5-axis paths are not compared")
    a, b, lines = collector.arrays()
    boxes = {box.tool: box.part for box in summary.boxes()}
    return ProgramPath(str(source), a, b, lines, result.ok, result.cycle_time, list(result.diagnostics),
                       sorted(t.tool for t in summary.tools() if t.loaded or t.tool != 0),
                       [o.origin for o in summary.origins()], boxes)


@dataclass
class DiffReport:
    """The comparison of two programs (see the module docstring for the JSON form)."""

    a: ProgramPath
    b: ProgramPath
    tolerance: float
    eps: float
    chord: float
    a_to_b: Directed
    b_to_a: Directed
    axes: list[str]

    @property
    def deviation(self) -> float:
        return max(self.a_to_b.maximum, self.b_to_a.maximum)

    @property
    def bound(self) -> float:
        return max(float(self.a_to_b.upper.max(initial=0.0)), float(self.b_to_a.upper.max(initial=0.0)))

    @property
    def within(self) -> bool:
        """The paths are within the tolerance and both programs ran to their end."""
        return self.bound <= self.tolerance and self.a.ok and self.b.ok

    def at(self) -> dict[str, Any]:
        """Where the largest deviation is."""
        forward = self.a_to_b.maximum >= self.b_to_a.maximum
        d, mine, other = (self.a_to_b, self.a, self.b) if forward else (self.b_to_a, self.b, self.a)
        if not len(d.lower):
            return {"from": "a", "point": {}, "a_line": None, "b_line": None}
        k = int(np.argmax(d.lower))
        point = {x: _round(float(v)) for x, v in zip(self.axes, d.where[k], strict=False)}
        here, there = int(mine.lines[k]), int(other.lines[d.near[k]])
        return {"from": "a" if forward else "b", "point": point,
                "a_line": here if forward else there, "b_line": there if forward else here}

    def regions(self) -> list[dict[str, Any]]:
        """Runs of consecutive segments beyond the tolerance, by source lines in both programs."""
        out = []
        for name, d, mine, other in (("a", self.a_to_b, self.a, self.b), ("b", self.b_to_a, self.b, self.a)):
            beyond = d.upper > self.tolerance
            if not beyond.any():
                continue
            idx = np.flatnonzero(beyond)
            breaks = np.flatnonzero(np.diff(idx) > 1)
            firsts = np.concatenate([[idx[0]], idx[breaks + 1]])
            lasts = np.concatenate([idx[breaks], [idx[-1]]])
            for f, la in zip(firsts, lasts, strict=True):
                near_lines = other.lines[d.near[f:la + 1]]
                out.append({"from": name, "lines": [int(mine.lines[f]), int(mine.lines[la])],
                            "other_lines": [int(near_lines.min()), int(near_lines.max())],
                            "max": _round(float(d.upper[f:la + 1].max()))})
                if len(out) >= MAX_REGIONS:
                    return out
        return out

    def differences(self) -> list[str]:
        """Tools, work offsets, boxes and cycle time that differ."""
        a, b = self.a, self.b
        out = []
        if a.tools != b.tools:
            out.append(f"tools: {_list('T', a.tools)} in A, {_list('T', b.tools)} in B")
        if a.offsets != b.offsets:
            out.append(f"work offsets: {', '.join(a.offsets) or 'none'} in A, {', '.join(b.offsets) or 'none'} in B")
        for tool in sorted(set(a.boxes) | set(b.boxes)):
            ba, bb = a.boxes.get(tool), b.boxes.get(tool)
            if ba is None or bb is None:
                continue
            worst = max((abs(ba.lo[x] - bb.lo.get(x, ba.lo[x])) for x in ba.lo), default=0.0)
            worst = max(worst, max((abs(ba.hi[x] - bb.hi.get(x, ba.hi[x])) for x in ba.hi), default=0.0))
            if worst > self.tolerance:
                out.append(f"T{tool} bounding box (part): {ba.text()} in A, {bb.text()} in B")
        if abs(a.cycle_time - b.cycle_time) >= 0.05:
            out.append(f"cycle time: {clock(a.cycle_time)} in A, {clock(b.cycle_time)} in B "
                       f"({b.cycle_time - a.cycle_time:+.1f} s)")
        for name, p in (("A", a), ("B", b)):
            if not p.ok:
                out.append(f"{name} ({p.file}) stops at an error: its path is compared up to there")
        return out

    def to_dict(self) -> dict[str, Any]:
        def program(p: ProgramPath) -> dict[str, Any]:
            return {"file": p.file, "ok": p.ok, "cycle_time": round(p.cycle_time, 3), "tools": p.tools,
                    "offsets": p.offsets, "bbox": {str(t): box.to_dict() for t, box in sorted(p.boxes.items())},
                    "diagnostics": [str(d) for d in p.diagnostics if d.severity != "info"]}

        return {"schema": SCHEMA, "a": self.a.file, "b": self.b.file, "tolerance": self.tolerance,
                "within": self.within, "deviation": _round(self.deviation), "bound": _round(self.bound),
                "eps": self.eps, "chord_error": self.chord, "at": self.at(),
                "a_to_b": _round(self.a_to_b.maximum), "b_to_a": _round(self.b_to_a.maximum),
                "regions": self.regions(), "segments": {"a": len(self.a.lines), "b": len(self.b.lines)},
                "programs": {"a": program(self.a), "b": program(self.b)}, "differences": self.differences()}

    def text(self) -> str:
        at = self.at()
        where = " ".join(f"{x}{v:.4f}" for x, v in at["point"].items())
        verdict = "within" if self.bound <= self.tolerance else "BEYOND"
        place = f" at {where}, line {at['a_line']} of A / line {at['b_line']} of B" if self.deviation > self.eps \
            else ": the same path"
        lines = [f"{self.a.file} vs {self.b.file}: max deviation {self.deviation:.4f} mm ({verdict} the tolerance "
                 f"{self.tolerance:g} mm){place}",
                 f"  A to B {self.a_to_b.maximum:.4f} mm, B to A {self.b_to_a.maximum:.4f} mm; "
                 f"{len(self.a.lines)} and {len(self.b.lines)} path segments (tool tip, part coordinates)"]
        for r in self.regions():
            side, other = ("A", "B") if r["from"] == "a" else ("B", "A")
            lines.append(f"  beyond: {side} lines {r['lines'][0]}-{r['lines'][1]} vs {other} lines "
                         f"{r['other_lines'][0]}-{r['other_lines'][1]}: up to {r['max']:.4f} mm")
        lines += [f"  {d}" for d in self.differences()]
        return "\n".join(lines)


def _list(prefix: str, values: list[int]) -> str:
    return " ".join(f"{prefix}{v}" for v in values) or "none"


def _round(v: float) -> float:
    return round(v, 6) + 0.0


def diff_programs(a: str | Path, b: str | Path, machine: Machine | dict | str | Path | None = None, *,
                  tolerance: float = 0.01, block_skip: bool = False) -> DiffReport:
    """Compare the planned tool paths of two programs (see the module docstring).  Raises
    :class:`DiffError` for what cannot be compared, :class:`~fagorcnc.config.machine.MachineError`
    for a bad machine."""
    if not (math.isfinite(tolerance) and tolerance > 0):
        raise DiffError("the tolerance must be a positive number of mm")
    mach = load_machine(machine)
    chord = min(CHORD_ERROR, tolerance / 20)
    eps = tolerance / 1000
    pa = program_path(a, mach, chord, block_skip=block_skip)
    pb = program_path(b, mach, chord, block_skip=block_skip)
    if not len(pa.lines) or not len(pb.lines):
        empty = pa.file if not len(pa.lines) else pb.file
        raise DiffError(f"{empty}: no motion to compare")
    from .geometry_index import SegmentIndex, directed  # on first use: the CLI builds this command's parser

    a_to_b = directed(pa.a, pa.b, SegmentIndex(pb.a, pb.b), tolerance, eps)
    b_to_a = directed(pb.a, pb.b, SegmentIndex(pa.a, pa.b), tolerance, eps)
    names = [a for a in mach.axis_names if not mach.axes[a].rotary][:3]
    return DiffReport(pa, pb, tolerance, eps, chord, a_to_b, b_to_a, names)


def command(args: argparse.Namespace) -> int:
    """Handler of ``fagorcnc diff``: 0 within the tolerance, 1 beyond, 2 bad usage."""
    for file in (args.a, args.b):
        if not Path(file).is_file():
            print(f"{file}: cannot read the file: {not_a_file(file)}", file=sys.stderr)
            return 2
    try:
        report = diff_programs(args.a, args.b, args.machine, tolerance=args.tolerance, block_skip=args.block_skip)
    except (DiffError, MachineError) as exc:
        print(f"fagorcnc: CLI001 {exc}" if isinstance(exc, DiffError) else f"fagorcnc: {exc}", file=sys.stderr)
        return 2
    for p in (report.a, report.b):
        for d in p.diagnostics:
            if d.is_error:
                print(d.render(), file=sys.stderr)
    if args.format == "json":
        print(json.dumps(report.to_dict(), indent=2, allow_nan=False))
    else:
        print(report.text())
    return 0 if report.within else 1


def add_parser(sub) -> None:
    """The ``diff`` sub-command's arguments."""
    p = sub.add_parser("diff", help="compare two programs' planned tool paths geometrically (max deviation, where, "
                                    "tools, offsets, boxes, cycle time); exit 1 beyond the tolerance")
    p.add_argument("a", metavar="A", help="the reference program (e.g. the old post-processor's output)")
    p.add_argument("b", metavar="B", help="the program compared with it")
    p.add_argument("--tolerance", type=float, default=0.01, metavar="MM",
                   help="largest deviation accepted between the paths (mm, default 0.01)")
    p.add_argument("--format", choices=("text", "json"), default="text", help="report format (default: text)")
    p.add_argument("--machine", metavar="M", help="machine configuration (TOML or LinuxCNC INI)")
    p.add_argument("--block-skip", action="store_true", help="skip blocks that start with '/'")
    p.set_defaults(func=command)
