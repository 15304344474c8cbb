"""mobman.planning.algorithms: the right inverse and the null-space projector, the extended pseudo-inverse, the
null-space term raising dexterity, the error's exponential decay (Tchoń, Jakubiak & Muszyński 2002 eq. 14–16),
non-convergence as a result, piecewise-constant controls, and the planners' input errors."""

from __future__ import annotations

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from mobman import ConvergenceError, InputError
from mobman.experiments import tchon2002
from mobman.model.robots import tchon_car_rtr
from mobman.planning.algorithms import Options, dexterity_gradient, null_space_projector, plan, right_inverse
from mobman.planning.basis import PiecewiseConstant
from mobman.planning.endpoint import (
    PlanningSetting,
    dexterity,
    endpoint,
    endpoint_jacobian,
    extended_jacobian,
    variational,
)

from planning_setting import Q0


def test_right_inverse_and_null_space_projector(coarse, z_test):
    J = variational(coarse, z_test, Q0[2], with_mobility=False).J
    inverse, rcond = right_inverse(J)
    assert rcond > 1e-8
    np.testing.assert_allclose(np.asarray(J @ inverse), np.eye(3), atol=1e-10)
    P = np.asarray(null_space_projector(J))
    np.testing.assert_allclose(P @ P, P, atol=1e-10)
    np.testing.assert_allclose(np.asarray(J) @ P, 0.0, atol=1e-10)
    # the paper's eq. (14) J#J − id is minus the projector: (J#J − I)² = −(J#J − I) ≠ J#J − I
    M = np.asarray(inverse @ J) - np.eye(13)
    np.testing.assert_allclose(M @ M, -M, atol=1e-10)
    assert np.abs(M @ M - M).max() > 0.5


def test_extended_pseudo_inverse_is_a_right_inverse(coarse, z_test):
    """J J^{e#} = I_r (§3.2), J^{e#} = first r columns of J^{E#}; and J̄ J^{e#} = 0: the extension is kept."""
    J_E = np.asarray(extended_jacobian(coarse, tchon2002.EXTENSION, z_test, Q0[0]))
    assert J_E.shape == (5, 13)
    np.testing.assert_allclose(J_E[:3], np.asarray(endpoint_jacobian(coarse, z_test, Q0[0])), atol=1e-14)
    inverse, _ = right_inverse(jnp.asarray(J_E), 3)
    np.testing.assert_allclose(
        J_E @ np.asarray(inverse), np.vstack([np.eye(3), np.zeros((2, 3))]), atol=1e-10
    )
    # the extension rows are ∂(x3, q3 + x1)/∂z: x3 and x1 enter directly (D̄), q3(T) through C̄ Ξ(T)
    assert J_E[3, 12] == 1.0 and J_E[4, 10] == 1.0


def test_null_space_term_raises_dexterity_without_moving_the_output(coarse, z_test):
    """Eq. (16) with w = ∇ det(J Jᵀ): the term (I − J#J) w leaves the output still to first order and
    increases
    the dexterity; the paper's sign (J#J − I) w would decrease it (the sign check of eq. 14)."""
    w = np.asarray(jax.jit(dexterity_gradient(coarse))(jnp.asarray(z_test), jnp.asarray(Q0[0])))
    J = np.asarray(endpoint_jacobian(coarse, z_test, Q0[0]))
    term = np.asarray(null_space_projector(jnp.asarray(J))) @ w
    np.testing.assert_allclose(J @ term, 0.0, atol=1e-10 * np.abs(w).max())
    eps = 1e-4 / np.linalg.norm(term)
    d = [dexterity(coarse, z_test + s * eps * term, Q0[0], parametric=True) for s in (-1.0, 0.0, 1.0)]
    assert d[2] > d[1] > d[0]


