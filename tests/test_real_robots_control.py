"""Whole-body pose control of TIAGo (docs/examples/tiago_pose.toml): Bayle's law with the system
eccentricity in the null space tracks a 6-D pose path with the platform, the torso and the arm together.

The pose error is checked against SciPy's rotations, its decay against the closed form exp(−W t) of
docs/pose_tasks.md, and the joint-limit report against a NumPy count with the limits read from the URDF
file itself (ElementTree, not mobman's reader)."""

import tomllib
from pathlib import Path

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from mobman.control import metrics, spec

from tiago_urdf import joint_limits

SPEC = Path(__file__).resolve().parents[1] / "docs" / "examples" / "tiago_pose.toml"


@pytest.fixture(scope="module")
def run():
    parsed = spec.load(SPEC)
    result = parsed.simulate()
    return parsed, result, metrics.summarize(result, parsed.robot)


def _outside(q, limits):
    """Samples with a coordinate outside its limits, and the largest excess per coordinate."""
    excess = np.clip(limits[:, 0] - q, 0, None) + np.clip(q - limits[:, 1], 0, None)
    return int(np.sum(np.any(excess > 0, axis=1))), excess.max(axis=0)


def _rotation_errors(rotvec_star, rotvec):
    """‖log(R* Rᵀ)‖ per sample, with SciPy's rotations (which read writable arrays only: the result's arrays are
    read-only views)."""
    star, actual = np.array(rotvec_star), np.array(rotvec)
    return (Rotation.from_rotvec(star) * Rotation.from_rotvec(actual).inv()).magnitude()


def test_the_reference_is_the_spec_s_path(run):
    _, result, _ = run
    table = tomllib.loads(SPEC.read_text())["reference"]
    for key, sample in (("start", 0), ("end", -1)):
        roll, pitch, yaw = table[f"{key}_rpy"]  # R = Rz(yaw) Ry(pitch) Rx(roll)
        rotation = Rotation.from_euler("ZYX", [yaw, pitch, roll])
        np.testing.assert_allclose(result.xi_star[sample, :3], table[key], atol=1e-12)
        assert _rotation_errors(result.xi_star[sample, 3:], rotation.as_rotvec()) < 1e-12
    distance = np.linalg.norm(np.subtract(table["end"], table["start"]))
    turn = _rotation_errors(result.xi_star[-1, 3:], result.xi_star[0, 3:])
    assert 0.3 < distance < 0.5 and turn > 0.5  # m, rad


def test_the_pose_error_decays_as_exp_minus_w_t(run):
    parsed, result, _ = run
    position = np.linalg.norm(result.xi_star[:, :3] - result.xi[:, :3], axis=1)
    orientation = _rotation_errors(result.xi_star[:, 3:], result.xi[:, 3:])
    np.testing.assert_allclose(np.linalg.norm(result.error[:, :3], axis=1), position, atol=1e-12)
    np.testing.assert_allclose(np.linalg.norm(result.error[:, 3:], axis=1), orientation, atol=1e-9)
    assert position[0] > 0.01 and orientation[0] > 0.1  # the path starts off the hand
    assert position[-1] < 1e-4 and orientation[-1] < 1e-4  # m, rad
    # scalar W, exact law: ‖e(t)‖ = ‖e(0)‖ exp(−W t) while the reference moves and turns
    norm = np.hypot(position, orientation)
    np.testing.assert_allclose(norm, norm[0] * np.exp(-float(parsed.law.W) * result.t), rtol=1e-3)


def test_platform_torso_and_arm_all_move(run):
    parsed, result, _ = run
    names = parsed.robot.coordinate_names
    moved = np.abs(result.q[-1] - result.q[0])
    assert names[:4] == ("x", "y", "theta", "torso_lift_joint")
    assert moved[0] > 0.2  # m: the platform drives forward
    assert moved[3] > 0.05  # m: the torso lifts
    assert np.count_nonzero(moved[4:] > 0.05) >= 4  # rad: the arm reconfigures
    heading = 0.5 * (result.q[1:, 2] + result.q[:-1, 2])  # an arc's chord lies along its mean heading
    step = np.diff(result.q[:, :2], axis=0)
    lateral = step[:, 1] * np.cos(heading) - step[:, 0] * np.sin(heading)
    assert np.abs(lateral).max() < 1e-3 * np.abs(np.diff(result.q[:, 0])).max()  # no sideways slip


def test_joint_limit_report_matches_the_urdf(run):
    parsed, result, summary = run
    names = parsed.robot.coordinate_names[3:]
    limits = joint_limits(names)
    count, excess = _outside(result.q[:, 3:], limits)
    assert summary["joint_limit_violations"] == count
    assert summary["joint_limit_worst"] == pytest.approx(excess.max(), abs=1e-12)
    assert summary["joint_limit_worst_joint"] == (names[int(np.argmax(excess))] if count else None)
    # the same report on this path pushed partly past arm_1_joint's lower limit (0 rad) and arm_4_joint's
    # upper one: the metric is the one `mobman simulate` prints
    shifted = result.q.copy()
    shifted[:, 4] -= 0.6
    shifted[:, 7] += 0.4
    count, excess = _outside(shifted[:, 3:], limits)
    report = metrics.joint_limit_violations(parsed.robot, shifted)
    assert count > 0 and count < len(shifted)
    assert report["joint_limit_violations"] == count
    assert report["joint_limit_worst"] == pytest.approx(excess.max(), abs=1e-12)
    assert report["joint_limit_worst_joint"] == names[int(np.argmax(excess))]
