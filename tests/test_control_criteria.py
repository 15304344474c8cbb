"""mobman.control.criteria: the cubic transition's boundary conditions, the criteria's gradients against finite
differences, the manipulability criterion's sign and the blend, and their errors."""

from __future__ import annotations

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from mobman import ModelError
from mobman.control import criteria
from mobman.model import robots
from mobman.model.tasks import Position

ROBOT = robots.bayle_planar()
TASK = Position("xy")


def test_cubic_transition_boundary_conditions():
    alpha = criteria.CubicTransition(start=1.0, end=3.0, coordinate=1)
    da = jax.grad(lambda s: alpha(jnp.array([0.0, s])))
    assert float(alpha(np.array([9.0, 1.0]))) == pytest.approx(1.0)
    assert float(alpha(np.array([9.0, 3.0]))) == pytest.approx(0.0)
    assert float(da(1.0)) == pytest.approx(0.0, abs=1e-12)
    assert float(da(3.0)) == pytest.approx(0.0, abs=1e-12)
    s = np.linspace(0.0, 4.0, 41)
    values = np.asarray(alpha(np.stack([0 * s, s], -1)))
    assert np.all(np.diff(values) <= 1e-15) and values.min() >= 0 and values.max() <= 1
    assert float(alpha(np.array([0.0, 2.0]))) == pytest.approx(0.5)  # cubic symmetric about the middle


def test_criterion_gradients_match_finite_differences():
    q = np.array([0.3, -0.2, 0.4, 0.7, 1.1])
    blend = criteria.Blend(
        criteria.Manipulability("eccentricity", "system"),
        criteria.Manipulability("eccentricity", "arm"),
        criteria.CubicTransition(0.0, 2.0),
    )
    xs = np.array([1.0, 0.0])
    for crit in (criteria.Manipulability("yoshikawa", "arm"), blend):
        grad = np.asarray(jax.jit(lambda qq, crit=crit: crit.gradient(ROBOT, qq, TASK, xs))(q))
        values = jax.jit(jax.vmap(lambda qq, crit=crit: crit(ROBOT, qq, TASK, xs)))(
            q + 1e-6 * np.concatenate([np.eye(5), -np.eye(5)])
        )
        assert np.allclose(grad, (values[:5] - values[5:]) / 2e-6, atol=1e-6)


def test_manipulability_sign_convention_and_blend():
    q = np.array([0.0, 0.0, 0.0, 0.7, 1.1])
    from mobman import manipulability as mp

    w = float(mp.measures(mp.arm_jacobian(ROBOT, q, TASK))["yoshikawa"])
    assert float(criteria.Manipulability("yoshikawa", "arm")(ROBOT, q, TASK)) == pytest.approx(-w)
    sys_p, arm_p = criteria.Manipulability(which="system"), criteria.Manipulability(which="arm")
    blend = criteria.Blend(sys_p, arm_p, criteria.CubicTransition(0.0, 2.0))
    for s, a in ((-1.0, 1.0), (1.0, 0.5), (3.0, 0.0)):
        expected = a * sys_p(ROBOT, q, TASK) + (1 - a) * arm_p(ROBOT, q, TASK)
        assert float(blend(ROBOT, q, TASK, np.array([s, 0.0]))) == pytest.approx(float(expected))


def test_criterion_errors():
    with pytest.raises(ModelError, match="measure"):
        criteria.Manipulability("roundness")
    with pytest.raises(ModelError, match="which"):
        criteria.Manipulability(which="platform")
    with pytest.raises(ModelError, match="start"):
        criteria.CubicTransition(1.0, 1.0)
