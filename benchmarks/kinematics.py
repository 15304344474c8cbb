"""Benchmark: reduced Jacobian J̄ (6 × 9) and the manipulability measures w, w2, w5 of a Franka Panda arm
on a differential-drive base, batched and one configuration at a time, against a NumPy per-call baseline.

    python benchmarks/kinematics.py            # 100,000 configurations
    python benchmarks/kinematics.py --n 1000000
    python benchmarks/kinematics.py --smoke    # tiny sizes (CI)

JAX runs it on its default device: on a GPU use ``--n 1000000`` or more (a GPU needs a large batch to fill).
The batched configurations are put in the device's memory before the timing.

The 6 task rows are the end-effector position and its ZYX Euler angles (``EulerAngles("ZYX")``): the
analytic Jacobian a task-space controller uses. Timings are the best of a few repetitions after compilation.

Two reference points are timed in the same run, so a run on a faster or slower machine can be read against
them: a straightforward jit + vmap JAX version (``jacfwd`` of a 4 × 4 transform chain, then
``jnp.linalg.svd``) and Pinocchio's arm Jacobian called from Python (when Pinocchio, a ``test`` extra, is
installed). They and the NumPy baseline are checked against mobman: a
difference above ``AGREEMENT`` ends the run with an error, so CI's smoke run fails on it.

The run ends with what limits it: the achieved fp64 GFLOP/s of the batched kernel (XLA's flop count of one
block, against the CPU's peak from ``lscpu``), and the structure of the compiled programs (kernels, gathers,
constant arrays, LAPACK calls, YNN library fusions) of one configuration, of one block and of the Jacobian's
reverse-mode derivative.
"""

from __future__ import annotations

import argparse
import contextlib
import functools
import math
import time

import jax
import jax.numpy as jnp
import numpy as np

import mobman  # noqa: F401  (float64)
from mobman import manipulability as mp
from mobman.engine import batched as batching
from mobman.model import MobileManipulator
from mobman.model.robots import PANDA_LIMITS, PANDA_MODIFIED_DH, panda_differential
from mobman.model.tasks import EulerAngles, Position, stack

from timing import best_time, describe_structure, print_peak, program_structure, roofline, xla_cost

AGREEMENT = 1e-9
"""Largest difference from a reference implementation the benchmark accepts (it exits with an error above)."""

# Franka Emika Panda, modified DH (Craig) rows (α_{i−1}, a_{i−1}, θ_i, d_i), as mobman's built-in robot has them
PANDA_ALPHA, PANDA_A, _, PANDA_D = zip(*PANDA_MODIFIED_DH)


def panda_on_differential_base() -> MobileManipulator:
    """Panda (7 joints) on a differential base (v_max = 1 m/s, ω_max = 1.5 rad/s), task = position + ZYX."""
    return panda_differential(height=0.0).with_task(stack(Position("xyz"), EulerAngles("ZYX")))


def random_configurations(robot: MobileManipulator, n: int, seed: int = 0) -> np.ndarray:
    rng = np.random.default_rng(seed)
    low = np.array([-5.0, -5.0, -math.pi] + [lo for lo, _ in PANDA_LIMITS])
    high = np.array([5.0, 5.0, math.pi] + [hi for _, hi in PANDA_LIMITS])
    return rng.uniform(low, high, size=(n, robot.n_q))


# --- the Panda's homogeneous transforms, for the NumPy baseline (xp = np) and the straightforward JAX one ---


def _planar(x, y, c, s, xp):
    """4 × 4 pose of the platform at (x, y) with heading cos c, sin s."""
    return xp.array([[c, -s, 0.0, x], [s, c, 0.0, y], [0.0, 0.0, 1.0, 0.0], [0.0, 0.0, 0.0, 1.0]])


def _mdh(i: int, ct, st, xp):
    """4 × 4 modified-DH transform of Panda joint i at cos θ = ct, sin θ = st."""
    ca, sa, a, d = math.cos(PANDA_ALPHA[i]), math.sin(PANDA_ALPHA[i]), PANDA_A[i], PANDA_D[i]
    return xp.array(
        [
            [ct, -st, 0.0, a],
            [st * ca, ct * ca, -sa, -sa * d],
            [st * sa, ct * sa, ca, ca * d],
            [0.0, 0.0, 0.0, 1.0],
        ]
    )


