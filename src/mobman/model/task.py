"""Operational coordinates ξ = f(q) (Bayle §2) and their Jacobians J = ∂f/∂q.

A task is an immutable, hashable object with ``names`` and two per-configuration methods:
``value(robot, q, frames)`` and ``jacobian(robot, q, frames)``, and the operational error
``error(xi_desired, xi)`` that the control laws regulate (e = ξ* − ξ for every task whose value is a point
of Rᵐ; :class:`Pose`, whose orientation lives on SO(3), measures it by the rotation vector log(R* Rᵀ), and
its Jacobian rows are the frame's angular velocity: ``jacobian`` maps q̇ to the rate of the error's
coordinates, which is ∂ξ/∂q for the vector tasks). Position tasks build the geometric
Jacobian from the chain; orientation tasks chain-rule the angle extraction through Ṙ = [ω]× R; both take
the frame and its columns from :func:`~mobman.model.frame_jacobian.frame_jacobian`, whose derivative is in
closed form (the kinematic Hessian). All other tasks (user functions of q) are differentiated by
forward-mode autodiff. Stacks concatenate rows — this is how Korayem's extra rows and Tchoń's output
extension are expressed.

**Representation singularities.** An angle read from a rotation by atan2 is undefined where both its
arguments vanish (the heading of a vertical axis, an Euler set's gimbal lock) and its derivative grows as
1 / margin near there. :meth:`Task.representation_singular` tells where the margin is below
:data:`REPRESENTATION_TOL`: there the task's coordinates do not describe the frame (a property of the chosen
coordinates, not of the robot — distinct from a kinematic or velocity singularity, Bayle §2–4).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property
from typing import TYPE_CHECKING, Callable

import jax
import jax.numpy as jnp

from mobman.errors import ModelError
from mobman.model import so3, spatial
from mobman.model.frame_jacobian import frame_jacobian

if TYPE_CHECKING:
    from mobman.model.robot import Frames, MobileManipulator

_AXES = {"x": 0, "y": 1, "z": 2}

REPRESENTATION_TOL = 1e-8
"""An orientation coordinate is representation-singular where the norm of its atan2 arguments (its margin,
|cos| of the middle Euler angle) is at most this: its derivative, 1 / margin, then exceeds 1e8 and its value
is fixed by rounding errors of the rotation to no better than about 1e-8 rad."""


@dataclass(frozen=True)
class Task:
    """Base class: subclasses define ``names`` and ``value``; ``jacobian`` defaults to autodiff."""

    @property
    def names(self) -> tuple[str, ...]:
        raise NotImplementedError

    @cached_property
    def dim(self) -> int:
        """m, the number of operational coordinates (computed once: public calls ask for it every time)."""
        return len(self.names)

    def value(self, robot: "MobileManipulator", q: jnp.ndarray, frames: "Frames") -> jnp.ndarray:
        raise NotImplementedError

    def jacobian(self, robot: "MobileManipulator", q: jnp.ndarray, frames: "Frames") -> jnp.ndarray:
        return jax.jacfwd(lambda qq: self.value(robot, qq, robot.frames(qq)))(q)

    @property
    def euclidean(self) -> bool:
        """True when the value is a point of Rᵐ, the error the difference ξ* − ξ and the Jacobian ∂ξ/∂q."""
        return True

    def error(self, xi_desired: jnp.ndarray, xi: jnp.ndarray) -> jnp.ndarray:
        """The operational error e of ξ with respect to ξ* (arrays (..., m)): here ξ* − ξ. Tasks whose value
        is not a point of Rᵐ (:class:`Pose`) override it; J q̇ is then the rate of change of −e at a fixed
        ξ*, where ξ = ξ*."""
        return xi_desired - xi

    def check(self, robot: "MobileManipulator") -> None:
        """Raise ModelError if the task does not fit the robot (arm index, link index)."""

    def representation_singular(
        self, robot: "MobileManipulator", q: jnp.ndarray, frames: "Frames"
    ) -> jnp.ndarray:
        """True where the task's coordinates are singular as a representation (module notes); never for
        positions and functions of q."""
        return jnp.asarray(False)


def _components(components: str) -> tuple[int, ...]:
    if not components or any(c not in _AXES for c in components) or len(set(components)) != len(components):
        raise ModelError(f"task components {components!r}: use distinct letters among x, y, z")
    return tuple(_AXES[c] for c in components)


def _rows(x: jnp.ndarray, indices: tuple[int, ...]) -> jnp.ndarray:
    """x[indices] for static row indices, from one split of x: indexing with an integer array compiles to a
    gather, a kernel of its own (and a scatter in reverse-mode derivatives), and a slice per row transposes to
    a padded array per row."""
    if indices == tuple(range(x.shape[0])):
        return x
    rows = spatial.unstack(x, axis=0)
    return jnp.stack([rows[i] for i in indices])


def _last_moving(robot: "MobileManipulator", arm: int, link: int) -> int:
    """The last joint that moves frame ``link`` of arm ``arm`` (``link=-1``: the tool frame)."""
    return robot.arms[arm].n_joints - 1 if link == -1 else link


def _check_arm(robot: "MobileManipulator", arm: int, link: int | None = None) -> None:
    if not 0 <= arm < len(robot.arms):
        raise ModelError(f"task: arm index {arm} out of range 0..{len(robot.arms) - 1}")
    n = robot.arms[arm].n_joints
    if link is not None and not -1 <= link < n:
        raise ModelError(f"task: link index {link} out of range -1 (tool) .. {n - 1}")


@dataclass(frozen=True)
class Position(Task):
    """Position of a point of an arm frame in the world, any subset of (x, y, z).

    ``link=-1`` is the tool (end-effector) frame; ``link=k`` the frame after joint k. ``point`` is an offset
    in that frame. The Jacobian is the geometric one, z_i × (p − o_i) (tested against autodiff).
    """

    components: str = "xyz"
    arm: int = 0
    link: int = -1
    point: tuple[float, float, float] = (0.0, 0.0, 0.0)
    label: str = "ee"

    def __post_init__(self) -> None:
        _components(self.components)

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(f"{c}_{self.label}" for c in self.components)

    def check(self, robot: "MobileManipulator") -> None:
        _check_arm(robot, self.arm, self.link)

    def _frame(self, frames):
        """The link's rotation and the task point."""
        rs, ps = frames.links[self.arm]
        return rs[self.link], ps[self.link] + spatial.matvec_constant(rs[self.link], self.point)

    def value(self, robot: "MobileManipulator", q: jnp.ndarray, frames: "Frames") -> jnp.ndarray:
        return _rows(self._frame(frames)[1], _components(self.components))

    def jacobian(self, robot: "MobileManipulator", q: jnp.ndarray, frames: "Frames") -> jnp.ndarray:
        upto = _last_moving(robot, self.arm, self.link)
        _, _, lin, _ = frame_jacobian(robot, self._frame, self.arm, upto, q)
        return _rows(lin, _components(self.components))


