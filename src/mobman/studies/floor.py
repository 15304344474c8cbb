"""The floor around a parked platform: keep-out regions where it may not stand, and the disc that covers it.

Base placement (:mod:`mobman.studies.placement`) leaves out the candidate bases from which the platform would
overlap furniture or a wall. A keep-out region is a rectangle of the floor with sides along the world's x and
y axes (:class:`KeepOut`: a table, a shelf, a strip along a wall). The platform is covered by a disc fixed in
its frame (:class:`FootprintDisc`): its centre (x, y) in the platform frame and its radius. A platform at
(x_b, y_b, θ) puts the disc's centre at c = (x_b, y_b) + R(θ) (x, y), and overlaps a region when the distance
from c to the rectangle,

    d = ‖(max(x_min − c_x, 0, c_x − x_max), max(y_min − c_y, 0, c_y − y_max))‖,

is less than the radius (a disc that touches a side does not overlap it).

A scene's boxes that stand on the floor (their lowest corner within :data:`ON_FLOOR` of the scene's floor,
z = 0 without one) are keep-out regions too (:func:`scene_regions`): each the rectangle with sides along x and
y that holds the box seen from above (the box itself for a box turned about the vertical only by multiples of
a right angle, a larger one otherwise).

:func:`footprint_disc` finds the disc of a robot from the shapes the viewer draws for its platform
(``MobileManipulator.platform_visuals``: a URDF's visuals of the base and everything fixed to it, wheels
and casters included): every shape's points projected on the floor, the disc centred on their bounding box
and just covering them. A robot without such shapes (the papers' robots, robot files) is covered by the body
box the viewer draws for its platform (:meth:`mobman.model.platforms.Platform.footprint`), which is an
illustration, not a measured outline: give the disc of the real platform instead.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Sequence

import numpy as np
import numpy.typing as npt

from mobman.errors import InputError, ModelError
from mobman.model import spatial
from mobman.model.robot import MobileManipulator
from mobman.model.scene import Scene
from mobman.model.visual import Visual
from mobman.studies import options

ON_FLOOR = 0.01
"""Largest height (m) of a box's lowest corner above the floor for it to stand on the floor
(:func:`scene_regions`)."""

ROUND_POINTS = 64
"""Points per circle of a cylinder's or a sphere's outline; the circle through them is widened by
1 / cos(π / ROUND_POINTS), so that the polygon they make covers the round shape."""


@dataclass(frozen=True)
class KeepOut:
    """A rectangle of the floor where the platform may not stand: x_min ≤ x ≤ x_max, y_min ≤ y ≤ y_max (m,
    world frame)."""

    x_min: float
    x_max: float
    y_min: float
    y_max: float

    def __post_init__(self) -> None:
        values = (self.x_min, self.x_max, self.y_min, self.y_max)
        if not all(isinstance(v, (int, float, np.integer, np.floating)) and math.isfinite(v) for v in values):
            raise InputError(
                f"keep_out must be 4 finite numbers x_min, x_max, y_min, y_max (m), got {values}"
            )
        if not (self.x_min < self.x_max and self.y_min < self.y_max):
            raise InputError(
                f"keep_out must have x_min < x_max and y_min < y_max (x_min, x_max, y_min, y_max), got "
                f"{', '.join(f'{v:g}' for v in values)}"
            )

    @classmethod
    def of(cls, value: "KeepOut | Sequence[float] | npt.ArrayLike") -> "KeepOut":
        """A region given as a :class:`KeepOut` or as its 4 numbers (x_min, x_max, y_min, y_max)."""
        if isinstance(value, KeepOut):
            return value
        numbers = options.vector(value, "keep_out", 4, "x_min, x_max, y_min, y_max in m")
        return cls(*(float(v) for v in numbers))


@dataclass(frozen=True)
class FootprintDisc:
    """The disc that covers the platform: ``radius`` (m) about the point (``x``, ``y``) of the platform frame."""

    radius: float
    x: float = 0.0
    y: float = 0.0

    def __post_init__(self) -> None:
        values = (self.radius, self.x, self.y)
        if not all(isinstance(v, (int, float, np.integer, np.floating)) and math.isfinite(v) for v in values):
            raise InputError(f"footprint must be finite numbers radius, x, y (m), got {values}")
        if not self.radius > 0:
            raise InputError(f"footprint radius must be > 0 (m), got {self.radius:g}")

    @classmethod
    def of(cls, value: "FootprintDisc | float | Sequence[float] | npt.ArrayLike") -> "FootprintDisc":
        """A disc given as a :class:`FootprintDisc`, a radius about the platform's origin, or (radius, x, y)."""
        if isinstance(value, FootprintDisc):
            return value
        try:
            numbers = np.atleast_1d(np.asarray(value, dtype=float))
        except (TypeError, ValueError):
            numbers = np.zeros(0)
        if numbers.shape not in ((1,), (3,)):
            raise InputError(f"footprint must be a radius, or radius, x, y (m), got {value!r}")
        return cls(*(float(v) for v in numbers))


def keep_out_regions(
    value: "KeepOut | Sequence[KeepOut | Sequence[float]] | npt.ArrayLike",
) -> tuple[KeepOut, ...]:
    """Keep-out regions given as one region (a :class:`KeepOut` or its 4 numbers) or a sequence of them."""
    if isinstance(value, KeepOut):
        return (value,)
    try:
        numbers = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        numbers = None  # a sequence holding KeepOut objects
    if numbers is not None and numbers.ndim == 1 and numbers.size:
        return (KeepOut.of(numbers),)
    return tuple(KeepOut.of(region) for region in value)  # type: ignore[union-attr]


