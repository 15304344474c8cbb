"""Collision avoidance as velocity dampers (Faverjon & Tournassoud 1987; the form of the holistic/NEO controller,
Haviland & Corke 2021): the rows that :class:`~mobman.control.laws.WholeBodyQP` adds to its program.

For each pair of the robot's collision spheres and the scene (or two of its own bodies) at a signed distance d
below the influence distance d_i, the distance rate ḋ = n̂ᵀ J̄_c η (:func:`mobman.collision.distances_one`, a row
over the quasi-velocities η, so the platform's nonholonomic constraint is in it) is bounded below:

    ḋ ≥ −ξ (d − d_s) / (d_i − d_s),

d_s the margin kept (``collision_margin``) and ξ the approach speed allowed at d_i (``collision_gain``, m/s).
Along the closed loop, ḋ ≥ −(ξ / (d_i − d_s)) (d − d_s): the distance beyond the margin decays at most at the
rate ξ / (d_i − d_s), so a pair that starts above d_s never goes below it, and one that starts below it (a start
in collision) is driven apart, at ḋ ≥ ξ (d_s − d) / (d_i − d_s) > 0. Under a zero-order hold of step h the
samples keep d_{k+1} ≥ d_s to first order in h when h ξ / (d_i − d_s) ≤ 1.

The program takes the ``collision_rows`` nearest pairs only (a fixed number of rows in
the compiled program): the others are farther than all of these and, while those are within d_i, the damper
bounds their approach in turn as soon as they become among the nearest. The distances are those of the sphere
cover (:mod:`mobman.model.collision_model`), never larger than the shapes' own: the margin the robot keeps from
the obstacles is d_s at least and d_s + τ at most, τ the cover tolerance.
"""

from __future__ import annotations

from dataclasses import replace
from functools import lru_cache
from typing import TYPE_CHECKING, NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from mobman import collision
from mobman.engine.kernels import definition
from mobman.model.collision_model import CollisionModel, collision_model, default_pairs
from mobman.model.scene import Scene

if TYPE_CHECKING:
    from mobman.model.robot import MobileManipulator


@lru_cache(maxsize=16)
def control_model(robot: MobileManipulator, tolerance: float, margin: float) -> CollisionModel:
    """The collision model the dampers watch: the cover of ``robot`` to the ``tolerance`` τ, its self pairs
    those of :func:`~mobman.model.collision_model.default_pairs` but the pairs closer than the ``margin``
    at the neutral posture (they could not keep it there: the wrist's links on either side of a joint)."""
    model = collision_model(robot, tolerance)
    return replace(model, pairs=default_pairs(model, margin))


class Dampers(NamedTuple):
    """The velocity-damper rows of the ``count`` nearest pairs at one configuration: ``rows`` (count, n_eta)
    and ``bound`` (count,) with ``rows · η ≥ bound`` (zero rows and −1 bounds, never active, for pairs beyond
    the influence distance), their ``active`` mask, and the nearest pair: ``distance`` (m) and ``pair`` (its
    index in :func:`mobman.collision.pair_names`)."""

    rows: jax.Array
    bound: jax.Array
    active: jax.Array
    distance: jax.Array
    pair: jax.Array


@definition
def nearest(distance: jax.Array, count: int) -> tuple[jax.Array, jax.Array]:
    """The ``count`` smallest entries of ``distance`` (P,), ascending, and their indices (ties by index)."""
    negated, index = jax.lax.top_k(-distance, count)
    return -negated, index


def dampers(
    model: CollisionModel,
    scene: Scene,
    q: jax.Array,
    margin: float,
    influence: float,
    gain: float,
    count: int,
) -> Dampers:
    """The velocity dampers ḋ ≥ −ξ (d − d_s)/(d_i − d_s) (module notes) of the ``count`` nearest pairs of
    ``model`` and ``scene`` at one configuration q (traced code), d_s = ``margin``, d_i = ``influence``,
    ξ = ``gain``."""
    distance, _, _, normal, _ = collision.distances_one(model, scene, q)  # the rows of every pair unused
    d, index = nearest(distance, min(count, distance.shape[0]))
    active = d < influence
    bound = jnp.where(active, -gain * (d - margin) / (influence - margin), -1.0)
    first, second = (jnp.asarray(s)[index] for s in collision.pair_spheres(model, scene))
    rows = collision.pair_rows_one(model, q, normal[index], first, second)
    return Dampers(jnp.where(active[:, None], rows, 0.0), bound, active, d[0], index[0])


def start_collision(model: CollisionModel, scene: Scene, q0: np.ndarray, margin: float) -> dict | None:
    """The nearest pair at the start configuration ``q0`` when it is closer than ``margin`` (m): ``pair`` (the
    two names), ``distance`` (m, negative when the spheres penetrate) and ``depth`` below the margin; None
    otherwise."""
    distance = collision.distances(model, scene, q0).distance
    nearest = int(np.argmin(distance))
    if distance[nearest] >= margin:
        return None
    return {
        "pair": list(collision.pair_names(model, scene)[nearest]),
        "distance": float(distance[nearest]),
        "depth": float(margin - distance[nearest]),
    }


def target_inside(scene: Scene, point: np.ndarray) -> dict | None:
    """The obstacle (or the floor) that holds the target ``point`` (3,), deepest first: ``obstacle`` and
    ``depth`` (m); None when the point is outside every obstacle."""
    phi = collision.point_distances(scene, point)
    deepest = int(np.argmin(phi)) if len(phi) else -1
    if deepest < 0 or phi[deepest] >= 0:
        return None
    return {"obstacle": scene.names[deepest], "depth": float(-phi[deepest])}


__all__ = ["Dampers", "dampers", "nearest", "start_collision", "target_inside"]
