"""mobman.studies.reaching: the arm's damped least-squares inverse kinematics within the joint limits, checked
against the planar 2R arm's closed form and, on TIAGo, against Pinocchio's forward kinematics."""

from __future__ import annotations

import numpy as np
import pytest

from mobman import kinematics as K
from mobman.model import robots
from mobman.model.tasks import Position
from mobman.redundancy import sample_configurations
from mobman.studies.reaching import best, reach, starting_postures

from tiago_urdf import pinocchio_tool_positions

TASK = Position("xyz")


def _solved(robot, base, targets, starts: int, iterations: int, tolerance: float):
    """reach() from ``starts`` postures, the best start of each target kept (w of J_a)."""
    every = reach(
        robot, np.asarray(base, dtype=float), targets, starting_postures(robot, starts), TASK, iterations
    )
    return best(robot, *every, tolerance, TASK, "yoshikawa", "arm")


def test_the_planar_2r_arm_reaches_its_annulus_in_the_closed_form_elbow_angle():
    l1, l2 = 0.7, 0.4
    robot = robots.bayle_planar(l1=l1, l2=l2)
    d = np.array([0.2, 0.3, 0.3 + 1e-9, 0.5, 0.8, 1.1 - 1e-9, 1.1, 1.2])
    angle = np.linspace(-np.pi, np.pi, d.size)  # directions over the whole turn, ±π included
    targets = np.stack([d * np.cos(angle), d * np.sin(angle), np.zeros_like(d)], axis=-1)
    q, error, _ = _solved(robot, np.zeros(3), targets, 4, 100, 1e-6)
    inside = (d >= l1 - l2) & (d <= l1 + l2)
    assert list(error <= 1e-6) == list(inside)
    # law of cosines: cos q5 = (d² − l1² − l2²) / (2 l1 l2)
    expected = (d**2 - l1**2 - l2**2) / (2 * l1 * l2)
    np.testing.assert_allclose(np.cos(q[inside, 4]), expected[inside], atol=1e-6)
    # outside it the error is at least the distance to the annulus
    gap = np.maximum(l1 - l2 - d, d - l1 - l2)
    assert np.all(error[~inside] >= gap[~inside] - 1e-12)


def test_tiago_reaches_the_tool_positions_of_its_own_postures_by_pinocchio_within_its_limits():
    robot = robots.build("tiago")
    q = sample_configurations(robot, 200, seed=11)
    q[:, :3] = 0.0
    targets = np.asarray(K.forward(robot, q, TASK))
    found, error, _ = _solved(robot, np.zeros(3), targets, 8, 60, 1e-9)
    reached = error <= 1e-9
    assert reached.mean() >= 0.99  # a local method: a few targets need more starts
    assert not robot.limit_violations(found).any()
    np.testing.assert_allclose(pinocchio_tool_positions(robot, found[reached]), targets[reached], atol=1e-9)


def test_joints_held_at_their_limits_let_the_others_take_the_step():
    # projected onto the limits alone, a step towards a limit is cut short at every iteration and 4 starts
    # of 60 steps reached 59 % of these targets; with the joints at a limit held, 99 %
    robot = robots.build("tiago")
    q = sample_configurations(robot, 300, seed=5)
    q[:, :3] = 0.0
    targets = np.asarray(K.forward(robot, q, TASK))
    _, error = reach(robot, np.zeros(3), targets, starting_postures(robot, 4), TASK, 60)
    assert error.shape == (300, 4)
    assert np.mean(error.min(axis=1) <= 1e-4) >= 0.95


@pytest.mark.parametrize("base", [(0.0, 0.0, np.pi / 2), (1.0, -2.0, np.pi), (-0.5, 0.3, -np.pi / 2)])
def test_a_target_moves_with_the_platform(base):
    robot = robots.build("panda-differential")
    q = sample_configurations(robot, 20, seed=3)
    q[:, :3] = base
    targets = np.asarray(K.forward(robot, q, TASK))
    found, error, _ = _solved(robot, base, targets, 8, 60, 1e-9)
    assert error.max() <= 1e-9
    np.testing.assert_array_equal(found[:, :3], np.broadcast_to(base, (20, 3)))


def test_of_the_starts_that_reach_a_target_the_one_of_highest_manipulability_is_kept():
    robot = robots.build("tiago")
    q = sample_configurations(robot, 30, seed=8)
    q[:, :3] = 0.0
    targets = np.asarray(K.forward(robot, q, TASK))
    every, errors = reach(robot, np.zeros(3), targets, starting_postures(robot, 8), TASK, 60)
    found, error, score = best(robot, every, errors, 1e-9, TASK, "yoshikawa", "arm")
    j = np.asarray(K.jacobian(robot, every, TASK))[..., 3:]  # the arm's columns, every start
    w = np.sqrt(np.linalg.det(j @ np.swapaxes(j, -1, -2)))
    reached = errors <= 1e-9
    assert (reached.sum(axis=1) >= 2).sum() >= 20  # most targets are reached from several postures
    np.testing.assert_allclose(score, np.where(reached, w, -np.inf).max(axis=1), rtol=1e-10)
    assert np.all(w[reached].max() >= score)
    # where no start reaches the target, the closest start is kept and its score is NaN
    far, far_error, far_score = _solved(robot, np.zeros(3), [[5.0, 0, 1]], 3, 10, 1e-9)
    assert np.isnan(far_score).all() and far_error[0] > 3.0 and far.shape == (1, robot.n_q)


def test_a_problem_run_in_calls_gives_the_rows_of_one_call_and_reports_its_progress(monkeypatch):
    from mobman.studies import reaching

    robot = robots.bayle_planar()
    angle = np.linspace(-np.pi, np.pi, 9)
    targets = np.stack([0.9 * np.cos(angle), 0.9 * np.sin(angle), np.zeros_like(angle)], axis=-1)
    bases = np.array([[0.0, 0.0, 0.0], [0.3, -0.2, np.pi / 2]])[:, None]  # (2, 1, 3) against (9, 3)
    starts = starting_postures(robot, 3)
    whole = reach(robot, bases, targets, starts, TASK, 40)
    padded = reach(robot, bases, targets, starts, TASK, 40, bucket=10)  # 54 rows as 60
    monkeypatch.setattr(reaching, "CHUNK", 16)  # 54 rows: calls of 16, the last padded from 6
    done = []
    chunked = reach(robot, bases, targets, starts, TASK, 40, lambda d, total: done.append((d, total)))
    assert done == [(16, 54), (32, 54), (48, 54), (54, 54)]
    assert whole[0].shape == (2, 9, 3, robot.n_q) and whole[1].shape == (2, 9, 3)
    for other in (padded, chunked):  # the same rows of other batch sizes: equal to round-off
        np.testing.assert_allclose(other[0], whole[0], rtol=0, atol=1e-12)
        np.testing.assert_allclose(other[1], whole[1], rtol=0, atol=1e-12)
