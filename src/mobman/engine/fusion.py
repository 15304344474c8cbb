"""Values computed once: a guard against XLA's fusion recomputing a shared value in every consumer.

XLA fuses elementwise operations into loops, and a cheap producer (sums and products) is copied into every
loop that reads it rather than written to memory once. That is right for a value read by one or two
consumers; for a value read by dozens, or by values that are read again, it multiplies the work. Three cases:

- a frame's origin p, read by every column of its Jacobian (a_j × (p − o_j)): p is the end of a chain of
  fixed offsets, and the fused assembly of TIAGo's J̄ would recompute that chain for each of its 60 entries
  (:mod:`mobman.engine.frame_rule`);
- the poses along a chain (:func:`mobman.model.spatial.shared`), each read by every pose after it, and the
  sine and cosine of a joint's angle (:func:`mobman.engine.products.rodrigues`): fused, TIAGo's batched J̄
  evaluated every joint's sine and cosine two to three times;
- the rounds of a Jacobi sweep, each entry an update of two entries of the round before
  (:mod:`mobman.engine.linalg`): fused, the last round's entries would recompute every earlier round.

:func:`computed_once` makes XLA write its argument to memory once and its consumers read it. It is an
identity on the values (the product reduction of x and 1: exact for every x, −0.0, infinities and NaN
included) and on the derivatives; XLA's CPU runtime does not copy a reduction into its consumers, which is
what stops the recomputation. Other backends get x itself.

:func:`computed_once_in_batches` does the same where the value is batched (under ``vmap``, as in every
block of a public batched function) and leaves a one-configuration program as it is: there each stored
value is one more kernel, and a few more kernels cost more than the recomputed scalars.
"""

from __future__ import annotations

import jax
import jax.numpy as jnp

from mobman.engine.kernels import drop_in


def computed_once(x: jnp.ndarray) -> jnp.ndarray:
    """x, written to memory once by XLA's CPU runtime so that its consumers read it instead of recomputing
    it (module notes)."""
    if jax.default_backend() != "cpu":
        return x
    return jnp.prod(jnp.stack([x, jnp.ones_like(x)]), axis=0)


@jax.custom_batching.custom_vmap
def _batched_computed_once(x: jnp.ndarray) -> jnp.ndarray:
    return x


@_batched_computed_once.def_vmap
def _batched_computed_once_rule(
    axis_size: int, in_batched: list[bool], x: jnp.ndarray
) -> tuple[jnp.ndarray, bool]:
    (batched,) = in_batched
    return (computed_once(x) if batched else x), batched


@jax.custom_jvp
def _in_batches(x: jnp.ndarray) -> jnp.ndarray:
    return _batched_computed_once(x)


@_in_batches.defjvp
def _in_batches_jvp(primals: tuple, tangents: tuple) -> tuple[jnp.ndarray, jnp.ndarray]:
    # the tangent passes as it is: linear, so reverse mode can transpose it (a custom_vmap cannot be)
    return _in_batches(primals[0]), tangents[0]


@drop_in("mobman.model.spatial.shared")
def computed_once_in_batches(x: jnp.ndarray) -> jnp.ndarray:
    """x, computed once per batch as :func:`computed_once` where it is batched (``vmap``), x itself in an
    unbatched program (module notes)."""
    if jax.default_backend() != "cpu":
        return x
    return _in_batches(x)


__all__ = ["computed_once", "computed_once_in_batches"]
