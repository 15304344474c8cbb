"""Everything tuned for speed, behind the model's plain definitions.

- :mod:`mobman.engine.batched`: the :func:`~mobman.engine.batched.batched` decorator that turns a
  per-configuration function into the public batched one (validation once at the NumPy boundary, ``jit``,
  cache-sized blocks, core sharing).
- :mod:`mobman.engine.kernels`: the registry that swaps a tuned drop-in in for a plain definition of the model.
- :mod:`mobman.engine.fusion`: :func:`~mobman.engine.fusion.computed_once`, for a value the drop-ins share
  between many consumers (XLA's fusion would recompute it in each).
- :mod:`mobman.engine.compilation_cache`: JAX's persistent compilation cache in the user's cache folder (the
  ``mobman`` command turns it on), so that a later process reads its compiled programs back.
- :mod:`mobman.engine.exported`: ``jax.jit`` that also keeps each traced program on disk (the ``mobman`` command
  turns it on), so that a later process calls it without tracing the Python function again.
- The drop-ins: :mod:`~mobman.engine.products` (written-out small products, constants as scalars, Rodrigues'
  formula), :mod:`~mobman.engine.linalg` (the batched Jacobi eigensolver), :mod:`~mobman.engine.extremes`
  (a batch's extreme eigenvalues and determinants, for the manipulability measures),
  :mod:`~mobman.engine.frame_rule` (the closed-form derivative of a frame's Jacobians),
  :mod:`~mobman.engine.selection` (the k smallest of a long vector without sorting it, for the collision
  dampers).

Importing the package registers every drop-in.
"""

from mobman.engine import (  # noqa: F401  (registers the drop-ins)
    extremes,
    frame_rule,
    fusion,
    linalg,
    products,
    selection,
)
