"""Batched execution of per-configuration functions: one decorator, :func:`batched`.

A kinematic or dynamic quantity is written for one configuration (``q`` of shape (n_q,)), as the papers
write it. :func:`batched` turns such a function into the public batched one: it validates the arguments once
at the NumPy boundary, compiles the function with the robot (and the other options) as static arguments,
evaluates it over the leading dimensions of its array arguments in cache-sized blocks (:func:`blocked`) and
spreads a large CPU batch over the cores (:func:`across_cores`).

**Blocks.** ``vmap`` over a large batch makes XLA evaluate every intermediate of a kernel (a frame, a
Jacobian column, a Jacobi rotation's state) as an array over the whole batch: on the CPU these arrays outgrow
the caches, and a kinematic chain or an eigenvalue sweep becomes bound by memory traffic. :func:`blocked`
instead runs the kernel on blocks of :data:`BLOCK` configurations, one after the other inside a single
compiled loop (a ``fori_loop`` that reads each block in place and writes it into the output), so each
block's intermediates stay in the L1/L2 cache. On accelerators, where one wide kernel over the whole batch is
what the hardware wants, and for batches of at most one block, it is plain ``vmap``.

**One configuration.** A program for one configuration is a few dozen to a hundred and fifty tiny kernels.
XLA's CPU runtime runs them one after the other on the calling thread only when every array they touch is at
most :data:`SEQUENTIAL_BYTES` (or there are at most 8 kernels); otherwise it schedules them over a thread
pool, at a cost of about a microsecond per kernel, several times their work. That rule holds for each
executor: the program itself and, separately, each branch of a conditional. So a one-configuration call on
the CPU runs :func:`sequential`'s program: the function in a conditional's branch that returns every result
in pieces of at most 512 bytes, joined outside it by a few kernels. The per-configuration definitions avoid
forming larger intermediate arrays where the mathematics allows it (a stacked task's J̄ is formed part by
part, :meth:`mobman.model.tasks.Stack.reduced_jacobian`; spatial inertias are held by columns,
:class:`mobman.dynamics.recursive.RigidInertia`); ``benchmarks/real_robots.py`` prints the largest array of
the one-configuration programs.

**Cores.** A compiled XLA program runs on one CPU core. :func:`across_cores` splits a large batch into one
equal share per core, runs the compiled function on the shares from a thread pool (XLA releases the GIL while
it computes) and joins the results. Traced calls (inside ``jit``, ``grad``, ``vmap``), accelerators and
batches smaller than two :data:`MIN_SHARE` are one plain call.
"""

from __future__ import annotations

import functools
import math
import os
from concurrent.futures import ThreadPoolExecutor
from typing import Any, Callable, TypeGuard

import jax
import jax.numpy as jnp
import numpy as np
import numpy.typing as npt

from mobman.engine import exported

BLOCK = 128
"""Configurations per block on the CPU (64–128 are best for a Panda's J̄ and 6 × 6 eigenvalues)."""

WORKERS = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count() or 1
"""Shares a large CPU batch is split into: the cores this process may run on (set it to 1 to disable)."""

MIN_SHARE = 16 * BLOCK
"""Smallest share worth a thread of its own (2,048 configurations: splitting costs a fraction of a ms)."""

SEQUENTIAL_BYTES = 512
"""XLA's CPU runtime runs an executor's kernels one after the other only when every array is at most this
size (``execute_sequential_buffer_threshold`` of its thunk executor)."""


