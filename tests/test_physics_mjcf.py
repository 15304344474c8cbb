"""The robot as a MuJoCo model (mobman.physics.mjcf, mobman.physics.state, ``mobman export-mjcf``).

Expected values come from outside the exporter: TIAGo's total mass from Pinocchio on the URDF file, its joint
and effort limits from the URDF text (``tiago_urdf``), Yamamoto & Yun's masses from their Table 1–2 numbers,
the rolling speed r ω of a wheel; the behaviours (standing still, rolling) are measured on MuJoCo's
simulation.
"""

from __future__ import annotations

import sys

import mujoco
import numpy as np
import pytest

from mobman.dynamics import DynamicModel, yamamoto_model
from mobman.errors import InputError, ModelError
from mobman.io.real_robots import REAL_ROBOTS, urdf_model
from mobman.model import robots
from mobman.model.platforms import Omnidirectional
from mobman.model.platforms.fixed import Fixed
from mobman.model.platforms.skid_steer import SkidSteer
from mobman.model.robot import MobileManipulator
from mobman.model.scene import Obstacle, Scene
from mobman.physics import measured_q, mjcf_text, set_configuration, to_mjspec
from mobman.physics import mjcf as physics_mjcf

from tiago_urdf import joint_limits

REST_DRIFT = 1e-3
"""Largest platform displacement (m) allowed over 10 s at rest."""


def _on_platform(platform) -> MobileManipulator:
    return MobileManipulator(platform, (robots.planar_arm((0.4, 0.3)),), name=f"arm-on-{platform.kind}")


@pytest.fixture(scope="module")
def tiago():
    model = urdf_model("tiago")
    dynamics = DynamicModel.from_urdf(model)
    return dynamics, model.torque_limits(), to_mjspec(dynamics, torque_limits=model.torque_limits())


def _simulate(model, data, seconds: float) -> None:
    for _ in range(round(seconds / model.opt.timestep)):
        mujoco.mj_step(model, data)


def _frame_velocity(model, data, body) -> np.ndarray:
    """The linear velocity of ``body`` in its own frame (forward, lateral, vertical for the platform)."""
    velocity = np.zeros(6)
    mujoco.mj_objectVelocity(model, data, mujoco.mjtObj.mjOBJ_BODY, body, velocity, 1)  # local frame
    return velocity[3:]


# --- the model loads, from the spec and from its MJCF text -------------------------------------------------


@pytest.mark.parametrize(
    "robot",
    [
        robots.build("bayle-rrp"),  # differential, stand-in inertials
        robots.build("tchon-car-rtr"),  # car
        _on_platform(SkidSteer(wheel_speed_max=10.0)),
        _on_platform(Omnidirectional((1.0, 1.0, 2.0))),
        _on_platform(Fixed()),
    ],
    ids=lambda r: r.platform.kind,
)
def test_every_platform_kind_loads_from_its_mjcf_text(robot):
    spec = to_mjspec(robot)
    compiled = spec.compile()
    loaded = mujoco.MjModel.from_xml_string(mjcf_text(spec))
    for field in ("body_mass", "body_inertia", "body_pos", "body_quat", "jnt_range", "actuator_ctrlrange"):
        assert np.array_equal(getattr(loaded, field), getattr(compiled, field)), field
    names = [loaded.actuator(i).name for i in range(loaded.nu)]
    assert names[-robot.n_eta + robot.platform.n_eta :] == list(robot.coordinate_names[robot.n_platform :])
    data = mujoco.MjData(loaded)
    set_configuration(loaded, data, robot, np.zeros(robot.n_q))
    _simulate(loaded, data, 0.5)
    assert np.all(np.isfinite(data.qpos))


def test_tiago_has_the_urdf_masses(tiago):
    """Total mass equal to Pinocchio's sum over the URDF's links (free-flyer root: the root link's mass
    counts) to 1e-9, in the spec's model and in the model read back from the MJCF text."""
    import pinocchio as pin

    full = pin.buildModelFromUrdf(str(REAL_ROBOTS["tiago"].path()), pin.JointModelFreeFlyer())
    expected = pin.computeTotalMass(full)
    _, _, spec = tiago
    for model in (spec.compile(), mujoco.MjModel.from_xml_string(mjcf_text(spec))):
        assert model.body_subtreemass[model.body("platform").id] == pytest.approx(expected, rel=1e-9)


def test_yamamoto_robot_has_the_papers_masses():
    """Table 2: m_c = 94 kg, m_w = 5 kg per wheel; Table 1: links of 10, 6 and 2 kg in each of the two
    arms."""
    model = to_mjspec(yamamoto_model()).compile()
    assert model.body_subtreemass[model.body("platform").id] == pytest.approx(94 + 2 * 5 + 2 * 18, rel=1e-12)
    assert model.body("wheel_right").mass[0] == 5.0
    assert [model.body(f"arm2.theta{i}").mass[0] for i in (1, 2, 3)] == [10.0, 6.0, 2.0]


