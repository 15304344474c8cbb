"""Several arms rigidly holding one object: grasp matrix and object dynamics (Yamamoto & Yun eq. 17–22).

The object's reference point is its centre of mass. Arm i holds it rigidly at a grasp point whose offset
from the centre of mass, in world axes, is r_i. With h_i the wrench that end effector i applies to the object
(force, then moment, at the grasp point) and h = [h_1; h_2; …] (eq. 18), the net wrench at the centre of mass
is h_o = W h (eq. 17) with W = [W_1 W_2 …] (eq. 19) and

    spatial (m = 6):  W_i = [[I₃, 0], [[r_i]×, I₃]]       planar (m = 3):  W_i = [[1, 0, 0], [0, 1, 0], [−r_iy, r_ix, 1]].

By virtual work the end-effector velocities are v = Wᵀ v_o (eq. 20): v_i = (ṗ_o + ω_o × r_i, ω_o); differentiating,
a = Wᵀ a_o + Ẇᵀ v_o (eq. 21), where ṙ_i = ω_o × r_i for a rigid grasp. The object obeys
M_o a_o + c_o + g_o = h_o (eq. 22) with M_o = diag(m I, I_o), c_o = (0, ω × I_o ω), g_o = (−m g, 0).

Planar quantities are (x, y, angle) components: force (f_x, f_y, n_z), velocity (ẋ, ẏ, ω_z), the components
that the planar tasks ``Position("xy") + PlanarAngle()`` measure.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import jax
import jax.numpy as jnp
import numpy as np
import numpy.typing as npt

from mobman import checks
from mobman.engine.batched import traced
from mobman.errors import InputError


def _offsets(offsets: npt.ArrayLike) -> jnp.ndarray:
    """Grasp offsets checked at the public functions' boundary (a user's traced value passes; mobman's own
    traced code calls the ``_one`` functions)."""
    r: jax.Array | np.ndarray
    if traced(offsets):
        r = offsets
    else:
        try:
            r = np.asarray(offsets, dtype=float)
        except (TypeError, ValueError):
            raise InputError(f"grasp offsets: expected numbers, got {type(offsets).__name__}") from None
        if not np.isfinite(r).all():
            raise InputError("grasp offsets: every component must be finite")
    if r.ndim < 2 or r.shape[-1] not in (2, 3) or r.shape[-2] == 0:
        raise InputError(
            f"grasp offsets: expected shape (..., k, 2) or (..., k, 3) with k ≥ 1, got {r.shape}"
        )
    return jnp.asarray(r)


def _cross_rows(r: jnp.ndarray) -> jnp.ndarray:
    """[r]× for stacks of 3-vectors, shape (..., 3, 3)."""
    x, y, z = r[..., 0], r[..., 1], r[..., 2]
    zero = jnp.zeros_like(x)
    return jnp.stack(
        [jnp.stack([zero, -z, y], -1), jnp.stack([z, zero, -x], -1), jnp.stack([-y, x, zero], -1)], -2
    )


def grasp_matrix(offsets: npt.ArrayLike) -> jnp.ndarray:
    """Grasp matrix W = [W_1 … W_k] with h_o = W h (eq. 17–19), batched over leading dimensions.

    ``offsets``: (..., k, 2) planar or (..., k, 3) spatial grasp-point offsets r_i from the object's centre of
    mass, in world axes. Returns (..., 3, 3k) planar or (..., 6, 6k) spatial.
    """
    return grasp_matrix_one(_offsets(offsets))


def grasp_matrix_one(r: jax.Array) -> jnp.ndarray:
    """:func:`grasp_matrix` of offsets r (..., k, 2 or 3), unvalidated: for traced code."""
    batch, k, d = r.shape[:-2], r.shape[-2], r.shape[-1]
    if d == 2:
        eye = jnp.broadcast_to(jnp.eye(2), batch + (k, 2, 2))
        top = jnp.concatenate([eye, jnp.zeros(batch + (k, 2, 1))], axis=-1)
        bottom = jnp.stack([-r[..., 1], r[..., 0], jnp.ones_like(r[..., 0])], axis=-1)[..., None, :]
        blocks = jnp.concatenate([top, bottom], axis=-2)  # (..., k, 3, 3)
    else:
        eye = jnp.broadcast_to(jnp.eye(3), batch + (k, 3, 3))
        top = jnp.concatenate([eye, jnp.zeros(batch + (k, 3, 3))], axis=-1)
        bottom = jnp.concatenate([_cross_rows(r), eye], axis=-1)
        blocks = jnp.concatenate([top, bottom], axis=-2)  # (..., k, 6, 6)
    m = blocks.shape[-1]
    return jnp.moveaxis(blocks, -3, -2).reshape(batch + (m, k * m))


def grasp_matrix_rate(offsets: npt.ArrayLike, omega: npt.ArrayLike) -> jnp.ndarray:
    """Ẇ for a rigid grasp (eq. 21): the offsets turn with the object, ṙ_i = ω_o × r_i.

    ``omega``: the object's angular velocity, (...,) planar (about the vertical) or (..., 3) spatial.
    Returns the time derivative of :func:`grasp_matrix`, same shape.
    """
    return grasp_matrix_rate_one(_offsets(offsets), jnp.asarray(omega, dtype=float))


def grasp_matrix_rate_one(r: jax.Array, omega: jax.Array) -> jnp.ndarray:
    """:func:`grasp_matrix_rate`, unvalidated: for traced code. W is affine in r, so Ẇ = W(ṙ) − W(0)."""
    if r.shape[-1] == 2:
        r_dot = omega[..., None, None] * jnp.stack([-r[..., 1], r[..., 0]], axis=-1)
    else:
        r_dot = jnp.cross(omega[..., None, :], r)
    return grasp_matrix_one(r_dot) - grasp_matrix_one(jnp.zeros_like(r_dot))


def internal_force_basis(w: jnp.ndarray | np.ndarray) -> jnp.ndarray:
    """Orthonormal basis of null(W), shape (..., mk, mk − m): the internal (squeeze) wrenches, which leave the
    object's net wrench unchanged. Assumes W of full row rank, as every W of :func:`grasp_matrix` is."""
    if not traced(w):
        w = np.asarray(w, dtype=float)
        if w.ndim < 2 or w.shape[-2] > w.shape[-1] or not np.isfinite(w).all():
            raise InputError(
                f"internal_force_basis: W must be a finite (..., m, n) matrix with m ≤ n, got {w.shape}"
            )
    _, _, vt = jnp.linalg.svd(w, full_matrices=True)
    return jnp.swapaxes(vt[..., w.shape[-2] :, :], -1, -2)


