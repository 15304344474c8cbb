"""The robot's surroundings: obstacles as geometric primitives and the floor plane.

An :class:`Obstacle` is a box, a sphere, a cylinder or a capsule with a name, a pose in the world and its sizes:

- ``box``: ``size = [x, y, z]``, the full extents along its own axes (m);
- ``sphere``: ``size = [radius]``;
- ``cylinder``: ``size = [radius, length]``, the axis along its own z, ``length`` the full height;
- ``capsule``: ``size = [radius, length]``, the points within ``radius`` of the segment of ``length`` along its
  own z through its centre (the straight part; the whole capsule is ``length + 2 radius`` long).

Its pose is the position of its centre and the rotation R = R_z(yaw) R_y(pitch) R_x(roll) of
``rpy = [roll, pitch, yaw]`` (URDF's convention, as :class:`mobman.model.robot.Mount`). The floor, when there
is one, is the half-space z ≤ ``floor`` below the plane z = ``floor``.

A :class:`Scene` is an immutable, hashable dataclass, so that it can be a static argument of :func:`jax.jit`
(its numbers become constants of the compiled program); it holds at most :data:`MAX_OBSTACLES` obstacles. Bad
descriptions raise a one-line :class:`~mobman.errors.ModelError` naming the obstacle and the field.
"""

from __future__ import annotations

import difflib
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from mobman import checks
from mobman.errors import ModelError
from mobman.model import spatial

SHAPES: dict[str, tuple[str, ...]] = {
    "box": ("x", "y", "z"),
    "sphere": ("radius",),
    "cylinder": ("radius", "length"),
    "capsule": ("radius", "length"),
}
"""The obstacle shapes and the meaning of each entry of their ``size``."""

MAX_OBSTACLES = 256
"""The most obstacles a scene holds (each is a constant of the compiled distance programs)."""

OBSTACLE_KEYS = ("name", "shape", "size", "position", "rpy")
"""The keys of an obstacle's table in a scene file."""

SCENE_KEYS = ("obstacle", "floor")
"""The top-level keys of a scene file (or of a ``[scene]`` table)."""


def _unknown(keys: Sequence[str], allowed: Sequence[str], owner: str) -> None:
    for key in keys:
        if key not in allowed:
            close = difflib.get_close_matches(str(key), allowed, n=1)
            hint = f" (did you mean {close[0]!r}?)" if close else ""
            raise ModelError(f"{owner}: unknown key {key!r}{hint}; allowed: {', '.join(allowed)}")


def _numbers(value: Any, count: int, name: str, owner: str) -> tuple[float, ...]:
    """``value`` as ``count`` finite floats."""
    values = list(value) if isinstance(value, (list, tuple, np.ndarray)) else [value]
    if len(values) != count:
        raise ModelError(f"{owner}: {name} must be {count} numbers, got {value!r}")
    return tuple(checks.finite(v, f"{name}[{i}]", owner) for i, v in enumerate(values))


