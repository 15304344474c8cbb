"""Whole-body pose control of TIAGo within its limits (docs/examples/tiago_limits.toml): the QP law keeps
every joint inside its position limits, every quasi-velocity within its limit and each wheel under its
speed limit, on a path that Bayle's law follows only by lifting the torso past its limit.

The limits are read from the URDF file itself (ElementTree, not mobman's reader); the wheel speeds are
formed here from v and ω with the wheels' radius and separation."""

import copy
import tomllib
from pathlib import Path

import numpy as np
import pytest

from mobman.control import metrics, spec

from tiago_urdf import joint_limits

SPEC = Path(__file__).resolve().parents[1] / "docs" / "examples" / "tiago_limits.toml"
RADIUS, SEPARATION = 0.0985, 0.4044  # m: TIAGo's wheels (tests/test_io_real_robots.py)


def _run(document):
    parsed = spec.parse(document)
    result = parsed.simulate()
    return parsed, result, metrics.summarize(result, parsed.robot)


@pytest.fixture(scope="module")
def document():
    return tomllib.loads(SPEC.read_text())


@pytest.fixture(scope="module")
def qp(document):
    return _run(document)


@pytest.fixture(scope="module")
def bayle(document):
    plain = copy.deepcopy(document)
    plain["law"] = {"kind": "bayle"}
    return _run(plain)


def _limits(parsed):
    return joint_limits(parsed.robot.coordinate_names[3:], ("lower", "upper", "velocity"))


def _wheel_speeds(eta):
    """(right, left) wheel speeds of a differential drive, rad/s, from η = (v, ω, …)."""
    v, omega = eta[:, 0], eta[:, 1]
    return np.stack([v + SEPARATION * omega / 2, v - SEPARATION * omega / 2], axis=1) / RADIUS


def test_bayle_s_law_leaves_the_limits_on_this_path(bayle):
    parsed, result, summary = bayle
    limits = _limits(parsed)
    assert result.q[:, 3].max() > limits[0, 1] + 0.25  # m: the torso lifted far past its 0.35 m
    assert summary["joint_limit_worst_joint"] == "torso_lift_joint"
    assert np.max(np.abs(result.eta[:, 2]) / limits[0, 2]) > 3  # the torso's speed, 3 times its limit


def test_the_qp_law_keeps_every_joint_inside_its_limits(qp):
    parsed, result, summary = qp
    limits = _limits(parsed)
    joints = result.q[:, 3:]
    assert np.all(joints >= limits[:, 0]) and np.all(joints <= limits[:, 1])
    assert summary["joint_limit_violations"] == 0
    assert result.q[:, 3].max() > limits[0, 1] - 2e-3  # the torso rises to its limit and stays below it
    assert summary["joint_limited_steps"] > 0 and summary["speed_limited_steps"] > 0


def test_the_qp_law_keeps_velocities_and_wheel_speeds_within_their_limits(qp):
    parsed, result, summary = qp
    limits = _limits(parsed)
    wheel = joint_limits(["wheel_right_joint", "wheel_left_joint"], ("velocity",))[:, 0]
    speeds = np.abs(_wheel_speeds(result.eta)) / wheel
    joints = np.abs(result.eta[:, 2:]) / limits[:, 2]
    assert speeds.max() <= 1 + 1e-9 and joints.max() <= 1 + 1e-9
    assert joints.max() > 1 - 1e-6  # a joint's speed limit binds
    assert summary["wheel_speed_ratio"] == pytest.approx(speeds.max(), rel=1e-12)
    platform = np.abs(result.eta[:, :2]) / [
        RADIUS * wheel[0],
        2 * RADIUS * wheel[0] / SEPARATION,
    ]  # the corners
    assert summary["velocity_limit_ratio"] == pytest.approx(max(platform.max(), joints.max()), rel=1e-9)


def test_the_qp_law_tracks_the_pose_as_well_as_bayle_s(qp, bayle):
    _, result, summary = qp
    _, plain, plain_summary = bayle
    assert np.linalg.norm(result.error[-1]) < 1e-4  # m and rad together
    settled = result.t >= 1.0
    assert (
        np.linalg.norm(result.error[settled], axis=1).max()
        < 1.05 * np.linalg.norm(plain.error[settled], axis=1).max()
    )
    assert summary["rms_error"] == pytest.approx(plain_summary["rms_error"], rel=0.01)
    moved = np.abs(result.q[-1] - result.q[0])
    assert moved[0] > 0.3 and np.count_nonzero(moved[4:] > 0.2) >= 4  # the platform and the arm make up


def test_under_a_zero_order_hold_the_damper_is_exact(document):
    """q_{k+1} = q_k + h η_k with η_k ≤ γ (q_max − q_k) and γ h = 1: no sample passes a limit, to the
    program's accuracy."""
    held = copy.deepcopy(document)
    held["integrator"] = "hold"
    held["law"]["limit_gain"] = 1.0 / held["dt"]
    parsed, result, _ = _run(held)
    limits = _limits(parsed)
    joints = result.q[:, 3:]
    assert np.all(joints >= limits[:, 0] - 1e-9) and np.all(joints <= limits[:, 1] + 1e-9)
    assert result.q[:, 3].max() > limits[0, 1] - 1e-6  # one step takes the torso to its limit
