"""6-D pose tasks: SO(3) exp/log against SciPy, the Pose task's Jacobian against finite differences and
autodiff of its error map, pose references, the control laws' use of the rotation error, a closed-loop run
of Bayle's law on a Panda on a differential base, and the spec kinds."""

from __future__ import annotations

import json
import math
import tomllib

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from mobman.cli import main
from mobman.control import criteria, laws, metrics, references, simulate, spec
from mobman.errors import InputError, ModelError
from mobman.kinematics import reduced_jacobian
from mobman.model import robots, so3
from mobman.model.tasks import EulerAngles, FunctionTask, Pose, Position, stack

ROBOT = robots.panda_differential()
LOWER = np.array([lo for lo, _ in ROBOT.position_limits[3:]])
UPPER = np.array([hi for _, hi in ROBOT.position_limits[3:]])
Q0 = np.array([0.2, -0.1, 0.3, 0.0, -0.3, 0.0, -2.0, 0.0, 1.8, 0.8])


def _rotations(n: int, seed: int = 0) -> np.ndarray:
    """Rotation vectors: random axes, angles uniform in [0, π] and exactly 0, π/2, π, and near 0 and π."""
    rng = np.random.default_rng(seed)
    axes = rng.normal(size=(n, 3))
    axes /= np.linalg.norm(axes, axis=1, keepdims=True)
    special = [0.0, 1e-12, 1e-9, 1e-5, 1e-3, math.pi / 2, math.pi - 1e-7, math.pi - 1e-4, math.pi]
    angles = np.concatenate([rng.uniform(0.0, math.pi, n - 4 * len(special)), np.repeat(special, 4)])
    return axes * angles[:, None]


def test_exp_and_log_match_scipy():
    r = _rotations(800)
    matrices = Rotation.from_rotvec(r).as_matrix()
    np.testing.assert_allclose(np.asarray(so3.exp(r)), matrices, rtol=0, atol=2e-15)
    logs = np.asarray(so3.log(matrices))
    expected = Rotation.from_matrix(matrices).as_rotvec()
    angle = np.linalg.norm(r, axis=1)
    below_pi = angle < math.pi - 1e-6
    np.testing.assert_allclose(logs[below_pi], expected[below_pi], rtol=0, atol=3e-15)
    np.testing.assert_allclose(logs[below_pi], r[below_pi], rtol=0, atol=3e-15)
    # near and at π the sign of the axis is a choice: ±log, of the right angle, and exp(log R) = R
    sign_free = np.minimum(np.abs(logs - expected).max(1), np.abs(logs + expected).max(1))
    assert sign_free.max() < 1e-8
    np.testing.assert_allclose(np.linalg.norm(logs, axis=1), angle, rtol=0, atol=1e-8)
    np.testing.assert_allclose(np.asarray(so3.exp(logs)), matrices, rtol=0, atol=3e-15)


def test_exp_and_log_derivatives():
    r = _rotations(40, seed=1)
    below_pi = np.linalg.norm(r, axis=1) < math.pi - 1e-3
    # log ∘ exp = id, with its derivative, below π
    jac = jax.jit(jax.vmap(jax.jacfwd(lambda x: so3.log(so3.exp(x)))))(jnp.asarray(r[below_pi]))
    np.testing.assert_allclose(np.asarray(jac), np.broadcast_to(np.eye(3), jac.shape), rtol=0, atol=1e-9)
    # exp's derivative against central differences of SciPy's rotation matrices
    step = 1e-6
    fd = np.stack(
        [
            (Rotation.from_rotvec(r + step * e).as_matrix() - Rotation.from_rotvec(r - step * e).as_matrix())
            / (2 * step)
            for e in np.eye(3)
        ],
        -1,
    )
    got = jax.jit(jax.vmap(jax.jacfwd(so3.exp)))(jnp.asarray(r))
    np.testing.assert_allclose(np.asarray(got), fd, rtol=0, atol=1e-8)
    # at the identity the derivative of log is the skew part's vector; at π it stays finite
    jac = jax.jit(jax.jacfwd(so3.log))(jnp.eye(3))
    np.testing.assert_allclose(np.asarray(jac), np.asarray(jax.jacfwd(so3.vee)(jnp.eye(3))), atol=1e-15)
    at_pi = jax.jit(jax.jacfwd(so3.log))(jnp.asarray(Rotation.from_rotvec([0.0, 0.0, math.pi]).as_matrix()))
    assert np.all(np.isfinite(np.asarray(at_pi)))


