"""Batched, differentiable kinematics of mobile manipulators (Bayle §3–4).

Every function takes a robot, configurations ``q`` of shape (..., n_q) and optionally a task (the robot's
own task by default), and returns arrays with the same leading dimensions. Each is written for one
configuration and batched by :func:`mobman.engine.batched.batched`: validated once, compiled with the robot and
the task as static arguments (a second call with the same shapes does not retrace), evaluated in blocks.
Traced code (inside ``jit``, ``grad``, ``vmap``) calls the per-configuration kernels
(:func:`jacobian_one`, :func:`reduced_jacobian_one`).

- :func:`forward` ξ = f(q)
- :func:`jacobian` J = ∂f/∂q (geometric for position/orientation tasks, autodiff otherwise)
- :func:`S`, :func:`constraints` the admissible-velocity basis and the nonholonomic constraints
- :func:`reduced_jacobian` J̄ = J S (Bayle eq. 2)
- :func:`representation_singular` where the task's coordinates are singular as a representation
- :func:`inverse_velocity` η = J̄# ξ̇ + (I − J̄# J̄) z, q̇ = S η (Bayle §4.3)
- :func:`is_consistent` rank[J̄ | ξ̇] = rank J̄
"""

from __future__ import annotations

from typing import Callable

import jax
import jax.numpy as jnp
import numpy as np
import numpy.typing as npt

from mobman.checks import all_finite
from mobman.engine.batched import batched, traced
from mobman.errors import InputError, SingularConfigurationError
from mobman.model.robot import Frames, MobileManipulator, compiled_frames
from mobman.model.tasks import Task


def checked_robot(robot: object) -> MobileManipulator:
    """``robot`` itself, or an InputError when it is not a :class:`mobman.MobileManipulator`."""
    if not isinstance(robot, MobileManipulator):
        raise InputError(f"robot must be a MobileManipulator, got {type(robot).__name__}")
    return robot


def resolve_task(robot: MobileManipulator, task: Task | None) -> Task:
    """The task to evaluate: ``task``, or the robot's own when None, checked against the robot."""
    task = checked_robot(robot).task if task is None else task
    task.check(robot)
    return task


# --- single-configuration kernels (for traced code) ------------------------------------------------


def jacobian_one(robot: MobileManipulator, task: Task, q: jnp.ndarray) -> jnp.ndarray:
    """J = ∂f/∂q (m × n_q) of one configuration ``q`` (n_q,), unvalidated: for traced code (Bayle §4)."""
    return task.jacobian(robot, q, robot.frames(q))


def reduced_jacobian_one(robot: MobileManipulator, task: Task, q: jnp.ndarray) -> jnp.ndarray:
    """J̄ = J S (m × δ) of one configuration ``q`` (n_q,), unvalidated: for traced code (Bayle §4.2)."""
    return task.reduced_jacobian(robot, q, robot.frames(q))


# --- public batched API ----------------------------------------------------------------------------


def validated_q(robot: MobileManipulator, q: npt.ArrayLike) -> np.ndarray | jax.Array:
    """Validated configurations. NumPy arrays go to the compiled functions as they are; a ``jax.Array`` is
    checked on its device and passed on without a copy to the host."""
    if type(q) is np.ndarray:  # the common case first (a call for one configuration is mostly overhead)
        return checked_robot(robot).validate_q(q)
    if isinstance(q, jax.Array) and traced(q):
        return q
    if isinstance(q, jax.Array):
        return checked_robot(robot).validate_q_on_device(q)
    return checked_robot(robot).validate_q(q)


def _robot_q(robot: MobileManipulator, q: npt.ArrayLike) -> tuple:
    return robot, validated_q(robot, q)


def _robot_q_task(robot: MobileManipulator, q: npt.ArrayLike, task: Task | None = None) -> tuple:
    return robot, validated_q(robot, q), resolve_task(robot, task)


@batched({1: 1}, static=(0, 2), validate=_robot_q_task)
def forward(robot: MobileManipulator, q: jax.Array, task: Task | None = None) -> jnp.ndarray:
    """Operational coordinates ξ = f(q), shape (..., m)."""
    assert task is not None  # resolved by the validator
    return task.value(robot, q, robot.frames(q))


