"""The command-line parsing helpers of mobman.cli.common: NAME=VALUE parameters, the step and disk estimates,
robots and their dynamic models by name or file, configuration CSV files, the available memory and the exit
of a run that missed its goal; every bad input is a one-line MobmanError naming the option."""

from __future__ import annotations

import math
import shutil
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest
import typer

from mobman.cli import common
from mobman.errors import InputError, MobmanError, ModelError
from mobman.io.real_robots import REAL_ROBOTS
from mobman.model import robots
from mobman.model.arm import Arm, Joint
from mobman.model.platforms import DifferentialDrive
from mobman.model.robot import MobileManipulator

PLANAR_FILE = Path(__file__).resolve().parents[1] / "docs" / "examples" / "planar_robot.toml"


def _one_line(info: pytest.ExceptionInfo, *fragments: str) -> str:
    message = str(info.value)
    assert "\n" not in message and isinstance(info.value, MobmanError)
    for fragment in fragments:
        assert fragment in message, (fragment, message)
    return message


@pytest.fixture(scope="module")
def robot() -> MobileManipulator:
    """A differential base with a revolute and a prismatic joint: coordinates x, y, theta, shoulder, slide."""
    arm = Arm((Joint("revolute", name="shoulder"), Joint("prismatic", (1.0, 0.0, 0.0), name="slide")))
    return MobileManipulator(DifferentialDrive(), (arm,))


# --- parse_params ----------------------------------------------------------------------------------


def test_parse_params_of_nothing_is_empty():
    assert common.parse_params(None) == {}
    assert common.parse_params([]) == {}


def test_parse_params_reads_names_and_numbers():
    params = common.parse_params(["l1=0.5", " l2 = pi/4 ", "r=1e-2"])
    assert params == {"l1": 0.5, "l2": pytest.approx(math.pi / 4, abs=1e-15), "r": 0.01}
    assert all(type(v) is float for v in params.values())


def test_parse_params_later_item_wins():
    assert common.parse_params(["l1=0.5", "l1=0.7"]) == {"l1": 0.7}


@pytest.mark.parametrize(
    ("item", "fragments"),
    [
        ("l1", ("--param 'l1'", "expected NAME=VALUE")),
        ("l1 0.5", ("--param 'l1 0.5'", "expected NAME=VALUE")),
        ("l1=", ("--param l1", "empty value")),
        ("l1=long", ("--param l1",)),
        ("l1=nan", ("--param l1",)),
        ("l1=inf", ("--param l1",)),
        ("l1=0.5=0.6", ("--param l1",)),
    ],
)
def test_parse_params_rejects_a_malformed_item(item, fragments):
    with pytest.raises(InputError) as info:
        common.parse_params(["l2=0.1", item])
    _one_line(info, *fragments)


# --- check_steps -----------------------------------------------------------------------------------


def test_check_steps_accepts_a_run_within_the_limits(monkeypatch):
    monkeypatch.setattr(common, "available_memory", lambda: 10**12)
    common.check_steps(common.MAX_STEPS, 1, "--dt")  # exactly at the limit
    common.check_steps(50, 3, "--dt", max_steps=50)


def test_check_steps_refuses_more_steps_than_the_limit(monkeypatch):
    monkeypatch.setattr(common, "available_memory", lambda: 10**12)
    with pytest.raises(InputError) as info:
        common.check_steps(2_000_001, 1, "--duration")
    _one_line(info, "--duration: ", "2e+06 steps", "limit of 1e+06 steps", "--max-steps")
    with pytest.raises(InputError, match="limit of 10 steps"):
        common.check_steps(11, 1, "--dt", max_steps=10)


def test_check_steps_refuses_a_run_larger_than_the_available_memory(monkeypatch):
    monkeypatch.setattr(common, "available_memory", lambda: 1000)
    common.check_steps(10, 1, "--dt")  # 10 × 64 B = 640 B fit
    with pytest.raises(InputError) as info:
        common.check_steps(10, 2, "--dt")  # 1280 B do not
    message = _one_line(info, "--dt: 10 steps, about 1.25 KiB of memory", "1e+03 B available")
    assert "--max-steps" not in message  # raising the step limit would not help


def test_check_steps_counts_only_the_steps_held_at_once(monkeypatch):
    monkeypatch.setattr(common, "available_memory", lambda: 1000)
    common.check_steps(1000, 1, "--dt", held=15)  # 15 × 64 B = 960 B at once
    with pytest.raises(InputError, match="available"):
        common.check_steps(1000, 1, "--dt", held=16)


def test_check_steps_skips_the_memory_check_when_unknown(monkeypatch):
    monkeypatch.setattr(common, "available_memory", lambda: None)
    common.check_steps(common.MAX_STEPS, 10**6, "--dt")


