"""Cache-blocked batching (mobman.batching): the same values as one vmap, for any batch shape."""

from __future__ import annotations

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from mobman import batching, kinematics
from mobman.model import robots


def _kernel(x):
    """A pytree-valued kernel of one (3,) vector."""
    return {"outer": jnp.outer(x, jnp.sin(x)), "norm": jnp.sqrt(x @ x)}


@pytest.mark.parametrize(
    "batch", [(), (1,), (5,), (batching.BLOCK,), (batching.BLOCK + 1,), (3, 2 * batching.BLOCK - 7)]
)
def test_blocked_equals_vmap_for_every_batch_shape(batch):
    x = np.random.default_rng(0).normal(size=batch + (3,))
    got = jax.jit(batching.blocked(_kernel))(x)
    flat = x.reshape(-1, 3)
    expected = jax.tree.map(lambda a: np.asarray(a).reshape(batch + a.shape[1:]), jax.vmap(_kernel)(flat))
    for key in ("outer", "norm"):
        assert got[key].shape == batch + expected[key].shape[len(batch) :]
        np.testing.assert_allclose(np.asarray(got[key]), expected[key], rtol=1e-14, atol=1e-14)


def test_blocked_kinematics_match_one_configuration_at_a_time():
    """More configurations than a block (blocked loop, last block moved back): J̄ as one at a time."""
    robot = robots.bayle_rrp()
    q = np.random.default_rng(1).uniform(-2, 2, (batching.BLOCK + 9, robot.n_q))
    batched = np.asarray(kinematics.reduced_jacobian(robot, q))
    single = np.stack([np.asarray(kinematics.reduced_jacobian(robot, qi)) for qi in q[-12:]])
    np.testing.assert_allclose(batched[-12:], single, rtol=1e-12, atol=1e-13)
