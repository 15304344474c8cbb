"""The scan-shaped Runge–Kutta kernel (mobman.engine.runge_kutta): its values and derivatives against the
definition (mobman.integration), plain and on the unicycle's group."""

from __future__ import annotations

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import mobman  # noqa: F401  (float64)
from mobman import integration
from mobman.engine import runge_kutta
from mobman.integration import CF4, DOP853

from ode_cases import TABLEAUS, arc, planar_system, unicycle_field, vector_field


@pytest.mark.parametrize("name", TABLEAUS)
def test_scan_kernel_equals_the_definition(name):
    tab = TABLEAUS[name]
    state = (jnp.array([0.2, -0.1, np.pi / 2]), jnp.ones((3, 2)))

    def f(t, y):
        k = planar_system(t, y)
        return k, {"q": y[0], "t": t}

    plain = jax.jit(lambda s: integration.step_path(tab, f, s, 0.3, 0.2, has_aux=True))(state)
    fast = jax.jit(lambda s: runge_kutta.step_path(tab, f, s, 0.3, 0.2, has_aux=True))(state)
    for a, b in zip(jax.tree.leaves(plain), jax.tree.leaves(fast)):
        np.testing.assert_allclose(np.asarray(a), np.asarray(b), rtol=0, atol=1e-13)


def test_stage_inputs_are_the_signal_at_the_stage_times():
    """An exogenous signal given at the stage times (``inputs``) is the same as f reading it at t + c_i h."""
    h, t = 0.2, 0.3
    inputs = jnp.sin(t + h * jnp.asarray(DOP853.c))[:, None] * jnp.ones(2)
    y0 = jnp.array([1.0, 1.0])

    def f(s, y, u):
        return vector_field(s, y) + u

    def reading(s, y):
        return vector_field(s, y) + jnp.sin(s)

    expected = np.asarray(integration.step(DOP853, reading, y0, t, h))
    for kernel in (integration, runge_kutta):
        got = kernel.step(DOP853, f, y0, t, h, inputs=inputs)
        np.testing.assert_allclose(np.asarray(got), expected, rtol=0, atol=1e-15)


def test_scan_kernel_equals_the_definition_on_the_group():
    q0 = jnp.array([0.1, 0.2, np.pi, 1.0])

    def f(t, q):
        k = unicycle_field(t, q) + jnp.array([0.0, jnp.sin(q[0]), 0.0])
        return k, k

    plain = integration.step_path(CF4, f, q0, 0.0, 0.25, exp=arc, has_aux=True)
    fast = runge_kutta.step_path(CF4, f, q0, 0.0, 0.25, exp=arc, has_aux=True)
    for a, b in zip(jax.tree.leaves(plain), jax.tree.leaves(fast)):
        np.testing.assert_allclose(np.asarray(a), np.asarray(b), rtol=0, atol=1e-13)
    assert len(plain[1]) == len(fast[1]) == 1


def test_scan_kernel_has_the_derivatives_of_the_definition():
    """The planners differentiate through the integrator (the autodiff endpoint Jacobian, forward mode): the
    derivatives of DOP853 steps with respect to the initial state agree."""

    def endpoint(kernel):
        def k_of(q0):
            state = (q0, jnp.zeros((3, 2)))
            return integration.integrate(DOP853, planar_system, state, 0.0, 0.1, 2, stepper=kernel.step)[0][0]

        return k_of

    q0 = jnp.array([0.2, -0.1, -np.pi / 2])
    plain, fast = endpoint(integration), endpoint(runge_kutta)
    derivative = np.asarray(jax.jit(jax.jacfwd(fast))(q0))
    np.testing.assert_allclose(np.asarray(jax.jit(jax.jacfwd(plain))(q0)), derivative, rtol=0, atol=1e-13)
    # and the derivative is the derivative: central differences
    eps, fast = 1e-6, jax.jit(fast)
    fd = np.stack([(fast(q0 + eps * e) - fast(q0 - eps * e)) / (2 * eps) for e in np.eye(3)], axis=1)
    np.testing.assert_allclose(derivative, fd, atol=1e-8)
