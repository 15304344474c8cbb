"""Collision avoidance in the QP law (velocity dampers, mobman.control.avoidance), on the scenario of
docs/examples/tiago_avoid.toml: TIAGo reaching a point over a table. Without the scene its base drives into the
table; with it, coal's distances of TIAGo's own URDF collision meshes to the obstacles (poses from the run, not
mobman's distances) stay above the margin at every sample, and the hand still reaches the target."""

from __future__ import annotations

import copy
from pathlib import Path

import coal
import numpy as np
import pytest
import trimesh

from mobman.control import spec
from mobman.control.laws import WholeBodyQP
from mobman.errors import InputError, ModelError
from mobman.io.real_robots import urdf_model
from mobman.io.spec import read_toml
from mobman.io.urdf import collision_shapes
from mobman.model import spatial
from mobman.model.collision_model import body_poses
from mobman.model.scene import Scene

EXAMPLES = Path(__file__).parents[1] / "docs" / "examples"


def _mesh_geometry(shape) -> coal.CollisionGeometry:
    """A URDF collision shape for coal: a primitive exactly, a mesh as its own triangles."""
    if shape.kind == "box":
        return coal.Box(*shape.size)
    if shape.kind == "cylinder":
        return coal.Cylinder(*shape.size)
    if shape.kind == "sphere":
        return coal.Sphere(shape.size[0])
    mesh = trimesh.load(shape.filename, force="mesh")
    mesh.apply_scale(shape.scale)
    triangles = coal.BVHModelOBBRSS()
    triangles.beginModel(len(mesh.faces), len(mesh.vertices))
    for a, b, c in np.asarray(mesh.triangles, dtype=float):
        triangles.addTriangle(a, b, c)
    triangles.endModel()
    return triangles


def _coal_min_distance(robot, shapes, scene: Scene, q_path: np.ndarray) -> float:
    """The least coal distance of the URDF's collision shapes to the scene's boxes over the path."""
    parts = [
        (index, spatial.as_matrix(s.origin), _mesh_geometry(s))
        for index, items in enumerate(shapes.values())
        for s in items
    ]
    assert list(shapes) == [(-1, 0)] + [(0, k) for k in range(robot.arms[0].n_joints)]
    boxes = [(coal.Box(*o.size), coal.Transform3s(o.rotation, np.array(o.position))) for o in scene.obstacles]
    least = np.inf
    for q in q_path:
        poses = body_poses(robot, q)
        for index, origin, geometry in parts:
            pose = spatial.as_matrix(spatial.transform(*poses[index])) @ origin
            placed = coal.Transform3s(pose[:3, :3], pose[:3, 3])
            for box, box_pose in boxes:
                request, result = coal.DistanceRequest(), coal.DistanceResult()
                least = min(least, coal.distance(geometry, placed, box, box_pose, request, result))
    return least


@pytest.fixture(scope="module")
def runs():
    document = read_toml(EXAMPLES / "tiago_avoid.toml")
    bare = copy.deepcopy(document)
    del bare["scene"]
    avoiding = spec.parse(document, EXAMPLES)
    return avoiding, avoiding.simulate(), spec.parse(bare, EXAMPLES).simulate()


def test_without_the_scene_the_base_drives_into_the_table(runs):
    avoiding, _, bare = runs
    model = urdf_model("tiago")
    assert bare.law.scene is None
    assert _coal_min_distance(model.robot, collision_shapes(model), avoiding.law.scene, bare.q) < 0.0


def test_with_the_scene_every_mesh_keeps_the_margin_and_the_hand_reaches_the_target(runs):
    avoiding, result, _ = runs
    model = urdf_model("tiago")
    margin = avoiding.law.collision_margin
    assert _coal_min_distance(model.robot, collision_shapes(model), avoiding.law.scene, result.q) >= margin
    assert np.linalg.norm(result.error[-1]) < 1e-3
    assert np.min(result.info["min_distance"]) >= margin  # the spheres', which bound the meshes' from below
    assert np.max(result.info["collision_slack"]) < 1e-6


def test_the_options_are_checked():
    scene = Scene()
    with pytest.raises(ModelError, match="influence_distance must be > collision_margin"):
        WholeBodyQP(scene=scene, collision_margin=0.3, influence_distance=0.2)
    with pytest.raises(ModelError, match="collision_gain must be a finite number > 0"):
        WholeBodyQP(scene=scene, collision_gain=0.0)
    with pytest.raises(ModelError, match="collision_rows must be an integer in 1..256"):
        WholeBodyQP(scene=scene, collision_rows=0)
    document = read_toml(EXAMPLES / "tiago_avoid.toml")
    document["law"] = {"kind": "bayle"}
    with pytest.raises(
        InputError, match='scene: the bayle law does not avoid collisions; give \\[law\\] kind = "qp"'
    ):
        spec.parse(document, EXAMPLES)
