"""The Runge–Kutta driver (mobman.integration) and its scan-shaped kernel (mobman.engine.runge_kutta): the
tableaus' consistency, their orders measured on ODEs with a closed-form solution, the commutator-free Lie
group method on the unicycle's group, and the kernel's values and derivatives against the definition."""

from __future__ import annotations

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import mobman  # noqa: F401  (float64)
from mobman import integration
from mobman.engine import runge_kutta
from mobman.integration import CF4, DOP853, RK4

TABLEAUS = {"rk4": RK4, "dop853": DOP853, "cf4": CF4}


def arc(q, u):
    """q ∘ exp(u) on SE(2) × R: the unicycle (x, y, θ) driven for unit time at the body twist (u0, 0, u1), i.e.
    along a circle of radius u0/u1 (a line if u1 = 0), closed form; q[3:] + u[2:] on the joints."""
    x, y, th = q[0], q[1], q[2]
    v, w = u[0], u[1]
    small = jnp.abs(w) < 1e-300
    w_safe = jnp.where(small, 1.0, w)
    dx = jnp.where(small, v * jnp.cos(th), v / w_safe * (jnp.sin(th + w) - jnp.sin(th)))
    dy = jnp.where(small, v * jnp.sin(th), -v / w_safe * (jnp.cos(th + w) - jnp.cos(th)))
    return jnp.concatenate([jnp.stack([x + dx, y + dy, th + w]), q[3:] + u[2:]])


def vector_field(t, y):
    """y0' = −y0² (y0 = 1/(1 + t) from 1), y1' = y1 cos t (y1 = e^{sin t} from 1)."""
    return jnp.stack([-(y[0] ** 2), y[1] * jnp.cos(t)])


def vector_solution(t):
    return np.array([1.0 / (1.0 + t), np.exp(np.sin(t))])


def unicycle_field(t, q):
    """η = (v, ω, q̇_3) with v = ω = 1 + θ²: the platform runs along the unit circle with θ' = 1 + θ², so from
    q = 0: θ = tan t, (x, y) = (sin θ, 1 − cos θ); the joint q̇_3 = q_3 cos t, q_3 = e^{sin t} from 1."""
    speed = 1.0 + q[2] ** 2
    return jnp.stack([speed, speed, q[3] * jnp.cos(t)])


def unicycle_solution(t):
    th = np.tan(t)
    return np.array([np.sin(th), 1.0 - np.cos(th), th, np.exp(np.sin(t))])


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


# --- the scan-shaped kernel against the definition -------------------------------------------------


def planar_system(t, state):
    """A pytree state (q, Ξ) like the planners' variational system: q̇ = S(q) u(t), Ξ̇ = A Ξ + B."""
    q, xi = state
    u = jnp.array([1.0 + jnp.sin(3.0 * t), jnp.cos(t)])
    c, s = jnp.cos(q[2]), jnp.sin(q[2])
    zero = jnp.zeros(())
    a = jnp.stack([jnp.stack([zero, zero, -s * u[0]]), jnp.stack([zero, zero, c * u[0]]), jnp.zeros(3)])
    b = jnp.stack([jnp.stack([c, zero]), jnp.stack([s, zero]), jnp.array([0.0, 1.0])])
    return jnp.stack([c * u[0], s * u[0], u[1]]), a @ xi + b * jnp.cos(2.0 * t)


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


def test_integrate_records_every_step():
    y_end, states = integration.integrate(RK4, vector_field, jnp.array([1.0, 1.0]), 0.5, 0.1, 4)
    y = jnp.array([1.0, 1.0])
    for k in range(4):
        y = integration.step(RK4, vector_field, y, 0.5 + 0.1 * k, 0.1)
        np.testing.assert_allclose(np.asarray(states[k]), np.asarray(y), rtol=0, atol=1e-15)
    np.testing.assert_allclose(np.asarray(y_end), np.asarray(y), rtol=0, atol=1e-15)
