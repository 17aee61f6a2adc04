"""Tool radius compensation on closed contours: the compensated path keeps the tool radius R from the contour.

Spec 04 §18-§22: every offset element lies at distance R from its programmed element; inside corners
trim the offsets to their intersection; outside corners are joined by an arc of radius R about the
programmed corner (G136) or by straight prolongations (G137, at most R / cos(psi/2) from the corner for a
deflection psi <= 90 degrees, R * sqrt(2) beyond).  So, away from the activation and cancellation
moves, every point of the tool centre path must be

* at distance >= R from the programmed contour (no gouging),
* at distance exactly R with G136, and farther than R with G137 only on the prolongations of an
  outside corner,
* on the tool side: inside the contour for G41 on a counter-clockwise contour (or G42 on a clockwise
  one), outside otherwise.

Why every closed contour here starts in the middle of a straight edge: the activation block (§19.2) and
the cancellation block (§20) only see the first and the last element, never the corner that closes the
contour.  Started at a vertex, the first offset element begins on its perpendicular point, which lies on
the closing edge (spec §26 square: the first offset starts at (10,13), on the edge X10), and the last
one ends on the first edge: a gouge the spec prescribes.  Started in the middle of an edge, the closing
"corner" is a straight continuation and the whole contour can be checked.

The approach goes perpendicular to that first edge from outside; the cancellation goes straight back.
The moves checked are those of the contour blocks, except the joins after the last contour block
(they belong to the cancellation, spec §20 table: "offset k ends at A; arc ... from A to B; then
B -> P2"; fagorcnc gives them the line of the last contour block).

1. hand-written contours (rectangle, rounded rectangle, concave arc, notch, slot, triangle; both
   orientations, G41/G42, G136/G137, R 3 and 5);
2. properties over random contours (convex polygons, star-shaped polygons, star-shaped contours with arc
   edges, convex polygons with fillets): refused with INT086 on a contour block, or compensated right.
   Global interference is exempt: a neck of the contour narrower than the tool between elements at least
   three blocks apart cannot be seen by a local look-ahead (spec 04 §16.2 asks for 3 elements);
3. regressions: the minimal examples of the bugs the properties found.
"""

from __future__ import annotations

import itertools
import math
import re
from collections import Counter
from dataclasses import dataclass

import pytest
from hypothesis import currently_in_test_context, event, given, settings
from hypothesis import strategies as st

import fagorcnc

EPS = 1e-6
Point = tuple[float, float]


def machine(radius: float) -> dict:
    return {"tools": {"1": {"1": {"radius": radius}}}}


# ------------------------------------------------------------------ contour geometry


@dataclass(frozen=True)
class Seg:
    p: Point
    q: Point

    @property
    def start(self) -> Point:
        return self.p

    @property
    def end(self) -> Point:
        return self.q

    def tangent(self, at_end: bool) -> Point:
        return _unit((self.q[0] - self.p[0], self.q[1] - self.p[1]))

    def length(self) -> float:
        return math.dist(self.p, self.q)

    def reversed(self) -> Seg:
        return Seg(self.q, self.p)

    def distance(self, x: Point) -> float:
        return _dist_seg(x, self.p, self.q)

    def points(self, step: float) -> list[Point]:
        n = max(2, math.ceil(self.length() / step))
        return [_lerp(self.p, self.q, k / n) for k in range(n + 1)]

    def text(self) -> str:
        return f"G01 X{_f(self.q[0])} Y{_f(self.q[1])}"


@dataclass(frozen=True)
class ArcEl:
    """A programmed arc from ``p`` to ``q`` about ``c``, counter-clockwise if ``ccw``."""

    p: Point
    q: Point
    c: Point
    ccw: bool

    @property
    def start(self) -> Point:
        return self.p

    @property
    def end(self) -> Point:
        return self.q

    @property
    def rho(self) -> float:
        return math.dist(self.p, self.c)

    @property
    def a0(self) -> float:
        return math.atan2(self.p[1] - self.c[1], self.p[0] - self.c[0])

    @property
    def sweep(self) -> float:
        a1 = math.atan2(self.q[1] - self.c[1], self.q[0] - self.c[0])
        d = (a1 - self.a0) % (2 * math.pi)
        return d if self.ccw else d - 2 * math.pi

    def tangent(self, at_end: bool) -> Point:
        x = self.q if at_end else self.p
        r = _unit((x[0] - self.c[0], x[1] - self.c[1]))
        return (-r[1], r[0]) if self.ccw else (r[1], -r[0])

    def length(self) -> float:
        return abs(self.sweep) * self.rho

    def reversed(self) -> ArcEl:
        return ArcEl(self.q, self.p, self.c, not self.ccw)

    def distance(self, x: Point) -> float:
        return _dist_arc(x, self.c, self.rho, self.a0, self.sweep, self.p, self.q)

    def points(self, step: float) -> list[Point]:
        n = max(4, math.ceil(self.length() / step))
        return [_polar(self.c, self.rho, self.a0 + self.sweep * k / n) for k in range(n + 1)]

    def text(self) -> str:
        i, j = self.c[0] - self.p[0], self.c[1] - self.p[1]
        return f"G0{3 if self.ccw else 2} X{_f(self.q[0])} Y{_f(self.q[1])} I{_f(i)} J{_f(j)}"


def _f(v: float) -> str:
    return f"{v:.9f}".rstrip("0").rstrip(".") if abs(v) > 5e-10 else "0"


def _r9(p: Point) -> Point:
    """Round to the 9 decimals the program text carries, so that text and geometry agree."""
    return (float(f"{p[0]:.9f}"), float(f"{p[1]:.9f}"))


def _unit(v: Point) -> Point:
    n = math.hypot(v[0], v[1])
    return (v[0] / n, v[1] / n)


def _lerp(p: Point, q: Point, k: float) -> Point:
    return (p[0] + k * (q[0] - p[0]), p[1] + k * (q[1] - p[1]))


def _polar(c: Point, r: float, a: float) -> Point:
    return (c[0] + r * math.cos(a), c[1] + r * math.sin(a))


def _cross(u: Point, v: Point) -> float:
    return u[0] * v[1] - u[1] * v[0]


