"""Properties of the dynamics core: structure of M, c, g; reduction; wheels; simulation (energy, no slip)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import mobman
from mobman import dynamics as dyn
from mobman import kinematics
from mobman.dynamics import equations
from mobman.model import robots, spatial

R, B = 0.1, 0.25
WHEEL = dyn.Wheel(5.0, 0.01, 0.135)


def _arm() -> mobman.Arm:
    """A yaw joint and two lifting joints (a vertical 2-link arm on a turret), full inertia tensors."""
    lift = (0.0, -1.0, 0.0)
    return mobman.Arm(
        (
            mobman.Joint(
                "revolute",
                (0.0, 0.0, 1.0),
                name="yaw",
                inertial=mobman.LinkInertial(
                    4.0, (0.0, 0.02, 0.05), (0.03, 0.0, 0.0, 0.0, 0.04, 0.0, 0.0, 0.0, 0.02)
                ),
            ),
            mobman.Joint(
                "revolute",
                lift,
                spatial.transform(None, (0.0, 0.0, 0.1)),
                name="shoulder",
                inertial=mobman.LinkInertial(
                    3.0, (0.2, 0.0, 0.01), (0.01, 0.001, 0.0, 0.001, 0.05, 0.0, 0.0, 0.0, 0.05)
                ),
            ),
            mobman.Joint(
                "revolute",
                lift,
                spatial.transform(None, (0.4, 0.0, 0.0)),
                name="elbow",
                inertial=mobman.LinkInertial(
                    2.0, (0.15, 0.01, 0.0), (0.005, 0.0, 0.0, 0.0, 0.02, 0.0, 0.0, 0.0, 0.02)
                ),
            ),
        ),
        tool=spatial.transform(None, (0.35, 0.0, 0.0)),
    )


def _model(wheel=WHEEL, gravity=(0.0, 0.0, -9.81)) -> dyn.DynamicModel:
    robot = mobman.MobileManipulator(
        mobman.DifferentialDrive(R, B), (_arm(),), (mobman.Mount(0.2, 0.05, 0.3),)
    )
    body = dyn.PlatformBody(30.0, 1.5, com=(-0.05, 0.01, 0.15))
    payload = dyn.Payload(1.5, (0.002, 0.002, 0.002), com=(0.05, 0.0, 0.0))
    return dyn.DynamicModel(robot, body, wheel, payload, gravity)


MODEL = _model()
N = 6


@pytest.fixture(scope="module")
def states():
    rng = np.random.default_rng(7)
    q = rng.uniform(-math.pi, math.pi, (N, 6))
    eta = rng.normal(size=(N, 5))
    eta_dot = rng.normal(size=(N, 5))
    q_dot = np.asarray(kinematics.S(MODEL.robot, q) @ eta[..., None])[..., 0]
    return q, q_dot, eta, eta_dot


def test_mass_matrix_symmetric_positive_definite(states):
    q = states[0]
    for model, m in ((MODEL, dyn.mass_matrix(MODEL, q)), (dyn.yamamoto_model(), None)):
        if m is None:
            q9 = np.random.default_rng(1).uniform(-3, 3, (N, 9))
            m = dyn.mass_matrix(model, q9)
        m = np.asarray(m)
        assert np.allclose(m, np.swapaxes(m, -1, -2), atol=1e-12)
        assert np.linalg.eigvalsh(m).min() > 1e-4


def test_mdot_minus_2c_is_skew_and_c_matches_bias(states):
    import jax

    q, q_dot = states[0], states[1]
    c_mat = np.asarray(dyn.coriolis_matrix(MODEL, q, q_dot))
    m_dot = np.asarray(jax.jvp(lambda x: dyn.mass_matrix(MODEL, x), (q,), (q_dot,))[1])
    skew = m_dot - 2 * c_mat
    assert np.abs(m_dot).max() > 0.1
    assert np.max(np.abs(skew + np.swapaxes(skew, -1, -2))) < 1e-10
    c_times_qdot = np.einsum("kij,kj->ki", c_mat, q_dot)
    c_bias = np.asarray(dyn.bias(MODEL, q, q_dot) - dyn.bias(MODEL, q, np.zeros_like(q_dot)))
    assert np.max(np.abs(c_times_qdot - c_bias)) < 1e-10


def test_newton_euler_force_equals_lagrange_form(states):
    """generalized_force (Newton–Euler, virtual work) = M q̈ + c + g (autodiff of M and V), wheels and
    payload included; the payload's own row is the difference made by adding it (the affine load term)."""
    q, q_dot = states[0], states[1]
    q_ddot = np.random.default_rng(3).normal(size=q.shape)
    lagrange = np.einsum("kij,kj->ki", np.asarray(dyn.mass_matrix(MODEL, q)), q_ddot) + np.asarray(
        dyn.bias(MODEL, q, q_dot)
    )
    newton_euler = np.asarray(dyn.generalized_force(MODEL, q, q_dot, q_ddot))
    assert np.abs(lagrange).max() > 1.0
    assert np.max(np.abs(newton_euler - lagrange)) < 1e-10 * np.abs(lagrange).max()
    forces, wheel = equations.body_forces_one(MODEL, q[0], q_dot[0], q_ddot[0])
    without = np.asarray(dyn.generalized_force(MODEL.with_payload(None), q[0], q_dot[0], q_ddot[0]))
    assert np.abs(wheel).max() > 1e-3
    assert np.allclose(np.asarray(forces[-1]), newton_euler[0] - without, atol=1e-10)


