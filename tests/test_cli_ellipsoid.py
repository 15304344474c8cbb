"""``mobman ellipsoid``: axes, directions and volume against independent formulas; one-line errors, exit 2."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from mobman import dynamics as dyn
from mobman import kinematics
from mobman.cli import main
from mobman.dynamics.ellipsoids import grasp_offsets, grasp_task
from mobman.dynamics.grasp import grasp_matrix
from mobman.model import robots
from mobman.model.tasks import Position, stack

YAMAMOTO_Q = "0.2,-0.1,0.3,0.3,0.8,1.1,-0.3,-0.8,-1.1"
TORQUES = np.array([200.0, 200.0, 200.0, 100.0, 30.0, 200.0, 100.0, 30.0])  # Tables 1–2: wheels, joints


def _json(args, capsys) -> dict:
    main(["ellipsoid", *args, "--json"])
    return json.loads(capsys.readouterr().out)


def _check_geometry(report: dict, expected_axes: np.ndarray, expected_form: np.ndarray | None = None) -> None:
    """Axes (major first) and directions: Σ d_k = a_k² d_k for the shape matrix Σ built independently."""
    axes = np.array(report["axes"])
    directions = np.array(report["directions"])  # one direction per row
    np.testing.assert_allclose(axes, expected_axes, rtol=1e-8)
    assert np.all(np.diff(axes) < 0)
    np.testing.assert_allclose(directions @ directions.T, np.eye(len(axes)), atol=1e-10)
    if expected_form is not None:
        np.testing.assert_allclose(
            directions @ expected_form @ directions.T, np.diag(axes**2), atol=1e-8 * axes[0] ** 2
        )
    unit_ball = math.pi ** (len(axes) / 2) / math.gamma(len(axes) / 2 + 1)
    assert math.isclose(report["volume"], unit_ball * np.prod(expected_axes), rel_tol=1e-8)


def test_kinematic_ellipsoid_is_the_svd_of_the_normalised_jacobian(capsys):
    robot = robots.bayle_planar()
    q = np.array([0.5, -0.2, 0.4, 1.0, 0.7])
    report = _json(["bayle-planar", "--q", ",".join(map(str, q))], capsys)
    jn = np.asarray(kinematics.reduced_jacobian(robot, q)) * np.array(robot.velocity_limits)
    _check_geometry(report, np.linalg.svd(jn, compute_uv=False), jn @ jn.T)
    assert report["names"] == list(robot.task.names) and report["kind"] == "kinematic"
    np.testing.assert_allclose(report["center"], 0.0)


def test_held_object_kinematic_ellipsoid_is_corrected_eq26(capsys):
    """Object velocities: {v_o : v_oᵀ W (Ĵ Ĵᵀ)⁻¹ Wᵀ v_o ≤ 1}, Ĵ = J̄ T Y⁻¹ with wheel speeds ≤ 1/r, joints ≤ 3.14."""
    robot = robots.yamamoto_dual_arm()
    q = np.array(YAMAMOTO_Q.split(","), dtype=float)
    report = _json(["yamamoto-dual-arm", "--q", YAMAMOTO_Q, "--held"], capsys)
    r, b = 0.075, 0.171
    t = np.eye(8)
    t[:2, :2] = [[r / 2, r / 2], [r / (2 * b), -r / (2 * b)]]
    jhat = (
        np.asarray(kinematics.reduced_jacobian(robot, q, grasp_task(robot)))
        @ t
        * np.array([1 / r] * 2 + [3.14] * 6)
    )
    w = np.asarray(grasp_matrix(grasp_offsets(robot, q)))
    sigma = np.linalg.inv(w @ np.linalg.inv(jhat @ jhat.T) @ w.T)
    _check_geometry(report, np.sqrt(np.linalg.eigvalsh(sigma)[::-1]), sigma)
    assert report["names"] == ["x_o", "y_o", "angle_o"] and report["held"]


def test_dynamic_exact_ellipsoid_is_the_image_of_the_torque_ball(capsys):
    """At rest without object: a = J̄ P⁻¹ B τ (P, B of the reduced dynamics, η coordinates), |Z τ| ≤ 1."""
    model = dyn.yamamoto_model()
    q = np.array(YAMAMOTO_Q.split(","), dtype=float)
    report = _json(["yamamoto-dual-arm", "--q", YAMAMOTO_Q, "--kind", "dynamic"], capsys)
    p = np.asarray(dyn.reduced_mass_matrix(model, q))
    b_mat = np.asarray(dyn.input_matrix(model, q))
    g = np.asarray(kinematics.reduced_jacobian(model.robot, q)) @ np.linalg.solve(p, b_mat) * TORQUES
    _check_geometry(report, np.linalg.svd(g, compute_uv=False), g @ g.T)
    np.testing.assert_allclose(report["torque_limits"], TORQUES)
    assert report["method"] == "exact" and report["units"].startswith("m/s²")


def test_dynamic_ellipsoid_with_velocities_is_shifted_by_the_velocity_terms(capsys):
    """--eta: a = J̄ η̇ + J̄̇ η with η̇ = P⁻¹(B τ − b): the same axes as at rest, centre J̄̇ η − J̄ P⁻¹ b
    (J̄̇ η by central differences of J̄ along q̇ = S η)."""
    model = dyn.yamamoto_model()
    q = np.array(YAMAMOTO_Q.split(","), dtype=float)
    eta = np.array([0.4, -0.3, 0.5, -0.2, 0.8, 0.1, 0.6, -0.7])
    base = ["yamamoto-dual-arm", "--q", YAMAMOTO_Q, "--kind", "dynamic"]
    rest = _json(base, capsys)
    moving = _json([*base, "--eta", ",".join(map(str, eta))], capsys)
    robot = model.robot
    q_dot = np.asarray(kinematics.S(robot, q)) @ eta
    h = 1e-6
    jbar_dot = (
        np.asarray(kinematics.reduced_jacobian(robot, q + h * q_dot))
        - np.asarray(kinematics.reduced_jacobian(robot, q - h * q_dot))
    ) / (2 * h)
    p = np.asarray(dyn.reduced_mass_matrix(model, q))
    b = np.asarray(dyn.reduced_bias(model, q, eta))
    centre = jbar_dot @ eta - np.asarray(kinematics.reduced_jacobian(robot, q)) @ np.linalg.solve(p, b)
    assert np.abs(centre).max() > 0.1
    np.testing.assert_allclose(moving["center"], centre, atol=1e-6)
    np.testing.assert_allclose(moving["axes"], rest["axes"], rtol=1e-9)
    np.testing.assert_allclose(moving["eta"], eta)


def test_dynamic_paper_ellipsoid_lies_inside_the_exact_one(capsys):
    args = ["yamamoto-dual-arm", "--q", YAMAMOTO_Q, "--kind", "dynamic", "--held"]
    exact = _json(args, capsys)
    paper = _json([*args, "--method", "paper"], capsys)
    assert paper["method"] == "paper" and paper["feasible"]
    assert 0 < paper["volume"] < exact["volume"]
    assert paper["axes"][0] <= exact["axes"][0] * (1 + 1e-9)


def test_point_grasp_from_the_command_line(capsys):
    """Hands at one point to 4-digit angles (within 1 mm): the (x_o, y_o) ellipse
    {v_o : v_oᵀ W (Ĵ Ĵᵀ)⁻¹ Wᵀ v_o ≤ 1} with W = [I₂ I₂] and Ĵ the two tool points' normalised rows."""
    q = "0,0,0,-0.8741,0.78,1.1312,0.8741,-0.78,-1.1312"
    kin = _json(["yamamoto-dual-arm", "--q", q, "--held", "--grasp", "point"], capsys)
    assert kin["names"] == ["x_o", "y_o"] and kin["grasp"] == "point" and len(kin["axes"]) == 2
    robot = robots.yamamoto_dual_arm()
    qv = np.array(q.split(","), dtype=float)
    r, b = 0.075, 0.171
    t = np.eye(8)
    t[:2, :2] = [[r / 2, r / 2], [r / (2 * b), -r / (2 * b)]]
    task = stack(Position("xy", arm=0), Position("xy", arm=1))
    jhat = np.asarray(kinematics.reduced_jacobian(robot, qv, task)) @ t * np.array([1 / r] * 2 + [3.14] * 6)
    w = np.hstack([np.eye(2), np.eye(2)])
    sigma = np.linalg.inv(w @ np.linalg.inv(jhat @ jhat.T) @ w.T)
    _check_geometry(kin, np.sqrt(np.linalg.eigvalsh(sigma)[::-1]), sigma)


