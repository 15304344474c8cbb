"""Signed distances of points to geometric primitives, in the primitive's own frame, in JAX.

Each function takes points x (..., 3) in the frame of the primitive (centred at its origin, a cylinder's or a
capsule's axis along z) and returns (φ, closest point, outward normal): φ the signed distance (the distance
outside, minus the depth inside), the point of the surface nearest to x and the unit normal n̂ = ∇φ(x) (for a
point inside, that of the nearest face). Closed forms (e.g. Ericson, *Real-Time Collision Detection*, 2005,
§5.1): for a box of half extents h, u = |x| − h and φ = ‖max(u, 0)‖ outside, max_i u_i inside; a sphere
φ = ‖x‖ − a; a cylinder (a, half length ℓ) with ρ = ‖(x₁, x₂)‖, u = (ρ − a, |x₃| − ℓ), φ = ‖max(u, 0)‖
outside, max u inside; a capsule (a, ℓ) φ = ‖x − (0, 0, clip(x₃, −ℓ, ℓ))‖ − a. Where φ is not
differentiable (equidistant faces, a sphere's centre) one of the normals is chosen; every branch is
evaluated with safe arguments, so derivatives through ``jnp.where`` stay finite.
"""

from __future__ import annotations

import jax
import jax.numpy as jnp

_TINY = 1e-30


def norm(v: jnp.ndarray) -> jnp.ndarray:
    """‖v‖ along the last axis, with a finite derivative at 0."""
    squared = jnp.sum(v * v, axis=-1)
    positive = squared > _TINY
    return jnp.where(positive, jnp.sqrt(jnp.where(positive, squared, 1.0)), 0.0)


def unit(v: jnp.ndarray, fallback: jnp.ndarray) -> jnp.ndarray:
    n = norm(v)[..., None]
    return jnp.where(n > 0, v / jnp.where(n > 0, n, 1.0), fallback)


def _sign(x: jnp.ndarray) -> jnp.ndarray:
    return jnp.where(x < 0, -1.0, 1.0)


def box_distance(x: jnp.ndarray, half: jnp.ndarray) -> tuple[jnp.ndarray, jnp.ndarray, jnp.ndarray]:
    """(φ, closest point, outward normal) of points x (..., 3) to boxes of half extents ``half`` (..., 3)
    centred at the origin of their axes."""
    u = jnp.abs(x) - half
    clamped = jnp.clip(x, -half, half)
    outside = jnp.any(u > 0, axis=-1)
    face = jnp.argmax(u, axis=-1)
    axis = jax.nn.one_hot(face, 3, dtype=x.dtype)
    inner_normal = axis * _sign(x)
    inner_point = jnp.where(axis > 0, _sign(x) * half, x)
    gap = x - clamped
    phi = jnp.where(outside, norm(gap), jnp.max(u, axis=-1))
    normal = jnp.where(outside[..., None], unit(gap, inner_normal), inner_normal)
    point = jnp.where(outside[..., None], clamped, inner_point)
    return phi, point, normal


def sphere_distance(x: jnp.ndarray, radius: jnp.ndarray) -> tuple[jnp.ndarray, jnp.ndarray, jnp.ndarray]:
    """(φ, closest point, outward normal) of points x (..., 3) to spheres of ``radius`` (...) at the origin."""
    normal = unit(x, jnp.array([0.0, 0.0, 1.0], dtype=x.dtype))
    return norm(x) - radius, radius[..., None] * normal, normal


def cylinder_distance(
    x: jnp.ndarray, radius: jnp.ndarray, half: jnp.ndarray
) -> tuple[jnp.ndarray, jnp.ndarray, jnp.ndarray]:
    """(φ, closest point, outward normal) of points x (..., 3) to cylinders (``radius``, half length
    ``half``) about the z axis, centred at the origin."""
    xy = x[..., :2]
    rho = norm(xy)
    radial = unit(xy, jnp.array([1.0, 0.0], dtype=x.dtype))
    ur, uz = rho - radius, jnp.abs(x[..., 2]) - half
    z_sign = _sign(x[..., 2])
    outside = (ur > 0) | (uz > 0)
    rim = jnp.concatenate(
        [jnp.minimum(rho, radius)[..., None] * radial, jnp.clip(x[..., 2], -half, half)[..., None]], -1
    )
    side_normal = jnp.concatenate([radial, jnp.zeros_like(x[..., 2:])], -1)
    cap_normal = jnp.concatenate([jnp.zeros_like(xy), z_sign[..., None]], -1)
    side = (ur > uz)[..., None]
    inner_normal = jnp.where(side, side_normal, cap_normal)
    inner_point = jnp.where(
        side,
        jnp.concatenate([radius[..., None] * radial, x[..., 2:]], -1),
        jnp.concatenate([xy, (z_sign * half)[..., None]], -1),
    )
    gap = x - rim
    phi = jnp.where(outside, jnp.hypot(jnp.maximum(ur, 0.0), jnp.maximum(uz, 0.0)), jnp.maximum(ur, uz))
    normal = jnp.where(outside[..., None], unit(gap, inner_normal), inner_normal)
    point = jnp.where(outside[..., None], rim, inner_point)
    return phi, point, normal


def capsule_distance(
    x: jnp.ndarray, radius: jnp.ndarray, half: jnp.ndarray
) -> tuple[jnp.ndarray, jnp.ndarray, jnp.ndarray]:
    """(φ, closest point, outward normal) of points x (..., 3) to capsules (``radius``, segment of half length
    ``half`` along z), centred at the origin."""
    zero = jnp.zeros_like(x[..., 0])
    axis_point = jnp.stack([zero, zero, jnp.clip(x[..., 2], -half, half)], -1)
    normal = unit(x - axis_point, jnp.array([1.0, 0.0, 0.0], dtype=x.dtype))
    return norm(x - axis_point) - radius, axis_point + radius[..., None] * normal, normal


__all__ = ["box_distance", "capsule_distance", "cylinder_distance", "norm", "sphere_distance", "unit"]