def scene_regions(scene: Scene) -> tuple[KeepOut, ...]:
    """The keep-out regions of ``scene``'s boxes standing on the floor (module notes)."""
    floor = 0.0 if scene.floor is None else scene.floor
    signs = np.array(np.meshgrid([-1, 1], [-1, 1], [-1, 1], indexing="ij")).reshape(3, -1).T
    regions = []
    for obstacle in scene.obstacles:
        if obstacle.shape != "box":
            continue
        corners = (signs * np.asarray(obstacle.size) / 2) @ obstacle.rotation.T + obstacle.position
        if corners[:, 2].min() <= floor + ON_FLOOR:
            low, high = corners[:, :2].min(axis=0), corners[:, :2].max(axis=0)
            regions.append(KeepOut(float(low[0]), float(high[0]), float(low[1]), float(high[1])))
    return tuple(regions)


def blocked(bases: npt.ArrayLike, footprint: FootprintDisc, regions: Sequence[KeepOut]) -> np.ndarray:
    """Which platform poses (x, y, θ) of ``bases`` (N, 3) put the footprint's disc over a keep-out region,
    shape (N,) (module notes)."""
    bases = np.asarray(bases, dtype=float).reshape(-1, 3)
    if not regions:
        return np.zeros(len(bases), dtype=bool)
    c, s = np.cos(bases[:, 2]), np.sin(bases[:, 2])
    centre_x = bases[:, 0] + c * footprint.x - s * footprint.y
    centre_y = bases[:, 1] + s * footprint.x + c * footprint.y
    box = np.array([[r.x_min, r.x_max, r.y_min, r.y_max] for r in regions]).T[:, None, :]  # (4, 1, M)
    dx = np.maximum(np.maximum(box[0] - centre_x[:, None], centre_x[:, None] - box[1]), 0.0)
    dy = np.maximum(np.maximum(box[2] - centre_y[:, None], centre_y[:, None] - box[3]), 0.0)
    return np.any(np.hypot(dx, dy) < footprint.radius, axis=1)


def footprint_disc(robot: MobileManipulator) -> FootprintDisc:
    """The disc covering ``robot``'s platform seen from above (module notes)."""
    if robot.platform_visuals:
        points = np.concatenate([_outline(v) for v in robot.platform_visuals])
    else:
        box = robot.platform.footprint()
        half = np.array([box.length, box.width]) / 2
        points = np.array([[box.x_centre, 0.0]]) + half * np.array([[1, 1], [1, -1], [-1, 1], [-1, -1]])
    centre = (points.min(axis=0) + points.max(axis=0)) / 2
    radius = float(np.max(np.linalg.norm(points - centre, axis=1)))
    return FootprintDisc(radius, float(centre[0]), float(centre[1]))


def _outline(visual: Visual) -> np.ndarray:
    """Points (K, 2) of one shape projected on the floor (platform frame) whose convex hull covers it."""
    rotation, offset = spatial.fixed_pose(visual.origin)
    if visual.kind == "box":
        corners = np.array(np.meshgrid([-1, 1], [-1, 1], [-1, 1], indexing="ij")).reshape(3, -1).T
        local = corners * np.asarray(visual.size) / 2
    elif visual.kind in ("cylinder", "sphere"):
        radius = visual.size[0] / math.cos(math.pi / ROUND_POINTS)
        angle = 2 * math.pi * np.arange(ROUND_POINTS) / ROUND_POINTS
        ring = np.stack([radius * np.cos(angle), radius * np.sin(angle), np.zeros(ROUND_POINTS)], axis=1)
        if visual.kind == "cylinder":  # the two end circles (axis along the local z)
            local = np.concatenate([ring + [0, 0, -visual.size[1] / 2], ring + [0, 0, visual.size[1] / 2]])
        else:  # a sphere's outline seen from any direction: its great circles about the three axes
            local = np.concatenate([ring, ring[:, [0, 2, 1]], ring[:, [2, 0, 1]]])
    else:
        local = _mesh_vertices(visual) * np.asarray(visual.scale)
    return (local @ rotation.T + offset)[:, :2]


def _mesh_vertices(visual: Visual) -> np.ndarray:
    """The vertices of a mesh shape's file (trimesh, which the URDF reader's yourdfpy brings along)."""
    try:
        import trimesh
    except ImportError:
        raise ModelError(
            f"footprint: reading the mesh of {visual.name or visual.filename!r} needs trimesh (pip install "
            "'mobman[robots]'); or give the footprint's radius"
        ) from None
    try:
        mesh = trimesh.load(visual.filename, force="mesh")
    except (OSError, ValueError) as exc:
        raise ModelError(
            f"footprint: cannot read the mesh {visual.filename} of {visual.name!r} ({exc}); give the footprint's "
            "radius"
        ) from None
    return np.asarray(mesh.vertices, dtype=float)  # type: ignore[attr-defined]


__all__ = [
    "FootprintDisc",
    "KeepOut",
    "ON_FLOOR",
    "ROUND_POINTS",
    "blocked",
    "footprint_disc",
    "keep_out_regions",
    "scene_regions",
]
