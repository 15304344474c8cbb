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

The formulas are written on the points' components x₁, x₂, x₃ one by one (no reduction over an axis of
length 3): XLA then evaluates a distance as one elementwise loop over the points, about twice as fast as
with the components as the last axis of the intermediate arrays (``benchmarks/collision.py``).
"""

from __future__ import annotations

import jax.numpy as jnp

_TINY = 1e-30


def norm(v: jnp.ndarray) -> jnp.ndarray:
    """‖v‖ along the last axis, with a finite derivative at 0."""
    return _norm(*_split(v))


def unit(v: jnp.ndarray, fallback: jnp.ndarray) -> jnp.ndarray:
    """v / ‖v‖ along the last axis, ``fallback`` where v = 0."""
    return jnp.stack(_unit(_split(v), _split(jnp.broadcast_to(fallback, v.shape))), -1)


def _split(x: jnp.ndarray) -> tuple[jnp.ndarray, ...]:
    """The components x[..., 0], x[..., 1], … of points x (..., k): every function below works on them one by
    one, so that XLA fuses a distance into one elementwise loop (no reduction over an axis of length 3)."""
    return tuple(x[..., k] for k in range(x.shape[-1]))


def _norm(*components: jnp.ndarray) -> jnp.ndarray:
    squared = sum(c * c for c in components)
    positive = squared > _TINY
    return jnp.where(positive, jnp.sqrt(jnp.where(positive, squared, 1.0)), 0.0)


def _unit(v: tuple[jnp.ndarray, ...], fallback: tuple[jnp.ndarray, ...]) -> tuple[jnp.ndarray, ...]:
    n = _norm(*v)
    safe = jnp.where(n > 0, n, 1.0)
    return tuple(jnp.where(n > 0, c / safe, f) for c, f in zip(v, fallback))


def _sign(x: jnp.ndarray) -> jnp.ndarray:
    return jnp.where(x < 0, -1.0, 1.0)


def box_distance(x: jnp.ndarray, half: jnp.ndarray) -> tuple[jnp.ndarray, jnp.ndarray, jnp.ndarray]:
    """(φ, closest point, outward normal) of points x (..., 3) to boxes of half extents ``half`` (..., 3)
    centred at the origin of their axes. Inside, the face is that of the largest u_i (the first on a tie)."""
    xs, hs = _split(x), _split(jnp.broadcast_to(half, x.shape))
    u = [jnp.abs(xi) - hi for xi, hi in zip(xs, hs)]
    clamped = [jnp.clip(xi, -hi, hi) for xi, hi in zip(xs, hs)]
    outside = (u[0] > 0) | (u[1] > 0) | (u[2] > 0)
    first = (u[0] >= u[1]) & (u[0] >= u[2])
    second = ~first & (u[1] >= u[2])
    face = (first, second, ~first & ~second)
    inner_normal = [jnp.where(f, _sign(xi), 0.0) for f, xi in zip(face, xs)]
    inner_point = [jnp.where(f, _sign(xi) * hi, xi) for f, xi, hi in zip(face, xs, hs)]
    gap = [xi - ci for xi, ci in zip(xs, clamped)]
    phi = jnp.where(outside, _norm(*gap), jnp.maximum(jnp.maximum(u[0], u[1]), u[2]))
    normal = [jnp.where(outside, n, i) for n, i in zip(_unit(tuple(gap), tuple(inner_normal)), inner_normal)]
    point = [jnp.where(outside, c, i) for c, i in zip(clamped, inner_point)]
    return phi, jnp.stack(point, -1), jnp.stack(normal, -1)


def sphere_distance(x: jnp.ndarray, radius: jnp.ndarray) -> tuple[jnp.ndarray, jnp.ndarray, jnp.ndarray]:
    """(φ, closest point, outward normal) of points x (..., 3) to spheres of ``radius`` (...) at the origin."""
    xs = _split(x)
    zero, one = jnp.zeros_like(xs[0]), jnp.ones_like(xs[0])
    normal = _unit(xs, (zero, zero, one))
    return _norm(*xs) - radius, jnp.stack([radius * n for n in normal], -1), jnp.stack(normal, -1)


def cylinder_distance(
    x: jnp.ndarray, radius: jnp.ndarray, half: jnp.ndarray
) -> tuple[jnp.ndarray, jnp.ndarray, jnp.ndarray]:
    """(φ, closest point, outward normal) of points x (..., 3) to cylinders (``radius``, half length
    ``half``) about the z axis, centred at the origin."""
    x1, x2, x3 = _split(x)
    zero, one = jnp.zeros_like(x1), jnp.ones_like(x1)
    rho = _norm(x1, x2)
    r1, r2 = _unit((x1, x2), (one, zero))
    ur, uz = rho - radius, jnp.abs(x3) - half
    z_sign = _sign(x3)
    outside = (ur > 0) | (uz > 0)
    side = ur > uz
    rim = (jnp.minimum(rho, radius) * r1, jnp.minimum(rho, radius) * r2, jnp.clip(x3, -half, half))
    inner_normal = (jnp.where(side, r1, 0.0), jnp.where(side, r2, 0.0), jnp.where(side, 0.0, z_sign))
    inner_point = (
        jnp.where(side, radius * r1, x1),
        jnp.where(side, radius * r2, x2),
        jnp.where(side, x3, z_sign * half),
    )
    gap = (x1 - rim[0], x2 - rim[1], x3 - rim[2])
    phi = jnp.where(outside, _norm(jnp.maximum(ur, 0.0), jnp.maximum(uz, 0.0)), jnp.maximum(ur, uz))
    normal = [jnp.where(outside, n, i) for n, i in zip(_unit(gap, inner_normal), inner_normal)]
    point = [jnp.where(outside, r, i) for r, i in zip(rim, inner_point)]
    return phi, jnp.stack(point, -1), jnp.stack(normal, -1)


def capsule_distance(
    x: jnp.ndarray, radius: jnp.ndarray, half: jnp.ndarray
) -> tuple[jnp.ndarray, jnp.ndarray, jnp.ndarray]:
    """(φ, closest point, outward normal) of points x (..., 3) to capsules (``radius``, segment of half length
    ``half`` along z), centred at the origin."""
    x1, x2, x3 = _split(x)
    zero, one = jnp.zeros_like(x1), jnp.ones_like(x1)
    axis = jnp.clip(x3, -half, half)
    away = (x1, x2, x3 - axis)
    normal = _unit(away, (one, zero, zero))
    point = (radius * normal[0], radius * normal[1], axis + radius * normal[2])
    return _norm(*away) - radius, jnp.stack(point, -1), jnp.stack(normal, -1)


__all__ = ["box_distance", "capsule_distance", "cylinder_distance", "norm", "sphere_distance", "unit"]
