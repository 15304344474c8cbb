"""The kinematic car (mobman.model.platforms.car): its constraints are no side slip of both axles."""

from __future__ import annotations

import jax.numpy as jnp

from mobman.model import (
    CarLike,
)


def test_car_constraints_are_no_side_slip_of_both_axles():
    car = CarLike(length=1.3)
    q = jnp.array([0.0, 0.0, 0.4, 0.3])
    eta = jnp.array([0.7, 0.2])
    qd = car.S(q) @ eta
    front_velocity = qd[:2] + 1.3 * qd[2] * jnp.array([-jnp.sin(0.4), jnp.cos(0.4)])
    lateral = jnp.array([-jnp.sin(0.7), jnp.cos(0.7)])
    assert abs(float(front_velocity @ lateral)) < 1e-14