@dataclass(frozen=True)
class MountPosition(Task):
    """Position of an arm's mount point in the world (Korayem's base point F = (x_f, y_f))."""

    components: str = "xy"
    arm: int = 0

    def __post_init__(self) -> None:
        _components(self.components)

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(f"{c}_f" for c in self.components)

    def check(self, robot: "MobileManipulator") -> None:
        _check_arm(robot, self.arm)

    def _frame(self, frames):
        return frames.mounts[self.arm]

    def value(self, robot: "MobileManipulator", q: jnp.ndarray, frames: "Frames") -> jnp.ndarray:
        return _rows(self._frame(frames)[1], _components(self.components))

    def jacobian(self, robot: "MobileManipulator", q: jnp.ndarray, frames: "Frames") -> jnp.ndarray:
        _, _, lin, _ = frame_jacobian(robot, self._frame, None, -1, q)
        return _rows(lin, _components(self.components))


@dataclass(frozen=True)
class _OrientationTask(Task):
    """Angles g(R) of an arm frame's rotation R. With Ṙ = [ω]× R and ω = Σ_j ω_j q̇_j,
    ∂g_k/∂q_j = ⟨∂g_k/∂R, [ω_j]× R⟩ = ω_j · vee(M_k − M_kᵀ) with M_k = (∂g_k/∂R) Rᵀ and
    vee(A) = (A₂₁, A₀₂, A₁₀): one 3 × 3 product per angle instead of one per column."""

    arm: int = field(default=0, kw_only=True)
    link: int = field(default=-1, kw_only=True)

    def check(self, robot) -> None:
        _check_arm(robot, self.arm, self.link)

    def angles(self, r: jnp.ndarray) -> jnp.ndarray:
        raise NotImplementedError

    def margin(self, r: jnp.ndarray) -> jnp.ndarray:
        """Norm of the atan2 arguments of the angles (the smallest one): 0 where they are undefined."""
        raise NotImplementedError

    def value(self, robot, q, frames):
        return self.angles(frames.links[self.arm][0][self.link])

    def representation_singular(self, robot, q, frames):
        return self.margin(frames.links[self.arm][0][self.link]) <= REPRESENTATION_TOL

    def _frame(self, frames):
        rs, ps = frames.links[self.arm]
        return rs[self.link], ps[self.link]

    def jacobian(self, robot, q, frames):
        upto = _last_moving(robot, self.arm, self.link)
        r, _, _, omega = frame_jacobian(robot, self._frame, self.arm, upto, q)
        m = spatial.matmul_expanded(jax.jacfwd(self.angles)(r), r.T)  # (k, 3, 3)
        axial = jnp.stack([m[:, 2, 1] - m[:, 1, 2], m[:, 0, 2] - m[:, 2, 0], m[:, 1, 0] - m[:, 0, 1]], -1)
        return spatial.matmul_expanded(axial, omega)


