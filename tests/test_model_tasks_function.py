"""mobman.model.tasks.function: a task from a user function (the elbow angle), its value and Jacobian."""

from __future__ import annotations

import math

import numpy as np
import pytest

from mobman import kinematics as K
from mobman.model import (
    FunctionTask,
    robots,
)
from mobman.model.tasks import elbow_angle


def test_function_task_elbow_angle():
    robot = robots.korayem_planar()
    task = FunctionTask(elbow_angle, ("beta",))
    q = np.array([0, 0, 0, 0.3, 1.0])
    assert float(K.forward(robot, q, task)[0]) == pytest.approx(math.pi - 1.0)
    np.testing.assert_allclose(K.jacobian(robot, q, task), [[0, 0, 0, 0, -1]])
