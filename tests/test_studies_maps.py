"""mobman.studies.maps: the reachability map of a planar 2R arm against its closed form (the annulus and
w = l1 l2 |sin q5|), TIAGo's map against Pinocchio, the grid, a stopped map resumed, and bad input."""

from __future__ import annotations

import numpy as np
import pytest

from mobman import kinematics as K
from mobman import manipulability as mp
from mobman.errors import InputError
from mobman.model import robots
from mobman.model.tasks import Position
from mobman.redundancy import sample_configurations
from mobman.studies import store
from mobman.studies.maps import (
    MAX_CELLS,
    default_bounds,
    from_study,
    grid_axes,
    reachability_map,
    tool_positions,
)

from tiago_urdf import pinocchio_tool_positions

L1, L2 = 0.7, 0.4
PLANE = [-1.2, 1.2, -1.2, 1.2, 0.0, 0.0]


@pytest.fixture(scope="module")
def planar():
    robot = robots.bayle_planar(l1=L1, l2=L2)
    return robot, reachability_map(robot, bounds=PLANE, step=0.1, starts=4, iterations=100)


def test_the_planar_2r_arm_reaches_the_annulus_with_the_closed_form_manipulability(planar):
    _, result = planar
    assert result.shape == (25, 25, 1)
    d = np.linalg.norm(result.centres()[..., :2], axis=-1)
    annulus = (d >= L1 - L2 - 1e-9) & (d <= L1 + L2 + 1e-9)
    np.testing.assert_array_equal(result.reached, annulus)
    # the measure at the posture found: w = l1 l2 |sin q5| of the planar 2R arm (rows x, y)
    q5 = result.q[..., 4]
    np.testing.assert_allclose(result.score[annulus], (L1 * L2 * np.abs(np.sin(q5)))[annulus], atol=1e-12)
    # and q5 is the law of cosines' elbow angle, to the tolerance's effect away from the singular rims
    cos_q5 = np.clip((d**2 - L1**2 - L2**2) / (2 * L1 * L2), -1.0, 1.0)
    inner = annulus & (d >= L1 - L2 + 1e-3) & (d <= L1 + L2 - 1e-3)
    np.testing.assert_allclose(result.score[inner], (L1 * L2 * np.sqrt(1.0 - cos_q5**2))[inner], atol=1e-6)
    assert np.isnan(result.score[~annulus]).all() and result.computed.all()
    assert result.fraction == pytest.approx(annulus.sum() / annulus.size)
    best = result.best()
    assert result.score[best] == pytest.approx(L1 * L2, abs=2e-3)  # the cell nearest d = √(l1² + l2²)


def test_tiago_s_reached_cells_put_its_tool_on_the_centre_by_pinocchio_within_its_limits():
    robot = robots.build("tiago")
    result = reachability_map(robot, bounds=[0.2, 0.8, -0.6, 0.2, 0.6, 1.2], step=0.2, level="system")
    assert result.shape == (4, 5, 4) and result.reached.sum() >= 20
    q = result.q[result.reached]
    assert not robot.limit_violations(q).any()
    assert np.abs(q[:, :3]).max() == 0.0  # the platform parked at the origin
    tool = pinocchio_tool_positions(robot, q)
    assert np.abs(tool - result.centres()[result.reached]).max() <= 1e-4
    # the system level scores J̄ = J S of the tool position, whose platform columns add to the arm's
    jbar = np.asarray(K.reduced_jacobian(robot, q, Position("xyz")))
    w = np.sqrt(np.linalg.det(jbar @ np.swapaxes(jbar, -1, -2)))
    np.testing.assert_allclose(result.score[result.reached], w, rtol=1e-9)
    arm = np.asarray(mp.jacobian_and_measures(robot, q, "arm", Position("xyz"))[1]["yoshikawa"])
    assert np.all(w >= arm)


def test_every_cell_near_a_posture_s_tool_is_reached():
    from scipy.spatial import cKDTree

    robot = robots.build("tiago")
    step = 0.1
    result = reachability_map(robot, bounds=[0.2, 0.8, -0.8, 0.0, 0.5, 1.3], step=step)
    q = sample_configurations(robot, 20_000, seed=4)
    q[:, :3] = 0.0
    tool = np.asarray(K.forward(robot, q, Position("xyz")))
    # cells with a sampled tool position within a tenth of a step of their centre
    distance, _ = cKDTree(tool).query(result.centres().reshape(-1, 3))
    near = distance <= 0.1 * step
    assert near.sum() >= 20
    assert result.reached.reshape(-1)[near].all()


