"""Many planning problems at once (Tchoń et al. 2002 §3 for each): lanes of problems advanced together.

A ``vmap`` of the whole ``while_loop`` would compute every problem until the slowest one stops (at the cap,
while most converge in a few iterations). Here a block of :data:`BLOCK` lanes makes one :func:`iteration` of
the problem each holds (``vmap`` over lanes) inside one compiled loop; a lane whose problem stops writes its
result and takes the next problem not yet started, so the lanes stay full until the last problems. The loop
runs at most :data:`ROUNDS` iterations per compiled call (a call stays short) and resumes from its carry, and
the problems are dealt to one such loop per core. Each problem goes through the same iterations as
:func:`mobman.planning.algorithms.plan`, so its status, iterations, z and error history are the same."""

from __future__ import annotations

import functools
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from functools import partial
from typing import NamedTuple

import jax
import jax.numpy as jnp
import numpy as np
import numpy.typing as npt

from mobman.engine.batched import WORKERS
from mobman.errors import InputError
from mobman.planning.algorithms import (
    RUNNING,
    STATUS,
    Kernel,
    Options,
    Plan,
    PlanResult,
    check_sizes,
    initial_state,
    iteration,
)
from mobman.planning.endpoint import PlanningSetting


@dataclass
class BatchResult:
    """Outcome of a batch: per problem the final z, status names, iterations and final errors."""

    z: np.ndarray
    status: list[str]
    iterations: np.ndarray
    final_errors: np.ndarray
    errors: np.ndarray

    @property
    def converged(self) -> np.ndarray:
        return np.array([s == "converged" for s in self.status])

    @property
    def success_rate(self) -> float:
        """Fraction of problems solved to the tolerance."""
        return float(np.mean(self.converged)) if self.status else 0.0

    def run(self, setting: PlanningSetting, index: int) -> PlanResult:
        """One problem of the batch as a :class:`PlanResult`."""
        k = int(self.iterations[index])
        lam, x = setting.split(self.z[index])
        return PlanResult(
            self.z[index],
            np.asarray(lam).reshape(-1),
            np.asarray(x),
            self.status[index],
            k,
            self.errors[index, : k + 1],
            np.full(k + 1, np.nan),
        )


BLOCK = 8
"""Lanes one compiled loop advances together (fewer when the batch is smaller): vectorised over 8 problems an
iteration costs about 0.4 of its one-problem time per problem on the CPU; 4 lanes were as fast, 6 slower, and
12 or 16 three times slower per problem, their loops too large for XLA to compile as one kernel
(``mobman.SMALL_LOOP_BYTES``; benchmarks/planning.py)."""

ROUNDS = 64
"""Iterations of the lanes per compiled call (about 0.2 s for 8 lanes of the §4 problems)."""


class _Lanes(NamedTuple):
    """The loop's carry: the problem each lane holds (``size``: none), the lanes' states, every problem's
    final state (written when it stops) and the next problem to start."""

    problem: jax.Array
    state: Plan
    out: Plan
    following: jax.Array


@partial(jax.jit, static_argnums=(0, 1, 2))
def _rounds(setting, kernel, rounds, lanes, size, z0, q0, y_d, *arguments):
    """Up to ``rounds`` iterations of every lane holding a problem (module docstring): the first
    ``size`` problems of z0, q0, y_d are real, the rest pad them to :func:`_capacity`. The vmap is over the
    lanes only: the algorithm and the step mode stay unbatched, so their branches are real ``lax.switch`` and
    ``lax.cond``."""

    def advance(lanes: _Lanes) -> _Lanes:
        held = lanes.problem < size
        index = jnp.where(held, lanes.problem, 0)
        state = jax.vmap(lambda s, q, y: iteration(setting, kernel, q, y, *arguments)(s))(
            lanes.state, q0[index], y_d[index]
        )
        stopped = held & (state.status != RUNNING)
        out = jax.tree.map(
            lambda o, s: o.at[jnp.where(stopped, lanes.problem, o.shape[0])].set(s, mode="drop"),
            lanes.out,
            state,
        )
        # the stopped lanes take the next problems in order
        fresh = lanes.following + jnp.cumsum(stopped) - 1
        problem = jnp.where(stopped, jnp.where(fresh < size, fresh, size), lanes.problem)
        loaded = _initial(kernel, z0[jnp.where(problem < size, problem, 0)])
        state = jax.tree.map(
            lambda a, b: jnp.where(stopped.reshape((-1,) + (1,) * (a.ndim - 1)), b, a), state, loaded
        )
        return _Lanes(problem, state, out, lanes.following + jnp.sum(stopped))

    def running(carry: tuple[_Lanes, jax.Array]) -> jax.Array:
        lanes, k = carry
        return jnp.any(lanes.problem < size) & (k < rounds)

    lanes, _ = jax.lax.while_loop(running, lambda c: (advance(c[0]), c[1] + 1), (lanes, jnp.asarray(0)))
    return lanes


