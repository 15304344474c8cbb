"""Small-matrix products written out for XLA's CPU runtime: drop-ins for the plain products of
:mod:`mobman.model.spatial` and Rodrigues' formula of :mod:`mobman.model.arm`.

- **No reductions.** Batched, XLA hands a reduction (``a @ b``, ``jnp.sum``) to a library kernel, slow for
  3 × 3 and 6 × 6 matrices, and for one configuration each small product becomes a kernel of its own. Written
  out as sums of outer products (:func:`matmul_expanded`), the products fuse with their neighbours as
  elementwise loops.
- **Constants as Python scalars.** A robot's fixed transforms are NumPy constants; multiplying by them entry
  by entry with the entries as Python floats (:func:`combine`) leaves no constant array in the compiled
  program (XLA's CPU runtime sets every constant array up again at each call) and no product by a structural
  0 or ±1 (a Denavit–Hartenberg origin is mostly zeros and ones).
- **One split.** The components of an array are taken by one ``lax.split`` (:func:`unstack`), whose
  reverse-mode transpose is one concatenation, where separate slices each transpose to a padded array.
"""

from __future__ import annotations

from typing import Sequence

import jax
import jax.numpy as jnp
import numpy as np

from mobman.engine.fusion import computed_once_in_batches
from mobman.engine.kernels import drop_in


@drop_in("mobman.model.spatial.unstack")
def unstack(a: jnp.ndarray, axis: int = -1) -> list[jnp.ndarray]:
    """The components of a along ``axis``, as one ``lax.split``."""
    return [jnp.squeeze(x, axis) for x in jax.lax.split(a, (1,) * a.shape[axis], axis=axis)]


@drop_in("mobman.model.spatial.rows")
def rows(x: jnp.ndarray, indices: tuple[int, ...]) -> jnp.ndarray:
    """x[indices] for static row indices from one split of x: indexing with an integer array compiles to a
    gather, a kernel of its own (and a scatter in reverse-mode derivatives), and a slice per row transposes to
    a padded array per row."""
    if indices == tuple(range(x.shape[0])):
        return x
    parts = unstack(x, axis=0)
    return jnp.stack([parts[i] for i in indices])


@drop_in("mobman.model.spatial.matmul_expanded")
def matmul_expanded(a: jnp.ndarray, b: jnp.ndarray) -> jnp.ndarray:
    """a @ b for stacks of small matrices, as the sum of the outer products of a's columns and b's rows."""
    terms = [c[..., :, None] * r[..., None, :] for c, r in zip(unstack(a), unstack(b, axis=-2))]
    return sum(terms[1:], terms[0])


def combine(vectors: Sequence[jnp.ndarray], weights: Sequence[float] | np.ndarray) -> jnp.ndarray | None:
    """Σ_k w_k v_k for constant weights, written out over the nonzero ones (±1 without a product); None
    when every weight is zero."""
    terms = [
        v if w == 1.0 else -v if w == -1.0 else float(w) * v for v, w in zip(vectors, weights) if w != 0.0
    ]
    return None if not terms else sum(terms[1:], terms[0])


@drop_in("mobman.model.spatial.matvec_constant")
def matvec_constant(a: jnp.ndarray, v: np.ndarray) -> jnp.ndarray:
    """a @ v for stacks of matrices a and a constant NumPy vector v, v's entries as scalars."""
    out = combine(unstack(a), np.asarray(v, dtype=float))
    return jnp.zeros(a.shape[:-1], a.dtype) if out is None else out


@drop_in("mobman.model.spatial.matmul_constant")
def matmul_constant(a: jnp.ndarray, c: np.ndarray) -> jnp.ndarray:
    """a @ c for stacks of matrices a and a constant NumPy matrix c, column by column, c's entries as
    scalars."""
    columns = unstack(a)
    out = [combine(columns, weights) for weights in np.asarray(c, dtype=float).T]
    return jnp.stack([jnp.zeros_like(columns[0]) if o is None else o for o in out], axis=-1)


def constant_combination(matrices: Sequence[np.ndarray], factors: Sequence[jnp.ndarray]) -> jnp.ndarray:
    """Σ_n f_n M_n, shape (..., rows, cols), for constant NumPy matrices M_n and batched scalars f_n, entry
    by entry with the entries of M_n as Python scalars (:func:`combine`)."""
    stacked = np.stack([np.asarray(m, dtype=float) for m in matrices], axis=-1)
    zero = jnp.zeros_like(factors[0])
    rows = [[combine(factors, weights) for weights in row] for row in stacked]
    return jnp.stack([jnp.stack([zero if e is None else e for e in row], -1) for row in rows], -2)


@drop_in("mobman.model.arm.rodrigues")
def rodrigues(r_o: np.ndarray, k: np.ndarray, angle: jnp.ndarray) -> jnp.ndarray:
    """R_o (I + sin θ K + (1 − cos θ) K²) as Σ f_n M_n with the constants M_n = R_o, R_o K, R_o K²
    (:func:`constant_combination`); sin θ and 1 − cos θ are computed once for all nine entries
    (:func:`~mobman.engine.fusion.computed_once_in_batches`)."""
    r_o, k = np.asarray(r_o, dtype=float), np.asarray(k, dtype=float)
    sin, one_minus_cos = unstack(
        computed_once_in_batches(jnp.stack([jnp.sin(angle), 1.0 - jnp.cos(angle)], -1))
    )
    return constant_combination((r_o, r_o @ k, r_o @ k @ k), (jnp.ones_like(angle), sin, one_minus_cos))


@drop_in("mobman.model.spatial.cross")
def cross(a: jnp.ndarray, b: jnp.ndarray, axis: int = -1) -> jnp.ndarray:
    """Cross product along ``axis``, written out component by component (``jnp.cross`` moves the axis and
    gathers under ``vmap``)."""
    a0, a1, a2 = unstack(a, axis)
    b0, b1, b2 = unstack(b, axis)
    return jnp.stack([a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0], axis=axis)


__all__ = [
    "combine",
    "constant_combination",
    "cross",
    "matmul_constant",
    "matmul_expanded",
    "matvec_constant",
    "rodrigues",
    "unstack",
]
