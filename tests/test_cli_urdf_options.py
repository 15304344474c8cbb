"""A URDF file wherever a robot is named: the reading options of :func:`mobman.io.urdf.read_urdf` on every
command that takes a ROBOT (``--tip``, ``--base``, ``--platform``, ``--wheels``, ``--lock``) and as the keys of
a spec file's ``[robot]`` table (``mobman simulate``, ``mobman load-capacity``)."""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

import numpy as np
import pytest
from urdf_samples import husky, husky_tool

from mobman import kinematics
from mobman.cli import common
from mobman.dynamics.ellipsoids import kinematic_ellipsoid
from mobman.errors import InputError, MobmanError
from mobman.io import robot_file
from mobman.io.numbers import parse_vector
from mobman.io.real_robots import REAL_ROBOTS, urdf_model
from mobman.io.urdf import load_urdf, write_urdf
from mobman.model import robots
from mobman.model.platforms.fixed import Fixed

ROOT = Path(__file__).resolve().parents[1]
WHEELS = "wheel_right_joint,wheel_left_joint"  # the wheel joints write_urdf gives a differential drive


@pytest.fixture(scope="module")
def planar(tmp_path_factory) -> Path:
    """Bayle's planar robot as URDF: wheels wheel_right_joint / wheel_left_joint, arm q4, q5, tip tool_link."""
    return write_urdf(robots.build("bayle-planar"), tmp_path_factory.mktemp("urdf") / "planar.urdf")


def _analysis(args: list[str], cli_run) -> dict:
    code, out, err = cli_run(["analyze", *args, "--json"])
    assert code == 0, err
    return json.loads(out)["results"][0]


# --- the command-line options --------------------------------------------------------------------------


def test_urdf_options_keep_read_urdf_s_defaults_for_what_is_not_given():
    assert common.urdf_options() == {}
    given = common.urdf_options(
        ["left_hand", "right_hand"],
        "base_link",
        "fixed",
        " r , l ",
        ["j1=pi/2"],
        ["x_icr=1/20", "base_height=0.1"],
    )
    assert given == {
        "tip": ("left_hand", "right_hand"),
        "base": "base_link",
        "platform": "fixed",
        "wheels": ("r", "l"),
        "locked": {"j1": pytest.approx(np.pi / 2, rel=1e-15)},
        "platform_options": {"x_icr": 0.05, "base_height": 0.1},
    }


def test_urdf_options_name_a_malformed_lock_or_platform_option():
    with pytest.raises(InputError) as info:
        common.urdf_options(lock=["q5"])
    assert str(info.value) == "--lock 'q5': expected NAME=VALUE"
    with pytest.raises(InputError) as info:
        common.urdf_options(platform_option=["wheel_radius"])
    assert str(info.value) == "--platform-option 'wheel_radius': expected NAME=VALUE"


@pytest.mark.parametrize("robot", ["bayle-planar", str(ROOT / "docs" / "examples" / "planar_robot.toml")])
def test_urdf_options_for_another_robot_are_refused_on_one_line(robot, cli_run):
    options = ["--platform", "fixed", "--lock", "q5=0", "--platform-option", "x_icr=0"]
    code, _, err = cli_run(["analyze", robot, *options, "--q", "0"])
    assert code == 2 and len(err.strip().splitlines()) == 1
    assert "--platform, --lock, --platform-option: for a URDF file (a path ending in .urdf), not robot" in err


def test_wheels_named_on_the_command_line_are_the_wheels_found(planar, cli_run):
    q = "0.2,-0.1,0.5,0.3,-1.1"
    found = _analysis([str(planar), "--tip", "tool_link", "--q", q], cli_run)
    named = _analysis([str(planar), "--tip", "tool_link", "--wheels", WHEELS, "--q", q], cli_run)
    assert named["J_bar"] == found["J_bar"] and np.shape(named["J_bar"]) == (3, 4)


def test_a_fixed_platform_leaves_the_arm_s_columns(planar, cli_run):
    q = "0.2,-0.1,0.5,0.3,-1.1"
    mobile = _analysis([str(planar), "--tip", "tool_link", "--q", q], cli_run)
    fixed = _analysis([str(planar), "--tip", "tool_link", "--platform", "fixed", "--q", q], cli_run)
    # J̄ of an arm on a base that does not move is J's arm columns (q_p = the placement, no η_p)
    np.testing.assert_allclose(fixed["J_bar"], np.asarray(mobile["J"])[:, 3:], rtol=0, atol=1e-15)


