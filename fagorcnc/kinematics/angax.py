"""Angular transformation of an inclined axis: #ANGAX ON/OFF/SUSP (seed 002 ch. 15, L11812-L12034;
spec 05 §4).

The machine file lists the transformations (``[[angular_axes]]``, numbered in file order, as the
manual's machine-parameter table).  The programmer writes Cartesian coordinates (x on the Cartesian
axis the angular slide replaces, z on the orthogonal axis); the real angular slide moves along
``d = cos(α) e_x + σ sin(α) e_z``, so [reconstruction, the manual's figure is lost; spec 05 §4]::

    real from Cartesian:  x' = x / cos α      z_r = z - σ x tan α

with α = ``angle`` (ANGANTR) and σ = ``sense`` (+1 or -1).  ``offset`` (OFFANGAX) only moves the origin
of the inclined system and cancels out when both axes are measured from machine zero; a non-zero
offset is refused at load (its use cannot be rebuilt without the figure).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..config.kinematics import AngularAxis
from .frame import AxisFrame


@dataclass(frozen=True, eq=False)
class AngaxFrame(AxisFrame):
    """The active angular transformations (a linear map: a line stays a line)."""

    transformations: tuple[AngularAxis, ...]
    description = "#ANGAX"

    @property
    def linear(self) -> tuple[str, str, str]:
        t = self.transformations[0]
        return t.angular, t.orthogonal, t.angular

    def point(self, pos: dict, near: dict | None = None) -> dict:
        out = dict(pos)
        for t in self.transformations:
            a = math.radians(t.angle)
            x = out[t.angular]
            out[t.angular] = x / math.cos(a)
            out[t.orthogonal] = out[t.orthogonal] - t.sense * x * math.tan(a)
        return out

    def inverse(self, machine: dict) -> dict:
        out = dict(machine)
        for t in reversed(self.transformations):
            a = math.radians(t.angle)
            xr = out[t.angular]
            out[t.angular] = xr * math.cos(a)
            out[t.orthogonal] = out[t.orthogonal] + t.sense * xr * math.sin(a)
        return out

    def affine_between(self, start: dict, end: dict) -> bool:
        return True


# ---------------------------------------------------------------------- statements
def statement(interp, node) -> None:
    """#ANGAX ON [n, ...], #ANGAX OFF <[n, ...]>, #ANGAX SUSP <[n, ...]> (seed 002 L11872-L11960)."""
    from ..interp.expressions import InterpError, whole
    from ..syntax.ast import ItemList, Keyed, Name

    st = interp.state
    kin = st.kin
    col = node.col
    args = node.args
    first = args[0] if args else None
    verb = first.name if type(first) in (Name, Keyed) else None
    if verb not in ("ON", "OFF", "SUSP") or len(args) != 1:
        raise InterpError("KIN005", "write #ANGAX ON [n,...], #ANGAX OFF <[n,...]> or #ANGAX SUSP <[n,...]>", col)
    numbers = []
    if type(first) is Keyed:
        items = first.value.items if type(first.value) is ItemList else ((first.value,),)
        for seq in items:
            if len(seq) != 1:
                raise InterpError("KIN005", "#ANGAX: one transformation number between commas", col)
            n = whole(interp.evaluator.value(seq[0]))
            if n is None or not 1 <= n <= len(kin.angular_axes):
                raise InterpError("KIN040", f"#ANGAX: transformation {n if n is not None else '?'} is not set up "
                                  f"(the machine file has {len(kin.angular_axes)}; L11885)", col)
            numbers.append(n)
    if verb == "ON" and not numbers:
        raise InterpError("KIN040", "#ANGAX ON needs at least one transformation number (L11885)", col)
    if verb in ("ON", "SUSP") and (kin.active or kin.rtcp or kin.tlc is not None or kin.caxis is not None):
        raise InterpError("KIN034", "#ANGAX together with #CS/#ACS, #RTCP, #TLC, #FACE or #CYL is not computed by "
                          "fagorcnc", col)
    chosen = numbers or list(range(1, len(kin.angular_axes) + 1))
    for n in chosen:
        if verb == "ON":
            kin.angax[n] = 1
        elif verb == "OFF":
            kin.angax.pop(n, None)
        elif n in kin.angax:
            kin.angax[n] = 2
    kin.rebuild(st)


def frame_of(kin) -> AngaxFrame | None:
    on = tuple(t for t in kin.angular_axes if t.number in kin.angax)
    return AngaxFrame(on) if on else None


def suspended_target(interp, bw, out: dict) -> None:
    """A suspended transformation: a block programming only the angular axis moves only that slide
    (its position written as a Cartesian value, x' = x / cos α), the orthogonal axis stays
    (seed 002 L11939-L11948)."""
    from ..interp.expressions import InterpError

    st = interp.state
    frame = st.kin.frame
    for t in st.kin.angular_axes:
        if st.kin.angax.get(t.number) != 2 or t.angular not in bw.axes or t.orthogonal in bw.axes:
            continue
        tr = st.transform
        if tr.scale != 1.0 or tr.angle != 0.0 or tr.mirror:
            raise InterpError("KIN041", "a suspended #ANGAX with scaling, rotation or mirror active is not "
                              "computed by fagorcnc", 1)
        real = frame.point(st.machine_pos)   # the orthogonal slide stays where it is
        a = math.radians(t.angle)
        x_v = out[t.angular] + st.axis_offset(t.angular)
        z_v = real[t.orthogonal] + t.sense * x_v * math.tan(a)
        out[t.orthogonal] = z_v - st.axis_offset(t.orthogonal)


def variables(st) -> dict:
    """V.MPK.NANG, ANGAXNA, ORTAXNA (also ORTGAXNA, as ch. 15 writes it), ANGANTR, OFFANGAX;
    V.G.ANGAXST, V.G.ANGIDST[i] (seed 002 L28939-L29007, L12010-L12034)."""
    from ..interp.expressions import InterpError, whole

    def entry(i: tuple) -> AngularAxis:
        n = whole(i[0]) if i else None
        if n is None or not 1 <= n <= len(st.kin.angular_axes):
            raise InterpError("INT045", f"angular transformation [{i[0] if i else ''}] does not exist", 1)
        return st.kin.angular_axes[n - 1]

    def logical(name: str) -> float:
        return float(st.axes.index(name) + 1)

    def channel_state(i: tuple) -> float:
        states = set(st.kin.angax.values())
        return 1.0 if 1 in states else 2.0 if 2 in states else 0.0

    out = {
        "V.MPK.NANG": (lambda i: float(len(st.kin.angular_axes)), None),
        "V.MPK.ANGAXNA[]": (lambda i: logical(entry(i).angular), None),
        "V.MPK.ORTAXNA[]": (lambda i: logical(entry(i).orthogonal), None),
        "V.MPK.ORTGAXNA[]": (lambda i: logical(entry(i).orthogonal), None),
        "V.MPK.ANGANTR[]": (lambda i: entry(i).angle, None),
        "V.MPK.OFFANGAX[]": (lambda i: entry(i).offset, None),
        "V.G.ANGAXST": (channel_state, None),
        "V.G.ANGIDST[]": (lambda i: float(st.kin.angax.get(entry(i).number, 0)), None),
    }
    return out
