"""Configurations over the whole joint range and the two independent derivatives (central differences of the
value, autodiff) shared by the tests of the task kinds (tests/test_model_tasks_*.py)."""

from __future__ import annotations

import math

import jax
import jax.numpy as jnp
import numpy as np

from mobman import kinematics as K

SPECIAL = (0.0, math.pi / 2, -math.pi / 2, math.pi)
"""Angles where representation singularities hide."""


def configurations(n_q: int, n: int = 10, seed: int = 0) -> np.ndarray:
    """(n, n_q) configurations: platform positions in [−3, 3], the heading and every joint over the whole
    circle; some rows have all angles, others one angle, exactly at 0, ±π/2 and π."""
    rng = np.random.default_rng(seed)
    q = rng.uniform(-math.pi, math.pi, size=(n, n_q))
    q[:, :2] = rng.uniform(-3.0, 3.0, size=(n, 2))
    for k, value in enumerate(SPECIAL):
        q[k, 2:] = value
        q[len(SPECIAL) + k, 2 + (k % (n_q - 2))] = value
    return q


def central_differences(robot, task, q: np.ndarray, step: float = 1e-6, angles: bool = False) -> np.ndarray:
    """(N, m, n_q) central differences of the task's value, from one batched forward call; ``angles``: the
    values are angles in (−π, π], their differences taken modulo 2π (across the cut at ±π)."""
    n_q = q.shape[-1]
    shifted = (
        q[:, None, None, :] + step * np.eye(n_q)[None, None] * np.array([1.0, -1.0])[None, :, None, None]
    )
    values = np.asarray(K.forward(robot, shifted, task))
    difference = values[:, 0] - values[:, 1]
    if angles:
        difference = (difference + math.pi) % (2 * math.pi) - math.pi
    return np.swapaxes(difference / (2 * step), 1, 2)


def autodiff(robot, task, q: np.ndarray) -> np.ndarray:
    """(N, m, n_q) forward-mode autodiff of the task's value through the frames."""
    value = lambda qq: task.value(robot, qq, robot.frames(qq))  # noqa: E731
    return np.asarray(jax.jit(jax.vmap(jax.jacfwd(value)))(jnp.asarray(q)))
