"""Many planning problems at once (Tchoń et al. 2002 §3 for each): blocks of problems advanced together.

A ``vmap`` of the whole ``while_loop`` would compute every problem until the slowest one stops (at the cap,
while most converge in a few iterations). Here a compiled call makes one :func:`iteration` of a block of
:data:`BLOCK` problems (``vmap`` over problems); after each round the problems still running are gathered into
full blocks again, and a round's blocks run on the cores. Each problem goes through the same iterations as
:func:`mobman.planning.algorithms.plan`, so its status, iterations, z and error history are the same."""

from __future__ import annotations

import functools
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from functools import partial

import jax
import jax.numpy as jnp
import numpy as np
import numpy.typing as npt

from mobman.engine.batched import WORKERS
from mobman.errors import InputError
from mobman.planning.algorithms import (
    RUNNING,
    STATUS,
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
"""Problems one compiled call advances together (fewer when the batch is smaller): vectorised over 4 to 32
problems, an iteration costs about half its one-problem time per problem on the CPU; wider blocks outgrow
the caches (benchmarks/planning.py)."""


@partial(jax.jit, static_argnums=(0, 1))
def _advance(setting, kernel, state, q0, y_d, *arguments):
    """One iteration of each problem of a block (vmap over problems only: the algorithm and the step mode
    stay unbatched, so their branches are real ``lax.switch``/``lax.cond``)."""
    return jax.vmap(lambda s, q, y: iteration(setting, kernel, q, y, *arguments)(s))(state, q0, y_d)


@functools.cache
def _pool() -> ThreadPoolExecutor:
    """The threads that run a round's blocks, one per core (XLA releases the GIL while it computes)."""
    return ThreadPoolExecutor(WORKERS, thread_name_prefix="mobman-plan-batch")


def plan_batch(
    setting: PlanningSetting,
    z0: npt.ArrayLike,
    q0: npt.ArrayLike,
    y_d: npt.ArrayLike,
    options: Options = Options(),
) -> BatchResult:
    """Solve K_{q0,T}(z) = y_d for a batch: z0 (B, n_z), q0 (B, n_p), y_d (B, r), or any of them unbatched
    (broadcast). Rounds of one iteration of every problem still running, in blocks (module docstring), until
    every problem has stopped."""
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
    first = initial_state(kernel, jnp.zeros(setting.n_z))
    # the state of every problem (the fields of Plan: z, status, iterations, errors, thetas), in NumPy
    state = [z0.copy(), *(np.array(np.broadcast_to(np.asarray(a), (size,) + a.shape)) for a in first[1:])]
    block = min(BLOCK, size)

    def advance(lanes: np.ndarray) -> list[np.ndarray]:
        padded = np.resize(lanes, block)  # a short last block repeats its problems
        block_state = Plan(*(jnp.asarray(a[padded]) for a in state))
        out = _advance(setting, kernel, block_state, q0[padded], y_d[padded], *arguments)
        return [np.asarray(b)[: lanes.size] for b in out]

    running = np.arange(size)
    while running.size:
        blocks = [running[i : i + block] for i in range(0, running.size, block)]
        outs = list(_pool().map(advance, blocks)) if len(blocks) > 1 else [advance(blocks[0])]
        for lanes, out in zip(blocks, outs):
            for a, b in zip(state, out):
                a[lanes] = b
        running = running[state[1][running] == RUNNING]
    z, status, iterations, errors, _ = state
    final = errors[np.arange(size), iterations]
    return BatchResult(z, [STATUS[int(s)] for s in status], iterations, final, errors)