def test_a_locked_joint_is_held_at_its_value(planar, cli_run):
    """The locked URDF robot's J̄ is the built-in robot's at q5 = π/2 without q5's column (a closed form from
    an independent model: the built-in DH robot)."""
    q = np.array([0.2, -0.1, 0.5, 0.3])
    locked = _analysis(
        [str(planar), "--tip", "tool_link", "--lock", "q5=pi/2", "--q", ",".join(map(str, q))], cli_run
    )
    reference = robots.build("bayle-planar")
    jbar = kinematics.reduced_jacobian(reference, np.append(q, np.pi / 2))  # rows x, y, φ
    np.testing.assert_allclose(np.asarray(locked["J_bar"])[:2], np.asarray(jbar)[:2, :3], rtol=0, atol=1e-12)


@pytest.mark.parametrize(
    ("options", "fragments"),
    [
        (["--wheels", "wheel_right_joint"], ["wheels: two joint names (right, left)"]),
        (["--wheels", "q4,wheel_left_joint"], ["wheels: joint"]),
        (["--platform", "omnidirectinal"], ["platform must be one of", "did you mean 'omnidirectional'?"]),
        (["--lock", "no_joint=0"], ["locked: 'no_joint' is not a moving joint"]),
        (["--tip", "no_link"], ["no_link"]),
    ],
)
def test_bad_urdf_options_are_one_line_and_exit_2(planar, options, fragments, cli_run):
    code, _, err = cli_run(["analyze", str(planar), "--tip", "tool_link", *options, "--q", "0,0,0,0,0"])
    assert code == 2 and len(err.strip().splitlines()) == 1 and err.startswith("error: ")
    assert all(f in err for f in fragments), err


def test_no_wheel_pair_names_the_options_that_fix_it(tmp_path, cli_run):
    arm_only = dataclasses.replace(robots.build("bayle-planar"), platform=Fixed())
    path = write_urdf(arm_only, tmp_path / "arm.urdf")
    code, _, err = cli_run(["analyze", str(path), "--tip", "tool_link", "--q", "0,0,0,0,0"])
    assert code == 2 and len(err.strip().splitlines()) == 1
    assert "continuous joints seen: none" in err and "--wheels RIGHT,LEFT" in err and "--platform" in err
    fixed = _analysis(
        [str(path), "--tip", "tool_link", "--platform", "fixed", "--q", "0,0,0,0.3,0.4"], cli_run
    )
    assert np.shape(fixed["J_bar"]) == (3, 2)


def test_ellipsoid_of_a_urdf_file_reads_it_with_the_options(cli_run):
    q = "0,0,0,0.15,0.5,0.3,-1.2,1.5,0.3,0.5,0"
    path = str(REAL_ROBOTS["tiago"].path())
    wheels = ["--wheels", "wheel_right_joint,wheel_left_joint"]
    code, out, err = cli_run(["ellipsoid", path, "--tip", "arm_tool_link", *wheels, "--q", q, "--json"])
    assert code == 0, err
    expected = kinematic_ellipsoid(robots.build("tiago"), np.array(parse_vector(q, "q", 11)))
    np.testing.assert_allclose(json.loads(out)["axes"], np.asarray(expected.axes), rtol=1e-12, atol=1e-15)


def test_dynamic_ellipsoid_of_tiago_s_urdf_file_is_the_built_in_one(cli_run):
    q = "0,0,0,0.15,0.5,0.3,-1.2,1.5,0.3,0.5,0"
    path = str(REAL_ROBOTS["tiago"].path())
    results = []
    for robot in ("tiago", path):
        code, out, err = cli_run(["ellipsoid", robot, "--kind", "dynamic", "--q", q, "--json"])
        assert code == 0, err
        results.append(json.loads(out)["axes"])
    np.testing.assert_allclose(results[1], results[0], rtol=1e-12)


def test_plan_reads_a_urdf_file_with_the_options(planar, cli_run):
    # the tip decides the task (xyz of tool_link: three values), and a wrong tip is named
    code, _, err = cli_run(["plan", str(planar), "--tip", "tool_link", "--target", "1,0"])
    assert code == 2 and "--target: expected 3 values, got 2" in err
    code, _, err = cli_run(["plan", str(planar), "--tip", "no_link", "--target", "1,0,0"])
    assert code == 2 and "no_link" in err and len(err.strip().splitlines()) == 1


