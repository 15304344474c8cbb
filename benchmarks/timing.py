"""Shared by the benchmark scripts (run as ``python benchmarks/NAME.py``, so this folder is on sys.path).

Besides the timer, two readings of XLA's compiled programs that the benchmarks print (they are properties of
the compiler's output, which change with the JAX version, so they are printed here, never asserted in tests):

- :func:`xla_cost`: the floating-point operations and the bytes read and written that XLA's own cost
  analysis counts for a compiled program (``jax.jit(f).lower(*args).compile().cost_analysis()``; a loop's
  body is counted once, a value recomputed in several fusions once per fusion), which :func:`roofline` sets
  against the machine's peak: a batched program whose kernels move much more memory than their
  operations need is bound by that traffic, not by its arithmetic;
- :func:`program_structure`: the kernels of a compiled program (fusions, library calls, products), the
  operations that cost XLA's CPU runtime most in small programs (gathers, constant arrays, LAPACK calls) and
  its largest array: XLA's CPU runtime runs an executor's kernels (the program's, each conditional
  branch's) one after the other on the calling thread only when every array they touch is at most 512 bytes
  (or there are at most 8 kernels); otherwise it schedules them over a thread pool, which costs a
  one-configuration program of tiny kernels several times their work. :func:`executor_arrays` reads the
  largest array of each executor (``tests/test_engine_batched.py`` uses it to check that TIAGo's
  one-configuration dynamics keep their branch under the limit).
"""

from __future__ import annotations

import argparse
import math
import os
import re
import subprocess
import time
from typing import Callable, NamedTuple

import jax

WARMUP_SECONDS = 1.0
"""Calls of a timed function before its timed calls run for this long (:data:`WARMUP_CALLS` at most)."""

WARMUP_CALLS = 20
"""Most calls of a timed function before its timed calls."""


def best_time(fn: Callable[[], object], repeat: int) -> float:
    """Best wall time in seconds of ``repeat`` calls of ``fn``, waiting for JAX's asynchronous results, after
    calls that warm it up for :data:`WARMUP_SECONDS` (at most :data:`WARMUP_CALLS` of them): the first calls
    of a process that writes large results run slower while the memory they write is touched for the first
    time (on a virtual machine, up to twice as long for the first second of 100,000 configurations' J̄), so
    every row is timed in the steady state of a process that has run it before."""
    start = time.perf_counter()
    for _ in range(WARMUP_CALLS):
        jax.block_until_ready(fn())
        if time.perf_counter() - start >= WARMUP_SECONDS:
            break
    best = math.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        jax.block_until_ready(fn())
        best = min(best, time.perf_counter() - t0)
    return best


def law_options(description: str, argv: list[str] | None) -> argparse.Namespace:
    """The options of a control-law benchmark against a per-step peer (whole_body_qp.py, avoidance.py):
    ``--configurations`` (law evaluations timed per call), ``--batch`` (runs simulated in one call) and
    ``--smoke`` (tiny sizes, for CI)."""
    parser = argparse.ArgumentParser(description=description)
    parser.add_argument("--configurations", type=int, default=64, help="law evaluations timed per call")
    parser.add_argument("--batch", type=int, default=64, help="runs of the spec simulated in one call")
    parser.add_argument("--smoke", action="store_true", help="tiny sizes for CI")
    args = parser.parse_args(argv)
    if args.smoke:
        args.configurations, args.batch = 4, 2
    return args


def one_per_call(evaluate: Callable, *columns) -> tuple[object, float]:
    """``evaluate`` (compiled) on each row of ``columns``, one call per row, each result waited for: the
    results stacked (NumPy) and the best time per call over three rounds (the latency a controller sees)."""
    import numpy as np

    rows = list(zip(*columns))
    results = np.stack([np.asarray(evaluate(*row)) for row in rows])

    def calls() -> None:
        for row in rows:
            jax.block_until_ready(evaluate(*row))

    return results, best_time(calls, 3) / len(rows)


