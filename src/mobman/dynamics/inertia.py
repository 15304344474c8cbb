"""Inertial description of a mobile manipulator: platform body, driving wheels, payload, and the model.

The arm links carry their own inertials (:class:`mobman.LinkInertial`, in each joint frame after its motion).
This module adds what the kinematic model lacks (Yamamoto & Yun Table 2, Korayem §3):

- :class:`PlatformBody` the platform without its driving wheels (mass m_c, inertia I_c about the vertical
  axis through its centre of mass, centre of mass in the platform frame);
- :class:`Wheel` each driving wheel with its motor rotor (mass m_w, I_w about the axle, I_m about a diameter);
- :class:`Payload` a rigid load held at an arm's tool frame;
- :class:`DynamicModel` robot + the above + gravity: a frozen, hashable dataclass (a static argument of jit).

Every value is validated on construction; a bad one raises :class:`mobman.ModelError` naming the field and
the allowed range.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from mobman import checks
from mobman.errors import ModelError
from mobman.model.arm import LinkInertial
from mobman.model.platform import DifferentialDrive
from mobman.model.robot import MobileManipulator


@dataclass(frozen=True)
class PlatformBody:
    """The platform without its driving wheels (and without the rotors of their motors).

    mass: m_c > 0 (kg); inertia_z: I_c ≥ 0 (kg m²) about the vertical axis through the centre of mass;
    com: centre of mass in the platform frame (m). With com = 0 the vertical axis passes through the
    reference point P_o, as in Yamamoto & Yun Table 2.
    """

    mass: float
    inertia_z: float
    com: tuple[float, float, float] = (0.0, 0.0, 0.0)

    def __post_init__(self) -> None:
        object.__setattr__(self, "mass", checks.positive(self.mass, "mass", "PlatformBody"))
        object.__setattr__(
            self, "inertia_z", checks.non_negative(self.inertia_z, "inertia_z", "PlatformBody")
        )
        object.__setattr__(self, "com", checks.vector3(self.com, "com", "PlatformBody"))


@dataclass(frozen=True)
class Wheel:
    """One driving wheel plus its motor rotor (both wheels are equal; Yamamoto & Yun Table 2).

    mass: m_w ≥ 0 (kg), at the wheel centre (0, ±b, 0) in the platform frame; I_w ≥ 0 (kg m²) about the
    axle; I_m ≥ 0 (kg m²) about a diameter (turned by the platform's yaw rate).
    """

    mass: float
    I_w: float
    I_m: float

    def __post_init__(self) -> None:
        object.__setattr__(self, "mass", checks.non_negative(self.mass, "mass", "Wheel"))
        object.__setattr__(self, "I_w", checks.non_negative(self.I_w, "I_w", "Wheel"))
        object.__setattr__(self, "I_m", checks.non_negative(self.I_m, "I_m", "Wheel"))


@dataclass(frozen=True)
class Payload:
    """A rigid load held at the tool frame of arm ``arm``.

    mass ≥ 0 (kg); inertia about its centre of mass in the tool frame (9 numbers row-major or 3 diagonal);
    com in the tool frame (m). A zero mass is allowed (no load): load-capacity computations scale it.
    """

    mass: float
    inertia: tuple[float, ...] = (0.0,) * 9
    com: tuple[float, float, float] = (0.0, 0.0, 0.0)
    arm: int = 0

    def __post_init__(self) -> None:
        object.__setattr__(self, "mass", checks.non_negative(self.mass, "mass", "Payload"))
        object.__setattr__(self, "inertia", checks.inertia_tensor(self.inertia, "inertia", "Payload"))
        object.__setattr__(self, "com", checks.vector3(self.com, "com", "Payload"))
        if not isinstance(self.arm, (int, np.integer)) or self.arm < 0:
            raise ModelError(f"Payload: arm must be an arm index ≥ 0, got {self.arm!r}")
        object.__setattr__(self, "arm", int(self.arm))

    def scaled(self, mass: float) -> "Payload":
        """The same load with another mass, its inertia scaled in proportion (unit mass: inertia per kg).

        A load of zero mass keeps a zero inertia.
        """
        factor = 0.0 if self.mass == 0 else mass / self.mass
        return replace(self, mass=mass, inertia=tuple(factor * v for v in self.inertia))


@dataclass(frozen=True)
class DynamicModel:
    """A robot with its complete inertial description and gravity (frozen, hashable).

    robot: every arm joint must carry a :class:`mobman.LinkInertial`; body: the platform body; wheel: the
    driving wheels (required for a :class:`DifferentialDrive` platform, ignored otherwise — other platforms
    are actuated directly on their quasi-velocities); payload: an optional load; gravity: the world vector
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
        if isinstance(self.robot.platform, DifferentialDrive) and not isinstance(self.wheel, Wheel):
            raise ModelError(
                "DynamicModel: wheel must be a Wheel(mass, I_w, I_m) for a differential-drive platform"
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
        """Number of actuator torques: the platform's (two wheels, or one per quasi-velocity) + the joints."""
        return self.robot.n_eta

    @property
    def actuator_names(self) -> tuple[str, ...]:
        """Names of the actuators in τ order: wheels (or platform quasi-velocities), then the arm joints."""
        return actuator_names(self.robot)

    def with_payload(self, payload: Payload | None) -> "DynamicModel":
        """The same model carrying another payload (or none)."""
        return replace(self, payload=payload)


def actuator_names(robot: MobileManipulator) -> tuple[str, ...]:
    """The actuators of a robot in τ order: both wheels of a differential drive (or one per platform
    quasi-velocity), then the arm joints."""
    if isinstance(robot.platform, DifferentialDrive):
        platform = ("wheel_right", "wheel_left")
    else:
        platform = tuple(f"platform_{n}" for n in robot.platform.control_names)
    return platform + tuple(robot.coordinate_names[robot.n_platform :])


def yamamoto_platform() -> tuple[PlatformBody, Wheel]:
    """Yamamoto & Yun's platform (Table 2): m_c = 94 kg, I_c = 6.609 kg m², m_w = 5 kg, I_w = 0.01 kg m²,
    I_m = 0.135 kg m²; the body's centre of mass is taken at P_o (the paper gives no offset)."""
    return PlatformBody(94.0, 6.609), Wheel(5.0, 0.01, 0.135)


__all__ = ["DynamicModel", "Payload", "PlatformBody", "Wheel", "actuator_names", "yamamoto_platform"]
