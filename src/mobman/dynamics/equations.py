"""Equations of motion M(q) q̈ + c(q, q̇) + g(q) = E(q) τ + G(q)ᵀ λ in the coordinates q = (x, y, θ, q_a…).

- :func:`mass_matrix` M(q) = Σ_bodies m J_vᵀ J_v + J_ωᵀ R I Rᵀ J_ω, composed from the linear and angular
  geometric Jacobians of every body's centre of mass (``robot.point_jacobian``): platform body, driving
  wheels (mass, I_m about a diameter, I_w about the axle), arm links, payload. The wheel spin enters through
  φ̇_r,l = (ẋ cos θ + ẏ sin θ ± b θ̇)/r: this equals the wheel speed wherever the wheel rolls, so on the
  constraint manifold (and hence in the reduced equations) it is exactly Yamamoto & Yun's model with the
  wheel angles as coordinates (their eq. 3–12).
- :func:`bias` c + g: c by autodiff of M in Christoffel form, c_i = Σ_jk Γ_ijk q̇_j q̇_k with
  Γ_ijk = ½(∂M_ij/∂q_k + ∂M_ik/∂q_j − ∂M_jk/∂q_i), i.e. c = Ṁ q̇ − ½ ∂(q̇ᵀ M q̇)/∂q; g = ∂V/∂q with
  V(q) = −Σ m gravityᵀ p_com. Nothing is derived by hand.
- :func:`coriolis_matrix` C(q, q̇) with c = C q̇ and Ṁ − 2C skew-symmetric.
- :func:`actuation_matrix` E(q): generalized forces of the actuator torques τ = (τ_wheel_r, τ_wheel_l,
  τ_joints…) (wheel torque τ does the work τ δφ; joint torques act on the joint motion variables, so a coupled
  arm gets Cᵀ τ). Platforms other than a differential drive are actuated directly on their quasi-velocities:
  E_p = S_p (S_pᵀ S_p)⁻¹, so that S_pᵀ E_p = I.

Functions here are batched over the leading dimensions of ``q`` (and ``q_dot``) and compiled with the model
static; the ``*_one`` kernels work on one configuration (for use inside other compiled code).
"""

from __future__ import annotations

from functools import partial
from typing import NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from mobman.dynamics.inertia import DynamicModel
from mobman.errors import InputError
from mobman.model.platform import DifferentialDrive
from mobman.model.robot import Frames


class Body(NamedTuple):
    """One rigid body at a configuration: mass, world centre of mass, world rotation of its inertia frame,
    its inertia about the centre of mass in that frame, and what moves it (arm index or None, last joint)."""

    mass: float
    point: jnp.ndarray
    rotation: jnp.ndarray
    inertia: np.ndarray
    arm: int | None
    upto: int


def bodies(model: DynamicModel, frames: Frames, payload_mass: float | None = None) -> list[Body]:
    """Every massive body of the model at the configuration whose ``frames`` are given.

    ``payload_mass`` overrides the payload's mass (its inertia scaled in proportion), e.g. 1 for the
    per-kilogram load terms of :mod:`mobman.dynamics.load_capacity`.
    """
    robot = model.robot
    r_p, p_p = frames.platform
    result = [
        Body(
            model.body.mass,
            p_p + r_p @ np.asarray(model.body.com),
            r_p,
            np.diag([0.0, 0.0, model.body.inertia_z]),
            None,
            0,
        )
    ]
    if isinstance(robot.platform, DifferentialDrive) and model.wheel is not None:
        b, r, w = robot.platform.half_track, robot.platform.wheel_radius, model.wheel
        for side in (1.0, -1.0):
            centre = p_p + r_p @ np.array([0.0, side * b, r])
            result.append(Body(w.mass, centre, r_p, np.diag([w.I_m, 0.0, w.I_m]), None, 0))
    for i, arm in enumerate(robot.arms):
        rs, ps = frames.links[i]
        for j, joint in enumerate(arm.joints):
            inertial = joint.inertial
            point = ps[j] + rs[j] @ np.asarray(inertial.com)
            result.append(Body(inertial.mass, point, rs[j], inertial.inertia_matrix, i, j))
    payload = model.payload
    if payload is not None:
        if payload_mass is not None:
            payload = payload.scaled(payload_mass)
        if payload.mass > 0:
            rs, ps = frames.links[payload.arm]
            n = robot.arms[payload.arm].n_joints
            point = ps[n] + rs[n] @ np.asarray(payload.com)
            result.append(
                Body(
                    payload.mass, point, rs[n], np.asarray(payload.inertia).reshape(3, 3), payload.arm, n - 1
                )
            )
    return result


