"""Benchmark: closed-loop simulation of the Bayle law (eq. 5–6) with the w5 gradient on ``bayle_planar``,
compiled (one ``lax.scan``) against a straightforward per-step NumPy loop of the same law, and a batch of
simulations over initial configurations in one call.

    python benchmarks/control.py            # 20,000 steps; 1,000 simulations × 1,000 steps
    python benchmarks/control.py --smoke    # tiny sizes (CI)

Law: η = J̄⁺(ξ̇* + W e) − k Hᵀ∇P, H = S (I − J̄⁺J̄), P = w5 of J̄ (task: EE position (x, y); W = 1, k = 0.5),
elliptic reference, classical RK4 (four law evaluations per step) in both implementations. The NumPy
baseline writes J̄ in closed form, uses ``np.linalg.pinv`` and a central finite-difference gradient of w5
(``np.linalg.svd``), as Bayle suggests ("compute their numerical gradient"). Both give the same η: the
agreement is printed. Timings are the best of a few repetitions after compilation; one step = one sample.

The run ends with the roofline of the batched simulation (XLA's flop count of four law evaluations, a lower
bound of an RK4 step's, against the CPU's peak) and the structure of the compiled law and of the 2 × 2
eigenvalues of a planar task's Gram matrix (closed form: no LAPACK call, no product kernel).
"""

from __future__ import annotations

import argparse
import math
import time

import jax
import jax.numpy as jnp
import numpy as np

import mobman  # noqa: F401  (float64)
from mobman.control import criteria, laws, references, simulate, simulation
from mobman.engine import linalg
from mobman.model import robots
from mobman.model.tasks import Position

from timing import best_time, describe_structure, print_peak, program_structure, roofline, xla_cost

L1 = L2 = 0.5
W, K = 1.0, 0.5
DT = 0.01
Q0 = np.array([0.0, 0.0, 0.0, -math.pi / 4, math.pi / 2])
ELLIPSE = {"center": (1.5, 0.5), "semi_axes": (1.0, 0.6), "period": 30.0, "phase": -math.pi / 2}


# --- NumPy per-step baseline -------------------------------------------------------------------------


def _np_reference(t: float) -> tuple[np.ndarray, np.ndarray]:
    (cx, cy), (a, b) = ELLIPSE["center"], ELLIPSE["semi_axes"]
    rate = 2.0 * math.pi / ELLIPSE["period"]
    phi = ELLIPSE["phase"] + rate * t
    return (
        np.array([cx + a * math.cos(phi), cy + b * math.sin(phi)]),
        np.array([-a * rate * math.sin(phi), b * rate * math.cos(phi)]),
    )


