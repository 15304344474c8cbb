"""Manipulability measures (Nait-Chabane eq. 13–26, Bayle §6): closed forms, NumPy SVD, autodiff vs finite
differences, restricted measures where D̄ < m, ellipsoids, batching and input errors."""

import jax.numpy as jnp
import numpy as np
import pytest

from mobman import kinematics as K
from mobman import manipulability as mp
from mobman.errors import InputError, ModelError
from mobman.model import robots
from mobman.model.tasks import Position

RNG = np.random.default_rng(7)


def _reference(j: np.ndarray) -> dict[str, np.ndarray]:
    """The three measures from NumPy's SVD (the definitions of Nait-Chabane eq. 17–19)."""
    s = np.linalg.svd(j, compute_uv=False)
    m = j.shape[-2]
    if s.shape[-1] < m:  # fewer columns than rows: rank deficient
        s = np.concatenate([s, np.zeros(s.shape[:-1] + (m - s.shape[-1],))], axis=-1)
    return {
        "yoshikawa": np.prod(s, axis=-1),
        "inverse_condition": s[..., -1] / s[..., 0],
        "eccentricity": np.sqrt(1 - (s[..., -1] / s[..., 0]) ** 2),
    }


@pytest.mark.parametrize("shape", [(3, 4), (2, 2), (6, 9), (5, 5)])
def test_measures_match_numpy_svd(shape):
    j = RNG.normal(size=(50,) + shape)
    got = mp.measures(j)
    want = _reference(j)
    for key in mp.MEASURES:
        np.testing.assert_allclose(got[key], want[key], rtol=1e-9, atol=1e-12, err_msg=key)
    np.testing.assert_allclose(
        got["yoshikawa"], np.sqrt(np.linalg.det(j @ np.swapaxes(j, -1, -2))), rtol=1e-9
    )
    np.testing.assert_allclose(
        mp.singular_values(j), np.linalg.svd(j, compute_uv=False), rtol=1e-9, atol=1e-12
    )


def test_yoshikawa_two_link_closed_form():
    """Yoshikawa's classic result for a planar 2R arm: w = l1 l2 |sin θ2|."""
    l1, l2 = 0.7, 0.4
    robot = robots.bayle_planar(l1=l1, l2=l2)
    q = RNG.uniform(-np.pi, np.pi, (200, robot.n_q))
    w = mp.yoshikawa(mp.arm_jacobian(robot, q, Position("xy")))
    np.testing.assert_allclose(w, l1 * l2 * np.abs(np.sin(q[:, 4])), rtol=1e-9, atol=1e-12)


def test_rank_deficient_jacobian_gives_degenerate_measures():
    j = np.array([[1.0, 2.0, 0.0], [2.0, 4.0, 0.0]])
    got = mp.measures(j)
    assert float(got["yoshikawa"]) == pytest.approx(0.0, abs=1e-7)
    assert float(got["inverse_condition"]) == pytest.approx(0.0, abs=1e-7)
    assert float(got["eccentricity"]) == pytest.approx(1.0, abs=1e-12)


def test_normalized_system_jacobian_scales_columns_by_velocity_limits():
    robot = robots.manus_platform()
    q = RNG.uniform(-1, 1, (10, robot.n_q))
    jn = mp.system_jacobian(robot, q, normalized=True)
    np.testing.assert_allclose(
        jn, np.asarray(K.reduced_jacobian(robot, q)) * np.asarray(robot.velocity_limits)
    )
    # Nait-Chabane's u_max = (0.33 m/s, 0.55 rad/s, π/3 rad/s per joint)
    np.testing.assert_allclose(robot.velocity_limits, [0.33, 0.55, np.pi / 3, np.pi / 3, np.pi / 3])


def test_normalized_measures_need_velocity_limits():
    robot = robots.tchon_car_rtr()
    if robot.velocity_limits is not None:
        pytest.fail("tchon_car_rtr is expected to carry no velocity limits (the paper gives none)")
    with pytest.raises(ModelError, match="velocity limits"):
        mp.system_jacobian(robot, np.zeros(robot.n_q), normalized=True)
    assert mp.analyze(robot, np.zeros(robot.n_q))["system_normalized"] is None


