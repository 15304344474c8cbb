"""Spectra of small symmetric matrices for large batches: a cyclic Jacobi eigenvalue solver, the drop-in for
:func:`mobman.model.spectra.eigvalsh` and :func:`~mobman.model.spectra.eigh`.

``jnp.linalg.eigh`` / ``svd`` call LAPACK (CPU) or cuSOLVER (GPU) once per tiny matrix, which is slow for a
million 6 × 6 matrices. Here the classical cyclic Jacobi method (Golub & Van Loan, *Matrix Computations*,
§8.5: ``sym.schur2`` rotations swept over every pair (p, q), here in the parallel round-robin order) is
written elementwise in a structure-of-arrays layout: every matrix entry is one array over the batch (batch
axis last in memory), and each sweep is one fully unrolled straight-line program that XLA fuses into tight
vectorised loops on the CPU and the GPU. Each round of the sweep reads the entries the previous one wrote
(:func:`mobman.engine.fusion.computed_once`): fused across rounds, every entry would recompute the cheap
updates of all earlier rounds of the sweep, 3.5 times the arithmetic; the angles of a round's rotations
(which touch disjoint rows and columns) are computed together, in one kernel. Eigenvalues alone stop
sweeping once the diagonal of every matrix in the batch is provably within eps · ‖A‖_F of the eigenvalues
(Weyl's and the Kato–Temple bounds); eigenvectors run the fixed count of sweeps.

One matrix is different: unrolled, the Jacobi program is about a hundred tiny XLA kernels per sweep, while
LAPACK solves a 6 × 6 problem in one call. So on the CPU a single n × n matrix (3 ≤ n ≤ 8) goes to LAPACK,
and the solver switches to Jacobi when it is vectorised (``jax.custom_batching.custom_vmap``: ``vmap``,
``blocked`` batches and explicit batch dimensions all get the Jacobi program). The eigenvectors of 2 × 2
problems come from their single exact rotation, their eigenvalues from the closed form m ± r (a few fused
operations with their gradient, for the Gram matrices of planar tasks); accelerators always use Jacobi.

Convergence of cyclic Jacobi is quadratic once the off-diagonal part is small; :data:`SWEEPS` sweeps reach
machine precision for the matrices met in kinematics (n ≤ 8; tested against LAPACK in ``tests/test_engine_linalg.py``).
Eigenvalues are accurate to about ``eps · ‖A‖`` in absolute terms (the usual bound of a backward-stable method).

Derivatives: :func:`eigvalsh` has a custom JVP, dλ_i = v_iᵀ dA v_i (first-order perturbation of a symmetric
matrix), so gradients do not differentiate through the iterations. It is exact for simple eigenvalues; at a
repeated eigenvalue the eigenvalues themselves are not differentiable and the rule returns a finite value
(one element of the generalised gradient) — symmetric functions of the eigenvalues (trace, determinant, …)
still get their exact derivative.
"""

from __future__ import annotations

from functools import lru_cache, partial, reduce
from typing import Callable, Literal, overload

import jax
import jax.numpy as jnp

from mobman.engine.fusion import computed_once
from mobman.engine.kernels import drop_in
from mobman.engine.products import unstack
from mobman.errors import InputError

SWEEPS = 7
"""Cyclic Jacobi sweeps: the number run for eigenvectors, the most run for eigenvalues (enough for double
precision up to n = 8, see tests)."""

MAX_JACOBI_SIZE = 8
"""Larger matrices go to ``jnp.linalg.eigh`` (the unrolled program grows as n³ · sweeps)."""

_Eigen = tuple[jnp.ndarray, jnp.ndarray | None]
"""Eigenvalues (..., n) and eigenvectors (..., n, n), or None where they were not asked for."""

_Sweep = tuple[list[jnp.ndarray], list[jnp.ndarray]]
"""The Jacobi state: the upper triangle of A and the entries of V (empty without eigenvectors)."""


def _soa(a: jnp.ndarray) -> jnp.ndarray:
    """(..., n, n) → (n, n, ...): structure of arrays, every entry a contiguous batch array."""
    return jnp.moveaxis(a, (-2, -1), (0, 1))


def _rotation(app, aqq, apq):
    """Cosine and sine of the Jacobi rotation that zeroes a_pq (Golub & Van Loan Alg. 8.5.1, division-free
    form t = 2 a_pq sign(d) / (|d| + √(d² + 4 a_pq²)), d = a_qq − a_pp; t = 0 when a_pq = 0)."""
    d = aqq - app
    num = 2.0 * apq * jnp.where(d >= 0, 1.0, -1.0)
    den = jnp.abs(d) + jnp.sqrt(d * d + 4.0 * apq * apq)
    t = num / jnp.where(den == 0, 1.0, den)
    c = 1.0 / jnp.sqrt(1.0 + t * t)
    return c, t * c, t


