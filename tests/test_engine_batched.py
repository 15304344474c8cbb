"""Cache-blocked batching (mobman.engine.batched): the same values as one vmap, for any batch shape."""

from __future__ import annotations

import os
import subprocess
import sys
import threading
from functools import partial

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from benchmark_timing import timing

from mobman import dynamics as dyn
from mobman import kinematics, manipulability
from mobman.dynamics import reduced
from mobman.engine import batched as batching
from mobman.io.real_robots import urdf_model
from mobman.model import robots
from mobman.redundancy import sample_configurations


def _kernel(x):
    """A pytree-valued kernel of one (3,) vector."""
    return {"outer": jnp.outer(x, jnp.sin(x)), "norm": jnp.sqrt(x @ x)}


@pytest.mark.parametrize(
    ("batch", "block"),
    [
        ((), 128),
        ((1,), 128),
        ((5,), 128),
        ((128,), 128),
        ((129,), 128),
        ((3, 249), 128),
        ((5,), 8),
        ((19,), 8),
    ],
)
def test_blocked_equals_vmap_for_every_batch_shape(batch, block):
    x = np.random.default_rng(0).normal(size=batch + (3,))
    got = jax.jit(batching.blocked(_kernel, block=block))(x)
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


# --- across_cores: large CPU batches shared between threads ----------------------------------------------


@pytest.fixture
def three_small_shares(monkeypatch):
    """Three workers and shares of at least 4 rows, whatever the machine, so the splitting runs in tests."""
    monkeypatch.setattr(batching, "WORKERS", 3)
    monkeypatch.setattr(batching, "MIN_SHARE", 4)


def _recording(calls: list):
    """A compiled pytree-valued kernel of (x (..., 3), y (..., 2)) that records its batch sizes and threads."""

    @jax.jit
    def kernel(x, scale, y):
        return {"x": x * scale + jnp.sum(y, axis=-1, keepdims=True), "n": jnp.linalg.norm(x, axis=-1)}

    def compiled(x, scale, y):
        traced = isinstance(x, jax.core.Tracer)
        calls.append((np.shape(x)[0], "traced" if traced else threading.current_thread().name))
        return kernel(x, scale, y)

    return kernel, batching.across_cores({0: 1, 2: 1})(compiled)


