"""Helpers of the canned-cycle tests: move lists in the notation of spec 09 §0.2."""

from __future__ import annotations

import fagorcnc


def _n(v: float) -> str:
    s = f"{round(v, 4):.4f}".rstrip("0").rstrip(".")
    return "0" if s in ("-0", "") else s


def notation(record) -> str:
    """``R(x,y,z)``, ``F(x,y,z)@f``, ``CW(x,y,z; cx,cy)@f``, ``DWELL(t)``, ``M3`` (part coordinates, G17)."""
    k = record.kind
    if k in ("rapid", "linear"):
        e = record.end_part
        point = f"({_n(e['X'])},{_n(e['Y'])},{_n(e['Z'])})"
        return f"R{point}" if k == "rapid" else f"F{point}@{_n(record.feed)}"
    if k == "arc":
        e, c = record.end_part, record.center_part
        a, o = record.plane[0], record.plane[1]
        return (f"{record.direction.upper()}({_n(e['X'])},{_n(e['Y'])},{_n(e['Z'])}; {_n(c[a])},{_n(c[o])})"
                f"@{_n(record.feed)}")
    if k == "dwell":
        return f"DWELL({_n(record.seconds)})"
    return f"{record.function}{_n(record.value)}"


def run(program: str, machine=None):
    return fagorcnc.simulate(program, machine=machine)


def moves(program: str, lines, machine=None, ok: bool = True) -> list[str]:
    """The records of the given source lines (an int or a collection), in the spec's notation."""
    result = run(program, machine)
    if ok:
        assert result.ok, [str(d) for d in result.diagnostics]
    wanted = {lines} if isinstance(lines, int) else set(lines)
    return [notation(r) for r in result.moves if r.line in wanted]


def split(text: str) -> list[str]:
    """A move list written as in the spec: moves separated by spaces (``CW(..; ..)`` kept whole)."""
    return text.replace("; ", ";").split() and [m.replace(";", "; ") for m in text.replace("; ", ";").split()]


def codes(program: str, machine=None) -> list[tuple[int, str]]:
    """(line, code) of every diagnostic of the run."""
    return [(d.line, d.code) for d in run(program, machine).diagnostics]


def channel(result):
    """The interpreter's channel state behind ``result.state`` (the canned-cycle state is not public API)."""
    return result.state._state