# --- the [robot] table of a spec file ------------------------------------------------------------------


def _robot_table(path: Path, extra: str = "") -> dict:
    import tomllib

    return tomllib.loads(f'[robot]\nfile = "{path.name}"\n{extra}')


def test_a_robot_table_reads_a_urdf_file_relative_to_the_spec(planar):
    data = _robot_table(planar, f'tip = "tool_link"\nwheels = {WHEELS.split(",")!r}\nlocked = {{ q5 = 0.5 }}')
    robot = robot_file.robot_table(data, planar.parent)
    expected = load_urdf(planar, tip="tool_link", locked={"q5": 0.5})
    assert robot.coordinate_names == expected.coordinate_names == ("x", "y", "theta", "q4")
    q = np.random.default_rng(0).uniform(-np.pi, np.pi, (50, robot.n_q))
    q[:4, 2:] = np.array([0.0, np.pi / 2, -np.pi / 2, np.pi])[:, None]  # θ and q4 at 0, ±π/2, π
    np.testing.assert_array_equal(
        kinematics.reduced_jacobian(robot, q), kinematics.reduced_jacobian(expected, q)
    )
    model = robot_file.urdf_table(data, planar.parent)
    assert model is not None and model.robot.coordinate_names == robot.coordinate_names


def test_urdf_table_is_the_real_robot_s_model_and_none_for_other_robots():
    assert robot_file.urdf_table({"robot": {"name": "tiago"}}) is urdf_model("tiago")
    assert robot_file.urdf_table({"robot": {"name": "tiago_dual"}}) is urdf_model("tiago-dual")
    assert robot_file.urdf_table({"robot": {"name": "bayle-planar"}}) is None
    assert robot_file.urdf_table({"robot": {"file": "planar_robot.toml"}}) is None
    assert robot_file.urdf_table({"robot": {"name": ["tiago"]}}) is None  # robot_table names the field


@pytest.mark.parametrize(
    ("keys", "message"),
    [
        ('tip = "tool_link"\nname = "tiago"', "robot.name: unknown key"),
        ("tip = 3", "robot.tip: a link or joint name or a list of them, got 3"),
        ('tip = ["tool_link", ""]', "robot.tip: a link or joint name or a list of them"),
        ('tip = "tool_link"\nwheels = ["wheel_right_joint"]', "robot.wheels: two joint names [right, left]"),
        ('tip = "tool_link"\nlocked = { q5 = "up" }', "robot.locked.q5: must be a finite number"),
        ('tip = "tool_link"\nlocked = 0.5', "robot.locked"),
        ('tip = "tool_link"\nplatform = "hover"', "platform must be one of"),
    ],
)
def test_a_robot_table_s_urdf_keys_are_checked(planar, keys, message):
    with pytest.raises(MobmanError) as info:
        robot_file.robot_table(_robot_table(planar, keys), planar.parent)
    assert message in str(info.value) and "\n" not in str(info.value)


def test_simulate_a_urdf_file_gives_the_built_in_robot_s_run(planar, tmp_path, cli_run):
    """Bayle's ellipse example with the robot read from its URDF: the same run (write_urdf's round trip
    gives the same ξ and J̄ to 1e-12)."""
    text = (ROOT / "docs" / "examples" / "bayle_ellipse.toml").read_text()
    built_in = 'name = "bayle-planar"\nparams = { l1 = 0.5, l2 = 0.5 }'
    assert built_in in text
    runs = []
    for i, robot in enumerate([built_in, f'file = "{planar}"\ntip = "tool_link"']):
        spec = tmp_path / f"spec{i}.toml"
        spec.write_text(text.replace(built_in, robot, 1))
        code, out, err = cli_run(["simulate", str(spec), "--json"])
        assert code == 0, err
        runs.append(json.loads(out))
    assert runs[1]["final_error"] == pytest.approx(runs[0]["final_error"], rel=1e-6, abs=1e-12)
    np.testing.assert_allclose(runs[1]["q_final"], runs[0]["q_final"], rtol=0, atol=1e-9)


