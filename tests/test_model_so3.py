"""mobman.model.so3: hat, vee, exp, log and error against SciPy's rotations and closed forms, over the whole
range of angles (0, tiny, π/2, just below π and exactly π), with derivatives against central differences."""

from __future__ import annotations

import math

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from mobman.model import so3

SPECIAL_ANGLES = (0.0, 1e-12, 1e-9, 1e-6, 1e-3, 0.5, math.pi / 2, 2.0, 3.0, math.pi - 1e-6, math.pi - 1e-9)
"""Angles (θ = ‖r‖) where a branch of exp or log switches or the formulas lose digits; π is tested apart."""


def _axes(n: int, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    axes = rng.normal(size=(n, 3))
    return axes / np.linalg.norm(axes, axis=1, keepdims=True)


_SIGNED_AXES = np.concatenate([np.eye(3), -np.eye(3), [[1.0, 1.0, 0.0], [0.0, -1.0, 1.0], [1.0, 1.0, 1.0]]])
COORDINATE_AXES = _SIGNED_AXES / np.linalg.norm(_SIGNED_AXES, axis=1, keepdims=True)
"""±x, ±y, ±z, then three axes with two or three equal largest components (ties of the axis pick in log)."""


def _rotation_vectors() -> np.ndarray:
    """Random and coordinate axes (with signs) at every special angle, plus random angles in [0, π)."""
    axes = np.concatenate([_axes(7, 0), COORDINATE_AXES])
    special = (axes[:, None, :] * np.asarray(SPECIAL_ANGLES)[None, :, None]).reshape(-1, 3)
    rng = np.random.default_rng(1)
    uniform = _axes(64, 2) * rng.uniform(0.0, math.pi, size=(64, 1))
    return np.concatenate([special, uniform])


R = _rotation_vectors()
ANGLES = np.linalg.norm(R, axis=1)


def _skew(v: np.ndarray) -> np.ndarray:
    x, y, z = v
    return np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])


def test_hat_is_the_cross_product_matrix():
    rng = np.random.default_rng(3)
    v, w = rng.normal(size=(2, 4, 5, 3))
    k = np.asarray(so3.hat(jnp.asarray(v)))
    assert k.shape == (4, 5, 3, 3)
    np.testing.assert_allclose(np.einsum("...ij,...j->...i", k, w), np.cross(v, w), rtol=0, atol=1e-14)
    np.testing.assert_array_equal(k, -np.swapaxes(k, -1, -2))
    np.testing.assert_array_equal(k[1, 2], _skew(v[1, 2]))


def test_vee_is_the_vector_of_the_skew_part():
    rng = np.random.default_rng(4)
    a = rng.normal(size=(6, 3, 3))
    got = np.asarray(so3.vee(jnp.asarray(a)))
    skew = 0.5 * (a - np.swapaxes(a, -1, -2))
    np.testing.assert_allclose(got, np.stack([skew[:, 2, 1], skew[:, 0, 2], skew[:, 1, 0]], -1), atol=1e-15)
    # the symmetric part has no vector; vee inverts hat
    np.testing.assert_array_equal(np.asarray(so3.vee(jnp.asarray(a + np.swapaxes(a, -1, -2)))), 0.0)
    v = rng.normal(size=(6, 3))
    np.testing.assert_allclose(np.asarray(so3.vee(so3.hat(jnp.asarray(v)))), v, rtol=0, atol=1e-15)


def test_exp_matches_scipy_at_every_angle():
    got = np.asarray(so3.exp(R))
    np.testing.assert_allclose(got, Rotation.from_rotvec(R).as_matrix(), rtol=0, atol=3e-15)
    # a rotation: orthonormal with determinant +1
    np.testing.assert_allclose(
        got @ np.swapaxes(got, -1, -2), np.broadcast_to(np.eye(3), got.shape), atol=3e-15
    )
    np.testing.assert_allclose(np.linalg.det(got), 1.0, rtol=0, atol=3e-15)


@pytest.mark.parametrize("angle", [0.0, math.pi / 2, -math.pi / 2, math.pi, -math.pi, 2.5, 2 * math.pi])
def test_exp_about_z_is_the_planar_rotation(angle):
    c, s = math.cos(angle), math.sin(angle)
    expected = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    np.testing.assert_allclose(np.asarray(so3.exp(jnp.array([0.0, 0.0, angle]))), expected, atol=3e-15)


