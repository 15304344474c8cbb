"""Nait-Chabane, Hoppenot & Colle (2006), eq. (30): u = J̄⁺ Ẋd − (I − J̄⁺J̄) W (∂P/∂q · M)ᵀ with M = S.

The optional ``feedback`` K adds J̄⁺ K e (eq. 30 itself is open loop). For W = k I it equals the Bayle law;
for a general W the product (I − J̄⁺J̄) W is not symmetric and Ṗ ≤ 0 is no longer guaranteed.
"""

from __future__ import annotations

from dataclasses import dataclass

import jax
import jax.numpy as jnp
import numpy.typing as npt

from mobman.control._tree import pytree
from mobman.control.criteria import Criterion
from mobman.control.laws.base import apply_gain, positive_gain
from mobman.control.laws.pseudo_inverse import PseudoInverseLaw
from mobman.model.spatial import matvec


@pytree("W", "criterion", "feedback", "damping", "damping_threshold")
@dataclass(frozen=True, eq=False)
class NaitChabane(PseudoInverseLaw):
    """Nait-Chabane eq. (30): u = J̄⁺(Ẋd + K e) − (I − J̄⁺J̄) W (∂P/∂q · S)ᵀ; ``feedback`` K (None: open loop).

    ``W``: δ-order positive-definite null-space weighting (scalar, vector or matrix).
    """

    kind = "nait-chabane"
    gains = ("W", "feedback")

    W: npt.ArrayLike = 1.0
    criterion: Criterion | None = None
    feedback: npt.ArrayLike | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "W", positive_gain(self.W, "W", "NaitChabane"))
        if self.feedback is not None:
            object.__setattr__(self, "feedback", positive_gain(self.feedback, "feedback", "NaitChabane"))
        self.check_options("NaitChabane")

    def feedback_term(self, e: jax.Array) -> jax.Array:
        return jnp.zeros_like(e) if self.feedback is None else apply_gain(self.feedback, e, "feedback")

    def self_motion(self, projector: jax.Array, s_scaled: jax.Array, grad: jax.Array) -> jax.Array:
        return -matvec(projector, apply_gain(self.W, matvec(s_scaled.T, grad), "W"))


__all__ = ["NaitChabane"]
