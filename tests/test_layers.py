"""The package's imports respect its layers (CONTRIBUTING.md): read from the source with ``ast``, nothing is
imported. Every import counts, also those inside functions.

    cli → experiments → studies → control, planning, dynamics → manipulability, redundancy, symbolic → collision → kinematics → model

with errors, checks and the engine below everything; ``io`` imports only model, errors, checks and the engine and is imported
by cli, experiments, control, planning and dynamics; ``viz`` is imported only by cli and experiments.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "src" / "mobman"

LAYERS = {
    "mobman.errors": 0,
    "mobman.checks": 0,
    "mobman.engine": 0,
    "mobman.integration": 0,
    "mobman": 1,  # the package itself re-exports the errors and the model
    "mobman.model": 1,
    "mobman.kinematics": 2,
    "mobman.collision": 2.5,  # distances: above the kinematics, below the analysis
    "mobman.manipulability": 3,
    "mobman.redundancy": 3,
    "mobman.symbolic": 3,
    "mobman.control": 4,
    "mobman.planning": 4,
    "mobman.dynamics": 4,
    "mobman.viz": 4,
    "mobman.io": 4,
    "mobman.studies": 5,
    "mobman.physics": 5,
    "mobman.experiments": 6,
    "mobman.cli": 7,
}
IO_MAY_IMPORT = ("mobman.io", "mobman.model", "mobman.errors", "mobman.checks", "mobman.engine")
IO_IMPORTED_BY = (
    "mobman.io",
    "mobman.cli",
    "mobman.experiments",
    "mobman.control",
    "mobman.planning",
    "mobman.dynamics",
    "mobman.viz",  # the viewer reads saved trajectories
)
VIZ_IMPORTED_BY = ("mobman.viz", "mobman.cli", "mobman.experiments")
FACADE_REGISTERS = "mobman.io.real_robots"
"""The one module the package itself imports above its layer: importing it registers the real robots."""


def _modules() -> dict[str, Path]:
    modules = {}
    for path in sorted(PACKAGE.rglob("*.py")):
        parts = list(path.relative_to(PACKAGE.parent).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts.pop()
        modules[".".join(parts)] = path
    return modules


MODULES = _modules()


def _type_only(tree: ast.AST) -> set[int]:
    """ids of the import statements under ``if TYPE_CHECKING:`` (never executed)."""
    ids = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.If) and "TYPE_CHECKING" in ast.unparse(node.test):
            ids |= {id(n) for statement in node.body for n in ast.walk(statement)}
    return ids


def _imports(module: str, path: Path, runtime_only: bool = False) -> list[tuple[str, str, int]]:
    """(imported module, imported name or "", line) for every import of a mobman module in ``path``, also
    inside functions (with ``runtime_only``, not those under ``if TYPE_CHECKING:``); an imported name that is
    itself a module counts as that module."""
    found = []
    package = module.split(".") if path.name == "__init__.py" else module.split(".")[:-1]
    tree = ast.parse(path.read_text(), str(path))
    skipped = _type_only(tree) if runtime_only else set()
    for node in ast.walk(tree):
        if id(node) in skipped:
            continue
        if isinstance(node, ast.Import):
            found += [
                (alias.name, "", node.lineno) for alias in node.names if alias.name.split(".")[0] == "mobman"
            ]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                base = ".".join(
                    package[: len(package) - node.level + 1] + ([node.module] if node.module else [])
                )
            if base.split(".")[0] != "mobman":
                continue
            for alias in node.names:
                sub = f"{base}.{alias.name}"
                found.append((sub, "", node.lineno) if sub in MODULES else (base, alias.name, node.lineno))
    return found


def _attribute_uses(path: Path) -> list[tuple[str, str, int]]:
    """(module, attribute, line) for ``alias.attr`` where ``alias`` names an imported mobman module."""
    tree = ast.parse(path.read_text(), str(path))
    aliases = {}
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for a in node.names:
                if a.name.split(".")[0] == "mobman" and a.asname:
                    aliases[a.asname] = a.name
        elif isinstance(node, ast.ImportFrom) and (node.module or "").split(".")[0] == "mobman":
            for a in node.names:
                if f"{node.module}.{a.name}" in MODULES:
                    aliases[a.asname or a.name] = f"{node.module}.{a.name}"
    return [
        (aliases[node.value.id], node.attr, node.lineno)
        for node in ast.walk(tree)
        if isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name) and node.value.id in aliases
    ]


GRAPH = {module: _imports(module, path) for module, path in MODULES.items()}


def _group(module: str) -> str:
    """The longest prefix of ``module`` in LAYERS."""
    parts = module.split(".")
    while ".".join(parts) not in LAYERS:
        parts.pop()
    return ".".join(parts)


def _within(module: str, prefixes: tuple[str, ...]) -> bool:
    return any(module == p or module.startswith(p + ".") for p in prefixes)


def test_every_module_has_a_layer():
    assert all(_group(m) in LAYERS for m in MODULES)


def test_no_module_imports_a_higher_layer():
    violations = []
    for module, imports in GRAPH.items():
        for target, _, line in imports:
            here, there = _group(module), _group(target)
            if module == "mobman" and target == FACADE_REGISTERS:
                continue
            if _within(target, ("mobman.io",)) and not _within(module, IO_IMPORTED_BY):
                violations.append(
                    f"{module}:{line} imports {target} (io is imported by {', '.join(IO_IMPORTED_BY)})"
                )
            elif _within(module, ("mobman.io",)) and not _within(target, IO_MAY_IMPORT):
                violations.append(
                    f"{module}:{line} imports {target} (io imports only {', '.join(IO_MAY_IMPORT)})"
                )
            elif _within(target, ("mobman.viz",)) and not _within(module, VIZ_IMPORTED_BY):
                violations.append(
                    f"{module}:{line} imports {target} (viz is imported by cli and experiments)"
                )
            elif LAYERS[there] > LAYERS[here]:
                violations.append(f"{module}:{line} imports the higher layer {target}")
    assert not violations, "\n".join(violations)


def test_no_private_name_is_imported_from_another_module():
    """No ``from m import _x`` and no ``m._x`` across modules; a private module (``control/_tree.py``) may be
    imported by the modules of its own package."""
    violations = []
    for module, path in MODULES.items():
        uses = [(t, n, line) for t, n, line in GRAPH[module] if n] + _attribute_uses(path)
        for target, name, line in uses:
            if name.startswith("_") and not name.startswith("__") and target != module:
                violations.append(f"{module}:{line} uses {target}.{name}")
        for target, _, line in GRAPH[module]:
            private = [i for i, part in enumerate(target.split(".")) if part.startswith("_")]
            if private and not module.startswith(".".join(target.split(".")[: private[0]]) + "."):
                violations.append(f"{module}:{line} imports the private module {target}")
    assert not violations, "\n".join(violations)


def _cycles() -> list[list[str]]:
    """Strongly connected components of more than one module (Tarjan), each sorted."""
    runtime = {m: _imports(m, path, runtime_only=True) for m, path in MODULES.items()}
    edges = {m: sorted({t for t, _, _ in runtime[m] if t in MODULES and t != m}) for m in MODULES}
    index, low, stack, on_stack, components, counter = {}, {}, [], set(), [], [0]

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on_stack.add(v)
        for w in edges[v]:
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
                components.append(sorted(component))

    for v in MODULES:
        if v not in index:
            visit(v)
    return components


def test_no_import_cycles():
    """No cycle of imports that run, at module level or inside functions. Imports under ``if TYPE_CHECKING:``
    (annotations only, never executed) do not count here; they do count for the layers and private names. A
    package's ``__init__`` re-exporting its modules is a cycle only if one of them imports the package back."""
    assert not _cycles(), "\n".join(" ↔ ".join(c) for c in _cycles())


@pytest.mark.parametrize(
    ("source", "expected"),
    [
        ("from mobman.cli.common import parse_vector", ("mobman.cli.common", "parse_vector")),
        ("from mobman.kinematics import _q", ("mobman.kinematics", "_q")),
        ("from . import spatial", ("mobman.model.spatial", "")),
        ("def f():\n    from mobman.io import robot_file", ("mobman.io.robot_file", "")),
    ],
)
def test_imports_are_resolved(source, expected, tmp_path):
    """The reader resolves absolute, named and relative imports (checked on small sources)."""
    path = tmp_path / "m.py"
    path.write_text(source + "\n")
    module = "mobman.model.m"
    assert _imports(module, path)[0][:2] == expected


def test_type_only_imports_are_left_out_of_the_cycle_graph(tmp_path):
    path = tmp_path / "m.py"
    path.write_text(
        "from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    from mobman.model.robot import Frames\n"
    )
    assert _imports("mobman.model.m", path)[0][:2] == ("mobman.model.robot", "Frames")
    assert _imports("mobman.model.m", path, runtime_only=True) == []
