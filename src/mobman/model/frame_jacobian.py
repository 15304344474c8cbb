"""The pose of a frame carried by the robot and the geometric Jacobians of its origin, in one call.

Every coordinate q_k moves the bodies after it by a screw: the platform's x and y translate along the
world axes, θ turns about the vertical through the platform origin, a revolute joint turns about its axis
a_k, a prismatic joint slides along a_k (a car's steering angle moves no body). With ω_k the screw's
angular part, the columns of the point's linear and angular Jacobians are J_k = ∂p/∂q_k and ω_k
(:meth:`MobileManipulator.point_jacobian`). The position and orientation tasks build their Jacobians
from :func:`frame_jacobian`. Its derivative here is autodiff through the frames; the engine attaches the
closed-form kinematic Hessian instead (:mod:`mobman.engine.frame_rule`).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Callable

import jax.numpy as jnp

from mobman.engine.kernels import definition

if TYPE_CHECKING:
    from mobman.model.robot import Frames, MobileManipulator


@definition
def frame_jacobian(
    robot: "MobileManipulator",
    frame_of: Callable[["Frames"], tuple[jnp.ndarray, jnp.ndarray]],
    arm: int | None,
    upto: int,
    q: jnp.ndarray,
) -> tuple[jnp.ndarray, jnp.ndarray, jnp.ndarray, jnp.ndarray]:
    """(R, p, J, Ω) of the frame ``frame_of(robot.frames(q))`` = (R, p), rigidly attached to frame ``upto``
    of arm ``arm`` (``arm=None``: to the platform), at one configuration: its pose and the linear and
    angular Jacobians (3 × n_q each) of its origin p (:meth:`MobileManipulator.point_jacobian`)."""
    frames = robot.frames(q)
    r, p = frame_of(frames)
    return (r, p, *robot.point_jacobian(q, frames, p, arm, upto))


__all__ = ["frame_jacobian"]