def test_gravity_is_gradient_of_potential_by_finite_differences(states):
    q = states[0][0]
    h = 1e-6
    fd = np.array(
        [
            (dyn.potential_energy(MODEL, q + h * e) - dyn.potential_energy(MODEL, q - h * e)) / (2 * h)
            for e in np.eye(6)
        ]
    )
    g = np.asarray(dyn.gravity_vector(MODEL, q))
    assert np.abs(g).max() > 1.0
    assert np.allclose(g, fd, atol=1e-6)
    assert np.allclose(
        g[:3], 0.0, atol=1e-12
    )  # horizontal floor: platform motion does no work against gravity


def test_wheels_add_the_closed_form_platform_inertia(states):
    """Wheel terms in P = Sᵀ M S: diag(2 m_w + 2 I_w / r², 2 m_w b² + 2 I_m + 2 I_w b² / r²) on (v, ω) only."""
    q = states[0]
    bare = _model(wheel=dyn.Wheel(0.0, 0.0, 0.0))
    diff = np.asarray(dyn.reduced_mass_matrix(MODEL, q) - dyn.reduced_mass_matrix(bare, q))
    expected = np.zeros((5, 5))
    expected[0, 0] = 2 * WHEEL.mass + 2 * WHEEL.I_w / R**2
    expected[1, 1] = 2 * WHEEL.mass * B**2 + 2 * WHEEL.I_m + 2 * WHEEL.I_w * B**2 / R**2
    assert np.allclose(diff, expected, atol=1e-10)


def test_input_matrix_maps_wheel_torques_to_force_and_moment(states):
    b_mat = np.asarray(dyn.input_matrix(MODEL, states[0]))
    expected = np.eye(5)
    expected[:2, :2] = [[1 / R, 1 / R], [B / R, -B / R]]
    assert np.allclose(b_mat, expected, atol=1e-12)


def test_wheel_angle_rates_agree_with_platform_kinematics(states):
    q, q_dot, eta = states[0], states[1], states[2]
    rates = np.asarray(dyn.wheel_angle_rates(MODEL, q, q_dot))
    assert np.allclose(rates, np.asarray(MODEL.robot.platform.eta_to_wheel_speeds(eta[:, :2])), atol=1e-12)


def test_reduced_bias_equals_projection_of_full_equations(states):
    """b = Sᵀ (M Ṡ η + c + g) with Ṡ η by central finite differences of S along q̇ = S η."""
    q, q_dot, eta = states[0], states[1], states[2]
    h = 1e-6
    s_dot = (
        np.asarray(kinematics.S(MODEL.robot, q + h * q_dot))
        - np.asarray(kinematics.S(MODEL.robot, q - h * q_dot))
    ) / (2 * h)
    s = np.asarray(kinematics.S(MODEL.robot, q))
    m = np.asarray(dyn.mass_matrix(MODEL, q))
    full = np.einsum("kij,kjl,kl->ki", m, s_dot, eta) + np.asarray(dyn.bias(MODEL, q, q_dot))
    expected = np.einsum("kji,kj->ki", s, full)
    assert np.allclose(np.asarray(dyn.reduced_bias(MODEL, q, eta)), expected, atol=1e-6)


def test_inverse_and_forward_dynamics_round_trip(states):
    q, _, eta, eta_dot = states
    tau = dyn.inverse_dynamics(MODEL, q, eta, eta_dot)
    assert np.allclose(np.asarray(dyn.forward_dynamics(MODEL, q, eta, tau)), eta_dot, atol=1e-9)