def test_small_step_error_decays_exponentially(setting):
    """Δθ = 0.01, γ = 1: ‖e(θ)‖ = ‖e(0)‖ exp(−γθ) within 1 % (the flow of eq. 15).

    The target is 0.09 away from the start's end-effector position, so the Euler discretisation of the θ-flow
    (error ∝ Δθ·‖e‖) stays well below the 1 % being tested.
    """
    options = tchon2002.options("pinv", 0.01, tchon2002.QUICK_CAP)
    z0 = tchon2002.initial_configuration()
    theta = 0.01 * np.arange(tchon2002.QUICK_CAP + 1)
    for q0 in Q0[[0, 2]]:
        target = np.asarray(endpoint(setting, z0, q0)) + np.array([0.05, -0.05, 0.05])
        result = plan(setting, z0, q0, target, options)
        assert result.status == "max_iterations"
        np.testing.assert_allclose(result.thetas, theta, atol=1e-12)
        np.testing.assert_allclose(result.errors, result.errors[0] * np.exp(-theta), rtol=0.01)


def test_non_convergence_is_a_result_unless_asked_to_raise(setting):
    """Steepest descent with Δθ = 0.1 from P is far from 1e-12 after the cap: a result, or
    ConvergenceError."""
    z0 = tchon2002.initial_configuration()
    options = tchon2002.options("adjoint", 0.1, tchon2002.QUICK_CAP)
    result = plan(setting, z0, Q0[0], tchon2002.TARGET, options)
    assert result.status == "max_iterations" and not result.converged
    assert result.iterations == tchon2002.QUICK_CAP and result.errors.shape == (tchon2002.QUICK_CAP + 1,)
    assert result.errors[-1] < result.errors[0]  # steepest descent decreases the error
    with pytest.raises(ConvergenceError) as info:
        plan(setting, z0, Q0[0], tchon2002.TARGET, options, raise_on_failure=True)
    assert info.value.history.iterations == tchon2002.QUICK_CAP


def test_bad_input_raises_input_error(setting):
    with pytest.raises(InputError, match="algorithm"):
        Options("newton")
    with pytest.raises(InputError, match="extension"):
        Options("extended")
    with pytest.raises(InputError, match="step"):
        Options("pinv", step=-0.1)
    with pytest.raises(InputError, match="horizon"):
        PlanningSetting(setting.robot, horizon=0.0)
    with pytest.raises(InputError, match="steps"):
        PlanningSetting(setting.robot, PiecewiseConstant(3), steps=100)
    with pytest.raises(InputError, match="y_d"):
        plan(setting, tchon2002.initial_configuration(), Q0[0], [0.0, 1.0])


def test_piecewise_constant_controls_plan_to_machine_precision():
    """The pseudo-inverse planner with 5 piecewise-constant pieces per control (13-dimensional z, like the
    paper's Fourier case) reaches 1e-12 from start P, and the plan holds when re-integrated 4× finer."""
    setting = PlanningSetting(tchon_car_rtr(), PiecewiseConstant(5))
    z0 = np.zeros(setting.n_z)
    z0[0], z0[5] = 0.01, -0.01
    z0[-3:] = [0.0, 2.0, np.pi / 4]
    q0 = np.array([5.0, 0.0, 0.0, np.pi / 6])
    result = plan(setting, z0, q0, [0.0, 0.0, 1.0])
    assert result.converged and result.final_error <= 1e-12
    fine = PlanningSetting(tchon_car_rtr(), PiecewiseConstant(5), steps=4 * setting.steps)
    assert np.abs(np.asarray(endpoint(fine, result.z, q0)) - [0.0, 0.0, 1.0]).max() < 1e-12


@pytest.mark.parametrize(
    ("options", "message"),
    [
        (dict(step=1e300), r"step Δθ must be a number in \(0, 10\]"),
        (dict(gamma=1e300), r"gamma must be a number in \(0, 1000\]"),
        (dict(gamma=float("nan")), r"gamma must be a number in \(0, 1000\]"),
    ],
)
def test_a_step_or_rate_that_can_only_overflow_is_refused(options, message):
    """Δθ or γ of 1e300 made the iteration's steps overflow (NaN in the output, exit 3): refused up front."""
    with pytest.raises(InputError, match=message):
        Options("pinv", **options)
    Options("pinv", step=10.0, gamma=1e3)  # the bounds themselves are accepted
