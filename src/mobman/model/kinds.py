"""Registries of classes by ``kind``: the name that robot and specification files give a task or a law.

A class registers itself when it is defined (its base's ``__init_subclass__`` calls :meth:`Kinds.add`), so a
new kind is one new module; the registry finds it by name and suggests the closest name for a typo.
"""

from __future__ import annotations

import difflib
import importlib
import pkgutil
from collections.abc import Iterable
from typing import Generic, TypeVar

from mobman.errors import ModelError

T = TypeVar("T", bound=type)


class Kinds(Generic[T]):
    """The classes of one family (``what``: "task", "law") by their ``kind`` class attribute."""

    def __init__(self, what: str) -> None:
        self.what = what
        self._classes: dict[str, T] = {}

    def add(self, cls: T) -> None:
        """Register ``cls`` under the ``kind`` it sets itself (classes that set none are not registered); a
        kind already taken by another class raises ModelError."""
        kind = cls.__dict__.get("kind", "")
        if not kind:
            return
        known = self._classes.get(kind)
        if known is not None and (known.__module__, known.__qualname__) != (cls.__module__, cls.__qualname__):
            raise ModelError(
                f"{self.what} kind {kind!r} is already {known.__module__}.{known.__qualname__}; choose another"
            )
        self._classes[kind] = cls

    def kinds(self) -> tuple[str, ...]:
        """The registered kinds, sorted."""
        return tuple(sorted(self._classes))

    def get(self, kind: str) -> T:
        """The class registered under ``kind``; an unknown kind raises ModelError naming the closest one."""
        if isinstance(kind, str) and kind in self._classes:
            return self._classes[kind]
        close = difflib.get_close_matches(kind, list(self._classes), n=1) if isinstance(kind, str) else []
        hint = f"did you mean {close[0]!r}? " if close else ""
        raise ModelError(f"{self.what} kind {kind!r} unknown; {hint}known: {', '.join(self.kinds())}")


def import_package(name: str, path: Iterable[str]) -> None:
    """Import every module of the package ``name`` (its ``__path__``): each registers the kinds it defines, so
    a new kind is one new module of the package."""
    for module in pkgutil.iter_modules(path):
        importlib.import_module(f"{name}.{module.name}")


__all__ = ["Kinds", "import_package"]
