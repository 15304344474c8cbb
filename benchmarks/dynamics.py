"""Benchmark: reduced dynamics of Yamamoto & Yun's dual-arm mobile manipulator (``yamamoto_model``) batched
over configurations, and the maximum allowable load along a 2 s trajectory sampled at 1 kHz.

    python benchmarks/dynamics.py            # 100,000 configurations, 2,001 trajectory samples
    python benchmarks/dynamics.py --n 1000000
    python benchmarks/dynamics.py --smoke    # tiny sizes (CI)

Rows: the reduced mass matrix P = Sᵀ M S (8 × 8), the reduced bias b = Sᵀ M Ṡ η + Sᵀ (c + g), both with
the input matrix at once (``reduced_terms``), one configuration at a time through the public API, and
``max_load`` (τ0, τ1 by the reduced inverse dynamics, DC-motor envelopes on the six joints, 200 N·m boxes
on the wheels, a point payload at arm 1's tool). Timings are the best of a few repetitions after
compilation; the load capacity's target is under 50 ms. The run ends with the roofline of the batched P and b
(XLA's flop count of one block of 128 configurations, against the CPU's peak).
"""

from __future__ import annotations

import argparse
import math
import time

import jax
import jax.numpy as jnp
import numpy as np

from mobman import dynamics as dyn
from mobman.dynamics import reduced
from mobman.dynamics.actuators import DCMotor, TorqueBox
from mobman.dynamics.load_capacity import eta_dot_from_samples, max_load

from timing import best_time, print_peak, roofline, xla_cost

LOAD_TARGET_S = 0.050


