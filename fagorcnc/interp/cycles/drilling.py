"""Hole cycles: G81 drilling, G82 variable peck, G83 constant peck, G84 tapping, G85 reaming,
G86 boring (digest §2.1-§2.6; the 8065 letters of §0.3).

Each family module has ``prepare(cycle, runner) -> plan`` (checks every parameter and fixes
the levels; errors before anything moves) and ``ops(cycle, plan, runner, point) -> list``
(the operations of one hole at ``point`` of the plane, for :meth:`CycleRunner.emit`).
"""

from __future__ import annotations

from dataclasses import dataclass

from ..expressions import InterpError, whole
from . import choices


@dataclass(frozen=True)
class Levels:
    """The three levels on the longitudinal axis, mm, programmed coordinates (digest §1.3)."""

    zr: float          # reference plane: feed starts here
    zb: float          # bottom
    down: float        # +1 or -1: the direction of machining along the longitudinal axis


def levels(cyc, rn, depth: bool = True) -> Levels:
    """Zr from Z (absolute, or from Zs with G91, or Zs when absent) and Zb from I (absolute, or from
    Zr with G91) as fixed at the definition (digest §1.2, §1.3 [8070] p233, [8055] p162)."""
    zs = cyc.zs
    if cyc.has("Z"):
        z = rn.length(cyc.get("Z"), cyc)
        zr = zs + z if cyc.incremental else z
    else:
        zr = zs
    if not depth:
        return Levels(zr, zr, -1.0)
    if not cyc.has("I"):
        raise InterpError("CYC001", f"G{cyc.code} needs the depth I (I<bottom>)", cyc.col("G"))
    i = rn.length(cyc.get("I"), cyc)
    zb = zr + i if cyc.incremental else i
    return _checked(cyc, zr, zb, "I")


def _checked(cyc, zr: float, zb: float, letter: str) -> Levels:
    if abs(zb - zr) <= 1e-9:
        raise InterpError("CYC002", f"G{cyc.code}: the bottom is on the reference plane (zero depth)",
                          cyc.col(letter))
    return Levels(zr, zb, 1.0 if zb > zr else -1.0)


def dwell(cyc) -> float:
    """K, the dwell at the bottom in seconds on the 8065 (digest §0.3); negative is an error."""
    k = cyc.get("K", 0.0)
    if k < 0:
        raise InterpError("CYC004", f"G{cyc.code} K{k:g}: the dwell must not be negative", cyc.col("K"))
    return k


def positive(cyc, letter: str, default: float | None, rn, allow_zero: bool = True) -> float | None:
    """A length parameter that must not be negative (mm); ``default`` when absent."""
    if not cyc.has(letter):
        return default
    v = cyc.get(letter)
    if v < 0 or (v == 0 and not allow_zero):
        raise InterpError("CYC004", f"G{cyc.code} {letter}{v:g}: must be {'' if allow_zero else 'more than '}"
                          f"{'0 or more' if allow_zero else '0'}", cyc.col(letter))
    return rn.length(v, cyc)


def at(cyc, point, z: float) -> dict:
    a, o, ln = cyc.plane
    return {a: point[0], o: point[1], ln: z}


# ------------------------------------------------------------------ prepare
def prepare(cyc, rn):
    code = cyc.code
    if code == 83:
        return _prepare_g83(cyc, rn)
    lv = levels(cyc, rn)
    k = dwell(cyc)
    if code == 82:
        return lv, k, _prepare_g82(cyc, rn, lv)
    if code == 84:
        return lv, k, _prepare_g84(cyc, rn)
    return lv, k, None


