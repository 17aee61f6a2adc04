"""Multiple machining G160-G165: the active cycle (or modal subroutine) repeated on a pattern of points
(seed 002 L1471-L1481; letters [8070-QR] p34-p36; derivation rules digest §2.10 [UNVERIFIED, 8055]).

Point 1 is the definition point, where the tool stands (already machined); the block machines the
others in order.  ``P Q R S T U V`` (not in G165) name points to leave out: ``Pn`` one point,
``Pn.m`` the points n to m (m with three decimals).  Skipped points are not visited.
"""

from __future__ import annotations

import math
from collections.abc import Iterator

from ..expressions import InterpError, whole
from ..records import Source
from . import choices
from .model import unit

SKIP_LETTERS = "PQRSTUV"


class _Def:
    """The letters of one multiple-machining block."""

    def __init__(self, code: int, params: dict, rn) -> None:
        self.code, self.rn = code, rn
        self.values = {k: v for k, (v, _c) in params.items() if k != "G"}
        self.cols = {k: c for k, (_v, c) in params.items()}

    def has(self, letter: str) -> bool:
        return letter in self.values

    def get(self, letter: str, default=None):
        return self.values.get(letter, default)

    def length(self, letter: str, default=None):
        return self.rn.length(self.values[letter]) if letter in self.values else default

    def col(self, letter: str = "G") -> int:
        return self.cols.get(letter, self.cols["G"])

    def bad(self, message: str, letter: str = "G") -> InterpError:
        return InterpError("CYC008", f"G{self.code}: {message}", self.col(letter))


def _count(d: _Def, letter: str) -> int | None:
    if not d.has(letter):
        return None
    k = d.get(letter)
    if whole(k) is None or k < 1:
        raise d.bad(f"{letter}{k:g}: the number of points is a whole number, 1 or more", letter)
    if k > d.rn.machine.limits.max_loop_iterations:
        raise d.bad(f"{letter}{k:g}: more points than limits.max_loop_iterations", letter)
    return int(k)


def _side(d: _Def, length: str, step: str, count: str, angular: bool = False) -> tuple[float, int]:
    """(step, count) of a side (or of an arc, ``angular``) from two of its length, step and number of
    points (§2.10)."""
    read = d.get if angular else d.length
    x, i, k = read(length), read(step), _count(d, count)
    given = sum(v is not None for v in (x, i, k))
    if given < 2:
        raise d.bad(f"two of {length} (length), {step} (step) and {count} (number of points) are needed")
    if k is None:
        if i == 0:
            raise d.bad(f"{step}0: the step must not be 0", step)
        n = x / i + 1.0
        if whole(round(n)) is None or abs(n - round(n)) > choices.PATTERN_WHOLE_TOLERANCE or round(n) < 1:
            raise d.bad(f"{length}{d.get(length):g} is not a whole number of steps {step}{d.get(step):g}", step)
        return i, _checked_count(d, round(n), step)
    if i is None:
        return (x / (k - 1) if k > 1 else 0.0), k
    if x is not None and abs(i * (k - 1) - x) > 1e-6:
        raise d.bad(f"{length}, {step} and {count} disagree: {step} x ({count} - 1) is not {length}", length)
    return i, k


def _checked_count(d: _Def, n: int, letter: str) -> int:
    if n > d.rn.machine.limits.max_loop_iterations:
        raise d.bad("more points than limits.max_loop_iterations", letter)
    return n


def skipped(d: _Def) -> list[tuple[int, int]]:
    """The ranges of points left out, from P..V (``Pn`` or ``Pn.m``)."""
    out = []
    for letter in SKIP_LETTERS:
        if not d.has(letter):
            continue
        v = d.get(letter)
        n = math.floor(v + 1e-9)
        m = round((v - n) * 10 ** choices.SKIP_RANGE_DECIMALS)
        if n < 1 or (m and m < n):
            raise d.bad(f"{letter}{v:g}: points to skip are Pn or Pn.m with m (3 decimals) from n on", letter)
        out.append((n, m or n))
    return out


# ------------------------------------------------------------------ the point sets
def _line(d: _Def, p1) -> Iterator:
    """G160 A X I K: points along a line at angle A (§2.10, §3.11, §3.12)."""
    step, k = _side(d, "X", "I", "K")
    u = unit(d.get("A", 0.0))
    for n in range(2, k + 1):
        yield n, (p1[0] + (n - 1) * step * u[0], p1[1] + (n - 1) * step * u[1]), None


def _parallelogram(d: _Def, p1, grid: bool) -> Iterator:
    """G161 (perimeter) / G162 (grid, zig-zag) A B X I K Y J D."""
    i, k = _side(d, "X", "I", "K")
    j, n2 = _side(d, "Y", "J", "D")
    u = unit(d.get("A", 0.0))
    v = unit(d.get("A", 0.0) + d.get("B", 90.0))

    def node(s: int, t: int) -> tuple:
        return (p1[0] + s * i * u[0] + t * j * v[0], p1[1] + s * i * u[1] + t * j * v[1])

    if grid:
        n = 0
        for t in range(n2):
            for s in (range(k) if t % 2 == 0 else range(k - 1, -1, -1)):
                n += 1
                if n > 1:
                    yield n, node(s, t), None
        return
    if k < 2 or n2 < 2:
        raise d.bad("a parallelogram needs at least 2 points on each side (K and D)")
    path = [(s, 0) for s in range(1, k)] + [(k - 1, t) for t in range(1, n2)] + \
        [(s, n2 - 1) for s in range(k - 2, -1, -1)] + [(0, t) for t in range(n2 - 2, 0, -1)]
    for n, (s, t) in enumerate(path, start=2):
        yield n, node(s, t), None


