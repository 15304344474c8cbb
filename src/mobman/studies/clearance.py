"""Collision-free postures: which postures a study finds are free of the robot itself and of a scene.

A posture of a reachability map's cell or of a placement's base counts only when its robot is free of
collision: the smallest signed distance over the pairs of its collision model (:mod:`mobman.collision`: every
sphere with every obstacle and the floor of the scene, and the self-collision pairs of
:class:`~mobman.model.collision_model.CollisionModel`, the platform's spheres included) is ≥ 0. The spheres
cover the robot's shapes and reach at most the cover tolerance τ beyond them, so a posture accepted is free of
collision for the shapes themselves, and one rejected comes within τ of a collision (docs/collision.md).

:data:`COVER_TOLERANCE` is the studies' default τ: coarser than the distance queries' 0.05 m, since a study
checks every posture it finds (TIAGo's covers: 132 spheres and 3,912 self pairs at 0.1 m, 646 and 44,356 at
0.05 m).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import partial

import jax
import jax.numpy as jnp
import numpy as np

from mobman import collision
from mobman.engine.batched import blocked
from mobman.errors import InputError
from mobman.model.collision_model import CollisionModel, collision_model
from mobman.model.robot import MobileManipulator
from mobman.model.scene import Scene

COVER_TOLERANCE = 0.1
"""The cover tolerance τ (m) of the collision model a study builds for a robot (module notes)."""

BUCKET = 1024
"""The postures checked are padded to a whole multiple of this many (one compiled program per multiple)."""


@dataclass(frozen=True)
class Clearance:
    """What the postures of a study are checked against: the robot's collision ``model`` (its self pairs)
    and the ``scene`` (no obstacle and no floor: the self pairs alone)."""

    model: CollisionModel
    scene: Scene = Scene()

    def describe(self) -> dict:
        """A JSON-friendly description (a study's definition holds it)."""
        return {
            "tolerance": self.model.tolerance,
            "spheres": len(self.model.spheres),
            "self_pairs": len(self.model.sphere_pairs),
            "scene": self.scene.describe(),
        }


def clearance_of(
    robot: MobileManipulator, model: CollisionModel | None, scene: Scene | None
) -> Clearance | None:
    """The checks a study makes: None when neither a collision model nor a scene is given; with a scene alone,
    the robot's :func:`~mobman.model.collision_model.collision_model` at :data:`COVER_TOLERANCE`."""
    if scene is not None and not isinstance(scene, Scene):
        raise InputError(f"scene must be a mobman.model.scene.Scene, got {type(scene).__name__}")
    if model is not None:
        if not isinstance(model, CollisionModel):
            raise InputError(
                f"collision must be a mobman.model.collision_model.CollisionModel, got {type(model).__name__}"
            )
        if model.robot is not robot and model.robot != robot:
            raise InputError(f"collision: the collision model is of another robot than {robot.name!r}")
    elif scene is None:
        return None
    if model is None:
        model = collision_model(robot, COVER_TOLERANCE)
    return Clearance(model, Scene() if scene is None else scene)


@partial(jax.jit, static_argnums=(0, 1))
def _smallest(model: CollisionModel, scene: Scene, q: jax.Array) -> jax.Array:
    """The smallest signed distance over every pair at each configuration of q (N, n_q); +inf without pairs."""

    def one(x: jax.Array) -> jax.Array:
        distance = collision.distances_one(model, scene, x)[0]  # the rows are left out of the program
        return jnp.min(distance, initial=jnp.inf)

    return blocked(one)(q)


def smallest_distance(checks: Clearance, q: np.ndarray, which: np.ndarray) -> np.ndarray:
    """The smallest signed distance (m) over every pair of ``checks`` at the postures q (..., n_q) where
    ``which`` (...) holds, NaN elsewhere (only those are computed)."""
    flat = q.reshape(-1, q.shape[-1])
    index = np.flatnonzero(np.reshape(which, -1))
    out = np.full(len(flat), np.nan)
    if len(index):
        rows = np.concatenate([index, np.full(-len(index) % BUCKET, index[0])])
        out[index] = np.asarray(_smallest(checks.model, checks.scene, flat[rows]))[: len(index)]
    return out.reshape(q.shape[:-1])


def free_postures(checks: Clearance | None, q: np.ndarray, which: np.ndarray) -> np.ndarray:
    """Which postures q (..., n_q) are free of collision (module notes), checked where ``which`` (...) holds
    and True elsewhere; all True without ``checks``."""
    if checks is None:
        return np.ones(q.shape[:-1], dtype=bool)
    return ~(smallest_distance(checks, q, which) < 0)


__all__ = ["BUCKET", "COVER_TOLERANCE", "Clearance", "clearance_of", "free_postures", "smallest_distance"]
