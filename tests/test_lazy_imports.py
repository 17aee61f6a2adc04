"""What ``fagorcnc check`` imports (issue 27: the start-up of every check process).

The modules a check of a plain program never runs are imported on first use: the back-ends and
``run`` behind ``fagorcnc.run`` (PEP 562 in ``fagorcnc/__init__.py``), the trajectory sampler, the
canned-cycle families (:class:`fagorcnc._lazy.LazyModule`), the kinematics statements, the
parallel checker's process pool ...  Each test runs a fresh interpreter, so what an earlier test
imported does not count; none measures time.  The public names stay where they were.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from fagorcnc import _lazy

ROOT = Path(__file__).resolve().parents[1]

#: Modules (and their packages' prefixes) a check of a plain program does not load.
NOT_FOR_A_PLAIN_CHECK = (
    "fagorcnc.commands.run", "fagorcnc.backends", "fagorcnc.plc", "pymodbus", "importlib.metadata", "email",
    "fagorcnc.plan.trajectory", "fagorcnc.interp.movestore", "fagorcnc.kinematics.statements",
    "fagorcnc.kinematics.caxis", "fagorcnc.interp.vcatalogue", "fagorcnc.interp.cycles.drilling",
    "fagorcnc.interp.cycles.milling", "fagorcnc.interp.cycles.patterns", "fagorcnc.interp.cycles.pockets",
    "fagorcnc.interp.cycles.threads", "fagorcnc.interp.independent", "fagorcnc.config.mpcatalogue",
    "fagorcnc.path.spline", "fagorcnc.path.clearance", "fagorcnc.path.proximity", "tomllib",
    "concurrent.futures.process", "multiprocessing", "xml.etree",
)
#: ... and what the ``fagorcnc check`` command does not load either.
NOT_FOR_THE_CHECK_COMMAND = (*NOT_FOR_A_PLAIN_CHECK, "fagorcnc.commands.plot", "fagorcnc.commands.plot_tool",
                             "fagorcnc.commands.geometry_index", "fagorcnc.commands.parse",
                             "fagorcnc.commands.emulate")

PLAIN = "G90 G0 X0 Y0 Z5 F1000\nG1 X10 Y5 Z-1\nG2 X20 Y5 I5 J0\nG3 X10 Y5 I-5 J0\nG0 Z5\nM30\n"
CYCLE = "S1000 M3\nG00 G90 X0 Y0 Z50\nG98 G81 X10 Y20 Z2 I-15 K0.5 F200\nX30\nG80\nM30\n"
COMPENSATED = "G90 G0 X0 Y0 Z5 F1000\nT1 D1 M6\nG41 G1 X10 Y0\nX20\nX30 Y10\nG40 G1 X40\nM30\n"
SENTENCE = "G0 X0 Y0 Z0\nG1 X10 Y10 F100\n#FLUSH\nM30\n"   # the kinematics statements are asked first


def _loaded(code: str, program: str, tmp_path: Path) -> dict:
    """Run ``code`` (``PATH`` is a file holding ``program``) in a fresh interpreter of this checkout;
    its ``result`` (a dict) and the package modules then loaded."""
    path = tmp_path / "part.nc"
    path.write_text(program, encoding="utf-8")
    script = "\n".join([
        "import contextlib, io, json, sys",
        "PATH, result = sys.argv[1], {}",
        "with contextlib.redirect_stdout(io.StringIO()):",
        textwrap.indent(textwrap.dedent(code).strip("\n"), "    "),
        'print(json.dumps({"result": result, "modules": sorted(sys.modules)}))',
    ])
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    done = subprocess.run([sys.executable, "-P", "-c", script, str(path)], capture_output=True, text=True, env=env,
                          check=False, cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    return json.loads(done.stdout)


def _among(modules: list[str], names: tuple[str, ...]) -> list[str]:
    return [m for m in modules if any(m == n or m.startswith(n + ".") for n in names)]


def test_a_plain_check_does_not_load_the_lazy_modules(tmp_path):
    run = _loaded("""
        from fagorcnc.commands.check import check_file
        report = check_file(PATH)
        result["verdict"], result["moves"] = report.verdict(), report.moves
    """, PLAIN, tmp_path)
    assert run["result"] == {"verdict": "pass", "moves": 5}
    assert _among(run["modules"], NOT_FOR_A_PLAIN_CHECK) == []
    assert "fagorcnc.commands.check" in run["modules"] and "fagorcnc.plan.planner" in run["modules"]


def test_the_check_command_does_not_load_the_other_commands(tmp_path):
    run = _loaded("""
        from fagorcnc.cli import main
        result["status"] = main(["check", PATH])
    """, PLAIN, tmp_path)
    assert run["result"] == {"status": 0}
    assert _among(run["modules"], NOT_FOR_THE_CHECK_COMMAND) == []


def test_the_lazy_modules_are_loaded_when_a_program_needs_them(tmp_path):
    """The counterpart: a cycle imports its family, G41 the gouge checks, a sentence the kinematics
    statements, and ``fagorcnc.run`` the back-ends, so the lists above are not vacuous."""
    cycle = _loaded("""
        from fagorcnc.commands.check import check_file
        report = check_file(PATH)
        result["verdict"], result["moves"] = report.verdict(), report.moves
    """, CYCLE, tmp_path)
    assert cycle["result"]["verdict"] == "pass" and cycle["result"]["moves"] > 4
    assert "fagorcnc.interp.cycles.drilling" in cycle["modules"]
    compensated = _loaded("""
        from fagorcnc.commands.check import check_file
        result["verdict"] = check_file(PATH).verdict()
    """, COMPENSATED, tmp_path)
    assert compensated["result"] == {"verdict": "pass"}
    assert {"fagorcnc.path.clearance", "fagorcnc.path.proximity"} <= set(compensated["modules"])
    sentence = _loaded("""
        import fagorcnc
        result["ok"] = fagorcnc.simulate(PATH).ok
    """, SENTENCE, tmp_path)
    assert sentence["result"] == {"ok": True} and "fagorcnc.kinematics.statements" in sentence["modules"]
    ran = _loaded("""
        import fagorcnc
        result["ok"] = fagorcnc.run(PATH).ok
    """, PLAIN, tmp_path)
    assert ran["result"] == {"ok": True}
    assert {"fagorcnc.commands.run", "fagorcnc.backends.sim", "fagorcnc.backends.registry"} <= set(ran["modules"])


@pytest.mark.parametrize("package", ["fagorcnc", "fagorcnc.plan", "fagorcnc.backends"])
def test_every_public_name_resolves(package):
    """Each name of ``__all__``: an attribute, in ``dir()``, and ``from package import *`` binds it."""
    module = __import__(package, fromlist=["__all__"])
    namespace: dict = {}
    exec(f"from {package} import *", namespace)
    for name in module.__all__:
        assert getattr(module, name) is namespace[name], name
        assert name in dir(module), name


def test_the_lazy_names_are_those_of_their_modules():
    import fagorcnc.backends
    import fagorcnc.plan
    from fagorcnc.backends.registry import get_backend
    from fagorcnc.backends.sim import SimulatorBackend
    from fagorcnc.commands.run import RunReport, run
    from fagorcnc.plan.trajectory import Trajectory, sample
    from fagorcnc.simulate import simulate
    assert (fagorcnc.run, fagorcnc.RunReport, fagorcnc.simulate) == (run, RunReport, simulate)
    assert callable(fagorcnc.simulate)   # the function, though fagorcnc.simulate is also a module
    assert (fagorcnc.plan.Trajectory, fagorcnc.plan.sample) == (Trajectory, sample)
    assert (fagorcnc.backends.get_backend, fagorcnc.backends.SimulatorBackend) == (get_backend, SimulatorBackend)
    with pytest.raises(AttributeError, match="no attribute 'nothing'"):
        fagorcnc.nothing   # noqa: B018
    with pytest.raises(ImportError):
        exec("from fagorcnc.plan import nothing", {})


def test_a_lazy_module_is_its_module():
    """:class:`LazyModule` reads, writes and lists the module itself, imported on first use."""
    lazy = _lazy.LazyModule("fagorcnc.interp.cycles.pockets")
    from fagorcnc.interp.cycles import pockets

    assert lazy.SQRT2 is pockets.SQRT2 and lazy.prepare is pockets.prepare
    assert "prepare" in dir(lazy) and "pockets" in repr(lazy)
    lazy.EXTRA = 1
    assert pockets.EXTRA == 1
    del lazy.EXTRA
    assert not hasattr(pockets, "EXTRA")
    with pytest.raises(AttributeError):
        lazy.nothing   # noqa: B018
    from fagorcnc.interp.cycles import runner

    assert runner.FAMILIES[87].prepare is pockets.prepare and runner.drilling.levels is not None