def wheel_rows(model: DynamicModel, q: jnp.ndarray) -> jnp.ndarray:
    """Rows a_r, a_l (2 × n_q) with φ̇_r,l = a · q̇ = (ẋ cos θ + ẏ sin θ ± b θ̇)/r (Yamamoto eq. 4–6)."""
    robot = model.robot
    b, r = robot.platform.half_track, robot.platform.wheel_radius
    c, s = jnp.cos(q[2]), jnp.sin(q[2])
    rows = [
        jnp.concatenate(
            [jnp.stack([c, s, side * b * jnp.ones_like(c)]) / r, jnp.zeros(robot.n_q - 3, dtype=q.dtype)]
        )
        for side in (1.0, -1.0)
    ]
    return jnp.stack(rows)


def mass_matrix_one(model: DynamicModel, q: jnp.ndarray, payload_mass: float | None = None) -> jnp.ndarray:
    """M(q) for one configuration (n_q × n_q): Σ m J_vᵀ J_v + J_ωᵀ (R I Rᵀ) J_ω over the bodies (+ wheel spin)."""
    robot = model.robot
    frames = robot.frames(q)
    parts = bodies(model, frames, payload_mass)
    groups = sorted({body.arm for body in parts}, key=lambda a: -1 if a is None else a)
    parts = [body for arm in groups for body in parts if body.arm == arm]
    j_v, j_w = [], []
    for arm in groups:  # one vmapped point_jacobian per chain: a small graph, fast to compile
        members = [body for body in parts if body.arm == arm]
        points = jnp.stack([body.point for body in members])
        upto = jnp.array([body.upto for body in members])
        lin, ang = jax.vmap(lambda p, u, arm=arm: robot.point_jacobian(q, frames, p, arm, u))(points, upto)
        j_v.append(lin)
        j_w.append(ang)
    j_v, j_w = jnp.concatenate(j_v), jnp.concatenate(j_w)
    masses = np.array([body.mass for body in parts])
    rotations = jnp.stack([jnp.broadcast_to(body.rotation, (3, 3)) for body in parts])
    inertia_world = rotations @ np.stack([body.inertia for body in parts]) @ jnp.swapaxes(rotations, 1, 2)
    m = jnp.einsum("b,bin,bim->nm", masses, j_v, j_v) + jnp.einsum("bin,bij,bjm->nm", j_w, inertia_world, j_w)
    if isinstance(robot.platform, DifferentialDrive) and model.wheel is not None:
        a = wheel_rows(model, q)
        m = m + model.wheel.I_w * a.T @ a
    return m


def potential_energy_one(
    model: DynamicModel, q: jnp.ndarray, payload_mass: float | None = None
) -> jnp.ndarray:
    """V(q) = −Σ m gravityᵀ p_com for one configuration."""
    gravity = np.asarray(model.gravity)
    return -sum(
        body.mass * (gravity @ body.point) for body in bodies(model, model.robot.frames(q), payload_mass)
    )


def gravity_one(model: DynamicModel, q: jnp.ndarray, payload_mass: float | None = None) -> jnp.ndarray:
    """g(q) = ∂V/∂q (autodiff)."""
    return jax.grad(partial(potential_energy_one, model, payload_mass=payload_mass))(q)


def velocity_terms_one(model: DynamicModel, q, q_dot, payload_mass: float | None = None) -> jnp.ndarray:
    """c(q, q̇) = Ṁ q̇ − ∂/∂q (½ q̇ᵀ M(q) q̇) (Lagrange's equations).

    Ṁ = (∂M/∂q) q̇ by one forward-mode jvp and the kinetic-energy gradient by reverse mode: directional
    derivatives only, several times cheaper than forming the whole ∂M/∂q. Equal to Σ_jk Γ_ijk q̇_j q̇_k, the
    Christoffel form of :func:`coriolis_matrix_one` (checked against it and against Pinocchio in the tests).
    """
    mass = partial(mass_matrix_one, model, payload_mass=payload_mass)
    m_dot = jax.jvp(mass, (q,), (q_dot,))[1]
    kinetic_gradient = jax.grad(lambda x: 0.5 * q_dot @ mass(x) @ q_dot)(q)
    return m_dot @ q_dot - kinetic_gradient


def bias_one(model: DynamicModel, q, q_dot, payload_mass: float | None = None) -> jnp.ndarray:
    """c(q, q̇) + g(q) for one configuration."""
    return velocity_terms_one(model, q, q_dot, payload_mass) + gravity_one(model, q, payload_mass)


def coriolis_matrix_one(model: DynamicModel, q, q_dot) -> jnp.ndarray:
    """C_ij = Σ_k Γ_ijk q̇_k with the Christoffel symbols of the first kind of M (jacfwd of M)."""
    dm = jax.jacfwd(partial(mass_matrix_one, model))(q)  # dm[i, j, k] = ∂M_ij/∂q_k
    return 0.5 * (dm @ q_dot + jnp.einsum("ikj,k->ij", dm, q_dot) - jnp.einsum("jki,k->ij", dm, q_dot))


