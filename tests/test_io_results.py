"""mobman.io.results: results holding NumPy/JAX arrays turned into strict JSON."""

from __future__ import annotations

import json
import math

import jax.numpy as jnp
import numpy as np
import pytest

from mobman.io.results import dump_json, to_jsonable


def _strict(text: str) -> object:
    """``json.loads`` that refuses the NaN/Infinity tokens JSON does not have."""

    def refuse(token: str) -> None:
        raise AssertionError(f"non-standard JSON token {token}")

    return json.loads(text, parse_constant=refuse)


def test_numpy_arrays_become_nested_lists_of_python_numbers():
    value = to_jsonable(np.array([[1.5, -2.0], [0.0, 3.25]]))
    assert value == [[1.5, -2.0], [0.0, 3.25]]
    assert type(value) is list and type(value[0]) is list and type(value[0][0]) is float


def test_integer_and_boolean_arrays_keep_their_kind():
    assert to_jsonable(np.arange(3)) == [0, 1, 2]
    assert all(type(v) is int for v in to_jsonable(np.arange(3)))
    assert to_jsonable(np.array([True, False])) == [True, False]
    assert all(type(v) is bool for v in to_jsonable(np.array([True, False])))


def test_jax_arrays_become_nested_lists():
    value = to_jsonable(jnp.array([[1.0, 2.0], [3.0, 4.5]]))
    assert value == [[1.0, 2.0], [3.0, 4.5]]
    assert type(value) is list and type(value[1][1]) is float


@pytest.mark.parametrize(
    ("scalar", "expected", "kind"),
    [
        (np.float64(0.25), 0.25, float),
        (np.float32(0.5), 0.5, float),
        (np.int64(7), 7, int),
        (np.bool_(True), True, bool),
        (np.array(2.5), 2.5, float),
        (jnp.float64(1.25), 1.25, float),
    ],
    ids=["float64", "float32", "int64", "bool", "zero-d-array", "jax-scalar"],
)
def test_numpy_and_jax_scalars_become_python_scalars(scalar: object, expected: object, kind: type):
    value = to_jsonable(scalar)
    assert value == expected and type(value) is kind


def test_nested_containers_are_converted_throughout():
    value = to_jsonable({"a": (1, np.array([2.0, 3.0])), 4: [{"b": np.int64(5)}, ("x", None)]})
    assert value == {"a": [1, [2.0, 3.0]], "4": [{"b": 5}, ["x", None]]}
    assert type(value["a"]) is list and type(value["4"][1]) is list


def test_keys_become_strings():
    assert to_jsonable({1: "one", 2.5: "x", None: 0}) == {"1": "one", "2.5": "x", "None": 0}


@pytest.mark.parametrize("bad", [math.nan, math.inf, -math.inf], ids=["nan", "inf", "-inf"])
def test_non_finite_floats_become_none(bad: float):
    assert to_jsonable(bad) is None
    assert to_jsonable(np.float64(bad)) is None
    assert to_jsonable([1.0, bad]) == [1.0, None]
    assert to_jsonable(np.array([[1.0, bad]])) == [[1.0, None]]
    assert to_jsonable(jnp.array([bad, 2.0])) == [None, 2.0]
    assert to_jsonable({"x": (bad,)}) == {"x": [None]}


def test_plain_values_pass_unchanged():
    for value in ("text", 3, -0.5, True, None, ""):
        assert to_jsonable(value) == value and type(to_jsonable(value)) is type(value)


def test_the_input_is_not_modified():
    data = {"q": [1.0, math.nan], "t": (0.0, 1.0)}
    to_jsonable(data)
    assert data["t"] == (0.0, 1.0) and math.isnan(data["q"][1])


def test_dump_json_is_strict_json_that_reads_back():
    data = {
        "t": np.linspace(0.0, 1.0, 3),
        "q": jnp.array([[0.1, 0.2], [0.3, np.nan]]),
        "steps": np.int64(3),
        "names": ("x", "y"),
        "error": np.inf,
    }
    assert _strict(dump_json(data)) == {
        "t": [0.0, 0.5, 1.0],
        "q": [[0.1, 0.2], [0.3, None]],
        "steps": 3,
        "names": ["x", "y"],
        "error": None,
    }


def test_dump_json_keeps_floats_exactly():
    values = np.array([0.1, 1 / 3, math.pi, 1e-300, -123456.789012345678])
    read = _strict(dump_json({"v": values}))["v"]
    assert np.array_equal(np.array(read), values)


def test_dump_json_is_indented_by_two_spaces():
    assert dump_json({"a": [1]}) == '{\n  "a": [\n    1\n  ]\n}'
