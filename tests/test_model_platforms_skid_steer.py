"""SkidSteer (model/platforms/skid_steer.py): the Husky-type base against closed forms, the differential drive
it reduces to at x_icr = 0, χ = 1, and every command run on a robot file of kind "skid_steer"."""

from __future__ import annotations

import math

import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import solve_ivp

from mobman import ModelError, dynamics, kinematics, symbolic
from mobman.dynamics.ellipsoids import dynamic_ellipsoid
from mobman.errors import InputError
from mobman.io import robot_file
from mobman.io.urdf import read_urdf, urdf_tips, write_urdf
from mobman.model import Arm, DifferentialDrive, MobileManipulator, Mount, SkidSteer, platform_class
from mobman.model.arm import LinkInertial

R, B, L, X_ICR, CHI, SPEED = 0.165, 0.2775, 0.512, 0.05, 1.4, 6.0
THETAS = np.array([0.0, math.pi / 2, -math.pi / 2, math.pi, -math.pi, 0.3, -2.1, 2.9])

ROBOT_FILE = f"""
name = "skid-2r"
task = "xy"

[platform]
kind = "skid_steer"
wheel_radius = {R}
half_track = {B}
wheelbase = {L}
x_icr = {X_ICR}
track_factor = {CHI}
wheel_speed_max = {SPEED}

[[arms]]
name = "arm"
table = [[0.0, 0.3, 0.5, 0.0], [0.0, 0.0, 0.4, 0.0]]
kinds = "RR"
velocity_max = [1.5, 1.5]
mount = [0.1, 0.0, 0.2, 0.0]
"""
LINKS = (
    LinkInertial(4.0, (-0.25, 0.0, 0.0), (0.01, 0, 0, 0, 0.08, 0, 0, 0, 0.08)),
    LinkInertial(2.5, (-0.2, 0.0, 0.0), (0.005, 0, 0, 0, 0.03, 0, 0, 0, 0.03)),
)
BODY, WHEEL = dynamics.PlatformBody(40.0, 2.2, (0.02, 0.0, 0.1)), dynamics.Wheel(2.0, 0.03, 0.015)


def _robot(platform) -> MobileManipulator:
    arm = Arm.from_dh([[0.0, 0.3, 0.5, 0.0], [0.0, 0.0, 0.4, 0.0]], "RR", velocity_limits=[1.5, 1.5])
    return MobileManipulator(platform, (arm,), (Mount(0.1, 0.0, 0.2),)).with_link_inertials(LINKS)


def _configurations(n_arm: int = 2, seed: int = 0) -> np.ndarray:
    """Random poses and joints over the whole range, headings including exactly ±π/2 and ±π."""
    rng = np.random.default_rng(seed)
    q = rng.uniform(-math.pi, math.pi, (len(THETAS), 3 + n_arm))
    q[:, 2] = THETAS
    return q


def _rotation(theta: float) -> np.ndarray:
    c, s = math.cos(theta), math.sin(theta)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


PLATFORM = SkidSteer(R, B, L, X_ICR, CHI, wheel_speed_max=SPEED)


def test_kind_is_registered():
    assert platform_class("skid_steer") is SkidSteer
    with pytest.raises(ModelError, match="did you mean 'skid_steer'"):
        platform_class("skid_ster")


def test_S_is_the_icr_unicycle_and_the_constraint_annihilates_it():
    """S = R(θ) (e_x, −x_icr e_y + e_z) (Kozłowski & Pazderski eq. 9–11), G S = 0 with G = (sin θ, −cos θ, −x_icr)."""
    for q in _configurations()[:, :3]:
        s = np.asarray(PLATFORM.S(q))
        expected = _rotation(q[2]) @ np.array([[1.0, 0.0], [0.0, -X_ICR], [0.0, 1.0]])
        np.testing.assert_allclose(s, expected, atol=1e-15)
        g = np.asarray(PLATFORM.constraints(q))
        np.testing.assert_allclose(g, [[math.sin(q[2]), -math.cos(q[2]), -X_ICR]], atol=1e-15)
        np.testing.assert_allclose(g @ s, 0.0, atol=1e-15)
        assert PLATFORM.lie_algebra_rank(q, depth=2) == 3


