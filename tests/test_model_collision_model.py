"""The robot's collision model: the sphere cover of boxes, cylinders, spheres and meshes (every point of the
shape covered, no sphere reaching beyond the shape by more than the cover tolerance, both measured with coal and
trimesh, not with mobman), and the self-collision pairs (no neighbours, none overlapping at the neutral posture)."""

from __future__ import annotations

import math

import coal
import numpy as np
import pytest
import trimesh

from mobman.errors import ModelError
from mobman.model import robots, spatial
from mobman.model.collision_model import (
    PLATFORM,
    CollisionModel,
    CollisionSphere,
    body_poses,
    collision_model,
    cover,
    generated_shapes,
    neutral_posture,
)
from mobman.model.visual import Visual

TOLERANCE = 0.05
ORIGIN = spatial.transform(spatial.rot_z(0.4) @ spatial.rot_x(math.pi / 2), (0.1, -0.2, 0.3))


def _directions(n: int) -> np.ndarray:
    """n unit vectors spread over the sphere (Fibonacci lattice)."""
    k = np.arange(n) + 0.5
    polar, azimuth = np.arccos(1 - 2 * k / n), math.pi * (1 + 5**0.5) * k
    return np.stack([np.cos(azimuth) * np.sin(polar), np.sin(azimuth) * np.sin(polar), np.cos(polar)], -1)


def _coal_and_mesh(shape: Visual) -> tuple[coal.ShapeBase, trimesh.Trimesh]:
    """The shape as coal's exact primitive and as a triangle mesh inscribed in it (points sampled in the mesh
    lie in the shape), both in the shape's own frame."""
    if shape.kind == "box":
        return coal.Box(*shape.size), trimesh.creation.box(extents=shape.size)
    if shape.kind == "cylinder":
        return coal.Cylinder(*shape.size), trimesh.creation.cylinder(
            radius=shape.size[0], height=shape.size[1], sections=96
        )
    mesh = trimesh.load(shape.filename, force="mesh")
    hull = mesh.convex_hull
    vertices = coal.StdVec_Vec3s()
    for v in hull.vertices:
        vertices.append(np.asarray(v, dtype=float))
    return coal.Convex.convexHull(vertices, False, None), mesh


def _check_cover(shape: Visual, tolerance: float) -> int:
    centres, radii = cover(shape, tolerance)
    rotation, offset = spatial.fixed_pose(shape.origin)
    local = (centres - offset) @ rotation  # back in the shape's own frame
    exact, mesh = _coal_and_mesh(shape)
    rng = np.random.default_rng(5)
    points = np.concatenate(
        [
            trimesh.sample.volume_mesh(mesh, 4000),
            trimesh.sample.sample_surface(mesh, 2000, seed=1)[0],
            mesh.vertices,
        ]
    )
    inside = np.min(np.linalg.norm(points[:, None] - local[None], axis=-1) - radii, axis=1)
    assert inside.max() <= 1e-9, "a point of the shape outside every sphere"
    # how far beyond the shape the spheres reach: coal's distance of points on each sphere to the shape
    directions = _directions(64)
    beyond = 0.0
    dot = coal.Sphere(1e-9)
    for c, r in zip(local, radii):
        for p in c + r * directions[rng.permutation(64)[:16]]:
            request, result = coal.DistanceRequest(), coal.DistanceResult()
            d = coal.distance(dot, coal.Transform3s(np.eye(3), p), exact, coal.Transform3s(), request, result)
            beyond = max(beyond, d + 1e-9)
    assert beyond <= tolerance + 1e-9
    return len(radii)


@pytest.mark.parametrize(
    "shape",
    [
        Visual("box", ORIGIN, (0.6, 0.375, 0.1), name="plate"),
        Visual("box", spatial.IDENTITY, (0.12, 0.12, 0.12), name="cube"),
        Visual("cylinder", ORIGIN, (0.035, 0.5), name="link"),
        Visual("cylinder", spatial.IDENTITY, (0.1, 0.04), name="wheel"),
    ],
    ids=lambda s: s.name,
)
def test_the_cover_covers_and_reaches_at_most_the_tolerance_beyond(shape):
    count = _check_cover(shape, TOLERANCE)
    assert count < 60  # a handful of spheres, not a voxel grid


