"""The real robots read from their URDF files against Pinocchio reading the same files.

Pinocchio's model: ``buildModelFromUrdf`` with a ``JointModelPlanar`` root (q = x, y, cos θ, sin θ; velocity
(v_x, v_y, ω_z) in the base frame), every joint off mobman's chains locked at zero (``buildReducedModel``,
which lumps the locked links into their parents, as mobman does). The admissible velocities of the
differential drive are v_x = v, v_y = 0, ω_z = ω: S_pin keeps the v_x and ω_z columns and the chain joints.

- FK of the tip (position and rotation) and J̄ = J S (linear and angular rows) at 1,000 random configurations
  within the joint limits (including exactly ±π/2 and π for the heading and unbounded joints): 1e-10.
- M(q) in mobman's coordinates (ẋ, ẏ, θ̇, q̇_a), with the wheels' spin left out: with q̇ = T v_pin,
  T = diag(R(θ), 1, I), Pinocchio's CRBA matrix is Tᵀ M T; the reduced Sᵀ M S equals S_pinᵀ M_pin S_pin plus the wheels' spin
  inertia, which Pinocchio's locked wheels lack: I_w (φ̇_r² + φ̇_l²) with φ̇_r,l = (v ± b ω)/r adds
  2 I_w / r² to the v entry and 2 I_w b² / r² to the ω entry (I_w read from Pinocchio's wheel inertia): 1e-9.
"""

from __future__ import annotations

import jax
import jax.numpy as jnp
import numpy as np
import pinocchio as pin
import pytest

from mobman import dynamics as dyn
from mobman.io.real_robots import REAL_ROBOTS, urdf_model

N = 1000


def _pinocchio(name: str):
    spec = REAL_ROBOTS[name]
    model = urdf_model(name)
    full = pin.buildModelFromUrdf(str(spec.path()), pin.JointModelPlanar())
    keep = {j.name for arm in model.robot.arms for j in arm.joints}
    reference = pin.neutral(full)
    for joint_name, value in spec.locked:
        reference[full.idx_qs[full.getJointId(joint_name)]] = value
    locked = [i for i in range(2, full.njoints) if full.names[i] not in keep]
    reduced = pin.buildReducedModel(full, locked, reference)
    return model, full, reduced


def _random_q(robot, rng, n):
    q = np.empty((n, robot.n_q))
    q[:, :2] = rng.uniform(-3.0, 3.0, (n, 2))
    q[:, 2] = rng.uniform(-np.pi, np.pi, n)
    specials = np.array([np.pi / 2, -np.pi / 2, np.pi, -np.pi, 0.0])
    q[: len(specials), 2] = specials
    for k, (lower, upper) in enumerate(robot.position_limits[3:], start=3):
        lo, hi = (-np.pi, np.pi) if not np.isfinite(lower) else (lower, upper)
        q[:, k] = rng.uniform(lo, hi, n)
        if not np.isfinite(lower):
            q[: len(specials), k] = specials[::-1]
        else:
            q[0, k], q[1, k] = lower, upper  # both ends of the range
    return q


def _to_pinocchio(reduced, robot, q):
    """mobman q (n, n_q) → Pinocchio q (n, nq): planar root (x, y, cos θ, sin θ), then the joints by name."""
    joint_names = [j.name for arm in robot.arms for j in arm.joints]
    out = np.zeros((len(q), reduced.nq))
    out[:, 0], out[:, 1] = q[:, 0], q[:, 1]
    out[:, 2], out[:, 3] = np.cos(q[:, 2]), np.sin(q[:, 2])
    columns = []
    for k, joint_name in enumerate(joint_names):
        jid = reduced.getJointId(joint_name)
        assert reduced.nqs[jid] == 1, f"{joint_name}: one coordinate in Pinocchio"
        out[:, reduced.idx_qs[jid]] = q[:, 3 + k]
        columns.append(reduced.idx_vs[jid])
    return out, np.array(columns)


def _tool_pose_and_jacobian(robot, arm: int):
    """Batched tool pose (R, p) and 6 × n_eta reduced Jacobian [linear; angular] of arm ``arm``'s tool frame."""
    n = robot.arms[arm].n_joints

    def one(q):
        frames = robot.frames(q)
        rs, ps = frames.links[arm]
        lin, ang = robot.point_jacobian(q, frames, ps[n], arm, n - 1)
        return rs[n], ps[n], robot.apply_S(jnp.concatenate([lin, ang]), q)

    return jax.jit(jax.vmap(one))