def compiled_text(fn: Callable, *args) -> str:
    """The optimised HLO of ``jax.jit(fn)`` at ``args``, from its entry computation on."""
    text = jax.jit(fn).lower(*args).compile().as_text()
    return text[text.index("ENTRY") :]


class Cost(NamedTuple):
    """XLA's count for one call of a compiled program."""

    flops: float
    bytes: float
    """Bytes its kernels read and write (every intermediate array that is not fused away, read and written)."""

    def scaled(self, factor: float) -> "Cost":
        """The count of ``factor`` calls (a fraction: per item of a batched call)."""
        return Cost(factor * self.flops, factor * self.bytes)

    def per(self, items: int) -> "Cost":
        """The count per item of a call over ``items`` items."""
        return self.scaled(1.0 / items)


def xla_cost(fn: Callable, *args) -> Cost:
    """Floating-point operations and bytes accessed of one call of ``jax.jit(fn)`` at ``args``, by XLA's cost
    analysis."""
    analysis = jax.jit(fn).lower(*args).compile().cost_analysis()
    if isinstance(analysis, (list, tuple)):  # older jaxlib: one dict per program
        analysis = analysis[0]
    return Cost(float(analysis.get("flops", 0.0)), float(analysis.get("bytes accessed", 0.0)))


def program_structure(fn: Callable, *args) -> dict[str, int]:
    """Counts in the compiled program of ``fn`` at ``args``: kernels (fusions, library calls and products of
    the entry computation and of the conditional branches that compute, :func:`_executors`), gathers and
    scatters, constant arrays (not scalars), LAPACK / cuSOLVER calls, XLA's YNN library fusions (small
    reductions handed to a library built for large ones), and the largest array of the entry computation and,
    where there are conditionals, of their computing branches."""
    full = jax.jit(fn).lower(*args).compile().as_text()
    entry, *branches = _executors(full)
    both = [entry, *branches]
    counts = {
        "kernels": sum(len(_KERNEL.findall(text)) for text in both),
        "gathers/scatters": len(re.findall(r"\b(?:gather|scatter)\(", full)),
        "constant arrays": sum(len([c for c in _CONSTANT.findall(text) if c]) for text in both),
        "solver calls": len(re.findall(r'custom_call_target="(?:lapack|cusolver|hipsolver)', full)),
        "YNN fusions": full.count("__ynn_fusion"),
        "largest array (bytes)": max(_array_bytes(entry), default=0),
    }
    if branches:
        counts["largest array of a branch (bytes)"] = max(max(_array_bytes(b), default=0) for b in branches)
    return counts


_KERNEL = re.compile(r"= \S+ (?:fusion|custom-call|dot)\(")
_CONSTANT = re.compile(r"= \w+\[([\d,]*)\]\S* constant\(")


def _computations(text: str) -> dict[str, str]:
    """The computations of a compiled program's HLO ``text`` by name, the entry's under ``"ENTRY"``."""
    out: dict[str, str] = {}
    for block in re.split(r"\n(?=(?:ENTRY )?%\S+ .*\{\n)", text):
        head = re.match(r"(ENTRY )?%(\S+) ", block)
        if head:
            out["ENTRY" if head.group(1) else head.group(2)] = block
    return out


def _executors(text: str) -> list[str]:
    """The computations XLA's CPU runtime runs as executors of their own: the entry computation, then of each
    of its conditionals the branch with the most kernels (the one that computes)."""
    computations = _computations(text)
    entry = computations["ENTRY"]
    branches = []
    for names in re.findall(r"branch_computations=\{([^}]*)\}", entry):
        bodies = [computations[name.strip().lstrip("%")] for name in names.split(",")]
        branches.append(max(bodies, key=lambda body: len(_KERNEL.findall(body))))
    return [entry, *branches]