HEADING_SEQUENCES = ("ZYX", "ZXY")
"""The Euler sets whose yaw :class:`PlanarAngle` gives."""


@dataclass(frozen=True)
class PlanarAngle(_OrientationTask):
    """Heading of an arm frame about the vertical: the yaw (first angle) of the Euler set ``sequence``.

    ``sequence="ZYX"`` (default): the heading of the frame's x axis, atan2(R₁₀, R₀₀) (Bayle's ξ3 in §5.1,
    Korayem's α_e; for a planar robot the sum of the platform angle and the joint angles); undefined where the
    x axis is vertical.
    ``sequence="ZXY"``: the heading of the frame's x–z plane, atan2(−R₀₁, R₁₁), undefined only where the
    y axis is vertical: for an arm that lifts about its y axis it stays ϑ + q4 through the vertical and past
    it (Bayle §5.2, ξ4 = q3 + q4). Continuous away from ±π, where it wraps.
    """

    sequence: str = "ZYX"

    def __post_init__(self) -> None:
        if self.sequence not in HEADING_SEQUENCES:
            raise ModelError(
                f"PlanarAngle: sequence {self.sequence!r} not supported; allowed: {', '.join(HEADING_SEQUENCES)}"
            )

    @property
    def names(self) -> tuple[str, ...]:
        return ("angle",)

    def angles(self, r: jnp.ndarray) -> jnp.ndarray:
        if self.sequence == "ZYX":
            return jnp.arctan2(r[1, 0], r[0, 0])[None]
        return jnp.arctan2(-r[0, 1], r[1, 1])[None]

    def margin(self, r: jnp.ndarray) -> jnp.ndarray:
        return spatial.gimbal_margin(r, self.sequence)


