"""The platform interface and the registry of platform kinds.

A platform is a driftless control system q̇_p = S(q_p) η_p (Bayle §4.1; Nait-Chabane's M(q), Tchoń's
G(q)). Its planar reference frame has its pose in the world as the first three coordinates (x, y, θ) of
q_p (Bayle §2); further coordinates (the steering angle of a car) follow. A :class:`Platform` carries its
whole behaviour: the admissible-velocity basis :meth:`Platform.S`, the constraints :meth:`Platform.constraints`
(G S = 0), both also in SymPy form, its velocity limits, how its actuators map to the quasi-velocities
(η_p = T u), its wheels for the dynamic model and the viewer, whether it moves along a constant body twist
(S(q_p) = R(θ) B, integrated exactly on SE(2)), and its URDF form (:meth:`Platform.from_urdf`,
:meth:`Platform.urdf_joints`; :mod:`mobman.model.platforms.urdf_form`).

Every subclass that sets ``kind`` registers itself: :func:`platform_class` finds it by that name (the
``kind`` of a robot file's ``[platform]`` table, the ``platform=`` of a URDF reader).
"""

from __future__ import annotations

import difflib
from abc import ABC, abstractmethod
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, ClassVar, NamedTuple

import jax
import jax.numpy as jnp
import numpy as np
from jax.typing import ArrayLike

from mobman import checks
from mobman.errors import ModelError
from mobman.model.inertial import PlatformBody, Wheel
from mobman.model.platforms.urdf_form import UrdfJoint, UrdfPlatform, UrdfReader

if TYPE_CHECKING:
    import sympy as sp

_REGISTRY: dict[str, type[Platform]] = {}


class WheelSite(NamedTuple):
    """A wheel of a platform: centre (x, y) in the platform frame (the centre is ``radius`` above the ground),
    its radius (m) and the index in ``actuator_names`` of the actuator that turns it (None for a wheel that is
    drawn only, e.g. the kinematic car's, whose dynamic model is actuated on its quasi-velocities)."""

    x: float
    y: float
    radius: float
    actuator: int | None


class RigidPart(NamedTuple):
    """A rigid body of a platform, fixed in the platform frame: mass (kg), centre of mass (x, y, z) and
    rotational inertia about it (3 × 3, platform axes)."""

    mass: float
    centre: tuple[float, float, float]
    inertia: np.ndarray


class Footprint(NamedTuple):
    """The body box drawn for a platform without visuals: length along x, width along y, height (m), and the
    x of its centre in the platform frame."""

    length: float
    width: float
    height: float
    x_centre: float


