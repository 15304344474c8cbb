"""benchmarks/timing.py: the warm-up before the timed calls, the fp64 peak the benchmarks' rooflines divide by,
from what ``lscpu`` reports, and XLA's count of flops and bytes they print."""

from __future__ import annotations

import os

import jax.numpy as jnp
import pytest
from benchmark_timing import timing

CORES = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count() or 1


def test_best_time_warms_up_before_its_timed_calls(monkeypatch):
    calls = []
    assert timing.best_time(lambda: calls.append(1), 3) >= 0.0
    assert len(calls) == timing.WARMUP_CALLS + 3  # fast calls: the most warm-up calls, then the timed ones
    monkeypatch.setattr(timing, "WARMUP_SECONDS", 0.0)
    calls.clear()
    timing.best_time(lambda: calls.append(1), 3)
    assert len(calls) == 1 + 3  # no warm-up time asked: one call all the same (it compiles)


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


def test_cost_of_a_fused_elementwise_program_is_its_operations_and_one_read_and_write():
    """x ↦ 2x + 1 over n doubles, fused into one loop: 2 operations per element, 8 bytes read and 8 written."""
    n = 1000
    cost = timing.xla_cost(lambda x: x * 2.0 + 1.0, jnp.ones(n))
    assert cost == timing.Cost(flops=2.0 * n, bytes=16.0 * n)
    assert cost.per(n) == timing.Cost(2.0, 16.0)
    line = timing.roofline("2x + 1", cost.per(n), 1e-9)  # one element a nanosecond
    assert "2 flops each (XLA), 2.00 GFLOP/s" in line and "16.0 GB/s" in line