def random_states(model: dyn.DynamicModel, n: int, seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """n configurations (platform anywhere, joints in [−π, π]) and quasi-velocities within the limits."""
    rng = np.random.default_rng(seed)
    robot = model.robot
    q = rng.uniform(-math.pi, math.pi, size=(n, robot.n_q))
    q[:, :2] *= 5.0 / math.pi
    eta = rng.uniform(-1.0, 1.0, size=(n, robot.n_eta)) * np.asarray(robot.velocity_limits)
    return q, eta


def trajectory(model: dyn.DynamicModel, duration: float = 2.0, rate: float = 1000.0):
    """A smooth whole-body motion satisfying q̇ = S η: the platform drives and turns, every joint swings."""
    t = np.linspace(0.0, duration, int(round(duration * rate)) + 1)
    v = 0.4 * np.sin(math.pi * t / duration) ** 2
    theta = 0.3 * np.sin(math.pi * t / duration)
    omega = 0.3 * math.pi / duration * np.cos(math.pi * t / duration)
    dt = np.diff(t)
    vx, vy = v * np.cos(theta), v * np.sin(theta)  # trapezoidal integration of ẋ = v cos θ, ẏ = v sin θ
    x = np.concatenate([[0.0], np.cumsum(0.5 * dt * (vx[1:] + vx[:-1]))])
    y = np.concatenate([[0.0], np.cumsum(0.5 * dt * (vy[1:] + vy[:-1]))])
    n_a = model.robot.n_q - 3
    phase = np.linspace(0.0, math.pi, n_a)
    qa = 0.5 + 0.6 * np.sin(1.5 * t[:, None] + phase)
    qa_dot = 0.9 * np.cos(1.5 * t[:, None] + phase)
    q = np.column_stack([x, y, theta, qa])
    eta = np.column_stack([v, omega, qa_dot])
    return t, q, eta, eta_dot_from_samples(t, eta)


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=100_000, help="configurations in the batched runs")
    parser.add_argument("--single", type=int, default=200, help="configurations in the one-at-a-time run")
    parser.add_argument("--rate", type=float, default=1000.0, help="trajectory sampling rate (Hz)")
    parser.add_argument("--smoke", action="store_true", help="tiny sizes for CI")
    args = parser.parse_args(argv)
    if args.smoke:
        args.n, args.single = 1_000, 10
    model = dyn.yamamoto_model(payload=dyn.Payload(1.0, arm=0))
    q, eta = random_states(model, args.n)

    t0 = time.perf_counter()
    jax.block_until_ready(reduced.reduced_terms(model, q, eta))
    first = time.perf_counter() - t0
    jax.block_until_ready((dyn.reduced_mass_matrix(model, q), dyn.reduced_bias(model, q, eta)))
    rows = [
        ("reduced mass matrix P (batched)", args.n, best_time(lambda: dyn.reduced_mass_matrix(model, q), 3)),
        ("reduced bias b (batched)", args.n, best_time(lambda: dyn.reduced_bias(model, q, eta), 3)),
        (
            "P, b, B at once (reduced_terms, batched)",
            args.n,
            best_time(lambda: reduced.reduced_terms(model, q, eta), 3),
        ),
    ]

    def single():
        out = None
        for qi, ei in zip(q[: args.single], eta[: args.single]):
            out = (dyn.reduced_mass_matrix(model, qi), dyn.reduced_bias(model, qi, ei))
        return out

    jax.block_until_ready((dyn.reduced_mass_matrix(model, q[0]), dyn.reduced_bias(model, q[0], eta[0])))
    rows.append(("P and b, one configuration per call", args.single, best_time(single, 2)))
    # the reference: the same definition as one plain jit + vmap over the whole batch (no blocks, one core)
    plain = jax.jit(jax.vmap(lambda x: reduced.reduced_mass_matrix_one(model, x)))
    p_plain = jax.block_until_ready(plain(q))
    rows.append(("reference: P by one plain jit + vmap", args.n, best_time(lambda: plain(q), 3)))
    err_p = float(np.max(np.abs(np.asarray(p_plain) - np.asarray(dyn.reduced_mass_matrix(model, q)))))

    t, q_t, eta_t, eta_dot_t = trajectory(model, rate=args.rate)
    joints = DCMotor(63.22, 3.5)
    actuators = {
        name: (TorqueBox.symmetric(200.0) if name.startswith("wheel") else joints)
        for name in model.actuator_names
    }
    t0 = time.perf_counter()
    result = max_load(model, t, q_t, eta_t, eta_dot_t, actuators)
    first_load = time.perf_counter() - t0
    t_load = best_time(lambda: max_load(model, t, q_t, eta_t, eta_dot_t, actuators).max_load, 5)

    print(
        f"Yamamoto & Yun dual-arm robot (n_q = {model.robot.n_q}, n_eta = {model.robot.n_eta}); device: "
        f"{jax.devices()[0].platform}; first batched call (compile) {first:.1f} s"
    )
    print(f"{'variant':50s} {'configs':>9s} {'µs/config':>11s} {'configs/s':>12s}")
    for name, n, dt in rows:
        print(f"{name:50s} {n:9d} {1e6 * dt / n:11.3f} {n / dt:12.3e}")
    print(
        f"batched P {rows[-1][2] / rows[0][2]:.1f}× faster than the plain jit + vmap (max difference {err_p:.1e})"
    )
    block_q, block_eta = jnp.asarray(q[:128]), jnp.asarray(eta[:128])
    print_peak()
    for (name, n, dt), fn, args_ in (
        (rows[0], jax.vmap(lambda x: reduced.reduced_mass_matrix_one(model, x)), (block_q,)),
        (rows[1], jax.vmap(lambda x, e: reduced.reduced_bias_one(model, x, e)), (block_q, block_eta)),
    ):
        print(roofline(name, xla_cost(fn, *args_).per(block_q.shape[0]), dt / n))
    verdict = "meets" if t_load < LOAD_TARGET_S else "MISSES"
    print(
        f"load capacity, {len(t)} samples ({t[-1]:.0f} s at {args.rate:.0f} Hz): "
        f"{1e3 * t_load:.1f} ms after "
        f"compilation (first call {first_load:.1f} s), {verdict} the {1e3 * LOAD_TARGET_S:.0f} ms target; "
        f"max load {result.max_load:.3f} kg, limited by {result.limiting_actuator} "
        f"at t = {result.limiting_time:.3f} s"
    )


if __name__ == "__main__":
    main()
