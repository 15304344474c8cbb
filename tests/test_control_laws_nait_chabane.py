"""Nait-Chabane's law (mobman.control.laws.nait_chabane, Nait-Chabane et al. eq. 30) at one configuration:
u = J̄⁺(Ẋd + K e) − (I − J̄⁺J̄) W (∂P/∂q · S)ᵀ against NumPy's pseudo-inverse, for a general positive-definite
weighting W, open and closed loop, at headings 0.3, ±π/2 and π; and its errors."""

from __future__ import annotations

import math

import jax.numpy as jnp
import numpy as np
import pytest

from mobman import ModelError, kinematics
from mobman.control import criteria, laws
from mobman.model import robots
from mobman.model.tasks import Position

ROBOT = robots.bayle_planar()
TASK = Position("xy")
W5 = criteria.Manipulability("eccentricity", "system", power=2)
W_MATRIX = np.array([[2.0, 0.3, 0.0, 0.1], [0.3, 1.0, 0.2, 0.0], [0.0, 0.2, 1.5, 0.4], [0.1, 0.0, 0.4, 0.8]])


def expected(q, xs, xsd, w, k):
    """Eq. 30 computed from the model's J̄, S and the criterion's gradient with NumPy."""
    jbar = np.asarray(kinematics.reduced_jacobian(ROBOT, q, TASK))
    pinv = np.linalg.pinv(jbar)
    e = np.asarray(xs) - np.asarray(kinematics.forward(ROBOT, q, TASK))
    grad = np.asarray(W5.gradient(ROBOT, q, TASK)) @ np.asarray(kinematics.S(ROBOT, q))
    feedback = 0.0 if k is None else k * e
    return pinv @ (np.asarray(xsd) + feedback) - (np.eye(4) - pinv @ jbar) @ (w @ grad)


@pytest.mark.parametrize("theta", [0.3, math.pi / 2, -math.pi / 2, math.pi])
@pytest.mark.parametrize("k", [None, np.array([2.0, 3.0])])
def test_eq_30_with_a_general_weighting(theta, k):
    q = jnp.array([0.2, 0.1, theta, 0.7, 1.1])
    xs, xsd = jnp.array([1.3, 0.6]), jnp.array([0.1, -0.2])
    law = laws.NaitChabane(W=W_MATRIX, criterion=W5, feedback=k)
    eta = np.asarray(law(ROBOT, TASK, q, 0.0, xs, xsd).eta)
    np.testing.assert_allclose(eta, expected(q, xs, xsd, W_MATRIX, k), rtol=0, atol=1e-12)
    # the task part is untouched by the self-motion: J̄ u = Ẋd (+ K e)
    jbar = np.asarray(kinematics.reduced_jacobian(ROBOT, q, TASK))
    e = np.asarray(xs) - np.asarray(kinematics.forward(ROBOT, q, TASK))
    np.testing.assert_allclose(jbar @ eta, np.asarray(xsd) + (0.0 if k is None else k * e), atol=1e-12)


def test_without_a_criterion_the_law_is_the_pseudo_inverse():
    q = jnp.array([0.2, 0.1, 0.3, 0.7, 1.1])
    xs, xsd = jnp.array([1.3, 0.6]), jnp.array([0.1, -0.2])
    eta = np.asarray(laws.NaitChabane(W=W_MATRIX)(ROBOT, TASK, q, 0.0, xs, xsd).eta)
    jbar = np.asarray(kinematics.reduced_jacobian(ROBOT, q, TASK))
    np.testing.assert_allclose(eta, np.linalg.pinv(jbar) @ np.asarray(xsd), rtol=0, atol=1e-12)


@pytest.mark.parametrize(
    ("options", "field"),
    [({"W": -1.0}, "W"), ({"W": np.diag([1.0, 1.0, 0.0, 1.0])}, "W"), ({"feedback": -2.0}, "feedback")],
)
def test_gains_must_be_positive(options, field):
    with pytest.raises(ModelError, match=field):
        laws.NaitChabane(**options)
