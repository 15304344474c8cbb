"""Benchmark: endogenous-configuration motion planning (Tchoń et al. 2002 §4, car + RTR arm, z ∈ R^13).

    python benchmarks/planning.py             # P, Q, R one at a time + 1,000 random reachable targets
    python benchmarks/planning.py --n 5000
    python benchmarks/planning.py --smoke     # tiny sizes (CI)

1. Time to solve each of the paper's problems P, Q, R to ‖K − y_d‖ ≤ 1e-12 with the Jacobian pseudo-inverse
   (Newton's step Δθ = 1), one problem per call, after compilation (best of a few repetitions).
2. Throughput of batch planning (``plan_batch``: blocks of problems advanced one vectorised iteration at a
   time, the problems still running gathered into full blocks each round) for random reachable targets: each
   target is K(z*) for a random configuration z* (λ ~ N(0, σ²), x uniform) from a random start on the circle
   of radius 5, solved from the paper's initial configuration; the success rate is reported with it. The
   same problems solved one compiled call at a time are the peer: both throughputs and their ratio are
   printed (the batch's results are checked to be the single solves' iteration counts).
"""

from __future__ import annotations

import argparse
import math
import time

import jax
import numpy as np

import mobman  # noqa: F401  (float64)
from mobman.experiments import tchon2002
from mobman.planning.algorithms import solve, to_result
from mobman.planning.batch import plan_batch
from mobman.planning.endpoint import endpoint

from timing import best_time


def random_problems(setting, n: int, sigma: float, seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """Starts q0 (n, 4) on the circle of radius 5 and reachable targets y_d = K_{q0,T}(z*) (n, 3)."""
    rng = np.random.default_rng(seed)
    angle = rng.uniform(0.0, 2 * math.pi, n)
    q0 = np.stack(
        [
            5 * np.cos(angle),
            5 * np.sin(angle),
            rng.uniform(-math.pi, math.pi, n),
            rng.uniform(-math.pi / 4, math.pi / 4, n),
        ],
        axis=1,
    )
    z_star = np.concatenate(
        [
            rng.normal(scale=sigma, size=(n, 10)),
            rng.uniform([-math.pi, 0.0, -math.pi / 2], [math.pi, 2.0, math.pi / 2], (n, 3)),
        ],
        axis=1,
    )
    return q0, np.asarray(endpoint(setting, z_star, q0))


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=1_000, help="random reachable targets in the batch")
    parser.add_argument("--sigma", type=float, default=3.0, help="scale of the random control coefficients")
    parser.add_argument("--repeat", type=int, default=5, help="repetitions (best time is reported)")
    parser.add_argument("--cap", type=int, default=30, help="iteration cap (Newton converges in ≈ 10 or not)")
    parser.add_argument(
        "--sequential", type=int, default=1_000, help="problems also solved one call at a time (the peer)"
    )
    parser.add_argument("--smoke", action="store_true", help="tiny sizes for CI")
    args = parser.parse_args(argv)
    if args.smoke:
        args.n, args.repeat, args.sequential = 20, 2, 5
    setting = tchon2002.setting()
    options = tchon2002.options("pinv", 1.0, args.cap)
    z0 = tchon2002.initial_configuration()

    print(
        f"Tchoń et al. §4: car + RTR arm, z ∈ R^13, {setting.method.upper()} {setting.steps} steps "
        f"(Jacobian {setting.jacobian_steps}); pinv, Δθ = 1, tol 1e-12; device: {jax.devices()[0].platform}"
    )
    t0 = time.perf_counter()
    jax.block_until_ready(solve(setting, options, z0, tchon2002.start_pose("P"), tchon2002.TARGET))
    print(f"first call (compile) {time.perf_counter() - t0:.1f} s")
    print(f"{'problem':10s} {'iterations':>10s} {'final ‖e‖':>11s} {'ms/solve':>10s}")
    for name in tchon2002.STARTS:
        q0 = tchon2002.start_pose(name)
        result = to_result(setting, solve(setting, options, z0, q0, tchon2002.TARGET))
        t = best_time(lambda q=q0: solve(setting, options, z0, q, tchon2002.TARGET), args.repeat)
        print(
            f"{name:10s} {result.iterations:10d} {result.final_error:11.2e} {1e3 * t:10.2f}"
            f"{'' if result.converged else '  (' + result.status + ')'}"
        )

    q0, targets = random_problems(setting, args.n, args.sigma)
    t0 = time.perf_counter()
    batch = plan_batch(setting, z0, q0, targets, options)
    first = time.perf_counter() - t0
    t = best_time(lambda: plan_batch(setting, z0, q0, targets, options).z, max(1, args.repeat // 2))
    print(
        f"plan_batch, {args.n} random reachable targets (cap {args.cap}): first call {first:.1f} s, then "
        f"{t:.2f} s = {args.n / t:.1f} problems/s; success rate {batch.success_rate:.1%}, median iterations "
        f"{np.median(batch.iterations):.0f}, max {batch.iterations.max()}"
    )
    n = min(args.sequential, args.n)
    t0 = time.perf_counter()
    iterations = [int(solve(setting, options, z0, q0[i], targets[i]).iterations) for i in range(n)]
    single = time.perf_counter() - t0  # the peer: one compiled call per problem (the same problems)
    assert iterations == batch.iterations[:n].tolist(), "plan_batch differs from the single solves"
    print(f"solve one at a time, first {n} of them: {single:.2f} s = {n / single:.1f} problems/s")
    print(f"plan_batch / one at a time: {(args.n / t) / (n / single):.1f}x (problems/s)")


if __name__ == "__main__":
    main()
