"""Chunked, resumable studies: rows computed chunk by chunk into a Zarr store, in this process or on a Dask
cluster.

A study is a table of rows computed independently of each other (the cells of a map, the designs of a sweep).
Its rows are cut into chunks of ``chunk`` rows, the unit of work. Every result is a Zarr array whose first
axis is the rows, chunked as the work is, so that a chunk's results are whole Zarr chunks. Once a chunk's
results are written, its flag in the ``done`` array (one Zarr chunk per flag) is set: a study that stops
(interrupted, a worker lost, the machine down) keeps every flagged chunk, and running it again with the same
definition computes the others only. A chunk written but not yet flagged is computed again and overwritten,
so a row never mixes two runs.

The definition (a JSON object: the kind of study, the robot, every option that changes a result) is kept in
the group's attributes (``attrs["mobman"]``); a store holding another definition is refused, with the first
field that differs named. A new store is created under a temporary name beside the path and renamed into
place, so the path never holds a half-created store.

With ``scheduler``, the chunks are computed on a Dask cluster (:mod:`distributed`, ``pip install
"mobman[studies]"``): ``"local"`` or ``"local:N"`` starts N worker processes on this machine, bound to
127.0.0.1; an address such as ``"tcp://10.0.0.5:8786"`` connects to a running scheduler. The workers compute;
this process writes each chunk's results as they arrive, so the workers need neither the store's folder nor
write access to it, and a lost worker loses at most the chunks it was computing.
"""

from __future__ import annotations

import json
import math
import os
import re
import shutil
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, NoReturn

import numpy as np

from mobman.errors import InputError

Compute = Callable[[int, int], dict[str, np.ndarray]]
"""The rows [start, stop) of a study → each result's values for them (first axis: the rows)."""

Progress = Callable[[int, int], None]
"""Called with (chunks done, chunks in all) after each chunk, and once before the first."""

FORMAT = 1
"""Version of the layout this module writes (``attrs["mobman"]["format"]``)."""

INSTALL = 'pip install "mobman[studies]"'

CONNECT_TIMEOUT = 30.0
"""Seconds to wait for a Dask scheduler named by its address."""

CHUNK = 4096
"""Rows per unit of work of a new study, unless told otherwise (:func:`run`'s ``new_chunk``)."""


@dataclass(frozen=True)
class Column:
    """One result of a study: the shape of a row's value (``()`` for a number), its dtype and the value of
    rows not computed yet."""

    shape: tuple[int, ...] = ()
    dtype: str = "float64"
    fill: Any = field(default=math.nan)


@dataclass(frozen=True)
class Study:
    """A study's results read back: every column with the rows first, the rows computed (``done``, one flag
    per row) and the definition it was computed for."""

    definition: dict[str, Any]
    columns: dict[str, np.ndarray]
    done: np.ndarray

    @property
    def complete(self) -> bool:
        return bool(self.done.all())


def chunks(rows: int, chunk: int) -> list[tuple[int, int]]:
    """The rows [start, stop) of each chunk."""
    return [(start, min(start + chunk, rows)) for start in range(0, rows, chunk)]


