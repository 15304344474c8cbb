"""Endpoint map K_{q0,T}(λ, x), its analytic Jacobian and the dexterity of an endogenous configuration.

The platform coordinates q_p are the state of the driftless system q̇_p = S_p(q_p) u(t) (Tchoń et al. eq. 1),
u(t) = Λ φ(t) with the coefficients Λ (m × N, row i = control u_i) of a :class:`~mobman.planning.basis.Basis`;
the arm coordinates x stay constant over [0, T]. The output is the robot's task at q = [q_p(T), x], so
``K = kinematics.forward(robot, [q_p(T), x])`` (eq. 3). An endogenous configuration is the flat vector
z = (vec Λ, x) ∈ R^{m·N + p}: u1's N coefficients, then u2's, …, then the joint positions.

Integration is a fixed-step explicit Runge–Kutta scheme (:mod:`~mobman.planning.integrators`: DOP853 of order
8 by default, or RK4; the driver of :mod:`mobman.integration`) in a ``lax.scan``. The Jacobian is computed two
ways:

- :func:`variational` integrates, together with q_p, the variational system (eqs. 5–7) driven by the basis
  functions: Ξ̇ = A(t) Ξ + B(t) (I_m ⊗ φ(t)ᵀ), Ξ(0) = 0, with A = ∂(S_p(q_p) u)/∂q_p and B = S_p(q_p), so that
  Ξ(T) = ∫ Φ(T, s) B(s) (I_m ⊗ φ(s)ᵀ) ds and J = [C Ξ(T), D] (eq. 8 restricted to the span of the basis);
  optionally also the mobility matrix 𝓜 = ∫ Φ(T, s) B Bᵀ Φᵀ(T, s) ds through the Lyapunov equation
  𝓜̇ = A𝓜 + 𝓜Aᵀ + BBᵀ, 𝓜(0) = 0;
- :func:`endpoint_jacobian` with ``method="autodiff"`` differentiates the integrator itself (``jax.jacfwd``).

Because Runge–Kutta methods commute with linearisation, both give the derivative of the *same* discrete map
and agree to rounding error.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from functools import partial
from typing import Any, Callable, NamedTuple, TypeVar

import jax
import jax.numpy as jnp
import numpy as np
import numpy.typing as npt

from mobman.engine import runge_kutta
from mobman.errors import InputError
from mobman.model.robot import MobileManipulator
from mobman.model.spatial import matmul, matvec
from mobman.model.tasks import Task
from mobman.planning import integrators
from mobman.planning.basis import Basis, Fourier

_Array = TypeVar("_Array", jax.Array, np.ndarray)

DEFAULT_METHOD = "dop853"
MAX_HORIZON = 1e4
"""Longest control horizon T (s): a motion plan, not a mission (the papers normalise T = 1); the controls'
frequencies scale with 1/T and the integration's steps with T, which past this only lose precision."""
DEFAULT_STEPS = 100
"""DOP853 steps over [0, T] for the endpoint map (discretisation error ≲ 1e-14 at the §4 solutions, see
docs/planning.md for the convergence study behind this value)."""
DEFAULT_JACOBIAN_STEPS = 40
"""DOP853 steps of the variational system inside the planners (relative Jacobian error ≤ 1e-4 at the §4 end
points: an inexact Newton step whose contraction factor is about that small, so the planners still converge
to 1e-12; the tolerance is checked on K with ``steps``)."""


