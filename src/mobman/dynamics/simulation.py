"""Forward-dynamics simulation of the reduced equations: one compiled ``lax.scan`` with classical RK4.

The four RK4 stages run in a ``fori_loop`` over the Butcher tableau, so the dynamics are traced and compiled
once instead of four times (half the compile time, for a slightly slower step).

State (q, η) with q̇ = S(q) η and η̇ = P⁻¹ (B τ − b) (:mod:`mobman.dynamics.reduced`). Because q̇ is always
S(q) η the simulated platform satisfies the nonholonomic constraints exactly (it never slips); the only
error is the integration error of RK4, O(dt⁴).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import partial
from typing import Callable

import jax
import jax.numpy as jnp
import numpy as np
import numpy.typing as npt

from mobman.dynamics import reduced
from mobman.dynamics.inertia import DynamicModel
from mobman.errors import InputError

TorqueFn = Callable[[jnp.ndarray, jnp.ndarray, jnp.ndarray], jnp.ndarray]
"""τ = torque_fn(t, q, η) for one state (traced by JAX; must be hashable, e.g. a module-level function)."""


@dataclass(frozen=True)
class SimulationResult:
    """Samples at t = 0, dt, …, N dt: t (N+1,), q (N+1, n_q), eta (N+1, n_eta), tau (N+1, n_actuators)."""

    t: np.ndarray
    q: np.ndarray
    eta: np.ndarray
    tau: np.ndarray


def zero_torque(t: jax.Array, q: jax.Array, eta: jax.Array) -> jnp.ndarray:
    """τ = 0 (unforced motion)."""
    return jnp.zeros_like(eta)


@partial(jax.jit, static_argnums=(0, 3, 4))
def _simulate(model: DynamicModel, q0, eta0, torque_fn: TorqueFn, steps: int, dt):
    robot = model.robot

    def deriv(t, q, eta):
        tau = torque_fn(t, q, eta)
        return robot.S(q) @ eta, reduced.forward_dynamics_one(model, q, eta, tau)

    nodes = jnp.array(
        [0.0, 0.5, 0.5, 1.0]
    )  # classical RK4 tableau: stage i evaluates at y + nodes[i] dt k_{i-1}
    weights = jnp.array([1.0, 2.0, 2.0, 1.0]) / 6.0

    def step(state, k):
        q, eta = state
        t = k * dt

        def stage(i, carry):  # one traced copy of the dynamics for the four stages: a small graph to compile
            (k_q, k_eta), (sum_q, sum_eta) = carry
            k_q, k_eta = deriv(t + nodes[i] * dt, q + nodes[i] * dt * k_q, eta + nodes[i] * dt * k_eta)
            return (k_q, k_eta), (sum_q + weights[i] * k_q, sum_eta + weights[i] * k_eta)

        zero = (jnp.zeros_like(q), jnp.zeros_like(eta))
        _, (sum_q, sum_eta) = jax.lax.fori_loop(0, 4, stage, (zero, zero))
        q_next, eta_next = q + dt * sum_q, eta + dt * sum_eta
        return (q_next, eta_next), (q_next, eta_next, torque_fn(t + dt, q_next, eta_next))

    _, (qs, etas, taus) = jax.lax.scan(step, (q0, eta0), jnp.arange(steps))
    tau0 = torque_fn(0.0 * dt, q0, eta0)
    return (
        jnp.concatenate([q0[None], qs]),
        jnp.concatenate([eta0[None], etas]),
        jnp.concatenate([tau0[None], taus]),
    )


def simulate(
    model: DynamicModel,
    q0: npt.ArrayLike,
    eta0: npt.ArrayLike,
    torque_fn: TorqueFn = zero_torque,
    duration: float = 1.0,
    dt: float = 1e-3,
) -> SimulationResult:
    """Integrate the reduced equations from (q0, η0) for ``duration`` seconds with step ``dt`` (RK4)."""
    if not (np.isfinite(duration) and duration > 0):
        raise InputError(f"simulate: duration must be a finite number > 0 s, got {duration!r}")
    if not (np.isfinite(dt) and 0 < dt <= duration):
        raise InputError(f"simulate: dt must be in (0, duration = {duration}] s, got {dt!r}")
    q0 = jnp.asarray(model.robot.validate_q(q0))
    eta0 = reduced.validated_eta(model, eta0, "eta0")
    steps = int(round(duration / dt))
    q, eta, tau = _simulate(model, q0, eta0, torque_fn, steps, float(dt))
    return SimulationResult(np.arange(steps + 1) * dt, np.asarray(q), np.asarray(eta), np.asarray(tau))


__all__ = ["SimulationResult", "simulate", "zero_torque"]
