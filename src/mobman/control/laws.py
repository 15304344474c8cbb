"""Operational control laws with redundancy resolution: η = law(q, t, ξ*, ξ̇*).

Every law is a frozen dataclass and a JAX pytree: its gains (``W``, ``k``, ``feedback``), damping
parameters and the numbers of its criterion (see :mod:`mobman.control.criteria`) are array leaves, so
a list of laws differing only in gains is batched by ``jax.vmap`` (see :func:`mobman.control.simulate`);
the other options are static. ``law(robot, task, q, t, xi_star, xi_star_dot) -> (eta, info)`` acts on one
configuration; ``info`` is a dict of scalars (damping, saturation, criterion value, …) recorded per step.

Laws
----
:class:`BaylePseudoInverse` — Bayle eq. (5)–(6):
    η = J̄⁺ (ξ̇* + W e) + (I − J̄⁺J̄) g,  g = −k Hᵀ ∇P,  H = S (I − J̄⁺J̄)  (n_q × δ),  e = ξ* − ξ.
    Dimensions: ∇P is n_q (P is a function of q), Hᵀ∇P is δ, so g is a quasi-velocity. Because I − J̄⁺J̄
    is a symmetric projector, (I − J̄⁺J̄) g = g, and Ṗ = ∇ᵀP S η_self = −k ‖Hᵀ∇P‖² ≤ 0. The paper's final
    formula "η = J̄⁺(…) − k (∇ᵀP) H Hᵀ (∇P)" is a typo: that expression is the scalar −Ṗ; the control is
    η = J̄⁺(ξ̇* + W e) − k Hᵀ∇P. With J̄⁺ a right inverse the error obeys ė + W e = 0.
:class:`NaitChabane` — Nait-Chabane eq. (30): u = J̄⁺ Ẋd − (I − J̄⁺J̄) W (∂P/∂q · M)ᵀ with M = S; the optional
    ``feedback`` K adds J̄⁺ K e (eq. 30 itself is open loop). For W = k I it equals the Bayle law; for a
    general W the product (I − J̄⁺J̄) W is not symmetric and Ṗ ≤ 0 is no longer guaranteed.
:class:`AugmentedJacobian` — Korayem eq. (30): the rows [J_c; J_e; J_z] q̇ = [0; ẋ_e; ẋ_n], the nonholonomic
    constraints, the task and a user-chosen extra task, form a square system. Solved in quasi-velocities,
    [J̄; J̄_z] η = [ξ̇* + K e] (the constraint rows are satisfied by q̇ = S η); ``info["det"]`` is |det| of
    Korayem's n_q × n_q matrix [G; J; J_z].

The operational error
---------------------
Every law takes e from the task, ``task.error(ξ*, ξ)``: the difference ξ* − ξ for the tasks whose value is
a point of Rᵐ (the papers' tasks: the same numbers as a plain subtraction), and for a
:class:`~mobman.model.task.Pose` the position difference and the rotation vector log(R* Rᵀ), with ξ̇* and
the Jacobian rows in the same coordinates (linear and angular velocity).

Options shared by all laws
--------------------------
``normalized``: weighted pseudo-inverse with R = diag(robot.velocity_limits): η = R (J̄R)⁺ …, i.e. the
    solution of minimum ‖R⁻¹ η‖ (Nait-Chabane's normalisation, eq. 20–26); the null-space term is formed in
    the same scaled coordinates (H = S R (I − (J̄R)⁺ J̄R)).
``damping`` (λ_max) and ``damping_threshold`` (ε): damped least squares J̄# = J̄ᵀ (J̄J̄ᵀ + λ² I)⁻¹ with the
    variable damping of Nakamura & Hanafusa / Chiaverini: λ² = λ_max² (1 − (σ_min/ε)²) when σ_min < ε, 0
    otherwise (σ_min the smallest singular value of the matrix inverted). Away from singularities the law is
    exact; near them the error dynamics are only approximately ė + W e = 0. ``info["damped"]`` reports it.
    With ``damping=0`` an exactly singular J̄ gives non-finite η, which :func:`simulate` reports as an error.
``saturate``: η is scaled uniformly by 1/max_i(|η_i|/η_i,max) when a limit is exceeded (the direction of
    η, hence of ξ̇, is kept; the tracking lags). ``info["limit_ratio"]`` = max_i |η_i|/η_i,max before
    saturation (also when ``saturate`` is off) and ``info["saturated"]`` whether scaling was applied.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import jax
import jax.numpy as jnp
import numpy as np

from mobman.control._tree import pytree
from mobman.control.criteria import Criterion
from mobman.errors import ModelError
from mobman.model.spatial import matmul, matvec
from mobman.model.spectra import eigvalsh
from mobman.model.task import Task, stack


def _gain(value, name: str, owner: str, allow_zero: bool = False) -> np.ndarray:
    """A positive-definite gain: a scalar, a vector (diagonal) or a square matrix (symmetric part > 0)."""
    arr = np.asarray(value, dtype=float)
    if arr.ndim > 2 or (arr.ndim == 2 and arr.shape[0] != arr.shape[1]) or not np.all(np.isfinite(arr)):
        raise ModelError(f"{owner}: {name} must be a finite scalar, vector or square matrix, got {value!r}")
    eig = np.linalg.eigvalsh(0.5 * (arr + arr.T)) if arr.ndim == 2 else arr
    if np.any(eig < 0) or (not allow_zero and np.any(eig <= 0)):
        raise ModelError(
            f"{owner}: {name} must be positive {'semi-' if allow_zero else ''}definite, got {value!r}"
        )
    return arr


def apply_gain(gain: jnp.ndarray, e: jnp.ndarray, name: str = "gain") -> jnp.ndarray:
    """W e for a scalar, diagonal (vector) or full (matrix) gain."""
    if gain.ndim == 2:
        if gain.shape[1] != e.shape[-1]:
            raise ModelError(
                f"{name} is {gain.shape[0]} × {gain.shape[1]}, the error has {e.shape[-1]} components"
            )
        return gain @ e
    if gain.ndim == 1 and gain.shape[0] != e.shape[-1]:
        raise ModelError(f"{name} has {gain.shape[0]} values, the error has {e.shape[-1]} components")
    return gain * e


def _small_inverse(a: jnp.ndarray) -> jnp.ndarray:
    """Inverse of a small symmetric positive (semi)definite matrix: closed form up to 2 × 2, else LU."""
    n = a.shape[-1]
    if n == 1:
        return 1.0 / a
    if n == 2:
        det = a[0, 0] * a[1, 1] - a[0, 1] * a[1, 0]
        return jnp.array([[a[1, 1], -a[0, 1]], [-a[1, 0], a[0, 0]]]) / det
    return jnp.linalg.inv(a)


def damped_inverse(a: jnp.ndarray, damping: float, threshold: float):
    """Right inverse aᵀ (a aᵀ + λ² I)⁻¹ of a (m × k, m ≤ k) with the variable damping λ² described in the
    module docstring. Returns (inverse, λ², σ_min).

    The laws' small products are broadcast sums (``spatial.matmul``), which XLA fuses with their neighbours;
    a library matrix product is a kernel of its own, and a law runs once per simulation step."""
    gram = matmul(a, a.T)
    sigma_min = jnp.sqrt(jnp.maximum(eigvalsh(gram)[-1], 0.0))
    lam2 = damping**2 * (1.0 - jnp.minimum(sigma_min / threshold, 1.0) ** 2)
    inverse = matmul(a.T, _small_inverse(gram + lam2 * jnp.eye(a.shape[0], dtype=a.dtype)))
    return inverse, lam2, sigma_min


@dataclass(frozen=True, eq=False)
class _Law:
    """Options shared by the laws (see the module docstring)."""

    damping: float = field(default=0.0, kw_only=True)
    damping_threshold: float = field(default=0.05, kw_only=True)
    normalized: bool = field(default=False, kw_only=True)
    saturate: bool = field(default=False, kw_only=True)

    def _check_options(self, owner: str) -> None:
        if not (np.ndim(self.damping) == 0 and np.isfinite(self.damping) and self.damping >= 0):
            raise ModelError(f"{owner}: damping must be a finite number ≥ 0, got {self.damping!r}")
        if not (
            np.ndim(self.damping_threshold) == 0
            and np.isfinite(self.damping_threshold)
            and self.damping_threshold > 0
        ):
            raise ModelError(
                f"{owner}: damping_threshold must be a number > 0, got {self.damping_threshold!r}"
            )
        object.__setattr__(self, "damping", np.float64(self.damping))
        object.__setattr__(self, "damping_threshold", np.float64(self.damping_threshold))

    def _limits(self, robot) -> np.ndarray | None:
        limits = robot.velocity_limits
        if limits is None and (self.normalized or self.saturate):
            option = "normalized" if self.normalized else "saturate"
            raise ModelError(
                f"{type(self).__name__}: {option}=True needs velocity limits, {robot.name} has none"
            )
        return None if limits is None else np.asarray(limits)

    def _scale(self, robot) -> np.ndarray:
        """R: the velocity limits when normalised, ones otherwise."""
        return self._limits(robot) if self.normalized else np.ones(robot.n_eta)

    def _finish(self, robot, eta: jnp.ndarray, info: dict) -> tuple[jnp.ndarray, dict]:
        """Saturation and the common info entries."""
        limits = self._limits(robot)
        if limits is None:
            ratio = jnp.zeros((), eta.dtype)
        else:
            ratio = jnp.max(jnp.abs(eta) / limits)
        saturated = (ratio > 1.0) if self.saturate else jnp.zeros((), bool)
        if self.saturate:
            eta = eta / jnp.maximum(ratio, 1.0)
        info = dict(info, limit_ratio=ratio, saturated=saturated, damped=info["damping"] > 0)
        return eta, info


@pytree("W", "k", "criterion", "damping", "damping_threshold")
@dataclass(frozen=True, eq=False)
class BaylePseudoInverse(_Law):
    """Bayle eq. (5)–(6): η = J̄⁺(ξ̇* + W e) − k Hᵀ∇P, H = S (I − J̄⁺J̄). ``criterion=None``: no self-motion.

    ``W``: m-order positive-definite error gain (scalar, diagonal vector or matrix), 1/s; ``k`` ≥ 0.
    """

    W: np.ndarray = 1.0
    k: np.ndarray = 0.0
    criterion: Criterion | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "W", _gain(self.W, "W", "BaylePseudoInverse"))
        object.__setattr__(self, "k", _gain(self.k, "k", "BaylePseudoInverse", allow_zero=True))
        if self.k.ndim:
            raise ModelError(f"BaylePseudoInverse: k must be a scalar ≥ 0, got {self.k!r}")
        self._check_options("BaylePseudoInverse")

    def _feedback(self, e):
        return apply_gain(self.W, e, "W")

    def _self_motion(self, projector, s_scaled, grad):
        # Hᵀ ∇P with H = S R (I − J⁺J) (n_q × δ), as (I − J⁺J)ᵀ ((S R)ᵀ ∇P): two products with vectors
        # instead of forming H
        return -self.k * matvec(projector.T, matvec(s_scaled.T, grad))

    def __call__(self, robot, task: Task, q, t, xi_star, xi_star_dot):
        return _resolve(self, robot, task, q, xi_star, xi_star_dot)


@pytree("W", "criterion", "feedback", "damping", "damping_threshold")
@dataclass(frozen=True, eq=False)
class NaitChabane(_Law):
    """Nait-Chabane eq. (30): u = J̄⁺(Ẋd + K e) − (I − J̄⁺J̄) W (∂P/∂q · S)ᵀ; ``feedback`` K (None: open loop).

    ``W``: δ-order positive-definite null-space weighting (scalar, vector or matrix).
    """

    W: np.ndarray = 1.0
    criterion: Criterion | None = None
    feedback: np.ndarray | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "W", _gain(self.W, "W", "NaitChabane"))
        if self.feedback is not None:
            object.__setattr__(self, "feedback", _gain(self.feedback, "feedback", "NaitChabane"))
        self._check_options("NaitChabane")

    def _feedback(self, e):
        return jnp.zeros_like(e) if self.feedback is None else apply_gain(self.feedback, e, "feedback")

    def _self_motion(self, projector, s_scaled, grad):
        return -matvec(projector, apply_gain(self.W, matvec(s_scaled.T, grad), "W"))

    def __call__(self, robot, task: Task, q, t, xi_star, xi_star_dot):
        return _resolve(self, robot, task, q, xi_star, xi_star_dot)


def _resolve(law, robot, task: Task, q, xi_star, xi_star_dot):
    """The pseudo-inverse laws: η̃ = J̃#(ξ̇* + K e) + self-motion, η = R η̃ with J̃ = J̄ R."""
    task = robot.task if task is None else task
    frames = robot.frames(q)
    xi = task.value(robot, q, frames)
    scale = law._scale(robot)
    jt = robot.apply_S(task.jacobian(robot, q, frames), q) * scale
    e = task.error(xi_star, xi)
    inverse, lam2, sigma_min = damped_inverse(jt, law.damping, law.damping_threshold)
    eta = matvec(inverse, xi_star_dot + law._feedback(e))
    info = {"damping": lam2, "sigma_min": sigma_min}
    if law.criterion is not None:
        value, grad = jax.value_and_grad(lambda qq: law.criterion(robot, qq, task, xi_star))(q)
        projector = jnp.eye(robot.n_eta, dtype=jt.dtype) - matmul(inverse, jt)
        eta = eta + law._self_motion(projector, robot.S(q) * scale, grad)
        info["P"] = value
    return law._finish(robot, eta * scale, info)


