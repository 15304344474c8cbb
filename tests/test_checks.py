"""The scalar and vector parameter checks of mobman.checks (finite, positive, non_negative, vector3,
inertia_tensor): accepted values come back as floats, each rejection is a one-line ModelError naming the
owner, the field and the allowed range; and all_finite, the test of array arguments."""

from __future__ import annotations

import math

import numpy as np
import pytest

from mobman import checks
from mobman.errors import MobmanError, ModelError

BIG = 10**400  # a Python int too large for a float


def _rejects(call, *fragments: str) -> str:
    """Run ``call``, expect a one-line ModelError holding every fragment, return its message."""
    with pytest.raises(ModelError) as info:
        call()
    message = str(info.value)
    assert "\n" not in message
    for fragment in fragments:
        assert fragment in message, (fragment, message)
    assert isinstance(info.value, MobmanError) and isinstance(info.value, ValueError)
    return message


# --- finite, positive, non_negative -----------------------------------------------------------------


@pytest.mark.parametrize(
    ("value", "expected"),
    [(3, 3.0), (-2.5, -2.5), (0, 0.0), (np.float32(0.5), 0.5), (np.int64(7), 7.0), ("1.25", 1.25)],
)
def test_finite_returns_a_python_float(value, expected):
    out = checks.finite(value, "mass", "Link")
    assert type(out) is float and out == expected


@pytest.mark.parametrize(
    ("value", "allowed"),
    [
        (math.nan, "must be finite"),
        (math.inf, "must be finite"),
        (-math.inf, "must be finite"),
        (np.float64("nan"), "must be finite"),
        (True, "must be a number"),
        (False, "must be a number"),
        ("heavy", "must be a number"),
        (None, "must be a number"),
        (complex(1.0, 2.0), "must be a number"),
        ([1.0, 2.0], "must be a number"),
    ],
)
def test_finite_rejects_non_numbers_and_non_finite_values(value, allowed):
    _rejects(lambda: checks.finite(value, "mass", "Link"), "Link: mass ", allowed)


@pytest.mark.parametrize(("value", "expected"), [(1e-300, 1e-300), (2, 2.0), (np.float64(0.1), 0.1)])
def test_positive_accepts_values_above_zero(value, expected):
    out = checks.positive(value, "length", "CarLike")
    assert type(out) is float and out == expected


@pytest.mark.parametrize(
    ("value", "allowed"),
    [
        (0, "must be a finite number > 0"),
        (0.0, "must be a finite number > 0"),
        (-0.0, "must be a finite number > 0"),
        (-1e-300, "must be a finite number > 0"),
        (-3, "must be a finite number > 0"),
        (math.nan, "must be finite"),
        (math.inf, "must be finite"),
        (True, "must be a number"),
    ],
)
def test_positive_rejects_zero_negative_and_non_finite(value, allowed):
    message = _rejects(lambda: checks.positive(value, "length", "CarLike"), "CarLike: length ", allowed)
    assert repr(value) in message  # the offending value is shown


@pytest.mark.parametrize(("value", "expected"), [(0, 0.0), (-0.0, 0.0), (1e-300, 1e-300), (4.5, 4.5)])
def test_non_negative_accepts_zero_and_above(value, expected):
    out = checks.non_negative(value, "damping", "Joint")
    assert type(out) is float and out == expected


@pytest.mark.parametrize(
    ("value", "allowed"),
    [
        (-1e-300, "must be a finite number ≥ 0"),
        (-2, "must be a finite number ≥ 0"),
        (math.nan, "must be finite"),
        (-math.inf, "must be finite"),
        ("x", "must be a number"),
    ],
)
def test_non_negative_rejects_negative_and_non_finite(value, allowed):
    _rejects(lambda: checks.non_negative(value, "damping", "Joint"), "Joint: damping ", allowed)


# --- vector3 ---------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    "value", [(1, 2, 3), [1.0, 2.0, 3.0], np.array([1.0, 2.0, 3.0]), np.array([[1.0], [2.0], [3.0]])]
)
def test_vector3_returns_three_floats(value):
    out = checks.vector3(value, "com", "LinkInertial")
    assert out == (1.0, 2.0, 3.0)
    assert isinstance(out, tuple) and all(type(v) is float for v in out)


@pytest.mark.parametrize("value", [(1.0, 2.0), (1.0, 2.0, 3.0, 4.0), [[1.0, 0.0], [0.0, 1.0]], 5.0, None, ()])
def test_vector3_rejects_a_wrong_number_of_entries(value):
    _rejects(lambda: checks.vector3(value, "com", "LinkInertial"), "LinkInertial: com ", "must be 3 numbers")


@pytest.mark.parametrize(
    ("value", "field", "allowed"),
    [
        ((0.0, math.nan, 0.0), "com[1] ", "must be finite"),
        ((math.inf, 0.0, 0.0), "com[0] ", "must be finite"),
        ((0.0, 0.0, "up"), "com[2] ", "must be a number"),
        ((0.0, True, 0.0), "com[1] ", "must be a number"),
    ],
)
def test_vector3_names_the_bad_entry(value, field, allowed):
    _rejects(lambda: checks.vector3(value, "com", "LinkInertial"), f"LinkInertial: {field}", allowed)


