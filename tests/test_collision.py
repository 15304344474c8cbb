"""Signed distances of collision spheres to primitives and to each other against coal (hpp-fcl), and the
distance-rate rows over η against finite differences along q(t) = q + t S(q) η and against autodiff."""

from __future__ import annotations

import math
from dataclasses import replace

import coal
import jax
import jax.numpy as jnp
import numpy as np
import pytest
from coal_shapes import coal_distance, coal_shape

from mobman import collision
from mobman.errors import ModelError
from mobman.model import robots, spatial
from mobman.model.arm import Joint
from mobman.model.collision_model import CollisionModel, CollisionSphere
from mobman.model.platforms import DifferentialDrive, Omnidirectional
from mobman.model.robot import Follower, MobileManipulator
from mobman.model.scene import Obstacle, Scene
from mobman.model.visual import Visual

# --- a small robot: the planar 2R arm on a platform, a few spheres ----------------------------------


def _robot(platform=None) -> MobileManipulator:
    base = robots.ROBOTS["bayle-planar"]()
    return base if platform is None else MobileManipulator(platform, base.arms, base.mounts, name="omni")


def _with_followers() -> MobileManipulator:
    """bayle-planar with two followers: a mast on the platform rising at half the shoulder angle (m/rad), and
    a flap on the upper link turning at −1.3 times the elbow, hung from the mast's side."""
    base = _robot()
    turned = spatial.as_matrix(spatial.transform(spatial.rot_x(0.4), (0.1, 0.05, 0.02)))
    mast = Follower(Joint("prismatic", (0.0, 0.0, 1.0), name="mast", offset=0.1), (-1, 0), 3, 0.5)
    flap = Follower(Joint("revolute", (0.0, 1.0, 0.0), tuple(turned.ravel()), name="flap"), (0, 0), 4, -1.3)
    return replace(base, followers=(mast, flap))


def _model(robot: MobileManipulator) -> CollisionModel:
    spheres = (
        CollisionSphere((-1, 0), (0.0, 0.0, -0.05), 0.3, "body"),
        CollisionSphere((-1, 0), (0.25, 0.0, -0.05), 0.12, "front"),
        CollisionSphere((0, 0), (0.25, 0.0, 0.0), 0.06, "upper"),
        CollisionSphere((0, 1), (0.2, 0.0, 0.0), 0.05, "fore"),
        CollisionSphere((0, 1), (0.45, 0.05, 0.02), 0.04, "hand"),
    )
    spheres += tuple(
        CollisionSphere((-2, k), (0.1, -0.05, 0.2), 0.07, f.joint.name) for k, f in enumerate(robot.followers)
    )
    return CollisionModel(robot, spheres, ((0, 2),), 0.0)


SCENE = Scene(
    (
        Obstacle("table", "box", (0.8, 1.2, 0.75), (1.3, 0.0, 0.375), (0.1, -0.2, 0.7)),
        Obstacle("ball", "sphere", (0.2,), (0.2, 0.9, 0.1)),
        Obstacle("post", "cylinder", (0.1, 1.0), (-0.8, -0.4, 0.5), (math.pi / 2, 0.0, 0.3)),
        Obstacle("rail", "capsule", (0.05, 1.5), (0.0, -1.0, 0.2), (0.0, math.pi / 2, 0.0)),
    ),
    floor=-0.02,
)


def test_distances_of_a_robot_match_coal_per_pair():
    robot = _robot()
    model = _model(robot)
    rng = np.random.default_rng(3)
    q = rng.uniform(-math.pi, math.pi, (6, robot.n_q))
    q[:, :2] = rng.uniform(-1.0, 1.0, (6, 2))
    q[0, 2:] = (math.pi / 2, -math.pi / 2, math.pi)
    out = collision.distances(model, SCENE, q)
    names = collision.pair_names(model, SCENE)
    n_s, n_o = len(model.spheres), len(SCENE.obstacles)
    arm = [k for k, s in enumerate(model.spheres) if s.body[0] >= 0]
    assert out.distance.shape == (6, n_s * n_o + len(arm) + len(model.sphere_pairs))
    assert len(names) == out.distance.shape[1]
    for c in range(len(q)):
        centres = np.asarray(collision.centres_one(model, jnp.asarray(q[c])))
        expected = []
        for k, s in enumerate(model.spheres):
            for o in SCENE.obstacles:
                expected.append(
                    coal_distance(
                        coal.Sphere(s.radius),
                        coal.Transform3s(np.eye(3), centres[k]),
                        coal_shape(o.shape, o.size),
                        coal.Transform3s(o.rotation, np.array(o.position)),
                    )[0]
                )
        for k in arm:
            floor = coal.Halfspace(np.array([0.0, 0.0, 1.0]), SCENE.floor)
            expected.append(
                coal_distance(
                    coal.Sphere(model.spheres[k].radius),
                    coal.Transform3s(np.eye(3), centres[k]),
                    floor,
                    coal.Transform3s(),
                )[0]
            )
        for i, j in model.sphere_pairs:
            expected.append(
                coal_distance(
                    coal.Sphere(model.spheres[i].radius),
                    coal.Transform3s(np.eye(3), centres[i]),
                    coal.Sphere(model.spheres[j].radius),
                    coal.Transform3s(np.eye(3), centres[j]),
                )[0]
            )
        np.testing.assert_allclose(out.distance[c], expected, atol=1e-9)
    # the witness points are the distance apart along the normal
    gap = out.robot_point - out.other_point
    np.testing.assert_allclose(np.einsum("...k,...k->...", gap, out.normal), out.distance, atol=1e-9)