def run(
    compute: Compute,
    rows: int,
    columns: dict[str, Column],
    definition: dict[str, Any],
    *,
    store: str | os.PathLike[str] | None = None,
    chunk: int | None = None,
    new_chunk: int = CHUNK,
    scheduler: str | None = None,
    progress: Progress | None = None,
) -> Study:
    """Compute every row of a study (module notes) and return its results.

    ``compute(start, stop)`` returns each column's values for those rows; it must be picklable (a
    module-level function or a :func:`functools.partial` of one) when ``scheduler`` is given. ``store``: the
    folder of the Zarr store the results are kept in (resumed where it exists, created otherwise); without
    it the results stay in memory. ``chunk``: rows per unit of work, by default ``new_chunk`` for a new study
    and the store's own for one resumed (another one is refused).
    """
    check_options(store, chunk, scheduler)
    definition = _normalised(definition)
    if store is not None and chunk is None and Path(store).exists():
        chunk = int(_existing(Path(store)).attrs["mobman"]["chunk"])
    chunk = new_chunk if chunk is None else int(chunk)
    spans = chunks(rows, chunk)
    if store is None:
        values = {name: _filled(rows, c) for name, c in columns.items()}
        done = np.zeros(len(spans), dtype=bool)

        def write(k: int, result: dict[str, np.ndarray]) -> None:
            start, stop = spans[k]
            for name in columns:
                values[name][start:stop] = result[name]
            done[k] = True

        _compute_all(compute, spans, done, write, scheduler, progress)
        return Study(definition, values, np.repeat(done, [b - a for a, b in spans]))
    group = _open(Path(store), rows, chunk, columns, definition)
    flags = group["done"]
    done = np.asarray(flags[:], dtype=bool)

    def write_store(k: int, result: dict[str, np.ndarray]) -> None:
        start, stop = spans[k]
        for name in columns:
            group[name][start:stop] = result[name]
        flags[k] = True  # after the results: a chunk flagged is a chunk whole

    _compute_all(compute, spans, done, write_store, scheduler, progress)
    return read(store)


def read(store: str | os.PathLike[str]) -> Study:
    """A study's results as they are in ``store`` (complete or not)."""
    group = _existing(Path(store))
    meta = _layout(group, str(store))
    rows, chunk = meta["rows"], meta["chunk"]
    spans = chunks(rows, chunk)
    flags = np.asarray(group["done"][:], dtype=bool)
    columns = {name: np.asarray(group[name][:]) for name in meta["columns"]}
    return Study(meta["definition"], columns, np.repeat(flags, [b - a for a, b in spans]))


def _layout(group: Any, path: str) -> dict[str, Any]:
    """The store's ``attrs["mobman"]`` checked against the layout it states (module notes): its rows and
    chunk, each column an array of the rows and the row shape and dtype stated, one ``done`` flag per chunk;
    an InputError naming the first field that is not so (a store edited or damaged)."""

    def refuse(field: str, text: str) -> NoReturn:
        raise InputError(f"store {path!r}: {field} {text} (a damaged or edited store)")

    meta = group.attrs["mobman"]
    if not isinstance(meta, dict):
        refuse("attrs['mobman']", "is not an object")
    for key in ("rows", "chunk"):
        value = meta.get(key)
        if not (isinstance(value, int) and not isinstance(value, bool) and value >= (key == "chunk")):
            refuse(key, f"must be an integer ≥ {int(key == 'chunk')}, got {value!r}")
    if not isinstance(meta.get("definition"), dict):
        refuse("definition", "is missing")
    columns = meta.get("columns")
    if not (isinstance(columns, dict) and columns):
        refuse("columns", "is missing")
    arrays = {"done": ((len(chunks(meta["rows"], meta["chunk"])),), "bool")}
    for name, column in columns.items():
        if not (isinstance(column, dict) and isinstance(column.get("shape"), list) and "dtype" in column):
            refuse(f"columns.{name}", "must give the shape and dtype of a row")
        arrays[name] = ((meta["rows"], *column["shape"]), column["dtype"])
    for name, (shape, dtype) in arrays.items():
        array = group.get(name) if hasattr(group, "get") else None
        if array is None or not hasattr(array, "shape"):
            refuse(name, "is missing")
        if tuple(array.shape) != tuple(shape) or str(array.dtype) != str(dtype):
            refuse(name, f"is {array.dtype} {tuple(array.shape)}, its layout says {dtype} {tuple(shape)}")
    return meta


def _compute_all(
    compute: Compute,
    spans: list[tuple[int, int]],
    done: np.ndarray,
    write: Callable[[int, dict[str, np.ndarray]], None],
    scheduler: str | None,
    progress: Progress | None,
) -> None:
    pending = [k for k in range(len(spans)) if not done[k]]
    finished = len(spans) - len(pending)
    if progress is not None:
        progress(finished, len(spans))
    results = (
        _local(compute, spans, pending) if scheduler is None else _on_dask(compute, spans, pending, scheduler)
    )
    for k, result in results:
        write(k, result)
        finished += 1
        if progress is not None:
            progress(finished, len(spans))


