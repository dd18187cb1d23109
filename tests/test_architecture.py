"""The house's structure: configuration on the ground floor, a pure core, no import cycles."""

import ast
import subprocess
import sys
from pathlib import Path

import pytest

from gbh_drake import REPO_ROOT

PACKAGE = REPO_ROOT / "gbh_drake"
#: Configuration modules: they may import Drake's config structs, never the pipeline.
CONFIG_MODULES = ("gbh_drake.scenario", "gbh_drake.scenario.schema", "gbh_drake.core.ranges",
                  "gbh_drake.yamlfiles.layers", "gbh_drake.core.params", "gbh_drake.core.pick_config",
                  "gbh_drake.perception.config", "gbh_drake.modeling.names",
                  "gbh_drake.modeling.directives", "gbh_drake.modeling.object_config",
                  "gbh_drake.seeds")
#: Modules that import no Drake at all (the core's rules, the station's names).
DRAKE_FREE = ("gbh_drake.core.ranges", "gbh_drake.core.params", "gbh_drake.core.pick_config",
              "gbh_drake.modeling.names")
#: What the configuration must not pull in.
PIPELINE = ("gbh_drake.perception.", "gbh_drake.planning", "gbh_drake.systems",
            "gbh_drake.station", "gbh_drake.trial", "gbh_drake.run", "gbh_drake.experiment",
            "gbh_drake.core.hangability", "gbh_drake.core.grasp_synthesis",
            "gbh_drake.core.antipodal", "gbh_drake.core.object_model")


def _module_name(path: Path) -> str:
    parts = path.relative_to(REPO_ROOT).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _imports(path: Path) -> set[str]:
    """gbh_drake modules imported by the module at ``path`` (top level and in functions)."""
    found = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            names = [node.module] + [f"{node.module}.{a.name}" for a in node.names]
        elif isinstance(node, ast.Import):
            names = [a.name for a in node.names]
        else:
            continue
        found |= {n for n in names if n.startswith("gbh_drake")}
    return found


def _graph() -> dict[str, set[str]]:
    modules = {_module_name(p): p for p in PACKAGE.rglob("*.py")}
    return {m: {i for i in _imports(p) if i in modules and i != m} for m, p in modules.items()}


@pytest.mark.parametrize("module", CONFIG_MODULES)
def test_configuration_imports_nothing_of_the_pipeline(module):
    """Loading a configuration module (in a fresh interpreter) loads no pipeline module."""
    code = (f"import sys, {module}; "
            "print('\\n'.join(m for m in sys.modules if m.startswith('gbh_drake')))")
    loaded = subprocess.run([sys.executable, "-c", code], check=True, capture_output=True,
                            text=True, cwd=REPO_ROOT).stdout.split()
    pulled = [m for m in loaded if m.startswith(PIPELINE) and m != "gbh_drake.perception.config"]
    assert pulled == [], f"{module} pulls in {pulled}"


@pytest.mark.parametrize("module", DRAKE_FREE)
def test_rules_and_names_import_no_drake(module):
    code = f"import sys, {module}; print(any(m.startswith('pydrake') for m in sys.modules))"
    loaded = subprocess.run([sys.executable, "-c", code], check=True, capture_output=True,
                            text=True, cwd=REPO_ROOT).stdout.strip()
    assert loaded == "False", f"{module} imports pydrake"


def test_no_module_imports_one_that_imports_it_back():
    graph = _graph()
    cycles = []

    def visit(node, stack, on_stack, done):
        on_stack.add(node)
        stack.append(node)
        for nxt in sorted(graph[node]):
            if nxt in on_stack:
                cycles.append(stack[stack.index(nxt):] + [nxt])
            elif nxt not in done:
                visit(nxt, stack, on_stack, done)
        stack.pop()
        on_stack.discard(node)
        done.add(node)

    done: set[str] = set()
    for module in sorted(graph):
        if module not in done:
            visit(module, [], set(), done)
    # A package's __init__ re-exporting its submodules is not a cycle of concern.
    cycles = [c for c in cycles if not any(c[i + 1].startswith(c[i] + ".")
                                           for i in range(len(c) - 1))]
    assert cycles == []


def test_the_core_is_pure():
    """gbh_drake.core is numpy/trimesh/open3d only: no pydrake, no other gbh_drake package."""
    for path in (PACKAGE / "core").rglob("*.py"):
        tree = ast.parse(path.read_text())
        for node in ast.walk(tree):
            names = [a.name for a in node.names] if isinstance(node, ast.Import) else \
                [node.module] if isinstance(node, ast.ImportFrom) and node.module else []
            for name in names:
                assert not name.startswith("pydrake"), f"{path.name} imports {name}"
                if name.startswith("gbh_drake"):
                    assert name.startswith("gbh_drake.core"), f"{path.name} imports {name}"


def _room(module: str) -> str:
    """The room (sub-package or top-level module) a module lives in."""
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else parts[0]


def test_no_room_imports_a_room_that_imports_it_back():
    """Rooms (sub-packages and top-level modules) import downward only: configuration
    (scenario, with the ground-floor configs of core, modeling, perception) below modeling and
    perception, those below planning and systems, those below the trial and the experiment."""
    rooms: dict[str, set[str]] = {}
    for module, imported in _graph().items():
        for other in imported:
            if _room(module) != _room(other) and "gbh_drake" not in (module, other):
                rooms.setdefault(_room(module), set()).add(_room(other))
    both_ways = sorted({tuple(sorted((a, b))) for a, bs in rooms.items() for b in bs
                        if a in rooms.get(b, set())})
    assert both_ways == []
