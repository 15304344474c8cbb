"""The load capacity (mobman.dynamics.load_capacity): torques affine in the payload mass, the largest load within
the actuators' envelopes, unbounded and infeasible motions."""

from __future__ import annotations

import math

import numpy as np
import pytest

from mobman import dynamics as dyn
from mobman.dynamics.actuators import DCMotor, TorqueBox
from mobman.dynamics.load_capacity import (
    InfeasibleMotionError,
    capacity_from_torques,
    eta_dot_from_samples,
    load_torques,
    max_load,
)
from mobman.errors import InputError
from mobman.model import spatial
from mobman.model.arm import Arm, Joint, LinkInertial
from mobman.model.platforms import DifferentialDrive
from mobman.model.robot import MobileManipulator

G = 9.81
LENGTH, LINK_COM, LINK_MASS = 0.8, 0.3, 4.0
N = 9


def yaw_lift_model() -> dyn.DynamicModel:
    """A differential base carrying a yaw joint and a lift joint (link of LENGTH along x, horizontal at 0),
    with a payload template whose inertia tensor is full (not diagonal)."""
    arm = Arm(
        (
            Joint(
                "revolute",
                (0.0, 0.0, 1.0),
                name="yaw",
                inertial=LinkInertial(2.0, (0.0, 0.0, 0.05), (0.02, 0.02, 0.01)),
            ),
            Joint(
                "revolute",
                (0.0, -1.0, 0.0),
                spatial.transform(None, (0.0, 0.0, 0.1)),
                name="lift",
                inertial=LinkInertial(LINK_MASS, (LINK_COM, 0.0, 0.0), (0.01, 0.2, 0.2)),
            ),
        ),
        spatial.transform(None, (LENGTH, 0.0, 0.0)),
    )
    robot = MobileManipulator(DifferentialDrive(), (arm,))
    inertia = (0.02, 0.003, -0.001, 0.003, 0.015, 0.002, -0.001, 0.002, 0.01)  # per kg
    return dyn.DynamicModel(
        robot,
        dyn.PlatformBody(20.0, 1.0, (0.05, 0.0, 0.1)),
        dyn.Wheel(1.0, 0.01, 0.01),
        payload=dyn.Payload(1.0, inertia),
    )


def moving_samples():
    """A motion with q̇ = S η exactly: the base drives straight (θ = 0.3), both joints swing."""
    t = np.linspace(0.0, 2.0, N)
    v, v_dot = 0.5 * np.sin(2 * t), np.cos(2 * t)
    travel = 0.25 * (1 - np.cos(2 * t))
    theta = 0.3
    qa = np.stack([0.7 * np.sin(1.5 * t), 0.4 + 0.5 * np.sin(t)], axis=1)
    qa_dot = np.stack([1.05 * np.cos(1.5 * t), 0.5 * np.cos(t)], axis=1)
    qa_ddot = np.stack([-1.575 * np.sin(1.5 * t), -0.5 * np.sin(t)], axis=1)
    q = np.column_stack([travel * math.cos(theta), travel * math.sin(theta), np.full_like(t, theta), qa])
    eta = np.column_stack([v, np.zeros_like(t), qa_dot])
    eta_dot = np.column_stack([v_dot, np.zeros_like(t), qa_ddot])
    return t, q, eta, eta_dot


def static_samples():
    t = np.linspace(0.0, 1.0, N)
    return t, np.zeros((N, 5)), np.zeros((N, 4)), np.zeros((N, 4))


def test_torque_is_affine_in_the_payload_mass():
    """τ0 + m τ1 (unit payload's Newton–Euler share) equals the full reduced inverse dynamics with mass m."""
    model = yaw_lift_model()
    t, q, eta, eta_dot = moving_samples()
    tau0, tau1, speed = load_torques(model, q, eta, eta_dot)
    # Reference: the Christoffel-form reduced inverse dynamics of mobman.dynamics with a 2.7-kg payload. τ0
    # (Lagrange with jvp) and τ1 (Newton–Euler) come from independent code, so a wrong term in either shows
    # here; test_static_lift_matches_the_closed_form checks τ0 and τ1 separately (m = 0: another compile).
    mass = 2.7
    loaded = model.with_payload(model.payload.scaled(mass))
    expected = np.asarray(dyn.inverse_dynamics(loaded, q, eta, eta_dot))
    np.testing.assert_allclose(tau0 + mass * tau1, expected, rtol=1e-10, atol=1e-10)
    assert np.max(np.abs(tau1)) > 0.1  # the load matters
    # actuator speeds: wheel spin rates (v ± b ω)/r and the joint rates
    wheels = np.asarray(model.robot.platform.eta_to_wheel_speeds(eta[:, :2]))
    np.testing.assert_allclose(speed, np.column_stack([wheels, eta[:, 2:]]), atol=1e-12)


