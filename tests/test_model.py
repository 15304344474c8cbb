"""The model layer (model/robot.py, arm.py, platforms, tasks, spatial.py): closed forms of the papers, autodiff,
properties. The kinematics functions on top of it: tests/test_kinematics.py."""

from __future__ import annotations

import math

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from hypothesis import strategies as st

import mobman
from mobman import kinematics as K
from mobman.model import (
    Arm,
    CarLike,
    DifferentialDrive,
    EulerAngles,
    FunctionTask,
    Joint,
    MobileManipulator,
    Mount,
    MountPosition,
    Omnidirectional,
    PlanarAngle,
    Position,
    robots,
    spatial,
    stack,
)
from mobman.model.spatial import euler_angles, euler_matrix
from mobman.model.tasks import elbow_angle

ALL = [f() for f in robots.PAPER_ROBOTS.values()]  # the real robots: test_urdf_pinocchio.py
angles = st.floats(-math.pi, math.pi)


def _random_q(robot, n=5, seed=0):
    return np.random.default_rng(seed).uniform(-2, 2, size=(n, robot.n_q))


# --- closed forms from the papers ---------------------------------------------------------------


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


# --- Jacobians three ways ---------------------------------------------------------------------------


@pytest.mark.parametrize("sequence", ["ZYZ", "ZYX", "XYZ", "ZXZ"])
def test_euler_angle_task_jacobian_matches_autodiff(sequence):
    robot = robots.manus_platform().with_task(stack(Position(), EulerAngles(sequence)))
    q = np.array([0.1, 0.2, 0.3, 0.4, 0.7, -0.2])
    j = np.asarray(K.jacobian(robot, q))
    auto = jax.jacfwd(lambda qq: robot.task.value(robot, qq, robot.frames(qq)))(jnp.asarray(q))
    np.testing.assert_allclose(j, auto, atol=1e-12)


@pytest.mark.parametrize("sequence", ["ZYZ", "ZYX", "XYZ", "ZXZ"])
def test_euler_angles_round_trip(sequence):
    a = np.array([0.3, 1.1, -0.7])
    np.testing.assert_allclose(euler_angles(jnp.asarray(euler_matrix(a, sequence)), sequence), a, atol=1e-12)


def _axis_rotation(axis: str, a: jnp.ndarray) -> jnp.ndarray:
    c, s = jnp.cos(a), jnp.sin(a)
    i, j = {"X": (1, 2), "Y": (2, 0), "Z": (0, 1)}[axis]
    r = jnp.eye(3)
    return r.at[i, i].set(c).at[j, j].set(c).at[i, j].set(-s).at[j, i].set(s)


@pytest.mark.parametrize("sequence", ["ZYX", "XYZ", "ZXY"])
@pytest.mark.parametrize("margin", [1.5e-8, 1e-6, 0.3])
def test_middle_euler_angle_has_unit_derivative_up_to_the_gimbal_lock(sequence, margin):
    """a2 of R_{s1}(a1) R_{s2}(a2) R_{s3}(a3) near a2 = π/2: ∂a2/∂a2 = 1 and ∂a1/∂a2 = ∂a3/∂a2 = 0, also a
    margin cos a2 of 1.5e-8 from the gimbal lock (an arcsin form gives NaN there)."""

    def angles(a2):
        r = (
            _axis_rotation(sequence[0], 0.4)
            @ _axis_rotation(sequence[1], a2)
            @ _axis_rotation(sequence[2], -0.8)
        )
        return euler_angles(r, sequence)

    a2 = math.acos(margin)
    np.testing.assert_allclose(angles(a2), [0.4, a2, -0.8], atol=1e-7)
    np.testing.assert_allclose(jax.jacfwd(angles)(a2), [0.0, 1.0, 0.0], atol=1e-6)


def test_planar_angle_equals_angle_sum():
    robot = robots.bayle_planar()
    q = np.array([0.0, 0.0, 0.2, 0.3, 0.4])
    assert float(K.forward(robot, q, PlanarAngle())[0]) == pytest.approx(0.9)


