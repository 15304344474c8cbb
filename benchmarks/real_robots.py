"""Benchmark: PAL TIAGo read from its URDF (example-robot-data): J̄ (6 × 10) with w, w2, w5, and the reduced
dynamics Sᵀ M S, bias and B (``reduced_terms``), batched and one configuration per call, against Pinocchio.

    python benchmarks/real_robots.py            # 100,000 configurations (kinematics), 10,000 (dynamics)
    python benchmarks/real_robots.py --smoke    # tiny sizes (CI)

mobman's J̄ rows are the tool position and its ZYX Euler angles (``Position`` + ``EulerAngles("ZYX")``), J̄
and its measures computed by ``jacobian_and_measures`` (one compiled call; a row times ``system_jacobian``
then ``measures``, which writes J̄ out and reads it back);
Pinocchio's reference per configuration is ``computeFrameJacobian`` (world-aligned, 6 × 11 with a planar
root joint), the selection of the v_x, ω_z and chain columns (S), and NumPy's SVD for w, w2, w5. The dynamics
reference per configuration is Pinocchio's ``crba`` + ``rnea`` (mass matrix and bias) on the same root joint,
every joint off the chain locked (``buildReducedModel``), as in ``tests/test_urdf_pinocchio.py``.

A one-configuration call is timed with each result waited for before the next call (the latency a controller
sees, as Pinocchio's synchronous calls; mobman runs CPU programs on the calling thread, :mod:`mobman`). Two
diagnostic rows show the cost of XLA's CPU scheduling: the compiled J̄ + measures program, whose arrays are
all at most 512 bytes, and the same program with one 800-byte output added. The structure printed is that
of the programs a one-configuration call runs (``mobman.engine.batched.sequential``: the function in a
conditional's branch, which returns its results in blocks of at most 512 bytes), and a row times the
dynamics' function compiled plainly, which XLA schedules over its thread pool. Two more rows time a compiled
call with the same arguments and results as each one-configuration program but no kernels of its own
(:func:`results_only`): what remains of the call's time above it is its kernels' and the Python work before it
(validation). The rooflines printed
are XLA's count of the flops and the bytes moved per configuration of one block of each batched program. The run
prints the ratios (Pinocchio's time per configuration over mobman's) and never asserts a timing; it exits with
an error when mobman and Pinocchio disagree by more than ``AGREEMENT`` (position rows of J̄, and Sᵀ M S with
the wheels' spin inertia added to Pinocchio's).
"""

from __future__ import annotations

import argparse
import os
import sys
from functools import partial

import jax
import jax.numpy as jnp
import numpy as np

import mobman  # noqa: F401  (float64)
from mobman import dynamics as dyn
from mobman import manipulability as mp
from mobman.dynamics.reduced import reduced_terms, reduced_terms_one
from mobman.engine.batched import BLOCK, sequential
from mobman.io.real_robots import REAL_ROBOTS, urdf_model
from mobman.model.tasks import EulerAngles, Position, stack
from mobman.redundancy import sample_configurations

from timing import best_time, describe_structure, print_peak, program_structure, roofline, xla_cost

REPEAT = 7
"""Timed repetitions of each row (its best is printed): a shared machine's times vary from call to call."""

AGREEMENT = 1e-9
"""Largest relative difference from Pinocchio the benchmark accepts (it exits with an error above)."""


def pinocchio_model(robot):
    """Pinocchio's TIAGo: planar root joint, every joint off mobman's chain locked at 0."""
    import pinocchio as pin

    full = pin.buildModelFromUrdf(str(REAL_ROBOTS["tiago"].path()), pin.JointModelPlanar())
    keep = {j.name for arm in robot.arms for j in arm.joints}
    locked = [i for i in range(2, full.njoints) if full.names[i] not in keep]
    return pin.buildReducedModel(full, locked, pin.neutral(full))


def pinocchio_q(q: np.ndarray) -> np.ndarray:
    """(x, y, θ, q_a) → Pinocchio's (x, y, cos θ, sin θ, q_a) (the chain joints keep mobman's order)."""
    return np.concatenate([q[:, :2], np.cos(q[:, 2:3]), np.sin(q[:, 2:3]), q[:, 3:]], axis=1)


def pinocchio_kinematics(model, q_pin: np.ndarray):
    """Per configuration: frame Jacobian, the S columns, NumPy's SVD and w, w2, w5. Returns the last J̄."""
    import pinocchio as pin

    data = model.createData()
    frame = model.getFrameId("arm_tool_link")
    columns = np.r_[0, 2, 3 : model.nv]
    aligned = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
    jbar = None
    for qi in q_pin:
        jbar = pin.computeFrameJacobian(model, data, qi, frame, aligned)[:, columns]
        sv = np.linalg.svd(jbar, compute_uv=False)
        ratio = sv[-1] / sv[0]
        _ = (np.prod(sv), ratio, np.sqrt(1.0 - ratio**2))
    return jbar


