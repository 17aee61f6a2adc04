"""The C axis: face machining #FACE and cylindrical-surface machining #CYL (seed 002 ch. 14,
L11529-L11810; spec 05 §3.2-§3.3).

While one is active the interpreter computes in the Cartesian (face) or developed (cylinder) plane,
the C axis programmed as a length; a :class:`FaceFrame` or :class:`CylinderFrame` on each move turns
that into the real axes, and the joint-space stage (:mod:`.stage`) cuts what is not a straight line
in the joints into lines within the tolerance.

* face: ``r = sqrt(x² + c²)`` on the radial axis (a radius), ``θ = atan2(c, x)`` on the C axis in
  degrees, followed continuously (no jump of 360); near ``r = 0`` the C axis turns fast and the
  planner's C limits slow the move down;
* cylinder: ``θ = s / R · 180/π`` for the developed coordinate ``s`` on a cylinder of radius ``R``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .frame import AxisFrame


def _nearest(angle: float, near: float | None) -> float:
    if near is None:
        return angle
    return angle + 360.0 * round((near - angle) / 360.0)


@dataclass(frozen=True, eq=False)
class FaceFrame(AxisFrame):
    """#FACE [radial, C, longitudinal]: the polar transformation of the face plane."""

    radial: str
    angular: str
    longitudinal: str
    description = "#FACE"
    arcs = False          # an arc of the face plane is never an arc of the joints
    wrapped = property(lambda self: (self.angular,))   # its angle is followed over whole turns
    initial_pieces = 32   # the first cut of a move, angles followed from piece to piece

    @property
    def linear(self) -> tuple[str, str, str]:
        return self.radial, self.angular, self.longitudinal

    def point(self, pos: dict, near: dict | None = None) -> dict:
        x, c = pos[self.radial], pos[self.angular]
        r = math.hypot(x, c)
        ref = near.get(self.angular) if near is not None else None
        theta = math.degrees(math.atan2(c, x)) if r > 1e-12 else (ref if ref is not None else 0.0)
        out = dict(pos)
        out[self.radial], out[self.angular] = r, _nearest(theta, ref)
        return out

    def inverse(self, machine: dict) -> dict:
        r, theta = machine[self.radial], math.radians(machine[self.angular])
        out = dict(machine)
        out[self.radial], out[self.angular] = r * math.cos(theta), r * math.sin(theta)
        return out

    def affine_between(self, start: dict, end: dict) -> bool:
        return False


@dataclass(frozen=True, eq=False)
class CylinderFrame(AxisFrame):
    """#CYL [abscissa, ordinate, longitudinal R]: the rotary axis programmed along the developed surface."""

    abscissa: str
    ordinate: str
    longitudinal: str
    rotary: str
    radius: float
    description = "#CYL"

    @property
    def linear(self) -> tuple[str, str, str]:
        return self.abscissa, self.ordinate, self.longitudinal

    def point(self, pos: dict, near: dict | None = None) -> dict:
        out = dict(pos)
        out[self.rotary] = math.degrees(pos[self.rotary] / self.radius)
        return out

    def inverse(self, machine: dict) -> dict:
        out = dict(machine)
        out[self.rotary] = math.radians(machine[self.rotary]) * self.radius
        return out

    def affine_between(self, start: dict, end: dict) -> bool:
        return True   # theta is proportional to s: a line stays a line