def _configurations(n: int, seed: int = 2) -> np.ndarray:
    """Over the whole joint circle, with joints exactly at ±π/2 and π in some configurations."""
    rng = np.random.default_rng(seed)
    q = rng.uniform(-math.pi, math.pi, size=(n, ROBOT.n_q))
    q[:, :2] = rng.uniform(-3.0, 3.0, size=(n, 2))
    for k, value in enumerate((math.pi / 2, -math.pi / 2, math.pi)):
        q[k::3, 3 + (k % 7)] = value
        q[k::5, 2] = value
    return q


def _error_map(q, xi0):
    """q ↦ e(ξ(q), ξ0): its derivative at ξ(q) = ξ0 is the task Jacobian."""
    return Pose().error(Pose().value(ROBOT, q, ROBOT.frames(q)), xi0)


@jax.jit
@jax.vmap
def _pose_quantities(q):
    frames = ROBOT.frames(q)
    xi = Pose().value(ROBOT, q, frames)
    return {
        "rotation": frames.links[0][0][-1],
        "position": frames.links[0][1][-1],
        "xi": xi,
        "jacobian": Pose().jacobian(ROBOT, q, frames),
        "autodiff": jax.jacfwd(_error_map)(q, xi),
        "position_rows": Position().jacobian(ROBOT, q, frames),
    }


@jax.jit
def _differences(q, xi0, step):
    """Central differences along every coordinate of the error map and of the tool rotation."""
    shifted = (
        q[:, None, None, :]
        + step * jnp.eye(q.shape[-1])[None, None] * jnp.array([1.0, -1.0])[None, :, None, None]
    )
    errors = jax.vmap(jax.vmap(jax.vmap(_error_map, (0, None)), (0, None)), (0, 0))(shifted, xi0)
    rotations = jax.vmap(jax.vmap(jax.vmap(lambda qq: ROBOT.frames(qq).links[0][0][-1])))(shifted)
    return (errors[:, 0] - errors[:, 1]) / (2 * step), (rotations[:, 0] - rotations[:, 1]) / (2 * step)


def test_pose_value_and_jacobian():
    out = {k: np.array(v) for k, v in _pose_quantities(jnp.asarray(_configurations(12))).items()}
    xi, jac, rotation = out["xi"], out["jacobian"], out["rotation"]
    np.testing.assert_allclose(xi[:, :3], out["position"], atol=1e-15)
    np.testing.assert_allclose(Rotation.from_rotvec(xi[:, 3:]).as_matrix(), rotation, atol=1e-14)
    # the Jacobian is the derivative of the error map q ↦ e(ξ(q), ξ(q0)) at q0 (autodiff, central differences)
    np.testing.assert_allclose(out["autodiff"], jac, rtol=0, atol=1e-12)
    fd, r_dot = (np.asarray(a) for a in _differences(jnp.asarray(_configurations(12)), jnp.asarray(xi), 1e-6))
    np.testing.assert_allclose(np.swapaxes(fd, 1, 2), jac, rtol=0, atol=1e-8)
    # independent of the error map: the angular rows are vee(Ṙ Rᵀ) of the rotation's central differences
    omega = so3.vee(r_dot @ np.swapaxes(rotation, -1, -2)[:, None])
    np.testing.assert_allclose(np.swapaxes(np.asarray(omega), 1, 2), jac[:, 3:], rtol=0, atol=1e-8)
    np.testing.assert_allclose(jac[:, :3], out["position_rows"], atol=1e-15)


def test_errors_of_tasks_and_stacks():
    rng = np.random.default_rng(3)
    a, b = rng.normal(size=(5, 6)), rng.normal(size=(5, 6))
    e = np.asarray(Pose().error(a, b))
    np.testing.assert_allclose(e[:, :3], a[:, :3] - b[:, :3], atol=0)
    rel = Rotation.from_rotvec(a[:, 3:]) * Rotation.from_rotvec(b[:, 3:]).inv()
    np.testing.assert_allclose(e[:, 3:], rel.as_rotvec(), atol=1e-14)
    mixed = stack(Position("xy"), Pose(), EulerAngles("ZYX", select=(0,)))
    x, y = rng.normal(size=(4, 9)), rng.normal(size=(4, 9))
    got = np.asarray(mixed.error(x, y))
    np.testing.assert_allclose(got[:, :2], x[:, :2] - y[:, :2], atol=0)
    np.testing.assert_allclose(got[:, 2:8], np.asarray(Pose().error(x[:, 2:8], y[:, 2:8])), atol=0)
    np.testing.assert_allclose(got[:, 8], x[:, 8] - y[:, 8], atol=0)
    vector = stack(Position("xy"), EulerAngles("ZYX"))
    assert vector.euclidean and not mixed.euclidean
    assert np.array_equal(np.asarray(vector.error(x[:, :5], y[:, :5])), x[:, :5] - y[:, :5])


