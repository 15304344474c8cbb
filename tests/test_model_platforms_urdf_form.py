"""The URDF form of a platform (model/platforms/urdf_form.py): a platform defined here, with its own
``from_urdf`` and ``urdf_joints``, is written and read by mobman.io.urdf with no edit there; the reader's
errors for the built-in kinds."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np
import pytest

from mobman import ModelError, dynamics, kinematics
from mobman.io.urdf import read_urdf, urdf_tips, write_urdf
from mobman.model import Arm, DifferentialDrive, MobileManipulator, Mount
from mobman.model.arm import LinkInertial
from mobman.model.platforms import platform_class
from mobman.model.platforms.urdf_form import (
    UrdfJoint,
    UrdfPlatform,
    UrdfReader,
    UrdfWheel,
    distance,
    midpoint,
)

LINKS = (
    LinkInertial(4.0, (-0.25, 0.0, 0.0), (0.01, 0, 0, 0, 0.08, 0, 0, 0, 0.08)),
    LinkInertial(2.5, (-0.2, 0.0, 0.0), (0.005, 0, 0, 0, 0.03, 0, 0, 0, 0.03)),
)
BODY, WHEEL = dynamics.PlatformBody(30.0, 1.8, (0.0, 0.0, 0.1)), dynamics.Wheel(1.5, 0.02, 0.01)


@dataclass(frozen=True)
class CasterDrive(DifferentialDrive):
    """A differential drive with a passive caster ``caster_behind`` m behind the axle; its wheels are
    named drive_right, drive_left and caster in its URDF form."""

    caster_behind: float = 0.3

    kind: ClassVar[str] = "test_caster_drive"

    @classmethod
    def from_urdf(cls, urdf: UrdfReader) -> UrdfPlatform:
        if "caster_joint" not in urdf.continuous_joints():
            raise ModelError("platform='test_caster_drive': no joint named caster_joint")
        return super().from_urdf(urdf)  # the axle as a differential drive's, built as a CasterDrive

    def urdf_joints(self) -> tuple[UrdfJoint, ...]:
        right, left = super().urdf_joints()
        caster = UrdfJoint("caster", "base_footprint", (-self.caster_behind, 0.0, 0.05), radius=0.05)
        return (right._replace(name="drive_right"), left._replace(name="drive_left"), caster)


def _robot(platform) -> MobileManipulator:
    arm = Arm.from_dh([[0.0, 0.3, 0.5, 0.0], [0.0, 0.0, 0.4, 0.0]], "RR", velocity_limits=[1.5, 1.5])
    return MobileManipulator(platform, (arm,), (Mount(0.1, 0.0, 0.2),)).with_link_inertials(LINKS)


def _configurations(n: int = 64, seed: int = 0) -> np.ndarray:
    """Poses and joints over the whole range, headings and joints including exactly ±π/2 and ±π."""
    rng = np.random.default_rng(seed)
    q = rng.uniform(-math.pi, math.pi, size=(n, 5))
    q[:, :2] = rng.uniform(-3.0, 3.0, size=(n, 2))
    special = np.array([0.0, math.pi / 2, -math.pi / 2, math.pi, -math.pi])
    q[: len(special), 2:] = special[:, None]
    return q


PLATFORM = CasterDrive(wheel_radius=0.09, half_track=0.2, wheel_speed_max=8.0, caster_behind=0.35)


def test_a_platform_defined_outside_mobman_is_found_by_its_kind():
    assert platform_class("test_caster_drive") is CasterDrive


def test_its_urdf_form_round_trips_through_the_reader_and_the_writer(tmp_path):
    robot = _robot(PLATFORM)
    path = write_urdf(robot, tmp_path / "caster.urdf", BODY, WHEEL)
    text = path.read_text()
    assert all(f'joint name="{n}_joint"' in text for n in ("drive_right", "drive_left", "caster"))
    back = read_urdf(
        path, tip=urdf_tips(robot), platform="test_caster_drive", platform_options={"caster_behind": 0.35}
    )
    assert type(back.robot.platform) is CasterDrive and back.robot.platform == PLATFORM
    assert back.summary.wheels == ("drive_right_joint", "drive_left_joint")
    assert "caster_joint" in back.summary.passive
    assert back.summary.wheel_radius == pytest.approx(0.09) and back.summary.half_track == pytest.approx(0.2)
    q = _configurations()
    np.testing.assert_allclose(kinematics.forward(back.robot, q), kinematics.forward(robot, q), atol=1e-12)
    np.testing.assert_allclose(
        kinematics.reduced_jacobian(back.robot, q), kinematics.reduced_jacobian(robot, q), atol=1e-12
    )
    model = dynamics.DynamicModel(robot, BODY, WHEEL)
    m, m_back = dynamics.mass_matrix(model, q), dynamics.mass_matrix(dynamics.DynamicModel.from_urdf(back), q)
    np.testing.assert_allclose(m_back, m, atol=1e-12 * np.abs(m).max())


def test_its_own_reading_rules_give_its_errors(tmp_path):
    plain = write_urdf(_robot(DifferentialDrive()), tmp_path / "plain.urdf")
    with pytest.raises(ModelError, match="no joint named caster_joint"):
        read_urdf(plain, tip=urdf_tips(_robot(DifferentialDrive())), platform="test_caster_drive")
    with pytest.raises(ModelError, match="caster_behind.*not a parameter of DifferentialDrive"):
        read_urdf(plain, tip="tool_link", platform="differential", platform_options={"caster_behind": 0.3})


def test_a_car_needs_one_steering_joint_ahead_of_the_axle(tmp_path):
    plain = write_urdf(_robot(DifferentialDrive()), tmp_path / "plain.urdf")
    with pytest.raises(ModelError, match="needs one steering joint.*candidates seen: none"):
        read_urdf(plain, tip="tool_link", platform="car")


def test_a_skid_steer_needs_two_axles(tmp_path):
    plain = write_urdf(_robot(DifferentialDrive()), tmp_path / "plain.urdf")
    with pytest.raises(
        ModelError, match="four wheel joints on two axles.*wheel_right_joint, wheel_left_joint"
    ):
        read_urdf(plain, tip="tool_link", platform="skid_steer")


def test_wheel_helpers():
    a, b = UrdfWheel("r", 0.1, -0.2, 0.05), UrdfWheel("l", 0.1, 0.2, 0.05)
    assert midpoint(a, b) == pytest.approx((0.1, 0.0)) and distance(a, b) == pytest.approx(0.4)
