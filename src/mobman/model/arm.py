"""Serial arms: each joint is a fixed transform followed by a revolute or prismatic motion about an axis.

This is the URDF joint model (``origin`` then motion about ``axis``), so URDF import needs no redesign.
Standard and modified Denavit–Hartenberg tables are converted to it by :meth:`Arm.from_dh` and
:meth:`Arm.from_modified_dh`. An optional linear ``coupling`` maps the arm coordinates q_a to the joint
motion variables (motion = C q_a), which models parallelogram linkages such as the Manus arm whose
coordinates are absolute link angles (Nait-Chabane eq. 3).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Literal, Sequence

import jax.numpy as jnp
import numpy as np

from mobman import checks
from mobman.engine.kernels import definition
from mobman.errors import ModelError
from mobman.model import spatial
from mobman.model.spatial import IDENTITY, Transform
from mobman.model.visual import Visual

JointKind = Literal["revolute", "prismatic"]


@dataclass(frozen=True)
class LinkInertial:
    """Inertial parameters of the link moved by a joint, in that joint's frame (after its motion).

    mass (kg) > 0; com: centre of mass (m); inertia: 3 × 3 inertia tensor about the centre of mass (kg m²),
    symmetric positive semi-definite, row-major tuple of 9 floats.
    """

    mass: float
    com: tuple[float, float, float] = (0.0, 0.0, 0.0)
    inertia: tuple[float, ...] = (0.0,) * 9

    def __post_init__(self) -> None:
        object.__setattr__(self, "mass", checks.positive(self.mass, "mass", "LinkInertial"))
        object.__setattr__(self, "com", checks.vector3(self.com, "com", "LinkInertial"))
        object.__setattr__(self, "inertia", checks.inertia_tensor(self.inertia, "inertia", "LinkInertial"))

    @property
    def inertia_matrix(self) -> np.ndarray:
        return np.asarray(self.inertia).reshape(3, 3)


@dataclass(frozen=True)
class Joint:
    """One joint: fixed ``origin`` transform from the previous frame, then motion about unit ``axis``.

    The motion variable is ``q + offset`` (radians for revolute, metres for prismatic joints).
    ``lower``/``upper`` bound the coordinate q, ``velocity_max`` bounds |q̇|, ``effort_max`` bounds the
    joint's torque or force (N·m or N). ``visuals`` are the shapes of the link the joint moves, in the joint's
    frame after its motion (for drawing only: they take no part in equality or hashing).
    """

    kind: JointKind = "revolute"
    axis: tuple[float, float, float] = (0.0, 0.0, 1.0)
    origin: Transform = IDENTITY
    offset: float = 0.0
    name: str = ""
    lower: float = -math.inf
    upper: float = math.inf
    velocity_max: float | None = None
    inertial: LinkInertial | None = None
    effort_max: float | None = None
    visuals: tuple[Visual, ...] = field(default=(), compare=False)

    def __post_init__(self) -> None:
        if self.kind not in ("revolute", "prismatic"):
            raise ModelError(
                f"Joint {self.name!r}: kind must be 'revolute' or 'prismatic', got {self.kind!r}"
            )
        axis = np.asarray(self.axis, dtype=float)
        norm = np.linalg.norm(axis)
        if axis.shape != (3,) or not np.isfinite(norm) or norm < 1e-12:
            raise ModelError(f"Joint {self.name!r}: axis must be a non-zero 3-vector, got {self.axis!r}")
        object.__setattr__(self, "axis", tuple(float(v) for v in axis / norm))
        origin = np.asarray(self.origin, dtype=float)
        if origin.size != 16 or not np.all(np.isfinite(origin)):
            raise ModelError(f"Joint {self.name!r}: origin must be a finite 4 × 4 transform")
        object.__setattr__(self, "origin", tuple(float(v) for v in origin.ravel()))
        if not self.lower <= self.upper:
            raise ModelError(
                f"Joint {self.name!r}: lower limit {self.lower} exceeds upper limit {self.upper}"
            )
        if self.velocity_max is not None and not (self.velocity_max > 0):
            raise ModelError(f"Joint {self.name!r}: velocity_max must be > 0, got {self.velocity_max!r}")
        if self.effort_max is not None and not (self.effort_max > 0):
            raise ModelError(f"Joint {self.name!r}: effort_max must be > 0, got {self.effort_max!r}")
        object.__setattr__(self, "visuals", tuple(self.visuals))

    def pose_after(
        self, parent: tuple[jnp.ndarray, jnp.ndarray], q: jnp.ndarray
    ) -> tuple[jnp.ndarray, jnp.ndarray]:
        """World pose (R, p) of the joint frame, from its parent frame's world pose and the joint's motion
        variable q (batched): ``origin`` (R_o, p_o) then the motion by v = q + offset.

        Revolute, with K = [axis]×: R = R_parent R_o exp(v K) (:func:`rodrigues`), p = p_parent + R_parent p_o.
        Prismatic: R = R_parent R_o, p = p_parent + R_parent (p_o + v R_o axis).
        """
        r, p = parent
        r_o, p_o = spatial.fixed_pose(self.origin)
        value = jnp.asarray(q) + self.offset
        p = p + spatial.matvec_constant(r, p_o)
        axis = np.asarray(self.axis)
        if self.kind == "prismatic":
            rotation = spatial.matmul_constant(r, r_o)
            return rotation, p + value[..., None] * spatial.matvec_constant(rotation, axis)
        return spatial.matmul_expanded(r, rodrigues(r_o, spatial.skew(axis), value)), p


@definition
def rodrigues(r_o: np.ndarray, k: np.ndarray, angle: jnp.ndarray) -> jnp.ndarray:
    """R_o exp(θ K), (..., 3, 3), for a constant rotation R_o, the cross-product matrix K = [a]× of a unit
    axis a and angles θ (...): Rodrigues' formula exp(θ K) = I + sin θ K + (1 − cos θ) K²."""
    sin, cos = jnp.sin(angle)[..., None, None], jnp.cos(angle)[..., None, None]
    return jnp.asarray(r_o) @ (jnp.eye(3) + sin * k + (1.0 - cos) * (k @ k))