def _centre(d: _Def, p1) -> tuple[tuple, float, float]:
    """Centre (X, Y: the vector from point 1 to the centre), radius, angle of point 1 (degrees)."""
    x, y = d.length("X", 0.0), d.length("Y", 0.0)
    radius = math.hypot(x, y)
    if radius <= 1e-9:
        raise d.bad("X, Y (from the first point to the centre) give a circle of radius 0", "X")
    c = (p1[0] + x, p1[1] + y)
    return c, radius, math.degrees(math.atan2(p1[1] - c[1], p1[0] - c[0]))


def _circle(d: _Def, p1) -> Iterator:
    """G163 X Y I K: a full circle; K points (I = 360/K counter-clockwise) or steps I (sign = direction)."""
    c, radius, start = _centre(d, p1)
    if d.has("I") == d.has("K"):
        raise d.bad("one of I (angular step) or K (number of points) is needed, not both")
    if d.has("K"):
        k = _count(d, "K")
        step = 360.0 / k
    else:
        step = d.get("I")
        n = 360.0 / abs(step) if step else math.inf
        if not math.isfinite(n) or abs(n - round(n)) > choices.PATTERN_WHOLE_TOLERANCE:
            raise d.bad(f"I{step:g} does not divide the circle into a whole number of points", "I")
        k = _checked_count(d, round(n), "I")
    for n in range(2, k + 1):
        yield n, _on(c, radius, start + (n - 1) * step), c


def _arc(d: _Def, p1) -> Iterator:
    """G164 X Y B I K: points on an arc of angle B; two of B, I, K (sign of B / I = direction)."""
    c, radius, start = _centre(d, p1)
    step, k = _side(d, "B", "I", "K", angular=True)
    for n in range(2, k + 1):
        yield n, _on(c, radius, start + (n - 1) * step), c


def _chord(d: _Def, p1) -> Iterator:
    """G165 X Y A I: the other end of a chord; A the angle of its perpendicular bisector, or I its length
    (I > 0 counter-clockwise)."""
    c, radius, start = _centre(d, p1)
    if d.has("A") == d.has("I"):
        raise d.bad("one of A (angle of the chord's bisector) or I (chord length) is needed, not both")
    if d.has("A"):
        u = unit(d.get("A"))
        vx, vy = p1[0] - c[0], p1[1] - c[1]
        dot = vx * u[0] + vy * u[1]
        yield 2, (c[0] + 2 * dot * u[0] - vx, c[1] + 2 * dot * u[1] - vy), c
        return
    chord = d.length("I")
    if abs(chord) > 2 * radius + 1e-9 or chord == 0:
        raise d.bad(f"the chord I{d.get('I'):g} is 0 or longer than the diameter {2 * radius:g}", "I")
    angle = math.degrees(2 * math.asin(min(1.0, abs(chord) / (2 * radius))))
    yield 2, _on(c, radius, start + math.copysign(angle, chord)), c


def _on(c: tuple, radius: float, angle: float) -> tuple:
    u = unit(angle)
    return (c[0] + radius * u[0], c[1] + radius * u[1])


POINTS = {160: _line, 161: lambda d, p: _parallelogram(d, p, False), 162: lambda d, p: _parallelogram(d, p, True),
          163: _circle, 164: _arc, 165: _chord}


# ------------------------------------------------------------------ execution
def run(rn, code: int, bw, src: Source):
    """Machine the points of a G160-G165 block with the active cycle (or the modal subroutine)."""
    st, interp = rn.state, rn.interp
    d = _Def(code, bw.cycle, rn)
    cyc = st.cycles.active
    modal = interp.modal_call is not None and not any(f.modal for f in interp.frames)
    if cyc is None and not modal:
        raise InterpError("CYC007", f"G{code} repeats a canned cycle or a modal subroutine: none is active",
                          d.col())
    if bw.axes or bw.nr is not None:
        raise d.bad("the multiple machining block takes only its parameters (no axis move, no NR)")
    st.cycles.pattern_params = dict(d.values)
    st.cycles.pattern_called = frozenset(d.values)
    a, o, _ln = cyc.plane if cyc is not None else st.plane_axes()
    here = st.programmed_pos()
    skip = skipped(d) if code != 165 else []
    move = _move(d, code)
    feed = rn.feed(d.get("F"), d.col("F")) if move != "R" else None
    moved = False
    visited = 0
    for n, (x, y), centre in POINTS[code](d, (here[a], here[o])):
        if any(lo <= n <= hi for lo, hi in skip):
            continue
        target = {a: x, o: y}
        if move == "R":
            op = ("R", target)
        elif move == "F" or centre is None:
            op = ("F", target, feed)
        else:
            op = ("A", target, centre, move == "CCW", feed)
        if visited:
            interp.count_block(d.col())   # each further point counts as a block for the runaway guards (as NR)
        visited += 1
        records = rn.emit([op], src, d.col())
        if cyc is not None:
            records += rn.hole(src, d.col())
        moved = moved or bool(records)
        yield from records
        if cyc is None:
            yield from interp.after_motion(src)
    return moved


def _move(d: _Def, code: int) -> str:
    """How the tool goes from point to point: rapid for G160-G162; C0 rapid, C1 G01, C2 G02, C3 G03 for
    G163-G165 ([8070-QR] p35-p36)."""
    if code < 163:
        return "R"
    c = d.get("C", 0.0)
    if c not in (0.0, 1.0, 2.0, 3.0):
        raise d.bad(f"C{c:g}: the move between points is C0 (rapid), C1 (G01), C2 (G02) or C3 (G03)", "C")
    return ("R", "F", "CW", "CCW")[int(c)]