def _gimbal_lock_rotation() -> np.ndarray:
    """An orientation with ZYX pitch exactly π/2 (the Euler-angle task's representation singularity)."""
    return Rotation.from_euler("ZYX", [0.4, math.pi / 2, -0.3]).as_matrix()


_sample = jax.jit(lambda reference, t: reference(t))
"""(ξ*(t), ξ̇*(t)) of a reference (a pytree: one compilation for references of the same structure)."""


def test_pose_reference():
    r0 = Rotation.from_rotvec([0.2, -0.5, 0.1]).as_matrix()
    r1 = _gimbal_lock_rotation()
    ref = references.PoseReference(((0.5, 0.0, 0.8), r0), ((1.0, 0.4, 0.6), r1), duration=4.0)
    same = references.PoseReference(
        ((0.5, 0.0, 0.8), [0.2, -0.5, 0.1]), ((1.0, 0.4, 0.6), Rotation.from_matrix(r1).as_rotvec()), 4.0
    )
    t = np.array([-1.0, 0.0, 0.7, 2.0, 3.3, 4.0, 5.0])
    xi, xi_dot = (np.array(v) for v in _sample(ref, t))
    np.testing.assert_allclose(np.asarray(_sample(same, t)[0]), xi, atol=1e-14)
    np.testing.assert_allclose(Rotation.from_rotvec(xi[[0, 1], 3:]).as_matrix(), [r0, r0], atol=1e-15)
    np.testing.assert_allclose(Rotation.from_rotvec(xi[[5, 6], 3:]).as_matrix(), [r1, r1], atol=1e-14)
    np.testing.assert_allclose(xi[[0, 6], :3], [(0.5, 0.0, 0.8), (1.0, 0.4, 0.6)], atol=1e-15)
    assert np.all(xi_dot[[0, 1, 5, 6]] == 0.0)
    # the geodesic: R*(t) R0ᵀ has angle s(t) · angle(R1 R0ᵀ), about a fixed axis; halfway (quintic) s = 1/2
    half = Rotation.from_rotvec(np.array(_sample(ref, 2.0)[0])[3:]) * Rotation.from_matrix(r0).inv()
    full = Rotation.from_matrix(r1) * Rotation.from_matrix(r0).inv()
    np.testing.assert_allclose(half.as_rotvec(), 0.5 * full.as_rotvec(), atol=1e-14)
    # velocities against central differences: ṗ, and ω = vee(Ṙ Rᵀ)
    h = 1e-6
    for tk in (0.7, 2.0, 3.3):
        (a, _), (b, _) = _sample(ref, tk - h), _sample(ref, tk + h)
        ra, rb = (Rotation.from_rotvec(np.array(x)[3:]).as_matrix() for x in (a, b))
        rm = Rotation.from_rotvec(np.array(_sample(ref, tk)[0])[3:]).as_matrix()
        fd = np.concatenate(
            [(np.asarray(b) - np.asarray(a))[:3] / (2 * h), so3.vee((rb - ra) / (2 * h) @ rm.T)]
        )
        np.testing.assert_allclose(np.asarray(_sample(ref, tk)[1]), fd, rtol=0, atol=1e-8)


def test_pose_function_reference():
    axis = np.array([1.0, 2.0, -2.0]) / 3.0
    r0 = jnp.asarray(Rotation.from_rotvec([0.3, 0.1, 0.0]).as_matrix())

    def path(t):
        return jnp.stack([t, 2.0 * t, jnp.sin(t)]), so3.exp(0.8 * t * jnp.asarray(axis)) @ r0

    ref = references.PoseFunctionReference(path)
    xi, xi_dot = (np.array(v) for v in ref(1.2))
    np.testing.assert_allclose(xi_dot, np.concatenate([[1.0, 2.0, math.cos(1.2)], 0.8 * axis]), atol=1e-14)
    expected = Rotation.from_rotvec(1.2 * 0.8 * axis) * Rotation.from_matrix(np.array(r0))
    np.testing.assert_allclose(xi[3:], expected.as_rotvec(), atol=1e-14)
    with pytest.raises(ModelError, match="p \\(3,\\) and R \\(3, 3\\)"):
        references.PoseFunctionReference(lambda t: (jnp.zeros(3), jnp.zeros(3)))


