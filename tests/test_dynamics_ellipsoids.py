"""Task-space ellipsoids (Yamamoto & Yun eq. 23–38): derivations checked by sampling and by independent formulas."""

from __future__ import annotations

import math

import numpy as np
import pytest

from mobman import dynamics as dyn
from mobman import kinematics
from mobman.dynamics.ellipsoids import (
    Ellipsoid,
    actuator_map,
    actuator_velocity_limits,
    closed_chain_matrices,
    dynamic_ellipsoid,
    dynamic_terms,
    grasp_offsets,
    grasp_task,
    kinematic_ellipsoid,
)
from mobman.dynamics.grasp import HeldObject, grasp_matrix
from mobman.errors import InputError, ModelError
from mobman.model import robots
from mobman.model.tasks import PlanarAngle, Position, stack

RNG = np.random.default_rng(3)
LIMITS = np.array([200.0, 200.0, 200.0, 100.0, 30.0, 200.0, 100.0, 30.0])
OBJ = HeldObject(2.0, (0.0, 0.0, 0.01))


@pytest.fixture(scope="module")
def model():
    return dyn.yamamoto_model()


@pytest.fixture(scope="module")
def robot(model):
    return model.robot


@pytest.fixture(scope="module")
def qs(robot):
    """Three configurations with both hands apart (non-zero grasp offsets), away from singularities."""
    q = RNG.uniform(-1.0, 1.0, size=(3, robot.n_q))
    q[:, [4, 7]] = RNG.uniform(0.6, 1.4, size=(3, 2)) * np.array([1, -1])
    return q


def _jhat(robot, q, scale=1.0, task=None):
    """Ĵ = J̄ T Y⁻¹ of eq. 24, written out here: wheel matrix and speed limits from the platform's parameters;
    J̄ of ``task`` (default: the held-object grasp task)."""
    platform = robot.platform
    t = np.eye(robot.n_eta)
    t[:2, :2] = [
        [platform.wheel_radius / 2] * 2,
        [
            platform.wheel_radius / (2 * platform.half_track),
            -platform.wheel_radius / (2 * platform.half_track),
        ],
    ]
    u_max = np.array([platform.wheel_speed_max * scale] * 2 + [3.14] * 6)
    return np.asarray(kinematics.reduced_jacobian(robot, q, task or grasp_task(robot))) @ t * u_max


# --- kinematic ---------------------------------------------------------------------------------------


def test_held_kinematic_ellipsoid_is_corrected_eq26(robot, qs):
    """v_oᵀ W (Ĵ Ĵᵀ)⁻¹ Wᵀ v_o ≤ 1: the printed eq. 26 without its extra Y."""
    e = kinematic_ellipsoid(robot, qs, held=True)
    jhat = _jhat(robot, qs)
    w = np.asarray(grasp_matrix(grasp_offsets(robot, qs)))
    form = w @ np.linalg.inv(jhat @ np.swapaxes(jhat, -1, -2)) @ np.swapaxes(w, -1, -2)
    np.testing.assert_allclose(np.linalg.inv(e.shape_matrix), form, rtol=1e-8)
    assert e.names == ("x_o", "y_o", "angle_o")