def test_constraint_forces_drop_out_of_the_reduced_equations(states):
    """A solution of the reduced equations satisfies the full ones with some λ (residual outside range Gᵀ = 0);
    a torque that violates the reduced equations leaves a residual."""
    q, _, eta, eta_dot = states
    tau = dyn.inverse_dynamics(MODEL, q, eta, eta_dot)
    lam, residual = dyn.constraint_forces(MODEL, q, eta, eta_dot, tau)
    assert np.abs(np.asarray(lam)).max() > 1.0  # the lateral wheel force is really there
    assert np.abs(np.asarray(residual)).max() < 1e-9
    _, wrong = dyn.constraint_forces(MODEL, q, eta, eta_dot, np.asarray(tau) + 1.0)
    assert np.abs(np.asarray(wrong)).max() > 0.1


@pytest.fixture(scope="module")
def unforced():
    q0 = np.array([0.3, -0.2, 0.5, 0.2, 0.6, -0.9])
    eta0 = np.array([0.4, 0.8, 1.0, -0.5, 0.7])
    return dyn.simulate(MODEL, q0, eta0, dyn.zero_torque, duration=5.0, dt=2e-3)


def test_energy_is_conserved_without_torques(unforced):
    e = np.asarray(dyn.energy(MODEL, unforced.q, unforced.eta))
    kinetic = e - np.asarray(dyn.potential_energy(MODEL, unforced.q))
    assert kinetic.max() - kinetic.min() > 0.1  # energy really moves between kinetic and potential
    assert np.max(np.abs(e - e[0])) <= 1e-6 * abs(e[0])


def test_simulated_platform_never_slips(unforced):
    """Lateral velocity from finite differences of the simulated path is zero to the O(dt²) = 4e-6 error of
    the central difference (a slipping platform would show lateral speeds of the order of its speed)."""
    q, dt = unforced.q, unforced.t[1]
    q_dot = (q[2:] - q[:-2]) / (2 * dt)
    theta = q[1:-1, 2]
    lateral = q_dot[:, 0] * np.sin(theta) - q_dot[:, 1] * np.cos(theta)
    speed = np.hypot(q_dot[:, 0], q_dot[:, 1])
    assert speed.max() > 0.1
    assert np.abs(lateral).max() < 1e-4 * speed.max()


@pytest.mark.parametrize(
    "build, field",
    [
        (lambda: dyn.PlatformBody(-1.0, 1.0), "mass"),
        (lambda: dyn.PlatformBody(1.0, math.nan), "inertia_z"),
        (lambda: dyn.Wheel(1.0, -0.1, 0.1), "I_w"),
        (lambda: dyn.Payload(1.0, (1, 2, 0, 0, 1, 0, 0, 0, 1)), "symmetric"),
        (lambda: dyn.Payload(1.0, (1.0, -1.0, 1.0)), "positive semi-definite"),
        (lambda: dyn.DynamicModel(robots.bayle_planar(), dyn.PlatformBody(1.0, 1.0), WHEEL), "inertial"),
        (lambda: dyn.DynamicModel(robots.yamamoto_dual_arm(), dyn.PlatformBody(1.0, 1.0), None), "wheel"),
        (lambda: dyn.DynamicModel(MODEL.robot, MODEL.body, WHEEL, dyn.Payload(1.0, arm=3)), "payload.arm"),
    ],
)
def test_invalid_inertial_data_names_the_field(build, field):
    with pytest.raises(mobman.ModelError, match=field):
        build()


def test_wrong_sizes_are_input_errors():
    with pytest.raises(mobman.InputError, match="q_ddot"):
        dyn.generalized_force(MODEL, np.zeros(6), np.zeros(6), np.zeros(5))
    with pytest.raises(mobman.InputError, match="q_dot"):
        dyn.generalized_force(MODEL, np.zeros(6), np.full(6, np.nan), np.zeros(6))
    with pytest.raises(mobman.InputError, match="eta"):
        dyn.reduced_bias(MODEL, np.zeros(6), np.zeros(4))


def test_public_reduced_functions_work_inside_a_users_vmap(states):
    """The validated public functions accept a user's traced values (their own jit, grad or vmap)."""
    import jax

    q, _, eta, eta_dot = states
    vmapped = jax.vmap(lambda x, e, a: dyn.inverse_dynamics(MODEL, x, e, a))(q, eta, eta_dot)
    np.testing.assert_allclose(vmapped, dyn.inverse_dynamics(MODEL, q, eta, eta_dot), rtol=1e-12, atol=1e-12)
