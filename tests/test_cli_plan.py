"""``mobman plan``: output, figures and one-line errors with exit status 2."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from mobman.cli import main
from mobman.io import trajectories
from mobman.kinematics import forward
from mobman.model import robots


def _run(args, capsys):
    with pytest.raises(SystemExit) as info:
        main(args)
    return info.value.code, capsys.readouterr()


def test_plan_json_reaches_tolerance_and_writes_figures(tmp_path, capsys):
    main(
        [
            "plan",
            "tchon-car-rtr",
            "--target",
            "0,0,1",
            "--start",
            "5,0,0,pi/6",
            "--x",
            "0,2,pi/4",
            "--json",
            "--out",
            str(tmp_path),
        ]
    )
    report = json.loads(capsys.readouterr().out)
    assert report["converged"] and report["final_error"] <= 1e-12
    assert report["iterations"] == len(report["error_history"]) - 1
    assert report["dexterity_start"] > 0 and report["dexterity_end"] > 0
    assert len(report["lambda"]) == 10 and len(report["x"]) == 3
    for name in ("paths.png", "convergence.png"):
        assert (tmp_path / name).stat().st_size > 1000
    (motion,) = trajectories.read(tmp_path)  # the planned q(t): platform from the start, the arm held at x
    assert motion.robot_name == "tchon-car-rtr" and motion.t[0] == 0.0 and motion.t[-1] == pytest.approx(1.0)
    np.testing.assert_allclose(motion.q[0, :4], [5.0, 0.0, 0.0, np.pi / 6], atol=1e-15)
    np.testing.assert_allclose(motion.q[:, 4:], np.broadcast_to(report["x"], (len(motion.t), 3)), atol=1e-15)


@pytest.mark.parametrize(
    "args, message",
    [
        (["--target", "0,0,1", "--algorithm", "newton"], "--algorithm"),
        (["--target", "0,0"], "--target"),
        (["--target", "0,0,1", "--horizon", "0"], "--horizon"),
        (["--target", "0,0,1", "--horizon", "-2"], "--horizon"),
        (["--target", "0,0,1", "--horizon", "1e300"], "--horizon must be a number in (0, 10000] s"),
        (["--target", "0,0,1", "--step", "1e300"], "step Δθ must be a number in (0, 10]"),
        (["--target", "0,0,1", "--gamma", "1e300"], "gamma must be a number in (0, 1000]"),
        (["--target", "0,0,1", "--start", "1,2"], "--start"),
        (["--target", "0,0,1", "--step", "fast"], "--step"),
    ],
)
def test_bad_input_is_one_line_and_exit_2(args, message, capsys):
    code, captured = _run(["plan", "tchon-car-rtr", *args], capsys)
    assert code == 2
    lines = captured.err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error:") and message in lines[0]


def test_extension_is_a_choice_of_coordinates_or_sums():
    import numpy as np

    from mobman.cli.plan import DEFAULT_EXTENSIONS, extension_task
    from mobman.model.robots import tchon_car_rtr

    robot = tchon_car_rtr()
    q = np.random.default_rng(0).uniform(-np.pi, np.pi, robot.n_q)
    for text in (DEFAULT_EXTENSIONS["tchon-car-rtr"], "6, 2 + 4", "q[6], q[2]+q[4]"):
        task = extension_task(text, robot)
        np.testing.assert_array_equal(np.asarray(task.fn(q)), [q[6], q[2] + q[4]])
        assert task.dim == 2


@pytest.mark.parametrize(
    ("extension", "needle"),
    [
        ("q[100]", "index 100 is out of range"),
        ("7", "index 7 is out of range"),
        ("x3, elbow", "'elbow' is not a coordinate"),
        ("sin(q[0])", "is not a coordinate"),
        ("().__class__.__base__.__subclasses__()", "is not a coordinate"),
        ("x3,, x1", "empty"),
        ("x3 + ", "empty"),
        (" , ", "one or more coordinates"),
    ],
)
def test_bad_extension_is_one_line_and_exit_2(extension, needle, capsys):
    args = ["--target", "0,0,1", "--algorithm", "extended", "--extension", extension]
    code, captured = _run(["plan", "tchon-car-rtr", *args], capsys)
    assert code == 2
    lines = captured.err.strip().splitlines()
    assert len(lines) == 1 and "--extension" in lines[0] and needle in lines[0]


def test_joint_limits_of_the_start_and_of_the_planned_arm_joints(tmp_path, cli_run):
    """bayle-rrp's prismatic q6 ≥ 0: a target reached with q6 = −0.4 (from a start inside the limits) ends
    outside them, a plan that cannot be executed: exit 3, one line saying by how much, the results written.
    A start outside them is reported before planning."""
    robot = robots.build("bayle-rrp")
    target = ",".join(
        repr(float(v)) for v in np.asarray(forward(robot, [0, 0, 0, 0.2, 0.5, -0.4], robot.task))
    )
    args = ["plan", "bayle-rrp", "--target", target, "--x", "0.2,0.5,0.1", "--harmonics", "1", "--json"]
    code, stdout, err = cli_run([*args, "--out", str(tmp_path / "plan")])
    report = json.loads(stdout)
    assert code == 3 and report["converged"] and report["reached"] is False
    assert report["x"][2] < 0.0
    assert report["outside_limits"] == {"start": [], "end": ["q6"]}
    (line,) = err.strip().splitlines()
    assert line.startswith(
        "warning: mobman plan: not reached: the plan ends outside the joint limits: q6 = -0.4 m, 0.4 m below "
        "its limits [0, inf] (final error "
    )
    assert (tmp_path / "plan" / "paths.png").stat().st_size > 0
    code, _, err = cli_run([*args, "--strict-limits"])  # --strict-limits is about the start
    assert code == 3 and err.startswith("warning: mobman plan: not reached: ")
    code, _, err = cli_run([*args[:5], "0.2,0.5,-0.5", "--strict-limits"])
    (line,) = err.strip().splitlines()
    assert (
        code == 2
        and line == "error: start (--start, --x): q6 = -0.5 outside [0, inf] (the robot's joint limits)"
    )


PAPER = ["plan", "tchon-car-rtr", "--target", "0,0,1", "--start", "5,0,0,pi/6", "--x", "0,2,pi/4"]


def _rock(tmp_path, y: float):
    """A rock of radius 0.1 m inside the car's body where the paper's plan (start P) has the platform at
    t = 0.3 s (x = 2.687, y = 0.283; the body spans z ∈ [−0.15, 0]), or moved aside to ``y``."""
    path = tmp_path / f"rock{y}.toml"
    path.write_text(
        f'[[obstacle]]\nname = "rock"\nshape = "sphere"\nsize = [0.1]\nposition = [2.687, {y}, -0.075]\n'
    )
    return path


def test_a_plan_through_an_obstacle_does_not_reach_its_goal(tmp_path, capsys):
    code, captured = _run([*PAPER, "--scene", str(_rock(tmp_path, 0.283)), "--json"], capsys)
    report = json.loads(captured.out)
    assert code == 3 and report["converged"] and not report["reached"]
    hit = report["first_collision"]
    assert (
        (hit["robot"], hit["other"]) == ("platform", "rock") and 0 < hit["time"] <= 0.3 and hit["depth"] > 0
    )
    assert report["min_distance"] < 0 and report["closest"]["other"] == "rock"
    line = captured.err.strip()
    assert len(line.splitlines()) == 1 and "not reached: the motion collides at t = " in line
    assert "platform against rock" in line and "m deep" in line


def test_a_plan_beside_an_obstacle_reaches_its_goal_and_reports_its_clearance(tmp_path, cli_json):
    scene = str(_rock(tmp_path, -4.0))
    report = cli_json([*PAPER, "--scene", scene, "--out", str(tmp_path / "run")])
    assert report["reached"] and report["first_collision"] is None and report["min_distance"] > 0
    closest = report["closest"]
    assert closest["distance"] == report["min_distance"]
    # the sample of the closest pair, asked of `mobman distance` one configuration at a time: the same pair
    (motion,) = trajectories.read(tmp_path / "run")
    k = int(np.argmin(np.abs(motion.t - closest["time"])))
    q = ",".join(repr(float(v)) for v in motion.q[k])
    alone = cli_json(["distance", "tchon-car-rtr", "--q", q, "--scene", scene])
    assert alone["min_distance"] == pytest.approx(report["min_distance"], abs=1e-12)
    assert (alone["closest"]["robot"], alone["closest"]["other"]) == (closest["robot"], closest["other"])
    np.testing.assert_allclose(alone["closest"]["robot_point"], closest["robot_point"], atol=1e-12)


def test_avoid_plans_around_the_obstacle_and_still_reaches_the_goal(tmp_path, cli_json):
    """The rock the paper's plan drives through: with --avoid the null-space term bends the path around it
    (every pair clear of the rock along the path) and the plan still converges to the target."""
    rock = (
        Path(__file__).resolve().parents[1] / "docs" / "examples" / "car_rock.toml"
    )  # _rock(tmp_path, 0.283)
    assert rock.read_text().endswith(_rock(tmp_path, 0.283).read_text().splitlines()[-1] + "\n")
    report = cli_json([*PAPER, "--scene", str(rock), "--avoid"])
    assert report["converged"] and report["reached"] and report["final_error"] <= 1e-12
    assert report["first_collision"] is None and report["min_distance"] > 0.1
    assert report["avoidance"] == {"influence_distance": 0.2, "gain": 10.0}


@pytest.mark.parametrize(
    ("options", "message"),
    [
        (["--avoid"], "--avoid: needs --scene FILE"),
        (["--avoid", "--scene", "ROCK", "--algorithm", "adjoint"], "--avoid: works through the null space"),
        (["--avoid", "--scene", "ROCK", "--avoid-gain", "0"], "--avoid-gain must be a finite number > 0"),
        (["--avoid", "--scene", "ROCK", "--influence-distance", "nan"], "--influence-distance must be"),
    ],
)
def test_bad_avoid_options_are_one_line(tmp_path, capsys, options, message):
    rock = str(_rock(tmp_path, 0.283))
    code, captured = _run([*PAPER, *(rock if o == "ROCK" else o for o in options)], capsys)
    assert code == 2 and len(captured.err.strip().splitlines()) == 1 and message in captured.err


def test_a_bad_scene_is_one_line(tmp_path, capsys):
    bad = tmp_path / "bad.toml"
    bad.write_text('[[obstacle]]\nname = "rock"\nshape = "sphere"\nsize = [0.0]\n')
    code, captured = _run([*PAPER, "--scene", str(bad)], capsys)
    assert code == 2 and len(captured.err.strip().splitlines()) == 1
    assert "obstacle 'rock': size[0] (radius) must be > 0" in captured.err and "bad.toml" in captured.err
    code, captured = _run([*PAPER, "--scene", str(_rock(tmp_path, 0.0)), "--cover-tolerance", "0"], capsys)
    assert code == 2 and "--cover-tolerance: must be a finite number > 0" in captured.err
