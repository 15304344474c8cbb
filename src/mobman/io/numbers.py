"""Numbers typed by a user: a float literal or a small arithmetic expression, never code.

A value such as ``pi/2`` or ``-(0.5 + 0.25) * 2`` is read by walking Python's syntax tree with a whitelist:
float and integer literals, the name ``pi``, the binary operators ``+ - * /``, unary ``+ -`` and parentheses.
Anything else (names, calls, attributes, ``**``, subscripts, strings) is refused, and the text length, the
nesting depth and the magnitude of every intermediate value are bounded, so that no input can run code or
take long to read.
"""

from __future__ import annotations

import ast
import math
import operator
from collections.abc import Callable

import numpy as np

from mobman.errors import InputError

MAX_MAGNITUDE = 1e6
"""Largest accepted |value| of a number read from the command line or a file (lengths in m, masses in kg,
torques in N·m, angles in rad, times in s …): larger values are input mistakes, not robots."""

MAX_TOKEN_LENGTH = 100
"""Longest accepted text of one number."""

MAX_DEPTH = 20
"""Deepest accepted nesting of an expression's syntax tree."""

MAX_TEXT_LENGTH = 100_000
"""Longest accepted text of a whole vector."""

_BINARY: dict[type[ast.operator], Callable[[float, float], float]] = {
    ast.Add: operator.add,
    ast.Sub: operator.sub,
    ast.Mult: operator.mul,
    ast.Div: operator.truediv,
}
_UNARY: dict[type[ast.unaryop], Callable[[float], float]] = {ast.UAdd: operator.pos, ast.USub: operator.neg}
_NAMES = {"pi": math.pi}
GRAMMAR = "a number or an expression of numbers and pi with + - * / and parentheses"


def _bounded(value: float, field: str, token: str) -> float:
    if not math.isfinite(value) or abs(value) > MAX_MAGNITUDE:
        raise InputError(f"{field}: {token!r} must be finite with |value| ≤ {MAX_MAGNITUDE:g}")
    return value


def _evaluate(node: ast.AST, field: str, token: str, depth: int) -> float:
    if depth > MAX_DEPTH:
        raise InputError(f"{field}: {token!r} is nested deeper than {MAX_DEPTH} levels")
    if (
        isinstance(node, ast.Constant)
        and isinstance(node.value, (int, float))
        and not isinstance(node.value, bool)
    ):
        try:
            return _bounded(float(node.value), field, token)
        except OverflowError:
            raise InputError(f"{field}: {token!r} must be finite with |value| ≤ {MAX_MAGNITUDE:g}") from None
    if isinstance(node, ast.Name) and node.id in _NAMES:
        return _NAMES[node.id]
    if isinstance(node, ast.UnaryOp) and type(node.op) in _UNARY:
        return _UNARY[type(node.op)](_evaluate(node.operand, field, token, depth + 1))
    if isinstance(node, ast.BinOp) and type(node.op) in _BINARY:
        left = _evaluate(node.left, field, token, depth + 1)
        right = _evaluate(node.right, field, token, depth + 1)
        if isinstance(node.op, ast.Div) and right == 0.0:
            raise InputError(f"{field}: {token!r} divides by zero")
        return _bounded(_BINARY[type(node.op)](left, right), field, token)
    raise InputError(f"{field}: {token!r} is not {GRAMMAR}")


def parse_number(token: str, field: str) -> float:
    """One number: a float literal (``0.5``, ``1e-3``) or an expression such as ``pi/4`` or ``-(1 + 2) / 3``.

    Raises InputError naming ``field`` for anything else, for a non-finite value or one beyond
    :data:`MAX_MAGNITUDE`.
    """
    token = token.strip()
    if not token:
        raise InputError(f"{field}: empty value (expected {GRAMMAR})")
    if len(token) > MAX_TOKEN_LENGTH:
        raise InputError(f"{field}: {token[:20]!r}… is longer than {MAX_TOKEN_LENGTH} characters")
    try:
        literal = float(token)
    except ValueError:
        literal = None
    if literal is not None:
        return _bounded(literal, field, token)
    try:
        tree = ast.parse(token, mode="eval")
    except (SyntaxError, ValueError, MemoryError, RecursionError):
        raise InputError(f"{field}: {token!r} is not {GRAMMAR}") from None
    return _evaluate(tree.body, field, token, 0)


def parse_vector(text: str, field: str, size: int | None = None) -> np.ndarray:
    """``"0.1, 0.2, pi/2"`` → array: comma- (or semicolon-) separated numbers of :func:`parse_number`.

    An empty item (``"0,,1"``) is an error, and so is a count other than ``size`` when it is given.
    """
    if len(text) > MAX_TEXT_LENGTH:
        raise InputError(f"{field}: longer than {MAX_TEXT_LENGTH} characters")
    tokens = text.replace(";", ",").split(",")
    if len(tokens) == 1 and not tokens[0].strip():
        raise InputError(f"{field}: no values (expected comma-separated numbers)")
    values = []
    for i, token in enumerate(tokens):
        if not token.strip():
            raise InputError(f"{field}: value {i + 1} is empty (expected comma-separated numbers)")
        values.append(parse_number(token, field))
    arr = np.asarray(values, dtype=float)
    if size is not None and arr.size != size:
        raise InputError(f"{field}: expected {size} values, got {arr.size}")
    return arr


__all__ = ["GRAMMAR", "MAX_MAGNITUDE", "parse_number", "parse_vector"]
