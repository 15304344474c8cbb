"""Benchmark: TIAGo's whole-body QP law (``laws.WholeBodyQP``, docs/examples/tiago_limits.toml) against
Pinocchio and quadprog solving the same program per evaluation, and against Bayle's law on the same run.

    python benchmarks/whole_body_qp.py            # 64 configurations per call; the spec's run; 64 runs at once
    python benchmarks/whole_body_qp.py --smoke    # tiny sizes (CI)

The program (docs/control.md): min ½‖J̄η − u‖² + ½μ‖η‖² within TIAGo's velocity limits, its wheels' speed
limits and the joints' velocity dampers, J̄ (6 × 10) the pose rows of ``arm_tool_link`` (linear and angular
velocity). mobman's law builds J̄ and solves it with qpax's interior-point method in JAX, 20 iterations. The
reference per evaluation is what a Python controller would write with the peers: Pinocchio's
``computeFrameJacobian`` (world-aligned, planar root joint, the columns of S) and quadprog's active-set solver
of the same program, built in NumPy. Both are evaluated at the configurations of the spec's run with ξ* = ξ and
a random ξ̇*, so u = ξ̇*; their η agree (printed; the run exits with an error above ``AGREEMENT``).

Rows: a law evaluation per call (jit, one configuration: the latency a controller sees), an evaluation within
the spec's compiled simulation (the run's time over its law evaluations, four per step), a step of the same
simulation with the ``hold`` integrator (one evaluation a step, held over it: a digital controller's loop, as
the reference's per-step work), the same for a batch of runs from perturbed initial configurations in one
call, Bayle's law in the same simulation, and the reference. The ratios are the reference's time over
mobman's; no timing is asserted.
"""

from __future__ import annotations

import sys
from dataclasses import replace
from pathlib import Path

import jax
import numpy as np

import mobman  # noqa: F401  (float64)
from mobman.control import laws, simulate, spec
from mobman.control.laws.qp import bounds

from real_robots import pinocchio_model, pinocchio_q
from timing import best_time, law_options, one_per_call

SPEC = Path(__file__).resolve().parents[1] / "docs" / "examples" / "tiago_limits.toml"
AGREEMENT = 1e-6
"""Largest |η − η_reference| (m/s, rad/s) the benchmark accepts."""


def reference_eta(model, data, frame, q_pin, q, u, limits, gain, mu):
    """One evaluation with the peers: Pinocchio's J̄ (pose rows, S columns) and quadprog's solution."""
    import pinocchio as pin
    import quadprog

    jbar = pin.computeFrameJacobian(model, data, q_pin, frame, pin.ReferenceFrame.LOCAL_WORLD_ALIGNED)
    jbar = jbar[:, np.r_[0, 2, 3 : model.nv]]
    speed, wheels, lower, upper = limits
    high = np.minimum(speed, np.maximum(-speed, gain * (upper - q)))
    low = np.maximum(-speed, np.minimum(speed, gain * (lower - q)))
    n = jbar.shape[1]
    rows = np.vstack([-np.eye(n), np.eye(n), -wheels, wheels])
    ends = np.concatenate([-high, low, -np.ones(len(wheels)), -np.ones(len(wheels))])
    return quadprog.solve_qp(jbar.T @ jbar + mu * np.eye(n), jbar.T @ u, rows.T, ends, 0)[0]


def main(argv=None) -> int:
    args = law_options(__doc__.splitlines()[0], argv)
    parsed = spec.load(SPEC)
    robot, task = parsed.robot, parsed.task
    qp = replace(parsed.law, criterion=None)  # the reference's program has no self-motion
    bayle = laws.BaylePseudoInverse(W=qp.W)

    # the configurations of the spec's run, and a random ξ̇* at each
    run = replace(parsed, law=qp).simulate()
    steps = len(run.t) - 1
    pick = np.linspace(0, steps, args.configurations).astype(int)
    q = np.asarray(run.q[pick])
    rng = np.random.default_rng(0)
    xi_dot = rng.normal(size=(len(q), 6)) * 0.5
    xi = np.asarray(run.xi[pick])
    evaluate = jax.jit(lambda qq, xs, xsd: qp(robot, task, qq, 0.0, xs, xsd).eta)
    ours, t_call = one_per_call(evaluate, q, xi, xi_dot)

    model = pinocchio_model(robot)
    data = model.createData()
    frame = model.getFrameId("arm_tool_link")
    q_pin = pinocchio_q(q)
    b = bounds(robot)
    speed = b.scale  # TIAGo has velocity limits: the program's x = η / scale is bounded by ±1
    wheels = b.wheels / speed
    limits = (speed, wheels, b.lower, b.upper)
    q_eta = np.concatenate([np.zeros((len(q), robot.platform.n_eta)), q[:, robot.n_platform :]], axis=1)

    def reference():
        return np.stack(
            [
                reference_eta(
                    model, data, frame, qp_i, qe, u, limits, float(qp.limit_gain), float(qp.regularization)
                )
                for qp_i, qe, u in zip(q_pin, q_eta, xi_dot)
            ]
        )

    theirs = reference()
    t_ref = best_time(reference, 3) / len(q)
    agreement = float(np.max(np.abs(ours - theirs)))

    # within the compiled simulation: the run's time over its law evaluations (four a step)
    def simulation(law, q0, integrator="auto"):
        return lambda: (
            simulate(
                robot, task, law, parsed.reference, q0, parsed.duration, parsed.dt, integrator=integrator
            ).q
        )

    evaluations = 4 * steps
    simulation(qp, parsed.q0)()
    t_sim = best_time(simulation(qp, parsed.q0), 3) / evaluations
    # a digital controller's loop: one evaluation a step, held over it (zero-order hold), as the reference's
    simulation(qp, parsed.q0, "hold")()
    t_hold = best_time(simulation(qp, parsed.q0, "hold"), 3) / steps
    q0s = parsed.q0 + rng.normal(size=(args.batch, robot.n_q)) * 0.01
    simulation(qp, q0s)()
    t_batch = best_time(simulation(qp, q0s), 3) / (evaluations * args.batch)
    simulation(bayle, parsed.q0)()
    t_bayle = best_time(simulation(bayle, parsed.q0), 3) / evaluations

    print(f"TIAGo, pose task (6 × 10), the QP law on {SPEC.name}; device {jax.devices()[0].platform}")
    print(f"{'variant':62s} {'µs/evaluation':>14s} {'reference / mobman':>19s}")
    rows = [
        ("QP law, one configuration per call (mobman)", t_call),
        (f"QP law within the compiled simulation, {steps} steps (mobman)", t_sim),
        ("  the same with the hold integrator: one evaluation a step", t_hold),
        (f"  {args.batch} runs in one call", t_batch),
        ("Bayle's law within the same simulation (mobman)", t_bayle),
        ("reference: Pinocchio computeFrameJacobian + quadprog, per call", t_ref),
    ]
    for name, t in rows:
        print(f"{name:62s} {1e6 * t:14.1f} {t_ref / t:19.2f}")
    print(f"max |η − reference| = {agreement:.1e} over {len(q)} configurations")
    if not agreement <= AGREEMENT:
        print("error: mobman and the reference disagree", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
