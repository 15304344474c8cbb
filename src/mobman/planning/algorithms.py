"""Jacobian motion planning algorithms as a discretised continuation in θ (Tchoń et al. §3).

Each algorithm follows a curve z(θ) in the endogenous configuration space along dz/dθ = γ·direction(z):

- ``"pinv"``: −J#e with J# = Jᵀ(J Jᵀ)⁻¹ (eqs. 10, 15), plus (I − J#J) w for a null-space vector w (eq. 16,
  sign corrected: see docs/planning.md);
- ``"extended"``: −J^{e#} e, J^{e#} = first r columns of J^{E#} = J^{E}ᵀ(J^E J^{E}ᵀ)⁻¹, J^E = [J; J̄] the
  Jacobian of the output extended with h(q, x) (eqs. 18–24);
- ``"adjoint"``: −Jᵀ e, steepest descent of ½‖e‖² (eqs. 25–29).

Here e = K(z) − y_d (eq. 17). The flow is discretised by z ← z + Δθ·γ·direction: fixed Δθ (Δθ·γ = 1 is
Newton's step for the pseudo-inverses), or ``step="adaptive"``, a backtracking line search along the
direction starting from the step that minimises the linearised error (Newton's step for the pseudo-inverses).
All loops run inside ``jax.jit`` (``lax.while_loop``) with the error history in a fixed-size buffer.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import partial
from typing import Callable, NamedTuple

import jax
import jax.numpy as jnp
import numpy as np
import numpy.typing as npt

from mobman.errors import ConvergenceError, InputError
from mobman.model.tasks import Task
from mobman.planning.endpoint import PlanningSetting, endpoint_of_task, output_jacobian, variational_of_task

ALGORITHMS = ("pinv", "extended", "adjoint")

RUNNING, CONVERGED, MAX_ITERATIONS, SINGULAR, LINE_SEARCH_FAILED, NOT_FINITE = range(6)
STATUS = ("running", "converged", "max_iterations", "singular", "line_search_failed", "not_finite")

SINGULAR_RCOND = 1e-13
"""A Gram matrix whose smallest/largest eigenvalue ratio is below this is treated as singular."""
MAX_HALVINGS = 40
ARMIJO = 1e-4

MAX_STEP = 10.0
"""Largest fixed continuation step Δθ (Newton's is 1; the papers use 0.1 to 1)."""

MAX_GAMMA = 1e3
"""Largest rate γ: with Δθ, the step z ← z + Δθ γ d, whose product with a larger γ only overflows."""


@dataclass(frozen=True)
class Options:
    """Algorithm settings.

    algorithm: one of ``ALGORITHMS``; step: Δθ > 0 or ``"adaptive"``; gamma: the rate γ > 0; tol: stop when
    ‖K − y_d‖ ≤ tol; max_iterations: the cap (also the history buffer size); extension: the output extension
    h(q, x) as a task (required by ``"extended"``, ignored by the others); nullspace: w(z, q0) for the
    null-space term of eq. (16) (``"pinv"`` only), e.g. :func:`dexterity_gradient`.

    Only :attr:`kernel` (extension, null-space vector, cap) shapes the compiled loop: the algorithm, the
    step mode, Δθ, γ and the tolerance are traced arguments, so comparing the three algorithms with fixed
    and adaptive steps compiles once.
    """

    algorithm: str = "pinv"
    step: float | str = 1.0
    gamma: float = 1.0
    tol: float = 1e-12
    max_iterations: int = 100
    extension: Task | None = None
    nullspace: Callable | None = None

    def __post_init__(self) -> None:
        if self.algorithm not in ALGORITHMS:
            raise InputError(f"algorithm must be one of {', '.join(ALGORITHMS)}, got {self.algorithm!r}")
        if self.step != "adaptive" and not (
            isinstance(self.step, (int, float)) and 0 < self.step <= MAX_STEP
        ):
            raise InputError(
                f"step Δθ must be a number in (0, {MAX_STEP:g}] or 'adaptive', got {self.step!r}"
            )
        if not (isinstance(self.gamma, (int, float)) and 0 < self.gamma <= MAX_GAMMA):
            raise InputError(f"gamma must be a number in (0, {MAX_GAMMA:g}], got {self.gamma!r}")
        if not (isinstance(self.tol, (int, float)) and self.tol > 0):
            raise InputError(f"tol must be a number > 0, got {self.tol!r}")
        if not isinstance(self.max_iterations, int) or self.max_iterations < 0:
            raise InputError(f"max_iterations must be an integer ≥ 0, got {self.max_iterations!r}")
        if self.algorithm == "extended" and self.extension is None:
            raise InputError("algorithm 'extended' needs an output extension h(q, x) (extension=...)")
        if self.nullspace is not None and self.algorithm != "pinv":
            raise InputError("a null-space vector (nullspace=...) is only used by algorithm 'pinv'")

    @property
    def kernel(self) -> "Kernel":
        """The static part of the compiled loop."""
        return Kernel(self.extension, self.nullspace, self.max_iterations)

    def arguments(self) -> tuple:
        """The traced arguments of the compiled loop: algorithm index, adaptive flag, Δθ, γ, tol."""
        adaptive = self.step == "adaptive"
        return (
            ALGORITHMS.index(self.algorithm),
            adaptive,
            0.0 if adaptive else float(self.step),
            float(self.gamma),
            float(self.tol),
        )


class Kernel(NamedTuple):
    """What the compiled loop is specialised on (hashable): the extension task (None: degree s = 0), the
    null-space vector field (None: no null-space term) and the iteration cap."""

    extension: Task | None
    nullspace: Callable | None
    max_iterations: int


class Plan(NamedTuple):
    """Outcome of one planning run (arrays; see :func:`plan` for the NumPy/dict view).

    z: the final endogenous configuration; status: index into ``STATUS``; iterations: updates made;
    errors, thetas: ‖e‖ and θ after each iteration (first ``iterations + 1`` entries valid, then NaN).
    """

    z: jnp.ndarray
    status: jnp.ndarray
    iterations: jnp.ndarray
    errors: jnp.ndarray
    thetas: jnp.ndarray


def right_inverse(J: jnp.ndarray, rows: int | None = None) -> tuple[jnp.ndarray, jnp.ndarray]:
    """J# = Jᵀ(J Jᵀ)⁻¹ restricted to its first ``rows`` columns, and the reciprocal condition of J Jᵀ.

    With J = J^E (extended Jacobian) and rows = r this is the extended Jacobian pseudo-inverse (eq. 23).
    """
    gram = J @ J.T
    w = jnp.linalg.eigvalsh(gram)
    rcond = w[0] / jnp.maximum(w[-1], 1e-300)
    inverse = J.T @ jnp.linalg.solve(gram, jnp.eye(J.shape[0]))
    return (inverse if rows is None else inverse[:, :rows]), rcond


def null_space_projector(J: jnp.ndarray) -> jnp.ndarray:
    """P = I − J#J, the orthogonal projector onto Ker J (the paper's eq. 14 has the opposite sign)."""
    inverse, _ = right_inverse(J)
    return jnp.eye(J.shape[1]) - inverse @ J


def _direction(
    setting: PlanningSetting,
    kernel: Kernel,
    algorithm: jax.Array,
    z: jax.Array,
    q0: jax.Array,
    y_d: jax.Array,
) -> tuple[jax.Array, jax.Array, jax.Array, jax.Array]:
    """e = K(z) − y_d, the Jacobian J, the θ-flow direction at z (for γ = 1) and the reciprocal condition of
    the Gram matrix inverted (1 for the adjoint). K is integrated with ``setting.steps``, the variational
    system with ``setting.jacobian_steps``; ``algorithm`` indexes ``ALGORITHMS`` (a traced ``lax.switch``)."""
    coarse = setting.jacobian_setting
    v = variational_of_task(coarse, setting.output, z, q0, False)
    J = v.J
    e = endpoint_of_task(setting, setting.output, z, q0) - y_d
    _, x = setting.split(z)

    def pinv():
        inverse, rcond = right_inverse(J)
        d = -inverse @ e
        if kernel.nullspace is not None:
            d = d + (jnp.eye(z.shape[0]) - inverse @ J) @ kernel.nullspace(z, q0)
        return d, rcond

    def extended():
        J_E = (
            J
            if kernel.extension is None
            else jnp.concatenate([J, output_jacobian(coarse, kernel.extension, v.q_T, v.Xi, x)])
        )
        inverse, rcond = right_inverse(J_E, e.shape[0])
        return -inverse @ e, rcond

    def adjoint():
        return -J.T @ e, jnp.ones(())

    d, rcond = jax.lax.switch(algorithm, (pinv, extended, adjoint))
    return e, J, d, rcond


def _line_search(setting, z, q0, y_d, e, J, d):
    """Backtracking on ½‖e‖² (Armijo) from α0 = argmin_α ‖e + α J d‖ (= 1 for the pseudo-inverses)."""
    slope = e @ (J @ d)
    alpha0 = -slope / jnp.maximum((J @ d) @ (J @ d), 1e-300)
    v0 = 0.5 * e @ e

    def value(alpha):
        e_new = endpoint_of_task(setting, setting.output, z + alpha * d, q0) - y_d
        return 0.5 * e_new @ e_new

    def cond(state):
        alpha, v, k = state
        return (~(v <= v0 + ARMIJO * alpha * slope)) & (k < MAX_HALVINGS)

    def body(state):
        alpha, _, k = state
        return alpha / 2, value(alpha / 2), k + 1

    alpha, v, _ = jax.lax.while_loop(cond, body, (alpha0, value(alpha0), 0))
    return alpha, v <= v0 + ARMIJO * alpha * slope


def initial_state(kernel: Kernel, z0: jax.Array) -> Plan:
    """The loop's state before the first iteration: z0, running, no update made, empty histories (θ = 0)."""
    nan = jnp.full(kernel.max_iterations + 1, jnp.nan)
    return Plan(z0, jnp.asarray(RUNNING), jnp.asarray(0), nan, nan.at[0].set(0.0))


def iteration(
    setting: PlanningSetting,
    kernel: Kernel,
    q0: jax.Array,
    y_d: jax.Array,
    algorithm: jax.Array,
    adaptive: jax.Array,
    step: jax.Array,
    gamma: jax.Array,
    tol: jax.Array,
) -> Callable[[Plan], Plan]:
    """One iteration of the loop as a function of its state: records ‖e‖ at z, sets the status (converged,
    cap reached, singular Gram matrix, failed line search, non-finite error) and, while running, moves z by
    Δθ·γ·direction."""

    def body(state: Plan) -> Plan:
        z, _, k, errors, thetas = state
        e, J, d, rcond = _direction(setting, kernel, algorithm, z, q0, y_d)
        err = jnp.linalg.norm(e)
        errors = errors.at[k].set(err)
        converged = err <= tol

        def search():
            alpha, ok = _line_search(setting, z, q0, y_d, e, J, d)
            return jnp.where(converged, 0.0, alpha / gamma), ok | converged

        dtheta, ok = jax.lax.cond(adaptive, search, lambda: (jnp.asarray(step, float), jnp.asarray(True)))
        status = jnp.select(
            [
                ~jnp.isfinite(err),
                converged,
                k >= kernel.max_iterations,
                (rcond < SINGULAR_RCOND) | ~jnp.all(jnp.isfinite(d)),
                ~ok,
            ],
            [NOT_FINITE, CONVERGED, MAX_ITERATIONS, SINGULAR, LINE_SEARCH_FAILED],
            RUNNING,
        )
        running = status == RUNNING
        z = jnp.where(running, z + dtheta * gamma * d, z)
        thetas = thetas.at[k + 1].set(jnp.where(running, thetas[k] + dtheta, jnp.nan))
        return Plan(z, status, k + running.astype(k.dtype), errors, thetas)

    return body


@partial(jax.jit, static_argnums=(0, 1))
def solve_loop(
    setting: PlanningSetting,
    kernel: Kernel,
    z0: jax.Array,
    q0: jax.Array,
    y_d: jax.Array,
    algorithm: jax.Array,
    adaptive: jax.Array,
    step: jax.Array,
    gamma: jax.Array,
    tol: jax.Array,
) -> Plan:
    """The compiled loop: :func:`iteration` until the status is no longer running (see
    :meth:`Options.arguments` for the traced arguments)."""
    body = iteration(setting, kernel, q0, y_d, algorithm, adaptive, step, gamma, tol)
    return jax.lax.while_loop(lambda state: state.status == RUNNING, body, initial_state(kernel, z0))


def solve(
    setting: PlanningSetting, options: Options, z0: npt.ArrayLike, q0: npt.ArrayLike, y_d: npt.ArrayLike
) -> Plan:
    """Run one algorithm from z0 (the compiled kernel behind :func:`plan`; arrays in, :class:`Plan` out).

    The algorithm, the step mode, Δθ, γ and the tolerance are traced arguments: changing them does not
    recompile (only :attr:`Options.kernel` does).
    """
    return solve_loop(
        setting,
        options.kernel,
        jnp.asarray(z0, float),
        jnp.asarray(q0, float),
        jnp.asarray(y_d, float),
        *options.arguments(),
    )


@dataclass
class PlanResult:
    """A planning run in NumPy: final z = (λ, x), status, iterations, error and θ histories."""

    z: np.ndarray
    lam: np.ndarray
    x: np.ndarray
    status: str
    iterations: int
    errors: np.ndarray
    thetas: np.ndarray

    @property
    def converged(self) -> bool:
        return self.status == "converged"

    @property
    def final_error(self) -> float:
        return float(self.errors[-1])


def to_result(setting: PlanningSetting, result: Plan) -> PlanResult:
    """NumPy view of one :class:`Plan` (histories cut to the iterations made)."""
    k = int(result.iterations)
    z = np.asarray(result.z)
    lam, x = setting.split(z)
    return PlanResult(
        z,
        np.asarray(lam).reshape(-1),
        np.asarray(x),
        STATUS[int(result.status)],
        k,
        np.asarray(result.errors)[: k + 1],
        np.asarray(result.thetas)[: k + 1],
    )


def plan(
    setting: PlanningSetting,
    z0: npt.ArrayLike,
    q0: npt.ArrayLike,
    y_d: npt.ArrayLike,
    options: Options = Options(),
    raise_on_failure: bool = False,
) -> PlanResult:
    """Solve K_{q0,T}(z) = y_d (eq. 4) from z0; non-convergence is a result (status) unless raise_on_failure.

    >>> from mobman.model.robots import tchon_car_rtr
    >>> setting = PlanningSetting(tchon_car_rtr())
    >>> z0 = [0.01, 0, 0, 0, 0, -0.01, 0, 0, 0, 0, 0, 2, 0.785]
    >>> plan(setting, z0, [5, 0, 0, 0.52], [0, 0, 1]).converged
    True
    """
    z0, q0, y_d = check_sizes(setting, z0, q0, y_d)
    for name, a in (("z0", z0), ("q0", q0), ("y_d", y_d)):
        if a.ndim != 1:
            raise InputError(
                f"plan: {name} must be one vector (plan_batch solves batches), got shape {a.shape}"
            )
    result = to_result(setting, solve(setting, options, z0, q0, y_d))
    if raise_on_failure and not result.converged:
        raise ConvergenceError(
            f"{options.algorithm} did not reach ‖e‖ ≤ {options.tol:g}: status {result.status} after "
            f"{result.iterations} iterations, ‖e‖ = {result.final_error:.3e}",
            history=result,
        )
    return result


def check_sizes(
    setting: PlanningSetting, z0: npt.ArrayLike, q0: npt.ArrayLike, y_d: npt.ArrayLike
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """z0, q0, y_d as float arrays with the setting's sizes on their last axis and finite values (InputError
    naming the argument otherwise)."""
    checks = (
        ("z0 (endogenous configuration)", z0, setting.n_z),
        ("q0 (platform start)", q0, setting.robot.platform.n_q),
        ("y_d (target)", y_d, setting.output.dim),
    )
    arrays = []
    for name, value, size in checks:
        try:
            value = np.asarray(value, float)
        except (TypeError, ValueError):
            raise InputError(f"{name}: expected {size} numbers, got {type(value).__name__}") from None
        arrays.append(value)
        if value.shape[-1:] != (size,):
            raise InputError(f"{name}: expected {size} values, got {value.shape[-1] if value.ndim else 1}")
        if not np.all(np.isfinite(value)):
            raise InputError(f"{name}: values must be finite")
    z, q, y = arrays
    return z, q, y


def dexterity_gradient(setting: PlanningSetting, gain: float = 1.0) -> Callable:
    """w(z, q0) = gain·∇_z det(J Jᵀ): a null-space vector that increases the (parametric) dexterity² (eq.
    16)."""

    def w(z, q0):
        def d2(zz):
            J = variational_of_task(setting.jacobian_setting, setting.output, zz, q0, False).J
            return jnp.linalg.det(J @ J.T)

        return gain * jax.jacfwd(d2)(z)  # forward mode: n_z is small and it compiles much faster

    return w