def pinocchio_dynamics(model, q_pin: np.ndarray, v_pin: np.ndarray):
    """Per configuration: ``crba`` (M) and ``rnea`` at zero acceleration (the bias c + g). Returns the last M."""
    import pinocchio as pin

    data = model.createData()
    zero = np.zeros(model.nv)
    m = None
    for qi, vi in zip(q_pin, v_pin):
        m = pin.crba(model, data, qi)
        pin.rnea(model, data, qi, vi, zero)
    return np.triu(m) + np.triu(m, 1).T


def results_only(fn, arrays: tuple[int, ...]):
    """A compiled one-configuration program with ``fn``'s arguments and results (shapes, dtypes, the same
    ``sequential`` form) whose results are one value filled in: the fixed cost of such a call, without the
    kernels of ``fn``."""

    def filled(*args):
        value = sum(args[i][0] for i in arrays)
        return jax.tree.map(lambda r: jnp.full(r.shape, value, r.dtype), jax.eval_shape(fn, *args))

    return jax.jit(sequential(filled, arrays))


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=100_000, help="configurations, batched kinematics")
    parser.add_argument("--n-dynamics", type=int, default=10_000, help="configurations, batched dynamics")
    parser.add_argument("--single", type=int, default=1_000, help="configurations timed one per call")
    parser.add_argument("--smoke", action="store_true", help="tiny sizes for CI")
    args = parser.parse_args(argv)
    if args.smoke:
        args.n, args.n_dynamics, args.single = 1_000, 200, 30
    if max(args.n_dynamics, args.single) > args.n:  # both are drawn from the --n configurations
        parser.error(f"--n-dynamics and --single must be at most --n ({args.n})")
    urdf = urdf_model("tiago")
    robot = urdf.robot.with_task(stack(Position("xyz"), EulerAngles("ZYX")))
    model = dyn.DynamicModel.from_urdf(urdf)
    pin_model = pinocchio_model(robot)
    q = sample_configurations(robot, args.n, seed=0)
    eta = np.random.default_rng(1).normal(size=(args.n, robot.n_eta))
    q_device = jax.device_put(q)
    q_pin = pinocchio_q(q[: args.single])
    v_pin = np.zeros((args.single, pin_model.nv))
    v_pin[:, 0], v_pin[:, 2], v_pin[:, 3:] = (
        eta[: args.single, 0],
        eta[: args.single, 1],
        eta[: args.single, 2:],
    )

    def batched():
        return mp.jacobian_and_measures(robot, q_device)

    def batched_two_calls():
        jbar = mp.system_jacobian(robot, q_device)
        return jbar, mp.measures(jbar)

    def per_call(fn) -> float:
        """Seconds per call of ``fn(i)`` for configuration i, one configuration (NumPy arrays) per call, each
        result waited for before the next call."""

        def run():
            out = None
            for i in range(args.single):
                out = jax.block_until_ready(fn(i))
            return out

        return best_time(run, REPEAT) / args.single

    jbar, _ = jax.block_until_ready(batched())
    t_batch = best_time(batched, REPEAT) / args.n
    jax.block_until_ready(batched_two_calls())
    t_batch_two = best_time(batched_two_calls, REPEAT) / args.n
    t_single = per_call(lambda i: mp.jacobian_and_measures(robot, q[i]))
    t_pin = best_time(lambda: pinocchio_kinematics(pin_model, q_pin), REPEAT) / args.single
    # the fixed cost of any compiled call with a NumPy argument: the floor of a one-configuration call
    identity = jax.jit(lambda x: x)
    t_floor = per_call(lambda i: identity(q[i]))
    # J̄ + measures' compiled program alone (every array at most 512 bytes: its kernels run one after the
    # other), and with one 800-byte output added, which makes XLA's CPU runtime schedule the same kernels
    # over its thread pool (mobman.engine.batched's notes)
    options = mp._prepare(robot, "system", None, None)

    def kinematics_one(x):
        return mp.jacobian_and_measures.one(robot, x, "system", *options)

    one_kinematics = jax.jit(kinematics_one)
    padded = jax.jit(lambda x: (one_kinematics(x), jnp.zeros(100, x.dtype) + x[0]))
    t_program = per_call(lambda i: one_kinematics(q[i]))
    t_padded = per_call(lambda i: padded(q[i]))
    kinematics_results = results_only(kinematics_one, (0,))
    t_results = per_call(lambda i: kinematics_results(q[i]))

    nd = args.n_dynamics
    q_dyn, eta_dyn = jax.device_put(q[:nd]), jax.device_put(eta[:nd])

    def dyn_batched():
        return reduced_terms(model, q_dyn, eta_dyn)

    p_ours, _, _ = jax.block_until_ready(dyn_batched())
    t_dyn_batch = best_time(dyn_batched, REPEAT) / nd
    t_dyn_single = per_call(lambda i: reduced_terms(model, q[i], eta[i]))
    # the same function compiled plainly: P and B (800 bytes) make XLA schedule it over its thread pool
    plain_dynamics = jax.jit(partial(reduced_terms_one, model))
    t_dyn_plain = per_call(lambda i: plain_dynamics(q[i], eta[i]))
    dynamics_results = results_only(partial(reduced_terms_one, model), (0, 1))
    t_dyn_results = per_call(lambda i: dynamics_results(q[i], eta[i]))
    t_dyn_pin = best_time(lambda: pinocchio_dynamics(pin_model, q_pin, v_pin), REPEAT) / args.single

    # agreement: position rows of the last configuration's J̄; Sᵀ M S with the wheels' spin inertia
    last = args.single - 1
    jbar_pin = pinocchio_kinematics(pin_model, q_pin[last:])
    err_j = float(np.max(np.abs(jbar_pin[:3] - np.asarray(jbar[last])[:3])))
    m_pin = pinocchio_dynamics(pin_model, q_pin[last:], v_pin[last:])
    select = np.zeros((pin_model.nv, robot.n_eta))
    select[0, 0] = select[2, 1] = 1.0
    select[3:, 2:] = np.eye(pin_model.nv - 3)
    p_pin = select.T @ m_pin @ select
    r, b, i_w = robot.platform.wheel_radius, robot.platform.half_track, model.wheel.I_w
    p_pin[0, 0] += 2 * i_w / r**2
    p_pin[1, 1] += 2 * i_w * b**2 / r**2
    err_p = float(np.max(np.abs(p_pin - np.asarray(p_ours[last])))) / float(np.abs(p_pin).max())

    print(
        f"TIAGo from its URDF, J̄ 6 × 10 + w, w2, w5; dynamics Sᵀ M S (10 × 10) + bias; device {jax.devices()[0].platform}"
    )
    if hasattr(os, "getloadavg"):  # the ratios vary much less than the times with what else runs
        print(f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores")
    print(f"{'variant':58s} {'µs/config':>10s} {'Pinocchio / mobman':>19s}")
    rows = [
        ("J̄ + measures, batched (mobman)", t_batch, t_pin / t_batch),
        ("  the same as two calls, system_jacobian then measures", t_batch_two, t_pin / t_batch_two),
        ("J̄ + measures, one configuration per call (mobman)", t_single, t_pin / t_single),
        ("Pinocchio computeFrameJacobian + columns + NumPy SVD", t_pin, 1.0),
        ("a compiled call of the identity (JAX's cost per call)", t_floor, t_pin / t_floor),
        ("J̄ + measures' compiled program alone, one configuration", t_program, t_pin / t_program),
        ("  the same with an 800-byte output added (thread pool)", t_padded, t_pin / t_padded),
        ("  its arguments and results alone (no kernels of its own)", t_results, t_pin / t_results),
        ("Sᵀ M S, bias and B, batched (mobman)", t_dyn_batch, t_dyn_pin / t_dyn_batch),
        ("Sᵀ M S, bias and B, one configuration per call (mobman)", t_dyn_single, t_dyn_pin / t_dyn_single),
        (
            "  its function compiled plainly (thread pool)",
            t_dyn_plain,
            t_dyn_pin / t_dyn_plain,
        ),
        (
            "  its arguments and results alone (no kernels of its own)",
            t_dyn_results,
            t_dyn_pin / t_dyn_results,
        ),
        ("Pinocchio crba + rnea", t_dyn_pin, 1.0),
    ]
    for name, t, ratio in rows:
        print(f"{name:58s} {1e6 * t:10.3f} {ratio:19.2f}")
    # what one block of the batched programs computes and moves per configuration (XLA's count)
    print_peak()
    block_q, block_eta = jax.device_put(q[:BLOCK]), jax.device_put(eta[:BLOCK])
    block_kinematics = jax.vmap(kinematics_one)
    block_dynamics = jax.vmap(partial(reduced_terms_one, model))
    print(roofline("J̄ + measures, batched", xla_cost(block_kinematics, block_q).per(BLOCK), t_batch))
    print(
        roofline(
            "Sᵀ M S, bias and B, batched",
            xla_cost(block_dynamics, block_q, block_eta).per(BLOCK),
            t_dyn_batch,
        )
    )
    # the programs a one-configuration call runs: the function in a conditional's branch (sequential)
    kinematics_program = sequential(kinematics_one, (0,))
    print(describe_structure("J̄ + measures, one configuration", program_structure(kinematics_program, q[0])))
    dynamics_program = sequential(partial(reduced_terms_one, model), (0, 1))
    print(describe_structure("P, b, B, one configuration", program_structure(dynamics_program, q[0], eta[0])))
    print(
        f"max |J̄ position rows − Pinocchio| = {err_j:.1e}, max |Sᵀ M S − Pinocchio| / max |M| = {err_p:.1e}"
    )
    if not (err_j <= AGREEMENT and err_p <= AGREEMENT):
        print("error: mobman and Pinocchio disagree", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
