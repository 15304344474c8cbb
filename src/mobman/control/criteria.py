"""Criteria P(q) minimised by the self-motion of the redundancy-resolution laws (Bayle §6–7).

A criterion is a frozen, hashable dataclass, ``criterion(robot, q, task=None, xi_star=None) -> scalar`` for
one configuration, written with ``jax.numpy`` so that :meth:`Criterion.gradient` (∇P = ∂P/∂q, by
``jax.grad``) is exact. ``task`` is the operational task the measure refers to (the robot's by default) and
``xi_star`` the current reference value, used only by :class:`Blend` (Bayle eq. 7).

Every criterion is also a JAX pytree whose numbers (``Manipulability.power``, the α breakpoints of
:class:`CubicTransition`) are leaves, the rest static: laws that differ only in those numbers are batched by
``jax.vmap`` in one compiled simulation (e.g. P = w5 and P = w5² side by side).

Sign convention: the laws always *decrease* P (Ṗ ≤ 0 for pure self-motion). Bayle's choices are P = w5
(eccentricity: 0 for an isotropic ellipse, 1 at a singularity) or P = −w (Yoshikawa's measure with the
opposite sign). :class:`Manipulability` therefore uses ``sign=+1`` for ``eccentricity`` and ``sign=−1`` for
``yoshikawa`` and ``inverse_condition`` unless ``sign`` is given.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Callable

import jax
import jax.numpy as jnp
import numpy as np

from mobman.control._tree import pytree
from mobman.errors import ModelError

if TYPE_CHECKING:
    from mobman.model.robot import MobileManipulator
    from mobman.model.tasks import Task

MEASURES = ("eccentricity", "yoshikawa", "inverse_condition")
WHICH = ("arm", "system", "system_normalized")


@dataclass(frozen=True)
class Criterion:
    """Base class of the criteria."""

    def __call__(
        self,
        robot: MobileManipulator,
        q: jax.Array,
        task: Task | None = None,
        xi_star: jax.Array | None = None,
    ) -> jnp.ndarray:
        raise NotImplementedError

    def gradient(
        self,
        robot: MobileManipulator,
        q: jax.Array,
        task: Task | None = None,
        xi_star: jax.Array | None = None,
    ) -> jnp.ndarray:
        """∇P(q), shape (n_q,), by reverse-mode autodiff (ξ* is held fixed)."""
        return jax.grad(lambda qq: self(robot, qq, task, xi_star))(jnp.asarray(q, dtype=float))


def measure_jacobian(robot: MobileManipulator, q: jax.Array, task: Task | None, which: str) -> jnp.ndarray:
    """The Jacobian whose ellipsoid a manipulability measure describes: J_a (arm), J̄ or J̄_N = J̄ R, of one
    configuration q (n_q,) (traced code: no validation)."""
    from mobman import kinematics as K
    from mobman import manipulability as mp

    return mp.jacobian_one(robot, K.resolve_task(robot, task), which, q)


@pytree("power")
@dataclass(frozen=True)
class Manipulability(Criterion):
    """P = sign · measure(J) with J the arm Jacobian J_a, the reduced Jacobian J̄ or its normalised form
    J̄ R (Nait-Chabane eq. 20–26; R = diag(robot.velocity_limits)). ``rank`` restricts the measure to the
    r largest singular values (see :func:`mobman.manipulability.measures`).

    ``power`` ∈ {1, 2, 4}: P = sign · measure^power — the same minimisers, level sets and descent directions,
    but not the same smoothness. For the eccentricity of a 2-row Jacobian (λ_i = σ_i² the eigenvalues of
    the 2 × 2 Gram matrix G): λ_max − λ_min = √((G11 − G22)² + 4 G12²) is a cone at the isotropic
    configurations, so w5 = √((λ_max − λ_min)/λ_max) has an unbounded gradient there (∇w5 = ∇(w5²)/(2 w5)),
    w5² = (λ_max − λ_min)/λ_max a bounded but discontinuous one — a sampled gradient law chatters around
    the optimum with both — and w5⁴ = (λ_max − λ_min)²/λ_max² is smooth, its gradient vanishing at the
    optimum (see docs/control.md, Bayle reproduction)."""

    measure: str = "eccentricity"
    which: str = "system"
    sign: float | None = None
    rank: int | None = None
    power: float = 1.0

    def __post_init__(self) -> None:
        if self.power not in (1, 2, 4):
            raise ModelError(f"Manipulability: power must be 1, 2 or 4, got {self.power!r}")
        object.__setattr__(self, "power", float(self.power))
        if self.measure not in MEASURES:
            raise ModelError(f"Manipulability: measure {self.measure!r} not one of {', '.join(MEASURES)}")
        if self.which not in WHICH:
            raise ModelError(f"Manipulability: which {self.which!r} not one of {', '.join(WHICH)}")
        sign = (1.0 if self.measure == "eccentricity" else -1.0) if self.sign is None else self.sign
        if sign not in (1.0, -1.0):
            raise ModelError(f"Manipulability: sign must be +1 or −1, got {sign!r}")
        object.__setattr__(self, "sign", float(sign))

    def __call__(
        self,
        robot: MobileManipulator,
        q: jax.Array,
        task: Task | None = None,
        xi_star: jax.Array | None = None,
    ) -> jax.Array:
        from mobman import manipulability as mp

        if self.which == "system_normalized" and robot.velocity_limits is None:
            raise ModelError(
                f"{robot.name}: the normalised measure needs velocity limits for every quasi-velocity"
            )
        jac = measure_jacobian(robot, q, task, self.which)
        assert self.sign is not None  # set in __post_init__
        return self.sign * mp.measures_one(jac, rank=self.rank)[self.measure] ** self.power


@pytree()
@dataclass(frozen=True)
class JointLimitDistance(Criterion):
    """P = Σ_i ((q_i − q̄_i) / (q_i,max − q_i,min))² over the arm joints with finite limits, q̄_i the middle
    of the range (Liégeois' criterion); 0 at mid-range. Joints without limits do not contribute."""

    def __call__(
        self,
        robot: MobileManipulator,
        q: jax.Array,
        task: Task | None = None,
        xi_star: jax.Array | None = None,
    ) -> jax.Array:
        terms = []
        for i, (lo, hi) in enumerate(robot.position_limits):
            if math.isfinite(lo) and math.isfinite(hi):
                terms.append(((q[i] - 0.5 * (lo + hi)) / (hi - lo)) ** 2)
        return jnp.sum(jnp.stack(terms)) if terms else jnp.zeros((), dtype=jnp.result_type(q, float))


@pytree("start", "end", "alpha_start", "alpha_end")
@dataclass(frozen=True)
class CubicTransition:
    """α(ξ*) of Bayle eq. 7: the cubic in s = ξ*[coordinate] with the four boundary conditions
    α(start) = alpha_start, α(end) = alpha_end, α'(start) = α'(end) = 0, constant outside [start, end]:
    α = alpha_start + (alpha_end − alpha_start)(3τ² − 2τ³), τ = (s − start)/(end − start) clipped to [0, 1].
    ``start > end`` is allowed (transition while s decreases)."""

    start: float
    end: float
    coordinate: int = 0
    alpha_start: float = 1.0
    alpha_end: float = 0.0

    def __post_init__(self) -> None:
        for name in ("start", "end", "alpha_start", "alpha_end"):
            if not math.isfinite(float(getattr(self, name))):
                raise ModelError(f"CubicTransition: {name} must be finite, got {getattr(self, name)!r}")
        if self.start == self.end:
            raise ModelError("CubicTransition: start and end must differ")
        if (
            isinstance(self.coordinate, bool)
            or not isinstance(self.coordinate, (int, np.integer))
            or self.coordinate < 0
        ):
            raise ModelError(
                f"CubicTransition: coordinate must be an index ≥ 0 into the task coordinates, got {self.coordinate!r}"
            )
        for name in ("alpha_start", "alpha_end"):
            if not 0.0 <= float(getattr(self, name)) <= 1.0:
                raise ModelError(f"CubicTransition: {name} must be in [0, 1], got {getattr(self, name)!r}")

    def __call__(self, xi_star: jax.Array) -> jnp.ndarray:
        xi_star = jnp.asarray(xi_star, dtype=float)
        m = xi_star.shape[-1] if xi_star.ndim else 0
        if self.coordinate >= m:  # shapes are static: checked once per trace, never clamped
            raise ModelError(
                f"CubicTransition: coordinate {self.coordinate} out of range: the task has {m} coordinates "
                f"(indices 0..{m - 1})"
            )
        s = xi_star[..., self.coordinate]
        tau = jnp.clip((s - self.start) / (self.end - self.start), 0.0, 1.0)
        return self.alpha_start + (self.alpha_end - self.alpha_start) * tau * tau * (3.0 - 2.0 * tau)


@pytree("system", "arm", "alpha")
@dataclass(frozen=True)
class Blend(Criterion):
    """P = α(ξ*) P_system + (1 − α(ξ*)) P_arm (Bayle eq. 7): a transition from the whole-system criterion
    to the arm criterion as the reference moves. Without ξ* (a plain evaluation) α is taken at ξ = f(q)."""

    system: Criterion
    arm: Criterion
    alpha: CubicTransition

    def __call__(
        self,
        robot: MobileManipulator,
        q: jax.Array,
        task: Task | None = None,
        xi_star: jax.Array | None = None,
    ) -> jax.Array:
        if xi_star is None:
            from mobman.kinematics import forward

            xi_star = jax.lax.stop_gradient(forward(robot, q, task))
        a = jax.lax.stop_gradient(self.alpha(xi_star))
        return a * self.system(robot, q, task, xi_star) + (1.0 - a) * self.arm(robot, q, task, xi_star)


@pytree()
@dataclass(frozen=True)
class FunctionCriterion(Criterion):
    """A user function P = fn(q) (one configuration, ``jax.numpy``); its gradient comes from autodiff."""

    fn: Callable[[jnp.ndarray], jnp.ndarray]

    def __post_init__(self) -> None:
        if not callable(self.fn):
            raise ModelError("FunctionCriterion: fn must be a callable of q")

    def __call__(
        self,
        robot: MobileManipulator,
        q: jax.Array,
        task: Task | None = None,
        xi_star: jax.Array | None = None,
    ) -> jax.Array:
        return jnp.reshape(jnp.asarray(self.fn(q)), ())


__all__ = [
    "Blend",
    "Criterion",
    "CubicTransition",
    "FunctionCriterion",
    "JointLimitDistance",
    "MEASURES",
    "Manipulability",
    "WHICH",
    "measure_jacobian",
]