@pytree("feedback", "damping", "damping_threshold")
@dataclass(frozen=True, eq=False)
class AugmentedJacobian(_Law):
    """Korayem eq. (30): the square system [J̄; J̄_z] η = ξ̇* + K e over the stacked task (task, extra).

    ``extra``: a model :class:`~mobman.model.task.Task` with n_eta − task.dim rows (Korayem's choices:
    ``stack(PlanarAngle(), FunctionTask(robots.elbow_angle, ("beta",)))`` or ``MountPosition()``); the
    reference then has task.dim + extra.dim components. ``feedback`` K on the whole stacked error (None: 0).
    """

    extra: Task | None = None
    feedback: np.ndarray | None = None

    def __post_init__(self) -> None:
        if not isinstance(self.extra, Task):
            raise ModelError("AugmentedJacobian: extra must be a model Task (the extra rows J_z)")
        if self.feedback is not None:
            object.__setattr__(self, "feedback", _gain(self.feedback, "feedback", "AugmentedJacobian"))
        self._check_options("AugmentedJacobian")

    def __call__(self, robot, task: Task, q, t, xi_star, xi_star_dot):
        task = robot.task if task is None else task
        if task.dim + self.extra.dim != robot.n_eta:
            raise ModelError(
                f"AugmentedJacobian: task ({task.dim}) + extra ({self.extra.dim}) rows must equal "
                f"n_eta = {robot.n_eta} of {robot.name}"
            )
        frames = robot.frames(q)
        xi = jnp.concatenate([task.value(robot, q, frames), self.extra.value(robot, q, frames)])
        jac = jnp.concatenate([task.jacobian(robot, q, frames), self.extra.jacobian(robot, q, frames)])
        scale = self._scale(robot)
        e = stack(task, self.extra).error(xi_star, xi)
        rhs = xi_star_dot if self.feedback is None else xi_star_dot + apply_gain(self.feedback, e, "feedback")
        jt = robot.apply_S(jac, q) * scale
        inverse, lam2, sigma_min = damped_inverse(jt, self.damping, self.damping_threshold)
        det = jnp.abs(jnp.linalg.det(jnp.concatenate([robot.constraints(q), jac])))
        info = {"damping": lam2, "sigma_min": sigma_min, "det": det}
        return self._finish(robot, matvec(inverse, rhs) * scale, info)


Law = BaylePseudoInverse | NaitChabane | AugmentedJacobian

__all__ = ["AugmentedJacobian", "BaylePseudoInverse", "Law", "NaitChabane", "apply_gain", "damped_inverse"]
