"""Signed distances of a robot's collision spheres to a scene and to each other, and their rates over η.

Pairs
-----
For a :class:`~mobman.model.collision_model.CollisionModel` and a :class:`~mobman.model.scene.Scene`, the pairs
are, in this order: every sphere with every obstacle (sphere-major), every sphere of an arm link with the
floor (the platform rests on it), then the self-collision sphere pairs of the model
(:attr:`~mobman.model.collision_model.CollisionModel.sphere_pairs`). :func:`pair_names` names them.

Distances
---------
A sphere (centre c, radius r) and a convex obstacle O: d = φ_O(c) − r, with φ_O the signed distance of a point
to O (its distance outside, minus its depth inside), in closed form in the obstacle's frame, x = Rᵀ(c − p)
(:mod:`mobman.model.primitives`); the floor z ≤ z_f: φ = z − z_f.

Two spheres: d = ‖c_i − c_j‖ − r_i − r_j. The witness points are the closest point of the obstacle (for a
penetrating pair the point of its surface nearest to the centre) and c − r n̂ on the sphere, with n̂ the unit
normal ∇φ_O(c) pointing from the obstacle toward the sphere (from sphere j to sphere i for a self pair).

Rates over η
------------
ḋ = n̂ᵀ ċ (n̂ᵀ (ċ_i − ċ_j) for a self pair), and ċ = J_c(q) q̇ = J_c(q) S(q) η with J_c the linear velocity
Jacobian of the sphere's centre (:meth:`~mobman.model.robot.MobileManipulator.body_point_jacobian`). The row
n̂ᵀ J_c S = n̂ᵀ J̄_c over the quasi-velocities η has the platform's nonholonomic constraint built in: its
entries are the rates along the admissible motions only (a differential drive cannot slide sideways away from a
wall). Where φ is not differentiable (a centre equidistant from two faces, or at a sphere's centre) the row is
that of the normal chosen.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache, partial

import jax
import jax.numpy as jnp
import numpy as np
import numpy.typing as npt

from mobman.engine.batched import blocked
from mobman.kinematics import validated_q
from mobman.model.collision_model import CollisionModel
from mobman.model.primitives import (
    box_distance,
    capsule_distance,
    cylinder_distance,
    norm,
    sphere_distance,
    unit,
)
from mobman.model.scene import Scene


@dataclass(frozen=True)
class PairDistances:
    """Per pair (:func:`pair_names`): ``distance`` (..., P) (m, negative when penetrating), the witness
    points ``robot_point`` (on the robot's sphere i) and ``other_point`` (on the obstacle, the floor or
    sphere j), (..., P, 3), the unit ``normal`` (..., P, 3) from the other toward the robot sphere, and the
    distance-rate ``rows`` (..., P, n_eta): ḋ = rows · η."""

    distance: np.ndarray
    robot_point: np.ndarray
    other_point: np.ndarray
    normal: np.ndarray
    rows: np.ndarray


_SHAPE_DISTANCE = {
    "box": lambda x, size: box_distance(x, size / 2),
    "sphere": lambda x, size: sphere_distance(x, size[..., 0]),
    "cylinder": lambda x, size: cylinder_distance(x, size[..., 0], size[..., 1] / 2),
    "capsule": lambda x, size: capsule_distance(x, size[..., 0], size[..., 1] / 2),
}


@lru_cache(maxsize=64)
def _layout(model: CollisionModel, scene: Scene) -> dict:
    """The constant arrays of a model and a scene (NumPy): sphere bodies, centres, radii, the obstacles' poses
    and sizes grouped by shape, the floor's spheres and the self pairs."""
    bodies = {b: i for i, b in enumerate(model.bodies)}
    spheres = model.spheres
    arm_spheres = np.array([i for i, s in enumerate(spheres) if s.body[0] >= 0], dtype=int)
    groups = {}
    for shape in ("box", "sphere", "cylinder", "capsule"):
        index = [k for k, o in enumerate(scene.obstacles) if o.shape == shape]
        if index:
            obstacles = [scene.obstacles[k] for k in index]
            groups[shape] = (
                np.array(index),
                np.stack([o.rotation for o in obstacles]),
                np.array([o.position for o in obstacles]),
                np.array([o.size + (0.0,) * (3 - len(o.size)) for o in obstacles]),
            )
    pairs = np.array(model.sphere_pairs, dtype=int).reshape(-1, 2)
    # the self pairs as blocks of spheres: body a's spheres × body b's, contiguous once the spheres are
    # grouped by body (a stable sort keeps each body's order), in the order of ``sphere_pairs``
    body = np.array([bodies[s.body] for s in spheres])
    grouped = np.argsort(body, kind="stable")
    start, end = (
        np.searchsorted(body[grouped], np.arange(len(bodies))),
        np.searchsorted(body[grouped], np.arange(len(bodies)), side="right"),
    )
    blocks = tuple(
        (int(start[a]), int(end[a]), int(start[b]), int(end[b]))
        for a, b in model.pairs
        if end[a] > start[a] and end[b] > start[b]
    )
    return dict(
        body=np.array([bodies[s.body] for s in spheres]),
        centre=np.array([s.centre for s in spheres]),
        radius=np.array([s.radius for s in spheres]),
        groups=groups,
        floor=arm_spheres if scene.floor is not None else np.zeros(0, dtype=int),
        floor_height=0.0 if scene.floor is None else scene.floor,
        pairs=pairs,
        grouped=grouped,
        blocks=blocks,
    )


