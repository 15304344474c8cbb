"""The differential drive (mobman.model.platforms.differential): wheel speeds to (v, ω) and back (Korayem
eq. 14–15), and the (v, ω) limits of a wheel speed limit."""

from __future__ import annotations

import numpy as np
import pytest

from mobman.model import (
    DifferentialDrive,
)


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
