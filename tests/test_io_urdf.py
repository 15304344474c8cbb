"""URDF import on small hand-written files and on the built-in real robots: what is read, every error, the
command line, and the write → read round trip of every paper robot."""

from __future__ import annotations

import json
import logging
import math
import re
import warnings

import numpy as np
import pytest
from urdf_samples import husky, husky_tool

from mobman import dynamics as dyn
from mobman import kinematics as K
from mobman import redundancy as R
from mobman.cli import main
from mobman.errors import InputError, MobmanError, ModelError
from mobman.io.real_robots import REAL_ROBOTS, urdf_model
from mobman.io.urdf import UrdfWarning, inspect_urdf, load_urdf, read_urdf, urdf_tips, write_urdf
from mobman.model import robots
from mobman.model.platforms import DifferentialDrive

WHEEL = """
  <link name="{side}_wheel">
    <inertial><mass value="1.0"/><inertia ixx="0.01" iyy="0.01" izz="0.02" ixy="0" ixz="0" iyz="0"/></inertial>
    <collision><geometry><cylinder radius="0.1" length="0.04"/></geometry></collision>
  </link>
  <joint name="{side}_wheel_joint" type="continuous">
    <parent link="base_link"/><child link="{side}_wheel"/>
    <origin xyz="{x} {y} 0.1" rpy="-1.5707963267948966 0 0"/><axis xyz="0 0 1"/>
    <limit effort="5" velocity="8"/>
  </joint>"""


def _urdf(tmp_path, arm_joint="revolute", extra="", wheels=True, wheel_x=0.1, name="small.urdf", mesh=""):
    """A base, two wheels at x = wheel_x (half track 0.2), a caster, a 2-joint arm with a fixed tool link."""
    parts = [
        '<?xml version="1.0"?>\n<robot name="small">',
        '  <link name="base_footprint"/>',
        '  <link name="base_link"><inertial><mass value="20"/><origin xyz="0.05 0 0.2"/>'
        '<inertia ixx="1" iyy="1" izz="0.8" ixy="0" ixz="0" iyz="0"/></inertial>'
        f"{mesh}</link>",
        '  <joint name="base_joint" type="fixed"><parent link="base_footprint"/><child link="base_link"/>'
        "</joint>",
    ]
    if wheels:
        parts.append(WHEEL.format(side="right", x=wheel_x, y=-0.2))
        parts.append(WHEEL.format(side="left", x=wheel_x, y=0.2))
    parts += [
        '  <link name="caster"/>',
        '  <joint name="caster_joint" type="continuous"><parent link="base_link"/><child link="caster"/>'
        '<origin xyz="-0.3 0 0.05"/><axis xyz="0 0 1"/></joint>',
        '  <link name="link1"><inertial><mass value="2"/><origin xyz="0 0 0.1"/>'
        '<inertia ixx="0.02" iyy="0.02" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial>'
        '<visual><geometry><box size="0.1 0.1 0.2"/></geometry></visual></link>',
        f'  <joint name="j1" type="{arm_joint}"><parent link="base_link"/><child link="link1"/>'
        '<origin xyz="0.1 0 0.3" rpy="0 0 0.3"/><axis xyz="0 0 1"/>'
        '<limit lower="-2" upper="2" velocity="1.5" effort="20"/></joint>',
        '  <link name="link2"><inertial><mass value="1"/><origin xyz="0.2 0 0"/>'
        '<inertia ixx="0.01" iyy="0.02" izz="0.02" ixy="0" ixz="0" iyz="0"/></inertial></link>',
        '  <joint name="j2" type="revolute"><parent link="link1"/><child link="link2"/>'
        '<origin xyz="0 0 0.2" rpy="1.5707963267948966 0 0"/><axis xyz="0 0 1"/>'
        '<limit lower="-1" upper="1" velocity="2" effort="10"/></joint>',
        '  <link name="tool"><inertial><mass value="0.5"/><inertia ixx="0.001" iyy="0.001" izz="0.001" '
        'ixy="0" ixz="0" iyz="0"/></inertial></link>',
        '  <joint name="tool_joint" type="fixed"><parent link="link2"/><child link="tool"/>'
        '<origin xyz="0.4 0 0"/></joint>',
        extra,
        "</robot>",
    ]
    path = tmp_path / name
    path.write_text("\n".join(parts))
    return path


