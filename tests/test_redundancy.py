"""Redundancy, singularities and consistency: every statement of Bayle et al. §5 checked numerically."""

from __future__ import annotations

import math

import numpy as np
import pytest

from mobman import kinematics as K
from mobman import redundancy as R
from mobman.model import robots

ODD_HALF_PI = [(2 * k + 1) * math.pi / 2 for k in range(-2, 2)]
K_PI = [k * math.pi for k in range(-2, 3)]


@pytest.fixture(scope="module")
def planar():
    return robots.bayle_planar()


@pytest.fixture(scope="module")
def rrp():
    return robots.bayle_rrp()


def _random(robot, n, seed):
    return R.sample_configurations(robot, n, seed)


# --- Bayle §5.1: HILARE + planar 2R ------------------------------------------------------------------


def test_planar_example_redundancy_degrees(planar):
    report = R.redundancy_report(planar)
    assert report == R.RedundancyReport(M=5, delta=4, D=3, R=2, D_bar=3, R_bar=1)
    assert report.as_dict() == {"M": 5, "delta": 4, "D": 3, "R": 2, "D_bar": 3, "R_bar": 1}


def test_planar_example_rank_j_is_3_everywhere_no_ksc(planar):
    q = _random(planar, 200, seed=1)
    q[:40, 3] = np.resize(ODD_HALF_PI, 40)  # the VSC too: J keeps full rank there
    d, _ = R.ranks(planar, q)
    assert np.all(d == 3)
    assert not R.is_kinematic_singular(planar, q).singular.any()


def test_planar_example_vsc_iff_q4_odd_half_pi(planar):
    q = _random(planar, 120, seed=2)
    q[:60, 3] = np.resize(ODD_HALF_PI, 60)
    q[60:80, 3] = np.resize(ODD_HALF_PI, 20) + 1e-3  # near but off the singular set
    flags, order = R.is_velocity_singular(planar, q)
    np.testing.assert_array_equal(flags, np.arange(120) < 60)
    np.testing.assert_array_equal(order, (np.arange(120) < 60).astype(int))
    _, d_bar = R.ranks(planar, q)
    assert np.all(d_bar[:60] == 2) and np.all(d_bar[60:] == 3)


# --- Bayle §5.2: HILARE + RRP ------------------------------------------------------------------------


def test_rrp_example_redundancy_degrees(rrp):
    assert R.redundancy_report(rrp) == R.RedundancyReport(M=6, delta=5, D=5, R=1, D_bar=4, R_bar=1)


def test_rrp_example_rank_j_in_4_5_ksc_iff_q5_k_pi(rrp):
    q = _random(rrp, 150, seed=3)
    q[:50, 4] = np.resize(K_PI, 50)
    d, _ = R.ranks(rrp, q)
    assert set(np.unique(d)) == {4, 5}
    flags, order = R.is_kinematic_singular(rrp, q)
    np.testing.assert_array_equal(flags, np.arange(150) < 50)
    assert np.all(order[:50] == 1)


def test_rrp_example_vsc_iff_q4_and_q5_k_pi(rrp):
    q = _random(rrp, 150, seed=4)
    q[:50, 3] = np.resize(K_PI, 50)
    q[:50, 4] = np.resize(K_PI[::-1], 50)
    q[50:100, 3] = np.resize(K_PI, 50)  # q4 = kπ alone: regular
    q[100:, 4] = np.resize(K_PI, 50)  # q5 = kπ alone: regular (a KSC, not a VSC)
    flags, order = R.is_velocity_singular(rrp, q)
    np.testing.assert_array_equal(flags, np.arange(150) < 50)
    np.testing.assert_array_equal(order, (np.arange(150) < 50).astype(int))
    _, d_bar = R.ranks(rrp, q)
    assert np.all(d_bar[:50] == 3) and np.all(d_bar[50:] == 4)