# --- check_disk ------------------------------------------------------------------------------------


def _usage(free: int):
    return shutil._ntuple_diskusage(total=10 * free + 1, used=0, free=free)


def test_check_disk_accepts_results_that_fit(tmp_path, monkeypatch):
    seen = []
    monkeypatch.setattr(shutil, "disk_usage", lambda p: seen.append(Path(p)) or _usage(4096))
    common.check_disk(tmp_path / "new" / "deeper", 4096)
    assert seen == [tmp_path]  # the nearest folder that exists


def test_check_disk_refuses_results_larger_than_the_free_space(tmp_path, monkeypatch):
    monkeypatch.setattr(shutil, "disk_usage", lambda p: _usage(2048))
    out = tmp_path / "results"
    with pytest.raises(InputError) as info:
        common.check_disk(out, 3 * 1024 * 1024)
    _one_line(info, f"--out {out}: ", "about 3 MiB", "the 2 KiB free there")
    with pytest.raises(InputError, match=r"^--trajectory "):
        common.check_disk(out, 4096, field="--trajectory")


def test_check_disk_gives_up_silently_when_the_file_system_cannot_be_asked(tmp_path, monkeypatch):
    def unavailable(path):
        raise OSError("no statvfs")

    monkeypatch.setattr(shutil, "disk_usage", unavailable)
    common.check_disk(tmp_path, 10**18)


# --- not_reached -----------------------------------------------------------------------------------


def test_not_reached_warns_on_one_line_and_exits_3(capsys):
    with pytest.raises(typer.Exit) as info:
        common.not_reached("plan", "not converged within 60 iterations")
    assert info.value.exit_code == 3
    captured = capsys.readouterr()
    assert captured.out == ""
    assert captured.err.splitlines() == ["warning: mobman plan: not converged within 60 iterations"]


# --- load_robot ------------------------------------------------------------------------------------


def test_load_robot_builds_a_built_in_robot_with_parameters():
    robot = common.load_robot("bayle-planar", ["l1=0.7"])
    assert dict(robot.parameters) == {"l1": 0.7, "l2": 0.5}
    assert robot.coordinate_names == ("x", "y", "theta", "q4", "q5")


def test_load_robot_reads_a_robot_file():
    robot = common.load_robot(str(PLANAR_FILE))
    assert robot.name == "planar-2r-on-differential-base"
    assert robot.n_q == 5 and robot.platform.wheel_radius == 0.1


def test_load_robot_reads_a_urdf_file_with_its_options(tmp_path):
    from mobman.io.urdf import write_urdf

    path = write_urdf(robots.build("bayle-planar"), tmp_path / "planar.urdf")
    robot = common.load_robot(str(path), None, common.urdf_options(["tool_link"]))
    assert robot.n_q == 5 and robot.arms[0].n_joints == 2


@pytest.mark.parametrize(
    ("name", "fragment"),
    [
        ("robot.urdf", "a URDF file takes --tip, --base, --platform, --wheels, --lock and --platform-option"),
        ("robot.toml", "edit the robot file instead"),
    ],
)
def test_load_robot_refuses_parameters_for_files(name, fragment):
    with pytest.raises(InputError) as info:
        common.load_robot(name, ["mount.z=0.1", "l1=0.5"])
    _one_line(
        info,
        "--param l1: a robot file takes only its arm's mount (mount.x, mount.y, mount.z, mount.yaw, mount.pitch",
        fragment,
    )


def test_load_robot_mounts_the_arm_of_a_built_in_robot_or_a_file(tmp_path):
    from mobman.io.urdf import write_urdf
    from mobman.model.robot import Mount

    mounted = common.load_robot("bayle-planar", ["l1=0.6", "mount.x=0.2", "mount.yaw=pi/2"])
    assert mounted == robots.design("bayle-planar", {"l1": 0.6, "mount.x": 0.2, "mount.yaw": math.pi / 2})
    assert mounted.mounts == (Mount(x=0.2, yaw=math.pi / 2),)
    path = write_urdf(robots.build("bayle-planar"), tmp_path / "planar.urdf")
    read = common.load_robot(str(path), ["mount.z=0.3"], common.urdf_options(["tool_link"]))
    assert read.mounts == (Mount(z=0.3),) and read.arms[0].n_joints == 2
    on_file = common.load_robot(str(PLANAR_FILE), ["mount.y=-0.1"])
    assert on_file.mounts[0].y == -0.1
    # the second arm of a two-arm robot, as a command with --arm asks
    dual = common.load_robot("yamamoto-dual-arm", ["mount.z=0.5"], arm=1)
    assert dual.mounts[0] == robots.build("yamamoto-dual-arm").mounts[0] and dual.mounts[1].z == 0.5
    with pytest.raises(ModelError) as info:
        common.load_robot("bayle-planar", ["mount.w=1"])
    _one_line(
        info,
        "robot bayle-planar: unknown parameter 'mount.w'; allowed: l1, l2, mount.x, mount.y, mount.z, mount.yaw",
    )
    with pytest.raises(ModelError) as info:
        common.load_robot("bayle-planar", ["mount.z=0.1"], arm=1)
    _one_line(info, "robot bayle-planar: arm 1 to mount: the robot has 1 arm(s)")


