"""A URDF's ``<collision>`` geometry (:func:`mobman.io.urdf.collision_shapes`) and its sphere cover on TIAGo: at
random postures, coal's distance of the URDF's own shapes to a box (boxes, cylinders, spheres; meshes as their
triangles and as their convex hulls, what the cover covers) is never smaller than the spheres' (they cover the
shapes), and the covered shapes' larger by at most the cover tolerance."""

from __future__ import annotations

import math

import coal
import numpy as np
import pytest
import trimesh

from mobman.io.real_robots import urdf_model
from mobman.io.urdf import collision_shapes
from mobman.model import spatial
from mobman.model.collision_model import CollisionModel, body_poses
from mobman.model.visual import Visual

TOLERANCE = 0.05


def _coal_geometry(shape: Visual) -> tuple[coal.CollisionGeometry, coal.CollisionGeometry]:
    """The shape for coal: an exact primitive, a mesh's convex hull (what the cover covers: module notes of
    mobman.model.collision_model) and the mesh's own triangles."""
    if shape.kind == "box":
        exact = coal.Box(*shape.size)
    elif shape.kind == "cylinder":
        exact = coal.Cylinder(*shape.size)
    elif shape.kind == "sphere":
        exact = coal.Sphere(shape.size[0])
    if shape.kind != "mesh":
        return exact, exact
    mesh = trimesh.load(shape.filename, force="mesh")
    mesh.apply_scale(shape.scale)
    vertices = coal.StdVec_Vec3s()
    for v in mesh.convex_hull.vertices:
        vertices.append(np.asarray(v, dtype=float))
    triangles = coal.BVHModelOBBRSS()
    triangles.beginModel(len(mesh.faces), len(mesh.vertices))
    for a, b, c in np.asarray(mesh.triangles, dtype=float):
        triangles.addTriangle(a, b, c)
    triangles.endModel()
    return coal.Convex.convexHull(vertices, False, None), triangles


def _distance(a, pose_a: np.ndarray, b, pose_b: np.ndarray) -> float:
    request, result = coal.DistanceRequest(), coal.DistanceResult()
    return coal.distance(
        a,
        coal.Transform3s(pose_a[:3, :3], pose_a[:3, 3]),
        b,
        coal.Transform3s(pose_b[:3, :3], pose_b[:3, 3]),
        request,
        result,
    )


@pytest.fixture(scope="module")
def tiago():
    model = urdf_model("tiago")
    shapes = collision_shapes(model)
    return model.robot, shapes, CollisionModel.from_shapes(model.robot, shapes, TOLERANCE)


def test_every_body_has_its_collision_shapes(tiago):
    robot, shapes, model = tiago
    assert set(shapes) == set(model.bodies)
    names = {body: {s.name for s in items} for body, items in shapes.items()}
    assert {"base_link", "wheel_right_link", "torso_fixed_link"} <= names[(-1, 0)]
    assert names[(0, 0)] >= {"torso_lift_link", "head_2_link"}  # the head hangs from the torso lift
    assert names[(0, 1)] == {"arm_1_link"} and "hand_palm_link" in names[(0, 8 - 1)]


def test_the_spheres_bound_the_urdf_shapes_distance_to_a_box(tiago):
    robot, shapes, model = tiago
    rng = np.random.default_rng(2)
    lower, upper = np.array(robot.position_limits, dtype=float).T
    geometry = {body: [(s, _coal_geometry(s)) for s in items] for body, items in shapes.items()}
    box = coal.Box(0.5, 0.6, 0.4)
    checked = 0
    for k in range(3):
        q = np.zeros(robot.n_q)
        q[:3] = (rng.uniform(-1, 1), rng.uniform(-1, 1), (math.pi / 2, -math.pi / 2, math.pi)[k])
        q[3:] = rng.uniform(lower[3:], upper[3:])
        poses = body_poses(robot, q)
        tool = np.asarray(robot.frames(q).links[0][1][-1])
        box_pose = spatial.as_matrix(
            spatial.transform(spatial.rot_z(rng.uniform(-math.pi, math.pi)), tool + (0.3, 0.0, -0.1))
        )
        for index, body in enumerate(model.bodies):
            frame = spatial.as_matrix(spatial.transform(*poses[index]))
            parts = [(frame @ spatial.as_matrix(s.origin), hull, own) for s, (hull, own) in geometry[body]]
            to_hull = min(_distance(hull, pose, box, box_pose) for pose, hull, _ in parts)
            to_mesh = min(_distance(own, pose, box, box_pose) for pose, _, own in parts)
            spheres = [s for s in model.spheres if s.body == body]
            covered = min(
                _distance(
                    coal.Sphere(s.radius),
                    frame @ spatial.as_matrix(spatial.transform(None, s.centre)),
                    box,
                    box_pose,
                )
                for s in spheres
            )
            if to_hull <= 0:  # the shape meets the box: so does a sphere (coal's penetration depths differ)
                assert covered <= 1e-9, (body, q)
                continue
            assert covered <= to_hull + 1e-9 and covered <= to_mesh + 1e-9, (body, q)  # spheres ⊇ hull ⊇ mesh
            assert to_hull - covered <= TOLERANCE + 1e-9, (body, q)
            checked += 1
    assert checked > 10
