"""Tasks that are user functions of the generalized coordinates, and Korayem's elbow angle (eq. 35)."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import jax
import jax.numpy as jnp
import numpy as np

from mobman.errors import ModelError
from mobman.model.tasks.base import SymbolicFrames, Task

if TYPE_CHECKING:
    import sympy as sp

    from mobman.model.robot import Frames, MobileManipulator


@dataclass(frozen=True)
class FunctionTask(Task):
    """A user function of the generalized coordinates, ξ = fn(q) for one configuration (shape (m,)).

    Its Jacobian is obtained by autodiff, so ``fn`` must be written with ``jax.numpy``; its closed form
    (:mod:`mobman.symbolic`) evaluates ``fn`` on a NumPy object array of SymPy symbols. Example: Korayem's
    elbow angle β = π − θ2 is ``FunctionTask(lambda q: jnp.pi - q[4:5], ("beta",))`` (:class:`ElbowAngle`).
    A Python function has no name in files: files name :class:`ElbowAngle` by its kind.
    """

    fn: Callable[[jnp.ndarray], jnp.ndarray] = None  # type: ignore[assignment]
    labels: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        if not callable(self.fn):
            raise ModelError("FunctionTask: fn must be a callable of q")
        if not self.labels:
            raise ModelError("FunctionTask: give the names (labels) of the outputs")

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(self.labels)

    def value(self, robot: MobileManipulator, q: jax.Array, frames: Frames) -> jax.Array:
        return jnp.reshape(jnp.asarray(self.fn(q)), (self.dim,))

    def symbolic(self, kin: SymbolicFrames) -> list[sp.Expr]:
        import sympy as sp

        q: Any = np.empty(len(kin.q), dtype=object)  # SymPy symbols through the jax.numpy function
        q[:] = kin.q
        try:
            out = np.asarray(self.fn(q), dtype=object).reshape(-1)
        except Exception as exc:
            raise ModelError(
                f"symbolic: FunctionTask {self.names} cannot be evaluated on SymPy symbols ({exc}); write it "
                "with operations that accept a NumPy object array"
            ) from None
        return [kin.exact(sp.sympify(v)) for v in out]


def elbow_angle(q: jnp.ndarray) -> jnp.ndarray:
    """Korayem's elbow angle β = π − θ2 (eq. 35) for ``korayem_planar`` (q = x, y, θ, θ1, θ2)."""
    return jnp.pi - q[4:5]


@dataclass(frozen=True)
class ElbowAngle(FunctionTask):
    """Korayem's elbow angle β = π − θ2 (eq. 35) of ``korayem_planar``, the function task of :func:`elbow_angle`
    with the output name ``beta``: the values and Jacobian of ``FunctionTask(elbow_angle, ("beta",))``."""

    kind = "elbow_angle"

    # factories: a plain default of a field that is not an argument would be read as a class attribute (a method)
    fn: Callable[[jnp.ndarray], jnp.ndarray] = field(default_factory=lambda: elbow_angle, init=False)
    labels: tuple[str, ...] = field(default_factory=lambda: ("beta",), init=False)
