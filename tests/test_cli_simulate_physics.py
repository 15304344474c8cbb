"""``mobman simulate SPEC --physics mujoco`` (mobman.cli.physics_run, mobman.physics.run): slow runs on a
high-friction floor end where the kinematic runs of the same specs end, with the wheels rolling without
measurable slip; a fast run on a slippery floor slips; bad settings are one line and exit 2; a run that
diverges stops with exit 3 and keeps its series up to there."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np
import pytest
from cli_runs import run_cli

from mobman import kinematics
from mobman.control import spec
from mobman.io import trajectories
from mobman.model.tasks import Position

EXAMPLES = Path(__file__).resolve().parents[1] / "docs" / "examples"

BAYLE = """
duration = {duration}
dt = 0.01
q0 = [0.0, 0.0, 0.0, -0.785, 1.57]
[robot]
name = "bayle-planar"
[task]
kind = "position"
components = "xy"
[reference]
kind = "line"
start = [0.707, 0.0]
end = [{end}]
duration = {move}
[law]
kind = "bayle"
[gains]
W = 2.0
[physics]
{physics}
"""

SLOW = BAYLE.format(duration=2.5, end="0.807, 0.05", move=2.0, physics='engine = "mujoco"\nfriction = 2.0')
FAST = BAYLE.format(duration=1.0, end="0.707, 1.0", move=1.0, physics='engine = "mujoco"\nfriction = 0.05')


def _tiago() -> str:
    """tiago_limits.toml shortened: the QP law moving the hand 6 cm forward and 4 cm up in 1.5 s (slow)."""
    text = (EXAMPLES / "tiago_limits.toml").read_text()
    text = text.replace("duration = 5.0 ", "duration = 2.0 ").replace("duration = 4.0 ", "duration = 1.5 ")
    text = text.replace("end = [1.0, 0.0, 1.35]", "end = [0.73, -0.24, 0.90]")
    text = text.replace("end_rpy = [1.95, -0.17, 1.14]", "end_rpy = [1.65, -0.17, 0.34]")
    return text + "\n[physics]\nfriction = 2.0\n"


def _write(tmp_path: Path, text: str, name: str = "spec.toml") -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


def _physics(tmp_path: Path, text: str, capsys, *args: str) -> tuple[int, dict, Path, str]:
    """Run the spec on MuJoCo with --out; exit status, results.json, the spec's path, standard error."""
    path = _write(tmp_path, text)
    out = tmp_path / "out"
    code, _, err = run_cli(["simulate", str(path), "--out", str(out), "--json", *args], capsys)
    return code, json.loads((out / "results.json").read_text()), path, err


def _assert_matches_kinematic_run(path: Path, results: dict, task_value) -> None:
    """The measured end point within 1 cm of the kinematic run's (mobman's own integration of the same
    spec), the platform's too; the median lateral slip |G(q_p) q̇_p| under 1 mm/s, from the series."""
    parsed = spec.load(path)
    kinematic = parsed.simulate()
    q_physics = np.asarray(results["series"]["q"])[-1]
    assert results["series"]["t"][-1] == pytest.approx(parsed.duration)
    assert (
        np.linalg.norm(task_value(parsed.robot, q_physics) - task_value(parsed.robot, kinematic.q[-1])) < 0.01
    )
    assert np.linalg.norm(q_physics[:2] - kinematic.q[-1, :2]) < 0.01
    slip = np.abs(np.asarray(results["series"]["physics"]["slip_lateral"]))
    assert np.median(slip) < 1e-3
    assert results["metrics"]["slip_lateral_median"] == pytest.approx(np.median(slip))


def test_bayle_slow_on_high_friction_ends_at_the_kinematic_end_point(tmp_path, capsys):
    code, results, path, _ = _physics(tmp_path, SLOW, capsys)
    assert code == 0
    _assert_matches_kinematic_run(
        path, results, lambda robot, q: np.asarray(kinematics.forward(robot, q, Position("xy")))
    )
    physics = results["series"]["physics"]
    assert results["physics"]["wheels"] == ["wheel_right", "wheel_left"]
    assert np.asarray(physics["slip_longitudinal"]).shape == (251, 2)
    # the robot's weight on its wheels (and frictionless casters): the wheels carry part of it, never more
    weight = 9.81 * 24.0  # stand-ins: a 20-kg platform body, two 1-kg wheels, two 1-kg links
    assert 0.0 < np.asarray(physics["contact_normal"])[-1].sum() <= weight
    # the replay file of `mobman view --results`: the measured motion
    motion = trajectories.read(tmp_path / "out")[0]
    assert np.allclose(motion.q, results["series"]["q"])
    assert (tmp_path / "out" / "physics.png").stat().st_size > 0


