"""The pseudo-inverse laws' common part (mobman.control.laws.pseudo_inverse): the normalised law as the weighted
minimum-norm solution, damping and saturation as reported, and the laws' errors."""

from __future__ import annotations

import jax.numpy as jnp
import numpy as np
import pytest

from mobman import ModelError, kinematics
from mobman.control import laws
from mobman.model import robots
from mobman.model.tasks import Position

ROBOT = robots.bayle_planar()
TASK = Position("xy")


def test_normalized_law_is_the_weighted_minimum_norm_solution():
    q = jnp.array([0.2, 0.1, 0.3, 0.7, 1.1])
    xsd = jnp.array([0.1, -0.2])
    xs = kinematics.forward(ROBOT, q, TASK)
    eta = laws.BaylePseudoInverse(W=1.0, normalized=True)(ROBOT, TASK, q, 0.0, xs, xsd).eta
    r = np.asarray(ROBOT.velocity_limits)
    jbar = np.asarray(kinematics.reduced_jacobian(ROBOT, q, TASK))
    assert np.allclose(jbar @ eta, xsd, atol=1e-12)
    # minimum of ‖R⁻¹η‖ among the solutions: η/r² is in the row space of J̄
    resid = (eta / r**2) - jbar.T @ np.linalg.lstsq(jbar.T, eta / r**2, rcond=None)[0]
    assert np.allclose(resid, 0.0, atol=1e-12)


def test_damping_and_saturation_are_reported():
    q = jnp.array([0.0, 0.0, 0.0, 0.7, 1.1])
    xs, xsd = jnp.array([5.0, 5.0]), jnp.array([3.0, 0.0])
    step = laws.BaylePseudoInverse(W=1.0)(ROBOT, TASK, q, 0.0, xs, xsd)
    eta = step.eta
    ratio = float(np.max(np.abs(eta) / np.asarray(ROBOT.velocity_limits)))
    assert float(step.limit_ratio) == pytest.approx(ratio) and ratio > 1 and not step.saturated
    step = laws.BaylePseudoInverse(W=1.0, saturate=True)(ROBOT, TASK, q, 0.0, xs, xsd)
    assert bool(step.saturated) and np.allclose(step.eta, eta / ratio)
    # damping active when σ_min < ε: λ² = λ_max² (1 − (σ_min/ε)²)
    step = laws.BaylePseudoInverse(W=1.0, damping=0.3, damping_threshold=100.0)(ROBOT, TASK, q, 0.0, xs, xsd)
    smin = np.linalg.svd(np.asarray(kinematics.reduced_jacobian(ROBOT, q, TASK)), compute_uv=False)[-1]
    assert float(step.sigma_min) == pytest.approx(smin)
    assert float(step.damping) == pytest.approx(0.09 * (1 - (smin / 100.0) ** 2)) and bool(step.damped)
    assert np.linalg.norm(step.eta) < np.linalg.norm(eta)


def test_pseudo_inverse_law_errors():
    with pytest.raises(ModelError, match="W"):
        laws.BaylePseudoInverse(W=-1.0)
    with pytest.raises(ModelError, match="damping"):
        laws.BaylePseudoInverse(W=1.0, damping=-0.1)
    with pytest.raises(ModelError, match="velocity limits"):
        laws.BaylePseudoInverse(W=1.0, normalized=True)(
            robots.tchon_car_rtr(), None, jnp.zeros(7), 0.0, jnp.zeros(3), jnp.zeros(3)
        )
