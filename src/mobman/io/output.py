"""Writing results without losing anything: every file atomically, every results folder as a whole.

A file is written to a temporary file in the same folder and renamed over its name (``os.replace``), so a run
stopped at any moment leaves the old file or the new one, never a part. A results folder (``--out``) is built
in a temporary sibling and renamed into place at the end, so an interrupted run never mixes new figures with
an old ``results.json``; the sibling is removed when the run fails or is interrupted.

A results folder carries a marker file naming the command that wrote it. ``--out`` may name a new folder,
an empty one, or one that the same command wrote before (it is replaced); anything else (a file, a folder
that cannot be written, a non-empty folder written by something else) is refused before any work, with
nothing touched.
"""

from __future__ import annotations

import contextlib
import os
import secrets
import shutil
import tempfile
from collections.abc import Iterator
from pathlib import Path
from typing import Any

from mobman.errors import InputError

MARKER = ".mobman-results"
"""Name of the marker file in a results folder; its text is the command that wrote the folder."""


def _permissions(path: Path, mode: int) -> None:
    """Give a temporary file (0600) or folder (0700) the permissions an ordinary one gets (``mode`` & ~umask)."""
    umask = os.umask(0)
    os.umask(umask)
    os.chmod(path, mode & ~umask)


@contextlib.contextmanager
def atomic_path(path: Path | str) -> Iterator[Path]:
    """A temporary path in ``path``'s folder to write to; renamed to ``path`` when the block succeeds, removed
    when it fails or is interrupted."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    # the name is chosen before the file is created (O_EXCL), so an interrupt landing just after its creation
    # (inside tempfile.mkstemp it would leave the file behind, unnamed) is caught below and the file removed
    while True:
        temporary = path.parent / f".{path.name}.{secrets.token_hex(8)}.partial"
        try:
            os.close(os.open(temporary, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600))
        except FileExistsError:
            continue  # another writer's name: never removed
        except BaseException:
            temporary.unlink(missing_ok=True)
            raise
        break
    try:
        yield temporary
        _permissions(temporary, 0o666)
        os.replace(temporary, path)
    except BaseException:
        temporary.unlink(missing_ok=True)
        raise


def write_text(path: Path | str, text: str) -> Path:
    """Write ``text`` (UTF-8) to ``path`` atomically."""
    with atomic_path(path) as temporary:
        with open(temporary, "w", encoding="utf-8") as handle:
            handle.write(text)
            handle.flush()
            os.fsync(handle.fileno())
    return Path(path)


def save_figure(fig: Any, path: Path | str, **kwargs: Any) -> Path:
    """``fig.savefig(path, **kwargs)`` atomically (the format follows ``path``'s suffix, PNG by default)."""
    path = Path(path)
    kwargs.setdefault("format", path.suffix.lstrip(".") or "png")
    with atomic_path(path) as temporary:
        fig.savefig(temporary, **kwargs)
    return path


def _owner(folder: Path) -> str | None:
    try:
        return (folder / MARKER).read_text(encoding="utf-8").strip()
    except (OSError, UnicodeDecodeError):
        return None


def check_folder(out: Path | str, command: str, field: str = "--out") -> Path:
    """Refuse (InputError) an output folder ``out`` that ``command`` may not write; see the module docstring."""
    out = Path(out)
    if Path(os.path.abspath(out)) in (Path.cwd(), *Path.cwd().parents):
        raise InputError(
            f"{field} {out}: the current folder or one above it; name a results folder inside it"
        )
    if out.exists() and not out.is_dir():
        raise InputError(f"{field} {out}: exists and is not a folder; choose a new or empty folder")
    if out.is_dir() and any(out.iterdir()):
        owner = _owner(out)
        if owner is None:
            raise InputError(
                f"{field} {out}: folder is not empty and was not written by mobman {command}; "
                "choose a new or empty folder"
            )
        if owner != command:
            raise InputError(
                f"{field} {out}: holds the results of mobman {owner}, not {command}; choose another folder"
            )
    parent = out.parent
    while not parent.exists():
        parent = parent.parent
    if not parent.is_dir():
        raise InputError(f"{field} {out}: {parent} is not a folder")
    try:  # the results are written into a sibling of ``out``: probe that folder, leaving nothing behind
        os.rmdir(tempfile.mkdtemp(dir=parent, prefix=".mobman-probe-"))
    except OSError as exc:
        raise InputError(f"{field} {out}: cannot write into {parent} ({exc.strerror or exc})") from None
    return out


def parent_folder(out: Path | str, command: str, field: str = "--out") -> Path:
    """Check (:func:`check_folder`) and create a folder that holds results folders of ``command`` (one per
    item, e.g. one per paper of ``mobman reproduce all``), marked as written by ``command``."""
    out = check_folder(out, command, field)
    try:
        out.mkdir(parents=True, exist_ok=True)
        if _owner(out) != command:
            write_text(out / MARKER, command + "\n")
    except OSError as exc:
        raise InputError(f"{field} {out}: cannot write ({exc.strerror})") from None
    return out


@contextlib.contextmanager
def results_folder(out: Path | str, command: str, field: str = "--out") -> Iterator[Path]:
    """A temporary sibling of ``out`` to write a command's results into, renamed to ``out`` at the end.

    ``out`` is checked first (:func:`check_folder`); an existing results folder of the same command is
    replaced only once the new one is complete. On failure or interrupt the sibling is removed and ``out``
    is left as it was.
    """
    out = check_folder(out, command, field)
    try:
        out.parent.mkdir(parents=True, exist_ok=True)
        staging = Path(tempfile.mkdtemp(dir=out.parent, prefix=f".{out.name}.", suffix=".partial"))
    except OSError as exc:
        raise InputError(f"{field} {out}: cannot write ({exc.strerror})") from None
    try:
        write_text(staging / MARKER, command + "\n")
        yield staging
        _permissions(staging, 0o777)
        _swap(staging, out)
    except BaseException:
        shutil.rmtree(staging, ignore_errors=True)
        raise


def _swap(staging: Path, out: Path) -> None:
    if not out.exists():
        os.rename(staging, out)
        return
    retired = Path(tempfile.mkdtemp(dir=out.parent, prefix=f".{out.name}.", suffix=".old"))
    os.rename(out, retired / "folder")
    os.rename(staging, out)
    shutil.rmtree(retired, ignore_errors=True)


__all__ = [
    "MARKER",
    "atomic_path",
    "check_folder",
    "parent_folder",
    "results_folder",
    "save_figure",
    "write_text",
]
