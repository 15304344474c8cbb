"""Reading TOML specification files (``mobman simulate``, ``mobman load-capacity``): each helper checks one
field and raises :class:`~mobman.errors.InputError` naming it (``robot.params.l1: must be > 0 …``)."""

from __future__ import annotations

import tomllib
from pathlib import Path
from typing import Any

import numpy as np

from mobman.errors import InputError, MobmanError


def read_toml(path: Path) -> dict:
    """The TOML document at ``path`` as a dict; unreadable or invalid files raise InputError."""
    try:
        with open(path, "rb") as handle:
            return tomllib.load(handle)
    except OSError as exc:
        raise InputError(f"{path}: cannot read ({exc.strerror})") from None
    except tomllib.TOMLDecodeError as exc:
        raise InputError(f"{path}: invalid TOML ({exc})") from None


def table(data: dict, key: str, field: str, required: bool = True) -> dict | None:
    """The sub-table ``data[key]`` (None when absent and not required)."""
    value = data.get(key)
    if value is None:
        if required:
            raise InputError(f"{field}: missing (a [{field}] table)")
        return None
    if not isinstance(value, dict):
        raise InputError(f"{field}: must be a table, got {value!r}")
    return value


def keys(entries: dict, field: str, allowed: tuple[str, ...]) -> None:
    """Reject keys of a table that are not in ``allowed``."""
    for key in entries:
        if key not in allowed:
            raise InputError(f"{field}.{key}: unknown key; allowed: {', '.join(allowed)}")


def kind(entries: dict, field: str, kinds: dict) -> Any:
    """The value of ``kinds`` selected by the table's ``kind`` key."""
    name = entries.get("kind")
    if name not in kinds:
        raise InputError(f"{field}.kind: {name!r} not one of {', '.join(kinds)}")
    return kinds[name]


def number(entries: dict, key: str, field: str, default: Any = None, positive: bool = False) -> float:
    """A finite number (optionally > 0) at ``entries[key]``."""
    value = entries.get(key, default)
    if value is None:
        raise InputError(f"{field}.{key}: missing (a number)" if field else f"{key}: missing (a number)")
    name = f"{field}.{key}" if field else key
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not np.isfinite(value):
        raise InputError(f"{name}: must be a finite number, got {value!r}")
    if positive and value <= 0:
        raise InputError(f"{name}: must be > 0, got {value!r}")
    return float(value)


def array(value, name: str) -> np.ndarray:
    """A finite float array from a TOML number or (nested) list."""
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"{name}: must be a number or an array of numbers, got {value!r}") from None
    if not np.all(np.isfinite(arr)):
        raise InputError(f"{name}: must be finite, got {value!r}")
    return arr


def build(field: str, factory, /, **kwargs):
    """Call a constructor; its ModelError becomes an InputError naming the spec field."""
    try:
        return factory(**kwargs)
    except MobmanError as exc:
        raise InputError(f"{field}: {exc}") from None
    except TypeError as exc:
        raise InputError(f"{field}: {exc}") from None
