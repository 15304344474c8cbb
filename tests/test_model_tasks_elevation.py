"""mobman.model.tasks.elevation: Elevation against the RRP and Manus lift angles over the whole turn, its
Jacobian against a closed form, differences and autodiff, its singularity where the y axis is vertical."""

from __future__ import annotations

import math

import numpy as np
import pytest

from mobman import kinematics as K
from mobman.errors import ModelError
from mobman.model import Arm, DifferentialDrive, Joint, MobileManipulator, robots
from mobman.model.tasks import Elevation, task_class

from task_checks import autodiff, central_differences, configurations


def _wrapped_difference(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """a − b on the circle, in (−π, π]."""
    return np.angle(np.exp(1j * (np.asarray(a) - np.asarray(b))))


RRP = robots.bayle_rrp()
MANUS = robots.manus_platform()


def test_elevation_of_the_rrp_arm_is_q5_over_the_whole_turn():
    """Bayle §5.2: ξ5 = q5, through the vertical (q5 = ±π/2) and past it, whatever the heading and q4."""
    q = configurations(RRP.n_q)
    q[:, 5] = np.abs(q[:, 5])  # the prismatic joint's lower limit is 0
    got = np.asarray(K.forward(RRP, q, Elevation()))
    assert got.shape == (len(q), 1)
    np.testing.assert_allclose(_wrapped_difference(got[:, 0], q[:, 4]), 0.0, rtol=0, atol=1e-14)
    assert np.all((got > -math.pi) & (got <= math.pi))
    expected = np.zeros((len(q), 1, RRP.n_q))
    expected[:, 0, 4] = 1.0
    np.testing.assert_allclose(np.asarray(K.jacobian(RRP, q, Elevation())), expected, rtol=0, atol=1e-14)
    np.testing.assert_allclose(
        central_differences(RRP, Elevation(), q, angles=True), expected, rtol=0, atol=1e-8
    )
    np.testing.assert_allclose(autodiff(RRP, Elevation(), q), expected, rtol=0, atol=1e-14)
    assert not np.any(K.representation_singular(RRP, q, Elevation()))


@pytest.mark.parametrize("link, joint", [(-1, 5), (2, 5), (1, 4), (0, None)])
def test_elevation_of_each_manus_frame_is_its_absolute_lift_angle(link, joint):
    """The Manus's q_a2, q_a3 are absolute elevations (parallelogram coupling): the tool and the frame after
    joint 3 have elevation q_a3, the frame after joint 2 q_a2, the frame after joint 1 none."""
    q = configurations(MANUS.n_q, seed=1)
    task = Elevation(link=link)
    got = np.asarray(K.forward(MANUS, q, task))[:, 0]
    expected_value = np.zeros(len(q)) if joint is None else q[:, joint]
    np.testing.assert_allclose(_wrapped_difference(got, expected_value), 0.0, rtol=0, atol=1e-14)
    expected = np.zeros((len(q), 1, MANUS.n_q))
    if joint is not None:
        expected[:, 0, joint] = 1.0
    jac = np.asarray(K.jacobian(MANUS, q, task))
    np.testing.assert_allclose(jac, expected, rtol=0, atol=1e-14)
    np.testing.assert_allclose(central_differences(MANUS, task, q, angles=True), expected, rtol=0, atol=1e-8)


def _roll_robot() -> MobileManipulator:
    """One revolute joint about the platform's x axis: the tool's y axis is vertical at a roll of ±π/2."""
    return MobileManipulator(DifferentialDrive(), (Arm((Joint("revolute", (1.0, 0.0, 0.0), name="roll"),)),))


def test_elevation_is_representation_singular_where_the_y_axis_is_vertical():
    """With R = R_z(θ) R_x(φ): R₂₀ = 0 and R₂₂ = cos φ, so the elevation is 0 or π, undefined at φ = ±π/2."""
    robot = _roll_robot()
    phi = np.array([0.0, 0.3, math.pi / 2, -math.pi / 2, math.pi / 2 + 1e-6, 2.0, math.pi])
    q = np.stack([np.full_like(phi, 0.5), np.full_like(phi, -0.2), np.full_like(phi, 1.1), phi], -1)
    singular = K.representation_singular(robot, q, Elevation())
    np.testing.assert_array_equal(singular, [False, False, True, True, False, False, False])
    got = np.asarray(K.forward(robot, q, Elevation()))[:, 0]
    regular = ~singular
    expected = np.where(np.cos(phi) > 0, 0.0, math.pi)
    np.testing.assert_allclose(_wrapped_difference(got[regular], expected[regular]), 0.0, atol=1e-14)


def test_elevation_names_kind_and_errors():
    assert Elevation().names == ("elevation",) and Elevation().dim == 1
    assert task_class("elevation") is Elevation
    assert Elevation(link=1, arm=0) == Elevation(arm=0, link=1)
    with pytest.raises(TypeError):
        Elevation(0)  # arm and link are keyword-only
    with pytest.raises(ModelError, match="arm index 1 out of range 0..0"):
        K.forward(RRP, np.zeros(RRP.n_q), Elevation(arm=1))
    with pytest.raises(ModelError, match="link index 3 out of range -1 \\(tool\\) .. 2"):
        K.forward(RRP, np.zeros(RRP.n_q), Elevation(link=3))
