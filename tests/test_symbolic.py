"""Symbolic closed forms against the papers' printed matrices and determinants, and against the numerics."""

from __future__ import annotations

import math

import numpy as np
import pytest
import sympy as sp

from mobman import kinematics as K
from mobman import symbolic as S
from mobman.errors import ModelError
from mobman.model import (
    FunctionTask,
    MountPosition,
    PlanarAngle,
    Pose,
    Position,
    robots,
    stack,
)
from mobman.model.tasks import elbow_angle
from mobman.redundancy import sample_configurations

sin, cos = sp.sin, sp.cos


def assert_same(a: sp.Matrix, b: sp.Matrix, q) -> None:
    """Exact identity of two matrices of trigonometric expressions (canonical form of the difference)."""
    a, b = sp.Matrix(a), sp.Matrix(b)
    assert a.shape == b.shape
    for i, j in np.ndindex(*a.shape):
        assert S.trig_normal(a[i, j] - b[i, j], q) == 0, f"entry ({i}, {j}): {a[i, j]} != {b[i, j]}"


def _symbols(model, names):
    return [model.params[n] for n in names]


# --- Bayle §5 ----------------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def planar():
    return S.model(robots.bayle_planar(), ("l1", "l2"))


@pytest.fixture(scope="module")
def rrp():
    return S.model(robots.bayle_rrp())


def test_bayle_planar_printed_j_and_j_bar(planar):
    x, y, q3, q4, q5 = planar.q
    l1, l2 = _symbols(planar, ("l1", "l2"))
    s34, c34, s345, c345 = sin(q3 + q4), cos(q3 + q4), sin(q3 + q4 + q5), cos(q3 + q4 + q5)
    a = l1 * s34 + l2 * s345
    b = l1 * c34 + l2 * c345
    j = sp.Matrix([[1, 0, -a, -a, -l2 * s345], [0, 1, b, b, l2 * c345], [0, 0, 1, 1, 1]])
    jbar = sp.Matrix([[cos(q3), -a, -a, -l2 * s345], [sin(q3), b, b, l2 * c345], [0, 1, 1, 1]])
    assert_same(planar.jacobian(), j, planar.q)
    assert_same(planar.reduced_jacobian(), jbar, planar.q)
    assert "\\cos" in sp.latex(planar.reduced_jacobian())


def test_bayle_rrp_printed_j_and_j_bar(rrp):
    x, y, q3, q4, q5, q6 = rrp.q
    c5, s5, c34, s34 = cos(q5), sin(q5), cos(q3 + q4), sin(q3 + q4)
    j = sp.Matrix(
        [
            [1, 0, -q6 * c5 * s34, -q6 * c5 * s34, -q6 * s5 * c34, c5 * c34],
            [0, 1, q6 * c5 * c34, q6 * c5 * c34, -q6 * s5 * s34, c5 * s34],
            [0, 0, 0, 0, q6 * c5, s5],
            [0, 0, 1, 1, 0, 0],
            [0, 0, 0, 0, 1, 0],
        ]
    )
    jbar = sp.Matrix(
        [
            [cos(q3), -q6 * c5 * s34, -q6 * c5 * s34, -q6 * s5 * c34, c5 * c34],
            [sin(q3), q6 * c5 * c34, q6 * c5 * c34, -q6 * s5 * s34, c5 * s34],
            [0, 0, 0, q6 * c5, s5],
            [0, 1, 1, 0, 0],
            [0, 0, 0, 1, 0],
        ]
    )
    assert_same(rrp.jacobian(), j, rrp.q)
    assert_same(rrp.reduced_jacobian(), jbar, rrp.q)


def test_bayle_rrp_direct_kinematics_is_the_printed_one(rrp):
    # Bayle §5.2 DK: the angles are the joint sums themselves, no chart (ξ5 = q5 over the whole turn)
    x, y, q3, q4, q5, q6 = rrp.q
    c5, s5 = cos(q5), sin(q5)
    dk = sp.Matrix([x + q6 * c5 * cos(q3 + q4), y + q6 * c5 * sin(q3 + q4), q6 * s5, q3 + q4, q5])
    assert_same(rrp.forward(), dk, rrp.q)
    assert rrp.forward()[3:, 0] == sp.Matrix([q3 + q4, q5])


def test_bayle_rank_drop_conditions():
    planar = S.rank_drop_conditions(robots.bayle_planar(), params=("l1", "l2"))
    q4 = sp.Symbol("q4", real=True)
    q5 = sp.Symbol("q5", real=True)
    assert planar.rank == 3
    assert planar.condition == sp.Eq(cos(q4), 0)  # VSC iff q4 = (2k+1)π/2
    assert S.rank_drop_conditions(robots.bayle_planar(), which="kinematic").condition == sp.false  # no KSC
    rrp_velocity = S.rank_drop_conditions(robots.bayle_rrp())
    assert rrp_velocity.rank == 4
    assert rrp_velocity.condition == sp.And(sp.Eq(sin(q4), 0), sp.Eq(sin(q5), 0))  # q4 = kπ and q5 = kπ
    rrp_kinematic = S.rank_drop_conditions(robots.bayle_rrp(), which="kinematic")
    assert rrp_kinematic.rank == 5 and rrp_kinematic.condition == sp.Eq(sin(q5), 0)  # KSC iff q5 = kπ


