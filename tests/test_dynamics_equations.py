"""Properties of the dynamics core: structure of M, c, g; reduction; wheels; simulation (energy, no slip)."""

from __future__ import annotations

import numpy as np
import pytest

from mobman import dynamics as dyn
from mobman.dynamics import equations

from dynamics_model import MODEL, WHEEL, B, N, R, random_states, turret_model


@pytest.fixture(scope="module")
def states():
    return random_states()


def test_mass_matrix_symmetric_positive_definite(states):
    q = states[0]
    for model, m in ((MODEL, dyn.mass_matrix(MODEL, q)), (dyn.yamamoto_model(), None)):
        if m is None:
            q9 = np.random.default_rng(1).uniform(-3, 3, (N, 9))
            m = dyn.mass_matrix(model, q9)
        m = np.asarray(m)
        assert np.allclose(m, np.swapaxes(m, -1, -2), atol=1e-12)
        assert np.linalg.eigvalsh(m).min() > 1e-4


def test_mdot_minus_2c_is_skew_and_c_matches_bias(states):
    import jax

    q, q_dot = states[0], states[1]
    c_mat = np.asarray(dyn.coriolis_matrix(MODEL, q, q_dot))
    m_dot = np.asarray(jax.jvp(lambda x: dyn.mass_matrix(MODEL, x), (q,), (q_dot,))[1])
    skew = m_dot - 2 * c_mat
    assert np.abs(m_dot).max() > 0.1
    assert np.max(np.abs(skew + np.swapaxes(skew, -1, -2))) < 1e-10
    c_times_qdot = np.einsum("kij,kj->ki", c_mat, q_dot)
    c_bias = np.asarray(dyn.bias(MODEL, q, q_dot) - dyn.bias(MODEL, q, np.zeros_like(q_dot)))
    assert np.max(np.abs(c_times_qdot - c_bias)) < 1e-10


def test_newton_euler_force_equals_lagrange_form(states):
    """generalized_force (Newton–Euler, virtual work) = M q̈ + c + g (autodiff of M and V), wheels and
    payload included; the payload's own row is the difference made by adding it (the affine load term)."""
    q, q_dot = states[0], states[1]
    q_ddot = np.random.default_rng(3).normal(size=q.shape)
    lagrange = np.einsum("kij,kj->ki", np.asarray(dyn.mass_matrix(MODEL, q)), q_ddot) + np.asarray(
        dyn.bias(MODEL, q, q_dot)
    )
    newton_euler = np.asarray(dyn.generalized_force(MODEL, q, q_dot, q_ddot))
    assert np.abs(lagrange).max() > 1.0
    assert np.max(np.abs(newton_euler - lagrange)) < 1e-10 * np.abs(lagrange).max()
    forces, wheel = equations.body_forces_one(MODEL, q[0], q_dot[0], q_ddot[0])
    without = np.asarray(dyn.generalized_force(MODEL.with_payload(None), q[0], q_dot[0], q_ddot[0]))
    assert np.abs(wheel).max() > 1e-3
    assert np.allclose(np.asarray(forces[-1]), newton_euler[0] - without, atol=1e-10)


def test_gravity_is_gradient_of_potential_by_finite_differences(states):
    q = states[0][0]
    h = 1e-6
    fd = np.array(
        [
            (dyn.potential_energy(MODEL, q + h * e) - dyn.potential_energy(MODEL, q - h * e)) / (2 * h)
            for e in np.eye(6)
        ]
    )
    g = np.asarray(dyn.gravity_vector(MODEL, q))
    assert np.abs(g).max() > 1.0
    assert np.allclose(g, fd, atol=1e-6)
    assert np.allclose(
        g[:3], 0.0, atol=1e-12
    )  # horizontal floor: platform motion does no work against gravity


def test_wheels_add_the_closed_form_platform_inertia(states):
    """Wheel terms in P = Sᵀ M S: diag(2 m_w + 2 I_w / r², 2 m_w b² + 2 I_m + 2 I_w b² / r²) on (v, ω) only."""
    q = states[0]
    bare = turret_model(wheel=dyn.Wheel(0.0, 0.0, 0.0))
    diff = np.asarray(dyn.reduced_mass_matrix(MODEL, q) - dyn.reduced_mass_matrix(bare, q))
    expected = np.zeros((5, 5))
    expected[0, 0] = 2 * WHEEL.mass + 2 * WHEEL.I_w / R**2
    expected[1, 1] = 2 * WHEEL.mass * B**2 + 2 * WHEEL.I_m + 2 * WHEEL.I_w * B**2 / R**2
    assert np.allclose(diff, expected, atol=1e-10)


def test_input_matrix_maps_wheel_torques_to_force_and_moment(states):
    b_mat = np.asarray(dyn.input_matrix(MODEL, states[0]))
    expected = np.eye(5)
    expected[:2, :2] = [[1 / R, 1 / R], [B / R, -B / R]]
    assert np.allclose(b_mat, expected, atol=1e-12)


def test_wheel_angle_rates_agree_with_platform_kinematics(states):
    q, q_dot, eta = states[0], states[1], states[2]
    rates = np.asarray(dyn.wheel_angle_rates(MODEL, q, q_dot))
    assert np.allclose(rates, np.asarray(MODEL.robot.platform.eta_to_wheel_speeds(eta[:, :2])), atol=1e-12)
