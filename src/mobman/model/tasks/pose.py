"""The pose of an arm frame: position and rotation vector, with the error on SO(3)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import jax
import jax.numpy as jnp

from mobman.model import so3
from mobman.model.frame_jacobian import frame_jacobian
from mobman.model.tasks.base import Task, check_arm, last_moving

if TYPE_CHECKING:
    from mobman.model.robot import Frames, MobileManipulator


@dataclass(frozen=True)
class Pose(Task):
    """Position and orientation of an arm frame: ξ = (p, r) with r = log R the rotation vector of the
    frame's rotation R (angle in [0, π]; :mod:`mobman.model.so3`).

    The error is e = (p* − p, log(R* Rᵀ)), the translation and the world-frame rotation vector that take
    the frame to the desired pose, and the Jacobian rows are the geometric ones, the linear and the angular
    velocity (v, ω) of the frame (:func:`~mobman.model.frame_jacobian.frame_jacobian`); a reference's
    velocity ξ̇* is likewise (ṗ*, ω*) (:class:`~mobman.control.references.PoseReference`). No
    representation singularity: r wraps at θ = π, but the error and the Jacobian are continuous, and the
    Jacobian has full rank wherever the robot can turn the frame about every axis.

    With J̄ η = ξ̇* + W e exactly (Bayle eq. 5–6 away from singularities), ė_p = −(W e)_p and, with E =
    R* Rᵀ = exp(e_o), Ė Eᵀ = [ω* − E ω]×; the left Jacobian J_l(e_o) of SO(3) maps ė_o to it, and with
    J_l⁻¹(I − E) = −[e_o]× and e_oᵀ J_l⁻¹ = e_oᵀ, ė_o = ω* × e_o − J_l⁻¹ (W e)_o: d‖e‖²/dt = −2 eᵀ W e. The
    norm of the pose error decays at least as fast as exp(−λ_min(W) t) (exactly so for a scalar W),
    whatever the reference's angular velocity.

    ``link=-1`` is the tool frame; ``link=k`` the frame after joint k. No closed form in
    :mod:`mobman.symbolic` (the rotation vector is not a rational function of sines and cosines).
    """

    kind = "pose"

    arm: int = 0
    link: int = -1
    label: str = "ee"

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(f"{c}_{self.label}" for c in ("x", "y", "z", "rx", "ry", "rz"))

    @property
    def euclidean(self) -> bool:
        return False

    def check(self, robot: MobileManipulator) -> None:
        check_arm(robot, self.arm, self.link)

    def _frame(self, frames: Frames) -> tuple[jax.Array, jax.Array]:
        rs, ps = frames.links[self.arm]
        return rs[self.link], ps[self.link]

    def value(self, robot: MobileManipulator, q: jax.Array, frames: Frames) -> jax.Array:
        r, p = self._frame(frames)
        return jnp.concatenate([p, so3.log(r)])

    def jacobian(self, robot: MobileManipulator, q: jax.Array, frames: Frames) -> jax.Array:
        upto = last_moving(robot, self.arm, self.link)
        _, _, lin, omega = frame_jacobian(robot, self._frame, self.arm, upto, q)
        return jnp.concatenate([lin, omega], axis=0)

    def error(self, xi_desired: jax.Array, xi: jax.Array) -> jax.Array:
        position = xi_desired[..., :3] - xi[..., :3]
        return jnp.concatenate([position, so3.error(xi_desired[..., 3:], xi[..., 3:])], axis=-1)
