"""Grasp matrix and held-object dynamics (Yamamoto & Yun eq. 17–22) against rigid-body motion by autodiff."""

from __future__ import annotations

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import mobman  # noqa: F401  (float64)
from mobman.dynamics.grasp import (
    HeldObject,
    grasp_matrix,
    grasp_matrix_one,
    grasp_matrix_rate,
    grasp_matrix_rate_one,
    internal_force_basis,
)
from mobman.errors import InputError, ModelError

RNG = np.random.default_rng(7)


def _rotation(angles):
    """R_z(a) R_y(b) R_x(c), differentiable."""
    a, b, c = angles
    rz = jnp.array([[jnp.cos(a), -jnp.sin(a), 0.0], [jnp.sin(a), jnp.cos(a), 0.0], [0.0, 0.0, 1.0]])
    ry = jnp.array([[jnp.cos(b), 0.0, jnp.sin(b)], [0.0, 1.0, 0.0], [-jnp.sin(b), 0.0, jnp.cos(b)]])
    rx = jnp.array([[1.0, 0.0, 0.0], [0.0, jnp.cos(c), -jnp.sin(c)], [0.0, jnp.sin(c), jnp.cos(c)]])
    return rz @ ry @ rx


def test_net_wrench_is_sum_of_forces_and_moments():
    """h_o = W h (eq. 17): net force Σ f_i and net moment Σ (r_i × f_i + n_i) about the centre of mass."""
    r = RNG.normal(size=(3, 3))
    h = RNG.normal(size=(3, 6))
    expected = np.concatenate([h[:, :3].sum(0), (np.cross(r, h[:, :3]) + h[:, 3:]).sum(0)])
    np.testing.assert_allclose(grasp_matrix(r) @ h.ravel(), expected, atol=1e-12)


def test_planar_grasp_matrix_is_the_planar_slice_of_the_spatial_one():
    r2 = RNG.normal(size=(2, 2))
    r3 = np.concatenate([r2, np.zeros((2, 1))], axis=1)
    w3 = np.asarray(grasp_matrix(r3))
    rows = [0, 1, 5]
    cols = [c + 6 * k for k in range(2) for c in rows]
    np.testing.assert_allclose(grasp_matrix(r2), w3[np.ix_(rows, cols)], atol=1e-15)


def test_velocities_and_accelerations_of_rigidly_attached_points():
    """v = Wᵀ v_o (eq. 20) and a = Wᵀ a_o + Ẇᵀ v_o (eq. 21) against the motion p_o(t) + R(t) r_i⁰, by autodiff."""
    r0 = RNG.normal(size=(2, 3))
    c0, c1, c2 = (RNG.normal(size=3) for _ in range(3))
    e0, e1, e2 = (RNG.normal(size=3) for _ in range(3))

    def rot(t):
        return _rotation(e0 + e1 * t + e2 * t**2)

    def points(t):
        return (c0 + c1 * t + c2 * t**2) + jnp.einsum("ij,kj->ki", rot(t), r0)

    t = 0.3
    rd = jax.jacfwd(rot)(t)
    omega_hat = rd @ rot(t).T
    omega = jnp.array([omega_hat[2, 1], omega_hat[0, 2], omega_hat[1, 0]])
    alpha = jax.jacfwd(
        lambda s: (lambda m: jnp.array([m[2, 1], m[0, 2], m[1, 0]]))(jax.jacfwd(rot)(s) @ rot(s).T)
    )(t)
    p_dot = c1 + 2 * c2 * t
    p_ddot = 2 * c2
    r = points(t) - (c0 + c1 * t + c2 * t**2)
    w = grasp_matrix(r)
    v_o = jnp.concatenate([p_dot, omega])
    a_o = jnp.concatenate([p_ddot, alpha])
    v = (w.T @ v_o).reshape(2, 6)
    np.testing.assert_allclose(v[:, :3], jax.jacfwd(points)(t), atol=1e-10)
    np.testing.assert_allclose(v[:, 3:], np.broadcast_to(omega, (2, 3)), atol=1e-10)
    a = (w.T @ a_o + grasp_matrix_rate(r, omega).T @ v_o).reshape(2, 6)
    np.testing.assert_allclose(a[:, :3], jax.jacfwd(jax.jacfwd(points))(t), atol=1e-9)
    np.testing.assert_allclose(a[:, 3:], np.broadcast_to(alpha, (2, 3)), atol=1e-10)