# ---------------------------------------------------------------------- #FACE / #CYL statements
def statement(interp, node, tokens: list) -> None:
    """#FACE [abs, ord <, long>] <[kin]>, #CYL [abs, ord, long R] <[kin]>, #FACE OFF, #CYL OFF
    (seed 002 L11664-L11810)."""
    from ..interp.expressions import InterpError, whole
    from ..syntax.ast import ItemList, Keyed, Name

    st = interp.state
    kin = st.kin
    kw = node.keyword
    col = node.col
    if tokens and type(tokens[0]) is Name and tokens[0].name == "OFF":
        if len(tokens) != 1:
            raise InterpError("KIN005", f"#{kw} OFF takes nothing more", col)
        if kin.caxis is not None and kin.caxis[0] == kw:
            _off(kin, st)
        return
    if not tokens or type(tokens[0]) is not ItemList:
        raise InterpError("KIN005", f"write #{kw} [abscissa, ordinate, ...] or #{kw} OFF", col)
    if kin.caxis is not None:
        raise InterpError("KIN034", f"#{kw}: #{kin.caxis[0]} is active; only one C axis at a time (L11531)", col)
    if kin.active or kin.rtcp or kin.tlc is not None:
        raise InterpError("KIN034", f"#{kw} together with #CS/#ACS, #RTCP or #TLC is not computed by fagorcnc", col)
    items = tokens[0].items
    names, radius = [], None
    for seq in items:
        if len(seq) != 1:
            raise InterpError("KIN005", f"#{kw}: one axis between commas", col)
        t = seq[0]
        if type(t) is Name:
            names.append(t.name)
        elif type(t) is Keyed and kw == "CYL" and len(names) == 2:
            names.append(t.name)
            radius = interp.iso.length(interp.evaluator.value(t.value))
        else:
            raise InterpError("KIN005", f"#{kw}: the list holds axis names", col)
    number = None
    if len(tokens) > 1:
        number = whole(interp.evaluator.value(tokens[1])) if len(tokens) == 2 else None
        if number is None:
            raise InterpError("KIN005", f"#{kw}: the kinematics number in brackets: #{kw} [...][1]", col)
        kinds = (41, 42) if kw == "FACE" else (43,)
        if not 1 <= number <= len(kin.kinematics) or kin.kinematics[number - 1].type not in kinds:
            raise InterpError("KIN033", f"#{kw} [{number}]: kinematics {number} is not a C-axis kinematics of "
                              f"type {' or '.join(map(str, kinds))}", col)
    for a in names:
        if a not in st.axes:
            raise InterpError("KIN032", f"#{kw}: axis {a} is not in the channel", col)
    if kw == "FACE":
        if len(names) not in (2, 3):
            raise InterpError("KIN005", "write #FACE [abscissa, ordinate <, longitudinal>]", col)
    elif len(names) != 3 or radius is None:
        raise InterpError("KIN030", "#CYL needs the longitudinal axis and the radius: #CYL [Y, B, Z20] (the "
                          "radius is mandatory since V3.10, L11783)", col)
    rotary = [a for a in names[:2] if st.machine.axes[a].rotary]
    if len(rotary) != 1:
        raise InterpError("KIN032", f"#{kw}: one of the two plane axes must be the rotary (C) axis", col)
    long_axis = names[2] if len(names) == 3 else next(
        (a for a in st.axes if a not in names and not st.machine.axes[a].rotary), None)
    if long_axis is None or st.machine.axes[long_axis].rotary:
        raise InterpError("KIN032", f"#{kw}: the longitudinal axis must be a linear axis", col)
    c = rotary[0]
    other = names[0] if names[1] == c else names[1]
    if abs(st.chain(c)) > 1e-12:
        # seed 002 L11567: the C component of an offset active at the switch-on is not applied
        raise InterpError("KIN035", f"#{kw}: a work offset with a {c} component is active; the CNC drops that "
                          "component (L11567), which fagorcnc does not compute: cancel it first", col)
    if kw == "CYL":
        if radius < 0:
            raise InterpError("KIN070", f"#CYL: the cylinder's radius is negative ({radius:g})", col)
        if radius == 0:
            radius = tip_radius(st, c, number, col)
        frame = CylinderFrame(names[0], names[1], long_axis, c, radius)
    else:
        if st.machine.axes[other].rotary:
            raise InterpError("KIN032", "#FACE: the radial axis must be linear", col)
        frame = FaceFrame(other, c, long_axis)
    # the plane is set (abscissa, ordinate as written: [X,C] and [C,X] are mirrored planes), radius
    # programming and G94; #FACE OFF / #CYL OFF bring back what was in force (A15: not stated)
    saved = (st.modes["plane"], st.g20_plane, st.modes.get("diameter"), st.modes["feed"])
    kin.caxis = (kw, frame, saved)
    kin.as_linear = frozenset({c})
    st.modes["plane"], st.g20_plane = 20, (names[0], names[1], long_axis)
    st.modes["diameter"], st.modes["feed"] = 152, 94
    kin.rebuild(st)
    interp.plane_changed()


def tip_radius(st, axis: str, number: int | None, col: int) -> float:
    """#CYL radius 0: the distance from the tool tip to the rotation line of ``axis`` when #CYL is given
    (seed 002 L11748: "on prendra comme rayon du cylindre la distance entre le centre de rotation et
    la pointe de l'outil").  The line is the joint of kinematics ``number`` or of the first type-43
    kinematics turning ``axis`` (L11752: the first one valid for this machining).  The radius is
    taken once, at the activation, and kept while #CYL is active [reading: the manual's example
    L11789 keeps its radius while Z moves 4 mm; "cylindres à rayon variable" read as parts of
    different radii run by one program].  The tool tip is the axes' position less the tool length
    offset (as ``V.A.TIPPOS``)."""
    from ..interp.expressions import InterpError

    kins = st.kin.kinematics
    cands = [kins[number - 1]] if number is not None else [k for k in kins if k.type == 43]
    kin = next((k for k in cands if k.type == 43 and k.joints[0].axis == axis), None)
    if kin is None:
        which = f"kinematics {number}" if number is not None else "no type-43 kinematics of the machine file"
        raise InterpError("KIN071", f"#CYL with radius 0 takes the tool tip's distance to the {axis} axis' "
                          f"rotation line, but {which} turns {axis}: give the radius, or the line in the "
                          "machine file ([[kinematics]] type = 43, axes, directions, pivots)", col)
    joint = kin.joints[0]
    lin = [a for a in st.axes if not st.machine.axes[a].rotary][:3]
    tip = np.array([st.machine_pos.get(a, 0.0) - st.length_offset.get(a, 0.0) for a in lin]
                   + [0.0] * (3 - len(lin)))
    d = np.asarray(joint.direction, dtype=float)
    rel = tip - np.asarray(joint.pivot, dtype=float)
    radius = float(np.linalg.norm(rel - d * float(d @ rel)))
    if radius < 1e-6:
        raise InterpError("KIN072", f"#CYL with radius 0: the tool tip is on the rotation line of {axis}, the "
                          "cylinder would have no radius", col)
    return radius