@pytest.mark.parametrize(
    ("name", "params", "fragment"),
    [
        ("no-such-robot", None, "unknown robot 'no-such-robot'"),
        ("bayle-planar", ["width=1"], "unknown parameter 'width'"),
        ("bayle-planar", ["l1=-1"], "l1"),
    ],
)
def test_load_robot_names_the_unknown_robot_or_parameter(name, params, fragment):
    with pytest.raises(ModelError) as info:
        common.load_robot(name, params)
    _one_line(info, fragment)


def test_load_robot_of_a_missing_file_is_a_clear_error(tmp_path):
    with pytest.raises(MobmanError) as info:
        common.load_robot(str(tmp_path / "absent.toml"))
    _one_line(info, "absent.toml")


@pytest.mark.parametrize("suffix", [".urdf.xacro", ".xacro", ".URDF.XACRO"])
def test_load_robot_of_a_xacro_file_says_how_to_expand_it(tmp_path, suffix):
    path = tmp_path / f"robot{suffix}"
    path.write_text("<robot xmlns:xacro='http://www.ros.org/wiki/xacro' name='r'/>")
    with pytest.raises(InputError) as info:
        common.load_robot(str(path))
    _one_line(info, str(path), "xacro file", "expand it to URDF first: xacro")


@pytest.mark.parametrize("name", ["/etc/hostname", "robots/tiago"])
def test_load_robot_of_a_file_that_is_no_robot_file_names_the_endings(name):
    with pytest.raises(InputError) as info:
        common.load_robot(name)
    _one_line(info, f"{name}: not a robot name", ".urdf", ".toml")


# --- load_dynamics ---------------------------------------------------------------------------------


def test_load_dynamics_of_yamamoto_is_horizontal_with_the_papers_limits():
    robot = robots.build("yamamoto-dual-arm")
    model, limits = common.load_dynamics("yamamoto-dual-arm", robot, "--dynamic")
    assert model.gravity == (0.0, 0.0, 0.0) and model.robot is robot
    assert len(limits) == model.n_actuators == 8
    assert np.all(np.isfinite(limits)) and np.all(limits > 0)


def _urdf_efforts(path: Path) -> dict[str, float]:
    root = ET.parse(path).getroot()
    return {
        j.get("name"): float(j.find("limit").get("effort"))
        for j in root.iter("joint")
        if j.find("limit") is not None and j.find("limit").get("effort") is not None
    }


@pytest.mark.parametrize("name", ["tiago", "tiago_dual"])
def test_load_dynamics_of_tiago_takes_the_urdf_effort_limits_and_gravity(name):
    key = name.replace("_", "-")
    robot = robots.build(key)
    model, limits = common.load_dynamics(name, robot, "--dynamic")
    assert model.gravity == pytest.approx((0.0, 0.0, -9.81))
    efforts = _urdf_efforts(REAL_ROBOTS[key].path())
    joints = robot.coordinate_names[robot.platform.n_q :]
    assert np.asarray(limits[2:]) == pytest.approx([efforts[j] for j in joints], rel=1e-12)
    assert np.asarray(limits[:2]) == pytest.approx(
        [efforts["wheel_right_joint"], efforts["wheel_left_joint"]]
    )


def test_load_dynamics_keeps_the_arm_s_mount_and_the_urdf_s_inertials():
    robot = common.load_robot("tiago", ["mount.z=0.2"])
    model, _ = common.load_dynamics("tiago", robot, "--dynamic")
    plain, _ = common.load_dynamics("tiago", robots.build("tiago"), "--dynamic")
    assert model.robot.mounts == robot.mounts and model.robot.mounts != plain.robot.mounts
    assert model.robot.arms == plain.robot.arms and model.body == plain.body and model.wheel == plain.wheel


def test_load_dynamics_names_what_a_robot_without_a_dynamic_model_lacks():
    robot = robots.build("bayle-planar")
    with pytest.raises(ModelError) as info:
        common.load_dynamics("bayle-planar", robot, "--load")
    _one_line(info, "robot bayle-planar: --load needs a dynamic model", "yamamoto-dual-arm", "tiago")


