"""The kinematic car: rear-wheel reference point, steered front wheels (Tchoń et al. eq. 31)."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, ClassVar

import jax.numpy as jnp

from mobman import checks
from mobman.errors import ModelError
from mobman.model.platforms.base import Footprint, Platform, WheelSite
from mobman.model.platforms.urdf_form import UrdfJoint, UrdfPlatform, UrdfReader, midpoint

if TYPE_CHECKING:
    import sympy as sp


@dataclass(frozen=True)
class CarLike(Platform):
    """Kinematic car (Tchoń et al. eq. 31): q_p = (x, y, θ, φ), η_p = (u1, u2).

    ẋ = u1 cos θ cos φ, ẏ = u1 sin θ cos φ, θ̇ = u1 sin φ / length, φ̇ = u2, where (x, y) is the middle of
    the rear axle, φ the steering angle of the front wheels and u1 the front-wheel speed. The two constraints
    are the no-side-slip conditions of the rear and front wheels. The dynamic model actuates it directly on
    (u1, u2); its wheels are drawn only.
    """

    length: float = 1.0
    u1_max: float | None = None
    u2_max: float | None = None

    kind: ClassVar[str] = "car"
    coordinate_names: ClassVar[tuple[str, ...]] = ("x", "y", "theta", "phi")
    control_names: ClassVar[tuple[str, ...]] = ("u1", "u2")

    def __post_init__(self) -> None:
        checks.positive(self.length, "length", "CarLike")
        for name in ("u1_max", "u2_max"):
            if getattr(self, name) is not None:
                checks.positive(getattr(self, name), name, "CarLike")
        if (self.u1_max is None) != (self.u2_max is None):
            raise ModelError("CarLike: u1_max and u2_max must be given together")

    @property
    def velocity_limits(self) -> tuple[float, ...] | None:
        if self.u1_max is None or self.u2_max is None:
            return None
        return (float(self.u1_max), float(self.u2_max))

    def parameters(self) -> dict[str, float]:
        return {"length": self.length}

    def S(self, q_p: jnp.ndarray) -> jnp.ndarray:
        ct, st = jnp.cos(q_p[2]), jnp.sin(q_p[2])
        cp, sp = jnp.cos(q_p[3]), jnp.sin(q_p[3])
        zero, one = jnp.zeros_like(ct), jnp.ones_like(ct)
        return jnp.stack(
            [
                jnp.stack([ct * cp, zero]),
                jnp.stack([st * cp, zero]),
                jnp.stack([sp / self.length, zero]),
                jnp.stack([zero, one]),
            ]
        )

    def constraints(self, q_p: jnp.ndarray) -> jnp.ndarray:
        theta, phi = q_p[2], q_p[3]
        zero = jnp.zeros_like(theta)
        rear = jnp.stack([jnp.sin(theta), -jnp.cos(theta), zero, zero])
        front = jnp.stack([-jnp.sin(theta + phi), jnp.cos(theta + phi), self.length * jnp.cos(phi), zero])
        return jnp.stack([rear, front])

    def symbolic_S(self, q_p: Sequence[sp.Expr], values: Mapping[str, sp.Expr]) -> sp.Matrix:
        import sympy as sp

        c, s, length = sp.cos(q_p[2]), sp.sin(q_p[2]), values["length"]
        return sp.Matrix(
            [[c * sp.cos(q_p[3]), 0], [s * sp.cos(q_p[3]), 0], [sp.sin(q_p[3]) / length, 0], [0, 1]]
        )

    def symbolic_constraints(self, q_p: Sequence[sp.Expr], values: Mapping[str, sp.Expr]) -> sp.Matrix:
        import sympy as sp

        theta, phi, length = q_p[2], q_p[3], values["length"]
        return sp.Matrix(
            [
                [sp.sin(theta), -sp.cos(theta), 0, 0],
                [-sp.sin(theta + phi), sp.cos(theta + phi), length * sp.cos(phi), 0],
            ]
        )

    def wheels(self) -> tuple[WheelSite, ...]:
        r, b, front = 0.15 * self.length, 0.3 * self.length, self.length
        return (
            WheelSite(0.0, b, r, None),
            WheelSite(0.0, -b, r, None),
            WheelSite(front, b, r, None),
            WheelSite(front, -b, r, None),
        )

    def footprint(self) -> Footprint:
        return Footprint(1.4 * self.length, 0.48 * self.length, 0.15 * self.length, self.length / 2)

    URDF_WHEEL_RADIUS: ClassVar[float] = 0.1
    """The wheel radius (m) of the car's URDF form (the kinematic car has none)."""

    @classmethod
    def from_urdf(cls, urdf: UrdfReader) -> UrdfPlatform:
        """The rear axle (the file's one wheel pair, or ``wheels=``) and one steering joint on the platform's
        centre line ahead of it: the platform frame at the rear axle's midpoint, ``length`` the steering
        joint's distance ahead of it; the platform frame on the ground where the rear wheels' geometry gives
        their radius."""
        right, left = urdf.wheel_pair()
        reference = midpoint(right, left)
        ahead = [s for s in urdf.steering_joints() if abs(s.y - reference[1]) < 1e-9]
        if len(ahead) != 1 or ahead[0].x - reference[0] <= 0:
            seen = ", ".join(s.name for s in ahead) or "none"
            raise ModelError(
                "platform='car': needs one steering joint (revolute about the vertical, on the platform's "
                f"centre line ahead of the rear axle); candidates seen: {seen}"
            )
        platform = urdf.build(cls, length=ahead[0].x - reference[0])
        names = (right.name, left.name)
        return UrdfPlatform(platform, reference, names, names, urdf.base_height((right, left)))

    def urdf_joints(self) -> tuple[UrdfJoint, ...]:
        """The rear wheels, the steering joint at (length, 0) and the front wheel it turns (none driven)."""
        r = self.URDF_WHEEL_RADIUS
        return (
            UrdfJoint("wheel_rear_right", "base_footprint", (0.0, -r, r), radius=r),
            UrdfJoint("wheel_rear_left", "base_footprint", (0.0, r, r), radius=r),
            UrdfJoint(
                "steering", "base_footprint", (self.length, 0.0, r), limits=(-math.pi / 2, math.pi / 2)
            ),
            UrdfJoint("wheel_front", "steering_link", (0.0, 0.0, 0.0), radius=r),
        )