@dataclass(frozen=True)
class Elevation(_OrientationTask):
    """Elevation of an arm frame about its own y axis: minus the pitch of the ZXY Euler set,
    atan2(R₂₀, R₂₂) (Bayle's ξ5 = q5 for the RRP arm, §5.2).

    While the y axis is horizontal (an arm that lifts about it) it is the angle of the x axis above the
    horizontal plane, continuous over the whole turn (−π, π]: ξ5 = q5 through the vertical and past it.
    Undefined only where the y axis is vertical (R₂₀ = R₂₂ = 0).
    """

    @property
    def names(self) -> tuple[str, ...]:
        return ("elevation",)

    def angles(self, r: jnp.ndarray) -> jnp.ndarray:
        return jnp.arctan2(r[2, 0], r[2, 2])[None]

    def margin(self, r: jnp.ndarray) -> jnp.ndarray:
        return jnp.hypot(r[2, 0], r[2, 2])


@dataclass(frozen=True)
class EulerAngles(_OrientationTask):
    """Euler angles of an arm frame, sequence ``ZYZ``, ``ZYX`` (roll-pitch-yaw as yaw, pitch, roll),
    ``XYZ``, ``ZXZ`` or ``ZXY``; ``select`` keeps a subset (indices into the three angles). Representation-
    singular at the gimbal lock of the sequence (:func:`~mobman.model.spatial.gimbal_margin`), whichever
    angles are selected."""

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

    def angles(self, r: jnp.ndarray) -> jnp.ndarray:
        return _rows(spatial.euler_angles(r, self.sequence), self.select)

    def margin(self, r: jnp.ndarray) -> jnp.ndarray:
        return spatial.gimbal_margin(r, self.sequence)


@dataclass(frozen=True)
class Pose(Task):
    """Position and orientation of an arm frame: ξ = (p, r) with r = log R the rotation vector of the
    frame's rotation R (angle in [0, π]; :mod:`mobman.model.so3`).

    The error is e = (p* − p, log(R* Rᵀ)), the translation and the world-frame rotation vector that take
    the frame to the desired pose, and the Jacobian rows are the geometric ones, the linear and the angular
    velocity (v, ω) of the frame (:func:`~mobman.model.frame_jacobian.frame_jacobian`); a reference's
    velocity ξ̇* is likewise (ṗ*, ω*) (:class:`~mobman.control.references.PoseReference`). No
    representation singularity: r wraps at θ = π, but the error and the Jacobian are continuous, and the
    Jacobian has full rank wherever the robot can turn the frame about every axis.

    With J̄ η = ξ̇* + W e exactly (Bayle eq. 5–6 away from singularities), ė_p = −(W e)_p and, with E =
    R* Rᵀ = exp(e_o), Ė Eᵀ = [ω* − E ω]×; the left Jacobian J_l(e_o) of SO(3) maps ė_o to it, and with
    J_l⁻¹(I − E) = −[e_o]× and e_oᵀ J_l⁻¹ = e_oᵀ, ė_o = ω* × e_o − J_l⁻¹ (W e)_o: d‖e‖²/dt = −2 eᵀ W e. The
    norm of the pose error decays at least as fast as exp(−λ_min(W) t) (exactly so for a scalar W),
    whatever the reference's angular velocity.

    ``link=-1`` is the tool frame; ``link=k`` the frame after joint k.
    """

    arm: int = 0
    link: int = -1
    label: str = "ee"

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(f"{c}_{self.label}" for c in ("x", "y", "z", "rx", "ry", "rz"))

    @property
    def euclidean(self) -> bool:
        return False

    def check(self, robot: "MobileManipulator") -> None:
        _check_arm(robot, self.arm, self.link)

    def _frame(self, frames):
        rs, ps = frames.links[self.arm]
        return rs[self.link], ps[self.link]

    def value(self, robot: "MobileManipulator", q: jnp.ndarray, frames: "Frames") -> jnp.ndarray:
        r, p = self._frame(frames)
        return jnp.concatenate([p, so3.log(r)])

    def jacobian(self, robot: "MobileManipulator", q: jnp.ndarray, frames: "Frames") -> jnp.ndarray:
        upto = _last_moving(robot, self.arm, self.link)
        _, _, lin, omega = frame_jacobian(robot, self._frame, self.arm, upto, q)
        return jnp.concatenate([lin, omega], axis=0)

    def error(self, xi_desired: jnp.ndarray, xi: jnp.ndarray) -> jnp.ndarray:
        position = xi_desired[..., :3] - xi[..., :3]
        return jnp.concatenate([position, so3.error(xi_desired[..., 3:], xi[..., 3:])], axis=-1)


