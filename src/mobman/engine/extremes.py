"""The extreme eigenvalues and the determinant of small symmetric matrices for large batches: the drop-in for
:func:`mobman.model.spectra.extremes`, what the manipulability measures w, w2, w5 need of a Gram matrix.

The measures read three numbers of the Gram matrix's spectrum, λ_max, λ_min and det = ∏ λ_i (Nait-Chabane
eq. 17–19). A full eigenvalue solver (the cyclic Jacobi method of :mod:`mobman.engine.linalg`, five sweeps of
fifteen rotations for a 6 × 6 matrix) finds all six to get these three. Here instead:

1. **Householder tridiagonalisation** (Golub & Van Loan, *Matrix Computations*, Alg. 8.3.1): n − 2
   reflections give T = Qᵀ A Q with diagonal d and off-diagonal e. It is backward stable, and keeps the
   spectrum and ‖A‖_F.
2. **The characteristic polynomial of T** p(x) = det(T − x I), with p′ and p″, by the three-term recurrence
   p_k = (d_k − x) p_{k−1} − e_{k−1}² p_{k−2} (Wilkinson, *The Algebraic Eigenvalue Problem*, §5.37); det A
   = p(0).
3. **Laguerre's method** (Wilkinson §7.11; Press et al., *Numerical Recipes* §9.5) on p from a bound on each
   side of the spectrum: x ← x − n / (G ± √((n − 1)(n H − G²))), G = p′/p, H = G² − p″/p. For a
   polynomial whose roots are all real it converges monotonically to the root nearest the start on its side
   (from above the largest, from below the smallest) and cubically to a simple root. T is scaled to
   ‖T‖_F = 1, so λ_max ≤ 1 is the upper start; the lower start is −:data:`BELOW` when every leading minor of
   T + BELOW·I is positive (Sturm: no eigenvalue below −BELOW, the case of every Gram matrix), else −1.

The iteration stops once every matrix of the batch has taken a step of at most 2 eps (in units of ‖A‖_F),
at most :data:`ITERATIONS` steps: 3 to 7 on the Gram matrices of TIAGo's J̄ at random configurations. The
accuracy is that of a backward-stable solver, about eps · ‖A‖ absolute (tests against LAPACK). A repeated
extreme eigenvalue makes the convergence linear (up to about 40 steps): slow for the block that holds one,
never wrong.

One matrix is different, as for the Jacobi solver: on the CPU a single n × n matrix goes to LAPACK, one
library call, where the loop is a few dozen tiny XLA kernels; ``vmap`` and explicit batches get the method
above. Derivatives: dλ = vᵀ dA v for the two extreme eigenvectors and d det = Σ_i (∏_{j≠i} λ_j) dλ_i, from
:func:`mobman.engine.linalg.eigenvalue_tangents`, so gradients do not differentiate through the iterations.
"""

from __future__ import annotations

from functools import reduce

import jax
import jax.numpy as jnp

from mobman.engine import linalg
from mobman.engine.fusion import computed_once
from mobman.engine.kernels import drop_in
from mobman.engine.products import unstack

ITERATIONS = 50
"""Most Laguerre steps (a repeated extreme eigenvalue, the slowest case seen, takes about 40)."""

BELOW = 1e-12
"""Lower start −BELOW (units of ‖A‖_F) for matrices without an eigenvalue below it: positive semidefinite
matrices, whose computed eigenvalues are at most a few eps below zero."""

_Extremes = tuple[jnp.ndarray, jnp.ndarray, jnp.ndarray]
"""λ_max, λ_min and det, each of the batch's shape."""


