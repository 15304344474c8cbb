"""Numbers typed by a user (mobman.io.numbers): a whitelisted arithmetic grammar, never code."""

from __future__ import annotations

import ast
import math
from pathlib import Path

import numpy as np
import pytest

from mobman.errors import InputError
from mobman.io.numbers import MAX_MAGNITUDE, parse_number, parse_vector

PACKAGE = Path(__file__).resolve().parents[1] / "src" / "mobman"


@pytest.mark.parametrize(
    ("text", "value"),
    [
        ("0.5", 0.5),
        (" -1e-3 ", -1e-3),
        ("pi", math.pi),
        ("pi/2", math.pi / 2),
        ("-pi/4", -math.pi / 4),
        ("2*pi/3", 2 * math.pi / 3),
        ("-(0.5 + 0.25) * 2", -1.5),
        ("+3 - -2", 5.0),
        ("1_000", 1000.0),
    ],
)
def test_numbers_and_expressions_are_read(text, value):
    assert parse_number(text, "f") == value


@pytest.mark.parametrize(
    ("text", "needle"),
    [
        ("10**10**10", "not a number"),
        ("2**3", "not a number"),
        ("().__class__", "not a number"),
        ("__import__('os')", "not a number"),
        ("abs(1)", "not a number"),
        ("x", "not a number"),
        ("'1'", "not a number"),
        ("True", "not a number"),
        ("1j", "not a number"),
        ("[1]", "not a number"),
        ("1 if 1 else 2", "not a number"),
        ("7 // 2", "not a number"),
        ("7 % 2", "not a number"),
        ("1/0", "divides by zero"),
        ("nan", "finite"),
        ("-inf", "finite"),
        ("1e308", "finite"),
        (f"{MAX_MAGNITUDE} * 10", "finite"),
        ("9" * 400, "longer than"),
        ("-" * 30 + "1", "nested deeper"),
        ("", "empty"),
    ],
)
def test_anything_else_is_refused_naming_the_field(text, needle):
    with pytest.raises(InputError, match=needle) as info:
        parse_number(text, "--q")
    assert str(info.value).startswith("--q:")


def test_vectors_refuse_empty_items_and_wrong_sizes():
    np.testing.assert_array_equal(parse_vector("0, pi; 1", "--q"), [0.0, math.pi, 1.0])
    for text in ("0,,0", "0,0,", ",0", "", "  "):
        with pytest.raises(InputError, match="--q: .*(empty|no values)"):
            parse_vector(text, "--q")
    with pytest.raises(InputError, match="expected 3 values, got 2"):
        parse_vector("1,2", "--q", 3)


def test_the_escape_payload_is_refused():
    with pytest.raises(InputError, match="^--q: .* is not a number"):
        parse_vector("0,0,0,0.3,().__class__.__base__.__subclasses__()", "--q")


def _builtin_calls(tree: ast.AST, names: set[str]):
    for node in ast.walk(tree):
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id in names:
            yield node.func.id, node.lineno


def test_the_package_never_evaluates_text():
    """No builtin ``eval``/``exec``/``compile`` call in the package (a method such as ``lowered.compile()``
    is not the builtin)."""
    found = []
    for path in sorted(PACKAGE.rglob("*.py")):
        tree = ast.parse(path.read_text(encoding="utf-8"))
        found += [
            f"{path.relative_to(PACKAGE)}:{line} {name}("
            for name, line in _builtin_calls(tree, {"eval", "exec", "compile", "__import__"})
        ]
    assert not found, found


def test_no_module_below_the_command_line_imports_it():
    """Number parsing lives in mobman.io: the library (control specs, robot files …) never imports mobman.cli."""
    offenders = []
    for path in sorted(PACKAGE.rglob("*.py")):
        if path.relative_to(PACKAGE).parts[0] == "cli":
            continue
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            names = [a.name for a in node.names] if isinstance(node, ast.Import) else []
            if isinstance(node, ast.ImportFrom) and node.module:
                names = [node.module]
            offenders += [
                f"{path.relative_to(PACKAGE)}: {n}" for n in names if n.split(".")[:2] == ["mobman", "cli"]
            ]
    assert not offenders, offenders
