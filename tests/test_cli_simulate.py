"""``mobman simulate SPEC.toml``: the example spec, JSON output, output folder, and one-line errors."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from mobman.cli import main
from mobman.io import trajectories
from mobman.model import robots

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


def test_example_spec_runs(tmp_path, capsys):
    text = EXAMPLE.read_text().replace("duration = 30.0", "duration = 1.0")
    main(["simulate", str(_spec(tmp_path, text)), "--json"])
    metrics = json.loads(capsys.readouterr().out)
    assert metrics["duration"] == pytest.approx(1.0)
    assert len(metrics["q_final"]) == 5 and "system_w5_min" in metrics


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
