"""Visual geometry attached to a robot's frames, for drawing it (the viewer, figures).

A :class:`Visual` is a shape fixed in one frame of the robot: the platform frame, or the frame of an arm joint
after its motion (the link that joint moves). Shapes are the URDF ``<visual>`` geometries — box, cylinder,
sphere, mesh — each with its own ``origin`` in that frame. Visuals never enter the kinematics: they are excluded
from equality and hashing, so two robots that differ only in how they look compile to the same functions.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import numpy as np

from mobman.errors import ModelError
from mobman.model.spatial import IDENTITY, Transform

VisualKind = Literal["box", "cylinder", "sphere", "mesh"]
_SIZES = {"box": 3, "cylinder": 2, "sphere": 1, "mesh": 0}


@dataclass(frozen=True)
class Visual:
    """One shape fixed in a robot frame.

    Parameters
    ----------
    kind:
        ``"box"`` (size = x, y, z edge lengths), ``"cylinder"`` (size = radius, length; axis along the local z),
        ``"sphere"`` (size = radius) or ``"mesh"`` (``filename``, scaled by ``scale``).
    origin:
        pose of the shape in the frame it is attached to (row-major 4 × 4, 16 floats).
    size:
        the dimensions listed above (m).
    filename:
        absolute path of a mesh file (``kind="mesh"``); ``""`` otherwise.
    scale:
        per-axis scale of a mesh.
    rgba:
        colour and opacity, each in [0, 1].
    name:
        a label (the URDF link name, say).
    """

    kind: VisualKind
    origin: Transform = IDENTITY
    size: tuple[float, ...] = ()
    filename: str = ""
    scale: tuple[float, float, float] = (1.0, 1.0, 1.0)
    rgba: tuple[float, float, float, float] = (0.7, 0.7, 0.75, 1.0)
    name: str = ""

    def __post_init__(self) -> None:
        if self.kind not in _SIZES:
            raise ModelError(
                f"Visual {self.name!r}: kind must be one of {', '.join(_SIZES)}, got {self.kind!r}"
            )
        size = tuple(float(v) for v in self.size)
        if len(size) != _SIZES[self.kind] or not all(np.isfinite(size)) or any(v <= 0 for v in size):
            raise ModelError(
                f"Visual {self.name!r}: a {self.kind} needs {_SIZES[self.kind]} positive size values, got {self.size!r}"
            )
        if self.kind == "mesh" and not self.filename:
            raise ModelError(f"Visual {self.name!r}: a mesh needs a filename")
        origin = np.asarray(self.origin, dtype=float)
        if origin.size != 16 or not np.all(np.isfinite(origin)):
            raise ModelError(f"Visual {self.name!r}: origin must be a finite 4 × 4 transform")
        rgba = tuple(float(v) for v in self.rgba)
        if len(rgba) != 4 or not all(0.0 <= v <= 1.0 for v in rgba):
            raise ModelError(f"Visual {self.name!r}: rgba must be 4 numbers in [0, 1], got {self.rgba!r}")
        object.__setattr__(self, "size", size)
        object.__setattr__(self, "origin", tuple(float(v) for v in origin.ravel()))
        object.__setattr__(self, "scale", tuple(float(v) for v in self.scale))
        object.__setattr__(self, "rgba", rgba)


__all__ = ["Visual", "VisualKind"]
