"""mobman.dynamics.simulation: an unforced motion conserves its energy and the platform never slips."""

from __future__ import annotations

import numpy as np
import pytest

from mobman import dynamics as dyn

from dynamics_model import MODEL


@pytest.fixture(scope="module")
def unforced():
    q0 = np.array([0.3, -0.2, 0.5, 0.2, 0.6, -0.9])
    eta0 = np.array([0.4, 0.8, 1.0, -0.5, 0.7])
    return dyn.simulate(MODEL, q0, eta0, dyn.zero_torque, duration=5.0, dt=2e-3)


def test_energy_is_conserved_without_torques(unforced):
    e = np.asarray(dyn.energy(MODEL, unforced.q, unforced.eta))
    kinetic = e - np.asarray(dyn.potential_energy(MODEL, unforced.q))
    assert kinetic.max() - kinetic.min() > 0.1  # energy really moves between kinetic and potential
    assert np.max(np.abs(e - e[0])) <= 1e-6 * abs(e[0])


def test_simulated_platform_never_slips(unforced):
    """Lateral velocity from finite differences of the simulated path is zero to the O(dt²) = 4e-6 error of
    the central difference (a slipping platform would show lateral speeds of the order of its speed)."""
    q, dt = unforced.q, unforced.t[1]
    q_dot = (q[2:] - q[:-2]) / (2 * dt)
    theta = q[1:-1, 2]
    lateral = q_dot[:, 0] * np.sin(theta) - q_dot[:, 1] * np.cos(theta)
    speed = np.hypot(q_dot[:, 0], q_dot[:, 1])
    assert speed.max() > 0.1
    assert np.abs(lateral).max() < 1e-4 * speed.max()
