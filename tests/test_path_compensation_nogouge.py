"""No gouge: random open and closed contours of lines and arcs, random tool radii, G41/G42, G136/G137.

Issue 21: wherever the compensated path of a contour block is defined (the program runs, possibly with
blocks not executed and the warning "profile modified", INT120-INT122, seed 002 L9455-L9459; or it stops
with INT086, and then what ran before the error), it never comes nearer to the programmed contour than the
tool radius minus 1e-6 mm.  Contours come from a turtle walk: each element turns from the last tangent by a
random angle, by 0 (tangent) or by 180 degrees (a cusp, the issue's reversal).  Elements two or more blocks
apart are kept 2R apart (a neck between far elements is beyond any local look-ahead: spec 04 §16.2), which
holds except near the joints; closed contours close with a line back to the start, approached from the
middle of their first element.  Bounded in the default suite; `-m slow` runs many more examples.
"""

from __future__ import annotations

import math
from collections import Counter

import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

import fagorcnc

Point = tuple[float, float]
EPS = 1e-6


def _f(v: float) -> str:
    return f"{v:.9f}".rstrip("0").rstrip(".")


def _r9(p: Point) -> Point:
    return (round(p[0], 9), round(p[1], 9))


def dist_seg(x: Point, p: Point, q: Point) -> float:
    d = (q[0] - p[0], q[1] - p[1])
    den = d[0] ** 2 + d[1] ** 2
    k = 0.0 if den == 0 else max(0.0, min(1.0, ((x[0] - p[0]) * d[0] + (x[1] - p[1]) * d[1]) / den))
    return math.dist(x, (p[0] + k * d[0], p[1] + k * d[1]))


def dist_arc(x: Point, el) -> float:
    _kind, p, q, c, ccw = el
    rho = math.dist(p, c)
    a0 = math.atan2(p[1] - c[1], p[0] - c[0])
    sw = (math.atan2(q[1] - c[1], q[0] - c[0]) - a0) % (2 * math.pi)
    if not ccw:
        sw = sw - 2 * math.pi if sw > 0 else sw
    ax = (math.atan2(x[1] - c[1], x[0] - c[0]) - a0) % (2 * math.pi)
    inside = ax <= sw if ccw else ax - 2 * math.pi >= sw or ax == 0
    if inside and math.dist(x, c) > 0:
        return abs(math.dist(x, c) - rho)
    return min(math.dist(x, p), math.dist(x, q))


def distance(x: Point, el) -> float:
    return dist_seg(x, el[1], el[2]) if el[0] == "line" else dist_arc(x, el)


def rot(t: Point, a: float) -> Point:
    return (t[0] * math.cos(a) - t[1] * math.sin(a), t[0] * math.sin(a) + t[1] * math.cos(a))


@st.composite
def walks(draw, closed: bool):
    """Elements ("line", p, q) / ("arc", p, q, c, ccw) with their block text."""
    n = draw(st.integers(2, 6))
    p, t = (0.0, 0.0), (1.0, 0.0)
    els, texts = [], []
    for _ in range(n):
        turn = draw(st.one_of(st.just(0.0), st.just(math.pi), st.floats(-2.8, 2.8)))
        t = rot(t, turn)
        if draw(st.booleans()):
            length = draw(st.floats(0.5, 30.0))
            q = _r9((p[0] + length * t[0], p[1] + length * t[1]))
            els.append(("line", p, q, None, True))
            texts.append(f"G01 X{_f(q[0])} Y{_f(q[1])}")
        else:
            rho = draw(st.floats(0.5, 20.0))
            ccw = draw(st.booleans())
            sweep = draw(st.floats(0.2, 3.0))
            nrm = (-t[1], t[0]) if ccw else (t[1], -t[0])
            ij = (round(rho * nrm[0], 9), round(rho * nrm[1], 9))
            c = (p[0] + ij[0], p[1] + ij[1])
            rel = rot((p[0] - c[0], p[1] - c[1]), sweep if ccw else -sweep)
            q = _r9((c[0] + rel[0], c[1] + rel[1]))
            els.append(("arc", p, q, c, ccw))
            texts.append(f"G0{3 if ccw else 2} X{_f(q[0])} Y{_f(q[1])} I{_f(ij[0])} J{_f(ij[1])}")
            u = ((q[0] - c[0]) / rho, (q[1] - c[1]) / rho)
            t = (-u[1], u[0]) if ccw else (u[1], -u[0])
        p = q
    if closed:
        assume(math.dist(p, (0.0, 0.0)) > 1.0)
        els.append(("line", p, (0.0, 0.0), None, True))
        texts.append("G01 X0 Y0")
    return els, texts


def program(els, texts, side: int, transition: int, closed: bool) -> tuple[str, int]:
    """Approach along the first element's start tangent, leave along the last's end tangent; contour blocks
    from line 5.  A closed walk starts and ends at the middle of an extra first line."""
    first, last = els[0], els[-1]

    def tangent(el, at_end):
        if el[0] == "line":
            d = (el[2][0] - el[1][0], el[2][1] - el[1][1])
        else:
            x = el[2] if at_end else el[1]
            u = (x[0] - el[3][0], x[1] - el[3][1])
            d = (-u[1], u[0]) if el[4] else (u[1], -u[0])
        n = math.hypot(*d)
        return (d[0] / n, d[1] / n)

    t0, t1 = tangent(first, False), tangent(last, True)
    p0 = _r9((first[1][0] - 20 * t0[0], first[1][1] - 20 * t0[1]))
    p2 = _r9((last[2][0] + 20 * t1[0], last[2][1] + 20 * t1[1]))
    lines = [f"G90 G17 G00 X{_f(p0[0])} Y{_f(p0[1])}", "T1 D1 M6", f"G{transition} G264",
             f"G01 G{side} X{_f(first[1][0])} Y{_f(first[1][1])} F500", *texts,
             f"G40 G01 X{_f(p2[0])} Y{_f(p2[1])}", "M30"]
    return "\n".join(lines) + "\n", 5


