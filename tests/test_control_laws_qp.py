"""The QP law (mobman.control.laws.qp) against an independent solver of the same program (quadprog:
Goldfarb & Idnani's dual active-set method, built here in NumPy from the published kinematics and the
limits of TIAGo's URDF file), against the closed form of damped Bayle without active limits and Bayle's
law itself as μ → 0, and its velocity damper at a joint outside its limits."""

from __future__ import annotations

import jax
import numpy as np
import pytest
import quadprog

from mobman import kinematics
from mobman.control import criteria, laws, simulate
from mobman.control.references import Line
from mobman.errors import ModelError
from mobman.io import real_robots
from mobman.model import robots
from mobman.model.tasks import Position

from tiago_urdf import joint_limits

TIAGO = real_robots.tiago()
NAMES = TIAGO.coordinate_names[3:]
LIMITS = joint_limits(NAMES, ("lower", "upper", "velocity"))  # torso (m, m/s), arm (rad, rad/s)
WHEEL = joint_limits(["wheel_right_joint", "wheel_left_joint"], ("velocity",))[:, 0]  # rad/s
RADIUS, SEPARATION = 0.0985, 0.4044  # m: TIAGo's wheels (tests/test_io_real_robots.py)
W5 = criteria.Manipulability("eccentricity", "system")


def reference_eta(q, u, mu, gain, *, weight=None, eta_s=None):
    """The law's program solved by quadprog in η itself: min ½‖J̄η − u‖² + ½μ‖R⁻¹(η − η_s)‖² within the
    velocity limits (the platform's v_max = r u_max and ω_max = 2 r u_max / b from the wheels), each wheel's
    speed |v ± b ω / 2| / r ≤ u_max, and the joints' dampers γ (q_min − q) ≤ q̇ ≤ γ (q_max − q) clipped into
    their velocity limits."""
    jbar = np.asarray(kinematics.reduced_jacobian(TIAGO, q))
    n = jbar.shape[1]
    weight = np.ones(n) if weight is None else weight
    eta_s = np.zeros(n) if eta_s is None else eta_s
    metric = np.diag(weight**-2)
    hessian = jbar.T @ jbar + mu * metric
    linear = -jbar.T @ u - mu * metric @ eta_s
    u_max = WHEEL[0]
    vmax = np.concatenate([[RADIUS * u_max, 2 * RADIUS * u_max / SEPARATION], LIMITS[:, 2]])
    upper, lower = vmax.copy(), -vmax
    upper[2:] = np.clip(gain * (LIMITS[:, 1] - q[3:]), -vmax[2:], vmax[2:])
    lower[2:] = np.clip(gain * (LIMITS[:, 0] - q[3:]), -vmax[2:], vmax[2:])
    wheels = np.zeros((2, n))
    wheels[:, :2] = [[1 / RADIUS, SEPARATION / (2 * RADIUS)], [1 / RADIUS, -SEPARATION / (2 * RADIUS)]]
    # quadprog: min ½ xᵀGx − aᵀx subject to Cᵀx ≥ b
    rows = np.vstack([-np.eye(n), np.eye(n), -wheels, wheels])
    ends = np.concatenate([-upper, lower, -WHEEL, -WHEEL])
    return quadprog.solve_qp(hessian, -linear, rows.T, ends, 0)[0]


def configurations(rng, count):
    """TIAGo postures over the whole joint ranges, a third each: uniform, one joint exactly at a limit, one
    joint just outside a limit; the heading over [−π, π] with ±π/2 and π among them."""
    lo, hi = LIMITS[:, 0], LIMITS[:, 1]
    q = np.zeros((count, TIAGO.n_q))
    q[:, :2] = rng.uniform(-3, 3, (count, 2))
    q[:, 2] = rng.uniform(-np.pi, np.pi, count)
    q[:3, 2] = [np.pi / 2, -np.pi / 2, np.pi]
    q[:, 3:] = rng.uniform(lo, hi, (count, len(lo)))
    third = count // 3
    for k, offset in ((1, 0.0), (2, 0.02)):
        rows = np.arange(k * third, (k + 1) * third)
        at, side = rng.integers(0, len(lo), third), rng.integers(0, 2, third)
        q[rows, 3 + at] = np.where(side, hi[at] + offset, lo[at] - offset)
    return q


def test_tiago_s_eta_is_the_optimum_an_independent_solver_finds():
    rng = np.random.default_rng(7)
    law = laws.WholeBodyQP(W=2.0)
    step = jax.jit(lambda q, xs, xsd: law(TIAGO, None, q, 0.0, xs, xsd))
    errors, limited = [], []
    for q in configurations(rng, 60):
        xi = np.asarray(kinematics.forward(TIAGO, q))
        xs = xi + rng.normal(size=3) * 0.1
        xsd = rng.normal(size=3) * rng.choice([0.05, 1.0, 4.0])  # m/s: within reach to far beyond the limits
        got = step(q, xs, xsd)
        errors.append(np.abs(np.asarray(got.eta) - reference_eta(q, xsd + 2.0 * (xs - xi), 1e-4, 5.0)).max())
        assert float(got.residual) < 1e-7
        limited.append(bool(got.speed_limited) or bool(got.joint_limited))
    errors = np.array(errors)
    assert errors[:20].max() < 1e-8 and errors[40:].max() < 1e-8
    # a joint exactly at its limit: its bound is 0 and, for a joint the task does not need, so is its optimal
    # velocity (a bound active with a zero multiplier), where interior-point iterates converge slowly
    assert errors[20:40].max() < 3e-5
    assert 10 < sum(limited) < 60  # both free and limited programs were drawn


