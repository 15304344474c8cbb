"""Shared by the tests: no persistent compilation cache, for the browser tests the artifacts
folder and the robot-pixel mask of a screenshot, and the planning tests' fixtures (tests/planning_setting.py)."""

from __future__ import annotations

import io
import os
from pathlib import Path

import numpy as np
import pytest

from planning_setting import coarse, setting, z_test  # noqa: F401  (the planning tests' fixtures)

# No persistent compilation cache: each test worker and each command line or script it starts compiles its own
# programs. Storing programs had XLA serialize every executable, which now and then crashed a worker (a
# segmentation fault inside jax's compilation_cache.put_executable_and_time); the cache itself is tested with
# folders of its own (tests/test_compilation_cache.py).
os.environ["MOBMAN_CACHE_DIR"] = "off"
for _name in ("JAX_COMPILATION_CACHE_DIR", "JAX_COMPILATION_CACHE_MAX_SIZE"):
    os.environ.pop(_name, None)
# Command lines run in the tests' own processes trace their programs as a script does: the kept exports of
# mobman.engine.exported are tested on their own (tests/test_engine_exported.py, tests/test_compilation_cache.py).
os.environ.setdefault("MOBMAN_EXPORTED", "off")


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
