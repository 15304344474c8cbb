"""mobman.model.platforms.omnidirectional: the holonomic base — S = I (world-frame velocities), no constraint,
velocity limits and their validation, controllability at depth 1, at headings 0, ±π/2 and π."""

from __future__ import annotations

import math

import jax.numpy as jnp
import numpy as np
import pytest
import sympy as sp

from mobman import kinematics as K
from mobman.errors import ModelError
from mobman.model import MobileManipulator, Omnidirectional, platform_class, robots
from mobman.model.tasks import Position

HEADINGS = (0.0, math.pi / 2, -math.pi / 2, math.pi, 0.7)


@pytest.mark.parametrize("theta", HEADINGS)
def test_s_is_the_identity_and_there_is_no_constraint(theta):
    platform = Omnidirectional()
    q_p = jnp.array([0.4, -1.2, theta])
    np.testing.assert_array_equal(np.asarray(platform.S(q_p)), np.eye(3))
    g = np.asarray(platform.constraints(q_p))
    assert g.shape == (0, 3)
    np.testing.assert_array_equal(np.asarray(platform.actuator_rows(q_p)), np.eye(3))


@pytest.mark.parametrize("theta", HEADINGS)
def test_controllable_with_the_vector_fields_alone(theta):
    platform = Omnidirectional()
    q_p = jnp.array([1.0, 2.0, theta])
    assert platform.lie_algebra_rank(q_p, depth=1) == 3
    assert platform.is_controllable(q_p, depth=1)


def _robot() -> MobileManipulator:
    return MobileManipulator(
        Omnidirectional(limits=(0.5, 0.4, 1.0)), (robots.planar_arm((0.5, 0.3), velocity_max=(2.0, 3.0)),)
    )


def test_quasi_velocities_are_world_frame_velocities_of_the_platform():
    """η_p = (ẋ, ẏ, θ̇) in the world frame: a unit η_x moves the tool along the world x axis at every
    heading, and J̄ = J."""
    robot = _robot()
    q = np.array([[0.3, -0.1, theta, 0.4, -0.8] for theta in HEADINGS])
    s = np.asarray(K.S(robot, q))
    np.testing.assert_array_equal(s, np.broadcast_to(np.eye(5), (len(q), 5, 5)))
    assert np.asarray(K.constraints(robot, q)).shape == (len(q), 0, 5)
    jac = np.asarray(K.jacobian(robot, q, Position("xy")))
    reduced = np.asarray(K.reduced_jacobian(robot, q, Position("xy")))
    np.testing.assert_array_equal(reduced, jac)
    np.testing.assert_allclose(reduced[:, :, :2], np.broadcast_to(np.eye(2), (len(q), 2, 2)), atol=0)
    # θ̇ swings the tool about the platform origin: (−(y_e − y), x_e − x)
    theta, q1, q2 = q[:, 2], q[:, 3], q[:, 4]
    dx = 0.5 * np.cos(theta + q1) + 0.3 * np.cos(theta + q1 + q2)
    dy = 0.5 * np.sin(theta + q1) + 0.3 * np.sin(theta + q1 + q2)
    np.testing.assert_allclose(reduced[:, :, 2], np.stack([-dy, dx], -1), rtol=0, atol=1e-15)


def test_names_dimensions_and_actuators():
    platform = Omnidirectional()
    assert platform.coordinate_names == ("x", "y", "theta")
    assert platform.control_names == ("vx", "vy", "omega")
    assert (platform.n_q, platform.n_eta) == (3, 3)
    assert platform.actuator_names == ("platform_vx", "platform_vy", "platform_omega")
    np.testing.assert_array_equal(platform.actuator_matrix(), np.eye(3))
    assert platform.wheels() == () and not platform.wheel_actuated
    assert platform_class("omnidirectional") is Omnidirectional


def test_symbolic_forms_are_the_identity_and_no_rows():
    q = sp.symbols("x y theta")
    platform = Omnidirectional()
    assert platform.symbolic_S(q, {}) == sp.eye(3)
    assert platform.symbolic_constraints(q, {}).shape == (0, 3)


def test_not_a_constant_body_twist_platform():
    """S = I is not R(θ) B with a constant B."""
    assert not Omnidirectional.constant_body_twist
    with pytest.raises(ModelError, match="Omnidirectional: S\\(q_p\\) is not R\\(θ\\) B"):
        Omnidirectional().body_twist_matrix()


def test_limits_are_stored_as_floats_and_are_the_velocity_limits():
    assert Omnidirectional().limits is None and Omnidirectional().velocity_limits is None
    platform = Omnidirectional(limits=(1, 2, np.float32(0.5)))
    assert platform.limits == (1.0, 2.0, 0.5) and all(type(v) is float for v in platform.limits)
    assert platform.velocity_limits == (1.0, 2.0, 0.5)
    assert platform == Omnidirectional(limits=[1.0, 2.0, 0.5])
    assert _robot().velocity_limits == (0.5, 0.4, 1.0, 2.0, 3.0)


@pytest.mark.parametrize(
    "limits, match",
    [
        ((1.0, 2.0), "Omnidirectional: limits needs 3 values, got 2"),
        ((1.0, 2.0, 3.0, 4.0), "Omnidirectional: limits needs 3 values, got 4"),
        ((1.0, 0.0, 1.0), "Omnidirectional: limits must be a finite number > 0"),
        ((1.0, -2.0, 1.0), "Omnidirectional: limits must be a finite number > 0"),
        ((1.0, 1.0, math.inf), "Omnidirectional: limits must be finite"),
    ],
)
def test_bad_limits_are_refused(limits, match):
    with pytest.raises(ModelError, match=f"^{match}"):
        Omnidirectional(limits=limits)
