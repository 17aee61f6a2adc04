"""The package's layering, as the README's architecture section documents it.

Every ``import`` in every module of ``fagorcnc`` is read (function-level ones too: a lazy import
is still a dependency), resolved to a module of the package, and checked against the rules:

* no import circle between modules;
* ``syntax/`` imports no other stage (only the diagnostics);
* no pipeline stage (syntax, interp, path, plan, backends, config, kinematics) imports the user's
  commands (``commands/``, ``cli``), the PLC service (``plc/``) or the public facade;
* ``config/`` imports no pipeline stage; ``config/linuxcnc`` does not import ``config/machine``
  (the machine loader imports the INI reader, never the other way round);
* ``backends/base.py`` imports no back-end implementation (the registry is ``backends/registry.py``);
* ``path/`` uses of the interpreter are limited to its record types (``interp/records``), the
  vocabulary of the record stream.
"""

from __future__ import annotations

import ast
from pathlib import Path

PACKAGE = Path(__file__).resolve().parents[1] / "fagorcnc"

#: The pipeline stages, in the order data flows (each a sub-package).
STAGES = ("syntax", "interp", "path", "plan", "backends", "config", "kinematics")
#: What sits above the pipeline: the user's commands, the PLC service, the public facade.
ABOVE = ("commands", "plc", "cli", "simulate", "__main__", "<api>")


def _modules() -> dict[str, Path]:
    found = {}
    for file in PACKAGE.rglob("*.py"):
        parts = list(file.relative_to(PACKAGE.parent).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts = parts[:-1]
        found[".".join(parts)] = file
    return found


def _imports(modules: dict[str, Path]) -> dict[str, set[str]]:
    """module -> the package modules it imports."""
    graph: dict[str, set[str]] = {}
    for name, file in modules.items():
        package = name.split(".") if file.name == "__init__.py" else name.split(".")[:-1]
        found: set[str] = set()
        for node in ast.walk(ast.parse(file.read_text(encoding="utf-8"))):
            if isinstance(node, ast.ImportFrom):
                if node.level:
                    base = package[: len(package) - (node.level - 1)] + ([node.module] if node.module else [])
                    base_name = ".".join(base)
                else:
                    base_name = node.module or ""
                for alias in node.names:
                    candidate = f"{base_name}.{alias.name}"
                    found.add(candidate if candidate in modules else base_name)
            elif isinstance(node, ast.Import):
                found.update(alias.name for alias in node.names)
        graph[name] = {m for m in found if m in modules and m != name}
    return graph


MODULES = _modules()
GRAPH = _imports(MODULES)


def _stage(module: str) -> str:
    parts = module.split(".")
    return "<api>" if len(parts) == 1 else parts[1]


def _edges(src_stages, dst_stages):
    return sorted((m, t) for m, targets in GRAPH.items() for t in targets
                  if _stage(m) in src_stages and _stage(t) in dst_stages)


def test_the_package_has_no_import_circle():
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    circles: list[list[str]] = []
    counter = 0

    def visit(v: str) -> None:   # Tarjan's strongly connected components
        nonlocal counter
        index[v] = low[v] = counter
        counter += 1
        stack.append(v)
        on_stack.add(v)
        for w in GRAPH[v]:
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                circles.append(sorted(component))

    for module in sorted(GRAPH):
        if module not in index:
            visit(module)
    assert circles == []


def test_syntax_imports_no_other_stage():
    allowed = {"syntax", "diagnostics"}
    assert [(m, t) for m, t in _edges({"syntax"}, set(STAGES) | set(ABOVE) | {"runtime"})
            if _stage(t) not in allowed] == []


def test_no_pipeline_stage_imports_the_commands_the_plc_or_the_facade():
    assert _edges(set(STAGES), set(ABOVE)) == []


def test_configuration_imports_no_pipeline_stage():
    assert _edges({"config"}, set(STAGES) - {"config"}) == []
    assert "fagorcnc.config.machine" not in GRAPH["fagorcnc.config.linuxcnc"]
    assert "fagorcnc.config.linuxcnc" in GRAPH["fagorcnc.config.machine"]


def test_the_backend_protocol_imports_no_implementation():
    base = GRAPH["fagorcnc.backends.base"]
    assert not {m for m in base if m.startswith(("fagorcnc.backends.sim", "fagorcnc.backends.interpcnc",
                                                    "fagorcnc.backends.registry"))}
    assert {"fagorcnc.backends.sim", "fagorcnc.backends.interpcnc"} <= GRAPH["fagorcnc.backends.registry"]


def test_path_uses_only_the_interpreters_record_types():
    assert [(m, t) for m, t in _edges({"path"}, {"interp"}) if t != "fagorcnc.interp.records"] == []


def test_each_command_has_its_module_and_the_old_import_paths_still_work():
    for command in ("run", "check", "plot", "parse", "emulate"):
        assert f"fagorcnc.commands.{command}" in MODULES
    from fagorcnc import Machine, dry_run, interpret, simulate  # noqa: F401
    from fagorcnc.backends import SimulatorBackend, get_backend  # noqa: F401
    from fagorcnc.backends.interpcnc import InterpCncBackend  # noqa: F401
    from fagorcnc.machine import Machine as OldMachine
    from fagorcnc.machine import MachineError, load_machine
    from fagorcnc.plan import Planner  # noqa: F401

    assert OldMachine is Machine
    assert isinstance(load_machine(None), Machine)
    assert issubclass(MachineError, ValueError)
