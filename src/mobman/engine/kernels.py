"""Drop-in kernels: a plain definition in the model, a tuned equivalent in the engine.

The model writes its mathematics plainly (``a @ b``, Rodrigues' formula, ``jnp.linalg.eigvalsh``, autodiff of
the frames) and marks each such function with :func:`definition`. A module of :mod:`mobman.engine` registers
a faster function with the same arguments and the same values with :func:`drop_in`, naming the definition by
its module and name; every call of the definition then runs the drop-in. The model never imports the engine's
tuned modules, and the engine never imports the model: they meet in this registry.

A drop-in must give the definition's values (to rounding) and its derivatives; ``tests/test_engine_kernels.py``
walks :func:`registry` and checks every pair on random inputs.

Example::

    # in mobman/model/spatial.py
    @definition
    def matmul_expanded(a, b):
        return a @ b

    # in mobman/engine/products.py
    @drop_in("mobman.model.spatial.matmul_expanded")
    def matmul_expanded(a, b):
        ...  # the sum of the outer products of a's columns and b's rows
"""

from __future__ import annotations

import functools
from dataclasses import dataclass
from typing import Callable, TypeVar

F = TypeVar("F", bound=Callable)

_DROP_INS: dict[str, Callable] = {}
_DEFINITIONS: dict[str, Callable] = {}


@dataclass(frozen=True)
class Kernel:
    """A definition and the drop-in that replaces it (None where one of them is not registered)."""

    name: str
    definition: Callable | None
    drop_in: Callable | None


def definition(fn: Callable) -> Callable:
    """Mark ``fn`` as the plain definition of a kernel, named ``module.name``: calls run the registered
    drop-in, or ``fn`` itself when there is none. The plain function stays available as ``.definition``."""
    name = f"{fn.__module__}.{fn.__qualname__}"
    _DEFINITIONS[name] = fn

    @functools.wraps(fn)
    def call(*args, **kwargs):
        return _DROP_INS.get(name, fn)(*args, **kwargs)

    call.definition = fn  # type: ignore[attr-defined]
    return call


def drop_in(name: str) -> Callable[[F], F]:
    """Register the decorated function as the drop-in for the definition ``name`` (``module.function``)."""

    def register(fn: F) -> F:
        if name in _DROP_INS and _DROP_INS[name] is not fn:
            raise ValueError(f"a drop-in for {name} is already registered ({_DROP_INS[name].__qualname__})")
        _DROP_INS[name] = fn
        return fn

    return register


def registry() -> dict[str, Kernel]:
    """Every definition seen so far (their modules imported) and every registered drop-in, by name."""
    names = sorted(set(_DEFINITIONS) | set(_DROP_INS))
    return {n: Kernel(n, _DEFINITIONS.get(n), _DROP_INS.get(n)) for n in names}


__all__ = ["Kernel", "definition", "drop_in", "registry"]
