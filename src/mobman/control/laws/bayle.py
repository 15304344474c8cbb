"""Bayle, Fourquet & Renaud (2003), eq. (5)–(6): the pseudo-inverse law with the gradient of a criterion
projected on the self-motions.

η = J̄⁺ (ξ̇* + W e) + (I − J̄⁺J̄) g,  g = −k Hᵀ ∇P,  H = S (I − J̄⁺J̄)  (n_q × δ),  e = ξ* − ξ.
Dimensions: ∇P is n_q (P is a function of q), Hᵀ∇P is δ, so g is a quasi-velocity. Because I − J̄⁺J̄ is a
symmetric projector, (I − J̄⁺J̄) g = g, and Ṗ = ∇ᵀP S η_self = −k ‖Hᵀ∇P‖² ≤ 0. The paper's final formula
"η = J̄⁺(…) − k (∇ᵀP) H Hᵀ (∇P)" is a typo: that expression is the scalar −Ṗ; the control is
η = J̄⁺(ξ̇* + W e) − k Hᵀ∇P. With J̄⁺ a right inverse the error obeys ė + W e = 0.
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
from mobman.errors import ModelError
from mobman.model.spatial import matvec


@pytree("W", "k", "criterion", "damping", "damping_threshold")
@dataclass(frozen=True, eq=False)
class BaylePseudoInverse(PseudoInverseLaw):
    """Bayle eq. (5)–(6): η = J̄⁺(ξ̇* + W e) − k Hᵀ∇P, H = S (I − J̄⁺J̄). ``criterion=None``: no self-motion.

    ``W``: m-order positive-definite error gain (scalar, diagonal vector or matrix), 1/s; ``k`` ≥ 0.
    """

    kind = "bayle"
    gains = ("W", "k")

    W: npt.ArrayLike = 1.0
    k: npt.ArrayLike = 0.0
    criterion: Criterion | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "W", positive_gain(self.W, "W", "BaylePseudoInverse"))
        k = positive_gain(self.k, "k", "BaylePseudoInverse", allow_zero=True)
        object.__setattr__(self, "k", k)
        if k.ndim:
            raise ModelError(f"BaylePseudoInverse: k must be a scalar ≥ 0, got {self.k!r}")
        self.check_options("BaylePseudoInverse")

    def feedback_term(self, e: jax.Array) -> jax.Array:
        return apply_gain(self.W, e, "W")

    def self_motion(self, projector: jax.Array, s_scaled: jax.Array, grad: jax.Array) -> jax.Array:
        # Hᵀ ∇P with H = S R (I − J⁺J) (n_q × δ), as (I − J⁺J)ᵀ ((S R)ᵀ ∇P): two products with vectors
        # instead of forming H
        return -matvec(projector.T, matvec(s_scaled.T, grad)) * jnp.asarray(self.k)


__all__ = ["BaylePseudoInverse"]