def test_param_changes_the_robot(capsys):
    q = "0,0,0,1,0.7"
    base = _json(["bayle-planar", "--q", q], capsys)
    longer = _json(["bayle-planar", "--q", q, "--param", "l2=0.8"], capsys)
    assert longer["params"]["l2"] == 0.8 and base["params"]["l2"] == 0.5
    robot = robots.bayle_planar(l2=0.8)
    jn = np.asarray(kinematics.reduced_jacobian(robot, np.array([0, 0, 0, 1, 0.7]))) * np.array(
        robot.velocity_limits
    )
    np.testing.assert_allclose(longer["axes"], np.linalg.svd(jn, compute_uv=False), rtol=1e-8)
    assert not np.allclose(longer["axes"], base["axes"], rtol=1e-3)


def test_human_readable_output_lists_axes_and_volume(capsys):
    main(["ellipsoid", "bayle-planar", "--q", "0,0,0,1,0.7"])
    out = capsys.readouterr().out
    report = _json(["bayle-planar", "--q", "0,0,0,1,0.7"], capsys)
    assert "semi-axis" in out and "volume:" in out
    assert f"{report['axes'][0]:.6g}" in out and f"{report['volume']:.6g}" in out


@pytest.mark.parametrize(
    "args, message",
    [
        (["bayle-planar"], "--q"),
        (["bayle-planar", "--q", "0,0,0,1"], "--q"),
        (["bayle-planar", "--q", "0,0,0,1,x"], "--q"),
        (["bayle-planar", "--q", "0,0,0,1,1", "--kind", "static"], "--kind"),
        (["bayle-planar", "--q", "0,0,0,1,1", "--kind", "dynamic"], "dynamic model"),
        (["tchon-car-rtr", "--q", "0,0,0,0,1,1,1"], "velocity limits"),
        (["bayle-planar", "--q", "0,0,0,1,1", "--held"], "two or more arms"),
        (["yamamoto-dual-arm", "--q", YAMAMOTO_Q, "--param", "L1=-1"], "L1"),
        (["yamamoto-dual-arm", "--q", YAMAMOTO_Q, "--param", "Lx=1"], "Lx"),
        (
            ["yamamoto-dual-arm", "--q", YAMAMOTO_Q, "--kind", "dynamic", "--held", "--object-mass", "-2"],
            "--object-mass",
        ),
        (["yamamoto-dual-arm", "--q", YAMAMOTO_Q, "--kind", "dynamic", "--method", "best"], "--method"),
        (["yamamoto-dual-arm", "--q", YAMAMOTO_Q, "--kind", "dynamic", "--eta", "1,2"], "--eta"),
        (["yamamoto-dual-arm", "--q", YAMAMOTO_Q, "--eta", "0,0,0,0,0,0,0,0"], "--eta"),
        (["no-such-robot", "--q", "0"], "unknown robot"),
        (["yamamoto-dual-arm", "--q", YAMAMOTO_Q, "--held", "--grasp", "glue"], "--grasp"),
        (["yamamoto-dual-arm", "--q", YAMAMOTO_Q, "--held", "--grasp", "point"], "grasp='point'"),
    ],
)
def test_bad_input_is_one_line_and_exit_2(args, message, capsys):
    with pytest.raises(SystemExit) as info:
        main(["ellipsoid", *args])
    assert info.value.code == 2
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error:") and message in lines[0]


