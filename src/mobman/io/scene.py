"""Scene files: the obstacles around a robot in TOML (:class:`mobman.model.scene.Scene`).

One ``[[obstacle]]`` table per obstacle and an optional top-level ``floor`` (the height of the floor plane, m)::

    floor = 0.0

    [[obstacle]]
    name = "table"
    shape = "box"                # box | sphere | cylinder | capsule
    size = [0.8, 1.2, 0.75]      # box: full extents x, y, z (m); sphere: [radius]; cylinder, capsule: [radius, length]
    position = [1.3, 0.0, 0.375] # m, world frame (the centre)
    rpy = [0.0, 0.0, 0.0]        # rad, R = Rz(yaw) Ry(pitch) Rx(roll); default zeros

Every error is one line naming the file, the obstacle and the field (:class:`~mobman.errors.InputError`).
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any

from mobman.errors import InputError, ModelError
from mobman.io import spec as fields
from mobman.model.scene import Scene


def parse(data: Mapping[str, Any], where: str = "scene") -> Scene:
    """The scene of a scene file's document or of a specification's ``[scene]`` table; errors name ``where``."""
    try:
        return Scene.from_table(data)
    except ModelError as exc:
        text = str(exc)
        raise InputError(text if text.startswith("scene") else f"{where}: {text}") from None


def load(path: Path | str) -> Scene:
    """Read a scene file (the module's format); errors name the file."""
    data = fields.read_toml(Path(path))
    with fields.naming(path):
        return parse(data)


__all__ = ["load", "parse"]
