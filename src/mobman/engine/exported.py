"""Exported programs kept on disk, so that a command's first call of a function skips tracing it.

JAX's persistent compilation cache (:mod:`mobman.engine.compilation_cache`) keeps compiled programs, but finds
one only after tracing the Python function and lowering it to StableHLO, which for a real robot's kinematics
takes most of a command's time (docs/performance.md: 0.3–1 s per program for TIAGo). :func:`jit` is
``jax.jit`` with static arguments that, once :func:`enable` has been called, also keeps each program it
traces as a serialized :class:`jax.export.Exported` (its StableHLO) in the folder ``exported/`` of the
compilation cache. A later process with the same function, static arguments and argument shapes reads it back
and calls it: no tracing, and the compilation comes from the persistent cache.

A stored program is found again only for the same key, the SHA-256 of

- the function's name (:func:`jit`'s ``name``),
- the static arguments, described by their classes and fields (robots, tasks and options are frozen
  dataclasses of numbers, strings and tuples; not the caches an instance keeps, which depend on what ran
  before), when every class and function they name is mobman's, NumPy's, JAX's or a builtin: a static
  argument that names anything else (a user's own task class, a function) is never stored, since its code
  could change without changing its description;
- the shapes and dtypes of the array arguments and the drop-in kernels registered
  (:mod:`mobman.engine.kernels`);
- the source code of the installed mobman package, JAX's and jaxlib's versions and the backend,

so any change of mobman, JAX, the robot or an option traces afresh. Calls with traced arguments (inside
``jit``, ``grad``, ``vmap``) and any program whose export or serialization fails (a host callback, say: an
empty ``KEY.plain`` file then tells later processes not to try again) are plain ``jax.jit``; so is
every call while the cache is off (the default: the ``mobman`` command turns it on, unless
``MOBMAN_EXPORTED=off``). The folder keeps at most
:data:`MAX_BYTES`, the least recently written programs removed first.
"""

from __future__ import annotations

import dataclasses
import enum
import functools
import hashlib
import io
import os
import pickle
import tempfile
from pathlib import Path
from typing import Any, Callable

import jax
import numpy as np

from mobman.engine import kernels
from mobman.errors import InputError

ENVIRONMENT = "MOBMAN_EXPORTED"
"""The environment variable that keeps the ``mobman`` command from using exported programs (``off``): it then
traces every program and reads only their compilations back."""

MAX_BYTES = 128 * 2**20
"""Largest size of the folder of exported programs (a robot's program is 10–200 kB)."""

TRUSTED_MODULES = ("mobman", "numpy", "jax", "builtins", "copyreg", "collections", "_codecs", "math")
"""Top-level modules whose classes and functions a stored program's static arguments may name."""

_folder: Path | None = None


def enable(compilation_folder: Path | None) -> Path | None:
    """Keep exported programs in ``compilation_folder / "exported"`` from now on in this process (None: off).
    Returns the folder, or None; raises :class:`mobman.InputError` when it cannot be created."""
    global _folder
    _folder = subfolder(compilation_folder, "exported", "exported programs")
    return _folder


def subfolder(compilation_folder: Path | None, name: str, what: str) -> Path | None:
    """``compilation_folder / name``, created readable by its owner only (None for None); an
    :class:`mobman.InputError` naming ``what`` when it cannot be created."""
    if compilation_folder is None:
        return None
    folder = Path(compilation_folder) / name
    try:
        folder.mkdir(mode=0o700, parents=True, exist_ok=True)
    except OSError as exc:
        raise InputError(f"{what}' folder {folder}: {exc.strerror or exc}") from None
    return folder


def disable() -> None:
    """Stop keeping and reading exported programs in this process."""
    global _folder
    _folder = None


