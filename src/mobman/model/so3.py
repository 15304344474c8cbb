"""The rotation group SO(3): exponential and logarithm maps, batched and differentiable.

A rotation vector r = θ a (unit axis a, angle θ = ‖r‖) stands for the rotation matrix given by Rodrigues'
formula (Murray, Li & Sastry, *A Mathematical Introduction to Robotic Manipulation*, 1994, eq. 2.14)

    exp(r) = I + (sin θ / θ) [r]× + ((1 − cos θ) / θ²) [r]×²,

and log is its inverse on angles θ ∈ [0, π] (at θ = π both ±π a are logarithms; one of them is returned).
Both are written so that they are exact, finite and differentiable everywhere they are defined:

- ``exp``: the two coefficients are replaced by their Taylor series when θ² < 1e-6 (truncation error below
  1e-19), so the value and the derivatives at r = 0 are exact.
- ``log``: with v = vee(R − Rᵀ)/2 = sin θ a and c = (tr R − 1)/2 = cos θ, the angle is atan2(‖v‖, c),
  accurate at every angle (arccos c is not, near 0 and π). For θ < π/2 the result is v · θ / sin θ (the
  factor by its series asin(s)/s = 1 + s²/6 + 3s⁴/40 for s² = ‖v‖² < 1e-6); for θ ≥ π/2, where v loses the
  axis as θ → π, the axis comes from the symmetric part, (R + Rᵀ)/2 − c I = (1 − c) a aᵀ, by its column
  with the largest diagonal entry, its sign from v. Every branch is evaluated with safe arguments, so
  derivatives through ``jnp.where`` stay finite.

The functions take (..., 3) rotation vectors and (..., 3, 3) matrices with any leading dimensions; they are
compiled (``jax.jit``), so that calls outside a compiled function do not run their few dozen operations
one by one.
"""

from __future__ import annotations

import jax
import jax.numpy as jnp

from mobman.model import spatial

_SMALL = 1e-6
"""θ² (exp) or sin²θ (log) below which the coefficients are their Taylor series."""


def hat(v: jnp.ndarray) -> jnp.ndarray:
    """[v]×, the cross-product matrix of (..., 3) vectors: [v]× w = v × w."""
    x, y, z = spatial.unstack(v)
    zero = jnp.zeros_like(x)
    return jnp.stack(
        [jnp.stack([zero, -z, y], -1), jnp.stack([z, zero, -x], -1), jnp.stack([-y, x, zero], -1)], -2
    )


def vee(a: jnp.ndarray) -> jnp.ndarray:
    """(A₂₁ − A₁₂, A₀₂ − A₂₀, A₁₀ − A₀₁) / 2: the vector of the skew part of (..., 3, 3) matrices."""
    return 0.5 * jnp.stack(
        [a[..., 2, 1] - a[..., 1, 2], a[..., 0, 2] - a[..., 2, 0], a[..., 1, 0] - a[..., 0, 1]], -1
    )


@jax.jit
def exp(r: jnp.ndarray) -> jnp.ndarray:
    """The rotation matrices (..., 3, 3) of rotation vectors r (..., 3), by Rodrigues' formula."""
    r = jnp.asarray(r, dtype=float)
    theta2 = jnp.sum(r * r, axis=-1)
    small = theta2 < _SMALL
    theta = jnp.sqrt(jnp.where(small, 1.0, theta2))
    a = jnp.where(small, 1.0 - theta2 / 6.0 + theta2**2 / 120.0, jnp.sin(theta) / theta)
    b = jnp.where(small, 0.5 - theta2 / 24.0 + theta2**2 / 720.0, (1.0 - jnp.cos(theta)) / theta**2)
    k = hat(r)
    eye = jnp.eye(3, dtype=r.dtype)
    return eye + a[..., None, None] * k + b[..., None, None] * spatial.matmul(k, k)


@jax.jit
def log(rotation: jnp.ndarray) -> jnp.ndarray:
    """The rotation vectors (..., 3), of angle in [0, π], of rotation matrices (..., 3, 3)."""
    rotation = jnp.asarray(rotation, dtype=float)
    v = vee(rotation)
    c = 0.5 * (rotation[..., 0, 0] + rotation[..., 1, 1] + rotation[..., 2, 2] - 1.0)
    s2 = jnp.sum(v * v, axis=-1)
    positive = s2 > 0.0
    s = jnp.where(positive, jnp.sqrt(jnp.where(positive, s2, 1.0)), 0.0)
    theta = jnp.arctan2(s, c)
    # θ < π/2: v θ / sin θ
    small = s2 < _SMALL
    factor = jnp.where(small, 1.0 + s2 / 6.0 + 0.075 * s2**2, theta / jnp.where(small, 1.0, s))
    near_zero = v * factor[..., None]
    # θ ≥ π/2: the axis from the symmetric part, (R + Rᵀ)/2 − c I = (1 − c) a aᵀ, 1 − c ≥ 1
    wide = c < 0.0
    c_wide = jnp.where(wide, c, -1.0)
    eye = jnp.eye(3, dtype=rotation.dtype)
    outer = (0.5 * (rotation + jnp.swapaxes(rotation, -1, -2)) - c_wide[..., None, None] * eye) / (
        1.0 - c_wide[..., None, None]
    )
    diagonal = jnp.stack([outer[..., 0, 0], outer[..., 1, 1], outer[..., 2, 2]], -1)
    pick = jnp.argmax(diagonal, axis=-1)[..., None] == jnp.arange(3)
    column = jnp.sum(jnp.where(pick[..., None, :], outer, 0.0), axis=-1)
    # the picked entry itself (jnp.max's derivative would average over tied entries)
    axis = column / jnp.sqrt(jnp.sum(jnp.where(pick, diagonal, 0.0), axis=-1))[..., None]
    sign = jnp.where(jnp.sum(axis * v, axis=-1) < 0.0, -1.0, 1.0)
    near_pi = axis * (sign * theta)[..., None]
    return jnp.where(wide[..., None], near_pi, near_zero)


@jax.jit
def error(r_desired: jnp.ndarray, r: jnp.ndarray) -> jnp.ndarray:
    """log(R* Rᵀ) for R* = exp(r_desired), R = exp(r): the rotation vector, in the world frame, that turns
    R into R*."""
    return log(spatial.matmul(exp(r_desired), jnp.swapaxes(exp(r), -1, -2)))


__all__ = ["error", "exp", "hat", "log", "vee"]
