"""The tool tip of a sampled trajectory: the joints the planner sampled, through the forward kinematics."""

from __future__ import annotations

import numpy as np

from ..config.kinematics import Kinematics
from .solve import forward


def tool_tip(trajectory, kinematics: Kinematics, length: float = 0.0, linear=("X", "Y", "Z")) -> dict[str, np.ndarray]:
    """``{"X": ..., "Y": ..., "Z": ...}``: the tool tip in the part frame (the table's frame at 0) at every
    sample of ``trajectory`` (``Result.trajectory()``), for a tool ``length`` mm long; with the tool
    direction as ``"I"``, ``"J"``, ``"K"`` (tip -> spindle)."""
    pos = trajectory.position
    n = len(trajectory.t)
    out = np.empty((n, 6))
    for k in range(n):
        angles = {a: float(pos[a][k]) for a in kinematics.axes}
        tip, d = forward(kinematics, [float(pos[a][k]) for a in linear], angles, length)
        out[k, :3], out[k, 3:] = tip, d
    return {"X": out[:, 0], "Y": out[:, 1], "Z": out[:, 2], "I": out[:, 3], "J": out[:, 4], "K": out[:, 5]}