def test_tiago_qp_slow_on_high_friction_ends_at_the_kinematic_end_point(tmp_path, capsys):
    code, results, path, _ = _physics(
        tmp_path, _tiago(), capsys, "--physics", "mujoco", "--tolerance", "0.05"
    )
    assert code == 0
    _assert_matches_kinematic_run(
        path, results, lambda robot, q: np.asarray(kinematics.forward(robot, q, Position("xyz")))
    )
    assert results["metrics"]["inertials"] == "the robot's dynamic model"
    robot = spec.load(path).robot
    wheels_and_joints = ["wheel_right", "wheel_left", *robot.coordinate_names[robot.n_platform :]]
    assert results["physics"]["actuators"] == wheels_and_joints
    # the reduced dynamics' B⁻¹ b(q, η) fed forward: the servos no longer lag under the arm's weight
    fed = tmp_path / "fed"
    fed.mkdir()
    code, with_ff, _, _ = _physics(
        fed, _tiago() + "feedforward = true\n", capsys, "--physics", "mujoco", "--tolerance", "0.05"
    )
    assert code == 0
    assert [r["metrics"]["feedforward"] for r in (results, with_ff)] == [False, True]
    deviation = [r["metrics"]["kinematic_deviation_max"] for r in (results, with_ff)]
    assert deviation[1] < 0.25 * deviation[0]
    # the torques recorded are the actuators' (servo and feed-forward): at the end, at rest, the same weight
    torque = [np.asarray(r["series"]["physics"]["torque"])[-1] for r in (results, with_ff)]
    torso = wheels_and_joints.index("torso_lift_joint")
    assert abs(torque[0][torso]) > 50.0
    assert torque[1][torso] == pytest.approx(torque[0][torso], rel=0.02)


def test_a_fast_run_on_a_slippery_floor_slips(tmp_path, capsys):
    code, results, _, _ = _physics(tmp_path, FAST, capsys, "--tolerance", "10")
    assert code == 0
    slip = np.abs(np.asarray(results["series"]["physics"]["slip_lateral"]))
    assert np.median(slip) > 1e-3


@pytest.mark.parametrize(
    ("physics", "field"),
    [
        ('engine = "mujoco"\ntimestep = 0.0', "physics.timestep"),
        ('engine = "mujoco"\ncontrol_rate = -100.0', "physics.control_rate"),
        ('engine = "mujoco"\ncontrol_rate = 300.0', "physics.control_rate"),
        ('engine = "bullet"', "physics.engine"),
        ('engine = "mujoco"\nfriction = 0.0', "physics.friction"),
        ('engine = "mujoco"\npayload = -1.0', "physics.payload"),
        ('engine = "mujoco"\nfeedforward = 1', "physics.feedforward"),
        ('engine = "mujoco"\nfeedforward = true', "physics.feedforward"),  # stand-in inertials
    ],
)
def test_bad_physics_settings_are_one_line_and_exit_2(tmp_path, capsys, physics, field):
    path = _write(tmp_path, BAYLE.format(duration=2.5, end="0.807, 0.05", move=2.0, physics=physics))
    code, out, err = run_cli(["simulate", str(path)], capsys)
    assert code == 2 and out == ""
    assert len(err.strip().splitlines()) == 1 and field in err


def test_an_unknown_engine_option_and_a_missing_extra_exit_2(tmp_path, capsys, monkeypatch):
    path = _write(tmp_path, BAYLE.format(duration=2.5, end="0.807, 0.05", move=2.0, physics=""))
    code, _, err = run_cli(["simulate", str(path), "--physics", "bullet"], capsys)
    assert code == 2 and "--physics" in err and "mujoco" in err
    monkeypatch.setitem(sys.modules, "mujoco", None)  # `import mujoco` fails as without the extra
    code, _, err = run_cli(["simulate", str(path), "--physics", "mujoco"], capsys)
    assert code == 2 and len(err.strip().splitlines()) == 1 and 'pip install -e ".[physics]"' in err


def test_a_diverging_run_stops_with_exit_3_and_keeps_its_series(tmp_path, capsys):
    """A 50-ms physics step is far too long for the servos: MuJoCo's state blows up."""
    diverging = BAYLE.format(
        duration=2.5,
        end="0.807, 0.05",
        move=2.0,
        physics='engine = "mujoco"\ntimestep = 0.05\ncontrol_rate = 20.0',
    )
    code, results, _, err = _physics(tmp_path, diverging, capsys)
    assert code == 3
    assert "stopped at t = " in err and "unstable" in err and len(err.strip().splitlines()) == 1
    t = np.asarray(results["series"]["t"])
    assert 2 <= len(t) < 51 and results["metrics"]["stopped"] in err
    assert len(results["series"]["physics"]["torque"]) == len(t)
    assert not list(tmp_path.glob(".out.*"))  # written whole: no staging folder left
