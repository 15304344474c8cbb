"""Fixed (model/platforms/fixed.py): an arm on a base that does not move; its placement q_p = (x, y, θ) kept as
coordinates. Closed forms, Pinocchio for a Panda read with platform="fixed", and every command on a robot
file of kind "fixed"."""

from __future__ import annotations

import math
from importlib import metadata

import numpy as np
import pinocchio as pin
import pytest
import sympy as sp

from mobman import dynamics, kinematics, symbolic
from mobman.control.laws import BaylePseudoInverse
from mobman.control.references import Line
from mobman.control.simulation import simulate
from mobman.io import robot_file
from mobman.io.urdf import read_urdf, urdf_tips, write_urdf
from mobman.model import Fixed, platform_class
from mobman.model.tasks import Position

ROBOT_FILE = """
name = "fixed-3r"

[platform]
kind = "fixed"

[[arms]]
name = "arm"
table = [[0.0, 0.3, 0.0, 1.5707963267948966], [0.0, 0.0, 0.5, 0.0], [0.0, 0.0, 0.4, 0.0]]
kinds = "RRR"
velocity_max = [1.5, 1.5, 1.5]
"""
THETAS = np.array([0.0, math.pi / 2, -math.pi / 2, math.pi, -math.pi, 0.7])


def _configurations(seed: int = 0) -> np.ndarray:
    rng = np.random.default_rng(seed)
    q = rng.uniform(-math.pi, math.pi, (len(THETAS), 6))
    q[:, 2] = THETAS
    q[0, 3:] = (math.pi / 2, -math.pi / 2, math.pi)
    return q


def _tool(q: np.ndarray) -> np.ndarray:
    """The 3R arm's tool point in closed form: reach ρ in the vertical plane at heading θ + q1."""
    x, y, theta, q1, q2, q3 = q
    rho = 0.5 * math.cos(q2) + 0.4 * math.cos(q2 + q3)
    z = 0.3 + 0.5 * math.sin(q2) + 0.4 * math.sin(q2 + q3)
    return np.array([x + rho * math.cos(theta + q1), y + rho * math.sin(theta + q1), z])


def _tool_jacobian(q: np.ndarray) -> np.ndarray:
    """∂(tool)/∂(q1, q2, q3) of :func:`_tool`, differentiated by hand."""
    _, _, theta, q1, q2, q3 = q
    rho = 0.5 * math.cos(q2) + 0.4 * math.cos(q2 + q3)
    c, s = math.cos(theta + q1), math.sin(theta + q1)
    d2, d3 = -0.5 * math.sin(q2) - 0.4 * math.sin(q2 + q3), -0.4 * math.sin(q2 + q3)
    z2, z3 = 0.5 * math.cos(q2) + 0.4 * math.cos(q2 + q3), 0.4 * math.cos(q2 + q3)
    return np.array([[-rho * s, d2 * c, d3 * c], [rho * c, d2 * s, d3 * s], [0.0, z2, z3]])


def test_kind_is_registered_and_has_no_quasi_velocity():
    assert platform_class("fixed") is Fixed
    p = Fixed()
    assert (p.n_q, p.n_eta, p.actuator_names, p.velocity_limits) == (3, 0, (), ())
    for q in _configurations()[:, :3]:
        assert np.asarray(p.S(q)).shape == (3, 0)
        np.testing.assert_array_equal(p.constraints(q), np.eye(3))
        np.testing.assert_array_equal(p.displace(q, np.zeros(0)), q)
    assert p.lie_algebra_rank(np.zeros(3)) == 0 and not p.is_controllable()


def test_robot_S_G_and_reduced_jacobian_are_the_arm_alone(tmp_path):
    (tmp_path / "fixed.toml").write_text(ROBOT_FILE)
    robot = robot_file.load(tmp_path / "fixed.toml")
    q = _configurations()
    s, g = np.asarray(robot.S(q[0])), np.asarray(robot.constraints(q[0]))
    np.testing.assert_array_equal(s, np.vstack([np.zeros((3, 3)), np.eye(3)]))
    np.testing.assert_array_equal(g, np.hstack([np.eye(3), np.zeros((3, 3))]))
    np.testing.assert_allclose(kinematics.forward(robot, q), [_tool(row) for row in q], atol=1e-14)
    np.testing.assert_allclose(
        kinematics.reduced_jacobian(robot, q), [_tool_jacobian(row) for row in q], atol=1e-14
    )
    model = symbolic.model(robot)
    assert model.S().shape == (6, 3) and model.constraints() == sp.eye(3).row_join(sp.zeros(3, 3))


def test_simulation_never_moves_the_base(tmp_path):
    (tmp_path / "fixed.toml").write_text(ROBOT_FILE)
    robot = robot_file.load(tmp_path / "fixed.toml")
    q0 = np.array([0.4, -0.2, math.pi / 2, 0.3, 0.5, 1.2])
    start = _tool(q0)
    reference = Line(tuple(start), tuple(start + np.array([-0.05, 0.05, -0.05])), duration=0.5)
    law = BaylePseudoInverse(W=2.0)
    for integrator in ("auto", "hold", "rk4"):
        run = simulate(robot, Position("xyz"), law, reference, q0, 0.5, 0.05, integrator=integrator)
        np.testing.assert_array_equal(np.asarray(run.q)[:, :3], np.broadcast_to(q0[:3], (len(run.t), 3)))
        assert np.abs(run.error).max() < (2e-2 if integrator == "hold" else 1e-4)