@batched({1: 1}, static=(0, 2), validate=_robot_q_task)
def jacobian(robot: MobileManipulator, q: jax.Array, task: Task | None = None) -> jnp.ndarray:
    """Jacobian J(q) = ∂f/∂q, shape (..., m, n_q) (Bayle §3)."""
    assert task is not None  # resolved by the validator
    return jacobian_one(robot, task, q)


@batched({1: 1}, static=(0, 2), validate=_robot_q_task)
def reduced_jacobian(robot: MobileManipulator, q: jax.Array, task: Task | None = None) -> jnp.ndarray:
    """Reduced Jacobian J̄(q) = J(q) S(q), shape (..., m, n_eta): ξ̇ = J̄ η (Bayle eq. 2)."""
    assert task is not None  # resolved by the validator
    return reduced_jacobian_one(robot, task, q)


@batched({1: 1}, static=(0, 2), validate=_robot_q_task)
def first_order(robot: MobileManipulator, q: jax.Array, task: Task | None = None) -> dict[str, jnp.ndarray]:
    """ξ = f(q), J, J̄ = J S (Bayle eq. 1–2) and whether ξ is singular as a representation there
    (:func:`representation_singular`), from one compiled program: ``{"xi": (..., m), "J": (..., m, n_q),
    "J_bar": (..., m, n_eta), "representation_singular": (...)}``. What an analysis of configurations needs
    at once, for the cost of tracing and compiling one program instead of four (J̄ formed from J)."""
    assert task is not None  # resolved by the validator
    frames = robot.frames(q)
    j = task.jacobian(robot, q, frames)
    return {
        "xi": task.value(robot, q, frames),
        "J": j,
        "J_bar": robot.apply_S(j, q),
        "representation_singular": task.representation_singular(robot, q, frames),
    }


@batched({1: 1}, static=(0, 2), validate=_robot_q_task)
def _representation(robot: MobileManipulator, q: jax.Array, task: Task | None = None) -> jnp.ndarray:
    assert task is not None  # resolved by the validator
    return task.representation_singular(robot, q, robot.frames(q))


def representation_singular(
    robot: MobileManipulator, q: npt.ArrayLike, task: Task | None = None
) -> np.ndarray:
    """True where the task's coordinates are singular as a representation (the heading of a vertical axis,
    an Euler set's gimbal lock; :mod:`mobman.model.task`), boolean, shape (...). There ξ is not a chart of the
    frame and J, J̄ may be unbounded or NaN; kinematic and velocity singularities (KSC, VSC) are another
    matter, a property of the robot."""
    return np.asarray(_representation(robot, q, task), dtype=bool)


@batched({1: 1}, static=(0,), validate=_robot_q)
def S(robot: MobileManipulator, q: jax.Array) -> jnp.ndarray:
    """Admissible-velocity basis S(q), shape (..., n_q, n_eta): q̇ = S(q) η."""
    return robot.S(q)


@batched({1: 1}, static=(0,), validate=_robot_q)
def constraints(robot: MobileManipulator, q: jax.Array) -> jnp.ndarray:
    """Nonholonomic constraint rows G(q), shape (..., n_q − n_eta, n_q): G(q) q̇ = 0."""
    return robot.constraints(q)


def frames(robot: MobileManipulator, q: npt.ArrayLike) -> Frames:
    """World poses of platform, mounts and arm frames of configurations q (..., n_q) (see :class:`Frames`):
    NumPy arrays from one compiled program (:func:`mobman.model.robot.compiled_frames`); traced q is
    evaluated in the caller's program."""
    q = validated_q(robot, q)
    return robot.frames(q) if traced(q) else compiled_frames(robot, q)


def _vector(x: npt.ArrayLike, name: str, size: int) -> np.ndarray | jax.Array:
    """A finite float array (..., size), or InputError naming ``name``."""
    if traced(x):
        return x
    try:
        arr = np.asarray(x, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"{name}: expected numbers, shape (..., {size}), got {type(x).__name__}") from None
    if arr.ndim < 1 or arr.shape[-1] != size:
        raise InputError(f"{name}: expected shape (..., {size}), got {arr.shape}")
    if not all_finite(arr):
        raise InputError(f"{name}: every component must be finite")
    return arr