def _dist_seg(x: Point, p: Point, q: Point) -> float:
    dx, dy = q[0] - p[0], q[1] - p[1]
    ll = dx * dx + dy * dy
    k = 0.0 if ll == 0 else max(0.0, min(1.0, ((x[0] - p[0]) * dx + (x[1] - p[1]) * dy) / ll))
    return math.dist(x, (p[0] + k * dx, p[1] + k * dy))


def _dist_arc(x: Point, c: Point, rho: float, a0: float, sweep: float, p: Point, q: Point) -> float:
    d = math.dist(x, c)
    if d > 1e-12:
        a = math.atan2(x[1] - c[1], x[0] - c[0])
        rel = ((a - a0) % (2 * math.pi)) if sweep > 0 else ((a0 - a) % (2 * math.pi))
        if rel <= abs(sweep) + 1e-12:
            return abs(d - rho)
    return min(math.dist(x, p), math.dist(x, q))


@dataclass(frozen=True)
class Contour:
    """A closed contour starting (and ending) at ``elements[0].start``, the middle of a straight edge."""

    name: str
    elements: tuple

    @property
    def start(self) -> Point:
        return self.elements[0].start

    def reversed(self) -> Contour:
        return Contour(self.name + " cw", tuple(e.reversed() for e in reversed(self.elements)))

    def distance(self, x: Point) -> float:
        return min(e.distance(x) for e in self.elements)

    def polygon(self) -> list[Point]:
        """The contour as a polygon, arcs within 0.01 (for the inside/outside test)."""
        pts: list[Point] = []
        for e in self.elements:
            if isinstance(e, ArcEl):
                step = 2 * math.acos(max(-1.0, 1 - 0.01 / e.rho))
                n = max(2, math.ceil(abs(e.sweep) / step))
                pts.extend(_polar(e.c, e.rho, e.a0 + e.sweep * k / n) for k in range(n))
            else:
                pts.append(e.start)
        return pts

    def ccw(self) -> bool:
        poly = self.polygon()
        area = sum(_cross(poly[k - 1], poly[k]) for k in range(len(poly)))
        return area > 0

    def corners(self):
        """(vertex, t1, t2) at each junction between two elements (the start point is a straight one)."""
        els = self.elements
        return [(els[k].end, els[k].tangent(True), els[k + 1].tangent(False)) for k in range(len(els) - 1)]


def _inside(x: Point, poly: list[Point]) -> bool:
    inside = False
    n = len(poly)
    for k in range(n):
        (x1, y1), (x2, y2) = poly[k - 1], poly[k]
        if (y1 > x[1]) != (y2 > x[1]):
            xc = x1 + (x[1] - y1) * (x2 - x1) / (y2 - y1)
            if xc > x[0]:
                inside = not inside
    return inside


def contour_from(name: str, start: Point, items) -> Contour:
    """Elements from ``start`` through ``items``: a point (line) or (point, centre, ccw) (arc)."""
    els = []
    p = start
    for it in items:
        if isinstance(it[0], tuple):
            q, c, ccw = it
            els.append(ArcEl(p, q, c, ccw))
        else:
            q = it
            els.append(Seg(p, q))
        p = q
    assert math.dist(p, start) < 1e-9, "the contour must close"
    return Contour(name, tuple(els))


# ------------------------------------------------------------------ the program and its run


@dataclass
class Run:
    text: str
    result: object
    checked: list          # the compensated moves of the contour blocks (activation/cancellation excluded)
    act_line: int
    edge_lines: list
    cancel_line: int


def outward(contour: Contour) -> Point:
    """The outward normal of the first edge at the start point: the direction of the approach (reversed)
    and of the cancellation."""
    t = contour.elements[0].tangent(False)
    return (t[1], -t[0]) if contour.ccw() else (-t[1], t[0])


def program(contour: Contour, side: int, transition: int, start_mode: int = 139, approach: float = 20.0) -> str:
    """Approach perpendicular to the first edge from outside, go round, cancel back out."""
    m = contour.start
    out = outward(contour)
    p0 = _r9((m[0] + approach * out[0], m[1] + approach * out[1]))
    lines = [f"G90 G17 G00 X{_f(p0[0])} Y{_f(p0[1])}",
             "T1 D1 M6",
             f"G{transition} G{start_mode}",
             f"G01 G{side} X{_f(m[0])} Y{_f(m[1])} F500"]
    lines += [e.text() for e in contour.elements]
    lines += [f"G40 G01 X{_f(p0[0])} Y{_f(p0[1])}", "M30"]
    return "\n".join(lines) + "\n"


def run(contour: Contour, side: int, transition: int, radius: float, start_mode: int = 139) -> Run:
    return run_text(program(contour, side, transition, start_mode), len(contour.elements), radius)


def run_text(text: str, n: int, radius: float) -> Run:
    """Run a program laid out by :func:`program` (``n`` contour blocks from line 5)."""
    r = fagorcnc.simulate(text, machine(radius))
    act, edges, cancel = 4, list(range(5, 5 + n)), 5 + n
    motion = [m for m in r.moves if m.kind in ("rapid", "linear", "arc")]
    checked = []
    seen_last = False
    for m in motion:
        if m.line == edges[-1]:
            if seen_last:
                continue          # a join after the last block: part of the cancellation (§20)
            seen_last = True
        if m.line in edges:
            checked.append(m)
    return Run(text, r, checked, act, edges, cancel)


def samples(m, step: float) -> list[Point]:
    """Points along a compensated move; arcs from their centre, radius, start and sweep."""
    p, q = (m.start["X"], m.start["Y"]), (m.end["X"], m.end["Y"])
    if m.kind != "arc":
        n = max(2, math.ceil(math.dist(p, q) / step))
        return [_lerp(p, q, k / n) for k in range(n + 1)]
    c = (m.center["X"], m.center["Y"])
    sw = math.radians(m.sweep)
    a0 = math.atan2(p[1] - c[1], p[0] - c[0])
    n = max(4, math.ceil(abs(sw) * m.radius / step))
    pts = [_polar(c, m.radius, a0 + sw * k / n) for k in range(n + 1)]
    # the record must be consistent: start and end on the circle, the sweep leads from start to end
    assert abs(math.dist(p, c) - m.radius) < EPS, f"line {m.line}: arc start not on its circle"
    assert abs(math.dist(q, c) - m.radius) < EPS, f"line {m.line}: arc end not on its circle"
    assert math.dist(pts[-1], q) < 1e-5, f"line {m.line}: sweep {m.sweep} does not lead from start to end"
    return pts