def jit(fn: Callable, static_argnums: tuple[int, ...] = (), name: str | None = None) -> Callable:
    """``jax.jit(fn, static_argnums=static_argnums)`` that reads and keeps its programs on disk once
    :func:`enable` has been called (see the module's docstring). Positional arguments only. ``name``: what
    tells this function's programs from every other's (by default its module and qualified name; give one
    where ``fn`` is made by a decorator, whose inner functions all share a qualified name)."""
    plain = jax.jit(fn, static_argnums=static_argnums)
    name = name or f"{fn.__module__}.{fn.__qualname__}"
    programs: dict[Any, Callable] = {}

    @functools.wraps(fn)
    def call(*args: Any) -> Any:
        if _folder is None:
            return plain(*args)
        arrays = [i for i in range(len(args)) if i not in static_argnums]
        if any(isinstance(args[i], jax.core.Tracer) for i in arrays):
            return plain(*args)
        shapes = tuple((np.shape(args[i]), _dtype(args[i]).str) for i in arrays)
        statics = tuple(args[i] for i in static_argnums if i < len(args))
        try:
            program = programs.get((statics, shapes))
        except TypeError:  # an unhashable static argument: jax.jit reports it
            return plain(*args)
        if program is None:
            program = _load_or_export(fn, name, static_argnums, args, arrays, shapes) or plain
            programs[(statics, shapes)] = program
        if program is plain:
            return plain(*args)
        return program(*(args[i] for i in arrays))

    call.plain = plain  # type: ignore[attr-defined]
    return call


def _load_or_export(
    fn: Callable, name: str, static_argnums: tuple[int, ...], args: tuple, arrays: list[int], shapes: tuple
) -> Callable | None:
    """The compiled call of the stored program for these arguments, exported and stored first if there is
    none; None when the static arguments cannot be keyed or the program cannot be exported."""
    assert _folder is not None
    statics = {i: args[i] for i in static_argnums if i < len(args)}
    key = _key(name, statics, shapes)
    if key is None:
        return None
    path, unexportable = _folder / f"{key}.exported", _folder / f"{key}.plain"
    if unexportable.exists():
        return None
    try:
        exported = jax.export.deserialize(bytearray(path.read_bytes()))
    except Exception:  # noqa: BLE001 - none stored yet, or a damaged file: exported afresh
        exported = _export(fn, statics, args, arrays)
        if exported is None:
            try:
                store(unexportable, b"", pattern="*.plain")  # later processes do not try again
            except OSError:
                pass
            return None
        try:
            store(path, exported.serialize())
        except (OSError, ValueError, TypeError, ImportError):
            pass  # a read-only cache or an unserializable result: the program still runs, unstored
    return jax.jit(exported.call)


def _export(fn: Callable, statics: dict[int, Any], args: tuple, arrays: list[int]) -> Any:
    def with_statics(*xs: Any) -> Any:
        full = list(args)
        for i, x in zip(arrays, xs):
            full[i] = x
        for i, s in statics.items():
            full[i] = s
        return fn(*full)

    specs = [jax.ShapeDtypeStruct(np.shape(args[i]), _dtype(args[i])) for i in arrays]
    try:
        return jax.export.export(jax.jit(with_statics))(*specs)
    except Exception:  # noqa: BLE001 - a program that cannot be exported runs as plain jit
        return None


def _dtype(x: Any) -> np.dtype:
    """The dtype of an array argument (of what NumPy makes of a number or a list)."""
    return np.dtype(x.dtype) if hasattr(x, "dtype") else np.result_type(x)


def _key(name: str, statics: dict[int, Any], shapes: tuple) -> str | None:
    try:
        description = pickle.dumps(described(statics), protocol=5)
    except _Untrusted:
        return None
    digest = hashlib.sha256()
    drop_ins = repr(sorted(n for n, k in kernels.registry().items() if k.drop_in is not None))
    for part in (
        name.encode(),
        description,
        repr(shapes).encode(),
        drop_ins.encode(),
        source_digest().encode(),
    ):
        digest.update(len(part).to_bytes(8, "little"))
        digest.update(part)
    return digest.hexdigest()


class _Untrusted(Exception):
    """A static argument names code outside :data:`TRUSTED_MODULES`, or is of a kind :func:`described` does
    not know: its program is not kept."""


