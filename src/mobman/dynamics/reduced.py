"""Reduced (constraint-free) equations of motion in the quasi-velocities η, q̇ = S(q) η (Yamamoto eq. 10–16).

Substituting q̇ = S η, q̈ = S η̇ + Ṡ η into M q̈ + c + g = E τ + Gᵀ λ and multiplying by Sᵀ (Sᵀ Gᵀ = 0)
removes the constraint forces:

    P(q) η̇ + b(q, η) = B(q) τ,   P = Sᵀ M S,   b = Sᵀ M Ṡ η + Sᵀ (c + g),   B = Sᵀ E      (eq. 15–16)

(Yamamoto's P ẋ = ξ + Q τ with ξ = −b, Q = B). B is square and invertible: one actuator per quasi-velocity.
P is formed from M (:mod:`mobman.dynamics.equations`); b is the Newton–Euler generalized force of the motion
q̇ = S η, q̈ = Ṡ η projected by Sᵀ — equal to Sᵀ (M Ṡ η + c + g) with c, g from the Lagrangian (tested), and
about 2.5 times cheaper to evaluate.

- :func:`reduced_mass_matrix`, :func:`reduced_bias`, :func:`input_matrix`
- :func:`inverse_dynamics` τ = B⁻¹ (P η̇ + b) along a trajectory (batched over time)
- :func:`forward_dynamics` η̇ = P⁻¹ (B τ − b)
- :func:`constraint_forces` λ of the full equations for a reduced solution, and the residual that must vanish
- :func:`energy` ½ ηᵀ P η + V
"""

from __future__ import annotations

import jax
import jax.numpy as jnp
import numpy as np
import numpy.typing as npt

from mobman.checks import all_finite
from mobman.dynamics import equations as eq
from mobman.dynamics.inertia import DynamicModel
from mobman.engine.batched import batched, traced
from mobman.errors import InputError
from mobman.model import spatial


def s_dot_eta(model: DynamicModel, q: jnp.ndarray, eta: jnp.ndarray) -> jnp.ndarray:
    """Ṡ η with Ṡ = ∂S/∂q · S η (forward-mode autodiff): [Ṡ_p η_p, 0], only the platform's block of S
    depends on q."""
    platform = model.robot.platform
    q_p, eta_p = q[: platform.n_q], eta[: platform.n_eta]
    _, s_p_dot = jax.jvp(platform.S, (q_p,), (spatial.matvec(platform.S(q_p), eta_p),))
    return jnp.concatenate([spatial.matvec(s_p_dot, eta_p), jnp.zeros(q.shape[0] - platform.n_q, q.dtype)])


def reduced_mass_matrix_one(
    model: DynamicModel, q: jax.Array, payload_mass: float | None = None
) -> jnp.ndarray:
    """P = Sᵀ M S: the composite-rigid-body algorithm with the platform's motion subspace taken in the
    quasi-velocities, S_p(q_p) (:func:`mobman.dynamics.equations.mass_matrix_one`)."""
    platform = model.robot.platform
    return eq.mass_matrix_one(model, q, payload_mass, platform_basis=platform.S(q[: platform.n_q]))


def reduced_bias_one(
    model: DynamicModel, q: jax.Array, eta: jax.Array, payload_mass: float | None = None
) -> jnp.ndarray:
    """b = Sᵀ (M Ṡ η + c + g): the generalized force of the motion q̇ = S η, q̈ = Ṡ η (η̇ = 0), by Newton–Euler
    (:func:`mobman.dynamics.equations.generalized_force_one`; equal to the Lagrange form, see the tests)."""
    robot = model.robot
    force = eq.generalized_force_one(model, q, robot.q_dot(q, eta), s_dot_eta(model, q, eta), payload_mass)
    return robot.apply_S(force[None, :], q)[0]


def input_matrix_one(model: DynamicModel, q: jax.Array) -> jnp.ndarray:
    """B = Sᵀ E (Yamamoto eq. 16), by blocks: S = diag(S_p, 1) and E = diag(E_p, C_1ᵀ, C_2ᵀ, …)
    (:func:`mobman.dynamics.equations.actuation_matrix_one`) give B = diag(S_pᵀ E_p, C_1ᵀ, C_2ᵀ, …), only
    its platform block depending on q (equal to Sᵀ E, tests). Formed row by row, so that a
    one-configuration program returns it in pieces (:func:`mobman.engine.batched.sequential`)."""
    robot = model.robot
    q_p = q[: robot.n_platform]
    platform = spatial.matmul_expanded(robot.platform.S(q_p).T, robot.platform.actuator_rows(q_p).T)
    arms = eq.arm_actuation(robot)
    k, a_p = platform.shape
    pad = jnp.zeros(arms.shape[1], q.dtype)
    rows = [jnp.concatenate([platform[r], pad]) for r in range(k)]
    rows += [jnp.asarray(np.concatenate([np.zeros(a_p), row]), q.dtype) for row in arms]
    return jnp.stack(rows)


