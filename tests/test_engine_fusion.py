"""mobman.engine.fusion: computed_once is the identity on values and derivatives."""

import jax
import jax.numpy as jnp
import numpy as np

import mobman  # noqa: F401  (float64)
from mobman.engine.fusion import computed_once


def test_computed_once_returns_every_value_bit_for_bit():
    # normal numbers only: XLA's CPU arithmetic flushes subnormals to zero (jit(lambda x: 2 * x) does too)
    x = np.array([0.0, -0.0, 1.5, -np.pi, np.inf, -np.inf, np.finfo(float).tiny, np.finfo(float).max])
    got = np.asarray(jax.jit(computed_once)(jnp.asarray(x)))
    np.testing.assert_array_equal(got, x)
    np.testing.assert_array_equal(np.signbit(got), np.signbit(x))  # −0.0 stays −0.0
    assert np.isnan(np.asarray(computed_once(jnp.asarray([np.nan])))).all()


def test_computed_once_has_the_identity_derivative():
    x = jnp.asarray(np.random.default_rng(0).normal(size=(4, 3)))
    np.testing.assert_array_equal(jax.jacfwd(computed_once)(x), jax.jacfwd(lambda y: y)(x))
    g = jax.grad(lambda y: jnp.sum(jnp.sin(computed_once(y))))(x)
    np.testing.assert_allclose(g, np.cos(np.asarray(x)), rtol=1e-15)
