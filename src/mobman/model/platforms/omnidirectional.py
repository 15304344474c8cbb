"""The holonomic (omnidirectional) platform, S = I."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, ClassVar

import jax.numpy as jnp

from mobman.model.platforms.base import Platform, limits

if TYPE_CHECKING:
    import sympy as sp


@dataclass(frozen=True)
class Omnidirectional(Platform):
    """Holonomic platform, S = I: q_p = (x, y, θ), η_p = (ẋ, ẏ, θ̇) in the world frame; no constraint.

    ``limits``: maximum |ẋ|, |ẏ|, |θ̇| (m/s, m/s, rad/s), or None.
    """

    limits: tuple[float, float, float] | None = field(default=None)

    kind: ClassVar[str] = "omnidirectional"
    coordinate_names: ClassVar[tuple[str, ...]] = ("x", "y", "theta")
    control_names: ClassVar[tuple[str, ...]] = ("vx", "vy", "omega")

    def __post_init__(self) -> None:
        object.__setattr__(self, "limits", limits(self.limits, 3, "limits", "Omnidirectional"))

    @property
    def velocity_limits(self) -> tuple[float, ...] | None:
        return self.limits

    def S(self, q_p: jnp.ndarray) -> jnp.ndarray:
        return jnp.eye(3, dtype=jnp.result_type(q_p, float))

    def constraints(self, q_p: jnp.ndarray) -> jnp.ndarray:
        return jnp.zeros((0, 3), dtype=jnp.result_type(q_p, float))

    def symbolic_S(self, q_p: Sequence[sp.Expr], values: Mapping[str, sp.Expr]) -> sp.Matrix:
        import sympy as sp

        return sp.eye(3)

    def symbolic_constraints(self, q_p: Sequence[sp.Expr], values: Mapping[str, sp.Expr]) -> sp.Matrix:
        import sympy as sp

        return sp.zeros(0, 3)
