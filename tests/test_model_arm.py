"""mobman.model.arm: a joint's pose after its motion, and arms from standard and modified DH tables against the
textbook products."""

from __future__ import annotations

import math

import jax.numpy as jnp
import numpy as np
import pytest

from mobman.model import (
    Arm,
    Joint,
)

PANDA_MDH = [
    (0, 0, 0, 0.333),
    (-math.pi / 2, 0, 0, 0),
    (math.pi / 2, 0, 0, 0.316),
    (math.pi / 2, 0.0825, 0, 0),
    (-math.pi / 2, -0.0825, 0, 0.384),
    (math.pi / 2, 0, 0, 0),
    (math.pi / 2, 0.088, 0, 0),
]


def _mdh_matrix(alpha, a, theta, d):
    ca, sa, ct, st_ = math.cos(alpha), math.sin(alpha), math.cos(theta), math.sin(theta)
    return np.array(
        [[ct, -st_, 0, a], [st_ * ca, ct * ca, -sa, -d * sa], [st_ * sa, ct * sa, ca, d * ca], [0, 0, 0, 1]]
    )


def _dh_matrix(theta, d, a, alpha):
    ca, sa, ct, st_ = math.cos(alpha), math.sin(alpha), math.cos(theta), math.sin(theta)
    return np.array(
        [[ct, -st_ * ca, st_ * sa, a * ct], [st_, ct * ca, -ct * sa, a * st_], [0, sa, ca, d], [0, 0, 0, 1]]
    )


@pytest.mark.parametrize("kind", ["revolute", "prismatic"])
def test_joint_pose_after_is_parent_then_origin_then_motion(kind):
    """Joint.pose_after (Rodrigues written with the constant factors as scalars) equals the parent pose times
    the origin transform times the motion built independently (SciPy's rotation vector), batched."""
    from scipy.spatial.transform import Rotation

    rng = np.random.default_rng(3)
    axis = rng.normal(size=3)
    axis /= np.linalg.norm(axis)
    origin, parent = np.eye(4), np.eye(4)
    origin[:3, :3] = Rotation.from_rotvec(rng.normal(size=3)).as_matrix()
    origin[:3, 3] = rng.normal(size=3)
    parent[:3, :3] = Rotation.from_rotvec(rng.normal(size=3)).as_matrix()
    parent[:3, 3] = rng.normal(size=3)
    joint = Joint(kind, tuple(axis), tuple(origin.ravel()), offset=0.3)
    q = rng.uniform(-3, 3, size=(4, 2))
    base = (jnp.broadcast_to(parent[:3, :3], (4, 2, 3, 3)), jnp.broadcast_to(parent[:3, 3], (4, 2, 3)))
    rot, p = joint.pose_after(base, jnp.asarray(q))
    assert rot.shape == (4, 2, 3, 3) and p.shape == (4, 2, 3)
    for index in np.ndindex(q.shape):
        motion = np.eye(4)
        value = q[index] + 0.3
        if kind == "revolute":
            motion[:3, :3] = Rotation.from_rotvec(value * axis).as_matrix()
        else:
            motion[:3, 3] = value * axis
        expected = parent @ origin @ motion
        np.testing.assert_allclose(rot[index], expected[:3, :3], atol=1e-14)
        np.testing.assert_allclose(p[index], expected[:3, 3], atol=1e-14)


def test_modified_dh_matches_textbook_product():
    arm = Arm.from_modified_dh(PANDA_MDH)
    q = np.random.default_rng(1).uniform(-2, 2, 7)
    expected = np.eye(4)
    for row, qi in zip(PANDA_MDH, q):
        alpha, a, theta, d = row
        expected = expected @ _mdh_matrix(alpha, a, theta + qi, d)
    rs, ps = arm.link_poses(jnp.asarray(q))
    np.testing.assert_allclose(rs[-1], expected[:3, :3], atol=1e-12)
    np.testing.assert_allclose(ps[-1], expected[:3, 3], atol=1e-12)


def test_standard_dh_with_prismatic_joint_matches_textbook_product():
    table = [(0.1, 0.3, 0.2, math.pi / 2), (0.0, 0.1, 0.0, -math.pi / 2), (0.4, 0.0, 0.3, 0.0)]
    arm = Arm.from_dh(table, "RPR")
    q = np.array([0.3, 0.25, -0.8])
    expected = np.eye(4)
    for (theta, d, a, alpha), qi, kind in zip(table, q, "RPR"):
        expected = expected @ (
            _dh_matrix(theta + qi, d, a, alpha) if kind == "R" else _dh_matrix(theta, d + qi, a, alpha)
        )
    rs, ps = arm.link_poses(jnp.asarray(q))
    np.testing.assert_allclose(rs[-1], expected[:3, :3], atol=1e-12)
    np.testing.assert_allclose(ps[-1], expected[:3, 3], atol=1e-12)
