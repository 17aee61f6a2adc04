"""Regression tests of issue 30 (an attack campaign): each reproducer ends in a diagnostic or a clean,
bounded error, never a traceback, a hang or a silently wrong result.  One test (or group) per item."""

from __future__ import annotations

import os

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


def test_a_two_axis_lathe_runs_its_arcs_in_g18():
    # seed 002 L3013-L3043: a lathe of X and Z always works in G18, Z the abscissa and X the ordinate;
    # G151: X10 is a diameter (radius 5), X20 radius 10; the arc ends at Z0, X radius 10
    r = fagorcnc.simulate("G18 G151 G1 X10 Z5 F100\nG2 X20 Z0 R10\nM30\n", LATHE)
    assert r.ok, [str(d) for d in r.diagnostics]
    arc = next(m for m in r.moves if m.kind == "arc")
    assert (round(arc.end["X"], 9), round(arc.end["Z"], 9)) == (10.0, 0.0)


@pytest.mark.parametrize(("machine", "text", "line"), [
    ({"axes": {"X": {}}}, "G2 X10 I5\nM30\n", 1),                      # G17 needs X and Y
    ({"axes": {"Z": {}}}, "G18 G1 Z10 F100\nG3 Z0 R5\nM30\n", 2),      # G18 needs Z (3rd) and X (1st)
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


# ---------------------------------------------------------------- items 5, 6, 7, 11: the subroutine file lookup
@pytest.fixture
def dirs(tmp_path):
    subs = tmp_path / "subs"
    subs.mkdir()
    (subs / "OK.nc").write_text("P100 = 1\nM17\n")
    prog = tmp_path / "prog"
    (prog / "deep").mkdir(parents=True)
    (prog / "deep" / "NEST.nc").write_text("P100 = 2\nM17\n")
    (subs / "deep").mkdir()
    (subs / "deep" / "INSUBS.nc").write_text("P100 = 3\nM17\n")
    return {"subroutine_paths": [str(subs)]}, subs, prog


def run_in(prog, machine, text: str):
    main_file = prog / "main.nc"
    main_file.write_text("P100 = 0\n" + text)
    return fagorcnc.simulate(main_file, machine), fagorcnc.dry_run(main_file, machine)


def test_item5_subroutine_name_too_long_is_int151(dirs):
    machine, _subs, prog = dirs
    for r in run_in(prog, machine, "L " + "A" * 300 + ".nc\nM30\n"):
        assert codes(r) == ["INT151"] and "too long" in r.diagnostics[0].message


def test_item5_path_sentence_too_long_is_int151(dirs):
    machine, _subs, prog = dirs
    for r in run_in(prog, machine, '#PATH ["' + "a" * 10000 + '"]\nL OK.nc\nM30\n'):   # under the line limit
        assert codes(r) == ["INT151"]
    for r in run_in(prog, machine, '#PATH ["' + "a" * 200000 + '"]\nL OK.nc\nM30\n'):  # 200 kB: over it
        assert codes(r) == ["SYN041"]


@pytest.mark.skipif(not hasattr(os, "symlink"), reason="no symbolic links on this system")
def test_item6_symlink_loop_is_int151(dirs):
    machine, subs, prog = dirs
    (subs / "L1.nc").symlink_to(subs / "L2.nc")
    (subs / "L2.nc").symlink_to(subs / "L1.nc")
    for r in run_in(prog, machine, "L L1.nc\nM30\n"):
        assert codes(r) == ["INT151"] and "loop of symbolic links" in r.diagnostics[0].message


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no FIFOs on this system")
def test_a_fifo_or_device_is_not_opened(dirs):
    machine, subs, prog = dirs
    os.mkfifo(subs / "PIPE.nc")   # opening it would block for ever
    for r in run_in(prog, machine, "L PIPE.nc\nM30\n"):
        assert codes(r) == ["INT151"] and "not a regular file" in r.diagnostics[0].message


@pytest.mark.parametrize("size", ["small", "large"])
def test_item7_unreadable_subroutine_is_int151(dirs, monkeypatch, size):
    """Always runs (the sandbox is root, for whom mode 000 is readable): open() of the file raises
    PermissionError as it would for a non-root user; both the parsed and the streamed reading."""
    import builtins

    machine, subs, prog = dirs
    body = "P100 = 3\n" + ("G0 X1\n" * 60000 if size == "large" else "") + "M17\n"
    (subs / "SECRET.nc").write_text(body)
    real_open = builtins.open

    def guarded(file, *args, **kwargs):
        if str(file).endswith("SECRET.nc"):
            raise PermissionError(13, "Permission denied", str(file))
        return real_open(file, *args, **kwargs)

    monkeypatch.setattr(builtins, "open", guarded)
    for r in run_in(prog, machine, "L SECRET.nc\nM30\n"):
        assert codes(r) == ["INT151"] and "permission denied" in r.diagnostics[0].message


@pytest.mark.skipif(not hasattr(os, "geteuid") or os.geteuid() == 0, reason="root reads a mode-000 file")
def test_item7_mode_000_as_a_user(dirs):
    machine, subs, prog = dirs
    (subs / "LOCKED.nc").write_text("P100 = 3\nM17\n")
    (subs / "LOCKED.nc").chmod(0)
    for r in run_in(prog, machine, "L LOCKED.nc\nM30\n"):
        assert codes(r) == ["INT151"]


def test_item11_relative_directory_resolves_in_the_search_directories(dirs, monkeypatch, tmp_path):
    machine, _subs, prog = dirs
    elsewhere = tmp_path / "cwd"
    (elsewhere / "deep").mkdir(parents=True)
    (elsewhere / "deep" / "NEST.nc").write_text("P100 = 666\nM17\n")
    monkeypatch.chdir(elsewhere)   # the working directory must play no part
    simulated, dry = run_in(prog, machine, "L deep/NEST.nc\nM30\n")
    assert simulated.ok and dry.ok and simulated.state.param(100) == 2   # the program's own directory
    simulated, dry = run_in(prog, machine, "L deep/INSUBS.nc\nM30\n")
    assert simulated.ok and dry.ok and simulated.state.param(100) == 3   # a subroutine_paths directory
    simulated, _ = run_in(prog, machine, '#PATH ["deep"]\nL NEST.nc\nM30\n')   # a relative #PATH, the same way
    assert simulated.ok and simulated.state.param(100) == 2


def test_lookup_order_is_path_then_program_directory_then_subpath(dirs):
    # seed 002 L10327-L10333: 1 #PATH, 2 the program's directory, 3 SUBPATH
    machine, subs, prog = dirs
    (prog / "TWICE.nc").write_text("P100 = 20\nM17\n")
    (subs / "TWICE.nc").write_text("P100 = 30\nM17\n")
    (subs / "deep" / "TWICE.nc").write_text("P100 = 40\nM17\n")
    assert run_in(prog, machine, "L TWICE.nc\nM30\n")[0].state.param(100) == 20
    assert run_in(prog, machine, f'#PATH ["{subs / "deep"}"]\nL TWICE.nc\nM30\n')[0].state.param(100) == 40


# ---------------------------------------------------------------- item 9: large subroutine files stream
def test_item9_large_subroutine_file_is_streamed(dirs, monkeypatch):
    from fagorcnc.interp import files
    from fagorcnc.interp.files import PARSE_WHOLE_BYTES

    streamed = []

    def stream_program(lines, file, compat=None):
        program, source = real_stream_program(lines, file, compat)
        streamed.append(source)
        return program, source

    real_stream_program = files.stream_program
    monkeypatch.setattr(files, "stream_program", stream_program)
    machine, subs, prog = dirs
    lines = ["P100 = P100 + 1", "P101 = 0"] + ["P101 = P101 + 1 ; a block of the subroutine, padded to 64 c."] * 5500
    lines += ["G1 X[P100 * 10] F1000", "M17"]
    (subs / "BIG.nc").write_text("\n".join(lines) + "\n")
    assert (subs / "BIG.nc").stat().st_size > PARSE_WHOLE_BYTES
    main_file = prog / "main.nc"
    main_file.write_text("P100 = 0\nL BIG.nc\nL BIG.nc\nM30\n")
    run = fagorcnc.interpret(main_file, machine)
    moves = [r.end["X"] for r in run if r.kind == "linear"]
    assert run.ok and moves == [10.0, 20.0] and run.state.param(101) == 5500   # called twice
    assert len(streamed) == 2 and all(s.released > 4000 for s in streamed)   # read twice, blocks dropped
    assert not run.interpreter.files._parsed and not run.interpreter.files._open   # nothing kept, files closed
    dry = fagorcnc.dry_run(main_file, machine)
    assert dry.ok and dry.moves == 2


# ---------------------------------------------------------------- item 10: the parameter file
@pytest.mark.parametrize("name", ["/dev/zero", "directory", "fifo"])
def test_item10_parameter_file_that_is_not_a_regular_file_is_cfg002(tmp_path, name):
    if name == "directory":
        name = str(tmp_path)
    elif name == "fifo":
        if not hasattr(os, "mkfifo"):
            pytest.skip("no FIFOs on this system")
        os.mkfifo(tmp_path / "params.var")   # opening it would block for ever
        name = str(tmp_path / "params.var")
    elif not os.path.exists(name):
        pytest.skip("no /dev/zero on this system")
    machine = {"parameter_file": name}
    for r in (fagorcnc.simulate("G0 X1\nM30\n", machine), fagorcnc.dry_run("G0 X1\nM30\n", machine)):
        assert codes(r) == ["CFG002"] and "not a regular file" in r.diagnostics[0].message


def test_item10_parameter_file_too_large_is_cfg002(tmp_path):
    from fagorcnc.config.parameter_file import MAX_PARAMETER_FILE_BYTES

    big = tmp_path / "params.var"
    with open(big, "w") as f:
        f.write("; padding\n" * (MAX_PARAMETER_FILE_BYTES // 10 + 1))   # a comment is 10 bytes: one over the cap
    assert big.stat().st_size > MAX_PARAMETER_FILE_BYTES
    r = fagorcnc.simulate("G0 X1\nM30\n", {"parameter_file": str(big)})
    assert codes(r) == ["CFG002"] and str(MAX_PARAMETER_FILE_BYTES) in r.diagnostics[0].message
    big.write_text("100\t2.5\n")   # a normal one is still read
    r = fagorcnc.simulate("P1 = P100\nM30\n", {"parameter_file": str(big)})
    assert r.ok and r.state.param(1) == 2.5


# ---------------------------------------------------------------- item 12: HSC, a one-block G60 corner, G50, HSC again
def test_item12_hsc_g60_g50_hsc_plans():
    text = ("G90 G17 G71 G94 G01 X0 Y0 F2000\n#HSC ON [CONTERROR 0.01, CORNER 150]\nX40\nG60 X45 Y1\nG50\n"
            "#HSC ON [FAST, CORNER 130]\nG01 Y40\nM30\n")
    r = fagorcnc.simulate(text)
    assert r.ok and r.cycle_time > 0
    # G60 stops at the end of its own block (seed 002 L8018): the tool is at rest at X45 Y1
    line4 = [s for s in r.segments() if s.line == 4]
    assert line4 and line4[-1].v1 == 0.0
    assert fagorcnc.dry_run(text).cycle_time == pytest.approx(r.cycle_time, rel=1e-12)


# ---------------------------------------------------------------- item 15: the rapid override
def test_item15_rapid_override_0_is_an_error_like_the_feed_override():
    # seed 002 L20355: whatever RAPIDOVR says, the override's 0 % position holds the axes, G00 too
    for r in (fagorcnc.simulate("G0 X100\nM30\n", {"planner": {"rapid_override": 0}}),
              fagorcnc.dry_run("G0 X100\nM30\n", {"planner": {"rapid_override": 0}})):
        assert codes(r) == ["PLN001"] and "rapid override is 0 %" in r.diagnostics[0].message
    assert fagorcnc.simulate("G1 X100 F1000\nM30\n", {"planner": {"rapid_override": 0}}).ok   # no rapid: runs


def test_item15_rapid_override_scales_the_axes_rapid_on_the_default_machine():
    def cycle(override, **extra):
        return fagorcnc.simulate("G0 X100\nM30\n", {"planner": {"rapid_override": override}, **extra}).cycle_time

    full = cycle(100)
    # X's max_velocity 10000 mm/min; 1 % of it is 100 mm/min = 1.6667 mm/s: 100 mm take 60 s, plus the
    # ramps (a = 1000 mm/s², j = 20000 mm/s³ reach 1.67 mm/s in about 0.02 s)
    assert 60.0 < cycle(1) < 60.1
    # 50 %: 83.33 mm/s, 100 mm in 1.2 s at speed, plus the ramps; strictly slower than 100 %
    assert full < cycle(50) < full + 1.2 and cycle(50) > 1.2
    # with a channel rapid of 5000 mm/min, 50 % is 2500 mm/min = 41.67 mm/s: 2.4 s at speed, plus the ramps
    assert 2.4 < cycle(50, rapid_feed=5000.0) < 2.6
    # a diagonal: u = (0.6, 0.8), Y reaches 166.67 mm/s first at 208.3 mm/s; 10 % is 20.83 mm/s: 100 mm in 4.8 s
    diagonal = fagorcnc.simulate("G0 X60 Y80\nM30\n", {"planner": {"rapid_override": 10}}).cycle_time
    assert 4.8 < diagonal < 4.9