@settings(max_examples=25, deadline=None)
@given(
    theta=st.sampled_from([math.pi / 2, -math.pi / 2, math.pi]) | st.floats(-math.pi, math.pi),
    x_icr=st.floats(-0.25, 0.25),
    chi=st.floats(1.0, 3.0),
)
def test_constraint_and_wheel_rows_hold_for_any_parameters(theta, x_icr, chi):
    p = SkidSteer(R, B, L, x_icr, chi)
    q = np.array([0.3, -0.2, theta])
    s = np.asarray(p.S(q))
    np.testing.assert_allclose(np.asarray(p.constraints(q)) @ s, 0.0, atol=1e-15)
    inverse = np.array([[1.0, chi * B], [1.0, -chi * B]]) / R  # (φ̇_r, φ̇_l) = ((v ± χbω)/r)
    np.testing.assert_allclose(np.asarray(p.actuator_rows(q)) @ s, inverse, rtol=1e-13, atol=1e-13)


def test_S_and_constraints_agree_with_the_symbolic_model():
    robot = _robot(PLATFORM)
    model = symbolic.model(robot)
    assert model.constants.values["platform.x_icr"] == sp.Rational(1, 20)
    s_fn = sp.lambdify(model.q, model.S(), "numpy")
    g_fn = sp.lambdify(model.q, model.constraints(), "numpy")
    for q in _configurations():
        np.testing.assert_allclose(np.asarray(s_fn(*q), float), np.asarray(robot.S(q)), atol=1e-14)
        np.testing.assert_allclose(np.asarray(g_fn(*q), float), np.asarray(robot.constraints(q)), atol=1e-14)


def test_wheel_matrix_is_the_track_factor_closed_form():
    """v = r(φ̇_r + φ̇_l)/2, ω = r(φ̇_r − φ̇_l)/(2χb) (Mandow et al. 2007); A S = T⁻¹ on the admissible motions."""
    t = np.array([[R / 2, R / 2], [R / (2 * CHI * B), -R / (2 * CHI * B)]])
    np.testing.assert_allclose(PLATFORM.actuator_matrix(), t, rtol=1e-15)
    np.testing.assert_allclose(PLATFORM.wheel_speeds_to_eta(np.array([3.0, 1.0])), [2 * R, R / (CHI * B)])
    for q in _configurations()[:, :3]:
        rows = np.asarray(PLATFORM.actuator_rows(q))
        np.testing.assert_allclose(rows @ np.asarray(PLATFORM.S(q)), np.linalg.inv(t), atol=1e-13)
    assert PLATFORM.velocity_limits == pytest.approx((R * SPEED, R * SPEED / (CHI * B)), rel=1e-15)
    assert PLATFORM.actuator_names == ("wheels_right", "wheels_left")
    sides = [(w.y < 0, w.actuator) for w in PLATFORM.wheels()]
    assert sorted(sides) == [(False, 1), (False, 1), (True, 0), (True, 0)]
    assert {(abs(w.x), abs(w.y)) for w in PLATFORM.wheels()} == {(L / 2, B)}


def test_displace_is_the_exact_flow_at_constant_eta():
    """The SE(2) exponential of the body twist (v, −x_icr ω, ω) against a tight numerical integration."""
    for q0 in _configurations()[:, :3]:
        for eta in (np.array([0.7, 1.3]), np.array([-0.4, 0.0]), np.array([0.0, -2.0])):
            exact = solve_ivp(
                lambda _, q, eta=eta: np.asarray(PLATFORM.S(q)) @ eta, (0, 0.8), q0, rtol=1e-12, atol=1e-12
            )
            np.testing.assert_allclose(
                np.asarray(PLATFORM.displace(q0, 0.8 * eta)), exact.y[:, -1], atol=1e-9
            )


