"""Rigid transforms in SE(3) as (R, p) pairs.

Poses are kept as a rotation ``R`` (..., 3, 3) and a translation ``p`` (..., 3) rather than 4 × 4
matrices. The products of the kinematic model are plain definitions (``a @ b``); the engine runs them
written out for XLA (:mod:`mobman.engine.products`, registered with :mod:`mobman.engine.kernels`).

Fixed transforms of a robot description are stored as hashable tuples (16 floats, row-major 4 × 4) so
that robot models can be static arguments of :func:`jax.jit`.
"""

from __future__ import annotations

from typing import Sequence

import jax.numpy as jnp
import numpy as np

from mobman.engine.kernels import definition
from mobman.errors import ModelError

Transform = tuple[float, ...]
"""A fixed homogeneous transform, row-major 4 × 4 flattened to 16 floats (hashable)."""

IDENTITY: Transform = tuple(float(v) for v in np.eye(4).ravel())


def transform(
    rotation: np.ndarray | None = None, translation: Sequence[float] = (0.0, 0.0, 0.0)
) -> Transform:
    """Build a hashable fixed transform from a rotation matrix and a translation."""
    matrix = np.eye(4)
    if rotation is not None:
        matrix[:3, :3] = np.asarray(rotation, dtype=float)
    matrix[:3, 3] = np.asarray(translation, dtype=float)
    return tuple(float(v) for v in matrix.ravel())


def as_matrix(t: Transform) -> np.ndarray:
    """The 4 × 4 NumPy matrix of a stored transform."""
    return np.asarray(t, dtype=float).reshape(4, 4)


def compose_fixed(*ts: Transform) -> Transform:
    """Product of fixed transforms, left to right."""
    out = np.eye(4)
    for t in ts:
        out = out @ as_matrix(t)
    return tuple(float(v) for v in out.ravel())


def rot_x(a: float) -> np.ndarray:
    c, s = np.cos(a), np.sin(a)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def rot_y(a: float) -> np.ndarray:
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def rot_z(a: float) -> np.ndarray:
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def skew(v: np.ndarray) -> np.ndarray:
    """The cross-product matrix [v]× of a constant 3-vector (NumPy)."""
    x, y, z = np.asarray(v, dtype=float)
    return np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])


# --- batched JAX operations on (R, p) poses ------------------------------------------------------


def matmul(a: jnp.ndarray, b: jnp.ndarray) -> jnp.ndarray:
    """a @ b for stacks of small matrices, as a broadcast product and sum: one reduction, which XLA fuses
    with what produces and uses it (the control laws' algebra at one configuration: pseudo-inverses,
    projectors, stage sums)."""
    return jnp.sum(a[..., :, :, None] * b[..., None, :, :], axis=-2)


@definition
def matmul_expanded(a: jnp.ndarray, b: jnp.ndarray) -> jnp.ndarray:
    """a @ b for stacks of small matrices: the kinematic model's products (a chain's rotations, Jacobian
    rows, Gram matrices). The engine runs it as a sum of outer products (:mod:`mobman.engine.products`)."""
    return a @ b


def matvec(a: jnp.ndarray | np.ndarray, v: jnp.ndarray | np.ndarray) -> jnp.ndarray:
    """a @ v for stacks of small matrices and vectors."""
    return jnp.sum(a * v[..., None, :], axis=-1)


@definition
def matvec_constant(a: jnp.ndarray, v: np.ndarray) -> jnp.ndarray:
    """a @ v for stacks of matrices a and a constant NumPy vector v (a robot's fixed offsets)."""
    return a @ jnp.asarray(v, dtype=a.dtype)


@definition
def matmul_constant(a: jnp.ndarray, c: np.ndarray) -> jnp.ndarray:
    """a @ c for stacks of matrices a and a constant NumPy matrix c (a robot's fixed rotations)."""
    return a @ jnp.asarray(c, dtype=a.dtype)


@definition
def unstack(a: jnp.ndarray, axis: int = -1) -> list[jnp.ndarray]:
    """The components of a along ``axis``: [a[..., 0], a[..., 1], …] for the last axis."""
    return list(jnp.moveaxis(a, axis, 0))


@definition
def shared(x: jnp.ndarray) -> jnp.ndarray:
    """x itself: marks a value that many later values read, such as the pose of a link of a chain (every
    pose after it and every column of a Jacobian reads it). The engine's drop-in has a batched program
    compute it once instead of once per reader (:mod:`mobman.engine.fusion`)."""
    return x


@definition
def rows(x: jnp.ndarray, indices: tuple[int, ...]) -> jnp.ndarray:
    """The rows ``indices`` (static) of x: x[indices] (a task's components, a tree's bodies)."""
    return x[jnp.asarray(indices, dtype=int)]


@definition
def cross(a: jnp.ndarray, b: jnp.ndarray, axis: int = -1) -> jnp.ndarray:
    """Cross product along ``axis`` (the last by default; 0 for the columns of 3 × n matrices)."""
    return jnp.cross(a, b, axis=axis)


def compose_fixed_pose(
    pose: tuple[jnp.ndarray, jnp.ndarray], t: Transform
) -> tuple[jnp.ndarray, jnp.ndarray]:
    """(R, p) ∘ T for a stored fixed transform T = (R_t, p_t): (R R_t, R p_t + p)."""
    r, p = pose
    r_t, p_t = fixed_pose(t)
    return matmul_constant(r, r_t), p + matvec_constant(r, p_t)