def test_small_urdf_is_read_as_written(tmp_path):
    model = read_urdf(_urdf(tmp_path), tip="tool")
    robot, summary = model.robot, model.summary
    assert robot.platform.wheel_radius == 0.1 and robot.platform.half_track == pytest.approx(0.2)
    assert robot.platform.wheel_speed_max == 8.0
    assert summary.wheels == ("right_wheel_joint", "left_wheel_joint")
    assert summary.reference_point == pytest.approx((0.1, 0.0))
    assert summary.passive == ("right_wheel_joint", "left_wheel_joint", "caster_joint")
    assert summary.folded == ("base_joint", "tool_joint")
    arm = robot.arms[0]
    assert [j.name for j in arm.joints] == ["j1", "j2"]
    assert [(j.lower, j.upper, j.velocity_max, j.effort_max) for j in arm.joints] == [
        (-2, 2, 1.5, 20),
        (-1, 1, 2, 10),
    ]
    # the tool link's 0.5 kg at (0.4, 0, 0) is lumped into link2: mass 1.5, com at (1·0.2 + 0.5·0.4)/1.5
    inertial = arm.joints[1].inertial
    assert inertial.mass == pytest.approx(1.5)
    assert inertial.com == pytest.approx((0.4 / 1.5, 0.0, 0.0))
    assert len(arm.joints[0].visuals) == 1 and arm.joints[0].visuals[0].kind == "box"
    # effort limits: wheels then joints; the platform body holds base and wheels (20 + 2 kg)
    assert model.effort_limits == (5.0, 5.0, 20.0, 10.0)
    assert model.body.mass == pytest.approx(22.0) and model.wheel.I_w == pytest.approx(0.02)
    # tool position at q = 0, by hand: the platform frame is at the axle midpoint (0.1, 0) of base_footprint;
    # j1 at (0.1, 0, 0.3) turned 0.3 rad; j2 0.2 above it; the tool 0.4 along j2's x (= j1's x after the roll)
    c, s = math.cos(0.3), math.sin(0.3)
    expected = np.array([0.0 + 0.4 * c, 0.4 * s, 0.5])
    assert np.asarray(K.forward(robot, np.zeros(robot.n_q))) == pytest.approx(expected, abs=1e-12)


def test_platform_choices_and_overrides(tmp_path):
    path = _urdf(tmp_path)
    omni = load_urdf(path, tip="tool", platform="omnidirectional")
    assert type(omni.platform).__name__ == "Omnidirectional"
    forced = load_urdf(path, tip="tool", wheel_radius=0.05, half_track=0.3, name="mine")
    assert (forced.platform.wheel_radius, forced.platform.half_track, forced.name) == (0.05, 0.3, "mine")
    named = load_urdf(path, tip="tool", wheels=("left_wheel_joint", "right_wheel_joint"))
    assert named.platform.half_track == pytest.approx(0.2)
    locked = read_urdf(path, tip="tool", locked={"j1": 0.5})
    assert [j.name for j in locked.robot.arms[0].joints] == ["j2"]
    assert locked.summary.locked == (("j1", 0.5),)
    assert "passive joints" in str(inspect_urdf(path, tip="tool"))


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"tip": "nowhere"}, "no link named 'nowhere'"),
        ({"tip": "base_link", "base": "tool"}, "tip link 'base_link' is not below base link 'tool'"),
        ({"tip": "tool", "platform": "tank"}, "platform must be one of"),
        ({"tip": "tool", "wheels": ("j1", "caster_joint")}, "common horizontal axle"),
        ({"tip": "tool", "locked": {"base_joint": 0.0}}, "'base_joint' is not a moving joint"),
    ],
)
def test_bad_options_name_the_link_or_joint(tmp_path, kwargs, message):
    with pytest.raises(ModelError, match=message):
        load_urdf(_urdf(tmp_path), **kwargs)


def test_no_wheel_pair_lists_the_continuous_joints(tmp_path):
    with pytest.raises(ModelError, match="continuous joints seen: caster_joint"):
        load_urdf(_urdf(tmp_path, wheels=False), tip="tool")


@pytest.mark.parametrize(
    "arm_joint, extra, message",
    [
        ("floating", "", "'j1' on the chain to 'tool' is floating"),
        ("planar", "", "'j1' on the chain to 'tool' is planar"),
    ],
)
def test_unsupported_joints_on_the_chain(tmp_path, arm_joint, extra, message):
    with pytest.raises(ModelError, match=message):
        load_urdf(_urdf(tmp_path, arm_joint=arm_joint, extra=extra), tip="tool")


def test_mimic_joint_on_the_chain(tmp_path):
    path = _urdf(tmp_path)
    text = path.read_text().replace(
        '<limit lower="-1" upper="1" velocity="2" effort="10"/></joint>',
        '<limit lower="-1" upper="1" velocity="2" effort="10"/><mimic joint="j1" multiplier="1"/></joint>',
    )
    path.write_text(text)
    with pytest.raises(ModelError, match="'j2' on the chain to 'tool' mimics 'j1'"):
        load_urdf(path, tip="tool")


def test_shared_joint_of_two_tips_must_be_locked(tmp_path):
    extra = (
        '<link name="other"/><joint name="j3" type="revolute"><parent link="link1"/><child link="other"/>'
        '<axis xyz="1 0 0"/><limit lower="-1" upper="1" velocity="1" effort="1"/></joint>'
    )
    path = _urdf(tmp_path, extra=extra)
    with pytest.raises(ModelError, match="'j1' is on the chains to 'tool' and 'other'.*locked="):
        load_urdf(path, tip=["tool", "other"])
    robot = load_urdf(path, tip=["tool", "other"], locked={"j1": 0.0})
    assert [a.n_joints for a in robot.arms] == [1, 1]


def test_bad_files(tmp_path):
    with pytest.raises(InputError, match="no such file"):
        load_urdf(tmp_path / "missing.urdf")
    xacro = tmp_path / "robot.urdf.xacro"
    xacro.write_text("<robot/>")
    with pytest.raises(InputError, match="xacro robot.urdf.xacro > robot.urdf"):
        load_urdf(xacro)
    macros = tmp_path / "macros.urdf"
    macros.write_text('<robot xmlns:xacro="http://www.ros.org/wiki/xacro"><xacro:macro name="m"/></robot>')
    with pytest.raises(InputError, match="xacro macros; expand it"):
        load_urdf(macros)
    other = tmp_path / "notes.urdf"
    other.write_text("just text")
    with pytest.raises(InputError, match="not a URDF file"):
        load_urdf(other)


