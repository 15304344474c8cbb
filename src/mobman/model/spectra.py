"""Spectra of small symmetric matrices: the eigenvalues behind the singular values of a Jacobian.

The singular values σ_1 ≥ … ≥ σ_p of J (m × k, p = min(m, k)) are the square roots of the eigenvalues of
the smaller Gram matrix, J Jᵀ or Jᵀ J (Nait-Chabane eq. 15–17). These are the plain definitions; the engine
runs a batched Jacobi solver in their place (:mod:`mobman.engine.linalg`), and a batch's extreme eigenvalues
and determinants by Laguerre's method (:mod:`mobman.engine.extremes`).
"""

from __future__ import annotations

import jax.numpy as jnp

from mobman.engine.kernels import definition
from mobman.model.spatial import matmul_expanded


@definition
def eigvalsh(a: jnp.ndarray) -> jnp.ndarray:
    """Eigenvalues of symmetric matrices a (..., n, n), in descending order, shape (..., n)."""
    return jnp.linalg.eigvalsh(a)[..., ::-1]


@definition
def eigh(a: jnp.ndarray) -> tuple[jnp.ndarray, jnp.ndarray]:
    """Eigenvalues (..., n) in descending order and the matching unit eigenvectors (..., n, n) as columns."""
    w, v = jnp.linalg.eigh(a)
    return w[..., ::-1], v[..., ::-1]


@definition
def extremes(a: jnp.ndarray) -> tuple[jnp.ndarray, jnp.ndarray, jnp.ndarray]:
    """λ_max, λ_min and det = ∏ λ_i of symmetric matrices a (..., n, n), each of shape (...): what the
    manipulability measures read of a Gram matrix (Nait-Chabane eq. 17–19)."""
    w = jnp.linalg.eigvalsh(a)
    return w[..., -1], w[..., 0], jnp.prod(w, axis=-1)


def gram(a: jnp.ndarray) -> jnp.ndarray:
    """The smaller Gram matrix of (..., m, k): A Aᵀ (m × m) if m ≤ k, else Aᵀ A (k × k).

    Its eigenvalues are the squared singular values σ_1² ≥ … ≥ σ_min(m,k)² of A.
    """
    m, k = a.shape[-2:]
    if m > k:
        a = jnp.swapaxes(a, -1, -2)
    return matmul_expanded(a, jnp.swapaxes(a, -1, -2))


__all__ = ["eigh", "eigvalsh", "extremes", "gram"]
