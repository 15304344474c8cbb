"""Angles g(R) of an arm frame's rotation: the common part of the orientation tasks (planar angle,
elevation, Euler angles), their Jacobian by the chain rule through Ṙ = [ω]× R."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import jax
import jax.numpy as jnp

from mobman.model import spatial
from mobman.model.frame_jacobian import frame_jacobian
from mobman.model.tasks.base import REPRESENTATION_TOL, SymbolicFrames, Task, check_arm, last_moving

if TYPE_CHECKING:
    import sympy as sp

    from mobman.model.robot import Frames, MobileManipulator


@dataclass(frozen=True)
class OrientationTask(Task):
    """Angles g(R) of an arm frame's rotation R. With Ṙ = [ω]× R and ω = Σ_j ω_j q̇_j,
    ∂g_k/∂q_j = ⟨∂g_k/∂R, [ω_j]× R⟩ = ω_j · vee(M_k − M_kᵀ) with M_k = (∂g_k/∂R) Rᵀ and
    vee(A) = (A₂₁, A₀₂, A₁₀): one 3 × 3 product per angle instead of one per column.

    Subclasses give ``angles(R)``, ``margin(R)`` (the norm of the atan2 arguments, 0 where the angles are
    undefined) and ``symbolic_angles(R, kin)``, the same angles of a SymPy rotation matrix.
    """

    arm: int = field(default=0, kw_only=True)
    link: int = field(default=-1, kw_only=True)

    def check(self, robot: MobileManipulator) -> None:
        check_arm(robot, self.arm, self.link)

    def angles(self, r: jax.Array) -> jax.Array:
        raise NotImplementedError

    def margin(self, r: jax.Array) -> jax.Array:
        """Norm of the atan2 arguments of the angles (the smallest one): 0 where they are undefined."""
        raise NotImplementedError

    def symbolic_angles(self, r: sp.Matrix, kin: SymbolicFrames) -> list[sp.Expr]:
        """The angles of the SymPy rotation matrix ``r`` (``kin.angle`` for an atan2)."""
        raise NotImplementedError

    def value(self, robot: MobileManipulator, q: jax.Array, frames: Frames) -> jax.Array:
        return self.angles(frames.links[self.arm][0][self.link])

    def representation_singular(self, robot: MobileManipulator, q: jax.Array, frames: Frames) -> jax.Array:
        return self.margin(frames.links[self.arm][0][self.link]) <= REPRESENTATION_TOL

    def _frame(self, frames: Frames) -> tuple[jax.Array, jax.Array]:
        rs, ps = frames.links[self.arm]
        return rs[self.link], ps[self.link]

    def jacobian(self, robot: MobileManipulator, q: jax.Array, frames: Frames) -> jax.Array:
        upto = last_moving(robot, self.arm, self.link)
        r, _, _, omega = frame_jacobian(robot, self._frame, self.arm, upto, q)
        m = spatial.matmul_expanded(jax.jacfwd(self.angles)(r), r.T)  # (k, 3, 3)
        axial = jnp.stack([m[:, 2, 1] - m[:, 1, 2], m[:, 0, 2] - m[:, 2, 0], m[:, 1, 0] - m[:, 0, 1]], -1)
        return spatial.matmul_expanded(axial, omega)

    def symbolic(self, kin: SymbolicFrames) -> list[sp.Expr]:
        return self.symbolic_angles(kin.link_poses(self.arm)[self.link][0], kin)
