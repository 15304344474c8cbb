"""mobman.io.output: files written atomically, results folders replaced as a whole, even when killed."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
from subprocesses import DUMP_ON_USR1, communicate_or_dump

from mobman.errors import InputError
from mobman.io.output import MARKER, check_folder, results_folder, write_text

SRC = Path(__file__).resolve().parents[1] / "src"
SIZE = 4_000_000

WRITER = (
    DUMP_ON_USR1
    + f"""
import sys
from mobman.io.output import write_text
print("ready", flush=True)
n = 0
while True:
    write_text(sys.argv[1], str(n % 10) * {SIZE})
    n += 1
"""
)


def _start(code: str, *args: str) -> subprocess.Popen:
    env = {**os.environ, "PYTHONPATH": str(SRC)}
    process = subprocess.Popen(
        [sys.executable, "-c", code, *args],
        env=env,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    assert process.stdout.readline().strip() in ("ready", "writing")
    return process


@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGKILL])
def test_a_file_killed_mid_write_is_the_old_or_the_new_one(tmp_path, sig):
    path = tmp_path / "results.json"
    write_text(path, "x" * SIZE)
    process = _start(WRITER, str(path))
    time.sleep(0.5)  # many rewrites of 4 MB: the signal lands in the middle of one
    process.send_signal(sig)
    communicate_or_dump(process)
    text = path.read_text()
    assert len(text) == SIZE and len(set(text)) == 1
    leftovers = [p.name for p in tmp_path.iterdir() if p.name != "results.json"]
    if sig == signal.SIGINT:  # the temporary file is removed on an interrupt
        assert leftovers == []


def test_results_folder_replaces_a_folder_of_the_same_command_only_when_complete(tmp_path):
    out = tmp_path / "run"
    with results_folder(out, "simulate") as staging:
        write_text(staging / "results.json", "old")
    assert (out / "results.json").read_text() == "old" and (out / MARKER).read_text().strip() == "simulate"
    with pytest.raises(RuntimeError), results_folder(out, "simulate") as staging:
        write_text(staging / "results.json", "new")
        raise RuntimeError("failed half-way")
    assert sorted(p.name for p in out.iterdir()) == [MARKER, "results.json"]
    assert (out / "results.json").read_text() == "old" and sorted(tmp_path.iterdir()) == [out]
    with results_folder(out, "simulate") as staging:
        write_text(staging / "report.md", "new")
    assert sorted(p.name for p in out.iterdir()) == [MARKER, "report.md"]
    with pytest.raises(InputError, match="results of mobman simulate, not plan"):
        check_folder(out, "plan")