def actuation_matrix_one(model: DynamicModel, q: jnp.ndarray) -> jnp.ndarray:
    """E(q) (n_q × n_actuators): generalized forces E τ of the actuator torques."""
    robot = model.robot
    n_p = robot.n_platform
    if isinstance(robot.platform, DifferentialDrive):
        e_p = wheel_rows(model, q)[:, :n_p].T
    else:
        s_p = robot.platform.S(q[:n_p])
        e_p = s_p @ jnp.linalg.inv(s_p.T @ s_p)
    blocks = [jnp.concatenate([e_p, jnp.zeros((robot.n_q - n_p, e_p.shape[1]), q.dtype)], axis=0)]
    for i, arm in enumerate(robot.arms):
        col = np.zeros((robot.n_q, arm.n_joints))
        col[robot.arm_slice(i), :] = arm.coupling_matrix.T
        blocks.append(jnp.asarray(col, dtype=q.dtype))
    return jnp.concatenate(blocks, axis=1)


# --- batched public API --------------------------------------------------------------------------


def _vectorized(fn, signature: str):
    return jnp.vectorize(fn, signature=signature)


@partial(jax.jit, static_argnums=(0,))
def _mass(model, q):
    return _vectorized(partial(mass_matrix_one, model), "(n)->(n,n)")(q)


@partial(jax.jit, static_argnums=(0,))
def _bias(model, q, q_dot):
    return _vectorized(partial(bias_one, model), "(n),(n)->(n)")(q, q_dot)


@partial(jax.jit, static_argnums=(0,))
def _gravity(model, q):
    return _vectorized(partial(gravity_one, model), "(n)->(n)")(q)


@partial(jax.jit, static_argnums=(0,))
def _potential(model, q):
    return _vectorized(partial(potential_energy_one, model), "(n)->()")(q)


@partial(jax.jit, static_argnums=(0,))
def _coriolis(model, q, q_dot):
    return _vectorized(partial(coriolis_matrix_one, model), "(n),(n)->(n,n)")(q, q_dot)


@partial(jax.jit, static_argnums=(0,))
def _actuation(model, q):
    return _vectorized(partial(actuation_matrix_one, model), "(n)->(n,a)")(q)


def _q(model: DynamicModel, q):
    if isinstance(q, jax.core.Tracer):
        return q
    return jnp.asarray(model.robot.validate_q(q))


def _q_dot(model: DynamicModel, q_dot):
    if isinstance(q_dot, jax.core.Tracer):
        return q_dot
    return jnp.asarray(model.robot.validate_q(q_dot))


def mass_matrix(model: DynamicModel, q) -> jnp.ndarray:
    """M(q), shape (..., n_q, n_q), symmetric positive definite."""
    return _mass(model, _q(model, q))


def bias(model: DynamicModel, q, q_dot) -> jnp.ndarray:
    """c(q, q̇) + g(q), shape (..., n_q)."""
    return _bias(model, _q(model, q), _q_dot(model, q_dot))


def gravity_vector(model: DynamicModel, q) -> jnp.ndarray:
    """g(q) = ∂V/∂q, shape (..., n_q)."""
    return _gravity(model, _q(model, q))


def potential_energy(model: DynamicModel, q) -> jnp.ndarray:
    """V(q), shape (...)."""
    return _potential(model, _q(model, q))


def coriolis_matrix(model: DynamicModel, q, q_dot) -> jnp.ndarray:
    """C(q, q̇) (Christoffel form), shape (..., n_q, n_q); c = C q̇ and Ṁ − 2C is skew-symmetric."""
    return _coriolis(model, _q(model, q), _q_dot(model, q_dot))


def actuation_matrix(model: DynamicModel, q) -> jnp.ndarray:
    """E(q), shape (..., n_q, n_actuators)."""
    return _actuation(model, _q(model, q))


def wheel_angle_rates(model: DynamicModel, q, q_dot) -> jnp.ndarray:
    """(θ̇_r, θ̇_l) of a differential drive for (q, q̇): the conversion to Yamamoto's wheel-angle coordinates
    q_v = (x_o, y_o, θ_r, θ_l), whose heading is ϕ = c (θ_r − θ_l), c = r/(2b) (eq. 4)."""
    if not isinstance(model.robot.platform, DifferentialDrive):
        raise InputError("wheel_angle_rates: the platform must be a DifferentialDrive")
    rows = jnp.vectorize(partial(wheel_rows, model), signature="(n)->(w,n)")(_q(model, q))
    return jnp.einsum("...wn,...n->...w", rows, _q_dot(model, q_dot))


__all__ = [
    "Body",
    "actuation_matrix",
    "bias",
    "bodies",
    "coriolis_matrix",
    "gravity_vector",
    "mass_matrix",
    "potential_energy",
    "wheel_angle_rates",
]