def test_equals_a_differential_drive_at_zero_offset_without_slip():
    """x_icr = 0, χ = 1: the same S, J̄ and E; M equal to the two-wheel model with each wheel counted twice and
    the four wheels' parallel-axis inertia 4 m_w (wheelbase/2)² added to the body's."""
    skid = _robot(SkidSteer(R, B, L, 0.0, 1.0))
    diff = _robot(DifferentialDrive(R, B))
    twice = dynamics.Wheel(2 * WHEEL.mass, 2 * WHEEL.I_w, 2 * WHEEL.I_m)
    body = dynamics.PlatformBody(BODY.mass, BODY.inertia_z + 4 * WHEEL.mass * (L / 2) ** 2, BODY.com)
    skid_model = dynamics.DynamicModel(skid, BODY, WHEEL, gravity=(0.0, 0.0, -9.81))
    diff_model = dynamics.DynamicModel(diff, body, twice, gravity=(0.0, 0.0, -9.81))
    q = _configurations()
    np.testing.assert_allclose(
        kinematics.reduced_jacobian(skid, q), kinematics.reduced_jacobian(diff, q), atol=1e-14
    )
    m_skid, m_diff = dynamics.mass_matrix(skid_model, q), dynamics.mass_matrix(diff_model, q)
    np.testing.assert_allclose(m_skid, m_diff, atol=1e-12)
    np.testing.assert_allclose(
        dynamics.actuation_matrix(skid_model, q), dynamics.actuation_matrix(diff_model, q), atol=1e-13
    )


def test_dynamic_model_needs_the_wheels_and_gives_a_finite_ellipsoid():
    robot = _robot(PLATFORM)
    with pytest.raises(ModelError, match="wheel must be a Wheel"):
        dynamics.DynamicModel(robot, BODY)
    model = dynamics.DynamicModel(robot, BODY, WHEEL)
    assert model.actuator_names == ("wheels_right", "wheels_left", "q1", "q2")
    q = _configurations()[:2]
    ellipsoid = dynamic_ellipsoid(model, q, [30.0, 30.0, 20.0, 10.0], method="exact")
    assert np.all(np.isfinite(ellipsoid.shape_matrix)) and np.all(ellipsoid.feasible)


@pytest.mark.parametrize(
    ("key", "value", "message"),
    [
        ("x_icr", "0.3", "x_icr must be in"),
        ("track_factor", "0.9", "track_factor must be"),
        ("wheelbase", "-1", ""),
    ],
)
def test_bad_parameters_are_one_line_errors(tmp_path, key, value, message):
    text = "\n".join(
        f"{key} = {value}" if line.startswith(f"{key} =") else line for line in ROBOT_FILE.splitlines()
    )
    (tmp_path / "bad.toml").write_text(text)
    with pytest.raises(InputError, match=f"platform: SkidSteer: {message}"):
        robot_file.load(tmp_path / "bad.toml")


