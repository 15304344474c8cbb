"""mobman.engine.selection: the k smallest entries by bisection over the floats' ordered integer keys, against
lax.top_k of the negated vector: the same indices in the same order (ties by index), including repeated values,
signed zeros, infinities and k equal to the length."""

from __future__ import annotations

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import mobman  # noqa: F401  (float64)
from mobman.engine.selection import nearest, ordered_keys

RNG = np.random.default_rng(23)


def _reference(values: np.ndarray, count: int) -> tuple[np.ndarray, np.ndarray]:
    negated, index = jax.lax.top_k(-jnp.asarray(values), count)
    return -np.asarray(negated), np.asarray(index)


@pytest.mark.parametrize("count", [1, 5, 32, 100])
def test_the_k_smallest_are_those_of_top_k_in_its_order(count):
    for trial in range(20):
        values = RNG.normal(size=100) * 10.0 ** RNG.integers(-12, 6)
        if trial % 2:
            values = np.round(values, 1)  # many ties
        if trial % 3 == 0:
            values[:4] = [-0.0, 0.0, np.inf, -np.inf]
        got = jax.jit(nearest, static_argnums=1)(jnp.asarray(values), count)
        want = _reference(values, count)
        np.testing.assert_array_equal(np.asarray(got[1]), want[1])
        np.testing.assert_array_equal(np.asarray(got[0]), want[0])


def test_the_keys_order_the_floats():
    values = np.sort(
        np.concatenate([RNG.normal(size=200) * 1e3, [-np.inf, -1e-300, -0.0, 0.0, 5e-324, np.inf]])
    )
    keys = np.asarray(ordered_keys(jnp.asarray(values)))
    assert np.all(np.diff(keys) >= 0)  # never out of order, and apart wherever the values are
    assert np.all(np.diff(keys)[np.diff(values) > 0] > 0)
