"""mobman.model.robot: a robot of two arms on offset mounts, an arm mounted anew (with_mount), models hashable
and equal by value, and the model's construction errors (robots, platforms, inertials, tasks, arms)."""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt
import pytest
from scipy.spatial.transform import Rotation

import mobman
from mobman import kinematics as K
from mobman.io.urdf import load_urdf, write_urdf
from mobman.model import (
    Arm,
    DifferentialDrive,
    EulerAngles,
    MobileManipulator,
    Mount,
    Position,
    robots,
    stack,
)
from mobman.redundancy import sample_configurations


def test_two_arms_and_mount_offsets():
    arm = robots.planar_arm((1.0,))
    robot = MobileManipulator(
        DifferentialDrive(),
        (arm, arm),
        (Mount(0.5), Mount(0.0, 0.3, 0.2, yaw=math.pi / 2)),
        task=stack(Position(arm=0), Position(arm=1)),
    )
    q = np.array([1.0, 2.0, 0.0, 0.0, 0.0])
    np.testing.assert_allclose(K.forward(robot, q), [2.5, 2.0, 0.0, 1.0, 3.3, 0.2], atol=1e-14)
    assert robot.coordinate_names == ("x", "y", "theta", "arm1.q1", "arm2.q1")  # two copies: prefixed


def rot_z(angle: npt.ArrayLike) -> np.ndarray:
    """Rotations about the vertical, shape (..., 3, 3)."""
    c, s = np.cos(angle), np.sin(angle)
    zero, one = np.zeros_like(c), np.ones_like(c)
    return np.stack(
        [np.stack([c, -s, zero], -1), np.stack([s, c, zero], -1), np.stack([zero, zero, one], -1)], -2
    )


@pytest.mark.parametrize(
    "mount",
    [Mount(0.1, -0.05, 0.5, yaw=math.pi / 2), Mount(0.2, 0.1, 0.6, yaw=-0.4, roll=0.3, pitch=-math.pi / 2)],
)
def test_with_mount_moves_the_arm_rigidly_with_the_platform(mount, tmp_path):
    # the tool at P + R(θ)(m + R_m a(q_a)), a(q_a) read off the robot's own mount (0, 0, 0.4) unturned, and
    # R_m = R_z(yaw) R_y(pitch) R_x(roll) by SciPy (extrinsic x, y, z: URDF's rpy)
    robot = robots.build("panda-differential")
    moved = robot.with_mount(mount)
    q = sample_configurations(robot, 64, seed=3)
    q[:4, 2] = [math.pi / 2, -math.pi / 2, math.pi, 0.0]
    platform = np.c_[q[:, :2], np.zeros(len(q))]
    turn = rot_z(q[:, 2])
    tool = np.asarray(K.forward(robot, q, Position()))
    a = np.einsum("nji,nj->ni", turn, tool - platform) - [0.0, 0.0, 0.4]
    r_m = Rotation.from_euler("xyz", [mount.roll, mount.pitch, mount.yaw]).as_matrix()
    expected = platform + np.einsum("nij,nj->ni", turn, [mount.x, mount.y, mount.z] + a @ r_m.T)
    np.testing.assert_allclose(K.forward(moved, q, Position()), expected, atol=1e-13)
    # written as URDF (the mount in the first joint's origin xyz and rpy) and read back by yourdfpy
    read = load_urdf(write_urdf(moved, tmp_path / "moved.urdf"), tip="tool_link")
    np.testing.assert_allclose(K.forward(read, q, Position()), expected, atol=1e-12)
    assert moved.mounts == (mount,) and moved != robot and robot.mounts == (Mount(z=0.4),)
    with pytest.raises(mobman.InputError, match="arm must be in 0..0"):
        robot.with_mount(mount, arm=1)
    with pytest.raises(mobman.InputError, match="mount must be a Mount, got tuple"):
        robot.with_mount((0.1, 0.0, 0.0))  # type: ignore[arg-type]


def test_design_builds_the_robot_and_mounts_the_arm_it_names():
    designed = robots.design("bayle_planar", {"l2": 0.7, "mount.z": 0.1})
    mounted = robots.build("bayle-planar", l2=0.7).with_mount(Mount(z=0.1))
    assert designed.mounts == mounted.mounts and designed.arms == mounted.arms
    assert designed.parameters == (("l1", 0.5), ("l2", 0.7), ("mount.z", 0.1))  # a saved motion rebuilds it
    panda = robots.build("panda-differential")
    assert robots.design(panda) is panda
    assert robots.design(panda, {"mount.x": 0.1}).mounts == (Mount(x=0.1, z=0.4),)  # its own z kept
    dual = robots.design("yamamoto-dual-arm", {"mount.yaw": 1.0}, arm=1)
    assert dual.mounts[0] == robots.build("yamamoto-dual-arm").mounts[0] and dual.mounts[1].yaw == 1.0
    assert dual.parameters == robots.build("yamamoto-dual-arm").parameters  # only the first arm's are kept