@lru_cache(maxsize=None)
def round_robin_pairs(n: int) -> tuple[tuple[int, int], ...]:
    """The pairs (p, q), p < q, of one Jacobi sweep over n indices in the parallel ("round-robin") order of
    Brent & Luk (*SIAM J. Sci. Stat. Comput.* 6, 1985; Golub & Van Loan §8.5): n − 1 rounds (n rounds for n
    odd) of ⌊n/2⌋ disjoint pairs, index 0 fixed and the others turned one place after each round, like the
    players of a chess tournament. Each pair appears once per sweep, so the sweep is cyclic and converges
    quadratically like the row-cyclic one; the rotations of a round touch disjoint rows and columns. It also
    converges sooner: on the 6 × 6 Gram matrices of a Panda J̄ at random configurations, 92 % of single
    matrices pass the stopping test after 4 sweeps and none needs more than 5 (row-cyclic order: 65 %, and
    a block of 128 needed 6 sweeps in 6 of 32 blocks, never in this order); the eigenvalues of a batch take
    about 20 % less time (docs/manipulability.md)."""
    if n < 0:
        raise InputError(f"round_robin_pairs: n must be a matrix size ≥ 0, got {n}")
    m = n + n % 2  # an odd n gets a dummy index m − 1: its pairs are skipped
    ring = list(range(m))
    pairs = []
    for _ in range(m - 1):
        for i in range(m // 2):
            p, q = sorted((ring[i], ring[m - 1 - i]))
            if q < n:
                pairs.append((p, q))
        ring = [ring[0], ring[-1], *ring[1:-1]]
    return tuple(pairs)


def _pivots(pairs: tuple[tuple[int, int], ...]) -> tuple[list[tuple[int, int]], ...]:
    """The (p, p), (q, q) and (p, q) entries of the rotations (p, q) of a round."""
    return [(p, p) for p, _ in pairs], [(q, q) for _, q in pairs], list(pairs)


def _jacobi(a: jnp.ndarray, vectors: bool, sweeps: int) -> _Eigen:
    """Unsorted eigenvalues (..., n) and, if ``vectors``, eigenvectors (..., n, n) (columns).

    The state is the upper triangle of A (and V) as separate batch arrays; one sweep visits every pair
    (p, q) once, in the parallel order of :func:`round_robin_pairs`, and is unrolled; sweeps run in a loop
    (small compile time): ``sweeps`` of them with eigenvectors, until convergence without. For n ≤ 2 one
    rotation is exact: a single sweep.
    """
    n = a.shape[-1]
    t = _soa(a)
    upper = [(i, j) for i in range(n) for j in range(i, n)]
    idx = {ij: k for k, ij in enumerate(upper)}

    def at(i, j):
        return idx[(i, j) if i <= j else (j, i)]

    state = [t[i, j] for i, j in upper]
    eye = [jnp.full_like(t[0, 0], 1.0 if i == j else 0.0) for i in range(n) for j in range(n)]

    pairs = round_robin_pairs(n)
    per_round = n // 2

    def sweep(_, carry):
        s, v = list(carry[0]), list(carry[1])
        for k, (p, q) in enumerate(pairs):
            if k % per_round == 0:  # a new round: rotations of disjoint rows and columns
                if k:  # it reads the last round's entries from memory
                    s, v = [computed_once(x) for x in s], [computed_once(x) for x in v]
                # its angles depend on the entries before it only: one kernel for all of them
                pivots = _pivots(pairs[k : k + per_round])
                angles = _rotation(*(jnp.stack([s[at(i, j)] for i, j in entries]) for entries in pivots))
            c, sn, tan = (x[k % per_round] for x in angles)
            app, aqq, apq = s[at(p, p)], s[at(q, q)], s[at(p, q)]
            for r in range(n):
                if r in (p, q):
                    continue
                arp, arq = s[at(r, p)], s[at(r, q)]
                s[at(r, p)] = c * arp - sn * arq
                s[at(r, q)] = sn * arp + c * arq
            s[at(p, p)] = app - tan * apq
            s[at(q, q)] = aqq + tan * apq
            s[at(p, q)] = jnp.zeros_like(apq)
            for r in range(n if vectors else 0):
                vrp, vrq = v[r * n + p], v[r * n + q]
                v[r * n + p] = c * vrp - sn * vrq
                v[r * n + q] = sn * vrp + c * vrq
        return s, v

    init = (state, eye if vectors else [])
    if n <= 2:
        s, v = sweep(0, init)
    elif vectors:
        s, v = jax.lax.fori_loop(0, sweeps, sweep, init)
    else:
        diagonal = [at(i, i) for i in range(n)]
        off = [at(i, j) for i, j in upper if i != j]
        s, v = _sweep_until_converged(sweep, init, diagonal, off, sweeps)
    w = jnp.stack([s[at(i, i)] for i in range(n)], axis=-1)
    if not vectors:
        return w, None
    return w, jnp.stack([jnp.stack(v[r * n : (r + 1) * n], axis=-1) for r in range(n)], axis=-2)


def _sweep_until_converged(
    sweep: Callable[[int, _Sweep], _Sweep], init: _Sweep, diagonal: list[int], off: list[int], sweeps: int
) -> _Sweep:
    """Jacobi sweeps until the diagonal of every matrix is within eps · ‖A‖_F of its eigenvalues, at most
    ``sweeps``. With A = D + E (E the off-diagonal part, ε = ‖E‖_F; ‖A‖_F is unchanged by the rotations):

    - Weyl's inequality: every |λ_(i) − d_(i)| ≤ ‖E‖₂ ≤ ε (both sorted), so ε ≤ eps ‖A‖_F suffices;
    - Kato–Temple, once Jacobi converges quadratically: with g the smallest gap between diagonal entries and
      g > 2ε, the interval d_i ± (g − ε) holds exactly one eigenvalue, and the residual of e_i is at most ε,
      so |λ − d_i| ≤ ε² / (g − ε); ε² ≤ eps ‖A‖_F (g − ε) suffices.

    That is the accuracy of a backward-stable solver, so more sweeps change nothing that matters. The test
    covers the whole batch (a block), so the loop runs until its slowest matrix has converged.
    ``diagonal``, ``off``: positions of the diagonal and off-diagonal entries in the upper-triangle state
    ``init[0]``.
    """
    upper = init[0]

    def off_norm2(s):  # ε² = ‖E‖_F², both triangles
        return 2.0 * sum(s[k] * s[k] for k in off)

    tol = jnp.finfo(upper[0].dtype).eps * jnp.sqrt(
        sum(upper[k] * upper[k] for k in diagonal) + off_norm2(upper)
    )

    def unconverged(carry):
        k, (s, _) = carry
        e2 = off_norm2(s)
        d = [s[i] for i in diagonal]
        gap = reduce(jnp.minimum, [jnp.abs(d[i] - d[j]) for i in range(len(d)) for j in range(i)])
        e = jnp.sqrt(e2)
        done = (e2 <= tol * tol) | ((gap > 2.0 * e) & (e2 <= tol * (gap - e)))
        return (k < sweeps) & ~jnp.all(done)

    def step(carry):
        k, state = carry
        return k + 1, sweep(k, state)

    return jax.lax.while_loop(unconverged, step, (0, init))[1]


def _lapack(a: jnp.ndarray, vectors: bool) -> _Eigen:
    """LAPACK's solver on the upper triangle of a, reordered to descending eigenvalues (LAPACK's are
    ascending: no sorting network needed)."""
    u, w = jax.lax.linalg.eigh(a, lower=False, symmetrize_input=False)
    return w[..., ::-1], (u[..., ::-1] if vectors else None)


def _jacobi_sorted(a: jnp.ndarray, vectors: bool, sweeps: int) -> _Eigen:
    w, v = _jacobi(a, vectors, sweeps)
    return (_sort_descending(w), None) if v is None else _sort_descending(w, v)


@lru_cache(maxsize=None)
def _one_or_many(vectors: bool, sweeps: int) -> Callable[[jnp.ndarray], _Eigen]:
    """Eigen-solver of one matrix that switches algorithm under ``vmap``: a single n × n matrix goes to LAPACK
    (one library call, where the unrolled Jacobi program would cost about a hundred small XLA kernels), a
    batch of them to the elementwise Jacobi program (where LAPACK would loop over tiny matrices)."""

    @jax.custom_batching.custom_vmap
    def solve(a):
        return _lapack(a, vectors)

    @solve.def_vmap
    def _batched(axis_size, in_batched, a):
        (batched,) = in_batched
        out = _jacobi_sorted(a, vectors, sweeps) if batched else _lapack(a, vectors)
        return out, jax.tree.map(lambda _: batched, out)

    return solve


@overload
def _eigh_descending(
    a: jnp.ndarray, vectors: Literal[True], sweeps: int
) -> tuple[jnp.ndarray, jnp.ndarray]: ...
@overload
def _eigh_descending(a: jnp.ndarray, vectors: Literal[False], sweeps: int) -> tuple[jnp.ndarray, None]: ...
def _eigh_descending(a: jnp.ndarray, vectors: bool, sweeps: int) -> _Eigen:
    """Eigenvalues (..., n), descending, and eigenvectors (..., n, n) or None, by the solver that suits the
    shape and backend (module notes)."""
    n = a.shape[-1]
    if n > MAX_JACOBI_SIZE:
        return _lapack(a, vectors)
    if a.ndim == 2 and n > 2 and jax.default_backend() == "cpu":
        return _one_or_many(vectors, sweeps)(a)
    return _jacobi_sorted(a, vectors, sweeps)


@overload
def _sort_descending(w: jnp.ndarray, v: None = None) -> jnp.ndarray: ...
@overload
def _sort_descending(w: jnp.ndarray, v: jnp.ndarray) -> tuple[jnp.ndarray, jnp.ndarray]: ...
def _sort_descending(
    w: jnp.ndarray, v: jnp.ndarray | None = None
) -> jnp.ndarray | tuple[jnp.ndarray, jnp.ndarray]:
    """Sort the last axis of w in descending order, and the columns of v (..., n, n) with it, by an
    odd–even transposition network (elementwise selects: fuses with the solver, unlike a general sort)."""
    n = w.shape[-1]
    x = [w[..., i] for i in range(n)]
    cols = None if v is None else [v[..., :, i] for i in range(n)]
    for k in range(n):
        for i in range(k % 2, n - 1, 2):
            swap = x[i] < x[i + 1]
            x[i], x[i + 1] = jnp.where(swap, x[i + 1], x[i]), jnp.where(swap, x[i], x[i + 1])
            if cols is not None:
                s = swap[..., None]
                cols[i], cols[i + 1] = jnp.where(s, cols[i + 1], cols[i]), jnp.where(s, cols[i], cols[i + 1])
    w = jnp.stack(x, axis=-1)
    return w if cols is None else (w, jnp.stack(cols, axis=-1))


@drop_in("mobman.model.spectra.eigvalsh")
def eigvalsh(a: jnp.ndarray, sweeps: int = SWEEPS) -> jnp.ndarray:
    """Eigenvalues of symmetric matrices a (..., n, n), in descending order, shape (..., n).

    Only the upper triangle of ``a`` is read. Differentiable: 2 × 2 matrices in closed form
    (:func:`_eigvalsh_2x2`), larger ones with the custom JVP dλ_i = v_iᵀ dA v_i.
    """
    if a.shape[-1] == 2:
        return _eigvalsh_2x2(a)
    return _eigvalsh_iterative(a, sweeps)


def _eigvalsh_2x2(a: jnp.ndarray) -> jnp.ndarray:
    """λ = m ± r with m = (a₀₀ + a₁₁)/2, r = √(((a₀₀ − a₁₁)/2)² + a₀₁²), differentiated by autodiff. At a
    repeated eigenvalue (r = 0) r is taken with derivative 0, so dλ = dm for both: one element of the
    generalised gradient, as for the iterative path. Absolute error about eps · ‖A‖, as Jacobi's. For the
    2 × 2 Gram matrix of a planar task (Bayle's law on ``bayle_planar``) the eigenvalues and their gradient
    compile to 3 fused kernels, where the Jacobi rotation, its sort and the eigenvector JVP took 6 and a
    matrix product."""
    top, bottom = unstack(a, axis=-2)
    a00, a01 = unstack(top)
    a11 = unstack(bottom)[1]
    mean, half = 0.5 * (a00 + a11), 0.5 * (a00 - a11)
    r2 = half * half + a01 * a01
    positive = r2 > 0
    r = jnp.where(positive, jnp.sqrt(jnp.where(positive, r2, 1.0)), 0.0)
    return jnp.stack([mean + r, mean - r], axis=-1)


@partial(jax.custom_jvp, nondiff_argnums=(1,))
def _eigvalsh_iterative(a: jnp.ndarray, sweeps: int) -> jnp.ndarray:
    return _eigh_descending(a, False, sweeps)[0]


@_eigvalsh_iterative.defjvp
def _eigvalsh_jvp(sweeps, primals, tangents):
    (a,), (da,) = primals, tangents
    return eigenvalue_tangents(a, da, sweeps)


def eigenvalue_tangents(
    a: jnp.ndarray, da: jnp.ndarray, sweeps: int = SWEEPS
) -> tuple[jnp.ndarray, jnp.ndarray]:
    """Eigenvalues w (..., n), descending, of symmetric a and their first-order change dw_i = v_iᵀ dA v_i
    along dA (symmetrised): the derivative rule of the engine's eigenvalue solvers (module notes)."""
    w, v = eigh(a, sweeps)
    da = 0.5 * (da + jnp.swapaxes(da, -1, -2))
    return w, jnp.einsum("...ai,...ab,...bi->...i", v, da, v)


@drop_in("mobman.model.spectra.eigh")
def eigh(a: jnp.ndarray, sweeps: int = SWEEPS) -> tuple[jnp.ndarray, jnp.ndarray]:
    """Eigenvalues (..., n) in descending order and the matching unit eigenvectors (..., n, n) as columns."""
    return _eigh_descending(a, True, sweeps)


__all__ = ["SWEEPS", "eigenvalue_tangents", "eigh", "eigvalsh", "round_robin_pairs"]