def _tridiagonal(a: jnp.ndarray) -> tuple[list[jnp.ndarray], list[jnp.ndarray]]:
    """The diagonal d (n entries) and the squared off-diagonal e² (n − 1) of T = Qᵀ A Q (Householder,
    Golub & Van Loan Alg. 8.3.1), for a (n, n, ...), n ≥ 2, with the batch last (each entry one batch array); only
    the upper triangle is read. Each reflection reads the entries the last one wrote
    (:func:`mobman.engine.fusion.computed_once`)."""
    n = a.shape[0]
    s = {(i, j): a[i, j] for i in range(n) for j in range(i, n)}

    def at(i: int, j: int) -> jnp.ndarray:
        return s[(i, j) if i <= j else (j, i)]

    d, e2 = [], []
    for k in range(n - 2):
        rest = range(k + 1, n)
        x = [at(r, k) for r in rest]
        sigma2 = reduce(jnp.add, [xi * xi for xi in x])
        sigma = jnp.sqrt(sigma2)
        # v = x − α e_1 with α = −sign(x_1) σ, so vᵀv = 2 (σ² + σ |x_1|) and β = 2 / vᵀv
        v = [x[0] + jnp.where(x[0] >= 0, sigma, -sigma), *x[1:]]
        h = sigma2 + sigma * jnp.abs(x[0])
        beta = jnp.where(h > 0, 1.0 / jnp.where(h > 0, h, 1.0), 0.0)
        p = [beta * reduce(jnp.add, [at(r, c) * vc for c, vc in zip(rest, v)]) for r in rest]
        half = 0.5 * beta * reduce(jnp.add, [pr * vr for pr, vr in zip(p, v)])
        w = [pr - half * vr for pr, vr in zip(p, v)]
        for i, r in enumerate(rest):
            for j in range(i, len(v)):
                s[(r, k + 1 + j)] = computed_once(at(r, k + 1 + j) - v[i] * w[j] - w[i] * v[j])
        d.append(at(k, k))
        e2.append(sigma2)
    d += [at(n - 2, n - 2), at(n - 1, n - 1)]
    e2.append(at(n - 2, n - 1) * at(n - 2, n - 1))
    return d, e2


def _minors(d: list, e2: list, x: jnp.ndarray) -> list[jnp.ndarray]:
    """The leading principal minors p_1 … p_n of T − x I (p_n = det(T − x I))."""
    before, p = jnp.ones_like(x), d[0] - x
    minors = [p]
    for dk, ek in zip(d[1:], e2):
        before, p = p, (dk - x) * p - ek * before
        minors.append(p)
    return minors


def _laguerre_step(d: list, e2: list, x: jnp.ndarray) -> jnp.ndarray:
    """Laguerre's step −n / (G ± √((n − 1)(n H − G²))), G = p′/p, H = G² − p″/p, on p(x) = det(T − x I),
    written as −n p / (p′ ± √((n − 1)((n − 1) p′² − n p p″))) (numerator and denominator times p): near a
    root p is tiny and G = p′/p would overflow, the product form stays finite (0 where p(x) = 0: x is an
    eigenvalue)."""
    n = len(d)
    p0, p1 = jnp.ones_like(x), d[0] - x
    dp0, dp1 = jnp.zeros_like(x), -jnp.ones_like(x)
    ddp0, ddp1 = jnp.zeros_like(x), jnp.zeros_like(x)
    for dk, ek in zip(d[1:], e2):
        shifted = dk - x
        p0, p1, dp0, dp1, ddp0, ddp1 = (
            p1,
            shifted * p1 - ek * p0,
            dp1,
            shifted * dp1 - p1 - ek * dp0,
            ddp1,
            shifted * ddp1 - 2.0 * dp1 - ek * ddp0,
        )
    spread = jnp.sqrt(jnp.maximum((n - 1) * ((n - 1) * dp1 * dp1 - n * p1 * ddp1), 0.0))
    den = dp1 + jnp.where(dp1 >= 0, spread, -spread)  # the sign that makes |den| largest: the nearer root
    ok = den != 0
    return jnp.where(ok, -n * p1 / jnp.where(ok, den, 1.0), 0.0)