def test_tiago_joint_and_actuator_limits_are_the_urdfs(tiago):
    dynamics, limits, spec = tiago
    model = spec.compile()
    robot = dynamics.robot
    joints = list(robot.coordinate_names[robot.n_platform :])
    urdf = joint_limits(joints, ("lower", "upper", "velocity", "effort"))
    ranges = np.array([model.joint(name).range for name in joints])
    assert np.array_equal(ranges, urdf[:, :2])
    for k, name in enumerate(joints):
        actuator = model.actuator(name)
        assert np.array_equal(actuator.ctrlrange, [-urdf[k, 2], urdf[k, 2]])
        assert np.array_equal(actuator.forcerange, [-urdf[k, 3], urdf[k, 3]])
        assert np.array_equal(actuator.actrange, urdf[k, :2])  # the integrated set point stays in the limits
    wheels = joint_limits(["wheel_right_joint", "wheel_left_joint"], ("velocity", "effort"))
    for k, name in enumerate(("wheel_right", "wheel_left")):
        assert np.array_equal(model.actuator(name).ctrlrange, [-wheels[k, 0], wheels[k, 0]])
        assert np.array_equal(model.actuator(name).forcerange, [-wheels[k, 1], wheels[k, 1]])


# --- at rest it stands still; a wheel command rolls it ------------------------------------------------------


@pytest.mark.parametrize("which", ["tiago", "yamamoto"])
def test_at_rest_the_robot_stands_still_on_its_wheels(which, tiago):
    """10 s simulated at a configuration inside the joint limits with every command 0: the platform moves
    less than REST_DRIFT and stays on the floor (its frame within 1 mm of the floor plane)."""
    if which == "tiago":
        dynamics, _, spec = tiago
    else:
        dynamics = yamamoto_model()
        spec = to_mjspec(dynamics)
    robot = dynamics.robot
    rng = np.random.default_rng(3)
    lower, upper = np.array(robot.position_limits).T
    bounded = np.isfinite(lower)
    q0 = rng.uniform(-np.pi, np.pi, robot.n_q)
    q0[bounded] = rng.uniform(lower[bounded], upper[bounded])
    q0[:3] = [0.4, -0.2, np.pi / 2]
    model = spec.compile()
    data = mujoco.MjData(model)
    set_configuration(model, data, robot, q0)
    _simulate(model, data, 10.0)
    q = measured_q(model, data, robot)
    assert np.linalg.norm(q[:2] - q0[:2]) < REST_DRIFT
    assert abs(q[2] - q0[2]) < REST_DRIFT
    assert abs(data.xpos[model.body("platform").id][2]) < 1e-3


@pytest.mark.parametrize("which", ["tiago", "yamamoto", "skid_steer"])
def test_a_slow_wheel_command_rolls_the_platform_at_r_omega(which, tiago):
    """Both wheels (sides) at ω: after the servo settles the platform moves forward at r ω (to 0.3 %: the
    wheel sphere sinks into the soft contact by about 0.1 mm, shortening the rolling radius) and sideways at
    less than 1e-5 m/s."""
    if which == "tiago":
        dynamics, _, spec = tiago
        robot = dynamics.robot
    elif which == "yamamoto":
        robot = yamamoto_model().robot
        spec = to_mjspec(yamamoto_model())
    else:
        robot = _on_platform(SkidSteer(wheel_speed_max=10.0))
        spec = to_mjspec(robot)
    model = spec.compile()
    data = mujoco.MjData(model)
    q0 = np.zeros(robot.n_q)
    q0[2] = -np.pi / 2
    set_configuration(model, data, robot, q0)
    omega = 0.5
    for name in robot.platform.actuator_names:
        data.ctrl[model.actuator(name).id] = omega
    _simulate(model, data, 1.0)
    velocities = []
    for _ in range(10):
        _simulate(model, data, 0.1)
        velocities.append(_frame_velocity(model, data, model.body("platform").id))
    forward, lateral, _ = np.median(velocities, axis=0)
    assert forward == pytest.approx(robot.platform.wheel_radius * omega, rel=3e-3)
    assert abs(lateral) < 1e-5


def test_car_rolls_forward_and_steers():
    """The car's rear wheels at ω roll it at r ω; the steering servo's rate u2 turns both front wheels."""
    robot = robots.build("tchon-car-rtr")
    model = to_mjspec(robot).compile()
    data = mujoco.MjData(model)
    set_configuration(model, data, robot, np.zeros(robot.n_q))
    radius = robot.platform.wheels()[0].radius
    data.ctrl[model.actuator("wheel_rear_right").id] = data.ctrl[model.actuator("wheel_rear_left").id] = 0.5
    _simulate(model, data, 2.0)
    assert _frame_velocity(model, data, model.body("platform").id)[0] == pytest.approx(0.5 * radius, rel=3e-3)
    data.ctrl[model.actuator("steering").id] = 0.2
    _simulate(model, data, 0.5)
    phi = measured_q(model, data, robot)[3]
    assert phi == pytest.approx(0.1, abs=0.01)
    assert data.qpos[model.jnt_qposadr[model.joint("steering_left").id]] == pytest.approx(phi, abs=1e-3)