@dataclass(frozen=True)
class PlanningSetting:
    """What stays fixed while planning: the robot, its task, the control basis, the horizon T, the integrator.

    Hashable, so the compiled functions take it as a static argument; the start q_p(0) is a dynamic argument
    (a batch of starts is one call). ``method`` is a Runge–Kutta scheme of
    :mod:`~mobman.planning.integrators`;
    ``steps`` discretises the endpoint map K (what the planners drive to the tolerance); ``jacobian_steps``
    the variational system the planners use for their directions.
    """

    robot: MobileManipulator
    basis: Basis = field(default_factory=Fourier)
    horizon: float = 1.0
    steps: int = DEFAULT_STEPS
    task: Task | None = None
    jacobian_steps: int = DEFAULT_JACOBIAN_STEPS
    method: str = DEFAULT_METHOD

    def __post_init__(self) -> None:
        integrators.tableau(self.method)
        if not (isinstance(self.horizon, (int, float)) and 0 < self.horizon <= MAX_HORIZON):
            raise InputError(f"horizon T must be a number in (0, {MAX_HORIZON:g}] s, got {self.horizon!r}")
        for name in ("steps", "jacobian_steps"):
            value = getattr(self, name)
            if not isinstance(value, int) or value < 1 or value % self.basis.pieces:
                raise InputError(
                    f"{name} must be a positive integer multiple of the basis' {self.basis.pieces} pieces, "
                    f"got {value!r}"
                )
        object.__setattr__(self, "horizon", float(self.horizon))
        if self.task is not None:
            self.task.check(self.robot)
        if not self.output.euclidean:
            # the planners (Tchoń et al. 2002, eqs. 9-20) solve K(z) = y_d with y_d − K(z) as the error and
            # ∂K/∂z as its Jacobian: an output whose error is not a difference (a Pose) has no meaning there
            raise InputError(
                f"planning output {', '.join(self.output.names)}: the planners need a task whose value is a "
                "point of Rᵐ (positions, angles), not a pose; plan to a position with Position()"
            )

    @property
    def output(self) -> Task:
        """The task whose value at q(T) is the endpoint (the robot's own task by default)."""
        return self.robot.task if self.task is None else self.task

    @property
    def n_controls(self) -> int:
        """m, number of platform controls."""
        return self.robot.platform.n_eta

    @property
    def n_joints(self) -> int:
        """p, number of arm joint positions x."""
        return self.robot.n_q - self.robot.platform.n_q

    @property
    def n_z(self) -> int:
        """Dimension of the endogenous configuration z = (vec Λ, x)."""
        return self.n_controls * self.basis.size + self.n_joints

    def split(self, z: _Array) -> tuple[_Array, _Array]:
        """z → (Λ of shape (m, N), x)."""
        n = self.n_controls * self.basis.size
        return z[:n].reshape(self.n_controls, self.basis.size), z[n:]

    def with_task(self, task: Task | None) -> "PlanningSetting":
        return replace(self, task=task)

    @property
    def jacobian_setting(self) -> "PlanningSetting":
        """The same setting integrated with ``jacobian_steps`` (what the planners differentiate)."""
        return replace(self, steps=self.jacobian_steps)


class Variational(NamedTuple):
    """Endpoint y = K(z), Jacobian J (r × n_z), C = ∂k/∂q_p, D = ∂k/∂x at q(T), Ξ(T), mobility 𝓜 (or None),
    and the platform state q_p(T)."""

    y: jnp.ndarray
    J: jnp.ndarray
    C: jnp.ndarray
    D: jnp.ndarray
    Xi: jnp.ndarray
    mobility: jnp.ndarray | None
    q_T: jnp.ndarray


def _output_derivatives(
    setting: PlanningSetting, task: Task, q_T: jnp.ndarray, x: jnp.ndarray
) -> tuple[jnp.ndarray, jnp.ndarray]:
    """C = ∂task/∂q_p and D = ∂task/∂x at (q_p(T), x) (eq. 6; C̄, D̄ of eq. 19 for an extension h)."""
    C = jax.jacfwd(lambda q: _output(setting, task, q, x))(q_T)
    D = jax.jacfwd(lambda xx: _output(setting, task, q_T, xx))(x)
    return C, D


def output_jacobian(
    setting: PlanningSetting, task: Task, q_T: jnp.ndarray, Xi: jnp.ndarray, x: jnp.ndarray
) -> jnp.ndarray:
    """J = [C Ξ(T), D] (eq. 8 on the span of the basis; eq. 19's extra rows for an extension task h).
    Ξ(T) does not depend on the task, so one variational integration serves every output."""
    C, D = _output_derivatives(setting, task, q_T, x)
    return jnp.concatenate([C @ Xi, D], axis=1)


