"""The interface of the operational control laws, η = law(q, t, ξ*, ξ̇*), their typed result and their registry.

Every law is a frozen dataclass and a JAX pytree: its gains (``W``, ``k``, ``feedback``), damping
parameters and the numbers of its criterion (see :mod:`mobman.control.criteria`) are array leaves, so
a list of laws differing only in gains is batched by ``jax.vmap`` (see :func:`mobman.control.simulate`);
the other options are static. ``law(robot, task, q, t, xi_star, xi_star_dot)`` acts on one configuration and
returns a :class:`LawStep` (η and what the simulation records per step: damping, σ_min, saturation, and
the law's own entries such as the criterion value ``P`` or ``det``). ``law.controlled_task(task)`` is the task
whose error the law regulates (the task itself, or the task stacked with the law's extra rows).

The operational error
---------------------
Every law takes e from the task, ``task.error(ξ*, ξ)``: the difference ξ* − ξ for the tasks whose value is
a point of Rᵐ (the papers' tasks: the same numbers as a plain subtraction), and for a
:class:`~mobman.model.tasks.Pose` the position difference and the rotation vector log(R* Rᵀ), with ξ̇* and
the Jacobian rows in the same coordinates (linear and angular velocity).

Options shared by all laws
--------------------------
``normalized``: weighted pseudo-inverse with R = diag(robot.velocity_limits): η = R (J̄R)⁺ …, i.e. the
    solution of minimum ‖R⁻¹ η‖ (Nait-Chabane's normalisation, eq. 20–26); the null-space term is formed in
    the same scaled coordinates (H = S R (I − (J̄R)⁺ J̄R)).
``damping`` (λ_max) and ``damping_threshold`` (ε): damped least squares J̄# = J̄ᵀ (J̄J̄ᵀ + λ² I)⁻¹ with the
    variable damping of Nakamura & Hanafusa / Chiaverini: λ² = λ_max² (1 − (σ_min/ε)²) when σ_min < ε, 0
    otherwise (σ_min the smallest singular value of the matrix inverted). Away from singularities the law is
    exact; near them the error dynamics are only approximately ė + W e = 0. ``LawStep.damped`` reports it.
    With ``damping=0`` an exactly singular J̄ gives non-finite η, which :func:`simulate` reports as an error.
``saturate``: η is scaled uniformly by 1/max_i(|η_i|/η_i,max) when a limit is exceeded (the direction of
    η, hence of ξ̇, is kept; the tracking lags). ``LawStep.limit_ratio`` = max_i |η_i|/η_i,max before
    saturation (also when ``saturate`` is off) and ``LawStep.saturated`` whether scaling was applied.

Kinds
-----
A subclass that sets ``kind`` registers itself (:func:`law_class`, :func:`law_kinds`); specification files
name the law by kind in ``[law]``, give the fields named in ``gains`` in ``[gains]``, the other fields in
``[law]`` and a ``criterion`` field in ``[criterion]``.
"""

from __future__ import annotations

from dataclasses import dataclass, field, fields
from typing import TYPE_CHECKING, Any, ClassVar

import jax.numpy as jnp
import numpy as np
import numpy.typing as npt

from mobman.control._tree import pytree
from mobman.errors import ModelError
from mobman.model.kinds import Kinds
from mobman.model.spatial import matmul
from mobman.model.spectra import eigvalsh

if TYPE_CHECKING:
    from mobman.model.robot import MobileManipulator
    from mobman.model.tasks import Task


def positive_gain(value: Any, name: str, owner: str, allow_zero: bool = False) -> np.ndarray:
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


def apply_gain(gain: npt.ArrayLike, e: jnp.ndarray, name: str = "gain") -> jnp.ndarray:
    """W e for a scalar, diagonal (vector) or full (matrix) gain."""
    gain = jnp.asarray(gain)
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


def damped_inverse(
    a: jnp.ndarray, damping: float, threshold: float
) -> tuple[jnp.ndarray, jnp.ndarray, jnp.ndarray]:
    """Right inverse aᵀ (a aᵀ + λ² I)⁻¹ of a (m × k, m ≤ k) with the variable damping λ² described in the
    module docstring. Returns (inverse, λ², σ_min).

    The laws' small products are broadcast sums (``spatial.matmul``), which XLA fuses with their neighbours;
    a library matrix product is a kernel of its own, and a law runs once per simulation step."""
    gram = matmul(a, a.T)
    sigma_min = jnp.sqrt(jnp.maximum(eigvalsh(gram)[-1], 0.0))
    lam2 = damping**2 * (1.0 - jnp.minimum(sigma_min / threshold, 1.0) ** 2)
    inverse = matmul(a.T, _small_inverse(gram + lam2 * jnp.eye(a.shape[0], dtype=a.dtype)))
    return inverse, lam2, sigma_min


