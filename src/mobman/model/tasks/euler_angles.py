"""Euler angles of an arm frame (the orientation rows of a 6-D end-effector task written in a chart)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import jax

from mobman.errors import ModelError
from mobman.model import spatial
from mobman.model.tasks.base import SymbolicFrames
from mobman.model.tasks.orientation import OrientationTask

if TYPE_CHECKING:
    import sympy as sp


@dataclass(frozen=True)
class EulerAngles(OrientationTask):
    """Euler angles of an arm frame, sequence ``ZYZ``, ``ZYX`` (roll-pitch-yaw as yaw, pitch, roll),
    ``XYZ``, ``ZXZ`` or ``ZXY`` (:func:`~mobman.model.spatial.euler_angles`); ``select`` keeps a subset
    (indices into the three angles). Representation-singular at the gimbal lock of the sequence
    (:func:`~mobman.model.spatial.gimbal_margin`), whichever angles are selected."""

    kind = "euler_angles"
    choices = {"sequence": spatial.EULER_SEQUENCES}

    sequence: str = "ZYZ"
    select: tuple[int, ...] = (0, 1, 2)

    def __post_init__(self) -> None:
        if self.sequence not in spatial.EULER_SEQUENCES:
            raise ModelError(
                f"EulerAngles: sequence {self.sequence!r} not supported; allowed: "
                f"{', '.join(spatial.EULER_SEQUENCES)}"
            )
        sel = tuple(int(i) for i in self.select)
        if not sel or any(i not in (0, 1, 2) for i in sel) or len(set(sel)) != len(sel):
            raise ModelError(
                f"EulerAngles: select must be distinct indices among 0, 1, 2, got {self.select!r}"
            )
        object.__setattr__(self, "select", sel)

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(f"{self.sequence.lower()}_{i + 1}" for i in self.select)

    def angles(self, r: jax.Array) -> jax.Array:
        return spatial.rows(spatial.euler_angles(r, self.sequence), self.select)

    def margin(self, r: jax.Array) -> jax.Array:
        return spatial.gimbal_margin(r, self.sequence)

    def symbolic_angles(self, r: sp.Matrix, kin: SymbolicFrames) -> list[sp.Expr]:
        """The formulas of :func:`~mobman.model.spatial.euler_angles`, entry by entry."""
        import sympy as sp

        angle = kin.angle
        if self.sequence in ("ZYZ", "ZXZ"):
            middle = sp.atan2(sp.sqrt(r[0, 2] ** 2 + r[1, 2] ** 2), r[2, 2])
            if self.sequence == "ZYZ":
                three = [angle(r[1, 2], r[0, 2]), middle, angle(r[2, 1], -r[2, 0])]
            else:
                three = [angle(r[0, 2], -r[1, 2]), middle, angle(r[2, 0], r[2, 1])]
        elif self.sequence == "ZYX":
            three = [angle(r[1, 0], r[0, 0]), sp.asin(-r[2, 0]), angle(r[2, 1], r[2, 2])]
        elif self.sequence == "XYZ":
            three = [angle(-r[1, 2], r[2, 2]), sp.asin(r[0, 2]), angle(-r[0, 1], r[0, 0])]
        else:  # ZXY
            three = [angle(-r[0, 1], r[1, 1]), sp.asin(r[2, 1]), angle(-r[2, 0], r[2, 2])]
        return [three[i] for i in self.select]