def test_omnidirectional_platform_follows_its_velocity_commands():
    robot = _on_platform(Omnidirectional((1.0, 1.0, 2.0)))
    model = to_mjspec(robot).compile()
    data = mujoco.MjData(model)
    set_configuration(model, data, robot, np.zeros(robot.n_q))
    data.ctrl[:3] = [0.2, -0.1, 0.3]
    _simulate(model, data, 1.0)
    before = measured_q(model, data, robot)[:3]
    _simulate(model, data, 1.0)
    assert measured_q(model, data, robot)[:3] - before == pytest.approx([0.2, -0.1, 0.3], abs=1e-3)


def test_a_wall_of_the_scene_stops_the_robot():
    """Driven at 1 m/s for 3 s toward a wall 1.4 m ahead, the robot stops against it (its arm's tool link
    touches the wall's near face at x = 1.4 m); without the scene it passes far beyond."""
    robot = robots.build("bayle-planar")
    wall = Obstacle("wall", "box", (0.2, 2.0, 1.0), (1.5, 0.0, 0.5))
    ends = []
    for scene in (None, Scene((wall,))):
        model = to_mjspec(robot, scene).compile()
        data = mujoco.MjData(model)
        set_configuration(model, data, robot, [0.0, 0.0, 0.0, -0.785, 1.57])
        data.ctrl[:2] = 1.0 / robot.platform.wheel_radius
        _simulate(model, data, 3.0)
        ends.append(measured_q(model, data, robot)[0])
        touching = {model.geom(g).name for c in data.contact[: data.ncon] for g in c.geom}
    assert ends[0] > 2.5
    assert ends[1] < 1.4 and "wall" in touching
    with pytest.raises(ModelError, match="physics floor is z = 0"):
        to_mjspec(robot, Scene((wall,), floor=0.2))


# --- what cannot be exported -------------------------------------------------------------------------------


def test_bad_input_is_one_clear_error(monkeypatch):
    robot = robots.build("bayle-planar")
    with pytest.raises(ModelError, match="joint coupling"):
        to_mjspec(robots.build("manus-platform"))
    with pytest.raises(InputError, match="friction"):
        to_mjspec(robot, friction=0.0)
    with pytest.raises(InputError, match="timestep"):
        to_mjspec(robot, timestep=-1e-3)
    with pytest.raises(InputError, match="torque_limits: 4 values"):
        to_mjspec(robot, torque_limits=[1.0, 2.0])
    monkeypatch.setattr(physics_mjcf, "KINDS", ("car",))
    with pytest.raises(ModelError, match="platform kind 'differential': no MuJoCo form"):
        to_mjspec(robot)


# --- the command -------------------------------------------------------------------------------------------


def test_export_mjcf_writes_a_file_mujoco_loads(cli_json, tmp_path):
    out = tmp_path / "yamamoto.xml"
    scene = tmp_path / "scene.toml"
    scene.write_text(
        '[[obstacle]]\nname = "post"\nshape = "cylinder"\nsize = [0.1, 1.0]\nposition = [2, 0, 0.5]\n'
    )
    report = cli_json(["export-mjcf", "yamamoto-dual-arm", "--scene", str(scene), "--out", str(out)])
    model = mujoco.MjModel.from_xml_path(str(out))
    assert report["obstacles"] == ["post"]
    assert np.array_equal(model.geom("post").size, [0.1, 0.5, 0.0]) and model.geom("post").pos[0] == 2.0
    assert model.body_subtreemass[model.body("platform").id] == pytest.approx(140.0, rel=1e-12)
    assert report["mass"] == pytest.approx(140.0, rel=1e-12)
    assert report["inertials"] == "the robot's dynamic model"
    assert report["actuators"][:2] == ["wheel_right", "wheel_left"]
    assert sorted(tmp_path.iterdir()) == sorted([out, scene])  # no temporary file left


def test_export_mjcf_errors_are_one_line(cli_run, tmp_path, monkeypatch):
    code, _, err = cli_run(["export-mjcf", "manus-platform", "--out", str(tmp_path / "m.xml")])
    assert code == 2 and err.startswith("error:") and "coupling" in err and len(err.strip().splitlines()) == 1
    monkeypatch.setitem(sys.modules, "mujoco", None)  # the physics extra not installed
    code, _, err = cli_run(["export-mjcf", "bayle-planar", "--out", str(tmp_path / "b.xml")])
    assert code == 2 and 'pip install -e ".[physics]"' in err
    assert not list(tmp_path.iterdir())