def test_missing_meshes_are_listed_and_said_once_where_drawn(tmp_path, caplog):
    mesh = "".join(
        f'<visual><geometry><mesh filename="package://nowhere/meshes/{part}.stl"/></geometry></visual>'
        for part in ("body", "cover", "body")
    )
    with warnings.catch_warnings(), caplog.at_level(logging.DEBUG - 1):
        warnings.simplefilter("error")  # no warning per mesh
        model = read_urdf(_urdf(tmp_path, mesh=mesh), tip="tool")
    assert not [r for r in caplog.records if r.levelno >= logging.WARNING]  # nor yourdfpy's log line per mesh
    assert model.summary.missing_meshes == (
        "package://nowhere/meshes/body.stl",
        "package://nowhere/meshes/cover.stl",
    )
    assert model.robot.platform_visuals == ()
    note = model.summary.mesh_note()
    assert note.startswith(f"2 meshes of small not found from {tmp_path}") and "\n" not in note
    assert inspect_urdf(_urdf(tmp_path), tip="tool").mesh_note() is None


def test_cli_reads_a_urdf_file_and_reports_errors_in_one_line(tmp_path, capsys):
    path = _urdf(tmp_path)
    main(["analyze", str(path), "--tip", "tool", "--json", "--q", "0,0,0,0.3,0.2"])
    data = json.loads(capsys.readouterr().out)
    assert data["coordinates"] == ["x", "y", "theta", "j1", "j2"]
    with pytest.raises(SystemExit) as exit_info:
        main(["analyze", str(path), "--tip", "nowhere"])
    assert exit_info.value.code == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "no link named 'nowhere'" in err[0]


# --- the built-in real robots ---------------------------------------------------------------------


def test_tiago_wheels_and_chain_from_its_urdf():
    model = urdf_model("tiago")
    platform = model.robot.platform
    assert platform.wheel_radius == pytest.approx(0.0985, abs=1e-12)
    assert 2 * platform.half_track == pytest.approx(0.4044, abs=1e-12)
    assert platform.wheel_speed_max == pytest.approx(10.152284264)
    assert model.summary.chains[0][0] == "torso_lift_joint" and len(model.summary.chains[0]) == 8
    assert model.robot.arms[0].joints[0].kind == "prismatic"
    assert model.summary.missing_meshes == ()
    assert all(v.kind != "mesh" or v.filename.startswith("/") for v in model.robot.platform_visuals)


def test_stretch_and_tiago_dual_from_their_urdfs():
    stretch = urdf_model("stretch").robot
    assert stretch.platform.wheel_radius == pytest.approx(0.0508, abs=1e-4)  # the collision mesh's half width
    assert [j.kind for j in stretch.arms[0].joints] == ["prismatic"] * 5 + ["revolute"] * 3
    dual = urdf_model("tiago-dual")
    assert [a.n_joints for a in dual.robot.arms] == [7, 7]
    assert dual.summary.locked == (("torso_lift_joint", 0.15),)
    assert {"suspension_right_joint", "suspension_left_joint"} <= set(dual.summary.passive)


def test_robots_command_lists_the_real_robots(capsys):
    main(["robots", "--json"])
    entries = {e["name"]: e for e in json.loads(capsys.readouterr().out)["robots"]}
    assert set(REAL_ROBOTS) <= set(entries)
    assert entries["tiago"]["coordinates"][3] == "torso_lift_joint"


def test_no_warning_on_the_built_in_files():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        for spec in REAL_ROBOTS.values():
            read_urdf(spec.path(), tip=spec.tips, base=spec.base, locked=dict(spec.locked))


# --- write → read round trips ---------------------------------------------------------------------

PAPER_ROBOTS = [
    "bayle-planar",
    "bayle-rrp",
    "manus-platform",
    "korayem-planar",
    "tchon-car-rtr",
    "yamamoto-dual-arm",
]


def _read_back(robot, path):
    platform = {"CarLike": "car", "Omnidirectional": "omnidirectional"}.get(
        type(robot.platform).__name__, "auto"
    )
    return load_urdf(path, tip=urdf_tips(robot), platform=platform).with_task(robot.task)


def _motion_map(robot) -> np.ndarray:
    """T with (platform q, motion variables) = T q: identity on the platform, each arm's coupling C."""
    t = np.eye(robot.n_q)
    for i, arm in enumerate(robot.arms):
        s = robot.arm_slice(i)
        t[s, s] = arm.coupling_matrix
    return t


