"""Equations of motion M(q) q̈ + c(q, q̇) + g(q) = E(q) τ + G(q)ᵀ λ in the coordinates q = (x, y, θ, q_a…).

- :func:`mass_matrix` M(q) by the composite-rigid-body algorithm and :func:`generalized_force`
  M q̈ + c + g by the recursive Newton–Euler algorithm (:mod:`mobman.dynamics.recursive`, Featherstone
  ch. 6 and 5) on the tree of every massive body (:func:`bodies`): platform body, driving wheels (mass, I_m
  about a diameter), arm links, payload; :func:`bias` c + g and :func:`gravity_vector` g are the same
  recursion at q̈ = 0 and at rest. The wheel spin (I_w about the axle) enters through
  φ̇_r,l = (ẋ cos θ + ẏ sin θ ± b θ̇)/r: this equals the wheel speed wherever the wheel rolls, so on the
  constraint manifold (and hence in the reduced equations) it is exactly Yamamoto & Yun's model with the
  wheel angles as coordinates (their eq. 3–12).
- The definitions these are tested against: M(q) = Σ_bodies m J_vᵀ J_v + J_ωᵀ R I Rᵀ J_ω over the bodies'
  centre-of-mass Jacobians (:func:`mass_matrix_definition_one`), and c + g by autodiff of that M and of
  V(q) = −Σ m gravityᵀ p_com in Lagrange's form c = Ṁ q̇ − ½ ∂(q̇ᵀ M q̇)/∂q, g = ∂V/∂q
  (:func:`lagrange_bias_one`); :func:`body_forces_one` the Newton–Euler force of each body by virtual
  work (the load capacity's per-body split).
- :func:`coriolis_matrix` C(q, q̇) with c = C q̇ and Ṁ − 2C skew-symmetric (Christoffel symbols of M).
- :func:`actuation_matrix` E(q): generalized forces of the actuator torques τ = (τ_platform…, τ_joints…)
  (an actuator torque τ does the work τ δu, u = A_p(q) q̇ the platform's actuator rows
  ``platform.actuator_rows``: the wheel rows of a differential drive or a skid-steer; joint torques act on the
  joint motion variables, so a coupled arm gets Cᵀ τ). Platforms without driven wheels are actuated directly
  on their quasi-velocities: E_p = A_pᵀ = S_p (S_pᵀ S_p)⁻¹, so that S_pᵀ E_p = I.

Functions here are batched over the leading dimensions of ``q`` (and ``q_dot``) and compiled with the model
static; the ``*_one`` kernels work on one configuration (for use inside other compiled code).
"""

from __future__ import annotations

from functools import partial
from typing import NamedTuple

import jax
import jax.numpy as jnp
import numpy as np
import numpy.typing as npt

from mobman import kinematics
from mobman.dynamics import recursive
from mobman.dynamics.inertia import DynamicModel
from mobman.engine.batched import batched
from mobman.errors import InputError
from mobman.model import spatial
from mobman.model.inertial import Wheel
from mobman.model.platforms import WheelSite
from mobman.model.robot import Frames, MobileManipulator


class Body(NamedTuple):
    """One rigid body at a configuration: mass, world centre of mass, world rotation of its inertia frame,
    its inertia about the centre of mass in that frame, what moves it (arm index or None, last joint) and
    whether it is the payload."""

    mass: float
    point: jnp.ndarray | np.ndarray
    rotation: jnp.ndarray
    inertia: np.ndarray
    arm: int | None
    upto: int
    payload: bool = False