def test_function_task_elbow_angle():
    robot = robots.korayem_planar()
    task = FunctionTask(elbow_angle, ("beta",))
    q = np.array([0, 0, 0, 0.3, 1.0])
    assert float(K.forward(robot, q, task)[0]) == pytest.approx(math.pi - 1.0)
    np.testing.assert_allclose(K.jacobian(robot, q, task), [[0, 0, 0, 0, -1]])


# --- properties -----------------------------------------------------------------------------------
# G S = 0, J̄ = J S and frame invariance for every built-in robot and platform: tests/test_identities.py


# --- platforms -------------------------------------------------------------------------------------


def test_controllability_by_lie_brackets():
    assert DifferentialDrive().is_controllable()
    assert CarLike().lie_algebra_rank(jnp.array([0.0, 0.0, 0.0, 0.3])) == 4
    assert CarLike().lie_algebra_rank(jnp.zeros(4), depth=1) == 2
    assert Omnidirectional().is_controllable(depth=1)


def test_wheel_kinematics_round_trip_korayem_eq14_15():
    p = DifferentialDrive(wheel_radius=0.075, half_track=0.171)
    wheels = np.array([2.0, 1.0])
    v, w = np.asarray(p.wheel_speeds_to_eta(wheels))
    assert v == pytest.approx(0.075 * 1.5)
    assert w == pytest.approx(0.075 * 1.0 / (2 * 0.171))
    np.testing.assert_allclose(p.eta_to_wheel_speeds(np.array([v, w])), wheels, atol=1e-14)
    limits = DifferentialDrive(
        wheel_radius=0.075, half_track=0.171, wheel_speed_max=1 / 0.075
    ).velocity_limits
    assert limits == pytest.approx((1.0, 1.0 / 0.171))


def test_car_constraints_are_no_side_slip_of_both_axles():
    car = CarLike(length=1.3)
    q = jnp.array([0.0, 0.0, 0.4, 0.3])
    eta = jnp.array([0.7, 0.2])
    qd = car.S(q) @ eta
    front_velocity = qd[:2] + 1.3 * qd[2] * jnp.array([-jnp.sin(0.4), jnp.cos(0.4)])
    lateral = jnp.array([-jnp.sin(0.7), jnp.cos(0.7)])
    assert abs(float(front_velocity @ lateral)) < 1e-14


# --- arms from DH tables ------------------------------------------------------------------------------

PANDA_MDH = [
    (0, 0, 0, 0.333),
    (-math.pi / 2, 0, 0, 0),
    (math.pi / 2, 0, 0, 0.316),
    (math.pi / 2, 0.0825, 0, 0),
    (-math.pi / 2, -0.0825, 0, 0.384),
    (math.pi / 2, 0, 0, 0),
    (math.pi / 2, 0.088, 0, 0),
]


def _mdh_matrix(alpha, a, theta, d):
    ca, sa, ct, st_ = math.cos(alpha), math.sin(alpha), math.cos(theta), math.sin(theta)
    return np.array(
        [[ct, -st_, 0, a], [st_ * ca, ct * ca, -sa, -d * sa], [st_ * sa, ct * sa, ca, d * ca], [0, 0, 0, 1]]
    )


def _dh_matrix(theta, d, a, alpha):
    ca, sa, ct, st_ = math.cos(alpha), math.sin(alpha), math.cos(theta), math.sin(theta)
    return np.array(
        [[ct, -st_ * ca, st_ * sa, a * ct], [st_, ct * ca, -ct * sa, a * st_], [0, sa, ca, d], [0, 0, 0, 1]]
    )