def _off(kin, st) -> None:
    _kw, _frame, saved = kin.caxis
    st.modes["plane"], st.g20_plane, diameter, st.modes["feed"] = saved
    if diameter is not None:
        st.modes["diameter"] = diameter
    kin.caxis = None
    kin.as_linear = frozenset()
    kin.rebuild(st)



# ---------------------------------------------------------------------- #CAX
def cax_statement(interp, node, src) -> list:
    """#CAX [<spindle><, name>], #CAX OFF (seed 002 L11576-L11662): the spindle stops and works as its C
    axis, which is referenced (moved to its home position); the records to hand on."""
    from ..interp.expressions import InterpError
    from ..interp.records import Line
    from ..interp.renaming import item_name
    from ..syntax.ast import ItemList, Name

    st = interp.state
    kin = st.kin
    col = node.col
    args = node.args
    if len(args) == 1 and type(args[0]) is Name and args[0].name == "OFF":
        kin.cax = None
        return []
    names = []
    if len(args) == 1 and type(args[0]) is ItemList:
        for seq in args[0].items:
            name = item_name(seq[0]) if len(seq) == 1 else None   # S, or S1 read as S with the value 1
            if name is None:
                raise InterpError("KIN005", "write #CAX, #CAX [S1], #CAX [S1, C1] or #CAX OFF", col)
            names.append(name)
    elif args:
        raise InterpError("KIN005", "write #CAX, #CAX [S1], #CAX [S1, C1] or #CAX OFF", col)
    # L11635-L11637: #CAX alone is the master spindle's; a named spindle is one of the channel, by its name there
    spindle = st.spindle_config.word(names[0], col) if names else st.master_spindle()
    if spindle is None:
        raise InterpError("KIN060", "#CAX: the channel has no spindle", col)
    if spindle not in st.machine.c_axes:
        raise InterpError("KIN060", f"#CAX: spindle {spindle} cannot work as a C axis (c_axis in the machine file, "
                          "CAXIS)", col)
    axis = st.machine.c_axes[spindle]
    if len(names) > 1 and names[1] != axis:
        raise InterpError("KIN060", f"#CAX: the C axis of {spindle} is {axis} in the machine file; another name "
                          f"({names[1]}) is not computed by fagorcnc", col)
    if len(names) > 2:
        raise InterpError("KIN005", "#CAX takes the spindle and the axis name", col)
    if kin.cax is not None and kin.cax[0] != spindle:
        raise InterpError("KIN034", f"#CAX: spindle {kin.cax[0]} already works as a C axis (one at a time, L11531)",
                          col)
    if kin.frame is not None:
        raise InterpError("KIN034", f"#CAX with {kin.frame.description} active is not computed by fagorcnc", col)
    kin.cax = (spindle, axis)
    st.spindle_state[spindle] = 5   # a turning spindle stops (L11600)
    st.speeds[spindle] = 0.0
    start = dict(st.machine_pos)
    end = {**start, axis: st.machine.axes[axis].home}   # the C axis is referenced (L11603)
    st.machine_pos = dict(end)
    if end == start:
        return []
    return [Line("rapid", start, end, st.to_part(end), None, "G94", src, dyn=st.dynamics())]


def cax_check(st, bw) -> None:
    """A spindle's C axis is programmed only under #CAX; a speed for the spindle working as C axis is
    refused (L11601)."""
    from ..interp.expressions import InterpError

    active = st.kin.cax
    for spindle, axis in st.machine.c_axes.items():
        on = active is not None and active[0] == spindle
        if axis in bw.axes and not on:
            raise InterpError("KIN061", f"{axis} is the C axis of spindle {spindle}: program #CAX first",
                              bw.axes[axis][1])
