"""mobman.model.robots: the paper robots' kinematics against the closed forms printed in the papers."""

from __future__ import annotations

import math

import numpy as np

from mobman import kinematics as K
from mobman.model import (
    MountPosition,
    robots,
)


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
    L2, L3, L4 = 0.12, 0.35, 0.3
    robot = robots.manus_platform(L2=L2, L3=L3, L4=L4, a=0.0, b=0.0, c=0.0)
    qa = np.array([0.4, 0.9, -0.5])
    c1, s1, c2, s2, c3, s3 = (f(v) for v in qa for f in (math.cos, math.sin))
    ja = [
        [-(L4 * c3 + L3 * c2) * s1 - L2 * c1, -L3 * c1 * s2, -L4 * c1 * s3],
        [(L4 * c3 + L3 * c2) * c1 - L2 * s1, -L3 * s1 * s2, -L4 * s3 * s1],
        [0, L3 * c2, L4 * c3],
    ]
    xa = [(L4 * c3 + L3 * c2) * c1 - L2 * s1, (L4 * c3 + L3 * c2) * s1 + L2 * c1, L4 * s3 + L3 * s2]
    q = np.concatenate([[0.0, 0.0, 0.0], qa])
    np.testing.assert_allclose(K.forward(robot, q), xa, atol=1e-14)
    np.testing.assert_allclose(np.asarray(K.jacobian(robot, q))[:, 3:], ja, atol=1e-14)


def test_tchon_output_map_eq31():
    l2, l3 = 0.6, 0.4
    robot = robots.tchon_car_rtr()
    q = np.array([1.0, -2.0, 0.3, 0.5, 0.7, 2.0, math.pi / 4])
    q1, q2, q3, _, x1, x2, x3 = q
    y = [
        q1 + (l2 + l3 * math.cos(x3)) * math.cos(q3 + x1),
        q2 + (l2 + l3 * math.cos(x3)) * math.sin(q3 + x1),
        x2 + l3 * math.sin(x3),
    ]
    np.testing.assert_allclose(K.forward(robot, q), y, atol=1e-14)


def test_korayem_mount_point_and_constraint_eq20_23():
    robot = robots.korayem_planar()
    q = np.array([0.2, 0.1, 0.7, 0.3, 1.0])
    f = K.forward(robot, q, MountPosition())
    np.testing.assert_allclose(f, [0.2 + 0.4 * math.cos(0.7), 0.1 + 0.4 * math.sin(0.7)], atol=1e-14)
    # velocity of F satisfies ẋ_f sin θ − ẏ_f cos θ + l0 θ̇ = 0 for any admissible motion (eq. 22)
    eta = np.array([0.3, -0.8, 0.1, 0.2])
    qdot = np.asarray(K.S(robot, q)) @ eta
    fdot = np.asarray(K.jacobian(robot, q, MountPosition())) @ qdot
    assert abs(fdot[0] * math.sin(0.7) - fdot[1] * math.cos(0.7) + 0.4 * qdot[2]) < 1e-14
