"""Values computed once: a guard against XLA's fusion recomputing a shared value in every consumer.

XLA fuses elementwise operations into loops, and a cheap producer (sums and products) is copied into every
loop that reads it rather than written to memory once. That is right for a value read by one or two
consumers; for a value read by dozens, or by values that are read again, it multiplies the work. Two cases:

- a frame's origin p, read by every column of its Jacobian (a_j × (p − o_j)): p is the end of a chain of
  fixed offsets, and the fused assembly of TIAGo's J̄ would recompute that chain for each of its 60 entries
  (:mod:`mobman.engine.frame_rule`);
- the rounds of a Jacobi sweep, each entry an update of two entries of the round before
  (:mod:`mobman.engine.linalg`): fused, the last round's entries would recompute every earlier round.

:func:`computed_once` makes XLA write its argument to memory once and its consumers read it. It is an
identity on the values (the product reduction of x and 1: exact for every x, −0.0, infinities and NaN
included) and on the derivatives; XLA's CPU runtime does not copy a reduction into its consumers, which is
what stops the recomputation. Other backends get x itself.
"""

from __future__ import annotations

import jax
import jax.numpy as jnp


def computed_once(x: jnp.ndarray) -> jnp.ndarray:
    """x, written to memory once by XLA's CPU runtime so that its consumers read it instead of recomputing
    it (module notes)."""
    if jax.default_backend() != "cpu":
        return x
    return jnp.prod(jnp.stack([x, jnp.ones_like(x)]), axis=0)


__all__ = ["computed_once"]
