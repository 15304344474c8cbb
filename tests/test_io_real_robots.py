"""The built-in real robots of mobman.io.real_robots (TIAGo, TIAGo dual, Stretch): the registry, each robot
read from its maker's URDF with the documented tips, coordinates and platform, the TIAGo wheel geometry,
the cache, and the one-line error with the install line when the package that ships a URDF is missing."""

from __future__ import annotations

import dataclasses
import subprocess
import sys
from importlib import metadata

import pytest

from mobman.errors import ModelError
from mobman.io import real_robots
from mobman.io.real_robots import EXTRA, FACTORIES, REAL_ROBOTS, RealRobot, urdf_model
from mobman.model import robots

NAMES = ("tiago", "tiago-dual", "stretch")
EXPECTED = {  # name: (tips, n_q)
    "tiago": (("arm_tool_link",), 3 + 8),
    "tiago-dual": (("arm_right_tool_link", "arm_left_tool_link"), 3 + 7 + 7),
    "stretch": (("link_grasp_center",), 3 + 8),
}


@pytest.fixture(scope="module")
def models():
    return {name: urdf_model(name) for name in NAMES}


def test_the_registry_lists_the_three_robots():
    assert tuple(REAL_ROBOTS) == NAMES
    assert tuple(FACTORIES) == NAMES
    assert FACTORIES == {
        "tiago": real_robots.tiago,
        "tiago-dual": real_robots.tiago_dual,
        "stretch": real_robots.stretch,
    }


@pytest.mark.parametrize("name", NAMES)
def test_each_robot_is_registered_as_a_built_in_robot(name):
    assert robots.ROBOTS[name] is FACTORIES[name]


def test_the_install_line():
    assert EXTRA == "pip install 'mobman[robots]'"


@pytest.mark.parametrize(
    ("name", "distribution"),
    [
        ("tiago", "example-robot-data"),
        ("tiago-dual", "example-robot-data"),
        ("stretch", "hello-robot-stretch-urdf"),
    ],
)
def test_each_urdf_is_a_file_of_its_installed_distribution(name, distribution):
    spec = REAL_ROBOTS[name]
    assert spec.distribution == distribution and spec.available()
    path = spec.path()
    assert path.is_file() and path.suffix == ".urdf"
    assert path.as_posix().endswith(spec.file)


@pytest.mark.parametrize("name", NAMES)
def test_each_robot_has_its_tips_coordinates_and_differential_base(models, name):
    robot = models[name].robot
    tips, n_q = EXPECTED[name]
    assert REAL_ROBOTS[name].tips == tips
    assert tuple(arm.name for arm in robot.arms) == tips
    assert robot.n_q == n_q and robot.name == name
    assert robot.platform.kind == "differential"
    assert robot.coordinate_names[:3] == ("x", "y", "theta")


def test_tiago_wheels_torso_and_arm(models):
    robot = models["tiago"].robot
    assert robot.platform.wheel_radius == pytest.approx(0.0985, abs=1e-12)
    assert 2 * robot.platform.half_track == pytest.approx(0.4044, abs=1e-12)
    joints = robot.arms[0].joints
    assert [j.name for j in joints] == ["torso_lift_joint"] + [f"arm_{i}_joint" for i in range(1, 8)]
    assert joints[0].kind == "prismatic" and all(j.kind == "revolute" for j in joints[1:])


def test_tiago_dual_locks_the_torso_at_0_15_m(models):
    assert real_robots.TIAGO_DUAL_TORSO == 0.15
    assert REAL_ROBOTS["tiago-dual"].locked == (("torso_lift_joint", 0.15),)
    model = models["tiago-dual"]
    assert model.summary.locked == (("torso_lift_joint", 0.15),)
    right, left = model.robot.arms
    assert [j.name for j in right.joints] == [f"arm_right_{i}_joint" for i in range(1, 8)]
    assert [j.name for j in left.joints] == [f"arm_left_{i}_joint" for i in range(1, 8)]
    # the URDF's joint names are unique across the arms: q is named by them, with no arm prefix
    assert model.robot.coordinate_names[3:] == tuple(j.name for j in right.joints + left.joints)
    assert model.robot.platform.wheel_radius == pytest.approx(0.0985, abs=1e-12)


def test_stretch_chain_and_unlimited_platform(models):
    robot = models["stretch"].robot
    names = [j.name for j in robot.arms[0].joints]
    assert names == [
        "joint_lift",
        "joint_arm_l3",
        "joint_arm_l2",
        "joint_arm_l1",
        "joint_arm_l0",
        "joint_wrist_yaw",
        "joint_wrist_pitch",
        "joint_wrist_roll",
    ]
    assert robot.platform.velocity_limits is None  # the URDF gives no wheel speed limit
    assert 0.04 < robot.platform.wheel_radius < 0.06  # from the wheel's collision mesh (a 4-inch wheel)


@pytest.mark.parametrize("name", NAMES)
def test_the_factories_return_the_cached_robot(models, name):
    factory = FACTORIES[name]
    assert factory() is models[name].robot
    assert factory() is factory()
    assert robots.build(name) is models[name].robot
    assert urdf_model(name) is models[name]


def test_a_real_robot_description_is_immutable():
    with pytest.raises(dataclasses.FrozenInstanceError):
        REAL_ROBOTS["tiago"].base = "base_link"


def test_an_unknown_real_robot_is_named_with_the_built_in_ones():
    with pytest.raises(ModelError) as info:
        urdf_model("pr2")
    assert str(info.value) == "unknown real robot 'pr2'; built in: tiago, tiago-dual, stretch"


def test_a_missing_package_gives_the_install_line(monkeypatch):
    def not_installed(distribution):
        raise metadata.PackageNotFoundError(distribution)

    monkeypatch.setattr(metadata, "files", not_installed)
    spec = REAL_ROBOTS["stretch"]
    with pytest.raises(ModelError) as info:
        spec.path()
    assert (
        str(info.value)
        == "this robot needs the package hello-robot-stretch-urdf: pip install 'mobman[robots]'"
    )
    assert not spec.available()


def test_a_package_without_the_file_gives_the_install_line(monkeypatch):
    monkeypatch.setattr(metadata, "files", lambda distribution: None)  # no RECORD: no files known
    spec = REAL_ROBOTS["tiago"]
    with pytest.raises(ModelError) as info:
        spec.path()
    message = str(info.value)
    assert message == (
        "example-robot-data is installed without tiago_description/robots/tiago.urdf: "
        "pip install 'mobman[robots]'"
    )
    assert not spec.available()


def test_urdf_model_of_a_robot_whose_package_is_missing_raises(monkeypatch):
    absent = RealRobot("no-such-distribution-xyz", "robots/robot.urdf", ("tool",), "base_link")
    monkeypatch.setitem(REAL_ROBOTS, "absent-robot", absent)
    with pytest.raises(ModelError, match=r"no-such-distribution-xyz: pip install 'mobman\[robots\]'$"):
        urdf_model("absent-robot")


def test_importing_the_module_does_not_import_yourdfpy():
    code = "import sys, mobman.io.real_robots; sys.exit('yourdfpy' in sys.modules)"
    assert subprocess.run([sys.executable, "-c", code], capture_output=True).returncode == 0
