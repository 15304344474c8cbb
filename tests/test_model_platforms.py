"""mobman.model.platforms: controllability by Lie brackets, wheel kinematics (Korayem eq. 14–15) and the car's
no-side-slip constraints."""

from __future__ import annotations

import jax.numpy as jnp
import numpy as np
import pytest

from mobman.model import (
    CarLike,
    DifferentialDrive,
    Omnidirectional,
)


def test_controllability_by_lie_brackets():
    assert DifferentialDrive().is_controllable()
    assert CarLike().lie_algebra_rank(jnp.array([0.0, 0.0, 0.0, 0.3])) == 4
    assert CarLike().lie_algebra_rank(jnp.zeros(4), depth=1) == 2
    assert Omnidirectional().is_controllable(depth=1)


def test_wheel_kinematics_round_trip_korayem_eq14_15():
    p = DifferentialDrive(wheel_radius=0.075, half_track=0.171)
    wheels = np.array([2.0, 1.0])
    v, w = np.asarray(p.wheel_speeds_to_eta(wheels))
    assert v == pytest.approx(0.075 * 1.5)
    assert w == pytest.approx(0.075 * 1.0 / (2 * 0.171))
    np.testing.assert_allclose(p.eta_to_wheel_speeds(np.array([v, w])), wheels, atol=1e-14)
    limits = DifferentialDrive(
        wheel_radius=0.075, half_track=0.171, wheel_speed_max=1 / 0.075
    ).velocity_limits
    assert limits == pytest.approx((1.0, 1.0 / 0.171))


def test_car_constraints_are_no_side_slip_of_both_axles():
    car = CarLike(length=1.3)
    q = jnp.array([0.0, 0.0, 0.4, 0.3])
    eta = jnp.array([0.7, 0.2])
    qd = car.S(q) @ eta
    front_velocity = qd[:2] + 1.3 * qd[2] * jnp.array([-jnp.sin(0.4), jnp.cos(0.4)])
    lateral = jnp.array([-jnp.sin(0.7), jnp.cos(0.7)])
    assert abs(float(front_velocity @ lateral)) < 1e-14
