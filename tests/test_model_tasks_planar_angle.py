"""mobman.model.tasks.planar_angle: the planar angle is the sum of the platform's and the joints' angles."""

from __future__ import annotations

import numpy as np
import pytest

from mobman import kinematics as K
from mobman.model import (
    PlanarAngle,
    robots,
)


def test_planar_angle_equals_angle_sum():
    robot = robots.bayle_planar()
    q = np.array([0.0, 0.0, 0.2, 0.3, 0.4])
    assert float(K.forward(robot, q, PlanarAngle())[0]) == pytest.approx(0.9)