@dataclass(frozen=True)
class Arm:
    """A serial chain of joints, a tool transform after the last joint, and an optional coupling.

    Parameters
    ----------
    joints: the joints, base to tip.
    tool: fixed transform from the last joint frame to the end-effector frame.
    coupling: optional n_joints × n_joints matrix C (row-major tuple) with motion = C q_a.
    name: a label.
    """

    joints: tuple[Joint, ...]
    tool: Transform = IDENTITY
    coupling: tuple[float, ...] | None = None
    name: str = "arm"

    def __post_init__(self) -> None:
        joints = tuple(self.joints)
        if not joints:
            raise ModelError(f"Arm {self.name!r}: needs at least one joint")
        object.__setattr__(self, "joints", joints)
        object.__setattr__(self, "tool", tuple(float(v) for v in np.asarray(self.tool, dtype=float).ravel()))
        if self.coupling is not None:
            c = np.asarray(self.coupling, dtype=float)
            n = len(joints)
            if c.size != n * n:
                raise ModelError(f"Arm {self.name!r}: coupling must be {n} × {n}, got {c.size} entries")
            if abs(np.linalg.det(c.reshape(n, n))) < 1e-12:
                raise ModelError(f"Arm {self.name!r}: coupling matrix must be invertible")
            object.__setattr__(self, "coupling", tuple(float(v) for v in c.ravel()))

    @property
    def n_joints(self) -> int:
        return len(self.joints)

    @property
    def coordinate_names(self) -> tuple[str, ...]:
        return tuple(j.name or f"q{i + 1}" for i, j in enumerate(self.joints))

    @property
    def coupling_matrix(self) -> np.ndarray:
        n = self.n_joints
        return np.eye(n) if self.coupling is None else np.asarray(self.coupling).reshape(n, n)

    @property
    def velocity_limits(self) -> tuple[float, ...] | None:
        limits = tuple(j.velocity_max for j in self.joints if j.velocity_max is not None)
        return limits if len(limits) == len(self.joints) else None

    @property
    def position_limits(self) -> tuple[tuple[float, float], ...]:
        return tuple((j.lower, j.upper) for j in self.joints)

    def motion_variables(self, q_a: jnp.ndarray) -> jnp.ndarray:
        """Joint motion variables C q_a (without offsets)."""
        if self.coupling is None:
            return q_a
        return spatial.matvec(self.coupling_matrix, q_a)

    def link_poses(
        self, q_a: jnp.ndarray, base: tuple[jnp.ndarray, jnp.ndarray] | None = None
    ) -> tuple[jnp.ndarray, jnp.ndarray]:
        """Poses (R, p) of every joint frame after its motion, then the tool frame.

        Returns R of shape (..., n_joints + 1, 3, 3) and p of shape (..., n_joints + 1, 3), expressed in the
        frame of ``base`` (a pose (R, p) broadcastable to the batch; the arm base frame when None).
        """
        q_a = jnp.asarray(q_a)
        batch = q_a.shape[:-1]
        if base is None:
            base = (jnp.broadcast_to(np.eye(3), batch + (3, 3)), jnp.zeros(batch + (3,)))
        pose, rs, ps = base, [], []
        for joint, v in zip(self.joints, spatial.unstack(self.motion_variables(q_a))):
            r, p = joint.pose_after(pose, v)
            pose = spatial.shared(r), spatial.shared(p)  # read by every later link
            rs.append(pose[0])
            ps.append(pose[1])
        r_tool, p_tool = spatial.compose_fixed_pose(pose, self.tool)
        rs.append(r_tool)
        ps.append(p_tool)
        return jnp.stack(rs, axis=-3), jnp.stack(ps, axis=-2)

    # --- constructors --------------------------------------------------------------------------------

    @classmethod
    def from_dh(
        cls,
        table: Sequence[Sequence[float]],
        kinds: Sequence[JointKind] | str | None = None,
        *,
        tool: Transform = IDENTITY,
        names: Sequence[str] | None = None,
        limits: Sequence[tuple[float, float]] | None = None,
        velocity_limits: Sequence[float] | None = None,
        inertials: Sequence[LinkInertial | None] | None = None,
        coupling: Sequence[float] | None = None,
        name: str = "arm",
    ) -> "Arm":
        """Arm from a standard DH table, rows (θ, d, a, α): T_i = Rz(θ_i) Tz(d_i) Tx(a_i) Rx(α_i).

        For a revolute joint the coordinate adds to θ (θ is the offset); for a prismatic one it adds to d.
        ``kinds`` is a sequence of 'revolute'/'prismatic' or a string such as "RRP" (default: all revolute).
        """
        rows = _table(table, "DH")
        kinds = _kinds(kinds, len(rows))
        joints, previous = [], IDENTITY
        for i, ((theta, d, a, alpha), kind) in enumerate(zip(rows, kinds)):
            if kind == "revolute":
                offset, trailing = theta, spatial.transform(spatial.rot_x(alpha), (a, 0.0, 0.0))
                trailing = spatial.compose_fixed(spatial.transform(None, (0.0, 0.0, d)), trailing)
            else:
                offset = d
                trailing = spatial.compose_fixed(
                    spatial.transform(spatial.rot_z(theta)),
                    spatial.transform(spatial.rot_x(alpha), (a, 0.0, 0.0)),
                )
            joints.append(_joint(i, kind, previous, offset, names, limits, velocity_limits, inertials))
            previous = trailing
        return cls(tuple(joints), spatial.compose_fixed(previous, tool), _coupling(coupling), name)

    @classmethod
    def from_modified_dh(
        cls,
        table: Sequence[Sequence[float]],
        kinds: Sequence[JointKind] | str | None = None,
        *,
        tool: Transform = IDENTITY,
        names: Sequence[str] | None = None,
        limits: Sequence[tuple[float, float]] | None = None,
        velocity_limits: Sequence[float] | None = None,
        inertials: Sequence[LinkInertial | None] | None = None,
        coupling: Sequence[float] | None = None,
        name: str = "arm",
    ) -> "Arm":
        """Arm from a modified (Craig) DH table, rows (α_{i−1}, a_{i−1}, θ_i, d_i):
        T_i = Rx(α_{i−1}) Tx(a_{i−1}) Rz(θ_i) Tz(d_i)."""
        rows = _table(table, "modified DH")
        kinds = _kinds(kinds, len(rows))
        joints = []
        for i, ((alpha, a, theta, d), kind) in enumerate(zip(rows, kinds)):
            base = spatial.transform(spatial.rot_x(alpha), (a, 0.0, 0.0))
            if kind == "revolute":
                origin, offset = spatial.compose_fixed(base, spatial.transform(None, (0.0, 0.0, d))), theta
            else:
                origin, offset = spatial.compose_fixed(base, spatial.transform(spatial.rot_z(theta))), d
            joints.append(_joint(i, kind, origin, offset, names, limits, velocity_limits, inertials))
        return cls(tuple(joints), tool, _coupling(coupling), name)


