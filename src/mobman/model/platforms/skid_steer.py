"""The four-wheel skid-steering platform (Husky-type): a unicycle whose centre of rotation is offset along x.

Model of Kozłowski & Pazderski, "Modeling and control of a 4-wheel skid-steering mobile robot", Int. J. Appl.
Math. Comput. Sci. 14(4), 2004, §2: the instantaneous centre of rotation (ICR) lies on the body x axis at
x_icr from the reference point, so the reference point moves sideways at −x_icr ω, the nonholonomic
constraint of their eq. (9). Slip is stated by the track factor χ ≥ 1 of Mandow et al., "Experimental
kinematics for wheeled skid-steer mobile robots", IROS 2007: the wheels skid when the robot turns, so the yaw
rate is that of a differential drive with a track χ times wider.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, ClassVar

import jax.numpy as jnp
import numpy as np

from mobman import checks
from mobman.errors import ModelError
from mobman.model.platforms.base import Footprint, Platform, WheelSite, check_wheel_limits
from mobman.model.platforms.urdf_form import UrdfPlatform, UrdfReader, UrdfWheel

if TYPE_CHECKING:
    import sympy as sp


@dataclass(frozen=True)
class SkidSteer(Platform):
    """Four wheels, the two of each side turning together (two actuators: right side, left side).

    q_p = (x, y, θ), η_p = (v, ω) (Kozłowski & Pazderski 2004, eq. 9–11):

        ẋ = v cos θ + x_icr ω sin θ,   ẏ = v sin θ − x_icr ω cos θ,   θ̇ = ω,

    with the constraint ẋ sin θ − ẏ cos θ − x_icr θ̇ = 0 (no sideways motion of the ICR). The side wheel
    speeds give v = r(φ̇_r + φ̇_l)/2 and ω = r(φ̇_r − φ̇_l)/(2χb) (Mandow et al. 2007, χ the track factor).
    At x_icr = 0 and χ = 1 this is a :class:`~mobman.model.platforms.differential.DifferentialDrive`.

    The dynamic model has the four wheels at (±wheelbase/2, ±b) and treats the constraint as ideal: it
    neglects the energy that skidding dissipates (the lateral friction forces of Kozłowski & Pazderski's
    eq. 17–19), so the wheel torques only accelerate the robot.

    Parameters
    ----------
    wheel_radius:
        r (m).
    half_track:
        b (m), half the distance between the left and right wheels.
    wheelbase:
        distance between the front and rear axles (m).
    x_icr:
        position of the ICR on the body x axis (m), |x_icr| < wheelbase/2 (0: at the reference point).
    track_factor:
        χ ≥ 1 (1: no skid, the yaw rate of a differential drive; measured values are about 1.2 to 2).
    v_max, omega_max:
        limits of the quasi-velocities (m/s, rad/s). Alternatively give ``wheel_speed_max`` (rad/s), from
        which v_max = r ω_w and ω_max = r ω_w / (χ b).
    """

    wheel_radius: float = 0.165
    half_track: float = 0.2775
    wheelbase: float = 0.512
    x_icr: float = 0.0
    track_factor: float = 1.0
    v_max: float | None = None
    omega_max: float | None = None
    wheel_speed_max: float | None = None

    kind: ClassVar[str] = "skid_steer"
    coordinate_names: ClassVar[tuple[str, ...]] = ("x", "y", "theta")
    control_names: ClassVar[tuple[str, ...]] = ("v", "omega")
    constant_body_twist: ClassVar[bool] = True

    def __post_init__(self) -> None:
        for name in ("wheel_radius", "half_track", "wheelbase"):
            checks.positive(getattr(self, name), name, "SkidSteer")
        x_icr = checks.finite(self.x_icr, "x_icr", "SkidSteer")
        if not abs(x_icr) < self.wheelbase / 2:
            raise ModelError(
                f"SkidSteer: x_icr must be in (−wheelbase/2, wheelbase/2) = "
                f"({-self.wheelbase / 2:g}, {self.wheelbase / 2:g}) m, got {self.x_icr!r}"
            )
        if not checks.finite(self.track_factor, "track_factor", "SkidSteer") >= 1.0:
            raise ModelError(
                f"SkidSteer: track_factor must be a finite number ≥ 1, got {self.track_factor!r}"
            )
        check_wheel_limits("SkidSteer", self.v_max, self.omega_max, self.wheel_speed_max)

    @property
    def effective_half_track(self) -> float:
        """χ b: the half track of the differential drive that turns at the same rate."""
        return self.track_factor * self.half_track

    @property
    def velocity_limits(self) -> tuple[float, ...] | None:
        if self.wheel_speed_max is not None:
            v = self.wheel_radius * self.wheel_speed_max
            return (v, v / self.effective_half_track)
        if self.v_max is not None and self.omega_max is not None:
            return (float(self.v_max), float(self.omega_max))
        return None

    def parameters(self) -> dict[str, float]:
        return {"x_icr": self.x_icr}

    def S(self, q_p: jnp.ndarray) -> jnp.ndarray:
        c, s = jnp.cos(q_p[2]), jnp.sin(q_p[2])
        zero, one = jnp.zeros_like(c), jnp.ones_like(c)
        d = self.x_icr
        return jnp.stack([jnp.stack([c, d * s]), jnp.stack([s, -d * c]), jnp.stack([zero, one])])

    def constraints(self, q_p: jnp.ndarray) -> jnp.ndarray:
        c, s = jnp.cos(q_p[2]), jnp.sin(q_p[2])
        return jnp.stack([s, -c, -self.x_icr * jnp.ones_like(c)])[None, :]

    def symbolic_S(self, q_p: Sequence[sp.Expr], values: Mapping[str, sp.Expr]) -> sp.Matrix:
        import sympy as sp

        c, s, d = sp.cos(q_p[2]), sp.sin(q_p[2]), values["x_icr"]
        return sp.Matrix([[c, d * s], [s, -d * c], [0, 1]])

    def symbolic_constraints(self, q_p: Sequence[sp.Expr], values: Mapping[str, sp.Expr]) -> sp.Matrix:
        import sympy as sp

        return sp.Matrix([[sp.sin(q_p[2]), -sp.cos(q_p[2]), -values["x_icr"]]])

    def body_twist_matrix(self) -> np.ndarray:
        """B with S = R(θ) B: the body twist is (v, −x_icr ω, ω)."""
        return np.array([[1.0, 0.0], [0.0, -self.x_icr], [0.0, 1.0]])

    @property
    def actuator_names(self) -> tuple[str, ...]:
        return ("wheels_right", "wheels_left")

    def actuator_matrix(self) -> np.ndarray:
        """T = W, (v, ω) = W (φ̇_r, φ̇_l): v = r(φ̇_r + φ̇_l)/2, ω = r(φ̇_r − φ̇_l)/(2χb) (Mandow et al.)."""
        return self.wheel_matrix()

    def wheel_matrix(self) -> np.ndarray:
        """W with (v, ω) = W (φ̇_r, φ̇_l) (:meth:`actuator_matrix`)."""
        r, b = self.wheel_radius, self.effective_half_track
        return np.array([[r / 2, r / 2], [r / (2 * b), -r / (2 * b)]])

    @property
    def actuator_speed_limits(self) -> tuple[float, ...] | None:
        return None if self.wheel_speed_max is None else (float(self.wheel_speed_max),) * 2

    def actuator_rows(self, q_p: jnp.ndarray) -> jnp.ndarray:
        """φ̇_r,l = (ẋ cos θ + ẏ sin θ ± χ b θ̇)/r: the forward speed v = ẋ cos θ + ẏ sin θ of the reference
        point and the yaw rate ω = θ̇ through W⁻¹."""
        b, r = self.effective_half_track, self.wheel_radius
        c, s = jnp.cos(q_p[2]), jnp.sin(q_p[2])
        return jnp.stack([jnp.stack([c, s, side * b * jnp.ones_like(c)]) / r for side in (1.0, -1.0)])

    def wheels(self) -> tuple[WheelSite, ...]:
        r, b, a = self.wheel_radius, self.half_track, self.wheelbase / 2
        return (
            WheelSite(a, -b, r, 0),
            WheelSite(-a, -b, r, 0),
            WheelSite(a, b, r, 1),
            WheelSite(-a, b, r, 1),
        )

    def footprint(self) -> Footprint:
        return Footprint(
            self.wheelbase + 2 * self.wheel_radius, 1.5 * self.half_track, self.wheel_radius, 0.0
        )

    @classmethod
    def from_urdf(cls, urdf: UrdfReader) -> UrdfPlatform:
        """The file's two axles (front, rear): r from the front right wheel's geometry, b half the distance
        between the front wheels, the wheelbase the distance between the axles, the platform frame at the
        centre of the four wheels; x_icr and track_factor from ``platform_options`` (a URDF does not state
        them). The platform frame is on the ground (the wheels' height less r). A file without wheel joints is
        read from the ``wheel_radius``, ``half_track`` and ``wheelbase`` given, its frame at the base link."""
        if urdf.without_wheels("wheel_radius", "half_track", "wheelbase"):
            return UrdfPlatform(urdf.build(cls))
        axles = urdf.axles()
        if len(axles) != 2 or len({w.name for axle in axles for w in axle}) != 4:
            seen = ", ".join(urdf.continuous_joints()) or "none"
            raise ModelError(
                "platform='skid_steer': needs four wheel joints on two axles (continuous joints off the arm "
                f"chains); continuous joints seen: {seen}; without them give wheel_radius, half_track and "
                "wheelbase (--platform-option KEY=VALUE)"
            )
        (front_right, front_left), (rear_right, rear_left) = sorted(axles, key=lambda a: -(a[0].x + a[1].x))
        wheels: tuple[UrdfWheel, ...] = (front_right, rear_right, front_left, rear_left)  # as in wheels()
        platform = urdf.build(
            cls,
            wheel_radius=urdf.wheel_radius(front_right),
            half_track=urdf.half_track(abs(front_left.y - front_right.y) / 2),
            wheelbase=abs(front_right.x - rear_right.x),
            wheel_speed_max=urdf.wheel_speed(wheels),
        )
        centre = (sum(w.x for w in wheels) / 4, sum(w.y for w in wheels) / 4)
        names = tuple(w.name for w in wheels)
        height = urdf.base_height(wheels, platform.wheel_radius)
        return UrdfPlatform(platform, centre, names, (front_right.name, front_left.name), height)
