"""Pocket cycles: G87 rectangular pocket, G88 circular pocket (digest §2.7, §2.8).

The letters and their defaults come from the 8060 quick reference and the 8070 manual
([8060] p71, [8070] p233, [8055] p182/p184); the tool path in the plane is the digest's
[CONSTRUCTION] (§2.7.1 roughing rings, §2.7.2 finishing contour with semicircle entry and exit).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..expressions import InterpError, whole
from . import choices
from .drilling import levels, positive
from .model import unit

SQRT2 = math.sqrt(2.0)


@dataclass(frozen=True)
class Pocket:
    zr: float
    down: float
    floors: tuple            # the levels Z_1 .. Z_n
    angle: float             # degrees: u axis of the pocket (G87 A, +90 when the pocket is taller than long)
    rings: tuple             # G87: (P, Q) half sizes of each ring; G88: radii
    centre_segment: float    # G87: d, half length of the central segment (0: none)
    rough: tuple             # G87: (a, b); G88: (a,)
    finish: tuple | None     # G87: (a_f, b_f); G88: (a_f,); None: no finishing
    stock: float             # |L|
    corners: tuple           # G87 finishing corners: (M, Q - r or chamfer cut) ; G88: ()
    ccw: bool
    square: bool             # finishing with square corners (L > 0, G07) or rounded (L < 0, G05)
    rough_feed: float | None  # F, H, V as programmed (None = default)
    finish_feed: float | None
    plunge_feed: float | None


def _floors(cyc, rn, lv) -> tuple:
    """Levels from the part surface Zr - D to Zb: B > 0 equal levels of at most B, B < 0 levels of |B|
    and the remainder (digest §2.7 [8060] p71, sign rule [UNVERIFIED, 8055])."""
    d = positive(cyc, "D", 0.0, rn)
    surface = lv.zr + lv.down * d
    total = (lv.zb - surface) * lv.down
    if total <= 1e-9:
        raise InterpError("CYC004", f"G{cyc.code}: the part surface (Z - D) is at or below the bottom I",
                          cyc.col("D") if cyc.has("D") else cyc.col("I"))
    if not cyc.has("B"):
        raise InterpError("CYC004", f"G{cyc.code} needs the depth of each level B", cyc.col("G"))
    b = rn.length(cyc.get("B"), cyc)
    if b == 0:
        raise InterpError("CYC004", f"G{cyc.code} B0: the depth of each level must not be 0", cyc.col("B"))
    _guard(total / abs(b), cyc, rn, "B")
    if b > 0:
        n = max(1, math.ceil(total / b - 1e-9))
        steps = [total * k / n for k in range(1, n + 1)]
    else:
        n = max(1, math.ceil(total / -b - 1e-9))
        steps = [min(-b * k, total) for k in range(1, n + 1)]
    return tuple(surface + lv.down * s for s in steps)


def _guard(count: float, cyc, rn, letter: str) -> None:
    rn.guard_moves(count, cyc, letter)


def _step(cyc, rn, r: float) -> float:
    """C, the side step: default 3/4 of the tool diameter, also for C0 ([8060] p71); more than the
    diameter is an error ([8055] p184).  Sign: + equal rings, - rings of |C| and the remainder."""
    c = rn.length(cyc.get("C", 0.0), cyc)
    if c == 0:
        c = choices.POCKET_STEP_OF_DIAMETER * 2.0 * r
        if c == 0:
            raise InterpError("CYC004", f"G{cyc.code}: the tool radius is 0, so the side step C must be "
                              "programmed", cyc.col("G"))
    elif r > 0 and abs(c) > 2.0 * r + 1e-9:
        raise InterpError("CYC004", f"G{cyc.code} C: the side step {abs(c):g} mm is more than the tool diameter "
                          f"{2 * r:g} mm", cyc.col("C"))
    return c


def _rings(size: float, c: float, cyc, rn) -> list:
    """Ring half sizes up to ``size``: equal steps of at most C (C > 0) or steps |C| and the rest."""
    if size <= 1e-12:
        return []
    _guard(size / abs(c), cyc, rn, "C")
    m = max(1, math.ceil(size / abs(c) - 1e-9))
    if c > 0:
        return [size * i / m for i in range(1, m + 1)]
    return [min(-c * i, size) for i in range(1, m + 1)]


def _feeds(cyc):
    h = cyc.get("H", 0.0) or None     # H0: F ([8055] p184)
    v = cyc.get("V", 0.0) or None     # V0: the default, F/2
    for letter, value in (("H", h), ("V", v)):
        if value is not None and value < 0:
            raise InterpError("CYC004", f"G{cyc.code} {letter}{value:g}: a feed must be positive", cyc.col(letter))
    return h, v


def prepare(cyc, rn) -> Pocket:
    lv = levels(cyc, rn)
    floors = _floors(cyc, rn, lv)
    r = rn.tool_radius()
    if not cyc.has("J"):
        raise InterpError("CYC004", f"G{cyc.code} needs J, the {'half length' if cyc.code == 87 else 'radius'} "
                          "(its sign gives the direction: J+ clockwise, J- counter-clockwise)", cyc.col("G"))
    j = rn.length(cyc.get("J"), cyc)
    if j == 0:
        raise InterpError("CYC004", f"G{cyc.code} J0: the pocket has no size", cyc.col("J"))
    stock = abs(rn.length(cyc.get("L", 0.0), cyc))
    c = _step(cyc, rn, r)
    h, v = _feeds(cyc)
    common = dict(zr=lv.zr, down=lv.down, floors=floors, stock=stock, ccw=j < 0, square=cyc.get("L", 0.0) > 0,
                  rough_feed=None, finish_feed=h, plunge_feed=v)
    if cyc.code == 88:
        a = abs(j) - r - stock
        if a < 0 or abs(j) - r <= 0:
            raise InterpError("CYC005", f"G88: the tool (radius {r:g} mm) is too big for the pocket of radius "
                              f"{abs(j):g} mm with finishing stock {stock:g}", cyc.col("J"))
        rings = _rings(a, c, cyc, rn)
        rn.guard_moves(len(floors) * (2 * len(rings) + 8), cyc, "B")
        return Pocket(angle=0.0, rings=tuple(rings), centre_segment=0.0, rough=(a,),
                      finish=(abs(j) - r,) if stock else None, corners=(), **common)
    if not cyc.has("K"):
        raise InterpError("CYC004", "G87 needs K, the half width of the pocket", cyc.col("G"))
    k = rn.length(cyc.get("K"), cyc)
    if k <= 0:
        raise InterpError("CYC004", f"G87 K{cyc.get('K'):g}: the half width must be more than 0", cyc.col("K"))
    a, b = abs(j) - r - stock, k - r - stock
    if a < 0 or b < 0 or abs(j) - r <= 0 or k - r <= 0:
        raise InterpError("CYC005", f"G87: the tool (radius {r:g} mm) is too big for the pocket {2 * abs(j):g} x "
                          f"{2 * k:g} mm with finishing stock {stock:g}", cyc.col("J"))
    af, bf = abs(j) - r, k - r
    corners = _corner(cyc, rn, abs(j), k, r)
    angle = cyc.get("A", 0.0)
    if b > a:   # the pocket is taller than long: turn its axes by 90 degrees (keeps the direction)
        a, b, af, bf, angle = b, a, bf, af, angle + 90.0
    rings = _rings(b, c, cyc, rn)
    rn.guard_moves(len(floors) * (6 * len(rings) + 16), cyc, "B")
    return Pocket(angle=angle, rings=tuple((a - b + q, q) for q in rings),
                  centre_segment=a - b, rough=(a, b), finish=(af, bf) if stock else None, corners=corners, **common)


def _corner(cyc, rn, j: float, k: float, r: float) -> tuple:
    """M0 square, M1 rounded (radius Q), M2 chamfered (size Q) corners of the finishing ([8060] p71)."""
    m = cyc.get("M", 0.0)
    if whole(m) is None or m not in (0, 1, 2):
        raise InterpError("CYC004", f"G87 M{m:g}: the corner type is 0 (square), 1 (rounded) or 2 (chamfer)",
                          cyc.col("M"))
    q = rn.length(cyc.get("Q", 0.0), cyc)
    if q < 0 or q > min(j, k) + 1e-9:
        raise InterpError("CYC004", f"G87 Q: the corner size {q:g} must be between 0 and the half sizes "
                          f"({min(j, k):g})", cyc.col("Q"))
    if m == 1 and q > r:
        return (1, q - r)                          # tool centre on an arc of radius Q - r
    if m == 2 and q - r * (2.0 - SQRT2) > 1e-12:
        # the chamfer offset by r cuts this much off each side of the finishing rectangle
        return (2, min(q - r * (2.0 - SQRT2), j - r, k - r))
    return (0, 0.0)


# ------------------------------------------------------------------ one pocket
def ops(cyc, pk: Pocket, rn, point) -> list:
    a_, o_, ln_ = cyc.plane
    out = []
    if rn.spindle() == 5 and choices.POCKET_STARTS_SPINDLE:
        out.append(("M", choices.POCKET_STARTS_SPINDLE))   # digest §1.4 [UNVERIFIED]
    f = rn.feed(None, cyc.col("G"))
    fh = rn.feed(pk.finish_feed, cyc.col("H")) if pk.finish_feed else f
    fv = rn.feed(pk.plunge_feed, cyc.col("V")) if pk.plunge_feed else f * choices.POCKET_PLUNGE_OF_F
    cos, sin = unit(pk.angle)
    cx, cy = point

    def p(u: float, v: float, z: float) -> dict:
        return {a_: cx + u * cos - v * sin, o_: cy + u * sin + v * cos, ln_: z}

    def c(u: float, v: float) -> tuple:
        q = p(u, v, 0.0)
        return (q[a_], q[o_])

    out.append(("R", p(0, 0, pk.zr)))
    for z in pk.floors:
        out.append(("F", p(0, 0, z), fv))
        if cyc.code == 87:
            out += _rectangles(pk, p, c, z, f, fh)
        else:
            out += _circles(pk, p, c, z, f, fh)
        end = out[-1][1]
        lift = z - pk.down * min(choices.POCKET_LIFT, abs(z - pk.zr))
        out += [("R", {**end, ln_: lift}), ("R", p(0, 0, lift))]
    return [*out, ("R", p(0, 0, rn.return_level(cyc, pk.zr)))]


def _rectangles(pk: Pocket, p, c, z: float, f: float, fh: float) -> list:
    """§2.7.1: central segment, then closed rings from (P, 0); §2.7.2 finishing contour."""
    out = []
    d = pk.centre_segment
    if d > 1e-12:
        out += [("F", p(-d, 0, z), f), ("F", p(d, 0, z), f)]
    for pp, qq in pk.rings:
        out.append(("F", p(pp, 0, z), f))
        out += [("F", p(u, v, z), f) for u, v in _rectangle(pp, qq, pk.ccw)]
    if pk.finish is None:
        return out
    a = pk.rings[-1][0] if pk.rings else d
    af, bf = pk.finish
    corner = {"G60": True} if pk.square else {"G61": True}
    centre = c((a + af) / 2.0, 0.0)
    out.append(("A", p(af, 0, z), centre, pk.ccw, fh, corner))
    out += _finish_contour(pk, p, c, z, af, bf, fh, corner)
    out.append(("A", p(a, 0, z), centre, pk.ccw, fh, corner))
    return out


def _rectangle(pp: float, qq: float, ccw: bool) -> list:
    if ccw:
        return [(pp, qq), (-pp, qq), (-pp, -qq), (pp, -qq), (pp, 0.0)]
    return [(pp, -qq), (-pp, -qq), (-pp, qq), (pp, qq), (pp, 0.0)]


def _finish_contour(pk: Pocket, p, c, z, af, bf, fh, corner) -> list:
    """The closed finishing rectangle from (a_f, 0), with the corners of M1 (arcs) or M2 (chamfers)."""
    kind, size = pk.corners
    out = []
    # the four corners in the order the contour meets them, each as (corner point, incoming side direction)
    sign = 1.0 if pk.ccw else -1.0
    corners = [(af, sign * bf), (-af, sign * bf), (-af, -sign * bf), (af, -sign * bf)]
    previous = (af, 0.0)
    for cu, cv in corners:
        if kind == 0 or size <= 1e-12:
            out.append(("F", p(cu, cv, z), fh, corner))
            previous = (cu, cv)
            continue
        # the corner is cut by ``size`` along the incoming and the outgoing side
        du, dv = _unit(previous, (cu, cv))
        before = (cu - du * size, cv - dv * size)
        nxt = _next_corner(corners, (cu, cv), af)
        eu, ev = _unit((cu, cv), nxt)
        after = (cu + eu * size, cv + ev * size)
        out.append(("F", p(*before, z), fh, corner))
        if kind == 1:
            centre = (before[0] + eu * size, before[1] + ev * size)
            out.append(("A", p(*after, z), c(*centre), pk.ccw, fh, corner))
        else:
            out.append(("F", p(*after, z), fh, corner))
        previous = after
    out.append(("F", p(af, 0.0, z), fh, corner))
    return out


def _next_corner(corners: list, here: tuple, af: float) -> tuple:
    i = corners.index(here)
    return corners[i + 1] if i + 1 < len(corners) else (af, 0.0)


def _unit(s: tuple, e: tuple) -> tuple:
    du, dv = e[0] - s[0], e[1] - s[1]
    n = math.hypot(du, dv)
    return (du / n, dv / n) if n else (0.0, 0.0)


def _circles(pk: Pocket, p, c, z: float, f: float, fh: float) -> list:
    """§2.8: out along +u to each ring radius and a full circle; finishing by semicircles."""
    out = []
    centre = c(0.0, 0.0)
    for radius in pk.rings:
        out += [("F", p(radius, 0, z), f), ("A", p(radius, 0, z), centre, pk.ccw, f)]
    if pk.finish is None:
        return out
    a = pk.rings[-1] if pk.rings else 0.0
    (af,) = pk.finish
    corner = {"G60": True} if pk.square else {"G61": True}
    entry = c((a + af) / 2.0, 0.0)
    return [*out, ("A", p(af, 0, z), entry, pk.ccw, fh, corner), ("A", p(af, 0, z), centre, pk.ccw, fh, corner),
            ("A", p(a, 0, z), entry, pk.ccw, fh, corner)]