# --- NumPy per-call baseline: homogeneous transforms, geometric Jacobian, ZYX rate map, np.linalg.svd ---


def _numpy_jbar(q: np.ndarray) -> np.ndarray:
    x, y, th = q[:3]
    c, s = math.cos(th), math.sin(th)
    t = _planar(x, y, c, s, np)
    origins, axes = [], []
    for i in range(7):
        t = t @ _mdh(i, math.cos(q[3 + i]), math.sin(q[3 + i]), np)
        origins.append(t[:3, 3].copy())
        axes.append(t[:3, 2].copy())
    r = t[:3, :3]
    p = t[:3, 3] + 0.107 * r[:, 2]
    jl = np.zeros((3, 10))
    jw = np.zeros((3, 10))
    jl[0, 0] = jl[1, 1] = 1.0
    jl[:, 2] = np.cross([0.0, 0.0, 1.0], p - np.array([x, y, 0.0]))
    jw[2, 2] = 1.0
    for i in range(7):
        jl[:, 3 + i] = np.cross(axes[i], p - origins[i])
        jw[:, 3 + i] = axes[i]
    yaw, pitch = math.atan2(r[1, 0], r[0, 0]), math.asin(max(-1.0, min(1.0, -r[2, 0])))
    cy, sy, cp, tp = math.cos(yaw), math.sin(yaw), math.cos(pitch), math.tan(pitch)
    # ω = E(yaw, pitch) (ẏaw, ṗitch, ṙoll) inverted for ZYX angles
    e_inv = np.array([[cy * tp, sy * tp, 1.0], [-sy, cy, 0.0], [cy / cp, sy / cp, 0.0]])
    j = np.vstack([jl, e_inv @ jw])
    s_mat = np.zeros((10, 9))
    s_mat[0, 0], s_mat[1, 0], s_mat[2, 1] = c, s, 1.0
    s_mat[3:, 2:] = np.eye(7)
    return j @ s_mat