def _output(setting: PlanningSetting, task: Task, q_p: jnp.ndarray, x: jnp.ndarray) -> jnp.ndarray:
    q = jnp.concatenate([q_p, x])
    return task.value(setting.robot, q, setting.robot.frames(q))


def _basis_grid(setting: PlanningSetting) -> jnp.ndarray:
    """φ at the stage times t_k + c_i h of every step, shape (steps, stages, N), each step with its own
    control (so a piecewise-constant basis switches exactly at step boundaries)."""
    h = setting.horizon / setting.steps
    t = h * np.arange(setting.steps)
    stages = jnp.asarray(t[:, None] + h * np.asarray(integrators.tableau(setting.method).c)[None, :])
    mid = jnp.asarray(t + 0.5 * h)
    return jax.vmap(lambda st, w: jax.vmap(lambda s: setting.basis.values(s, setting.horizon, w))(st))(
        stages, mid
    )


def _integrate(
    setting: PlanningSetting, rhs: Callable[[Any, jax.Array], Any], state: Any, record: bool = False
) -> tuple[Any, Any]:
    """Fixed-step Runge–Kutta (``setting.method``) of d state/dt = rhs(state, φ(t)) over [0, T], the basis
    values φ at the stage times given to the driver as its input.

    Returns the final state, and the states after every step if ``record``.
    """
    h = setting.horizon / setting.steps
    method = integrators.tableau(setting.method)

    def step(s, k):
        t, phi = k
        new = runge_kutta.step(method, lambda _, y, u: rhs(y, u), s, t, h, inputs=phi)
        return new, (new if record else None)

    return jax.lax.scan(step, state, (jnp.asarray(h * np.arange(setting.steps)), _basis_grid(setting)))


def _control(lam: jnp.ndarray, phi: jnp.ndarray) -> jnp.ndarray:
    """u = Λ φ(t)."""
    return matvec(lam, phi)


def _velocity(setting: PlanningSetting, q: jnp.ndarray, u: jnp.ndarray) -> jnp.ndarray:
    """q̇_p = S_p(q_p) u (eq. 1)."""
    return matvec(setting.robot.platform.S(q), u)


def endpoint_of_task(setting: PlanningSetting, task: Task, z: jax.Array, q0: jax.Array) -> jnp.ndarray:
    """K_{q0,T}(z) (Tchoń et al. 2002, eq. 3) for any output ``task``, one configuration, traceable."""
    lam, x = setting.split(z)
    q_T, _ = _integrate(setting, lambda q, phi: _velocity(setting, q, _control(lam, phi)), q0)
    return _output(setting, task, q_T, x)


@partial(jax.jit, static_argnums=(0,))
def _endpoint(setting, z, q0):
    return endpoint_of_task(setting, setting.output, z, q0)


def endpoint(setting: PlanningSetting, z: npt.ArrayLike, q0: npt.ArrayLike) -> jnp.ndarray:
    """K_{q0,T}(z) = k(q_p(T), x) (eq. 3), shape (..., r) for z of shape (..., n_z) and q0 (..., n_p)."""
    return _batch(_endpoint, setting, z, q0, "(r)")


@partial(jax.jit, static_argnums=(0,))
def _trajectory(setting, z, q0):
    lam, x = setting.split(z)
    _, states = _integrate(setting, lambda q, phi: _velocity(setting, q, _control(lam, phi)), q0, record=True)
    q_p = jnp.concatenate([q0[None], states])
    y = jax.vmap(lambda q: _output(setting, setting.output, q, x))(q_p)
    return q_p, y


