"""mobman.model.spatial: components by one split with their gradient, and the matrix products against NumPy."""

from __future__ import annotations

import jax
import jax.numpy as jnp
import numpy as np

from mobman.model import (
    spatial,
)


def test_unstack_components_and_their_one_concatenation_gradient():
    """spatial.unstack gives a[..., i], and its reverse-mode derivative equals central differences."""
    from mobman.model.spatial import cross, unstack

    a = np.random.default_rng(5).normal(size=(4, 3))
    for i, part in enumerate(unstack(jnp.asarray(a))):
        np.testing.assert_array_equal(part, a[:, i])

    def loss(x):
        return jnp.sum(cross(x, x[::-1]) ** 2)

    h = 1e-6
    fd = np.zeros_like(a)
    for index in np.ndindex(a.shape):
        e = np.zeros_like(a)
        e[index] = h
        fd[index] = (loss(a + e) - loss(a - e)) / (2 * h)
    np.testing.assert_allclose(jax.grad(loss)(jnp.asarray(a)), fd, rtol=1e-6, atol=1e-8)


def test_matrix_products_written_out_and_as_reductions_equal_numpy():
    """spatial.matmul (one reduction) and spatial.matmul_expanded (sum of outer products) equal NumPy's
    product for stacks with broadcast leading dimensions and non-square shapes, and so do their gradients."""
    rng = np.random.default_rng(12)
    a, b = rng.normal(size=(4, 1, 3, 5)), rng.normal(size=(6, 5, 2))
    for product in (spatial.matmul, spatial.matmul_expanded):
        np.testing.assert_allclose(product(jnp.asarray(a), jnp.asarray(b)), a @ b, rtol=0, atol=1e-14)
        grad = jax.grad(lambda x, f=product: jnp.sum(f(x, jnp.asarray(b)) ** 2))(jnp.asarray(a))
        np.testing.assert_allclose(
            grad, (2 * (a @ b) @ np.swapaxes(b, -1, -2)).sum(axis=1, keepdims=True), atol=1e-12
        )
