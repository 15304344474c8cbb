"""Collision-free postures in reachability maps and base placement (mobman.studies.clearance), on TIAGo.

The reference is coal on the URDF's own collision geometry, through Pinocchio (``buildGeomFromUrdf`` with
its meshes, reduced to mobman's chains like tests/test_urdf_pinocchio.py), never mobman's own distances:

- a map of the cells around and inside TIAGo's base reaches some of them only with the hand inside the base
  (within 0.25 m of the platform's centre, below 0.3 m) when postures are not checked; checked, no such cell
  is reached, they are counted as colliding, and coal finds no collision of the self pairs at the posture of
  any reached cell;
- TIAGo reaching over a table, the table's rectangle kept out of the footprint: the best posture without the
  scene puts the arm through the table (coal), with it the best posture is free of the table and of itself.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

from mobman.errors import InputError
from mobman.io.real_robots import REAL_ROBOTS, urdf_model
from mobman.io.urdf import collision_shapes
from mobman.model.collision_model import CollisionModel
from mobman.model.scene import Obstacle, Scene
from mobman.studies.clearance import COVER_TOLERANCE
from mobman.studies.floor import scene_regions
from mobman.studies.maps import reachability_map
from mobman.studies.placement import place

TABLE = Obstacle("table", "box", (0.6, 1.0, 0.75), (1.2, 0.0, 0.375))
TARGET = [0.95, 0.0, 0.9]
GRID = dict(radii=[0.5, 0.7, 0.9], bearings=8, headings=4, starts=8)


@pytest.fixture(scope="module")
def tiago():
    model = urdf_model("tiago")
    return model.robot, CollisionModel.from_shapes(model.robot, collision_shapes(model), COVER_TOLERANCE)


@pytest.fixture(scope="module")
def coal_tiago(tiago):
    """Pinocchio's reduced model and collision geometry of TIAGo, and for each geometry object mobman's body
    (its index in CollisionModel.bodies)."""
    robot, model = tiago
    spec = REAL_ROBOTS["tiago"]
    path = str(spec.path())
    full = pin.buildModelFromUrdf(path, pin.JointModelPlanar())
    package = str(spec.path().parents[4])  # package://example-robot-data/…
    geometry = pin.buildGeomFromUrdf(full, path, pin.GeometryType.COLLISION, package_dirs=[package])
    keep = {j.name for arm in robot.arms for j in arm.joints}
    reference = pin.neutral(full)
    for joint_name, value in spec.locked:
        reference[full.idx_qs[full.getJointId(joint_name)]] = value
    locked = [i for i in range(2, full.njoints) if full.names[i] not in keep]
    reduced, geometry = pin.buildReducedModel(full, geometry, locked, reference)
    joints = [j.name for arm in robot.arms for j in arm.joints]
    body = []
    for obj in geometry.geometryObjects:
        name = reduced.names[obj.parentJoint]
        body.append(0 if obj.parentJoint <= 1 else model.bodies.index((0, joints.index(name))))
    return reduced, geometry, np.array(body)


def _pinocchio_q(reduced, robot, q: np.ndarray) -> np.ndarray:
    out = np.zeros(reduced.nq)
    out[:2], out[2], out[3] = q[:2], np.cos(q[2]), np.sin(q[2])
    for k, joint in enumerate(j.name for arm in robot.arms for j in arm.joints):
        out[reduced.idx_qs[reduced.getJointId(joint)]] = q[3 + k]
    return out


def _colliding_pairs(coal_tiago, tiago, q: np.ndarray, table: bool) -> list[tuple[str, str]]:
    """The pairs coal finds in collision at q: the self pairs of mobman's model (as bodies) over the URDF's
    collision geometry, and with ``table`` every geometry object against the table."""
    reduced, geometry, body = coal_tiago
    robot, model = tiago
    geometry = geometry.copy()
    objects = len(geometry.geometryObjects)
    pairs = {tuple(p) for p in model.pairs}
    for a in range(objects):
        for b in range(a + 1, objects):
            if (min(body[a], body[b]), max(body[a], body[b])) in pairs:
                geometry.addCollisionPair(pin.CollisionPair(a, b))
    if table:
        import coal

        placement = pin.SE3(np.eye(3), np.asarray(TABLE.position))
        index = geometry.addGeometryObject(
            pin.GeometryObject("table", 0, 0, placement, coal.Box(*TABLE.size))
        )
        for a in range(objects):
            geometry.addCollisionPair(pin.CollisionPair(a, index))
    data, geometry_data = reduced.createData(), geometry.createData()
    pin.computeCollisions(reduced, data, geometry, geometry_data, _pinocchio_q(reduced, robot, q), False)
    names = [o.name for o in geometry.geometryObjects]
    return [
        (names[p.first], names[p.second])
        for p, result in zip(geometry.collisionPairs, geometry_data.collisionResults)
        if result.isCollision()
    ]


def _inside_base(centres: np.ndarray) -> np.ndarray:
    return (np.hypot(centres[..., 0], centres[..., 1]) <= 0.25) & (centres[..., 2] < 0.3)


def test_no_cell_is_reached_only_from_inside_the_robot(tiago, coal_tiago):
    robot, model = tiago
    options = dict(bounds=[-0.3, 0.5, -0.3, 0.3, 0.0, 0.5], step=0.1, starts=8, iterations=60)
    unchecked = reachability_map(robot, **options)
    inside = _inside_base(unchecked.centres())
    assert np.sum(unchecked.reached & inside) >= 5  # the hand held inside the base, unchecked
    checked = reachability_map(robot, collision=model, **options)
    assert not np.any(checked.reached & inside)
    assert np.sum(checked.colliding & inside) >= 5
    assert checked.reached.any() and not np.any(checked.reached & checked.colliding)
    assert checked.clearance is not None and checked.clearance["self_pairs"] == len(model.sphere_pairs)
    for q in checked.q[checked.reached]:
        assert _colliding_pairs(coal_tiago, tiago, q, table=False) == [], q


def test_placement_over_a_table_keeps_the_arm_out_of_it(tiago, coal_tiago):
    robot, model = tiago
    scene = Scene((TABLE,), floor=0.0)
    (region,) = scene_regions(scene)
    assert np.allclose([region.x_min, region.x_max, region.y_min, region.y_max], [0.9, 1.5, -0.5, 0.5])
    plain = place(robot, TARGET, keep_out=[region], **GRID)
    assert plain.best is not None
    through = _colliding_pairs(coal_tiago, tiago, plain.q[plain.best], table=True)
    assert any("table" in pair for pair in through), through  # the arm through the table top
    result = place(robot, TARGET, scene=scene, collision=model, **GRID)
    assert result.best is not None
    assert np.array_equal(
        result.blocked, plain.blocked
    )  # the table's box on the floor is the keep-out region
    assert result.colliding.sum() >= 1 and not np.any(result.colliding & (result.reached | result.blocked))
    assert result.reached.sum() < plain.reached.sum()
    for k in np.flatnonzero(result.reached):
        assert _colliding_pairs(coal_tiago, tiago, result.q[k], table=True) == [], result.bases[k]


def test_bad_collision_arguments_are_one_line(tiago):
    robot, model = tiago
    with pytest.raises(InputError, match="scene must be"):
        place(robot, TARGET, scene="table.toml", **GRID)
    with pytest.raises(InputError, match="collision must be"):
        reachability_map(robot, collision=0.1, step=0.5)


def test_scene_regions_are_the_boxes_on_the_floor():
    turned = Obstacle("turned", "box", (1.0, 2.0, 0.5), (0.0, 0.0, 0.25), (0.0, 0.0, np.pi / 2))
    shelf = Obstacle("shelf", "box", (1.0, 1.0, 0.1), (0.0, 0.0, 1.0))
    ball = Obstacle("ball", "sphere", (0.2,), (3.0, 0.0, 0.2))
    (region,) = scene_regions(Scene((turned, shelf, ball)))
    assert np.allclose([region.x_min, region.x_max, region.y_min, region.y_max], [-1.0, 1.0, -0.5, 0.5])
    assert scene_regions(Scene((shelf,), floor=0.95)) != ()  # standing on a raised floor
