"""The extreme eigenvalues and determinants of mobman.engine.extremes (Householder tridiagonalisation and
Laguerre's method) against LAPACK and NumPy's determinant, on random symmetric matrices, the Gram matrices
of a Panda's J̄ over its whole joint range, rank-deficient and repeated spectra, and their derivatives against
finite differences."""

import math

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from mobman import manipulability as mp
from mobman.engine import extremes
from mobman.model import robots, spectra

RNG = np.random.default_rng(11)
EPS = np.finfo(float).eps


def _symmetric(n: int, batch: int, scale: float = 1.0) -> np.ndarray:
    a = RNG.normal(size=(batch, n, n)) * scale
    return a + np.swapaxes(a, -1, -2)


def _with_spectrum(spectra_: np.ndarray) -> np.ndarray:
    """Symmetric matrices Q diag(λ) Qᵀ with random orthogonal Q, one per row of ``spectra_``."""
    q = np.linalg.qr(RNG.normal(size=spectra_.shape + spectra_.shape[-1:]))[0]
    return (q * spectra_[:, None, :]) @ np.swapaxes(q, -1, -2)


def _panda_grams(count: int) -> np.ndarray:
    """Gram matrices J̄ J̄ᵀ (6 × 6) of a Panda on a differential base, its joints over their whole range
    with exactly 0, ±π/2 and π among them."""
    robot = robots.panda_differential()
    q = RNG.uniform(-math.pi, math.pi, size=(count, robot.n_q))
    special = RNG.random(q.shape) < 0.3
    q[special] = RNG.choice([0.0, math.pi / 2, -math.pi / 2, math.pi], size=int(special.sum()))
    j = np.asarray(mp.system_jacobian(robot, q))
    j = j[np.isfinite(j).all(axis=(-2, -1))]  # the Euler angles' representation singularity: NaN rows
    return j @ np.swapaxes(j, -1, -2)


def _assert_matches_lapack(a: np.ndarray, top, low, det) -> None:
    want = np.linalg.eigvalsh(a)
    norm = np.linalg.norm(a, axis=(-2, -1))
    assert np.max(np.abs(np.asarray(top) - want[:, -1]) / norm) < 20 * EPS
    assert np.max(np.abs(np.asarray(low) - want[:, 0]) / norm) < 20 * EPS
    n = a.shape[-1]
    assert np.max(np.abs(np.asarray(det) - np.linalg.det(a)) / norm**n) < 100 * EPS


@pytest.mark.parametrize("n", [3, 5, 6, 8])
def test_extremes_and_determinant_match_lapack(n):
    a = _symmetric(n, batch=300)
    _assert_matches_lapack(a, *extremes.extremes(jnp.asarray(a)))


def test_gram_matrices_of_a_panda_over_its_whole_joint_range():
    a = _panda_grams(2000)
    _assert_matches_lapack(a, *extremes.extremes(jnp.asarray(a)))


@pytest.mark.parametrize(
    "spectrum",
    [
        [3.0, 3.0, 2.0, 1.0, 0.5, 0.1],  # repeated largest eigenvalue: linear convergence
        [1.0, 0.5, 0.2, 0.1, 0.0, 0.0],  # rank 4: a double zero
        [1.0, 1e-3, 1e-6, 1e-9, 1e-12, 1e-15],  # graded
        [2.0, 2.0, 2.0, 2.0, 2.0, 2.0],  # a multiple of the identity
        [1.0, -1.0, 0.5, -0.5, 0.25, -2.0],  # indefinite: no Sturm shortcut below
    ],
)
def test_hard_spectra_keep_the_accuracy_of_a_backward_stable_solver(spectrum):
    a = _with_spectrum(np.tile(np.asarray(spectrum), (20, 1)))
    _assert_matches_lapack(a, *extremes.extremes(jnp.asarray(a)))


@pytest.mark.parametrize("scale", [1e-150, 1e150])
def test_the_spectrum_is_scaled_so_tiny_and_huge_matrices_neither_underflow_nor_overflow(scale):
    a = _symmetric(6, batch=20)
    top, low, _ = extremes.extremes(jnp.asarray(a * scale))
    want = np.linalg.eigvalsh(a)
    np.testing.assert_allclose(np.asarray(top) / scale, want[:, -1], rtol=1e-13)
    np.testing.assert_allclose(np.asarray(low) / scale, want[:, 0], atol=1e-13 * np.abs(want).max())


