"""mobman.model.tasks.mount_position: MountPosition against the platform pose and mount offset, its Jacobian
against a closed form, differences and autodiff, component selection and the constructor's errors."""

from __future__ import annotations

import numpy as np
import pytest

from mobman import kinematics as K
from mobman.errors import ModelError
from mobman.model import robots
from mobman.model.tasks import MountPosition, task_class

from task_checks import autodiff, central_differences, configurations


def test_korayem_base_point_is_l0_ahead_of_the_axle():
    """Korayem eq. 37: F = (x + l0 cos θ, y + l0 sin θ); its Jacobian has no arm columns."""
    robot = robots.korayem_planar(l0=0.4)
    q = configurations(robot.n_q)
    x, y, theta = q[:, :3].T
    task = MountPosition()
    got = np.asarray(K.forward(robot, q, task))
    np.testing.assert_allclose(
        got, np.stack([x + 0.4 * np.cos(theta), y + 0.4 * np.sin(theta)], -1), atol=1e-15
    )
    expected = np.zeros((len(q), 2, robot.n_q))
    expected[:, 0, 0] = expected[:, 1, 1] = 1.0
    expected[:, 0, 2] = -0.4 * np.sin(theta)
    expected[:, 1, 2] = 0.4 * np.cos(theta)
    np.testing.assert_allclose(np.asarray(K.jacobian(robot, q, task)), expected, rtol=0, atol=1e-15)
    np.testing.assert_allclose(central_differences(robot, task, q), expected, rtol=0, atol=1e-9)
    np.testing.assert_allclose(autodiff(robot, task, q), expected, rtol=0, atol=1e-15)
    # J̄ = J S: the base point moves with v along the heading and l0 ω across it
    reduced = np.asarray(K.reduced_jacobian(robot, q, task))
    np.testing.assert_allclose(reduced[:, :, 0], np.stack([np.cos(theta), np.sin(theta)], -1), atol=1e-15)
    np.testing.assert_allclose(reduced[:, :, 1], expected[:, :, 2], atol=1e-15)
    np.testing.assert_array_equal(reduced[:, :, 2:], 0.0)


def test_spatial_mount_of_the_manus_with_every_component():
    """Nait-Chabane's arm base (a, b, c) in the platform frame: (x, y, 0) + R_z(θ) (a, b, c)."""
    robot = robots.manus_platform(a=0.12, b=-0.05, c=0.4)
    q = configurations(robot.n_q, seed=1)
    x, y, theta = q[:, :3].T
    c, s = np.cos(theta), np.sin(theta)
    expected = np.stack([x + 0.12 * c + 0.05 * s, y + 0.12 * s - 0.05 * c, np.full_like(x, 0.4)], -1)
    task = MountPosition("xyz")
    np.testing.assert_allclose(np.asarray(K.forward(robot, q, task)), expected, rtol=0, atol=1e-15)
    jac = np.asarray(K.jacobian(robot, q, task))
    np.testing.assert_allclose(jac, central_differences(robot, task, q), rtol=0, atol=1e-9)
    np.testing.assert_allclose(jac, autodiff(robot, task, q), rtol=0, atol=1e-15)
    np.testing.assert_array_equal(jac[:, 2], 0.0)
    np.testing.assert_array_equal(jac[:, :, 3:], 0.0)


@pytest.mark.parametrize("components, rows", [("yx", [1, 0]), ("z", [2]), ("xy", [0, 1])])
def test_components_select_and_order_the_rows(components, rows):
    robot = robots.manus_platform()
    q = configurations(robot.n_q, seed=2)[:4]
    task = MountPosition(components)
    assert task.names == tuple(f"{c}_f" for c in components)
    full = np.asarray(K.forward(robot, q, MountPosition("xyz")))
    np.testing.assert_allclose(np.asarray(K.forward(robot, q, task)), full[:, rows], rtol=0, atol=0)


def test_second_arm_mount_of_the_dual_arm_robot_is_the_axle_midpoint():
    robot = robots.yamamoto_dual_arm()
    q = configurations(robot.n_q, seed=3)
    np.testing.assert_allclose(np.asarray(K.forward(robot, q, MountPosition(arm=1))), q[:, :2], atol=1e-15)


def test_default_kind_and_names():
    assert MountPosition().names == ("x_f", "y_f")
    assert task_class("mount_position") is MountPosition
    assert MountPosition().euclidean


@pytest.mark.parametrize("components", ["", "xz x", "xx", "q", 3])
def test_bad_components_are_refused(components):
    with pytest.raises(ModelError, match="task components .*use distinct letters among x, y, z"):
        MountPosition(components)


@pytest.mark.parametrize("arm", [1, -1, 5])
def test_an_arm_the_robot_lacks_is_refused(arm):
    robot = robots.korayem_planar()
    with pytest.raises(ModelError, match=f"arm index {arm} out of range 0..0"):
        K.forward(robot, np.zeros(robot.n_q), MountPosition(arm=arm))
