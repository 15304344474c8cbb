"""benchmarks/timing.py: the fp64 peak the benchmarks' rooflines divide by, from what ``lscpu`` reports."""

from __future__ import annotations

import os

import pytest
from benchmark_timing import timing

CORES = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count() or 1


@pytest.mark.parametrize(
    ("vendor", "family", "flags", "doubles"),
    [
        ("AuthenticAMD", "25", "fma avx2 avx512f", 4),  # Zen 4: 512-bit operations on 256-bit pipes
        ("AuthenticAMD", "25", "fma avx2", 4),  # Zen 3
        ("AuthenticAMD", "26", "fma avx2 avx512f", 8),  # Zen 5: 512-bit pipes
        ("GenuineIntel", "6", "fma avx2 avx512f", 8),  # Skylake-SP and later
        ("GenuineIntel", "6", "sse2", 2),
    ],
)
def test_peak_counts_doubles_per_fma_and_cycle(monkeypatch, vendor, family, flags, doubles):
    info = {"Vendor ID": vendor, "CPU family": family, "Flags": flags, "CPU max MHz": "2500.0"}
    monkeypatch.setattr(timing, "_lscpu", lambda: info)
    fma = 1 if "fma" not in flags else timing.FMA_UNITS
    peak, formula = timing.cpu_peak()
    assert peak == pytest.approx(CORES * 2.5 * fma * doubles * 2)
    assert f"{doubles} doubles" in formula