def _motion(robot: MobileManipulator, q: np.ndarray, eta: np.ndarray, t: float) -> np.ndarray:
    return q + t * np.asarray(robot.S(jnp.asarray(q))) @ eta


@pytest.mark.parametrize("robot", [_robot(), _robot(Omnidirectional()), _with_followers()])
def test_rows_match_finite_differences_and_autodiff(robot):
    model = _model(robot)
    rng = np.random.default_rng(11)
    q = rng.uniform(-math.pi, math.pi, robot.n_q)
    q[:2] = (0.3, -0.2)
    q[2] = math.pi / 2
    eta = rng.normal(size=robot.n_eta)
    rows = collision.distances(model, SCENE, q).rows
    h = 1e-6
    plus = collision.distances(model, SCENE, _motion(robot, q, eta, h)).distance
    minus = collision.distances(model, SCENE, _motion(robot, q, eta, -h)).distance
    np.testing.assert_allclose(rows @ eta, (plus - minus) / (2 * h), atol=1e-7)
    # autodiff of the distance along q(t) = q + t S(q) η
    s = jnp.asarray(np.asarray(robot.S(jnp.asarray(q))))
    rate = jax.jit(
        jax.jacfwd(lambda t: collision.distances_one(model, SCENE, jnp.asarray(q) + t * s @ eta)[0])
    )(0.0)
    np.testing.assert_allclose(rows @ eta, np.asarray(rate), atol=1e-10)


def test_a_differential_drive_cannot_slide_sideways_away_from_a_wall():
    """A wall along x beside the platform: the distance of the platform's body sphere does not change with the
    forward speed or the turn (the rows' platform entries vanish), though sliding sideways would change it
    (the row over q has a lateral entry); an omnidirectional platform's row has it."""
    wall = Scene((Obstacle("wall", "box", (4.0, 0.1, 1.0), (0.0, 0.6, 0.0)),))
    results = {}
    for platform in (None, Omnidirectional()):
        robot = _robot(platform)
        model = CollisionModel(robot, (CollisionSphere((-1, 0), (0.0, 0.0, 0.0), 0.3, "body"),), (), 0.0)
        out = collision.distances(model, wall, np.zeros(robot.n_q))
        assert out.distance[0] == pytest.approx(0.6 - 0.05 - 0.3, abs=1e-12)
        np.testing.assert_allclose(out.normal[0], (0.0, -1.0, 0.0), atol=1e-12)
        results[type(robot.platform).__name__] = out.rows[0]
    diff = results["DifferentialDrive"]
    np.testing.assert_allclose(diff, 0.0, atol=1e-12)  # v along the wall, ω about the centre: no rate
    robot = _robot()
    assert isinstance(robot.platform, DifferentialDrive)
    lateral = np.array([0.0, 1.0, 0.0, 0.0, 0.0])  # q̇ sliding along y at θ = 0: not admissible
    assert abs(float((np.asarray(robot.constraints(jnp.zeros(robot.n_q))) @ lateral)[0])) == pytest.approx(
        1.0
    )
    omni = results["Omnidirectional"]
    assert omni[1] == pytest.approx(-1.0, abs=1e-12)  # sliding toward +y closes the gap at unit rate


def test_bad_configuration_is_one_line():
    from mobman.errors import InputError

    robot = _robot()
    with pytest.raises(InputError, match="configuration"):
        collision.distances(_model(robot), SCENE, [0.0, float("nan"), 0.0, 0.0])


def test_a_follower_is_a_body_of_the_collision_model_next_to_its_parent():
    robot = _with_followers()
    shapes = {(-2, 0): (Visual("box", size=(0.1, 0.1, 0.1)),), (0, 1): (Visual("sphere", size=(0.05,)),)}
    model = CollisionModel.from_shapes(robot, shapes)
    names = [model.body_name(b) for b in model.bodies]
    assert names[-2:] == ["mast", "flap"]
    index = {b: i for i, b in enumerate(model.bodies)}
    assert (index[(-1, 0)], index[(-2, 0)]) not in model.pairs  # the mast and the platform: neighbours


def test_bad_followers_are_one_line():
    base = _robot()
    lift = Joint("prismatic", name="lift")
    with pytest.raises(ModelError, match="follower 'lift' leads from q\\[1\\], not an arm coordinate"):
        replace(base, followers=(Follower(lift, (-1, 0), 1),))
    with pytest.raises(ModelError, match="follower 'lift' hangs from \\(0, 5\\)"):
        replace(base, followers=(Follower(lift, (0, 5), 3),))
    with pytest.raises(ModelError, match="multiplier must be finite"):
        Follower(lift, (-1, 0), 3, math.nan)
