"""Korayem, Nikoobin & Azimirad (2009), eq. (30): the augmented Jacobian.

The rows [J_c; J_e; J_z] q̇ = [0; ẋ_e; ẋ_n], the nonholonomic constraints, the task and a user-chosen extra
task, form a square system. Solved in quasi-velocities, [J̄; J̄_z] η = [ξ̇* + K e] (the constraint rows are
satisfied by q̇ = S η); the step's ``det`` is |det| of Korayem's n_q × n_q matrix [G; J; J_z].
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import jax
import jax.numpy as jnp
import numpy.typing as npt

from mobman.control._tree import pytree
from mobman.control.laws.base import Law, LawStep, apply_gain, damped_inverse, positive_gain
from mobman.errors import ModelError
from mobman.model.spatial import matvec
from mobman.model.tasks import Task, stack

if TYPE_CHECKING:
    from mobman.model.robot import MobileManipulator


@pytree("eta", "damping", "sigma_min", "limit_ratio", "saturated", "damped", "det")
@dataclass(frozen=True)
class AugmentedStep(LawStep):
    """A :class:`~mobman.control.laws.base.LawStep` with ``det`` = |det [G; J; J_z]| (Korayem eq. 30)."""

    det: jnp.ndarray | None = None


@pytree("feedback", "damping", "damping_threshold")
@dataclass(frozen=True, eq=False)
class AugmentedJacobian(Law):
    """Korayem eq. (30): the square system [J̄; J̄_z] η = ξ̇* + K e over the stacked task (task, extra).

    ``extra``: a model :class:`~mobman.model.tasks.Task` with n_eta − task.dim rows (Korayem's choices:
    ``stack(PlanarAngle(), ElbowAngle())`` or ``MountPosition()``); the reference then has task.dim +
    extra.dim components (:meth:`controlled_task`). ``feedback`` K on the whole stacked error (None: 0).
    """

    kind = "augmented"
    gains = ("feedback",)

    extra: Task | None = None
    feedback: npt.ArrayLike | None = None

    def __post_init__(self) -> None:
        if not isinstance(self.extra, Task):
            raise ModelError("AugmentedJacobian: extra must be a model Task (the extra rows J_z)")
        if self.feedback is not None:
            object.__setattr__(
                self, "feedback", positive_gain(self.feedback, "feedback", "AugmentedJacobian")
            )
        self.check_options("AugmentedJacobian")

    @property
    def rows(self) -> Task:
        """The extra task (checked to be a Task when the law is made)."""
        assert isinstance(self.extra, Task)
        return self.extra

    def controlled_task(self, task: Task) -> Task:
        """The task stacked with the extra rows."""
        return stack(task, self.rows)

    def __call__(
        self,
        robot: MobileManipulator,
        task: Task | None,
        q: jax.Array,
        t: jax.Array,
        xi_star: jax.Array,
        xi_star_dot: jax.Array,
    ) -> AugmentedStep:
        task = robot.task if task is None else task
        if task.dim + self.rows.dim != robot.n_eta:
            raise ModelError(
                f"AugmentedJacobian: task ({task.dim}) + extra ({self.rows.dim}) rows must equal "
                f"n_eta = {robot.n_eta} of {robot.name}"
            )
        frames = robot.frames(q)
        xi = jnp.concatenate([task.value(robot, q, frames), self.rows.value(robot, q, frames)])
        jac = jnp.concatenate([task.jacobian(robot, q, frames), self.rows.jacobian(robot, q, frames)])
        scale = self.scale(robot)
        e = self.controlled_task(task).error(xi_star, xi)
        rhs = xi_star_dot if self.feedback is None else xi_star_dot + apply_gain(self.feedback, e, "feedback")
        jt = robot.apply_S(jac, q) * scale
        inverse, lam2, sigma_min = damped_inverse(jt, self.damping, self.damping_threshold)
        det = jnp.abs(jnp.linalg.det(jnp.concatenate([robot.constraints(q), jac])))
        eta, ratio, saturated = self.saturation(robot, matvec(inverse, rhs) * scale)
        return AugmentedStep(eta, lam2, sigma_min, ratio, saturated, lam2 > 0, det=det)


__all__ = ["AugmentedJacobian", "AugmentedStep"]