def bodies(model: DynamicModel, frames: Frames, payload_mass: float | None = None) -> list[Body]:
    """Every massive body of the model at the configuration whose ``frames`` are given.

    ``payload_mass`` overrides the payload's mass (its inertia scaled in proportion), e.g. 1 for the
    per-kilogram load terms of :mod:`mobman.dynamics.load_capacity`.
    """
    robot = model.robot
    r_p, p_p = frames.platform
    result = [
        Body(part.mass, p_p + spatial.matvec_constant(r_p, part.centre), r_p, part.inertia, None, 0)
        for part in robot.platform.inertia_bodies(model.body, model.wheel)
    ]
    for i, arm in enumerate(robot.arms):
        rs, ps = frames.links[i]
        for j, joint in enumerate(arm.joints):
            inertial = joint.inertial
            assert inertial is not None  # DynamicModel checks that every joint has one
            point = ps[j] + spatial.matvec_constant(rs[j], inertial.com)
            result.append(Body(inertial.mass, point, rs[j], inertial.inertia_matrix, i, j))
    payload = model.payload
    if payload is not None:
        if payload_mass is not None:
            payload = payload.scaled(payload_mass)
        if payload.mass > 0:
            rs, ps = frames.links[payload.arm]
            n = robot.arms[payload.arm].n_joints
            point = ps[n] + spatial.matvec_constant(rs[n], payload.com)
            result.append(
                Body(
                    payload.mass,
                    point,
                    rs[n],
                    np.asarray(payload.inertia).reshape(3, 3),
                    payload.arm,
                    n - 1,
                    payload=True,
                )
            )
    return result


def actuator_rows(model: DynamicModel, q: jnp.ndarray) -> jnp.ndarray:
    """Rows A (n_platform_actuators × n_q) with u = A q̇, u the platform's actuator speeds
    (``platform.actuator_rows``; for a differential drive φ̇_r,l = (ẋ cos θ + ẏ sin θ ± b θ̇)/r, Yamamoto
    eq. 4–6)."""
    robot = model.robot
    rows = robot.platform.actuator_rows(q[: robot.n_platform])
    return jnp.concatenate([rows, jnp.zeros((rows.shape[0], robot.n_q - robot.n_platform), q.dtype)], axis=1)


def wheel_rows(model: DynamicModel, q: jnp.ndarray) -> jnp.ndarray:
    """Rows a_i (one per driven wheel × n_q) with the wheel's spin φ̇_i = a_i · q̇: the row of the actuator
    that turns it (:func:`actuator_rows`)."""
    rows = actuator_rows(model, q)
    return spatial.rows(rows, tuple(site.actuator for site in _driven_wheels(model)))


class BodyJacobians(NamedTuple):
    """The bodies of :func:`bodies` at one configuration, ordered by chain (platform bodies first, then arm
    0, 1, …, the payload last): masses (B,), centre-of-mass Jacobians (B, 3, n_q) and world inertias about
    the centre of mass (B, 3, 3)."""

    masses: jnp.ndarray
    linear: jnp.ndarray
    angular: jnp.ndarray
    inertia: jnp.ndarray


def body_jacobians(model: DynamicModel, q: jnp.ndarray, payload_mass: float | None = None) -> BodyJacobians:
    """Linear and angular geometric Jacobians of every body's centre of mass (``robot.point_jacobian``)."""
    robot = model.robot
    frames = robot.frames(q)
    parts = bodies(model, frames, payload_mass)

    def chain(body: Body) -> tuple[bool, int]:  # platform (-1), arms 0, 1, …, then the payload
        return body.payload, -1 if body.arm is None else body.arm

    j_v, j_w, ordered = [], [], []
    chains = sorted({chain(body) for body in parts})
    for key in chains:  # one vmapped point_jacobian per chain: fast to compile
        members = [body for body in parts if chain(body) == key]
        ordered += members
        arm = members[0].arm
        points = jnp.stack([body.point for body in members])
        upto = jnp.array([body.upto for body in members])
        lin, ang = jax.vmap(lambda p, u, arm=arm: robot.point_jacobian(q, frames, p, arm, u))(points, upto)
        j_v.append(lin)
        j_w.append(ang)
    rotations = jnp.stack([jnp.broadcast_to(body.rotation, (3, 3)) for body in ordered])
    inertia_world = rotations @ np.stack([body.inertia for body in ordered]) @ jnp.swapaxes(rotations, 1, 2)
    masses = jnp.asarray([body.mass for body in ordered], dtype=q.dtype)
    return BodyJacobians(masses, jnp.concatenate(j_v), jnp.concatenate(j_w), inertia_world)


def _driven_wheels(model: DynamicModel) -> tuple[WheelSite, ...]:
    return tuple(site for site in model.robot.platform.wheels() if site.actuator is not None)


def _spinning_wheel(model: DynamicModel) -> Wheel | None:
    """The wheel whose spin adds kinetic energy (a platform with driven wheels), or None."""
    return model.wheel if model.robot.platform.wheel_actuated else None


