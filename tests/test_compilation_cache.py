"""The persistent compilation cache (mobman.engine.compilation_cache): which folder it takes, that a second
process reads its programs back, that it can be turned off, and that an unusable folder is one line (an error
in Python, a warning on the command line, which still runs).

Each case runs in a child process: JAX opens its cache once per process, and the test session has its own
(tests/conftest.py)."""

from __future__ import annotations

import json
import os
import stat
import subprocess
import sys
from pathlib import Path

import pytest

from mobman.engine import compilation_cache
from mobman.errors import InputError

# enable, then compile and run one program (kept whatever its compile time: the variable JAX reads wins)
CHILD = """
import jax, jax.numpy as jnp, numpy as np
import mobman
from mobman.engine import compilation_cache
print(compilation_cache.enable())
jax.jit(lambda x: jnp.sin(x) @ jnp.cos(x).T)(np.ones((40, 40))).block_until_ready()
"""


def _environment(tmp_path: Path, **extra: str) -> dict[str, str]:
    env = {
        k: v
        for k, v in os.environ.items()
        if k
        not in (
            "JAX_COMPILATION_CACHE_DIR",
            "JAX_COMPILATION_CACHE_MAX_SIZE",  # the tests' own bound (conftest)
            compilation_cache.ENVIRONMENT,
            "XDG_CACHE_HOME",
        )
    }
    env["XDG_CACHE_HOME"] = str(tmp_path / "xdg")
    env["JAX_PERSISTENT_CACHE_MIN_COMPILE_TIME_SECS"] = "0"
    return env | extra


def _child(env: dict[str, str]) -> str:
    out = subprocess.run([sys.executable, "-c", CHILD], env=env, capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr[-3000:]
    return out.stdout.strip().splitlines()[-1]


def _entries(folder: Path) -> dict[str, bytes]:
    """Each stored program's name and its last-read stamp (JAX rewrites the stamp at every read)."""
    return {
        p.name: p.with_name(p.name.replace("-cache", "-atime")).read_bytes() for p in folder.glob("*-cache")
    }


def test_the_default_folder_is_the_user_cache_and_a_second_process_reads_the_program_back(tmp_path):
    env = _environment(tmp_path)
    folder = tmp_path / "xdg" / "mobman" / "xla"
    assert _child(env) == str(folder)
    assert stat.S_IMODE(folder.stat().st_mode) == 0o700
    first = _entries(folder)
    assert len(first) == 1
    assert _child(env) == str(folder)
    second = _entries(folder)
    assert second.keys() == first.keys()  # read back, not compiled and stored again
    assert all(second[k] != first[k] for k in first)  # and read: its stamp moved


def test_mobman_cache_dir_names_the_folder(tmp_path):
    folder = tmp_path / "mine"
    assert _child(_environment(tmp_path, MOBMAN_CACHE_DIR=str(folder))) == str(folder)
    assert len(_entries(folder)) == 1
    assert not (tmp_path / "xdg").exists()


@pytest.mark.parametrize("value", ["", "off", " OFF "])
def test_an_empty_or_off_mobman_cache_dir_turns_the_cache_off(tmp_path, value):
    assert _child(_environment(tmp_path, MOBMAN_CACHE_DIR=value)) == "None"
    assert not (tmp_path / "xdg").exists()


def test_a_folder_jax_is_configured_with_is_kept(tmp_path):
    folder = tmp_path / "jax's"
    env = _environment(tmp_path, JAX_COMPILATION_CACHE_DIR=str(folder), MOBMAN_CACHE_DIR=str(tmp_path / "no"))
    assert _child(env) == str(folder)
    assert len(list(folder.glob("*-cache"))) == 1
    assert not list(folder.glob("*-atime"))  # JAX's own settings: no size limit, so no read stamps
    assert not (tmp_path / "no").exists() and not (tmp_path / "xdg").exists()


def test_an_unusable_folder_is_one_error_naming_it(tmp_path):
    blocker = tmp_path / "a file"
    blocker.write_text("")
    with pytest.raises(InputError, match=r"compilation cache folder .*a file/xla: .*MOBMAN_CACHE_DIR"):
        compilation_cache.enable(blocker / "xla")
    with pytest.raises(InputError, match="a file: File exists"):
        compilation_cache.enable(blocker)


def test_the_command_warns_of_an_unusable_folder_in_one_line_and_still_runs(tmp_path):
    blocker = tmp_path / "a file"
    blocker.write_text("")
    env = _environment(tmp_path, MOBMAN_CACHE_DIR=str(blocker / "xla"))
    code = "from mobman.cli import main; main(['analyze', 'bayle-planar', '--q', '0,0,0,0.3,1.2', '--json'])"
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=180)
    assert out.returncode == 0, out.stderr[-3000:]
    assert out.stderr.strip().splitlines() == [
        f"warning: compilation cache folder {blocker / 'xla'}: Not a directory; set MOBMAN_CACHE_DIR to a "
        "writable folder, or to the empty string to turn the cache off"
    ]
    assert json.loads(out.stdout)["robot"] == "bayle-planar"


def test_the_command_keeps_its_programs_in_the_default_folder(tmp_path):
    env = _environment(tmp_path)
    code = "from mobman.cli import main; main(['analyze', 'bayle-planar', '--q', '0,0,0,0.3,1.2', '--json'])"
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=180)
    assert out.returncode == 0, out.stderr[-3000:]
    assert _entries(tmp_path / "xdg" / "mobman" / "xla")


def test_the_command_keeps_exported_programs_unless_told_not_to(tmp_path):
    """A command keeps its traced programs as exports beside the compilations and a later one reads them back
    with the same output; MOBMAN_EXPORTED=off keeps none."""
    code = (
        "from mobman.cli import main; main(['analyze', 'bayle-planar', '--q', '0,0,pi/2,0.3,1.2', '--json'])"
    )

    def run(**extra: str) -> str:
        env = {k: v for k, v in _environment(tmp_path).items() if k != "MOBMAN_EXPORTED"} | extra
        out = subprocess.run(
            [sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=180
        )
        assert out.returncode == 0, out.stderr[-3000:]
        return out.stdout

    first = run(MOBMAN_CACHE_DIR=str(tmp_path / "kept"))
    kept = sorted((tmp_path / "kept" / "exported").glob("*.exported"))
    assert kept
    assert run(MOBMAN_CACHE_DIR=str(tmp_path / "kept")) == first
    assert sorted((tmp_path / "kept" / "exported").glob("*.exported")) == kept
    assert run(MOBMAN_CACHE_DIR=str(tmp_path / "off"), MOBMAN_EXPORTED="off") == first
    assert not list((tmp_path / "off").rglob("*.exported"))
