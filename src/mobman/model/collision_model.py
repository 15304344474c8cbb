"""The robot's collision model: spheres fixed in its bodies, and the self-collision pairs.

Bodies
------
Body 0 is the platform (its frame, :attr:`mobman.model.robot.Frames.platform`); then, arm by arm, the link each
joint moves, in that joint's frame after its motion (the frames of :meth:`mobman.model.arm.Arm.link_poses`),
where :class:`mobman.model.visual.Visual` shapes are attached; then the followers
(:class:`mobman.model.robot.Follower`: bodies off the chains that follow an arm coordinate), each in its frame.

Shapes and their sphere cover
-----------------------------
Every body's shapes (boxes, cylinders, spheres, meshes: URDF ``<collision>`` geometry, or for the papers' robots
the generated geometry of :func:`generated_shapes`) are covered by spheres (:func:`cover`) so that

- **every point of the shape lies in a sphere** (the union covers the solid), and
- **no sphere reaches farther than the cover tolerance τ beyond the shape**: each sphere is centred at a point
  c of the shape at depth δ(c) (its distance to the surface) with a radius r ≤ δ(c) + τ, so that it lies
  within τ of the ball of radius δ(c) about c, which is inside the shape.

Hence for any obstacle, the distance of the spheres is at most the distance of the shape, and at least that
distance minus τ: the spheres are conservative, pessimistic by at most τ. :func:`cover` builds them by halving
the shape's bounding box. A sphere shape is its own cover (exact). A mesh is read with trimesh and covered
through its convex hull, which contains it (so the spheres still cover the mesh, and τ is measured from the
hull): URDF collision meshes are often hulls already, and a watertight mesh may be a hollow shell (TIAGo's
base is one: a tenth of its hull's volume) whose inside a cover of the mesh itself would leave open.

Self-collision pairs
--------------------
Every pair of bodies, except neighbours (the platform and each arm's first link, consecutive links of an arm, a
follower and the body it hangs from) and pairs whose spheres overlap at the neutral posture (every joint at 0, or at its nearer limit when 0 is
outside its range), the way an SRDF's disabled pairs work; :meth:`CollisionModel.with_pairs` overrides them.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, replace
from functools import lru_cache
from typing import Any, Callable

import jax
import numpy as np

from mobman import checks
from mobman.errors import ModelError
from mobman.model import primitives, spatial
from mobman.model.robot import FOLLOWER, PLATFORM, Body, MobileManipulator, compiled_frames
from mobman.model.visual import Visual

DEFAULT_TOLERANCE = 0.05
"""The default cover tolerance τ (m): how far the spheres may reach beyond the shapes they cover."""

CONTROL_TOLERANCE = 0.1
"""The cover tolerance τ (m) of the collision avoidance in the control loop
(:class:`~mobman.control.laws.WholeBodyQP`): a lean cover, evaluated at every law step (TIAGo: 179 spheres, 6071
self sphere pairs, against 854 and 60 k at :data:`DEFAULT_TOLERANCE`); the robot keeps its margin plus at most
τ from the obstacles."""


@dataclass(frozen=True)
class CollisionSphere:
    """A sphere fixed in a body: its ``centre`` in the body's frame (m), its ``radius`` (m) and the ``label``
    of the shape it covers (the URDF link's name, ``body``, ``link2``, …)."""

    body: Body
    centre: tuple[float, float, float]
    radius: float
    label: str = ""

    def __post_init__(self) -> None:
        object.__setattr__(self, "centre", checks.vector3(self.centre, "centre", f"sphere {self.label!r}"))
        object.__setattr__(self, "radius", checks.positive(self.radius, "radius", f"sphere {self.label!r}"))
        object.__setattr__(self, "body", (int(self.body[0]), int(self.body[1])))


@dataclass(frozen=True)
class CollisionModel:
    """The spheres of a robot, the pairs of bodies checked against each other and the cover tolerance τ (m).

    Immutable and hashable: a static argument of compiled functions. ``bodies`` lists every body of the
    robot (platform first, then each arm's links); ``pairs`` are pairs of indices into it.
    """

    robot: MobileManipulator
    spheres: tuple[CollisionSphere, ...]
    pairs: tuple[tuple[int, int], ...] = ()
    tolerance: float = DEFAULT_TOLERANCE

    def __post_init__(self) -> None:
        spheres = tuple(self.spheres)
        if not spheres:
            raise ModelError(f"{self.robot.name}: a collision model needs at least one sphere")
        known = set(self.bodies)
        for s in spheres:
            if s.body not in known:
                raise ModelError(f"sphere {s.label!r}: body {s.body} is not a body of {self.robot.name}")
        object.__setattr__(self, "spheres", spheres)
        object.__setattr__(self, "pairs", _checked_pairs(self.pairs, len(self.bodies)))
        object.__setattr__(
            self, "tolerance", checks.non_negative(self.tolerance, "tolerance", "collision model")
        )

    @property
    def bodies(self) -> tuple[Body, ...]:
        """Every body of the robot: the platform, then each arm's links, then the followers."""
        return bodies(self.robot)

    def body_name(self, body: Body) -> str:
        """A body's name: ``platform``, its joint's coordinate name, or a follower's joint name."""
        if body == PLATFORM:
            return "platform"
        arm, link = body
        if arm == FOLLOWER:
            return self.robot.followers[link].joint.name or f"follower{link}"
        return self.robot.coordinate_names[self.robot.arm_slice(arm)][link]

    @property
    def sphere_pairs(self) -> tuple[tuple[int, int], ...]:
        """The pairs of sphere indices of :attr:`pairs`: every sphere of one body with every one of the other."""
        index = {b: i for i, b in enumerate(self.bodies)}
        by_body: dict[int, list[int]] = {}
        for k, s in enumerate(self.spheres):
            by_body.setdefault(index[s.body], []).append(k)
        return tuple((i, j) for a, b in self.pairs for i in by_body.get(a, ()) for j in by_body.get(b, ()))

    def with_pairs(self, pairs: Iterable[tuple[str, str]]) -> "CollisionModel":
        """The same spheres with the self-collision pairs ``pairs`` given by body name (:meth:`body_name`)."""
        names = {self.body_name(b): i for i, b in enumerate(self.bodies)}
        chosen = []
        for a, b in pairs:
            for name in (a, b):
                if name not in names:
                    raise ModelError(f"pairs: unknown body {name!r}; bodies: {', '.join(names)}")
            chosen.append((names[a], names[b]))
        return replace(self, pairs=tuple(chosen))

    @classmethod
    def from_shapes(
        cls,
        robot: MobileManipulator,
        shapes: Mapping[Body, Sequence[Visual]],
        tolerance: float = DEFAULT_TOLERANCE,
    ) -> "CollisionModel":
        """The model covering ``shapes`` (per body, in the body's frame) to the cover ``tolerance`` τ, with the
        self-collision pairs of the module notes."""
        tolerance = checks.positive(tolerance, "tolerance", "collision model")
        spheres = []
        for body, items in shapes.items():
            for shape in items:
                centres, radii = cover(shape, tolerance)
                spheres += [
                    CollisionSphere(body, tuple(c), float(r), shape.name) for c, r in zip(centres, radii)
                ]
        model = cls(robot, tuple(spheres), (), tolerance)
        return replace(model, pairs=default_pairs(model))


def _checked_pairs(pairs: Iterable[tuple[int, int]], n: int) -> tuple[tuple[int, int], ...]:
    out = []
    for pair in pairs:
        a, b = (int(v) for v in pair)
        if not (0 <= a < n and 0 <= b < n and a != b):
            raise ModelError(f"pairs: ({a}, {b}) must be two different bodies in 0..{n - 1}")
        out.append((min(a, b), max(a, b)))
    return tuple(dict.fromkeys(out))


def bodies(robot: MobileManipulator) -> tuple[Body, ...]:
    """Every body of a robot: the platform, then each arm's links, then the followers."""
    links = tuple((a, k) for a, arm in enumerate(robot.arms) for k in range(arm.n_joints))
    return (PLATFORM, *links, *((FOLLOWER, k) for k in range(len(robot.followers))))


def neutral_posture(robot: MobileManipulator) -> np.ndarray:
    """q = 0, each joint clipped to its limits (the posture at which overlapping pairs are disabled)."""
    lower, upper = np.array(robot.position_limits, dtype=float).T
    return np.clip(np.zeros(robot.n_q), lower, upper)


def body_poses(robot: MobileManipulator, q: np.ndarray) -> list[tuple[np.ndarray, np.ndarray]]:
    """World poses (R, p) of every body (:func:`bodies`) at one configuration ``q``."""
    frames = compiled_frames(robot, np.asarray(q, dtype=float))
    poses = [frames.body(body) for body in bodies(robot)]
    return [(np.asarray(rotation), np.asarray(origin)) for rotation, origin in poses]


def default_pairs(model: CollisionModel, clearance: float = 0.0) -> tuple[tuple[int, int], ...]:
    """Every pair of bodies but neighbours and those whose spheres overlap at :func:`neutral_posture` (come
    closer than ``clearance``, m: a controller that keeps a margin disables the pairs within it there)."""
    bodies = model.bodies
    index = {b: i for i, b in enumerate(bodies)}
    neighbours = {(0, index[(a, 0)]) for a in range(len(model.robot.arms))}
    neighbours |= {
        (index[(a, k)], index[(a, k + 1)])
        for a, arm in enumerate(model.robot.arms)
        for k in range(arm.n_joints - 1)
    }
    neighbours |= {
        (index[follower.parent], index[(FOLLOWER, k)]) for k, follower in enumerate(model.robot.followers)
    }
    poses = body_poses(model.robot, neutral_posture(model.robot))
    body_of = np.array([index[s.body] for s in model.spheres])
    local = np.array([s.centre for s in model.spheres])
    rotation = np.stack([poses[b][0] for b in body_of])
    centres = np.einsum("kij,kj->ki", rotation, local) + np.stack([poses[b][1] for b in body_of])
    radii = np.array([s.radius for s in model.spheres])
    gap = np.linalg.norm(centres[:, None] - centres[None], axis=-1) - radii[:, None] - radii[None]
    overlapping = {
        (min(body_of[i], body_of[j]), max(body_of[i], body_of[j]))
        for i, j in zip(*np.nonzero(gap < clearance))
    }
    present = sorted(set(body_of.tolist()))
    return tuple(
        (a, b)
        for n, a in enumerate(present)
        for b in present[n + 1 :]
        if (a, b) not in neighbours and (a, b) not in overlapping
    )


# --- the papers' robots: generated geometry ------------------------------------------------------


def generated_shapes(robot: MobileManipulator) -> dict[Body, tuple[Visual, ...]]:
    """The shapes the viewer draws for a robot without visuals: the platform's body box of
    :meth:`~mobman.model.platforms.base.Platform.footprint` (top at the platform frame, z from −height to 0),
    its wheels (radius r, width 0.4 r, axles along y at mid-height), a pillar under each raised mount, and each
    link as a cylinder from its joint frame to the next joint's origin (to the tool frame after the last), of
    radius 3.5 % of the arm's reach (at most 3.5 cm). A prismatic joint's travel is not part of its link."""
    box = robot.platform.footprint()
    h = box.height
    platform = [
        Visual(
            "box",
            spatial.transform(None, (box.x_centre, 0.0, -h / 2)),
            (box.length, box.width, h),
            name="body",
        )
    ]
    axle = spatial.rot_x(-math.pi / 2)  # the cylinder's z along y
    platform += [
        Visual(
            "cylinder",
            spatial.transform(axle, (w.x, w.y, -h / 2)),
            (w.radius, 0.4 * w.radius),
            name=f"wheel{i}",
        )
        for i, w in enumerate(robot.platform.wheels())
    ]
    platform += [
        Visual("cylinder", spatial.transform(None, (m.x, m.y, m.z / 2)), (0.6 * h, m.z), name=f"mount{i}")
        for i, m in enumerate(robot.mounts)
        if m.z > 1e-6
    ]
    shapes: dict[Body, tuple[Visual, ...]] = {PLATFORM: tuple(platform)}
    for a, arm in enumerate(robot.arms):
        ends = [spatial.fixed_pose(j.origin)[1] for j in arm.joints[1:]] + [spatial.fixed_pose(arm.tool)[1]]
        reach = max(0.3, float(sum(np.linalg.norm(e) for e in ends)))
        radius = 0.035 * min(1.0, reach)
        for k, (joint, end) in enumerate(zip(arm.joints, ends)):
            length = float(np.linalg.norm(end))
            name = joint.name or f"link{k + 1}"
            if length < 1e-9:
                link = Visual("sphere", spatial.IDENTITY, (radius,), name=name)
            else:
                link = Visual(
                    "cylinder",
                    spatial.transform(_z_onto(end / length), tuple(end / 2)),
                    (radius, length),
                    name=name,
                )
            shapes[(a, k)] = (link,)
    return shapes


def _z_onto(d: np.ndarray) -> np.ndarray:
    """A rotation whose z axis is the unit vector d."""
    helper = np.array([1.0, 0.0, 0.0]) if abs(d[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    x = np.cross(helper, d)
    x /= np.linalg.norm(x)
    return np.stack([x, np.cross(d, x), d], axis=1)


def robot_shapes(robot: MobileManipulator) -> dict[Body, tuple[Visual, ...]]:
    """Each body's shapes: the visuals the robot carries (a URDF's), else the generated geometry of
    :func:`generated_shapes` for that body."""
    shapes = generated_shapes(robot)
    if robot.platform_visuals:
        shapes[PLATFORM] = robot.platform_visuals
    for a, arm in enumerate(robot.arms):
        for k, joint in enumerate(arm.joints):
            if joint.visuals:
                shapes[(a, k)] = joint.visuals
    for k, follower in enumerate(robot.followers):
        if follower.joint.visuals:
            shapes[(FOLLOWER, k)] = follower.joint.visuals
    return shapes


@lru_cache(maxsize=32)
def collision_model(robot: MobileManipulator, tolerance: float = DEFAULT_TOLERANCE) -> CollisionModel:
    """The collision model of :func:`robot_shapes` to the cover ``tolerance`` (m): the generated geometry of the
    papers' robots, the visual shapes of a robot read from a URDF file."""
    return CollisionModel.from_shapes(robot, robot_shapes(robot), tolerance)


# --- the sphere cover of one shape ---------------------------------------------------------------


@dataclass(frozen=True)
class _Solid:
    """A convex or meshed solid in its own frame: ``project(x)`` gives (φ, closest surface point) of points
    (N, 3), φ the signed distance (< 0 inside); ``low``, ``high`` its bounding box."""

    project: Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]]
    low: np.ndarray
    high: np.ndarray


def _solid(shape: Visual) -> _Solid:
    if shape.kind == "box":
        half = np.asarray(shape.size) / 2
        return _Solid(_padded(_BOX, half), -half, half)
    if shape.kind == "cylinder":
        radius, half_length = shape.size[0], shape.size[1] / 2

        extent = np.array([radius, radius, half_length])
        return _Solid(_padded(_CYLINDER, np.array([radius, half_length])), -extent, extent)
    mesh = _mesh(shape)

    def meshed(x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        import trimesh

        point, _, _ = trimesh.proximity.closest_point(mesh, x)
        return -np.asarray(trimesh.proximity.signed_distance(mesh, x), dtype=float), np.asarray(point)

    low, high = np.asarray(mesh.bounds, dtype=float)
    return _Solid(meshed, low, high)


_CHUNK = 512
_BOX = jax.jit(lambda x, half: primitives.box_distance(x, half)[:2])
_CYLINDER = jax.jit(lambda x, size: primitives.cylinder_distance(x, size[0], size[1])[:2])


def _padded(
    distance: Callable[..., tuple[jax.Array, jax.Array]], size: np.ndarray
) -> Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]]:
    """(φ, closest point) of points (N, 3) by a compiled primitive distance of the primitive of ``size``, in
    chunks of :data:`_CHUNK` points (one compilation)."""

    def project(x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        padded = np.concatenate([x, np.zeros((-len(x) % _CHUNK, 3))])
        parts = [distance(padded[k : k + _CHUNK], size) for k in range(0, len(padded), _CHUNK)]
        phi, point = (np.concatenate([np.asarray(p[i]) for p in parts])[: len(x)] for i in (0, 1))
        return phi, point

    return project


def _mesh(shape: Visual) -> Any:  # a trimesh.Trimesh (trimesh is optional: imported here)
    """The convex hull of a mesh shape, scaled (module notes)."""
    try:
        import trimesh
    except ImportError:
        raise ModelError(
            f"shape {shape.name!r}: covering a mesh needs trimesh (pip install 'mobman[robots]')"
        ) from None
    try:
        mesh: Any = trimesh.load(shape.filename, force="mesh")  # force="mesh" gives a Trimesh
    except (OSError, ValueError) as exc:
        raise ModelError(f"shape {shape.name!r}: cannot read the mesh {shape.filename} ({exc})") from None
    mesh.apply_scale(shape.scale)
    return mesh.convex_hull


def cover(shape: Visual, tolerance: float = DEFAULT_TOLERANCE) -> tuple[np.ndarray, np.ndarray]:
    """Spheres covering ``shape`` (centres (K, 3) in the frame the shape is attached to, radii (K,)), none
    reaching farther than ``tolerance`` τ beyond it.

    An octree-like subdivision of the shape's bounding box: each cell that may meet the shape gets the point c
    of the shape nearest to the cell's centre (the centre itself when inside) and the radius r reaching the
    farthest corner of the cell clipped to the bounding box (so the sphere holds every point of the shape in
    the cell); it is kept when r ≤ δ(c) + τ, δ the depth of c, else the cell is halved across its longest
    side. A cell whose centre is farther from the shape than its half diagonal meets no point of it and is
    dropped. A sphere shape is its own cover."""
    rotation, offset = spatial.fixed_pose(shape.origin)
    if shape.kind == "sphere":
        return offset[None].copy(), np.array([shape.size[0]])
    solid = _solid(shape)
    low, high = solid.low[None], solid.high[None]
    centres, radii = [], []
    while len(low):
        middle = (low + high) / 2
        phi, nearest = solid.project(middle)
        meets = phi <= np.linalg.norm(high - low, axis=1) / 2
        low, high, middle, phi, nearest = low[meets], high[meets], middle[meets], phi[meets], nearest[meets]
        centre = np.where((phi <= 0)[:, None], middle, nearest)
        corners = np.stack([np.where(np.array(bits, bool), high, low) for bits in np.ndindex(2, 2, 2)], 1)
        radius = np.max(np.linalg.norm(corners - centre[:, None], axis=-1), axis=1)
        done = radius <= np.maximum(-phi, 0.0) + tolerance
        centres.append(centre[done])
        radii.append(radius[done])
        low, high = low[~done], high[~done]
        axis = np.argmax(high - low, axis=1)
        split = (low[np.arange(len(low)), axis] + high[np.arange(len(low)), axis]) / 2
        upper_low, lower_high = low.copy(), high.copy()
        upper_low[np.arange(len(low)), axis] = split
        lower_high[np.arange(len(low)), axis] = split
        low, high = np.concatenate([low, upper_low]), np.concatenate([lower_high, high])
    centre, radius = np.concatenate(centres), np.concatenate(radii)
    return centre @ rotation.T + offset, radius


__all__ = [
    "CONTROL_TOLERANCE",
    "DEFAULT_TOLERANCE",
    "FOLLOWER",
    "PLATFORM",
    "Body",
    "CollisionModel",
    "CollisionSphere",
    "bodies",
    "body_poses",
    "cover",
    "default_pairs",
    "collision_model",
    "generated_shapes",
    "neutral_posture",
    "robot_shapes",
]
