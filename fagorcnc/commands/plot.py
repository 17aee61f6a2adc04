"""``fagorcnc plot``: a picture of the tool path (matplotlib, optional).

The path drawn is the **planned** motion in machine coordinates: every planned
piece is sampled, so arcs, helices and the corner blends of G05/HSC are
smooth curves; rapids are dashed, feeds solid, one colour per tool.  The moves
are the tool-centre path (radius compensation applied); when the program
compensates, the programmed contour (the same program run with every tool
radius set to 0) is drawn thin and black under it.  ``XY`` view by default,
``XZ``/``YZ`` on request, or a 3D view.  The title names the file and the
planned cycle time.  Moves made under a kinematics (#RTCP, #TOOL ORI) carry
tool-axis glyphs, short segments along the tool at sampled points; ``view``
``"tip"`` draws them at the tool tip in the part frame instead of the joints
(:mod:`fagorcnc.commands.plot_tool`).

matplotlib is an optional dependency (``pip install 'fagorcnc[plot]'``);
:func:`plot_program` raises :class:`MatplotlibMissingError` without it.  Only the
object-oriented API with the Agg/SVG canvases is used: no GUI, no global
pyplot state.
"""

from __future__ import annotations

import argparse
import copy
import dataclasses
import math
import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..config.machine import Machine, MachineError, load_machine
from ._shared import clock, not_a_file
from .plot_tool import VIEWS, ToolAxes, five_axis, tool_points

#: Output formats by file suffix.
FORMATS = (".png", ".svg", ".pdf")
#: Chord length of the sampling of curved pieces (mm) and the bounds of points per piece.
SAMPLE_STEP = 0.5
MIN_POINTS, MAX_POINTS = 8, 200
_RAPID_STYLE = {"linestyle": (0, (4, 3)), "linewidth": 0.8, "alpha": 0.7}
_FEED_STYLE = {"linestyle": "solid", "linewidth": 1.3}


class MatplotlibMissingError(RuntimeError):
    """matplotlib is not installed."""


@dataclass
class PlotInfo:
    """What :func:`plot_program` drew."""

    output: Path
    ok: bool                  # the program had no error
    diagnostics: list
    cycle_time: float         # s, planned
    segments: int             # planned motion segments drawn
    programmed: bool          # the programmed contour was drawn too
    view: str = "joints"      # "joints" or "tip" (see plot_tool)
    tool_axes: int = 0        # tool-axis glyphs drawn (moves under a kinematics)
    tool_axis_segments: np.ndarray | None = None   # the glyphs (k, 2, view axes): foot, other end


def _matplotlib():
    try:
        import matplotlib
        from matplotlib.figure import Figure
    except ImportError as exc:
        raise MatplotlibMissingError("fagorcnc plot needs matplotlib: pip install 'fagorcnc[plot]' "
                              "(or pip install matplotlib)") from exc
    return matplotlib, Figure


def _piece_points(piece) -> np.ndarray:
    """Points along a planned piece (machine coordinates, shape (n, axes))."""
    if not getattr(piece, "curved", False):
        return np.vstack([piece.start, piece.end])
    n = int(min(MAX_POINTS, max(MIN_POINTS, math.ceil(piece.length / SAMPLE_STEP) + 1)))
    if hasattr(piece, "points"):
        return piece.points(n)
    return piece.derivatives(np.linspace(0.0, piece.length, n))[0]


def _record_points(rec, axes: list[str]) -> np.ndarray:
    """Points along a motion record (for the programmed contour)."""
    start = np.array([rec.start.get(a, 0.0) for a in axes])
    end = np.array([rec.end.get(a, 0.0) for a in axes])
    if rec.kind != "arc":
        return np.vstack([start, end])
    a, o = rec.plane[0], rec.plane[1]
    ia, io = axes.index(a), axes.index(o)
    ca, co = rec.center[a], rec.center[o]
    th0 = math.atan2(start[io] - co, start[ia] - ca)
    r0 = math.hypot(start[ia] - ca, start[io] - co)
    r1 = math.hypot(end[ia] - ca, end[io] - co)
    sweep = math.radians(rec.sweep)
    n = int(min(MAX_POINTS, max(MIN_POINTS, math.ceil(abs(sweep) * max(r0, r1) / SAMPLE_STEP) + 1)))
    t = np.linspace(0.0, 1.0, n)
    pts = start + np.outer(t, end - start)
    r = r0 + (r1 - r0) * t
    pts[:, ia] = ca + r * np.cos(th0 + sweep * t)
    pts[:, io] = co + r * np.sin(th0 + sweep * t)
    return pts


def _zero_radius(machine: Machine) -> Machine:
    """The machine with every tool radius (and radius wear) 0: the programmed contour."""
    out = copy.copy(machine)
    out.tools = {t: {d: dataclasses.replace(off, radius=0.0, radius_wear=0.0) for d, off in offsets.items()}
                 for t, offsets in machine.tools.items()}
    return out


