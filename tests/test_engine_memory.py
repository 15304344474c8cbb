"""The memory a computation may take: the machine's available memory and the sizes the refusals print."""

from __future__ import annotations

import io
import os

import pytest

from mobman.engine import memory
from mobman.engine.memory import available_memory, size
from mobman.errors import InputError


def test_available_memory_is_positive_and_at_most_the_physical_memory():
    available = available_memory()
    assert available is not None and 0 < available <= os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")


def test_available_memory_reads_mem_available_in_bytes(monkeypatch):
    meminfo = "MemTotal:       16000000 kB\nMemFree:         1000 kB\nMemAvailable:    2048 kB\n"
    monkeypatch.setattr(memory, "open", lambda *a, **k: io.StringIO(meminfo), raising=False)
    assert memory.available_memory() == 2048 * 1024


def test_available_memory_falls_back_to_the_free_pages(monkeypatch):
    def no_proc(*args, **kwargs):
        raise OSError("no /proc")

    monkeypatch.setattr(memory, "open", no_proc, raising=False)
    pages = {"SC_AVPHYS_PAGES": 1000, "SC_PAGE_SIZE": 4096}
    monkeypatch.setattr(os, "sysconf", lambda name: pages[name])
    assert memory.available_memory() == 4_096_000


def test_available_memory_is_none_when_nothing_tells(monkeypatch):
    monkeypatch.setattr(memory, "open", lambda *a, **k: io.StringIO("MemTotal: 1 kB\n"), raising=False)

    def no_sysconf(name):
        raise ValueError(name)

    monkeypatch.setattr(os, "sysconf", no_sysconf)
    assert memory.available_memory() is None


@pytest.mark.parametrize(
    "n, text",
    [(0, "0 B"), (1023, "1.02e+03 B"), (1536, "1.5 KiB"), (3 * 2**30, "3 GiB"), (2**70, "1.05e+06 PiB")],
)
def test_sizes_in_binary_units(n, text):
    assert size(n) == text


def test_a_batch_beyond_the_available_memory_names_its_largest_count(monkeypatch):
    from mobman.studies import options

    monkeypatch.setattr(options, "available_memory", lambda: 2**30)
    options.memory({"starts": 8, "chunk": 4096}, 2**30 // options.BYTES_PER_VALUE)  # exactly fits
    with pytest.raises(
        InputError, match=r"^chunk 4,097: with starts 8, .* about 1 GiB at once, more than the 1 GiB"
    ):
        options.memory({"starts": 8, "chunk": 4097}, 2**30 // options.BYTES_PER_VALUE + 1)
