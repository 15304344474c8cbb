"""URDF readings kept on disk, so that a later command reads a robot back without parsing its file again.

Reading a URDF (:func:`mobman.io.urdf.read_urdf`) imports yourdfpy, trimesh and SciPy's spatial module and
parses the file: about a second for TIAGo, most of a one-configuration command's time once its programs are
kept too (:mod:`mobman.engine.exported`). :func:`read` is ``read_urdf`` that, once :func:`enable` has been
called (the ``mobman`` command does), keeps each reading as a pickle in the folder ``urdf/`` of the compilation
cache, keyed by the SHA-256 of the file's bytes, its absolute path (relative mesh paths are resolved from it),
the reading's options, mobman's source (:func:`mobman.engine.exported.source_digest`) and the versions of
yourdfpy and trimesh. A kept reading is used only while every mesh file it draws still has the size and
modification time it had; a reading whose meshes were not all found is not kept (they may be installed
later). A mesh changed in place while the URDF file and the drawn meshes stay the same (a wheel's collision
mesh, whose size gives the wheel radius) is not noticed: turn the cache off (``MOBMAN_CACHE_DIR=off``) or
remove the folder after such an edit. Readings are unpickled only from mobman's, NumPy's and the standard
library's classes (:func:`mobman.engine.exported.trusted_loads`); the folder is its owner's only.
"""

from __future__ import annotations

import hashlib
import os
import pickle
import warnings
from importlib import metadata
from pathlib import Path
from typing import Any

from mobman.engine.exported import described, source_digest, store, subfolder, trusted_loads
from mobman.io.urdf import UrdfModel, UrdfWarning, collision_shapes, read_urdf
from mobman.model.collision_model import CollisionModel
from mobman.model.robot import MobileManipulator

MAX_BYTES = 64 * 2**20
"""Largest size of the folder of kept readings (TIAGo's is about 200 kB)."""

_folder: Path | None = None


def enable(compilation_folder: Path | None) -> Path | None:
    """Keep URDF readings in ``compilation_folder / "urdf"`` from now on in this process (None: off). Returns
    the folder, or None; raises :class:`mobman.InputError` when it cannot be created."""
    global _folder
    _folder = subfolder(compilation_folder, "urdf", "URDF readings")
    return _folder


def disable() -> None:
    """Stop keeping and reading URDF readings in this process."""
    global _folder
    _folder = None


def read(path: str | os.PathLike[str], **options: Any) -> UrdfModel:
    """:func:`mobman.io.urdf.read_urdf` ``(path, **options)``, read back from the folder when it was kept
    (its :class:`mobman.io.urdf.UrdfWarning` notes said again), else read and kept."""
    if _folder is None:
        return read_urdf(path, **options)
    try:
        data = Path(path).read_bytes()
    except OSError:
        return read_urdf(path, **options)  # read_urdf names the file and what is wrong
    key = _key(data, Path(path).resolve(), options)
    kept = _folder / f"{key}.pickle"
    model = _kept(kept)
    if model is not None:
        for note in model.summary.notes:
            warnings.warn(note, UrdfWarning, stacklevel=2)
        return model
    model = read_urdf(path, **options)
    if not model.summary.missing_meshes:
        try:
            store(kept, pickle.dumps((model, _mesh_stamps(model)), protocol=5), MAX_BYTES, "*.pickle")
        except (OSError, pickle.PicklingError):
            pass  # a read-only folder: the reading is still returned
    return model


def collision_model(
    path: str | os.PathLike[str], robot: MobileManipulator, tolerance: float, **options: Any
) -> CollisionModel:
    """The spheres covering the ``<collision>`` shapes of the URDF file ``path`` (read with ``options``) on
    ``robot`` (the file's robot, or a design of it) to the cover tolerance ``tolerance``
    (:meth:`mobman.model.collision_model.CollisionModel.from_shapes`), read back from the folder when they
    were kept: a cover takes seconds to build (the meshes' hulls), a kept one milliseconds."""
    model = read(path, **options)
    if _folder is None:
        return CollisionModel.from_shapes(robot, collision_shapes(model), tolerance)
    parts = {"robot": described(robot), "tolerance": float(tolerance), "options": options}
    key = _key(Path(path).read_bytes(), Path(path).resolve(), {"collision model": pickle.dumps(parts)})
    kept = _folder / f"{key}.pickle"
    try:
        cover = trusted_loads(kept.read_bytes())
    except Exception:  # noqa: BLE001 - none kept, or a damaged or foreign file: built afresh
        cover = None
    if isinstance(cover, CollisionModel):
        return cover
    cover = CollisionModel.from_shapes(robot, collision_shapes(model), tolerance)
    try:
        store(kept, pickle.dumps(cover, protocol=5), MAX_BYTES, "*.pickle")
    except (OSError, pickle.PicklingError):
        pass
    return cover


def _kept(path: Path) -> UrdfModel | None:
    """The reading kept at ``path`` if there is one, whole, and its meshes are unchanged."""
    try:
        model, stamps = trusted_loads(path.read_bytes())
    except Exception:  # noqa: BLE001 - none kept, or a damaged or foreign file: read afresh
        return None
    if not isinstance(model, UrdfModel) or stamps != _mesh_stamps(model):
        return None
    return model


def _mesh_stamps(model: UrdfModel) -> tuple:
    """(file, size, modification time) of every mesh the robot draws; a file gone is (file, None, None)."""
    robot = model.robot
    joints = [*(j for arm in robot.arms for j in arm.joints), *(f.joint for f in robot.followers)]
    visuals = [*robot.platform_visuals, *(v for j in joints for v in j.visuals)]
    out: list[tuple[str, int | None, int | None]] = []
    for name in sorted({v.filename for v in visuals if v.filename}):
        try:
            st = os.stat(name)
            out.append((name, st.st_size, st.st_mtime_ns))
        except OSError:
            out.append((name, None, None))
    return tuple(out)


def _key(data: bytes, path: Path, options: dict[str, Any]) -> str:
    versions = []
    for distribution in ("yourdfpy", "trimesh"):
        try:
            versions.append(metadata.version(distribution))
        except metadata.PackageNotFoundError:
            versions.append("")
    digest = hashlib.sha256()
    for part in (data, str(path).encode(), repr(_canonical(options)).encode(), repr(versions).encode()):
        digest.update(len(part).to_bytes(8, "little"))
        digest.update(part)
    digest.update(source_digest().encode())
    return digest.hexdigest()


def _canonical(value: Any) -> Any:
    """``value`` with every mapping as its sorted items, so that equal options give equal keys."""
    if isinstance(value, dict):
        return tuple(sorted((str(k), _canonical(v)) for k, v in value.items()))
    if isinstance(value, (list, tuple)):
        return tuple(_canonical(v) for v in value)
    return value


__all__ = ["MAX_BYTES", "collision_model", "disable", "enable", "read"]
