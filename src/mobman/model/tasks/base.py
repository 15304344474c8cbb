"""Operational coordinates ξ = f(q) (Bayle §2) and their Jacobians J = ∂f/∂q: the :class:`Task` interface and
the registry of task kinds.

A task is an immutable, hashable object with ``names`` and two per-configuration methods:
``value(robot, q, frames)`` and ``jacobian(robot, q, frames)``, and the operational error
``error(xi_desired, xi)`` that the control laws regulate (e = ξ* − ξ for every task whose value is a point
of Rᵐ; :class:`~mobman.model.tasks.pose.Pose`, whose orientation lives on SO(3), measures it by the rotation
vector log(R* Rᵀ), and its Jacobian rows are the frame's angular velocity: ``jacobian`` maps q̇ to the rate
of the error's coordinates, which is ∂ξ/∂q for the vector tasks). A task also gives its closed form in SymPy
(``symbolic``, used by :mod:`mobman.symbolic`) and where its coordinates are singular as a representation.

**Representation singularities.** An angle read from a rotation by atan2 is undefined where both its
arguments vanish (the heading of a vertical axis, an Euler set's gimbal lock) and its derivative grows as
1 / margin near there. :meth:`Task.representation_singular` tells where the margin is below
:data:`REPRESENTATION_TOL`: there the task's coordinates do not describe the frame (a property of the chosen
coordinates, not of the robot — distinct from a kinematic or velocity singularity, Bayle §2–4).

**Kinds.** A subclass that sets ``kind`` (a class attribute) registers itself under that name when its module
is imported; :mod:`mobman.model.tasks` imports every module of the package, and :func:`task_class` finds a
kind (robot and specification files name tasks by kind). Files build a task from a table generically: the
table's keys are the dataclass fields, converted by their annotations (:mod:`mobman.io.tasks`);
``choices`` lists the allowed strings of a field and :meth:`Task.from_table` is the hook for kinds that need
more than calling the class.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from functools import cached_property
from typing import TYPE_CHECKING, Any, ClassVar, Protocol

import jax
import jax.numpy as jnp

from mobman.errors import ModelError
from mobman.model.kinds import Kinds

if TYPE_CHECKING:
    import sympy as sp

    from mobman.model.robot import Frames, MobileManipulator

REPRESENTATION_TOL = 1e-8
"""An orientation coordinate is representation-singular where the norm of its atan2 arguments (its margin,
|cos| of the middle Euler angle) is at most this: its derivative, 1 / margin, then exceeds 1e8 and its value
is fixed by rounding errors of the rotation to no better than about 1e-8 rad."""

TASKS: Kinds[type[Task]] = Kinds("task")
"""The task classes by kind."""


class SymbolicFrames(Protocol):
    """What a task's closed form reads (:class:`mobman.symbolic.SymbolicRobot` provides it): the coordinate
    symbols, the symbolic frames and the model's numbers as exact SymPy numbers."""

    q: tuple[sp.Symbol, ...]

    def link_poses(self, arm: int) -> tuple[tuple[sp.Matrix, sp.Matrix], ...]: ...

    def mount_pose(self, arm: int) -> tuple[sp.Matrix, sp.Matrix]: ...

    def vector(self, values: Any) -> sp.Matrix: ...

    def angle(self, y: sp.Expr, x: sp.Expr) -> sp.Expr: ...

    def exact(self, expr: sp.Expr) -> sp.Expr: ...