def test_static_lift_matches_the_closed_form():
    """Holding the link and a load horizontal: τ0 = m_l g l_c, τ1 = g l, so m_max = (k1 − m_l g l_c)/(g l)."""
    model = yaw_lift_model()
    t, q, eta, eta_dot = static_samples()
    k1 = 63.22
    result = max_load(model, t, q, eta, eta_dot, {"lift": DCMotor(k1, 3.5)})
    assert result.max_load == pytest.approx((k1 - LINK_MASS * G * LINK_COM) / (G * LENGTH), rel=1e-12)
    assert result.limiting_actuator == "lift"
    assert result.limiting_time == 0.0
    np.testing.assert_allclose(result.tau0[:, 3], LINK_MASS * G * LINK_COM, rtol=1e-12)
    np.testing.assert_allclose(result.tau1[:, 3], G * LENGTH, rtol=1e-12)
    again = capacity_from_torques(
        result.names, t, result.tau0, result.tau1, result.speed, {"lift": DCMotor(k1, 3.5)}
    )
    assert again.max_load == result.max_load and again.limiting_actuator == "lift"
    with pytest.raises(InputError, match=r"shape \(9, 4\)"):
        capacity_from_torques(result.names, t, result.tau0[:, :3], result.tau1, result.speed, None)
    # a box that is tighter on the other side does not change a positive holding torque's bound
    box = max_load(
        model, t, q, eta, eta_dot, {"lift": TorqueBox(-1.0, 30.0), "yaw": TorqueBox.symmetric(1.0)}
    )
    assert box.max_load == pytest.approx((30.0 - LINK_MASS * G * LINK_COM) / (G * LENGTH), rel=1e-12)


def test_unbounded_and_infeasible():
    model = yaw_lift_model()
    t, q, eta, eta_dot = static_samples()
    # only the yaw joint limited: holding still needs no yaw torque whatever the load
    result = max_load(model, t, q, eta, eta_dot, {"yaw": DCMotor(5.0, 3.5)})
    assert math.isinf(result.max_load) and not result.bounded
    assert result.limiting_actuator is None and result.limiting_time is None
    assert result.summary()["max_load_kg"] is None
    # the link alone needs 11.77 N·m: a 10 N·m motor cannot even hold it
    with pytest.raises(InfeasibleMotionError, match=r"'lift' needs τ = 11\.77.* outside its envelope"):
        max_load(model, t, q, eta, eta_dot, {"lift": DCMotor(10.0, 3.5)})


def test_capacity_is_monotone_in_stall_torque():
    model = yaw_lift_model()
    t, q, eta, eta_dot = moving_samples()
    loads = [
        max_load(model, t, q, eta, eta_dot, {"yaw": DCMotor(k1, 3.5), "lift": DCMotor(k1, 3.5)}).max_load
        for k1 in (60.0, 80.0, 120.0, 250.0)
    ]
    assert all(np.isfinite(loads))
    assert np.all(np.diff(loads) > 0)


def test_motion_validation():
    model = yaw_lift_model()
    t, q, eta, eta_dot = moving_samples()
    with pytest.raises(InputError, match="eta must have 4 components"):
        max_load(model, t, q, eta[:, :3], eta_dot, DCMotor(60.0, 3.5))
    with pytest.raises(InputError, match="t must hold 9"):
        max_load(model, t[:-1], q, eta, eta_dot, DCMotor(60.0, 3.5))
    with pytest.raises(InputError, match="strictly increasing"):
        eta_dot_from_samples(t[::-1], eta)
    with pytest.raises(InputError, match="inertials: arm 0"):
        model.robot.with_link_inertials([LinkInertial(1.0)])


def test_eta_dot_from_samples_is_second_order_exact_on_quadratics():
    t = np.linspace(0.0, 1.0, 11) ** 1.3  # uneven steps
    eta = np.column_stack([t**2, 3 * t - 1])
    np.testing.assert_allclose(
        eta_dot_from_samples(t, eta), np.column_stack([2 * t, np.full_like(t, 3.0)]), atol=1e-12
    )