def _np_kinematics(q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """ξ = (x_E, y_E) and J̄ = J S (2 × 4) of the platform + 2R arm mounted at the axle midpoint."""
    x, y, th, q4, q5 = q
    elbow = np.array([L1 * math.cos(th + q4), L1 * math.sin(th + q4)])
    tip = elbow + np.array([L2 * math.cos(th + q4 + q5), L2 * math.sin(th + q4 + q5)])
    jbar = np.array(
        [
            [math.cos(th), -tip[1], -tip[1], -(tip[1] - elbow[1])],
            [math.sin(th), tip[0], tip[0], tip[0] - elbow[0]],
        ]
    )
    return np.array([x, y]) + tip, jbar


def _np_s(q: np.ndarray) -> np.ndarray:
    s = np.zeros((5, 4))
    s[0, 0], s[1, 0], s[2, 1], s[3, 2], s[4, 3] = math.cos(q[2]), math.sin(q[2]), 1.0, 1.0, 1.0
    return s


def _np_w5(q: np.ndarray) -> float:
    sv = np.linalg.svd(_np_kinematics(q)[1], compute_uv=False)
    return math.sqrt(max(0.0, 1.0 - (sv[-1] / sv[0]) ** 2))


def numpy_law(q: np.ndarray, t: float) -> np.ndarray:
    xs, xsd = _np_reference(t)
    xi, jbar = _np_kinematics(q)
    pinv = np.linalg.pinv(jbar)
    h = 1e-6
    grad = np.array([(_np_w5(q + h * e) - _np_w5(q - h * e)) / (2 * h) for e in np.eye(5)])
    big_h = _np_s(q) @ (np.eye(4) - pinv @ jbar)
    return pinv @ (xsd + W * (xs - xi)) - K * big_h.T @ grad


def numpy_simulation(n: int) -> np.ndarray:
    """n samples with classical RK4 on q̇ = S(q) η (the per-step loop a user would write first)."""
    q, out = Q0.copy(), np.empty((n, 5))
    for i in range(n):
        t = i * DT
        out[i] = q
        k1 = _np_s(q) @ numpy_law(q, t)
        y = q + 0.5 * DT * k1
        k2 = _np_s(y) @ numpy_law(y, t + 0.5 * DT)
        y = q + 0.5 * DT * k2
        k3 = _np_s(y) @ numpy_law(y, t + 0.5 * DT)
        y = q + DT * k3
        k4 = _np_s(y) @ numpy_law(y, t + DT)
        q = q + DT * (k1 + 2 * k2 + 2 * k3 + k4) / 6
    return out


# --- mobman ------------------------------------------------------------------------------------------


def setup():
    robot = robots.bayle_planar(l1=L1, l2=L2)
    law = laws.BaylePseudoInverse(W=W, k=K, criterion=criteria.Manipulability("eccentricity", "system"))
    return robot, Position("xy"), law, references.Ellipse(**ELLIPSE)


def run(robot, task, law, ref, q0, n: int, integrator: str = "rk4"):
    return simulate(robot, task, law, ref, q0, (n - 1) * DT, DT, integrator=integrator)


def compiler_report(robot, task, law, ref, q0s: np.ndarray, seconds_per_step: float) -> None:
    """Print the roofline of the batched simulation and the structure of the compiled law."""

    def evaluate(q):
        xs, xsd = ref(0.0)
        return law(robot, task, q, 0.0, xs, xsd).eta

    block = jnp.asarray(q0s[:128])
    cost = xla_cost(jax.vmap(evaluate), block).scaled(4 / block.shape[0])  # RK4: four law evaluations a step
    print_peak()
    print(roofline("batched RK4 step (4 law evaluations)", cost, seconds_per_step))
    print(describe_structure("law with ∇w5, one configuration", program_structure(evaluate, jnp.asarray(Q0))))
    gram = jnp.array([[2.0, 0.3], [0.3, 1.0]])
    eig = jax.value_and_grad(lambda a: linalg.eigvalsh(a)[1])
    print(describe_structure("2 × 2 eigenvalues and gradient", program_structure(eig, gram)))


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=20_000, help="steps of the single compiled simulation")
    parser.add_argument("--baseline", type=int, default=300, help="steps of the NumPy loop")
    parser.add_argument("--batch", type=int, default=1_000, help="simulations in the batched call")
    parser.add_argument("--batch-steps", type=int, default=1_000, help="steps of each batched simulation")
    parser.add_argument("--smoke", action="store_true", help="tiny sizes for CI")
    args = parser.parse_args(argv)
    if args.smoke:
        args.steps, args.baseline, args.batch, args.batch_steps = 500, 20, 16, 100
    robot, task, law, ref = setup()

    t0 = time.perf_counter()
    res = run(robot, task, law, ref, Q0, args.steps)
    first = time.perf_counter() - t0
    t_single = best_time(lambda: run(robot, task, law, ref, Q0, args.steps).q, 3)
    # the cost of computing a run in calls of SCAN_SAMPLES steps (Ctrl-C answered between them): one call
    scan, simulation.SCAN_SAMPLES = simulation.SCAN_SAMPLES, args.steps
    run(robot, task, law, ref, Q0, args.steps)
    t_one_call = best_time(lambda: run(robot, task, law, ref, Q0, args.steps).q, 3)
    simulation.SCAN_SAMPLES = scan
    # a digital controller: η held over each step, exact arcs of the platform (one law evaluation a step)
    run(robot, task, law, ref, Q0, args.steps, "hold")
    t_hold = best_time(lambda: run(robot, task, law, ref, Q0, args.steps, "hold").q, 3)

    rng = np.random.default_rng(0)
    q0s = Q0 + rng.uniform(-0.3, 0.3, size=(args.batch, 5))
    batch = run(robot, task, law, ref, q0s, args.batch_steps)
    t_batch = best_time(lambda: run(robot, task, law, ref, q0s, args.batch_steps).q, 2)
    if not np.all(np.isfinite(batch.q)):
        raise SystemExit("batched simulation produced non-finite values")

    nb = min(args.baseline, args.steps)
    t0 = time.perf_counter()
    q_np = numpy_simulation(nb)
    t_numpy = time.perf_counter() - t0
    # same law: η of the NumPy code at mobman's samples, and the two trajectories over the baseline's steps
    eta_np = np.array([numpy_law(q, t) for q, t in zip(res.q[:nb], res.t[:nb])])
    err_eta = float(np.max(np.abs(eta_np - res.eta[:nb])))
    err_q = float(np.max(np.abs(q_np - res.q[:nb])))

    rows = [
        (f"compiled simulate, RK4 (calls of {simulation.SCAN_SAMPLES} steps)", args.steps, t_single),
        ("compiled simulate, RK4, one call (Ctrl-C at its end)", args.steps, t_one_call),
        ("compiled simulate, zero-order hold (1 law call/step)", args.steps, t_hold),
        (f"batched simulate, {args.batch} initial configurations", args.batch * args.batch_steps, t_batch),
        ("NumPy per-step loop (pinv, FD gradient)", nb, t_numpy),
    ]
    print(
        f"Bayle law + w5 gradient on bayle_planar, RK4 dt = {DT} s; device: {jax.devices()[0].platform}; "
        f"first call (compile) {first:.1f} s"
    )
    print(f"{'variant':52s} {'steps':>10s} {'µs/step':>10s} {'steps/s':>12s}")
    for name, n, t in rows:
        print(f"{name:52s} {n:10d} {1e6 * t / n:10.3f} {n / t:12.3e}")
    speedup = (args.steps / t_single) / (nb / t_numpy)
    print(
        f"compiled / NumPy loop: {speedup:.0f}×; batched / NumPy loop: "
        f"{(args.batch * args.batch_steps / t_batch) / (nb / t_numpy):.0f}×"
    )
    print(f"calls of {simulation.SCAN_SAMPLES} steps / one call: {t_single / t_one_call:.2f}× the time")
    print(f"max |η − η_NumPy| = {err_eta:.1e} (FD gradient), max |q − q_NumPy| over {nb} steps = {err_q:.1e}")
    compiler_report(robot, task, law, ref, q0s, t_batch / (args.batch * args.batch_steps))


if __name__ == "__main__":
    main()
