"""V. variables of the kinematics (seed 002 L28769-L28937, L13375-L13413; spec 07 §B.8, spec 05 §6.10).

``V.MPK.NKIN``, ``V.MPK.TYPE[kin]``, ``V.MPK.NKINAX[kin]`` read the machine file's ``[[kinematics]]``;
``V.MPK.TDATAk[nb]`` / ``TDATA_Ik[nb]`` are refused (KIN023): fagorcnc names the geometry instead of
numbering it.  ``V.G.POSROTF`` / ``POSROTS`` are the present positions of the selected kinematics'
main and secondary rotary axes (writable: a head positioned by hand), ``V.G.TOOLORIF1``/``S1``/``F2``/
``S2`` the positions that put the tool perpendicular to the active plane (solution 1, solution 2);
``V.G.KINID``, ``V.G.CS``/``ACS`` (the last one activated, 0 for none or the unnamed one),
``V.G.TOOLCOMP`` (1 RTCP, 2 TLC, 3 none), ``V.G.CSMAT1..9`` (the plane's rotation, row by row) and
``CSMAT10..12`` (its zero from machine zero).
"""

from __future__ import annotations

from ..interp.expressions import InterpError, whole


def _kin(st, index: tuple):
    kins = st.kin.kinematics
    n = whole(index[0]) if index else None
    if n is None or not 1 <= n <= len(kins):
        raise InterpError("INT045", f"kinematics [{index[0] if index else ''}] does not exist (the machine "
                          f"defines {len(kins)})", 1)
    return kins[n - 1]


def _rotary(st, k: int) -> str:
    kin = st.kin.current
    if kin is None or len(kin.joints) <= k:
        raise InterpError("KIN003", "no kinematics with that rotary axis is selected (#KIN ID)", 1)
    return kin.joints[k].axis


def _set_rotary(st, k: int, value: float) -> None:
    st.machine_pos[_rotary(st, k)] = value


def _toolori(st, solution: int, k: int) -> float:
    sols = st.kin.toolori
    if sols is None:
        return 0.0
    kin = st.kin.current
    return sols[solution][kin.joints[k].axis]


def _plane_variables(st) -> dict:
    """V.G.KINID, V.G.CS, V.G.ACS, V.G.TOOLCOMP, V.G.CSMAT1..12 (seed 002 L41252-L41430)."""
    import numpy as np

    def last(kind: str) -> float:
        ids = [n for k, n, *_ in st.kin.active if k == kind]
        return float(ids[-1] or 0) if ids else 0.0

    def matrix(k: int) -> float:
        r, v = st.kin.plane()
        if k <= 9:
            return float(r[(k - 1) // 3, (k - 1) % 3])
        zero = st.kin.zero if st.kin.zero is not None else np.zeros(3)
        return float((zero + v)[k - 10])   # the plane's zero from machine zero

    out = {
        "V.G.KINID": (lambda i: float(st.kin.kinid if st.kin.current is not None else 0), None),
        "V.G.CS": (lambda i: last("CS"), None),
        "V.G.ACS": (lambda i: last("ACS"), None),
        "V.G.TOOLCOMP": (lambda i: 1.0 if st.kin.rtcp else 2.0 if st.kin.tlc is not None else 3.0, None),
    }
    for k in range(1, 13):
        out[f"V.G.CSMAT{k}"] = (lambda i, k=k: matrix(k), None)
    return out


def _tdata(index: tuple) -> float:
    raise InterpError("KIN023", "V.MPK.TDATA values are the manufacturer's installation data; fagorcnc names the "
                      "kinematics geometry in the machine file instead ([[kinematics]] in the README)", 1)


def variables(st) -> dict:
    """Name -> (getter(index), setter(index, value) or None), as ``Variables.plain_vars``."""
    out = {
        "V.MPK.NKIN": (lambda i: float(len(st.kin.kinematics)), None),
        "V.MPK.TYPE[]": (lambda i: float(_kin(st, i).type), None),
        "V.MPK.NKINAX[]": (lambda i: float(len(_kin(st, i).joints)), None),
        "V.G.POSROTF": (lambda i: st.machine_pos[_rotary(st, 0)], lambda i, v: _set_rotary(st, 0, v)),
        "V.G.POSROTS": (lambda i: st.machine_pos[_rotary(st, 1)], lambda i, v: _set_rotary(st, 1, v)),
        "V.G.POSROTT": (lambda i: st.machine_pos[_rotary(st, 2)], lambda i, v: _set_rotary(st, 2, v)),
        "V.G.TOOLORIF1": (lambda i: _toolori(st, 0, 0), None),
        "V.G.TOOLORIS1": (lambda i: _toolori(st, 0, 1), None),
        "V.G.TOOLORIF2": (lambda i: _toolori(st, 1, 0), None),
        "V.G.TOOLORIS2": (lambda i: _toolori(st, 1, 1), None),
    }
    from .angax import variables as angax_variables

    out.update(angax_variables(st))
    out.update(tangential_variables(st))
    out.update(_plane_variables(st))
    for n in range(1, 7):
        out[f"V.MPK.TDATA{n}[]"] = (_tdata, None)
        out[f"V.MPK.TDATA_I{n}[]"] = (_tdata, None)
    return out


def axis_variables() -> dict:
    """V.A.TANGAN.Xn (the programmed tangential angle, kept while suspended) and V.A.TGCTRLST.Xn
    (0 off, 1 active, 2 suspended), as ``Variables.axis_vars`` (seed 002 L12331-L12391)."""
    def entry(st, a: str):
        return st.kin.tangential.get(a)

    return {
        "V.A.TANGAN": (lambda st, i, a: entry(st, a)[0] if entry(st, a) else 0.0, None),
        "V.A.TGCTRLST": (lambda st, i, a: float(entry(st, a)[1]) if entry(st, a) else 0.0, None),
    }


def tangential_variables(st) -> dict:
    """V.G.TANGFEED and V.G.TGCTRLST (the channel: 0 off, 1 active, 2 suspended)."""
    def channel(i: tuple) -> float:
        modes = {m for _phi, m in st.kin.tangential.values()}
        return 1.0 if 1 in modes else 2.0 if 2 in modes else 0.0

    return {
        "V.G.TANGFEED": (lambda i: st.kin.tangfeed or 0.0, None),
        "V.G.TGCTRLST": (channel, None),
    }