def _tree(
    model: DynamicModel, q: jnp.ndarray, payload_mass: float | None = None
) -> tuple[recursive.RigidInertia, list[recursive.Chain]]:
    """The model's kinematic tree at one configuration for :mod:`mobman.dynamics.recursive`: the inertia of
    the platform's bodies and one :class:`recursive.Chain` per arm (its joints' motion subspace columns and
    the inertia each joint moves, a payload added to its link's), all about the platform's reference point o
    in world-aligned axes."""
    robot = model.robot
    frames = robot.frames(q)
    origin = frames.platform[1]
    parts = bodies(model, frames, payload_mass)
    every = recursive.RigidInertia.of_bodies(
        jnp.asarray([body.mass for body in parts], dtype=q.dtype),
        jnp.stack([body.point for body in parts]) - origin,
        _world_inertia_columns(parts),
    )

    def rows(index: list[int]) -> recursive.RigidInertia:
        return jax.tree.map(lambda x: spatial.rows(x, tuple(index)), every)

    root = rows([k for k, body in enumerate(parts) if body.arm is None])
    chains = []
    for i, arm in enumerate(robot.arms):
        links = {body.upto: k for k, body in enumerate(parts) if body.arm == i and not body.payload}
        chain = rows([links[j] for j in range(arm.n_joints)])
        for k, body in enumerate(parts):
            if body.arm == i and body.payload:
                chain = jax.tree.map(lambda c, x, k=k, j=body.upto: c.at[j].add(x[k]), chain, every)
        rs, ps = frames.links[i]
        axes = jnp.stack([spatial.matvec_constant(rs[j], joint.axis) for j, joint in enumerate(arm.joints)])
        revolute = np.array([joint.kind == "revolute" for joint in arm.joints])[:, None]
        columns = recursive.Motion(
            jnp.where(revolute, axes, 0.0),
            jnp.where(revolute, spatial.cross(ps[: arm.n_joints] - origin, axes), axes),
        )
        chains.append(recursive.Chain(columns, chain))
    # read by the mass matrix and the bias alike, and within each by every joint: computed once
    return jax.tree.map(spatial.shared, (root, chains))


def _world_inertia_columns(parts: list[Body]) -> tuple[jnp.ndarray, jnp.ndarray, jnp.ndarray]:
    """The bodies' world inertias R Ī Rᵀ by columns (:class:`recursive.RigidInertia`), each (B, 3): with
    r_m = R e_m over the bodies, column k is Σ_m r_m (Ī Rᵀ)_mk, where (Ī Rᵀ)_mk = Σ_n Ī_mn (r_n)_k."""
    r = [jnp.stack([jnp.broadcast_to(body.rotation, (3, 3))[:, m] for body in parts]) for m in range(3)]
    local = np.stack([body.inertia for body in parts])

    def column(k: int) -> jnp.ndarray:
        weights = [
            local[:, m, 0] * r[0][:, k] + local[:, m, 1] * r[1][:, k] + local[:, m, 2] * r[2][:, k]
            for m in range(3)
        ]
        return r[0] * weights[0][:, None] + r[1] * weights[1][:, None] + r[2] * weights[2][:, None]

    return column(0), column(1), column(2)


def _platform_axes(basis: np.ndarray | jnp.ndarray) -> recursive.Motion:
    """The platform's motion subspace at o for the columns of ``basis`` (n_p × k) over its coordinates:
    x, y translate it (0, e_x), (0, e_y), θ turns it about the vertical through o (e_z, 0); further platform
    coordinates (a steering angle) do not move its bodies."""
    zero = jnp.zeros_like(basis[0])
    return recursive.Motion(
        jnp.stack([zero, zero, basis[2]], axis=-1), jnp.stack([basis[0], basis[1], zero], axis=-1)
    )


def _couple(robot: MobileManipulator, h: jax.Array, k: int) -> jax.Array:
    """Tᵀ H T with T = diag(1_k, C_1, C_2, …): a matrix over the joints' motion variables → over q_a (each
    arm's motion = C q_a); H itself when no arm is coupled."""
    if not any(arm.coupling is not None for arm in robot.arms):
        return h
    t = np.eye(h.shape[0])
    start = k
    for arm in robot.arms:
        t[start : start + arm.n_joints, start : start + arm.n_joints] = arm.coupling_matrix
        start += arm.n_joints
    return jnp.asarray(t.T) @ h @ jnp.asarray(t)


