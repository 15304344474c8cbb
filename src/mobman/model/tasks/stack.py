"""Tasks stacked row-wise: how Korayem's extra rows and Tchoń's output extension are expressed."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import jax
import jax.numpy as jnp

from mobman.errors import ModelError
from mobman.model.tasks.base import SymbolicFrames, Task

if TYPE_CHECKING:
    import sympy as sp

    from mobman.model.robot import Frames, MobileManipulator


@dataclass(frozen=True)
class Stack(Task):
    """Several tasks stacked row-wise: ξ = [f_1(q); f_2(q); …]. In files: ``tasks = [{kind = …}, …]``."""

    kind = "stack"

    tasks: tuple[Task, ...] = ()

    def __post_init__(self) -> None:
        tasks = tuple(self.tasks)
        if not tasks or not all(isinstance(t, Task) for t in tasks):
            raise ModelError("Stack: give one or more tasks")
        object.__setattr__(self, "tasks", tasks)

    @classmethod
    def from_table(cls, values: dict[str, Any]) -> Stack:
        """The nested stacks of a file flattened (:func:`stack`)."""
        return stack(*values.get("tasks", ()))

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(n for t in self.tasks for n in t.names)

    def check(self, robot: MobileManipulator) -> None:
        for t in self.tasks:
            t.check(robot)

    def value(self, robot: MobileManipulator, q: jax.Array, frames: Frames) -> jax.Array:
        return jnp.concatenate([t.value(robot, q, frames) for t in self.tasks])

    def representation_singular(self, robot: MobileManipulator, q: jax.Array, frames: Frames) -> jax.Array:
        return jnp.any(jnp.stack([t.representation_singular(robot, q, frames) for t in self.tasks]))

    def jacobian(self, robot: MobileManipulator, q: jax.Array, frames: Frames) -> jax.Array:
        return jnp.concatenate([t.jacobian(robot, q, frames) for t in self.tasks], axis=0)

    def reduced_jacobian(self, robot: MobileManipulator, q: jax.Array, frames: Frames) -> jax.Array:
        """The parts' J̄ stacked: J S row block by row block, the same numbers as J S. The m × n_q matrix J
        is never formed: for one configuration every array of the compiled program then stays small, and
        XLA's CPU runtime runs its kernels on the calling thread (:mod:`mobman.engine.batched`)."""
        return jnp.concatenate([t.reduced_jacobian(robot, q, frames) for t in self.tasks], axis=0)

    def symbolic(self, kin: SymbolicFrames) -> list[sp.Expr]:
        return [e for t in self.tasks for e in t.symbolic(kin)]

    @property
    def euclidean(self) -> bool:
        return all(t.euclidean for t in self.tasks)

    def error(self, xi_desired: jax.Array, xi: jax.Array) -> jax.Array:
        """Each part's error on its rows (the difference when every part is euclidean)."""
        if self.euclidean:
            return xi_desired - xi
        parts, start = [], 0
        for t in self.tasks:
            parts.append(t.error(xi_desired[..., start : start + t.dim], xi[..., start : start + t.dim]))
            start += t.dim
        return jnp.concatenate(parts, axis=-1)


def stack(*tasks: Task) -> Stack:
    """Stack tasks row-wise (flattening nested stacks)."""
    flat: list[Task] = []
    for t in tasks:
        flat.extend(t.tasks if isinstance(t, Stack) else (t,))
    return Stack(tuple(flat))
