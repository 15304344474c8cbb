"""Endogenous-configuration motion planning (Tchoń, Jakubiak & Muszyński 2002): mathematics and reproduction."""

from __future__ import annotations

import math

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from mobman import ConvergenceError, InputError
from mobman.experiments import tchon2002
from mobman.planning.algorithms import Options, null_space_projector, plan, right_inverse
from mobman.planning.basis import Fourier, PiecewiseConstant
from mobman.planning.batch import plan_batch
from mobman.planning.endpoint import (
    PlanningSetting,
    dexterity,
    dexterity_matrix,
    endpoint,
    endpoint_jacobian,
    variational,
)

Q0 = np.stack([tchon2002.start_pose(n) for n in tchon2002.STARTS])


@pytest.fixture(scope="module")
def setting():
    return tchon2002.setting()


@pytest.fixture(scope="module")
def coarse(setting):
    """The planners' Jacobian grid: the variational-system checks run there (compiled once)."""
    return setting.jacobian_setting


@pytest.fixture(scope="module")
def z_test():
    """A generic configuration with all harmonics active (not the paper's nearly constant start)."""
    rng = np.random.default_rng(7)
    z = tchon2002.initial_configuration()
    z[:10] = rng.normal(scale=1.0, size=10)
    return z


@pytest.fixture(scope="module")
def reproduction(tmp_path_factory):
    out = tmp_path_factory.mktemp("tchon2002")
    return tchon2002.run(out, quick=True), out


@pytest.mark.parametrize("basis", [Fourier(3), PiecewiseConstant(4)])
def test_basis_is_orthonormal(basis):
    horizon, n = 2.5, 4000
    t = (np.arange(n) + 0.5) * horizon / n
    phi = np.asarray(jax.vmap(lambda s: basis.values(s, horizon))(jnp.asarray(t)))
    gram = phi.T @ phi * horizon / n
    np.testing.assert_allclose(gram, np.eye(basis.size), atol=1e-9)


def test_fourier_matches_paper_series():
    t = 0.3
    lam = np.array([0.5, -1.0, 2.0, 0.25, 3.0])
    paper = lam[0] + math.sqrt(2) * (lam[1] * math.sin(2 * math.pi * t) + lam[2] * math.cos(2 * math.pi * t)
                                     + lam[3] * math.sin(4 * math.pi * t) + lam[4] * math.cos(4 * math.pi * t))
    assert float(Fourier(2).values(jnp.asarray(t), 1.0) @ lam) == pytest.approx(paper, rel=1e-14)


def test_endpoint_converges_with_rk4_steps(setting, z_test):
    """RK4 is 4th order: halving h divides the error by ≈ 16; the default grid is accurate to ≪ 1e-12."""
    ref = np.asarray(endpoint(PlanningSetting(setting.robot, steps=2 * setting.steps), z_test, Q0[0]))
    e1 = np.abs(np.asarray(endpoint(PlanningSetting(setting.robot, steps=500), z_test, Q0[0])) - ref).max()
    e2 = np.abs(np.asarray(endpoint(PlanningSetting(setting.robot, steps=1000), z_test, Q0[0])) - ref).max()
    assert 12 < e1 / e2 < 20
    assert e2 * (1000 / setting.steps) ** 4 < 1e-13


def test_variational_jacobian_equals_autodiff_and_finite_differences(coarse, z_test):
    J_var = np.asarray(endpoint_jacobian(coarse, z_test, Q0[1], "variational"))
    J_ad = np.asarray(endpoint_jacobian(coarse, z_test, Q0[1], "autodiff"))
    assert np.abs(J_var - J_ad).max() <= 1e-9 * max(1.0, np.abs(J_ad).max())
    h = 1e-6
    eye = np.eye(z_test.size)
    plus = np.asarray(endpoint(coarse, z_test + h * eye, Q0[1]))
    minus = np.asarray(endpoint(coarse, z_test - h * eye, Q0[1]))
    J_fd = ((plus - minus) / (2 * h)).T
    np.testing.assert_allclose(J_var, J_fd, atol=1e-7)


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


