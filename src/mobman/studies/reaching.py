"""Reaching a target with the arm, the platform parked: damped least-squares inverse kinematics within the
joint limits, from several starting postures.

With the platform at a pose (x, y, θ), the arm's coordinates q_a are driven towards the task target ξ* by

    Δq_a = J_aᵀ (J_a J_aᵀ + λ² I)⁻¹ e,   q_a ← clip(q_a + Δq_a, lower, upper),

with e the task's error of ξ(q) with respect to ξ* (the difference, or the rotation vector of a
:class:`~mobman.model.tasks.pose.Pose`), J_a the arm's columns of J (Bayle §3; the ``arm`` level of
:mod:`mobman.manipulability`) and every step shortened to at most :data:`MAX_STEP` in each coordinate.
Projection onto the joint limits keeps every posture admissible. Each base and target keeps one start
(:func:`best`): of those that reach the target, the one of highest manipulability.
The solver is one compiled loop (``lax.fori_loop``) batched over bases, starts and targets by
:func:`mobman.engine.batched.batched`; a large problem runs as several such calls of :data:`CHUNK`
rows, with its progress reported and Ctrl-C answered between them. :mod:`mobman.studies.placement` (many bases, one target) and
:mod:`mobman.studies.maps` (one base, many targets) are built on it.
"""

from __future__ import annotations

import math
from typing import Callable

import jax
import jax.numpy as jnp
import numpy as np
import numpy.typing as npt

from mobman import kinematics as K
from mobman import manipulability as mp
from mobman.engine.batched import MIN_SHARE, batched
from mobman.model.robot import MobileManipulator
from mobman.model.tasks import Task
from mobman.redundancy import sample_configurations

DAMPING = 1e-3
"""λ of the damped least-squares step (in the task's units): small enough not to slow the last steps down
(their error shrinks by about λ²/σ_min² per step), large enough to keep a step bounded at a singular J_a."""

MAX_STEP = 0.5
"""Largest change of one arm coordinate per step (rad or m): a step from far away stays in the region where
J_a describes the motion."""


CHUNK = 2 * MIN_SHARE
"""Rows (base, target and start) of one compiled call of :func:`reach`: a larger problem runs as calls of
this many rows, reporting its progress and answering Ctrl-C between them. Two shares of
:data:`mobman.engine.batched.MIN_SHARE`, so that every call still runs on two cores."""


def starting_postures(robot: MobileManipulator, starts: int, seed: int = 0) -> np.ndarray:
    """``starts`` postures of the arm's coordinates, (starts, n_q − n_platform): 0 clipped to the joint
    limits, then seeded random ones over the limits (:func:`mobman.redundancy.sample_configurations`)."""
    arm_part = slice(robot.n_platform, robot.n_q)
    lower, upper = np.array(robot.position_limits).T
    first = np.clip(np.zeros(robot.n_q), lower, upper)[arm_part]
    seeds = sample_configurations(robot, starts - 1, seed)[:, arm_part]
    return np.concatenate([first[None], seeds])


@batched({1: 1, 2: 1, 3: 1}, static=(0, 4, 5))
def _solve(
    robot: MobileManipulator,
    base: jax.Array,
    start: jax.Array,
    target: jax.Array,
    task: Task,
    iterations: int,
) -> tuple[jax.Array, jax.Array]:
    """Damped least squares on the arm's coordinates from ``start`` with the platform at ``base`` (module
    notes): (the last posture, the norm of its error)."""
    n_p = robot.n_platform
    platform = jnp.concatenate([base, jnp.zeros(n_p - 3, base.dtype)])
    lower, upper = (jnp.asarray(b[n_p:], base.dtype) for b in np.array(robot.position_limits).T)

    def error(q_a):
        q = jnp.concatenate([platform, q_a])
        return task.error(target, task.value(robot, q, robot.frames(q))), q

    def least_squares(j, e):
        gram = j @ j.T + DAMPING**2 * jnp.eye(j.shape[0], dtype=j.dtype)
        return j.T @ jnp.linalg.solve(gram, e)

    def step(_, q_a):
        e, q = error(q_a)
        j_a = K.jacobian_one(robot, task, q)[:, n_p:]
        delta = least_squares(j_a, e)
        # joints at a limit that the step pushes further out are held: the step is taken by the others
        held = ((q_a <= lower) & (delta < 0)) | ((q_a >= upper) & (delta > 0))
        delta = least_squares(jnp.where(held, 0.0, j_a), e)
        delta = delta * jnp.minimum(1.0, MAX_STEP / jnp.maximum(jnp.max(jnp.abs(delta)), 1e-300))
        return jnp.clip(q_a + delta, lower, upper)

    q_a = jax.lax.fori_loop(0, iterations, step, jnp.clip(start, lower, upper))
    e, q = error(q_a)
    return q, jnp.linalg.norm(e)