def inverse_dynamics_one(
    model: DynamicModel, q: jax.Array, eta: jax.Array, eta_dot: jax.Array, payload_mass: float | None = None
) -> jnp.ndarray:
    lhs = reduced_mass_matrix_one(model, q, payload_mass) @ eta_dot + reduced_bias_one(
        model, q, eta, payload_mass
    )
    return jnp.linalg.solve(input_matrix_one(model, q), lhs)


def forward_dynamics_one(model: DynamicModel, q: jax.Array, eta: jax.Array, tau: jax.Array) -> jnp.ndarray:
    rhs = input_matrix_one(model, q) @ tau - reduced_bias_one(model, q, eta)
    return jnp.linalg.solve(reduced_mass_matrix_one(model, q), rhs)


def energy_one(model: DynamicModel, q: jax.Array, eta: jax.Array) -> jnp.ndarray:
    return 0.5 * eta @ reduced_mass_matrix_one(model, q) @ eta + eq.potential_energy_one(model, q)


def constraint_forces_one(
    model: DynamicModel, q: jax.Array, eta: jax.Array, eta_dot: jax.Array, tau: jax.Array
) -> tuple[jax.Array, jax.Array]:
    """λ minimising |M q̈ + c + g − E τ − Gᵀ λ| and the residual left (zero when the reduced equations hold)."""
    robot = model.robot
    s = robot.S(q)
    q_ddot = s @ eta_dot + s_dot_eta(model, q, eta)
    lhs = (
        eq.mass_matrix_one(model, q) @ q_ddot
        + eq.bias_one(model, q, s @ eta)
        - eq.actuation_matrix_one(model, q) @ tau
    )
    g_t = robot.constraints(q).T
    lam = jnp.linalg.lstsq(g_t, lhs)[0] if g_t.shape[1] else jnp.zeros(0, q.dtype)
    return lam, lhs - g_t @ lam


# --- batched public API ---------------------------------------------------------------------------


@batched({1: 1}, static=(0,))
def _reduced_mass(model, q):
    return reduced_mass_matrix_one(model, q)


def reduced_terms_one(
    model: DynamicModel, q: jax.Array, eta: jax.Array, payload_mass: float | None = None
) -> tuple[jax.Array, jax.Array, jax.Array]:
    """(P, b, B) for one state: everything the reduced equations need."""
    return (
        reduced_mass_matrix_one(model, q, payload_mass),
        reduced_bias_one(model, q, eta, payload_mass),
        input_matrix_one(model, q),
    )


@batched({1: 1, 2: 1}, static=(0,))
def _terms(model, q, eta):
    return reduced_terms_one(model, q, eta)


@batched({1: 1, 2: 1}, static=(0,))
def _bias(model, q, eta):
    return reduced_bias_one(model, q, eta)


@batched({1: 1}, static=(0,))
def _input(model, q):
    return input_matrix_one(model, q)


@jax.jit
def _solve_inverse(p, b, b_mat, eta_dot):
    return jnp.linalg.solve(b_mat, p @ eta_dot[..., None] + b[..., None])[..., 0]


@jax.jit
def _solve_forward(p, b, b_mat, tau):
    return jnp.linalg.solve(p, b_mat @ tau[..., None] - b[..., None])[..., 0]


@batched({1: 1, 2: 1}, static=(0,))
def _energy(model, q, eta):
    return energy_one(model, q, eta)


@batched({1: 1, 2: 1, 3: 1, 4: 1}, static=(0,))
def _constraint_forces(model, q, eta, eta_dot, tau):
    return constraint_forces_one(model, q, eta, eta_dot, tau)