def test_exp_of_tiny_vectors_is_the_second_order_series():
    """For θ ≤ 1e-6 the series I + [r]× + [r]×²/2 is exact to rounding; exp(0) is exactly I."""
    r = _axes(5, 5) * np.array([1e-12, 1e-9, 1e-7, 5e-7, 1e-6])[:, None]
    k = np.stack([_skew(v) for v in r])
    np.testing.assert_allclose(np.asarray(so3.exp(r)), np.eye(3) + k + 0.5 * k @ k, rtol=0, atol=1e-18)
    np.testing.assert_array_equal(np.asarray(so3.exp(jnp.zeros(3))), np.eye(3))


def test_exp_keeps_leading_dimensions():
    r = R[:24].reshape(2, 3, 4, 3)
    got = np.asarray(so3.exp(r))
    assert got.shape == (2, 3, 4, 3, 3)
    np.testing.assert_allclose(got.reshape(-1, 3, 3), Rotation.from_rotvec(R[:24]).as_matrix(), atol=3e-15)


def test_log_inverts_exp_below_pi():
    matrices = Rotation.from_rotvec(R).as_matrix()
    logs = np.asarray(so3.log(matrices))
    assert np.all(np.isfinite(logs))
    below = ANGLES < math.pi - 1e-7
    np.testing.assert_allclose(logs[below], R[below], rtol=0, atol=5e-15)
    np.testing.assert_allclose(logs[below], Rotation.from_matrix(matrices[below]).as_rotvec(), atol=5e-15)
    # just below π the vector is determined up to the conditioning of the axis sign: angle and exp(log R) = R
    np.testing.assert_allclose(np.linalg.norm(logs, axis=1), ANGLES, rtol=0, atol=1e-8)
    np.testing.assert_allclose(np.asarray(so3.exp(logs)), matrices, rtol=0, atol=5e-15)
    np.testing.assert_array_equal(np.asarray(so3.log(jnp.eye(3))), 0.0)


@pytest.mark.parametrize(
    "axis", list(COORDINATE_AXES) + list(_axes(4, 6)), ids=lambda a: np.array2string(a, 2)
)
def test_log_at_exactly_pi_is_one_of_the_two_logarithms(axis):
    """At θ = π both ±π a are logarithms: the result has angle π, is ± the axis, and exp(log R) = R."""
    rotation = Rotation.from_rotvec(math.pi * axis).as_matrix()
    got = np.asarray(so3.log(rotation))
    assert np.all(np.isfinite(got))
    assert np.linalg.norm(got) == pytest.approx(math.pi, abs=1e-12)
    assert min(np.abs(got - math.pi * axis).max(), np.abs(got + math.pi * axis).max()) < 1e-12
    np.testing.assert_allclose(np.asarray(so3.exp(got)), rotation, rtol=0, atol=3e-15)


def test_log_of_half_turns_about_coordinate_axes_are_exact():
    """diag(1, −1, −1) and its permutations: the half turns about x, y, z."""
    for i in range(3):
        rotation = -np.eye(3)
        rotation[i, i] = 1.0
        got = np.abs(np.asarray(so3.log(rotation)))
        np.testing.assert_allclose(got, math.pi * np.eye(3)[i], rtol=0, atol=1e-15)


def test_exp_log_round_trip_over_random_matrices():
    """exp ∘ log = id on rotation matrices (SciPy's random rotations, uniform on SO(3))."""
    matrices = Rotation.random(200, random_state=7).as_matrix()
    logs = np.asarray(so3.log(matrices))
    assert np.all(np.linalg.norm(logs, axis=1) <= math.pi + 1e-15)
    np.testing.assert_allclose(np.asarray(so3.exp(logs)), matrices, rtol=0, atol=5e-15)


def _scipy_fd(fn, x: np.ndarray, step: float = 1e-6) -> np.ndarray:
    """Central differences of fn along each coordinate of x (the derivative index last)."""
    return np.stack([(fn(x + step * e) - fn(x - step * e)) / (2 * step) for e in np.eye(x.shape[-1])], -1)


_EXP_JACOBIAN = jax.jit(jax.vmap(jax.jacfwd(so3.exp)))


def test_exp_derivative_matches_central_differences():
    points = np.concatenate(
        [
            [[0.0, 0.0, 0.0], [1e-9, 0.0, 0.0], [0.0, 0.0, math.pi / 2], [0.0, -math.pi / 2, 0.0]],
            [[math.pi, 0.0, 0.0], COORDINATE_AXES[-1] * (math.pi - 1e-9), [0.3, -1.2, 2.0]],
        ]
    )
    got = np.asarray(_EXP_JACOBIAN(jnp.asarray(points)))
    fd = _scipy_fd(lambda x: Rotation.from_rotvec(x).as_matrix(), points)
    np.testing.assert_allclose(got, fd, rtol=0, atol=1e-9)
    # at r = 0 the derivative along e_i is [e_i]× exactly
    np.testing.assert_allclose(got[0], np.stack([_skew(e) for e in np.eye(3)], -1), rtol=0, atol=1e-16)