@pytest.mark.parametrize("name", PAPER_ROBOTS)
def test_paper_robots_round_trip_through_urdf(name, tmp_path):
    robot = robots.build(name)
    back = _read_back(robot, write_urdf(robot, tmp_path / f"{name}.urdf"))
    assert type(back.platform) is type(robot.platform) and back.n_q == robot.n_q
    q = R.sample_configurations(robot, 64, seed=3)
    t = _motion_map(robot)  # a coupled arm is written in its motion variables
    q_back = q @ t.T
    assert np.abs(np.asarray(K.forward(back, q_back)) - np.asarray(K.forward(robot, q))).max() < 1e-12
    jbar, jbar_back = np.asarray(K.reduced_jacobian(robot, q)), np.asarray(K.reduced_jacobian(back, q_back))
    n_p = robot.platform.n_eta
    t_eta = np.eye(robot.n_eta)
    t_eta[n_p:, n_p:] = t[robot.n_platform :, robot.n_platform :]
    assert np.abs(jbar_back @ t_eta - jbar).max() < 1e-12
    if isinstance(robot.platform, DifferentialDrive) and robot.platform.wheel_speed_max is not None:
        assert back.platform == robot.platform  # the per-wheel speed limit is written too


def test_mass_matrix_round_trips_through_urdf(tmp_path):
    """Yamamoto & Yun's robot with its Table 1–2 inertials: platform body, wheels and links written and read."""
    model = dyn.yamamoto_model()
    path = write_urdf(model.robot, tmp_path / "yamamoto.urdf", model.body, model.wheel)
    back = read_urdf(path, tip=urdf_tips(model.robot))
    assert back.body.mass == pytest.approx(model.body.mass + 2 * model.wheel.mass, rel=1e-12)
    back_model = dyn.DynamicModel.from_urdf(back, model.gravity)
    q = R.sample_configurations(model.robot, 16, seed=4)
    m, m_back = np.asarray(dyn.mass_matrix(model, q)), np.asarray(dyn.mass_matrix(back_model, q))
    assert np.abs(m_back - m).max() < 1e-12 * np.abs(m).max()


def test_tiago_round_trips_through_urdf(tmp_path):
    model = urdf_model("tiago")
    path = write_urdf(model.robot, tmp_path / "tiago.urdf", model.body, model.wheel)
    back = read_urdf(path, tip=urdf_tips(model.robot))
    assert back.robot.platform == model.robot.platform
    assert back.wheel.I_w == pytest.approx(model.wheel.I_w, rel=1e-12)
    assert back.body.inertia_z == pytest.approx(model.body.inertia_z, rel=1e-12)
    q = R.sample_configurations(model.robot, 32, seed=5)
    jbar = np.asarray(K.reduced_jacobian(model.robot, q))
    assert np.abs(np.asarray(K.reduced_jacobian(back.robot, q)) - jbar).max() < 1e-12


def test_missing_extra_gives_the_install_line(monkeypatch, capsys):
    from mobman.io import real_robots

    absent = real_robots.RealRobot("no-such-distribution", "robot.urdf", ("tool",), "base_link")
    with pytest.raises(ModelError, match=r"no-such-distribution: pip install 'mobman\[robots\]'"):
        absent.path()
    monkeypatch.setitem(real_robots.REAL_ROBOTS, "stretch", absent)
    main(["robots", "--json"])
    entries = {e["name"]: e for e in json.loads(capsys.readouterr().out)["robots"]}
    assert entries["stretch"]["summary"].endswith("needs pip install 'mobman[robots]'")
    assert entries["stretch"]["coordinates"] == []


# --- the ground, wheels that are not joints, virtual base joints, mimic joints ----------------------------


def _configurations(n: int, n_q: int, seed: int) -> np.ndarray:
    q = np.random.default_rng(seed).uniform(-np.pi, np.pi, (n, n_q))
    q[:4, 2] = [np.pi / 2, -np.pi / 2, np.pi, -np.pi]  # θ at ±π/2 and ±π
    q[:4, -1] = [np.pi / 2, -np.pi / 2, np.pi, 0.0]
    return q


def test_a_skid_steer_s_platform_frame_is_on_the_ground_its_wheels_define(tmp_path):
    model = read_urdf(
        husky(tmp_path),
        tip="tool",
        base="base_link",
        platform="skid_steer",
        platform_options={"x_icr": 0.05, "track_factor": 1.5},
    )
    platform = model.robot.platform
    assert (platform.wheel_radius, platform.x_icr, platform.track_factor) == (0.1651, 0.05, 1.5)
    assert platform.wheelbase == pytest.approx(0.512, abs=1e-15)
    assert platform.half_track == pytest.approx(0.2854, abs=1e-15)
    height = 0.1651 - 0.03282
    assert model.summary.base_height == pytest.approx(height, abs=1e-15)
    assert f"platform frame on the ground, {height:.6g} m below base_link" in str(model.summary)
    q = _configurations(64, model.robot.n_q, 0)
    xi = np.asarray(K.forward(model.robot, q))
    np.testing.assert_allclose(xi, husky_tool(q, height), rtol=0, atol=1e-12)
    # a given wheel radius is the wheels' too: the ground moves with it
    bigger = read_urdf(husky(tmp_path), tip="tool", base="base_link", platform="skid_steer", wheel_radius=0.2)
    assert bigger.summary.base_height == pytest.approx(0.2 - 0.03282, abs=1e-15)


