"""How long a one-configuration command takes from the shell: ``mobman analyze``, ``ellipsoid`` and
``distance`` on TIAGo, each run as a new process, import included.

    python benchmarks/cli_latency.py            # three runs of each, warm and cold
    python benchmarks/cli_latency.py --smoke    # one run of analyze on a paper robot (CI)

Rows, per command:

- *cold*: a new, empty cache folder (``MOBMAN_CACHE_DIR``): every program is traced, compiled and kept, and
  the URDF is read and kept;
- *warm*: the folder the cold run filled (the best of the runs): the programs are read back from their kept
  exports (:mod:`mobman.engine.exported`) and compiled programs, the robot from its kept reading
  (:mod:`mobman.io.urdf_cache`);
- *warm, compiled programs only* (the reference): the same folder, with the kept exports and URDF readings
  turned off, as the command ran before they were kept: every program is traced again and only its
  compilation is read back.

Then the time to import the command (``import mobman.cli``), which every run pays. The ratio printed is the
reference's time over the warm time.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

TIAGO_Q = "0,0,0,0.15,0.5,0.3,-1.2,1.5,0.3,0.5,0"
SCENE = Path(__file__).resolve().parents[1] / "docs" / "examples" / "tiago_scene.toml"
COMMANDS = {
    "analyze": ["analyze", "tiago"],
    "ellipsoid": ["ellipsoid", "tiago", "--q", TIAGO_Q],
    "distance": ["distance", "tiago", "--q", TIAGO_Q, "--scene", str(SCENE)],
}
SMOKE = {"analyze": ["analyze", "bayle-planar", "--q", "0,0,0,0.3,1.2"]}

FULL = "from mobman.cli import main; import sys; main(sys.argv[1:])"
COMPILED_ONLY = (
    "from mobman.engine import exported; from mobman.io import urdf_cache; "
    "exported.enable = urdf_cache.enable = lambda folder: None; "
    "from mobman.cli import main; import sys; main(sys.argv[1:])"
)


def wall(code: str, args: list[str], folder: Path) -> float:
    """Wall time (s) of ``python -c code args`` with the cache in ``folder``; its failure is fatal."""
    env = {**os.environ, "MOBMAN_CACHE_DIR": str(folder)}
    env.pop("JAX_COMPILATION_CACHE_DIR", None)
    start = time.perf_counter()
    run = subprocess.run([sys.executable, "-c", code, *args], env=env, capture_output=True, text=True)
    elapsed = time.perf_counter() - start
    if run.returncode != 0:
        raise SystemExit(f"mobman {' '.join(args)} failed ({run.returncode}): {run.stderr.strip()[-500:]}")
    return elapsed


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--smoke", action="store_true", help="one run of analyze on a paper robot (CI)")
    parser.add_argument("--repeat", type=int, default=3, help="warm runs per row (the best is printed)")
    args = parser.parse_args()
    commands, repeat = (SMOKE, 1) if args.smoke else (COMMANDS, args.repeat)
    with tempfile.TemporaryDirectory() as tmp:
        root = Path(tmp)
        start = time.perf_counter()
        subprocess.run([sys.executable, "-c", "import mobman.cli"], check=True)
        imported = time.perf_counter() - start
        print(f"{'command':<12} {'cold s':>8} {'warm s':>8} {'compiled only s':>16} {'ratio':>6}")
        for name, words in commands.items():
            folder = root / name
            cold = wall(FULL, words, folder)
            warm = min(wall(FULL, words, folder) for _ in range(repeat))
            reference = min(wall(COMPILED_ONLY, words, folder) for _ in range(repeat))
            print(f"{name:<12} {cold:8.2f} {warm:8.2f} {reference:16.2f} {reference / warm:5.1f}×")
        print(f"import mobman.cli: {imported:.2f} s (in every run)")


if __name__ == "__main__":
    main()