def test_parametric_gram_is_below_paper_dexterity_matrix(coarse, z_test):
    """J Jᵀ (finite parametrisation) ≼ 𝒟 = C𝓜Cᵀ + DDᵀ (eq. 11): Bessel's inequality for the basis span."""
    D_paper = np.asarray(dexterity_matrix(coarse, z_test, Q0[0]))
    D_param = np.asarray(dexterity_matrix(coarse, z_test, Q0[0], parametric=True))
    assert np.linalg.eigvalsh(D_paper - D_param).min() > -1e-10
    assert np.linalg.eigvalsh(D_paper - D_param).max() > 1e-3  # really different: the basis is truncated
    assert dexterity(coarse, z_test, Q0[0]) > dexterity(coarse, z_test, Q0[0], parametric=True) > 0


def test_reproduction_pinv_reaches_tolerance(reproduction):
    result, out = reproduction
    pinv = [r for r in result.results if r["algorithm"] == "pinv"]
    assert {r["start"] for r in pinv} == {"P", "Q", "R"}
    for r in pinv:
        assert r["converged"] and r["final_error"] <= 1e-12
        assert len(r["lambda"]) == 10 and len(r["x"]) == 3
        assert r["error_history"][-1] == r["final_error"]
    for path in result.figures:
        assert path.exists() and path.stat().st_size > 1000


def test_reproduction_solutions_reach_target_on_a_finer_grid(setting, reproduction):
    """The planned configurations solve the *continuous* problem: endpoint on twice the grid still within tol."""
    result, _ = reproduction
    runs = [r for r in result.results if r["algorithm"] == "pinv"]
    z = np.stack([np.concatenate([r["lambda"], r["x"]]) for r in runs])
    q0 = np.stack([tchon2002.start_pose(r["start"]) for r in runs])
    fine = PlanningSetting(setting.robot, steps=2 * setting.steps)
    err = np.linalg.norm(np.asarray(endpoint(fine, z, q0)) - tchon2002.TARGET, axis=-1)
    assert np.all(err < 1e-12)


def test_dexterity_positive_at_visited_configurations(reproduction):
    result, _ = reproduction
    for r in result.results:
        if r["converged"]:
            assert r["dexterity_start"] > 0 and r["dexterity_end"] > 0


def test_small_step_error_decays_exponentially(setting):
    """Δθ = 0.01, γ = 1: ‖e(θ)‖ = ‖e(0)‖ exp(−γθ) within 1 % (the flow of eq. 15).

    The target is 0.09 away from the start's end-effector position, so the Euler discretisation of the θ-flow
    (error ∝ Δθ·‖e‖) stays well below the 1 % being tested.
    """
    options = tchon2002.options("pinv", 0.01, tchon2002.QUICK_CAP)
    z0 = tchon2002.initial_configuration()
    targets = np.asarray(endpoint(setting, np.broadcast_to(z0, (3, 13)), Q0)) + np.array([0.05, -0.05, 0.05])
    batch = plan_batch(setting, z0, Q0, targets, options)
    assert all(s == "max_iterations" for s in batch.status)
    theta = 0.01 * np.arange(tchon2002.QUICK_CAP + 1)
    for errors in batch.errors:
        predicted = errors[0] * np.exp(-theta)
        np.testing.assert_allclose(errors, predicted, rtol=0.01)


def test_non_convergence_is_a_result_unless_asked_to_raise(setting):
    z0 = tchon2002.initial_configuration()
    options = Options("adjoint", 1.0, max_iterations=5)
    result = plan(setting, z0, Q0[0], tchon2002.TARGET, options)
    assert result.status == "max_iterations" and not result.converged
    assert result.iterations == 5 and result.errors.shape == (6,)
    assert result.errors[-1] < result.errors[0]  # steepest descent decreases the error
    with pytest.raises(ConvergenceError) as info:
        plan(setting, z0, Q0[0], tchon2002.TARGET, options, raise_on_failure=True)
    assert info.value.history.iterations == 5


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