@pytest.mark.parametrize("wheels", ["fixed", "none"])
def test_a_differential_drive_without_wheel_joints_takes_the_values_given(tmp_path, wheels):
    path = husky(tmp_path, wheels)
    with pytest.raises(ModelError, match="--platform-option wheel_radius=R --platform-option half_track=B"):
        load_urdf(path, tip="tool", base="base_link", platform="differential")
    options = {"wheel_radius": 0.1651, "half_track": 0.2854, "wheel_speed_max": 10.0}
    with pytest.warns(UrdfWarning, match="no wheel joint of the file gives the ground under 'base_link'"):
        model = read_urdf(
            path, tip="tool", base="base_link", platform="differential", platform_options=options
        )
    assert model.robot.platform == DifferentialDrive(**options)
    assert model.summary.base_height is None and len(model.summary.notes) == 1
    assert "platform frame at the height of base_link" in str(model.summary)
    q = _configurations(64, model.robot.n_q, 1)
    np.testing.assert_allclose(np.asarray(K.forward(model.robot, q)), husky_tool(q, 0.0), rtol=0, atol=1e-12)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # the height given: nothing to say
        placed = read_urdf(
            path, tip="tool", base="base_link", platform_options={**options, "base_height": 0.4}
        )
    assert placed.summary.base_height == 0.4 and placed.summary.notes == ()
    np.testing.assert_allclose(np.asarray(K.forward(placed.robot, q)), husky_tool(q, 0.4), rtol=0, atol=1e-12)


@pytest.mark.parametrize(
    ("options", "message"),
    [
        (
            {"x_icr": 0.1},
            r"platform option 'x_icr': not a parameter of DifferentialDrive .*allowed: wheel_radius",
        ),
        ({"wheel_radius": -0.1}, "wheel_radius must be a finite number > 0, got -0.1"),
        ({"base_height": math.nan}, "platform option base_height: must be a finite number"),
    ],
)
def test_bad_platform_options_name_the_key(tmp_path, options, message):
    with pytest.raises(ModelError, match=message):
        load_urdf(_urdf(tmp_path), tip="tool", platform_options=options)


def test_a_wheel_without_geometry_names_the_option_that_gives_its_radius(tmp_path):
    path = _urdf(tmp_path)
    collision = '<collision><geometry><cylinder radius="0.1" length="0.04"/></geometry></collision>'
    path.write_text(path.read_text().replace(collision, ""))
    with pytest.raises(ModelError, match=r"wheel radius; give it: --platform-option wheel_radius=R"):
        load_urdf(path, tip="tool")
    assert load_urdf(path, tip="tool", platform_options={"wheel_radius": 0.1}).platform.wheel_radius == 0.1


def _virtual_base(tmp_path) -> str:
    """A simulator export: world → joint_x, joint_y (prismatic) → joint_rz (revolute) → base_link, and the
    small file's wheels and arm below base_link."""
    text = _urdf(tmp_path).read_text()
    virtual = "".join(
        f'<link name="{child}"/><joint name="{name}" type="{kind}"><parent link="{parent}"/>'
        f'<child link="{child}"/><axis xyz="{axis}"/><limit lower="-10" upper="10" velocity="1" effort="1"/></joint>'
        for name, kind, axis, parent, child in [
            ("joint_x", "prismatic", "1 0 0", "world", "x_link"),
            ("joint_y", "prismatic", "0 1 0", "x_link", "y_link"),
        ]
    )
    virtual += (
        '<joint name="joint_rz" type="revolute"><parent link="y_link"/><child link="base_footprint"/>'
        '<axis xyz="0 0 1"/><limit lower="-10" upper="10" velocity="1" effort="1"/></joint>'
    )
    path = tmp_path / "export.urdf"
    path.write_text(
        text.replace(
            '<link name="base_footprint"/>', f'<link name="world"/><link name="base_footprint"/>{virtual}'
        )
    )
    return path


def test_virtual_base_joints_are_refused_naming_the_base_below_them(tmp_path):
    path = _virtual_base(tmp_path)
    with pytest.raises(
        ModelError,
        match=r"joints joint_x, joint_y, joint_rz on the chain to 'tool' move 'world'.*--base base_footprint",
    ):
        load_urdf(path, tip="tool", base="world")
    below = load_urdf(path, tip="tool")  # from base_footprint: the small robot itself
    q = _configurations(16, below.n_q, 2)
    np.testing.assert_array_equal(K.forward(below, q), K.forward(load_urdf(_urdf(tmp_path), tip="tool"), q))