@dataclass(frozen=True)
class Task:
    """Base class: subclasses define ``names`` and ``value``; ``jacobian`` defaults to autodiff.

    ``kind``: the name files use for the task (empty: not built from files, e.g. a Python function of q);
    setting it in a subclass registers the subclass.
    """

    kind: ClassVar[str] = ""
    choices: ClassVar[Mapping[str, tuple[str, ...]]] = {}
    """Allowed values of string fields (field name → values), checked when a file names them."""

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        TASKS.add(cls)

    @property
    def names(self) -> tuple[str, ...]:
        raise NotImplementedError

    @cached_property
    def dim(self) -> int:
        """m, the number of operational coordinates (computed once: public calls ask for it every time)."""
        return len(self.names)

    def value(self, robot: MobileManipulator, q: jnp.ndarray, frames: Frames) -> jnp.ndarray:
        raise NotImplementedError

    def jacobian(self, robot: MobileManipulator, q: jnp.ndarray, frames: Frames) -> jnp.ndarray:
        return jax.jacfwd(lambda qq: self.value(robot, qq, robot.frames(qq)))(q)

    def reduced_jacobian(self, robot: MobileManipulator, q: jnp.ndarray, frames: Frames) -> jnp.ndarray:
        """J̄ = J S (m × n_eta), the Jacobian in the quasi-velocities (Bayle §4.2, eq. 2)."""
        return robot.apply_S(self.jacobian(robot, q, frames), q)

    def symbolic(self, kin: SymbolicFrames) -> list[sp.Expr]:
        """ξ = f(q) as SymPy expressions of ``kin.q`` (unsimplified), from the symbolic frames of ``kin``
        (:class:`mobman.symbolic.SymbolicRobot`). Tasks without a closed form raise ModelError."""
        raise ModelError(f"symbolic: task {type(self).__name__} is not supported symbolically")

    @property
    def euclidean(self) -> bool:
        """True when the value is a point of Rᵐ, the error the difference ξ* − ξ and the Jacobian ∂ξ/∂q."""
        return True

    def error(self, xi_desired: jnp.ndarray, xi: jnp.ndarray) -> jnp.ndarray:
        """The operational error e of ξ with respect to ξ* (arrays (..., m)): here ξ* − ξ. Tasks whose value
        is not a point of Rᵐ (:class:`~mobman.model.tasks.pose.Pose`) override it; J q̇ is then the rate of
        change of −e at a fixed ξ*, where ξ = ξ*."""
        return xi_desired - xi

    def check(self, robot: MobileManipulator) -> None:
        """Raise ModelError if the task does not fit the robot (arm index, link index)."""

    def representation_singular(
        self, robot: MobileManipulator, q: jnp.ndarray, frames: Frames
    ) -> jnp.ndarray:
        """True where the task's coordinates are singular as a representation (module notes); never for
        positions and functions of q."""
        return jnp.asarray(False)

    @classmethod
    def from_table(cls, values: dict[str, Any]) -> Task:
        """The task of a file's table, ``values`` holding the given fields already converted by their
        annotations (absent fields keep the dataclass defaults). Override for kinds that are not the plain
        call of the class."""
        return cls(**values)


def task_kinds() -> tuple[str, ...]:
    """The registered task kinds, sorted."""
    return TASKS.kinds()


def task_class(kind: str) -> type[Task]:
    """The task class registered under ``kind``; an unknown kind raises ModelError naming the closest one."""
    return TASKS.get(kind)


_AXES = {"x": 0, "y": 1, "z": 2}


def component_indices(components: str) -> tuple[int, ...]:
    """The row indices (0, 1, 2) of components such as ``"xy"``; ModelError unless distinct letters of xyz."""
    if (
        not isinstance(components, str)
        or not components
        or any(c not in _AXES for c in components)
        or len(set(components)) != len(components)
    ):
        raise ModelError(f"task components {components!r}: use distinct letters among x, y, z")
    return tuple(_AXES[c] for c in components)


def last_moving(robot: MobileManipulator, arm: int, link: int) -> int:
    """The last joint that moves frame ``link`` of arm ``arm`` (``link=-1``: the tool frame)."""
    return robot.arms[arm].n_joints - 1 if link == -1 else link


def check_arm(robot: MobileManipulator, arm: int, link: int | None = None) -> None:
    """ModelError unless ``arm`` is an arm index of the robot and ``link`` (if given) −1 (tool) or a joint."""
    if not 0 <= arm < len(robot.arms):
        raise ModelError(f"task: arm index {arm} out of range 0..{len(robot.arms) - 1}")
    n = robot.arms[arm].n_joints
    if link is not None and not -1 <= link < n:
        raise ModelError(f"task: link index {link} out of range -1 (tool) .. {n - 1}")


__all__ = [
    "REPRESENTATION_TOL",
    "SymbolicFrames",
    "TASKS",
    "Task",
    "check_arm",
    "component_indices",
    "last_moving",
    "task_class",
    "task_kinds",
]