@dataclass(frozen=True)
class FunctionTask(Task):
    """A user function of the generalized coordinates, ξ = fn(q) for one configuration (shape (m,)).

    Its Jacobian is obtained by autodiff, so ``fn`` must be written with ``jax.numpy``. Examples: Korayem's
    elbow angle β = π − θ2 is ``FunctionTask(lambda q: jnp.pi - q[4:5], ("beta",))``.
    """

    fn: Callable[[jnp.ndarray], jnp.ndarray] = None  # type: ignore[assignment]
    labels: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        if not callable(self.fn):
            raise ModelError("FunctionTask: fn must be a callable of q")
        if not self.labels:
            raise ModelError("FunctionTask: give the names (labels) of the outputs")

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(self.labels)

    def value(self, robot: "MobileManipulator", q: jnp.ndarray, frames: "Frames") -> jnp.ndarray:
        return jnp.reshape(jnp.asarray(self.fn(q)), (self.dim,))


@dataclass(frozen=True)
class Stack(Task):
    """Several tasks stacked row-wise: ξ = [f_1(q); f_2(q); …]."""

    tasks: tuple[Task, ...] = ()

    def __post_init__(self) -> None:
        tasks = tuple(self.tasks)
        if not tasks or not all(isinstance(t, Task) for t in tasks):
            raise ModelError("Stack: give one or more tasks")
        object.__setattr__(self, "tasks", tasks)

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(n for t in self.tasks for n in t.names)

    def check(self, robot: "MobileManipulator") -> None:
        for t in self.tasks:
            t.check(robot)

    def value(self, robot: "MobileManipulator", q: jnp.ndarray, frames: "Frames") -> jnp.ndarray:
        return jnp.concatenate([t.value(robot, q, frames) for t in self.tasks])

    def representation_singular(
        self, robot: "MobileManipulator", q: jnp.ndarray, frames: "Frames"
    ) -> jnp.ndarray:
        return jnp.any(jnp.stack([t.representation_singular(robot, q, frames) for t in self.tasks]))

    def jacobian(self, robot: "MobileManipulator", q: jnp.ndarray, frames: "Frames") -> jnp.ndarray:
        return jnp.concatenate([t.jacobian(robot, q, frames) for t in self.tasks], axis=0)

    @property
    def euclidean(self) -> bool:
        return all(t.euclidean for t in self.tasks)

    def error(self, xi_desired: jnp.ndarray, xi: jnp.ndarray) -> jnp.ndarray:
        """Each part's error on its rows (the difference when every part is euclidean)."""
        if self.euclidean:
            return xi_desired - xi
        parts, start = [], 0
        for t in self.tasks:
            parts.append(t.error(xi_desired[..., start : start + t.dim], xi[..., start : start + t.dim]))
            start += t.dim
        return jnp.concatenate(parts, axis=-1)


def stack(*tasks: Task) -> Stack:
    """Stack tasks row-wise (flattening nested stacks)."""
    flat: list[Task] = []
    for t in tasks:
        flat.extend(t.tasks if isinstance(t, Stack) else (t,))
    return Stack(tuple(flat))