@pytest.mark.parametrize("kind", ["revolute", "prismatic"])
def test_joint_pose_after_is_parent_then_origin_then_motion(kind):
    """Joint.pose_after (Rodrigues written with the constant factors as scalars) equals the parent pose times
    the origin transform times the motion built independently (SciPy's rotation vector), batched."""
    from scipy.spatial.transform import Rotation

    rng = np.random.default_rng(3)
    axis = rng.normal(size=3)
    axis /= np.linalg.norm(axis)
    origin, parent = np.eye(4), np.eye(4)
    origin[:3, :3] = Rotation.from_rotvec(rng.normal(size=3)).as_matrix()
    origin[:3, 3] = rng.normal(size=3)
    parent[:3, :3] = Rotation.from_rotvec(rng.normal(size=3)).as_matrix()
    parent[:3, 3] = rng.normal(size=3)
    joint = Joint(kind, tuple(axis), tuple(origin.ravel()), offset=0.3)
    q = rng.uniform(-3, 3, size=(4, 2))
    base = (jnp.broadcast_to(parent[:3, :3], (4, 2, 3, 3)), jnp.broadcast_to(parent[:3, 3], (4, 2, 3)))
    rot, p = joint.pose_after(base, jnp.asarray(q))
    assert rot.shape == (4, 2, 3, 3) and p.shape == (4, 2, 3)
    for index in np.ndindex(q.shape):
        motion = np.eye(4)
        value = q[index] + 0.3
        if kind == "revolute":
            motion[:3, :3] = Rotation.from_rotvec(value * axis).as_matrix()
        else:
            motion[:3, 3] = value * axis
        expected = parent @ origin @ motion
        np.testing.assert_allclose(rot[index], expected[:3, :3], atol=1e-14)
        np.testing.assert_allclose(p[index], expected[:3, 3], atol=1e-14)


def test_unstack_components_and_their_one_concatenation_gradient():
    """spatial.unstack gives a[..., i], and its reverse-mode derivative equals central differences."""
    from mobman.model.spatial import cross, unstack

    a = np.random.default_rng(5).normal(size=(4, 3))
    for i, part in enumerate(unstack(jnp.asarray(a))):
        np.testing.assert_array_equal(part, a[:, i])

    def loss(x):
        return jnp.sum(cross(x, x[::-1]) ** 2)

    h = 1e-6
    fd = np.zeros_like(a)
    for index in np.ndindex(a.shape):
        e = np.zeros_like(a)
        e[index] = h
        fd[index] = (loss(a + e) - loss(a - e)) / (2 * h)
    np.testing.assert_allclose(jax.grad(loss)(jnp.asarray(a)), fd, rtol=1e-6, atol=1e-8)


def test_matrix_products_written_out_and_as_reductions_equal_numpy():
    """spatial.matmul (one reduction) and spatial.matmul_expanded (sum of outer products) equal NumPy's
    product for stacks with broadcast leading dimensions and non-square shapes, and so do their gradients."""
    rng = np.random.default_rng(12)
    a, b = rng.normal(size=(4, 1, 3, 5)), rng.normal(size=(6, 5, 2))
    for product in (spatial.matmul, spatial.matmul_expanded):
        np.testing.assert_allclose(product(jnp.asarray(a), jnp.asarray(b)), a @ b, rtol=0, atol=1e-14)
        grad = jax.grad(lambda x, f=product: jnp.sum(f(x, jnp.asarray(b)) ** 2))(jnp.asarray(a))
        np.testing.assert_allclose(
            grad, (2 * (a @ b) @ np.swapaxes(b, -1, -2)).sum(axis=1, keepdims=True), atol=1e-12
        )


@pytest.mark.parametrize("task", [Position("xz"), EulerAngles("ZYX", select=(2, 0))])
def test_task_rows_are_the_chosen_rows_of_the_full_task(task):
    """A task restricted to some rows gives exactly those rows of the full task's value and Jacobian."""
    robot = robots.manus_platform()
    full = Position("xyz") if isinstance(task, Position) else EulerAngles("ZYX")
    rows = [0, 2] if isinstance(task, Position) else [2, 0]
    q = _random_q(robot, 3)
    np.testing.assert_array_equal(K.jacobian(robot, q, task), np.asarray(K.jacobian(robot, q, full))[:, rows])
    np.testing.assert_array_equal(K.forward(robot, q, task), np.asarray(K.forward(robot, q, full))[:, rows])


