"""Every public function and method of the package has type hints on its parameters and its return
(CONTRIBUTING.md, "Types"); ``python -m mypy`` checks them. Read from the source with ``ast``: nothing is
imported."""

from __future__ import annotations

import ast
from pathlib import Path

PACKAGE = Path(__file__).resolve().parents[1] / "src" / "mobman"


def _public(name: str) -> bool:
    return not name.startswith("_") or (name.startswith("__") and name.endswith("__"))


def unannotated(source: str) -> list[str]:
    """``name: what is missing`` for each public function or method of ``source`` (module-level functions and
    the methods of public classes, nested classes included) without a hint on a parameter or its return."""
    found = []

    def visit(node: ast.AST, prefix: str) -> None:
        for child in ast.iter_child_nodes(node):
            if isinstance(child, ast.ClassDef) and not child.name.startswith("_"):
                visit(child, f"{prefix}{child.name}.")
            elif isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef)) and _public(child.name):
                args = child.args
                params = [*args.posonlyargs, *args.args, *args.kwonlyargs]
                if prefix and params and params[0].arg in ("self", "cls"):
                    params = params[1:]
                missing = [a.arg for a in params if a.annotation is None]
                missing += [f"*{a.arg}" for a in (args.vararg,) if a is not None and a.annotation is None]
                missing += [f"**{a.arg}" for a in (args.kwarg,) if a is not None and a.annotation is None]
                if child.returns is None and child.name != "__init__":
                    missing.append("return")
                if missing:
                    found.append(f"{prefix}{child.name}: {', '.join(missing)}")

    visit(ast.parse(source), "")
    return found


def test_every_public_function_and_method_has_type_hints():
    missing = [
        f"{path.relative_to(PACKAGE.parent)}: {entry}"
        for path in sorted(PACKAGE.rglob("*.py"))
        for entry in unannotated(path.read_text(encoding="utf-8"))
    ]
    assert not missing, "public functions without type hints:\n" + "\n".join(missing)


def test_the_check_finds_a_missing_hint_and_skips_private_names():
    source = (
        "def f(x, y: int) -> int: ...\n"
        "def g(x: int): ...\n"
        "def _h(x): ...\n"
        "class A:\n"
        "    def __init__(self, n): ...\n"
        "    def m(self, *a, **k) -> None: ...\n"
        "    def _p(self, x): ...\n"
        "class _B:\n"
        "    def m(self, x): ...\n"
        "def ok(x: int, *a: int, **k: str) -> None: ...\n"
    )
    assert unannotated(source) == ["f: x", "g: return", "A.__init__: n", "A.m: *a, **k"]
