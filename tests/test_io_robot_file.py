"""Robot description files (mobman.io.robot_file): the same robot as a built-in one, a built-in robot's params
(its arm's mount too), use from the command line and from spec files, and one-line errors naming the field."""

import json
from pathlib import Path

import numpy as np
import pytest

from mobman import kinematics as K
from mobman.cli import main
from mobman.errors import InputError
from mobman.io import robot_file
from mobman.model import Mount, robots
from mobman.model.tasks import Position

EXAMPLE = Path(__file__).resolve().parents[1] / "docs" / "examples" / "planar_robot.toml"


def test_example_file_is_bayle_planar():
    """The example file describes bayle_planar's geometry: same ξ and J̄ at random configurations."""
    robot = robot_file.load(EXAMPLE)
    reference = robots.bayle_planar().with_task(Position("xy"))
    q = np.random.default_rng(1).uniform(-np.pi, np.pi, (50, 5))
    np.testing.assert_allclose(K.forward(robot, q), K.forward(reference, q), atol=1e-12)
    np.testing.assert_allclose(K.reduced_jacobian(robot, q), K.reduced_jacobian(reference, q), atol=1e-12)
    np.testing.assert_allclose(robot.velocity_limits, [0.5, 1.0, 1.5708, 1.5708])


def test_two_arms_mounts_and_modified_dh(tmp_path):
    path = tmp_path / "two.toml"
    path.write_text(
        """
name = "two-arms"
[platform]
kind = "car"
length = 1.2
[[arms]]
convention = "modified-dh"
table = [[0.0, 0.0, 0.0, 0.3], [1.5707963267948966, 0.0, 0.0, 0.0]]
kinds = "RP"
mount = [0.1, 0.2, 0.3, 0.0]
[[arms]]
table = [[0.0, 0.0, 0.4, 0.0]]
tool = [0.1, 0.0, 0.0]
mount = [0.0, -0.2, 0.0, 3.141592653589793]
"""
    )
    robot = robot_file.load(path)
    assert robot.n_q == 4 + 2 + 1 and len(robot.arms) == 2
    assert robot.mounts[0].z == pytest.approx(0.3)
    arm2 = Position("xyz", arm=1)
    xi = np.asarray(K.forward(robot, np.zeros(robot.n_q), arm2))
    np.testing.assert_allclose(
        xi, [-0.5, -0.2, 0.0], atol=1e-12
    )  # mounted backwards: 0.4 m link + 0.1 m tool


def test_a_mount_of_six_numbers_is_x_y_z_roll_pitch_yaw(tmp_path):
    text = EXAMPLE.read_text().replace(
        "mount = [0.0, 0.0, 0.0, 0.0]", "mount = [0.1, 0.2, 0.3, 0.4, -0.5, 0.6]"
    )
    assert text != EXAMPLE.read_text()
    path = tmp_path / "tilted.toml"
    path.write_text(text)
    assert robot_file.load(path).mounts == (Mount(0.1, 0.2, 0.3, yaw=0.6, roll=0.4, pitch=-0.5),)
    path.write_text(text.replace("0.6]", "0.6, 0.7]"))
    with pytest.raises(
        InputError, match=r"mount: 4 numbers \(x, y, z, yaw\) or 6 \(x, y, z, roll, pitch, yaw\)"
    ):
        robot_file.load(path)


def test_a_built_in_robot_s_params_mount_its_arm():
    data = {"robot": {"name": "korayem-planar", "params": {"l1": 0.6, "mount.x": 0.1, "mount.yaw": 0.5}}}
    robot = robot_file.robot_table(data)
    assert robot == robots.design("korayem-planar", {"l1": 0.6, "mount.x": 0.1, "mount.yaw": 0.5})
    assert robot.mounts[0] == Mount(0.1, 0.0, 0.0, 0.5)  # korayem's own mount (l0, 0, 0) replaced
    data["robot"]["params"] = {"mount.w": 1.0}
    with pytest.raises(
        InputError, match="robot: robot korayem-planar: unknown parameter 'mount.w'; allowed: l0"
    ):
        robot_file.robot_table(data)


def test_analyze_accepts_a_robot_file(capsys):
    main(["analyze", str(EXAMPLE), "--q", "0,0,0,0.3,1.2", "--json"])
    data = json.loads(capsys.readouterr().out)
    assert data["robot"] == "planar-2r-on-differential-base"
    assert data["redundancy"] == {"M": 5, "delta": 4, "D": 2, "R": 3, "D_bar": 2, "R_bar": 2}


def test_simulation_spec_can_name_a_robot_file(tmp_path, capsys):
    (tmp_path / "robot.toml").write_text(EXAMPLE.read_text())
    spec = (Path(__file__).resolve().parents[1] / "docs" / "examples" / "bayle_ellipse.toml").read_text()
    spec = spec.replace('name = "bayle-planar"', 'file = "robot.toml"')
    spec = "\n".join(line for line in spec.splitlines() if not line.strip().startswith("params"))
    spec = spec.replace("duration = 30.0", "duration = 1.0")
    (tmp_path / "spec.toml").write_text(spec)
    # the first second of the run leaves 0.29 m of the tool's 0.8 m from the ellipse: within 0.5 m, reached
    main(["simulate", str(tmp_path / "spec.toml"), "--json", "--tolerance", "0.5"])
    summary = json.loads(capsys.readouterr().out)
    assert summary["duration"] == 1.0 and np.isfinite(summary["max_error"]) and summary["reached"]


@pytest.mark.parametrize(
    ("old", "new", "field"),
    [
        ('kind = "differential"', 'kind = "tracked"', "platform.kind"),
        ("wheel_radius = 0.1", "wheel_radius = -0.1", "wheel_radius"),
        ('convention = "dh"', 'convention = "urdf"', "arms[0].convention"),
        ("table = [[0.0, 0.0, 0.5, 0.0], [0.0, 0.0, 0.5, 0.0]]", "table = [[0.0, 0.5]]", "arms[0].table"),
        ("velocity_max = [1.5708, 1.5708]", "velocity_max = [1.5708]", "arms[0].velocity_max"),
        ("mount = [0.0, 0.0, 0.0, 0.0]", "mount = [0.0, 0.0]", "arms[0].mount"),
    ],
)
def test_bad_files_name_the_field(tmp_path, old, new, field):
    text = EXAMPLE.read_text()
    assert old in text
    path = tmp_path / "bad.toml"
    path.write_text(text.replace(old, new))
    with pytest.raises(InputError, match=field.replace("[", r"\[").replace("]", r"\]")):
        robot_file.load(path)


def test_cli_error_for_a_missing_file(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["analyze", "/nonexistent/robot.toml"])
    assert exc.value.code == 2
    assert "cannot read" in capsys.readouterr().err