@pytree("eta", "damping", "sigma_min", "limit_ratio", "saturated", "damped")
@dataclass(frozen=True)
class LawStep:
    """What a law gives for one configuration: the quasi-velocities ``eta`` (n_eta) and the scalars the
    simulation records per step: ``damping`` λ², ``sigma_min`` of the matrix inverted, ``limit_ratio``
    max_i |η_i|/η_i,max before saturation (0 without velocity limits), ``saturated`` and ``damped`` (λ² > 0).
    Laws add their own entries in subclasses (fields that may be None when the law has nothing to report)."""

    eta: jnp.ndarray
    damping: jnp.ndarray
    sigma_min: jnp.ndarray
    limit_ratio: jnp.ndarray
    saturated: jnp.ndarray
    damped: jnp.ndarray

    def recorded(self) -> dict[str, jnp.ndarray]:
        """Every entry but η (those that are not None), by name: the simulation's ``info`` per step."""
        values = {f.name: getattr(self, f.name) for f in fields(self) if f.name != "eta"}
        return {name: value for name, value in values.items() if value is not None}


LAWS: Kinds[type[Law]] = Kinds("law")
"""The law classes by kind."""


@dataclass(frozen=True, eq=False)
class Law:
    """Base class of the laws: the options shared by all (module docstring), the saturation, the registry.

    ``kind``: the name in specification files (empty: not in files); ``gains``: the fields given in the
    ``[gains]`` table of a specification file.
    """

    kind: ClassVar[str] = ""
    gains: ClassVar[tuple[str, ...]] = ()

    damping: float = field(default=0.0, kw_only=True)
    damping_threshold: float = field(default=0.05, kw_only=True)
    normalized: bool = field(default=False, kw_only=True)
    saturate: bool = field(default=False, kw_only=True)

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        LAWS.add(cls)

    def __call__(
        self,
        robot: MobileManipulator,
        task: Task | None,
        q: jnp.ndarray,
        t: jnp.ndarray,
        xi_star: jnp.ndarray,
        xi_star_dot: jnp.ndarray,
    ) -> LawStep:
        """η and the recorded entries at one configuration ``q`` and time ``t`` for the reference
        (ξ*, ξ̇*) of the controlled task (``task=None``: the robot's own)."""
        raise NotImplementedError

    def controlled_task(self, task: Task) -> Task:
        """The task whose error the law regulates and whose reference it takes: ``task`` itself here."""
        return task

    def check_options(self, owner: str) -> None:
        """Validate the shared options (``owner``: the name in the messages), from ``__post_init__``."""
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

    def _limits(self, robot: MobileManipulator) -> np.ndarray | None:
        limits = robot.velocity_limits
        if limits is None and (self.normalized or self.saturate):
            option = "normalized" if self.normalized else "saturate"
            raise ModelError(
                f"{type(self).__name__}: {option}=True needs velocity limits, {robot.name} has none"
            )
        return None if limits is None else np.asarray(limits)

    def scale(self, robot: MobileManipulator) -> np.ndarray:
        """R: the velocity limits when normalised, ones otherwise."""
        limits = self._limits(robot) if self.normalized else None
        return np.ones(robot.n_eta) if limits is None else limits

    def saturation(
        self, robot: MobileManipulator, eta: jnp.ndarray
    ) -> tuple[jnp.ndarray, jnp.ndarray, jnp.ndarray]:
        """(η after the ``saturate`` option, the limit ratio max_i |η_i|/η_i,max before it, whether it scaled η)."""
        limits = self._limits(robot)
        if limits is None:
            ratio = jnp.zeros((), eta.dtype)
        else:
            ratio = jnp.max(jnp.abs(eta) / limits)
        saturated = (ratio > 1.0) if self.saturate else jnp.zeros((), bool)
        if self.saturate:
            eta = eta / jnp.maximum(ratio, 1.0)
        return eta, ratio, saturated


def law_kinds() -> tuple[str, ...]:
    """The registered law kinds, sorted."""
    return LAWS.kinds()


def law_class(kind: str) -> type[Law]:
    """The law class registered under ``kind``; an unknown kind raises ModelError naming the closest one."""
    return LAWS.get(kind)


__all__ = [
    "LAWS",
    "Law",
    "LawStep",
    "apply_gain",
    "damped_inverse",
    "law_class",
    "law_kinds",
    "positive_gain",
]