def _laguerre(a: jnp.ndarray) -> tuple[jnp.ndarray, jnp.ndarray, jnp.ndarray, jnp.ndarray]:
    """λ_max, λ_min, det of a (n, n, ...), n ≥ 3, with the batch last (module notes), and the number of
    Laguerre steps taken."""
    d, e2 = _tridiagonal(a)
    det = _minors(d, e2, jnp.zeros_like(d[0]))[-1]
    frobenius = jnp.sqrt(reduce(jnp.add, [x * x for x in d]) + 2.0 * reduce(jnp.add, e2))
    scale = jnp.where(frobenius > 0, frobenius, 1.0)
    d = [x / scale for x in d]
    e2 = [x / (scale * scale) for x in e2]
    below = reduce(jnp.logical_and, [m > 0 for m in _minors(d, e2, jnp.full_like(d[0], -BELOW))])
    start = jnp.stack([jnp.ones_like(d[0]), jnp.where(below, -BELOW, -1.0)])  # above, below the spectrum
    tol = 2.0 * jnp.finfo(start.dtype).eps

    def unconverged(carry):
        k, _, step = carry
        return (k < ITERATIONS) & jnp.any(jnp.abs(step) > tol)

    def iterate(carry):
        k, x, _ = carry
        step = _laguerre_step(d, e2, x)
        return k + 1, x + step, step

    init = (jnp.asarray(0), start, jnp.full_like(start, jnp.inf))
    steps, x, _ = jax.lax.while_loop(unconverged, iterate, init)
    return x[0] * scale, x[1] * scale, det, steps


def _from_eigenvalues(a: jnp.ndarray) -> _Extremes:
    """The three from all eigenvalues (:func:`mobman.engine.linalg.eigvalsh`), by one split (slices and a
    product reduction would be kernels of their own in the 2 × 2 programs of planar tasks)."""
    w = unstack(linalg.eigvalsh(a))
    return w[0], w[-1], reduce(jnp.multiply, w)


@jax.custom_batching.custom_vmap
def _one_or_many(a: jnp.ndarray) -> _Extremes:
    """One matrix (CPU): LAPACK; a batch under ``vmap``: the tridiagonal and Laguerre's method."""
    return _from_eigenvalues(a)


@_one_or_many.def_vmap
def _batched(axis_size, in_batched, a):
    (batched,) = in_batched
    out = _laguerre(jnp.moveaxis(a, 0, -1))[:3] if batched else _from_eigenvalues(a)
    return out, (batched,) * 3


def _solve(a: jnp.ndarray) -> _Extremes:
    if a.ndim == 2 and jax.default_backend() == "cpu":
        return _one_or_many(a)
    return _laguerre(jnp.moveaxis(a, (-2, -1), (0, 1)))[:3]


@jax.custom_jvp
def _extremes(a: jnp.ndarray) -> _Extremes:
    return _solve(a)


@_extremes.defjvp
def _extremes_jvp(primals, tangents):
    (a,), (da,) = primals, tangents
    w, dw = linalg.eigenvalue_tangents(a, da)
    others = jnp.prod(jnp.where(jnp.eye(w.shape[-1], dtype=bool), 1.0, w[..., None, :]), axis=-1)  # ∏_{j≠i}
    return (w[..., 0], w[..., -1], jnp.prod(w, axis=-1)), (dw[..., 0], dw[..., -1], jnp.sum(others * dw, -1))


@drop_in("mobman.model.spectra.extremes")
def extremes(a: jnp.ndarray) -> _Extremes:
    """λ_max, λ_min and det = ∏ λ_i of symmetric matrices a (..., n, n), each of shape (...). Only the upper
    triangle of ``a`` is read. Differentiable (module notes); 2 × 2 and larger than 8 × 8 matrices take
    :func:`mobman.engine.linalg.eigvalsh` (its closed form, LAPACK) and its derivatives."""
    n = a.shape[-1]
    return _from_eigenvalues(a) if n <= 2 or n > linalg.MAX_JACOBI_SIZE else _extremes(a)


__all__ = ["BELOW", "ITERATIONS", "extremes"]