def test_load_capacity_of_tiago_s_urdf_file_takes_its_inertials_and_effort_limits(tmp_path, cli_run):
    text = (ROOT / "docs" / "examples" / "tiago_load.toml").read_text()
    short = text.replace("dt = 0.02", "dt = 0.1")  # 21 samples
    path = REAL_ROBOTS["tiago"].path()
    loads = []
    for i, robot in enumerate(['name = "tiago"', f'file = "{path}"']):
        spec = tmp_path / f"load{i}.toml"
        spec.write_text(short.replace('name = "tiago"', robot, 1))
        code, out, err = cli_run(["load-capacity", str(spec), "--json"])
        assert code == 0, err
        loads.append(json.loads(out))
    assert loads[0]["bounded"] and loads[1]["max_load_kg"] == pytest.approx(
        loads[0]["max_load_kg"], rel=1e-12
    )
    assert loads[1]["limiting_actuator"] == loads[0]["limiting_actuator"]


def _tiago_load(robot: dict, monkeypatch) -> tuple[dict, list]:
    """docs/examples/tiago_load.toml with ``robot`` as its [robot] table and a motion of two samples, and the
    list of the URDF files read from then on."""
    import tomllib

    from mobman.io import urdf

    data = tomllib.loads((ROOT / "docs" / "examples" / "tiago_load.toml").read_text())
    data["robot"] = robot
    data["motion"]["control"]["duration"] = data["motion"]["control"]["dt"]
    reads: list = []
    original = urdf.read_urdf
    monkeypatch.setattr(
        urdf, "read_urdf", lambda *args, **kwargs: reads.append(args) or original(*args, **kwargs)
    )
    return data, reads


def test_a_load_capacity_spec_reads_its_urdf_file_once(tmp_path, monkeypatch):
    """The [robot] file of a load-capacity spec whose motion is a control simulation is read once: the
    simulation's specification takes the robot already built."""
    from mobman.cli.dynamics import parse

    data, reads = _tiago_load({"file": str(REAL_ROBOTS["tiago"].path())}, monkeypatch)
    spec = parse(data, tmp_path)
    assert len(reads) == 1
    assert spec.model.robot.n_q == 3 + 8 and spec.q.shape == (2, spec.model.robot.n_q)


def test_a_load_capacity_spec_mounts_a_real_robot_s_arm_from_its_params(tmp_path, monkeypatch):
    from mobman.cli.dynamics import parse

    data, reads = _tiago_load({"name": "tiago", "params": {"mount.z": 0.1}}, monkeypatch)
    spec = parse(data, tmp_path)
    assert len(reads) <= 1 and spec.model.robot.mounts[0].z == 0.1  # a real robot's model is cached
    assert spec.model.robot.arms == urdf_model("tiago").robot.arms  # the URDF's inertials
    data["robot"]["params"] = {"l1": 0.5}  # a real robot has only its mount's parameters
    with pytest.raises(InputError) as info:
        parse(data, tmp_path)
    assert "robot: robot tiago: unknown parameter 'l1'; allowed: mount.x, mount.y, mount.z, mount.yaw" in str(
        info.value
    )


def test_urdf_actuators_of_a_robot_without_a_urdf_name_both_sources():
    from mobman.cli.dynamics import parse

    text = (ROOT / "docs" / "examples" / "korayem_load.toml").read_text()
    import tomllib

    data = tomllib.loads(text)
    data["actuators"] = "urdf"
    with pytest.raises(InputError) as info:
        parse(data)
    assert 'actuators: "urdf" takes the effort limits of a robot read from a URDF' in str(info.value)
    assert "tiago" in str(info.value) and 'file = "….urdf"' in str(info.value)


# --- platform options, the ground, meshes ---------------------------------------------------------------


def test_a_skid_steer_urdf_is_read_from_the_command_line(tmp_path, cli_run):
    path = husky(tmp_path)
    q = np.array([0.3, -0.2, np.pi / 2, 0.25, -np.pi / 2])
    options = ["--platform-option", "x_icr=0.05", "--platform-option", "track_factor=1.5"]
    analysis = _analysis(
        [
            str(path),
            "--tip",
            "tool",
            "--base",
            "base_link",
            "--platform",
            "skid_steer",
            *options,
            "--q",
            ",".join(map(str, q)),
        ],
        cli_run,
    )
    # ξ by hand, the platform frame on the ground 0.13228 m below base_link
    np.testing.assert_allclose(analysis["xi"], husky_tool(q[None], 0.1651 - 0.03282)[0], rtol=0, atol=1e-12)
    expected = load_urdf(
        path,
        tip="tool",
        base="base_link",
        platform="skid_steer",
        platform_options={"x_icr": 0.05, "track_factor": 1.5},
    )
    np.testing.assert_allclose(
        analysis["J_bar"], kinematics.reduced_jacobian(expected, q), rtol=0, atol=1e-15
    )