def test_the_default_bounds_hold_every_sampled_tool_position_and_a_planar_arm_s_single_layer():
    tiago = robots.build("tiago")
    tool = tool_positions(tiago, 0)
    bounds = default_bounds(tool, 0.05)
    assert np.all(bounds[:, 0] <= tool.min(axis=0) - 0.05 + 1e-12)
    assert np.all(bounds[:, 1] >= tool.max(axis=0) + 0.05 - 1e-12)
    planar = robots.bayle_planar()
    flat = default_bounds(tool_positions(planar, 0), 0.1)
    assert flat[2, 0] == flat[2, 1]
    assert [len(a) for a in grid_axes(flat, 0.1)][2] == 1


def test_grid_axes_run_from_the_lower_bound_to_the_upper_one():
    x, y, z = grid_axes(np.array([[0.0, 1.0], [-0.25, 0.25], [0.3, 0.3]]), 0.25)
    np.testing.assert_allclose(x, [0.0, 0.25, 0.5, 0.75, 1.0])
    np.testing.assert_allclose(y, [-0.25, 0.0, 0.25])
    np.testing.assert_allclose(z, [0.3])


def test_a_stopped_map_is_resumed_to_the_same_cells(tmp_path, planar):
    robot, whole = planar
    path = tmp_path / "map.zarr"

    def stop_after_two(done, total):
        if done == 2:
            raise KeyboardInterrupt

    options = {"bounds": PLANE, "step": 0.1, "starts": 4, "iterations": 100}
    with pytest.raises(KeyboardInterrupt):
        reachability_map(robot, store=str(path), chunk=100, progress=stop_after_two, **options)
    stopped = from_study(store.read(path))
    assert stopped.computed.sum() == 200 and not stopped.computed.all()
    resumed = reachability_map(robot, store=str(path), **options)
    np.testing.assert_array_equal(resumed.reached, whole.reached)
    np.testing.assert_allclose(resumed.score, whole.score, equal_nan=True, atol=1e-12)
    with pytest.raises(InputError, match="starts: 8 asked, 4 in the store"):
        reachability_map(robot, store=str(path), **(options | {"starts": 8}))
    with pytest.raises(InputError, match="robot_digest"):
        reachability_map(robots.bayle_planar(l1=0.6, l2=L2), store=str(path), **options)


@pytest.mark.parametrize(
    ("options", "message"),
    [
        ({"step": 0.0}, "step must be a finite distance > 0"),
        ({"step": float("nan")}, "step must be a finite distance > 0"),
        ({"bounds": [0, 1, 0, 1]}, "bounds must be 6 finite numbers"),
        ({"bounds": [0, 1, 0, 1, 0, float("inf")]}, "NaN or infinite"),
        ({"bounds": [1, 0, 0, 1, 0, 1]}, "x_min 1 is above x_max 0"),
        ({"starts": 0}, "starts must be an integer ≥ 1"),
        ({"iterations": 1.5}, "iterations must be an integer ≥ 1"),
        ({"tolerance": -1.0}, "tolerance must be a number > 0 and ≤ 0.1"),
        ({"measure": "volume"}, "measure must be one of yoshikawa"),
        ({"level": "platform"}, "level must be one of arm, system"),
        ({"arm": 1}, "arm must be an integer from 0 to 0"),
        ({"bounds": [-10, 10, -10, 10, -10, 10], "step": 0.001}, f"more than {MAX_CELLS:,}"),
    ],
)
def test_bad_input_is_one_error_naming_the_field(options, message):
    with pytest.raises(InputError, match=message):
        reachability_map(robots.bayle_planar(), **options)


def test_a_point_s_cell_is_the_nearest_centre(planar):
    _, result = planar
    assert result.cell([0.52, -0.04, 0.0]) == (17, 12, 0)
    with pytest.raises(InputError, match="point must be 3 finite numbers"):
        result.cell([0.0, 0.0])


def test_the_robot_digest_follows_the_kinematics_not_the_task_nor_the_visuals():
    import dataclasses

    from mobman.studies.maps import robot_digest

    tiago = robots.build("tiago")
    assert robot_digest(tiago) == robot_digest(tiago.with_task(Position("xy")))
    assert robot_digest(tiago) == robot_digest(dataclasses.replace(tiago, platform_visuals=()))
    bare = dataclasses.replace(
        tiago,
        arms=tuple(
            dataclasses.replace(arm, joints=tuple(dataclasses.replace(j, visuals=()) for j in arm.joints))
            for arm in tiago.arms
        ),
    )
    assert robot_digest(bare) == robot_digest(tiago)  # mesh files lie where each machine installed them
    assert robot_digest(robots.bayle_planar(l1=0.5)) != robot_digest(robots.bayle_planar(l1=0.6))
