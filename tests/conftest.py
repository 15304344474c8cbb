"""Shared by the tests: one persistent XLA compilation cache for the run, a bound on the programs a worker
keeps, for the browser tests the artifacts folder and the robot-pixel mask of a screenshot, and the planning
tests' fixtures (tests/planning_setting.py)."""

from __future__ import annotations

import gc
import io
import os
import tempfile
from pathlib import Path

import jax
import numpy as np
import pytest

from planning_setting import coarse, setting, z_test  # noqa: F401  (the planning tests' fixtures)

# One persistent XLA compilation cache for the whole run, shared by the test workers and the subprocesses they
# start (examples, command lines): a program compiled once (the same robot's kinematics in many tests) is read
# back instead of compiled again. It only stores compiled programs; every test still computes its values.
_CACHE = Path(os.environ.get("MOBMAN_TEST_JAX_CACHE", Path(tempfile.gettempdir()) / "mobman-test-jax-cache"))
os.environ.setdefault("JAX_COMPILATION_CACHE_DIR", str(_CACHE))
os.environ.setdefault("JAX_PERSISTENT_CACHE_MIN_COMPILE_TIME_SECS", "0.2")
# A size bound turns JAX's file lock on: without it a worker could read a program another worker is still
# writing (JAX writes the file in place).
os.environ.setdefault("JAX_COMPILATION_CACHE_MAX_SIZE", str(4 * 2**30))
# Command lines run in the tests' own processes trace their programs as a script does: the kept exports of
# mobman.engine.exported are tested on their own (tests/test_engine_exported.py, tests/test_compilation_cache.py).
os.environ.setdefault("MOBMAN_EXPORTED", "off")
jax.config.update("jax_compilation_cache_dir", os.environ["JAX_COMPILATION_CACHE_DIR"])
jax.config.update("jax_compilation_cache_max_size", int(os.environ["JAX_COMPILATION_CACHE_MAX_SIZE"]))
jax.config.update(
    "jax_persistent_cache_min_compile_time_secs",
    float(os.environ["JAX_PERSISTENT_CACHE_MIN_COMPILE_TIME_SECS"]),
)


def _memory_mappings() -> tuple[int, int] | None:
    """(this process's memory mappings, the kernel's limit vm.max_map_count), or None off Linux."""
    try:
        with open("/proc/self/maps", "rb") as maps:
            count = sum(1 for _ in maps)
        return count, int(Path("/proc/sys/vm/max_map_count").read_text())
    except OSError:
        return None


@pytest.fixture(autouse=True, scope="module")
def _bounded_compiled_programs():
    """A test worker keeps every program it compiles, and each XLA CPU executable maps memory of its own: past
    the kernel's limit on a process's mappings (vm.max_map_count, 65,530 by default) the next compilation
    aborts the worker. Before a module, a worker holding more than half that many mappings drops its compiled
    programs (those still needed are compiled again)."""
    mappings = _memory_mappings()
    if mappings is not None and mappings[0] > mappings[1] // 2:
        jax.clear_caches()
        gc.collect()
    yield


@pytest.fixture(scope="session")
def artifacts(tmp_path_factory) -> Path:
    """``$MOBMAN_ARTIFACTS`` (kept by CI) or a temporary folder, for the screenshots."""
    folder = os.environ.get("MOBMAN_ARTIFACTS")
    path = Path(folder) if folder else tmp_path_factory.mktemp("artifacts")
    path.mkdir(parents=True, exist_ok=True)
    return path


def _robot_pixels(png: bytes) -> np.ndarray:
    from PIL import Image

    rgb = np.asarray(Image.open(io.BytesIO(png)).convert("RGB"), dtype=float)
    r, g, b = rgb[..., 0], rgb[..., 1], rgb[..., 2]
    return (r > 90) & (r - b > 0.5 * r) & (g > 0.3 * r) & (g < 0.8 * r)


@pytest.fixture(scope="session")
def robot_pixels():
    """PNG bytes → mask of the generated links' orange (255, 140, 26) under any shading: red well above blue,
    green in between (the axes' red, the paths' green and the ellipsoid's blue stay out)."""
    return _robot_pixels


@pytest.fixture
def cli_run(capsys):
    """``cli_run(args)``: run ``mobman ARGS`` in-process and return (exit status, stdout, stderr)."""
    from cli_runs import run_cli

    return lambda args: run_cli(args, capsys)


@pytest.fixture
def cli_json(capsys):
    """``cli_json(args)``: run ``mobman ARGS --json`` in-process, assert exit 0 (stderr as the message) and return
    the printed JSON."""
    import json

    from mobman.cli import main

    def run(args: list[str]) -> dict:
        try:
            main([*args, "--json"])
            code = 0
        except SystemExit as exc:
            code = exc.code
        captured = capsys.readouterr()
        assert code == 0, captured.err
        return json.loads(captured.out)

    return run