def test_rrp_arm_pointing_up_gives_a_finite_ellipsoid_and_the_flags(capsys):
    report = _json(["bayle-rrp", "--q", "0,0,0,0.2,1.5707963267948966,0.9"], capsys)
    assert report["representation_singular"] is False and report["outside_limits"] == []
    assert np.isfinite(report["axes"]).all() and np.isfinite(report["directions"]).all()


def test_singular_closed_chain_gets_its_degenerate_ellipsoid_flagged(capsys):
    """Both arms stretched (q = 0): their Jacobians lose rank and the closed chain's equations are singular.
    The command answers (exit 0) with the degenerate ellipsoid, flagged ``singular`` in JSON and by one line
    of the table (the ellipsoid itself: tests/test_api_contract.py)."""
    args = ["yamamoto-dual-arm", "--q", "0,0,0,0,0,0,0,0,0", "--kind", "dynamic", "--held"]
    report = _json(args, capsys)
    assert report["singular"] is True and np.isfinite(report["axes"]).all() and report["axes"][0] > 0
    main(["ellipsoid", *args])
    notes = [line for line in capsys.readouterr().out.splitlines() if line.startswith("singular")]
    assert notes == [
        "singular: the closed-chain equations (mass matrix, task Jacobian, grasp matrix) are singular: an "
        "arm's Jacobian loses rank there (stretched or folded) and its hand forces are undetermined; the "
        "ellipsoid is that of their minimum-norm solution"
    ]
    assert _json([*args, "--method", "paper"], capsys)["singular"] is False
    regular = _json(
        ["yamamoto-dual-arm", "--q", "0,0,0,0.3,0.6,0.9,-0.3,-0.6,-0.9", "--kind", "dynamic", "--held"],
        capsys,
    )
    assert regular["singular"] is False


def test_ellipsoid_outside_the_joint_limits_warns_or_fails_with_strict_limits(capsys):
    report = _json(["bayle-rrp", "--q", "0,0,0,0.2,0.5,-0.5"], capsys)
    assert report["outside_limits"] == ["q6"]
    with pytest.raises(SystemExit) as exc:
        main(["ellipsoid", "bayle-rrp", "--q", "0,0,0,0.2,0.5,-0.5", "--strict-limits"])
    assert exc.value.code == 2 and "q6 = -0.5 outside" in capsys.readouterr().err
