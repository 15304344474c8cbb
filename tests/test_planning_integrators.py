"""The planners' Runge–Kutta schemes (mobman.planning.integrators.tableau): each method name gives an explicit
tableau of its documented stages and order, checked by the order conditions and by the convergence of an
independent stepper; an unknown name is one InputError listing the methods."""

from __future__ import annotations

import math

import numpy as np
import pytest

from mobman.errors import InputError
from mobman.planning import integrators

DOCUMENTED = {"rk4": (4, 4), "dop853": (12, 8)}  # name: (stages, order)


def _matrices(tab):
    s = len(tab.c)
    a = np.zeros((s, s))
    for i, row in enumerate(tab.A):
        a[i, : len(row)] = row
    return a, np.asarray(tab.b, float), np.asarray(tab.c, float)


def test_the_methods_are_exactly_the_documented_ones():
    assert set(integrators.METHODS) == set(DOCUMENTED)


@pytest.mark.parametrize(("method", "stages_order"), DOCUMENTED.items())
def test_tableau_is_explicit_with_the_documented_stages_and_order(method, stages_order):
    stages, order = stages_order
    tab = integrators.tableau(method)
    assert tab.order == order
    assert len(tab.c) == len(tab.b) == len(tab.A) == stages
    assert [len(row) for row in tab.A] == list(range(stages))  # strictly lower triangular
    a, b, c = _matrices(tab)
    np.testing.assert_allclose(a.sum(axis=1), c, atol=1e-14)  # row sums are the nodes


@pytest.mark.parametrize(("method", "stages_order"), DOCUMENTED.items())
def test_tableau_meets_the_order_conditions_of_the_linear_test_equation(method, stages_order):
    """y' = y: one step is Σ_k h^k bᵀ A^(k−1) 1, which matches e^h up to h^p exactly when
    bᵀ A^(k−1) 1 = 1/k! for k ≤ p."""
    _, order = stages_order
    a, b, _ = _matrices(integrators.tableau(method))
    power = np.ones(len(b))
    for k in range(1, order + 1):
        assert b @ power == pytest.approx(1 / math.factorial(k), rel=1e-12, abs=1e-15), k
        power = a @ power


@pytest.mark.parametrize("method", DOCUMENTED)
def test_tableau_meets_the_nonlinear_order_conditions_up_to_four(method):
    a, b, c = _matrices(integrators.tableau(method))
    assert b.sum() == pytest.approx(1.0, rel=1e-14)
    assert b @ c == pytest.approx(1 / 2, rel=1e-13)
    assert b @ c**2 == pytest.approx(1 / 3, rel=1e-13)
    assert b @ (a @ c) == pytest.approx(1 / 6, rel=1e-13)
    assert b @ c**3 == pytest.approx(1 / 4, rel=1e-13)
    assert b @ (c * (a @ c)) == pytest.approx(1 / 8, rel=1e-13)
    assert b @ (a @ c**2) == pytest.approx(1 / 12, rel=1e-13)
    assert b @ (a @ (a @ c)) == pytest.approx(1 / 24, rel=1e-13)


def _solve(tab, steps: int) -> float:
    """y' = −y² + t on [0, 1], y(0) = 1, fixed steps of the explicit tableau."""
    a, b, c = _matrices(tab)
    h, t, y = 1.0 / steps, 0.0, 1.0
    for _ in range(steps):
        k = np.zeros(len(b))
        for i in range(len(b)):
            yi = y + h * (a[i, :i] @ k[:i])
            k[i] = -(yi**2) + t + c[i] * h
        y, t = y + h * (b @ k), t + h
    return y


def test_rk4_converges_with_order_four_on_a_nonlinear_equation():
    tab = integrators.tableau("rk4")
    reference = _solve(integrators.tableau("dop853"), 400)
    errors = [abs(_solve(tab, n) - reference) for n in (10, 20, 40)]
    rates = [math.log2(errors[i] / errors[i + 1]) for i in range(2)]
    assert all(3.8 < r < 4.3 for r in rates), rates


def test_dop853_is_far_more_accurate_than_rk4_at_the_same_steps():
    reference = _solve(integrators.tableau("dop853"), 400)
    err4 = abs(_solve(integrators.tableau("rk4"), 10) - reference)
    err8 = abs(_solve(integrators.tableau("dop853"), 10) - reference)
    assert err8 < 1e-9 < err4


@pytest.mark.parametrize("method", ["RK4", "rk45", "euler", "", "dop-853", None])
def test_an_unknown_method_names_the_field_and_the_allowed_names(method):
    with pytest.raises(InputError) as info:
        integrators.tableau(method)
    message = str(info.value)
    assert "\n" not in message
    assert message == f"method must be one of rk4, dop853, got {method!r}"
