"""Base placement (mobman.studies.placement): the reach and the manipulability of a planar 2R arm in closed form,
TIAGo's reached postures against Pinocchio's forward kinematics, a full 6-D pose, and the errors."""

from __future__ import annotations

import numpy as np
import pytest
from lift_robot import HIGHEST, LOWEST, lift_file

from mobman import kinematics as K
from mobman.errors import InputError
from mobman.io import robot_file
from mobman.model import robots
from mobman.model.tasks import EulerAngles, Pose, Position
from mobman.redundancy import sample_configurations
from mobman.studies.placement import candidate_bases, closest_height, place, reach_radius

from tiago_urdf import pinocchio_tool_positions

L1 = L2 = 0.5


def _planar():
    """Bayle's platform with its horizontal 2R arm at the axle midpoint, the task the tip's (x, y)."""
    return robots.build("bayle-planar", l1=L1, l2=L2).with_task(Position("xy"))


def test_closest_height_is_the_end_of_the_lift_s_travel(tmp_path):
    """The lift robot's tool reaches the heights 0.5 to 1.1 m (tests/lift_robot.py): a height outside is met
    by the nearest end of the lift's travel, one inside by itself; a task without a height has none."""
    robot = robot_file.load(lift_file(tmp_path))
    assert closest_height(robot, 1.5) == pytest.approx(HIGHEST, abs=1e-9)
    assert closest_height(robot, -2.0) == pytest.approx(LOWEST, abs=1e-9)
    assert closest_height(robot, 0.7) == pytest.approx(0.7, abs=1e-9)
    assert closest_height(robot, 1.0, Pose()) == pytest.approx(1.0, abs=1e-9)
    assert closest_height(robot, 1.0, Position("xy")) is None


def test_candidate_bases_circle_the_centre_and_the_first_heading_faces_it():
    bases = candidate_bases([1.0, -2.0], [0.5, 1.0], bearings=4, headings=3)
    assert bases.shape == (2 * 4 * 3, 3)
    offsets = bases[:, :2] - np.array([1.0, -2.0])
    np.testing.assert_allclose(np.linalg.norm(offsets, axis=1), np.repeat([0.5, 1.0], 12), atol=1e-15)
    facing = bases[::3]  # heading 0 of each (radius, bearing)
    towards = -offsets[::3] / np.linalg.norm(offsets[::3], axis=1, keepdims=True)
    np.testing.assert_allclose(np.c_[np.cos(facing[:, 2]), np.sin(facing[:, 2])], towards, atol=1e-12)
    assert np.all((bases[:, 2] >= -np.pi) & (bases[:, 2] < np.pi))


def test_a_planar_2r_arm_reaches_within_l1_plus_l2_with_the_closed_form_manipulability():
    robot = _planar()
    radii = [0.2, 0.5, np.sqrt(L1**2 + L2**2), 0.9, 1.1, 1.5]
    target = np.array([0.3, -0.4])
    result = place(robot, target, radii=radii, bearings=4, headings=4, starts=4)
    distance = np.linalg.norm(result.bases[:, :2] - target, axis=1)
    np.testing.assert_array_equal(result.reached, distance < L1 + L2)
    assert result.error[result.reached].max() <= 1e-9
    assert result.error[~result.reached].min() >= 0.1 - 1e-9  # 1.1 m away: 0.1 m short at best
    # Yoshikawa's w of the arm's 2 × 2 Jacobian: |det J_a| = l1 l2 |sin q5|, with cos q5 from the distance
    cos_q5 = (distance**2 - L1**2 - L2**2) / (2 * L1 * L2)
    w = L1 * L2 * np.sqrt(np.clip(1.0 - cos_q5**2, 0.0, None))
    np.testing.assert_allclose(result.score[result.reached], w[result.reached], atol=1e-9)
    np.testing.assert_array_equal(result.score[~result.reached], 0.0)
    # the best distance is √(l1² + l2²) (the elbow at a right angle, w = l1 l2), whatever the bearing
    assert distance[result.best] == pytest.approx(np.sqrt(L1**2 + L2**2))
    assert result.score[result.best] == pytest.approx(L1 * L2, abs=1e-9)
    assert np.abs(np.asarray(K.forward(robot, result.q[result.reached])) - target).max() <= 1e-9


