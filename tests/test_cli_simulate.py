"""``mobman simulate SPEC.toml``: the example spec, JSON output, output folder, and one-line errors."""

from __future__ import annotations

import json
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from mobman import kinematics
from mobman.cli import common, main
from mobman.cli import simulate as simulate_cli
from mobman.control import spec
from mobman.control.metrics import RunningSummary
from mobman.io import trajectories
from mobman.model import robots
from mobman.model.tasks import Position

EXAMPLE = Path(__file__).resolve().parents[1] / "docs" / "examples" / "bayle_ellipse.toml"

SHORT = """
duration = 0.4
dt = 0.02
q0 = [0.0, 0.0, 0.0, -0.785, 1.57]
measures = ["system_w5"]
[robot]
name = "bayle-planar"
[task]
kind = "position"
components = "xy"
[reference]
kind = "line"
start = [0.707, 0.0]
end = [0.907, 0.1]
duration = 0.4
[law]
kind = "bayle"
[criterion]
kind = "manipulability"
[gains]
W = 2.0
k = 0.2
"""


def _spec(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "spec.toml"
    path.write_text(text)
    return path


def test_a_run_short_of_its_goal_exits_3_saying_by_how_much_with_its_results_written(tmp_path, cli_run):
    """The example's first second: the tool starts 0.799 m from the ellipse (at (1.5, −0.1); the tool at
    (0.5√2, 0)) and Bayle's law closes ė = −W e, so 0.799 e^{−1} = 0.294 m is left at t = 1 s."""
    text = EXAMPLE.read_text().replace("duration = 30.0", "duration = 1.0")
    path, out = _spec(tmp_path, text), tmp_path / "run"
    code, stdout, err = cli_run(["simulate", str(path), "--json", "--out", str(out)])
    metrics = json.loads(stdout)
    left = np.hypot(1.5 - 0.5 * np.sqrt(2), 0.1) * np.exp(-1.0)
    assert (
        code == 3 and metrics["final_error"] == pytest.approx(left, rel=1e-4) and metrics["reached"] is False
    )
    assert err.strip().splitlines()[-1] == (
        f"warning: mobman simulate: not reached: final error {left:.3g} m > tolerance 0.001 m"
    )
    assert json.loads((out / "results.json").read_text())["metrics"]["reached"] is False
    assert (
        (out / "paths.png").stat().st_size > 0 and len(metrics["q_final"]) == 5 and "system_w5_min" in metrics
    )
    code, stdout, _ = cli_run(["simulate", str(path), "--json", "--tolerance", "0.3"])
    assert code == 0 and json.loads(stdout)["reached"] is True and json.loads(stdout)["tolerance"] == 0.3


TO_TARGET = ["--duration", "4", "--dt", "0.02", "--json"]


@pytest.mark.parametrize("law", ["qp", "bayle"])
def test_simulate_robot_to_a_target_without_a_spec(tmp_path, cli_run, law):
    """bayle-planar's tool (at the height 0) driven to (1.5, 0.5, 0) from the robot's default configuration
    (every coordinate 0), within the tolerance; the QP law's velocity limits hold it back on the way
    (saturated samples) without keeping it from the goal."""
    out = tmp_path / "run"
    code, stdout, err = cli_run(
        ["simulate", "bayle-planar", "--target", "1.5,0.5,0", *TO_TARGET, "--law", law]
    )
    metrics = json.loads(stdout)
    assert code == 0 and err == "" and metrics["reached"] is True and metrics["final_error"] <= 1e-3
    assert metrics["q0"] == [0.0] * 5 and metrics["target"] == [1.5, 0.5, 0.0] and metrics["law"] == law
    tool = kinematics.forward(robots.bayle_planar(), metrics["q_final"], Position("xyz"))
    np.testing.assert_allclose(tool, [1.5, 0.5, 0.0], atol=1e-3)
    if law == "qp":
        assert metrics["saturated_steps"] > 0 and metrics["velocity_limit_ratio"] <= 1 + 1e-9
        code, _, _ = cli_run(
            ["simulate", "bayle-planar", "--target", "1.5,0.5,0", *TO_TARGET, "--out", str(out)]
        )
        saved = json.loads((out / "results.json").read_text())
        assert code == 0 and saved["robot"] == "bayle-planar" and saved["target"] == [1.5, 0.5, 0.0]
        (motion,) = trajectories.read(out)
        np.testing.assert_array_equal(motion.q[0], np.zeros(5))


@pytest.mark.parametrize(
    "target, left, cut",
    [
        ("1.5,0.5,0.8", "0.8 m", ""),  # a planar robot: its tool stays at the height 0
        ("1e6,0,0", "1e+06 m", "; the limits cut the controls at "),  # 1e6 m away, at most 0.5 m/s
    ],
)
def test_simulate_robot_to_a_target_out_of_reach_exits_3(tmp_path, cli_run, target, left, cut):
    out = tmp_path / "run"
    code, stdout, err = cli_run(
        ["simulate", "bayle-planar", "--target", target, *TO_TARGET, "--out", str(out)]
    )
    line = err.strip().splitlines()[-1]
    assert code == 3 and json.loads(stdout)["reached"] is False
    assert line.startswith(
        f"warning: mobman simulate: not reached: final error {left} > tolerance 0.001 m{cut}"
    )
    assert json.loads((out / "results.json").read_text())["metrics"]["reached"] is False


@pytest.mark.parametrize(
    "args, message",
    [
        (["bayle-planar", "--target", "1,0"], "--target: 3 values x,y,z (m) or 6"),
        (["bayle-planar", "--target", "1,0,0", "--law", "pid"], "--law must be one of qp, bayle, got 'pid'"),
        (["bayle-planar", "--target", "1,0,0", "--duration", "-1"], "--duration must be a finite number > 0"),
        (["bayle-planar", "--target", "1,0,0", "--dt", "nan"], "--dt must be a finite number > 0"),
        (["bayle-planar", "--target", "1,0,0", "--q", "0,0"], "--q: "),
        (
            ["bayle-planar", "--target", "1,0,0", "--tolerance", "0"],
            "--tolerance must be a finite number > 0",
        ),
        ([str(EXAMPLE), "--q", "0,0,0,0,0"], "--q: only with ROBOT --target"),
        (
            ["bayle-planar"],
            "'bayle-planar' is not a spec file (SPEC.toml); to simulate a robot toward a target",
        ),
        ([str(EXAMPLE), "--tolerance", "-1"], "--tolerance must be a finite number > 0"),
    ],
)
def test_invalid_target_options_are_one_line_exit_2(cli_run, args, message):
    code, _, err = cli_run(["simulate", *args])
    (line,) = err.strip().splitlines()
    assert code == 2 and line.startswith("error: ") and message in line


def test_simulate_json_and_out(tmp_path, capsys):
    out = tmp_path / "run"
    main(["simulate", str(_spec(tmp_path, SHORT)), "--out", str(out), "--json"])
    metrics = json.loads(capsys.readouterr().out)
    assert metrics["max_error"] < 1e-3  # starts on the line: pure tracking
    saved = json.loads((out / "results.json").read_text())
    assert len(saved["series"]["t"]) == 21 and saved["metrics"]["max_error"] == pytest.approx(
        metrics["max_error"]
    )
    assert (out / "paths.png").stat().st_size > 0 and (out / "timeseries.png").stat().st_size > 0
    (motion,) = trajectories.read(out)  # q(t) and the robot beside the results, for `mobman view`
    assert motion.robot_name == "bayle-planar" and motion.describes(robots.bayle_planar())
    np.testing.assert_array_equal(motion.q, saved["series"]["q"])
    np.testing.assert_array_equal(motion.t, saved["series"]["t"])
    main(["simulate", str(_spec(tmp_path, SHORT))])
    assert "graining_points" in capsys.readouterr().out


@pytest.mark.parametrize(
    "old, new, field",
    [
        ("period = 30.0", "period = -1.0", "reference"),
        ('kind = "ellipse"', 'kind = "spiral"', "reference.kind"),
        ('name = "bayle-planar"', 'name = "walle"', "robot"),
        ('q0 = "0, 0, 0, -pi/4, pi/2"', "q0 = [0, 0, 0]", "q0"),
        ("W = 1.0", "W = -1.0", "gains"),
        ("k = 2.0", "kk = 2.0", "gains.kk"),
        ("dt = 0.02", 'dt = "fast"', "dt"),
        ('measure = "eccentricity"', 'measure = "beauty"', "criterion"),
        ('measures = ["system_w5", "arm_w5"]', 'measures = ["w7"]', "measures"),
        ('components = "xy"', 'components = "xyz"', "reference"),  # 2-D ellipse for a 3-D task
    ],
)
def test_invalid_spec_is_one_line_exit_2(tmp_path, capsys, old, new, field):
    text = EXAMPLE.read_text()
    assert old in text
    path = _spec(tmp_path, text.replace(old, new))
    with pytest.raises(SystemExit) as exc:
        main(["simulate", str(path)])
    assert exc.value.code == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and err.startswith(f"error: {path}: {field}")


def test_unreadable_spec(tmp_path, capsys):
    with pytest.raises(SystemExit) as exc:
        main(["simulate", str(tmp_path / "missing.toml")])
    assert exc.value.code == 2
    bad = _spec(tmp_path, "duration = [")
    with pytest.raises(SystemExit):
        main(["simulate", str(bad)])
    assert "invalid TOML" in capsys.readouterr().err


def _limited_robot(tmp_path: Path) -> str:
    """SHORT with the example robot file given joint limits that its q5 = 1.57 exceeds."""
    robot = (EXAMPLE.parent / "planar_robot.toml").read_text()
    (tmp_path / "robot.toml").write_text(robot + "limits = [[-3.1, 3.1], [-1.5, 1.5]]\n")
    return SHORT.replace('name = "bayle-planar"', 'file = "robot.toml"')


def test_q0_outside_the_joint_limits_warns_or_fails_with_strict_limits(tmp_path, capsys):
    path = _spec(tmp_path, _limited_robot(tmp_path))
    main(["simulate", str(path), "--json"])
    captured = capsys.readouterr()
    metrics = json.loads(captured.out)
    assert len(metrics["outside_limits"]) == 1 and metrics["duration"] == pytest.approx(0.4)
    (line,) = captured.err.strip().splitlines()
    assert line.startswith("warning: q0: ") and "= 1.57 outside [-1.5, 1.5]" in line
    with pytest.raises(SystemExit) as exc:
        main(["simulate", str(path), "--json", "--strict-limits", "--out", str(tmp_path / "run")])
    assert exc.value.code == 2 and not (tmp_path / "run").exists()
    (line,) = capsys.readouterr().err.strip().splitlines()
    assert line.startswith("error: ") and "q0: " in line and "= 1.57 outside [-1.5, 1.5]" in line


def test_q0_inside_the_joint_limits_is_reported_as_such(tmp_path, capsys):
    main(["simulate", str(_spec(tmp_path, SHORT)), "--json", "--strict-limits"])
    captured = capsys.readouterr()
    assert json.loads(captured.out)["outside_limits"] == [] and captured.err == ""


def test_a_long_run_is_computed_and_written_in_pieces(tmp_path, capsys, monkeypatch):
    """With pieces of 8 samples (21 in all: two whole pieces and a cut one), the files and metrics are those
    of the run held in memory."""
    path = _spec(tmp_path, SHORT)
    whole = tmp_path / "whole"
    main(["simulate", str(path), "--out", str(whole), "--json"])
    expected = json.loads(capsys.readouterr().out)
    series = json.loads((whole / "results.json").read_text())["series"]
    monkeypatch.setattr(simulate_cli, "STREAM_STEPS", 8)
    monkeypatch.setattr(simulate_cli, "PLOT_SAMPLES", 5)
    pieces = tmp_path / "pieces"
    main(["simulate", str(path), "--out", str(pieces), "--json"])
    metrics = json.loads(capsys.readouterr().out)
    assert metrics.keys() == expected.keys()
    for key, value in expected.items():
        assert metrics[key] == (
            pytest.approx(value, rel=1e-12, abs=1e-15) if isinstance(value, float) else value
        )
    document = json.loads((pieces / "results.json").read_text())
    assert document["samples"] == 21 and document["figure_stride"] == 5
    files = dict(document["series"])
    files.update({f"measures.{k}": v for k, v in files.pop("measures").items()})
    assert len(files) == len(series) - 1 + len(series["measures"])
    for name, file in files.items():
        saved = series["measures"][name[9:]] if name.startswith("measures.") else series[name]
        array = np.load(pieces / file)  # a complete file: np.load checks the data against the header's shape
        assert array.shape == np.shape(saved)
        np.testing.assert_allclose(array.astype(float), np.asarray(saved, dtype=float), rtol=0, atol=1e-12)
    (motion,) = trajectories.read(pieces)  # every 5th sample, and the last
    rows = [0, 5, 10, 15, 20]
    np.testing.assert_array_equal(motion.q, np.load(pieces / "q.npy")[rows])
    np.testing.assert_array_equal(motion.t, np.load(pieces / "t.npy")[rows])
    assert (pieces / "paths.png").stat().st_size > 0 and (pieces / "timeseries.png").stat().st_size > 0
    assert sorted(p.name for p in tmp_path.iterdir()) == ["pieces", "spec.toml", "whole"]


def test_the_memory_check_counts_one_piece_of_a_long_run(tmp_path, capsys, monkeypatch):
    path = _spec(tmp_path, SHORT)
    per_sample = simulate_cli._values_per_step(spec.load(path)) * common.BYTES_PER_VALUE
    monkeypatch.setattr(common, "available_memory", lambda: 12 * per_sample)  # 21 samples do not fit
    with pytest.raises(SystemExit) as exc:
        main(["simulate", str(path), "--json"])
    assert exc.value.code == 2
    (line,) = capsys.readouterr().err.strip().splitlines()
    assert line.startswith("error: duration / dt: 21 steps") and "available" in line
    monkeypatch.setattr(simulate_cli, "STREAM_STEPS", 8)  # pieces of 8 samples do
    main(["simulate", str(path), "--json"])
    assert json.loads(capsys.readouterr().out)["duration"] == pytest.approx(0.4)
    with pytest.raises(SystemExit) as exc:  # the step limit still counts every step
        main(["simulate", str(path), "--json", "--max-steps", "20"])
    assert exc.value.code == 2 and "--max-steps" in capsys.readouterr().err
    monkeypatch.setattr(
        common.shutil, "disk_usage", lambda _: SimpleNamespace(total=10**9, used=10**9, free=1000)
    )
    with pytest.raises(SystemExit) as exc:  # the files of a run in pieces must fit on the disk
        main(["simulate", str(path), "--json", "--out", str(tmp_path / "run")])
    (line,) = capsys.readouterr().err.strip().splitlines()
    assert exc.value.code == 2 and "free there" in line and not (tmp_path / "run").exists()


def test_an_interrupted_long_run_leaves_the_old_results(tmp_path, capsys, monkeypatch):
    path = _spec(tmp_path, SHORT)
    out = tmp_path / "run"
    main(["simulate", str(path), "--out", str(out), "--json"])
    before = {p.name: p.read_bytes() for p in out.iterdir()}
    capsys.readouterr()
    monkeypatch.setattr(simulate_cli, "STREAM_STEPS", 8)
    add, calls = RunningSummary.add, []

    def interrupted(self, piece):
        calls.append(piece)
        if len(calls) == 2:  # the first piece is already written
            raise KeyboardInterrupt
        add(self, piece)

    monkeypatch.setattr(RunningSummary, "add", interrupted)
    with pytest.raises(SystemExit) as exc:
        main(["simulate", str(path), "--out", str(out), "--json"])
    assert exc.value.code == 130 and len(calls) == 2
    assert {p.name: p.read_bytes() for p in out.iterdir()} == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["run", "spec.toml"]


QP = SHORT.replace('kind = "bayle"', 'kind = "qp"\nlimit_gain = 4.0')


def test_qp_law_spec_reports_its_limit_flags(tmp_path, capsys):
    main(["simulate", str(_spec(tmp_path, QP)), "--json"])
    metrics = json.loads(capsys.readouterr().out)
    assert metrics["max_error"] < 1e-3 and metrics["velocity_limit_ratio"] <= 1 + 1e-9
    assert {"joint_limited_steps", "speed_limited_steps"} <= set(metrics)
    assert metrics["wheel_speed_ratio"] is None  # bayle-planar gives (v, ω) limits, not per-wheel ones


@pytest.mark.parametrize(
    "old, new, message",
    [
        ("limit_gain = 4.0", "limit_gain = -4.0", "limit_gain must be a finite number > 0"),
        ("limit_gain = 4.0", "regularization = 0.0", "regularization must be a finite number ≥ 1e-7"),
        ("limit_gain = 4.0", "iterations = 0", "iterations must be an integer in 1..1000"),
        ("limit_gain = 4.0", "iterations = 2.5", "law.iterations: must be an integer"),
        ("limit_gain = 4.0", "saturate = true", "saturate does not apply"),
    ],
)
def test_invalid_qp_law_is_one_line_exit_2(tmp_path, capsys, old, new, message):
    path = _spec(tmp_path, QP.replace(old, new))
    with pytest.raises(SystemExit) as exc:
        main(["simulate", str(path)])
    assert exc.value.code == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and message in err
