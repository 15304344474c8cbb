"""mobman.model.tasks.euler_angles: the Jacobian against autodiff, the round trip through the rotation matrix, the
middle angle up to the gimbal lock."""

from __future__ import annotations

import math

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from mobman import kinematics as K
from mobman.model import (
    EulerAngles,
    Position,
    robots,
    stack,
)
from mobman.model.spatial import euler_angles, euler_matrix


@pytest.mark.parametrize("sequence", ["ZYZ", "ZYX", "XYZ", "ZXZ"])
def test_euler_angle_task_jacobian_matches_autodiff(sequence):
    robot = robots.manus_platform().with_task(stack(Position(), EulerAngles(sequence)))
    q = np.array([0.1, 0.2, 0.3, 0.4, 0.7, -0.2])
    j = np.asarray(K.jacobian(robot, q))
    auto = jax.jacfwd(lambda qq: robot.task.value(robot, qq, robot.frames(qq)))(jnp.asarray(q))
    np.testing.assert_allclose(j, auto, atol=1e-12)


@pytest.mark.parametrize("sequence", ["ZYZ", "ZYX", "XYZ", "ZXZ"])
def test_euler_angles_round_trip(sequence):
    a = np.array([0.3, 1.1, -0.7])
    np.testing.assert_allclose(euler_angles(jnp.asarray(euler_matrix(a, sequence)), sequence), a, atol=1e-12)


def _axis_rotation(axis: str, a: jnp.ndarray) -> jnp.ndarray:
    c, s = jnp.cos(a), jnp.sin(a)
    i, j = {"X": (1, 2), "Y": (2, 0), "Z": (0, 1)}[axis]
    r = jnp.eye(3)
    return r.at[i, i].set(c).at[j, j].set(c).at[i, j].set(-s).at[j, i].set(s)


@pytest.mark.parametrize("sequence", ["ZYX", "XYZ", "ZXY"])
@pytest.mark.parametrize("margin", [1.5e-8, 1e-6, 0.3])
def test_middle_euler_angle_has_unit_derivative_up_to_the_gimbal_lock(sequence, margin):
    """a2 of R_{s1}(a1) R_{s2}(a2) R_{s3}(a3) near a2 = π/2: ∂a2/∂a2 = 1 and ∂a1/∂a2 = ∂a3/∂a2 = 0, also a
    margin cos a2 of 1.5e-8 from the gimbal lock (an arcsin form gives NaN there)."""

    def angles(a2):
        r = (
            _axis_rotation(sequence[0], 0.4)
            @ _axis_rotation(sequence[1], a2)
            @ _axis_rotation(sequence[2], -0.8)
        )
        return euler_angles(r, sequence)

    a2 = math.acos(margin)
    np.testing.assert_allclose(angles(a2), [0.4, a2, -0.8], atol=1e-7)
    np.testing.assert_allclose(jax.jacfwd(angles)(a2), [0.0, 1.0, 0.0], atol=1e-6)