def _trusted_name(thing: Any) -> str:
    module = getattr(thing, "__module__", None) or ""
    if module.split(".")[0] not in TRUSTED_MODULES:
        raise _Untrusted(module)
    return f"{module}.{getattr(thing, '__qualname__', type(thing).__qualname__)}"


def described(value: Any) -> Any:
    """``value`` as plain builtins that equal values describe alike in every process: a dataclass by its
    class and fields only (not the caches an instance keeps in its ``__dict__``, which depend on what ran
    before), containers by their items (sets sorted), arrays by dtype, shape and bytes, classes and functions
    by their qualified names (only mobman's, NumPy's, JAX's and builtins': :class:`_Untrusted` otherwise)."""
    if value is None or isinstance(value, (bool, int, float, complex, str, bytes)):
        return (type(value).__name__, value)
    if isinstance(value, (np.ndarray, np.generic, jax.Array)):
        array = np.asarray(value)
        return ("array", array.dtype.str, array.shape, array.tobytes())
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        fields = tuple((f.name, described(getattr(value, f.name))) for f in dataclasses.fields(value))
        return ("dataclass", _trusted_name(type(value)), fields)
    if isinstance(value, type) or callable(value):
        return ("ref", _trusted_name(value))
    if isinstance(value, enum.Enum):
        return ("enum", _trusted_name(type(value)), value.name)
    if isinstance(value, (tuple, list)):
        return (_trusted_name(type(value)), tuple(described(v) for v in value))
    if isinstance(value, dict):
        items = ((repr(described(k)), described(v)) for k, v in value.items())
        return ("dict", tuple(sorted(items, key=repr)))
    if isinstance(value, (set, frozenset)):
        return ("set", tuple(sorted((described(v) for v in value), key=repr)))
    raise _Untrusted(type(value).__qualname__)


def trusted_loads(data: bytes) -> Any:
    """``pickle.loads`` that refuses (``pickle.UnpicklingError``) any class or function outside
    :data:`TRUSTED_MODULES`: for what mobman itself keeps on disk (:mod:`mobman.io.urdf_cache`)."""
    return _TrustedOnly(io.BytesIO(data)).load()


class _TrustedOnly(pickle.Unpickler):
    def find_class(self, module: str, name: str) -> Any:
        if module.split(".")[0] not in TRUSTED_MODULES:
            raise pickle.UnpicklingError(f"{module}.{name}")
        return super().find_class(module, name)


@functools.cache
def source_digest() -> str:
    """SHA-256 of the installed mobman package's Python sources, JAX's and jaxlib's versions and the backend."""
    import jaxlib

    package = Path(__file__).resolve().parents[1]
    digest = hashlib.sha256()
    for path in sorted(package.rglob("*.py")):
        digest.update(str(path.relative_to(package)).encode())
        digest.update(path.read_bytes())
    digest.update(f"{jax.__version__} {jaxlib.__version__} {jax.default_backend()}".encode())
    return digest.hexdigest()


def store(
    path: Path, data: bytes | bytearray, max_bytes: int = MAX_BYTES, pattern: str = "*.exported"
) -> None:
    """Write ``data`` to ``path`` atomically, then keep the files ``pattern`` of its folder within ``max_bytes``
    (the least recently written removed first)."""
    with tempfile.NamedTemporaryFile(dir=path.parent, delete=False, suffix=".tmp") as f:
        f.write(data)
    os.replace(f.name, path)
    files = sorted(path.parent.glob(pattern), key=lambda p: p.stat().st_mtime)
    total = sum(p.stat().st_size for p in files)
    for old in files:
        if total <= max_bytes:
            break
        total -= old.stat().st_size
        old.unlink(missing_ok=True)


__all__ = [
    "MAX_BYTES",
    "TRUSTED_MODULES",
    "disable",
    "enable",
    "jit",
    "source_digest",
    "store",
    "trusted_loads",
]