def plot_program(source: str | Path, output: str | Path, machine: Machine | dict | str | Path | None = None, *,
                 three_d: bool = False, plane: str = "XY", programmed: bool = True, limits: bool = False,
                 block_skip: bool = False, title: str | None = None, dpi: int = 150, view: str = "joints",
                 tool_axis: bool = True) -> PlotInfo:
    """Draw the planned tool path of a program into ``output`` (``.png``, ``.svg`` or ``.pdf``).

    ``plane`` names the two axes of the 2D view (``"XY"``, ``"XZ"``, ``"ZX"``...);
    ``three_d`` draws X, Y, Z in 3D instead; ``programmed`` adds the programmed
    contour when the program uses radius compensation; ``limits`` draws the
    soft limits.  ``view`` ``"joints"`` draws the planned joint positions,
    ``"tip"`` the tool tip of moves made under a kinematics; ``tool_axis`` draws
    the tool-axis glyphs of those moves.  Raises :class:`MatplotlibMissingError`
    without matplotlib, :class:`ValueError` for a bad output suffix, plane or view,
    :class:`~fagorcnc.config.machine.MachineError` for a bad machine.
    """
    from ..simulate import simulate

    output = Path(output)
    if output.suffix.lower() not in FORMATS:
        raise ValueError(f"{output}: the picture must be {', '.join(FORMATS)}")
    if view not in VIEWS:
        raise ValueError(f"view {view!r}: one of {', '.join(VIEWS)}")
    view_mode = view
    _, figure_class = _matplotlib()
    mach = load_machine(machine)
    axes_names = mach.axis_names
    view = ("X", "Y", "Z") if three_d else tuple(plane.upper())
    if len(view) != (3 if three_d else 2) or len(set(view)) != len(view) or any(a not in axes_names for a in view):
        raise ValueError(f"plane {plane!r}: name {'three' if three_d else 'two'} different axes of the machine "
                         f"({' '.join(axes_names)})")
    idx = [axes_names.index(a) for a in view]

    result = simulate(source, mach, block_skip=block_skip)
    # the records once, as objects: the tool of each is found by its id, and result.moves makes them
    # again at each access (fagorcnc.interp.movestore)
    moves = list(result.moves)
    polylines: list[tuple[np.ndarray, bool, int]] = []   # points, rapid?, tool
    tool = next_tool = 0
    by_record = {}
    for rec in moves:   # the tool in the spindle for each record (M06 loads the preselected T)
        if rec.kind == "aux" and rec.function == "T":
            next_tool = int(rec.value)
        elif rec.kind == "aux" and rec.function == "M" and int(rec.value) == 6:
            tool = next_tool
        by_record[id(rec)] = tool
    count = 0
    tool = 0
    tool_axes = ToolAxes()
    tipped = False   # some move drawn at the tool tip (the tip view of a move under a kinematics)
    if moves:
        from ..plan import Planner, PlanningError

        try:
            for seg in Planner(result.machine, keep_profiles=False).segments(moves):
                if seg.piece is None:
                    continue
                tool = by_record.get(id(seg.record), tool)
                rapid = getattr(seg.record, "kind", "") == "rapid" and not seg.blend
                pts = _piece_points(seg.piece)
                frame = five_axis(seg.record)
                if frame is not None:
                    pts, dirs = tool_points(pts, axes_names, frame, view_mode)
                    if all(a in frame.linear for a in view):   # (no glyph in a view of a rotary axis)
                        tool_axes.add(pts[:, idx], dirs[:, idx], seg.record.src)
                    tipped = tipped or view_mode == "tip"
                pts = pts[:, idx]
                if polylines and polylines[-1][1] == rapid and polylines[-1][2] == tool \
                        and np.allclose(polylines[-1][0][-1], pts[0]):
                    polylines[-1] = (np.vstack([polylines[-1][0], pts[1:]]), rapid, tool)
                else:
                    polylines.append((pts, rapid, tool))
                count += 1
        except PlanningError:
            pass   # reported in result.diagnostics; draw what was planned

    contour: list[np.ndarray] = []
    compensated = any(getattr(r, "comp", None) and r.comp[1] for r in moves)
    if programmed and compensated:
        zero = simulate(source, _zero_radius(mach), block_skip=block_skip)
        contour = [_record_points(r, axes_names)[:, idx] for r in zero.moves if r.kind in ("linear", "arc")]

    fig = figure_class(figsize=(8, 6.5) if not three_d else (8, 7))
    ax = fig.add_subplot(projection="3d") if three_d else fig.add_subplot()
    colours = [f"C{i}" for i in range(10)]
    tools_seen: list[int] = []
    labelled: set[tuple[int, bool]] = set()
    for pts, rapid, t in polylines:
        if t not in tools_seen:
            tools_seen.append(t)
        colour = colours[tools_seen.index(t) % len(colours)]
        key = (t, rapid)
        label = None
        if key not in labelled:
            labelled.add(key)
            label = f"T{t} {'rapid' if rapid else 'feed'}"
        style = _RAPID_STYLE if rapid else _FEED_STYLE
        ax.plot(*pts.T, color=colour, label=label, **style)
    for i, pts in enumerate(contour):
        ax.plot(*pts.T, color="black", linewidth=0.5, label="programmed contour" if i == 0 else None)
    if not three_d:   # holes: feed moves along the view's normal only (drilling, canned cycles) are points
        holes: dict[tuple, int] = {}
        for rec in moves:
            if rec.kind == "linear" and rec.length > 0 and all(abs(rec.end[a] - rec.start[a]) < 1e-9 for a in view):
                holes.setdefault((round(rec.end[view[0]], 6), round(rec.end[view[1]], 6)), by_record[id(rec)])
        for i, ((hx, hy), t) in enumerate(holes.items()):
            colour = colours[tools_seen.index(t) % len(colours)] if t in tools_seen else "black"
            ax.plot([hx], [hy], marker="o", markersize=5, fillstyle="none", color=colour, linestyle="none",
                    label="plunge / hole" if i == 0 else None)
    glyphs = np.empty((0, 2, len(view)))
    if tool_axis and tool_axes.points:
        every = np.vstack([p for p, _, _ in polylines])
        extent = float(np.max(every.max(axis=0) - every.min(axis=0))) or 1.0
        glyphs = tool_axes.glyphs(extent)
        gap = np.full((len(glyphs), 1, len(view)), np.nan)   # one line, broken between the glyphs
        line = np.concatenate([glyphs, gap], axis=1).reshape(-1, len(view))
        ax.plot(*line.T, color="purple", linewidth=0.7, gid="tool-axis",
                label=f"tool axis ({'at the tip' if view_mode == 'tip' else 'from the joints'})")
    if polylines:
        start = polylines[0][0][0]
        ax.plot(*([v] for v in start), marker="o", color="green", markersize=4, linestyle="none", label="start")
    if limits and not three_d:
        lo = [mach.axes[a].min_limit for a in view]
        hi = [mach.axes[a].max_limit for a in view]
        ax.plot([lo[0], hi[0], hi[0], lo[0], lo[0]], [lo[1], lo[1], hi[1], hi[1], lo[1]], color="red",
                linewidth=0.8, linestyle=":", label="soft limits")

    basis = "tool-tip view, mm" if tipped else "machine, mm"
    ax.set_xlabel(f"{view[0]} ({basis})")
    ax.set_ylabel(f"{view[1]} ({basis})")
    if three_d:
        ax.set_zlabel(f"{view[2]} ({basis})")
        _equal_3d(ax, [p for p, _, _ in polylines] + contour)
    else:
        ax.set_aspect("equal", adjustable="datalim")
        ax.grid(True, linewidth=0.3, alpha=0.5)
    name = Path(str(source)).name if "\n" not in str(source) else "<program>"
    heading = title or f"{name} — cycle time {clock(result.cycle_time)} (planned)"
    if not result.ok:
        heading += f" — {sum(d.is_error for d in result.diagnostics)} error(s)"
    ax.set_title(heading, fontsize=10)
    if polylines or contour:
        ax.legend(fontsize=7, loc="best")
    fig.tight_layout()
    fig.savefig(output, dpi=dpi)
    return PlotInfo(output, result.ok, result.diagnostics, result.cycle_time, count, bool(contour), view_mode,
                    len(glyphs), glyphs)