@pytest.mark.parametrize(
    ("which", "measure"),
    [("arm", "yoshikawa"), ("system", "eccentricity"), ("system_normalized", "inverse_condition")],
)
def test_gradient_autodiff_matches_finite_differences(which, measure):
    robot = robots.manus_platform()
    q = np.array([0.3, -0.2, 0.4, 1.1, 0.7, -0.9])

    def value(qq):
        j = (
            mp.arm_jacobian(robot, qq)
            if which == "arm"
            else mp.system_jacobian(robot, qq, normalized=which == "system_normalized")
        )
        return float(mp.measures(j)[measure])

    h = 1e-6
    fd = np.array([(value(q + h * e) - value(q - h * e)) / (2 * h) for e in np.eye(robot.n_q)])
    got = np.asarray(mp.gradient(robot, q, which=which, measure=measure))
    np.testing.assert_allclose(got, fd, rtol=1e-6, atol=1e-8)


def test_gradient_is_batched():
    robot = robots.bayle_planar()
    q = RNG.uniform(-np.pi, np.pi, (4, robot.n_q))
    batched = np.asarray(mp.gradient(robot, q))
    single = np.stack([np.asarray(mp.gradient(robot, qi)) for qi in q])
    np.testing.assert_allclose(batched, single, rtol=1e-12, atol=1e-14)
    # the platform pose does not change the system measures of a planar task (world invariance)
    np.testing.assert_allclose(batched[:, :3], 0.0, atol=1e-10)


@pytest.mark.parametrize("which", mp.WHICH)
def test_jacobian_and_measures_is_the_jacobian_then_its_measures(which):
    """One compiled call gives what the two public calls give, batched and for one configuration (where the
    measures come from LAPACK instead of the batched Jacobi solver), checked against NumPy's SVD."""
    robot = robots.manus_platform()
    q = RNG.uniform(-1.0, 1.0, (5, robot.n_q))
    jac, meas = mp.jacobian_and_measures(robot, q, which=which)
    want = (
        mp.arm_jacobian(robot, q)
        if which == "arm"
        else mp.system_jacobian(robot, q, normalized=which == "system_normalized")
    )
    np.testing.assert_allclose(jac, want, rtol=1e-13, atol=1e-15)
    reference = _reference(np.asarray(want))
    for i in range(len(q)):
        jac_i, meas_i = mp.jacobian_and_measures(robot, q[i], which=which)
        np.testing.assert_allclose(jac_i, want[i], rtol=1e-13, atol=1e-15)
        for key in mp.MEASURES:
            np.testing.assert_allclose(meas_i[key], reference[key][i], rtol=1e-9)
    for key in mp.MEASURES:
        assert meas[key].shape == (5,)
        np.testing.assert_allclose(meas[key], reference[key], rtol=1e-9)


def test_jacobian_and_measures_restricted_and_bad_input():
    robot = robots.bayle_rrp()
    q = RNG.uniform(-1.0, 1.0, (4, robot.n_q))
    q[:, 4] = RNG.uniform(0.3, 1.2, 4)
    jbar, meas = mp.jacobian_and_measures(robot, q, rank="auto")
    s = np.linalg.svd(np.asarray(jbar), compute_uv=False)
    np.testing.assert_allclose(meas["yoshikawa"], np.prod(s[:, :4], axis=1), rtol=1e-8)
    with pytest.raises(InputError, match="which"):
        mp.jacobian_and_measures(robot, q, which="base")
    with pytest.raises(InputError, match="rank"):
        mp.jacobian_and_measures(robot, q, rank=9)
    # the options' checks are cached: an equal option of another type, or an unhashable one, is still refused
    mp.jacobian_and_measures(robot, q, rank=4)
    for bad in (4.0, [4]):
        with pytest.raises(InputError, match="rank must be None or an integer"):
            mp.jacobian_and_measures(robot, q, rank=bad)
        with pytest.raises(InputError, match="rank must be None or an integer"):
            mp.gradient(robot, q, rank=bad)
    car = robots.tchon_car_rtr()
    with pytest.raises(ModelError, match="velocity limits"):
        mp.jacobian_and_measures(car, np.zeros(car.n_q), which="system_normalized")


