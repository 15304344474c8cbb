"""Reading TOML specification files (``mobman simulate``, ``mobman load-capacity``): each helper checks one
field and raises :class:`~mobman.errors.InputError` naming it (``robot.params.l1: must be > 0 …``)."""

from __future__ import annotations

import contextlib
import dataclasses
import difflib
import math
import tomllib
import types
import typing
from collections.abc import Callable, Collection, Iterator, Mapping
from pathlib import Path
from typing import Any, Literal, TypeVar, overload

import numpy as np
import numpy.typing as npt

from mobman.errors import InputError, MobmanError
from mobman.io.numbers import MAX_MAGNITUDE

T = TypeVar("T")

MAX_FILE_BYTES = 16 * 2**20
"""Largest accepted robot or specification file."""

MAX_NESTING = 8
"""Deepest accepted nesting of tables and arrays in a robot or specification file."""


def read_text(path: Path, field: str, limit: int = MAX_FILE_BYTES) -> str:
    """The UTF-8 text of the file at ``path``; unreadable, binary, non-UTF-8 or larger than ``limit`` bytes
    → InputError naming ``field``."""
    try:
        with open(path, "rb") as handle:
            raw = handle.read(limit + 1)
    except OSError as exc:
        raise InputError(f"{field}: cannot read ({exc.strerror or exc})") from None
    if len(raw) > limit:
        size = f"{limit // 2**20} MiB" if limit >= 2**20 else f"{limit} bytes"
        raise InputError(f"{field}: larger than {size}")
    if b"\0" in raw:
        raise InputError(f"{field}: binary content (a NUL byte at {raw.index(0)}); expected a text file")
    try:
        return raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise InputError(f"{field}: not UTF-8 text (byte {exc.start}); save the file as UTF-8") from None


def _depth(value: Any) -> int:
    """Nesting depth of tables and arrays, without recursion (0 for a scalar)."""
    deepest, pending = 0, [(value, 0)]
    while pending:
        item, level = pending.pop()
        if isinstance(item, (dict, list)):
            if level + 1 > MAX_NESTING:
                return level + 1
            deepest = max(deepest, level + 1)
            pending.extend((v, level + 1) for v in (item.values() if isinstance(item, dict) else item))
    return deepest


def read_toml(path: Path) -> dict:
    """The TOML document at ``path`` as a dict; unreadable, binary, non-UTF-8, invalid or too deeply nested
    files raise InputError naming the file."""
    text = read_text(path, str(path))
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise InputError(f"{path}: invalid TOML ({exc})") from None
    except RecursionError:
        raise InputError(f"{path}: nested deeper than {MAX_NESTING} levels") from None
    if _depth(data) > MAX_NESTING:
        raise InputError(f"{path}: nested deeper than {MAX_NESTING} levels")
    return data


@contextlib.contextmanager
def naming(path: Path | str) -> Iterator[None]:
    """Prefix the message of an InputError raised in the block with the file's path (once)."""
    try:
        yield
    except InputError as exc:
        if str(exc).startswith(f"{path}:"):
            raise
        raise InputError(f"{path}: {exc}") from None


@overload
def table(data: dict, key: str, field: str, required: Literal[True] = True) -> dict: ...
@overload
def table(data: dict, key: str, field: str, required: bool) -> dict | None: ...
def table(data: dict, key: str, field: str, required: bool = True) -> dict | None:
    """The sub-table ``data[key]`` (None when absent and not required)."""
    value = data.get(key)
    if value is None:
        if required:
            raise InputError(f"{field}: missing (a [{field}] table)")
        return None
    if not isinstance(value, dict):
        raise InputError(f"{field}: must be a table, got {_shown(value)}")
    return value


def _shown(value: Any) -> str:
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


def keys(entries: dict, field: str, allowed: tuple[str, ...]) -> None:
    """Reject keys of a table that are not in ``allowed``, suggesting the closest allowed one."""
    for key in entries:
        if key not in allowed:
            close = difflib.get_close_matches(str(key), allowed, n=1)
            hint = f"did you mean {close[0]!r}? " if close else ""
            name = f"{field}.{key}" if field else str(key)
            raise InputError(f"{name}: unknown key; {hint}allowed: {', '.join(allowed)}")


