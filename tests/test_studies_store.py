"""mobman.studies.store: chunked studies kept in a Zarr store, resumed after a stop, refused for another
definition, and computed on a local Dask cluster to the same values."""

from __future__ import annotations

import json
from functools import partial

import numpy as np
import pytest
import zarr

from mobman.errors import InputError
from mobman.studies import store

COLUMNS = {
    "value": store.Column(),
    "vector": store.Column((3,)),
    "flag": store.Column((), "bool", False),
}
DEFINITION = {"study": "test", "scale": 2.0, "tuple": (1, 2)}


def rows(start: int, stop: int, scale: float = 2.0) -> dict[str, np.ndarray]:
    """A study whose row r is (scale r, (r, r², r³), r odd): a module-level function, so Dask can ship it."""
    r = np.arange(start, stop, dtype=float)
    return {"value": scale * r, "vector": np.stack([r, r**2, r**3], axis=-1), "flag": r % 2 == 1}


def expected(n: int) -> dict[str, np.ndarray]:
    return rows(0, n)


def check(study: store.Study, n: int) -> None:
    assert study.complete and study.done.shape == (n,)
    for name, values in expected(n).items():
        np.testing.assert_array_equal(study.columns[name], values)


class Recorder:
    """``rows`` that records the chunks it computes and can fail at one of them."""

    def __init__(self, fail_at: int | None = None):
        self.calls: list[int] = []
        self.fail_at = fail_at

    def __call__(self, start: int, stop: int) -> dict[str, np.ndarray]:
        if start == self.fail_at:
            raise KeyboardInterrupt  # a stop in the middle: Ctrl-C, a machine lost
        self.calls.append(start)
        return rows(start, stop)


def test_in_memory_and_in_a_store_give_the_rows_and_report_progress(tmp_path):
    seen = []
    memory = store.run(rows, 10, COLUMNS, DEFINITION, chunk=3, progress=lambda d, t: seen.append((d, t)))
    check(memory, 10)
    assert seen == [(0, 4), (1, 4), (2, 4), (3, 4), (4, 4)]
    kept = store.run(rows, 10, COLUMNS, DEFINITION, store=tmp_path / "s.zarr", chunk=3)
    check(kept, 10)
    check(store.read(tmp_path / "s.zarr"), 10)
    group = zarr.open_group(str(tmp_path / "s.zarr"), mode="r")
    assert group["value"].chunks == (3,) and group["done"].shape == (4,)
    meta = group.attrs["mobman"]
    assert meta["definition"] == json.loads(json.dumps(DEFINITION)) and meta["rows"] == 10


def test_a_stopped_study_keeps_its_chunks_and_resumes_with_the_rest(tmp_path):
    path = tmp_path / "s.zarr"
    first = Recorder(fail_at=6)
    with pytest.raises(KeyboardInterrupt):
        store.run(first, 10, COLUMNS, DEFINITION, store=path, chunk=3)
    assert first.calls == [0, 3]
    partial_study = store.read(path)
    assert list(partial_study.done) == [True] * 6 + [False] * 4
    assert np.isnan(partial_study.columns["value"][6:]).all()  # not computed: the fill value
    second = Recorder()
    check(store.run(second, 10, COLUMNS, DEFINITION, store=path), 10)  # the store's chunk of 3 is kept
    assert second.calls == [6, 9]
    third = Recorder()
    check(store.run(third, 10, COLUMNS, DEFINITION, store=path), 10)
    assert third.calls == []


def test_a_chunk_written_but_not_flagged_is_computed_again(tmp_path):
    path = tmp_path / "s.zarr"
    store.run(rows, 10, COLUMNS, DEFINITION, store=path, chunk=5)
    group = zarr.open_group(str(path), mode="r+")
    group["value"][5:] = -1.0  # a run that stopped between a chunk's results and its flag
    group["done"][1] = False
    check(store.run(rows, 10, COLUMNS, DEFINITION, store=path), 10)


