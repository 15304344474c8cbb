"""The differential drive: two independently driven wheels on one axle (HILARE-like unicycle)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, ClassVar

import jax.numpy as jnp
import numpy as np

from mobman import checks
from mobman.model.platforms.base import Footprint, Platform, WheelSite, check_wheel_limits
from mobman.model.platforms.urdf_form import UrdfPlatform, UrdfReader, distance, midpoint

if TYPE_CHECKING:
    import sympy as sp


@dataclass(frozen=True)
class DifferentialDrive(Platform):
    """Two independently driven wheels on one axle (HILARE-like unicycle), reference point at the axle midpoint.

    q_p = (x, y, θ), η_p = (v, ω); ẋ = v cos θ, ẏ = v sin θ, θ̇ = ω; rolling without slipping
    ẋ sin θ − ẏ cos θ = 0 (Bayle §4.1). The wheels turn at (φ̇_r, φ̇_l) = ((v + bω)/r, (v − bω)/r)
    (Korayem eq. 14–15, Yamamoto & Yun eq. 4–6); the right wheel is at y = −b.

    Parameters
    ----------
    wheel_radius:
        r (m), Yamamoto & Yun's r, Korayem's R.
    half_track:
        b (m), half the distance between the driving wheels (Yamamoto & Yun's b).
    v_max, omega_max:
        limits of the quasi-velocities (m/s, rad/s). Alternatively give ``wheel_speed_max`` (rad/s), from
        which v_max = r ω_w and ω_max = r ω_w / b (one wheel forward, the other backward at full speed).
    """

    wheel_radius: float = 0.1
    half_track: float = 0.25
    v_max: float | None = None
    omega_max: float | None = None
    wheel_speed_max: float | None = None

    kind: ClassVar[str] = "differential"
    coordinate_names: ClassVar[tuple[str, ...]] = ("x", "y", "theta")
    control_names: ClassVar[tuple[str, ...]] = ("v", "omega")
    constant_body_twist: ClassVar[bool] = True

    def __post_init__(self) -> None:
        checks.positive(self.wheel_radius, "wheel_radius", "DifferentialDrive")
        checks.positive(self.half_track, "half_track", "DifferentialDrive")
        check_wheel_limits("DifferentialDrive", self.v_max, self.omega_max, self.wheel_speed_max)

    @property
    def velocity_limits(self) -> tuple[float, ...] | None:
        if self.wheel_speed_max is not None:
            v = self.wheel_radius * self.wheel_speed_max
            return (v, v / self.half_track)
        if self.v_max is not None and self.omega_max is not None:
            return (float(self.v_max), float(self.omega_max))
        return None

    def S(self, q_p: jnp.ndarray) -> jnp.ndarray:
        c, s = jnp.cos(q_p[2]), jnp.sin(q_p[2])
        zero, one = jnp.zeros_like(c), jnp.ones_like(c)
        return jnp.stack([jnp.stack([c, zero]), jnp.stack([s, zero]), jnp.stack([zero, one])])

    def constraints(self, q_p: jnp.ndarray) -> jnp.ndarray:
        c, s = jnp.cos(q_p[2]), jnp.sin(q_p[2])
        return jnp.stack([s, -c, jnp.zeros_like(c)])[None, :]

    def symbolic_S(self, q_p: Sequence[sp.Expr], values: Mapping[str, sp.Expr]) -> sp.Matrix:
        import sympy as sp

        return sp.Matrix([[sp.cos(q_p[2]), 0], [sp.sin(q_p[2]), 0], [0, 1]])

    def symbolic_constraints(self, q_p: Sequence[sp.Expr], values: Mapping[str, sp.Expr]) -> sp.Matrix:
        import sympy as sp

        return sp.Matrix([[sp.sin(q_p[2]), -sp.cos(q_p[2]), 0]])

    def body_twist_matrix(self) -> np.ndarray:
        """B with S = R(θ) B: the body twist is (v, 0, ω)."""
        return np.array([[1.0, 0.0], [0.0, 0.0], [0.0, 1.0]])

    @property
    def actuator_names(self) -> tuple[str, ...]:
        return ("wheel_right", "wheel_left")

    def actuator_matrix(self) -> np.ndarray:
        """T = W, (v, ω) = W (φ̇_r, φ̇_l): v = r(φ̇_r + φ̇_l)/2, ω = r(φ̇_r − φ̇_l)/(2b) (Korayem eq. 14–15)."""
        return self.wheel_matrix()

    @property
    def actuator_speed_limits(self) -> tuple[float, ...] | None:
        return None if self.wheel_speed_max is None else (float(self.wheel_speed_max),) * 2

    def actuator_rows(self, q_p: jnp.ndarray) -> jnp.ndarray:
        """φ̇_r,l = (ẋ cos θ + ẏ sin θ ± b θ̇)/r: the forward speed of each wheel centre over r (Yamamoto
        eq. 4–6), the wheel speed wherever the wheels roll."""
        b, r = self.half_track, self.wheel_radius
        c, s = jnp.cos(q_p[2]), jnp.sin(q_p[2])
        return jnp.stack([jnp.stack([c, s, side * b * jnp.ones_like(c)]) / r for side in (1.0, -1.0)])

    def wheels(self) -> tuple[WheelSite, ...]:
        r, b = self.wheel_radius, self.half_track
        return (WheelSite(0.0, -b, r, 0), WheelSite(0.0, b, r, 1))

    def footprint(self) -> Footprint:
        return Footprint(2.4 * self.half_track, 1.5 * self.half_track, self.wheel_radius, 0.0)

    @classmethod
    def from_urdf(cls, urdf: UrdfReader) -> UrdfPlatform:
        """The file's one axle (or the ``wheels=`` pair): r from the right wheel's geometry, b half the
        distance between the wheels, the platform frame at the axle midpoint on the ground (the axle's height
        less r) and the wheel speed limit the smaller of the two joints' velocity limits. A file without
        wheel joints is read from the ``wheel_radius`` and ``half_track`` given, its frame at the base link."""
        if urdf.without_wheels("wheel_radius", "half_track"):
            return UrdfPlatform(urdf.build(cls))
        right, left = urdf.wheel_pair()
        platform = urdf.build(
            cls,
            wheel_radius=urdf.wheel_radius(right),
            half_track=urdf.half_track(distance(right, left) / 2),
            wheel_speed_max=urdf.wheel_speed((right, left)),
        )
        names = (right.name, left.name)
        height = urdf.base_height((right, left), platform.wheel_radius)
        return UrdfPlatform(platform, midpoint(right, left), names, names, height)

    def wheel_matrix(self) -> np.ndarray:
        """W with (v, ω) = W (φ̇_r, φ̇_l): v = r(φ̇_r + φ̇_l)/2, ω = r(φ̇_r − φ̇_l)/(2b) (Korayem eq. 14–15)."""
        r, b = self.wheel_radius, self.half_track
        return np.array([[r / 2, r / 2], [r / (2 * b), -r / (2 * b)]])
