"""mobman.model.tasks.orientation: OrientationTask's value g(R), its chain-rule Jacobian against differences
and autodiff, the margin test and the arm/link checks, with a test-only task (g any smooth function of R)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import jax.numpy as jnp
import numpy as np
import pytest

from mobman import kinematics as K
from mobman.errors import ModelError
from mobman.model import robots
from mobman.model.tasks import REPRESENTATION_TOL, task_kinds
from mobman.model.tasks.orientation import OrientationTask

from task_checks import autodiff, central_differences, configurations


@dataclass(frozen=True)
class Entries(OrientationTask):
    """g(R) = (R₀₂, R₁₀ R₂₁, R₂₂² + R₀₁), not angles but any smooth function of R will do; margin |R₂₂|."""

    @property
    def names(self) -> tuple[str, ...]:
        return ("a", "b", "c")

    def angles(self, r):
        return jnp.stack([r[0, 2], r[1, 0] * r[2, 1], r[2, 2] ** 2 + r[0, 1]])

    def margin(self, r):
        return jnp.abs(r[2, 2])


def _g(r: np.ndarray) -> np.ndarray:
    return np.stack([r[..., 0, 2], r[..., 1, 0] * r[..., 2, 1], r[..., 2, 2] ** 2 + r[..., 0, 1]], -1)


def _rot_z(a: np.ndarray) -> np.ndarray:
    c, s, z, o = np.cos(a), np.sin(a), np.zeros_like(a), np.ones_like(a)
    return np.stack([np.stack([c, -s, z], -1), np.stack([s, c, z], -1), np.stack([z, z, o], -1)], -2)


def _rot_y(a: np.ndarray) -> np.ndarray:
    c, s, z, o = np.cos(a), np.sin(a), np.zeros_like(a), np.ones_like(a)
    return np.stack([np.stack([c, z, s], -1), np.stack([z, o, z], -1), np.stack([-s, z, c], -1)], -2)


MANUS = robots.manus_platform()
Q_MANUS = configurations(MANUS.n_q)


def _manus_rotations(q: np.ndarray) -> list[np.ndarray]:
    """Frames after joints 1, 2, 3 and the tool: R_z(θ − π/2 + q_a1) (the arm frame is turned by −π/2,
    Nait-Chabane eq. 8) then the lift about −y by the absolute elevation (q_a2 for the upper arm, q_a3 for
    the forearm and the tool)."""
    heading = _rot_z(q[:, 2] - math.pi / 2 + q[:, 3])
    return [heading, heading @ _rot_y(-q[:, 4]), heading @ _rot_y(-q[:, 5]), heading @ _rot_y(-q[:, 5])]


@pytest.mark.parametrize("link", [-1, 0, 1])
def test_value_is_g_of_the_frame_rotation(link):
    expected = _g(_manus_rotations(Q_MANUS)[link])
    np.testing.assert_allclose(
        np.asarray(K.forward(MANUS, Q_MANUS, Entries(link=link))), expected, atol=1e-15
    )


@pytest.mark.parametrize("link", [-1, 1])
def test_chain_rule_jacobian_matches_differences_and_autodiff(link):
    task = Entries(link=link)
    jac = np.asarray(K.jacobian(MANUS, Q_MANUS, task))
    assert jac.shape == (len(Q_MANUS), 3, MANUS.n_q)
    np.testing.assert_allclose(jac, central_differences(MANUS, task, Q_MANUS), rtol=0, atol=1e-8)
    np.testing.assert_allclose(jac, autodiff(MANUS, task, Q_MANUS), rtol=0, atol=1e-14)
    if link == 1:  # the frame after joint 2 does not move with q_a3
        np.testing.assert_array_equal(jac[:, :, 5], 0.0)
    np.testing.assert_array_equal(jac[:, :, :2], 0.0)  # rotations do not depend on the platform position


def test_jacobian_of_a_frame_of_the_second_arm():
    robot = robots.yamamoto_dual_arm()
    q = configurations(robot.n_q, seed=1)
    task = Entries(arm=1, link=1)
    expected = _g(_rot_z(q[:, 2] + q[:, 6] + q[:, 7]))
    np.testing.assert_allclose(np.asarray(K.forward(robot, q, task)), expected, rtol=0, atol=1e-15)
    jac = np.asarray(K.jacobian(robot, q, task))
    np.testing.assert_allclose(jac, central_differences(robot, task, q), rtol=0, atol=1e-8)
    np.testing.assert_array_equal(jac[:, :, 3:6], 0.0)  # the first arm
    np.testing.assert_array_equal(jac[:, :, 8], 0.0)  # joint 3 of the second arm, after the frame


def test_representation_singular_where_the_margin_is_at_most_the_tolerance():
    """margin = |R₂₂| = |cos q_a3| for the Manus tool: singular at q_a3 = ±π/2 exactly, not 1e-6 away."""
    q = np.zeros((6, MANUS.n_q))
    q[:, 5] = [
        math.pi / 2,
        -math.pi / 2,
        math.pi / 2 + 1e-6,
        0.0,
        math.pi,
        math.pi / 2 - 0.5 * REPRESENTATION_TOL,
    ]
    np.testing.assert_array_equal(
        K.representation_singular(MANUS, q, Entries()), [True, True, False, False, False, True]
    )


def test_arm_and_link_are_keyword_only_and_checked():
    assert Entries(arm=0, link=1) == Entries(link=1)
    with pytest.raises(TypeError):
        Entries(0)
    with pytest.raises(ModelError, match="arm index 2 out of range 0..1"):
        Entries(arm=2).check(robots.yamamoto_dual_arm())
    with pytest.raises(ModelError, match="link index 3 out of range -1 \\(tool\\) .. 2"):
        K.forward(MANUS, Q_MANUS[0], Entries(link=3))
    with pytest.raises(ModelError, match="link index -2 out of range"):
        K.jacobian(MANUS, Q_MANUS[0], Entries(link=-2))


def test_a_subclass_without_a_kind_is_not_registered():
    assert Entries.kind == "" and "" not in task_kinds()


def test_the_base_class_leaves_the_angles_to_subclasses():
    with pytest.raises(NotImplementedError):
        OrientationTask().angles(jnp.eye(3))
    with pytest.raises(NotImplementedError):
        OrientationTask().margin(jnp.eye(3))
