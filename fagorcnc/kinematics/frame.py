"""The active transformation of a record: from the interpreter's coordinates to the machine's joints.

While #CS/#ACS, #RTCP, #TLC or an oriented tool (#TOOL ORI) is active, the interpreter computes in
*virtual* coordinates: the programmed point plus the origin chain and the tool length on the
longitudinal axis, as it does without a transformation, so that radius compensation and the corner
aids work in the plane they are programmed in.  A :class:`Frame` turns such a position into machine
joint positions:

* plane: ``p = R (v - l) + t`` (spec 05 §6.5: ``p_machine = O + T_A(T_C(p_programmed))``, ``t = O + V - R O``,
  ``l`` the tool length offset);
* no kinematics in use: ``machine = p + l`` (the tool length stays along the machine's tool axis);
* kinematics in use (#RTCP, or #TOOL ORI under a plane): ``p`` is the tool tip in the part frame and
  the joints come from :func:`~fagorcnc.kinematics.solve.linear_for_tip` at the position's own
  rotary-axis values;
* #TLC ``d``: the position moves ``d`` along the tool toward the spindle (seed 002 L13343-L13373).

Axes outside the three linear axes of the trihedron pass through unchanged.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..config.kinematics import Kinematics
from .solve import forward, linear_for_tip, tool_direction_machine


@dataclass(frozen=True, eq=False)
class Frame:
    """The transformation of the records made while it is active (``record.frame``).

    ``description`` names what is active (``"#CS"``, ``"#RTCP"``, ``"#CS+#RTCP"``, ``"#TLC"``...),
    ``kinematics`` the kinematics in use (None when the joints are the linear axes alone).
    """

    description: str
    rotation: np.ndarray              # 3x3, the plane's R (identity without a plane)
    shift: np.ndarray                 # t = O + V - R O
    linear: tuple[str, str, str]      # the trihedron's machine axes (X, Y, Z)
    length: np.ndarray                # the tool length offset on the linear axes, virtual coordinates
    kinematics: Kinematics | None = None
    engaged: bool = False             # the kinematics turns tool-tip positions into joints
    tlc: float = 0.0
    pieces: bool = False              # the frame of the joint-space lines of one move (one per move)
    arcs = True                       # an arc may stay an arc (see stage.JointStage)
    initial_pieces = 1                # the first cut of a move into joint-space lines

    @property
    def tool_length(self) -> float:
        return float(self.length.sum())

    def rotates(self) -> bool:
        """Whether the plane is turned (a non-identity R)."""
        return not np.allclose(self.rotation, np.eye(3), atol=1e-12)

    def _angles(self, pos: dict) -> dict:
        kin = self.kinematics
        return {a: pos.get(a, 0.0) for a in kin.axes} if kin is not None else {}

    def point(self, pos: dict, near: dict | None = None) -> dict:
        """Machine joint positions of the virtual position ``pos`` (a dict of every axis it names);
        ``near`` is for frames whose joints have several values (see caxis.FaceFrame)."""
        x, y, z = self.linear
        v = np.array([pos[x], pos[y], pos[z]], dtype=float)
        p = self.rotation @ (v - self.length) + self.shift
        kin = self.kinematics
        angles = self._angles(pos)
        m = linear_for_tip(kin, p, angles, self.tool_length) if self.engaged else p + self.length
        if self.tlc:
            m = m + self.tlc * self._tool(angles)
        out = dict(pos)
        out[x], out[y], out[z] = float(m[0]), float(m[1]), float(m[2])
        return out

    def inverse(self, machine: dict) -> dict:
        """The virtual position of machine joint positions ``machine`` (inverse of :meth:`point`)."""
        x, y, z = self.linear
        m = np.array([machine[x], machine[y], machine[z]], dtype=float)
        angles = self._angles(machine)
        if self.tlc:
            m = m - self.tlc * self._tool(angles)
        p = forward(self.kinematics, m, angles, self.tool_length)[0] if self.engaged else m - self.length
        v = self.rotation.T @ (p - self.shift) + self.length
        out = dict(machine)
        out[x], out[y], out[z] = float(v[0]), float(v[1]), float(v[2])
        return out

    def _tool(self, angles: dict) -> np.ndarray:
        kin = self.kinematics
        return tool_direction_machine(kin, angles) if kin is not None else np.array([0.0, 0.0, 1.0])

    def affine_between(self, start: dict, end: dict) -> bool:
        """Whether the map is the same rigid motion at both positions (no rotary axis of the
        kinematics moves), so a line stays a line and an arc an arc."""
        kin = self.kinematics
        if kin is None or not (self.engaged or self.tlc):
            return True
        return all(abs(start.get(a, 0.0) - end.get(a, 0.0)) < 1e-12 for a in kin.axes)

    def linear_part(self, pos: dict) -> np.ndarray:
        """The 3x3 matrix of the map at ``pos``'s rotary values (its rotation part)."""
        x, y, z = self.linear
        base = self.point(pos)
        cols = []
        for axis in (x, y, z):
            q = dict(pos)
            q[axis] = q[axis] + 1.0
            p = self.point(q)
            cols.append([p[x] - base[x], p[y] - base[y], p[z] - base[z]])
        return np.array(cols, dtype=float).T

    def tool_axis(self, pos: dict) -> tuple[float, float, float]:
        """The tool direction (tip -> spindle) in machine coordinates at ``pos``."""
        return tuple(float(c) for c in self._tool(self._angles(pos)))


@dataclass(frozen=True, eq=False, kw_only=True)
class AxisFrame:
    """What the frames of the axis transformations share (#FACE, #CYL, #ANGAX): a map of the programmed
    axes onto the machine's, with no kinematics and no tool length of their own.  Each subclass names
    itself in ``description`` and says whether an arc stays an arc (``arcs``) and how finely a move is
    first cut (``initial_pieces``)."""

    kinematics: object = None
    engaged: bool = False
    tlc: float = 0.0
    pieces: bool = False
    description = ""
    arcs = False
    initial_pieces = 1

