"""mobman.model.robots: the paper robots' kinematics against the closed forms printed in the papers.

Each paper robot's mount is checked against its paper's forward-kinematics equation typed literally (the
``*_literal`` tests): the value at configurations over the whole joint range (angles exactly at 0, ±π/2 and
π included), and J̄ against ``jax.jacfwd`` of the literal formula times the paper's S(q).
"""

from __future__ import annotations

import math

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from mobman import kinematics as K
from mobman.model import (
    MountPosition,
    robots,
)
from mobman.model.tasks import PlanarAngle, Position, stack

from task_checks import configurations


def unicycle(theta: jnp.ndarray, n_arm: int) -> jnp.ndarray:
    """S(q) = diag(S_p(θ), I): ẋ = v cos θ, ẏ = v sin θ, θ̇ = ω (Bayle §4.1; Nait-Chabane eq. 5 and 11;
    Korayem eq. 17 with v = R(φ̇_r + φ̇_l)/2; Yamamoto & Yun eq. 4–6 with v = cb(θ̇_r + θ̇_l), ω = φ̇)."""
    s_p = jnp.array([[jnp.cos(theta), 0.0], [jnp.sin(theta), 0.0], [0.0, 1.0]])
    return jax.scipy.linalg.block_diag(s_p, jnp.eye(n_arm))


def assert_matches_literal(robot, literal, S, q, task=None, angles=()) -> None:
    """ξ = literal(q) (the rows ``angles`` modulo 2π) and J̄ = ∂literal/∂q · S(q) at every row of ``q``."""
    expected = np.asarray(jax.vmap(literal)(jnp.asarray(q)))
    value = np.asarray(K.forward(robot, q, task))
    difference = value - expected
    difference[:, list(angles)] = np.angle(np.exp(1j * difference[:, list(angles)]))
    np.testing.assert_allclose(difference, 0.0, atol=1e-13)
    jbar = jax.vmap(lambda qq: jax.jacfwd(literal)(qq) @ S(qq))(jnp.asarray(q))
    np.testing.assert_allclose(K.reduced_jacobian(robot, q, task), jbar, rtol=0, atol=1e-13)


def manus_arm(L2: float, L3: float, L4: float, q_a) -> tuple[jnp.ndarray, jnp.ndarray]:
    """Nait-Chabane's arm alone: x_a = (x_a1, x_a2, x_a3) of eq. 3 and J_a of eq. 27, (..., 3) and (..., 3, 3)."""
    c1, s1, c2, s2, c3, s3 = (f(q_a[..., k]) for k in range(3) for f in (jnp.cos, jnp.sin))
    reach = L4 * c3 + L3 * c2
    x_a = jnp.stack([reach * c1 - L2 * s1, reach * s1 + L2 * c1, L4 * s3 + L3 * s2], -1)
    rows = [
        [-reach * s1 - L2 * c1, -L3 * c1 * s2, -L4 * c1 * s3],
        [reach * c1 - L2 * s1, -L3 * s1 * s2, -L4 * s3 * s1],
        [jnp.zeros_like(c1), L3 * c2, L4 * c3],
    ]
    return x_a, jnp.stack([jnp.stack(row, -1) for row in rows], -2)


def test_bayle_planar_forward_and_jacobians_match_paper():
    l1, l2 = 0.7, 0.4
    robot = robots.bayle_planar(l1=l1, l2=l2)
    q = np.array([0.3, -1.2, 0.4, 1.1, -0.6])
    _, _, q3, q4, q5 = q
    s34, c34 = math.sin(q3 + q4), math.cos(q3 + q4)
    s345, c345 = math.sin(q3 + q4 + q5), math.cos(q3 + q4 + q5)
    xi = [q[0] + l1 * c34 + l2 * c345, q[1] + l1 * s34 + l2 * s345, q3 + q4 + q5]
    j = [
        [1, 0, -(l1 * s34 + l2 * s345), -(l1 * s34 + l2 * s345), -l2 * s345],
        [0, 1, l1 * c34 + l2 * c345, l1 * c34 + l2 * c345, l2 * c345],
        [0, 0, 1, 1, 1],
    ]
    jbar = [
        [math.cos(q3), j[0][2], j[0][3], j[0][4]],
        [math.sin(q3), j[1][2], j[1][3], j[1][4]],
        [0, 1, 1, 1],
    ]
    np.testing.assert_allclose(K.forward(robot, q), xi, atol=1e-14)
    np.testing.assert_allclose(K.jacobian(robot, q), j, atol=1e-14)
    np.testing.assert_allclose(K.reduced_jacobian(robot, q), jbar, atol=1e-14)


