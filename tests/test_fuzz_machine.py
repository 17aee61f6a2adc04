"""Fuzzing the machine configuration: random values of every type for every key, as a dict and as a
TOML file.  No exception but :class:`MachineError` (naming the key) escapes :func:`load_machine`,
and :func:`fagorcnc.simulate`, :func:`fagorcnc.dry_run` and ``fagorcnc check`` answer with a
diagnostic (CFG001) or a verdict, never a traceback (issue 30 item 2).  Budgets come from the
Hypothesis profile (``tests/conftest.py``); the ``fagorcnc check`` property runs a tenth of them."""

from __future__ import annotations

import math

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import fagorcnc
from fagorcnc.cli import main
from fagorcnc.config.machine import Axis, Limits, MachineError, PlannerConfig, ToolOffset, load_machine

PROGRAM = "G0 X10 Y5\nG1 X20 F1000\nG2 X30 Y5 I5 J0\nT1 D1 M6\nP100 = P100 + 1\nM30\n"

#: Every key of the machine file, as a path of table names.
KEYS: list[tuple] = (
    [("axes",), ("axes", "X"), ("axes", "Q"), ("axes", "X1")]
    + [("axes", "X", f) for f in Axis.__dataclass_fields__ if f != "name"]
    + [("axes", "C", f) for f in ("type", "rotary_mode", "direction", "module")]
    + [(k,) for k in ("spindles", "defaults", "local_params", "global_params", "common_params", "origins",
                      "fixtures", "tools", "max_feed", "rapid_feed", "servo_period", "cirinerr", "cirinfact",
                      "subroutine_paths", "oem_subroutines", "m_functions", "limits", "planner", "backends",
                      "parameter_file")]
    + [("defaults", k) for k in ("INCHES", "IPLANE", "ICORNER", "NOSUCH")]
    + [("origins", k) for k in ("G54", "G159.7", "7", "G159.x", "0", "100")]
    + [("origins", "G54", "X"), ("fixtures", "1"), ("fixtures", "1", "X"), ("fixtures", "11")]
    + [("tools", "1"), ("tools", "1", "1"), ("tools", "a"), ("tools", "1", "b")]
    + [("tools", "1", "1", f) for f in ToolOffset.__dataclass_fields__]
    + [("oem_subroutines", "180"), ("oem_subroutines", "x"), ("m_functions", "8"), ("m_functions", "x")]
    + [("limits", f) for f in Limits.__dataclass_fields__]
    + [("planner", f) for f in PlannerConfig.__dataclass_fields__]
    + [("backends", "interpcnc")]
)

scalars = st.one_of(
    st.booleans(), st.integers(), st.integers(-3, 3), st.sampled_from([0, 1, -1, 2**63, 10**400 // 10**300]),
    st.floats(), st.sampled_from([math.nan, math.inf, -math.inf, 0.0, -0.0, 1e-320, 1e308]),
    st.text(max_size=8), st.sampled_from(["", "X", "linear", "rotary", "before", "after", "S", "/dev/zero", "\0"]),
)
values = st.recursive(scalars, lambda children: st.one_of(
    st.lists(children, max_size=3), st.dictionaries(st.text(max_size=3) | st.sampled_from(["X", "1", "G54"]),
                                                    children, max_size=3)), max_leaves=6)
dict_values = st.one_of(values, st.none())


def _set(machine: dict, path: tuple, value) -> dict:
    table = machine
    for key in path[:-1]:
        nxt = table.get(key)
        if not isinstance(nxt, dict):
            nxt = table[key] = {}
        table = nxt
    table[path[-1]] = value
    return machine


@st.composite
def machine_dicts(draw, value_strategy=dict_values):
    machine: dict = {}
    path = draw(st.sampled_from(KEYS))
    _set(machine, path, draw(value_strategy))
    for _ in range(draw(st.integers(0, 2))):   # sometimes a few more keys, valid or not
        _set(machine, draw(st.sampled_from(KEYS)), draw(value_strategy))
    return machine, path


def _check_loads(machine, path) -> bool:
    """load_machine returns a Machine or raises MachineError naming the key; True when it loaded."""
    try:
        load_machine(machine)
        return True
    except MachineError as exc:
        text = str(exc)
        assert text and "Traceback" not in text
        return False


@settings(suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
@given(machine_dicts())
def test_random_machine_dicts(case):
    machine, path = case
    loaded = _check_loads(machine, path)
    for result in (fagorcnc.simulate(PROGRAM, machine), fagorcnc.dry_run(PROGRAM, machine)):
        if not loaded:
            assert [d.code for d in result.diagnostics] == ["CFG001"]
        assert all(d.line >= 1 and d.col >= 1 for d in result.diagnostics)


def _toml(value) -> str:
    """A TOML value (inline tables and arrays); TOML has no null."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value) if abs(value) < 2**63 else _toml(float(value) if abs(value) < 1e308 else math.inf)
    if isinstance(value, float):
        return "nan" if math.isnan(value) else ("inf" if value > 0 else "-inf") if math.isinf(value) else repr(value)
    if isinstance(value, str):
        return '"' + "".join(c if c.isprintable() and c not in '"\\' else f"\\u{ord(c):04x}" for c in value) + '"'
    if isinstance(value, list):
        return "[" + ", ".join(_toml(v) for v in value) + "]"
    return "{" + ", ".join(f"{_toml(str(k))} = {_toml(v)}" for k, v in value.items()) + "}"


def toml_text(machine: dict) -> str:
    return "".join(f"{_toml(str(k))} = {_toml(v)}\n" for k, v in machine.items())


@settings(max_examples=max(10, settings.default.max_examples // 10),
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large, HealthCheck.function_scoped_fixture])
@given(machine_dicts(values))
def test_random_machine_files_through_fagorcnc_check(tmp_path, capsys, case):
    machine, _path = case
    m = tmp_path / "m.toml"
    m.write_text(toml_text(machine), encoding="utf-8")
    p = tmp_path / "p.nc"
    p.write_text(PROGRAM)
    try:
        load_machine(m)
    except MachineError as exc:
        assert str(exc).startswith(str(m))
    assert main(["check", str(p), "--machine", str(m)]) in (0, 1, 2)
    out = capsys.readouterr()
    assert "Traceback" not in out.out + out.err and "internal error" not in out.out + out.err
