"""The batched Jacobi eigenvalue solver of mobman.engine.linalg against LAPACK, and its custom derivative rule against
JAX's own eigvalsh derivative and finite differences."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from mobman.engine import linalg
from mobman.errors import InputError
from mobman.model import spectra

RNG = np.random.default_rng(3)


def _symmetric(n: int, batch: int = 200, scale: float = 1.0) -> np.ndarray:
    a = RNG.normal(size=(batch, n, n)) * scale
    return a + np.swapaxes(a, -1, -2)


@pytest.mark.parametrize("n", [2, 3, 5, 8, 10])
def test_eigenvalues_match_lapack_to_machine_precision(n):
    a = _symmetric(n)
    got = np.asarray(linalg.eigvalsh(jnp.asarray(a)))
    want = np.linalg.eigvalsh(a)[..., ::-1]
    norm = np.linalg.norm(a, ord=2, axis=(-2, -1))[:, None]
    assert np.max(np.abs(got - want) / norm) < 20 * np.finfo(float).eps


@pytest.mark.parametrize("n", [3, 6])
def test_eigenvectors_are_orthonormal_and_diagonalise(n):
    a = _symmetric(n, batch=50)
    w, v = (np.asarray(x) for x in linalg.eigh(jnp.asarray(a)))
    np.testing.assert_allclose(np.swapaxes(v, -1, -2) @ v, np.broadcast_to(np.eye(n), a.shape), atol=1e-12)
    np.testing.assert_allclose(a @ v, v * w[:, None, :], atol=1e-11)
    assert np.all(np.diff(w, axis=-1) <= 0)  # descending


def test_graded_spectrum_small_eigenvalues_absolute_accuracy():
    """Gram matrices of ill-conditioned Jacobians: absolute error about eps · ‖A‖ (the documented bound),
    for a batch (Jacobi) and for one matrix (LAPACK on the CPU)."""
    u, _ = np.linalg.qr(RNG.normal(size=(4, 4)))
    lam = np.array([1.0, 1e-3, 1e-6, 1e-10])
    a = (u * lam) @ u.T
    for got in (linalg.eigvalsh(jnp.asarray(a[None]))[0], linalg.eigvalsh(jnp.asarray(a))):
        np.testing.assert_allclose(np.asarray(got), lam, atol=10 * np.finfo(float).eps)


@pytest.mark.parametrize("fn", [linalg.eigvalsh, lambda a: linalg.eigh(a)[1]])
def test_one_matrix_a_vmapped_batch_and_a_stacked_batch_agree(fn):
    """One n × n matrix (LAPACK on the CPU), the same function under vmap and with batch dimensions (the
    batched Jacobi solver) give the same values."""
    a = _symmetric(6, batch=4)
    np.testing.assert_allclose(
        np.abs(np.asarray(fn(jnp.asarray(a)))), np.abs(np.asarray(jax.vmap(fn)(jnp.asarray(a)))), atol=1e-12
    )
    one = np.stack([np.abs(np.asarray(fn(jnp.asarray(x)))) for x in a])  # |.|: eigenvector signs may differ
    np.testing.assert_allclose(np.abs(np.asarray(jax.vmap(fn)(jnp.asarray(a)))), one, atol=1e-12)


def test_batched_derivative_equals_the_derivative_of_each_matrix():
    """jit(vmap(grad)) goes through the Jacobi solver, grad of one matrix through LAPACK: same gradients."""
    a = jnp.asarray(_symmetric(5, batch=6))
    weights = jnp.array([1.0, -2.0, 0.5, 3.0, 0.25])

    def f(x):
        return jnp.dot(weights, linalg.eigvalsh(x))

    batched = np.asarray(jax.jit(jax.vmap(jax.grad(f)))(a))
    one = np.stack([np.asarray(jax.grad(f)(x)) for x in a])
    np.testing.assert_allclose(batched, one, atol=1e-10)


@pytest.mark.parametrize("n", [4, 2])  # 2 × 2: the closed form, differentiated by autodiff
@pytest.mark.parametrize("batched", [False, True])
def test_derivative_matches_jax_eigvalsh_and_finite_differences(batched, n):
    a = jnp.asarray(_symmetric(n, batch=1)[0])
    weights = jnp.array([1.0, -2.0, 0.5, 3.0])[:n]

    def ours(x):
        if batched:  # the Jacobi path
            return jnp.dot(weights, linalg.eigvalsh(x[None])[0])
        return jnp.dot(weights, linalg.eigvalsh(x))

    def reference(x):
        return jnp.dot(weights, jnp.linalg.eigvalsh(x)[::-1])

    g = np.asarray(jax.grad(ours)(a))
    np.testing.assert_allclose(
        g + g.T, np.asarray(jax.grad(reference)(a) + jax.grad(reference)(a).T), atol=1e-10
    )
    d = _symmetric(n, batch=1)[0]
    h = 1e-6
    fd = (float(ours(a + h * d)) - float(ours(a - h * d))) / (2 * h)
    assert float(jnp.sum(jax.grad(ours)(a) * d)) == pytest.approx(fd, rel=1e-7, abs=1e-9)


@pytest.mark.parametrize("n", [3, 2])
def test_derivative_is_finite_at_repeated_eigenvalues_and_exact_for_the_trace(n):
    a = jnp.eye(n) * 2.0
    g = jax.grad(lambda x: jnp.sum(linalg.eigvalsh(x)))(a)
    np.testing.assert_allclose(g, np.eye(n), atol=1e-12)
    assert np.all(np.isfinite(np.asarray(jax.grad(lambda x: linalg.eigvalsh(x)[0])(a))))


def test_gram_is_the_smaller_product():
    a = RNG.normal(size=(10, 3, 7))
    np.testing.assert_allclose(spectra.gram(jnp.asarray(a)), a @ np.swapaxes(a, -1, -2), rtol=1e-13)
    b = np.swapaxes(a, -1, -2)
    np.testing.assert_allclose(spectra.gram(jnp.asarray(b)), a @ np.swapaxes(a, -1, -2), rtol=1e-13)


def test_eigenvalue_sweeps_stop_once_the_diagonal_is_within_eps_of_the_eigenvalues():
    """The eigenvalue-only solver sweeps until every matrix of the batch passes Weyl's test (‖E‖_F ≤ eps ‖A‖_F)
    or, with a gap g between diagonal entries, the Kato–Temple test (‖E‖_F² ≤ eps ‖A‖_F (g − ‖E‖_F)), never
    more than the cap; a diagonal batch takes no sweep. A 2 × 2 stand-in sweep divides the off-diagonal entry
    by 1000 and counts itself in a spare entry (the tolerance is set from the initial state)."""

    def sweep(_, carry):
        (d0, off, d1, count), v = carry
        return [d0, off / 1000.0, d1, count + 1.0], v

    def sweeps_run(d1, off0, cap):
        state = [jnp.full(4, 2.0), jnp.full(4, off0), jnp.full(4, d1), jnp.zeros(4)]
        return np.asarray(linalg._sweep_until_converged(sweep, (state, []), [0, 2], [1], cap)[0][3])

    # equal diagonal (no gap): ‖A‖_F = √10, Weyl needs √2 off ≤ eps √10, i.e. off ≤ 5e-16: 6 divisions
    np.testing.assert_array_equal(sweeps_run(2.0, 1.0, 7), 6)
    np.testing.assert_array_equal(sweeps_run(2.0, 1.0, 4), 4)
    np.testing.assert_array_equal(sweeps_run(2.0, 0.0, 7), 0)
    # gap 1: ‖A‖_F = √7, Kato–Temple needs 2 off² ≤ eps √7 (1 − √2 off), i.e. off ≤ 1.7e-8: 3 divisions
    np.testing.assert_array_equal(sweeps_run(1.0, 1.0, 7), 3)


def test_stopped_sweeps_keep_the_eigenvalues_to_machine_precision():
    """Where the Kato–Temple test stops the sweeps early (well-separated eigenvalues) the eigenvalues still
    match LAPACK to a few eps · ‖A‖."""
    u, _ = np.linalg.qr(RNG.normal(size=(300, 6, 6)))
    lam = np.sort(RNG.uniform(0.0, 10.0, (300, 6)), axis=1)[:, ::-1]
    a = (u * lam[:, None, :]) @ np.swapaxes(u, -1, -2)
    got = np.asarray(linalg.eigvalsh(jnp.asarray(a)))
    want = np.linalg.eigvalsh(a)[..., ::-1]
    assert np.max(np.abs(got - want) / np.linalg.norm(a, axis=(-2, -1))[:, None]) < 10 * np.finfo(float).eps


@pytest.mark.parametrize("n", range(2, 10))
def test_round_robin_order_visits_every_pair_once_in_rounds_of_disjoint_pairs(n):
    pairs = linalg.round_robin_pairs(n)
    assert sorted(pairs) == [(p, q) for p in range(n) for q in range(p + 1, n)]
    per_round = n // 2
    for k in range(0, len(pairs), per_round):
        touched = [i for pair in pairs[k : k + per_round] for i in pair]
        assert len(set(touched)) == len(touched)


def test_round_robin_order_of_no_or_one_index_is_empty_and_a_negative_size_is_refused():
    assert linalg.round_robin_pairs(0) == linalg.round_robin_pairs(1) == ()
    with pytest.raises(InputError, match="n must be a matrix size"):
        linalg.round_robin_pairs(-2)


def _sweeps_until_converged(a: np.ndarray, each: bool = False) -> np.ndarray:
    """Sweeps the eigenvalue-only solver runs on a batch a (..., n, n), counted by a wrapped sweep; with
    ``each``, for every matrix alone (under vmap the loop stops matrix by matrix)."""
    counts = []

    def counting(sweep, init, diagonal, off, cap):
        def counted(k, carry):
            return sweep(k, (carry[0], []))[0], [carry[1][0] + 1]

        state, (count,) = stop(counted, (init[0], [jnp.zeros(())]), diagonal, off, cap)
        counts.append(count)
        return state, []

    def run(x):
        linalg._jacobi(x, False, linalg.SWEEPS)
        return counts[-1]

    stop, linalg._sweep_until_converged = linalg._sweep_until_converged, counting
    try:
        return np.asarray(jax.jit(jax.vmap(run) if each else run)(a))
    finally:
        linalg._sweep_until_converged = stop


def test_parallel_order_needs_fewer_sweeps_than_the_cap():
    """Gram matrices of random 6 × 9 matrices (the shape of a Panda J̄): in the round-robin order most single
    matrices are converged after 4 sweeps (row-cyclic order: about half of them) and none needs more than 5,
    so a batch of 128 stops after 5 (row-cyclic: 5 or 6)."""
    x = np.random.default_rng(7).normal(size=(128, 6, 9))
    a = x @ np.swapaxes(x, -1, -2)
    each = _sweeps_until_converged(a, each=True)
    assert each.max() <= 5 and np.mean(each <= 4) >= 0.8
    assert _sweeps_until_converged(a) == 5