def trajectory(
    setting: PlanningSetting, z: npt.ArrayLike, q0: npt.ArrayLike
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Times t_k, platform states q_p(t_k) and task values k(q_p(t_k), x) on the integration grid (for
    plotting)."""
    q_p, y = _trajectory(setting, jnp.asarray(z, float), jnp.asarray(q0, float))
    return np.linspace(0.0, setting.horizon, setting.steps + 1), np.asarray(q_p), np.asarray(y)


def configuration_path(
    setting: PlanningSetting, z: npt.ArrayLike, q0: npt.ArrayLike
) -> tuple[np.ndarray, np.ndarray]:
    """Times t_k and whole configurations q(t_k) = (q_p(t_k), x) of the planned motion (the arm's joints held
    at x, Tchoń et al. §2), on the integration grid."""
    t, q_p, _ = trajectory(setting, z, q0)
    _, x = setting.split(jnp.asarray(z, float))
    return t, np.concatenate([q_p, np.broadcast_to(np.asarray(x), (len(t), setting.n_joints))], axis=1)


def configuration_path_of(setting: PlanningSetting, z: jax.Array, q0: jax.Array) -> jnp.ndarray:
    """The configurations q(t_k) (steps + 1, n_q) of :func:`configuration_path`, traceable (differentiable in
    z)."""
    lam, x = setting.split(z)
    _, states = _integrate(setting, lambda q, phi: _velocity(setting, q, _control(lam, phi)), q0, record=True)
    q_p = jnp.concatenate([q0[None], states])
    return jnp.concatenate([q_p, jnp.broadcast_to(x, (q_p.shape[0], setting.n_joints))], axis=1)


def variational_of_task(
    setting: PlanningSetting, task: Task, z: jax.Array, q0: jax.Array, with_mobility: bool
) -> Variational:
    """Endpoint, Jacobian (Tchoń et al. 2002, eqs. 5–8) and optionally 𝓜 for any output ``task``, traceable."""
    lam, x = setting.split(z)
    n_p = q0.shape[0]
    platform = setting.robot.platform

    def rhs(state, phi):
        q, xi, mob = state
        u = _control(lam, phi)
        A = jax.jacfwd(lambda s: _velocity(setting, s, u))(q)
        B = platform.S(q)
        d_xi = matmul(A, xi) + (B[:, :, None] * phi[None, None, :]).reshape(n_p, -1)  # B (I_m ⊗ φᵀ)
        d_mob = matmul(A, mob) + matmul(mob, A.T) + matmul(B, B.T) if with_mobility else None
        return _velocity(setting, q, u), d_xi, d_mob

    # without 𝓜 its slot is None: nothing integrated, no slope buffer
    start = (
        q0,
        jnp.zeros((n_p, z.shape[0] - setting.n_joints)),
        jnp.zeros((n_p, n_p)) if with_mobility else None,
    )
    (q_T, xi, mob), _ = _integrate(setting, rhs, start)
    y = _output(setting, task, q_T, x)
    C, D = _output_derivatives(setting, task, q_T, x)
    return Variational(y, jnp.concatenate([C @ xi, D], axis=1), C, D, xi, mob, q_T)


@partial(jax.jit, static_argnums=(0, 3))
def _variational_jit(setting, z, q0, with_mobility):
    return variational_of_task(setting, setting.output, z, q0, with_mobility)


def variational(
    setting: PlanningSetting, z: npt.ArrayLike, q0: npt.ArrayLike, with_mobility: bool = True
) -> Variational:
    """Endpoint, Jacobian (eqs. 5–8) and, if asked, the mobility matrix 𝓜 from the variational system."""
    return _variational_jit(setting, jnp.asarray(z, float), jnp.asarray(q0, float), with_mobility)


@partial(jax.jit, static_argnums=(0,))
def _autodiff_jacobian(setting, z, q0):
    return jax.jacfwd(_endpoint, argnums=1)(setting, z, q0)


def endpoint_jacobian(
    setting: PlanningSetting, z: npt.ArrayLike, q0: npt.ArrayLike, method: str = "variational"
) -> jnp.ndarray:
    """Analytic Jacobian J_{q0,T}(z), shape (r, n_z): ``"variational"`` (eqs. 5–8) or ``"autodiff"``."""
    z, q0 = jnp.asarray(z, float), jnp.asarray(q0, float)
    if method == "variational":
        return _variational_jit(setting, z, q0, False).J
    if method == "autodiff":
        return _autodiff_jacobian(setting, z, q0)
    raise InputError(f"method must be 'variational' or 'autodiff', got {method!r}")


@partial(jax.jit, static_argnums=(0, 1))
def _extended_jacobian(setting, extension, z, q0):
    v = variational_of_task(setting, setting.output, z, q0, False)
    _, x = setting.split(z)
    return jnp.concatenate([v.J, output_jacobian(setting, extension, v.q_T, v.Xi, x)])


def extended_jacobian(
    setting: PlanningSetting, extension: Task, z: npt.ArrayLike, q0: npt.ArrayLike
) -> jnp.ndarray:
    """Extended Jacobian J^E = [J; J̄] (eq. 19), shape (r + s, n_z): the rows of the output, then those of the
    output extension h (a task of dimension s), at z and the start q0."""
    return _extended_jacobian(setting, extension, jnp.asarray(z, float), jnp.asarray(q0, float))


def mobility_matrix(setting: PlanningSetting, z: npt.ArrayLike, q0: npt.ArrayLike) -> jnp.ndarray:
    """Mobility matrix 𝓜_{q0,T}(u) of the platform: the state reachability Gramian over all of L²[0, T]."""
    mobility = variational(setting, z, q0).mobility
    assert mobility is not None  # computed: with_mobility is True
    return mobility


@partial(jax.jit, static_argnums=(0, 3))
def _dexterity_matrix(setting, z, q0, parametric):
    v = variational_of_task(setting, setting.output, z, q0, not parametric)
    if v.mobility is None:
        return v.J @ v.J.T
    return v.C @ v.mobility @ v.C.T + v.D @ v.D.T


def dexterity_matrix(
    setting: PlanningSetting, z: npt.ArrayLike, q0: npt.ArrayLike, parametric: bool = False
) -> jnp.ndarray:
    """Dexterity matrix, shape (..., r, r) for batches of z and q0.

    parametric=False: the paper's 𝒟 = C𝓜Cᵀ + DDᵀ (eq. 11), controls ranging over all of L²[0, T];
    parametric=True: J Jᵀ of the finite parametrisation (the Gram matrix the planners invert). Since the
    basis is orthonormal, C Ξ Ξᵀ Cᵀ is 𝒟's first term with 𝓜 replaced by its compression to the span of the
    basis, so J Jᵀ ≼ 𝒟 (Bessel's inequality), with equality only if the basis spans every relevant control.
    """
    return _batch(lambda s, zz, qq: _dexterity_matrix(s, zz, qq, parametric), setting, z, q0, "(r,r)")


def dexterity(
    setting: PlanningSetting, z: npt.ArrayLike, q0: npt.ArrayLike, parametric: bool = False
) -> float | np.ndarray:
    """Dexterity d = √det 𝒟 (eq. 12) (parametric=True: √det(J Jᵀ)); positive iff the configuration is regular.

    A float for one configuration, an array for a batch.
    """
    det = np.linalg.det(np.asarray(dexterity_matrix(setting, z, q0, parametric)))
    d = np.sqrt(np.maximum(det, 0.0))
    return float(d) if d.ndim == 0 else d


def is_regular(setting: PlanningSetting, z: npt.ArrayLike, q0: npt.ArrayLike, rtol: float = 1e-10) -> bool:
    """Whether J is surjective: the smallest eigenvalue of 𝒟 exceeds rtol times the largest."""
    w = np.linalg.eigvalsh(np.asarray(dexterity_matrix(setting, z, q0)))
    return bool(w[0] > rtol * max(w[-1], 1e-300))


def _batch(fn, setting, z, q0, core_out):
    z, q0 = jnp.asarray(z, float), jnp.asarray(q0, float)
    return jnp.vectorize(partial(fn, setting), signature=f"(z),(n)->{core_out}")(z, q0)