def numpy_baseline(q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    jbars, out = [], []
    for qi in q:
        jb = _numpy_jbar(qi)
        sv = np.linalg.svd(jb, compute_uv=False)
        out.append((np.prod(sv), sv[-1] / sv[0], math.sqrt(1.0 - (sv[-1] / sv[0]) ** 2)))
        jbars.append(jb)
    return np.array(jbars), np.array(out)


# --- timed variants ----------------------------------------------------------------------------------


def batched(robot, q):
    jbar = mp.system_jacobian(robot, q)
    return jbar, mp.measures(jbar)


def single(robot, q):
    out = None
    for qi in q:
        out = mp.jacobian_and_measures(robot, qi)
    return out


def single_two_calls(robot, q):
    out = None
    for qi in q:
        jbar = mp.system_jacobian(robot, qi)
        out = (jbar, mp.measures(jbar))
    return out


def _straightforward_task(q: jnp.ndarray) -> jnp.ndarray:
    """ξ = (p, yaw, pitch, roll) of the Panda's flange: a product of 4 × 4 homogeneous transforms."""
    t = _planar(q[0], q[1], jnp.cos(q[2]), jnp.sin(q[2]), jnp)
    for i in range(7):
        t = t @ _mdh(i, jnp.cos(q[3 + i]), jnp.sin(q[3 + i]), jnp)
    r, p = t[:3, :3], t[:3, 3] + 0.107 * t[:3, 2]
    angles = jnp.stack([jnp.arctan2(r[1, 0], r[0, 0]), jnp.arcsin(-r[2, 0]), jnp.arctan2(r[2, 1], r[2, 2])])
    return jnp.concatenate([p, angles])


def _with_svd_measures(jbar: jnp.ndarray):
    """(J̄, (w, w2, w5)) from ``jnp.linalg.svd``."""
    sv = jnp.linalg.svd(jbar, compute_uv=False)
    ratio = sv[-1] / sv[0]
    return jbar, (jnp.prod(sv), ratio, jnp.sqrt(1.0 - ratio**2))


@jax.jit
def straightforward(q):
    """The reference point a user would write first: J = ``jacfwd`` of a 4 × 4 transform chain, J̄ = J S,
    singular values by ``jnp.linalg.svd``, one jit + vmap over the batch."""

    def one(qi):
        c, s = jnp.cos(qi[2]), jnp.sin(qi[2])
        s_platform = jnp.array([[c, 0.0], [s, 0.0], [0.0, 1.0]])
        s_matrix = jax.scipy.linalg.block_diag(s_platform, jnp.eye(7))
        return _with_svd_measures(jax.jacfwd(_straightforward_task)(qi) @ s_matrix)

    return jax.vmap(one)(q)


@functools.partial(jax.jit, static_argnums=0)
def svd_of_system_jacobian(robot, q):
    """One jit + vmap of mobman's J̄ and ``jnp.linalg.svd``: what the measures cost by LAPACK's SVD."""

    def one(qi):
        return _with_svd_measures(mp.system_jacobian(robot, qi))

    return jax.vmap(one)(q)


def pinocchio_arm_jacobian(robot: MobileManipulator, q: np.ndarray) -> tuple[float, float] | None:
    """Pinocchio's arm Jacobian called from Python (``computeFrameJacobian``, world-aligned), the other
    reference point, for the same Panda chain (each joint's fixed origin then its
    revolute axis, the tool as a frame): (seconds a call, max |position rows − mobman's J̄ arm columns| at
    the platform's origin). None when Pinocchio (a ``test`` extra) is not installed."""
    try:
        import pinocchio as pin
    except ImportError:
        return None
    arm = robot.arms[0]
    model = pin.Model()
    parent = 0
    for joint in arm.joints:
        origin = pin.SE3(np.reshape(joint.origin, (4, 4)))
        parent = model.addJoint(
            parent, pin.JointModelRevoluteUnaligned(np.array(joint.axis)), origin, joint.name
        )
    tool = pin.SE3(np.reshape(arm.tool, (4, 4)))
    frame = model.addFrame(pin.Frame("tool", parent, 0, tool, pin.FrameType.OP_FRAME))
    data = model.createData()
    arm_q = [np.ascontiguousarray(qi[3:]) for qi in q]
    aligned = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED

    def calls():
        for qi in arm_q:
            pin.computeFrameJacobian(model, data, qi, frame, aligned)

    seconds = best_time(calls, 3) / len(arm_q)
    j_pin = pin.computeFrameJacobian(model, data, arm_q[0], frame, aligned)
    at_origin = np.concatenate([np.zeros(3), arm_q[0]])  # platform frame = world frame (no mount offset)
    j_ours = np.asarray(mp.system_jacobian(robot, at_origin))[:3, 2:]
    return seconds, float(np.max(np.abs(j_pin[:3] - j_ours)))


def compiler_report(robot: MobileManipulator, q: np.ndarray, seconds_per_config: float) -> None:
    """Print the roofline of the batched kernel and the structure of the compiled programs."""
    block = jnp.asarray(q[: batching.BLOCK])
    kernel = jax.vmap(lambda qi: batched(robot, qi))  # one block of the batched J̄ + measures
    print_peak()
    print(roofline("batched J̄ + w, w2, w5", xla_cost(kernel, block).per(batching.BLOCK), seconds_per_config))
    one = jnp.asarray(q[0])
    structures = [
        ("one configuration (jacobian_and_measures)", lambda qi: mp.jacobian_and_measures(robot, qi), one),
        (f"one block of {batching.BLOCK} (system_jacobian + measures)", kernel, block),
        ("∇ of Σ J (reverse mode)", jax.grad(lambda qi: jnp.sum(mp.system_jacobian(robot, qi))), one),
    ]
    for label, fn, arg in structures:
        print(describe_structure(label, program_structure(fn, arg)))


BATCHED_REPEAT = 7
"""Timed repetitions of the batched rows (their best is printed): each takes a tenth of a second, and on a
shared machine the first calls after compiling are often the slowest."""


@contextlib.contextmanager
def one_worker():
    """Large batches on one thread, as before ``batching.across_cores`` shared them between the cores."""
    workers, batching.WORKERS = batching.WORKERS, 1
    try:
        yield
    finally:
        batching.WORKERS = workers


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=100_000, help="configurations in the batched run")
    parser.add_argument("--single", type=int, default=2_000, help="configurations in the one-at-a-time run")
    parser.add_argument("--baseline", type=int, default=300, help="configurations in the NumPy baseline")
    parser.add_argument("--smoke", action="store_true", help="tiny sizes for CI")
    args = parser.parse_args(argv)
    if args.smoke:
        args.n, args.single, args.baseline = 1_000, 50, 20
    robot = panda_on_differential_base()
    q = random_configurations(robot, args.n)
    q_device = jax.device_put(q)  # batched throughput is timed on inputs already in the device's memory

    t0 = time.perf_counter()
    jbar, meas = jax.block_until_ready(batched(robot, q_device))
    first = time.perf_counter() - t0
    t_batch = best_time(lambda: batched(robot, q_device), BATCHED_REPEAT)
    with one_worker():
        batched(robot, q_device)
        t_one_core = best_time(lambda: batched(robot, q_device), BATCHED_REPEAT)
    jbar_plain, _ = straightforward(q_device)
    t_reference = best_time(lambda: straightforward(q_device), 3)
    svd_of_system_jacobian(robot, q_device)
    t_svd = best_time(lambda: svd_of_system_jacobian(robot, q_device), 3)
    single(robot, q[:2])
    t_single = best_time(lambda: single(robot, q[: args.single]), 3)
    single_two_calls(robot, q[:2])
    t_two_calls = best_time(lambda: single_two_calls(robot, q[: args.single]), 3)
    pinocchio = pinocchio_arm_jacobian(robot, q[: args.single])
    nb = min(args.baseline, args.n)
    t0 = time.perf_counter()
    jbar_np, meas_np = numpy_baseline(q[:nb])
    t_numpy = time.perf_counter() - t0

    err_j = float(np.max(np.abs(np.asarray(jbar[:nb]) - jbar_np)))
    ours = np.stack([np.asarray(meas[k][:nb]) for k in mp.MEASURES], axis=-1)
    err_m = float(np.max(np.abs(ours - meas_np)))
    rows = [
        (f"batched public API (system_jacobian + measures), {batching.WORKERS} threads", args.n, t_batch),
        ("the same on one thread (batching.WORKERS = 1)", args.n, t_one_core),
        ("reference: straightforward jit + vmap (jacfwd, svd)", args.n, t_reference),
        ("jit + vmap of mobman's J̄ with jnp.linalg.svd", args.n, t_svd),
        ("single configuration, one call (jacobian_and_measures)", args.single, t_single),
        ("single configuration, system_jacobian then measures", args.single, t_two_calls),
        ("NumPy per call (J̄ + np.linalg.svd)", nb, t_numpy),
    ]
    if pinocchio is not None:
        label = "reference: Pinocchio, arm Jacobian alone, per call"
        rows.append((label, args.single, pinocchio[0] * args.single))
    print(
        f"Panda on a differential base, J̄ 6 × 9 (position + ZYX Euler rows) + w, w2, w5; device: "
        f"{jax.devices()[0].platform}; first batched call (compile) {first:.1f} s"
    )
    print(f"{'variant':60s} {'configs':>9s} {'µs/config':>11s} {'configs/s':>12s}")
    for name, n, t in rows:
        print(f"{name:60s} {n:9d} {1e6 * t / n:11.3f} {n / t:12.3e}")
    print(f"max |J̄ − NumPy| = {err_j:.1e}, max |measures − NumPy SVD| = {err_m:.1e}")
    err_plain = float(np.max(np.abs(np.asarray(jbar_plain) - np.asarray(jbar))))
    pin_note = f"max |J_Pinocchio − J̄ arm columns| = {pinocchio[1]:.1e}" if pinocchio else "no Pinocchio row"
    print(f"max |J̄ − straightforward J̄| = {err_plain:.1e}, {pin_note}")
    # the position rows are well conditioned everywhere (the Euler-angle rows not near pitch = ±π/2)
    err_position = float(np.max(np.abs(np.asarray(jbar_plain)[:, :3] - np.asarray(jbar)[:, :3])))
    disagreeing = [
        name
        for name, err in (
            ("NumPy J̄", err_j),
            ("NumPy SVD measures", err_m),
            ("straightforward J̄ position rows", err_position),
            ("Pinocchio", pinocchio[1] if pinocchio else 0.0),
        )
        if not err <= AGREEMENT
    ]
    if disagreeing:
        raise SystemExit(
            f"mobman disagrees with the reference(s) beyond {AGREEMENT:g}: {', '.join(disagreeing)}"
        )
    print(
        f"batched public API {t_reference / t_batch:.1f}× faster than the straightforward jit + vmap, "
        f"{t_svd / t_batch:.1f}× faster than mobman's J̄ with jnp.linalg.svd"
    )
    compiler_report(robot, q, t_batch / args.n)


if __name__ == "__main__":
    main()