def pair_spheres(model: CollisionModel, scene: Scene) -> tuple[np.ndarray, np.ndarray]:
    """Per pair, in the order of :func:`distances`: the index of its robot sphere i, and of the other sphere j
    of a self pair (−1 for an obstacle or the floor)."""
    layout = _layout(model, scene)
    n_o = len(scene.obstacles)
    robot = np.concatenate(
        [np.repeat(np.arange(len(model.spheres)), n_o), layout["floor"], layout["pairs"][:, 0]]
    )
    other = np.concatenate([np.full(len(robot) - len(layout["pairs"]), -1), layout["pairs"][:, 1]])
    return robot, other


def pair_names(model: CollisionModel, scene: Scene) -> tuple[tuple[str, str], ...]:
    """Per pair, in the order of :func:`distances`: (the body of its robot sphere, the obstacle, ``floor`` or the
    body of the other sphere), bodies named by :meth:`~mobman.model.collision_model.CollisionModel.body_name`."""
    bodies = [model.body_name(s.body) for s in model.spheres]
    others = [o.name for o in scene.obstacles]
    robot, other = pair_spheres(model, scene)
    n_o = len(others)
    return tuple(
        (
            bodies[i],
            bodies[j] if j >= 0 else (others[k % n_o] if k < len(bodies) * n_o else "floor"),
        )
        for k, (i, j) in enumerate(zip(robot.tolist(), other.tolist()))
    )


def centres_one(model: CollisionModel, q: jnp.ndarray) -> jnp.ndarray:
    """World centres (n_spheres, 3) of the model's spheres at one configuration q (n_q,)."""
    layout = _layout(model, Scene())
    frames = model.robot.frames(q)
    followers = frames.followers
    rs = [frames.platform[0][None]] + [r[: a.n_joints] for (r, _), a in zip(frames.links, model.robot.arms)]
    ps = [frames.platform[1][None]] + [p[: a.n_joints] for (_, p), a in zip(frames.links, model.robot.arms)]
    rs += [jnp.stack([r for r, _ in followers])] if followers else []
    ps += [jnp.stack([p for _, p in followers])] if followers else []
    rotation, origin = jnp.concatenate(rs)[layout["body"]], jnp.concatenate(ps)[layout["body"]]
    return jnp.einsum("kij,kj->ki", rotation, jnp.asarray(layout["centre"])) + origin


def centre_jacobians_one(model: CollisionModel, q: jnp.ndarray) -> jnp.ndarray:
    """Linear velocity Jacobians (n_spheres, 3, n_q) of the spheres' centres at one configuration q, by
    :meth:`~mobman.model.robot.MobileManipulator.body_point_jacobian` of the body each is fixed in."""
    robot = model.robot
    frames = robot.frames(q)
    centres = centres_one(model, q)
    layout = _layout(model, Scene())
    blocks, order = [], []
    for index, body in enumerate(model.bodies):
        members = np.nonzero(layout["body"] == index)[0]
        if not len(members):
            continue

        def one(point: jnp.ndarray, body: tuple[int, int] = body) -> jnp.ndarray:
            return robot.body_point_jacobian(q, frames, point, body)[0]

        blocks.append(jax.vmap(one)(centres[members]))
        order.append(members)
    return jnp.concatenate(blocks)[np.argsort(np.concatenate(order))]


