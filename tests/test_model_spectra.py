"""mobman.model.spectra: eigvalsh, eigh and gram against NumPy's LAPACK solvers and SVD, one matrix and
batches, with repeated eigenvalues and rank-deficient Gram matrices (whatever kernel runs the definitions)."""

from __future__ import annotations

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from mobman.model import spectra

RNG = np.random.default_rng(0)


def _symmetric(shape: tuple[int, ...], n: int) -> np.ndarray:
    a = RNG.normal(size=(*shape, n, n))
    return 0.5 * (a + np.swapaxes(a, -1, -2))


def _with_spectrum(eigenvalues: list[float]) -> np.ndarray:
    """Q diag(λ) Qᵀ for a random orthogonal Q."""
    n = len(eigenvalues)
    q, _ = np.linalg.qr(RNG.normal(size=(n, n)))
    return (q * np.asarray(eigenvalues)) @ q.T


def _scale(a: np.ndarray) -> float:
    return float(np.abs(a).max())


@pytest.mark.parametrize("n", [1, 2, 3, 6])
@pytest.mark.parametrize("shape", [(), (2, 3)], ids=["one", "batch"])
def test_eigvalsh_matches_numpy_in_descending_order(n, shape):
    a = _symmetric(shape, n)
    got = np.asarray(spectra.eigvalsh(jnp.asarray(a)))
    assert got.shape == (*shape, n)
    expected = np.linalg.eigvalsh(a)[..., ::-1]
    np.testing.assert_allclose(got, expected, rtol=0, atol=1e-13 * _scale(a))
    assert np.all(np.diff(got, axis=-1) <= 0.0)


@pytest.mark.parametrize("n, shape", [(6, ()), (2, (2, 3)), (3, (2, 3))])
def test_eigh_gives_orthonormal_eigenvectors_of_the_descending_eigenvalues(n, shape):
    a = _symmetric(shape, n)
    w, v = (np.asarray(x) for x in spectra.eigh(jnp.asarray(a)))
    assert w.shape == (*shape, n) and v.shape == (*shape, n, n)
    np.testing.assert_allclose(w, np.linalg.eigvalsh(a)[..., ::-1], rtol=0, atol=1e-13 * _scale(a))
    eye = np.broadcast_to(np.eye(n), v.shape)
    np.testing.assert_allclose(np.swapaxes(v, -1, -2) @ v, eye, rtol=0, atol=1e-13)
    # A v_i = λ_i v_i, column by column
    np.testing.assert_allclose(a @ v, v * w[..., None, :], rtol=0, atol=1e-12 * _scale(a))
    # simple eigenvalues: each column is ± NumPy's eigenvector of the same eigenvalue
    reference = np.linalg.eigh(a)[1][..., ::-1]
    alignment = np.abs(np.sum(v * reference, axis=-2))
    np.testing.assert_allclose(alignment, 1.0, rtol=0, atol=1e-10)


@pytest.mark.parametrize(
    "eigenvalues",
    [
        [3.0, 3.0, 1.0],
        [2.0, -1.0, -1.0],
        [5.0, 5.0, 5.0, 0.0],
        [1.0, 1.0, 1.0, 1.0, 1.0, 1.0],
        [4.0, 0.0, 0.0],
    ],
    ids=str,
)
def test_repeated_eigenvalues(eigenvalues):
    a = _with_spectrum(eigenvalues)
    expected = np.sort(eigenvalues)[::-1]
    np.testing.assert_allclose(np.asarray(spectra.eigvalsh(jnp.asarray(a))), expected, rtol=0, atol=1e-13)
    w, v = (np.asarray(x) for x in spectra.eigh(jnp.asarray(a)))
    np.testing.assert_allclose(w, expected, rtol=0, atol=1e-13)
    # any orthonormal basis of a repeated eigenspace will do: check the defining identities
    np.testing.assert_allclose(v.T @ v, np.eye(len(eigenvalues)), rtol=0, atol=1e-13)
    np.testing.assert_allclose(a @ v, v * w, rtol=0, atol=1e-12)


def test_eigvalsh_of_a_diagonal_matrix_sorts_the_diagonal():
    a = np.diag([0.5, -2.0, 7.0, 0.0])
    np.testing.assert_allclose(
        np.asarray(spectra.eigvalsh(jnp.asarray(a))), [7.0, 0.5, 0.0, -2.0], atol=1e-15
    )


def test_eigvalsh_under_vmap_and_jit_equals_the_batched_call():
    a = _symmetric((6,), 3)
    batched = np.asarray(spectra.eigvalsh(jnp.asarray(a)))
    mapped = np.asarray(jax.jit(jax.vmap(spectra.eigvalsh))(jnp.asarray(a)))
    np.testing.assert_allclose(mapped, batched, rtol=0, atol=1e-13 * _scale(a))
    np.testing.assert_allclose(mapped, np.linalg.eigvalsh(a)[..., ::-1], rtol=0, atol=1e-13 * _scale(a))


@pytest.mark.parametrize("m, k", [(2, 5), (5, 3), (3, 3), (6, 1)])
def test_gram_is_the_smaller_product_and_its_spectrum_the_squared_singular_values(m, k):
    a = RNG.normal(size=(2, 3, m, k))
    g = np.asarray(spectra.gram(jnp.asarray(a)))
    p = min(m, k)
    assert g.shape == (2, 3, p, p)
    expected = a @ np.swapaxes(a, -1, -2) if m <= k else np.swapaxes(a, -1, -2) @ a
    np.testing.assert_allclose(g, expected, rtol=0, atol=1e-13)
    sigma = np.linalg.svd(a, compute_uv=False)
    got = np.asarray(spectra.eigvalsh(jnp.asarray(g)))
    np.testing.assert_allclose(got, sigma**2, rtol=0, atol=1e-12 * max(1.0, float(sigma.max()) ** 2))


@pytest.mark.parametrize("m, k, rank", [(2, 5, 1), (5, 3, 2), (4, 6, 2), (3, 3, 0)])
def test_rank_deficient_gram_has_zero_eigenvalues(m, k, rank):
    """A = U Vᵀ of rank r: the last min(m, k) − r eigenvalues of the Gram matrix are 0 (to rounding, never
    clearly negative), the others σ_i²."""
    a = RNG.normal(size=(m, rank)) @ RNG.normal(size=(rank, k))
    g = np.asarray(spectra.gram(jnp.asarray(a)))
    np.testing.assert_allclose(g, g.T, rtol=0, atol=0)
    got = np.asarray(spectra.eigvalsh(jnp.asarray(g)))
    sigma = np.linalg.svd(a, compute_uv=False)
    scale = max(1.0, float(sigma.max()) ** 2)
    np.testing.assert_allclose(got, sigma**2, rtol=0, atol=1e-12 * scale)
    np.testing.assert_allclose(got[rank:], 0.0, rtol=0, atol=1e-12 * scale)
    assert np.all(got[:rank] > 1e-6)
