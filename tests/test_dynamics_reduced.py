"""mobman.dynamics.reduced: the reduced bias as the projection of the full equations, Ṡ η and B against their
definitions, inverse and forward dynamics, the constraint forces dropping out, the public functions inside a user's vmap and their size errors."""

from __future__ import annotations

import math

import numpy as np
import pytest

import mobman
from mobman import dynamics as dyn
from mobman import kinematics
from mobman.dynamics import equations, reduced
from mobman.io.real_robots import urdf_model

from dynamics_model import MODEL, random_states

TIAGO = dyn.DynamicModel.from_urdf(urdf_model("tiago"))


@pytest.fixture(scope="module")
def states():
    return random_states()


def test_reduced_bias_equals_projection_of_full_equations(states):
    """b = Sᵀ (M Ṡ η + c + g) with Ṡ η by central finite differences of S along q̇ = S η."""
    q, q_dot, eta = states[0], states[1], states[2]
    h = 1e-6
    s_dot = (
        np.asarray(kinematics.S(MODEL.robot, q + h * q_dot))
        - np.asarray(kinematics.S(MODEL.robot, q - h * q_dot))
    ) / (2 * h)
    s = np.asarray(kinematics.S(MODEL.robot, q))
    m = np.asarray(dyn.mass_matrix(MODEL, q))
    full = np.einsum("kij,kjl,kl->ki", m, s_dot, eta) + np.asarray(dyn.bias(MODEL, q, q_dot))
    expected = np.einsum("kji,kj->ki", s, full)
    assert np.allclose(np.asarray(dyn.reduced_bias(MODEL, q, eta)), expected, atol=1e-6)


@pytest.mark.parametrize("model", [MODEL, TIAGO], ids=["yamamoto", "tiago"])
def test_s_dot_eta_and_the_input_matrix_equal_their_definitions(model, states):
    """Ṡ η against central differences of S along q̇ = S η, and B = Sᵀ E with S formed."""
    robot = model.robot
    rng = np.random.default_rng(11)
    q = rng.uniform(-math.pi, math.pi, (6, robot.n_q))
    q[:3, 2] = (-math.pi / 2, math.pi / 2, math.pi)
    eta = rng.normal(size=(6, robot.n_eta))
    h = 1e-6
    for x, e in zip(q, eta):
        q_dot = np.asarray(robot.S(x)) @ e
        s_dot = (np.asarray(robot.S(x + h * q_dot)) - np.asarray(robot.S(x - h * q_dot))) / (2 * h)
        np.testing.assert_allclose(np.asarray(reduced.s_dot_eta(model, x, e)), s_dot @ e, atol=1e-8)
        b_mat = np.asarray(robot.S(x)).T @ np.asarray(equations.actuation_matrix_one(model, x))
        np.testing.assert_allclose(np.asarray(reduced.input_matrix_one(model, x)), b_mat, atol=1e-14)


def test_inverse_and_forward_dynamics_round_trip(states):
    q, _, eta, eta_dot = states
    tau = dyn.inverse_dynamics(MODEL, q, eta, eta_dot)
    assert np.allclose(np.asarray(dyn.forward_dynamics(MODEL, q, eta, tau)), eta_dot, atol=1e-9)


def test_constraint_forces_drop_out_of_the_reduced_equations(states):
    """A solution of the reduced equations satisfies the full ones with some λ (residual outside range Gᵀ = 0);
    a torque that violates the reduced equations leaves a residual."""
    q, _, eta, eta_dot = states
    tau = dyn.inverse_dynamics(MODEL, q, eta, eta_dot)
    lam, residual = dyn.constraint_forces(MODEL, q, eta, eta_dot, tau)
    assert np.abs(np.asarray(lam)).max() > 1.0  # the lateral wheel force is really there
    assert np.abs(np.asarray(residual)).max() < 1e-9
    _, wrong = dyn.constraint_forces(MODEL, q, eta, eta_dot, np.asarray(tau) + 1.0)
    assert np.abs(np.asarray(wrong)).max() > 0.1


def test_wrong_sizes_are_input_errors():
    with pytest.raises(mobman.InputError, match="q_ddot"):
        dyn.generalized_force(MODEL, np.zeros(6), np.zeros(6), np.zeros(5))
    with pytest.raises(mobman.InputError, match="q_dot"):
        dyn.generalized_force(MODEL, np.zeros(6), np.full(6, np.nan), np.zeros(6))
    with pytest.raises(mobman.InputError, match="eta"):
        dyn.reduced_bias(MODEL, np.zeros(6), np.zeros(4))


def test_public_reduced_functions_work_inside_a_users_vmap(states):
    """The validated public functions accept a user's traced values (their own jit, grad or vmap)."""
    import jax

    q, _, eta, eta_dot = states
    vmapped = jax.vmap(lambda x, e, a: dyn.inverse_dynamics(MODEL, x, e, a))(q, eta, eta_dot)
    np.testing.assert_allclose(vmapped, dyn.inverse_dynamics(MODEL, q, eta, eta_dot), rtol=1e-12, atol=1e-12)