@pytest.mark.parametrize(
    ("change", "message"),
    [
        ({"definition": {**DEFINITION, "scale": 3.0}}, "scale: 3.0 asked, 2.0 in the store"),
        ({"rows": 12}, "rows: 12 asked, 10 in the store"),
        ({"chunk": 4}, "chunk: 4 asked, 5 in the store"),
        ({"columns": {"value": store.Column()}}, "columns"),
    ],
)
def test_a_store_of_another_study_is_refused_naming_the_field(tmp_path, change, message):
    path = tmp_path / "s.zarr"
    store.run(rows, 10, COLUMNS, DEFINITION, store=path, chunk=5)
    args = {"rows": 10, "columns": COLUMNS, "definition": DEFINITION, "chunk": None} | change
    with pytest.raises(InputError, match="holds another study") as info:
        store.run(rows, args["rows"], args["columns"], args["definition"], store=path, chunk=args["chunk"])
    assert message in str(info.value)
    check(store.read(path), 10)  # untouched


def test_paths_that_are_no_study_are_refused(tmp_path):
    (tmp_path / "file").write_text("x")
    (tmp_path / "folder").mkdir()
    for path in (tmp_path / "file", tmp_path / "folder"):
        with pytest.raises(InputError, match="is not a mobman study"):
            store.run(rows, 4, COLUMNS, DEFINITION, store=path)
    with pytest.raises(InputError, match="does not exist"):
        store.run(rows, 4, COLUMNS, DEFINITION, store=tmp_path / "missing" / "s.zarr")
    with pytest.raises(InputError, match="no such study"):
        store.read(tmp_path / "nothing.zarr")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["file", "folder"]  # no partial store left


@pytest.mark.parametrize("chunk", [0, -1, 2.5, "3"])
def test_a_bad_chunk_is_one_error(chunk):
    with pytest.raises(InputError, match="chunk must be an integer ≥ 1"):
        store.run(rows, 4, COLUMNS, DEFINITION, chunk=chunk)


@pytest.mark.parametrize(
    ("scheduler", "message"),
    [("lokal", "scheduler must be 'local'"), ("local:0", "local:N"), ("local:x", "local:N")],
)
def test_a_bad_scheduler_is_one_error(scheduler, message):
    with pytest.raises(InputError, match=message):
        store.run(rows, 4, COLUMNS, DEFINITION, scheduler=scheduler)


def test_an_unreachable_scheduler_is_one_error(monkeypatch):
    monkeypatch.setattr(store, "CONNECT_TIMEOUT", 1.0)
    with pytest.raises(InputError, match="cannot connect"):
        store.run(rows, 4, COLUMNS, DEFINITION, scheduler="tcp://127.0.0.1:9")


def test_a_local_dask_cluster_computes_the_same_study_into_the_store(tmp_path, monkeypatch):
    """… on a cluster listening on the loopback address only (Dask's protocol unpickles what it is sent)."""
    import distributed

    addresses = []

    class Recorded(distributed.LocalCluster):
        def close(self, *args, **kwargs):
            addresses.extend([self.scheduler_address, *(w.address for w in self.workers.values())])
            return super().close(*args, **kwargs)

    monkeypatch.setattr(distributed, "LocalCluster", Recorded)
    path = tmp_path / "s.zarr"
    compute = partial(rows, scale=2.0)
    first = Recorder(fail_at=4)
    with pytest.raises(KeyboardInterrupt):
        store.run(first, 10, COLUMNS, DEFINITION, store=path, chunk=2)
    seen = []
    study = store.run(
        compute,
        10,
        COLUMNS,
        DEFINITION,
        store=path,
        scheduler="local:2",
        progress=lambda d, t: seen.append(d),
    )
    check(study, 10)
    assert seen == [2, 3, 4, 5]  # the two chunks kept, then the three computed on the cluster
    assert len(addresses) == 3 and all(a.startswith("tcp://127.0.0.1:") for a in addresses), addresses