def distances_one(
    model: CollisionModel, scene: Scene, q: jnp.ndarray
) -> tuple[jnp.ndarray, jnp.ndarray, jnp.ndarray, jnp.ndarray, jnp.ndarray]:
    """(distance (P,), robot point (P, 3), other point (P, 3), normal (P, 3), rows (P, n_eta)) at one
    configuration q (n_q,), unvalidated: for traced code (module notes)."""
    layout = _layout(model, scene)
    centre = centres_one(model, q)
    radius = jnp.asarray(layout["radius"])
    n_s, dtype = centre.shape[0], centre.dtype
    # robot–obstacle: (n_s, n_obstacles) in scene order
    n_o = len(scene.obstacles)
    phi = jnp.zeros((n_s, n_o), dtype)
    point = jnp.zeros((n_s, n_o, 3), dtype)
    normal = jnp.zeros((n_s, n_o, 3), dtype)
    for shape, (index, rotation, position, size) in layout["groups"].items():
        local = _rotate(np.swapaxes(rotation, 1, 2), centre[:, None, :] - position)  # Rᵀ (c − p)
        f, p_local, n_local = _SHAPE_DISTANCE[shape](local, jnp.broadcast_to(jnp.asarray(size), local.shape))
        phi = phi.at[:, index].set(f)
        point = point.at[:, index].set(_rotate(rotation, p_local) + position)
        normal = normal.at[:, index].set(_rotate(rotation, n_local))
    sphere_index = [np.repeat(np.arange(n_s), n_o)]
    phis, points, normals = [phi.reshape(-1)], [point.reshape(-1, 3)], [normal.reshape(-1, 3)]
    # robot–floor
    floor = layout["floor"]
    if len(floor):
        c = centre[floor]
        height = layout["floor_height"]
        phis.append(c[:, 2] - height)
        points.append(c.at[:, 2].set(height))
        normals.append(jnp.broadcast_to(jnp.array([0.0, 0.0, 1.0], dtype), c.shape))
        sphere_index.append(floor)
    scene_sphere = np.concatenate(sphere_index)
    phi_s, point_s, normal_s = jnp.concatenate(phis), jnp.concatenate(points), jnp.concatenate(normals)
    d_s = phi_s - radius[scene_sphere]
    robot_s = centre[scene_sphere] - radius[scene_sphere, None] * normal_s
    # self pairs: sphere i (robot) and sphere j (other), body block by body block (no gathers)
    i, j = layout["pairs"].T
    (c_i, c_j), (r_i, r_j) = _self_blocks(centre, layout), _self_blocks(radius[:, None], layout)
    between = c_i - c_j
    normal_p = unit(between, jnp.array([0.0, 0.0, 1.0], dtype))
    d_p = norm(between) - r_i[:, 0] - r_j[:, 0]
    robot_p = c_i - r_i * normal_p
    other_p = c_j + r_j * normal_p
    jac = centre_jacobians_one(model, q)
    rows = jnp.concatenate(
        [
            pair_rows_one(model, q, normal_s, scene_sphere, jac=jac),
            pair_rows_one(model, q, normal_p, i, j, jac),
        ]
    )
    return (
        jnp.concatenate([d_s, d_p]),
        jnp.concatenate([robot_s, robot_p]),
        jnp.concatenate([point_s, other_p]),
        jnp.concatenate([normal_s, normal_p]),
        rows,
    )


def _rotate(rotation: np.ndarray, v: jnp.ndarray) -> jnp.ndarray:
    """R v for constant rotations ``rotation`` (n_o, 3, 3) and vectors v (..., n_o, 3), component by component
    (a sum of three products each, which XLA fuses with the primitive distances that use them)."""
    return jnp.stack([sum(rotation[:, i, j] * v[..., j] for j in range(3)) for i in range(3)], -1)


