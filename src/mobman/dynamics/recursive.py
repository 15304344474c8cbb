"""Recursive rigid-body algorithms on a mobile manipulator's kinematic tree: the composite-rigid-body
algorithm (CRBA) for the joint-space inertia matrix and the recursive Newton–Euler algorithm (RNEA) for the
inverse dynamics (Featherstone, *Rigid Body Dynamics Algorithms*, Springer 2008: ch. 6, §6.2, Table 6.2 and
ch. 5, §5.3, Table 5.1).

The tree has the platform as its root body, moved by the platform coordinates through the columns of the
root's motion subspace, and one serial chain per arm attached to it. Every spatial quantity is expressed in
one fixed frame: world-aligned, with its origin at the platform's reference point o at the instant (the
"absolute coordinates" form of Featherstone §5.3 and §6.2: no transforms between bodies). In Plücker
coordinates a motion vector is (ω, v_o) and a force vector (n_o, f); a pair (angular, linear) of 3-vectors
here, each batched over the leading axis (one row per joint or column).

In these coordinates a chain's composite inertia is the plain sum of its outer bodies' inertias, a body's
velocity the root's plus the sum of the joint velocities s_k u̇_k of the joints inboard of it, and the
force a joint transmits the sum of the outer bodies' forces: both algorithms are cumulative sums along the
chain, with no sequential loop.

- :class:`RigidInertia` a spatial inertia about o (eq. 2.63), built from a body's mass, centre of mass and
  rotational inertia; :meth:`RigidInertia.apply` the product I v;
- :func:`cross_motion`, :func:`cross_force` the spatial cross products v × m and v ×* f (eq. 2.31–2.32);
- :func:`mass_matrix` the CRBA: H_ij = s_iᵀ I^c_{max(i,j)} s_j along a chain (eq. 6.12–6.13);
- :func:`inverse_dynamics` the RNEA: τ = sᵀ f^c with f = I a + v ×* I v (eq. 5.7–5.11).
"""

from __future__ import annotations

from itertools import accumulate
from typing import NamedTuple, Sequence

import jax
import jax.numpy as jnp
import numpy as np

from mobman.model import spatial


class Motion(NamedTuple):
    """Spatial motion vectors (ω, v_o), each (..., 3): angular velocity and the velocity of the body point
    at o (the columns of a motion subspace, velocities, accelerations)."""

    angular: jnp.ndarray
    linear: jnp.ndarray


class Force(NamedTuple):
    """Spatial force vectors (n_o, f), each (..., 3): moment about o and force."""

    moment: jnp.ndarray
    force: jnp.ndarray


class RigidInertia(NamedTuple):
    """Spatial inertias about o, batched over the leading axis: mass m, first moment h = m c and rotational
    inertia about o, J = Ī + m [c]× [c]×ᵀ, for a body of mass m, centre of mass c (relative to o) and
    rotational inertia Ī about its centre of mass (Featherstone eq. 2.63:
    I = [[Ī + m c× c×ᵀ, m c×], [m c×ᵀ, m 1]]).

    J is held by its three columns J e_k, each (..., 3): a one-configuration program runs its kernels one
    after the other only while every array is at most 512 bytes (:mod:`mobman.engine.batched`), which a stack
    of 3 × 3 matrices over 8 or more bodies (TIAGo's chain, its 11 bodies) exceeds and three stacks of their
    columns do not (up to 21 bodies)."""

    mass: jnp.ndarray
    first_moment: jnp.ndarray
    rotational: tuple[jnp.ndarray, jnp.ndarray, jnp.ndarray]

    @classmethod
    def of_bodies(
        cls, mass: jnp.ndarray, com: jnp.ndarray, inertia: tuple[jnp.ndarray, jnp.ndarray, jnp.ndarray]
    ) -> "RigidInertia":
        """From masses (B,), centres of mass relative to o (B, 3) and the columns of the inertias about them
        (each (B, 3))."""
        square, c = _dot(com, com), spatial.unstack(com)
        unit = np.eye(3)
        rotational = tuple(
            column + mass[:, None] * (square[:, None] * unit[k] - com * c[k][:, None])
            for k, column in enumerate(inertia)
        )
        # every composite inertia and every product with a motion reads these: computed once
        return jax.tree.map(spatial.shared, cls(mass, mass[:, None] * com, rotational))

    def apply(self, v: Motion) -> Force:
        """I v = (J ω + h × v_o, m v_o − h × ω): the momentum of bodies moving with v (row by row)."""
        omega = spatial.unstack(v.angular)
        spin = self.rotational[0] * omega[0][..., None]
        spin = spin + self.rotational[1] * omega[1][..., None] + self.rotational[2] * omega[2][..., None]
        moment = spin + spatial.cross(self.first_moment, v.linear)
        force = self.mass[..., None] * v.linear - spatial.cross(self.first_moment, v.angular)
        return Force(moment, force)

    def total(self) -> "RigidInertia":
        """The sum over the leading axis: the inertia of all these bodies as one."""
        return jax.tree.map(lambda x: jnp.sum(x, axis=0), self)

    def outboard(self) -> "RigidInertia":
        """Composite inertias along a chain, I^c_j = Σ_{k ≥ j} I_k (Featherstone eq. 6.11 in absolute
        coordinates)."""
        return jax.tree.map(_reverse_cumsum, self)