def test_several_targets_are_reached_from_one_base_each_with_its_own_posture():
    """Two targets of the planar 2R arm: a base reaches both when both lie within l1 + l2 of its shoulder, and
    is scored by the lower of the closed-form w = l1 l2 |sin q5| of its two postures."""
    robot = _planar()
    targets = np.array([[0.3, -0.4], [0.6, 0.1]])
    result = place(robot, targets, radii=[0.2, 0.4, 0.6, 0.8, 1.0], bearings=8, headings=4, starts=4)
    assert result.target.shape == (2, 2) and result.q.shape == (len(result.bases), 2, robot.n_q)
    # the grid is centred on the middle of the targets' bounding box
    np.testing.assert_allclose(result.bases[0, :2], [0.45 + 0.2, -0.15], atol=1e-12)
    distance = np.linalg.norm(result.bases[:, None, :2] - targets, axis=2)  # (N, 2)
    inside = distance < L1 + L2 - 1e-9
    clear = np.all(np.abs(distance - (L1 + L2)) > 1e-6, axis=1)  # not at the edge of the reach
    np.testing.assert_array_equal(result.reached[clear], np.all(inside, axis=1)[clear])
    assert 0 < result.reached.sum() < np.any(inside, axis=1).sum()
    cos_q5 = (distance**2 - L1**2 - L2**2) / (2 * L1 * L2)
    w = L1 * L2 * np.sqrt(np.clip(1.0 - cos_q5**2, 0.0, None))
    np.testing.assert_allclose(result.score[result.reached], w.min(axis=1)[result.reached], atol=1e-9)
    for k in range(2):  # each posture puts the tool on its own target
        tool = np.asarray(K.forward(robot, result.q[result.reached, k]))
        assert np.abs(tool - targets[k]).max() <= 1e-9
    np.testing.assert_array_equal(result.q[result.reached, 0, :3], result.q[result.reached, 1, :3])
    ranked = result.ranking(3)
    assert ranked[0] == result.best and len(ranked) == 3


def test_the_ranking_lists_each_relative_placement_once():
    done = []
    result = place(
        _planar(), [0.0, 0.0], radii=[0.3, 0.6, 0.9], bearings=6, headings=2, starts=2,
        progress=lambda d, total: done.append((d, total)),
    )  # fmt: skip
    assert done == [(72, 72)]  # 36 bases × 2 starts, one call
    everything = result.ranking(count=100, distinct=False)
    assert len(everything) == result.reached.sum() == 36
    assert np.all(np.diff(result.score[everything]) <= 0)
    distinct = result.ranking(count=100)
    # the arm's posture depends on the distance and the heading towards the target, not on the bearing:
    # at most 3 distances × 2 headings × 2 elbow branches of the 36 reached bases
    arm = result.q[distinct, 3:]
    assert 6 <= len(distinct) <= 12
    assert all(
        np.max(np.abs(arm[i] - arm[j])) > 1e-6 for i in range(len(arm)) for j in range(i + 1, len(arm))
    )


def test_tiago_s_reached_postures_put_its_tool_on_the_target_by_pinocchio_within_the_joint_limits():
    robot = robots.build("tiago")
    target = np.array([1.0, 0.5, 0.8])
    result = place(robot, target, radii=[0.4, 0.7], bearings=2, headings=4, starts=3)
    assert result.reached.sum() >= 4
    reached = result.q[result.reached]
    assert not robot.limit_violations(reached).any()
    np.testing.assert_allclose(reached[:, :3], result.bases[result.reached], atol=0)
    tool = pinocchio_tool_positions(robot, reached)
    assert np.abs(tool - target).max() <= 1e-6