# --- inertia_tensor --------------------------------------------------------------------------------


def test_inertia_tensor_expands_a_diagonal_row_major():
    out = checks.inertia_tensor((1.0, 2.0, 3.0), "inertia", "Body")
    assert out == (1.0, 0.0, 0.0, 0.0, 2.0, 0.0, 0.0, 0.0, 3.0)
    assert all(type(v) is float for v in out)


def test_inertia_tensor_keeps_a_full_tensor_in_row_major_order():
    tensor = [[0.02, 0.003, -0.001], [0.003, 0.015, 0.002], [-0.001, 0.002, 0.01]]
    expected = (0.02, 0.003, -0.001, 0.003, 0.015, 0.002, -0.001, 0.002, 0.01)
    assert checks.inertia_tensor(tensor, "inertia", "Body") == expected
    assert checks.inertia_tensor(expected, "inertia", "Body") == expected  # 9 numbers flat


@pytest.mark.parametrize(
    "value",
    [
        (0.0, 0.0, 0.0),  # a point mass: zero inertia is semi-definite
        ((1.0, 1.0, 0.0), (1.0, 1.0, 0.0), (0.0, 0.0, 0.0)),  # rank 1
        (1.0, 1.0, -1e-13),  # a round-off negative eigenvalue
    ],
)
def test_inertia_tensor_accepts_semi_definite_tensors(value):
    out = checks.inertia_tensor(value, "inertia", "Body")
    assert len(out) == 9


def test_inertia_tensor_tolerates_round_off_asymmetry():
    tensor = np.diag([1.0, 2.0, 3.0])
    tensor[0, 1], tensor[1, 0] = 0.1, 0.1 + 1e-15
    out = checks.inertia_tensor(tensor, "inertia", "Body")
    assert out[1] == 0.1 and out[3] == 0.1 + 1e-15


@pytest.mark.parametrize(
    ("value", "allowed"),
    [
        ((1.0, 2.0), "must be 9 finite numbers (3 × 3, row-major) or 3 (diagonal)"),
        ((1.0,) * 4, "must be 9 finite numbers (3 × 3, row-major) or 3 (diagonal)"),
        ([[1.0, 0.0], [0.0, 1.0]], "must be 9 finite numbers (3 × 3, row-major) or 3 (diagonal)"),
        ((1.0, math.nan, 1.0), "must be 9 finite numbers"),
        ((1.0, 1.0, math.inf), "must be 9 finite numbers"),
        ("heavy", "must be 9 numbers (3 × 3, row-major) or 3 (diagonal)"),
        (((1.0, 0.0), (0.0, 1.0, 0.0), (0.0,)), "must be 9 numbers"),  # ragged
        (((1.0, 0.5, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0)), "must be symmetric"),
        ((1.0, -1e-3, 1.0), "must be positive semi-definite (eigenvalues ≥ 0)"),
        (((1.0, 2.0, 0.0), (2.0, 1.0, 0.0), (0.0, 0.0, 1.0)), "must be positive semi-definite"),
    ],
)
def test_inertia_tensor_rejections_name_the_field_and_the_allowed_form(value, allowed):
    _rejects(lambda: checks.inertia_tensor(value, "inertia", "Body"), "Body: inertia ", allowed)


@pytest.mark.parametrize(
    ("call", "field"),
    [
        (lambda: checks.finite(BIG, "mass", "Link"), "Link: mass "),
        (lambda: checks.positive(BIG, "mass", "Link"), "Link: mass "),
        (lambda: checks.vector3((0.0, 0.0, BIG), "com", "Link"), "Link: com[2] "),
        (lambda: checks.inertia_tensor((1.0, 1.0, BIG), "inertia", "Link"), "Link: inertia "),
    ],
    ids=["finite", "positive", "vector3", "inertia_tensor"],
)
def test_an_integer_too_large_for_a_float_is_a_model_error(call, field):
    """An integer beyond the float range (e.g. from a TOML robot file) is refused like a non-finite value."""
    _rejects(call, field, "must be")


# --- all_finite -------------------------------------------------------------------------------------


@pytest.mark.parametrize("size", [1, 13, 32, 33, 1000])  # the Python path (≤ 32 elements) and NumPy's
@pytest.mark.parametrize("bad", [math.nan, math.inf, -math.inf, None])
def test_all_finite_agrees_with_numpy(size: int, bad: float | None) -> None:
    arr = np.random.default_rng(size).uniform(0.5e308, 1e308, size)  # finite values whose sum overflows
    if bad is not None:
        arr[size // 2] = bad
    assert checks.all_finite(arr) is bool(np.isfinite(arr).all()) is (bad is None)
    assert checks.all_finite(arr.reshape(1, size, 1)) is (bad is None)
