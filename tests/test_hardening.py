"""Regression tests of issue 30 (an attack campaign): each reproducer ends in a diagnostic or a clean,
bounded error, never a traceback, a hang or a silently wrong result.  One test (or group) per item."""

from __future__ import annotations

import pytest

import fagorcnc
from fagorcnc.cli import main
from fagorcnc.config.machine import MachineError, load_machine


def codes(result) -> list[str]:
    return [d.code for d in result.diagnostics if d.is_error]


# ---------------------------------------------------------------- item 1: machines without the plane's axes
ROTARY_ONLY = {"axes": {"A": {"type": "rotary"}}}
LATHE = {"axes": {"X": {"diameter": True}, "Z": {}}}


def test_rotary_only_machine_runs_its_moves():
    r = fagorcnc.simulate("G0 A10\nG1 A20 F1000\nM30\n", ROTARY_ONLY)
    assert r.ok, [str(d) for d in r.diagnostics]
    moves = [(m.kind, m.end) for m in r.moves if m.kind != "aux"]   # M30 is an aux record
    assert moves == [("rapid", {"A": 10.0}), ("linear", {"A": 20.0})]
    assert r.cycle_time > 0


def test_lathe_runs_linear_moves_in_diameter():
    # G151: X is programmed as a diameter, so X10 is the radius 5 (seed 002 L2599)
    r = fagorcnc.simulate("G18 G151 G1 X10 Z5 F100\nM30\n", LATHE)
    assert r.ok, [str(d) for d in r.diagnostics]
    assert r.moves[0].end == {"X": 5.0, "Z": 5.0}


@pytest.mark.parametrize(("machine", "text", "line"), [
    ({"axes": {"X": {}}}, "G2 X10 I5\nM30\n", 1),                      # G17 needs X and Y
    ({"axes": {"Z": {}}}, "G18 G1 Z10 F100\nG3 Z0 R5\nM30\n", 2),      # G18 needs Z (3rd) and X (1st)
    (LATHE, "G18 G151 G1 X10 Z5 F100\nG2 X20 Z0 R10\nM30\n", 2),       # with two axes Z is not the 3rd
    (ROTARY_ONLY, "G0 A10\nG30 I0 J0\nM30\n", 2),                      # polar origin
    (ROTARY_ONLY, "G41 G1 A20 F1000\nM30\n", 1),                       # radius compensation
    ({"axes": {"X": {}}}, "G1 X10 Q10 F1000\nM30\n", 1),               # polar move
    ({"axes": {"X": {}}}, "G1 X10 F100\nG36 I2\nG1 X20\nM30\n", 2),    # corner aid
    ({"axes": {"X": {}}}, "G73 Q30\nM30\n", 1),                        # rotation
])
def test_moves_that_need_a_missing_plane_axis_are_refused(machine, text, line):
    for result in (fagorcnc.simulate(text, machine), fagorcnc.dry_run(text, machine)):
        errors = [d for d in result.diagnostics if d.is_error]
        assert [d.code for d in errors] == ["INT150"], [str(d) for d in result.diagnostics]
        assert errors[0].line == line and errors[0].col >= 1


