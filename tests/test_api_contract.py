"""The Python API's contract, by property: every public function of mobman.kinematics, manipulability,
redundancy and dynamics (a representative list) either returns finite arrays of the promised shape or raises
a MobmanError subclass, for random valid and invalid inputs (wrong sizes, NaN, strings, empty batches, …)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from mobman import dynamics as dyn
from mobman import kinematics as K
from mobman import manipulability as mp
from mobman import redundancy as R
from mobman.dynamics.ellipsoids import kinematic_ellipsoid
from mobman.errors import MobmanError
from mobman.model import robots

ROBOT = robots.bayle_rrp()
MODEL = dyn.yamamoto_model()
ANGLES = st.sampled_from([0.0, math.pi / 2, -math.pi / 2, math.pi, -math.pi]) | st.floats(-math.pi, math.pi)


def _configurations(n: int):
    """Valid configurations: one (n,) or a batch (2, n) (two shapes: one compilation each), angles over the
    whole turn with ±π/2, π."""
    one = st.lists(ANGLES, min_size=n, max_size=n).map(np.array)
    return one | st.lists(one, min_size=2, max_size=2).map(np.stack)


def _invalid(n: int):
    """Inputs that are not configurations of n coordinates."""
    return st.one_of(
        st.lists(ANGLES, min_size=0, max_size=n + 3).filter(lambda v: len(v) != n).map(np.array),
        st.just(np.full(n, np.nan)),
        st.just(np.r_[np.zeros(n - 1), np.inf]),
        st.text(max_size=5),
        st.just([["a"] * n]),
        st.just([[1.0, 2.0], [3.0]]),
        st.none(),
        st.just(object()),
    )


def _finite_arrays(out, shape_of: dict[str, tuple]) -> None:
    for key, want in shape_of.items():
        value = np.asarray(out[key] if isinstance(out, dict) else out[int(key)] if key.isdigit() else out)
        assert value.shape == want, (key, value.shape, want)
        if value.dtype != bool:
            assert np.isfinite(value).all(), key


def _call(fn, *args):
    """fn(*args), or None when it raises a MobmanError (anything else fails the test)."""
    try:
        return fn(*args)
    except MobmanError:
        return None


def _lead(q) -> tuple:
    return tuple(np.shape(q)[:-1])


KINEMATICS = {
    "forward": (lambda q: K.forward(ROBOT, q), lambda b: {"x": (*b, 5)}),
    "jacobian": (lambda q: K.jacobian(ROBOT, q), lambda b: {"x": (*b, 5, 6)}),
    "reduced_jacobian": (lambda q: K.reduced_jacobian(ROBOT, q), lambda b: {"x": (*b, 5, 5)}),
    "S": (lambda q: K.S(ROBOT, q), lambda b: {"x": (*b, 6, 5)}),
    "constraints": (lambda q: K.constraints(ROBOT, q), lambda b: {"x": (*b, 1, 6)}),
    "representation_singular": (lambda q: K.representation_singular(ROBOT, q), lambda b: {"x": b}),
    "inverse_velocity": (lambda q: K.inverse_velocity(ROBOT, q, np.ones(5))[1], lambda b: {"x": (*b, 6)}),
    "limit_violations": (ROBOT.limit_violations, lambda b: {"x": (*b, 6)}),
    "ranks": (lambda q: R.ranks(ROBOT, q), lambda b: {"0": b, "1": b}),
    "is_velocity_singular": (lambda q: R.is_velocity_singular(ROBOT, q), lambda b: {"0": b, "1": b}),
    "consistency_relations": (lambda q: R.consistency_relations(ROBOT, q), lambda b: {"x": (*b, 1, 5)}),
    "analyze": (lambda q: mp.analyze(ROBOT, q, rank="auto")["system"], lambda b: {"yoshikawa": b}),
    "gradient": (lambda q: mp.gradient(ROBOT, q, rank="auto"), lambda b: {"x": (*b, 6)}),
    "kinematic_ellipsoid": (lambda q: kinematic_ellipsoid(ROBOT, q).matrix, lambda b: {"x": (*b, 5, 5)}),
}
DYNAMICS = {
    "mass_matrix": (lambda q: dyn.mass_matrix(MODEL, q), lambda b: {"x": (*b, 9, 9)}),
    "reduced_mass_matrix": (lambda q: dyn.reduced_mass_matrix(MODEL, q), lambda b: {"x": (*b, 8, 8)}),
    "input_matrix": (lambda q: dyn.input_matrix(MODEL, q), lambda b: {"x": (*b, 8, 8)}),
}
SETTINGS = settings(max_examples=6, deadline=None, suppress_health_check=[HealthCheck.too_slow])


@pytest.mark.parametrize("name", list(KINEMATICS))
@SETTINGS
@given(data=st.data())
def test_kinematics_and_measures_return_finite_arrays_or_raise_mobman_errors(name, data):
    fn, shapes = KINEMATICS[name]
    q = data.draw(_configurations(6) | _invalid(6))
    out = _call(fn, q)
    valid = isinstance(q, np.ndarray) and q.shape[-1:] == (6,) and np.isfinite(q).all()
    if out is None:
        assert not valid or name in ("ranks", "is_velocity_singular", "consistency_relations")
        return
    assert valid, (name, q)
    _finite_arrays(out, shapes(_lead(q)))


@pytest.mark.parametrize("name", list(DYNAMICS))
@SETTINGS
@given(data=st.data())
def test_dynamics_return_finite_arrays_or_raise_mobman_errors(name, data):
    fn, shapes = DYNAMICS[name]
    q = data.draw(_configurations(9) | _invalid(9))
    out = _call(fn, q)
    valid = isinstance(q, np.ndarray) and q.shape[-1:] == (9,) and np.isfinite(q).all()
    assert (out is not None) == valid, (name, q)
    if out is not None:
        _finite_arrays(out, shapes(_lead(q)))


MATRICES = st.one_of(
    st.integers(1, 4).flatmap(
        lambda m: st.integers(1, 5).flatmap(
            lambda k: st.lists(st.floats(-5, 5), min_size=m * k, max_size=m * k).map(
                lambda v: np.reshape(v, (m, k))
            )
        )
    ),
    st.just(np.full((3, 3), np.nan)),
    st.just(np.zeros((0, 3))),
    st.just(np.zeros(3)),
    st.text(max_size=3),
    st.just([[1.0, 2.0], [3.0]]),
)


@SETTINGS
@given(j=MATRICES)
def test_measures_of_a_jacobian_return_finite_values_or_raise_mobman_errors(j):
    matrix = isinstance(j, np.ndarray) and j.ndim == 2 and np.isfinite(j).all()
    for fn in (mp.measures, mp.singular_values, K.rank):
        out = _call(fn, j)
        valid = matrix and (j.size > 0 or fn is K.rank)  # the rank of a 0 × k matrix is 0
        assert (out is not None) == valid, (fn.__name__, j)
        if out is not None:
            values = out.values() if isinstance(out, dict) else [out]
            assert all(np.isfinite(np.asarray(v)).all() for v in values)


def test_nan_jacobian_measures_are_an_error_not_zero():
    j = np.array([[1.0, np.nan], [0.0, 1.0]])
    with pytest.raises(MobmanError, match="NaN"):
        mp.measures(j)
    with pytest.raises(MobmanError, match="NaN"):
        K.rank(j)


def test_limit_violations_name_the_coordinates_outside_the_joint_limits():
    q = np.array([[0, 0, 0, 0.2, 0.5, -0.5], [0, 0, 0, 0.2, 0.5, 0.0], [9, 9, 9, 9, 9, 9]])
    np.testing.assert_array_equal(ROBOT.limit_violations(q), [[0, 0, 0, 0, 0, 1], [0] * 6, [0] * 6])
    with pytest.raises(MobmanError):
        ROBOT.limit_violations(np.zeros(5))


def test_a_jacobian_that_never_moves_names_the_cause_not_a_rank_range():
    from mobman.model import Arm, DifferentialDrive, MobileManipulator, Position

    arm = Arm.from_dh([(0, 0, 0, 0), (0, 0, 0, 0)])  # zero-length links: the tool point never moves
    robot = MobileManipulator(DifferentialDrive(), (arm,), task=Position("xy"))
    with pytest.raises(MobmanError, match="arm Jacobian is zero.*does not move with the arm's joints"):
        mp.analyze(robot, np.full(robot.n_q, 0.3), rank="auto")


def test_an_alpha_coordinate_out_of_range_is_an_error_never_clamped():
    from mobman.control.criteria import CubicTransition

    with pytest.raises(MobmanError, match="coordinate 99 out of range"):
        CubicTransition(0.0, 1.0, coordinate=99)(np.zeros(3))
    with pytest.raises(MobmanError, match="coordinate must be an index"):
        CubicTransition(0.0, 1.0, coordinate=-1)
    assert float(CubicTransition(0.0, 1.0, coordinate=2)(np.array([0.0, 0.0, 0.5]))) == pytest.approx(0.5)


def test_a_singular_closed_chain_gets_its_degenerate_ellipsoid_flagged():
    """Both arms stretched: the closed chain's equations are singular (the hand forces undetermined). The
    exact ellipsoid is then their minimum-norm solution's, flagged: each of its points a_o, for the torque τ
    that maps to it, is an acceleration the chain can have (some u̇, h satisfy the equations: least squares
    by SciPy, residual at rounding)."""
    from scipy.linalg import lstsq

    from mobman.dynamics.ellipsoids import dynamic_ellipsoid, dynamic_terms
    from mobman.dynamics.grasp import HeldObject
    from mobman.experiments.yamamoto1999 import torque_limits

    stretched, obj = np.zeros(9), HeldObject(2.0)
    limits = torque_limits(MODEL.robot)
    e = dynamic_ellipsoid(MODEL, stretched, limits, obj=obj, method="exact")
    assert bool(e.singular) and np.isfinite(e.matrix).all() and e.axes[0] > 0
    t = dynamic_terms(MODEL, stretched, obj=obj)
    n, r, m = t.p.shape[-1], t.j.shape[-2], t.w.shape[-2]
    a = np.zeros((n + m + r, n + r))  # unknowns u̇, h for a given a_o and τ
    a[:n, :n], a[:n, n:] = t.p, t.j.T
    a[n : n + m, n:] = -t.w
    a[n + m :, :n] = t.j
    for s in np.random.default_rng(3).normal(size=(4, n)):
        s /= np.linalg.norm(s)
        a_o, tau = e.center + e.matrix @ s, limits * s  # a point of the boundary and its torque
        # P u̇ + Jᵀ h = Q τ − b,  −W h = −(c_o + g_o) − M_o a_o,  J u̇ = Wᵀ a_o − drift
        b = np.concatenate([t.q @ tau - t.b, -t.bias_o - t.m_o @ a_o, t.w.T @ a_o - t.drift])
        x = lstsq(a, b)[0]
        assert np.linalg.norm(a @ x - b) <= 1e-9 * np.linalg.norm(b)


def test_a_spec_alpha_coordinate_out_of_range_names_the_field(tmp_path):
    import re
    from pathlib import Path

    from mobman.control import spec

    text = (Path(__file__).resolve().parents[1] / "docs" / "examples" / "bayle_ellipse.toml").read_text()
    blend = (
        '[criterion]\nkind = "blend"\n'
        'system = { kind = "manipulability", measure = "eccentricity", which = "system" }\n'
        'arm = { kind = "manipulability", measure = "eccentricity", which = "arm" }\n'
        "alpha = { start = 0.5, end = 1.5, coordinate = 99 }\n\n"
    )
    path = tmp_path / "blend.toml"
    path.write_text(re.sub(r"\[criterion\].*?(?=\[gains\])", blend, text, flags=re.DOTALL))
    with pytest.raises(MobmanError, match=r"criterion\.alpha\.coordinate: 99 out of range 0\.\.1"):
        spec.load(path)


@pytest.mark.parametrize(
    "call, message",
    [
        (
            lambda: __import__("mobman.studies.placement").studies.placement.place(None, [1.0, 0.0, 0.5]),
            "robot must",
        ),
        (lambda: K.forward(None, np.zeros(6)), "robot must be a MobileManipulator, got NoneType"),
        (
            lambda: __import__("mobman.studies.placement").studies.placement.place_with_map(
                ROBOT, None, [1, 0, 0]
            ),
            "reachability must be a ReachabilityMap, got NoneType",
        ),
        (
            lambda: __import__("mobman.studies.store").studies.store.run(None, 1, {}, {}, store=5),
            "store must be",
        ),
        (
            lambda: __import__("mobman.studies.store").studies.store.run(None, 1, {}, {}, scheduler=123),
            "scheduler",
        ),
    ],
)
def test_arguments_of_the_wrong_type_are_mobman_errors(call, message):
    with pytest.raises(MobmanError, match=message):
        call()


def test_a_reachability_map_s_store_and_scheduler_are_checked_before_any_work(monkeypatch):
    from mobman.studies import maps

    monkeypatch.setattr(maps, "tool_positions", lambda *_: pytest.fail("worked before checking its options"))
    for options, message in [
        ({"store": 5}, "store must be a folder's path"),
        ({"scheduler": 123}, "scheduler must"),
    ]:
        with pytest.raises(MobmanError, match=message):
            maps.reachability_map(ROBOT, **options)


@pytest.mark.parametrize("fn", [K.forward, K.jacobian, K.S, K.constraints])
def test_complex_configurations_are_refused_not_cast(fn):
    import jax.numpy as jnp

    q = np.full(6, 0.3) + 1e-3j
    for value in (q, jnp.asarray(q), list(q)):
        with pytest.raises(MobmanError, match="must be real numbers, got complex"):
            fn(ROBOT, value)


def test_a_jacobian_whose_measures_overflow_is_refused_not_infinite():
    for j in (np.diag([1e200, 1e200]), np.full((6, 6), 1e30)):
        with pytest.raises(MobmanError, match="its measures would overflow float64"):
            mp.measures(j)
    big = np.diag([1e60, 2e60])  # within the bound: finite, and w, w2 by their closed forms
    out = mp.measures(big)
    assert float(out["yoshikawa"]) == pytest.approx(2e120) and float(
        out["inverse_condition"]
    ) == pytest.approx(0.5)


def test_a_sweep_s_fixed_parameters_are_checked():
    from mobman.studies.sweep import sweep

    for fixed, message in [
        ({"l2": math.nan}, "fixed: l2 must be finite"),
        ({"l2": "a"}, "fixed: l2 must be a number"),
    ]:
        with pytest.raises(MobmanError, match=message):
            sweep("bayle-planar", {"l1": [0.5]}, fixed=fixed, samples=10)


def test_a_torque_function_returning_nan_stops_the_simulation_naming_the_time():
    import jax.numpy as jnp

    def nan_after(t, q, eta):
        return jnp.where(t >= 0.05, jnp.nan, 0.0) * jnp.ones_like(eta)

    with pytest.raises(MobmanError, match=r"torque_fn returned NaN or infinite torques at t = 0\.05 s"):
        dyn.simulate(MODEL, np.zeros(9), np.zeros(8), nan_after, duration=0.1, dt=0.01)


def test_a_qp_law_s_or_a_simulation_s_argument_of_the_wrong_type_is_a_mobman_error_naming_it():
    from mobman.control import laws, simulate

    with pytest.raises(MobmanError, match="regularization must be a finite number ≥ 1e-7, got '1e-4'"):
        laws.WholeBodyQP(W=1.0, regularization="1e-4")
    robot = robots.bayle_planar()
    with pytest.raises(MobmanError, match="reference: a reference .*, got NoneType"):
        simulate(robot, None, laws.BaylePseudoInverse(W=1.0), None, np.zeros(5), 0.1, 0.01)
