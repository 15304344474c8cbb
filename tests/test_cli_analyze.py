"""``mobman analyze``: both output forms for every built-in robot, the JSON schema, CSV input, symbolic output and
one-line errors with exit status 2."""

import json

import numpy as np
import pytest

from mobman.cli import main
from mobman.model import robots

MEASURE_KEYS = {"yoshikawa", "inverse_condition", "eccentricity"}


def _run(capsys, *argv):
    main(["analyze", *argv])
    return capsys.readouterr().out


@pytest.mark.parametrize("name", list(robots.PAPER_ROBOTS))  # the real robots: docs/real_robots.md
def test_every_builtin_robot_in_both_output_forms(name, capsys):
    data = json.loads(_run(capsys, name, "--json"))
    robot = robots.build(name)
    assert data["robot"] == robot.name and data["coordinates"] == list(robot.coordinate_names)
    assert set(data["redundancy"]) == {"M", "delta", "D", "R", "D_bar", "R_bar"}
    red = data["redundancy"]
    assert red["R"] == red["M"] - red["D"] and red["R_bar"] == red["delta"] - red["D_bar"]
    (result,) = data["results"]
    for key in (
        "q",
        "xi",
        "J",
        "J_bar",
        "rank_J",
        "rank_J_bar",
        "singular_values",
        "kinematic_singular",
        "velocity_singular",
        "manipulability",
    ):
        assert key in result, key
    assert np.shape(result["J_bar"]) == (robot.task.dim, robot.n_eta)
    for level in ("arm", "system"):
        assert set(result["manipulability"][level]) == MEASURE_KEYS
    normalized = result["manipulability"]["system_normalized"]
    assert (normalized is None) == (robot.velocity_limits is None)
    text = _run(capsys, name)
    assert "redundancy" in text and "manipulability" in text


def test_bayle_planar_values_at_a_given_configuration(capsys):
    """At q = (0, 0, 0, q4, q5) the end effector is at (l1 cos q4 + l2 cos(q4+q5), …) with angle q4 + q5 (Bayle §5.1)."""
    q4, q5 = 0.3, 1.2
    data = json.loads(_run(capsys, "bayle-planar", "--param", "l1=0.7", "--q", f"0,0,0,{q4},{q5}", "--json"))
    (result,) = data["results"]
    want = [0.7 * np.cos(q4) + 0.5 * np.cos(q4 + q5), 0.7 * np.sin(q4) + 0.5 * np.sin(q4 + q5), q4 + q5]
    np.testing.assert_allclose(result["xi"], want, atol=1e-12)
    assert data["redundancy"] == {"M": 5, "delta": 4, "D": 3, "R": 2, "D_bar": 3, "R_bar": 1}
    assert not result["velocity_singular"]


def test_velocity_singular_configuration_is_flagged(capsys):
    """Bayle example 1: VSC iff q4 = (2k+1)π/2."""
    data = json.loads(_run(capsys, "bayle-planar", "--q", "0,0,0,pi/2,0.4", "--json"))
    (result,) = data["results"]
    assert result["velocity_singular"] and result["rank_J_bar"] == 2


def test_configurations_from_csv_with_header(tmp_path, capsys):
    robot = robots.bayle_planar()
    path = tmp_path / "q.csv"
    rows = np.array([[0, 0, 0, 0.3, 1.2], [1, 2, 0.5, -0.4, 0.9], [0, 0, 0, 0.1, 0.2]])
    path.write_text(
        ",".join(robot.coordinate_names) + "\n" + "\n".join(",".join(map(str, r)) for r in rows) + "\n"
    )
    data = json.loads(_run(capsys, "bayle-planar", "--q-file", str(path), "--json"))
    np.testing.assert_allclose([r["q"] for r in data["results"]], rows)


def test_symbolic_output(capsys):
    data = json.loads(_run(capsys, "bayle-planar", "--symbolic", "--json"))
    assert "cos" in data["symbolic"]["velocity_singular_where"]
    assert "J_bar_latex" in data["symbolic"]


@pytest.mark.parametrize(
    ("argv", "needle"),
    [
        (["no-such-robot"], "unknown robot"),
        (["bayle-planar", "--param", "l9=1"], "l9"),
        (["bayle-planar", "--param", "l1=-1"], "l1"),
        (["bayle-planar", "--q", "1,2,3"], "--q"),
        (["bayle-planar", "--q", "0,0,nan,0,0"], "--q"),
        (["bayle-planar", "--q-file", "/nonexistent/q.csv"], "--q-file"),
    ],
)
def test_bad_input_is_one_line_and_exit_status_2(argv, needle, capsys):
    with pytest.raises(SystemExit) as exc:
        main(["analyze", *argv])
    assert exc.value.code == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("error:") and len(err.splitlines()) == 1 and needle in err
