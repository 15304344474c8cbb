"""Ordinary differential equations with closed-form solutions (or a known structure), shared by the tests of the
Runge–Kutta driver (tests/test_integration.py) and of its scan-shaped kernel (tests/test_engine_runge_kutta.py)."""

from __future__ import annotations

import jax.numpy as jnp
import numpy as np

import mobman  # noqa: F401  (float64)
from mobman.integration import CF4, DOP853, RK4

TABLEAUS = {"rk4": RK4, "dop853": DOP853, "cf4": CF4}
"""The tableaus every test runs: classical RK4, Dormand–Prince 8(5,3), the commutator-free Lie group method."""


def arc(q, u):
    """q ∘ exp(u) on SE(2) × R: the unicycle (x, y, θ) driven for unit time at the body twist (u0, 0, u1), i.e.
    along a circle of radius u0/u1 (a line if u1 = 0), closed form; q[3:] + u[2:] on the joints."""
    x, y, th = q[0], q[1], q[2]
    v, w = u[0], u[1]
    small = jnp.abs(w) < 1e-300
    w_safe = jnp.where(small, 1.0, w)
    dx = jnp.where(small, v * jnp.cos(th), v / w_safe * (jnp.sin(th + w) - jnp.sin(th)))
    dy = jnp.where(small, v * jnp.sin(th), -v / w_safe * (jnp.cos(th + w) - jnp.cos(th)))
    return jnp.concatenate([jnp.stack([x + dx, y + dy, th + w]), q[3:] + u[2:]])


def vector_field(t, y):
    """y0' = −y0² (y0 = 1/(1 + t) from 1), y1' = y1 cos t (y1 = e^{sin t} from 1)."""
    return jnp.stack([-(y[0] ** 2), y[1] * jnp.cos(t)])


def vector_solution(t):
    return np.array([1.0 / (1.0 + t), np.exp(np.sin(t))])


def unicycle_field(t, q):
    """η = (v, ω, q̇_3) with v = ω = 1 + θ²: the platform runs along the unit circle with θ' = 1 + θ², so from
    q = 0: θ = tan t, (x, y) = (sin θ, 1 − cos θ); the joint q̇_3 = q_3 cos t, q_3 = e^{sin t} from 1."""
    speed = 1.0 + q[2] ** 2
    return jnp.stack([speed, speed, q[3] * jnp.cos(t)])


def unicycle_solution(t):
    th = np.tan(t)
    return np.array([np.sin(th), 1.0 - np.cos(th), th, np.exp(np.sin(t))])


def planar_system(t, state):
    """A pytree state (q, Ξ) like the planners' variational system: q̇ = S(q) u(t), Ξ̇ = A Ξ + B."""
    q, xi = state
    u = jnp.array([1.0 + jnp.sin(3.0 * t), jnp.cos(t)])
    c, s = jnp.cos(q[2]), jnp.sin(q[2])
    zero = jnp.zeros(())
    a = jnp.stack([jnp.stack([zero, zero, -s * u[0]]), jnp.stack([zero, zero, c * u[0]]), jnp.zeros(3)])
    b = jnp.stack([jnp.stack([c, zero]), jnp.stack([s, zero]), jnp.array([0.0, 1.0])])
    return jnp.stack([c * u[0], s * u[0], u[1]]), a @ xi + b * jnp.cos(2.0 * t)