def separated(els, radius: float) -> bool:
    """Elements two or more apart keep more than 2R + 0.01 from each other (sampled)."""
    def pts(el):
        if el[0] == "line":
            return [(el[1][0] + (el[2][0] - el[1][0]) * k / 40, el[1][1] + (el[2][1] - el[1][1]) * k / 40)
                    for k in range(41)]
        c, p = el[3], el[1]
        rho = math.dist(p, c)
        a0 = math.atan2(p[1] - c[1], p[0] - c[0])
        a1 = math.atan2(el[2][1] - c[1], el[2][0] - c[0])
        sw = (a1 - a0) % (2 * math.pi) if el[4] else -((a0 - a1) % (2 * math.pi))
        return [(c[0] + rho * math.cos(a0 + sw * k / 40), c[1] + rho * math.sin(a0 + sw * k / 40))
                for k in range(41)]
    n = len(els)
    samples = [pts(e) for e in els]
    for i in range(n):
        for j in range(i + 2, n):
            if min(distance(x, els[j]) for x in samples[i]) <= 2 * radius + 0.01:
                return False
    return True


def check(els, texts, side, transition, radius, closed) -> str:
    """Run the contour; no gouge on what ran.  Returns the outcome: ok, dropped (blocks not executed) or
    refused (INT086)."""
    text, first_line = program(els, texts, side, transition, closed)
    r = fagorcnc.simulate(text, {"tools": {"1": {"1": {"radius": radius}}}})
    errors = [d for d in r.errors]
    assert all(d.code == "INT086" for d in errors), text + "\n".join(map(str, r.diagnostics))
    assert all(d.code in ("INT120", "INT121", "INT122") for d in r.diagnostics
               if not d.is_error and d.code.startswith("INT")), text
    contour_lines = range(first_line, first_line + len(els))
    last = first_line + len(els) - 1
    motion = [m for m in r.moves if m.kind in ("rapid", "linear", "arc")]
    seen_last = False
    for m in motion:
        if m.line not in contour_lines:
            continue
        if m.line == last or (m.line < last and all(k.line != last for k in motion)):
            pass
        if m.line == last:
            if seen_last:
                continue      # a join after the last block belongs to the cancellation (spec 04 §20)
            seen_last = True
        p, q = (m.start["X"], m.start["Y"]), (m.end["X"], m.end["Y"])
        if m.kind == "arc":
            c = (m.center["X"], m.center["Y"])
            a0, sw = math.atan2(p[1] - c[1], p[0] - c[0]), math.radians(m.sweep)
            rho = math.dist(p, c)
            xs = [(c[0] + rho * math.cos(a0 + sw * k / 64), c[1] + rho * math.sin(a0 + sw * k / 64))
                  for k in range(65)]
        else:
            xs = [(p[0] + (q[0] - p[0]) * k / 64, p[1] + (q[1] - p[1]) * k / 64) for k in range(65)]
        for x in xs:
            d = min(distance(x, e) for e in els)
            assert d >= radius - EPS, (f"gouge {radius - d:.6f} at ({x[0]:.5f},{x[1]:.5f}) on line {m.line}\n"
                                       + text + "\n".join(map(str, r.diagnostics)))
    return "refused" if errors else "dropped" if any(d.code.startswith("INT12") for d in r.diagnostics) else "ok"


CASES = st.tuples(st.sampled_from([41, 42]), st.sampled_from([136, 137]), st.floats(0.2, 5.0),
                  st.booleans())


def _property(walk, case, stats: Counter | None = None):
    side, transition, radius, closed = case
    els, texts = walk
    assume(separated(els, radius))
    outcome = check(els, texts, side, transition, radius, closed)
    if stats is not None:
        stats[outcome] += 1


@st.composite
def drawn(draw):
    case = draw(CASES)
    return draw(walks(case[3])), case


def test_no_gouge_bounded():
    stats: Counter = Counter()

    @settings(max_examples=60, deadline=None,
              suppress_health_check=[HealthCheck.filter_too_much, HealthCheck.too_slow])
    @given(drawn())
    def prop(data):
        _property(*data, stats=stats)

    prop()
    # not vacuous: most contours run (about 3 in 4 without a dropped block, 1 in 10 with; 1 in 6 refused)
    assert stats["ok"] + stats["dropped"] >= sum(stats.values()) / 2, stats


@pytest.mark.slow
@settings(max_examples=max(1000, settings.default.max_examples), deadline=None,
          suppress_health_check=[HealthCheck.filter_too_much, HealthCheck.too_slow])
@given(drawn())
def test_no_gouge_long(data):
    _property(*data)


def test_issue_cusp_is_a_case_of_the_property():
    # the issue's inch cusp in mm with G42 R 0.075 in: an arc ending heading -Y, then the line heading +Y
    c = (2.0502 * 25.4, 2.845 * 25.4)
    p, q = (2.2708 * 25.4, 2.845 * 25.4), (1.8296 * 25.4, 2.845 * 25.4)
    els = [("arc", p, q, c, True), ("line", q, (q[0], 3.56 * 25.4), None, True)]
    texts = [f"G03 X{_f(q[0])} Y{_f(q[1])} I{_f(c[0] - p[0])} J0", f"G01 X{_f(q[0])} Y{_f(3.56 * 25.4)}"]
    for side in (41, 42):
        check(els, texts, side, 136, 0.075 * 25.4, False)
