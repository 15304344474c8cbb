"""mobman.planning.clearance: a path's distances to a scene and itself, all samples in one call, reduced to the
smallest distance and the first collision; checked against the car body's box in closed form (the spheres cover
it: they collide wherever it does, and apart they are no farther than it) and against one-configuration queries
sample by sample."""

from __future__ import annotations

import numpy as np
import pytest

from mobman import collision
from mobman.model import robots
from mobman.model.collision_model import collision_model
from mobman.model.scene import Obstacle, Scene
from mobman.planning.clearance import path_clearance

ROBOT = robots.ROBOTS["tchon-car-rtr"]()
MODEL = collision_model(ROBOT)
T = np.linspace(0.0, 1.0, 41)
# the car backs along the x axis from x = 5 to x = 1 (θ = 0, φ = 0), the RTR arm held still
Q = np.zeros((len(T), ROBOT.n_q))
Q[:, 0] = 5.0 - 4.0 * T
Q[:, 4:] = (0.3, 0.5, -0.4)
RADIUS = 0.1


def rock(y: float) -> Scene:
    return Scene((Obstacle("rock", "sphere", (RADIUS,), (2.0, y, -0.075)),))


def box_distance(x_platform: float, centre: np.ndarray) -> float:
    """The rock's distance to the car's body box (footprint: length, width, height, x_centre; its top at the
    platform frame's z = 0), in closed form."""
    box = ROBOT.platform.footprint()
    low = np.array([x_platform + box.x_centre - box.length / 2, -box.width / 2, -box.height])
    high = np.array([x_platform + box.x_centre + box.length / 2, box.width / 2, 0.0])
    outside = np.maximum(np.maximum(low - centre, centre - high), 0.0)
    inside = np.max(np.maximum(low - centre, centre - high))
    return float(np.linalg.norm(outside) if outside.any() else inside) - RADIUS


def per_sample(scene: Scene) -> tuple[np.ndarray, list[int]]:
    """The smallest distance and its pair at each sample, one configuration at a time."""
    each = [collision.distances(MODEL, scene, q).distance for q in Q]
    return np.array([d.min() for d in each]), [int(d.argmin()) for d in each]


def test_an_obstacle_on_the_path_is_hit_no_later_than_the_body_s_box_hits_it():
    scene = rock(0.0)
    clearance = path_clearance(MODEL, scene, T, Q)
    centre = np.array([2.0, 0.0, -0.075])
    box = np.array([box_distance(x, centre) for x in Q[:, 0]])
    first_box = int(np.flatnonzero(box < 0)[0])
    hit = clearance.first_collision
    assert hit is not None and hit.pair == ("platform", "rock")
    assert hit.time <= T[first_box] and hit.distance < 0
    # the spheres cover the box: they collide wherever it does, and apart they are no farther than it
    assert (clearance.distance[box < 0] < 0).all()
    assert (clearance.distance[box >= 0] <= box[box >= 0] + 1e-12).all()
    minimum, pairs = per_sample(scene)
    np.testing.assert_allclose(clearance.distance, minimum, atol=1e-12)
    first = int(np.flatnonzero(minimum < 0)[0])
    names = collision.pair_names(MODEL, scene)
    assert hit.time == T[first] and hit.pair == names[pairs[first]]
    assert hit.distance == pytest.approx(minimum[first], abs=1e-12)
    k = int(np.argmin(minimum))
    out = collision.distances(MODEL, scene, Q[k])
    assert clearance.closest.time == T[k] and clearance.closest.pair == names[pairs[k]]
    np.testing.assert_allclose(clearance.closest.robot_point, out.robot_point[pairs[k]], atol=1e-12)
    np.testing.assert_allclose(clearance.closest.other_point, out.other_point[pairs[k]], atol=1e-12)


def test_an_obstacle_off_the_path_leaves_it_free():
    scene = rock(5.0)
    clearance = path_clearance(MODEL, scene, T, Q)
    assert clearance.first_collision is None and clearance.min_distance > 0
    minimum, _ = per_sample(scene)
    assert clearance.min_distance == pytest.approx(minimum.min(), abs=1e-12)


def test_without_pairs_nothing_is_reported():
    lone = MODEL.with_pairs(())
    clearance = path_clearance(lone, Scene(), T, Q)
    assert clearance.min_distance is None and clearance.first_collision is None
    assert np.isinf(clearance.distance).all()


def test_the_avoidance_vector_is_minus_the_penalty_s_gradient_by_finite_differences():
    """w(z) = −k ∇_z P(z): along a random direction its projection equals −k times the central difference of
    P, which it lowers; P is zero where every pair is farther than d_i."""
    import jax
    import jax.numpy as jnp

    from mobman.planning.basis import Fourier
    from mobman.planning.clearance import avoidance, clearance_penalty
    from mobman.planning.endpoint import PlanningSetting

    setting = PlanningSetting(ROBOT, Fourier(1), horizon=1.0, steps=8, jacobian_steps=8)
    scene = Scene((Obstacle("rock", "sphere", (RADIUS,), (5.0, 0.0, 0.15)),))  # over the car at its start
    rng = np.random.default_rng(2)
    z = jnp.asarray(np.concatenate([rng.normal(0.0, 0.3, setting.n_controls * 3), [0.3, 0.5, -0.4]]))
    q0 = jnp.asarray([5.0, 0.0, 0.0, 0.0])
    penalty_of = jax.jit(lambda zz: clearance_penalty(setting, MODEL, scene, 0.2, zz, q0))
    penalty = lambda zz: float(penalty_of(zz))  # noqa: E731
    assert penalty(z) > 0
    w = np.asarray(jax.jit(avoidance(setting, MODEL, scene, 0.2, 3.0))(z, q0))
    v = rng.normal(size=z.shape)
    h = 1e-6
    slope = (penalty(z + h * v) - penalty(z - h * v)) / (2 * h)
    assert w @ v == pytest.approx(-3.0 * slope, rel=1e-5, abs=1e-9)
    assert penalty(z + 1e-3 * w) < penalty(z)
    far = Scene((Obstacle("rock", "sphere", (RADIUS,), (40.0, 0.0, 0.0)),))
    assert float(jax.jit(lambda zz: clearance_penalty(setting, MODEL, far, 0.2, zz, q0))(z)) == 0.0