def test_stretched_and_folded_arms_and_the_zero_posture():
    stretched = np.zeros(TIAGO.n_q)
    stretched[[3, 4]] = [0.1, 0.5]  # the torso and arm_1 off their lower limits, every other joint at 0
    folded = stretched.copy()
    folded[[5, 7]] = [-1.5, 2.3]  # arm_2 down, the elbow (arm_4) bent near its upper limit
    law = laws.WholeBodyQP(W=2.0)
    step = jax.jit(lambda q, xs, xsd: law(TIAGO, None, q, 0.0, xs, xsd))
    rng = np.random.default_rng(5)
    for q in (stretched, folded, np.zeros(TIAGO.n_q)):  # the zero posture: torso and arm_1 at their limits
        xi = np.asarray(kinematics.forward(TIAGO, q))
        for speed in (0.05, 2.0):  # m/s: free, and beyond the limits
            xsd = rng.normal(size=3) * speed
            got = step(q, xi, xsd)
            np.testing.assert_allclose(np.asarray(got.eta), reference_eta(q, xsd, 1e-4, 5.0), atol=1e-10)


def test_the_self_motion_and_the_normalisation_enter_as_in_bayle_s_law():
    rng = np.random.default_rng(8)
    law = laws.WholeBodyQP(W=1.5, k=0.8, criterion=W5, normalized=True, regularization=1e-3, limit_gain=3.0)
    weight = np.asarray(TIAGO.velocity_limits)
    step = jax.jit(lambda q, xs, xsd: law(TIAGO, None, q, 0.0, xs, xsd))
    gradient = jax.jit(lambda q: W5.gradient(TIAGO, q))
    for q in configurations(rng, 12):
        xi = np.asarray(kinematics.forward(TIAGO, q))
        xs, xsd = xi + rng.normal(size=3) * 0.05, rng.normal(size=3) * 0.3
        got = step(q, xs, xsd)
        grad = np.asarray(gradient(q))
        eta_s = -0.8 * weight**2 * (np.asarray(kinematics.S(TIAGO, q)).T @ grad)
        want = reference_eta(q, xsd + 1.5 * (xs - xi), 1e-3, 3.0, weight=weight, eta_s=eta_s)
        np.testing.assert_allclose(np.asarray(got.eta), want, atol=1e-8)
        assert float(got.P) == pytest.approx(float(jax.jit(lambda qq: W5(TIAGO, qq))(q)), rel=1e-12)


ROBOT = robots.bayle_planar()  # velocity limits, no position limits, no wheel limits
TASK = Position("xy")


def test_without_active_limits_it_is_damped_bayle_and_bayle_as_mu_vanishes():
    q = np.array([0.2, 0.1, 0.3, 0.7, 1.1])
    xs = np.asarray(kinematics.forward(ROBOT, q, TASK)) + [0.01, -0.02]
    xsd = np.array([0.05, -0.03])
    criterion = criteria.Manipulability("eccentricity", "system", power=2)
    u = xsd + 2.0 * (xs - np.asarray(kinematics.forward(ROBOT, q, TASK)))
    grad = np.asarray(criterion.gradient(ROBOT, q, TASK))
    for normalized in (False, True):
        weight = np.asarray(ROBOT.velocity_limits) if normalized else np.ones(ROBOT.n_eta)
        jt = np.asarray(kinematics.reduced_jacobian(ROBOT, q, TASK)) * weight
        scaled_s = -0.05 * weight * (np.asarray(kinematics.S(ROBOT, q)).T @ grad)  # R⁻¹ η_s
        bayle = laws.BaylePseudoInverse(W=2.0, k=0.05, criterion=criterion, normalized=normalized)
        exact = np.asarray(jax.jit(lambda qq, law=bayle: law(ROBOT, TASK, qq, 0.0, xs, xsd).eta)(q))
        run = jax.jit(lambda law, qq: law(ROBOT, TASK, qq, 0.0, xs, xsd))  # μ is a leaf of the law
        gaps = []
        for mu in (1e-2, 1e-5, 1e-6):
            qp = laws.WholeBodyQP(
                W=2.0, k=0.05, criterion=criterion, normalized=normalized, regularization=mu
            )
            got = run(qp, q)
            assert (
                not bool(got.speed_limited) and float(np.max(np.abs(got.eta) / ROBOT.velocity_limits)) < 0.9
            )
            closed = weight * np.linalg.solve(jt.T @ jt + mu * np.eye(ROBOT.n_eta), jt.T @ u + mu * scaled_s)
            np.testing.assert_allclose(np.asarray(got.eta), closed, atol=1e-10)
            gaps.append(np.abs(np.asarray(got.eta) - exact).max())
        assert gaps[2] < 1e-5 and 5 < gaps[1] / gaps[2] < 20  # Bayle's η, approached as O(μ)