def mass_matrix_one(
    model: DynamicModel,
    q: jax.Array,
    payload_mass: float | None = None,
    platform_basis: jax.Array | np.ndarray | None = None,
) -> jnp.ndarray:
    """M(q) for one configuration (n_q × n_q) by the composite-rigid-body algorithm
    (:func:`mobman.dynamics.recursive.mass_matrix`, Featherstone §6.2), plus the wheel spin I_w aᵀ a.

    ``platform_basis``: a matrix B (n_p × k) over the platform coordinates; the result is then
    diag(B, 1)ᵀ M diag(B, 1) ((k + n_a) square), e.g. P = Sᵀ M S with B = S_p(q_p). Equal to
    :func:`mass_matrix_definition_one` (tests).
    """
    robot = model.robot
    n_p = robot.n_platform
    basis = np.eye(n_p) if platform_basis is None else platform_basis
    root, chains = _tree(model, q, payload_mass)
    m = _couple(robot, recursive.mass_matrix(_platform_axes(basis), root, chains), basis.shape[1])
    spin = _spinning_wheel(model)
    if spin is not None:
        a = wheel_rows(model, q)
        if platform_basis is not None:
            a = jnp.concatenate([spatial.matmul_expanded(a[:, :n_p], basis), a[:, n_p:]], axis=1)
        m = m + spin.I_w * spatial.matmul_expanded(a.T, a)
    return m


def mass_matrix_definition_one(
    model: DynamicModel, q: jnp.ndarray, payload_mass: float | None = None
) -> jnp.ndarray:
    """M(q) for one configuration by its definition, Σ m J_vᵀ J_v + J_ωᵀ (R I Rᵀ) J_ω over the bodies'
    centre-of-mass Jacobians (+ wheel spin): the reference :func:`mass_matrix_one` is tested against."""
    jac = body_jacobians(model, q, payload_mass)
    m = jnp.einsum("b,bin,bim->nm", jac.masses, jac.linear, jac.linear) + jnp.einsum(
        "bin,bij,bjm->nm", jac.angular, jac.inertia, jac.angular
    )
    spin = _spinning_wheel(model)
    if spin is not None:
        a = wheel_rows(model, q)
        m = m + spin.I_w * a.T @ a
    return m


def _wheel_spin_force(model: DynamicModel, q: jax.Array, q_dot: jax.Array, q_ddot: jax.Array) -> jax.Array:
    """The generalized force of the wheels' spin, T_w = ½ I_w |A(q) q̇|²: Lagrange's d/dt ∂T/∂q̇ − ∂T/∂q
    (autodiff of the two rows of :func:`wheel_rows`); zero without wheels."""
    spin = _spinning_wheel(model)
    if spin is None:
        return jnp.zeros_like(q)

    def momentum(x, v):
        a_rows = wheel_rows(model, x)
        return spin.I_w * spatial.matvec(a_rows.T, spatial.matvec(a_rows, v))

    return jax.jvp(momentum, (q, q_dot), (q_dot, q_ddot))[1] - jax.grad(
        lambda x: 0.5 * jnp.sum(q_dot * momentum(x, q_dot))
    )(q)