def problems(rn: Run, contour: Contour, side: int, transition: int, radius: float, step: float = 0.5,
             far: list | None = None) -> list[str]:
    """Everything wrong with the compensated path (an empty list when it is right).

    With ``far`` (a list), a point nearer than R only to elements at least three blocks away from its own
    (on both sides), at distance >= R from its own and its neighbours, is a global interference: the contour
    has a neck narrower than the tool that only a look-ahead over the whole contour would see (spec 04 §16.2
    asks for 3 elements).  Such points go to ``far`` instead."""
    out = []
    els = contour.elements
    n = len(els)
    motion = [m for m in rn.result.moves if m.kind in ("rapid", "linear", "arc")]
    for a, b in itertools.pairwise(motion):
        if math.dist((a.end["X"], a.end["Y"]), (b.start["X"], b.start["Y"])) > EPS:
            out.append(f"path jumps between line {a.line} and line {b.line}: {a.end} -> {b.start}")
    s = 1 if side == 41 else -1
    ccw = contour.ccw()
    tool_inside = (s == 1) == ccw
    outside_corners = []
    for v, t1, t2 in contour.corners():
        cr, dot = _cross(t1, t2), t1[0] * t2[0] + t1[1] * t2[1]
        if s * cr < -1e-9 or (abs(cr) <= 1e-9 and dot < 0):
            psi = math.acos(max(-1.0, min(1.0, dot)))
            bound = radius / math.cos(psi / 2) if psi <= math.pi / 2 + 1e-9 else radius * math.sqrt(2)
            outside_corners.append((v, bound))
    poly = contour.polygon()
    for m in rn.checked:
        pts = samples(m, step)
        own = m.line - rn.edge_lines[0]
        interfered = False
        for x in pts:
            d = contour.distance(x)
            if radius - EPS <= d <= radius + EPS:
                continue
            where = (f"line {m.line} ({m.kind} {m.start['X']:.4f},{m.start['Y']:.4f} -> "
                     f"{m.end['X']:.4f},{m.end['Y']:.4f}) at ({x[0]:.4f},{x[1]:.4f})")
            if d < radius - EPS:
                near = [j for j in range(n) if els[j].distance(x) < radius - EPS]
                if far is not None and all(3 <= (j - own) % n <= n - 3 for j in near):
                    far.append(f"global interference {radius - d:.6f} on {where} (elements {near})")
                    interfered = True
                    continue
                out.append(f"gouge {radius - d:.6f} (distance {d:.6f} < R {radius}) on {where}")
            elif dropped(rn):
                continue   # blocks not executed (INT120-INT122): the path keeps R or more from the profile
            elif transition == 136:
                out.append(f"distance {d:.6f} > R {radius} with G136 on {where}")
            elif not any(math.dist(x, v) <= bound + EPS for v, bound in outside_corners):
                # G137: farther than R only on the prolongations of an outside corner V, at most
                # R / cos(psi / 2) from V (R * sqrt(2) beyond 90 degrees)
                out.append(f"distance {d:.6f} > R {radius} away from the prolongations of the outside "
                           f"corners (G137) on {where}")
        # the side: at a distance >= R from the contour the path cannot cross it, one point per move will do
        x = pts[len(pts) // 2]
        if not interfered and _inside(x, poly) != tool_inside:
            out.append(f"tool on the wrong side ({'outside' if tool_inside else 'inside'} the contour) on line "
                       f"{m.line} at ({x[0]:.4f},{x[1]:.4f})")
    return out


def dropped(rn: Run) -> list:
    """The blocks the compensation did not execute, with the warning "profile modified" (spec 04 §16.2)."""
    return [d for d in rn.result.diagnostics if d.code in ("INT120", "INT121", "INT122")]


def report(rn: Run, found: list[str]) -> str:
    return "\n" + rn.text + "\n".join(found[:8]) + (f"\n... {len(found)} problems" if len(found) > 8 else "")


def contour_of(text: str) -> Contour:
    """The contour of a program laid out by :func:`program`: from the point of the activation block (line 4)
    through the blocks up to the G40 block."""
    def word(line: str, letter: str) -> float:
        return float(re.search(rf"\b{letter}(-?[0-9.]+)", line).group(1))

    lines = text.splitlines()
    start = p = (word(lines[3], "X"), word(lines[3], "Y"))
    els: list = []
    for line in lines[4:]:
        if line.startswith("G40"):
            break
        q = (word(line, "X"), word(line, "Y"))
        if line.startswith(("G02", "G03")):
            els.append(ArcEl(p, q, (p[0] + word(line, "I"), p[1] + word(line, "J")), line.startswith("G03")))
        else:
            els.append(Seg(p, q))
        p = q
    assert math.dist(p, start) < 1e-9, "the contour must close"
    return Contour("program", tuple(els))


def check_program(text: str, radius: float, convex: bool = False) -> None:
    """:func:`check_contour` for a program written out (the regression tests)."""
    side = 41 if " G41 " in text else 42
    transition, start_mode = (int(g) for g in re.match(r"G(13[67]) G(13[89])", text.splitlines()[2]).groups())
    contour = contour_of(text)
    assert program(contour, side, transition, start_mode) == text   # laid out as the properties do
    p = {"radius": radius, "side": side, "transition": transition, "start_mode": start_mode}
    check_contour(contour, p, Counter(), convex)


# ------------------------------------------------------------------ 1. hand-written contours

RECT = contour_from("rectangle", (30, 0), [(60, 0), (60, 40), (0, 40), (0, 0), (30, 0)])
ROUNDED = contour_from("rounded rectangle", (30, 0), [
    (52, 0), ((60, 8), (52, 8), True), (60, 32), ((52, 40), (52, 32), True),
    (8, 40), ((0, 32), (8, 32), True), (0, 8), ((8, 0), (8, 8), True), (30, 0)])
CONCAVE = contour_from("rectangle with a concave arc", (30, 0), [
    (60, 0), (60, 40), ((0, 40), (30, 80), False), (0, 0), (30, 0)])
NOTCH = contour_from("rectangle with a half-circle notch", (30, 0), [
    (60, 0), (60, 40), (38, 40), ((22, 40), (30, 40), False), (0, 40), (0, 0), (30, 0)])
SLOT = contour_from("slot", (25, -10), [
    (50, -10), ((50, 10), (50, 0), True), (0, 10), ((0, -10), (0, 0), True), (25, -10)])
TRIANGLE = contour_from("triangle", (30, 0), [(60, 0), (30, 50), (0, 0), (30, 0)])

HAND = [RECT, ROUNDED, CONCAVE, NOTCH, SLOT, TRIANGLE]


@pytest.mark.parametrize("radius", [3.0, 5.0])
@pytest.mark.parametrize("transition", [136, 137])
@pytest.mark.parametrize("side", [41, 42])
@pytest.mark.parametrize("reverse", [False, True], ids=["ccw", "cw"])
@pytest.mark.parametrize("contour", HAND, ids=[c.name for c in HAND])
def test_hand_written_contours(contour, reverse, side, transition, radius):
    c = contour.reversed() if reverse else contour
    rn = run(c, side, transition, radius)
    assert rn.result.ok, report(rn, [str(d) for d in rn.result.diagnostics])
    # every contour block is compensated, each once, in order
    mains = [m.line for k, m in enumerate(rn.checked) if k == 0 or rn.checked[k - 1].line != m.line]
    assert mains == rn.edge_lines, report(rn, [f"contour blocks compensated: {mains}"])
    found = problems(rn, c, side, transition, radius)
    assert not found, report(rn, found)


def test_hand_written_contours_hit_both_corner_kinds():
    # the rectangle cases above must really exercise both joins: G41 CCW is all inside corners,
    # G42 CCW all outside ones (two arcs with G136, two straight pieces with G137 at each corner)
    inside = run(RECT, 41, 136, 3.0)
    assert [m.kind for m in inside.checked] == ["linear"] * 5
    outside = run(RECT, 42, 136, 3.0)
    assert [m.kind for m in outside.checked].count("arc") == 4
    outside = run(RECT, 42, 137, 3.0)
    assert len(outside.checked) == 5 + 2 * 4


def test_concave_arc_offsets():
    # the arc of radius 50 about (30,80) is concave: G41 (tool inside, G02) follows radius 53, G42 radius 47
    for side, rho in ((41, 53.0), (42, 47.0)):
        rn = run(CONCAVE, side, 136, 3.0)
        arc = next(m for m in rn.checked if m.line == 7)    # the offset of the block; joins follow it
        assert arc.kind == "arc" and arc.radius == pytest.approx(rho)
        assert (arc.center["X"], arc.center["Y"]) == pytest.approx((30.0, 80.0))


def test_vertex_start_at_an_inside_corner_is_refused():
    # why the contours above start in the middle of an edge: the square of spec 04 §26, closed at its corner
    # (10,10), G41 on a CCW square (the tool inside, R = 3).  The activation (line 3, §19.2) ends at B = (10,13),
    # the first edge's perpendicular point, which is ON the closing edge X10 (y 10..40): distance 0, so the tool
    # would cut R - 0 = 3 mm into it; the last move (line 7) would end at (13,10), on the first edge (§20).  The
    # manual leaves that corner untrimmed; fagorcnc refuses the gouge before anything moves (INT086).
    text = "G90 G17 G00 X-10 Y-10\nT1 D1 M6\nG01 G41 X10 Y10 F500\nX40\nY40\nX10\nY10\nG40 X-10 Y-10\nM30\n"
    r = fagorcnc.simulate(text, machine(3.0))
    errors = [d for d in r.diagnostics if d.severity == "error"]
    assert not r.ok and [d.code for d in errors] == ["INT086"], [str(d) for d in r.diagnostics]
    assert "3.0000 mm into the profile of line 7" in errors[0].message
    assert "closes at the corner where compensation started" in errors[0].message
    assert errors[0].line == 4 and not any(m.kind == "linear" and m.line >= 4 for m in r.moves)


def test_vertex_start_at_an_outside_corner_runs():
    # the same square with G42: the tool outside, the untrimmed corner leaves material, it does not gouge.
    # First edge heading +X, right normal (0,-1): offset Y = 7.  The activation's offset line passes through
    # (-10,-10) + 3(1,-1)/sqrt2 = (-7.879,-12.121) with direction (1,1) and meets Y = 7 at x = -7.879 + 19.121 =
    # 11.243 (§19.2).  The closing edge X10 heading -Y has the right normal (-1,0): offset X = 7, and the last
    # move ends at (7,11.243) by symmetry.  Every point of the path keeps >= 3 mm from the square.
    text = "G90 G17 G00 X-10 Y-10\nT1 D1 M6\nG01 G42 X10 Y10 F500\nX40\nY40\nX10\nY10\nG40 X-10 Y-10\nM30\n"
    r = fagorcnc.simulate(text, machine(3.0))
    assert r.ok, [str(d) for d in r.diagnostics]
    main = {m.line: m for m in reversed(r.moves) if m.kind == "linear" and 4 <= m.line <= 7}
    assert (main[4].start["X"], main[4].start["Y"]) == pytest.approx((11.2426, 7.0), abs=1e-4)
    assert (main[7].end["X"], main[7].end["Y"]) == pytest.approx((7.0, 11.2426), abs=1e-4)
    square = [Seg((10, 10), (40, 10)), Seg((40, 10), (40, 40)), Seg((40, 40), (10, 40)), Seg((10, 40), (10, 10))]
    for line in (4, 5, 6, 7):
        assert all(min(e.distance(x) for e in square) >= 3.0 - EPS for x in samples(main[line], 0.5))


def test_mid_edge_start_of_the_same_closed_square_runs():
    # started at (25,10), the middle of the first edge, the closing corner (10,10) is an ordinary inside corner:
    # offsets Y=13 and X=13 meet at (13,13); lines 5..7 run the inside square 13..37 exactly.
    text = ("G90 G17 G00 X25 Y-10\nT1 D1 M6\nG01 G41 X25 Y10 F500\nX40\nY40\nX10\nY10\nX25\n"
            "G40 X25 Y-10\nM30\n")
    r = fagorcnc.simulate(text, machine(3.0))
    assert r.ok, [str(d) for d in r.diagnostics]
    ends = {m.line: (m.end["X"], m.end["Y"]) for m in r.moves if m.kind == "linear" and 4 <= m.line <= 8}
    assert ends == {4: pytest.approx((37.0, 13.0)), 5: pytest.approx((37.0, 37.0)), 6: pytest.approx((13.0, 37.0)),
                    7: pytest.approx((13.0, 13.0)), 8: pytest.approx((25.0, 13.0))}


# ------------------------------------------------------------------ 2. random polygons


WEIGHTS = st.one_of(st.just(0.0), st.floats(0.0, 10.0))
RADII = st.floats(30.0, 100.0)
RADIUS_KIND = st.sampled_from(["30", "100", "any", "near"])
NEAR = st.floats(-5.0, 5.0)
BULGES = st.one_of(st.just(0.0), st.sampled_from([-1.0, -0.5, 0.5, 1.0]),
                   st.floats(-1.0, 1.0).filter(lambda b: abs(b) > 0.01))
FILLETS = st.one_of(st.just(0.0), st.floats(0.5, 10.0))


def _gaps(draw, n: int, gmin: float, gmax: float = 2 * math.pi) -> list[float]:
    """``n`` angular gaps between ``gmin`` and ``gmax`` adding up to a full turn."""
    w = [draw(WEIGHTS) for _ in range(n)]
    total = sum(w)
    x = [v / total for v in w] if total else [1.0 / n] * n
    extra = 2 * math.pi - n * gmin
    target = 0.999 * (gmax - gmin) / extra
    if max(x) > target:   # blend with equal gaps until the largest fits
        lam = (max(x) - target) / (max(x) - 1.0 / n)
        x = [(1 - lam) * v + lam / n for v in x]
    return [gmin + extra * v for v in x]


@st.composite
def convex_polygons(draw) -> list[Point]:
    rc = draw(st.floats(30.0, 100.0))
    n = draw(st.integers(3, 12))
    gmin = 2 * math.asin(5.0 / rc)          # every edge >= 10
    a = draw(st.floats(0.0, 2 * math.pi))
    pts = []
    for g in _gaps(draw, n, gmin):
        pts.append(_r9(_polar((0.0, 0.0), rc, a)))
        a += g
    return pts


MIN_EDGE_STAR = 2.0


@st.composite
def star_polygons(draw) -> list[Point]:
    n = draw(st.integers(3, 12))
    gmin = math.asin(MIN_EDGE_STAR / 30.0)  # every edge >= MIN_EDGE_STAR whatever the radii
    # no angular gap over 150 degrees: two long edges could otherwise pinch the origin between them
    # to a neck narrower than the tool (a global interference no local look-ahead can see)
    gaps = _gaps(draw, n, gmin, math.radians(150))
    a = draw(st.floats(0.0, 2 * math.pi))
    pts = []
    r = 30.0
    for g in gaps:
        # extreme radii, any radius, or one near the previous (short edges next to sharp corners)
        kind = draw(RADIUS_KIND)
        r = (30.0 if kind == "30" else 100.0 if kind == "100" else draw(RADII) if kind == "any"
             else min(100.0, max(30.0, r + draw(NEAR))))
        pts.append(_r9(_polar((0.0, 0.0), r, a)))
        a += g
    return pts


def polygon_contour(pts: list[Point], ccw: bool, first: int = 0, bulges: list[float] | None = None) -> Contour:
    """The polygon (vertices counter-clockwise about the origin) as a contour starting in the middle of
    the edge ending at ``pts[first % n]``, which the compensation sees as two collinear moves (the
    closing edge).  ``bulges[k]`` turns the edge ending at ``pts[k]`` into an arc (see :func:`_arc_edge`).
    """
    n = len(pts)
    bulges = bulges or [0.0] * n
    k = first % n
    pts, bulges = pts[k:] + pts[:k], bulges[k:] + bulges[:k]
    m = _r9(_lerp(pts[-1], pts[0], 0.5))
    els: list = [Seg(m, pts[0])]
    for i in range(1, n):
        els.append((_arc_edge(pts[i - 1], pts[i], bulges[i]) if bulges[i] else None) or Seg(pts[i - 1], pts[i]))
    els.append(Seg(pts[-1], m))
    contour = Contour("polygon", tuple(els))
    return contour if ccw else contour.reversed()


def _arc_edge(p: Point, q: Point, bulge: float) -> ArcEl | None:
    """The arc from ``p`` to ``q`` of sweep 4 atan(bulge) (counter-clockwise if positive: outward on a
    counter-clockwise polygon), or None when it would leave the sector of the origin between ``p`` and
    ``q`` or come nearer than 15 to the origin (the contour stays simple, without narrow necks).

    (Found by the property itself: an arc leaving its end point almost along the ray, where the
    neighbouring edge ran too, crossed that edge.)"""
    theta = 4 * math.atan(bulge)
    d = _unit((q[0] - p[0], q[1] - p[1]))
    k = math.dist(p, q) / 2 / math.tan(theta / 2)
    mid = _lerp(p, q, 0.5)
    arc = ArcEl(p, q, _r9((mid[0] - d[1] * k, mid[1] + d[0] * k)), theta > 0)
    # moving round the origin (polar angle increasing) by a margin at both ends, where a neighbour may
    # run along the ray, and at every sample in between
    if min(_cross(_unit(x), arc.tangent(end)) for x, end in ((p, False), (q, True))) < math.sin(math.radians(5)):
        return None
    pts = arc.points(0.5)
    if min(math.hypot(*x) for x in pts) < 15:
        return None
    for x, y in itertools.pairwise(pts):
        if _cross(x, y) <= 0:   # the polar angle must keep increasing
            return None
    return arc


@st.composite
def star_contours_with_arcs(draw) -> tuple[list[Point], list[float]]:
    pts = draw(star_polygons())
    bulges = [draw(BULGES) for _ in pts]
    return pts, bulges


@st.composite
def rounded_polygons(draw) -> tuple[list[Point], list[float]]:
    """A convex polygon and a fillet radius (0: sharp corner) for each vertex."""
    pts = draw(convex_polygons())
    return pts, [draw(FILLETS) for _ in pts]


def rounded_contour(pts: list[Point], radii: list[float], ccw: bool, first: int = 0) -> Contour:
    """The convex polygon with each corner k rounded by a tangent arc of radius ``radii[k]``, shrunk so that
    at least a fifth of every edge stays straight; it starts in the middle of the straight part of the
    edge ending at ``pts[first % n]``."""
    n = len(pts)
    k = first % n
    pts, radii = pts[k:] + pts[:k], radii[k:] + radii[:k]
    t = [_unit((pts[i][0] - pts[i - 1][0], pts[i][1] - pts[i - 1][1])) for i in range(n)]  # edge i ends at i
    half = [math.acos(max(-1.0, min(1.0, t[i][0] * t[(i + 1) % n][0] + t[i][1] * t[(i + 1) % n][1]))) / 2
            for i in range(n)]                                                             # deflection / 2
    tl = [radii[i] * math.tan(half[i]) for i in range(n)]                                  # tangent lengths
    room = [0.8 * math.dist(pts[i - 1], pts[i]) / max(tl[i - 1] + tl[i], 1e-12) for i in range(n)]
    f = [min(1.0, room[i], room[(i + 1) % n]) for i in range(n)]
    radii = [radii[i] * f[i] for i in range(n)]
    tl = [tl[i] * f[i] for i in range(n)]
    ends = [_r9((pts[i][0] - tl[i] * t[i][0], pts[i][1] - tl[i] * t[i][1])) for i in range(n)]
    starts = [_r9((pts[i][0] + tl[i] * t[(i + 1) % n][0], pts[i][1] + tl[i] * t[(i + 1) % n][1]))
              for i in range(n)]                           # the straight part of edge i + 1 starts here
    m = _r9(_lerp(starts[-1], ends[0], 0.5))
    els: list = [Seg(m, ends[0])]
    for i in range(n):
        if radii[i] > 0:
            ni, no = (-t[i][1], t[i][0]), (-t[(i + 1) % n][1], t[(i + 1) % n][0])
            b = _unit((ni[0] + no[0], ni[1] + no[1]))
            d = radii[i] / math.cos(half[i])
            els.append(ArcEl(ends[i], starts[i], _r9((pts[i][0] + d * b[0], pts[i][1] + d * b[1])), True))
        els.append(Seg(starts[i], ends[i + 1] if i + 1 < n else m))
    contour = Contour("rounded polygon", tuple(e for e in els if e.length() > 1e-9))
    return contour if ccw else contour.reversed()


def locally_feasible(contour: Contour, side: int, radius: float, start_mode: int = 139) -> bool:
    """No offset element is reversed by the trims of its inside corners (tool radius R * tan(phi / 2)
    at a corner of deflection phi), no offset arc has a radius <= 0, with a margin, and the transitions
    keep R from the contour (:func:`transitions_clear`)."""
    s = 1 if side == 41 else -1
    els = contour.elements
    out = outward(contour)
    # the corners between the elements, with the activation and the cancellation corners (spec 04 §19, §20)
    corners = [((-out[0], -out[1]), els[0].tangent(False))]
    corners += [(t1, t2) for _v, t1, t2 in contour.corners()]
    corners.append((els[-1].tangent(True), out))
    trims = [0.0] * (len(els) + 1)
    for k, (t1, t2) in enumerate(corners):
        cr, dot = _cross(t1, t2), t1[0] * t2[0] + t1[1] * t2[1]
        if s * cr > 1e-9:
            trims[k] = radius * math.tan(math.acos(max(-1.0, min(1.0, dot))) / 2)
    arcs_ok = all(e.rho - s * (1 if e.ccw else -1) * radius > 1e-3 for e in els if isinstance(e, ArcEl))
    return arcs_ok and all(e.length() > trims[k] + trims[k + 1] + 1e-3 for k, e in enumerate(els)) and \
        transitions_clear(contour, side, radius, start_mode)


def transitions_clear(contour: Contour, side: int, radius: float, start_mode: int) -> bool:
    """With G139, an activation or cancellation at an outside corner goes round the start point on an arc of
    radius R (spec 04 §19.2, §20): the cancellation's arc ends at m + R n(out) and the activation's starts at
    m + R n(-out) (n: the normal on the tool's side), R from m along the closing edge.  With the tool inside,
    next to a vertex (a first or last half-edge shorter than about 2R), that point comes nearer than R to the
    next edge, and fagorcnc refuses the transition (found by the property: a thin triangle started 5 mm from a
    vertex under a 3 mm tool, the exit arc 2 mm from that vertex)."""
    if start_mode != 139:
        return True
    m, out = contour.start, outward(contour)
    els = contour.elements

    def normal(v: Point) -> Point:
        return (-v[1], v[0]) if side == 41 else (v[1], -v[0])

    sign = 1 if side == 41 else -1
    ends = []
    for v, (t1, t2) in ((out, (els[-1].tangent(True), out)), ((-out[0], -out[1]), ((-out[0], -out[1]),
                                                                                 els[0].tangent(False)))):
        if sign * _cross(t1, t2) < -1e-9:   # an outside corner: the arc round m
            n = normal(v)
            ends.append((m[0] + radius * n[0], m[1] + radius * n[1]))
    return all(e.distance(x) >= radius - 1e-6 for x in ends for e in els[1:-1])


params = st.fixed_dictionaries({
    "radius": st.floats(0.5, 5.0).map(lambda r: float(f"{r:.4f}")),
    "ccw": st.booleans(),
    "side": st.sampled_from([41, 42]),
    "transition": st.sampled_from([136, 137]),
    "start_mode": st.sampled_from([138, 139]),
    "first": st.integers(0, 11),     # which edge holds the start point
})


def _count(stats: Counter, outcome: str) -> None:
    stats[outcome] += 1
    if currently_in_test_context():
        event(outcome)


def check_contour(contour: Contour, p, stats: Counter, convex: bool = False) -> bool:
    """Refused with INT086 on a contour block, or compensated right (see :func:`problems`); True if run."""
    side, transition, radius = p["side"], p["transition"], p["radius"]
    rn = run(contour, side, transition, radius, p["start_mode"])
    r = rn.result
    feasible = locally_feasible(contour, side, radius, p["start_mode"])
    if not r.ok:
        errors = [d for d in r.diagnostics if d.severity == "error"]
        assert errors and all(d.code == "INT086" for d in errors), report(rn, [str(d) for d in r.diagnostics])
        assert all(d.line in (*rn.edge_lines, rn.cancel_line) for d in errors), report(rn, [str(d) for d in errors])
        _count(stats, "refused")
        # convex contours: a refusal must be a step (or an arc smaller than the tool), never a feasible offset
        assert not (convex and feasible), report(
            rn, ["a convex polygon whose offset is feasible was refused", *map(str, errors)])
        return False
    far: list[str] = []
    found = problems(rn, contour, side, transition, radius, step=1.0, far=far)
    assert not found, report(rn, found)
    _count(stats, "neck" if far else "dropped" if dropped(rn) else "ok")
    if feasible and not dropped(rn):
        mains = [m.line for k, m in enumerate(rn.checked) if k == 0 or rn.checked[k - 1].line != m.line]
        assert mains == rn.edge_lines, report(rn, [f"contour blocks compensated: {mains}"])
    return True


def test_convex_polygons():
    stats: Counter = Counter()

    @settings(report_multiple_bugs=False)   # one bug shrunk is enough: keeps a failing run short
    @given(convex_polygons(), params)
    def prop(pts, p):
        ok = check_contour(polygon_contour(pts, p["ccw"], p["first"]), p, stats, convex=True)
        # long edges must always do: every edge > 4R and, with the tool inside, no corner sharper than 90
        # degrees (an inside corner of deflection phi trims R tan(phi / 2) off both moves, R at most; the
        # perpendicular approach and exit trim R off the two halves of the first edge when the tool is
        # outside).  With the tool inside, an acute corner can need more than 4R: see `locally_feasible`.
        n = len(pts)
        t = [_unit((pts[i][0] - pts[i - 1][0], pts[i][1] - pts[i - 1][1])) for i in range(n)]
        sharpest = max(math.acos(max(-1.0, min(1.0, t[i - 1][0] * t[i][0] + t[i - 1][1] * t[i][1])))
                       for i in range(n))
        tool_inside = (p["side"] == 41) == p["ccw"]
        if min(math.dist(pts[i - 1], pts[i]) for i in range(n)) > 4 * p["radius"] and \
                (not tool_inside or sharpest <= math.pi / 2):
            assert ok, f"refused: {pts} {p}"

    prop()
    assert stats["ok"] >= (stats["ok"] + stats["refused"]) / 2, stats


def test_star_polygons():
    stats: Counter = Counter()

    @settings(report_multiple_bugs=False)   # one bug shrunk is enough: keeps a failing run short
    @given(star_polygons(), params)
    def prop(pts, p):
        check_contour(polygon_contour(pts, p["ccw"], p["first"]), p, stats)

    prop()
    assert stats["ok"] > 0, stats


def test_star_contours_with_arcs():
    stats: Counter = Counter()

    @settings(report_multiple_bugs=False)   # one bug shrunk is enough: keeps a failing run short
    @given(star_contours_with_arcs(), params)
    def prop(pb, p):
        check_contour(polygon_contour(pb[0], p["ccw"], p["first"], pb[1]), p, stats)

    prop()
    assert stats["ok"] > 0, stats


def test_rounded_convex_polygons():
    # tangent arcs at the corners: a fillet of radius < R cannot be followed from inside (spec 04 §16.2:
    # "concave arc with R >= rho"); every other case must be compensated exactly
    stats: Counter = Counter()

    @settings(report_multiple_bugs=False)   # one bug shrunk is enough: keeps a failing run short
    @given(rounded_polygons(), params)
    def prop(pr, p):
        contour = rounded_contour(pr[0], pr[1], p["ccw"], p["first"])
        check_contour(contour, p, stats, convex=True)

    prop()
    # most drawn contours must be compensated, or the property checks little: about three in four are
    # (one in two in a rare unlucky random run: the examples Hypothesis draws are not independent)
    assert stats["ok"] >= (stats["ok"] + stats["refused"]) / 4, stats


# ------------------------------------------------------------------ 3. regressions: what the properties found
#
# Each was a silent gouge (or a wrong refusal) in fagorcnc/path/compensation.py when found; the package, edited
# at the same time, was fixed before these tests were finished.  The programs are hypothesis' minimal examples
# (laid out by `program`) or hand-made reductions.

# A. A move shortened past its start by the trim of the inside corner at its start, and followed by an outside
#    corner or by the cancellation, was not seen as a step (only inside corners were checked): its offset ran
#    backwards.  Here line 6 (X30 Y0, 2.27 long) is trimmed by 2.32 at its start (deflection 98 degrees, R 2) and
#    ends at an outside corner: its offset ran backwards, 0.05 into the edge of line 5.
STEP_BEFORE_OUTSIDE_CORNER = """\
G90 G17 G00 X8.787202077 Y-29.114184737
T1 D1 M6
G136 G138
G01 G41 X3.344094 Y-9.8691185 F500
G01 X30.931034 Y-2.066667
G01 X30 Y0
G01 X29.933259 Y2
G01 X29.733333 Y3.991101
G01 X29.401112 Y5.964444
G01 X28.938074 Y7.91125
G01 X28.346279 Y9.822854
G01 X27.62836 Y11.690753
G01 X26.787512 Y13.506636
G01 X7.256574 Y29.109142
G01 X-24.242846 Y-17.67157
G01 X3.344094 Y-9.8691185
G40 G01 X8.787202077 Y-29.114184737
M30
"""


def test_regression_step_before_an_outside_corner():
    check_program(STEP_BEFORE_OUTSIDE_CORNER, 2.0)
    # hand-made: line 5 (X50 -> X40 Y2) turns back 169 degrees, inside for G41: trimmed past its start
    text = "G90 G17 G00 X0 Y-10\nT1 D1 M6\nG01 G41 X0 Y0 F500\nX50\nX40 Y2\nX40 Y30\nG40 X60 Y30\nM30\n"
    r = fagorcnc.simulate(text, machine(3.0))
    # not executed, with the warning "profile modified" (seed 002 L9455-L9459)
    assert r.ok and [(d.code, d.line) for d in r.diagnostics if d.code.startswith("INT")] == [("INT120", 5)], \
        [str(d) for d in r.diagnostics]


# B. A concave arc whose radius is not larger than the tool radius (spec 04 §16.2, §23.1: offset radius
#    rho - R <= 0, "the arc cannot be followed") was only detected when the arc took part in an inside-corner
#    trim.  Between tangent or outside corners its offset end points were taken on the far side of the centre,
#    the arc was followed with radius R - rho and the tool cut into the contour, with no diagnostic.

ROUNDED_POCKET = contour_from("rectangle with fillets of radius 2", (30, 0), [
    (58, 0), ((60, 2), (58, 2), True), (60, 38), ((58, 40), (58, 38), True),
    (2, 40), ((0, 38), (2, 38), True), (0, 2), ((2, 0), (2, 2), True), (30, 0)])


def refused_or_right(rn: Run, contour: Contour, side: int, transition: int, radius: float) -> None:
    if rn.result.ok:
        found = problems(rn, contour, side, transition, radius)
        assert not found, report(rn, found)


@pytest.mark.parametrize("transition", [136, 137])
def test_regression_fillets_smaller_than_the_tool_inside(transition):
    # corners rounded to radius 2, milled from inside (G41, CCW) with R 3: line 5 ran to (58,3), the fillet of
    # line 6 became an arc of radius 1 about (58,2) from (58,3) to (57,2), line 7 started at (57,2): 2 from the
    # fillet, a 1 mm gouge at every corner
    refused_or_right(run(ROUNDED_POCKET, 41, transition, 3.0), ROUNDED_POCKET, 41, transition, 3.0)


def test_regression_notch_smaller_than_the_tool_outside():
    # a half-circle notch of radius 8 milled from outside (G42) with R 9: an arc of radius 1 about (30,40) from
    # (29,40) to (31,40) between two G136 joins swinging into the notch: gouge up to 1.97
    refused_or_right(run(NOTCH, 42, 136, 9.0), NOTCH, 42, 136, 9.0)


SMALL_CONCAVE_ARC = """\
G90 G17 G00 X13.451797136 Y-29.519539425
T1 D1 M6
G136 G138
G01 G41 X5.158459137 Y-11.320073915 F500
G01 X-19.683081726 Y-22.64014783
G01 X-4.171752919 Y29.708525335
G01 X25.827475408 Y15.262421632
G03 X26.78751188 Y13.506635676 I0.480018236 J-0.877892978
G01 X27.628360165 Y11.690753381
G01 X28.346278997 Y9.822854321
G01 X28.938074074 Y7.911249515
G01 X29.401112266 Y5.964444444
G01 X29.733333333 Y3.991101213
G01 X29.933259094 Y2
G01 X30 Y0
G01 X5.158459137 Y-11.320073915
G40 G01 X13.451797136 Y-29.519539425
M30
"""


def test_regression_small_concave_arc():
    # minimal example of test_star_contours_with_arcs: line 8 is a half circle of radius 1 into a clockwise
    # contour milled from outside (G41) with R 2: the join after line 7 and the offset of line 8 came within
    # 0.0011 of the contour (gouge 1.9989)
    check_program(SMALL_CONCAVE_ARC, 2.0)


# C. A G136 join at an outside corner of tiny deflection (above the 1e-9 tangency threshold, end points closer
#    than 1e-7) was recorded with start == end, which an arc record reads as a full turn: the tool circled the
#    corner point once (sweep -360), cutting R deep into the contour.

FULL_CIRCLE_JOIN = """\
G90 G17 G00 X22.17061766 Y1.152138294
T1 D1 M6
G136 G138
G01 G41 X41.629784778 Y5.771750299 F500
G01 X40.259569557 Y11.543500598
G02 X41.152112392 Y11.811166142 I0.454078873 J0.107798458
G01 X41.837209302 Y9.932165816
G01 X43 Y0
G01 X41.629784778 Y5.771750299
G40 G01 X22.17061766 Y1.152138294
M30
"""


def test_regression_near_tangent_join_is_not_a_full_circle():
    # minimal example of test_rounded_convex_polygons: the fillet (line 6, 9 decimals) meets line 7 at a
    # deflection of about 1e-10 rad: the join after line 6 was a 360 degree arc about (41.152,11.811), gouge 0.91
    check_program(FULL_CIRCLE_JOIN, 1.0, convex=True)
    # hand-made: the arc starts 1e-8 rad off the tangent of line 4
    text = ("G90 G17 G00 X0 Y-10\nT1 D1 M6\nG01 G41 X0 Y0 F500\nX20\n"
            "G02 X29.9999999 Y-10 I-0.0000001 J-10\nG40 G01 X29.9999999 Y-30\nM30\n")
    r = fagorcnc.simulate(text, machine(3.0))
    assert r.ok, [str(d) for d in r.diagnostics]
    assert all(abs(m.sweep) < 1.0 for m in r.moves if m.kind == "arc" and m.line == 4)
    contour = [Seg((0.0, 0.0), (20.0, 0.0)), ArcEl((20.0, 0.0), (29.9999999, -10.0), (19.9999999, -10.0), False)]
    worst = min(min(e.distance(x) for e in contour) for m in r.moves if m.line in (4, 5) for x in samples(m, 0.5))
    assert worst >= 3.0 - 1e-6, f"gouge {3.0 - worst:.6f}"


# D. At a line -> arc junction tangent but for rounding (|cross| just above 1e-9, here 1.05e-9) the inside-corner
#    trim of the nearly tangent offset line and circle fell 1.7e-7 before the arc's start (ill-conditioned): the
#    offset arc swept 1e-5 degree more than the programmed one, and the step test (1e-6 degree) refused a
#    convex contour milled from outside: "INT086 this arc is too short for the tool radius" on line 6.

NEAR_TANGENT_TRIM = """\
G90 G17 G00 X42.423961235 Y-20.296676084
T1 D1 M6
G136 G138
G01 G41 X24.404583877 Y-11.619001302 F500
G01 X18.809167754 Y-23.238002604
G02 X18.469943787 Y-23.508524691 I-0.450484434 J0.216941869
G01 X-6.675628019 Y-29.247837365
G01 X-27.029066037 Y-13.016512174
G01 X-27.029066037 Y13.016512174
G01 X-6.675628019 Y29.247837365
G01 X18.704694056 Y23.454944474
G01 X30 Y0
G01 X24.404583877 Y-11.619001302
G40 G01 X42.423961235 Y-20.296676084
M30
"""


def test_regression_near_tangent_trim_is_not_a_step():
    check_program(NEAR_TANGENT_TRIM, 0.5, convex=True)