def test_bayle_rrp_consistency_relation_is_the_printed_one_with_q6_for_g6(rrp):
    relations = S.consistency_relations(robots.bayle_rrp())
    assert relations.shape == (1, 5)
    x, y, q3, q4, q5, q6 = rrp.q
    printed = sp.Matrix(
        [
            [
                sin(q3) * sin(q5),
                -cos(q3) * sin(q5),
                sin(q4) * cos(q5),
                q6 * cos(q4) * cos(q5) * sin(q5),
                -q6 * sin(q4),
            ]
        ]
    )
    assert_same(relations, printed, rrp.q)
    assert_same(printed * rrp.reduced_jacobian(), sp.zeros(1, 5), rrp.q)


# --- Nait-Chabane eq. 27–28 --------------------------------------------------------------------------


def _manus_arm_jacobian(q_a, L2, L3, L4):
    c1, c2, c3 = (cos(v) for v in q_a)
    s1, s2, s3 = (sin(v) for v in q_a)
    return sp.Matrix(
        [  # eq. (27)
            [-(L4 * c3 + L3 * c2) * s1 - L2 * c1, -L3 * c1 * s2, -L4 * c1 * s3],
            [(L4 * c3 + L3 * c2) * c1 - L2 * s1, -L3 * s1 * s2, -L4 * s3 * s1],
            [0, L3 * c2, L4 * c3],
        ]
    )


def test_nait_chabane_eq27_arm_jacobian():
    model = S.SymbolicRobot(robots.manus_platform(a=0.0, b=0.0, c=0.0), params=("L2", "L3", "L4"))
    L2, L3, L4 = _symbols(model, ("L2", "L3", "L4"))
    x, y, theta, *q_a = model.q
    # platform at the origin, θ = π/2: {A} is the world frame (eq. 8), the arm columns of J are J_a
    j_arm = model.jacobian()[:, 3:].subs(theta, sp.pi / 2)
    assert_same(j_arm, _manus_arm_jacobian(q_a, L2, L3, L4), model.q)


def test_nait_chabane_eq28_reduced_jacobian():
    names = ("L2", "L3", "L4", "a", "b", "c")
    model = S.SymbolicRobot(robots.manus_platform(), params=names, factory=robots.manus_platform)
    L2, L3, L4, a, b, c = _symbols(model, names)
    x, y, th, q1, q2, q3 = model.q
    ja = _manus_arm_jacobian((q1, q2, q3), L2, L3, L4)
    xa1 = (L4 * cos(q3) + L3 * cos(q2)) * cos(q1) - L2 * sin(q1)
    xa2 = (L4 * cos(q3) + L3 * cos(q2)) * sin(q1) + L2 * cos(q1)
    ct, st = cos(th), sin(th)
    expected = sp.Matrix(
        [
            [ct, -(xa2 + a) * st - (b - xa1) * ct] + [ja[1, k] * ct + ja[0, k] * st for k in range(3)],
            [st, (xa2 + a) * ct - (b - xa1) * st] + [ja[1, k] * st - ja[0, k] * ct for k in range(3)],
            [0, 0, ja[2, 0], ja[2, 1], ja[2, 2]],
        ]
    )
    assert_same(model.reduced_jacobian(), expected, model.q)
    # eq. (8), third row: x_3 = x_a3 + c
    assert_same(model.forward()[2:, :], sp.Matrix([[L3 * sin(q2) + L4 * sin(q3) + c]]), model.q)


# --- Korayem eq. 36–37 -------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def korayem():
    return S.model(robots.korayem_planar(), ("l0", "l1", "l2"))


def _korayem_printed(extra_rows, l0, l1, l2):
    """Korayem's printed augmented matrices in his coordinates (x_f, y_f, θ0, θ1, θ2), J_ij from eq. 27."""
    t0, t1, t2 = sp.symbols("theta0 theta1 theta2", real=True)
    j13 = -l1 * sin(t0 + t1) - l2 * sin(t0 + t1 + t2)
    j15 = -l2 * sin(t0 + t1 + t2)
    j23 = l1 * cos(t0 + t1) + l2 * cos(t0 + t1 + t2)
    j25 = l2 * cos(t0 + t1 + t2)  # the paper prints J15 = −J25, i.e. J25 = l2 sin(...): a typo
    rows = [[sin(t0), -cos(t0), l0, 0, 0], [1, 0, j13, j13, j15], [0, 1, j23, j23, j25]] + extra_rows
    return sp.Matrix(rows), (t0, t1, t2)