def test_a_mesh_cover(tmp_path):
    """A convex mesh (the reference distance is coal's, to its convex hull, the mesh itself)."""
    path = tmp_path / "part.stl"
    mesh = trimesh.creation.capsule(height=0.3, radius=0.06, count=(16, 16))
    mesh.apply_transform(trimesh.transformations.rotation_matrix(0.7, (1.0, 0.0, 0.0)))
    mesh.export(path)
    _check_cover(Visual("mesh", spatial.IDENTITY, filename=str(path), name="part"), TOLERANCE)


def test_a_sphere_is_its_own_cover():
    centres, radii = cover(Visual("sphere", ORIGIN, (0.2,)), TOLERANCE)
    np.testing.assert_allclose(centres, [[0.1, -0.2, 0.3]])
    np.testing.assert_allclose(radii, [0.2])


@pytest.mark.parametrize("name", ["bayle-planar", "bayle-rrp", "yamamoto-dual-arm", "panda-differential"])
def test_self_pairs_skip_neighbours_and_pairs_overlapping_at_the_neutral_posture(name):
    robot = robots.ROBOTS[name]()
    model = collision_model(robot)
    bodies = model.bodies
    assert {s.body for s in model.spheres} == set(bodies)  # the platform and every link have spheres
    index = {b: i for i, b in enumerate(bodies)}
    neighbours = {(0, index[(a, 0)]) for a in range(len(robot.arms))} | {
        (index[(a, k)], index[(a, k + 1)])
        for a, arm in enumerate(robot.arms)
        for k in range(arm.n_joints - 1)
    }
    poses = body_poses(robot, neutral_posture(robot))
    world = np.array([poses[index[s.body]][0] @ s.centre + poses[index[s.body]][1] for s in model.spheres])
    radii = np.array([s.radius for s in model.spheres])
    body_of = np.array([index[s.body] for s in model.spheres])

    def overlap(a: int, b: int) -> bool:
        i, j = np.nonzero(body_of == a)[0], np.nonzero(body_of == b)[0]
        gap = np.linalg.norm(world[i, None] - world[None, j], axis=-1) - radii[i, None] - radii[None, j]
        return bool(np.any(gap < 0))

    expected = {
        (a, b)
        for a in range(len(bodies))
        for b in range(a + 1, len(bodies))
        if (a, b) not in neighbours and not overlap(a, b)
    }
    assert set(model.pairs) == expected
    assert len(model.sphere_pairs) == sum(
        int(np.sum(body_of == a)) * int(np.sum(body_of == b)) for a, b in model.pairs
    )


def test_pairs_can_be_overridden_by_body_name():
    robot = robots.ROBOTS["panda-differential"]()
    model = collision_model(robot)
    names = [model.body_name(b) for b in model.bodies]
    chosen = model.with_pairs([(names[0], names[-1])])
    assert chosen.pairs == ((0, len(names) - 1),) and chosen.spheres == model.spheres
    with pytest.raises(ModelError, match="pairs: unknown body 'hand'"):
        model.with_pairs([("hand", names[0])])


def test_bad_models_are_one_line():
    robot = robots.ROBOTS["bayle-planar"]()
    with pytest.raises(ModelError, match="radius must be a finite number > 0"):
        CollisionSphere(PLATFORM, (0.0, 0.0, 0.0), -0.1, "body")
    with pytest.raises(ModelError, match=r"body \(3, 0\) is not a body"):
        CollisionModel(robot, (CollisionSphere((3, 0), (0.0, 0.0, 0.0), 0.1, "x"),))
    with pytest.raises(ModelError, match=r"pairs: \(0, 0\) must be two different bodies"):
        CollisionModel(robot, (CollisionSphere(PLATFORM, (0.0, 0.0, 0.0), 0.1, "x"),), ((0, 0),))
    with pytest.raises(ModelError, match="tolerance must be a finite number > 0"):
        CollisionModel.from_shapes(robot, generated_shapes(robot), 0.0)