@pytest.mark.parametrize(
    "start, match",
    [
        (((0.0, 0.0), [0.0, 0.0, 0.0]), "start position"),
        (((0.0, 0.0, 0.0), np.diag([1.0, 1.0, -1.0])), "not a rotation matrix"),
        (((0.0, 0.0, 0.0), [0.0, math.nan, 0.0]), "start orientation"),
        ((0.0, 0.0, 0.0), "pair"),
    ],
)
def test_pose_reference_bad_input(start, match):
    with pytest.raises(ModelError, match=match):
        references.PoseReference(start, ((0.0, 0.0, 0.0), np.eye(3)), 1.0)


def test_laws_regulate_the_rotation_error():
    """With J̄ of full rank and no damping, η solves J̄ η = ξ̇* + K e with e the pose error (orientation:
    SciPy's rotation vector of R* Rᵀ), not the difference of rotation vectors: Bayle's law (Nait-Chabane's
    shares its resolution) and Korayem's augmented law, whose extra rows here hold the first three joints."""
    q = jnp.asarray(Q0)
    xi = np.array(Pose().value(ROBOT, q, ROBOT.frames(q)))
    r_star = Rotation.from_rotvec([0.0, 0.0, 2.5]) * Rotation.from_rotvec(xi[3:])
    xi_star = np.concatenate([xi[:3] + [0.05, -0.02, 0.01], r_star.as_rotvec()])
    xi_star_dot = np.array([0.1, 0.0, -0.05, 0.2, 0.1, -0.3])
    e = np.concatenate([xi_star[:3] - xi[:3], (r_star * Rotation.from_rotvec(xi[3:]).inv()).as_rotvec()])
    jbar = np.asarray(reduced_jacobian(ROBOT, Q0, Pose()))
    extra = FunctionTask(_first_joints, ("q1", "q2", "q3"))  # Korayem's extra rows J_z
    cases = [
        (laws.BaylePseudoInverse(W=2.0), 2.0, xi_star, xi_star_dot),
        (
            laws.AugmentedJacobian(extra=extra, feedback=1.5),
            1.5,
            np.concatenate([xi_star, Q0[3:6] + 0.01]),
            np.concatenate([xi_star_dot, np.zeros(3)]),
        ),
    ]
    for law, gain, reference, velocity in cases:
        eta = jax.jit(lambda qq, law=law, r=reference, v=velocity: law(ROBOT, Pose(), qq, 0.0, r, v).eta)(q)
        np.testing.assert_allclose(jbar @ np.asarray(eta), xi_star_dot + gain * e, rtol=0, atol=1e-10)
    np.testing.assert_allclose(np.asarray(eta)[2:5], 1.5 * 0.01 * np.ones(3), rtol=0, atol=1e-10)


def _first_joints(q):
    return q[3:6]


W = 2.0


@pytest.fixture(scope="module")
def tracking():
    """Bayle's law with ∇w5 in the null space tracking a line + slerp that ends at ZYX pitch = π/2, from an
    initial pose error of 3 cm and 0.3 rad."""
    q0 = jnp.asarray(Q0)
    xi0 = np.array(Pose().value(ROBOT, q0, ROBOT.frames(q0)))
    start_rotation = Rotation.from_rotvec([0.3, 0.0, 0.0]) * Rotation.from_rotvec(xi0[3:])
    ref = references.PoseReference(
        (xi0[:3] + [0.03, 0.0, 0.0], start_rotation.as_matrix()),
        (xi0[:3] + [0.6, 0.3, -0.1], _gimbal_lock_rotation()),
        duration=4.0,
    )
    law = laws.BaylePseudoInverse(W=W, k=0.3, criterion=criteria.Manipulability("eccentricity", "system"))
    return simulate(ROBOT, Pose(), law, ref, Q0, duration=6.0, dt=0.02)


def test_closed_loop_pose_tracking(tracking):
    res = tracking
    position, orientation = (np.linalg.norm(res.error[:, s], axis=1) for s in (slice(0, 3), slice(3, 6)))
    assert position[0] == pytest.approx(0.03) and orientation[0] == pytest.approx(0.3)
    # d‖e‖²/dt = −2 W ‖e‖² while J̄ J̄⁺ = I: the error norm decays as exp(−W t) along the moving reference
    norm = np.linalg.norm(res.error, axis=1)
    np.testing.assert_allclose(norm, norm[0] * np.exp(-W * res.t), rtol=1e-3, atol=1e-9)
    assert position[-1] < 1e-5 and orientation[-1] < 1e-5
    # the end orientation is a gimbal lock of the ZYX angles: that task's J̄ loses rank, the pose task's does not
    euler = np.linalg.svd(
        np.asarray(reduced_jacobian(ROBOT, res.q[-1], stack(Position(), EulerAngles("ZYX"))))
    )
    pose = np.linalg.svd(np.asarray(reduced_jacobian(ROBOT, res.q[-1], Pose())))
    assert euler[1][0] / euler[1][-1] > 1e4 > 100.0 > pose[1][0] / pose[1][-1]
    assert not np.any(res.damped)