def test_bayle_rrp_jacobians_match_paper():
    robot = robots.bayle_rrp()
    q = np.array([0.5, 0.2, -0.3, 0.9, 0.45, 1.3])
    q3, q4, q5, q6 = q[2:]
    c5, s5, c34, s34 = math.cos(q5), math.sin(q5), math.cos(q3 + q4), math.sin(q3 + q4)
    j = np.array(
        [
            [1, 0, -q6 * c5 * s34, -q6 * c5 * s34, -q6 * s5 * c34, c5 * c34],
            [0, 1, q6 * c5 * c34, q6 * c5 * c34, -q6 * s5 * s34, c5 * s34],
            [0, 0, 0, 0, q6 * c5, s5],
            [0, 0, 1, 1, 0, 0],
            [0, 0, 0, 0, 1, 0],
        ]
    )
    xi = [q[0] + q6 * c5 * c34, q[1] + q6 * c5 * s34, q6 * s5, q3 + q4, q5]
    jbar = np.column_stack([math.cos(q3) * j[:, 0] + math.sin(q3) * j[:, 1], j[:, 2:]])
    np.testing.assert_allclose(K.forward(robot, q), xi, atol=1e-14)
    np.testing.assert_allclose(K.jacobian(robot, q), j, atol=1e-14)
    np.testing.assert_allclose(K.reduced_jacobian(robot, q), jbar, atol=1e-14)


def test_manus_arm_jacobian_matches_nait_chabane_eq27():
    """Eq. 3 and 27 in the arm frame {A}: with a = b = c = 0 and θ_p = π/2, eq. 8 gives X = X_a."""
    L2, L3, L4 = 0.12, 0.35, 0.3
    robot = robots.manus_platform(L2=L2, L3=L3, L4=L4, a=0.0, b=0.0, c=0.0)
    q = configurations(6, seed=10)
    q[:, :3] = (0.0, 0.0, math.pi / 2)
    x_a, j_a = manus_arm(L2, L3, L4, q[:, 3:])
    np.testing.assert_allclose(K.forward(robot, q), x_a, atol=1e-14)
    np.testing.assert_allclose(np.asarray(K.jacobian(robot, q))[:, :, 3:], j_a, atol=1e-14)


def test_bayle_planar_literal():
    """Bayle §5.1: the 2R arm's base at the axle midpoint, its angle q4 counted from the heading (DK)."""
    l1, l2 = 0.7, 0.4
    robot = robots.bayle_planar(l1=l1, l2=l2)

    def dk(q):  # Bayle §5.1, DK
        q1, q2, q3, q4, q5 = q
        return jnp.array(
            [
                q1 + l1 * jnp.cos(q3 + q4) + l2 * jnp.cos(q3 + q4 + q5),
                q2 + l1 * jnp.sin(q3 + q4) + l2 * jnp.sin(q3 + q4 + q5),
                q3 + q4 + q5,
            ]
        )

    assert_matches_literal(robot, dk, lambda q: unicycle(q[2], 2), configurations(5, seed=11), angles=(2,))


def test_bayle_rrp_literal():
    """Bayle §5.2: the RRP arm's base at the axle midpoint, q4 counted from the heading (DK)."""
    robot = robots.bayle_rrp()

    def dk(q):  # Bayle §5.2, DK
        q1, q2, q3, q4, q5, q6 = q
        return jnp.array(
            [
                q1 + q6 * jnp.cos(q5) * jnp.cos(q3 + q4),
                q2 + q6 * jnp.cos(q5) * jnp.sin(q3 + q4),
                q6 * jnp.sin(q5),
                q3 + q4,
                q5,
            ]
        )

    q = configurations(6, seed=12)
    q[:, 5] = np.abs(q[:, 5])  # q6 ≥ 0: the prismatic joint's range
    assert_matches_literal(robot, dk, lambda q: unicycle(q[2], 3), q, angles=(3, 4))


