"""The clearance of a planned motion: its distances to a scene and to the robot itself along the path.

A plan of Tchoń, Jakubiak & Muszyński (2002) gives the configurations q(t_k) = (q_p(t_k), x) of its motion on the
integration grid (:func:`mobman.planning.endpoint.configuration_path`; the arm held at x, §2). At every sample,
every pair of the robot's collision model (:mod:`mobman.collision`: its spheres against each obstacle and the
floor of the scene, and its self-collision pairs) has a signed distance, all samples evaluated in one batched
call. Reported: the smallest distance over the pairs and the samples with its pair, time and witness points, and
the first sample at which some pair penetrates (distance < 0) with its deepest pair. The samples are T/steps
apart: a contact shorter than that between two samples goes unseen.

:func:`avoidance` is the planners' way around obstacles: the null-space vector of the pseudo-inverse
algorithm (Tchoń et al. 2002, eq. 16), w(z) = −k ∇_z P(z), with P the clearance penalty of the whole path

    P(z) = ½ Σ_k Σ_pairs max(0, d_i − d_pair(q(t_k)))²,

d_i the influence distance: zero when every pair along the path is farther than d_i, growing as a pair comes
closer (or penetrates). Projected onto the kernel of the endpoint Jacobian, it moves the path away from the
obstacles without moving its end, so the planner still reaches its target (to first order).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import jax
import jax.numpy as jnp
import numpy as np
import numpy.typing as npt

from mobman import collision
from mobman.errors import InputError
from mobman.model.collision_model import CollisionModel
from mobman.model.scene import Scene
from mobman.planning.endpoint import PlanningSetting, configuration_path_of

INFLUENCE = 0.2
"""The default influence distance d_i of :func:`avoidance` (m)."""

GAIN = 10.0
"""The default gain of :func:`avoidance` (1/m²): on the paper's car plan past a rock (Tchoń et al.'s start P),
gains 1 and 10 converge around it, 100 no longer converges."""


@dataclass(frozen=True)
class PairAt:
    """A pair of the collision model at one sample of the path: its names (the robot's body; the obstacle,
    ``floor`` or the other body), the time (s), the signed distance (m, negative when penetrating) and the
    witness points on the robot and on the other (3,)."""

    pair: tuple[str, str]
    time: float
    distance: float
    robot_point: np.ndarray
    other_point: np.ndarray


@dataclass(frozen=True)
class PathClearance:
    """The clearance of a path: ``distance`` (T,) the smallest signed distance over the pairs at each sample
    (+inf without pairs), ``closest`` the pair at the smallest of them, ``first_collision`` the deepest pair
    at the first sample with a negative distance (None when the path is free of collision)."""

    distance: np.ndarray
    closest: PairAt | None
    first_collision: PairAt | None

    @property
    def min_distance(self) -> float | None:
        """The smallest signed distance along the path (m); None without pairs."""
        return None if self.closest is None else self.closest.distance


def path_clearance(model: CollisionModel, scene: Scene, t: npt.ArrayLike, q: npt.ArrayLike) -> PathClearance:
    """The clearance (module notes) of the motion q(t_k) (T, n_q) at the times t (T,) against ``scene`` and
    the self-collision pairs of ``model``."""
    t = np.asarray(t, dtype=float)
    out = collision.distances(model, scene, q)  # (T, P): every sample at once
    if not out.distance.shape[-1]:
        return PathClearance(np.full(len(t), np.inf), None, None)
    nearest = out.distance.argmin(axis=1)
    distance = out.distance[np.arange(len(t)), nearest]
    names = collision.pair_names(model, scene)

    def at(k: int) -> PairAt:
        p = int(nearest[k])
        return PairAt(names[p], float(t[k]), float(distance[k]), out.robot_point[k, p], out.other_point[k, p])

    colliding = np.flatnonzero(distance < 0)
    return PathClearance(
        distance, at(int(distance.argmin())), at(int(colliding[0])) if len(colliding) else None
    )


def clearance_penalty(
    setting: PlanningSetting,
    model: CollisionModel,
    scene: Scene,
    influence: float,
    z: jax.Array,
    q0: jax.Array,
) -> jnp.ndarray:
    """P(z) = ½ Σ_k Σ_pairs max(0, d_i − d)² over the path of ``setting`` (module notes), traceable."""
    q = configuration_path_of(setting, z, q0)
    d = jax.vmap(lambda qk: collision.distances_one(model, scene, qk)[0])(q)
    return 0.5 * jnp.sum(jnp.maximum(influence - d, 0.0) ** 2)


def avoidance(
    setting: PlanningSetting,
    model: CollisionModel,
    scene: Scene,
    influence: float = INFLUENCE,
    gain: float = GAIN,
) -> Callable[[jax.Array, jax.Array], jnp.ndarray]:
    """The null-space vector w(z, q0) = −gain ∇_z P(z) (module notes) of the ``"pinv"`` algorithm
    (``Options(nullspace=...)``), the path integrated with ``setting.jacobian_steps`` steps; ``influence``
    d_i (m, > 0), ``gain`` (1/m², > 0)."""
    for name, value in (("influence", influence), ("gain", gain)):
        if not (isinstance(value, (int, float)) and np.isfinite(value) and value > 0):
            raise InputError(f"avoidance: {name} must be a finite number > 0, got {value!r}")
    coarse = setting.jacobian_setting

    def w(z: jax.Array, q0: jax.Array) -> jnp.ndarray:
        return -gain * jax.grad(lambda zz: clearance_penalty(coarse, model, scene, influence, zz, q0))(z)

    return w


__all__ = ["GAIN", "INFLUENCE", "PairAt", "PathClearance", "avoidance", "clearance_penalty", "path_clearance"]
