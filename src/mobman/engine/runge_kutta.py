"""Scan-shaped kernel of the Runge–Kutta driver: a drop-in for :func:`mobman.integration.step_path`.

The definition (:mod:`mobman.integration`) writes the stages out one after the other, so a traced f appears s
times in the compiled program. Here the stages run in one ``lax.scan`` over the rows of the tableau (the index
i that stores k_i into a buffer of the s slopes, the rows α^e_i, the node c_i): f is traced
once, and the compiled program and its compilation time stay those of one evaluation of f whatever the number
of stages. The stages' aux are written as one flat vector per stage (``ravel_pytree``): one output buffer
instead of one per entry. Same values as the definition to rounding, and the same derivatives
(tests/test_engine_runge_kutta.py).
"""

from __future__ import annotations

from typing import Any, Callable

import jax
import jax.numpy as jnp
import numpy as np
from jax.flatten_util import ravel_pytree

from mobman.integration import AnyTableau, Exp, add, coefficients


def _combination(h: Any, weights: jnp.ndarray, slopes: Any) -> Any:
    """h Σ_j w_j K[j] over the slope buffer K (leading axis s) as a broadcast product and sum, which XLA
    fuses into one loop."""
    return jax.tree.map(
        lambda k: h * jnp.sum(weights.reshape((-1,) + (1,) * (k.ndim - 1)) * k, axis=0), slopes
    )


SMALL_BUFFER_BYTES = 512
"""XLA's CPU runtime runs a loop body's kernels one after the other on the calling thread when every buffer
they touch is at most this size (or there are at most 8 of them); otherwise it schedules them as a task graph
over a thread pool, which costs more than these tiny kernels."""


def _store(buffer: jnp.ndarray, index: jnp.ndarray, k: jnp.ndarray) -> jnp.ndarray:
    """The slope buffer with k as row ``index``: for a small buffer as a select of the row e_i (elementwise,
    fused with its neighbours, under :data:`SMALL_BUFFER_BYTES`), for a larger one as an in-place row update
    (a select would sweep the whole buffer at every stage). The update is a plain dynamic slice, without the
    bounds check that ``buffer.at[index].set`` compiles to (a kernel of its own in the stage loop)."""
    if buffer.size * buffer.dtype.itemsize <= SMALL_BUFFER_BYTES:
        row = jnp.arange(buffer.shape[0]) == index
        return jnp.where(row.reshape((-1,) + (1,) * jnp.ndim(k)), k, buffer)
    return jax.lax.dynamic_update_index_in_dim(buffer, k, index, 0)


def step_path(
    tab: AnyTableau,
    f: Callable,
    y: Any,
    t: Any,
    h: Any,
    *,
    exp: Exp | None = None,
    has_aux: bool = False,
    inputs: Any = None,
) -> tuple[Any, list, Any]:
    """:func:`mobman.integration.step_path` with the stages in one ``lax.scan`` (module docstring)."""
    exp = add if exp is None else exp
    c, A, b = coefficients(tab)
    stages = len(c)
    if inputs is not None:
        f_of_row = f
    else:

        def f_of_row(s, x, _):
            return f(s, x)

    shapes = jax.eval_shape(f_of_row, t, y, jax.tree.map(lambda a: a[0], inputs))
    slope_shapes = shapes[0] if has_aux else shapes
    slopes = jax.tree.map(lambda a: jnp.zeros((stages,) + a.shape, a.dtype), slope_shapes)
    unravel: list[Callable] = []  # set while the stage is traced: how to split a stage's flat aux vector back

    def stage(slopes, row):
        index, alphas, c_i, u_i = row
        y_i = y
        for e in range(A.shape[0]):
            y_i = exp(y_i, _combination(h, alphas[e], slopes))
        out = f_of_row(t + c_i * h, y_i, u_i)
        k_i, aux = out if has_aux else (out, None)
        slopes = jax.tree.map(lambda buffer, k: _store(buffer, index, k), slopes, k_i)
        if not has_aux:
            return slopes, None
        sample, split = ravel_pytree(aux)
        unravel[:] = [split]
        return slopes, sample

    rows = (np.arange(stages), np.transpose(A, (1, 0, 2)), c, inputs)
    slopes, samples = jax.lax.scan(stage, slopes, rows)
    points = [y]
    for beta in b:
        points.append(exp(points[-1], _combination(h, jnp.asarray(beta), slopes)))
    aux = jax.vmap(unravel[0])(samples) if has_aux else None
    return points[-1], points[1:-1], aux


def step(
    tab: AnyTableau,
    f: Callable,
    y: Any,
    t: Any,
    h: Any,
    *,
    exp: Exp | None = None,
    has_aux: bool = False,
    inputs: Any = None,
) -> Any:
    """:func:`mobman.integration.step` on this kernel. A step in a vector space without aux (the planners'
    endpoint and variational systems, the dynamic simulation) runs its stages as a ``fori_loop`` that reads
    row i of A in place and writes k_i into the slope buffer (:func:`_additive_step`)."""
    if exp is None and not has_aux:
        return _additive_step(tab, f, y, t, h, inputs)
    y_next, _, aux = step_path(tab, f, y, t, h, exp=exp, has_aux=has_aux, inputs=inputs)
    return (y_next, aux) if has_aux else y_next


def _row(a: jnp.ndarray, i: jax.Array) -> jnp.ndarray:
    """Row i of a, i a stage index in range: a plain dynamic slice, without the bounds checks and the
    wrapping of negative indices that ``a[i]`` compiles to (each a kernel of its own in the stage loop)."""
    return jax.lax.dynamic_index_in_dim(a, i, 0, keepdims=False)


def _additive_step(tab: AnyTableau, f: Callable, y: Any, t: Any, h: Any, inputs: Any) -> Any:
    """One explicit step y + h Σ b_j k_j, k_i = f(t + c_i h, y + h Σ_j a_ij k_j[, inputs[i]]), the stages in a
    ``fori_loop``: f traced once, each stage's slope stored in place."""
    c, A, b = coefficients(tab)
    stages = len(c)
    rows, nodes = jnp.asarray(A[0]), jnp.asarray(c)

    def f_of(i, s, x):
        return f(s, x) if inputs is None else f(s, x, jax.tree.map(lambda u: _row(u, i), inputs))

    shapes = jax.eval_shape(lambda x: f_of(0, t, x), y)
    slopes = jax.tree.map(lambda a: jnp.zeros((stages,) + a.shape, a.dtype), shapes)

    def stage(i, slopes):
        k_i = f_of(i, t + _row(nodes, i) * h, add(y, _combination(h, _row(rows, i), slopes)))
        return jax.tree.map(lambda buffer, k: _store(buffer, i, k), slopes, k_i)

    slopes = jax.lax.fori_loop(0, stages, stage, slopes)
    return add(y, _combination(h, jnp.asarray(b[0]), slopes))


__all__ = ["step", "step_path"]