MIMIC = """<?xml version="1.0"?>
<robot name="mimic">
  <link name="base_link"/>
  <link name="wheel_right"><collision><geometry><sphere radius="0.12"/></geometry></collision></link>
  <joint name="wheel_right_joint" type="continuous"><parent link="base_link"/><child link="wheel_right"/>
    <origin xyz="0.05 -0.25 0.02"/><axis xyz="0 1 0"/></joint>
  <link name="wheel_left"><collision><geometry><sphere radius="0.12"/></geometry></collision></link>
  <joint name="wheel_left_joint" type="continuous"><parent link="base_link"/><child link="wheel_left"/>
    <origin xyz="0.05 0.25 0.02"/><axis xyz="0 1 0"/></joint>
  <link name="lift_link"/>
  <joint name="arm_lift_joint" type="prismatic"><parent link="base_link"/><child link="lift_link"/>
    <origin xyz="0.1 0 0.3"/><axis xyz="0 0 1"/><limit lower="0" upper="0.5" velocity="0.1" effort="100"/></joint>
  <link name="hand"/>
  <joint name="wrist_joint" type="revolute"><parent link="lift_link"/><child link="hand"/>
    <origin xyz="0.2 0 0.1" rpy="0.3 0 0"/><axis xyz="0 0 1"/><limit lower="-3" upper="3" velocity="1" effort="10"/></joint>
  <link name="torso_link"/>
  <joint name="torso_lift_joint" type="prismatic"><parent link="base_link"/><child link="torso_link"/>
    <origin xyz="-0.1 0 0.4"/><axis xyz="0 0 1"/><limit lower="0" upper="0.3" velocity="0.1" effort="100"/>
    <mimic joint="arm_lift_joint" multiplier="0.5" offset="0.01"/></joint>
  <link name="head"/>
  <joint name="head_tilt_joint" type="revolute"><parent link="torso_link"/><child link="head"/>
    <origin xyz="0.05 0 0.2"/><axis xyz="0 1 0"/><limit lower="-1" upper="1" velocity="1" effort="1"/></joint>
</robot>
"""
"""HSR-like: the torso follows the arm lift at half its travel (plus 0.01 m), off the chain to the hand;
base_link 0.12 − 0.02 = 0.1 m above the ground, the axle midpoint at x = 0.05 m."""


def test_a_mimic_joint_follows_a_locked_leader_as_pinocchio_does(tmp_path):
    path = tmp_path / "mimic.urdf"
    path.write_text(MIMIC)
    model = read_urdf(path, tip=["hand", "head"], base="base_link", locked={"arm_lift_joint": 0.2})
    assert model.summary.mimics == (("torso_lift_joint", "arm_lift_joint", pytest.approx(0.11, abs=1e-15)),)
    assert model.summary.base_height == pytest.approx(0.1, abs=1e-15) and model.summary.notes == ()
    robot = model.robot
    import pinocchio

    pin_model = pinocchio.buildModelFromUrdf(str(path), mimic=True)
    data = pin_model.createData()
    q = _configurations(32, robot.n_q, 3)
    q[:, 3] = np.clip(q[:, 3], -3, 3)
    q[:, 4] = np.clip(q[:, 4], -1, 1)
    links = K.frames(robot, q).links
    for k, qk in enumerate(q):
        v = np.zeros(pin_model.nq)
        for name, value in [("arm_lift_joint", 0.2), ("wrist_joint", qk[3]), ("head_tilt_joint", qk[4])]:
            v[pin_model.idx_qs[pin_model.getJointId(name)]] = value
        pinocchio.framesForwardKinematics(pin_model, data, v)
        # the platform frame at (x, y, θ) is base_link shifted to the axle midpoint on the ground
        world = _platform_pose(qk[:3]) @ _translation(-0.05, 0.0, 0.1)
        for arm, frame in enumerate(("hand", "head")):
            expected = world @ data.oMf[pin_model.getFrameId(frame)].homogeneous
            np.testing.assert_allclose(np.asarray(links[arm][1][k, -1]), expected[:3, 3], rtol=0, atol=1e-12)
            np.testing.assert_allclose(np.asarray(links[arm][0][k, -1]), expected[:3, :3], rtol=0, atol=1e-12)


def _platform_pose(q_p: np.ndarray) -> np.ndarray:
    """The platform frame's pose in the world at q_p = (x, y, θ)."""
    t = _translation(q_p[0], q_p[1], 0.0)
    c, s = math.cos(q_p[2]), math.sin(q_p[2])
    t[:2, :2] = [[c, -s], [s, c]]
    return t


def _translation(x: float, y: float, z: float) -> np.ndarray:
    t = np.eye(4)
    t[:3, 3] = (x, y, z)
    return t


def test_a_mimic_joint_of_an_arm_coordinate_off_the_chain_follows_it_as_pinocchio_does(tmp_path):
    """The torso (and the head hanging from it) rise with the arm lift at half its travel: a Follower body,
    whose frame agrees with Pinocchio's mimic joint at random configurations, limits included."""
    import pinocchio

    path = tmp_path / "mimic.urdf"
    path.write_text(MIMIC)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # nothing is held that should follow: no note
        model = read_urdf(path, tip="hand", base="base_link")
    assert model.summary.mimics == () and "torso_lift_joint" not in model.summary.passive
    assert model.summary.followers == (("torso_lift_joint", "arm_lift_joint", 0.5, pytest.approx(0.01)),)
    assert "torso_lift_joint = 0.5 · arm_lift_joint + 0.01" in str(model.summary)
    robot = model.robot
    (follower,) = robot.followers
    assert (follower.leader, follower.multiplier, follower.parent) == (3, 0.5, (-1, 0))
    (described,) = robot.describe()["followers"]
    assert described == {
        "joint": "torso_lift_joint",
        "leader": "arm_lift_joint",
        "multiplier": 0.5,
        "offset": pytest.approx(0.01),
    }
    pin_model = pinocchio.buildModelFromUrdf(str(path), mimic=True)
    data = pin_model.createData()
    q = _configurations(32, robot.n_q, 4)
    q[:, 3] = np.random.default_rng(5).uniform(0.0, 0.5, 32)
    q[:2, 3] = [0.0, 0.5]  # the lift at its limits
    followers = K.frames(robot, q).followers[0]
    for k, qk in enumerate(q):
        v = np.zeros(pin_model.nq)
        for name, value in [("arm_lift_joint", qk[3]), ("wrist_joint", qk[4])]:
            v[pin_model.idx_qs[pin_model.getJointId(name)]] = value
        pinocchio.framesForwardKinematics(pin_model, data, v)
        expected = _platform_pose(qk[:3]) @ _translation(-0.05, 0.0, 0.1)
        expected = expected @ data.oMf[pin_model.getFrameId("torso_link")].homogeneous
        np.testing.assert_allclose(np.asarray(followers[1][k]), expected[:3, 3], rtol=0, atol=1e-12)
        np.testing.assert_allclose(np.asarray(followers[0][k]), expected[:3, :3], rtol=0, atol=1e-12)