def test_a_full_pose_is_reached_from_the_base_it_was_taken_at():
    robot = robots.build("tiago").with_task(Pose())
    rng = np.random.default_rng(3)
    lower, upper = np.array(robot.position_limits[3:]).T
    q_star = np.concatenate([[0.0, 0.0, 0.0], rng.uniform(lower, upper)])
    target = np.asarray(K.forward(robot, q_star))
    # the grid's one radius is 0 about the origin: its two headings are θ = π and θ = 0, the base of q*
    result = place(
        robot, target, centre=[0.0, 0.0], radii=[0.0], bearings=1, headings=2, starts=8, iterations=200
    )
    np.testing.assert_allclose(result.bases[1], [0.0, 0.0, 0.0], atol=1e-15)
    assert result.reached[1], result.error
    pose = np.asarray(K.forward(robot, result.q[1]))
    np.testing.assert_allclose(pose[:3], target[:3], atol=1e-6)
    assert np.linalg.norm(np.asarray(robot.task.error(target, pose))) <= 1e-6


def test_tiago_s_reach_covers_every_posture_and_stays_below_its_offsets():
    robot = robots.build("tiago")
    q = sample_configurations(robot, 20_000, seed=7)
    q[:, :3] = 0.0
    tool = np.asarray(K.forward(robot, q, Position("xy")))
    radius = reach_radius(robot)
    assert np.linalg.norm(tool, axis=1).max() <= radius <= 1.5  # the sum of TIAGo's offsets is 2.26 m


def test_the_default_radii_run_from_zero_to_the_arm_s_reach():
    robot = _planar()
    assert reach_radius(robot) == pytest.approx(L1 + L2)
    result = place(robot, [0.2, 0.1], bearings=2, headings=1, starts=1)
    np.testing.assert_allclose(
        np.unique(np.round(np.linalg.norm(result.bases[:, :2] - [0.2, 0.1], axis=1), 12)),
        np.linspace(0.0, L1 + L2, 8),
        atol=1e-12,
    )


@pytest.mark.parametrize(
    ("options", "message"),
    [
        ({"target": [1.0, 2.0, 3.0]}, r"target must be 2 numbers \(x_ee, y_ee\), got shape \(3,\)"),
        ({"target": [np.nan, 0.0]}, "target contains NaN"),
        (
            {"target": [[0.3, 0.1], [0.2, 0.1, 0.0]]},
            r"target must be 2 numbers \(x_ee, y_ee\), or rows of them",
        ),
        ({"target": [[0.3, 0.1], [0.2, np.inf]]}, "target contains NaN or infinite values"),
        ({"target": np.zeros((0, 2))}, r"target: no target given; give 2 numbers \(x_ee, y_ee\)"),
        ({"radii": [0.5, -0.1]}, "radii must be one or more finite distances ≥ 0"),
        ({"radii": []}, "radii must be one or more"),
        ({"bearings": 0}, "bearings must be an integer ≥ 1, got 0"),
        ({"headings": 1.5}, "headings must be an integer ≥ 1"),
        ({"starts": 0}, "starts must be an integer ≥ 1"),
        ({"iterations": 0}, "iterations must be an integer ≥ 1"),
        ({"tolerance": 0.0}, "tolerance must be a number > 0 and ≤ 0.1"),
        ({"measure": "volume"}, "measure must be one of yoshikawa, inverse_condition, eccentricity"),
        ({"level": "wheels"}, "level must be one of arm, system"),
        ({"centre": [0.0]}, r"centre must be 2 numbers \(x, y\)"),
    ],
)
def test_bad_input_is_one_error_naming_the_field(options, message):
    arguments = {"target": [0.3, 0.2], **options}
    with pytest.raises(InputError, match=message):
        place(_planar(), arguments.pop("target"), **arguments)


