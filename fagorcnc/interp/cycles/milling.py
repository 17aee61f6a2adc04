"""G210 bore milling (digest §2.9, provisional: no source gives its parameters).

G211/G212 (thread milling) are in :mod:`.threads`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..expressions import InterpError
from . import choices
from .drilling import levels, positive


@dataclass(frozen=True)
class Bore:
    zr: float
    zb: float
    radius: float          # path radius rho = |J| - r
    pitch: float           # depth per helix turn, mm
    finish: bool           # C1: a full circle at the bottom
    bottom_feed: float | None   # H as programmed (None: F)
    ccw: bool


def prepare(cyc, rn) -> Bore:
    lv = levels(cyc, rn)
    positive(cyc, "D", 0.0, rn)   # D only names where the cut starts; it does not change the path (§2.9)
    r = rn.tool_radius()
    if not cyc.has("J"):
        raise InterpError("CYC004", "G210 needs J, the bore radius (J+ clockwise, J- counter-clockwise)",
                          cyc.col("G"))
    j = rn.length(cyc.get("J"), cyc)
    if abs(j) <= r or j == 0:
        raise InterpError("CYC005", f"G210: the tool (radius {r:g} mm) is too big for the bore of radius "
                          f"{abs(j):g} mm", cyc.col("J"))
    k = positive(cyc, "K", 0.0, rn)
    if k >= 2 * abs(j):
        raise InterpError("CYC004", f"G210 K: the pre-drilled diameter {k:g} mm is not smaller than the bore",
                          cyc.col("K"))
    if not cyc.has("B") or cyc.get("B") == 0:
        raise InterpError("CYC004", "G210 needs B, the helix pitch (depth per turn), not 0",
                          cyc.col("B") if cyc.has("B") else cyc.col("G"))
    pitch = abs(rn.length(cyc.get("B"), cyc))
    turns = abs(lv.zb - lv.zr) / pitch
    rn.guard_moves(turns, cyc, "B")
    c = cyc.get("C", 0.0)
    if c not in (0.0, 1.0):
        raise InterpError("CYC004", f"G210 C{c:g}: C1 finishes the bottom with a full circle, C0 does not",
                          cyc.col("C"))
    h = cyc.get("H", 0.0) or None
    return Bore(lv.zr, lv.zb, abs(j) - r, pitch, c == 1.0, h, j < 0)


def ops(cyc, bore: Bore, rn, point) -> list:
    """Entry semicircle, helix of pitch B at radius rho down to Zb, bottom circle (C1), exit semicircle
    [CONSTRUCTION, digest §2.9].  A partial last turn ends off the start angle: the bottom is then
    finished along the circle back to it, so the exit semicircle always starts at (rho, 0)."""
    a, o, ln = cyc.plane
    cx, cy = point
    f = rn.feed(None, cyc.col("G"))
    fh = rn.feed(bore.bottom_feed, cyc.col("H")) if bore.bottom_feed else f
    rho = bore.radius
    down = 1.0 if bore.zb > bore.zr else -1.0
    sign = 1.0 if bore.ccw else -1.0

    def p(u: float, v: float, z: float) -> dict:
        return {a: cx + u, o: cy + v, ln: z}

    out = []
    if rn.spindle() == 5 and choices.POCKET_STARTS_SPINDLE:
        out.append(("M", choices.POCKET_STARTS_SPINDLE))
    entry = (cx + rho / 2.0, cy)
    out += [("R", p(0, 0, bore.zr)), ("A", p(rho, 0, bore.zr), entry, bore.ccw, f)]
    depth = abs(bore.zb - bore.zr)
    full = int(depth / bore.pitch + 1e-9)
    for n in range(1, full + 1):
        out.append(("A", p(rho, 0, bore.zr + down * bore.pitch * n), point, bore.ccw, f))
    rest = depth - full * bore.pitch
    if rest > 1e-9:   # the partial last turn, then back along the bottom to the start angle
        angle = sign * 2.0 * math.pi * rest / bore.pitch
        out.append(("A", p(rho * math.cos(angle), rho * math.sin(angle), bore.zb), point, bore.ccw, f))
        out.append(("A", p(rho, 0, bore.zb), point, bore.ccw, fh))
    if bore.finish:
        out.append(("A", p(rho, 0, bore.zb), point, bore.ccw, fh))
    out += [("A", p(0, 0, bore.zb), entry, bore.ccw, f), ("R", p(0, 0, rn.return_level(cyc, bore.zr)))]
    return out