def _relation(q, g6=None):
    """Bayle §5.2's consistency relation; g6=None reads the printed 'g6' as q6 (the corrected form)."""
    q3, q4, q5, q6 = (q[..., i] for i in range(2, 6))
    g = q6 if g6 is None else g6
    s3, c3, s4, c4, s5, c5 = np.sin(q3), np.cos(q3), np.sin(q4), np.cos(q4), np.sin(q5), np.cos(q5)
    return np.stack([s3 * s5, -c3 * s5, s4 * c5, c4 * c5 * s5 * g, -s4 * g], axis=-1)


def test_rrp_consistency_relation_corrected_spans_left_null_space(rrp):
    # ξ5 = q5 over the whole turn (exactly ±π/2 and π included), off the VSC
    q = _random(rrp, 100, seed=5)
    q[:, 4] = np.random.default_rng(6).uniform(-math.pi, math.pi, 100)
    q[:4, 4] = [math.pi / 2, -math.pi / 2, 0.5 * math.pi + 1e-9, math.pi - 0.3]
    jbar = np.asarray(K.reduced_jacobian(rrp, q))
    y = _relation(q)
    np.testing.assert_allclose(np.einsum("ni,nij->nj", y, jbar), 0.0, atol=1e-12)
    rows = R.consistency_relations(rrp, q)
    assert rows.shape == (100, 1, 5)
    cosine = np.einsum("ni,ni->n", rows[:, 0], y) / np.linalg.norm(y, axis=-1)
    np.testing.assert_allclose(np.abs(cosine), 1.0, atol=1e-10)


def test_rrp_printed_relation_with_a_constant_g6_is_not_consistent(rrp):
    q = _random(rrp, 20, seed=7)
    q[:, 5] = 0.35 + np.arange(20) * 0.1  # q6 ≠ 1
    jbar = np.asarray(K.reduced_jacobian(rrp, q))
    residual = np.einsum("ni,nij->nj", _relation(q, g6=1.0), jbar)
    assert np.all(np.linalg.norm(residual, axis=-1) > 1e-3)


def test_consistency_test_accepts_image_and_rejects_relation_violations(rrp):
    q = _random(rrp, 30, seed=8)
    q[:, 4] = np.random.default_rng(9).uniform(-1.5, 1.5, 30)
    eta = np.random.default_rng(10).normal(size=(30, 5))
    xi_dot = np.einsum("nij,nj->ni", np.asarray(K.reduced_jacobian(rrp, q)), eta)
    assert R.is_consistent(rrp, q, xi_dot).all()
    bad = xi_dot + _relation(q)  # a component along the left null vector
    assert not R.is_consistent(rrp, q, bad).any()


def test_no_consistency_relation_when_d_bar_equals_m(planar):
    rows = R.consistency_relations(planar, _random(planar, 4, seed=11))
    assert rows.shape == (4, 0, 3)


# --- general properties -------------------------------------------------------------------------------


@pytest.mark.parametrize("name", list(robots.ROBOTS))
def test_degrees_are_ordered_for_every_builtin_robot(name):
    robot = robots.build(name)
    report = R.redundancy_report(robot)
    assert report.M == robot.n_q and report.delta == robot.n_eta
    assert report.D_bar <= report.D <= min(report.M, robot.task.dim)  # D̄ ≤ D (Bayle §4.2)
    assert report.D_bar <= report.delta
    assert report.R == report.M - report.D and report.R_bar == report.delta - report.D_bar


def test_batched_shapes_and_per_configuration_agreement(rrp):
    q = _random(rrp, 12, seed=12).reshape(3, 4, 6)
    q[0, 0, 3:5] = 0.0
    d, d_bar = R.ranks(rrp, q)
    assert d.shape == d_bar.shape == (3, 4)
    flags, order = R.is_velocity_singular(rrp, q)
    assert flags.shape == order.shape == (3, 4)
    for i, j in np.ndindex(3, 4):
        one = R.is_velocity_singular(rrp, q[i, j])
        assert bool(one.singular) == bool(flags[i, j]) and int(one.order) == int(order[i, j])


def test_samples_respect_joint_limits(rrp):
    q = R.sample_configurations(rrp, 500, seed=0)
    assert q[:, 5].min() >= 0.0  # the prismatic joint's lower limit
    np.testing.assert_array_equal(q, R.sample_configurations(rrp, 500, seed=0))  # seeded
