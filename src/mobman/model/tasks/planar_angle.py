"""The heading of an arm frame about the vertical (Bayle's ξ3 in §5.1 and ξ4 in §5.2, Korayem's α_e)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import jax
import jax.numpy as jnp

from mobman.errors import ModelError
from mobman.model import spatial
from mobman.model.tasks.base import SymbolicFrames
from mobman.model.tasks.orientation import OrientationTask

if TYPE_CHECKING:
    import sympy as sp

HEADING_SEQUENCES = ("ZYX", "ZXY")
"""The Euler sets whose yaw :class:`PlanarAngle` gives."""


@dataclass(frozen=True)
class PlanarAngle(OrientationTask):
    """Heading of an arm frame about the vertical: the yaw (first angle) of the Euler set ``sequence``.

    ``sequence="ZYX"`` (default): the heading of the frame's x axis, atan2(R₁₀, R₀₀) (Bayle's ξ3 in §5.1,
    Korayem's α_e; for a planar robot the sum of the platform angle and the joint angles); undefined where the
    x axis is vertical.
    ``sequence="ZXY"``: the heading of the frame's x–z plane, atan2(−R₀₁, R₁₁), undefined only where the
    y axis is vertical: for an arm that lifts about its y axis it stays ϑ + q4 through the vertical and past
    it (Bayle §5.2, ξ4 = q3 + q4). Continuous away from ±π, where it wraps.
    """

    kind = "planar_angle"
    choices = {"sequence": HEADING_SEQUENCES}

    sequence: str = "ZYX"

    def __post_init__(self) -> None:
        if self.sequence not in HEADING_SEQUENCES:
            raise ModelError(
                f"PlanarAngle: sequence {self.sequence!r} not supported; allowed: {', '.join(HEADING_SEQUENCES)}"
            )

    @property
    def names(self) -> tuple[str, ...]:
        return ("angle",)

    def angles(self, r: jax.Array) -> jax.Array:
        if self.sequence == "ZYX":
            return jnp.arctan2(r[1, 0], r[0, 0])[None]
        return jnp.arctan2(-r[0, 1], r[1, 1])[None]

    def margin(self, r: jax.Array) -> jax.Array:
        return spatial.gimbal_margin(r, self.sequence)

    def symbolic_angles(self, r: sp.Matrix, kin: SymbolicFrames) -> list[sp.Expr]:
        if self.sequence == "ZYX":
            return [kin.angle(r[1, 0], r[0, 0])]
        return [kin.angle(-r[0, 1], r[1, 1])]