def kind(entries: dict, field: str, kinds: dict) -> Any:
    """The value of ``kinds`` selected by the table's ``kind`` key."""
    name = entries.get("kind")
    if not isinstance(name, str) or name not in kinds:
        close = difflib.get_close_matches(name, list(kinds), n=1) if isinstance(name, str) else []
        hint = f" (did you mean {close[0]!r}?)" if close else ""
        raise InputError(f"{field}.kind: {_shown(name)} not one of {', '.join(kinds)}{hint}")
    return kinds[name]


def text(entries: dict, key: str, field: str, default: Any = None, allowed: tuple[str, ...] = ()) -> Any:
    """A string at ``entries[key]`` (``default`` when absent), one of ``allowed`` when given."""
    value = entries.get(key, default)
    name = f"{field}.{key}" if field else key
    if value is default:
        return value
    if not isinstance(value, str) or len(value) > 200:
        raise InputError(f"{name}: must be a string (at most 200 characters), got {_shown(value)}")
    if allowed and value not in allowed:
        close = difflib.get_close_matches(value, allowed, n=1) or [
            a for a in allowed if a.casefold() == value.casefold()
        ]
        hint = f" (did you mean {close[0]!r}?)" if close else ""
        raise InputError(f"{name}: {value!r} not one of {', '.join(allowed)}{hint}")
    return value


def integer(entries: dict, key: str, field: str, default: Any = None, minimum: int | None = None) -> Any:
    """An integer at ``entries[key]`` (``default`` when absent), ≥ ``minimum`` when given."""
    value = entries.get(key, default)
    name = f"{field}.{key}" if field else key
    if value is default:
        return value
    if isinstance(value, bool) or not isinstance(value, int) or abs(value) > 10**6:
        raise InputError(f"{name}: must be an integer, got {_shown(value)}")
    if minimum is not None and value < minimum:
        raise InputError(f"{name}: must be ≥ {minimum}, got {value}")
    return value


def _checked(value: float, name: str) -> float:
    if not math.isfinite(value) or abs(value) > MAX_MAGNITUDE:
        raise InputError(f"{name}: must be a finite number with |value| ≤ {MAX_MAGNITUDE:g}, got {value!r}")
    return value


def number(entries: dict, key: str, field: str, default: Any = None, positive: bool = False) -> float:
    """A finite number (optionally > 0) at ``entries[key]``, |value| ≤ :data:`~mobman.io.numbers.MAX_MAGNITUDE`."""
    value = entries.get(key, default)
    if value is None:
        raise InputError(f"{field}.{key}: missing (a number)" if field else f"{key}: missing (a number)")
    name = f"{field}.{key}" if field else key
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise InputError(f"{name}: must be a finite number, got {_shown(value)}")
    try:
        _checked(float(value), name)
    except OverflowError:
        raise InputError(f"{name}: must be a finite number with |value| ≤ {MAX_MAGNITUDE:g}") from None
    if positive and value <= 0:
        raise InputError(f"{name}: must be > 0, got {value!r}")
    return float(value)


def array(value: object, name: str) -> np.ndarray:
    """A finite float array from a TOML number or (nested, rectangular) list of numbers, each
    |value| ≤ :data:`~mobman.io.numbers.MAX_MAGNITUDE`."""
    pending = [value]
    while pending:
        item = pending.pop()
        if isinstance(item, (list, tuple, np.ndarray)):
            pending.extend(item.ravel().tolist() if isinstance(item, np.ndarray) else item)
        elif isinstance(item, bool) or not isinstance(item, (int, float)):
            raise InputError(f"{name}: must be a number or an array of numbers, got {_shown(value)}")
        else:
            try:
                _checked(float(item), name)
            except OverflowError:
                raise InputError(f"{name}: must be finite numbers with |value| ≤ {MAX_MAGNITUDE:g}") from None
    try:
        return np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"{name}: must be a rectangular array of numbers, got {_shown(value)}") from None