def test_korayem_eq36_determinant_is_l0_up_to_sign(korayem):
    l0, l1, l2 = _symbols(korayem, ("l0", "l1", "l2"))
    task = stack(Position("xy"), PlanarAngle(), FunctionTask(elbow_angle, ("beta",)))
    ours = S.trig_normal(korayem.augmented_jacobian(task).det(), korayem.q)
    printed, angles = _korayem_printed([[0, 0, 1, 1, 1], [0, 0, 0, 0, -1]], l0, l1, l2)
    theirs = S.trig_normal(printed.det(), angles)
    # The platform coordinates here are the axle midpoint, Korayem's are the mount point F: the change of
    # coordinates (x_f, y_f) = (x + l0 cos θ, y + l0 sin θ) has unit Jacobian determinant, so both agree.
    assert ours == theirs == -l0  # the paper states Det = l0: |det| = l0, never singular


def test_korayem_eq37_determinant(korayem):
    l0, l1, l2 = _symbols(korayem, ("l0", "l1", "l2"))
    task = stack(Position("xy"), MountPosition())
    ours = S.trig_normal(korayem.augmented_jacobian(task).det(), korayem.q)
    printed, (t0, t1, t2) = _korayem_printed([[1, 0, 0, 0, 0], [0, 1, 0, 0, 0]], l0, l1, l2)
    theirs = S.trig_normal(printed.det(), (t0, t1, t2))
    theta2 = korayem.q[4]
    assert ours == l0 * l1 * l2 * sin(theta2)
    assert theirs == l0 * l1 * l2 * sin(t2)


def test_korayem_coordinate_change_relates_the_augmented_jacobians(korayem):
    l0, l1, l2 = _symbols(korayem, ("l0", "l1", "l2"))
    x, y, th, t1, t2 = korayem.q
    task = stack(Position("xy"), MountPosition())
    printed, (a0, a1, a2) = _korayem_printed([[1, 0, 0, 0, 0], [0, 1, 0, 0, 0]], l0, l1, l2)
    change = sp.Matrix([x + l0 * cos(th), y + l0 * sin(th), th, t1, t2])
    t = change.jacobian(sp.Matrix(korayem.q))
    assert sp.simplify(t.det()) == 1
    assert_same(printed.subs({a0: th, a1: t1, a2: t2}) * t, korayem.augmented_jacobian(task), korayem.q)


# --- symbolic vs numerical model ---------------------------------------------------------------------


@pytest.mark.parametrize(
    "name", ["bayle-planar", "bayle-rrp", "korayem-planar", "tchon-car-rtr", "yamamoto-dual-arm"]
)
def test_symbolic_j_bar_matches_numerical_model(name):
    robot = robots.build(name)
    model = S.model(robot)
    fn = sp.lambdify(model.q, model.reduced_jacobian(), "numpy")
    q = sample_configurations(robot, 8, seed=3)
    numeric = np.asarray(K.reduced_jacobian(robot, q))
    symbolic = np.stack([np.asarray(fn(*row), dtype=float) for row in q])
    np.testing.assert_allclose(symbolic, numeric, atol=1e-12)


def test_symbolic_parameters_match_numerical_model_at_other_values():
    names = ("L2", "L3", "L4", "a", "b", "c")
    model = S.SymbolicRobot(robots.manus_platform(), params=names, factory=robots.manus_platform)
    values = dict(L2=0.2, L3=0.45, L4=0.3, a=-0.1, b=0.05, c=0.7)
    jbar = model.reduced_jacobian().subs({model.params[k]: v for k, v in values.items()})
    fn = sp.lambdify(model.q, jbar, "numpy")
    robot = robots.manus_platform(**values)
    q = sample_configurations(robot, 5, seed=4)
    numeric = np.asarray(K.reduced_jacobian(robot, q))
    np.testing.assert_allclose(
        np.stack([np.asarray(fn(*row), dtype=float) for row in q]), numeric, atol=1e-12
    )


def test_a_mounted_robot_s_symbolic_parameters_keep_its_mount():
    # l1 a symbol, the arm 0.3 m ahead of the axle: x_ee = x + 3/10 cos θ + l1 cos(θ + q4) + l2 cos(θ + q4 + q5)
    model = S.SymbolicRobot(robots.design("bayle-planar", {"mount.x": 0.3}), params=("l1",))
    x, _, theta, q4, q5 = model.q
    l1 = model.params["l1"]
    expected = x + sp.Rational(3, 10) * sp.cos(theta) + l1 * sp.cos(theta + q4) + sp.cos(theta + q4 + q5) / 2
    assert sp.simplify(model.forward()[0] - expected) == 0


def test_exact_numbers():
    assert S.exact(0.12) == sp.Rational(3, 25)
    assert S.exact(math.pi) == sp.pi
    assert S.exact(math.cos(math.pi / 2)) == 0
    assert S.exact(math.sqrt(2) / 2) == sp.sqrt(2) / 2
    assert isinstance(S.exact(0.123456789), sp.Float)


def test_unsupported_inputs_raise_model_errors():
    with pytest.raises(ModelError, match="unknown parameter"):
        S.SymbolicRobot(robots.bayle_planar(), params=("l3",))
    with pytest.raises(ModelError, match="Pose is not supported"):  # the rotation vector: no closed form
        S.jacobian(robots.bayle_rrp(), Pose())
    with pytest.raises(ModelError, match="which"):
        S.rank_drop_conditions(robots.bayle_planar(), which="dynamic")
