"""The products written out for XLA (mobman.engine.products) equal NumPy's: by constant vectors and matrices
(zeros, ±1 and general entries; batched), constant combinations, fixed poses composed. Every drop-in's values
and derivatives against its definition: tests/test_engine_kernels.py."""

from __future__ import annotations

import math

import jax.numpy as jnp
import numpy as np

import mobman  # noqa: F401  (float64; imports the model, whose definitions register themselves)
from mobman.engine import products
from mobman.model import robots, spatial, spectra  # noqa: F401  (spectra: its definitions register)


def test_products_by_constants_written_over_their_nonzero_entries():
    """products.combine / matvec_constant / matmul_constant / constant_combination / compose_fixed_pose equal
    NumPy's products (zeros, ±1 and general entries; batched), and an all-zero combination is None."""
    rng = np.random.default_rng(11)
    a = rng.normal(size=(5, 3, 3))
    c = np.array([[0.0, 1.0, -2.5], [-1.0, 0.0, 0.0], [0.0, 0.25, 0.0]])
    v = np.array([0.0, -1.0, 0.7])
    np.testing.assert_allclose(spatial.matmul_constant(jnp.asarray(a), c), a @ c, rtol=0, atol=1e-15)
    np.testing.assert_allclose(spatial.matvec_constant(jnp.asarray(a), v), a @ v, rtol=0, atol=1e-15)
    np.testing.assert_array_equal(spatial.matvec_constant(jnp.asarray(a), np.zeros(3)), np.zeros((5, 3)))
    assert products.combine([jnp.ones(2)] * 3, [0.0, 0.0, 0.0]) is None
    f = rng.normal(size=(3, 5))
    expected = sum(f[n][:, None, None] * m for n, m in enumerate((c, c.T, np.eye(3))))
    combined = products.constant_combination((c, c.T, np.eye(3)), tuple(jnp.asarray(x) for x in f))
    np.testing.assert_allclose(combined, expected, rtol=0, atol=1e-15)
    t = spatial.transform(spatial.rot_x(math.pi / 2), (0.1, 0.0, -0.3))
    r, p = spatial.compose_fixed_pose((jnp.asarray(a), jnp.asarray(a[:, 0])), t)
    m = spatial.as_matrix(t)
    np.testing.assert_allclose(r, a @ m[:3, :3], rtol=0, atol=1e-15)
    np.testing.assert_allclose(p, a @ m[:3, 3] + a[:, 0], rtol=0, atol=1e-15)
