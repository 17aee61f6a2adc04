"""What ``fagorcnc plot`` draws of the tool under a kinematics: the tool-tip view and the tool-axis glyphs.

A move made while a kinematics is in use (``record.frame`` a :class:`~fagorcnc.kinematics.frame.Frame`
with a kinematics: #RTCP, #TOOL ORI, or a plane with the rotary axes programmed) is planned in machine
joints: the linear axes are the head reference point, the rotary axes turn the head or the table.

* **joints** view: the planned joint positions, as every other move.  A tool-axis glyph at a sampled
  point is the tool itself, from the head reference point toward the tip (``-t`` in machine
  coordinates, ``t`` the tool direction tip -> spindle).
* **tip** view: the tool tip in the part frame (the table turned back to 0, forward kinematics with the
  frame's tool length), plus the tool length offset the interpreter puts on the longitudinal axis --
  the position the axes would show for that tip without a kinematics, the basis on which every
  move made without one is drawn [CONSTRUCTION: records made without a kinematics do not carry their
  tool length, so the tip view keeps the machine positions' basis; with a zero tool length it is the
  tip itself].  A glyph goes from that point along the tool direction in the part frame.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..kinematics.frame import Frame
from ..kinematics.solve import forward, tool_direction_machine

#: The views of ``fagorcnc plot --view``.
VIEWS = ("joints", "tip")
#: Glyph length and the least distance between two glyphs, as fractions of the drawing's extent
#: [CONSTRUCTION: readable on a screen-sized picture].
GLYPH_LENGTH, GLYPH_SPACING = 0.06, 0.025


def five_axis(record) -> Frame | None:
    """The frame of ``record`` when it was made with a kinematics of rotary joints in use, else None."""
    frame = getattr(record, "frame", None)
    if type(frame) is not Frame or frame.kinematics is None or frame.kinematics.c_axis:
        return None
    return frame


@dataclass
class ToolAxes:
    """The tool-axis glyph candidates of a run: (point, direction) pairs in the drawing's axes, with the
    block each comes from."""

    points: list = field(default_factory=list)
    directions: list = field(default_factory=list)
    blocks: list = field(default_factory=list)

    def add(self, points: np.ndarray, directions: np.ndarray, block) -> None:
        self.points.extend(points)
        self.directions.extend(directions)
        self.blocks.extend([block] * len(points))

    def glyphs(self, extent: float) -> np.ndarray:
        """Segments (k, 2, dims) of length ``GLYPH_LENGTH * extent``: one where each block ends, and one
        wherever the glyph's foot or its other end has run ``GLYPH_SPACING * extent`` since the last
        one drawn (a tool turning about a fixed tip gets glyphs too)."""
        if not self.points:
            return np.empty((0, 2, 0))
        length, spacing = GLYPH_LENGTH * extent, GLYPH_SPACING * extent
        out: list[np.ndarray] = []
        run = 0.0
        prev = None
        n = len(self.points)
        for i, (p, d) in enumerate(zip(self.points, self.directions, strict=True)):
            seg = np.vstack([p, p + length * d])
            if prev is not None:
                run += float(np.max(np.linalg.norm(seg - prev, axis=1)))
            prev = seg
            end = i == n - 1 or self.blocks[i + 1] != self.blocks[i]
            if not out or run >= spacing or (end and not np.allclose(out[-1], seg, atol=1e-9)):
                run = 0.0
                out.append(seg)
        return np.array(out)


def tool_points(points: np.ndarray, axes: list[str], frame: Frame, view: str) -> tuple[np.ndarray, np.ndarray]:
    """(positions, glyph directions) of the sampled joint ``points`` (shape (n, len(axes))) of a move made
    under ``frame``: positions in the chosen ``view`` (all axes; the linear ones moved to the tip in the
    tip view), directions unit vectors on the linear axes (0 on the others)."""
    kin = frame.kinematics
    lin = [axes.index(a) for a in frame.linear]
    out = np.array(points, dtype=float)
    dirs = np.zeros_like(out)
    length = frame.tool_length
    for k, row in enumerate(out):
        angles = {a: float(row[axes.index(a)]) if a in axes else 0.0 for a in kin.axes}
        if view == "tip":
            tip, d = forward(kin, row[lin], angles, length)
            out[k, lin] = tip + frame.length
            dirs[k, lin] = d
        else:
            dirs[k, lin] = -tool_direction_machine(kin, angles)
    return out, dirs

