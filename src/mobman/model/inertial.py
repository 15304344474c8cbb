"""Inertial data beyond the arm links: the platform body, the driving wheels, a payload.

The arm links carry their own inertials (:class:`mobman.LinkInertial`, in each joint frame after its motion).
These plain, validated, frozen dataclasses describe the rest of a robot's mass (Yamamoto & Yun Table 2,
Korayem §3); :class:`mobman.dynamics.DynamicModel` assembles them with the robot and gravity, and
:mod:`mobman.io.urdf` reads and writes them.

- :class:`PlatformBody` the platform without its driving wheels (mass m_c, inertia I_c about the vertical
  axis through its centre of mass, centre of mass in the platform frame);
- :class:`Wheel` each driving wheel with its motor rotor (mass m_w, I_w about the axle, I_m about a diameter);
- :class:`Payload` a rigid load held at an arm's tool frame.

Every value is validated on construction; a bad one raises :class:`mobman.ModelError` naming the field and
the allowed range.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from mobman import checks
from mobman.errors import ModelError


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


__all__ = ["Payload", "PlatformBody", "Wheel"]