def test_models_are_hashable_and_equal_by_value():
    assert robots.bayle_planar() == robots.bayle_planar()
    assert hash(robots.bayle_planar()) == hash(robots.bayle_planar())
    assert robots.bayle_planar(l1=0.6) != robots.bayle_planar()


@pytest.mark.parametrize(
    "make, match",
    [
        (lambda: robots.bayle_planar(l1=-1.0), "l1 \\(a length\\) must be a finite number > 0"),
        (lambda: robots.build("nonexistent"), "unknown robot"),
        (lambda: robots.build("bayle-planar", l9=1.0), "unknown parameter 'l9'"),
        (lambda: DifferentialDrive(wheel_radius=0.0), "wheel_radius must be"),
        (lambda: mobman.LinkInertial(-1.0), "mass must be"),
        (lambda: mobman.LinkInertial(1.0, inertia=(1, 2, 0, 0, 1, 0, 0, 0, 1)), "symmetric"),
        (lambda: mobman.LinkInertial(1.0, inertia=(-1.0, 1.0, 1.0)), "positive semi-definite"),
        (lambda: Position("xw"), "components"),
        (lambda: EulerAngles("ABC"), "not supported"),
        (lambda: Arm.from_dh([(0, 0, 1)]), "4 numbers"),
        (lambda: robots.design("nope"), "unknown robot 'nope'"),
        (lambda: robots.design("bayle-planar", {"mount.q": 1.0}), "'mount.q'; allowed: l1, l2, mount.x"),
        (lambda: robots.design(robots.bayle_planar(), {"l1": 1.0}), "'l1'; allowed: mount.x, mount.y"),
        (lambda: robots.design("bayle-planar", {"mount.z": math.nan}), "Mount: z must be finite"),
    ],
)
def test_bad_model_input_raises_model_error(make, match):
    with pytest.raises(mobman.ModelError, match=match):
        make()


@pytest.mark.parametrize("name", sorted(robots.PAPER_ROBOTS) + ["panda-differential"])
def test_q_dot_is_S_times_eta_over_the_whole_range(name):
    """robot.q_dot(q, η) = S(q) η without forming S, for every kind of platform, θ at ±π/2 and π too."""
    robot = robots.build(name)
    rng = np.random.default_rng(3)
    q = rng.uniform(-math.pi, math.pi, (8, robot.n_q))
    q[:4, 2] = (-math.pi / 2, math.pi / 2, math.pi, -math.pi)
    eta = rng.normal(size=(8, robot.n_eta))
    s = np.asarray(K.S(robot, q))
    for qi, ei, si in zip(q, eta, s):
        np.testing.assert_allclose(np.asarray(robot.q_dot(qi, ei)), si @ ei, rtol=0, atol=1e-14)


def test_a_robot_of_more_joints_than_the_budget_is_refused_naming_the_limit():
    from mobman.model.robot import MAX_JOINTS

    arm = robots.planar_arm((0.1,) * (MAX_JOINTS + 1))
    with pytest.raises(mobman.ModelError, match=f"{MAX_JOINTS + 1} arm joints, more than the {MAX_JOINTS}"):
        MobileManipulator(DifferentialDrive(), (arm,))
    assert (
        MobileManipulator(DifferentialDrive(), (robots.planar_arm((0.1,) * MAX_JOINTS),)).n_q
        == MAX_JOINTS + 3
    )


def test_a_500_joint_urdf_is_refused_in_one_line_before_any_work(tmp_path, capsys):
    from cli_runs import run_cli

    joints = "".join(
        f'<link name="l{i + 1}"/><joint name="j{i}" type="revolute"><parent link="l{i}"/><child link="l{i + 1}"/>'
        f'<origin xyz="0.01 0 0"/><axis xyz="0 0 1"/><limit lower="-1" upper="1" velocity="1" effort="1"/></joint>'
        for i in range(500)
    )
    path = tmp_path / "long.urdf"
    path.write_text(f'<?xml version="1.0"?><robot name="long"><link name="l0"/>{joints}</robot>')
    code, _, err = run_cli(
        ["analyze", str(path), "--tip", "l500", "--base", "l0", "--platform", "omnidirectional"], capsys
    )
    assert code == 2 and err.count("\n") == 1 and "500 arm joints, more than the 64" in err