def _prepare_g82(cyc, rn, lv: Levels) -> tuple:
    """G82 letters (digest §2.2 [POST] 8065.cps L666-L703; semantics [UNVERIFIED], 8055 G69)."""
    if not cyc.has("B"):
        raise InterpError("CYC004", "G82 needs the peck B", cyc.col("G"))
    b = rn.length(abs(cyc.get("B")), cyc)
    if b == 0:
        raise InterpError("CYC004", "G82 B0: the peck must not be 0", cyc.col("B"))
    c = cyc.get("C", 0.0)
    if c < 0:
        raise InterpError("CYC004", f"G82 C{c:g}: the approach distance must not be negative", cyc.col("C"))
    c = rn.length(c, cyc) if c else choices.G82_APPROACH
    if c >= b:
        raise InterpError("CYC004", f"G82: the approach distance C ({c:g} mm) must be less than the peck B "
                          f"({b:g} mm)", cyc.col("C") if cyc.has("C") else cyc.col("B"))
    d = positive(cyc, "D", 0.0, rn)
    h = positive(cyc, "H", 0.0, rn)
    j = cyc.get("J", 0.0)
    if whole(j) is None or j < 0:
        raise InterpError("CYC004", f"G82 J{j:g}: the number of steps per full retract is a whole number, 0 "
                          "or more", cyc.col("J"))
    j = int(j) or choices.G82_J_ZERO
    minimum = positive(cyc, "L", choices.G82_MIN_PECK, rn)
    r = cyc.get("R", 1.0)
    if not 0 < r <= 1:
        raise InterpError("CYC004", f"G82 R{r:g}: the peck reduction factor must be more than 0 and at most 1",
                          cyc.col("R"))
    if r < 1 and minimum <= 0:
        raise InterpError("CYC004", "G82: with a reduction factor R below 1 the minimum peck L must be more "
                          "than 0 (the pecks would never reach the bottom)", cyc.col("L") if cyc.has("L")
                          else cyc.col("R"))
    smallest = min(b, minimum) if minimum > 0 else b
    rn.guard_moves(3 * abs(lv.zb - lv.zr) / smallest, cyc, "L" if minimum < b and r < 1 else "B")
    return b, c, d, h, j, minimum, r


def _prepare_g83(cyc, rn):
    """G83 Z I J: I is the peck, always incremental; Zb = Zr + I*J (digest §2.3, [POST] 8065.cps L714)."""
    lv = levels(cyc, rn, depth=False)
    if not cyc.has("I"):
        raise InterpError("CYC001", "G83 needs the peck I (I<depth of each peck>)", cyc.col("G"))
    if not cyc.has("J"):
        raise InterpError("CYC001", "G83 needs the number of pecks J", cyc.col("G"))
    i = rn.length(cyc.get("I"), cyc)
    if i == 0:
        raise InterpError("CYC004", "G83 I0: the peck must not be 0", cyc.col("I"))
    j = cyc.get("J")
    if whole(j) is None or not 1 <= j <= 9999:
        raise InterpError("CYC004", f"G83 J{j:g}: the number of pecks is a whole number 1..9999", cyc.col("J"))
    lv = _checked(cyc, lv.zr, lv.zr + i * j, "I")
    return lv, 0.0, (i, int(j))


def _prepare_g84(cyc, rn) -> tuple:
    """G84 R0 normal / R1 rigid, B peck (rigid only) (digest §2.4, [POST] 8065.cps L724-L777)."""
    r = cyc.get("R", 0.0)
    if r not in (0.0, 1.0):
        raise InterpError("CYC004", f"G84 R{r:g}: R0 normal tapping or R1 rigid tapping", cyc.col("R"))
    b = positive(cyc, "B", 0.0, rn)
    if b and r == 0:
        raise InterpError("CYC004", "G84 B (tapping in pecks) needs rigid tapping R1", cyc.col("B"))
    return bool(r), b


def plc_marks(cyc, plan) -> tuple:
    """The PLC marks on while the hole of ``cyc`` runs (its records from the approach to Zr to the return):
    TAPPING during a tapping canned cycle (seed 002 L29849), RIGID during rigid tapping (L29856: "G63";
    G84 R1 too, digest §1.4 [UNVERIFIED], ``choices.RIGID_MARK_IN_G84_R1``)."""
    if cyc.code != 84:
        return ()
    rigid = plan[2][0]
    return ("TAPPING", "RIGID") if rigid and choices.RIGID_MARK_IN_G84_R1 else ("TAPPING",)


