"""Tangential control: G45, G145, #TANGCTRL (seed 002 ch. 16, L12036-L12391; spec 05 §5).

A rotary axis of modulo type is kept at an angle φ to the path in the active plane: it stands at
``θ_path + φ`` (θ_path = atan2(d ordinate, d abscissa), 0 along +abscissa [reconstruction, A19]),
reached by the shortest way.  Before a move whose start tangent differs from the axis' angle, the
axis turns alone (a rotary-only record at the tangential feed); on a line it stays; on an arc it turns
with the tangent, by the arc's signed sweep.  The stage runs as the interpreter makes each record, so
the channel's position of the axis follows.

Not computed (refused, KIN052): tangential control with radius compensation, corner aids G36-G39
or a coordinate transformation active (the manual allows compensation; where the CNC turns the axis
on the compensated joins is not stated).
"""

from __future__ import annotations

import math
from dataclasses import replace

from ..interp.expressions import InterpError

MAX_ANGLE = 359.9999


def _shortest(delta: float) -> float:
    d = math.fmod(delta, 360.0)
    if d > 180.0:
        d -= 360.0
    elif d <= -180.0:
        d += 360.0
    return d


def check_axis(st, axis: str, col: int) -> None:
    """Only a modulo rotary axis outside the plane and the longitudinal axis (L12069)."""
    ax = st.machine.axes.get(axis)
    if ax is None or axis not in st.axes:
        raise InterpError("KIN050", f"tangential control: axis {axis} is not in the channel", col)
    if not ax.rotary or ax.rotary_mode == "linearlike":
        raise InterpError("KIN050", f"tangential control needs a rotary axis of modulo type; {axis} is not one "
                          "(L12069)", col)
    if axis in st.plane_axes():
        raise InterpError("KIN050", f"tangential control: {axis} is an axis of the plane or the longitudinal axis "
                          "(L12070)", col)


def _angle(value: float, col: int) -> float:
    if not -MAX_ANGLE <= value <= MAX_ANGLE:
        raise InterpError("KIN051", f"tangential angle {value:g} outside ±359.9999 degrees (L12130)", col)
    return value


def activate(interp, angles: dict[str, float], col: int) -> None:
    st = interp.state
    kin = st.kin
    if kin.frame is not None:
        raise InterpError("KIN052", "tangential control with a coordinate transformation active is not computed "
                          "by fagorcnc", col)
    for axis, value in angles.items():
        check_axis(st, axis, col)
        kin.tangential[axis] = [_angle(value, col), 1]


def cancel(kin, axes=None) -> None:
    for a in list(kin.tangential) if axes is None else axes:
        kin.tangential.pop(a, None)


def g45(interp, bw, col: int) -> None:
    """G45 axis angle {axis angle}; G45 alone cancels every axis (L12106, L12204)."""
    kin = interp.state.kin
    angles = {a: v for a, (v, _c) in bw.axes.items()}
    bw.axes.clear()   # the words are the angles, not targets
    if not angles:
        cancel(kin)
        return
    activate(interp, angles, col)


def g145(interp, bw, col: int) -> None:
    """G145 <K0|K1> <axes>: suspend (K0, the default) or resume (K1) (L12240-L12329)."""
    st = interp.state
    k = bw.params.pop("K", None)
    value = 0.0 if k is None else k[0]
    if value not in (0.0, 1.0):
        raise InterpError("KIN051", f"G145 K{value:g}: K is 0 (suspend) or 1 (resume) (L12262)", col)
    axes = list(bw.axes) or None
    bw.axes.clear()
    _suspend(st.kin, axes, value == 0.0)


def _suspend(kin, axes, suspend: bool) -> None:
    for a in (list(kin.tangential) if axes is None else axes):
        if a in kin.tangential:
            kin.tangential[a][1] = 2 if suspend else 1