def test_load_dynamics_of_a_urdf_without_inertials_names_the_option(tmp_path):
    from mobman.io.urdf import write_urdf

    path = write_urdf(robots.build("bayle-planar"), tmp_path / "planar.urdf")
    robot = common.load_robot(str(path), None, {"tip": "tool_link"})
    with pytest.raises(ModelError) as info:
        common.load_dynamics(str(path), robot, "--dynamic", {"tip": "tool_link"})
    _one_line(info, "--dynamic: ", "inertial")


# --- read_configurations ---------------------------------------------------------------------------


def _csv(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "q.csv"
    path.write_text(text, encoding="utf-8")
    return path


def test_read_configurations_with_a_header(tmp_path, robot):
    path = _csv(tmp_path, "x,y,theta,shoulder,slide\n0,0,0,0.5,0.1\n1, 2, -3.5, 1e-3, 0.25\n")
    q = common.read_configurations(path, robot)
    assert q.shape == (2, 5) and q.dtype == float
    np.testing.assert_array_equal(q, [[0, 0, 0, 0.5, 0.1], [1, 2, -3.5, 1e-3, 0.25]])


def test_read_configurations_without_a_header_and_with_blank_lines(tmp_path, robot):
    path = _csv(tmp_path, "\n0.1,0.2,0.3,0.4,0.5\n\n , , \n")
    q = common.read_configurations(path, robot)
    np.testing.assert_array_equal(q, [[0.1, 0.2, 0.3, 0.4, 0.5]])


def test_read_configurations_accepts_spaces_around_header_names(tmp_path, robot):
    path = _csv(tmp_path, " x , y , theta , shoulder , slide \n0,0,0,0,0\n")
    assert common.read_configurations(path, robot).shape == (1, 5)


def test_read_configurations_reads_expressions_as_on_the_command_line(tmp_path, robot):
    path = _csv(tmp_path, "0,0,pi/2,-pi,0.5\n1,2,3,4,5\n")
    np.testing.assert_array_equal(
        common.read_configurations(path, robot), [[0, 0, np.pi / 2, -np.pi, 0.5], [1, 2, 3, 4, 5]]
    )


@pytest.mark.parametrize(
    ("text", "fragments"),
    [
        ("", ("no configurations",)),
        ("\n\n", ("no configurations",)),
        ("x,y,theta,shoulder,slide\n", ("no configurations",)),
        (
            "a,b,c,d,e\n0,0,0,0,0\n",
            ("header ['a', 'b', 'c', 'd', 'e'] does not match coordinates", "'shoulder'"),
        ),
        ("x,y,theta,shoulder\n0,0,0,0\n", ("header", "does not match coordinates")),
        ("0,0,0,0\n", ("row 1", "expected 5 values, got 4")),
        ("0,0,0,0,0\n0,0,0,0,0,0\n", ("row 2", "expected 5 values, got 6")),
        ("0,0,0,0,0\n0,0,zero,0,0\n", ("row 2: 'zero' is not",)),
        ("0,0,0,0,0\n0,0,nan,0,0\n", ("row 2",)),
        ("0,0,0,inf,0\n", ("row 1",)),
    ],
    ids=[
        "empty",
        "blank",
        "header-only",
        "wrong-header",
        "short-header",
        "short-row",
        "long-row",
        "non-numeric",
        "nan",
        "inf",
    ],
)
def test_read_configurations_rejects_bad_files(tmp_path, robot, text, fragments):
    path = _csv(tmp_path, text)
    with pytest.raises(InputError) as info:
        common.read_configurations(path, robot)
    _one_line(info, f"--q-file {path}", *fragments)


def test_read_configurations_of_a_missing_or_binary_file(tmp_path, robot):
    with pytest.raises(InputError) as info:
        common.read_configurations(tmp_path / "absent.csv", robot)
    _one_line(info, "--q-file", "absent.csv", "cannot read")
    binary = tmp_path / "q.bin"
    binary.write_bytes(b"0,0,0,0,0\x00\n")
    with pytest.raises(InputError) as info:
        common.read_configurations(binary, robot)
    _one_line(info, "--q-file", "binary")


def test_array_text_never_switches_to_e_notation():
    from mobman.cli.common import array_text

    text = array_text([1.234e-7, -0.5, 1.0, 12345.678901], 3)
    assert "e" not in text
    assert text.split() == ["[", "0.", "-0.5", "1.", "12345.679]"]
    assert "e" not in array_text([[1e-12, 2.5e4], [3.0, -1e-9]])
