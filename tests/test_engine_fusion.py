"""mobman.engine.fusion: computed_once and computed_once_in_batches are the identity on values and derivatives."""

import jax
import jax.numpy as jnp
import numpy as np

import mobman  # noqa: F401  (float64)
from mobman.engine.fusion import computed_once, computed_once_in_batches


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


def _f(y):
    return jnp.sin(computed_once_in_batches(y)) * y


def test_computed_once_in_batches_is_the_identity_batched_and_not():
    x = np.array([0.0, -0.0, 1.5, -np.pi, np.inf, -np.inf, np.finfo(float).max])
    for fn in (jax.jit(computed_once_in_batches), jax.jit(jax.vmap(computed_once_in_batches))):
        got = np.asarray(fn(jnp.asarray(x)))
        np.testing.assert_array_equal(got, x)
        np.testing.assert_array_equal(np.signbit(got), np.signbit(x))
    nested = jax.jit(jax.vmap(jax.vmap(computed_once_in_batches)))(jnp.asarray(x.reshape(7, 1)))
    np.testing.assert_array_equal(np.asarray(nested).ravel(), x)


def test_computed_once_in_batches_has_the_identity_derivative_in_every_mode():
    x = jnp.asarray(np.random.default_rng(1).normal(size=(5, 3)))
    want_grad = np.cos(np.asarray(x)) * np.asarray(x) + np.sin(np.asarray(x))  # d/dy sin(y) y
    # reverse mode (a transposed tangent), batched and not, and forward mode under vmap
    grad_one = jax.grad(lambda y: jnp.sum(_f(y)))
    np.testing.assert_allclose(jax.jit(grad_one)(x), want_grad, rtol=1e-14)
    np.testing.assert_allclose(jax.jit(jax.vmap(grad_one))(x), want_grad, rtol=1e-14)
    batched_sum = jax.grad(lambda y: jnp.sum(jax.vmap(_f)(y)))
    np.testing.assert_allclose(jax.jit(batched_sum)(x), want_grad, rtol=1e-14)
    forward = jax.jit(jax.vmap(jax.jacfwd(_f)))(x)
    np.testing.assert_allclose(np.einsum("bii->bi", forward), want_grad, rtol=1e-14)


def test_computed_once_in_batches_leaves_an_unbatched_value_of_a_batched_program_alone():
    # under vmap, a value that does not depend on the batched argument stays unbatched
    c = jnp.arange(3.0)
    out = jax.vmap(lambda y: y + computed_once_in_batches(c))(jnp.ones((4, 3)))
    np.testing.assert_array_equal(out, np.ones((4, 3)) + np.arange(3.0))
