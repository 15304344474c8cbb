"""The position of a point of an arm frame in the world (Bayle's ξ1, ξ2; Korayem's end effector)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import jax

from mobman.model import spatial
from mobman.model.frame_jacobian import frame_jacobian
from mobman.model.tasks.base import SymbolicFrames, Task, check_arm, component_indices, last_moving

if TYPE_CHECKING:
    import sympy as sp

    from mobman.model.robot import Frames, MobileManipulator


@dataclass(frozen=True)
class Position(Task):
    """Position of a point of an arm frame in the world, any subset of (x, y, z).

    ``link=-1`` is the tool (end-effector) frame; ``link=k`` the frame after joint k. ``point`` is an offset
    in that frame. The Jacobian is the geometric one, z_i × (p − o_i) (tested against autodiff).
    """

    kind = "position"

    components: str = "xyz"
    arm: int = 0
    link: int = -1
    point: tuple[float, float, float] = (0.0, 0.0, 0.0)
    label: str = "ee"

    def __post_init__(self) -> None:
        component_indices(self.components)

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(f"{c}_{self.label}" for c in self.components)

    def check(self, robot: MobileManipulator) -> None:
        check_arm(robot, self.arm, self.link)

    def _frame(self, frames: Frames) -> tuple[jax.Array, jax.Array]:
        """The link's rotation and the task point."""
        rs, ps = frames.links[self.arm]
        return rs[self.link], ps[self.link] + spatial.matvec_constant(rs[self.link], self.point)

    def value(self, robot: MobileManipulator, q: jax.Array, frames: Frames) -> jax.Array:
        return spatial.rows(self._frame(frames)[1], component_indices(self.components))

    def jacobian(self, robot: MobileManipulator, q: jax.Array, frames: Frames) -> jax.Array:
        upto = last_moving(robot, self.arm, self.link)
        _, _, lin, _ = frame_jacobian(robot, self._frame, self.arm, upto, q)
        return spatial.rows(lin, component_indices(self.components))

    def symbolic(self, kin: SymbolicFrames) -> list[sp.Expr]:
        r, p = kin.link_poses(self.arm)[self.link]
        point = p + r * kin.vector(self.point)
        return [point[i] for i in component_indices(self.components)]