@pytest.mark.parametrize("as_jax", [False, True])
@pytest.mark.parametrize("batch", [(20,), (4, 5), (3, 7)])
def test_across_cores_equals_one_call(three_small_shares, batch, as_jax):
    """Equal shares (the last moved back when the size does not divide), joined in order, any batch shape,
    NumPy or jax input, the static argument passed to every share, the other argument broadcast."""
    rng = np.random.default_rng(2)
    x, y = rng.normal(size=batch + (3,)), rng.normal(size=batch[-1:] + (2,))
    if as_jax:
        x, y = jnp.asarray(x), jnp.asarray(y)
    calls = []
    kernel, split = _recording(calls)
    got, want = split(x, 2.0, y), kernel(x, 2.0, y)
    size = int(np.prod(batch))
    runs = [(n, name) for n, name in calls if name != "traced"]  # traced once for the output shapes
    assert [n for n, _ in runs] == [-(-size // 3)] * 3
    assert all(name.startswith("mobman") for _, name in runs)
    for key in ("x", "n"):
        assert got[key].shape == want[key].shape
        np.testing.assert_array_equal(np.asarray(got[key]), np.asarray(want[key]))


def test_across_cores_splits_a_batch_made_by_broadcasting(three_small_shares):
    """The batch size is checked against the shares from the leading sizes' product, an upper bound of the
    broadcast batch: arguments of 4 and 5 rows broadcast to 20 configurations are still split."""
    rng = np.random.default_rng(6)
    x, y = rng.normal(size=(4, 1, 3)), rng.normal(size=(5, 2))
    calls = []
    kernel, split = _recording(calls)
    got, want = split(x, 3.0, y), kernel(x, 3.0, y)
    assert [n for n, name in calls if name != "traced"] == [7, 7, 7]
    assert got["x"].shape == (4, 5, 3) and got["n"].shape == (4, 5)  # every result over the whole batch
    for key in ("x", "n"):  # the unsplit program vectorises the broadcast differently: equal to rounding
        expected = np.broadcast_to(np.asarray(want[key]), got[key].shape)
        np.testing.assert_allclose(np.asarray(got[key]), expected, rtol=1e-14, atol=1e-15)


def test_across_cores_plain_call_for_small_batches_tracers_and_one_worker(three_small_shares, monkeypatch):
    calls = []
    kernel, split = _recording(calls)
    x, y = np.ones((11, 3)), np.ones((11, 2))
    split(x, 1.0, y)  # 11 rows: at most two shares of 4, so two workers (after one trace for the shapes)
    assert calls[0] == (6, "traced") and [n for n, _ in calls[1:]] == [6, 6]
    assert all(name.startswith("mobman") for _, name in calls[1:])
    calls.clear()
    split(x[:7], 1.0, y[:7])  # under two shares
    jax.jit(lambda a, b: split(a, 1.0, b))(x, y)  # traced: one call inside the caller's program
    assert calls == [(7, "MainThread"), (11, "traced")]
    calls.clear()
    monkeypatch.setattr(batching, "WORKERS", 1)
    split(x, 1.0, y)
    assert [n for n, _ in calls] == [11]


def test_across_cores_joins_outputs_with_an_empty_core_dimension(three_small_shares):
    """A result with a zero-size core (like the constraint rows of a holonomic platform) keeps its shape."""
    split = batching.across_cores({0: 1})(
        jax.jit(lambda x: {"none": jnp.zeros(x.shape[:1] + (0, 3)), "x": x})
    )
    x = np.random.default_rng(5).normal(size=(13, 3))
    out = split(x)
    assert out["none"].shape == (13, 0, 3)
    np.testing.assert_array_equal(np.asarray(out["x"]), x)


def test_public_functions_share_large_batches_between_threads(three_small_shares, monkeypatch):
    """J̄ and the measures of a batch split between three threads equal those of one plain call."""
    robot = robots.bayle_planar()
    q = np.random.default_rng(4).uniform(-2, 2, (50, robot.n_q))
    jbar = kinematics.reduced_jacobian(robot, q)
    measures = manipulability.measures(jbar)
    monkeypatch.setattr(batching, "WORKERS", 1)
    np.testing.assert_allclose(
        np.asarray(jbar), np.asarray(kinematics.reduced_jacobian(robot, q)), atol=1e-15
    )
    for key, value in manipulability.measures(jbar).items():
        np.testing.assert_allclose(np.asarray(measures[key]), np.asarray(value), rtol=1e-13, atol=1e-15)


# --- batched: the decorator of the public functions ---------------------------------------------------


def test_batched_validates_once_and_broadcasts_the_batched_arguments():
    """A function of one (3,) vector and one 2 × 3 matrix, a static scale: broadcast leading dimensions,
    the validator called once per public call with the call's arguments, the plain function kept as .one."""
    calls = []

    def validate(x, m, scale=2.0):
        calls.append(scale)
        return np.asarray(x, dtype=float), np.asarray(m, dtype=float), float(scale)

    @batching.batched({0: 1, 1: 2}, static=(2,), validate=validate)
    def affine(x, m, scale=2.0):
        """scale · m x"""
        return scale * (m @ x)

    rng = np.random.default_rng(5)
    x, m = rng.normal(size=(4, 1, 3)), rng.normal(size=(6, 2, 3))
    got = affine(x, m, scale=3.0)
    assert got.shape == (4, 6, 2) and calls == [3.0]
    np.testing.assert_allclose(got, 3.0 * np.einsum("...ij,...j->...i", m, x), rtol=1e-14)
    np.testing.assert_allclose(affine.one(x[0, 0], m[0], 3.0), 3.0 * m[0] @ x[0, 0], rtol=1e-14)
    assert affine.__doc__ == "scale · m x"


def _rows_kernel(x):
    """Results over and under SEQUENTIAL_BYTES: a 10 × 10 matrix built from rows, a 100-vector, a scalar and
    an integer count."""
    rows = [jnp.sin(x * k) + x[k] for k in range(10)]
    return {
        "matrix": jnp.stack(rows),
        "long": jnp.tile(x, 10),
        "norm": jnp.sqrt(x @ x),
        "count": jnp.sum(x > 0),
    }


def test_sequential_equals_the_function_and_is_nan_for_a_non_finite_argument():
    x = np.random.default_rng(3).normal(size=10)
    got = jax.jit(batching.sequential(_rows_kernel, (0,)))(x)
    expected = jax.jit(_rows_kernel)(x)
    for key in expected:
        assert got[key].shape == expected[key].shape and got[key].dtype == expected[key].dtype
        np.testing.assert_array_equal(np.asarray(got[key]), np.asarray(expected[key]))
    x[4] = np.inf
    missing = jax.jit(batching.sequential(_rows_kernel, (0,)))(x)
    assert np.isnan(np.asarray(missing["matrix"])).all() and int(missing["count"]) == 0


@pytest.mark.parametrize(
    ("shape", "blocks"),
    [
        ((64,), None),
        ((65,), [slice(0, 33), slice(33, 65)]),
        ((10, 10), [slice(0, 5), slice(5, 10)]),
        ((3, 100), [slice(0, 1), slice(1, 2), slice(2, 3)]),
    ],
)
def test_row_blocks_are_at_most_the_sequential_size(shape, blocks):
    assert batching._row_blocks(shape, np.float64) == blocks


def test_one_configuration_dynamics_keep_every_array_of_their_branch_small():
    """TIAGo's P, b and B (10 × 10, 10, 10 × 10) for one configuration: the conditional's branch that computes
    them makes no array over SEQUENTIAL_BYTES (so XLA runs its kernels one after the other), and the
    public call returns what the batched program does."""
    model = dyn.DynamicModel.from_urdf(urdf_model("tiago"))
    q = sample_configurations(model.robot, 3, seed=2)
    eta = np.random.default_rng(2).normal(size=(3, model.robot.n_eta))
    program = jax.jit(batching.sequential(partial(reduced.reduced_terms_one, model), (0, 1)))
    entry, *branches = timing.executor_arrays(program.lower(q[0], eta[0]).compile().as_text()).values()
    assert branches and max(branches) <= batching.SEQUENTIAL_BYTES, branches
    assert entry == 800  # P and B are joined outside the branch
    together = reduced.reduced_terms(model, q, eta)
    for k in range(3):
        for one, batch in zip(reduced.reduced_terms(model, q[k], eta[k]), together):
            np.testing.assert_allclose(np.asarray(one), np.asarray(batch[k]), rtol=1e-13, atol=1e-13)


def test_only_an_unbatched_untraced_cpu_call_runs_the_sequential_program():
    """One configuration compiles the public function's sequential program; a batch, and a call traced in the
    user's own jit, take the batched program (the sequential one is not compiled for them; .plain: its jax.jit)."""

    @batching.batched({0: 1})
    def scaled_outer(x):
        return jnp.outer(x, x) * 2.0

    x = np.random.default_rng(4).normal(size=(3, 12))
    jax.jit(lambda v: scaled_outer(v))(x[0])
    scaled_outer(x)
    assert scaled_outer.sequential.plain._cache_size() == 0
    one = scaled_outer(x[0])
    assert scaled_outer.sequential.plain._cache_size() == 1
    np.testing.assert_array_equal(np.asarray(one), 2.0 * np.outer(x[0], x[0]))


@pytest.mark.parametrize(
    ("environment", "expected"),
    [(None, "False"), ("1", "True"), ("Yes", "True"), ("0", "False"), ("off", "False"), ("maybe", "False")],
)
def test_importing_mobman_makes_cpu_dispatch_synchronous_unless_asked_not_to(environment, expected):
    """mobman turns JAX's asynchronous CPU dispatch off (a one-configuration program then runs on the
    calling thread, without a hand-over to a worker) unless ``MOBMAN_CPU_ASYNC_DISPATCH`` asks to keep it;
    a value that is not a yes or no is a warning naming the variable."""
    env = {k: v for k, v in os.environ.items() if k != "MOBMAN_CPU_ASYNC_DISPATCH"}
    if environment is not None:
        env["MOBMAN_CPU_ASYNC_DISPATCH"] = environment
    code = "import jax, mobman; print(jax.config.values['jax_cpu_enable_async_dispatch'])"
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == expected
    assert ("MOBMAN_CPU_ASYNC_DISPATCH must be" in out.stderr) == (environment == "maybe")


_SMALL_LOOP = (
    "import jax, jax.numpy as jnp, mobman\n"
    "loop = jax.jit(lambda x: jax.lax.fori_loop(0, 5, lambda i, y: jnp.sin(y) * 2.0 + y, x))\n"
    "print('xla_cpu_small_call' in loop.lower(jnp.ones(512)).compile().as_text())"
)


@pytest.mark.parametrize(
    ("switch", "flags", "expected"),
    [
        (None, None, "True"),
        ("1", "--xla_cpu_enable_fast_math=false", "True"),
        ("0", None, "False"),
        ("no", None, "False"),
        ("maybe", None, "True"),
        (None, "--xla_backend_extra_options=xla_cpu_small_while_loop_byte_threshold=0", "False"),
    ],
)
def test_importing_mobman_makes_small_while_loops_one_kernel_unless_asked_not_to(switch, flags, expected):
    """A loop over 4 kB (above XLA's own 1 kB threshold) is compiled as one kernel (XLA marks it
    ``xla_cpu_small_call``) once mobman is imported; not with ``MOBMAN_XLA_SMALL_LOOPS=0``, and not where
    ``XLA_FLAGS`` already sets XLA's backend options (the user's threshold stands); other flags are kept. A
    value that is not a yes or no is a warning naming the variable."""
    env = {k: v for k, v in os.environ.items() if k not in ("MOBMAN_XLA_SMALL_LOOPS", "XLA_FLAGS")}
    if switch is not None:
        env["MOBMAN_XLA_SMALL_LOOPS"] = switch
    if flags is not None:
        env["XLA_FLAGS"] = flags
    out = subprocess.run(
        [sys.executable, "-c", _SMALL_LOOP], env=env, capture_output=True, text=True, timeout=120
    )
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == expected
    assert ("MOBMAN_XLA_SMALL_LOOPS must be" in out.stderr) == (switch == "maybe")