def test_held_kinematic_ellipsoid_is_the_image_of_the_unit_ball(robot, qs):
    """Sampling: every normalised rate |ū| ≤ 1 that keeps the grasp rigid moves the object inside E, and every
    boundary point of E needs a normalised rate of norm exactly 1."""
    full = kinematic_ellipsoid(robot, qs, held=True)
    e = Ellipsoid(full.center[0], full.matrix[0], full.names, full.feasible[0])
    jhat = _jhat(robot, qs)[0]
    w = np.asarray(grasp_matrix(grasp_offsets(robot, qs)))[0]
    # rigid-grasp rates: Ĵ ū ∈ range Wᵀ
    internal = np.eye(6) - np.linalg.pinv(w) @ w
    _, s, vt = np.linalg.svd(internal @ jhat)
    null = vt[np.sum(s > 1e-10) :].T
    u = RNG.normal(size=(20000, null.shape[1]))
    u *= (RNG.uniform(size=(20000, 1)) ** 0.2) / np.linalg.norm(u, axis=1, keepdims=True)
    rates = u @ null.T
    v_o = np.linalg.lstsq(w.T, (jhat @ rates.T), rcond=None)[0].T
    np.testing.assert_allclose(w.T @ v_o.T, jhat @ rates.T, atol=1e-10)  # the grasp is respected
    assert np.all(e.contains(v_o, tol=1e-9))
    # the samples fill E: along each principal axis they reach (almost) its end
    reach = np.max(np.abs(v_o @ e.directions), axis=0)
    assert np.all(reach > 0.8 * e.axes)
    # boundary points need exactly unit norm (minimum-norm rate Ĵ⁺ Wᵀ v_o)
    boundary = e.matrix @ np.linalg.svd(e.matrix)[2][:3].T  # images of unit vectors of the row space
    needed = np.linalg.norm(np.linalg.pinv(jhat) @ w.T @ boundary, axis=0)
    np.testing.assert_allclose(needed, 1.0, atol=1e-9)


def test_printed_eq26_is_a_typo(robot, qs):
    """(Y Ĵ⁺ Wᵀ)ᵀ(Y Ĵ⁺ Wᵀ) as printed weighs the rates by Y twice: not the image of the unit ball."""
    e = kinematic_ellipsoid(robot, qs, held=True)
    jhat = _jhat(robot, qs)
    w = np.asarray(grasp_matrix(grasp_offsets(robot, qs)))
    y = 1.0 / np.array([1 / 0.075] * 2 + [3.14] * 6)
    printed = np.diag(y) @ np.linalg.pinv(jhat) @ np.swapaxes(w, -1, -2)
    form = np.swapaxes(printed, -1, -2) @ printed
    assert np.all(np.abs(form / np.linalg.inv(e.shape_matrix) - 1).max(axis=(-1, -2)) > 0.5)


def test_single_task_kinematic_ellipsoid_is_the_normalised_jacobian_image():
    robot = robots.bayle_planar()
    q = RNG.uniform(-1, 1, size=(4, robot.n_q))
    e = kinematic_ellipsoid(robot, q)
    jn = np.asarray(kinematics.reduced_jacobian(robot, q)) * np.array(robot.velocity_limits)
    np.testing.assert_allclose(e.axes, np.linalg.svd(jn, compute_uv=False), rtol=1e-10)
    np.testing.assert_allclose(
        np.abs(np.einsum("...ij,...ij->...j", e.directions, np.linalg.svd(jn)[0])), 1.0, atol=1e-8
    )
    assert e.names == robot.task.names


def test_platform_scale_zero_is_the_fixed_dual_arm(robot, qs):
    e = kinematic_ellipsoid(robot, qs, held=True, platform_scale=0.0)
    jhat = _jhat(robot, qs)[..., 2:]  # the arms' columns only
    w = np.asarray(grasp_matrix(grasp_offsets(robot, qs)))
    fixed = w @ np.linalg.inv(jhat @ np.swapaxes(jhat, -1, -2)) @ np.swapaxes(w, -1, -2)
    np.testing.assert_allclose(np.linalg.inv(e.shape_matrix), fixed, rtol=1e-8)


def test_platform_scale_broadcasts_and_grows_the_ellipsoid(robot, qs):
    scales = np.array([0.0, 0.5, 1.0])
    e = kinematic_ellipsoid(robot, qs[:, None], held=True, platform_scale=scales)
    assert e.axes.shape == (3, 3, 3)
    np.testing.assert_allclose(e.matrix[:, 2], kinematic_ellipsoid(robot, qs, held=True).matrix, atol=1e-12)
    assert np.all(np.diff(e.volume, axis=1) > 0)


def test_actuator_coordinates(robot):
    t = actuator_map(robot, wheels=True)
    np.testing.assert_allclose(t[:2, :2], robot.platform.wheel_matrix())
    np.testing.assert_allclose(actuator_velocity_limits(robot, 0.5)[:2], 0.5 / 0.075)


