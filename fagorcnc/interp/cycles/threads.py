"""G211 inside / G212 outside thread milling (digest §2.9, provisional: no source gives their parameters).

``G21x [G98|G99] [point] [Z] I [D] J K B [C]`` with the digest's recommended meanings:

* ``Z``, ``I``, ``D`` as G87 (reference plane, bottom, distance to the part surface: D moves nothing);
* ``J`` the thread radius the tooth tip reaches ("nominal thread radius", §2.9); the tool centre mills at
  ``|J| - r`` (G211) or ``|J| + r`` (G212);
* ``K`` the radial thread depth: the entry and the exit go from and to the clearance radius
  ``|J| - r - K`` (G211) or ``|J| + r + K`` (G212);
* ``B`` the pitch, its sign the hand (B+ right-hand, B- left-hand);
* ``C`` 0 top-down (from Zr to Zb), 1 bottom-up (a rapid down to Zb at the clearance radius first).

The path is the digest's [CONSTRUCTION]; what spec 09 leaves open is fixed in ``choices``
(``THREAD_*``): one pass, tangential semicircles, the retract order, the hand and the turning sense.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..expressions import InterpError
from . import choices
from .drilling import levels, positive


@dataclass(frozen=True)
class Thread:
    zr: float
    zb: float
    radius: float          # path radius of the tool centre: |J| - r (G211) or |J| + r (G212)
    clearance: float       # entry/exit radius: radius - K (G211) or radius + K (G212)
    pitch: float           # |B|, mm per turn
    ccw: bool              # turning sense of the helix (G03), from the hand and the axial direction
    bottom_up: bool        # C1


def prepare(cyc, rn) -> Thread:
    """Every parameter of G211/G212 checked (digest §1.5 errors) before anything moves."""
    lv = levels(cyc, rn)
    positive(cyc, "D", 0.0, rn)   # as G210: D only names where the cut starts (§2.9)
    name = f"G{cyc.code}"
    if cyc.has("H"):
        raise InterpError("CYC004", f"{name} H: no source gives H a meaning in thread milling (provisional "
                          "semantics); leave it out", cyc.col("H"))
    if not cyc.has("J"):
        raise InterpError("CYC004", f"{name} needs J, the thread radius (where the tooth tip cuts)", cyc.col("G"))
    j = rn.length(cyc.get("J"), cyc)
    if j <= 0:
        raise InterpError("CYC004", f"{name} J{cyc.get('J'):g}: the thread radius must be more than 0 (the hand "
                          "is the sign of B)", cyc.col("J"))
    if not cyc.has("K") or cyc.get("K") <= 0:
        raise InterpError("CYC004", f"{name} needs K, the radial depth of the thread, more than 0",
                          cyc.col("K") if cyc.has("K") else cyc.col("G"))
    k = rn.length(cyc.get("K"), cyc)
    if not cyc.has("B") or cyc.get("B") == 0:
        raise InterpError("CYC004", f"{name} needs B, the thread pitch (B+ right-hand, B- left-hand), not 0",
                          cyc.col("B") if cyc.has("B") else cyc.col("G"))
    b = rn.length(cyc.get("B"), cyc)
    c = cyc.get("C", 0.0)
    if c not in (0.0, 1.0):
        raise InterpError("CYC004", f"{name} C{c:g}: C0 mills from the top down, C1 from the bottom up",
                          cyc.col("C"))
    r = rn.tool_radius()
    inside = cyc.code == 211
    radius = j - r if inside else j + r
    clearance = radius - k if inside else radius + k
    if inside and (radius <= 0 or clearance < -1e-9):
        raise InterpError("CYC005", f"G211: the tool (radius {r:g} mm) is too big for the thread of radius {j:g} "
                          f"mm and depth {k:g} mm (it needs a radius of at most {j - k:g} mm)", cyc.col("J"))
    pitch = abs(b)
    rn.guard_moves(abs(lv.zb - lv.zr) / pitch, cyc, "B")
    bottom_up = c == 1.0
    # the axial motion during the helix: towards Zb (top-down) or back towards Zr (bottom-up)
    rising = (lv.down > 0) != bottom_up
    right_hand = (b > 0) == (choices.THREAD_RIGHT_HAND_B > 0)
    # a right-hand helix turns counter-clockwise (seen from +l) while it rises along +l (planes G17, G18
    # and G19 are all right-handed: (X, Y, Z), (Z, X, Y), (Y, Z, X))
    ccw = rising == right_hand
    return Thread(lv.zr, lv.zb, radius, max(clearance, 0.0), pitch, ccw, bottom_up)


def ops(cyc, th: Thread, rn, point) -> list:
    """One thread at ``point``: approach, entry semicircle, helix of pitch |B|, exit semicircle, retract
    [CONSTRUCTION, digest §2.9; the open details in ``choices.THREAD_*``]."""
    a, o, ln = cyc.plane
    cx, cy = point
    f = rn.feed(None, cyc.col("G"))
    inside = cyc.code == 211

    def p(u: float, v: float, z: float) -> dict:
        return {a: cx + u, o: cy + v, ln: z}

    out = []
    if rn.spindle() == 5 and choices.POCKET_STARTS_SPINDLE:
        out.append(("M", choices.POCKET_STARTS_SPINDLE))   # milling cycles start a stopped spindle (§1.4)
    start, end = (th.zb, th.zr) if th.bottom_up else (th.zr, th.zb)
    rho, rc = th.radius, th.clearance
    out += [("R", p(0, 0, th.zr)), ("R", p(rc, 0, th.zr))]
    if th.bottom_up:
        out.append(("R", p(rc, 0, th.zb)))   # down at the clearance radius, in rapid (§2.9)
    # tangential entry: inside the semicircle turns with the helix, outside against it (choices)
    semi = th.ccw if inside else not th.ccw
    out.append(("A", p(rho, 0, start), (cx + (rho + rc) / 2.0, cy), semi, f))
    depth = abs(end - start)
    step = math.copysign(th.pitch, end - start)
    full = int(depth / th.pitch + 1e-9)
    rest = depth - full * th.pitch
    for n in range(1, full + 1):   # the last whole turn ends exactly on the end level when no part turn follows
        z = end if n == full and rest <= 1e-9 else start + step * n
        out.append(("A", p(rho, 0, z), point, th.ccw, f))
    angle = 0.0
    if rest > 1e-9:   # the partial last turn ends off the start angle; the exit leaves from there
        angle = (1.0 if th.ccw else -1.0) * 2.0 * math.pi * rest / th.pitch
        out.append(("A", p(rho * math.cos(angle), rho * math.sin(angle), end), point, th.ccw, f))
    cos, sin = math.cos(angle), math.sin(angle)
    mid = (rho + rc) / 2.0
    out.append(("A", p(rc * cos, rc * sin, end), (cx + mid * cos, cy + mid * sin), semi, f))
    ret = rn.return_level(cyc, th.zr)
    if inside:   # inside the hole: to the axis first, then up
        return [*out, ("R", p(0, 0, end)), ("R", p(0, 0, ret))]
    # outside, the axis is over the part: up at the clearance radius first (to the return level, or to Zr
    # when the starting plane lies below it), then to the axis
    down = 1.0 if th.zb > th.zr else -1.0
    up = ret if (ret - th.zr) * down <= 0 else th.zr
    return [*out, ("R", p(rc * cos, rc * sin, up)), ("R", p(0, 0, up)), ("R", p(0, 0, ret))]