def _local(compute: Compute, spans: list[tuple[int, int]], pending: list[int]) -> Iterator:
    for k in pending:
        yield k, compute(*spans[k])


def _on_dask(compute: Compute, spans: list[tuple[int, int]], pending: list[int], scheduler: str) -> Iterator:
    """Each pending chunk a task on the cluster ``scheduler`` names (module notes); results as they arrive."""
    try:
        from distributed import Client, LocalCluster, as_completed
    except ImportError:
        raise InputError(f"scheduler {scheduler!r} needs Dask's distributed scheduler: {INSTALL}") from None
    cluster = None
    if scheduler == "local" or scheduler.startswith("local:"):
        workers = _local_workers(scheduler)
        cluster = LocalCluster(
            n_workers=workers, threads_per_worker=1, host="127.0.0.1", dashboard_address=None, processes=True
        )
        client = Client(cluster)
    else:  # an address (check_scheduler)
        try:
            client = Client(scheduler, timeout=CONNECT_TIMEOUT)
        except (OSError, TimeoutError) as exc:
            raise InputError(f"scheduler {scheduler!r}: cannot connect ({exc})") from None
    try:
        futures = [client.submit(compute, *spans[k], key=f"mobman-chunk-{k}-{os.getpid()}") for k in pending]
        index = {future.key: k for future, k in zip(futures, pending)}
        for future in as_completed(futures):
            yield index[future.key], future.result()
    finally:
        client.close()
        if cluster is not None:
            cluster.close()


def check_options(store: object, chunk: object, scheduler: object) -> None:
    """:func:`run`'s ``store`` (a path or None), ``chunk`` (an integer ≥ 1 or None) and ``scheduler``
    (:func:`check_scheduler`, or None), checked: a study's public function calls it before any work."""
    if chunk is not None and not (isinstance(chunk, (int, np.integer)) and chunk >= 1):
        raise InputError(f"chunk must be an integer ≥ 1 (rows per unit of work), got {chunk!r}")
    if store is not None and not isinstance(store, (str, os.PathLike)):
        raise InputError(f"store must be a folder's path (str or os.PathLike), got {type(store).__name__}")
    if scheduler is not None:
        check_scheduler(scheduler)


def check_scheduler(scheduler: object) -> None:
    """An InputError unless ``scheduler`` is ``"local"``, ``"local:N"`` (N ≥ 1) or an address with a
    protocol Dask speaks, a host and a port (``tcp://HOST:PORT``, ``tls://HOST:PORT``)."""
    local = isinstance(scheduler, str) and (scheduler == "local" or scheduler.startswith("local:"))
    address = (
        re.fullmatch(r"(tcp|tls)://[^\s:/]+:(\d{1,5})", scheduler) if isinstance(scheduler, str) else None
    )
    if not (local or (address and 1 <= int(address.group(2)) <= 65535)):
        raise InputError(
            f"scheduler must be 'local', 'local:N' (N worker processes) or an address tcp://HOST:PORT "
            f"or tls://HOST:PORT (port 1 to 65535), got {scheduler!r}"
        )
    if local:
        _local_workers(str(scheduler))


def _local_workers(scheduler: str) -> int:
    if scheduler == "local":
        return max(
            1, len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count() or 1
        )
    count = scheduler.split(":", 1)[1]
    if not (count.isdigit() and int(count) >= 1):
        raise InputError(f"scheduler 'local:N' needs N, the worker processes, an integer ≥ 1, got {count!r}")
    return int(count)


def _filled(rows: int, column: Column) -> np.ndarray:
    return np.full((rows,) + tuple(column.shape), column.fill, dtype=column.dtype)


def _normalised(definition: dict[str, Any]) -> dict[str, Any]:
    """The definition as JSON reads it back (tuples as lists, NumPy numbers as Python ones)."""
    try:
        return json.loads(json.dumps(definition, default=_plain))
    except (TypeError, ValueError) as exc:
        raise InputError(f"a study's definition must be plain JSON values: {exc}") from None