def _equal_3d(ax, arrays: list[np.ndarray]) -> None:
    if not arrays:
        return
    pts = np.vstack(arrays)
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    span = np.maximum(hi - lo, 1e-9)
    ax.set_box_aspect(tuple(np.maximum(span / span.max(), 0.05)))



# --- the ``fagorcnc plot`` command -----------------------------------------------------

def command(args: argparse.Namespace) -> int:
    """Handler of ``fagorcnc plot``: exit 0 when drawn from a clean program, 1 with errors, 2 on bad usage."""
    if not Path(args.file).is_file():
        print(f"{args.file}: cannot read the file: {not_a_file(args.file)}", file=sys.stderr)
        return 2
    try:
        info = plot_program(Path(args.file), args.output, args.machine, three_d=args.three_d, plane=args.plane,
                            programmed=not args.no_programmed, limits=args.limits, block_skip=args.block_skip,
                            view=args.view, tool_axis=not args.no_tool_axis)
    except MatplotlibMissingError as exc:
        print(f"fagorcnc: {exc}", file=sys.stderr)
        return 2
    except (MachineError, ValueError) as exc:
        print(f"fagorcnc: {exc}", file=sys.stderr)
        return 2
    except OSError as exc:
        print(f"fagorcnc: cannot write {args.output}: {exc.strerror or exc}", file=sys.stderr)
        return 2
    for d in info.diagnostics:
        if d.severity != "info":
            print(d.render(), file=sys.stderr)
    print(f"{args.output}: {info.segments} planned segments, cycle time {clock(info.cycle_time)}"
          + (", programmed contour drawn" if info.programmed else "")
          + (f", {info.tool_axes} tool-axis glyphs ({info.view} view)" if info.tool_axes else ""))
    return 0 if info.ok else 1
