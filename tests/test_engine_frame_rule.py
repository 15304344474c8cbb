"""The closed-form derivatives of a frame's pose and Jacobians (mobman.engine.frame_rule, the drop-in for
mobman.model.frame_jacobian), three ways: against autodiff through the chain, finite differences and a
hand-derived kinematic Hessian."""

from __future__ import annotations

import math

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from mobman import kinematics as K
from mobman.model import (
    Arm,
    CarLike,
    DifferentialDrive,
    EulerAngles,
    Joint,
    MobileManipulator,
    Mount,
    MountPosition,
    PlanarAngle,
    Position,
    robots,
    stack,
)
from mobman.model.frame_jacobian import frame_jacobian
from mobman.model.spatial import transform


def _coupled_prismatic_robot() -> MobileManipulator:
    """A car-like base with a 3D arm: revolute, prismatic, revolute, coupled joints 1 and 3."""
    joints = (
        Joint("revolute", (0.0, 0.0, 1.0), transform(None, (0.1, 0.0, 0.3))),
        Joint("prismatic", (1.0, 0.0, 0.0), transform(None, (0.0, 0.0, 0.2))),
        Joint("revolute", (0.0, 1.0, 0.0), transform(None, (0.3, 0.1, 0.0))),
    )
    arm = Arm(joints, tool=transform(None, (0.2, 0.0, 0.05)), coupling=(1, 0, 0, 0, 1, 0, 0.5, 0, 1))
    return MobileManipulator(CarLike(), (arm,), (Mount(0.3, 0.1, 0.2, yaw=0.4),), name="coupled")


def _two_arms() -> MobileManipulator:
    arm = robots.planar_arm((0.6, 0.4))
    return MobileManipulator(DifferentialDrive(), (arm, arm), (Mount(0.5), Mount(0.0, 0.3, 0.2, yaw=1.2)))


def _tool(frames, arm=0):
    return frames.links[arm][0][-1], frames.links[arm][1][-1]


def _offset_point_of_link_1(frames):
    r, p = frames.links[0][0][1], frames.links[0][1][1]
    return r, p + r @ jnp.array([0.1, -0.2, 0.3])


# (robot, arm, upto, frame): tool frames, an inner link's frame moved to an offset point, a mount frame
CASES = {
    "bayle-planar": (robots.bayle_planar(), 0, 1, _tool),
    "bayle-rrp": (robots.bayle_rrp(), 0, 2, _tool),
    "manus": (robots.manus_platform(), 0, 2, _tool),
    "tchon-car": (robots.tchon_car_rtr(), 0, 2, _tool),
    "coupled": (_coupled_prismatic_robot(), 0, 2, _tool),
    "coupled-link-1": (_coupled_prismatic_robot(), 0, 1, _offset_point_of_link_1),
    "second-arm": (_two_arms(), 1, 1, lambda f: _tool(f, arm=1)),
    "mount-frame": (_two_arms(), None, -1, lambda f: f.mounts[1]),
}


def _plain(robot, arm, upto, frame_of):
    """The same pose and columns, differentiated by autodiff through every frame of the chain."""

    def pose_and_columns(q):
        frames = robot.frames(q)
        r, p = frame_of(frames)
        return (r, p, *robot.point_jacobian(q, frames, p, arm, upto))

    return pose_and_columns


