"""A platform's inertia model (Platform.inertia_bodies, model/platforms/base.py): the default bodies, and a
platform defined here that adds a body, against the closed-form kinetic energy of a point mass on the
platform."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from mobman import dynamics
from mobman.model import Arm, DifferentialDrive, MobileManipulator, Mount
from mobman.model.arm import LinkInertial
from mobman.model.inertial import PlatformBody, Wheel
from mobman.model.platforms.base import RigidPart

LINKS = (
    LinkInertial(4.0, (-0.25, 0.0, 0.0), (0.01, 0, 0, 0, 0.08, 0, 0, 0, 0.08)),
    LinkInertial(2.5, (-0.2, 0.0, 0.0), (0.005, 0, 0, 0, 0.03, 0, 0, 0, 0.03)),
)
BODY, WHEEL = PlatformBody(30.0, 1.8, (0.05, 0.0, 0.1)), Wheel(1.5, 0.02, 0.01)
MASS, AT = 7.0, (0.3, -0.12, 0.4)


@dataclass(frozen=True)
class LoadedDrive(DifferentialDrive):
    """A differential drive carrying a point mass MASS at AT (platform frame), e.g. a battery pack."""

    kind: ClassVar[str] = "test_loaded_drive"

    def inertia_bodies(self, body: PlatformBody, wheel: Wheel | None) -> tuple[RigidPart, ...]:
        return super().inertia_bodies(body, wheel) + (RigidPart(MASS, AT, np.zeros((3, 3))),)


def _model(platform) -> dynamics.DynamicModel:
    arm = Arm.from_dh([[0.0, 0.3, 0.5, 0.0], [0.0, 0.0, 0.4, 0.0]], "RR")
    robot = MobileManipulator(platform, (arm,), (Mount(0.1, 0.0, 0.2),)).with_link_inertials(LINKS)
    return dynamics.DynamicModel(robot, BODY, WHEEL)


def test_the_default_bodies_are_the_body_and_the_driven_wheels():
    platform = DifferentialDrive(wheel_radius=0.1, half_track=0.25)
    parts = platform.inertia_bodies(BODY, WHEEL)
    assert [p.mass for p in parts] == [30.0, 1.5, 1.5]
    assert parts[0].centre == BODY.com and parts[0].inertia[2, 2] == 1.8
    assert {p.centre for p in parts[1:]} == {(0.0, -0.25, 0.1), (0.0, 0.25, 0.1)}
    np.testing.assert_array_equal(parts[1].inertia, np.diag([0.01, 0.0, 0.01]))
    assert len(platform.inertia_bodies(BODY, None)) == 1


def test_a_body_a_platform_adds_enters_the_reduced_mass_matrix_as_its_kinetic_energy():
    """A point mass m at (x0, y0) on a unicycle moves at (v − ω y0, ω x0) in the platform frame, so it adds
    m [[1, −y0], [−y0, x0² + y0²]] to P's (v, ω) block and nothing elsewhere."""
    base = DifferentialDrive(wheel_radius=0.1, half_track=0.25)
    loaded = LoadedDrive(wheel_radius=0.1, half_track=0.25)
    rng = np.random.default_rng(3)
    q = rng.uniform(-math.pi, math.pi, (8, 5))
    q[:4, 2] = [math.pi / 2, -math.pi / 2, math.pi, -math.pi]
    q[:, :2] = rng.uniform(-2.0, 2.0, (8, 2))
    added = np.asarray(dynamics.reduced_mass_matrix(_model(loaded), q)) - np.asarray(
        dynamics.reduced_mass_matrix(_model(base), q)
    )
    x0, y0, _ = AT
    expected = np.zeros((4, 4))
    expected[:2, :2] = MASS * np.array([[1.0, -y0], [-y0, x0**2 + y0**2]])
    np.testing.assert_allclose(added, np.broadcast_to(expected, added.shape), atol=1e-12)