def test_kinematic_errors(robot, qs):
    with pytest.raises(InputError, match="platform_scale"):
        kinematic_ellipsoid(robot, qs[0], held=True, platform_scale=-1.0)
    with pytest.raises(ModelError, match="two or more arms"):
        kinematic_ellipsoid(robots.bayle_planar(), np.zeros(5), held=True)
    with pytest.raises(ModelError, match="velocity limits"):
        kinematic_ellipsoid(robots.tchon_car_rtr(), np.zeros(7))
    with pytest.raises(InputError, match="coordinates"):
        kinematic_ellipsoid(robot, np.zeros(4))


# --- the Ellipsoid object ----------------------------------------------------------------------------


def test_ellipsoid_geometry_against_brute_force():
    a = RNG.normal(size=(3, 3))
    e = Ellipsoid(np.array([0.1, -0.2, 0.3]), a, ("a", "b", "c"), np.array(True))
    assert math.isclose(float(e.volume), 4 / 3 * math.pi * abs(np.linalg.det(a)), rel_tol=1e-10)
    d = e.directions
    np.testing.assert_allclose(d.T @ d, np.eye(3), atol=1e-12)
    assert np.all(np.diff(e.axes) <= 0)
    # points of the boundary, from the matrix form, on the ellipsoid
    s = RNG.normal(size=(500, 3))
    s /= np.linalg.norm(s, axis=1, keepdims=True)
    pts = e.center + s @ a.T
    assert np.all(e.contains(pts, tol=1e-9)) and not np.any(e.contains(e.center + 1.01 * (pts - e.center)))
    # section at c = 0.05 and projection, against a dense sample of the solid ellipsoid
    inner = e.center + (s * RNG.uniform(size=(500, 1)) ** (1 / 3)) @ a.T
    solid = np.concatenate([pts, inner])
    proj = e.projection([0, 1])
    assert np.all(proj.contains(solid[:, :2], tol=1e-9))
    sec = e.section([0, 1], at=[0.05])
    grid = np.stack(np.meshgrid(np.linspace(-3, 3, 121), np.linspace(-3, 3, 121)), -1).reshape(-1, 2)
    inside_3d = e.contains(np.concatenate([grid, np.full((len(grid), 1), 0.05)], axis=1))
    np.testing.assert_array_equal(sec.contains(grid), inside_3d)
    outline = e.boundary(64)
    assert outline.shape == (64, 2) and np.all(proj.contains(outline, tol=1e-9))


# --- dynamic -----------------------------------------------------------------------------------------


def _independent_forward_map(model, q, task_rows, obj):
    """a_o = G τ at rest, derived here by the object's operational-space inertia (Schur complement):
    u̇ = P⁻¹(Qτ − Jᵀh), J u̇ = Wᵀ a_o, M_o a_o = W h ⇒ (M_o + W Λ_e Wᵀ) a_o = W Λ_e J P⁻¹ Q τ, Λ_e = (J P⁻¹ Jᵀ)⁻¹,
    in η coordinates (P = SᵀMS, Q = SᵀE from the dynamics API)."""
    robot = model.robot
    p = np.asarray(dyn.reduced_mass_matrix(model, q))
    b = np.asarray(dyn.input_matrix(model, q))
    j = np.asarray(kinematics.reduced_jacobian(robot, q, task_rows))
    jp = j @ np.linalg.inv(p)
    if obj is None:
        return jp @ b
    w = np.asarray(grasp_matrix(grasp_offsets(robot, q)))
    wt = np.swapaxes(w, -1, -2)
    lam_e = np.linalg.inv(jp @ np.swapaxes(j, -1, -2))
    return np.linalg.solve(obj.mass_matrix() + w @ lam_e @ wt, w @ lam_e @ jp @ b)


@pytest.fixture(scope="module")
def held_terms(model, qs):
    return dynamic_terms(model, qs, obj=OBJ)