def test_a_mimic_joint_of_an_arm_coordinate_on_a_chain_is_refused(tmp_path):
    path = tmp_path / "mimic.urdf"
    path.write_text(MIMIC)
    with pytest.raises(
        ModelError, match="'torso_lift_joint' on the chain to 'head' mimics 'arm_lift_joint'.*lock"
    ):
        read_urdf(path, tip=["hand", "head"], base="base_link")


def test_a_follower_is_written_back_as_a_mimic_joint(tmp_path):
    path = tmp_path / "mimic.urdf"
    path.write_text(MIMIC.replace('<link name="head"/>', HEAD))
    robot = read_urdf(path, tip="hand", base="base_link").robot
    written = write_urdf(robot, tmp_path / "written.urdf")
    again = read_urdf(written, tip=urdf_tips(robot), base="base_footprint").robot
    assert again.followers[0].multiplier == 0.5 and again.followers[0].leader == 3
    assert len(again.followers[0].joint.visuals) == 1
    q = _configurations(8, robot.n_q, 6)
    ours, theirs = K.frames(robot, q).followers[0], K.frames(again, q).followers[0]
    np.testing.assert_allclose(np.asarray(theirs[1]), np.asarray(ours[1]), rtol=0, atol=1e-12)
    np.testing.assert_allclose(np.asarray(theirs[0]), np.asarray(ours[0]), rtol=0, atol=1e-12)


HEAD = """<link name="head"><visual><geometry><box size="0.2 0.2 0.2"/></geometry></visual>
    <collision><geometry><box size="0.2 0.2 0.2"/></geometry></collision></link>"""
"""A head of 20 cm on MIMIC's torso (visual and collision box)."""


# --- files that lie: one line naming the file and what is wrong ---------------------------------------


def _edited(tmp_path, old: str, new: str, name: str = "lying.urdf"):
    path = _urdf(tmp_path)
    text = path.read_text()
    assert text.count(old) >= 1
    (tmp_path / name).write_text(text.replace(old, new, 1))
    return tmp_path / name


LIES = {
    "velocity NaN": ('velocity="1.5"', 'velocity="nan"', "joint 'j1': limit velocity is NaN"),
    "velocity < 0": ('velocity="1.5"', 'velocity="-1"', "joint 'j1': limit velocity must be ≥ 0"),
    "effort < 0": ('effort="20"', 'effort="-3"', "joint 'j1': limit effort must be ≥ 0"),
    "mass < 0": ('<mass value="2"/>', '<mass value="-2"/>', "link 'link1': mass must be a finite number ≥ 0"),
    "link twice": ('<link name="tool">', '<link name="link1">', "link names used twice: 'link1'"),
    "joint twice": ('name="j2"', 'name="j1"', "joint names used twice: 'j1'"),
    "origin NaN": ('<origin xyz="0 0 0.2"', '<origin xyz="nan 0 0.2"', r"joint 'j2': origin \(xyz, rpy\)"),
    "two parents": (
        "</robot>",
        '<joint name="back" type="fixed"><parent link="link2"/><child link="link1"/></joint></robot>',
        "link 'link1' is the child of two joints, 'j1' and 'back'",
    ),
    "cycle": (
        '<parent link="base_link"/><child link="link1"/>',
        '<parent link="link2"/><child link="link1"/>',
        r"cycle, link 'link1' is its own ancestor \(link1 → link2 → link1\)",
    ),
    "mesh outside": (
        '<box size="0.1 0.1 0.2"/>',
        '<mesh filename="file:///etc/passwd"/>',
        "mesh 'file:///etc/passwd' is /etc/passwd, not a mesh file",
    ),
    "wheel mesh outside": (
        '<cylinder radius="0.1" length="0.04"/>',
        '<mesh filename="file:///etc/passwd"/>',
        "link 'right_wheel': mesh 'file:///etc/passwd' is /etc/passwd, not a mesh file",
    ),
}


@pytest.mark.parametrize("lie", list(LIES))
def test_a_file_that_lies_is_refused_naming_the_file_and_what_is_wrong(tmp_path, lie):
    old, new, message = LIES[lie]
    path = _edited(tmp_path, old, new)
    with pytest.raises(MobmanError) as info:
        load_urdf(path, tip="tool")
    text = str(info.value)
    assert "\n" not in text
    assert re.search(message, text), text
    assert text.startswith(f"{path}: "), text


