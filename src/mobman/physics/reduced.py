"""mobman's reduced equations of motion read off MuJoCo's model of the robot: the check of
:mod:`mobman.dynamics.reduced` against an independent rigid-body engine on the exported robot.

MuJoCo's model (:func:`mobman.physics.to_mjspec`) is free-floating: its velocity v (``qvel``, n_v) holds the
platform's free joint (the linear velocity of the platform frame's origin in world axes, the angular velocity
in the platform's axes), each wheel's spin and each arm joint's rate. Its equations of motion are

    M_mj(q) v̇ + c_mj(q, v) = E_mj τ + (contact forces),

with ``mj_fullM`` giving M_mj, ``qfrc_bias`` c_mj (Coriolis, centrifugal and gravity forces) and the
actuators' moment arms E_mj. The motions mobman's reduced model describes, q̇ = S(q) η with the wheels rolling
without slipping (Yamamoto & Yun eq. 10–16), are in MuJoCo's coordinates v = S_mj(q) η (:func:`admissible_basis`):
the free joint's linear velocity (ẋ, ẏ, 0), its angular velocity (0, 0, θ̇), each wheel's spin φ̇_i = a_i(q) q̇
(the actuator row of the wheel's motor, :meth:`Platform.actuator_rows`), the joint rates q̇_a. Along them
v̇ = S_mj η̇ + Ṡ_mj η, and the forces that keep the wheels rolling do no work on them (S_mjᵀ J_cᵀ = 0 for a
contact point at rest on the floor), so MuJoCo's own model gives

    P_mj = S_mjᵀ M_mj S_mj,   b_mj = S_mjᵀ (M_mj Ṡ_mj η + c_mj),   B_mj = S_mjᵀ E_mj          (:func:`mujoco_reduced_terms`)

which equal mobman's P, b, B (:func:`mobman.dynamics.reduced.reduced_terms`) wherever the two models hold
the same bodies: docs/physics.md lists where they do and why the agreement is to rounding.

Ṡ_mj η is the derivative of v = S_mj(q) η along q̇ = S η (one forward-mode ``jax.jvp``). Differential-drive
and skid-steer platforms (free joint and wheels), omnidirectional (slide joints) and fixed platforms are
supported; a car (steering hinges) is a :class:`mobman.ModelError`.
"""

from __future__ import annotations

from typing import Any

import jax
import jax.numpy as jnp
import numpy as np
import numpy.typing as npt

from mobman.dynamics.inertia import DynamicModel
from mobman.errors import InputError, ModelError
from mobman.model.robot import MobileManipulator
from mobman.physics.mjcf import mujoco_module, to_mjspec
from mobman.physics.state import set_configuration


class _Layout:
    """Where each piece of mobman's q̇ goes in MuJoCo's velocity vector v of a model built from ``robot``."""

    def __init__(self, model: Any, robot: MobileManipulator) -> None:
        platform = robot.platform
        kind = platform.kind
        if kind not in ("differential", "skid_steer", "omnidirectional", "fixed"):
            raise ModelError(
                f"platform kind {kind!r}: the reduced equations on MuJoCo support differential, "
                "skid_steer, omnidirectional and fixed platforms"
            )
        self.robot, self.nv, self.kind = robot, int(model.nv), kind

        def dof(name: str) -> int:
            return int(model.jnt_dofadr[model.joint(name).id])

        self.arm = np.array([dof(n) for n in robot.coordinate_names[robot.n_platform :]], dtype=int)
        if kind == "omnidirectional":
            self.planar = np.array([dof(n) for n in platform.actuator_names], dtype=int)
        elif kind != "fixed":
            self.free = dof("platform")
            sites = platform.wheels()
            names = [j.name for j in platform.urdf_joints()]
            self.wheels = np.array([dof(n) for n in names], dtype=int)
            if any(s.actuator is None for s in sites):
                raise ModelError(f"{robot.name}: a wheel without a motor has no reduced form on MuJoCo here")
            self.wheel_rows = tuple(int(s.actuator or 0) for s in sites)
        self.actuators = np.array([model.actuator(n).id for n in _actuator_names(robot)], dtype=int)

    def velocity(self, q: jax.Array, q_dot: jax.Array) -> jax.Array:
        """MuJoCo's v (n_v,) for mobman's (q, q̇) (the wheels rolling)."""
        robot, n_p = self.robot, self.robot.n_platform
        v = jnp.zeros(self.nv, q.dtype).at[self.arm].set(q_dot[n_p:])
        if self.kind == "omnidirectional":
            return v.at[self.planar].set(q_dot[:3])
        if self.kind == "fixed":
            return v
        v = v.at[self.free : self.free + 2].set(q_dot[:2]).at[self.free + 5].set(q_dot[2])
        spins = robot.platform.actuator_rows(q[:n_p]) @ q_dot[:n_p]
        return v.at[self.wheels].set(spins[jnp.asarray(self.wheel_rows)])