def executor_arrays(text: str) -> dict[str, int]:
    """The largest array (bytes) of each executor of a compiled program's HLO ``text`` (:func:`_executors`:
    the entry computation, then the computing branch of each conditional), in that order; a fusion's inner
    values are not arrays of the program."""
    return {f"executor {k}": max(_array_bytes(body), default=0) for k, body in enumerate(_executors(text))}


_BYTES = {
    "f64": 8,
    "s64": 8,
    "u64": 8,
    "c64": 8,
    "f32": 4,
    "s32": 4,
    "u32": 4,
    "f16": 2,
    "pred": 1,
    "s8": 1,
    "u8": 1,
}


def _array_bytes(entry: str) -> list[int]:
    """Sizes of the arrays the entry computation's instructions produce (tuple elements included)."""
    return [
        _BYTES.get(dtype, 8) * math.prod(int(d) for d in dims.split(",") if d)
        for dtype, dims in re.findall(r"\b(f64|s64|u64|c64|f32|s32|u32|f16|pred|s8|u8)\[([\d,]*)\]", entry)
    ]


def describe_structure(label: str, counts: dict[str, int]) -> str:
    return f"{label}: " + ", ".join(f"{name} {value}" for name, value in counts.items())


def _lscpu() -> dict[str, str]:
    try:
        out = subprocess.run(["lscpu"], capture_output=True, text=True, check=True).stdout
    except (OSError, subprocess.CalledProcessError):
        return {}
    return {k.strip(): v.strip() for k, v in (line.split(":", 1) for line in out.splitlines() if ":" in line)}


FMA_UNITS = 2
"""Vector FMA pipes per core assumed in the peak (two on current x86 server cores: Zen 2–4, Skylake-SP on)."""


def cpu_peak() -> tuple[float, str]:
    """Peak fp64 GFLOP/s of the cores this process may use and the formula, from ``lscpu``:
    cores × GHz × FMA units × doubles per FMA and cycle × 2 (an FMA is two operations)."""
    info = _lscpu()
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count() or 1
    mhz = info.get("CPU max MHz") or info.get("CPU MHz")
    if mhz is None:
        try:
            with open("/proc/cpuinfo") as f:
                mhz = next(line.split(":")[1] for line in f if line.startswith("cpu MHz"))
        except (OSError, StopIteration):
            mhz = "0"
    ghz = float(mhz) / 1000.0
    flags = info.get("Flags", "").split()
    width = 8 if "avx512f" in flags else 4 if "avx2" in flags or "avx" in flags else 2
    if width == 8 and info.get("Vendor ID") == "AuthenticAMD" and info.get("CPU family") == "25":
        width = 4  # Zen 4 runs a 512-bit operation as two halves on its 256-bit FMA pipes
    fma = FMA_UNITS if "fma" in flags or width == 8 else 1
    peak = cores * ghz * fma * width * 2
    model = info.get("Model name", "CPU")
    formula = f"{cores} cores × {ghz:.2f} GHz × {fma} FMA units × {width} doubles × 2 = {peak:.1f} GFLOP/s"
    return peak, f"{model}: {formula}"


def roofline(label: str, cost_per_item: Cost, seconds_per_item: float) -> str:
    """One line: XLA's flop count per item, the achieved fp64 GFLOP/s and, on a CPU, the share of its peak;
    the bytes its kernels move per item and the memory traffic that makes."""
    achieved = cost_per_item.flops / seconds_per_item / 1e9
    line = f"{label}: {cost_per_item.flops:,.0f} flops each (XLA), {achieved:.2f} GFLOP/s"
    if jax.default_backend() == "cpu":
        peak, _ = cpu_peak()
        line += f" = {100 * achieved / peak:.1f} % of the {peak:.0f} GFLOP/s peak"
    traffic = cost_per_item.bytes / seconds_per_item / 1e9
    return line + f"; {cost_per_item.bytes / 1e3:,.1f} kB moved each, {traffic:.1f} GB/s"


def print_peak() -> None:
    if jax.default_backend() == "cpu":
        print(f"fp64 peak: {cpu_peak()[1]}")