def statement(interp, node) -> None:
    """#TANGCTRL ON [<axis angle,...>, <F feed>], OFF <[axes]>, SUSP <[axes]>, RESUME <[axes]>."""
    from ..syntax.ast import ItemList, Keyed, Name

    st = interp.state
    kin = st.kin
    col = node.col
    first = node.args[0] if len(node.args) == 1 else None
    verb = first.name if type(first) in (Name, Keyed) else None
    if verb not in ("ON", "OFF", "SUSP", "RESUME"):
        raise InterpError("KIN005", "write #TANGCTRL ON [A90, F300], OFF, SUSP or RESUME <[axes]>", col)
    items = first.value.items if type(first) is Keyed and type(first.value) is ItemList else ()
    if verb == "ON":
        angles, feed = {}, None
        for seq in items:
            if len(seq) != 1 or type(seq[0]) is not Keyed:
                raise InterpError("KIN005", "#TANGCTRL ON [axis angle, ..., F feed]", col)
            t = seq[0]
            value = interp.evaluator.value(t.value)
            if t.name == "F":
                feed = interp.iso.length(value)
            else:
                angles[t.name] = value
        if not angles and feed is None:
            raise InterpError("KIN051", "#TANGCTRL ON needs an axis with its angle or the feed F (L12113)", col)
        if feed is not None:
            if feed <= 0:
                raise InterpError("KIN051", f"#TANGCTRL feed F{feed:g} must be positive", col)
            kin.tangfeed = feed   # kept after cancellation (L12170)
        activate(interp, angles, col)
        return
    axes = []
    for seq in items:
        if len(seq) != 1 or type(seq[0]) is not Name:
            raise InterpError("KIN005", f"#TANGCTRL {verb} [axis, ...]", col)
        axes.append(seq[0].name)
    if verb == "OFF":
        cancel(kin, axes or None)
    else:
        _suspend(kin, axes or None, verb == "SUSP")


def programmed(st, bw) -> None:
    """A tangential axis cannot be programmed while active or suspended (L12076)."""
    for a in st.kin.tangential:
        if a in bw.axes:
            raise InterpError("KIN053", f"axis {a} is under tangential control: it cannot be programmed (L12076)",
                              bw.axes[a][1])


def _tangents(rec, a: str, o: str):
    """(start, end) directions of a move in the plane, degrees; None when it does not move in it."""
    if rec.kind == "arc":
        ca, co = rec.center[a], rec.center[o]
        sign = 1.0 if rec.direction == "ccw" else -1.0

        def tangent(p):
            return math.degrees(math.atan2(sign * (p[a] - ca), -sign * (p[o] - co)))

        return tangent(rec.start), tangent(rec.start) + rec.sweep
    da, do = rec.end[a] - rec.start[a], rec.end[o] - rec.start[o]
    if math.hypot(da, do) < 1e-9:
        return None
    t = math.degrees(math.atan2(do, da))
    return t, t


def follow(records, interp):
    """The stage: each move of the plane with the tangential axes where tangential control puts them."""
    from ..interp.records import Line
    from .stage import StageError

    st = interp.state
    kin = st.kin
    for rec in records:
        if not kin.tangential or rec.kind not in ("linear", "rapid", "arc", "aid"):
            yield rec
            continue
        if rec.kind == "aid" or getattr(rec, "comp", None) is not None or kin.frame is not None:
            raise StageError(rec, "KIN052", "tangential control with radius compensation, corner aids G36-G39 "
                             "or a coordinate transformation is not computed by fagorcnc")
        if rec.kind == "arc":
            a, o = rec.plane[0], rec.plane[1]
        else:
            a, o, _n = st.plane_axes()
        ts = _tangents(rec, a, o)
        if ts is None:
            yield rec
            continue
        start, end = dict(rec.start), dict(rec.end)
        turn = {}
        for axis, (phi, mode) in kin.tangential.items():
            if mode != 1:
                continue   # suspended: the axis stays where it is
            cur = start[axis]
            target = cur + _shortest(ts[0] + phi - cur)
            if abs(target - cur) > 1e-9:
                turn[axis] = target
            start[axis] = target
            end[axis] = target + (ts[1] - ts[0])
        if turn:   # the axis turns alone before the move (L12190), at the tangential feed or its MAXFEED
            feed = kin.tangfeed or min(st.machine.axes[x].max_feed or st.machine.axes[x].max_velocity for x in turn)
            at = {k: rec.start[k] - (rec.end[k] - v) for k, v in rec.end_part.items()}
            at.update({x: v - (rec.end[x] - rec.end_part[x]) for x, v in turn.items()})
            yield Line("linear", dict(rec.start), {**rec.start, **turn}, at, feed, "G94", rec.src, None, rec.dyn)
        rec = replace(rec, start=start, end=end,
                      end_part={**rec.end_part, **{x: end[x] - (rec.end[x] - rec.end_part[x])
                                                   for x in kin.tangential}})
        for axis in kin.tangential:
            st.machine_pos[axis] = end[axis]
        yield rec
