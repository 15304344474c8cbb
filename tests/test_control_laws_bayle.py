"""Bayle's law (mobman.control.laws.bayle) at one configuration against its closed form (the task error
dynamics, the self-motion's projected gradient), and Nait-Chabane's law (mobman.control.laws.nait_chabane)
equal to it."""

from __future__ import annotations

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from mobman import kinematics
from mobman.control import criteria, laws
from mobman.model import robots
from mobman.model.tasks import Position

ROBOT = robots.bayle_planar()
TASK = Position("xy")
W5 = criteria.Manipulability("eccentricity", "system", power=2)


def bayle(W=2.0, k=0.5, **options):
    return laws.BaylePseudoInverse(W=W, k=k, criterion=W5, **options)


def test_bayle_law_pointwise_properties():
    q = jnp.array([0.2, 0.1, 0.3, 0.7, 1.1])
    xs, xsd = jnp.array([1.3, 0.6]), jnp.array([0.1, -0.2])
    law = bayle(W=np.array([2.0, 3.0]), k=0.7)
    step = jax.jit(lambda qq: law(ROBOT, TASK, qq, 0.0, xs, xsd))(q)
    eta = step.eta
    jbar = kinematics.reduced_jacobian(ROBOT, q, TASK)
    e = xs - kinematics.forward(ROBOT, q, TASK)
    assert np.allclose(jbar @ eta, xsd + np.array([2.0, 3.0]) * e, atol=1e-12)  # ė = −W e
    # self-motion: η − J̄⁺(…) = −k Hᵀ∇P, and Ṗ = ∇ᵀP S η_self = −k ‖Hᵀ∇P‖² ≤ 0
    pinv = np.linalg.pinv(np.asarray(jbar))
    s = np.asarray(kinematics.S(ROBOT, q))
    h = s @ (np.eye(4) - pinv @ jbar)
    grad = np.asarray(W5.gradient(ROBOT, q, TASK))
    assert np.allclose(eta - pinv @ (xsd + np.array([2.0, 3.0]) * e), -0.7 * h.T @ grad, atol=1e-12)
    assert float(step.P) == pytest.approx(float(W5(ROBOT, q, TASK)))
    # Nait-Chabane eq. 30 with W = k I and feedback K equals the Bayle law
    nc = laws.NaitChabane(W=0.7, criterion=W5, feedback=np.array([2.0, 3.0]))
    assert np.allclose(jax.jit(lambda qq: nc(ROBOT, TASK, qq, 0.0, xs, xsd).eta)(q), eta, atol=1e-12)