def _plain(value: Any) -> Any:
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, np.generic):
        return value.item()
    raise TypeError(f"{type(value).__name__} is not a JSON value")


def _zarr() -> Any:
    try:
        import zarr
    except ImportError:
        raise InputError(f"a study's store needs Zarr: {INSTALL}") from None
    return zarr


def _existing(path: Path) -> Any:
    """The study's Zarr group at ``path``; an InputError when there is none."""
    zarr = _zarr()
    if not path.exists():
        raise InputError(f"store {str(path)!r}: no such study (folder)")
    try:
        group = zarr.open_group(str(path), mode="r+")
    except Exception:  # noqa: BLE001 - Zarr raises several kinds for a folder that is no store
        group = None
    if group is None or "mobman" not in group.attrs:
        raise InputError(
            f"store {str(path)!r} exists and is not a mobman study (a Zarr group); give a new path"
        )
    return group


def _open(path: Path, rows: int, chunk: int, columns: dict[str, Column], definition: dict[str, Any]) -> Any:
    """The study's group at ``path``, created when the path does not exist, checked against the definition
    when it does."""
    meta = {
        "format": FORMAT,
        "definition": definition,
        "rows": rows,
        "chunk": chunk,
        "columns": {name: {"shape": list(c.shape), "dtype": c.dtype} for name, c in columns.items()},
    }
    if path.exists():
        group = _existing(path)
        held = dict(group.attrs["mobman"])
        difference = _first_difference(held, _normalised(meta))
        if difference is not None:
            raise InputError(
                f"store {str(path)!r} holds another study ({difference}); give a new path or remove it to "
                "start again"
            )
        return group
    if not path.parent.is_dir():
        raise InputError(f"store {str(path)!r}: the folder {str(path.parent)!r} does not exist")
    zarr = _zarr()
    temporary = path.with_name(f".{path.name}.{os.getpid()}.partial")
    shutil.rmtree(temporary, ignore_errors=True)
    try:
        group = zarr.open_group(str(temporary), mode="w")
        for name, c in columns.items():
            group.create_array(
                name,
                shape=(rows,) + tuple(c.shape),
                chunks=(chunk,) + tuple(c.shape),
                dtype=c.dtype,
                fill_value=c.fill,
            )
        group.create_array(
            "done", shape=(len(chunks(rows, chunk)),), chunks=(1,), dtype=bool, fill_value=False
        )
        group.attrs["mobman"] = _normalised(meta)
        os.rename(temporary, path)
    except OSError as exc:
        shutil.rmtree(temporary, ignore_errors=True)
        raise InputError(f"store {str(path)!r}: cannot create it ({exc.strerror or exc})") from None
    return zarr.open_group(str(path), mode="r+")


def _first_difference(held: dict[str, Any], wanted: dict[str, Any], where: str = "") -> str | None:
    """'FIELD is A here, B in the store' for the first field where two definitions differ, else None."""
    for key in sorted(set(held) | set(wanted), key=lambda k: (k != "definition", k)):  # the definition first
        name = f"{where}.{key}" if where else key
        a, b = held.get(key), wanted.get(key)
        if isinstance(a, dict) and isinstance(b, dict):
            inner = _first_difference(a, b, name)
            if inner is not None:
                return inner
        elif a != b:
            return f"{name.removeprefix('definition.')}: {_shown(b)} asked, {_shown(a)} in the store"
    return None


def _shown(value: Any, width: int = 60) -> str:
    """A value of a definition in a message: JSON, numbers to 6 digits, cut to ``width`` characters."""
    text = json.dumps(_rounded(value))
    return text if len(text) <= width else text[: width - 1] + "…"


def _rounded(value: Any) -> Any:
    if isinstance(value, float):
        return float(f"{value:.6g}")
    if isinstance(value, list):
        return [_rounded(v) for v in value]
    return value


__all__ = [
    "CHUNK",
    "CONNECT_TIMEOUT",
    "Column",
    "Compute",
    "FORMAT",
    "Progress",
    "Study",
    "check_options",
    "check_scheduler",
    "chunks",
    "read",
    "run",
]
