"""A persistent cache of compiled programs, so that a second ``mobman`` command (or script) with the same
robot reads its programs back instead of compiling them: JAX's persistent compilation cache in a folder of the
user's own (docs/performance.md gives the time it saves).

Each public function compiles its program for a robot, task and array shape the first time it is called in a
process. The ``mobman`` command calls :func:`enable` before anything compiles. A program is found again only
for the same computation, shapes, JAX version and machine (JAX's cache key), so a changed robot, option or
mobman version compiles afresh and never reads a stale program.

The folder, in order:

1. ``folder`` given to :func:`enable`;
2. the one JAX is already configured with (``JAX_COMPILATION_CACHE_DIR``, or ``jax.config`` set by the
   caller): it is kept, with JAX's own settings;
3. ``MOBMAN_CACHE_DIR``, where the empty string or ``off`` turns the cache off;
4. ``$XDG_CACHE_HOME/mobman/xla``, by default ``~/.cache/mobman/xla``.

mobman's folder holds at most :data:`MAX_BYTES` (the least recently read programs are removed first, under a
file lock, so that concurrent commands share it safely) and keeps programs that took at least
:data:`MIN_COMPILE_SECONDS` to compile. JAX's environment variables ``JAX_COMPILATION_CACHE_MAX_SIZE`` and
``JAX_PERSISTENT_CACHE_MIN_COMPILE_TIME_SECS``, where set, take precedence. Anyone who can write to the folder
can make a later command run code of their choosing (JAX's warning): it is created readable by its owner only.
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

import jax

from mobman.errors import InputError

ENVIRONMENT = "MOBMAN_CACHE_DIR"
"""The environment variable naming the folder (the empty string or ``off``: no cache)."""

MAX_BYTES = 512 * 2**20
"""Largest size of mobman's folder (512 MiB; a robot's programs take a few hundred kB)."""

MIN_COMPILE_SECONDS = 0.2
"""Programs compiled faster than this are not stored (reading one back costs about as much)."""


def default_folder() -> Path:
    """``$XDG_CACHE_HOME/mobman/xla``, ``~/.cache/mobman/xla`` when that variable is unset or empty."""
    base = os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache"
    return Path(base) / "mobman" / "xla"


def enable(folder: str | os.PathLike[str] | None = None) -> Path | None:
    """Turn JAX's persistent compilation cache on for this process; returns its folder, or None when it is
    off (``MOBMAN_CACHE_DIR`` empty or ``off``). Call it before the first compiled call: JAX opens its cache
    once, at its first compilation.

    Raises :class:`mobman.InputError` naming the folder when it cannot be created or written to.
    """
    configured = jax.config.values.get("jax_compilation_cache_dir")
    if folder is None and configured:
        return Path(configured)
    if folder is None:
        chosen = os.environ.get(ENVIRONMENT)
        if chosen is not None and chosen.strip().lower() in ("", "off"):
            return None
        path = Path(chosen).expanduser() if chosen is not None else default_folder()
    else:
        path = Path(folder).expanduser()
    try:
        path.mkdir(mode=0o700, parents=True, exist_ok=True)
        tempfile.TemporaryFile(dir=path).close()  # JAX would warn at every program it fails to store
    except OSError as exc:
        raise InputError(
            f"compilation cache folder {path}: {exc.strerror or exc}; set {ENVIRONMENT} to a writable folder, "
            "or to the empty string to turn the cache off"
        ) from None
    jax.config.update("jax_compilation_cache_dir", str(path))
    if "JAX_COMPILATION_CACHE_MAX_SIZE" not in os.environ:
        jax.config.update("jax_compilation_cache_max_size", MAX_BYTES)
    if "JAX_PERSISTENT_CACHE_MIN_COMPILE_TIME_SECS" not in os.environ:
        jax.config.update("jax_persistent_cache_min_compile_time_secs", MIN_COMPILE_SECONDS)
    return path


__all__ = ["ENVIRONMENT", "MAX_BYTES", "MIN_COMPILE_SECONDS", "default_folder", "enable"]
