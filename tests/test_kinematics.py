"""mobman.kinematics: the Jacobians three ways (closed form, autodiff, finite differences), frame invariance,
batches, reduced inverse velocity kinematics and the validation of configurations."""

from __future__ import annotations

import math

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import mobman
import mobman.model.robot as robot_module
from mobman import kinematics as K
from mobman.model import Position, robots

ALL = [f() for f in robots.PAPER_ROBOTS.values()]  # the real robots: test_urdf_pinocchio.py
angles = st.floats(-math.pi, math.pi)


def _random_q(robot, n=5, seed=0):
    return np.random.default_rng(seed).uniform(-2, 2, size=(n, robot.n_q))


def _finite_difference(fn, q, h=1e-6):
    cols = []
    for i in range(q.shape[-1]):
        e = np.zeros_like(q)
        e[i] = h
        cols.append((np.asarray(fn(q + e)) - np.asarray(fn(q - e))) / (2 * h))
    return np.stack(cols, axis=-1)


@pytest.mark.parametrize("robot", ALL, ids=lambda r: r.name)
def test_geometric_jacobian_equals_autodiff_and_finite_differences(robot):
    """J is the derivative of the error map q ↦ e(ξ(q), ξ(q0)) at q0: ∂ξ/∂q for the vector tasks."""
    q = _random_q(robot, 3)
    j = np.asarray(K.jacobian(robot, q))
    task = robot.task

    @jax.jit
    def error_map(qq, xi0):
        return task.error(task.value(robot, qq, robot.frames(qq)), xi0)

    xi = jnp.asarray(K.forward(robot, q))
    auto = jax.jit(jax.vmap(jax.jacfwd(error_map)))(jnp.asarray(q), xi)
    np.testing.assert_allclose(j, auto, atol=1e-12)
    for k in range(q.shape[0]):
        fd = _finite_difference(lambda qq, k=k: error_map(jnp.asarray(qq), xi[k]), q[k])
        np.testing.assert_allclose(j[k], fd, atol=1e-7)


@settings(max_examples=25, deadline=None)
@given(x=st.floats(-5, 5), y=st.floats(-5, 5), turn=angles, q=st.lists(angles, min_size=5, max_size=5))
def test_reduced_jacobian_rotates_with_world_for_planar_task(x, y, turn, q):
    """Moving the platform rigidly in the world rotates the position rows of J̄ and leaves the rest."""
    robot = robots.bayle_planar()
    q = np.array(q)
    moved = q.copy()
    c, s = math.cos(turn), math.sin(turn)
    moved[:2] = [c * q[0] - s * q[1] + x, s * q[0] + c * q[1] + y]
    moved[2] += turn
    jb, jm = np.asarray(K.reduced_jacobian(robot, q)), np.asarray(K.reduced_jacobian(robot, moved))
    rot = np.array([[c, -s], [s, c]])
    np.testing.assert_allclose(jm[:2], rot @ jb[:2], atol=1e-12)
    np.testing.assert_allclose(jm[2], jb[2], atol=1e-12)
    np.testing.assert_allclose(
        np.linalg.svd(jm, compute_uv=False), np.linalg.svd(jb, compute_uv=False), atol=1e-12
    )


@pytest.mark.parametrize("robot", ALL, ids=lambda r: r.name)
def test_batched_equals_per_configuration(robot):
    q = _random_q(robot, 4).reshape(2, 2, robot.n_q)
    batched = np.asarray(K.reduced_jacobian(robot, q))
    assert batched.shape == (2, 2, robot.task.dim, robot.n_eta)
    for i in range(2):
        for k in range(2):
            np.testing.assert_allclose(batched[i, k], K.reduced_jacobian(robot, q[i, k]), atol=1e-15)


def test_inverse_velocity_realises_consistent_velocity_and_respects_constraint():
    robot = robots.bayle_planar()
    q = np.array([0.1, 0.2, 0.3, 0.4, 0.5])
    xi_dot = np.array([0.1, -0.2, 0.3])
    z = np.array([1.0, -1.0, 0.5, 0.2])
    eta, q_dot = K.inverse_velocity(robot, q, xi_dot, z=z)
    np.testing.assert_allclose(np.asarray(K.jacobian(robot, q)) @ np.asarray(q_dot), xi_dot, atol=1e-12)
    assert abs(float(np.asarray(K.constraints(robot, q))[0] @ np.asarray(q_dot))) < 1e-14
    assert bool(K.is_consistent(robot, q, xi_dot))


def test_inconsistent_velocity_detected_for_rrp():
    robot = robots.bayle_rrp()
    q = np.array([0.0, 0.0, 0.3, 0.5, 0.4, 1.0])
    jbar = np.asarray(K.reduced_jacobian(robot, q))
    left_null = np.linalg.svd(jbar)[0][:, -1]
    assert not bool(K.is_consistent(robot, q, left_null))
    assert bool(K.is_consistent(robot, q, jbar @ np.ones(5)))