# The sums below are written out over their few terms (3 components, a chain's joints): elementwise
# operations that XLA fuses with their neighbours. Batched, XLA would hand reductions, cumulative sums and
# these tiny dot products to library kernels made for large arrays: written out, the batched P and b of
# TIAGo run 2–3 times faster (benchmarks/real_robots.py), with the same values to round-off.


def _dot(a: jnp.ndarray, b: jnp.ndarray) -> jnp.ndarray:
    """a · b along the last axis (of size 3)."""
    x, y = spatial.unstack(a), spatial.unstack(b)
    return x[0] * y[0] + x[1] * y[1] + x[2] * y[2]


def _cumsum(x: jnp.ndarray) -> jnp.ndarray:
    """Σ_{k ≤ j} x_k along the leading axis."""
    return jnp.stack(list(accumulate(spatial.unstack(x, 0))))


def _reverse_cumsum(x: jnp.ndarray) -> jnp.ndarray:
    """Σ_{k ≥ j} x_k along the leading axis."""
    return jnp.stack(list(accumulate(spatial.unstack(x, 0)[::-1]))[::-1])


def cross_motion(v: Motion, m: Motion) -> Motion:
    """v × m = (ω × ω_m, ω × v_m + v × ω_m) (Featherstone eq. 2.31)."""
    return Motion(
        spatial.cross(v.angular, m.angular),
        spatial.cross(v.angular, m.linear) + spatial.cross(v.linear, m.angular),
    )


def cross_force(v: Motion, f: Force) -> Force:
    """v ×* f = (ω × n + v × f, ω × f) (Featherstone eq. 2.32)."""
    return Force(
        spatial.cross(v.angular, f.moment) + spatial.cross(v.linear, f.force),
        spatial.cross(v.angular, f.force),
    )


def power(m: Motion, f: Force) -> jnp.ndarray:
    """The scalar product mᵀ f = ω · n + v · f, row by row (shape (...,))."""
    return _dot(m.angular, f.moment) + _dot(m.linear, f.force)


def _pairing(a: Motion, f: Force) -> jnp.ndarray:
    """The matrix of a_iᵀ f_j for rows a_i of ``a`` and f_j of ``f``."""
    return _dot(a.angular[:, None, :], f.moment[None, :, :]) + _dot(a.linear[:, None, :], f.force[None, :, :])


class Chain(NamedTuple):
    """One serial chain attached to the root: the motion subspace columns s_j of its joints (n rows) and
    the inertia of the body each joint moves (n rows, a payload included in its link's)."""

    axes: Motion
    inertia: RigidInertia