def batched(
    core_dims: dict[int, int],
    static: tuple[int, ...] = (),
    validate: Callable[..., tuple] | None = None,
    min_share: int | None = None,
) -> Callable[[Callable], Callable]:
    """Decorator: a function written for one configuration becomes the public batched function.

    ``core_dims`` maps the position of every batched argument to its number of core dimensions (1 for a
    configuration q of shape (n_q,), 2 for a matrix); the decorated function receives one configuration of
    each and the public one takes any leading dimensions (broadcast between the batched arguments) and
    returns results with those leading dimensions. ``static``: the positions of the hashable arguments the
    program is compiled for (robots, tasks, options). ``validate``: called with the public call's arguments
    (positional and keyword), it checks them once, outside the compiled code, and returns every argument
    by position (checked arrays, resolved defaults). ``min_share``: see :func:`across_cores`.

    The call runs: ``validate`` → :func:`across_cores` → ``jax.jit`` (``static``) → :func:`blocked` →
    the function; an unbatched, untraced call on the CPU runs ``fn.sequential`` instead, the compiled
    :func:`sequential` program. The function itself stays plain (``fn.one``): traced code calls it, not the
    public function, whose validation needs concrete arrays.
    """
    arrays = tuple(sorted(core_dims))

    def decorate(fn: Callable) -> Callable:
        def program(*args):
            def one(*xs):
                full = list(args)
                for i, x in zip(arrays, xs):
                    full[i] = x
                return fn(*full)

            return blocked(one, tuple(core_dims[i] for i in arrays))(*(args[i] for i in arrays))

        name = f"{fn.__module__}.{fn.__qualname__}"
        compiled = across_cores(core_dims, min_share)(
            exported.jit(program, static_argnums=static, name=f"{name} (batched)")
        )
        single = exported.jit(sequential(fn, arrays), static_argnums=static, name=f"{name} (sequential)")

        def call(args: tuple) -> Any:
            one = all(
                i < len(args) and np.ndim(args[i]) == core_dims[i] and not traced(args[i]) for i in arrays
            )
            return single(*args) if one and on_cpu() else compiled(*args)

        if validate is None:

            @functools.wraps(fn)
            def public(*args):
                return call(args)

        else:

            @functools.wraps(fn)
            def public(*args, **kwargs):
                return call(validate(*args, **kwargs))

        public.one = fn  # type: ignore[attr-defined]
        public.sequential = single  # type: ignore[attr-defined]
        return public

    return decorate


@functools.cache
def on_cpu() -> bool:
    """Whether JAX's default backend is the CPU: fixed once JAX has started its backends, and asked once
    (``jax.default_backend()`` costs about a microsecond, a few per cent of a one-configuration call)."""
    return jax.default_backend() == "cpu"


def sequential(fn: Callable, arrays: tuple[int, ...]) -> Callable:
    """``fn`` of one configuration (its array arguments at positions ``arrays``) as a program whose kernels
    XLA's CPU runtime runs one after the other on the calling thread, though its results are larger than
    :data:`SEQUENTIAL_BYTES`: ``fn`` runs in a conditional's branch (an executor of its own) that returns each
    result in row blocks of at most that size (:func:`_row_blocks`; XLA forms only the blocks when the
    result is built from rows), and the program joins them. The conditional's other branch, taken when an
    array argument is not finite, returns NaN (zeros for integer results): mobman's public functions reject
    such arguments before this. Equal to ``fn`` (tests); fast only when ``fn``'s intermediate arrays are
    small too."""

    def program(*args):
        results, tree = jax.tree.flatten(jax.eval_shape(lambda: fn(*args)))
        blocks = [_row_blocks(r.shape, r.dtype) for r in results]

        def split(leaves: list) -> list:
            return [x if b is None else [x[row] for row in b] for x, b in zip(leaves, blocks)]

        def missing() -> list:
            return [
                jnp.full(r.shape, jnp.nan if jnp.issubdtype(r.dtype, jnp.inexact) else 0, r.dtype)
                for r in results
            ]

        finite = jnp.all(jnp.stack([jnp.all(jnp.isfinite(args[i])) for i in arrays]))
        pieces = jax.lax.cond(finite, lambda: split(jax.tree.leaves(fn(*args))), lambda: split(missing()))
        joined = [x if b is None else jnp.concatenate(x) for x, b in zip(pieces, blocks)]
        return jax.tree.unflatten(tree, joined)

    return program