_LOG_JVP = jax.jit(jax.vmap(lambda rot, tangent: jax.jvp(so3.log, (rot,), (tangent,))[1]))


def _log_rate_and_differences(r: np.ndarray, w: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """d/dt log(exp(t w) R) at t = 0 by jvp of log, and by central differences of SciPy's rotation vectors."""
    rotations = Rotation.from_rotvec(r).as_matrix()
    tangents = np.stack([_skew(v) for v in w]) @ rotations
    got = np.asarray(_LOG_JVP(jnp.asarray(rotations), jnp.asarray(tangents)))
    h = 1e-6
    fd = (
        (Rotation.from_rotvec(h * w) * Rotation.from_rotvec(r)).as_rotvec()
        - (Rotation.from_rotvec(-h * w) * Rotation.from_rotvec(r)).as_rotvec()
    ) / (2 * h)
    return got, fd


def test_log_derivative_along_rotations_matches_central_differences():
    rng = np.random.default_rng(8)
    axes = np.concatenate([_axes(24, 12), np.eye(3), -np.eye(3)])
    angles = np.concatenate([rng.uniform(0.0, 3.0, 24), [0.0, math.pi / 2, 3.0, 1e-9, 2.0, 3.1]])
    r = axes * angles[:, None]
    got, fd = _log_rate_and_differences(r, rng.normal(size=r.shape))
    np.testing.assert_allclose(got, fd, rtol=0, atol=1e-8)


@pytest.mark.parametrize("angle", [2.0, 3.0])
def test_log_derivative_at_axes_with_equal_largest_components(angle):
    """θ ≥ π/2 reads the axis from the largest diagonal entry of (1 − c) a aᵀ; where two entries tie (axis
    (1, 1, 1)/√3, (0, −1, 1)/√2) the derivative must still be that of the one branch taken."""
    rng = np.random.default_rng(13)
    r = COORDINATE_AXES[6:] * angle
    got, fd = _log_rate_and_differences(r, rng.normal(size=r.shape))
    np.testing.assert_allclose(got, fd, rtol=0, atol=1e-8)


def test_log_derivative_is_finite_at_pi():
    jac = np.asarray(jax.jacfwd(so3.log)(jnp.asarray(Rotation.from_rotvec([0.0, math.pi, 0.0]).as_matrix())))
    assert np.all(np.isfinite(jac))


def test_error_is_the_world_rotation_vector_from_r_to_r_desired():
    """error(r*, r) = log(R* Rᵀ): SciPy's rotation vector of R* R⁻¹, zero for equal rotations, and
    exp(e) R = R*."""
    rng = np.random.default_rng(9)
    desired = _axes(40, 10) * rng.uniform(0.0, math.pi, size=(40, 1))
    current = _axes(40, 11) * rng.uniform(0.0, math.pi, size=(40, 1))
    current[:4] = [[0.0, 0.0, 0.0], [0.0, 0.0, math.pi / 2], [0.0, -math.pi / 2, 0.0], [math.pi, 0.0, 0.0]]
    e = np.asarray(so3.error(desired, current))
    relative = Rotation.from_rotvec(desired) * Rotation.from_rotvec(current).inv()
    np.testing.assert_allclose(e, relative.as_rotvec(), rtol=0, atol=1e-13)
    np.testing.assert_allclose(
        np.asarray(so3.exp(e)) @ Rotation.from_rotvec(current).as_matrix(),
        Rotation.from_rotvec(desired).as_matrix(),
        rtol=0,
        atol=1e-14,
    )
    np.testing.assert_allclose(np.asarray(so3.error(current, current)), 0.0, rtol=0, atol=1e-15)
    # not the body-frame error Rᵀ R* (they differ unless the rotations commute)
    body = (Rotation.from_rotvec(current).inv() * Rotation.from_rotvec(desired)).as_rotvec()
    assert np.abs(e[4:] - body[4:]).max() > 0.1


def test_error_of_a_rotation_vector_beyond_pi_is_the_shorter_turn():
    """r and r − 2π a are the same rotation: the error between them is zero, and a turn of 3π/2 about z is
    reached by −π/2."""
    axis = COORDINATE_AXES[-1]
    np.testing.assert_allclose(
        np.asarray(so3.error(axis * (1.5 * math.pi), -axis * (0.5 * math.pi))), 0.0, atol=1e-14
    )
    got = np.asarray(so3.error(jnp.array([0.0, 0.0, 1.5 * math.pi]), jnp.zeros(3)))
    np.testing.assert_allclose(got, [0.0, 0.0, -0.5 * math.pi], rtol=0, atol=1e-14)