def mass_matrix(root_axes: Motion, root_inertia: RigidInertia, chains: Sequence[Chain]) -> jnp.ndarray:
    """The joint-space inertia matrix H of the tree by the CRBA (Featherstone §6.2, eq. 6.12–6.13):

        H_ij = s_iᵀ I^c_j s_j for i inboard of (or equal to) j,   H_ji = H_ij,   0 for joints on different chains,

    with I^c_j the composite inertia of all bodies outboard of joint j (for a root column: of the whole tree).
    ``root_axes``: the k columns of the root's motion subspace; ``root_inertia``: the root bodies (summed).
    Returns H, (k + Σ n) square, in the order root columns, chain 0, chain 1, …
    """
    total = root_inertia.total()
    composites = [chain.inertia.outboard() for chain in chains]
    for composite in composites:
        total = jax.tree.map(lambda a, b: a + b[0], total, composite)
    axes = Motion(*(jnp.concatenate(x) for x in zip(root_axes, *(chain.axes for chain in chains))))
    f = [total.apply(root_axes)] + [c.apply(chain.axes) for c, chain in zip(composites, chains)]
    g = _pairing(axes, Force(*(jnp.concatenate(x) for x in zip(*f))))  # g[i, j] = s_iᵀ I^c_j s_j
    inboard = _inboard(root_axes.angular.shape[0], [chain.axes.angular.shape[0] for chain in chains])
    return jnp.where(inboard, g, jnp.where(inboard.T, g.T, 0.0))


def _inboard(k: int, sizes: Sequence[int]) -> np.ndarray:
    """inboard[i, j]: column i is the root's or a joint of j's chain at or before j (i ∈ κ(j) ∪ {j})."""
    n = k + sum(sizes)
    out = np.zeros((n, n), dtype=bool)
    out[:k, :] = True
    start = k
    for size in sizes:
        out[start : start + size, start : start + size] = np.triu(np.ones((size, size), dtype=bool))
        start += size
    return out


def inverse_dynamics(
    root_axes: Motion,
    root_inertia: RigidInertia,
    root_velocity: Motion,
    root_acceleration: Motion,
    chains: Sequence[Chain],
    rates: Sequence[jnp.ndarray],
    accelerations: Sequence[jnp.ndarray],
) -> tuple[jnp.ndarray, list[jnp.ndarray]]:
    """The generalized forces of a motion by the RNEA (Featherstone §5.3, Table 5.1, eq. 5.7–5.11):

        v_j = v_root + Σ_{k ≤ j} s_k u̇_k,   a_j = a_root + Σ_{k ≤ j} (s_k ü_k + v_k × s_k u̇_k),
        f_j = I_j a_j + v_j ×* I_j v_j,      τ_j = s_jᵀ Σ_{k ≥ j} f_k,

    the velocity-product term ṡ_k = v_k × s_k of an axis fixed in a moving body (eq. 5.8 in absolute
    coordinates). ``root_velocity``, ``root_acceleration``: the root body's (gravity enters as a fictitious
    acceleration −a_g of the root, §5.3); ``rates``, ``accelerations``: u̇, ü of each chain's joints.
    Returns (root generalized forces, one per column of ``root_axes``; per chain its joint forces τ).
    """
    total = root_inertia.total()
    f_root = _body_force(total, root_velocity, root_acceleration)
    taus = []
    for chain, u_dot, u_ddot in zip(chains, rates, accelerations):
        joint_v = Motion(*(x * u_dot[:, None] for x in chain.axes))
        v = Motion(*(r + _cumsum(x) for r, x in zip(root_velocity, joint_v)))
        terms = cross_motion(v, joint_v)
        a = Motion(
            *(r + _cumsum(s * u_ddot[:, None] + t) for r, s, t in zip(root_acceleration, chain.axes, terms))
        )
        composite = Force(*(_reverse_cumsum(x) for x in _body_force(chain.inertia, v, a)))
        taus.append(power(chain.axes, composite))
        f_root = Force(*(r + x[0] for r, x in zip(f_root, composite)))
    return power(root_axes, Force(*(x[None, :] for x in f_root))), taus


def _body_force(inertia: RigidInertia, v: Motion, a: Motion) -> Force:
    """f = I a + v ×* I v (Featherstone eq. 5.9), computed once for the composite forces that read it."""
    return Force(*(spatial.shared(x + y) for x, y in zip(inertia.apply(a), cross_force(v, inertia.apply(v)))))


__all__ = [
    "Chain",
    "Force",
    "Motion",
    "RigidInertia",
    "cross_force",
    "cross_motion",
    "inverse_dynamics",
    "mass_matrix",
    "power",
]