@pytest.mark.parametrize("name", ["tiago", "stretch", "tiago-dual"])
def test_tool_pose_and_reduced_jacobian_match_pinocchio(name):
    model, _, reduced = _pinocchio(name)
    robot = model.robot
    rng = np.random.default_rng(20)
    n = N if name != "tiago-dual" else N // 4
    q = _random_q(robot, rng, n)
    q_pin, columns = _to_pinocchio(reduced, robot, q)
    data = reduced.createData()
    for arm, tip in enumerate(REAL_ROBOTS[name].tips):
        r_ours, p_ours, jbar_ours = map(np.asarray, _tool_pose_and_jacobian(robot, arm)(q))
        fid = reduced.getFrameId(tip)
        chain = robot.arm_slice(arm)
        arm_columns = columns[chain.start - 3 : chain.stop - 3]
        worst_pose, worst_jac = 0.0, 0.0
        for k in range(n):
            pin.framesForwardKinematics(reduced, data, q_pin[k])
            pose = data.oMf[fid]
            worst_pose = max(
                worst_pose,
                np.abs(pose.translation - p_ours[k]).max(),
                np.abs(pose.rotation - r_ours[k]).max(),
            )
            jac = pin.computeFrameJacobian(reduced, data, q_pin[k], fid, pin.LOCAL_WORLD_ALIGNED)
            expected = np.zeros((6, robot.n_eta))
            expected[:, :2] = jac[:, [0, 2]]  # v_x = v, ω_z = ω (v_y = 0: the rolling constraint)
            s = robot.arm_eta_slice(arm)
            expected[:, s] = jac[:, arm_columns]
            worst_jac = max(worst_jac, np.abs(expected - jbar_ours[k]).max())
        assert worst_pose < 1e-10 and worst_jac < 1e-10, (worst_pose, worst_jac)


def _wheel_spin(full, model):
    """I_w = I_zz of the right wheel's Pinocchio inertia about its centre of mass (the wheel joints turn about
    their frame's z axis)."""
    jid = full.getJointId(model.summary.wheels[0])
    assert full.joints[jid].shortname() in ("JointModelRUBZ", "JointModelRZ")
    return float(full.inertias[jid].inertia[2, 2])


@pytest.mark.parametrize("name", ["tiago", "stretch"])
def test_mass_matrices_match_pinocchio_crba(name):
    """M(q) on TIAGo (the full matrix costs a compilation of its own), Sᵀ M S on both robots."""
    model, full, reduced = _pinocchio(name)
    robot = model.robot
    rng = np.random.default_rng(7)
    q = _random_q(robot, rng, 12)
    q_pin, columns = _to_pinocchio(reduced, robot, q)
    if name == "tiago":
        no_spin = dyn.DynamicModel(robot, model.body, dyn.Wheel(0.0, 0.0, 0.0), None, (0.0, 0.0, -9.81))
        m_ours = np.asarray(dyn.mass_matrix(no_spin, q))
    p_ours = np.asarray(dyn.reduced_mass_matrix(dyn.DynamicModel.from_urdf(model), q))
    i_w = _wheel_spin(full, model)
    assert i_w == pytest.approx(model.wheel.I_w, rel=1e-12)
    r, b = robot.platform.wheel_radius, robot.platform.half_track
    data = reduced.createData()
    for k in range(len(q)):
        m_pin = pin.crba(reduced, data, q_pin[k]).copy()
        m_pin = np.triu(m_pin) + np.triu(m_pin, 1).T
        order = np.r_[0, 1, 2, columns]
        m_pin = m_pin[np.ix_(order, order)]
        t = np.eye(robot.n_q)
        c, s = np.cos(q[k, 2]), np.sin(q[k, 2])
        t[:2, :2] = [[c, -s], [s, c]]
        scale = np.abs(m_pin).max()
        if name == "tiago":
            assert np.abs(t.T @ m_ours[k] @ t - m_pin).max() <= 1e-9 * scale
        select = np.zeros((robot.n_q, robot.n_eta))
        select[0, 0] = select[2, 1] = 1.0
        select[3:, 2:] = np.eye(robot.n_q - 3)
        expected = select.T @ m_pin @ select
        expected[0, 0] += 2 * i_w / r**2
        expected[1, 1] += 2 * i_w * b**2 / r**2
        assert np.abs(p_ours[k] - expected).max() <= 1e-9 * scale