@pytest.mark.parametrize("case", CASES)
def test_derivative_rule_equals_autodiff_through_the_chain_and_finite_differences(case):
    robot, arm, upto, frame_of = CASES[case]
    ruled = jax.jit(lambda q: frame_jacobian(robot, frame_of, arm, upto, q))
    plain = jax.jit(_plain(robot, arm, upto, frame_of))
    derivatives = [jax.jit(d(ruled)) for d in (jax.jacfwd, jax.jacrev)]
    expected_derivative = jax.jit(jax.jacfwd(plain))
    h = 1e-6
    for q in np.random.default_rng(1).uniform(-2.0, 2.0, size=(3, robot.n_q)):
        for a, b in zip(ruled(q), plain(q)):
            np.testing.assert_allclose(a, b, atol=1e-13)
        expected = expected_derivative(q)
        for derivative in derivatives:
            for a, b in zip(derivative(q), expected):
                np.testing.assert_allclose(a, b, atol=1e-12)
        steps = h * np.eye(robot.n_q)
        up, down = jax.vmap(ruled)(q + steps), jax.vmap(ruled)(q - steps)  # leading axis: the steps
        for got, u, d in zip(derivatives[0](q), up, down):
            np.testing.assert_allclose(got, np.moveaxis((u - d) / (2 * h), 0, -1), atol=1e-8)


def test_kinematic_hessian_of_bayle_planar_in_closed_form():
    """∂J̄/∂q of the end-effector position rows of HILARE + planar 2R, derived by hand: with a = θ + q4,
    b = a + q5 and the tip (x', y') = (l1 cos a + l2 cos b, l1 sin a + l2 sin b) relative to the axle,
    J̄ = [[cos θ, −y', −y', −l2 sin b], [sin θ, x', x', l2 cos b]]."""
    l1, l2 = 0.7, 0.4
    robot = robots.bayle_planar(l1=l1, l2=l2)
    task = Position("xy")
    q = jnp.array([0.3, -1.2, 0.4, 1.1, -0.6])
    th, q4, q5 = (float(v) for v in q[2:])
    a, b = th + q4, th + q4 + q5
    xp, yp = l1 * math.cos(a) + l2 * math.cos(b), l1 * math.sin(a) + l2 * math.sin(b)
    tip_dot_b = np.array([-l2 * math.cos(b), -l2 * math.sin(b)])  # ∂/∂b of (−l2 sin b, l2 cos b)
    arm_col_dot = np.array([-xp, -yp])  # ∂/∂θ = ∂/∂q4 of (−y', x')
    expected = np.zeros((2, 4, 5))  # [row, column of J̄, coordinate]
    expected[:, 0, 2] = (-math.sin(th), math.cos(th))
    for k in (2, 3):
        expected[:, 1, k] = expected[:, 2, k] = arm_col_dot
        expected[:, 3, k] = tip_dot_b
    expected[:, 1, 4] = expected[:, 2, 4] = expected[:, 3, 4] = tip_dot_b
    for derivative in (jax.jacfwd, jax.jacrev):
        got = jax.jit(derivative(lambda qq: K.reduced_jacobian_one(robot, task, qq)))(q)
        np.testing.assert_allclose(got, expected, atol=1e-14)


@pytest.mark.parametrize(
    "robot",
    [
        _two_arms().with_task(stack(Position(arm=0), MountPosition("xy", arm=1), Position("z", arm=1))),
        _coupled_prismatic_robot().with_task(
            stack(Position(link=1, point=(0.1, 0.0, 0.2)), EulerAngles("ZYX"), PlanarAngle(link=0))
        ),
    ],
    ids=["positions-and-mount", "position-and-orientations"],
)
def test_task_jacobians_differentiate_through_the_rule(robot):
    """Position, mount and orientation tasks build J from the rule's frame and columns: the derivative
    of J equals the second derivative of ξ = f(q) by autodiff through the chain."""
    q = jnp.asarray(np.random.default_rng(2).uniform(-1.0, 1.0, robot.n_q))
    plain = jax.jacfwd(lambda qq: robot.task.value(robot, qq, robot.frames(qq)))
    np.testing.assert_allclose(K.jacobian(robot, q), jax.jit(plain)(q), atol=1e-13)
    expected = jax.jit(jax.jacfwd(plain))(q)
    for derivative in (jax.jacfwd, jax.jacrev):
        got = jax.jit(derivative(lambda qq: K.jacobian_one(robot, robot.task, qq)))(q)
        np.testing.assert_allclose(got, expected, atol=1e-12)