def body_forces_one(
    model: DynamicModel, q: jax.Array, q_dot: jax.Array, q_ddot: jax.Array, payload_mass: float | None = None
) -> tuple[jax.Array, jax.Array]:
    """Generalized force of every body for the motion (q, q̇, q̈), by Newton–Euler and virtual work:

        Q_b = m J_vᵀ (a − gravity) + J_ωᵀ (I α + ω × I ω),   a = J_v q̈ + J̇_v q̇,   α = J_ω q̈ + J̇_ω q̇,

    with J̇ q̇ from one forward-mode jvp of the Jacobians. Q_b = d/dt ∂T_b/∂q̇ − ∂T_b/∂q + ∂V_b/∂q for the
    kinetic and potential energy of body b, so Σ_b Q_b plus the wheel-spin term equals M q̈ + c + g (the
    Lagrange form of :func:`mass_matrix_definition_one` and :func:`lagrange_bias_one`, checked in the tests).
    Returns (forces (B, n_q) in the body order of :func:`body_jacobians`, the payload last; the wheel-spin
    force (n_q,), zero without wheels).
    """
    jac, jac_dot = jax.jvp(partial(body_jacobians, model, payload_mass=payload_mass), (q,), (q_dot,))
    omega = jac.angular @ q_dot
    a = jac.linear @ q_ddot + jac_dot.linear @ q_dot - np.asarray(model.gravity)
    alpha = jac.angular @ q_ddot + jac_dot.angular @ q_dot
    moment = jnp.einsum("bij,bj->bi", jac.inertia, alpha) + jnp.cross(
        omega, jnp.einsum("bij,bj->bi", jac.inertia, omega)
    )
    forces = jnp.einsum("b,bin,bi->bn", jac.masses, jac.linear, a) + jnp.einsum(
        "bin,bi->bn", jac.angular, moment
    )
    return forces, _wheel_spin_force(model, q, q_dot, q_ddot)


def generalized_force_one(
    model: DynamicModel, q: jax.Array, q_dot: jax.Array, q_ddot: jax.Array, payload_mass: float | None = None
) -> jax.Array:
    """M(q) q̈ + c(q, q̇) + g(q) for one state by the recursive Newton–Euler algorithm
    (:func:`mobman.dynamics.recursive.inverse_dynamics`, Featherstone §5.3), plus the wheel spin: the inverse
    dynamics of the unconstrained equations, without forming M.

    The platform is the root body: with o its reference point and ω = θ̇ e_z, its spatial velocity at o is
    (ω, ȯ) and its acceleration (ω̇, ö − ω × ȯ) (the derivative in the fixed frame at o), less the gravity
    vector (Featherstone §5.3's fictitious base acceleration)."""
    robot = model.robot
    n_p = robot.n_platform
    root, chains = _tree(model, q, payload_mass)
    e_z = np.array([0.0, 0.0, 1.0])
    zero = jnp.zeros_like(q[0])
    velocity = jnp.stack([q_dot[0], q_dot[1], zero])
    acceleration = jnp.stack([q_ddot[0] + q_dot[2] * q_dot[1], q_ddot[1] - q_dot[2] * q_dot[0], zero])
    motion = [robot.motion_rates(x)[n_p:] for x in (q_dot, q_ddot)]
    sizes = [arm.n_joints for arm in robot.arms]
    q_p, tau = recursive.inverse_dynamics(
        _platform_axes(np.eye(n_p)),
        root,
        recursive.Motion(q_dot[2] * e_z, velocity),
        recursive.Motion(q_ddot[2] * e_z, acceleration - np.asarray(model.gravity)),
        chains,
        jnp.split(motion[0], np.cumsum(sizes)[:-1]),
        jnp.split(motion[1], np.cumsum(sizes)[:-1]),
    )
    forces = jnp.concatenate(
        [q_p, *(t if arm.coupling is None else t @ arm.coupling_matrix for t, arm in zip(tau, robot.arms))]
    )
    return forces + _wheel_spin_force(model, q, q_dot, q_ddot)


def potential_energy_one(
    model: DynamicModel, q: jnp.ndarray, payload_mass: float | None = None
) -> jnp.ndarray:
    """V(q) = −Σ m gravityᵀ p_com for one configuration."""
    gravity = jnp.asarray(model.gravity)
    terms = [
        body.mass * (gravity @ body.point) for body in bodies(model, model.robot.frames(q), payload_mass)
    ]
    return -sum(terms[1:], terms[0])  # the platform body is always there


def gravity_one(model: DynamicModel, q: jnp.ndarray, payload_mass: float | None = None) -> jnp.ndarray:
    """g(q): the Newton–Euler force of the robot at rest (equal to ∂V/∂q, tests)."""
    zero = jnp.zeros_like(q)
    return generalized_force_one(model, q, zero, zero, payload_mass)


