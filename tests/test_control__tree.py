"""mobman.control._tree: a dataclass registered as a pytree has its numeric fields as leaves (traced,
transformed) and the others as static data; unflattening keeps the class and skips its validation."""

from __future__ import annotations

from dataclasses import dataclass

import jax
import jax.numpy as jnp
import numpy as np

from mobman.control._tree import pytree


@pytree("gain", "offset")
@dataclass(frozen=True)
class Scaled:
    gain: object
    offset: object
    name: str = "scaled"

    def __post_init__(self) -> None:
        if isinstance(self.gain, float) and self.gain <= 0:
            raise ValueError("gain must be > 0")

    def __call__(self, x):
        return self.gain * x + self.offset


def test_the_data_fields_are_the_leaves_and_the_others_static():
    law = Scaled(2.0, np.array([1.0, -1.0]), name="a")
    leaves, treedef = jax.tree_util.tree_flatten(law)
    assert len(leaves) == 2 and leaves[0] == 2.0
    np.testing.assert_array_equal(leaves[1], [1.0, -1.0])
    rebuilt = jax.tree_util.tree_unflatten(treedef, leaves)
    assert type(rebuilt) is Scaled and rebuilt.name == "a"
    # the static field is part of the structure: a different name is a different tree
    assert jax.tree_util.tree_structure(Scaled(2.0, 0.0, name="b")) != jax.tree_util.tree_structure(
        Scaled(2.0, 0.0, name="a")
    )


def test_leaves_are_traced_under_jit_and_differentiated():
    law = Scaled(2.0, jnp.array([1.0, -1.0]))
    out = jax.jit(lambda f, x: f(x))(law, jnp.array([3.0, 4.0]))
    np.testing.assert_allclose(out, [7.0, 7.0])
    grads = jax.grad(lambda f: jnp.sum(f(jnp.array([3.0, 4.0]))))(law)
    assert isinstance(grads, Scaled)
    assert float(grads.gain) == 7.0
    np.testing.assert_allclose(grads.offset, [1.0, 1.0])


def test_tree_map_builds_copies_without_running_the_validation():
    law = Scaled(2.0, 1.0)
    negated = jax.tree.map(lambda x: -x, law)  # a gain of −2 would fail __post_init__
    assert negated.gain == -2.0 and negated.offset == -1.0 and negated.name == "scaled"


def test_batched_over_the_leaves_with_vmap():
    laws = Scaled(jnp.array([1.0, 2.0, 3.0]), jnp.zeros(3))
    out = jax.vmap(lambda f: f(jnp.array(2.0)))(laws)
    np.testing.assert_allclose(out, [2.0, 4.0, 6.0])