def test_planar_rate_matches_finite_difference_of_turning_offsets():
    r0 = RNG.normal(size=(2, 2))
    omega, dt = 0.7, 1e-6

    def offsets(t):
        c, s = np.cos(omega * t), np.sin(omega * t)
        return r0 @ np.array([[c, s], [-s, c]])

    fd = (np.asarray(grasp_matrix(offsets(dt))) - np.asarray(grasp_matrix(offsets(-dt)))) / (2 * dt)
    np.testing.assert_allclose(grasp_matrix_rate(r0, omega), fd, atol=1e-8)


def test_grasp_matrix_is_batched():
    r = RNG.normal(size=(4, 5, 2, 2))
    w = np.asarray(grasp_matrix(r))
    assert w.shape == (4, 5, 3, 6)
    np.testing.assert_allclose(w[2, 3], grasp_matrix(r[2, 3]))


def test_internal_forces_do_not_move_the_object():
    w = grasp_matrix(RNG.normal(size=(2, 2)))
    basis = np.asarray(internal_force_basis(w))
    assert basis.shape == (6, 3)
    np.testing.assert_allclose(w @ basis, 0.0, atol=1e-12)
    np.testing.assert_allclose(basis.T @ basis, np.eye(3), atol=1e-12)


def test_object_dynamics_gravity_and_gyroscopic_terms():
    """Eq. 22: the grasp holds the object against gravity with h = W⁺ g_o; c_o = ω × I ω (Euler)."""
    obj = HeldObject(2.0, (0.1, 0.2, 0.3))
    np.testing.assert_allclose(obj.bias(np.zeros(6)), [0, 0, 2 * 9.81, 0, 0, 0], atol=1e-12)
    w = grasp_matrix(RNG.normal(size=(2, 3)))
    h = np.linalg.pinv(w) @ obj.bias(np.zeros(6))
    np.testing.assert_allclose(w @ h, obj.bias(np.zeros(6)), atol=1e-12)
    omega = np.array([1.0, -2.0, 0.5])
    gyro = np.asarray(obj.bias(np.concatenate([np.zeros(3), omega]), gravity=(0, 0, 0)))[3:]
    inertia = np.diag([0.1, 0.2, 0.3])
    np.testing.assert_allclose(gyro, np.cross(omega, inertia @ omega), atol=1e-12)
    # horizontal motion: no gravity in the planar components, M_o = diag(m, m, I_zz)
    np.testing.assert_allclose(obj.bias(np.ones(3)), 0.0)
    np.testing.assert_allclose(obj.mass_matrix(), np.diag([2.0, 2.0, 0.3]))


@pytest.mark.parametrize(
    "kwargs, field",
    [
        ({"mass": 0.0}, "mass"),
        ({"mass": float("nan")}, "mass"),
        ({"mass": 1.0, "inertia": (1.0, -1.0, 1.0)}, "inertia"),
        ({"mass": 1.0, "inertia": (0, 1, 0, 0, 0, 0, 0, 0, 0)}, "inertia"),
        ({"mass": 1.0, "inertia": (1.0, 2.0)}, "inertia"),
    ],
)
def test_invalid_object_names_the_field(kwargs, field):
    with pytest.raises(ModelError, match=field):
        HeldObject(**kwargs)


def test_bad_offsets_shape():
    with pytest.raises(InputError, match="offsets"):
        grasp_matrix(np.zeros((2, 4)))


@pytest.mark.parametrize("d", [2, 3])
def test_traced_code_calls_the_plain_functions_with_the_same_values(d):
    """The ``_one`` functions (for jit, grad, vmap) give the public functions' values; the public functions
    check their input at the boundary."""
    r = RNG.normal(size=(4, 2, d))
    omega = RNG.normal(size=(4,) if d == 2 else (4, 3))
    np.testing.assert_array_equal(jax.jit(grasp_matrix_one)(r), grasp_matrix(r))
    np.testing.assert_array_equal(jax.jit(grasp_matrix_rate_one)(r, omega), grasp_matrix_rate(r, omega))
    np.testing.assert_array_equal(jax.jit(grasp_matrix)(r), grasp_matrix(r))  # a user's own jit
    r[1, 0, 0] = np.nan
    with pytest.raises(InputError, match="finite"):
        grasp_matrix(r)
