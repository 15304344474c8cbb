"""The clearance of a planned motion: its distances to a scene and to the robot itself along the path.

A plan of Tchoń, Jakubiak & Muszyński (2002) gives the configurations q(t_k) = (q_p(t_k), x) of its motion on the
integration grid (:func:`mobman.planning.endpoint.configuration_path`; the arm held at x, §2). At every sample,
every pair of the robot's collision model (:mod:`mobman.collision`: its spheres against each obstacle and the
floor of the scene, and its self-collision pairs) has a signed distance, all samples evaluated in one batched
call. Reported: the smallest distance over the pairs and the samples with its pair, time and witness points, and
the first sample at which some pair penetrates (distance < 0) with its deepest pair. The samples are T/steps
apart: a contact shorter than that between two samples goes unseen.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from mobman import collision
from mobman.model.collision_model import CollisionModel
from mobman.model.scene import Scene


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


__all__ = ["PairAt", "PathClearance", "path_clearance"]