def test_exact_dynamic_ellipsoid_is_the_image_of_the_torque_ball(model, qs):
    e = dynamic_ellipsoid(model, qs, LIMITS, obj=OBJ, method="exact")
    g = _independent_forward_map(model, qs, grasp_task(model.robot), OBJ)
    np.testing.assert_allclose(e.matrix, g * LIMITS, rtol=1e-7, atol=1e-9)
    np.testing.assert_allclose(e.center, 0.0, atol=1e-9)  # at rest, no gravity in the plane


ARM_TASK = stack(Position("xy", arm=0), PlanarAngle(arm=0))


def test_exact_dynamic_ellipsoid_without_object_is_the_image_of_the_torque_box(model, qs):
    """No object: sampled torques in the box give a = J̄ P⁻¹ B τ (P, B from the dynamics API) = K τ̄."""
    e = dynamic_ellipsoid(model, qs, LIMITS, method="exact", task=ARM_TASK)
    g = _independent_forward_map(model, qs, ARM_TASK, None)
    tau_bar = RNG.uniform(-1, 1, size=(50, 8))
    for k in range(len(qs)):
        a = (tau_bar * LIMITS) @ g[k].T
        np.testing.assert_allclose(a, tau_bar @ e.matrix[k].T, rtol=1e-8, atol=1e-8)
        assert np.all(
            Ellipsoid(e.center[k], e.matrix[k], e.names, e.feasible[k]).contains(a / np.sqrt(8), tol=1e-9)
        )  # |τ̄| ≤ √8 in the box: scaled into the ball


def test_paper_ellipsoid_is_consistent_and_inside_the_exact_one(model, qs, held_terms):
    """τ = Λ_o a_o (eq. 33) produces a_o through the closed-chain dynamics (G Λ = I), and since it is one
    particular torque the paper's ellipsoid lies inside the image of the whole torque ball."""
    paper = dynamic_ellipsoid(model, qs, LIMITS, obj=OBJ, method="paper")
    exact = dynamic_ellipsoid(model, qs, LIMITS, obj=OBJ, method="exact")
    g, _, _ = closed_chain_matrices(held_terms)
    lam = np.linalg.pinv(paper.matrix) * LIMITS[:, None]  # at rest ρ = 1 and K = Λ̄⁺, Λ = Z⁻¹ Λ̄
    np.testing.assert_allclose(g @ lam, np.broadcast_to(np.eye(3), (3, 3, 3)), atol=1e-8)
    s = RNG.normal(size=(200, 3))
    s /= np.linalg.norm(s, axis=1, keepdims=True)
    for k in range(len(qs)):
        inside = Ellipsoid(exact.center[k], exact.matrix[k], exact.names, exact.feasible[k])
        boundary = paper.center[k] + s @ (paper.directions[k] * paper.axes[k]).T
        assert np.all(inside.contains(boundary, tol=1e-9))
    assert np.all(exact.volume > paper.volume)


def test_non_redundant_case_paper_equals_exact(model, qs):
    """Platform braked, one arm's (x, y, angle): Λ̄ is square-invertible on that arm, both ellipsoids coincide."""
    kw = dict(task=ARM_TASK, platform_fixed=True)
    paper = dynamic_ellipsoid(model, qs, LIMITS, method="paper", **kw)
    exact = dynamic_ellipsoid(model, qs, LIMITS, method="exact", **kw)
    np.testing.assert_allclose(paper.shape_matrix, exact.shape_matrix, rtol=1e-8)


ETA = 0.5 * np.random.default_rng(11).normal(size=(3, 8))


@pytest.fixture(scope="module")
def moving_terms(model, qs):
    return dynamic_terms(model, qs, eta=ETA, obj=OBJ)