@pytest.mark.parametrize("as_array", [np.asarray, jnp.asarray], ids=["numpy", "jax"])
def test_bad_configuration_raises_input_error(as_array):
    robot = robots.bayle_planar()
    with pytest.raises(mobman.InputError, match="5 coordinates"):
        K.forward(robot, as_array(np.zeros(4)))
    with pytest.raises(mobman.InputError, match="5 coordinates"):
        K.forward(robot, as_array(np.float64(0.0)))
    with pytest.raises(mobman.InputError, match="NaN"):
        K.forward(robot, as_array(np.array([[0.0] * 5, [0, 0, np.nan, 0, 0]])))
    with pytest.raises(mobman.InputError, match="NaN"):
        K.forward(robot, as_array(np.array([0, 0, np.inf, 0, 0])))
    with pytest.raises(mobman.InputError, match="NaN"):
        K.forward(robot, as_array(np.array([0, 0, np.inf, -np.inf, 0])))
    # finite values whose sum overflows are still configurations
    assert np.isfinite(K.S(robot, as_array(np.array([1e308, 1e308, 0.2, 0.0, 0.0])))).all()
    with pytest.raises(mobman.ModelError, match="arm index"):
        K.forward(robot, np.zeros(5), Position(arm=2))


@pytest.mark.parametrize("in_host_memory", [True, False], ids=["host", "accelerator"])
def test_configurations_on_the_device_are_checked_there_and_not_copied(monkeypatch, in_host_memory):
    """A float64 jax.Array batch is validated on its device and reaches the compiled kernels as it is (a
    round trip through NumPy cost 20 ms per million configurations on a GPU); other dtypes become float64."""
    # on a CPU-only machine the accelerator branch (one reduction on the device) is taken by pretending
    monkeypatch.setattr(robot_module, "_in_host_memory", lambda q: in_host_memory)
    robot = robots.bayle_planar()
    q = jnp.asarray(np.random.default_rng(0).uniform(-1, 1, (7, 5)))
    assert K.validated_q(robot, q) is q
    for bad in (np.nan, np.inf, -np.inf):
        with pytest.raises(mobman.InputError, match="NaN or infinite"):
            K.validated_q(robot, q.at[3, 2].set(bad))
    as_int = K.validated_q(robot, jnp.zeros((3, 5), dtype=jnp.int32))
    assert isinstance(as_int, jax.Array) and as_int.dtype == jnp.float64
    np.testing.assert_array_equal(K.reduced_jacobian(robot, q), K.reduced_jacobian(robot, np.asarray(q)))


@pytest.mark.parametrize("robot", ALL, ids=lambda r: r.name)
def test_first_order_is_forward_jacobian_reduced_jacobian_and_the_representation_flag_at_once(robot):
    special = np.array([-math.pi, -math.pi / 2, 0.0, math.pi / 2, math.pi])
    corners = special[(np.arange(5)[:, None] + np.arange(robot.n_q)) % 5]  # each joint at each value
    q = np.clip(np.concatenate([_random_q(robot, 6, seed=3), corners]), *np.array(robot.position_limits).T)
    first = K.first_order(robot, q)
    np.testing.assert_allclose(first["xi"], K.forward(robot, q), rtol=0, atol=1e-12)
    np.testing.assert_allclose(first["J"], K.jacobian(robot, q), rtol=0, atol=1e-12)
    np.testing.assert_allclose(first["J_bar"], K.reduced_jacobian(robot, q), rtol=0, atol=1e-12)
    np.testing.assert_array_equal(first["representation_singular"], K.representation_singular(robot, q))
    one = K.first_order(robot, q[0])  # one configuration: no leading axis
    assert one["J"].shape == (robot.task.dim, robot.n_q) and one["representation_singular"].shape == ()


@pytest.mark.parametrize("robot", ALL[:2], ids=lambda r: r.name)
def test_frames_are_the_robot_s_frames_from_one_compiled_program(robot):
    q = _random_q(robot, 4, seed=5)
    for value in (q, q[0]):
        compiled, direct = K.frames(robot, value), robot.frames(jnp.asarray(value))
        for got, expected in zip(jax.tree.leaves((compiled.platform, compiled.mounts, compiled.links)),
                                 jax.tree.leaves((direct.platform, direct.mounts, direct.links))):  # fmt: skip
            assert isinstance(got, np.ndarray)
            np.testing.assert_allclose(got, expected, rtol=0, atol=1e-14)
    traced = jax.jit(lambda x: K.frames(robot, x).links[0][1])(q[0])  # inside a program: traced
    np.testing.assert_allclose(traced, K.frames(robot, q[0]).links[0][1], rtol=0, atol=1e-14)
