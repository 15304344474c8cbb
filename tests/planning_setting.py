"""Tchoń, Jakubiak & Muszyński's (2002) planning setting shared by the planning tests: the car with the RTR arm,
its start poses Q0, and the fixtures (registered by conftest.py): the setting, its Jacobian grid and a
generic configuration z."""

from __future__ import annotations

import numpy as np
import pytest

from mobman.experiments import tchon2002

Q0 = np.stack([tchon2002.start_pose(n) for n in tchon2002.STARTS])


@pytest.fixture(scope="module")
def setting():
    return tchon2002.setting()


@pytest.fixture(scope="module")
def coarse(setting):
    """The planners' Jacobian grid: the variational-system checks run there (compiled once)."""
    return setting.jacobian_setting


@pytest.fixture(scope="module")
def z_test():
    """A generic configuration with all harmonics active (not the paper's nearly constant start)."""
    rng = np.random.default_rng(7)
    z = tchon2002.initial_configuration()
    z[:10] = rng.normal(scale=1.0, size=10)
    return z