def test_drift_matches_finite_difference(model, qs, moving_terms):
    """J̇ u − Ẇᵀ v_o of the closure (eq. 21, 27 with velocities) against a central difference of J̄ along
    q̇ = S η, and Ẇ of the rigid grasp."""
    from mobman.dynamics.grasp import grasp_matrix_rate

    robot = model.robot
    task = grasp_task(robot)
    h = 1e-6
    dq = np.einsum("kij,kj->ki", np.asarray(kinematics.S(robot, qs)), ETA)
    fd = (
        np.asarray(kinematics.reduced_jacobian(robot, qs + h * dq, task))
        - np.asarray(kinematics.reduced_jacobian(robot, qs - h * dq, task))
    ) / (2 * h)
    j = np.asarray(kinematics.reduced_jacobian(robot, qs, task))
    w = np.asarray(grasp_matrix(grasp_offsets(robot, qs)))
    v_o = np.linalg.lstsq(w[0].T, j[0] @ ETA[0], rcond=None)[0]
    w_dot = np.asarray(grasp_matrix_rate(grasp_offsets(robot, qs[0]), v_o[2]))
    expected = fd[0] @ ETA[0] - w_dot.T @ v_o
    np.testing.assert_allclose(moving_terms.drift[0], expected, rtol=1e-6, atol=1e-6)


def test_velocity_offset_mu_corrected_eq35(model, qs, moving_terms):
    """With velocities, the torque τ = Λ_o a_o + μ_o must produce a_o in the closed-chain dynamics for every a_o;
    that holds with μ_o = Q⁻¹(−ξ + P J⁺(Ẇᵀv_o − J̇u) + JᵀW⁺(c_o + g_o)) and fails with the printed +Q⁻¹ξ. The
    ellipsoid's centre is −Λ̄⁺μ̄ (eq. 38)."""
    eta, t = ETA, moving_terms
    g, g0, _ = closed_chain_matrices(t)
    j_plus, w_plus = np.linalg.pinv(t.j), np.linalg.pinv(t.w)
    jt = np.swapaxes(t.j, -1, -2)
    lam = np.linalg.solve(t.q, t.p @ j_plus @ np.swapaxes(t.w, -1, -2) + jt @ w_plus @ t.m_o)
    rest = np.einsum("kij,kj->ki", jt @ w_plus, t.bias_o) - np.einsum("kij,kj->ki", t.p @ j_plus, t.drift)
    mu = np.linalg.solve(t.q, (t.b + rest)[..., None])[..., 0]
    mu_printed = np.linalg.solve(t.q, (-t.b + rest)[..., None])[..., 0]
    a_o = RNG.normal(size=(3, 3))
    produced = np.einsum("kij,kj->ki", g, np.einsum("kij,kj->ki", lam, a_o) + mu) + g0
    np.testing.assert_allclose(produced, a_o, atol=1e-8)
    printed = np.einsum("kij,kj->ki", g, np.einsum("kij,kj->ki", lam, a_o) + mu_printed) + g0
    assert np.max(np.abs(printed - a_o)) > 1e-3
    e = dynamic_ellipsoid(model, qs, LIMITS, eta=eta, obj=OBJ, method="paper")
    lam_bar, mu_bar = lam / LIMITS[:, None], mu / LIMITS
    np.testing.assert_allclose(e.center, -np.einsum("kij,kj->ki", np.linalg.pinv(lam_bar), mu_bar), atol=1e-9)
    assert np.all(e.feasible) and not np.allclose(e.center, 0.0)
    # points of the boundary satisfy eq. 38 with equality
    s = RNG.normal(size=(3, 3))
    s /= np.linalg.norm(s, axis=1, keepdims=True)
    pts = e.center + np.einsum("kij,kj->ki", e.directions * e.axes[:, None, :], s)
    lhs = np.einsum("kij,kj->ki", lam_bar, pts) + mu_bar
    np.testing.assert_allclose(np.sum(lhs**2, axis=1), 1.0, atol=1e-9)


