"""A law closed on MuJoCo (mobman.physics.loop): Bayle's law on the paper's planar robot ends where the
kinematic run of the same law ends, with the wheels rolling without measurable slip; a fast run on a slippery
floor slips (so the slip figure can fail)."""

from __future__ import annotations

import numpy as np
import pytest

from mobman.control.laws import BaylePseudoInverse
from mobman.control.references import Line
from mobman.control.simulation import simulate
from mobman.errors import InputError
from mobman.model import robots
from mobman.model.scene import Obstacle, Scene
from mobman.model.tasks import Position
from mobman.physics.loop import run_on_physics
from mobman.physics.mjcf import dynamic_model

ROBOT = robots.build("bayle-planar")
TASK = Position("xy")
Q0 = np.array([0.0, 0.0, 0.0, -0.785, 1.57])
LAW = BaylePseudoInverse(W=2.0)
SLOW = Line([0.707, 0.0], [0.807, 0.05], 2.0)


@pytest.fixture(scope="module")
def slow_run():
    return run_on_physics(ROBOT, LAW, SLOW, Q0, 2.5, 0.01, task=TASK)


def test_slow_motion_ends_at_the_kinematic_runs_end_point(slow_run):
    """The same law at the same control rate (zero-order hold, mobman's exact kinematic flow) and the MuJoCo
    run end within 1 cm of each other in ξ and in the platform position; the lateral slip's median is below
    1 mm/s."""
    assert slow_run.stopped is None
    kinematic = simulate(ROBOT, TASK, LAW, SLOW, Q0, 2.5, 0.01, integrator="hold")
    assert slow_run.q.shape == np.asarray(kinematic.q).shape
    end_physics = np.asarray(TASK.value(ROBOT, slow_run.q[-1], ROBOT.frames(slow_run.q[-1])))
    end_kinematic = np.asarray(TASK.value(ROBOT, kinematic.q[-1], ROBOT.frames(kinematic.q[-1])))
    assert np.linalg.norm(end_physics - end_kinematic) < 0.01
    assert np.linalg.norm(slow_run.q[-1, :2] - np.asarray(kinematic.q[-1, :2])) < 0.01
    assert np.linalg.norm(end_physics - SLOW.end) < 0.01  # and the reference's end was reached
    assert np.median(np.abs(slow_run.slip)) < 1e-3


def test_a_fast_run_on_a_slippery_floor_slips(slow_run):
    fast = run_on_physics(
        ROBOT, LAW, Line([0.707, 0.0], [0.707, 1.0], 1.0), Q0, 1.0, 0.01, task=TASK, friction=0.05
    )
    assert np.median(np.abs(fast.slip)) > 1e-3
    assert np.median(np.abs(fast.slip)) > 10 * np.median(np.abs(slow_run.slip))


def test_bad_rates_are_refused():
    with pytest.raises(InputError, match="whole multiple of the physics step"):
        run_on_physics(ROBOT, LAW, SLOW, Q0, 1.0, 0.0015, task=TASK)
    with pytest.raises(InputError, match="control_dt must be"):
        run_on_physics(ROBOT, LAW, SLOW, Q0, 1.0, -0.01, task=TASK)


def test_feedforward_needs_inertials_and_joint_actuators():
    with pytest.raises(InputError, match="feedforward: needs the robot's inertials"):
        run_on_physics(ROBOT, LAW, SLOW, Q0, 1.0, 0.01, task=TASK, feedforward=True)
    car = dynamic_model(robots.build("tchon-car-rtr"))  # stand-in inertials; its wheels are not its actuators
    with pytest.raises(InputError, match="the car platform's .* are not"):
        run_on_physics(car, LAW, SLOW, np.zeros(car.robot.n_q), 1.0, 0.01, task=TASK, feedforward=True)


def test_a_scene_s_wall_stops_the_robot_on_physics():
    """The tool driven 1 m ahead, through a wall 0.5 m ahead of it: the wall is in MuJoCo's model (the platform
    and the links touch it), so the run stops at it; without the scene the tool reaches the end."""
    wall = Obstacle("wall", "box", (0.1, 2.0, 1.0), (1.25, 0.0, 0.5))
    ahead = Line([0.707, 0.0], [1.707, 0.0], 2.0)
    blocked = run_on_physics(ROBOT, LAW, ahead, Q0, 2.5, 0.01, task=TASK, scene=Scene((wall,)))
    free = run_on_physics(ROBOT, LAW, ahead, Q0, 2.5, 0.01, task=TASK)
    tool = [np.asarray(TASK.value(ROBOT, run.q[-1], ROBOT.frames(run.q[-1])))[0] for run in (blocked, free)]
    assert tool[0] < 1.2 and tool[1] > 1.65