@pytest.mark.parametrize("coupling", [1e-300, 1e-150, 1e-96, 1e-40, 1e-9])
def test_an_eigenvalue_split_off_by_a_tiny_coupling_stays_finite(coupling):
    """An eigenvalue separated from the rest by off-diagonal entries of 1e-96 (a heading of 7.7e-96 rad in a
    Gram matrix J̄ J̄ᵀ): Laguerre's iterate comes within ~1e-190 of it, where p′/p would overflow."""
    a = np.tile(np.array([[1.0, 0.0, 0.0], [0.0, 23.3, 36.8], [0.0, 36.8, 63.8]]), (4, 1, 1))
    a[3, 0, 1:] = a[3, 1:, 0] = coupling
    _assert_matches_lapack(a, *extremes.extremes(jnp.asarray(a)))


def test_zero_and_non_finite_matrices():
    a = np.zeros((3, 6, 6))
    a[1] = np.eye(6)
    a[2, 0, 3] = a[2, 3, 0] = np.nan
    top, low, det = (np.asarray(x) for x in extremes.extremes(jnp.asarray(a)))
    np.testing.assert_array_equal(top[:2], [0.0, 1.0])
    np.testing.assert_array_equal(low[:2], [0.0, 1.0])
    np.testing.assert_allclose(det[:2], [0.0, 1.0], atol=1e-15)
    assert np.isnan(top[2]) and np.isnan(low[2]) and np.isnan(det[2])


def test_laguerre_stops_within_a_few_steps_on_gram_matrices():
    """The loop ends once every matrix has converged, not at the cap: about 3 to 7 steps on a block of
    Panda Gram matrices (a test of the stopping rule; a repeated extreme eigenvalue takes more)."""
    a = jnp.moveaxis(jnp.asarray(_panda_grams(128)), (-2, -1), (0, 1))
    *_, steps = extremes._laguerre(a)
    assert int(steps) <= 12
    repeated = _with_spectrum(np.tile([3.0, 3.0, 2.0, 1.0, 0.5, 0.1], (4, 1)))
    *_, steps = extremes._laguerre(jnp.moveaxis(jnp.asarray(repeated), (-2, -1), (0, 1)))
    assert 12 < int(steps) <= extremes.ITERATIONS


def test_one_matrix_a_vmapped_batch_and_a_stacked_batch_agree():
    """One matrix (LAPACK on the CPU), the same function under vmap and with a batch dimension (Laguerre)."""
    a = jnp.asarray(_symmetric(6, batch=5))
    stacked = np.asarray(extremes.extremes(a))
    mapped = np.asarray(jax.vmap(extremes.extremes)(a))
    one = np.stack([np.asarray(extremes.extremes(x)) for x in a], axis=-1)
    np.testing.assert_allclose(stacked, mapped, atol=1e-12)
    np.testing.assert_allclose(stacked, one, atol=1e-12)


@pytest.mark.parametrize("batched", [False, True])
def test_derivatives_match_finite_differences_also_at_a_singular_gram_matrix(batched):
    """d det at a rank-5 Gram matrix (one zero eigenvalue) is finite and exact: d det = ∏_{j≠i} λ_j dλ_i."""
    a = _with_spectrum(np.array([[3.0, 2.0, 1.5, 1.0, 0.5, 0.0], [3.0, 2.0, 1.5, 1.0, 0.5, 0.2]]))
    da = _symmetric(6, batch=2)
    f = jax.vmap(extremes.extremes) if batched else (lambda x: extremes.extremes(x[0]))
    x, dx = (jnp.asarray(a), jnp.asarray(da)) if batched else (jnp.asarray(a[:1]), jnp.asarray(da[:1]))
    _, tangent = jax.jvp(f, (x,), (dx,))
    h = 1e-6
    plus, minus = f(x + h * dx), f(x - h * dx)
    for t, p, m in zip(tangent, plus, minus):
        np.testing.assert_allclose(np.asarray(t), (np.asarray(p) - np.asarray(m)) / (2 * h), atol=1e-6)


def test_the_definition_and_the_drop_in_give_the_same_values():
    a = jnp.asarray(_symmetric(6, batch=50))
    np.testing.assert_allclose(
        np.asarray(spectra.extremes.definition(a)), np.asarray(spectra.extremes(a)), atol=1e-12
    )