def test_modified_dh_matches_textbook_product():
    arm = Arm.from_modified_dh(PANDA_MDH)
    q = np.random.default_rng(1).uniform(-2, 2, 7)
    expected = np.eye(4)
    for row, qi in zip(PANDA_MDH, q):
        alpha, a, theta, d = row
        expected = expected @ _mdh_matrix(alpha, a, theta + qi, d)
    rs, ps = arm.link_poses(jnp.asarray(q))
    np.testing.assert_allclose(rs[-1], expected[:3, :3], atol=1e-12)
    np.testing.assert_allclose(ps[-1], expected[:3, 3], atol=1e-12)


def test_standard_dh_with_prismatic_joint_matches_textbook_product():
    table = [(0.1, 0.3, 0.2, math.pi / 2), (0.0, 0.1, 0.0, -math.pi / 2), (0.4, 0.0, 0.3, 0.0)]
    arm = Arm.from_dh(table, "RPR")
    q = np.array([0.3, 0.25, -0.8])
    expected = np.eye(4)
    for (theta, d, a, alpha), qi, kind in zip(table, q, "RPR"):
        expected = expected @ (
            _dh_matrix(theta + qi, d, a, alpha) if kind == "R" else _dh_matrix(theta, d + qi, a, alpha)
        )
    rs, ps = arm.link_poses(jnp.asarray(q))
    np.testing.assert_allclose(rs[-1], expected[:3, :3], atol=1e-12)
    np.testing.assert_allclose(ps[-1], expected[:3, 3], atol=1e-12)


def test_two_arms_and_mount_offsets():
    arm = robots.planar_arm((1.0,))
    robot = MobileManipulator(
        DifferentialDrive(),
        (arm, arm),
        (Mount(0.5), Mount(0.0, 0.3, 0.2, yaw=math.pi / 2)),
        task=stack(Position(arm=0), Position(arm=1)),
    )
    q = np.array([1.0, 2.0, 0.0, 0.0, 0.0])
    np.testing.assert_allclose(K.forward(robot, q), [2.5, 2.0, 0.0, 1.0, 3.3, 0.2], atol=1e-14)
    assert robot.coordinate_names == ("x", "y", "theta", "arm1.q1", "arm2.q1")


# --- immutability and errors ----------------------------------------------------------------------------


def test_models_are_hashable_and_equal_by_value():
    assert robots.bayle_planar() == robots.bayle_planar()
    assert hash(robots.bayle_planar()) == hash(robots.bayle_planar())
    assert robots.bayle_planar(l1=0.6) != robots.bayle_planar()


@pytest.mark.parametrize(
    "make, match",
    [
        (lambda: robots.bayle_planar(l1=-1.0), "l1 \\(a length\\) must be a finite number > 0"),
        (lambda: robots.build("nonexistent"), "unknown robot"),
        (lambda: robots.build("bayle-planar", l9=1.0), "unknown parameter 'l9'"),
        (lambda: DifferentialDrive(wheel_radius=0.0), "wheel_radius must be"),
        (lambda: mobman.LinkInertial(-1.0), "mass must be"),
        (lambda: mobman.LinkInertial(1.0, inertia=(1, 2, 0, 0, 1, 0, 0, 0, 1)), "symmetric"),
        (lambda: mobman.LinkInertial(1.0, inertia=(-1.0, 1.0, 1.0)), "positive semi-definite"),
        (lambda: Position("xw"), "components"),
        (lambda: EulerAngles("ABC"), "not supported"),
        (lambda: Arm.from_dh([(0, 0, 1)]), "4 numbers"),
    ],
)
def test_bad_model_input_raises_model_error(make, match):
    with pytest.raises(mobman.ModelError, match=match):
        make()