def _self_blocks(per_sphere: jnp.ndarray, layout: dict) -> tuple[jnp.ndarray, jnp.ndarray]:
    """``per_sphere`` (n_s, k) of the first and of the second sphere of every self pair (P_self, k), in the
    order of ``sphere_pairs``: each block of body a's spheres × body b's broadcast, not gathered."""
    grouped = per_sphere[layout["grouped"]]
    k = per_sphere.shape[1]
    first, second = [], []
    for a0, a1, b0, b1 in layout["blocks"]:
        shape = (a1 - a0, b1 - b0, k)
        first.append(jnp.broadcast_to(grouped[a0:a1, None], shape).reshape(-1, k))
        second.append(jnp.broadcast_to(grouped[None, b0:b1], shape).reshape(-1, k))
    empty = jnp.zeros((0, k), per_sphere.dtype)
    return jnp.concatenate(first) if first else empty, jnp.concatenate(second) if second else empty


def pair_rows_one(
    model: CollisionModel,
    q: jnp.ndarray,
    normal: jnp.ndarray,
    first: npt.ArrayLike,
    second: npt.ArrayLike | None = None,
    jac: jnp.ndarray | None = None,
) -> jnp.ndarray:
    """The rates rows n̂ᵀ (J_first − J_second) S (P', n_eta) over η of the pairs of spheres ``first`` and
    ``second`` (P',) with normals ``normal`` (P', 3) at one configuration q: J a sphere centre's linear
    velocity Jacobian (:func:`centre_jacobians_one`, or ``jac`` when already computed); ``second`` None, or
    −1 in an entry, for a pair whose other side is an obstacle or the floor (it does not move). A controller
    that keeps a few pairs forms their rows only (:func:`mobman.control.avoidance.dampers`)."""
    jac = centre_jacobians_one(model, q) if jac is None else jac
    # J̄_c = J_c S per sphere (n_s, 3, n_eta), then per pair Σ_k n̂_k (J̄_first − J̄_second)_k
    reduced = jax.vmap(lambda j: model.robot.apply_S(j, q))(jac)
    if second is not None:  # index −1 reads the appended zero Jacobian
        reduced = jnp.concatenate([reduced, jnp.zeros((1,) + reduced.shape[1:], reduced.dtype)])
    x, y, z = (
        normal[:, k, None] * (reduced[first, k] if second is None else reduced[first, k] - reduced[second, k])
        for k in range(3)
    )
    return x + y + z


BLOCK = 8
"""Configurations per block of the batched distances (:func:`mobman.engine.batched.blocked`): a
configuration's pairs, witness points, normals and rows over η (TIAGo: about 6 kB of results and 13 MB moved
in all) outgrow the caches in blocks of the kinematics' 128; blocks of 8 were 1.5× faster for TIAGo's
scene and self pairs (``benchmarks/collision.py``)."""


@partial(jax.jit, static_argnums=(0, 1))
def _program(model: CollisionModel, scene: Scene, q: jax.Array) -> tuple:
    return blocked(lambda x: distances_one(model, scene, x), block=BLOCK)(q)


def distances(model: CollisionModel, scene: Scene, q: npt.ArrayLike) -> PairDistances:
    """Signed distances, witness points, normals and rows over η of every pair (:func:`pair_names`) at
    configurations q (..., n_q) (module notes)."""
    q = validated_q(model.robot, q)
    return PairDistances(*(np.asarray(v) for v in _program(model, scene, q)))


def point_distances(scene: Scene, point: npt.ArrayLike) -> np.ndarray:
    """Signed distances (m, negative inside) of one world ``point`` (3,) to each obstacle of ``scene`` and to
    its floor, in the order of :attr:`~mobman.model.scene.Scene.names`."""
    x = np.asarray(point, dtype=float)
    phi = [
        float(
            _SHAPE_DISTANCE[o.shape](
                o.rotation.T @ (x - o.position), np.asarray(o.size + (0.0,) * (3 - len(o.size)))
            )[0]
        )
        for o in scene.obstacles
    ]
    return np.array(phi + ([] if scene.floor is None else [x[2] - scene.floor]))


__all__ = [
    "PairDistances",
    "centre_jacobians_one",
    "centres_one",
    "distances",
    "distances_one",
    "pair_names",
    "pair_rows_one",
    "pair_spheres",
    "point_distances",
]