# ---------------------------------------------------------------- item 2: machine values of the wrong type
WRONG_TYPES = [
    ({"axes": ["X"]}, "axes"), ({"axes": None}, "axes"), ({"axes": 3}, "axes"),
    ({"axes": {"x": {}}}, "axes.x"), ({"axes": {"X": 5}}, "axes.X"),
    ({"axes": {"X": {"direction": "abc"}}}, "axes.X.direction"),
    ({"axes": {"X": {"diameter": "yes"}}}, "axes.X.diameter"), ({"axes": {"X": {"type": 1}}}, "axes.X.type"),
    ({"tools": 5}, "tools"), ({"tools": "x"}, "tools"), ({"tools": {"a": {"1": {}}}}, "tools.a"),
    ({"tools": {"1": {"1": 5}}}, "tools.1.1"), ({"tools": {"1": {"b": {}}}}, "tools.1.b"),
    ({"origins": []}, "origins"), ({"origins": {"G159.x": {}}}, "origins.G159.x"),
    ({"origins": {"G54": 3}}, "origins.G54"), ({"fixtures": {"a": {}}}, "fixtures.a"),
    ({"local_params": 5}, "local_params"), ({"local_params": ["a", "b"]}, "local_params"),
    ({"local_params": [0, 1, 2]}, "local_params"), ({"global_params": [100.5, 200]}, "global_params"),
    ({"spindles": 5}, "spindles"), ({"spindles": ["S", 3]}, "spindles"),
    ({"subroutine_paths": 5}, "subroutine_paths"), ({"subroutine_paths": [None]}, "subroutine_paths"),
    ({"oem_subroutines": 5}, "oem_subroutines"), ({"oem_subroutines": {"x": "a.nc"}}, "oem_subroutines.x"),
    ({"oem_subroutines": {"180": 5}}, "oem_subroutines.180"),
    ({"m_functions": 5}, "m_functions"), ({"m_functions": {"x": "after"}}, "m_functions.x"),
    ({"defaults": 5}, "defaults"), ({"defaults": {"INCHES": "0"}}, "defaults.INCHES"),
]


@pytest.mark.parametrize(("machine", "key"), WRONG_TYPES, ids=[repr(m) for m, _ in WRONG_TYPES])
def test_wrong_types_are_cfg001_naming_the_key(machine, key):
    with pytest.raises(MachineError) as err:
        load_machine(machine)
    assert key in str(err.value)
    for result in (fagorcnc.simulate("G1 X1 F100\nM30\n", machine), fagorcnc.dry_run("G1 X1 F100\nM30\n", machine)):
        assert codes(result) == ["CFG001"] and key in result.diagnostics[0].message


TOML_WRONG_TYPES = [
    ('axes = ["X"]\n', "axes"), ("axes = 3\n", "axes"), ('[axes.X]\ndirection = "abc"\n', "axes.X.direction"),
    ("tools = 5\n", "tools"), ('tools = "x"\n', "tools"), ("[tools.a.1]\nlength = 1.0\n", "tools.a"),
    ("[tools.1]\n1 = 5\n", "tools.1.1"), ("origins = []\n", "origins"), ('[origins."G159.x"]\nX = 1.0\n', "G159.x"),
    ("[fixtures.a]\nX = 1.0\n", "fixtures.a"), ("local_params = 5\n", "local_params"),
    ('local_params = ["a", "b"]\n', "local_params"), ("local_params = [0, 1, 2]\n", "local_params"),
    ("spindles = 5\n", "spindles"), ("subroutine_paths = 5\n", "subroutine_paths"),
    ("oem_subroutines = 5\n", "oem_subroutines"), ('[oem_subroutines]\nx = "a.nc"\n', "oem_subroutines.x"),
    ("m_functions = 5\n", "m_functions"), ('[m_functions]\nx = "after"\n', "m_functions.x"),
    ("defaults = 5\n", "defaults"),
]


@pytest.mark.parametrize(("body", "key"), TOML_WRONG_TYPES, ids=[b for b, _ in TOML_WRONG_TYPES])
def test_wrong_types_in_toml_name_the_key_and_the_file(tmp_path, capsys, body, key):
    machine = tmp_path / "m.toml"
    machine.write_text(body)
    program = tmp_path / "p.nc"
    program.write_text("G1 X1 F100\nM30\n")
    with pytest.raises(MachineError) as err:
        load_machine(machine)
    assert str(err.value).startswith(f"{machine}: ") and key in str(err.value)
    assert main(["check", str(program), "--machine", str(machine)]) in (1, 2)
    out = capsys.readouterr()
    assert "Traceback" not in out.out + out.err and "CRASHED" not in out.out + out.err
    assert key in out.out + out.err