def test_a_task_without_x_and_y_needs_a_centre():
    robot = robots.build("tiago").with_task(EulerAngles("ZYX"))
    with pytest.raises(InputError, match=r"centre: the task's coordinates \(.*\) do not start with x and y"):
        place(robot, [0.0, 0.0, 0.0])


def test_a_task_singular_at_every_posture_reaches_nothing_and_says_so():
    # a horizontal arm's tool z axis is vertical at every posture: ZYZ Euler angles are in gimbal lock, J is
    # undefined, and every base reports an infinite error instead of failing or ranking NaN
    robot = robots.build("bayle-planar").with_task(EulerAngles("ZYZ"))
    result = place(robot, [0.1, 0.0, 0.2], centre=[0.0, 0.0], radii=[0.5], bearings=2, headings=1, starts=2)
    assert np.all(result.error == np.inf) and not result.reached.any() and result.best is None
    np.testing.assert_array_equal(result.score, 0.0)
    assert len(result.ranking()) == 0


def test_a_planar_map_places_the_base_anywhere_in_the_annulus_with_the_closed_form_score():
    from mobman.studies.maps import reachability_map
    from mobman.studies.placement import place_with_map

    l1, l2 = 0.7, 0.4
    robot = robots.bayle_planar(l1=l1, l2=l2)
    reachability = reachability_map(robot, bounds=[-1.2, 1.2, -1.2, 1.2, 0, 0], step=0.1, starts=4)
    target = np.array([0.3, -0.4, 0.0])
    result = place_with_map(robot, reachability, target, headings=8)
    assert len(result.bases) == 8 * reachability.reached.sum() and result.reached.all()
    # the shoulder (the platform's reference point) lies in the annulus around the target
    distance = np.linalg.norm(result.bases[:, :2] - target[:2], axis=1)
    assert np.all((distance >= l1 - l2 - 1e-9) & (distance <= l1 + l2 + 1e-9))
    tool = np.asarray(K.forward(robot, result.q, Position("xyz")))
    assert np.abs(tool - target).max() <= 1e-6
    np.testing.assert_allclose(result.score, l1 * l2 * np.abs(np.sin(result.q[:, 4])), atol=1e-12)
    assert result.score[result.best] == pytest.approx(l1 * l2, abs=2e-3)


def test_tiago_s_map_places_bases_whose_postures_reach_the_target_by_pinocchio():
    from mobman.studies.maps import reachability_map
    from mobman.studies.placement import place_with_map

    robot = robots.build("tiago")
    reachability = reachability_map(robot, bounds=[0.0, 0.9, -0.9, 0.3, 0.7, 0.9], step=0.1)
    target = np.array([1.0, 0.5, 0.83])  # between two layers of the map: its postures are refined
    result = place_with_map(robot, reachability, target, headings=4)
    assert result.reached.mean() >= 0.9
    reached = result.q[result.reached]
    assert not robot.limit_violations(reached).any()
    np.testing.assert_allclose(reached[:, :3], result.bases[result.reached], atol=0)
    assert np.abs(pinocchio_tool_positions(robot, reached) - target).max() <= 1e-6
    grid = place(robot, target, radii=[0.4, 0.7], bearings=4, headings=4)
    assert result.score[result.best] >= grid.score[grid.best]  # far more candidates, each from a scored cell


def test_a_map_of_another_robot_or_no_cell_at_the_target_s_height():
    from mobman.studies.maps import reachability_map
    from mobman.studies.placement import place_with_map

    reachability = reachability_map(robots.bayle_planar(), step=0.2)
    with pytest.raises(InputError, match="computed for another robot"):
        place_with_map(robots.bayle_planar(l1=0.6), reachability, [0.5, 0.0, 0.0])
    with pytest.raises(InputError, match="target must be 3 numbers"):
        place_with_map(robots.bayle_planar(), reachability, [0.5, 0.0])
    nothing = place_with_map(robots.bayle_planar(), reachability, [0.5, 0.0, 1.0])
    assert len(nothing.bases) == 0 and nothing.best is None
