"""mobman.planning.endpoint: the endpoint map's integrator order, the variational Jacobian against autodiff and finite
differences, the parametric Gram matrix below the paper's dexterity matrix (Tchoń et al. 2002 eq. 11), and a
pose output refused."""

from __future__ import annotations

import math

import numpy as np
import pytest

from mobman import InputError
from mobman.planning import integrators
from mobman.planning.endpoint import (
    PlanningSetting,
    dexterity,
    dexterity_matrix,
    endpoint,
    endpoint_jacobian,
    is_regular,
)

from planning_setting import Q0


@pytest.mark.parametrize("method, steps", [("rk4", 250), ("dop853", 8)])
def test_endpoint_integrator_has_its_order(setting, z_test, method, steps):
    """Halving h divides the endpoint error by ≈ 2^order (4 for RK4, 8 for DOP853); the default grid is
    accurate to ≪ 1e-12."""
    ref = np.asarray(endpoint(PlanningSetting(setting.robot, steps=400), z_test, Q0[0]))

    def error(n):
        return np.abs(
            np.asarray(endpoint(PlanningSetting(setting.robot, steps=n, method=method), z_test, Q0[0])) - ref
        ).max()

    order = integrators.tableau(method).order
    assert abs(math.log2(error(steps) / error(2 * steps)) - order) < 1.5
    assert np.abs(np.asarray(endpoint(setting, z_test, Q0[0])) - ref).max() < 1e-13


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


def test_parametric_gram_is_below_paper_dexterity_matrix(coarse, z_test):
    """J Jᵀ (finite parametrisation) ≼ 𝒟 = C𝓜Cᵀ + DDᵀ (eq. 11): Bessel's inequality for the basis span."""
    D_paper = np.asarray(dexterity_matrix(coarse, z_test, Q0[0]))
    D_param = np.asarray(dexterity_matrix(coarse, z_test, Q0[0], parametric=True))
    assert np.linalg.eigvalsh(D_paper - D_param).min() > -1e-10
    assert np.linalg.eigvalsh(D_paper - D_param).max() > 1e-3  # really different: the basis is truncated
    assert dexterity(coarse, z_test, Q0[0]) > dexterity(coarse, z_test, Q0[0], parametric=True) > 0
    assert is_regular(coarse, z_test, Q0[0])


def test_a_pose_output_is_refused_with_a_clear_error():
    """The planners subtract endpoints (y_d − K(z)): a Pose task, whose error is log(R* Rᵀ), is refused."""
    from mobman.model.robots import panda_differential
    from mobman.model.tasks import Pose

    with pytest.raises(InputError, match="planning output .*not a pose"):
        PlanningSetting(panda_differential(), task=Pose())
    with pytest.raises(InputError, match="not a pose"):
        PlanningSetting(panda_differential())  # its own task is the flange pose
