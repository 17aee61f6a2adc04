"""Programmed-coordinate transformations: scaling G72/#SCALE, mirror G10-G14, rotation G73.

Order (spec 04 §10.1, seed 002 L8705-L9141): a programmed point (part
coordinates as written, after units, G90/G91 and polar resolution) is scaled
about the part zero, then mirrored about the part zero, then rotated in the
active plane about the G73 centre.  Scaling applies to the linear axes; the
G73 centre is itself mirrored (L8906-L8980).  The inverse gives the
programmed coordinates of a point, e.g. of the current position for G91
moves and polar coordinates.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field


@dataclass
class Transform:
    """The active scale, mirrored axes and rotation of a channel."""

    scale: float = 1.0
    mirror: set = field(default_factory=set)
    angle: float = 0.0                 # degrees, counter-clockwise in the plane
    centre: tuple = (0.0, 0.0)         # G73 I J, programmed coordinates of the plane
    plane: tuple = ("X", "Y")          # plane the rotation was programmed in
    linear: frozenset = frozenset()    # axes that scale (linear axes)

    @property
    def identity(self) -> bool:
        return self.scale == 1.0 and not self.mirror and self.angle == 0.0

    def flips(self, a: str, o: str) -> bool:
        """True when an odd number of the plane's axes is mirrored: G02 <-> G03 (L8740)."""
        return (a in self.mirror) != (o in self.mirror)

    def _rot(self) -> tuple[float, float, float, float, str, str]:
        q = math.radians(self.angle)
        a, o = self.plane
        ca = -self.centre[0] if a in self.mirror else self.centre[0]
        co = -self.centre[1] if o in self.mirror else self.centre[1]
        return math.cos(q), math.sin(q), ca, co, a, o

    def apply(self, p: dict) -> dict:
        """Programmed coordinates -> transformed part coordinates."""
        if self.identity:
            return dict(p)
        out = {}
        for axis, v in p.items():
            if axis in self.linear:
                v *= self.scale
            if axis in self.mirror:
                v = -v
            out[axis] = v
        if self.angle:
            c, s, ca, co, a, o = self._rot()
            if a in out and o in out:
                da, do = out[a] - ca, out[o] - co
                out[a], out[o] = ca + c * da - s * do, co + s * da + c * do
        return out

    def invert(self, p: dict) -> dict:
        """Transformed part coordinates -> programmed coordinates."""
        if self.identity:
            return dict(p)
        out = dict(p)
        if self.angle:
            c, s, ca, co, a, o = self._rot()
            if a in out and o in out:
                da, do = out[a] - ca, out[o] - co
                out[a], out[o] = ca + c * da + s * do, co - s * da + c * do
        for axis in out:
            if axis in self.mirror:
                out[axis] = -out[axis]
            if axis in self.linear and self.scale != 0:
                out[axis] /= self.scale
        return out
