"""The position of an arm's mount point in the world (Korayem's base point F, eq. 37)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import jax

from mobman.model import spatial
from mobman.model.frame_jacobian import frame_jacobian
from mobman.model.tasks.base import SymbolicFrames, Task, check_arm, component_indices

if TYPE_CHECKING:
    import sympy as sp

    from mobman.model.robot import Frames, MobileManipulator


@dataclass(frozen=True)
class MountPosition(Task):
    """Position of an arm's mount point in the world (Korayem's base point F = (x_f, y_f))."""

    kind = "mount_position"

    components: str = "xy"
    arm: int = 0

    def __post_init__(self) -> None:
        component_indices(self.components)

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(f"{c}_f" for c in self.components)

    def check(self, robot: MobileManipulator) -> None:
        check_arm(robot, self.arm)

    def _frame(self, frames: Frames) -> tuple[jax.Array, jax.Array]:
        return frames.mounts[self.arm]

    def value(self, robot: MobileManipulator, q: jax.Array, frames: Frames) -> jax.Array:
        return spatial.rows(self._frame(frames)[1], component_indices(self.components))

    def jacobian(self, robot: MobileManipulator, q: jax.Array, frames: Frames) -> jax.Array:
        _, _, lin, _ = frame_jacobian(robot, self._frame, None, -1, q)
        return spatial.rows(lin, component_indices(self.components))

    def symbolic(self, kin: SymbolicFrames) -> list[sp.Expr]:
        p = kin.mount_pose(self.arm)[1]
        return [p[i] for i in component_indices(self.components)]