@dataclass(frozen=True)
class HeldObject:
    """A rigid object held by the arms (Yamamoto & Yun §2.2): mass (kg) and inertia tensor about its centre
    of mass (kg m², 9 values row-major, or 3 diagonal values, in world axes for the configuration considered;
    for planar motion only the vertical component I_zz matters).

    The centre of mass is the centroid of the arms' tool points (see :func:`mobman.dynamics.ellipsoids`).
    """

    mass: float
    inertia: tuple[float, ...] = (0.0,) * 9

    def __post_init__(self) -> None:
        object.__setattr__(self, "mass", checks.positive(self.mass, "mass", "HeldObject"))
        object.__setattr__(self, "inertia", checks.inertia_tensor(self.inertia, "inertia", "HeldObject"))

    @property
    def inertia_matrix(self) -> np.ndarray:
        return np.asarray(self.inertia).reshape(3, 3)

    def mass_matrix(self, planar: bool = True) -> np.ndarray:
        """M_o of eq. 22: diag(m, m, I_zz) (planar) or diag(m I₃, I_o) (spatial)."""
        if planar:
            return np.diag([self.mass, self.mass, self.inertia_matrix[2, 2]])
        out = np.zeros((6, 6))
        out[:3, :3] = self.mass * np.eye(3)
        out[3:, 3:] = self.inertia_matrix
        return out

    def bias(self, v_o: jax.Array, gravity: Sequence[float] = (0.0, 0.0, -9.81)) -> jnp.ndarray:
        """c_o + g_o of eq. 22 for object velocities ``v_o`` (..., 3) planar or (..., 6) spatial.

        c_o = (0, ω × I_o ω) (zero in the plane), g_o = (−m g, 0): the wrench that holds the object against
        gravity. Planar motion takes the horizontal components of g.
        """
        v_o = jnp.asarray(v_o, dtype=float)
        g = np.asarray(gravity, dtype=float)
        if v_o.shape[-1] == 3:
            return jnp.broadcast_to(jnp.array([-self.mass * g[0], -self.mass * g[1], 0.0]), v_o.shape)
        if v_o.shape[-1] != 6:
            raise InputError(
                f"HeldObject.bias: v_o needs 3 (planar) or 6 (spatial) components, got {v_o.shape}"
            )
        omega = v_o[..., 3:]
        gyro = jnp.cross(omega, omega @ self.inertia_matrix.T)
        return jnp.concatenate([jnp.broadcast_to(-self.mass * g, omega.shape), gyro], axis=-1)