def bias_one(
    model: DynamicModel, q: jax.Array, q_dot: jax.Array, payload_mass: float | None = None
) -> jnp.ndarray:
    """c(q, q̇) + g(q) for one configuration: the Newton–Euler force at q̈ = 0."""
    return generalized_force_one(model, q, q_dot, jnp.zeros_like(q), payload_mass)


def lagrange_bias_one(
    model: DynamicModel, q: jax.Array, q_dot: jax.Array, payload_mass: float | None = None
) -> jnp.ndarray:
    """c(q, q̇) + g(q) by Lagrange's equations from the definition of M and V, the reference
    :func:`bias_one` is tested against: c = Ṁ q̇ − ∂/∂q (½ q̇ᵀ M(q) q̇) (Ṁ = (∂M/∂q) q̇ by one forward-mode
    jvp, the kinetic-energy gradient by reverse mode), g = ∂V/∂q."""
    mass = partial(mass_matrix_definition_one, model, payload_mass=payload_mass)
    m_dot = jax.jvp(mass, (q,), (q_dot,))[1]
    kinetic_gradient = jax.grad(lambda x: 0.5 * q_dot @ mass(x) @ q_dot)(q)
    gravity = jax.grad(partial(potential_energy_one, model, payload_mass=payload_mass))(q)
    return m_dot @ q_dot - kinetic_gradient + gravity


def coriolis_matrix_one(model: DynamicModel, q: jax.Array, q_dot: jax.Array) -> jnp.ndarray:
    """C_ij = Σ_k Γ_ijk q̇_k with the Christoffel symbols of the first kind of M (jacfwd of M)."""
    dm = jax.jacfwd(partial(mass_matrix_one, model))(q)  # dm[i, j, k] = ∂M_ij/∂q_k
    return 0.5 * (dm @ q_dot + jnp.einsum("ikj,k->ij", dm, q_dot) - jnp.einsum("jki,k->ij", dm, q_dot))


def arm_actuation(robot: MobileManipulator) -> np.ndarray:
    """The arms' block of E ((n_q − n_p) × the arms' actuators): diag(C_1ᵀ, C_2ᵀ, …), joint torques acting on
    each arm's joint motion variables (C the arm's coupling matrix, the identity when uncoupled)."""
    blocks = [arm.coupling_matrix.T for arm in robot.arms]
    out = np.zeros((sum(b.shape[0] for b in blocks), sum(b.shape[1] for b in blocks)))
    row = col = 0
    for b in blocks:
        out[row : row + b.shape[0], col : col + b.shape[1]] = b
        row, col = row + b.shape[0], col + b.shape[1]
    return out


def actuation_matrix_one(model: DynamicModel, q: jnp.ndarray) -> jnp.ndarray:
    """E(q) (n_q × n_actuators) = diag(E_p(q_p), C_1ᵀ, C_2ᵀ, …): generalized forces E τ of the actuator
    torques (E_p = A_pᵀ, the platform's actuator rows; :func:`arm_actuation`)."""
    robot = model.robot
    n_p = robot.n_platform
    e_p = robot.platform.actuator_rows(q[:n_p]).T
    arms = arm_actuation(robot)
    top = jnp.concatenate([e_p, jnp.zeros((n_p, arms.shape[1]), q.dtype)], axis=1)
    return jnp.concatenate(
        [top, jnp.asarray(np.block([np.zeros((arms.shape[0], e_p.shape[1])), arms]), q.dtype)]
    )


# --- batched public API --------------------------------------------------------------------------


@batched({1: 1}, static=(0,))
def _mass(model, q):
    return mass_matrix_one(model, q)


@batched({1: 1, 2: 1}, static=(0,))
def _bias(model, q, q_dot):
    return bias_one(model, q, q_dot)


@batched({1: 1, 2: 1, 3: 1}, static=(0,))
def _generalized_force(model, q, q_dot, q_ddot):
    return generalized_force_one(model, q, q_dot, q_ddot)


@batched({1: 1}, static=(0,))
def _gravity(model, q):
    return gravity_one(model, q)


@batched({1: 1}, static=(0,))
def _potential(model, q):
    return potential_energy_one(model, q)


@batched({1: 1, 2: 1}, static=(0,))
def _coriolis(model, q, q_dot):
    return coriolis_matrix_one(model, q, q_dot)


@batched({1: 1}, static=(0,))
def _actuation(model, q):
    return actuation_matrix_one(model, q)


