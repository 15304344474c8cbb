"""Many planning problems at once: ``jax.vmap`` of the compiled planner over starts, targets and initial z."""

from __future__ import annotations

from dataclasses import dataclass
from functools import partial

import jax
import jax.numpy as jnp
import numpy as np
import numpy.typing as npt

from mobman.errors import InputError
from mobman.planning.algorithms import STATUS, Options, PlanResult, check_sizes, solve_loop
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


@partial(jax.jit, static_argnums=(0, 1))
def _solve_batch(setting, kernel, z0, q0, y_d, *arguments):
    """vmap over problems only: the algorithm and the step mode stay unbatched, so their branches are real
    ``lax.switch``/``lax.cond`` (only the chosen one runs)."""
    return jax.vmap(lambda z, q, y: solve_loop(setting, kernel, z, q, y, *arguments))(z0, q0, y_d)


def plan_batch(
    setting: PlanningSetting,
    z0: npt.ArrayLike,
    q0: npt.ArrayLike,
    y_d: npt.ArrayLike,
    options: Options = Options(),
) -> BatchResult:
    """Solve K_{q0,T}(z) = y_d for a batch: z0 (B, n_z), q0 (B, n_p), y_d (B, r), or any of them unbatched
    (broadcast). One compiled, vectorised call; the loop runs until every problem has stopped."""
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
    out = _solve_batch(
        setting, options.kernel, jnp.asarray(z0), jnp.asarray(q0), jnp.asarray(y_d), *options.arguments()
    )
    iterations = np.asarray(out.iterations)
    errors = np.asarray(out.errors)
    final = errors[np.arange(size), iterations]
    return BatchResult(
        np.asarray(out.z), [STATUS[int(s)] for s in np.asarray(out.status)], iterations, final, errors
    )