def validated_eta(model: DynamicModel, value: npt.ArrayLike, name: str) -> np.ndarray | jax.Array:
    """A quasi-velocity-sized array (η, η̇ or τ) checked for shape and finiteness; errors name ``name``. A
    user's traced value (the public functions inside their own ``jit``, ``grad`` or ``vmap``) passes as it is;
    mobman's own traced code calls the ``_one`` functions."""
    if traced(value):
        return value
    on_device = isinstance(value, jax.Array) and any(d.platform != "cpu" for d in value.devices())
    # host values are checked by NumPy in place and passed on as NumPy arrays: an eager jnp test (two
    # dispatches and a device-to-host wait) or a device_put costs more than a one-configuration compiled call
    arr = value if on_device and isinstance(value, jax.Array) else np.asarray(value, dtype=float)
    n = model.robot.n_eta
    if arr.ndim == 0 or arr.shape[-1] != n:
        raise InputError(
            f"{name} must have {n} components ({', '.join(model.robot.control_names)}), "
            f"got shape {tuple(arr.shape)}"
        )
    finite = bool(jnp.all(jnp.isfinite(arr))) if on_device else all_finite(np.asarray(arr))
    if not finite:
        raise InputError(f"{name} contains NaN or infinite values")
    return arr if arr.dtype == jnp.float64 else arr.astype(jnp.float64)


def reduced_mass_matrix(model: DynamicModel, q: npt.ArrayLike) -> jnp.ndarray:
    """P(q) = Sᵀ M S, shape (..., n_eta, n_eta) (Yamamoto eq. 15)."""
    return _reduced_mass(model, eq.validated_q(model, q))


def reduced_bias(model: DynamicModel, q: npt.ArrayLike, eta: npt.ArrayLike) -> jnp.ndarray:
    """b(q, η) = Sᵀ M Ṡ η + Sᵀ (c + g), shape (..., n_eta) (−ξ of Yamamoto eq. 16)."""
    return _bias(model, eq.validated_q(model, q), validated_eta(model, eta, "eta"))


def input_matrix(model: DynamicModel, q: npt.ArrayLike) -> jnp.ndarray:
    """B(q) = Sᵀ E, shape (..., n_eta, n_actuators) (Yamamoto's Q, eq. 16)."""
    return _input(model, eq.validated_q(model, q))


def inverse_dynamics(
    model: DynamicModel, q: npt.ArrayLike, eta: npt.ArrayLike, eta_dot: npt.ArrayLike
) -> jnp.ndarray:
    """Actuator torques τ = B⁻¹ (P η̇ + b), shape (..., n_actuators); batched over time or configurations."""
    eta_dot = validated_eta(model, eta_dot, "eta_dot")
    return _solve_inverse(*_terms(model, eq.validated_q(model, q), validated_eta(model, eta, "eta")), eta_dot)


def forward_dynamics(
    model: DynamicModel, q: npt.ArrayLike, eta: npt.ArrayLike, tau: npt.ArrayLike
) -> jnp.ndarray:
    """η̇ = P⁻¹ (B τ − b), shape (..., n_eta)."""
    tau = validated_eta(model, tau, "tau")
    return _solve_forward(*_terms(model, eq.validated_q(model, q), validated_eta(model, eta, "eta")), tau)


def reduced_terms(
    model: DynamicModel, q: npt.ArrayLike, eta: npt.ArrayLike
) -> tuple[jax.Array, jax.Array, jax.Array]:
    """(P, b, B) at once (one compiled evaluation), shapes (..., k, k), (..., k), (..., k, a)."""
    return _terms(model, eq.validated_q(model, q), validated_eta(model, eta, "eta"))


def energy(model: DynamicModel, q: npt.ArrayLike, eta: npt.ArrayLike) -> jnp.ndarray:
    """Total mechanical energy ½ ηᵀ P η + V(q), shape (...)."""
    return _energy(model, eq.validated_q(model, q), validated_eta(model, eta, "eta"))


def constraint_forces(
    model: DynamicModel, q: npt.ArrayLike, eta: npt.ArrayLike, eta_dot: npt.ArrayLike, tau: npt.ArrayLike
) -> tuple[jax.Array, jax.Array]:
    """(λ, residual): the constraint multipliers of the full equations M q̈ + c + g = E τ + Gᵀ λ for a motion
    of the reduced equations, and the part of M q̈ + c + g − E τ outside the range of Gᵀ (zero when the
    reduced equations hold: the constraint forces drop out of them exactly)."""
    return _constraint_forces(
        model,
        eq.validated_q(model, q),
        validated_eta(model, eta, "eta"),
        validated_eta(model, eta_dot, "eta_dot"),
        validated_eta(model, tau, "tau"),
    )


__all__ = [
    "constraint_forces",
    "energy",
    "forward_dynamics",
    "input_matrix",
    "inverse_dynamics",
    "reduced_bias",
    "reduced_mass_matrix",
    "reduced_terms",
]