def _row_blocks(shape: tuple[int, ...], dtype: npt.DTypeLike) -> list[slice] | None:
    """None for a result of at most :data:`SEQUENTIAL_BYTES`, else its rows in equal blocks of at most that
    size (a single row of more is a block of its own)."""
    row = np.dtype(dtype).itemsize * math.prod(shape[1:])
    if not shape or row * shape[0] <= SEQUENTIAL_BYTES:
        return None
    count = -(-shape[0] // max(1, SEQUENTIAL_BYTES // row))
    size = -(-shape[0] // count)
    return [slice(start, min(start + size, shape[0])) for start in range(0, shape[0], size)]


def traced(x: object) -> TypeGuard[jax.Array]:
    """Whether ``x`` is an abstract value of a JAX transformation (no values to check)."""
    return isinstance(x, jax.core.Tracer)


def blocked(fn: Callable, core_ndims: int | tuple[int, ...] = 1, block: int = BLOCK) -> Callable:
    """``fn`` of one or more arrays, vectorised over their (broadcast) leading dimensions.

    ``core_ndims``: the number of core dimensions of each argument (one int for all). The result has the
    broadcast leading dimensions followed by ``fn``'s output shape (any pytree of arrays). ``block``: rows per
    block on the CPU (module notes; a kernel whose intermediates per configuration are large wants fewer).
    """

    def apply(*xs):
        ndims = (core_ndims,) * len(xs) if isinstance(core_ndims, int) else core_ndims
        arrays = [jnp.asarray(x) for x in xs]
        cores = [x.shape[x.ndim - n :] for x, n in zip(arrays, ndims)]
        batch = jnp.broadcast_shapes(*(x.shape[: x.ndim - n] for x, n in zip(arrays, ndims)))
        if not batch:
            return fn(*arrays)
        size = math.prod(batch)
        flat = [jnp.broadcast_to(x, batch + c).reshape((size,) + c) for x, c in zip(arrays, cores)]
        kernel = jax.vmap(fn)
        if size <= block or not on_cpu():
            out = kernel(*flat)
        else:
            out = _in_blocks(kernel, flat, size, block)
        return jax.tree.map(lambda a: a.reshape(batch + a.shape[1:]), out)

    return apply


def _in_blocks(kernel: Callable, flat: list, size: int, block: int) -> Any:
    """``kernel`` (vectorised) over ``size`` rows, ``block`` rows at a time, in one compiled loop. Each block is
    read in place and written into one output buffer; the last block is moved back to end at row ``size``
    (it recomputes a few rows of the previous one), so no padded copy of the inputs is made."""
    shapes = jax.eval_shape(kernel, *(jax.ShapeDtypeStruct((block,) + f.shape[1:], f.dtype) for f in flat))
    out = jax.tree.map(lambda s: jnp.zeros((size,) + s.shape[1:], s.dtype), shapes)

    def body(i, out):
        start = jnp.minimum(i * block, size - block)
        rows = kernel(*(jax.lax.dynamic_slice_in_dim(f, start, block) for f in flat))
        return jax.tree.map(lambda o, b: jax.lax.dynamic_update_slice_in_dim(o, b, start, 0), out, rows)

    return jax.lax.fori_loop(0, -(-size // block), body, out)


def across_cores(core_ndims: dict[int, int], min_share: int | None = None) -> Callable[[Callable], Callable]:
    """Decorator for a compiled batched function (its outputs all batched along the leading dimensions of
    its inputs, as :func:`blocked` makes them): large CPU batches run as :data:`WORKERS` concurrent calls.

    ``core_ndims`` maps the position of every batched argument to its number of core dimensions; the other
    arguments (robots, tasks, static options) go unchanged to every call. The batch is the broadcast of the
    batched arguments' leading dimensions. The shares have equal sizes (the last one moved back to end at the
    batch's end, so one compiled program serves every share). Each thread copies its share's results into
    one output buffer per result, which JAX takes over without a copy (DLPack).
    ``min_share``: the smallest share worth a thread (:data:`MIN_SHARE` by default; lower for costly rows,
    such as whole simulations).
    """

    positions = tuple(core_ndims.items())

    def decorate(compiled: Callable) -> Callable:
        @functools.wraps(compiled)
        def call(*args, **kwargs):
            plan = _share_plan(args, positions, MIN_SHARE if min_share is None else min_share)
            if plan is None:
                return compiled(*args, **kwargs)
            return _shared_call(compiled, args, kwargs, *plan)

        return call

    return decorate


def _shared_call(
    compiled: Callable, args: tuple, kwargs: dict, batch: tuple, flat: dict, share: int, starts: list
) -> Any:
    """``compiled`` on the shares ``flat[i][start : start + share]`` from the thread pool, each thread copying
    its results into the joint output buffers (the rows the last share recomputed are skipped)."""

    def with_shares(take):
        sub = list(args)
        for i, x in flat.items():
            sub[i] = take(x)
        return sub

    abstract = with_shares(lambda x: jax.ShapeDtypeStruct((share,) + x.shape[1:], x.dtype))
    # the plain jitted function (an exported.jit keeps it as .plain) takes its static arguments as static
    shapes = jax.eval_shape(getattr(compiled, "plain", compiled), *abstract, **kwargs)
    rows = math.prod(batch)
    outs = jax.tree.map(lambda s: _aligned_empty((rows,) + s.shape[1:], s.dtype), shapes)

    def run(k: int) -> None:
        part = compiled(*with_shares(lambda x: _take(x, starts[k], share)), **kwargs)
        done = k * share - starts[k]
        for out, leaf in zip(jax.tree.leaves(outs), jax.tree.leaves(part)):
            np.copyto(out[k * share : starts[k] + share], np.asarray(leaf)[done:])

    list(_pool(WORKERS).map(run, range(len(starts))))
    return jax.tree.map(lambda o: _as_jax(o.reshape(batch + o.shape[1:])), outs)


def _share_plan(
    args: tuple, batched: tuple[tuple[int, int], ...], min_share: int
) -> tuple[tuple[int, ...], dict[int, np.ndarray | jax.Array], int, list[int]] | None:
    """(batch shape, flattened batched arguments, share size, share starts), or None for one plain call.

    ``batched``: the (position, core dimensions) of the batched arguments. A small batch (one configuration
    above all) is turned away first, from the shapes alone, in one short pass: Python work before a small
    call's dispatch costs it about twice its own time (measured), so the common case does the least."""
    if WORKERS < 2:
        return None
    bound = 1
    for i, n in batched:
        if i >= len(args):
            return None
        shape = args[i].shape if hasattr(args[i], "shape") else np.shape(args[i])
        if len(shape) < n:
            return None  # let the compiled function report the bad shape
        bound *= math.prod(shape[: len(shape) - n])
    if bound < 2 * min_share:
        return None  # the product of the leading sizes bounds the broadcast batch's size
    shapes = {i: np.shape(args[i]) for i, _ in batched}
    leading = {i: shapes[i][: len(shapes[i]) - n] for i, n in batched}
    if not on_cpu() or any(isinstance(a, jax.core.Tracer) for a in args):
        return None
    try:
        batch = tuple(np.broadcast_shapes(*leading.values()))
    except ValueError:
        return None
    size = math.prod(batch)
    workers = min(WORKERS, size // min_share)
    if workers < 2:
        return None
    flat = {}
    for i, n in batched:
        x, core = args[i], shapes[i][len(shapes[i]) - n :]
        xp = jnp if isinstance(x, jax.Array) else np
        flat[i] = xp.reshape(xp.broadcast_to(x, batch + core), (size,) + core)
    share = -(-size // workers)
    return batch, flat, share, [min(k * share, size - share) for k in range(workers)]


def _take(x: np.ndarray | jax.Array, start: int, size: int) -> np.ndarray | jax.Array:
    """Rows start … start + size of x: a view of a NumPy array, one dynamic slice of a jax.Array (the same
    compiled slice for every start)."""
    if isinstance(x, jax.Array):
        return jax.lax.dynamic_slice_in_dim(x, start, size)
    return x[start : start + size]


def _aligned_empty(shape: tuple, dtype: npt.DTypeLike) -> np.ndarray:
    """An uninitialised NumPy array whose data start on a 64-byte boundary, so that JAX can take it over
    without a copy (:func:`_as_jax`)."""
    nbytes = math.prod(shape) * np.dtype(dtype).itemsize
    raw = np.empty(nbytes + 64, dtype=np.uint8)
    offset = -raw.ctypes.data % 64
    return raw[offset : offset + nbytes].view(dtype).reshape(shape)


def _as_jax(x: np.ndarray) -> jax.Array:
    """The joined result as a jax.Array sharing x's memory (DLPack; x is not used again)."""
    return jnp.from_dlpack(x) if x.size else jnp.zeros(x.shape, x.dtype)


@functools.cache
def _pool(workers: int) -> ThreadPoolExecutor:
    return ThreadPoolExecutor(max_workers=workers, thread_name_prefix="mobman")


__all__ = [
    "BLOCK",
    "MIN_SHARE",
    "SEQUENTIAL_BYTES",
    "WORKERS",
    "across_cores",
    "batched",
    "blocked",
    "sequential",
    "traced",
]