def reach(
    robot: MobileManipulator,
    bases: npt.ArrayLike,
    targets: npt.ArrayLike,
    starts: np.ndarray,
    task: Task,
    iterations: int,
    progress: Callable[[int, int], None] | None = None,
    bucket: int = 1,
) -> tuple[np.ndarray, np.ndarray]:
    """The posture reached from each of ``starts`` (S, n_q − n_platform) for each pair of platform pose
    ``bases`` (..., 3) and task target ``targets`` (..., m), broadcast against each other: (q (..., S, n_q),
    the norm of the task's error there (..., S)). The platform's further coordinates, such as a steering
    angle, are 0. An error is inf where J was undefined on the way (an Euler task's gimbal lock). The
    arguments are taken as checked (the callers check them).

    The rows run as calls of :data:`CHUNK` (module notes), the last one padded to a whole call, so that a
    problem compiles the solver once; ``progress(done, total)`` is called with the rows done after each
    call. ``bucket``: a problem of one call is padded to a whole multiple of this many rows, so that
    problems whose sizes differ a little (a map's cells at other heights) share a compiled solver."""
    base = np.asarray(bases, dtype=float)[..., None, :]
    target = np.asarray(targets, dtype=float)[..., None, :]
    start = np.asarray(starts, dtype=float)
    lead = np.broadcast_shapes(base.shape[:-1], start.shape[:-1], target.shape[:-1])
    rows = math.prod(lead)
    flat = [np.broadcast_to(a, lead + a.shape[-1:]).reshape(rows, a.shape[-1]) for a in (base, start, target)]
    size = CHUNK if rows > CHUNK else -(-rows // bucket) * bucket
    q, error = np.empty((rows, robot.n_q)), np.empty(rows)
    for first in range(0, rows, CHUNK):
        done = min(first + CHUNK, rows)
        take = np.minimum(np.arange(first, first + size), rows - 1)  # padded with the last row
        q_chunk, error_chunk = _solve(robot, *(f[take] for f in flat), task, int(iterations))
        q[first:done], error[first:done] = np.asarray(q_chunk)[: done - first], error_chunk[: done - first]
        if progress is not None:
            progress(done, rows)
    return q.reshape(lead + (robot.n_q,)), np.where(np.isnan(error), np.inf, error).reshape(lead)


def best(
    robot: MobileManipulator,
    q: np.ndarray,
    error: np.ndarray,
    tolerance: float,
    task: Task,
    measure: str,
    level: str,
    free: np.ndarray | None = None,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """One start of :func:`reach`'s per pair: among the starts that reach the target (error ≤
    ``tolerance``) with a posture free of collision (``free`` (..., S), :mod:`mobman.studies.clearance`; every
    posture when None), the one where the manipulability ``measure`` of the ``level`` Jacobian (``"arm"``: J_a,
    ``"system"``: J̄ = J S) of ``task`` is highest; where none does, the one of least error. Returns
    (q (..., n_q), error (...,), score (...,): the measure there, NaN exactly where no start reached the
    target with a free posture). Several starts often reach a target in different postures (elbow up or
    down, another torso height): the measure, not the round-off of their errors, decides between them."""
    reached = error <= tolerance
    if free is not None:
        reached = reached & free
    # every start's measure, kept where it reaches: one array shape for any number of reached starts, so
    # that the measures' program compiles once per shape of the problem, not once per count reached
    measured = np.asarray(mp.jacobian_and_measures(robot, np.nan_to_num(q), level, task)[1][measure])
    rank = np.where(reached, np.nan_to_num(measured), np.nan)
    chosen = np.where(
        reached.any(axis=-1), np.argmax(np.where(reached, rank, -np.inf), axis=-1), np.argmin(error, axis=-1)
    )
    take = chosen[..., None]
    return (
        np.take_along_axis(q, take[..., None], axis=-2)[..., 0, :],
        np.take_along_axis(error, take, axis=-1)[..., 0],
        np.take_along_axis(rank, take, axis=-1)[..., 0],
    )


__all__ = ["DAMPING", "MAX_STEP", "best", "reach", "starting_postures"]
