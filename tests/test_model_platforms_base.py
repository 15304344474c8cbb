"""The platform interface (mobman.model.platforms.base): controllability by Lie brackets, on the differential
drive, the car and the omnidirectional base."""

from __future__ import annotations

import jax.numpy as jnp

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
