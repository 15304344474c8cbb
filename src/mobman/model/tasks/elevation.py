"""The elevation of an arm frame about its own y axis (Bayle's ξ5 = q5 for the RRP arm, §5.2)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import jax
import jax.numpy as jnp

from mobman.model.tasks.base import SymbolicFrames
from mobman.model.tasks.orientation import OrientationTask

if TYPE_CHECKING:
    import sympy as sp


@dataclass(frozen=True)
class Elevation(OrientationTask):
    """Elevation of an arm frame about its own y axis: minus the pitch of the ZXY Euler set,
    atan2(R₂₀, R₂₂) (Bayle's ξ5 = q5 for the RRP arm, §5.2).

    While the y axis is horizontal (an arm that lifts about it) it is the angle of the x axis above the
    horizontal plane, continuous over the whole turn (−π, π]: ξ5 = q5 through the vertical and past it.
    Undefined only where the y axis is vertical (R₂₀ = R₂₂ = 0).
    """

    kind = "elevation"

    @property
    def names(self) -> tuple[str, ...]:
        return ("elevation",)

    def angles(self, r: jax.Array) -> jax.Array:
        return jnp.arctan2(r[2, 0], r[2, 2])[None]

    def margin(self, r: jax.Array) -> jax.Array:
        return jnp.hypot(r[2, 0], r[2, 2])

    def symbolic_angles(self, r: sp.Matrix, kin: SymbolicFrames) -> list[sp.Expr]:
        return [kin.angle(r[2, 0], r[2, 2])]