@dataclass(frozen=True)
class Obstacle:
    """One primitive obstacle: ``shape`` (:data:`SHAPES`), ``size`` (m), the world ``position`` of its centre
    (m) and its orientation ``rpy`` = (roll, pitch, yaw) (rad), R = R_z(yaw) R_y(pitch) R_x(roll)."""

    name: str
    shape: str
    size: tuple[float, ...]
    position: tuple[float, float, float] = (0.0, 0.0, 0.0)
    rpy: tuple[float, float, float] = (0.0, 0.0, 0.0)

    def __post_init__(self) -> None:
        if not isinstance(self.name, str) or not self.name:
            raise ModelError(f"obstacle {self.name!r}: name must be a non-empty string")
        owner = f"obstacle {self.name!r}"
        if self.shape not in SHAPES:
            close = difflib.get_close_matches(str(self.shape), SHAPES, n=1)
            hint = f" (did you mean {close[0]!r}?)" if close else ""
            raise ModelError(f"{owner}: shape must be one of {', '.join(SHAPES)}, got {self.shape!r}{hint}")
        fields = SHAPES[self.shape]
        meaning = f"{self.shape}: [{', '.join(fields)}] in m, each > 0"
        values = list(self.size) if isinstance(self.size, (list, tuple, np.ndarray)) else [self.size]
        if len(values) != len(fields):
            raise ModelError(f"{owner}: size must be {len(fields)} numbers ({meaning}), got {self.size!r}")
        size = tuple(checks.finite(v, f"size[{i}]", owner) for i, v in enumerate(values))
        for i, v in enumerate(size):
            if v <= 0:
                raise ModelError(f"{owner}: size[{i}] ({fields[i]}) must be > 0 ({meaning}), got {v:g}")
        object.__setattr__(self, "size", size)
        object.__setattr__(self, "position", _numbers(self.position, 3, "position", owner))
        object.__setattr__(self, "rpy", _numbers(self.rpy, 3, "rpy", owner))

    @property
    def rotation(self) -> np.ndarray:
        """R = R_z(yaw) R_y(pitch) R_x(roll), the obstacle's axes in the world (3 × 3)."""
        roll, pitch, yaw = self.rpy
        return spatial.rot_z(yaw) @ spatial.rot_y(pitch) @ spatial.rot_x(roll)

    @classmethod
    def from_table(cls, table: Mapping[str, Any], index: int = 0) -> "Obstacle":
        """An obstacle from a scene file's ``[[obstacle]]`` table (keys :data:`OBSTACLE_KEYS`; ``rpy`` and
        ``position`` default to zeros); ``index`` names an unnamed one."""
        if not isinstance(table, Mapping):
            raise ModelError(f"obstacle {index + 1}: must be a table, got {table!r}")
        name = table.get("name", f"obstacle {index + 1}")
        owner = f"obstacle {name!r}"
        _unknown(list(table), OBSTACLE_KEYS, owner)
        for key in ("name", "shape", "size"):
            if key not in table:
                raise ModelError(f"{owner}: missing {key!r}")
        return cls(
            name=table["name"],
            shape=table["shape"],
            size=table["size"],
            position=table.get("position", (0.0, 0.0, 0.0)),
            rpy=table.get("rpy", (0.0, 0.0, 0.0)),
        )


@dataclass(frozen=True)
class Scene:
    """The obstacles around a robot and, optionally, the floor z ≤ ``floor`` (m; None: no floor).

    Immutable and hashable: a static argument of compiled functions. Names are unique; at most
    :data:`MAX_OBSTACLES` obstacles.
    """

    obstacles: tuple[Obstacle, ...] = field(default=())
    floor: float | None = None

    def __post_init__(self) -> None:
        obstacles = tuple(self.obstacles)
        if len(obstacles) > MAX_OBSTACLES:
            raise ModelError(f"scene: {len(obstacles)} obstacles, at most {MAX_OBSTACLES} allowed")
        seen: set[str] = set()
        for obstacle in obstacles:
            if not isinstance(obstacle, Obstacle):
                raise ModelError(f"scene: obstacles must be Obstacle objects, got {type(obstacle).__name__}")
            if obstacle.name in seen:
                raise ModelError(f"obstacle {obstacle.name!r}: name used twice; names must be unique")
            seen.add(obstacle.name)
        object.__setattr__(self, "obstacles", obstacles)
        if self.floor is not None:
            object.__setattr__(self, "floor", checks.finite(self.floor, "floor", "scene"))

    @property
    def names(self) -> tuple[str, ...]:
        """The obstacles' names, then ``"floor"`` when the scene has one."""
        return tuple(o.name for o in self.obstacles) + (() if self.floor is None else ("floor",))

    @classmethod
    def from_table(cls, table: Mapping[str, Any]) -> "Scene":
        """A scene from a scene file's document or a specification's ``[scene]`` table: ``[[obstacle]]`` tables
        (:meth:`Obstacle.from_table`) and an optional ``floor`` height (m)."""
        if not isinstance(table, Mapping):
            raise ModelError(f"scene: must be a table, got {table!r}")
        _unknown(list(table), SCENE_KEYS, "scene")
        rows = table.get("obstacle", [])
        if not isinstance(rows, list):
            raise ModelError("scene: obstacle must be an array of tables ([[obstacle]])")
        if len(rows) > MAX_OBSTACLES:
            raise ModelError(f"scene: {len(rows)} obstacles, at most {MAX_OBSTACLES} allowed")
        floor = table.get("floor")
        return cls(tuple(Obstacle.from_table(row, i) for i, row in enumerate(rows)), floor)

    def describe(self) -> dict:
        """A JSON-friendly description (the scene file's form)."""
        out: dict[str, Any] = {
            "obstacle": [
                {
                    "name": o.name,
                    "shape": o.shape,
                    "size": list(o.size),
                    "position": list(o.position),
                    "rpy": list(o.rpy),
                }
                for o in self.obstacles
            ]
        }
        if self.floor is not None:
            out["floor"] = self.floor
        return out


__all__ = ["MAX_OBSTACLES", "OBSTACLE_KEYS", "SCENE_KEYS", "SHAPES", "Obstacle", "Scene"]
