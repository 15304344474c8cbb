"""Finite parametrisations of the platform controls u(t) = Σ_k λ_k φ_k(t) on [0, T] (Tchoń et al. §4).

Both bases are orthonormal in L²[0, T], so the inner product (2) of two controls equals the Euclidean inner
product of their coefficient vectors: the endogenous configuration space becomes R^{m·N} × R^p with its
ordinary metric, and the adjoint Jacobian (28) restricted to the span is the transposed matrix Jᵀ.
"""

from __future__ import annotations

from dataclasses import dataclass

import jax.numpy as jnp

from mobman.errors import InputError


@dataclass(frozen=True)
class Basis:
    """Common interface: ``size`` functions φ_k evaluated by ``values(t, horizon)``."""

    @property
    def size(self) -> int:
        raise NotImplementedError

    @property
    def pieces(self) -> int:
        """Number of equal intervals of [0, T] on which φ is smooth (integration steps must divide it)."""
        return 1

    def values(self, t: jnp.ndarray, horizon: float, within: jnp.ndarray | None = None) -> jnp.ndarray:
        """φ(t), shape (size,), for one instant t ∈ [0, horizon].

        ``within`` is an instant inside the same integration step: at a discontinuity it selects the side
        of the step (a Runge–Kutta step evaluates its end point with the control of that step).
        """
        raise NotImplementedError


@dataclass(frozen=True)
class Fourier(Basis):
    """Truncated Fourier series with ``harmonics`` harmonics, orthonormal on [0, T]:

    φ = (1, √2 sin ω t, √2 cos ω t, √2 sin 2ω t, √2 cos 2ω t, …) / √T, ω = 2π/T.

    With T = 1 and two harmonics this is exactly the paper's §4 series, coefficient order λ0, λ1 (sin 2πt),
    λ2 (cos 2πt), λ3 (sin 4πt), λ4 (cos 4πt).
    """

    harmonics: int = 2

    def __post_init__(self) -> None:
        if not isinstance(self.harmonics, int) or self.harmonics < 0:
            raise InputError(f"harmonics must be an integer ≥ 0, got {self.harmonics!r}")

    @property
    def size(self) -> int:
        return 1 + 2 * self.harmonics

    def values(self, t: jnp.ndarray, horizon: float, within: jnp.ndarray | None = None) -> jnp.ndarray:
        k = jnp.arange(1, self.harmonics + 1)
        phase = 2.0 * jnp.pi * k * t / horizon
        pairs = jnp.stack([jnp.sin(phase), jnp.cos(phase)], axis=-1).reshape(-1)
        return jnp.concatenate([jnp.ones(1), jnp.sqrt(2.0) * pairs]) / jnp.sqrt(horizon)


@dataclass(frozen=True)
class PiecewiseConstant(Basis):
    """``count`` equal intervals, φ_k = 1/√(T/N) on [kT/N, (k+1)T/N), zero elsewhere (orthonormal)."""

    count: int = 10

    def __post_init__(self) -> None:
        if not isinstance(self.count, int) or self.count < 1:
            raise InputError(f"count (number of pieces) must be an integer ≥ 1, got {self.count!r}")

    @property
    def size(self) -> int:
        return self.count

    @property
    def pieces(self) -> int:
        return self.count

    def values(self, t: jnp.ndarray, horizon: float, within: jnp.ndarray | None = None) -> jnp.ndarray:
        width = horizon / self.count
        index = jnp.clip(jnp.floor((t if within is None else within) / width), 0, self.count - 1)
        return jnp.where(jnp.arange(self.count) == index, 1.0 / jnp.sqrt(width), 0.0)