# ---------------------------------------------------------------- item 3: expressions nested too deeply
DEEP = {
    "sum": "P1 = 1" + "+1" * 988,
    "sin": "P1 = " + "SIN[" * 988 + "1" + "]" * 988,
    "param-index": "P1 = " + "P[" * 495 + "1" + "]" * 495,
    "minus": "P1 = " + "-[" * 600 + "P2" + "]" * 600,   # -[-[1]] is folded into a number, -[P2] is not
    "bracket-list": "#HSC ON [" + "1,[" * 400 + "]" * 400 + "]",
}


@pytest.mark.parametrize("line", list(DEEP.values()), ids=list(DEEP))
def test_deep_expressions_are_syn040_from_parse_and_simulate(line):
    text = line + "\nM30\n"
    program = fagorcnc.parse_text(text)
    assert [d.code for d in program.diagnostics] == ["SYN040"] and program.diagnostics[0].line == 1
    for result in (fagorcnc.simulate(text), fagorcnc.dry_run(text)):
        assert codes(result) == ["SYN040"]


def test_expressions_up_to_the_depth_limit_are_computed():
    from fagorcnc.syntax.parser import MAX_EXPRESSION_DEPTH

    n = MAX_EXPRESSION_DEPTH
    # 1 + 1 + ... (n additions) = n + 1; P[P[...P[1]...]] with P1 = 1 is 1 at any depth
    assert fagorcnc.simulate("P1 = 1" + "+1" * n + "\nM30\n").state.param(1) == n + 1
    nested = "P1 = 1\nP2 = " + "P[" * (n - 1) + "1" + "]" * (n - 1) + "\nM30\n"
    assert fagorcnc.dry_run(nested).ok and fagorcnc.simulate(nested).state.param(2) == 1
    assert codes(fagorcnc.simulate("P1 = 1" + "+1" * (n + 1) + "\nM30\n")) == ["SYN040"]


# ---------------------------------------------------------------- item 8: a line of unbounded length
def _long_line_file(path, megabytes: int, newline_after: bool = True):
    with open(path, "w") as f:
        f.write("G1 X1 F100\n")
        chunk = "X" * (1 << 20)
        for _ in range(megabytes):
            f.write(chunk)
        if newline_after:
            f.write("\nG1 X[1\nM30\n")   # line 3: another syntax error, found after the resynchronisation
    return path


def test_overlong_line_is_syn041_in_constant_memory(tmp_path, capsys):
    import tracemalloc

    from fagorcnc.syntax.reader import MAX_LINE_LENGTH

    program = _long_line_file(tmp_path / "long.nc", 24)   # 24 MiB in one line
    tracemalloc.start()
    try:
        result = fagorcnc.dry_run(program)
        _, peak = tracemalloc.get_traced_memory()
        assert [(d.code, d.line) for d in result.diagnostics if d.is_error] == [("SYN041", 2), ("SYN003", 3)]
        assert str(24 << 20) in result.diagnostics[0].message and str(MAX_LINE_LENGTH) in result.diagnostics[0].message
        tracemalloc.reset_peak()
        assert main(["check", str(program)]) == 1
        _, peak_check = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert peak < 8e6 and peak_check < 8e6, (peak, peak_check)   # the line alone is 24 MiB (50 MB as str)
    assert "SYN041" in capsys.readouterr().out
    assert codes(fagorcnc.simulate(program))[:1] == ["SYN041"]


def test_file_without_any_newline(tmp_path):
    program = tmp_path / "one.nc"
    program.write_text("G1 X1 " * 5000)   # 30 000 characters, no line end
    assert codes(fagorcnc.dry_run(program)) == ["SYN041"]


@pytest.mark.parametrize("length", [16384, 16385])
def test_line_length_limit_is_exact(length):
    # "G0 X1" + a comment filling the line up to `length` characters
    line = "G0 X1 ;" + "c" * (length - 7)
    assert len(line) == length
    result = fagorcnc.dry_run(line + "\nM30\n")
    assert codes(result) == ([] if length <= 16384 else ["SYN041"])
