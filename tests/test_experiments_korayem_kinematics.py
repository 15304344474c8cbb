"""Korayem simulation models 1 and 2: end points, the paper's determinants, initial-vector consistency."""

from __future__ import annotations

import math

import numpy as np
import pytest

from mobman import kinematics as K
from mobman.experiments import korayem_kinematics as kk
from mobman.model import robots
from mobman.model.tasks import MountPosition, Position, stack


@pytest.fixture(scope="module")
def reproduction(tmp_path_factory):
    out = tmp_path_factory.mktemp("korayem")
    return kk.run(out, quick=True)


@pytest.fixture(scope="module")
def robot():
    return robots.korayem_planar(l0=0.4, l1=0.5, l2=0.5)


@pytest.fixture(scope="module")
def runs(robot):
    m1, m2 = kk.models()
    return {1: (m1, kk.run_model(robot, m1, 0.01)), 2: (m2, kk.run_model(robot, m2, 0.01))}


def test_results_structure_and_figures(reproduction):
    assert reproduction.name == "korayem-kinematics"
    assert [r["model"] for r in reproduction.results] == [1, 2]
    for r in reproduction.results:
        assert set(r) >= {"q_final", "ee_final", "base_point_final", "min_abs_det", "damped"}
        assert len(r["q_final"]) == 5
    assert len(reproduction.figures) == 4
    for path in reproduction.figures:
        assert path.read_bytes()[:4] == b"\x89PNG"
    assert "not consistent" in reproduction.report


def test_end_effector_reaches_final_point(reproduction):
    # model 2 ends exactly at a singular configuration (|EE − F| = l1 + l2) where the damped law can only
    # approach it: 1 mm tolerance there, the regular model 1 is tracked to 1e-6 m
    m1, m2 = reproduction.results
    np.testing.assert_allclose(m1["ee_final"], [1.5, 0.75], atol=1e-6)
    np.testing.assert_allclose(m2["ee_final"], [1.5, 0.75], atol=1e-3)
    np.testing.assert_allclose(m2["base_point_final"], [0.5, 0.75], atol=1e-3)


def test_model1_final_elbow_and_orientation(runs, robot):
    model, result = runs[1]
    x = K.forward(robot, result.q[-1], stack(Position("xy"), model.extra))
    np.testing.assert_allclose(x, [1.5, 0.75, math.radians(60), math.pi], atol=1e-6)


def test_determinants_match_paper_closed_forms(runs, robot):
    l0, l1, l2 = 0.4, 0.5, 0.5
    _, r1 = runs[1]
    _, r2 = runs[2]
    np.testing.assert_allclose(r1.info["det"], l0, rtol=1e-12)  # eq. 36: Det = l0, any configuration
    np.testing.assert_allclose(
        r2.info["det"], l0 * l1 * l2 * np.abs(np.sin(r2.q[:, 4])), atol=1e-12
    )  # eq. 37


def test_damping_needed_only_at_model2_singular_end(runs):
    assert not runs[1][1].damped.any()
    damped = runs[2][1].damped
    assert damped.any() and damped[-1]
    assert runs[2][1].t[damped].min() > 1.5  # only near the stretched end
    assert np.abs(runs[2][1].q[-1, 4]) < 0.2  # θ2 → 0: arm stretched


def test_initial_configurations(robot):
    m1, m2 = kk.models()
    check1 = kk.stated_initial_check(robot, m1)
    assert not check1["consistent"] and check1["ee_distance_from_stated"] > 0.1
    q1 = kk.initial_configuration(robot, m1)
    np.testing.assert_allclose(
        K.forward(robot, q1, stack(Position("xy"), m1.extra)), m1.x_initial, atol=1e-12
    )
    assert q1[2] == 0.0
    assert kk.stated_initial_check(robot, m2)["consistent"]
    q2 = kk.initial_configuration(robot, m2)
    np.testing.assert_allclose(K.forward(robot, q2, MountPosition()), [0.0, 0.0], atol=1e-12)
    with pytest.raises(ValueError, match="reach"):
        kk.model2_configuration(robot, (2.0, 0.0, 0.0, 0.0))


def test_platform_never_slips(runs):
    # each integration step is two arcs q → q_mid → q_next; a rolling arc's chord points along the mean heading
    for _, result in runs.values():
        q, mid = result.q[:-1], result.info["q_mid"][:-1]
        for a, b in ((q, mid), (mid, result.q[1:])):
            heading = 0.5 * (a[:, 2] + b[:, 2])
            d = b[:, :2] - a[:, :2]
            lateral = d[:, 0] * np.sin(heading) - d[:, 1] * np.cos(heading)
            assert np.max(np.abs(lateral)) < 1e-12
