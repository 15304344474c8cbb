"""The fixed base: an arm on a platform that does not move."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, ClassVar

import jax.numpy as jnp
import numpy as np

from mobman.model.platforms.base import Footprint, Platform

if TYPE_CHECKING:
    import sympy as sp


@dataclass(frozen=True)
class Fixed(Platform):
    """A base that does not move: q_p = (x, y, θ) is its placement in the world (kept as coordinates, so the
    tasks and the viewer read the base pose), η_p is empty (δ_p = 0), S = 0 (3 × 0) and the constraints
    G = I₃ (q̇_p = 0). A manipulator on it is the classical fixed-base arm (Bayle §4.2 with no platform
    columns)."""

    kind: ClassVar[str] = "fixed"
    coordinate_names: ClassVar[tuple[str, ...]] = ("x", "y", "theta")
    control_names: ClassVar[tuple[str, ...]] = ()
    constant_body_twist: ClassVar[bool] = True

    @property
    def velocity_limits(self) -> tuple[float, ...] | None:
        return ()

    def S(self, q_p: jnp.ndarray) -> jnp.ndarray:
        return jnp.zeros((3, 0), dtype=jnp.result_type(q_p, float))

    def constraints(self, q_p: jnp.ndarray) -> jnp.ndarray:
        return jnp.eye(3, dtype=jnp.result_type(q_p, float))

    def symbolic_S(self, q_p: Sequence[sp.Expr], values: Mapping[str, sp.Expr]) -> sp.Matrix:
        import sympy as sp

        return sp.zeros(3, 0)

    def symbolic_constraints(self, q_p: Sequence[sp.Expr], values: Mapping[str, sp.Expr]) -> sp.Matrix:
        import sympy as sp

        return sp.eye(3)

    def body_twist_matrix(self) -> np.ndarray:
        """B = 0 (3 × 0): the base never moves."""
        return np.zeros((3, 0))

    def actuator_rows(self, q_p: jnp.ndarray) -> jnp.ndarray:
        return jnp.zeros((0, 3), dtype=jnp.result_type(q_p, float))

    def footprint(self) -> Footprint:
        return Footprint(0.3, 0.3, 0.08, 0.0)