def test_restricted_measures_where_velocity_degree_below_task_dimension():
    """bayle_rrp: J̄ is 5 × 5 of rank ≤ D̄ = 4 everywhere, so plain w = 0 and w5 = 1; restricted ones are not."""
    robot = robots.bayle_rrp()
    q = RNG.uniform(-1.0, 1.0, (20, robot.n_q))
    q[:, 4] = RNG.uniform(0.3, 1.2, 20)  # away from the kinematic singularity q5 = kπ
    plain = mp.analyze(robot, q)
    np.testing.assert_allclose(plain["system"]["eccentricity"], 1.0, atol=1e-12)
    np.testing.assert_allclose(plain["system"]["yoshikawa"], 0.0, atol=1e-6)
    auto = mp.analyze(robot, q, rank="auto")
    assert auto["restricted"] and auto["ranks"]["system"] == 4
    s = np.linalg.svd(np.asarray(K.reduced_jacobian(robot, q)), compute_uv=False)
    np.testing.assert_allclose(auto["system"]["yoshikawa"], np.prod(s[:, :4], axis=1), rtol=1e-8)
    np.testing.assert_allclose(
        auto["system"]["eccentricity"], np.sqrt(1 - (s[:, 3] / s[:, 0]) ** 2), rtol=1e-8
    )
    assert np.all(np.asarray(auto["system"]["eccentricity"]) < 1.0)


def test_plain_measures_are_not_restricted_when_full_rank():
    robot = robots.bayle_planar()
    result = mp.analyze(robot, np.array([0.0, 0.0, 0.0, 0.3, 1.2]), rank="auto")
    assert result["ranks"]["system"] is None  # D̄ = 3 = m: plain system measures
    assert result["ranks"]["arm"] == 2 and result["restricted"]  # J_a is 3 × 2: the arm's are restricted


def test_ellipsoid_axes_and_directions():
    j = RNG.normal(size=(20, 3, 5))
    axes, directions = mp.ellipsoid(j)
    np.testing.assert_allclose(axes, np.linalg.svd(j, compute_uv=False), rtol=1e-9)
    eye = np.broadcast_to(np.eye(3), (20, 3, 3))
    np.testing.assert_allclose(np.swapaxes(directions, -1, -2) @ directions, eye, atol=1e-10)
    jjt = j @ np.swapaxes(j, -1, -2)
    np.testing.assert_allclose(jjt @ directions, directions * np.asarray(axes)[:, None, :] ** 2, atol=1e-9)


def test_measures_under_jit_tracing():
    import jax

    j = jnp.asarray(RNG.normal(size=(4, 2, 3)))
    traced = jax.jit(lambda a: mp.measures(a)["eccentricity"])(j)
    np.testing.assert_allclose(traced, _reference(np.asarray(j))["eccentricity"], rtol=1e-9)


@pytest.mark.parametrize(
    ("call", "match"),
    [
        (lambda: mp.measures(np.ones(3)), "shape"),
        (lambda: mp.gradient(robots.bayle_planar(), np.zeros(5), measure="w7"), "measure"),
        (lambda: mp.gradient(robots.bayle_planar(), np.zeros(5), which="base"), "which"),
        (lambda: mp.arm_jacobian(robots.bayle_planar(), np.zeros(5), arm=1), "arm index"),
    ],
)
def test_bad_input_is_a_clear_error(call, match):
    with pytest.raises(InputError, match=match):
        call()


def test_measures_accept_any_numeric_jacobian_and_reject_vectors():
    """Integer, float32, NumPy and jax inputs give the float64 measures; a float64 jax.Array is used as it is
    (no re-wrapped copy, which would leave jit's fast dispatch path); a vector is refused by name."""
    j = np.array([[2.0, 0.0, 1.0], [0.0, 1.0, 0.0]])
    want = mp.measures(j)
    for given in (j.astype(int), j.astype(np.float32), jnp.asarray(j, dtype=jnp.float32), jnp.asarray(j)):
        got = mp.measures(given)
        for key in mp.MEASURES:
            assert got[key].dtype == jnp.float64
            np.testing.assert_allclose(got[key], want[key], rtol=1e-7)
    arr = jnp.asarray(j)
    assert mp._as_jacobian(arr) is arr
    with pytest.raises(InputError, match=r"shape \(\.\.\., m, k\)"):
        mp.measures(np.ones(3))
