"""Dataclasses as JAX pytrees: numeric fields are leaves (traced, batchable), the others static."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import fields
from typing import TypeVar

import jax

T = TypeVar("T")


def pytree(*data: str) -> Callable[[type[T]], type[T]]:
    """Class decorator: register a dataclass as a pytree whose ``data`` fields are leaves.

    Unflattening bypasses ``__init__`` (and its validation), so transformed copies may hold tracers.
    """

    def register(cls):
        meta = tuple(f.name for f in fields(cls) if f.name not in data)

        def flatten(obj):
            return tuple(getattr(obj, n) for n in data), tuple(getattr(obj, n) for n in meta)

        def unflatten(aux, children):
            obj = object.__new__(cls)
            for n, v in zip(data + meta, tuple(children) + tuple(aux)):
                object.__setattr__(obj, n, v)
            return obj

        jax.tree_util.register_pytree_node(cls, flatten, unflatten)
        return cls

    return register
