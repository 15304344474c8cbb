"""The augmented-Jacobian law (mobman.control.laws.augmented, Korayem et al.): the extra tasks tracked with the
main one to their end points, the constant determinant of Korayem eq. 36, and its errors."""

from __future__ import annotations

import numpy as np
import pytest

from mobman import ModelError, kinematics
from mobman.control import laws, references, simulate
from mobman.model import robots
from mobman.model.tasks import FunctionTask, MountPosition, PlanarAngle, Position, elbow_angle, stack

DT, DURATION = 0.01, 2.0


def test_augmented_jacobian_hits_end_points():
    robot = robots.korayem_planar()
    q0 = np.array([0.0, 0.0, 0.0, np.pi / 3, np.pi / 2])
    task = Position("xy")
    extra = stack(PlanarAngle(), FunctionTask(elbow_angle, ("beta",)))
    start = np.asarray(kinematics.forward(robot, q0, stack(task, extra)))
    end = start + np.array([0.8, 0.5, 0.3, -0.4])
    law = laws.AugmentedJacobian(extra=extra, feedback=5.0)
    res = simulate(robot, task, law, references.Line(start, end, 1.5, "quintic"), q0, DURATION, DT)
    np.testing.assert_allclose(res.xi, kinematics.forward(robot, res.q, stack(task, extra)), atol=1e-13)
    assert np.allclose(res.xi[-1], end, atol=1e-8)
    assert np.max(np.abs(res.error)) < 1e-6
    # Korayem eq. 36: det [J_c; J_e; J_z] = l0 whatever the configuration
    assert np.allclose(res.info["det"], 0.4, atol=1e-12)
    with pytest.raises(ModelError, match="extra"):
        simulate(
            robot,
            task,
            laws.AugmentedJacobian(extra=MountPosition("x")),
            references.Line((0,) * 3, (1,) * 3, 1.0),
            q0,
            0.1,
            DT,
        )


def test_augmented_jacobian_needs_an_extra_task():
    with pytest.raises(ModelError, match="extra"):
        laws.AugmentedJacobian(extra=None)
