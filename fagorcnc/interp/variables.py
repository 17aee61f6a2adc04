"""V. variables an offline interpreter honours (seed 002 ch. 22; spec 07, 08).

Names are matched after the parser's normalisation (``V.A.ORGT[1].X`` is
``"V.A.ORGT[].X"`` with index ``(1,)``).  The axis of ``V.A.<name>.<axis>``
may be an axis name or its logical number (1 = first channel axis).  The
channel selector ``V.[n].`` is accepted for channel 1 only (one channel
offline).  Writing a read-only variable is an error (seed 002 L1809-L1812);
an unknown variable is an error naming it.  User variables ``V.P.name``
(local) and ``V.S.name`` (global) are created by assignment (L1821-L1860).
"""

from __future__ import annotations

from collections.abc import Callable

from .expressions import InterpError
from .state import ChannelState

Getter = Callable[[ChannelState, tuple, str | None], float]
Setter = Callable[[ChannelState, tuple, str | None, float], None]


def _entry(table: dict, n: int, col: int, what: str, hi: int) -> dict:
    if not 1 <= n <= hi:
        raise InterpError("INT045", f"{what}[{n}] does not exist (entries 1..{hi})", col)
    return table.setdefault(n, {})


class Variables:
    """Reads and writes ``V.`` variables against a :class:`ChannelState`."""

    def __init__(self, state: ChannelState) -> None:
        self.state = state
        s = state
        # name -> (getter, setter or None); axis variables take the axis as 3rd argument
        self.axis_vars: dict[str, tuple[Getter, Setter | None]] = {
            "V.A.PPOS": (lambda st, i, a: st.part_pos()[a], None),          # L35650
            "V.A.POS": (lambda st, i, a: st.machine_pos[a], None),          # L35803
            "V.A.TPOS": (lambda st, i, a: st.machine_pos[a], None),         # L35816
            "V.A.TIPPOS": (lambda st, i, a: st.machine_pos[a], None),       # L35846
            "V.A.TIPTPOS": (lambda st, i, a: st.machine_pos[a], None),
            "V.A.APOS": (lambda st, i, a: st.part_pos()[a], None),          # L35734
            "V.A.ATPOS": (lambda st, i, a: st.part_pos()[a], None),
            "V.A.ATIPPOS": (lambda st, i, a: st.part_pos()[a], None),
            "V.A.ATIPTPOS": (lambda st, i, a: st.part_pos()[a], None),
            "V.A.ORG": (lambda st, i, a: st.abs_offset[a] + st.inc_offset[a], None),  # L35123
            "V.A.ADDORG": (lambda st, i, a: st.inc_offset[a], None),         # L35159
            "V.A.FIX": (lambda st, i, a: st.fixture_table.get(st.fixture, {}).get(a, 0.0)
                        if st.fixture else 0.0, None),                        # L35384
            "V.A.ORGT[]": (lambda st, i, a: _entry(st.origin_table, i[0], 1, "V.A.ORGT", 99).get(a, 0.0),
                           lambda st, i, a, v: _entry(st.origin_table, i[0], 1, "V.A.ORGT", 99).__setitem__(a, v)),
            "V.A.FIXT[]": (lambda st, i, a: _entry(st.fixture_table, i[0], 1, "V.A.FIXT", 10).get(a, 0.0),
                           lambda st, i, a, v: _entry(st.fixture_table, i[0], 1, "V.A.FIXT", 10).__setitem__(a, v)),
            "V.A.LOLIM": (lambda st, i, a: st.lower_limits[a], None),
            "V.A.UPLIM": (lambda st, i, a: st.upper_limits[a], None),
        }
        # the manual also writes the fixture table V.G.FIXT[n].X (L2126, spec 01 §18.8)
        self.axis_vars["V.G.FIXT[]"] = self.axis_vars["V.A.FIXT[]"]
        self.plain_vars: dict[str, tuple[Callable[[tuple], float], Callable[[tuple, float], None] | None]] = {
            "V.G.FIX": (lambda i: float(s.fixture), self._set_fix),          # L35373
            "V.G.TOOL": (lambda i: float(s.tool), None),                     # L37501
            "V.G.NXTOOL": (lambda i: float(s.next_tool), None),
            "V.G.TOD": (lambda i: float(s.offset), None),
            "V.G.PRGF": (lambda i: s.feed_programmed or 0.0, None),
            "V.G.FEED": (lambda i: s.feed_programmed or 0.0, None),
            "V.G.PRGS": (lambda i: s.speeds.get(s.machine.spindles[0], 0.0) if s.machine.spindles else 0.0, None),
            "V.G.BLKSKIP": (lambda i: 1.0 if s.block_skip else 0.0, None),
            "V.G.NUMORG": (lambda i: 99.0, None),
            "V.G.FORG": (lambda i: 1.0, None),
            "V.G.NUMFIX": (lambda i: 10.0, None),
            "V.G.FFIX": (lambda i: 1.0, None),
            "V.G.PORGF": (lambda i: s.polar_origin[0], None),                # L40519
            "V.G.PORGS": (lambda i: s.polar_origin[1], None),
            "V.G.BLKN": (lambda i: float(s.line), None),
        }
        for group, label in (("motion", "GMOTION"), ("plane", "PLANE"), ("units", "UNITS")):
            self.plain_vars[f"V.G.{label}"] = (lambda i, g=group: float(s.modes[g] or 0), None)

    # ------------------------------------------------------------------
    def _set_fix(self, index: tuple, value: float) -> None:
        n = int(value)
        if n != value or not 0 <= n <= 10:
            raise InterpError("INT045", f"V.G.FIX = {value:g}: the fixture number must be 0..10", 1)
        self.state.fixture = n

    def _axis(self, token: str, col: int) -> str:
        axes = self.state.axes
        if token in axes:
            return token
        if token.isdigit() and 1 <= int(token) <= len(axes):
            return axes[int(token) - 1]
        raise InterpError("INT046", f"axis {token} does not exist in this channel", col)

    def _resolve(self, name: str, index: tuple, col: int):
        if name.startswith("V.[]."):
            if index and index[0] != 1:
                raise InterpError("INT047", f"channel {index[0]:g} does not exist (one channel offline)", col)
            name, index = "V." + name[5:], index[1:]
        if name.startswith(("V.P.", "V.S.")):
            return ("user", name, index)
        if name in self.plain_vars:
            return ("plain", name, index)
        head, _, tail = name.rpartition(".")
        if head in self.axis_vars and tail:
            return ("axis", head, (index, self._axis(tail, col)))
        raise InterpError("INT044", f"unknown variable {name.replace('[]', '[..]')}", col)

    def get(self, name: str, index: tuple, col: int = 1) -> float:
        kind, key, extra = self._resolve(name, index, col)
        if kind == "user":
            try:
                return self.state.user_vars[key]
            except KeyError:
                raise InterpError("INT043", f"variable {key} has no value yet (use EXIST[{key}])", col) from None
        if kind == "plain":
            return self.plain_vars[key][0](extra)
        idx, axis = extra
        try:
            return self.axis_vars[key][0](self.state, tuple(int(x) for x in idx), axis)
        except InterpError as exc:
            exc.col = col
            raise

    def set(self, name: str, index: tuple, value: float, col: int = 1) -> None:
        kind, key, extra = self._resolve(name, index, col)
        if kind == "user":
            self.state.user_vars[key] = value
            return
        if kind == "plain":
            setter = self.plain_vars[key][1]
            if setter is None:
                raise InterpError("INT048", f"{key} is read-only", col)
            setter(extra, value)
            return
        idx, axis = extra
        setter = self.axis_vars[key][1]
        if setter is None:
            raise InterpError("INT048", f"{key}.{axis} is read-only", col)
        setter(self.state, tuple(int(x) for x in idx), axis, value)

    def exists(self, name: str, index: tuple) -> bool:
        try:
            kind, key, _ = self._resolve(name, index, 1)
        except InterpError:
            return False
        return key in self.state.user_vars if kind == "user" else True

    def delete(self, name: str, index: tuple, col: int) -> None:
        """#DELETE of a user variable (seed 002 L1839-L1845)."""
        kind, key, _ = self._resolve(name, index, col)
        if kind != "user":
            raise InterpError("INT049", f"#DELETE only deletes user variables V.P.. and V.S.., not {key}", col)
        self.state.user_vars.pop(key, None)
