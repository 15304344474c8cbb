"""The closed-form derivative of a frame's pose and Jacobians (the kinematic Hessian), as a custom JVP.

Every coordinate q_k moves the bodies after it by a screw: the platform's x and y translate along the
world axes, θ turns about the vertical through the platform origin, a revolute joint turns about its axis
a_k, a prismatic joint slides along a_k (a car's steering angle moves no body). With ω_k the screw's
angular part (e_z for θ, a_k for a revolute joint, 0 otherwise), the columns of the point's linear and
angular Jacobians are J_k = ∂p/∂q_k and ω_k (:meth:`MobileManipulator.point_jacobian`). A screw depends
only on the coordinates before it in the chain (platform, then the arm's joints): q_k, k < j, carries
screw j as a rigid body turning about screw k. Differentiating J_j = v_j + ω_j × p then gives the
kinematic Hessian

    ∂J_j/∂q_k = ω_min(j,k) × J_max(j,k),        ∂ω_j/∂q_k = ω_k × ω_j  (k < j),  0  (k ≥ j),

and, along a velocity q̇, the time derivatives of the columns (the Jacobian's JVP):

    J̇_j = W_j × J_j + ω_j × V_j,    ω̇_j = W_j × ω_j,    W_j = Σ_{k<j} q̇_k ω_k,    V_j = Σ_{k≥j} q̇_k J_k

(W_j is the angular velocity of the body before joint j, V_j the velocity of p due to joints j and after).
Columns of other arms and of joints after the point's link are zero and drop out of both sums. An arm's
coupling (motion = C q_a) is applied after: the rule runs on the motion variables, q̇_m = C q̇_a, and maps
the columns back by C.

:func:`frame_jacobian` is the drop-in for :func:`mobman.model.frame_jacobian.frame_jacobian` (whose
derivative is autodiff through the frames): the same pose (R, p) and Jacobians of its origin, with this rule
attached to all four (``jax.custom_jvp``; Ṙ = [Ω q̇]× R, ṗ = J q̇). Forward-mode derivatives use it directly
and reverse mode transposes it, so the gradient of a criterion of J̄ (the manipulability criteria of the
control laws) costs two running sums and a few cross products instead of a reverse pass through every frame
of the chain.
"""

from __future__ import annotations

from functools import partial
from typing import Any, Callable

import jax
import jax.numpy as jnp

from mobman.engine.fusion import computed_once
from mobman.engine.kernels import drop_in
from mobman.engine.products import cross, unstack


@drop_in("mobman.model.frame_jacobian.frame_jacobian")
@partial(jax.custom_jvp, nondiff_argnums=(0, 1, 2, 3))
def frame_jacobian(
    robot: Any, frame_of: Callable, arm: int | None, upto: int, q: jnp.ndarray
) -> tuple[jnp.ndarray, jnp.ndarray, jnp.ndarray, jnp.ndarray]:
    """(R, p, J, Ω) of the frame ``frame_of(robot.frames(q))`` at one configuration, as the definition
    computes them, differentiable by the closed-form rule of the module notes."""
    frames = robot.frames(q)
    r, p = frame_of(frames)
    p = computed_once(p)  # read by every column of the Jacobians
    return (r, p, *robot.point_jacobian(q, frames, p, arm, upto))


@frame_jacobian.defjvp
def _frame_jacobian_jvp(robot, frame_of, arm, upto, primals, tangents):
    (q,), (q_dot,) = primals, tangents
    frames = robot.frames(q)
    r, p = frame_of(frames)
    p = computed_once(p)
    lin, ang = robot.point_jacobian(q, frames, p, arm, upto, coupled=False)
    m_dot = robot.motion_rates(q_dot)
    w = _running_sum(ang * m_dot, exclusive=True)
    v = _running_sum(lin * m_dot, reverse=True)
    # cross products of the columns (axis 0 of the 3 × n matrices)
    lin_dot = cross(w, lin, axis=0) + cross(ang, v, axis=0)
    ang_dot = cross(w, ang, axis=0)
    omega, p_dot = jnp.sum(ang * m_dot, axis=-1), jnp.sum(lin * m_dot, axis=-1)
    r_dot = cross(jnp.broadcast_to(omega[:, None], r.shape), r, axis=0)
    primal = (r, p, robot.couple(lin), robot.couple(ang))
    return primal, (r_dot, p_dot, robot.couple(lin_dot), robot.couple(ang_dot))


def _running_sum(x: jnp.ndarray, exclusive: bool = False, reverse: bool = False) -> jnp.ndarray:
    """Running sums of the columns of x (3 × n): Σ_{k≤j} (``exclusive``: k < j; ``reverse``: k ≥ j).
    Written out column by column: for a chain's few columns XLA fuses the sums with their consumers, where
    ``lax.cumsum`` is a kernel of its own."""
    columns = unstack(x)
    if reverse:
        columns = columns[::-1]
    sums, total = [], jnp.zeros_like(columns[0])
    for column in columns:
        if not exclusive:
            total = total + column
        sums.append(total)
        if exclusive:
            total = total + column
    return jnp.stack(sums[::-1] if reverse else sums, axis=-1)


__all__ = ["frame_jacobian"]