def pinv(a: jnp.ndarray) -> jnp.ndarray:
    """Moore–Penrose inverse, batched (the default generalized inverse)."""
    return jnp.linalg.pinv(a)


def inverse_velocity(
    robot: MobileManipulator,
    q: npt.ArrayLike,
    xi_dot: npt.ArrayLike,
    z: npt.ArrayLike | None = None,
    task: Task | None = None,
    inverse: Callable[[jnp.ndarray], jnp.ndarray] = pinv,
) -> tuple[jnp.ndarray, jnp.ndarray]:
    """Reduced inverse velocity kinematics (Bayle §4.3): η = J̄# ξ̇ + (I − J̄# J̄) z, then q̇ = S(q) η.

    ``inverse`` is any generalized inverse (J̄ J̄# J̄ = J̄); the Moore–Penrose inverse by default. ``z`` is
    an arbitrary vector of size n_eta (zero by default). The result is exact only when ξ̇ is consistent
    (see :func:`is_consistent`); otherwise it is the least-squares solution of the chosen inverse.
    Returns (η, q̇).
    """
    task = resolve_task(robot, task)
    q = validated_q(robot, q)
    xi_dot = jnp.asarray(_vector(xi_dot, "xi_dot", task.dim))
    jbar = reduced_jacobian(robot, q, task)
    if not traced(jbar) and not bool(jnp.all(jnp.isfinite(jbar))):
        raise SingularConfigurationError(
            "inverse_velocity: J̄ holds NaN or infinite entries where the task's coordinates are singular as a "
            "representation (see representation_singular)"
        )
    jsharp = inverse(jbar)
    eta = jnp.einsum("...ij,...j->...i", jsharp, xi_dot)
    if z is not None:
        z = jnp.asarray(_vector(z, "z", robot.n_eta))
        projector = jnp.eye(robot.n_eta) - jsharp @ jbar
        eta = eta + jnp.einsum("...ij,...j->...i", projector, z)
    q_dot = jnp.einsum("...ij,...j->...i", S(robot, q), eta)
    return eta, q_dot


def rank(a: npt.ArrayLike, rtol: float = 1e-9) -> np.ndarray:
    """Numerical rank of (batched) matrices: singular values above rtol · σmax (absolute floor 1e-12).
    InputError for NaN or infinite entries (their rank is undefined)."""
    try:
        a = np.asarray(a, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"rank: expected an array of numbers, got {type(a).__name__}") from None
    if a.ndim < 2:
        raise InputError(f"rank: expected matrices of shape (..., m, k), got shape {a.shape}")
    if not np.isfinite(a).all():
        bad = np.argwhere(~np.isfinite(a).all(axis=(-2, -1)))
        where = f" at batch index {tuple(int(i) for i in bad[0])}" if bad.size else ""
        raise InputError(f"rank: the matrix holds NaN or infinite entries{where}")
    s = np.linalg.svd(a, compute_uv=False)
    smax = s[..., :1] if s.shape[-1] else np.zeros(s.shape[:-1] + (1,))
    return np.sum(s > np.maximum(rtol * smax, 1e-12), axis=-1)


def is_consistent(
    robot: MobileManipulator,
    q: npt.ArrayLike,
    xi_dot: npt.ArrayLike,
    task: Task | None = None,
    rtol: float = 1e-9,
) -> np.ndarray:
    """Consistency of the reduced kinematics: rank[J̄ | ξ̇] = rank J̄ (Bayle §4.3), batched."""
    task = resolve_task(robot, task)
    jbar = np.asarray(reduced_jacobian(robot, q, task))
    xi_dot = _vector(xi_dot, "xi_dot", task.dim)
    try:
        xi_dot = np.broadcast_to(xi_dot, jbar.shape[:-1])
    except ValueError:
        raise InputError(
            f"xi_dot of shape {xi_dot.shape} does not match the configurations' batch shape {jbar.shape[:-2]}"
        ) from None
    augmented = np.concatenate([jbar, xi_dot[..., None]], axis=-1)
    return rank(augmented, rtol) == rank(jbar, rtol)
