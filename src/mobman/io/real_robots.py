"""Real robots built in, read from their makers' URDF files: PAL Robotics TIAGo (one arm and two arms) and
Hello Robot Stretch.

The files come with the optional extra ``mobman[robots]``: TIAGo's from ``example-robot-data`` (Pinocchio's
robot collection), Stretch's from ``hello-robot-stretch-urdf``. They are located through the installed
distributions' metadata (:mod:`importlib.metadata`), read once per process by :func:`mobman.io.urdf.read_urdf`
(wheel pair, radius, track, limits, inertials, visuals; the command line reads it back from the disk,
:mod:`mobman.io.urdf_cache`) and cached; the robots are immutable. Importing this
module (done by importing :mod:`mobman.io`) registers them in :data:`mobman.model.robots.ROBOTS` under the names
below; it reads no file and does not import yourdfpy: a robot's URDF is read when the robot is first built.

Modelling choices:

- ``tiago``: PMB2 differential base (wheel radius 0.0985 m, track 0.4044 m), torso lift (prismatic) and the
  7-DoF arm as one chain of 8 joints to ``arm_tool_link``; head and hand joints are passive (held at 0).
- ``tiago-dual``: the two 7-DoF arms to ``arm_right_tool_link`` and ``arm_left_tool_link`` (arm 1 right, arm 2
  left). mobman's arms share no joint, and the torso lift carries both arms, so the torso is locked at
  ``TIAGO_DUAL_TORSO`` = 0.15 m (mid-travel is 0.175 m): with a moving torso in one arm's chain the other arm
  would not follow it. The prismatic wheel suspensions and the caster swivels are passive.
- ``stretch``: Stretch 3 (SE3) with the DW3 wrist and the SG3 gripper; differential base to ``link_grasp_center``:
  the lift, the four telescoping arm segments as the URDF's four prismatic joints (on the robot one motor drives
  them together), wrist yaw, pitch and roll. The wheel radius comes from the wheel's collision mesh. The URDF
  gives no wheel speed or effort limit, so the platform has no velocity limits (the normalised measures and the
  kinematic ellipsoid need them) and the dynamic ellipsoid no wheel torque limits.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import lru_cache
from importlib import metadata
from pathlib import Path
from typing import TYPE_CHECKING

from mobman.errors import ModelError
from mobman.model import robots
from mobman.model.robot import MobileManipulator

if TYPE_CHECKING:
    from mobman.io.urdf import UrdfModel

EXTRA = "pip install 'mobman[robots]'"
TIAGO_DUAL_TORSO = 0.15


@dataclass(frozen=True)
class RealRobot:
    """Where a built-in real robot's URDF file is and how it is read (:func:`mobman.io.urdf.read_urdf` options)."""

    distribution: str
    file: str
    tips: tuple[str, ...]
    base: str
    locked: tuple[tuple[str, float], ...] = field(default=())

    def path(self) -> Path:
        """The URDF file inside the installed distribution (ModelError with the install line when missing)."""
        try:
            files = metadata.files(self.distribution) or ()
        except metadata.PackageNotFoundError:
            raise ModelError(f"this robot needs the package {self.distribution}: {EXTRA}") from None
        for entry in files:
            if str(entry).replace("\\", "/").endswith(self.file):
                return Path(entry.locate())
        raise ModelError(f"{self.distribution} is installed without {self.file}: {EXTRA}")

    def available(self) -> bool:
        try:
            self.path()
        except ModelError:
            return False
        return True


REAL_ROBOTS: dict[str, RealRobot] = {
    "tiago": RealRobot(
        "example-robot-data", "tiago_description/robots/tiago.urdf", ("arm_tool_link",), "base_footprint"
    ),
    "tiago-dual": RealRobot(
        "example-robot-data",
        "tiago_description/robots/tiago_dual.urdf",
        ("arm_right_tool_link", "arm_left_tool_link"),
        "base_footprint",
        (("torso_lift_joint", TIAGO_DUAL_TORSO),),
    ),
    "stretch": RealRobot(
        "hello-robot-stretch-urdf",
        "stretch_urdf/SE3/stretch_description_SE3_eoa_wrist_dw3_tool_sg3.urdf",
        ("link_grasp_center",),
        "base_link",
    ),
}


@lru_cache(maxsize=None)
def urdf_model(name: str) -> "UrdfModel":
    """The :class:`mobman.io.urdf.UrdfModel` of a built-in real robot (robot, summary, inertials, effort limits)."""
    from mobman.io import urdf_cache

    if name not in REAL_ROBOTS:
        raise ModelError(f"unknown real robot {name!r}; built in: {', '.join(REAL_ROBOTS)}")
    spec = REAL_ROBOTS[name]
    return urdf_cache.read(spec.path(), tip=spec.tips, base=spec.base, name=name, locked=dict(spec.locked))


def tiago() -> MobileManipulator:
    """PAL TIAGo: PMB2 differential base, torso lift and 7-DoF arm to arm_tool_link (URDF, mobman[robots])."""
    return urdf_model("tiago").robot


def tiago_dual() -> MobileManipulator:
    """PAL TIAGo dual: differential base, two 7-DoF arms (right, left), torso locked at 0.15 m (URDF)."""
    return urdf_model("tiago-dual").robot


def stretch() -> MobileManipulator:
    """Hello Robot Stretch 3: differential base, lift, telescoping arm, 3-DoF wrist (URDF, mobman[robots])."""
    return urdf_model("stretch").robot


FACTORIES = {"tiago": tiago, "tiago-dual": tiago_dual, "stretch": stretch}
for _name, _factory in FACTORIES.items():
    robots.register(_name, _factory)

__all__ = ["EXTRA", "FACTORIES", "REAL_ROBOTS", "RealRobot", "stretch", "tiago", "tiago_dual", "urdf_model"]