def _initial(kernel: Kernel, z0: jax.Array) -> Plan:
    """The states before the first iteration of problems starting at z0 (n, n_z)."""
    return jax.vmap(lambda z: initial_state(kernel, z))(z0)


def _capacity(size: int) -> int:
    """The padded number of problems of a share: the next power of two (a program per size class)."""
    return 1 << max(size - 1, 0).bit_length()


@functools.cache
def _pool() -> ThreadPoolExecutor:
    """The threads that run the shares, one per core (XLA releases the GIL while it computes)."""
    return ThreadPoolExecutor(WORKERS, thread_name_prefix="mobman-plan-batch")


def plan_batch(
    setting: PlanningSetting,
    z0: npt.ArrayLike,
    q0: npt.ArrayLike,
    y_d: npt.ArrayLike,
    options: Options = Options(),
) -> BatchResult:
    """Solve K_{q0,T}(z) = y_d for a batch: z0 (B, n_z), q0 (B, n_p), y_d (B, r), or any of them unbatched
    (broadcast). The problems are dealt to one loop of lanes per core (module docstring)."""
    names = ("z0", "q0", "y_d")
    arrays = z0, q0, y_d = check_sizes(setting, z0, q0, y_d)
    sizes = {a.shape[0] for a in arrays if a.ndim == 2}
    for name, a in zip(names, arrays):
        if a.ndim not in (1, 2) or (a.ndim == 2 and a.shape[0] == 0):
            raise InputError(
                f"plan_batch: {name} must be one problem (n,) or a non-empty batch (B, n), got {a.shape}"
            )
    if len(sizes - {1}) > 1:
        raise InputError(f"plan_batch: batch sizes of z0, q0, y_d differ: {[a.shape for a in arrays]}")
    size = max(sizes, default=1)
    z0, q0, y_d = (np.broadcast_to(a, (size, a.shape[-1])) for a in (z0, q0, y_d))
    kernel, arguments = options.kernel, options.arguments()
    # a share per core once each fills its lanes, dealt in turn (neighbouring problems are often alike)
    shares = max(1, min(WORKERS, size // BLOCK))
    dealt = [np.arange(k, size, shares) for k in range(shares)]

    def solve(problems: np.ndarray) -> list[np.ndarray]:
        """The final z, status, iterations, errors and thetas of ``problems`` (indices into the batch)."""
        n, lanes = problems.size, min(BLOCK, problems.size)
        padded = np.resize(problems, _capacity(n))  # the padding is never started
        z, q, y = (jnp.asarray(a[padded]) for a in (z0, q0, y_d))
        carry = _Lanes(
            jnp.arange(lanes), _initial(kernel, z[:lanes]), _initial(kernel, z), jnp.asarray(lanes)
        )
        while True:
            carry = _rounds(setting, kernel, ROUNDS, carry, n, z, q, y, *arguments)
            if not bool(jnp.any(carry.problem < n)):
                return [np.asarray(a)[:n] for a in carry.out]

    outs = list(_pool().map(solve, dealt)) if shares > 1 else [solve(dealt[0])]
    z, status, iterations, errors, thetas = (np.empty((size,) + a.shape[1:], a.dtype) for a in outs[0])
    for problems, out in zip(dealt, outs):
        for whole, part in zip((z, status, iterations, errors, thetas), out):
            whole[problems] = part
    final = errors[np.arange(size), iterations]
    return BatchResult(z, [STATUS[int(s)] for s in status], iterations, final, errors)