def _actuator_names(robot: MobileManipulator) -> tuple[str, ...]:
    return tuple(robot.platform.actuator_names) + robot.coordinate_names[robot.n_platform :]


def admissible_basis(
    model: Any, robot: MobileManipulator, q: npt.ArrayLike, eta: npt.ArrayLike
) -> tuple[np.ndarray, np.ndarray]:
    """(S_mj (..., n_v, n_eta), Ṡ_mj η (..., n_v)) at states (q, η) (leading dimensions alike) for a MuJoCo
    ``model`` built from ``robot``: the admissible velocities v = S_mj η in MuJoCo's coordinates and their
    acceleration at η̇ = 0."""
    layout = _Layout(model, robot)

    def one(x: jax.Array, e: jax.Array) -> tuple[jax.Array, jax.Array]:
        def v_of(y: jax.Array, f: jax.Array) -> jax.Array:
            return layout.velocity(y, robot.S(y) @ f)

        s_dot_eta = jax.jvp(lambda y: v_of(y, e), (x,), (robot.S(x) @ e,))[1]
        return jax.jacfwd(v_of, argnums=1)(x, e), s_dot_eta

    basis = jax.jit(jnp.vectorize(one, signature="(n),(k)->(v,k),(v)"))
    s_mj, s_dot_eta = basis(jnp.asarray(q, dtype=float), jnp.asarray(eta, dtype=float))
    return np.asarray(s_mj), np.asarray(s_dot_eta)


def mujoco_reduced_terms(
    dynamics: DynamicModel, q: npt.ArrayLike, eta: npt.ArrayLike, *, model: Any = None
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(P_mj, b_mj, B_mj) of MuJoCo's model of ``dynamics`` at the states (q, η) (shapes (N, n_q), (N, n_eta);
    the module docstring gives the formulas), shapes (N, k, k), (N, k), (N, k, n_actuators), B's columns in
    mobman's actuator order (``dynamics.actuator_names``). ``model``: the compiled MuJoCo model of
    ``dynamics`` (default: :func:`mobman.physics.to_mjspec` of it, compiled); its gravity is set to the
    dynamic model's. One MuJoCo evaluation (``mj_forward``, ``mj_fullM``) per state."""
    mj = mujoco_module()
    robot = dynamics.robot
    q = np.atleast_2d(np.asarray(q, dtype=float))
    eta = np.atleast_2d(np.asarray(eta, dtype=float))
    if q.shape[1:] != (robot.n_q,) or eta.shape != (q.shape[0], robot.n_eta):
        raise InputError(
            f"q, eta: states of {robot.n_q} and {robot.n_eta} numbers, one η per q, got {q.shape}, {eta.shape}"
        )
    if model is None:
        model = to_mjspec(dynamics).compile()
    model.opt.gravity[:] = dynamics.gravity
    actuators = _Layout(model, robot).actuators
    s_mj, s_dot_eta = admissible_basis(model, robot, q, eta)
    data = mj.MjData(model)
    mass = np.zeros((len(q), model.nv, model.nv))
    bias = np.zeros((len(q), model.nv))
    moment = np.zeros((len(q), model.nu, model.nv))
    for k in range(len(q)):  # one MuJoCo evaluation per state (a check, not a hot path)
        set_configuration(model, data, robot, q[k])
        data.qvel[:] = s_mj[k] @ eta[k]
        mj.mj_forward(model, data)
        mj.mj_fullM(model, data, mass[k])
        bias[k] = data.qfrc_bias
        mj.mju_sparse2dense(
            moment[k], data.actuator_moment, data.moment_rownnz, data.moment_rowadr, data.moment_colind
        )
    s_t = np.swapaxes(s_mj, 1, 2)
    p = s_t @ mass @ s_mj
    b = np.einsum("nvk,nv->nk", s_mj, np.einsum("nvw,nw->nv", mass, s_dot_eta) + bias)
    return p, b, s_t @ np.swapaxes(moment[:, actuators], 1, 2)


__all__ = ["admissible_basis", "mujoco_reduced_terms"]