MANUS_DESIGNS = [
    {},  # §4.2.2: L2 = 0.12, L3 = L4 = 0.35 (chosen), arm base (0.12, 0.12, 0.4) m
    {"L2": 0.1, "L3": 0.3, "L4": 0.25, "a": 0.07, "b": -0.05, "c": 0.3},  # every length distinct
    {"a": 0.0, "b": 0.0, "c": 0.0},  # §4.1.2: arm base at the axle midpoint
]


@pytest.mark.parametrize("params", MANUS_DESIGNS)
def test_nait_chabane_manus_platform_literal(params):
    """Nait-Chabane eq. 8 with the arm's own forward kinematics eq. 3: the arm frame {A} at (a, b, c) in the
    platform frame, turned by −π/2 about the vertical (x4 = φ + θ_p − π/2), S = M(q) of eq. 11."""
    robot = robots.manus_platform(**params)
    p = {"L2": 0.12, "L3": 0.35, "L4": 0.35, "a": 0.12, "b": 0.12, "c": 0.4, **params}
    L2, L3, L4, a, b, c = (p[k] for k in ("L2", "L3", "L4", "a", "b", "c"))

    def eq8(q):
        xp, yp, thp = q[:3]
        xa1, xa2, xa3 = manus_arm(L2, L3, L4, q[3:])[0]  # eq. 3
        return jnp.array(
            [
                xp + (xa2 + a) * jnp.cos(thp) - (b - xa1) * jnp.sin(thp),  # eq. 8
                yp + (xa2 + a) * jnp.sin(thp) + (b - xa1) * jnp.cos(thp),
                xa3 + c,
            ]
        )

    q = configurations(6, seed=13)
    assert_matches_literal(robot, eq8, lambda q: unicycle(q[2], 3), q)
    # x4 = φ + θ_p − π/2: every heading in {A} is the world heading less θ_p − π/2
    theta = q[:, 2] - math.pi / 2
    rotation, _ = K.frames(robot, q).mounts[0]
    zero = np.zeros_like(theta)
    turn = np.stack(
        [np.cos(theta), -np.sin(theta), zero, np.sin(theta), np.cos(theta), zero, zero, zero, zero + 1]
    )
    np.testing.assert_allclose(rotation, turn.T.reshape(-1, 3, 3), atol=1e-15)


def test_nait_chabane_printed_reduced_jacobian_eq28():
    """J̄ of eq. 28 entry by entry, with J_a of eq. 27 and x_a1, x_a2 of eq. 3, at the arm base (a, b, c)."""
    L2, L3, L4, a, b, c = 0.1, 0.3, 0.25, 0.07, -0.05, 0.3
    robot = robots.manus_platform(L2=L2, L3=L3, L4=L4, a=a, b=b, c=c)
    q = configurations(6, seed=17)
    ct, st = np.cos(q[:, 2]), np.sin(q[:, 2])
    x_a, ja = (np.asarray(v) for v in manus_arm(L2, L3, L4, q[:, 3:]))
    xa1, xa2 = x_a[:, 0], x_a[:, 1]
    jbar = np.zeros((len(q), 3, 5))
    jbar[:, 0, 0], jbar[:, 1, 0] = ct, st
    jbar[:, 0, 1] = -(xa2 + a) * st - (b - xa1) * ct
    jbar[:, 1, 1] = (xa2 + a) * ct - (b - xa1) * st
    jbar[:, 0, 2:] = ja[:, 1] * ct[:, None] + ja[:, 0] * st[:, None]  # J̄_13, J̄_14, J̄_15
    jbar[:, 1, 2:] = ja[:, 1] * st[:, None] - ja[:, 0] * ct[:, None]  # J̄_23, J̄_24, J̄_25
    jbar[:, 2, 2:] = ja[:, 2]
    np.testing.assert_allclose(K.reduced_jacobian(robot, q), jbar, rtol=0, atol=1e-14)


