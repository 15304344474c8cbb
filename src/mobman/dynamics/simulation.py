"""Forward-dynamics simulation of the reduced equations: one compiled ``lax.scan`` with classical RK4
(:data:`mobman.integration.RK4`, on the scan-shaped kernel: the dynamics are traced and compiled once, not once
per stage).

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

from mobman import integration
from mobman.dynamics import reduced
from mobman.dynamics.inertia import DynamicModel
from mobman.engine import runge_kutta
from mobman.errors import ConvergenceError, InputError

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
def _simulate(
    model: DynamicModel, q0: jax.Array, eta0: jax.Array, torque_fn: TorqueFn, steps: int, dt: float
) -> tuple[jax.Array, jax.Array, jax.Array]:
    robot = model.robot

    def deriv(t, q, eta):
        tau = torque_fn(t, q, eta)
        return robot.S(q) @ eta, reduced.forward_dynamics_one(model, q, eta, tau)

    _, (qs, etas) = integration.integrate(
        integration.RK4,
        lambda t, y: deriv(t, *y),
        (q0, eta0),
        0.0,
        dt,
        steps,
        stepper=runge_kutta.step,
    )
    q = jnp.concatenate([q0[None], qs])
    eta = jnp.concatenate([eta0[None], etas])
    return q, eta, jax.vmap(torque_fn)(dt * jnp.arange(steps + 1), q, eta)


def simulate(
    model: DynamicModel,
    q0: npt.ArrayLike,
    eta0: npt.ArrayLike,
    torque_fn: TorqueFn = zero_torque,
    duration: float = 1.0,
    dt: float = 1e-3,
) -> SimulationResult:
    """Integrate the reduced equations from (q0, η0) for ``duration`` seconds with step ``dt`` (RK4).

    Never a NaN: a torque function that returns NaN or infinite torques is an InputError naming the time; a
    state that becomes NaN or infinite a ConvergenceError naming the time, its ``history`` the samples before.
    """
    if not (np.isfinite(duration) and duration > 0):
        raise InputError(f"simulate: duration must be a finite number > 0 s, got {duration!r}")
    if not (np.isfinite(dt) and 0 < dt <= duration):
        raise InputError(f"simulate: dt must be in (0, duration = {duration}] s, got {dt!r}")
    q0 = jnp.asarray(model.robot.validate_q(q0))
    eta0 = reduced.validated_eta(model, eta0, "eta0")
    steps = int(round(duration / dt))
    q, eta, tau = (np.asarray(x) for x in _simulate(model, q0, eta0, torque_fn, steps, float(dt)))
    t = np.arange(steps + 1) * dt
    finite = np.isfinite(q).all(axis=1) & np.isfinite(eta).all(axis=1) & np.isfinite(tau).all(axis=1)
    if not finite.all():
        k = int(np.argmin(finite))
        if not np.isfinite(tau[k]).all():
            raise InputError(f"simulate: torque_fn returned NaN or infinite torques at t = {t[k]:.6g} s")
        raise ConvergenceError(
            f"simulate: the state (q, η) is NaN or infinite from t = {t[k]:.6g} s on (the motion diverges; "
            "a smaller dt, or torques that keep it bounded)",
            SimulationResult(t[:k], q[:k], eta[:k], tau[:k]),
        )
    return SimulationResult(t, q, eta, tau)


__all__ = ["SimulationResult", "simulate", "zero_torque"]