def _table(table: Sequence[Sequence[float]], label: str) -> list[tuple[float, ...]]:
    rows = [tuple(float(v) for v in row) for row in table]
    if not rows or any(len(r) != 4 for r in rows):
        raise ModelError(f"{label} table: each row needs 4 numbers")
    if not all(math.isfinite(v) for r in rows for v in r):
        raise ModelError(f"{label} table: entries must be finite")
    return rows


def _kinds(kinds: Sequence[JointKind] | str | None, n: int) -> list[JointKind]:
    if kinds is None:
        return ["revolute"] * n
    if isinstance(kinds, str):
        mapping: dict[str, JointKind] = {"R": "revolute", "P": "prismatic"}
        if any(k not in mapping for k in kinds.upper()):
            raise ModelError(f"joint kinds {kinds!r}: use letters R (revolute) and P (prismatic)")
        kinds = [mapping[k] for k in kinds.upper()]
    kinds = list(kinds)
    if len(kinds) != n:
        raise ModelError(f"joint kinds: {len(kinds)} given for {n} joints")
    return kinds


def _joint(
    i: int,
    kind: JointKind,
    origin: Transform,
    offset: float,
    names: Sequence[str] | None,
    limits: Sequence[tuple[float, float]] | None,
    velocity_limits: Sequence[float] | None,
    inertials: Sequence[LinkInertial | None] | None,
) -> Joint:
    lower, upper = (-math.inf, math.inf) if limits is None else limits[i]
    return Joint(
        kind=kind,
        axis=(0.0, 0.0, 1.0),
        origin=origin,
        offset=offset,
        name=names[i] if names is not None else f"q{i + 1}",
        lower=lower,
        upper=upper,
        velocity_max=None if velocity_limits is None else velocity_limits[i],
        inertial=None if inertials is None else inertials[i],
    )


def _coupling(coupling: Sequence[float] | None) -> tuple[float, ...] | None:
    return None if coupling is None else tuple(float(v) for v in np.asarray(coupling, dtype=float).ravel())


__all__ = ["Arm", "Joint", "LinkInertial", "rodrigues"]
