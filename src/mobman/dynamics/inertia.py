"""The dynamic model of a mobile manipulator: the robot with its complete inertial description and gravity.

The inertial data (:class:`PlatformBody`, :class:`Wheel`, :class:`Payload`) live in
:mod:`mobman.model.inertial` and are re-exported here; :class:`DynamicModel` is robot + those + gravity: a
frozen, hashable dataclass (a static argument of jit). Yamamoto & Yun Table 2, Korayem §3.

Every value is validated on construction; a bad one raises :class:`mobman.ModelError` naming the field and
the allowed range.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

from mobman import checks
from mobman.errors import ModelError
from mobman.model.arm import LinkInertial
from mobman.model.inertial import Payload, PlatformBody, Wheel
from mobman.model.robot import MobileManipulator, actuator_names

if TYPE_CHECKING:
    from mobman.io.urdf import UrdfModel


@dataclass(frozen=True)
class DynamicModel:
    """A robot with its complete inertial description and gravity (frozen, hashable).

    robot: every arm joint must carry a :class:`mobman.LinkInertial`; body: the platform body; wheel: the
    driving wheels (required for a platform with driven wheels, ``platform.wheel_actuated``: a differential
    drive, a skid-steer; ignored otherwise — other platforms are actuated directly on their quasi-velocities); payload: an optional load; gravity: the world vector
    (m/s²).
    """

    robot: MobileManipulator
    body: PlatformBody
    wheel: Wheel | None = None
    payload: Payload | None = None
    gravity: tuple[float, float, float] = (0.0, 0.0, -9.81)

    def __post_init__(self) -> None:
        if not isinstance(self.robot, MobileManipulator):
            raise ModelError(
                f"DynamicModel: robot must be a MobileManipulator, got {type(self.robot).__name__}"
            )
        if not isinstance(self.body, PlatformBody):
            raise ModelError("DynamicModel: body must be a PlatformBody(mass, inertia_z, com)")
        if self.robot.platform.wheel_actuated and not isinstance(self.wheel, Wheel):
            raise ModelError(
                f"DynamicModel: wheel must be a Wheel(mass, I_w, I_m) for a {type(self.robot.platform).__name__} "
                "platform (driven wheels)"
            )
        if self.payload is not None:
            if not isinstance(self.payload, Payload):
                raise ModelError("DynamicModel: payload must be a Payload or None")
            if self.payload.arm >= len(self.robot.arms):
                raise ModelError(
                    f"DynamicModel: payload.arm must be in 0..{len(self.robot.arms) - 1}, got {self.payload.arm}"
                )
        for i, arm in enumerate(self.robot.arms):
            for j, joint in enumerate(arm.joints):
                if not isinstance(joint.inertial, LinkInertial):
                    raise ModelError(
                        f"DynamicModel: arm {i} ({arm.name}) joint {j} ({joint.name}) has no inertial "
                        "(LinkInertial(mass, com, inertia))"
                    )
        object.__setattr__(self, "gravity", checks.vector3(self.gravity, "gravity", "DynamicModel"))

    @property
    def n_actuators(self) -> int:
        """Number of actuator torques: the platform's (its driven wheels, or one per quasi-velocity) + the
        joints."""
        return self.robot.n_eta

    @property
    def actuator_names(self) -> tuple[str, ...]:
        """Names of the actuators in τ order: wheels (or platform quasi-velocities), then the arm joints."""
        return actuator_names(self.robot)

    @classmethod
    def from_urdf(
        cls, urdf: "UrdfModel", gravity: tuple[float, float, float] = (0.0, 0.0, -9.81)
    ) -> "DynamicModel":
        """The model of a robot read by :func:`mobman.io.urdf.read_urdf`: its platform body and wheel spin
        inertia from the URDF's inertials, no payload (ModelError where the URDF gives no platform inertial)."""
        if urdf.body is None:
            raise ModelError(f"{urdf.robot.name}: the URDF gives no inertial for the platform body")
        return cls(urdf.robot, urdf.body, urdf.wheel, None, gravity)

    def with_payload(self, payload: Payload | None) -> "DynamicModel":
        """The same model carrying another payload (or none)."""
        return replace(self, payload=payload)


def yamamoto_platform() -> tuple[PlatformBody, Wheel]:
    """Yamamoto & Yun's platform (Table 2): m_c = 94 kg, I_c = 6.609 kg m², m_w = 5 kg, I_w = 0.01 kg m²,
    I_m = 0.135 kg m²; the body's centre of mass is taken at P_o (the paper gives no offset)."""
    return PlatformBody(94.0, 6.609), Wheel(5.0, 0.01, 0.135)


__all__ = ["DynamicModel", "Payload", "PlatformBody", "Wheel", "actuator_names", "yamamoto_platform"]
