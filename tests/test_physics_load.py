"""mobman.physics.load: the load capacity predicted by mobman.dynamics.max_load run on MuJoCo, an independent
rigid-body engine: at 90 % of the capacity the arm tracks the motion inside every envelope, with MuJoCo's
inverse-dynamics torques equal to mobman's τ0 + m τ1; at 120 % the limiting actuator saturates."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from mobman.cli import main
from mobman.cli.dynamics import load
from mobman.dynamics.load_capacity import eta_dot_from_samples, max_load
from mobman.errors import InputError, ModelError
from mobman.model import robots
from mobman.physics import to_mjspec
from mobman.physics.load import check_capacity, run_with_load

EXAMPLES = Path(__file__).resolve().parents[1] / "docs" / "examples"


def _predicted(name: str):
    spec = load(EXAMPLES / name)
    eta_dot = eta_dot_from_samples(spec.t, spec.eta)
    return spec, max_load(spec.model, spec.t, spec.q, spec.eta, eta_dot, spec.actuators)


@pytest.mark.parametrize("name", ["korayem_load.toml", "tiago_load.toml", "yamamoto_load.toml"])
def test_below_the_capacity_the_arm_tracks_inside_its_envelopes_and_above_it_saturates(name):
    spec, capacity = _predicted(name)
    below, above = check_capacity(spec.model, spec.t, spec.q, spec.actuators, capacity)
    assert below.mass == pytest.approx(0.9 * capacity.max_load) and above.mass == pytest.approx(
        1.2 * capacity.max_load
    )
    assert below.first_saturation is None and below.tracking_error < 1e-3
    limiting = above.names.index(capacity.limiting_actuator)
    at_limit = int(np.argmin(np.abs(above.t - capacity.limiting_time)))
    assert above.saturated[: at_limit + 1, limiting].any()  # by the limiting time, the limiting actuator
    assert above.tracking_error > 50 * below.tracking_error
    # MuJoCo's inverse dynamics asks, at the limiting time, the torque mobman predicts (τ0 + m τ1)
    step = int(np.argmin(np.abs(below.t - capacity.limiting_time)))
    sample = int(np.argmin(np.abs(capacity.t - capacity.limiting_time)))
    column = capacity.names.index(capacity.limiting_actuator)
    predicted = capacity.torques(below.mass)[sample, column]
    assert below.required[step, limiting] == pytest.approx(predicted, rel=5e-3)


def test_the_yamamoto_example_holds_the_paper_s_inertials():
    from mobman import dynamics as dyn

    spec = load(EXAMPLES / "yamamoto_load.toml")
    paper = dyn.yamamoto_model(payload=spec.model.payload)
    q = np.random.default_rng(3).uniform(-np.pi, np.pi, (16, paper.robot.n_q))
    assert np.allclose(dyn.reduced_mass_matrix(spec.model, q), dyn.reduced_mass_matrix(paper, q), atol=1e-12)


def test_mujoco_s_torques_follow_mobman_s_along_a_smooth_motion():
    spec, capacity = _predicted("korayem_load.toml")  # a quintic time law: smooth to the second derivative
    run = run_with_load(spec.model, spec.t, spec.q, spec.actuators, 10.0)
    predicted = capacity.torques(10.0)[:, -len(run.names) :]
    steps = np.searchsorted(run.t, capacity.t - 1e-9)
    scale = np.max(np.abs(predicted), axis=0)
    # the motion's samples every 10 ms: its spline and the finite differences of η agree to ~0.3 %
    assert np.all(np.abs(run.required[steps] - predicted) < 5e-3 * scale)


def test_bad_arguments_are_one_line():
    spec, _ = _predicted("korayem_load.toml")
    with pytest.raises(InputError, match="mass must be a finite number ≥ 0"):
        run_with_load(spec.model, spec.t, spec.q, spec.actuators, -1.0)
    with pytest.raises(InputError, match="actuators: unknown"):
        run_with_load(spec.model, spec.t, spec.q, {"elbow": None}, 1.0)
    with pytest.raises(InputError, match="q must have shape"):
        run_with_load(spec.model, spec.t, spec.q[:, :3], spec.actuators, 1.0)
    with pytest.raises(InputError, match="platform must be one of wheels, prescribed"):
        to_mjspec(spec.model, platform="rails")
    with pytest.raises(ModelError, match="coordinates x, y, theta alone"):
        to_mjspec(robots.build("tchon-car-rtr"), platform="prescribed")


def test_the_command_line_runs_the_check_and_writes_its_figure(tmp_path, capsys):
    out = tmp_path / "run"
    spec = str(EXAMPLES / "korayem_load.toml")
    main(["load-capacity", spec, "--physics", "mujoco", "--json", "--out", str(out)])
    physics = json.loads(capsys.readouterr().out)["physics"]
    assert physics["limiting_actuator"] == "theta1"
    assert [run["fraction"] for run in physics["runs"]] == pytest.approx([0.9, 1.2])
    assert (
        physics["runs"][0]["first_saturation"] is None and physics["runs"][1]["saturated_steps"]["theta1"] > 0
    )
    assert (out / "physics_torques.png").stat().st_size > 10_000
    with pytest.raises(SystemExit) as exc:
        main(["load-capacity", spec, "--physics", "bullet"])
    assert exc.value.code == 2
    assert "--physics must be mujoco" in capsys.readouterr().err


def test_a_prediction_that_does_not_hold_on_physics_exits_3_and_says_which_run(monkeypatch, capsys):
    from mobman.physics import load as physics_load

    monkeypatch.setattr(physics_load, "FRACTIONS", (0.9, 0.95))  # 95 % of the capacity cannot saturate
    with pytest.raises(SystemExit) as exc:
        main(["load-capacity", str(EXAMPLES / "korayem_load.toml"), "--physics", "mujoco", "--json"])
    assert exc.value.code == 3
    assert "on MuJoCo 95% of the capacity never saturated" in capsys.readouterr().err