def test_a_truncated_file_is_not_repaired_and_yourdfpy_says_nothing(tmp_path, caplog):
    text = _urdf(tmp_path).read_text()
    path = tmp_path / "truncated.urdf"
    path.write_text(text[: 2 * len(text) // 3])
    with caplog.at_level(logging.DEBUG), pytest.raises(InputError, match=rf"{path}: not well-formed XML \("):
        load_urdf(path, tip="tool")
    assert not [r for r in caplog.records if r.name.startswith("yourdfpy")]


def test_a_mesh_is_a_mesh_file_in_the_robot_s_folder_or_package(tmp_path):
    package = tmp_path / "robot_description"
    (package / "urdf").mkdir(parents=True)
    (package / "meshes").mkdir()
    (package / "meshes" / "body.stl").write_bytes(b"solid body\nendsolid body\n")
    (package / "meshes" / "notes.txt").write_text("not a mesh")
    (tmp_path / "outside.stl").write_bytes(b"solid x\nendsolid x\n")

    def visual(filename: str):
        mesh = f'<visual><geometry><mesh filename="{filename}"/></geometry></visual>'
        return read_urdf(_urdf(package / "urdf", mesh=mesh), tip="tool").robot.platform_visuals

    found = visual("package://robot_description/meshes/body.stl")
    assert [v.filename for v in found] == [str(package / "meshes" / "body.stl")]
    assert visual(str(tmp_path / "outside.stl"))[0].filename == str(
        tmp_path / "outside.stl"
    )  # absolute: as named
    with pytest.raises(InputError, match=r"mesh '\.\./\.\./outside\.stl' is .*outside the robot's folder"):
        visual("../../outside.stl")
    with pytest.raises(InputError, match=r"outside the robot's folder .*robot_description"):
        visual("package://robot_description/meshes/../../../outside.stl")
    with pytest.raises(
        InputError, match=r"mesh 'package://robot_description/\.\./outside\.stl' names no file"
    ):
        visual("package://robot_description/../outside.stl")  # yourdfpy's resolver fails on it
    with pytest.raises(InputError, match=r"notes\.txt, not a mesh file \(\.stl, "):
        visual("package://robot_description/meshes/notes.txt")


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"tip": 5}, "tip: a link's name or a list of them, got 5"),
        ({"tip": ["tool", 5]}, "tip: a link's name or a list of them, got 5"),
        ({"tip": "tool", "locked": {"j1": "abc"}}, "locked: j1 must be a number"),
        ({"tip": "tool", "locked": ["j1"]}, "locked: a mapping of joint names to values"),
    ],
)
def test_options_of_the_wrong_type_are_model_errors(tmp_path, kwargs, message):
    with pytest.raises(ModelError, match=re.escape(message)):
        load_urdf(_urdf(tmp_path), **kwargs)


def test_a_path_of_bytes_is_an_input_error(tmp_path):
    with pytest.raises(InputError, match="path must be a URDF file's path"):
        load_urdf(str(_urdf(tmp_path)).encode(), tip="tool")


def test_a_velocity_limit_of_zero_is_no_limit_as_urdf_writers_mean_it_and_says_so(tmp_path):
    with pytest.warns(UrdfWarning, match="velocity limit 0 read as none given .*: joint 'j1'$"):
        robot = load_urdf(_edited(tmp_path, 'velocity="1.5"', 'velocity="0"'), tip="tool")
    assert robot.arms[0].joints[0].velocity_max is None


def test_a_file_changed_after_a_reading_is_read_again(tmp_path):
    path = husky(tmp_path)
    options = {"tip": "tool", "base": "base_link", "platform": "skid_steer"}
    assert read_urdf(path, **options).robot.arms[0].joints[0].upper == 0.5
    path.write_text(path.read_text().replace('upper="0.5" velocity="0.1"', 'upper="0.25" velocity="0.1"'))
    assert read_urdf(path, **options).robot.arms[0].joints[0].upper == 0.25


def test_a_follower_s_collision_shapes_rise_with_its_leader(tmp_path):
    """The head box on MIMIC's torso, under a ceiling: lifting the arm by 0.2 m raises the head by 0.1 m, so the
    head's distance to the ceiling falls by 0.1 m, and its distance rate is half the lift's."""
    from mobman import collision
    from mobman.io.urdf import collision_shapes
    from mobman.model.collision_model import CollisionModel
    from mobman.model.scene import Obstacle, Scene

    path = tmp_path / "mimic.urdf"
    path.write_text(MIMIC.replace('<link name="head"/>', HEAD))
    model = read_urdf(path, tip="hand", base="base_link")
    shapes = collision_shapes(model)
    assert [s.kind for s in shapes[(-2, 0)]] == ["box"]
    cover = CollisionModel.from_shapes(model.robot, {(-2, 0): shapes[(-2, 0)]}, tolerance=0.01)
    ceiling = Scene((Obstacle("ceiling", "box", (4.0, 4.0, 0.1), (0.0, 0.0, 1.5)),))
    q = np.array([[0.0, 0.0, 0.0, 0.1, 0.0], [0.0, 0.0, 0.0, 0.3, 0.0]])
    out = collision.distances(cover, ceiling, q)
    low, high = out.distance.min(axis=1)
    assert low - high == pytest.approx(0.1, abs=1e-9)
    closest = int(np.argmin(out.distance[1]))
    np.testing.assert_allclose(
        out.rows[1, closest, 2], -0.5, atol=1e-9
    )  # ḋ = −½ q̇_lift (η: v, ω, lift, wrist)