def fixed_pose(t: Transform) -> tuple[np.ndarray, np.ndarray]:
    """(R, p) of a stored fixed transform, as NumPy constants."""
    m = as_matrix(t)
    return m[:3, :3], m[:3, 3]


def planar_pose(x: jnp.ndarray, y: jnp.ndarray, theta: jnp.ndarray) -> tuple[jnp.ndarray, jnp.ndarray]:
    """(R, p) of a frame at (x, y, 0) rotated by theta about the vertical axis."""
    c, s = jnp.cos(theta), jnp.sin(theta)
    zero, one = jnp.zeros_like(c), jnp.ones_like(c)
    r = jnp.stack(
        [jnp.stack([c, -s, zero], -1), jnp.stack([s, c, zero], -1), jnp.stack([zero, zero, one], -1)], -2
    )
    p = jnp.stack([x, y, jnp.zeros_like(x)], -1)
    return r, p


# --- orientation coordinates -----------------------------------------------------------------------

EULER_SEQUENCES = ("ZYZ", "ZYX", "XYZ", "ZXZ", "ZXY")


def euler_angles(r: jnp.ndarray, sequence: str) -> jnp.ndarray:
    """Euler angles (a1, a2, a3) of rotation matrices r = R_{s1}(a1) R_{s2}(a2) R_{s3}(a3).

    Supported sequences: ``ZYZ`` (θ in [0, π]), ``ZYX`` (yaw, pitch, roll; pitch in [−π/2, π/2]), ``XYZ``,
    ``ZXZ`` and ``ZXY`` (yaw, roll, pitch: the pitch about the frame's own y axis covers (−π, π]). The
    representation is singular where the middle angle is at the end of its range (gimbal lock, see
    :func:`gimbal_margin`): operational coordinates are local variables (Bayle §2). The middle angle of ZYX,
    XYZ and ZXY is atan2(s, c) with c = the margin ≥ 0, not arcsin(s): the same value, and a derivative that
    stays accurate up to the gimbal lock (arcsin's 1/√(1 − s²) loses every digit once 1 − s² is near the
    float64 epsilon, a margin of about 1e-8).
    """
    if sequence == "ZYZ":
        a1 = jnp.arctan2(r[..., 1, 2], r[..., 0, 2])
        a2 = jnp.arctan2(jnp.hypot(r[..., 0, 2], r[..., 1, 2]), r[..., 2, 2])
        a3 = jnp.arctan2(r[..., 2, 1], -r[..., 2, 0])
    elif sequence == "ZXZ":
        a1 = jnp.arctan2(r[..., 0, 2], -r[..., 1, 2])
        a2 = jnp.arctan2(jnp.hypot(r[..., 0, 2], r[..., 1, 2]), r[..., 2, 2])
        a3 = jnp.arctan2(r[..., 2, 0], r[..., 2, 1])
    elif sequence == "ZYX":
        a1 = jnp.arctan2(r[..., 1, 0], r[..., 0, 0])
        a2 = jnp.arctan2(-r[..., 2, 0], jnp.hypot(r[..., 0, 0], r[..., 1, 0]))
        a3 = jnp.arctan2(r[..., 2, 1], r[..., 2, 2])
    elif sequence == "XYZ":
        a1 = jnp.arctan2(-r[..., 1, 2], r[..., 2, 2])
        a2 = jnp.arctan2(r[..., 0, 2], jnp.hypot(r[..., 1, 2], r[..., 2, 2]))
        a3 = jnp.arctan2(-r[..., 0, 1], r[..., 0, 0])
    elif sequence == "ZXY":
        a1 = jnp.arctan2(-r[..., 0, 1], r[..., 1, 1])
        a2 = jnp.arctan2(r[..., 2, 1], jnp.hypot(r[..., 0, 1], r[..., 1, 1]))
        a3 = jnp.arctan2(-r[..., 2, 0], r[..., 2, 2])
    else:
        raise ModelError(f"unknown Euler sequence {sequence!r}; allowed: {', '.join(EULER_SEQUENCES)}")
    return jnp.stack([a1, a2, a3], axis=-1)


_GIMBAL_ENTRIES = {
    "ZYZ": ((0, 2), (1, 2)),
    "ZXZ": ((0, 2), (1, 2)),
    "ZYX": ((0, 0), (1, 0)),
    "XYZ": ((1, 2), (2, 2)),
    "ZXY": ((0, 1), (1, 1)),
}


def gimbal_margin(r: jnp.ndarray, sequence: str) -> jnp.ndarray:
    """|sin| (ZYZ, ZXZ) or |cos| (the others) of the middle Euler angle of rotation matrices r, shape (...).

    It is the norm of the pair of entries whose atan2 gives the first angle: where it vanishes (gimbal lock)
    the first and third angles are undefined and their derivatives unbounded, as 1 / margin.
    """
    (i0, j0), (i1, j1) = _GIMBAL_ENTRIES[sequence]
    return jnp.hypot(r[..., i0, j0], r[..., i1, j1])


def euler_matrix(angles: np.ndarray, sequence: str) -> np.ndarray:
    """Rotation matrix of Euler angles (NumPy; used for checks and for building fixed frames)."""
    rots = {"X": rot_x, "Y": rot_y, "Z": rot_z}
    out = np.eye(3)
    for axis, a in zip(sequence, angles):
        out = out @ rots[axis](a)
    return out