def test_fixed_wheels_take_the_radius_and_half_track_given_and_say_where_heights_start(tmp_path, cli_run):
    path = str(husky(tmp_path, "fixed"))
    q = "0,0,0,0.1,0"
    base = [path, "--tip", "tool", "--base", "base_link", "--q", q]
    code, _, err = cli_run(["analyze", *base, "--platform", "differential"])
    assert code == 2 and len(err.strip().splitlines()) == 1
    assert "--platform-option wheel_radius=R --platform-option half_track=B" in err
    given = ["--platform-option", "wheel_radius=0.1651", "--platform-option", "half_track=0.2854"]
    code, out, err = cli_run(["analyze", *base, *given, "--json"])
    assert code == 0 and err.strip().splitlines() == [err.strip()]  # one warning line
    assert err.startswith("warning: no wheel joint of the file gives the ground under 'base_link'")
    assert "--platform-option base_height=H" in err
    assert json.loads(out)["results"][0]["xi"] == pytest.approx([0.4, 0.05, 0.3], abs=1e-12)
    code, out, err = cli_run(["analyze", *base, *given, "--platform-option", "base_height=0.2", "--json"])
    assert code == 0 and err == ""
    assert json.loads(out)["results"][0]["xi"] == pytest.approx([0.4, 0.05, 0.5], abs=1e-12)


@pytest.mark.parametrize(
    ("option", "fragments"),
    [
        (
            "caster=1",
            [
                "platform option 'caster': not a parameter of DifferentialDrive",
                "allowed: wheel_radius, half_track",
            ],
        ),
        ("half_track=0", ["half_track must be a finite number > 0, got 0"]),
        ("wheel_radius=big", ["--platform-option wheel_radius"]),
    ],
)
def test_bad_platform_options_are_one_line_and_exit_2(planar, option, fragments, cli_run):
    code, _, err = cli_run(
        ["analyze", str(planar), "--tip", "tool_link", "--platform-option", option, "--q", "0,0,0,0,0"]
    )
    assert code == 2 and len(err.strip().splitlines()) == 1 and err.startswith("error: ")
    assert all(f in err for f in fragments), err


def test_a_robot_table_gives_platform_options(tmp_path):
    path = husky(tmp_path, "none")
    data = _robot_table(
        path,
        'tip = "tool"\nbase = "base_link"\nplatform_options = { wheel_radius = 0.2, half_track = 0.3, base_height = 0.1 }',
    )
    robot = robot_file.robot_table(data, tmp_path)
    assert (robot.platform.wheel_radius, robot.platform.half_track) == (0.2, 0.3)
    q = np.array([[0.0, 0.0, 0.0, 0.1, 0.0]])
    np.testing.assert_allclose(kinematics.forward(robot, q), husky_tool(q, 0.1), rtol=0, atol=1e-12)
    with pytest.raises(MobmanError) as info:
        robot_file.robot_table(
            _robot_table(path, 'tip = "tool"\nplatform_options = { wheel_radius = "r" }'), tmp_path
        )
    assert "robot.platform_options.wheel_radius: must be a finite number" in str(info.value)


def test_missing_meshes_are_one_line_where_the_robot_is_drawn_and_none_elsewhere(
    planar, tmp_path, cli_run, capsys
):
    text = planar.read_text()
    mesh = '<visual><geometry><mesh filename="package://nowhere/{0}.stl"/></geometry></visual>'
    for k, link in enumerate(("q4_link", "q5_link")):
        assert f'<link name="{link}"/>' in text
        text = text.replace(f'<link name="{link}"/>', f'<link name="{link}">{mesh.format(k)}</link>')
    path = tmp_path / "meshes.urdf"
    path.write_text(text)
    code, _, err = cli_run(["analyze", str(path), "--tip", "tool_link", "--q", "0,0,0,0,0", "--json"])
    assert code == 0 and err == ""  # analyze draws nothing
    common.load_robot(str(path), urdf={"tip": ("tool_link",)}, drawn=True)
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(
        f"warning: 2 meshes of {robots.build('bayle-planar').name} not found"
    )