def test_dynamic_errors(model, qs):
    with pytest.raises(InputError, match="torque_limits"):
        dynamic_ellipsoid(model, qs[0], LIMITS[:5])
    with pytest.raises(InputError, match="torque_limits"):
        dynamic_ellipsoid(model, qs[0], -LIMITS)
    with pytest.raises(InputError, match="method"):
        dynamic_ellipsoid(model, qs[0], LIMITS, method="best")
    with pytest.raises(InputError, match="platform_scale"):
        dynamic_ellipsoid(model, qs[0], LIMITS, platform_scale=0.0)
    with pytest.raises(InputError, match="eta"):
        dynamic_ellipsoid(model, qs[0], LIMITS, eta=np.zeros(3))


# --- point grasp (hands at the object's centre of mass through pivots) ----------------------------------


@pytest.fixture(scope="module")
def q_point(robot):
    """Three configurations with both tool points at one point (mirror arms about a direction from the base)."""
    from mobman.experiments.yamamoto1999 import paper_configuration

    out = []
    for angle, posture, pose in (
        (20.0, (0.7, 1.2), (0.3, -0.2, 0.4)),
        (75.0, (1.0, 0.9), (-1.0, 0.5, -0.7)),
        (-40.0, (0.5, 1.5), (0.0, 0.0, 2.0)),
    ):
        q = paper_configuration(robot, angle, posture)
        q[:3] = pose
        out.append(q)
    return np.array(out)


def test_point_grasp_kinematic_ellipsoid(robot, q_point):
    """{v_o : v_oᵀ W (Ĵ Ĵᵀ)⁻¹ Wᵀ v_o ≤ 1} with W = [I₂ I₂] and Ĵ the two tool points' rows."""
    e = kinematic_ellipsoid(robot, q_point, held=True, grasp="point")
    assert robot.platform.wheel_speed_max == 1 / 0.075  # Table 2's wheel speed limit
    jhat = _jhat(robot, q_point, task=stack(Position("xy", arm=0), Position("xy", arm=1)))
    w = np.hstack([np.eye(2), np.eye(2)])
    form = w @ np.linalg.inv(jhat @ np.swapaxes(jhat, -1, -2)) @ w.T
    np.testing.assert_allclose(np.linalg.inv(e.shape_matrix), form, rtol=1e-8)
    assert e.names == ("x_o", "y_o")


def test_point_grasp_exact_dynamic_ellipsoid_is_the_image_of_the_torque_ball(model, q_point):
    """a_o = G τ at rest by the object's operational-space inertia with W = [I₂ I₂], M_o = m I₂:
    (M_o + W Λ_e Wᵀ) a_o = W Λ_e J P⁻¹ B τ, Λ_e = (J P⁻¹ Jᵀ)⁻¹ (η coordinates, P and B from the dynamics API)."""
    e = dynamic_ellipsoid(model, q_point, LIMITS, obj=OBJ, method="exact", grasp="point")
    task = stack(Position("xy", arm=0), Position("xy", arm=1))
    p = np.asarray(dyn.reduced_mass_matrix(model, q_point))
    b = np.asarray(dyn.input_matrix(model, q_point))
    j = np.asarray(kinematics.reduced_jacobian(model.robot, q_point, task))
    jp = j @ np.linalg.inv(p)
    lam_e = np.linalg.inv(jp @ np.swapaxes(j, -1, -2))
    w = np.hstack([np.eye(2), np.eye(2)])
    g = np.linalg.solve(OBJ.mass * np.eye(2) + w @ lam_e @ w.T, w @ lam_e @ jp @ b)
    np.testing.assert_allclose(e.matrix, g * LIMITS, rtol=1e-7, atol=1e-9)
    paper = dynamic_ellipsoid(model, q_point, LIMITS, obj=OBJ, method="paper", grasp="point")
    assert np.all(paper.volume < e.volume) and paper.names == ("x_o", "y_o")


def test_point_grasp_needs_the_hands_at_one_point(model, robot, qs):
    with pytest.raises(InputError, match="grasp='point'"):
        kinematic_ellipsoid(robot, qs, held=True, grasp="point")
    with pytest.raises(InputError, match="grasp"):
        dynamic_ellipsoid(model, qs[0], LIMITS, obj=OBJ, grasp="glued")
