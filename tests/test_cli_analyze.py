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


VERTICAL = "0,0,0,0.2,1.5707963267948966,0.9"  # Bayle's RRP arm pointing straight up


def test_rrp_arm_pointing_up_is_regular_and_follows_the_joint(capsys):
    (result,) = json.loads(_run(capsys, "bayle-rrp", "--q", VERTICAL, "--json"))["results"]
    assert result["representation_singular"] is False and result["outside_limits"] == []
    np.testing.assert_allclose(result["xi"], [0.0, 0.0, 0.9, 0.2, np.pi / 2], atol=1e-15)
    np.testing.assert_allclose(
        np.asarray(result["J_bar"])[3:], [[0, 1, 1, 0, 0], [0, 0, 0, 1, 0]], atol=1e-15
    )
    assert result["rank_J_bar"] == 4 and np.isfinite(result["singular_values"]).all()
    (past,) = json.loads(_run(capsys, "bayle-rrp", "--q", "0,0,0,0.2,2.5,0.9", "--json"))["results"]
    assert past["xi"][4] == pytest.approx(2.5)  # ξ5 = q5 beyond the vertical, not π − q5


def test_representation_singular_task_prints_every_finite_quantity(tmp_path, capsys):
    from mobman.cli.analyze import analysis
    from mobman.model import EulerAngles

    robot = robots.bayle_rrp().with_task(EulerAngles("ZYZ"))  # ZYZ locked where the tool's z axis is vertical
    data = analysis(robot, np.array([[0, 0, 0, 0.2, 0.0, 0.9], [0, 0, 0, 0.2, 0.4, 0.9]]))
    locked, regular = data["results"]
    assert locked["representation_singular"] and not regular["representation_singular"]
    assert np.isfinite(locked["xi"]).all() and locked["rank_J"] is None and locked["manipulability"] is None
    assert regular["rank_J"] == 2 and np.isfinite(regular["J_bar"]).all()  # R depends on ψ and q5 only


def test_configuration_outside_the_joint_limits_warns_or_fails_with_strict_limits(capsys):
    q = "0,0,0,0.2,0.5,-0.5"  # q6 ≥ 0
    (result,) = json.loads(_run(capsys, "bayle-rrp", "--q", q, "--json"))["results"]
    assert result["outside_limits"] == ["q6"]
    main(["analyze", "bayle-rrp", "--q", q])
    err = capsys.readouterr().err.strip()
    assert err.startswith("warning:") and "q6 = -0.5" in err and len(err.splitlines()) == 1
    with pytest.raises(SystemExit) as exc:
        main(["analyze", "bayle-rrp", "--q", q, "--strict-limits"])
    assert exc.value.code == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("error: --q: q6 = -0.5 outside [0, inf]") and len(err.splitlines()) == 1


def test_a_zero_shoulder_offset_is_a_valid_geometry(capsys):
    (result,) = json.loads(_run(capsys, "manus-platform", "--param", "L2=0", "--json"))["results"]
    assert np.isfinite(result["J_bar"]).all()
    with pytest.raises(SystemExit):
        main(["analyze", "manus-platform", "--param", "L3=0"])
    assert "L3 (a length) must be a finite number > 0" in capsys.readouterr().err


def test_without_q_the_default_configuration_is_named_and_headings_hold_no_python_values(capsys):
    """`mobman analyze bayle-rrp` (no --q): a note on standard error says which configuration is analysed;
    the manipulability heading lists the measures' ranks in words, no Python dict."""
    main(["analyze", "bayle-rrp"])
    captured = capsys.readouterr()
    assert "note: no --q or --q-file: analysing the default configuration" in captured.err
    assert len(captured.err.strip().splitlines()) == 1
    heading = next(line for line in captured.out.splitlines() if "manipulability, configuration 1" in line)
    assert "{" not in heading and "None" not in heading
    main(["analyze", "bayle-rrp", "--json"])
    assert json.loads(capsys.readouterr().out)["default_configuration"] is True
    main(["analyze", "bayle-rrp", "--q", "0,0,0,0.3,0.5,0.4"])
    assert capsys.readouterr().err == ""