def test_every_command_runs_on_a_skid_steer_robot_file(tmp_path, cli_json):
    path = tmp_path / "skid.toml"
    path.write_text(ROBOT_FILE)
    robot = robot_file.load(path)
    assert robot.platform == PLATFORM
    q = np.array([0.2, -0.1, math.pi / 2, 0.3, 1.2])
    q_text = "0.2,-0.1,pi/2,0.3,1.2"

    report = cli_json(["analyze", str(path), "--q", q_text])
    assert report["redundancy"] == {"M": 5, "delta": 4, "D": 2, "R": 3, "D_bar": 2, "R_bar": 2}

    # kinematic ellipsoid in wheel-side speeds: the image of |ū| ≤ 1 under J̄ T diag(u_max)
    report = cli_json(["ellipsoid", str(path), "--q", q_text])
    t = np.eye(4)
    t[:2, :2] = [[R / 2, R / 2], [R / (2 * CHI * B), -R / (2 * CHI * B)]]
    j_hat = np.asarray(kinematics.reduced_jacobian(robot, q)) @ t @ np.diag([SPEED, SPEED, 1.5, 1.5])
    np.testing.assert_allclose(report["axes"], np.linalg.svd(j_hat, compute_uv=False), rtol=1e-8)

    # the tool at q0 = (0, 0, 0, 0.3, 1.2): mount x 0.1, links 0.5 and 0.4
    start = [0.1 + 0.5 * math.cos(0.3) + 0.4 * math.cos(1.5), 0.5 * math.sin(0.3) + 0.4 * math.sin(1.5)]
    spec = tmp_path / "spec.toml"
    spec.write_text(
        f'duration = 0.5\ndt = 0.05\nq0 = "0, 0, 0, 0.3, 1.2"\n[robot]\nfile = "skid.toml"\n'
        f'[task]\nkind = "position"\ncomponents = "xy"\n'
        f'[reference]\nkind = "line"\nstart = {start}\nend = [1.2, 0.6]\nduration = 0.5\n'
        '[law]\nkind = "bayle"\n[criterion]\nkind = "manipulability"\nmeasure = "eccentricity"\n'
        "[gains]\nW = 1.0\nk = 1.0\n"
    )
    summary = cli_json(["simulate", str(spec)])
    assert summary["max_error"] < 1e-2

    plan = cli_json(["plan", str(path), "--target", "1.5,0.5", "--harmonics", "1"])
    assert plan["converged"] and plan["final_error"] < 1e-10

    links = "".join(
        f"[[links]]\nmass = {link.mass}\ncom = {list(link.com)}\ninertia = {list(link.inertia)}\n"
        for link in LINKS
    )
    load = tmp_path / "load.toml"
    load.write_text(
        f'[robot]\nfile = "{path}"\n[motion]\nkind = "control"\n[motion.control]\nduration = 0.5\ndt = 0.05\n'
        f'q0 = [0.0, 0.0, 0.0, 0.3, 1.2]\n[motion.control.reference]\nkind = "line"\nstart = {start}\n'
        'end = [1.2, 0.6]\nduration = 0.5\n[motion.control.law]\nkind = "bayle"\n'
        "[motion.control.gains]\nW = 1.0\nk = 1.0\n"
        f"[platform]\nmass = {BODY.mass}\ninertia_z = {BODY.inertia_z}\n"
        f"[wheel]\nmass = {WHEEL.mass}\nI_w = {WHEEL.I_w}\nI_m = {WHEEL.I_m}\n{links}"
        '[actuators.wheels_right]\nkind = "torque_box"\nlower = -40.0\nupper = 40.0\n'
        '[actuators.q1]\nkind = "torque_box"\nlower = -60.0\nupper = 60.0\n'
    )
    result = cli_json(["load-capacity", str(load)])
    assert result["bounded"] and result["max_load_kg"] > 0
    assert set(result["per_actuator"]) == {"wheels_right", "wheels_left", "q1", "q2"}


def test_urdf_round_trip_keeps_xi_jbar_and_m(tmp_path):
    robot = _robot(PLATFORM)
    model = dynamics.DynamicModel(robot, BODY, WHEEL)
    path = write_urdf(robot, tmp_path / "skid.urdf", BODY, WHEEL)
    back = read_urdf(
        path,
        tip=urdf_tips(robot),
        platform="skid_steer",
        platform_options={"x_icr": X_ICR, "track_factor": CHI},
    )
    assert back.robot.platform == PLATFORM
    assert back.summary.wheels == ("wheel_front_right_joint", "wheel_front_left_joint")
    q = _configurations()
    np.testing.assert_allclose(kinematics.forward(back.robot, q), kinematics.forward(robot, q), atol=1e-12)
    np.testing.assert_allclose(
        kinematics.reduced_jacobian(back.robot, q), kinematics.reduced_jacobian(robot, q), atol=1e-12
    )
    # the URDF lumps the wheels' mass and inertia about the vertical into the body: the same planar M
    m, m_back = dynamics.mass_matrix(model, q), dynamics.mass_matrix(dynamics.DynamicModel.from_urdf(back), q)
    np.testing.assert_allclose(m_back, m, atol=1e-12 * np.abs(m).max())


def test_viewer_draws_the_four_wheels_at_the_axles(tmp_path):
    from mobman.viz.viewer import Viewer

    path = tmp_path / "skid.toml"
    path.write_text(ROBOT_FILE)
    robot = robot_file.load(path)
    with Viewer(robot, port=0) as v:
        wheels = sorted(n for n in v.nodes if n.startswith("/robot/platform/wheel"))
        assert len(wheels) == 4
        centres = sorted(tuple(np.asarray(v.nodes[n].vertices, dtype=float).mean(axis=0)[:2]) for n in wheels)
        a, b = PLATFORM.wheelbase / 2, PLATFORM.half_track
        np.testing.assert_allclose(centres, sorted((x, y) for x in (a, -a) for y in (b, -b)), atol=1e-6)