def test_a_joint_beyond_its_limit_moves_back_at_the_damper_s_rate():
    q = np.array([0.0, 0.0, 0.0, 0.36, 0.5, 0.3, -1.2, 1.5, 0.3, 0.5, 0.0])  # torso 1 cm above 0.35 m
    law = laws.WholeBodyQP(W=1.0, limit_gain=2.0)
    xi = np.asarray(kinematics.forward(TIAGO, q))
    up = jax.jit(lambda qq: law(TIAGO, None, qq, 0.0, xi + [0, 0, 0.3], np.zeros(3)))(q)
    assert float(up.eta[2]) == pytest.approx(2.0 * (0.35 - 0.36), abs=1e-8)  # m/s: γ times the excess
    assert bool(up.joint_limited)
    far = q.copy()
    far[3] = 0.5  # 0.15 m above: γ · 0.15 is more than the torso's 0.07 m/s
    step = jax.jit(lambda qq: law(TIAGO, None, qq, 0.0, xi, np.zeros(3)))(far)
    assert float(step.eta[2]) == pytest.approx(-LIMITS[0, 2], abs=1e-8)
    assert bool(step.speed_limited)


def test_saturated_says_when_the_limits_cut_the_task_velocity():
    """``saturated``: a bound is active and J̄η falls short of ξ̇* + W e (checked here with J̄ from the
    kinematics); a joint held by its damper while the others make up for it cuts nothing."""
    q = np.array([0.2, 0.1, 0.3, 0.7, 1.1])
    xi = np.asarray(kinematics.forward(ROBOT, q, TASK))
    jbar = np.asarray(kinematics.reduced_jacobian(ROBOT, q, TASK))
    law = laws.WholeBodyQP(W=2.0)
    step = jax.jit(lambda xsd: law(ROBOT, TASK, q, 0.0, xi, xsd))
    for xsd, cut in (([0.05, -0.03], False), ([5.0, -3.0], True), ([0.0, 0.0], False)):  # m/s
        got = step(np.array(xsd))
        shortfall = np.linalg.norm(jbar @ np.asarray(got.eta) - xsd)
        assert bool(got.saturated) is cut and bool(got.speed_limited) is cut
        assert (
            shortfall > 0.5 * np.linalg.norm(xsd) if cut else shortfall < 1e-3 * np.linalg.norm(xsd) + 1e-12
        )
    torso_above = np.array([0.0, 0.0, 0.0, 0.36, 0.5, 0.3, -1.2, 1.5, 0.3, 0.5, 0.0])
    xi = np.asarray(kinematics.forward(TIAGO, torso_above))
    held = jax.jit(lambda qq: laws.WholeBodyQP(W=1.0)(TIAGO, None, qq, 0.0, xi + [0, 0, 0.1], np.zeros(3)))(
        torso_above
    )
    realised = np.asarray(kinematics.reduced_jacobian(TIAGO, torso_above)) @ np.asarray(held.eta)
    assert bool(held.joint_limited) and not bool(held.saturated)
    np.testing.assert_allclose(realised, [0, 0, 0.1], atol=1e-4)


def test_laws_differing_in_gains_run_as_one_batch():
    q0 = np.array([0.0, 0.0, 0.0, 0.7, 1.1])
    start = np.asarray(kinematics.forward(ROBOT, q0, TASK))
    reference = Line(start, start + [0.3, 0.1], 0.4)
    pair = [laws.WholeBodyQP(W=w, limit_gain=g) for w, g in ((1.0, 5.0), (3.0, 2.0))]
    batch = simulate(ROBOT, TASK, pair, reference, q0, 0.4, 0.02)
    for i, law in enumerate(pair):
        alone = simulate(ROBOT, TASK, law, reference, q0, 0.4, 0.02)
        np.testing.assert_allclose(batch.q[i], alone.q, atol=1e-12)


@pytest.mark.parametrize(
    ("options", "message"),
    [
        ({"regularization": 1e-8}, "regularization must be a finite number ≥ 1e-7"),
        ({"regularization": np.nan}, "regularization must be a finite number ≥ 1e-7"),
        ({"limit_gain": -1.0}, "limit_gain must be a finite number > 0"),
        ({"iterations": 0}, "iterations must be an integer in 1..1000"),
        ({"iterations": 2.5}, "iterations must be an integer in 1..1000"),
        ({"k": [1.0, 2.0]}, "k must be a scalar ≥ 0"),
        ({"W": -1.0}, "W must be positive definite"),
        ({"saturate": True}, "saturate does not apply"),
    ],
)
def test_bad_options_name_the_field(options, message):
    with pytest.raises(ModelError, match=message):
        laws.WholeBodyQP(**options)