@dataclass(frozen=True)
class Platform(ABC):
    """Common interface of the platforms (abstract). Subclasses are frozen dataclasses whose fields are
    the platform's parameters (the keys of a robot file's ``[platform]`` table)."""

    kind: ClassVar[str]
    coordinate_names: ClassVar[tuple[str, ...]] = ()
    control_names: ClassVar[tuple[str, ...]] = ()
    constant_body_twist: ClassVar[bool] = False
    """Whether S(q_p) = R(θ) B with a constant B (:meth:`body_twist_matrix`): constant η_p then moves the
    platform along one SE(2) exponential, which :meth:`displace` gives exactly."""

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        kind = cls.__dict__.get("kind")
        if kind is None:
            return
        if kind in _REGISTRY and _REGISTRY[kind].__qualname__ != cls.__qualname__:
            raise ModelError(f"platform kind {kind!r} is already taken by {_REGISTRY[kind].__name__}")
        _REGISTRY[kind] = cls

    # --- dimensions and limits ------------------------------------------------------------------------

    @property
    def n_q(self) -> int:
        """Mobility index of the platform, M_p = dim q_p."""
        return len(self.coordinate_names)

    @property
    def n_eta(self) -> int:
        """Mobility degree of the platform, δ_p = dim η_p."""
        return len(self.control_names)

    @property
    @abstractmethod
    def velocity_limits(self) -> tuple[float, ...] | None:
        """Maximum |η_p| per quasi-velocity, or None when not given."""

    # --- kinematics -----------------------------------------------------------------------------------

    @abstractmethod
    def S(self, q_p: jnp.ndarray) -> jnp.ndarray:
        """Admissible-velocity basis S(q_p), shape (n_q, n_eta), for one configuration."""

    @abstractmethod
    def constraints(self, q_p: jnp.ndarray) -> jnp.ndarray:
        """Constraint rows G(q_p) with G S = 0, shape (n_q − n_eta, n_q), for one configuration."""

    def parameters(self) -> dict[str, float]:
        """The numbers S and the constraints read, by name (exact or symbolic constants of
        :mod:`mobman.symbolic`); none by default."""
        return {}

    @abstractmethod
    def symbolic_S(self, q_p: Sequence[sp.Expr], values: Mapping[str, sp.Expr]) -> sp.Matrix:
        """S(q_p) as a SymPy matrix; ``values`` holds the :meth:`parameters` as SymPy numbers or symbols."""

    @abstractmethod
    def symbolic_constraints(self, q_p: Sequence[sp.Expr], values: Mapping[str, sp.Expr]) -> sp.Matrix:
        """G(q_p) as a SymPy matrix (n_q − n_eta rows); ``values`` as for :meth:`symbolic_S`."""

    def body_twist_matrix(self) -> np.ndarray:
        """B (3 × n_eta) with S(q_p) = R(θ) B: the body twist (v_x, v_y, ω) of the platform frame per unit
        η_p. ModelError for a platform without a constant body twist."""
        raise ModelError(f"{type(self).__name__}: S(q_p) is not R(θ) B with a constant B")

    def displace(self, q_p: jnp.ndarray, u: jnp.ndarray) -> jnp.ndarray:
        """q_p after the constant quasi-velocity increment u = h η_p: the SE(2) exponential of the body
        twist B u (exact; only where :attr:`constant_body_twist`)."""
        vx, vy, dth = jnp.asarray(self.body_twist_matrix(), dtype=q_p.dtype) @ u
        return planar_exp(q_p, vx, vy, dth)

    # --- actuators and wheels -------------------------------------------------------------------------

    @property
    def actuator_names(self) -> tuple[str, ...]:
        """The platform's actuators in τ order: ``platform_<control>`` for a platform actuated directly on
        its quasi-velocities."""
        return tuple(f"platform_{n}" for n in self.control_names)

    def actuator_matrix(self) -> np.ndarray:
        """T (n_eta × n_eta) with η_p = T u, u the actuator speeds; I for direct actuation."""
        return np.eye(self.n_eta)

    @property
    def actuator_speed_limits(self) -> tuple[float, ...] | None:
        """Maximum |u| per actuator where the limit is given per actuator (e.g. per wheel), else None."""
        return None

    def wheel_speeds_to_eta(self, wheel_speeds: ArrayLike) -> jnp.ndarray:
        """Actuator speeds u → η_p = T u; batched over leading dimensions."""
        return jnp.asarray(wheel_speeds) @ self.actuator_matrix().T

    def eta_to_wheel_speeds(self, eta: ArrayLike) -> jnp.ndarray:
        """η_p → actuator speeds u = T⁻¹ η_p; batched."""
        return jnp.asarray(eta) @ np.linalg.inv(self.actuator_matrix()).T

    @property
    def wheel_actuated(self) -> bool:
        """Whether the actuators are driven wheels (their speeds u differ from η_p)."""
        return any(w.actuator is not None for w in self.wheels())

    def actuator_rows(self, q_p: jnp.ndarray) -> jnp.ndarray:
        """Rows A(q_p) (n_eta × n_q) with u = A q̇_p, exact on the admissible velocities (A S = T⁻¹); the
        generalized forces of the actuator torques are Aᵀ τ (virtual work τ·δu). By default
        A = T⁻¹ (Sᵀ S)⁻¹ Sᵀ, so Aᵀ τ = S (Sᵀ S)⁻¹ τ for direct actuation."""
        s = self.S(q_p)
        rows = jnp.linalg.solve(s.T @ s, s.T)
        if self.wheel_actuated:
            rows = jnp.asarray(np.linalg.inv(self.actuator_matrix())) @ rows
        return rows

    def wheels(self) -> tuple[WheelSite, ...]:
        """The wheels, for the dynamic model (those with an actuator: their mass and spin) and the viewer."""
        return ()

    def footprint(self) -> Footprint:
        """The body box the viewer draws for this platform."""
        return Footprint(0.6, 0.5, 0.08, 0.0)

    # --- inertia --------------------------------------------------------------------------------------

    def inertia_bodies(self, body: PlatformBody, wheel: Wheel | None) -> tuple[RigidPart, ...]:
        """The platform's bodies for the dynamic model (the parameters of Yamamoto & Yun Table 2): the body
        (m_c, I_c about the vertical through its centre of mass) and, for driven wheels, each wheel of
        :meth:`wheels` with an actuator at its centre (m_w, I_m about its diameters). A wheel's spin I_w
        enters separately, through :meth:`actuator_rows` (the wheel speeds)."""
        parts = [RigidPart(body.mass, body.com, np.diag([0.0, 0.0, body.inertia_z]))]
        if wheel is not None and self.wheel_actuated:
            parts += [
                RigidPart(wheel.mass, (site.x, site.y, site.radius), np.diag([wheel.I_m, 0.0, wheel.I_m]))
                for site in self.wheels()
                if site.actuator is not None
            ]
        return tuple(parts)

    # --- URDF form ------------------------------------------------------------------------------------

    @classmethod
    def from_urdf(cls, urdf: UrdfReader) -> UrdfPlatform:
        """The platform read from a URDF file (:func:`mobman.io.urdf.read_urdf` with ``platform=kind``). By
        default no wheels: the platform frame at the base link's origin, the parameters from
        ``platform_options``."""
        return UrdfPlatform(urdf.build(cls))

    def urdf_joints(self) -> tuple[UrdfJoint, ...]:
        """The platform's joints in a URDF file (:func:`mobman.io.urdf.write_urdf`). By default one
        continuous joint per wheel of :meth:`wheels`, driven by its actuator at the actuator's speed limit:
        wheel_right, wheel_left for two wheels; wheel_front_right, wheel_rear_right, … for more."""
        sites, speeds = self.wheels(), self.actuator_speed_limits
        if len(sites) == 2:
            names = ["wheel_right" if site.y < 0 else "wheel_left" for site in sites]
        else:
            names = [
                f"wheel_{'front' if s.x > 0 else 'rear'}_{'right' if s.y < 0 else 'left'}" for s in sites
            ]
        return tuple(
            UrdfJoint(
                name,
                "base_footprint",
                (site.x, site.y, site.radius),
                radius=site.radius,
                speed=None if speeds is None or site.actuator is None else speeds[site.actuator],
                driven=site.actuator is not None,
            )
            for name, site in zip(names, sites)
        )

    # --- controllability ------------------------------------------------------------------------------

    def lie_algebra_rank(self, q_p: jnp.ndarray, depth: int = 3, tol: float = 1e-9) -> int:
        """Rank at q_p of the columns of S and their iterated Lie brackets up to ``depth``.

        Brackets [f, g](q) = Dg(q) f(q) − Df(q) g(q) are formed with forward-mode autodiff. The platform
        is (small-time locally) controllable where the rank equals n_q (Chow's theorem).
        """
        q_p = jnp.asarray(q_p, dtype=float)
        if self.n_eta == 0:
            return 0
        fields = [lambda q, i=i: self.S(q)[:, i] for i in range(self.n_eta)]
        generated = list(fields)
        frontier = list(fields)
        for _ in range(depth - 1):
            new = []
            for f in fields:
                for g in frontier:
                    new.append(_bracket(f, g))
            generated.extend(new)
            frontier = new
        vectors = np.stack([np.asarray(f(q_p)) for f in generated], axis=1)
        s = np.linalg.svd(vectors, compute_uv=False)
        return int(np.sum(s > tol * max(1.0, s[0])))

    def is_controllable(self, q_p: jnp.ndarray | None = None, depth: int = 3) -> bool:
        """Whether the Lie algebra rank condition holds at q_p (default: the origin)."""
        q_p = jnp.zeros(self.n_q) if q_p is None else q_p
        return self.lie_algebra_rank(q_p, depth=depth) == self.n_q


