"""The pseudo-inverse laws with self-motion (Bayle eq. 5–6, Nait-Chabane eq. 30): η̃ = J̃#(ξ̇* + K e) + a
null-space term from a criterion P(q), η = R η̃ with J̃ = J̄ R."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import jax
import jax.numpy as jnp

from mobman.control._tree import pytree
from mobman.control.criteria import Criterion
from mobman.control.laws.base import Law, LawStep, damped_inverse
from mobman.model.spatial import matmul, matvec

if TYPE_CHECKING:
    from mobman.model.robot import MobileManipulator
    from mobman.model.tasks import Task


@pytree("eta", "damping", "sigma_min", "limit_ratio", "saturated", "damped", "P")
@dataclass(frozen=True)
class PseudoInverseStep(LawStep):
    """A :class:`~mobman.control.laws.base.LawStep` with ``P``, the criterion's value (None without one)."""

    P: jnp.ndarray | None = None


@dataclass(frozen=True, eq=False)
class PseudoInverseLaw(Law):
    """Base of the laws η̃ = J̃#(ξ̇* + K e) + self-motion. Subclasses give ``feedback_term(e)`` (K e) and
    ``self_motion(projector, s_scaled, grad)`` (the null-space term from ∇P, in the scaled coordinates), and
    a ``criterion`` field (None: no self-motion)."""

    criterion: Criterion | None = None

    def feedback_term(self, e: jax.Array) -> jax.Array:
        raise NotImplementedError

    def self_motion(self, projector: jax.Array, s_scaled: jax.Array, grad: jax.Array) -> jax.Array:
        raise NotImplementedError

    def __call__(
        self,
        robot: MobileManipulator,
        task: Task | None,
        q: jax.Array,
        t: jax.Array,
        xi_star: jax.Array,
        xi_star_dot: jax.Array,
    ) -> PseudoInverseStep:
        task = robot.task if task is None else task
        frames = robot.frames(q)
        xi = task.value(robot, q, frames)
        scale = self.scale(robot)
        jt = task.reduced_jacobian(robot, q, frames) * scale
        e = task.error(xi_star, xi)
        inverse, lam2, sigma_min = damped_inverse(jt, self.damping, self.damping_threshold)
        eta = matvec(inverse, xi_star_dot + self.feedback_term(e))
        value = None
        criterion = self.criterion
        if criterion is not None:
            value, grad = jax.value_and_grad(lambda qq: criterion(robot, qq, task, xi_star))(q)
            projector = jnp.eye(robot.n_eta, dtype=jt.dtype) - matmul(inverse, jt)
            eta = eta + self.self_motion(projector, robot.S(q) * scale, grad)
        eta, ratio, saturated = self.saturation(robot, eta * scale)
        return PseudoInverseStep(eta, lam2, sigma_min, ratio, saturated, lam2 > 0, P=value)


__all__ = ["PseudoInverseLaw", "PseudoInverseStep"]