# ------------------------------------------------------------------ one hole
def ops(cyc, plan, rn, point) -> list:
    lv, k, extra = plan
    code = cyc.code
    if code == 84:
        return _g84(cyc, lv, k, extra, rn, point)
    _spindle_warning(cyc, rn)
    f = rn.feed(None, cyc.col("G"))
    ret = rn.return_level(cyc, lv.zr)
    def p(z: float) -> dict:
        return at(cyc, point, z)

    out = [("R", p(lv.zr))]
    if code == 81:
        out += [("F", p(lv.zb), f), ("D", k), ("R", p(ret))]
    elif code == 82:
        out += [*_g82(lv, extra, p, f), ("D", k), ("R", p(ret))]
    elif code == 83:
        out += [*_g83(lv, extra, p, f), ("R", p(ret))]
    elif code == 85:   # reaming: feed back to Zr (digest §2.5)
        out += [("F", p(lv.zb), f), ("D", k), ("F", p(lv.zr), f), ("R", p(ret))]
    else:              # G86 boring: spindle stopped, rapid out, spindle restarted (digest §2.6)
        spindle = rn.spindle()
        out += [("F", p(lv.zb), f), ("D", k), ("M", 5), ("R", p(ret))]
        if spindle in (3, 4):
            out.append(("M", spindle))
    return out


def _spindle_warning(cyc, rn) -> None:
    if choices.WARN_SPINDLE_STOPPED and rn.spindle() == 5 and not cyc.warned:
        cyc.warned = True
        rn.warn("CYC011", f"G{cyc.code} with the spindle stopped: program S and M03/M04 before the cycle",
                cyc.col("G"))


def _g82(lv: Levels, extra: tuple, p, f: float) -> list:
    """Variable peck: s1 = B + D, then max(L, R^(n-1) B), clipped at the bottom (digest §2.2)."""
    b, c, d, h, j, minimum, r = extra
    down, zr, zb = lv.down, lv.zr, lv.zb

    def clip(z: float) -> float:
        return zb if (z - zb) * down >= 0 else z

    bottom = clip(zr + down * (b + d))
    out = [("F", p(bottom), f)]
    n = 1
    while bottom != zb:
        level = zr if h == 0 or n % j == 0 else bottom - down * h
        out.append(("R", p(level)))
        approach = bottom - down * c
        if (level - approach) * down < 0:   # still above the approach level: rapid down to it
            out.append(("R", p(approach)))
        step = max(minimum, r ** n * b)
        bottom = clip(bottom + down * step)
        out.append(("F", p(bottom), f))
        n += 1
    return out


def _g83(lv: Levels, extra: tuple, p, f: float) -> list:
    """Constant peck: back to Zr after each peck, rapid to 1 mm short of the previous bottom."""
    i, j = extra
    zr = lv.zr
    sign = 1.0 if i > 0 else -1.0
    out = [("F", p(zr + i), f)]
    for k in range(2, j + 1):
        previous = zr + (k - 1) * i
        gap = min(choices.G83_APPROACH, abs(previous - zr))
        out += [("R", p(zr)), ("R", p(previous - sign * gap)), ("F", p(zr + k * i), f)]
    return out


def _g84(cyc, lv: Levels, k: float, extra: tuple, rn, point) -> list:
    """Tapping: feed in, spindle reversal, feed out to Zr; rigid R1 with optional pecks B."""
    rigid, b = extra
    spindle = rn.spindle()
    if spindle == 5 and choices.G84_SPINDLE_STOPPED_IS_ERROR:
        raise InterpError("CYC004", "G84 tapping with the spindle stopped: program S and M03 (right-hand "
                          "thread) or M04 (left-hand) before the cycle", cyc.col("G"))
    f = rn.feed(None, cyc.col("G"))
    ret = rn.return_level(cyc, lv.zr)
    def p(z: float) -> dict:
        return at(cyc, point, z)

    out = [("R", p(lv.zr))]
    if rigid:   # spindle interpolated with the axis: pitch F/S as G63 (seed 002 L7562-L7565)
        steps = [lv.zb]
        if b:
            n = int(abs(lv.zb - lv.zr) // b)
            steps = [lv.zr + lv.down * b * m for m in range(1, n + 1)]
            if not steps or abs(steps[-1] - lv.zb) > 1e-9:
                steps.append(lv.zb)
        for z in steps:
            out.append(("F", p(z), f))
            if z == steps[-1]:
                out.append(("D", k))
            out.append(("F", p(lv.zr), f))
        return [*out, ("R", p(ret))]
    reverse = 4 if spindle == 3 else 3
    stop = [("M", 5)] if rn.machine.default("SREVM05") else []   # seed 002 L21990-L21997
    out += [("T", p(lv.zb), f), *stop, ("D", k), ("M", reverse), ("T", p(lv.zr), f), *stop, ("M", spindle)]
    return [*out, ("R", p(ret))]