def test_every_command_runs_on_a_fixed_base_robot_file(tmp_path, cli_json):
    path = tmp_path / "fixed.toml"
    path.write_text(ROBOT_FILE)
    q = np.array([0.0, 0.0, math.pi, 0.3, 1.2, 0.4])
    report = cli_json(["analyze", str(path), "--q", "0,0,pi,0.3,1.2,0.4"])
    assert report["redundancy"]["delta"] == 3 and report["redundancy"]["R_bar"] == 0
    report = cli_json(["ellipsoid", str(path), "--q", "0,0,pi,0.3,1.2,0.4"])
    expected = np.linalg.svd(_tool_jacobian(q) * 1.5, compute_uv=False)
    np.testing.assert_allclose(report["axes"], expected, rtol=1e-10)
    start = _tool(np.array([0.0, 0.0, 0.0, 0.3, 0.5, 0.4])).tolist()
    control = (
        f'duration = 0.5\ndt = 0.05\nq0 = [0.0, 0.0, 0.0, 0.3, 0.5, 0.4]\n[{{p}}reference]\nkind = "line"\n'
        f"start = {start}\nend = {[start[0] - 0.05, start[1], start[2]]}\nduration = 0.5\n"
        '[{p}law]\nkind = "bayle"\n[{p}gains]\nW = 1.0\nk = 1.0\n'
    )
    (tmp_path / "spec.toml").write_text(control.format(p="") + f'[robot]\nfile = "{path}"\n')
    assert cli_json(["simulate", str(tmp_path / "spec.toml")])["max_error"] < 1e-3
    plan = cli_json(["plan", str(path), "--target", "0.5,0.3,0.6", "--x", "0.3,0.5,0.4"])
    assert plan["converged"] and np.allclose(
        _tool(np.array([0, 0, 0, *plan["x"]])), [0.5, 0.3, 0.6], atol=1e-9
    )
    load = (
        f'[robot]\nfile = "{path}"\n[motion]\nkind = "control"\n[motion.control]\n'
        + control.format(p="motion.control.")
        + "[platform]\nmass = 10.0\ninertia_z = 1.0\n"
        + "[[links]]\nmass = 2.0\ncom = [0.0, 0.0, 0.0]\ninertia = [0.01, 0.01, 0.01]\n"
        + "[[links]]\nmass = 3.0\ncom = [-0.25, 0.0, 0.0]\ninertia = [0.01, 0.06, 0.06]\n"
        + "[[links]]\nmass = 2.0\ncom = [-0.2, 0.0, 0.0]\ninertia = [0.01, 0.03, 0.03]\n"
        + '[actuators.q2]\nkind = "torque_box"\nlower = -80.0\nupper = 80.0\n'
    )
    (tmp_path / "load.toml").write_text(load)
    result = cli_json(["load-capacity", str(tmp_path / "load.toml")])
    assert (
        result["bounded"] and result["max_load_kg"] > 0 and set(result["per_actuator"]) == {"q1", "q2", "q3"}
    )


@pytest.fixture(scope="module")
def panda_path() -> str:
    files = [
        p
        for p in metadata.files("example-robot-data") or ()
        if str(p).endswith("panda_description/urdf/panda.urdf")
    ]
    assert files, "example-robot-data is installed without panda_description/urdf/panda.urdf"
    return str(files[0].locate())


def test_panda_loads_on_a_fixed_base_and_matches_pinocchio(panda_path):
    """load_urdf(platform="fixed"): the hand's position and the arm's mass matrix (Sᵀ M S) against Pinocchio
    (fingers locked at 0), the base placed at (x, y, θ)."""
    urdf = read_urdf(panda_path, tip="panda_hand", base="panda_link0", platform="fixed")
    robot = urdf.robot
    assert isinstance(robot.platform, Fixed) and robot.n_eta == 7 and urdf.summary.wheels is None
    full = pin.buildModelFromUrdf(panda_path)
    locked = [full.getJointId(n) for n in ("panda_finger_joint1", "panda_finger_joint2")]
    model = pin.buildReducedModel(full, locked, pin.neutral(full))
    data, hand = model.createData(), model.getFrameId("panda_hand")
    rng = np.random.default_rng(3)
    q_a = rng.uniform(model.lowerPositionLimit, model.upperPositionLimit, (4, 7))
    q = np.hstack(
        [rng.uniform(-1, 1, (4, 2)), np.array([[0.0], [math.pi / 2], [-math.pi / 2], [math.pi]]), q_a]
    )
    xi = np.asarray(kinematics.forward(robot, q))
    m = np.asarray(dynamics.reduced_mass_matrix(dynamics.DynamicModel.from_urdf(urdf), q))
    for k in range(len(q)):
        pin.framesForwardKinematics(model, data, q_a[k])
        c, s = math.cos(q[k, 2]), math.sin(q[k, 2])
        placed = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]) @ data.oMf[hand].translation
        np.testing.assert_allclose(xi[k], placed + [q[k, 0], q[k, 1], 0.0], atol=1e-12)
        m_pin = pin.crba(model, data, q_a[k])
        m_pin = np.triu(m_pin) + np.triu(m_pin, 1).T
        np.testing.assert_allclose(m[k], m_pin, atol=1e-10 * np.abs(m_pin).max())


def test_write_urdf_round_trip(tmp_path):
    (tmp_path / "fixed.toml").write_text(ROBOT_FILE)
    robot = robot_file.load(tmp_path / "fixed.toml")
    path = write_urdf(robot, tmp_path / "fixed.urdf")
    back = read_urdf(path, tip=urdf_tips(robot), platform="fixed").robot
    q = _configurations()
    assert back.platform == Fixed()
    np.testing.assert_allclose(kinematics.forward(back, q), kinematics.forward(robot, q), atol=1e-12)
    np.testing.assert_allclose(
        kinematics.reduced_jacobian(back, q), kinematics.reduced_jacobian(robot, q), atol=1e-12
    )
