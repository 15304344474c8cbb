"""The Runge–Kutta driver (mobman.integration): the tableaus' consistency, their orders measured on ODEs with a
closed-form solution, and the commutator-free Lie group method on the unicycle's group."""

from __future__ import annotations

import jax.numpy as jnp
import numpy as np
import pytest

import mobman  # noqa: F401  (float64)
from mobman import integration
from mobman.integration import CF4, RK4

from ode_cases import TABLEAUS, arc, unicycle_field, unicycle_solution, vector_field, vector_solution


def _run(tab, f, y0, t_end, n, exp=None):
    return np.asarray(integration.integrate(tab, f, jnp.asarray(y0), 0.0, t_end / n, n, exp=exp)[0])


@pytest.mark.parametrize("name", TABLEAUS)
def test_rows_of_A_sum_to_the_nodes(name):
    c, A, b = integration.coefficients(TABLEAUS[name])
    np.testing.assert_allclose(A.sum(axis=(0, 2)), c, rtol=0, atol=2e-15)
    assert np.all(np.triu(A, 0) == 0.0)  # explicit: stage i reaches only the slopes before it
    assert b.sum() == pytest.approx(1.0, abs=1e-14)


@pytest.mark.parametrize(
    "name, steps", [("rk4", (8, 16)), ("dop853", (3, 6)), ("cf4", (8, 16))], ids=["rk4", "dop853", "cf4"]
)
def test_order_on_a_vector_field_with_closed_form_solution(name, steps):
    tab = TABLEAUS[name]
    errors = [np.abs(_run(tab, vector_field, [1.0, 1.0], 2.0, n) - vector_solution(2.0)).max() for n in steps]
    assert errors[1] > 1e-13  # above rounding: the ratio measures the method
    assert 0.7 * 2**tab.order < errors[0] / errors[1] < 1.5 * 2**tab.order


def test_lie_method_order_on_the_unicycle():
    errors = [
        np.abs(
            _run(CF4, unicycle_field, [0.0, 0.0, 0.0, 1.0], 0.6, n, exp=arc) - unicycle_solution(0.6)
        ).max()
        for n in (16, 32)
    ]
    assert 0.7 * 16 < errors[0] / errors[1] < 1.5 * 16


@pytest.mark.parametrize("theta", [0.0, 0.4, np.pi / 2, -np.pi / 2, np.pi, -3.0])
@pytest.mark.parametrize("eta", [(0.7, 1.3, -0.4), (1.1, 0.0, 2.0), (-0.5, -2.5, 0.0), (0.0, 0.9, 1.0)])
def test_lie_method_is_exact_at_constant_velocity(theta, eta):
    """At constant η one step of any length is the exact motion: the arc of radius v/ω (a line at ω = 0)."""
    q0 = jnp.array([0.3, -0.2, theta, 0.5])
    v, w, qd = eta
    h = 1.7
    q1 = integration.step(CF4, lambda t, q: jnp.asarray(eta), q0, 0.0, h, exp=arc)
    if w == 0.0:
        x, y = 0.3 + v * h * np.cos(theta), -0.2 + v * h * np.sin(theta)
    else:
        x = 0.3 + v / w * (np.sin(theta + w * h) - np.sin(theta))
        y = -0.2 - v / w * (np.cos(theta + w * h) - np.cos(theta))
    np.testing.assert_allclose(np.asarray(q1), [x, y, theta + w * h, 0.5 + qd * h], rtol=0, atol=1e-14)


def test_lie_method_on_an_abelian_group_is_classical_rk4():
    y0 = jnp.array([1.0, 1.0])
    for h in (0.3, 0.05):
        lie = integration.step(CF4, vector_field, y0, 0.2, h, exp=integration.add)
        rk4 = integration.step(RK4, vector_field, y0, 0.2, h)
        np.testing.assert_allclose(np.asarray(lie), np.asarray(rk4), rtol=0, atol=1e-15)


def test_junction_and_aux_of_a_lie_step():
    """The junction is y ∘ exp(h Σ β¹_j k_j); the aux are the stages' own, stacked in stage order."""
    q0 = jnp.array([0.0, 0.0, 0.0, 1.0])
    h = 0.1

    def f(t, q):
        k = unicycle_field(t, q)
        return k, {"t": t, "k": k}

    q1, (mid,), aux = integration.step_path(CF4, f, q0, 0.0, h, exp=arc, has_aux=True)
    np.testing.assert_allclose(np.asarray(aux["t"]), h * np.array(CF4.c), rtol=0, atol=1e-17)
    expected_mid = arc(q0, h * jnp.asarray(CF4.b[0]) @ aux["k"])
    np.testing.assert_allclose(np.asarray(mid), np.asarray(expected_mid), rtol=0, atol=1e-15)
    np.testing.assert_allclose(np.asarray(arc(mid, h * jnp.asarray(CF4.b[1]) @ aux["k"])), q1, atol=1e-15)


def test_integrate_records_every_step():
    y_end, states = integration.integrate(RK4, vector_field, jnp.array([1.0, 1.0]), 0.5, 0.1, 4)
    y = jnp.array([1.0, 1.0])
    for k in range(4):
        y = integration.step(RK4, vector_field, y, 0.5 + 0.1 * k, 0.1)
        np.testing.assert_allclose(np.asarray(states[k]), np.asarray(y), rtol=0, atol=1e-15)
    np.testing.assert_allclose(np.asarray(y_end), np.asarray(y), rtol=0, atol=1e-15)
