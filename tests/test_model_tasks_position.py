"""mobman.model.tasks.position: Position against hand-derived forward kinematics (planar and 3-D robots, every
link, an offset point), its Jacobian against a closed form, central differences and autodiff, its errors."""

from __future__ import annotations

import math

import jax.numpy as jnp
import numpy as np
import pytest

from mobman import kinematics as K
from mobman.errors import ModelError
from mobman.model import robots
from mobman.model.tasks import Position

from task_checks import autodiff, central_differences, configurations


def _rot_z(angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def _bayle_planar_points(q: np.ndarray, l1: float = 0.5, l2: float = 0.5) -> list[np.ndarray]:
    """World points of the frames after joint 1, joint 2 and of the tool: (x, y) + the arm's planar chain."""
    x, y, theta, q4, q5 = q.T
    zero = np.zeros_like(x)
    joint2 = np.stack([x + l1 * np.cos(theta + q4), y + l1 * np.sin(theta + q4), zero], -1)
    tool = joint2 + np.stack([l2 * np.cos(theta + q4 + q5), l2 * np.sin(theta + q4 + q5), zero], -1)
    return [np.stack([x, y, zero], -1), joint2, tool]


BAYLE = robots.bayle_planar()
Q_BAYLE = configurations(BAYLE.n_q)


@pytest.mark.parametrize("link", [-1, 0, 1])
def test_link_positions_of_the_planar_arm_match_the_planar_chain(link):
    expected = _bayle_planar_points(Q_BAYLE)[link]
    got = np.asarray(K.forward(BAYLE, Q_BAYLE, Position(link=link)))
    np.testing.assert_allclose(got, expected, rtol=0, atol=1e-14)


def test_offset_point_is_carried_by_the_link_rotation():
    point = (0.1, -0.2, 0.3)
    expected = _bayle_planar_points(Q_BAYLE)[1] + np.stack(
        [_rot_z(t + a + b) @ point for t, a, b in Q_BAYLE[:, 2:]]
    )
    got = np.asarray(K.forward(BAYLE, Q_BAYLE, Position(link=1, point=point)))
    np.testing.assert_allclose(got, expected, rtol=0, atol=1e-14)


def test_planar_tool_jacobian_matches_its_closed_form_differences_and_autodiff():
    task = Position()
    x, y, theta, q4, q5 = Q_BAYLE.T
    s1, c1 = 0.5 * np.sin(theta + q4), 0.5 * np.cos(theta + q4)
    s12, c12 = 0.5 * np.sin(theta + q4 + q5), 0.5 * np.cos(theta + q4 + q5)
    one, zero = np.ones_like(x), np.zeros_like(x)
    expected = np.stack(
        [
            np.stack([one, zero, -s1 - s12, -s1 - s12, -s12], -1),
            np.stack([zero, one, c1 + c12, c1 + c12, c12], -1),
            np.zeros((len(x), 5)),
        ],
        1,
    )
    jac = np.asarray(K.jacobian(BAYLE, Q_BAYLE, task))
    np.testing.assert_allclose(jac, expected, rtol=0, atol=1e-14)
    np.testing.assert_allclose(central_differences(BAYLE, task, Q_BAYLE), expected, rtol=0, atol=1e-8)
    np.testing.assert_allclose(autodiff(BAYLE, task, Q_BAYLE), expected, rtol=0, atol=1e-14)
    # J̄ = J S with the differential drive's S = [(cos θ, sin θ, 0), (0, 0, 1)] in the platform columns
    reduced = np.asarray(K.reduced_jacobian(BAYLE, Q_BAYLE, task))
    forward_speed = expected[:, :, 0] * np.cos(theta)[:, None] + expected[:, :, 1] * np.sin(theta)[:, None]
    np.testing.assert_allclose(reduced[:, :, 0], forward_speed, rtol=0, atol=1e-14)
    np.testing.assert_allclose(reduced[:, :, 1:], expected[:, :, 2:], rtol=0, atol=1e-14)


MANUS = robots.manus_platform()
Q_MANUS = configurations(MANUS.n_q, seed=1)


def _manus_tool(q: np.ndarray, L2=0.12, L3=0.35, L4=0.35, a=0.12, b=0.12, c=0.4) -> np.ndarray:
    """Nait-Chabane's Manus: base at (a, b, c) in the platform frame, its frame turned by −π/2 (eq. 8),
    q_a2 and q_a3 absolute elevations."""
    out = []
    for x, y, theta, qa1, qa2, qa3 in q:
        local = np.array(
            [L3 * math.cos(qa2) + L4 * math.cos(qa3), L2, L3 * math.sin(qa2) + L4 * math.sin(qa3)]
        )
        out.append(
            np.array([x, y, 0.0])
            + _rot_z(theta) @ np.array([a, b, c])
            + _rot_z(theta - math.pi / 2 + qa1) @ local
        )
    return np.array(out)


def test_spatial_tool_position_and_jacobian_of_the_manus():
    task = Position()
    np.testing.assert_allclose(np.asarray(K.forward(MANUS, Q_MANUS, task)), _manus_tool(Q_MANUS), atol=1e-14)
    jac = np.asarray(K.jacobian(MANUS, Q_MANUS, task))
    assert jac.shape == (len(Q_MANUS), 3, MANUS.n_q)
    np.testing.assert_allclose(jac, central_differences(MANUS, task, Q_MANUS), rtol=0, atol=1e-8)
    np.testing.assert_allclose(jac, autodiff(MANUS, task, Q_MANUS), rtol=0, atol=1e-13)


def test_mounted_arm_tool_position_of_korayem_planar():
    robot = robots.korayem_planar(l0=0.4, l1=0.5, l2=0.5)
    q = configurations(robot.n_q, seed=2)
    x, y, theta, t1, t2 = q.T
    expected = np.stack(
        [
            x + 0.4 * np.cos(theta) + 0.5 * np.cos(theta + t1) + 0.5 * np.cos(theta + t1 + t2),
            y + 0.4 * np.sin(theta) + 0.5 * np.sin(theta + t1) + 0.5 * np.sin(theta + t1 + t2),
        ],
        -1,
    )
    np.testing.assert_allclose(np.asarray(K.forward(robot, q)), expected, rtol=0, atol=1e-14)
    jac = np.asarray(K.jacobian(robot, q))
    np.testing.assert_allclose(jac, central_differences(robot, robot.task, q), rtol=0, atol=1e-8)


def test_second_arm_of_the_dual_arm_robot():
    robot = robots.yamamoto_dual_arm()
    q = configurations(robot.n_q, n=8, seed=3)
    x, y, theta = q[:, :3].T
    angles = theta[:, None] + np.cumsum(q[:, 6:9], axis=1)
    expected = np.stack([x + 0.5 * np.cos(angles).sum(1), y + 0.5 * np.sin(angles).sum(1)], -1)
    task = Position("xy", arm=1)
    np.testing.assert_allclose(np.asarray(K.forward(robot, q, task)), expected, rtol=0, atol=1e-14)
    jac = np.asarray(K.jacobian(robot, q, task))
    np.testing.assert_array_equal(jac[:, :, 3:6], 0.0)  # the first arm's joints do not move the second tool


@pytest.mark.parametrize("components, rows", [("zx", [2, 0]), ("yzx", [1, 2, 0])])
def test_components_select_and_order_the_rows(components, rows):
    task = Position(components, label="tip")
    assert task.names == tuple(f"{c}_tip" for c in components)
    assert task.dim == len(components)
    np.testing.assert_allclose(
        np.asarray(K.forward(MANUS, Q_MANUS[:3], task)), _manus_tool(Q_MANUS[:3])[:, rows], atol=1e-14
    )
    full = np.asarray(K.jacobian(MANUS, Q_MANUS[:3], Position()))
    np.testing.assert_allclose(np.asarray(K.jacobian(MANUS, Q_MANUS[:3], task)), full[:, rows], atol=1e-15)


@pytest.mark.parametrize("components", ["", "xx", "w", "xyzx", "X", None])
def test_bad_components_are_refused(components):
    with pytest.raises(ModelError, match="task components .*use distinct letters among x, y, z"):
        Position(components)


@pytest.mark.parametrize(
    "task, match",
    [
        (Position(arm=1), "arm index 1 out of range 0..0"),
        (Position(arm=-1), "arm index -1 out of range"),
        (Position(link=2), "link index 2 out of range -1 \\(tool\\) .. 1"),
        (Position(link=-2), "link index -2 out of range"),
    ],
)
def test_an_arm_or_link_the_robot_lacks_is_refused(task, match):
    with pytest.raises(ModelError, match=match):
        task.check(BAYLE)
    with pytest.raises(ModelError, match=match):
        K.forward(BAYLE, Q_BAYLE[0], task)


def test_position_is_euclidean_and_never_representation_singular():
    task = Position()
    assert task.euclidean
    assert task.kind == "position"
    np.testing.assert_array_equal(np.asarray(task.error(jnp.array([1.0, 2.0, 3.0]), jnp.ones(3))), [0, 1, 2])
    assert not np.any(K.representation_singular(BAYLE, Q_BAYLE, task))