def build(field: str, factory: Callable[..., T], /, **kwargs: Any) -> T:
    """Call a constructor; its ModelError becomes an InputError naming the spec field."""
    try:
        return factory(**kwargs)
    except (MobmanError, TypeError, ValueError) as exc:
        raise InputError(f"{field}: {' '.join(str(exc).split())}") from None


def _array_like(tp: Any) -> bool:
    """Whether the annotation ``tp`` is ``numpy.typing.ArrayLike`` (or it or None)."""
    args = [a for a in typing.get_args(tp) if a is not type(None)]
    return tp == npt.ArrayLike or (bool(args) and typing.Union[tuple(args)] == npt.ArrayLike)


def _converted(value: Any, tp: Any, field: str, key: str, choices: tuple[str, ...], convert: Mapping) -> Any:
    """``value`` (at ``field.key``) read as the annotation ``tp`` (see :func:`dataclass_values`)."""
    origin, args = typing.get_origin(tp), typing.get_args(tp)
    name = f"{field}.{key}" if field else key
    if _array_like(tp):
        return array(value, name)
    if origin in (typing.Union, types.UnionType):
        (inner,) = [a for a in args if a is not type(None)]
        return _converted(value, inner, field, key, choices, convert)
    if tp in convert:
        return convert[tp](value, name)
    if tp is bool:
        if not isinstance(value, bool):
            raise InputError(f"{name}: must be true or false, got {_shown(value)}")
        return value
    if tp is np.ndarray:
        return array(value, name)
    readers = {
        str: lambda: text({key: value}, key, field, allowed=choices),
        int: lambda: integer({key: value}, key, field),
        float: lambda: number({key: value}, key, field),
    }
    if tp in readers:
        return readers[tp]()
    if origin is not tuple or not isinstance(value, list):
        raise InputError(f"{name}: must be an array, got {_shown(value)}")
    variadic = len(args) == 2 and args[1] is Ellipsis
    if not variadic and len(value) != len(args):
        raise InputError(f"{name}: {len(args)} values, got {len(value)}")
    items = [args[0]] * len(value) if variadic else list(args)
    return tuple(
        _converted(v, t, field, f"{key}[{i}]", (), convert) for i, (v, t) in enumerate(zip(value, items))
    )


def _readable(tp: Any, convert: Mapping) -> bool:
    """Whether a field annotated ``tp`` can be read from a file (a number, string, bool, array, a tuple of
    those or a type of ``convert``)."""
    origin, args = typing.get_origin(tp), typing.get_args(tp)
    if _array_like(tp):
        return True
    if origin in (typing.Union, types.UnionType):
        inner = [a for a in args if a is not type(None)]
        return len(inner) == 1 and _readable(inner[0], convert)
    if origin is tuple:
        return all(a is Ellipsis or _readable(a, convert) for a in args)
    return tp in convert or tp in (str, bool, int, float, np.ndarray)


def dataclass_values(
    cls: type,
    entries: dict,
    field: str,
    *,
    names: Collection[str] | None = None,
    other_keys: tuple[str, ...] = ("kind",),
    choices: Mapping[str, tuple[str, ...]] | None = None,
    convert: Mapping[type, Callable[[Any, str], Any]] | None = None,
) -> dict[str, Any]:
    """The keyword arguments of the dataclass ``cls`` given by a file's table: its keys are the fields that a
    file can give (``names``, if given, keeps only those; ``other_keys`` are allowed and left out), each value
    converted by the field's annotation — str, int, float, bool, a NumPy array, a tuple of those, or a type
    found in ``convert`` (value, field name → object: a nested table). ``choices`` lists the allowed values
    of string fields. Absent keys are left out (the dataclass defaults apply); an unknown key or a value of
    the wrong type raises InputError naming it."""
    convert = convert or {}
    hints = typing.get_type_hints(cls)
    readable = [
        f.name
        for f in dataclasses.fields(cls)
        if f.init and (names is None or f.name in names) and _readable(hints[f.name], convert)
    ]
    keys(entries, field, (*other_keys, *readable))
    return {
        key: _converted(entries[key], hints[key], field, key, (choices or {}).get(key, ()), convert)
        for key in readable
        if key in entries
    }