def _bracket(f, g):
    def h(q):
        _, dg_f = jax.jvp(g, (q,), (f(q),))
        _, df_g = jax.jvp(f, (q,), (g(q),))
        return dg_f - df_g

    return h


def planar_exp(q_p: jnp.ndarray, vx: jnp.ndarray, vy: jnp.ndarray, dth: jnp.ndarray) -> jnp.ndarray:
    """q_p with its pose (x, y, θ) moved along the body twist (vx, vy, Δθ) for unit time, the exponential of
    SE(2): the body-frame displacement V(Δθ)(vx, vy) with V(φ) = (2 sin(φ/2)/φ) R(φ/2), i.e. a chord of the
    arc along the heading θ + Δθ/2. Further coordinates are kept."""
    half = q_p[2] + 0.5 * dth
    scale = jnp.sinc(dth / (2.0 * jnp.pi))  # 2 sin(Δθ/2) / Δθ
    c, s = jnp.cos(half), jnp.sin(half)
    pose = jnp.stack([q_p[0] + scale * (vx * c - vy * s), q_p[1] + scale * (vx * s + vy * c), q_p[2] + dth])
    return jnp.concatenate([pose, q_p[3:]])


def check_wheel_limits(
    owner: str, v_max: float | None, omega_max: float | None, wheel_speed_max: float | None
) -> None:
    """The velocity limits of a platform with a driven wheel pair: positive, and either (v_max, omega_max)
    together or wheel_speed_max (ModelError naming ``owner`` otherwise)."""
    for name, value in (("v_max", v_max), ("omega_max", omega_max), ("wheel_speed_max", wheel_speed_max)):
        if value is not None:
            checks.positive(value, name, owner)
    if wheel_speed_max is not None and (v_max is not None or omega_max is not None):
        raise ModelError(f"{owner}: give either (v_max, omega_max) or wheel_speed_max, not both")
    if (v_max is None) != (omega_max is None):
        raise ModelError(f"{owner}: v_max and omega_max must be given together")


def limits(values: Sequence[float] | None, n: int, name: str, owner: str) -> tuple[float, ...] | None:
    """``values`` as n positive floats (None stays None)."""
    if values is None:
        return None
    values = tuple(float(v) for v in values)
    if len(values) != n:
        raise ModelError(f"{owner}: {name} needs {n} values, got {len(values)}")
    for v in values:
        checks.positive(v, name, owner)
    return values


def platform_kinds() -> tuple[str, ...]:
    """The registered platform kinds, sorted."""
    return tuple(sorted(_REGISTRY))


def platform_class(kind: str) -> type[Platform]:
    """The platform class registered as ``kind`` (ModelError with the closest kind otherwise)."""
    if not isinstance(kind, str) or kind not in _REGISTRY:
        close = difflib.get_close_matches(str(kind), list(_REGISTRY), n=1)
        hint = f" (did you mean {close[0]!r}?)" if close else ""
        raise ModelError(f"platform kind {kind!r} not one of {', '.join(platform_kinds())}{hint}")
    return _REGISTRY[kind]
