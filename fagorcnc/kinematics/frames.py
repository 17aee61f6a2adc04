"""Coordinate systems of #CS and #ACS: the six definition modes and the active stack (seed 002
L12557-L13129; spec 05 §6.3-§6.5).

Every mode gives an origin ``V`` (in the parent frame) and a right-handed orthonormal ``R`` whose
columns are the new axes X', Y', Z' written in the parent frame: ``p_parent = V + R p_new``.
Angles are degrees, positive counter-clockwise seen from the positive end of the axis (right-hand rule;
the manual's figures are lost, A20).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .rotation import rx, ry, rz, unit

#: Values after ``MODE m``: (origin and angles, optional trailing flag)
MODE_VALUES = {1: 6, 2: 6, 3: 6, 4: 6, 5: 6, 6: 4}


@dataclass(frozen=True)
class CoordinateSystem:
    """One #CS or #ACS definition: ``p_parent = origin + rotation @ p_new``."""

    mode: int
    origin: tuple[float, float, float]
    rotation: tuple[tuple[float, float, float], ...]
    values: tuple[float, ...] = ()
    sol2: bool = False

    @property
    def matrix(self) -> np.ndarray:
        return np.array(self.rotation, dtype=float)

    @property
    def vector(self) -> np.ndarray:
        return np.array(self.origin, dtype=float)


IDENTITY = ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))


def _tuple(m: np.ndarray) -> tuple[tuple[float, float, float], ...]:
    return tuple(tuple(float(x) for x in row) for row in m)


def mode_1(a: float, b: float, c: float) -> np.ndarray:
    """MODE 1: about X, then about the new Y', then about the new Z'' (seed 002 L12815-L12842)."""
    return rx(a) @ ry(b) @ rz(c)


def mode_2(a: float, b: float, c: float) -> np.ndarray:
    """MODE 2, spherical (Euler): about Z, then the new Y', then the new Z'' (seed 002 L12844-L12872)."""
    return rz(a) @ ry(b) @ rz(c)


_MODE_AXES = {3: ((1, 0, 0), (0, 1, 0), (0, 0, 1)), 4: ((1, 0, 0), (0, 0, 1), (0, -1, 0)),
              5: ((0, 1, 0), (0, 0, 1), (1, 0, 0))}


def mode_345(mode: int, alpha: float, beta: float, psi: float, edge: int) -> np.ndarray:
    """MODES 3-5: the plane by its angles to two machine axes [reconstruction, spec 05 §6.4.3; the
    manual's figures are lost].  ``edge`` 0 puts X' along the plane's trace on the first axis, 1 puts
    Y' along the trace on the second axis."""
    u, w, m = (np.array(v, dtype=float) for v in _MODE_AXES[mode])
    ca, sa = math.cos(math.radians(alpha)), math.sin(math.radians(alpha))
    cb, sb = math.cos(math.radians(beta)), math.sin(math.radians(beta))
    a = ca * u + sa * m
    b = cb * w + sb * m
    n = unit(np.cross(a, b))
    if edge:
        y = unit(b)
        x = np.cross(y, n)
    else:
        x = unit(a)
        y = np.cross(n, x)
    return np.column_stack([x, y, n]) @ rz(psi)


def mode_6(tool: np.ndarray, psi: float, which: str | None, tool_frame: np.ndarray | None = None) -> np.ndarray:
    """MODE 6: Z' along the present tool direction ``tool`` (seed 002 L12965-L13022).  ``which``
    "FIRST": the projection of X' lies along machine X; "SECOND": Y' along machine Y; None: the tool's
    own frame ``tool_frame`` (the head's X'' Y'' Z'') when given, else FIRST."""
    n = unit(tool)
    if which is None and tool_frame is not None:
        base = tool_frame
    elif which == "SECOND":
        y = np.array([0.0, 1.0, 0.0]) - n[1] * n
        if np.linalg.norm(y) < 1e-9:
            raise ValueError("the tool lies along machine Y: SECOND cannot align Y'")
        y = unit(y)
        base = np.column_stack([np.cross(y, n), y, n])
    else:
        x = np.array([1.0, 0.0, 0.0]) - n[0] * n
        if np.linalg.norm(x) < 1e-9:
            raise ValueError("the tool lies along machine X: FIRST cannot align X'")
        x = unit(x)
        base = np.column_stack([x, np.cross(n, x), n])
    return base @ rz(psi)


def make(mode: int, origin, rotation: np.ndarray, values=(), sol2: bool = False) -> CoordinateSystem:
    return CoordinateSystem(mode, tuple(float(v) for v in origin), _tuple(rotation), tuple(values), sol2)


def compose(systems: list[CoordinateSystem]) -> tuple[np.ndarray, np.ndarray]:
    """(R, V) of systems applied in order: ``p = T1(T2(...(p_new)))``, ``Ti(p) = Vi + Ri p``."""
    r = np.eye(3)
    v = np.zeros(3)
    for cs in systems:
        v = v + r @ cs.vector
        r = r @ cs.matrix
    return r, v