def test_joint_limit_violations_are_reported(tracking):
    summary = metrics.summarize(tracking, ROBOT)
    arm = tracking.q[:, 3:]
    excess = np.maximum(LOWER - arm, 0.0) + np.maximum(arm - UPPER, 0.0)
    assert summary["joint_limit_violations"] == int(np.count_nonzero(excess.max(axis=1) > 0))
    assert summary["joint_limit_worst"] == pytest.approx(float(excess.max()), abs=1e-15)
    # a crafted path: joint 4 0.1 rad below its lower limit in one sample, joint 6 0.2 rad above in another
    q = np.repeat(Q0[None], 4, axis=0)
    q[1, 6] = LOWER[3] - 0.1
    q[2, 8] = UPPER[5] + 0.2
    report = metrics.joint_limit_violations(ROBOT, q)
    assert report["joint_limit_violations"] == 2
    assert report["joint_limit_worst"] == pytest.approx(0.2)
    assert report["joint_limit_worst_joint"] == ROBOT.coordinate_names[8]
    assert metrics.joint_limit_violations(ROBOT, q[[0, 3]])["joint_limit_worst_joint"] is None


SPEC = """
duration = 6.0
dt = 0.02
q0 = [0.2, -0.1, 0.3, 0.0, -0.3, 0.0, -2.0, 0.0, 1.8, 0.8]
[robot]
name = "panda-differential"
[task]
kind = "pose"
[reference]
kind = "pose"
start = [0.4, 0.0, 0.9]
start_rotvec = [3.0, 0.0, 0.0]
end = [0.6, 0.1, 0.8]
end_rpy = [0.2, 1.5707963267948966, 0.4]
duration = 4.0
[law]
kind = "bayle"
[criterion]
kind = "manipulability"
[gains]
W = 2.0
k = 0.3
"""
"""The law, step and duration of the ``tracking`` run: the command reuses its compiled simulation."""


def test_spec_pose_kinds(tmp_path, capsys, tracking):
    parsed = spec.parse(tomllib.loads(SPEC))
    assert parsed.task == Pose()
    direct = references.PoseReference(
        ((0.4, 0.0, 0.9), [3.0, 0.0, 0.0]),
        ((0.6, 0.1, 0.8), Rotation.from_euler("xyz", [0.2, math.pi / 2, 0.4]).as_matrix()),
        4.0,
    )
    for t in (0.0, 1.3, 4.0):
        np.testing.assert_allclose(np.asarray(parsed.reference(t)[0]), np.asarray(direct(t)[0]), atol=1e-14)
        np.testing.assert_allclose(np.asarray(parsed.reference(t)[1]), np.asarray(direct(t)[1]), atol=1e-14)
    path = tmp_path / "pose.toml"
    path.write_text(SPEC)
    main(["simulate", str(path), "--json"])
    out = json.loads(capsys.readouterr().out)
    run = simulate(parsed.robot, parsed.task, parsed.law, parsed.reference, parsed.q0, 6.0, 0.02)
    direct = metrics.summarize(run, parsed.robot)
    for key in ("joint_limit_violations", "joint_limit_worst_joint"):
        assert out[key] == direct[key]
    for key in ("joint_limit_worst", "final_error"):
        assert out[key] == pytest.approx(direct[key], rel=1e-12, abs=1e-15)
    assert len(out["q_final"]) == ROBOT.n_q


@pytest.mark.parametrize(
    "old, new, match",
    [
        ("end_rpy = [0.2, 1.5707963267948966, 0.4]", "", "give one of end_rotvec, end_rpy"),
        ("start_rotvec = [3.0, 0.0, 0.0]", "start_rotvec = [3.0, 0.0]\nstart_rpy = [0, 0, 0]", "give one of"),
        ("start_rotvec = [3.0, 0.0, 0.0]", "start_rotvec = [3.0, 0.0]", "reference.start_rotvec: 3 numbers"),
        ("start = [0.4, 0.0, 0.9]", "start = [0.4, 0.0]", "reference: PoseReference: start position"),
        ('kind = "pose"\n[reference]', 'kind = "pose"\narm = 3\n[reference]', "task"),
    ],
)
def test_spec_pose_errors(old, new, match):
    assert old in SPEC
    with pytest.raises(InputError, match=match):
        spec.parse(tomllib.loads(SPEC.replace(old, new)))