def test_korayem_planar_literal():
    """Korayem eq. 20 and 25: the arm at F, l0 ahead of the axle midpoint on the heading, its first joint's
    angle θ1 counted from the heading; α_e = θ0 + θ1 + θ2; F's velocity obeys eq. 22."""
    l0, l1, l2 = 0.4, 0.5, 0.3
    robot = robots.korayem_planar(l0=l0, l1=l1, l2=l2)
    task = stack(Position("xy"), PlanarAngle())

    def eq25(q):
        xb, yb, th0, th1, th2 = q
        xf, yf = xb + l0 * jnp.cos(th0), yb + l0 * jnp.sin(th0)  # eq. 20
        return jnp.array(
            [
                xf + l1 * jnp.cos(th0 + th1) + l2 * jnp.cos(th0 + th1 + th2),
                yf + l1 * jnp.sin(th0 + th1) + l2 * jnp.sin(th0 + th1 + th2),
                th0 + th1 + th2,
            ]
        )

    q = configurations(5, seed=14)
    assert_matches_literal(robot, eq25, lambda q: unicycle(q[2], 2), q, task, angles=(2,))
    # eq. 22: ẋ_f sin θ0 − ẏ_f cos θ0 + l0 θ̇0 = 0 for every admissible motion
    eta = np.random.default_rng(14).normal(size=(len(q), 4))
    qdot = np.einsum("nij,nj->ni", np.asarray(K.S(robot, q)), eta)
    fdot = np.einsum("nij,nj->ni", np.asarray(K.jacobian(robot, q, MountPosition())), qdot)
    residual = fdot[:, 0] * np.sin(q[:, 2]) - fdot[:, 1] * np.cos(q[:, 2]) + l0 * qdot[:, 2]
    np.testing.assert_allclose(residual, 0.0, atol=1e-14)


def test_tchon_car_rtr_literal():
    """Tchoń et al. eq. 31: the RTR arm's base at the rear-axle midpoint, x1 counted from the heading; S from
    the control system of eq. 31 (the car's length is the unit)."""
    l2, l3 = 0.6, 0.4
    robot = robots.tchon_car_rtr(l2=l2, l3=l3)

    def k(q):  # eq. 31
        q1, q2, q3, _, x1, x2, x3 = q
        return jnp.array(
            [
                q1 + (l2 + l3 * jnp.cos(x3)) * jnp.cos(q3 + x1),
                q2 + (l2 + l3 * jnp.cos(x3)) * jnp.sin(q3 + x1),
                x2 + l3 * jnp.sin(x3),
            ]
        )

    def control_system(q):  # eq. 31: q̇1 = u1 cos q3 cos q4, q̇2 = u1 sin q3 cos q4, q̇3 = u1 sin q4, q̇4 = u2
        _, _, q3, q4 = q[:4]
        g = jnp.array(
            [
                [jnp.cos(q3) * jnp.cos(q4), 0.0],
                [jnp.sin(q3) * jnp.cos(q4), 0.0],
                [jnp.sin(q4), 0.0],
                [0.0, 1.0],
            ]
        )
        return jax.scipy.linalg.block_diag(g, jnp.eye(3))

    assert_matches_literal(robot, k, control_system, configurations(7, seed=15))


def test_yamamoto_dual_arm_literal():
    """Yamamoto & Yun §4: both arms have their common origin at the midpoint P_o between the wheels, links of
    Table 1 (L_i = 0.5 m), motion horizontal. The paper prints no forward kinematics and its figures 1–2 are
    missing from the text, so the direction of each arm's zero angle is not given: the arms' zero angle
    along the heading φ is the model's choice, and only the common origin at P_o and the link lengths are
    the paper's."""
    robot = robots.yamamoto_dual_arm()
    L = 0.5

    def tools(q):
        x, y, phi = q[:3]
        out = []
        for arm in (q[3:6], q[6:9]):
            angles = phi + jnp.cumsum(arm)
            out += [x + L * jnp.sum(jnp.cos(angles)), y + L * jnp.sum(jnp.sin(angles)), angles[-1]]
        return jnp.array(out)

    task = stack(Position("xy"), PlanarAngle(), Position("xy", arm=1), PlanarAngle(arm=1))
    assert_matches_literal(
        robot, tools, lambda q: unicycle(q[2], 6), configurations(9, seed=16), task, (2, 5)
    )
