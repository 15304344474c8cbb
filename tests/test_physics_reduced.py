"""mobman's reduced dynamics (mobman.dynamics.reduced) against MuJoCo's rigid-body model of the exported robot
(mobman.physics.reduced): P = Sᵀ M S, b = Sᵀ (M Ṡ η + c + g) and B = Sᵀ E from ``mj_fullM``, ``qfrc_bias``
and the actuators' moment arms, exact to rounding; and a slow motion on wheel contacts, where the torques
MuJoCo's servos apply match mobman's inverse dynamics of the measured motion within the contact softness."""

from __future__ import annotations

import math

import mujoco
import numpy as np
import pytest

from mobman.dynamics import DynamicModel, yamamoto_model
from mobman.dynamics.reduced import inverse_dynamics, reduced_terms
from mobman.io.real_robots import urdf_model
from mobman.physics import measured_q, set_configuration, to_mjspec
from mobman.physics.reduced import admissible_basis, mujoco_reduced_terms

EXACT = 1e-11
"""Relative agreement of mobman's and MuJoCo's P, b, B (both float64 rigid-body algorithms on the same
bodies: rounding only)."""

CONTACT = 0.15
"""Largest difference between the torque MuJoCo's servo applies and mobman's inverse dynamics of the measured
motion, relative to that actuator's peak torque (docs/physics.md: the platform rocking on its soft contacts)."""


def _random_states(robot, n: int, seed: int) -> tuple[np.ndarray, np.ndarray]:
    """n states over the whole range: the heading and every joint angle uniform in their ranges, with exactly
    ±π/2 and π among the headings (and the joints where their ranges hold them); η uniform in ±1."""
    rng = np.random.default_rng(seed)
    q = rng.uniform(-math.pi, math.pi, (n, robot.n_q))
    q[:, :2] *= 3.0
    q[:4, 2] = [math.pi / 2, -math.pi / 2, math.pi, 0.0][:n]
    joints = [j for arm in robot.arms for j in arm.joints]
    for k, joint in enumerate(joints, robot.n_platform):
        lower = joint.lower if math.isfinite(joint.lower) else -math.pi
        upper = joint.upper if math.isfinite(joint.upper) else math.pi
        q[:, k] = rng.uniform(lower, upper, n)
        for row, special in enumerate((math.pi / 2, -math.pi / 2, math.pi)[:n]):
            if lower <= special <= upper:
                q[row, k] = special
    return q, rng.uniform(-1.0, 1.0, (n, robot.n_eta))


@pytest.mark.parametrize(
    "dynamics",
    [yamamoto_model(), DynamicModel.from_urdf(urdf_model("tiago"))],
    ids=["yamamoto", "tiago"],
)
def test_reduced_terms_equal_mujocos(dynamics):
    """Yamamoto & Yun's robot (Table 1–2, planar) and TIAGo (URDF inertials, a 3-D arm under gravity)."""
    q, eta = _random_states(dynamics.robot, 8, seed=3)
    p, b, b_mat = (np.asarray(x) for x in reduced_terms(dynamics, q, eta))
    p_mj, b_mj, b_mat_mj = mujoco_reduced_terms(dynamics, q, eta)
    assert np.abs(p - p_mj).max() <= EXACT * np.abs(p_mj).max()
    assert np.abs(b - b_mj).max() <= EXACT * max(np.abs(b_mj).max(), 1.0)
    assert np.abs(b_mat - b_mat_mj).max() <= EXACT * np.abs(b_mat_mj).max()


def test_the_comparison_can_fail():
    """A platform body 1 kg heavier in MuJoCo's model than in mobman's shows in P (so the check is live)."""
    dynamics = yamamoto_model()
    heavier = to_mjspec(dynamics)
    heavier.body("platform").mass += 1.0
    q, eta = _random_states(dynamics.robot, 8, seed=3)
    p = np.asarray(reduced_terms(dynamics, q, eta)[0])
    p_mj = mujoco_reduced_terms(dynamics, q, eta, model=heavier.compile())[0]
    assert abs(p_mj[0, 0, 0] - p[0, 0, 0]) == pytest.approx(1.0, rel=1e-9)  # the mass seen by v


def test_slow_motion_on_contacts_needs_mobmans_torques():
    """Yamamoto & Yun's robot drives, turns and swings both arms for 2 s on its wheels (velocity servos on
    friction contacts, 1-kHz physics). At every step the torque each servo applied (its force, with the
    implicit integrator's damping over the step) equals mobman's τ = B⁻¹ (P η̇ + b) at the measured state,
    η the measured velocity projected on S_mj, η̇ its step difference, within :data:`CONTACT` of the
    actuator's peak."""
    dynamics = yamamoto_model()
    robot = dynamics.robot
    model = to_mjspec(dynamics).compile()
    data = mujoco.MjData(model)
    q0 = np.array([0.0, 0.0, 0.0, 0.3, 0.6, -0.4, -0.3, -0.6, 0.4])
    set_configuration(model, data, robot, q0)
    h, n = model.opt.timestep, 2000
    ids = np.array([model.actuator(name).id for name in dynamics.actuator_names])
    dofs = model.jnt_dofadr[model.actuator_trnid[ids, 0]]
    qs, vs, forces = np.zeros((n, robot.n_q)), np.zeros((n, model.nv)), np.zeros((n, len(ids)))
    for k in range(n):
        s = math.sin(math.pi * k / n) ** 2  # rest to rest
        eta = np.array([0.2 * s, 0.3 * s, *(0.3 * s * np.array([1, -1, 1, -1, 1, -1]))])
        data.ctrl[ids] = np.concatenate([np.asarray(robot.platform.eta_to_wheel_speeds(eta[:2])), eta[2:]])
        mujoco.mj_forward(model, data)
        qs[k], vs[k], force = measured_q(model, data, robot), data.qvel, data.actuator_force[ids].copy()
        mujoco.mj_step(model, data)
        # implicitfast integrates the servos' damping (force = … + biasprm[2] × velocity) at the new velocity
        forces[k] = force + model.actuator_biasprm[ids, 2] * (data.qvel[dofs] - vs[k, dofs])
    s_mj, _ = admissible_basis(model, robot, qs, np.zeros((n, robot.n_eta)))
    eta = np.einsum("nkv,nv->nk", np.linalg.pinv(s_mj), vs)
    tau = np.asarray(inverse_dynamics(dynamics, qs[:-1], eta[:-1], np.diff(eta, axis=0) / h))
    peak = np.abs(forces).max(axis=0)
    assert np.all(peak > 0.05)  # every actuator works
    assert np.all(np.abs(tau - forces[:-1]).max(axis=0) <= CONTACT * peak)