def validated_q(model: DynamicModel, q: npt.ArrayLike) -> np.ndarray | jax.Array:
    """Configurations of ``model``'s robot checked for shape and finiteness (traced values pass as they are;
    host values go to the compiled functions as NumPy arrays, a ``jax.Array`` stays where it is:
    :func:`mobman.kinematics.validated_q`)."""
    return kinematics.validated_q(model.robot, q)


def _q_dot(model: DynamicModel, q_dot: npt.ArrayLike, name: str = "q_dot") -> np.ndarray | jax.Array:
    """A validated rate (q̇ or q̈) in the full coordinates; errors name the argument."""
    try:
        return kinematics.validated_q(model.robot, q_dot)
    except InputError as exc:
        raise InputError(f"{name}: {exc}") from None


def mass_matrix(model: DynamicModel, q: npt.ArrayLike) -> jnp.ndarray:
    """M(q), shape (..., n_q, n_q), symmetric positive definite."""
    return _mass(model, validated_q(model, q))


def bias(model: DynamicModel, q: npt.ArrayLike, q_dot: npt.ArrayLike) -> jnp.ndarray:
    """c(q, q̇) + g(q), shape (..., n_q)."""
    return _bias(model, validated_q(model, q), _q_dot(model, q_dot))


def generalized_force(
    model: DynamicModel, q: npt.ArrayLike, q_dot: npt.ArrayLike, q_ddot: npt.ArrayLike
) -> jnp.ndarray:
    """M(q) q̈ + c(q, q̇) + g(q), shape (..., n_q), by Newton–Euler (:func:`body_forces_one`): the
    unconstrained inverse dynamics, equal to ``mass_matrix(q) @ q_ddot + bias(q, q_dot)`` at a fraction of
    the cost."""
    return _generalized_force(
        model, validated_q(model, q), _q_dot(model, q_dot), _q_dot(model, q_ddot, "q_ddot")
    )


def gravity_vector(model: DynamicModel, q: npt.ArrayLike) -> jnp.ndarray:
    """g(q) = ∂V/∂q, shape (..., n_q)."""
    return _gravity(model, validated_q(model, q))


def potential_energy(model: DynamicModel, q: npt.ArrayLike) -> jnp.ndarray:
    """V(q), shape (...)."""
    return _potential(model, validated_q(model, q))


def coriolis_matrix(model: DynamicModel, q: npt.ArrayLike, q_dot: npt.ArrayLike) -> jnp.ndarray:
    """C(q, q̇) (Christoffel form), shape (..., n_q, n_q); c = C q̇ and Ṁ − 2C is skew-symmetric."""
    return _coriolis(model, validated_q(model, q), _q_dot(model, q_dot))


def actuation_matrix(model: DynamicModel, q: npt.ArrayLike) -> jnp.ndarray:
    """E(q), shape (..., n_q, n_actuators)."""
    return _actuation(model, validated_q(model, q))


def wheel_angle_rates(model: DynamicModel, q: npt.ArrayLike, q_dot: npt.ArrayLike) -> jnp.ndarray:
    """(θ̇_r, θ̇_l) of a platform with driven wheels (one rate per actuator) for (q, q̇): for a differential
    drive the conversion to Yamamoto's wheel-angle coordinates q_v = (x_o, y_o, θ_r, θ_l), whose heading is
    ϕ = c (θ_r − θ_l), c = r/(2b) (eq. 4)."""
    if not model.robot.platform.wheel_actuated:
        raise InputError(
            f"wheel_angle_rates: the platform must have driven wheels, {type(model.robot.platform).__name__} has none"
        )
    rows = jnp.vectorize(partial(actuator_rows, model), signature="(n)->(w,n)")(validated_q(model, q))
    return jnp.einsum("...wn,...n->...w", rows, _q_dot(model, q_dot))


__all__ = [
    "Body",
    "actuation_matrix",
    "bias",
    "BodyJacobians",
    "bodies",
    "body_forces_one",
    "body_jacobians",
    "coriolis_matrix",
    "generalized_force",
    "generalized_force_one",
    "gravity_vector",
    "mass_matrix",
    "potential_energy",
    "wheel_angle_rates",
]
