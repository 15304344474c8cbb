"""Every task kind on every built-in robot over the whole joint range, exactly ±π/2 and π included: values
finite, J and J̄ finite unless the task reports a representation singularity, closed-form J = autodiff =
central finite differences; Bayle's RRP angles equal the joints (ξ4 = q3 + q4, ξ5 = q5, §5.2) everywhere."""

from __future__ import annotations

import math

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from mobman import kinematics as K
from mobman.model import (
    Elevation,
    EulerAngles,
    FunctionTask,
    MountPosition,
    PlanarAngle,
    Position,
    robots,
    spatial,
    stack,
)
from mobman.redundancy import sample_configurations

SPECIAL = np.array([0.0, math.pi / 2, -math.pi / 2, math.pi, -math.pi])


def _configurations(robot, n: int = 48, seed: int = 11) -> np.ndarray:
    """Random configurations over the whole range; each angle (platform heading, revolute joints) is
    replaced by one of 0, ±π/2, ±π with probability 1/2."""
    rng = np.random.default_rng(seed)
    q = sample_configurations(robot, n, seed)
    kinds = ["revolute"] * robot.platform.n_q + [j.kind for a in robot.arms for j in a.joints]
    angles = [i for i, kind in enumerate(kinds) if kind == "revolute" and i >= 2]
    special = rng.choice(SPECIAL, size=(n, len(angles)))
    keep = rng.random((n, len(angles))) < 0.5
    q[:, angles] = np.where(keep, q[:, angles], special)
    return q


def _tasks(robot) -> list:
    """One of every task kind, for the last arm's tool frame (the first arm's mount); two Euler sequences
    per robot, each sequence on two robots. The robot's own task comes first unless it is a pose, whose rows
    are (v, ω) rather than ∂ξ/∂q (checked over the whole range in test_model_tasks_pose.py)."""
    arm = len(robot.arms) - 1
    k = list(robots.ROBOTS).index(robot.name)
    sequences = spatial.EULER_SEQUENCES[k % 5], spatial.EULER_SEQUENCES[(k + 1) % 5]
    own = [robot.task] if robot.task.euclidean else []
    return [
        *own,
        Position("xyz", arm=arm),
        MountPosition("xy"),
        PlanarAngle(arm=arm),
        PlanarAngle("ZXY", arm=arm),
        Elevation(arm=arm),
        *(EulerAngles(seq, arm=arm) for seq in sequences),
        FunctionTask(lambda q: jnp.stack([jnp.sin(q[2]) * q[-1], q[0] - q[-1]]), ("f1", "f2")),
    ]


def _wrapped(d: np.ndarray) -> np.ndarray:
    return (d + math.pi) % (2 * math.pi) - math.pi


@pytest.mark.parametrize("name", list(robots.ROBOTS))
def test_every_task_over_the_whole_range(name):
    robot = robots.build(name)
    tasks = _tasks(robot)
    whole = stack(*tasks)
    rows = np.cumsum([0] + [t.dim for t in tasks])
    q = _configurations(robot, 32)
    h = 1e-6
    steps = h * np.eye(robot.n_q)
    points = np.concatenate(
        [q, (q[:, None] + steps).reshape(-1, robot.n_q), (q[:, None] - steps).reshape(-1, robot.n_q)]
    )

    def one(qq):  # everything from one compiled program (the public per-configuration methods)
        frames = robot.frames(qq)
        jac = whole.jacobian(robot, qq, frames)
        autodiff = jax.jacfwd(lambda x: whole.value(robot, x, robot.frames(x)))(qq)
        flags = jnp.stack([t.representation_singular(robot, qq, frames) for t in tasks])
        return whole.value(robot, qq, frames), jac, robot.apply_S(jac, qq), autodiff, robot.S(qq), flags

    value, jac, jbar, autodiff, s, flags = (np.asarray(a) for a in jax.jit(jax.vmap(one))(points))
    n = q.shape[0]
    plus, minus = value[n : n + n * robot.n_q], value[n + n * robot.n_q :]
    fd = _wrapped(plus - minus).reshape(n, robot.n_q, -1).transpose(0, 2, 1) / (2 * h)
    value, jac, jbar, autodiff, s, flags = value[:n], jac[:n], jbar[:n], autodiff[:n], s[:n], flags[:n]
    assert np.isfinite(value).all()
    public = K.representation_singular(robot, q, tasks[0]), K.reduced_jacobian(robot, q, tasks[0])  # batched
    np.testing.assert_array_equal(flags[:, 0], public[0])
    np.testing.assert_allclose(np.asarray(public[1]), jbar[:, : rows[1]], atol=1e-12)

    for k, task in enumerate(tasks):
        r = slice(rows[k], rows[k + 1])
        regular = ~flags[:, k]
        assert np.isfinite(jac[regular, r]).all(), task
        assert np.isfinite(jbar[regular, r]).all(), task
        np.testing.assert_allclose(jac[regular, r], autodiff[regular, r], rtol=1e-9, atol=1e-9)
        np.testing.assert_allclose(jbar[regular, r], (jac @ s)[regular, r], rtol=1e-9, atol=1e-9)
        tame = regular & (np.abs(jac[:, r]).max(axis=(1, 2)) < 10.0)  # FD error grows as 1 / margin³
        assert tame.sum() >= 5 or not regular.any(), task  # ZYZ on a planar arm: always locked
        np.testing.assert_allclose(fd[tame, r], jac[tame, r], atol=2e-6)


def test_representation_flags_where_the_coordinates_are_undefined():
    robot = robots.bayle_rrp()  # q5 = ±π/2: the tool's x axis vertical, its y axis (the lift axis) horizontal
    q = np.array([[0.1, -0.2, 0.3, 0.2, math.pi / 2, 0.9], [0.1, -0.2, 0.3, 0.2, -math.pi / 2, 0.9]])
    assert K.representation_singular(robot, q, PlanarAngle()).all()  # heading of a vertical x axis
    assert not K.representation_singular(robot, q, PlanarAngle("ZXY")).any()
    assert not K.representation_singular(robot, q, Elevation()).any()
    assert K.representation_singular(robot, q, EulerAngles("ZYX")).all()  # pitch ±π/2: gimbal lock
    assert not K.representation_singular(robot, q).any()  # the paper's ξ
    assert K.representation_singular(robot, q, stack(Position(), PlanarAngle())).all()
    q[:, 4] = 0.3
    assert not K.representation_singular(robot, q, stack(Position(), PlanarAngle(), EulerAngles("ZYX"))).any()
    assert K.representation_singular(robot, q[:, [0, 1, 2, 3, 3, 5]] * 0, EulerAngles("ZYZ")).all()


@pytest.mark.parametrize("q5", [*np.linspace(-math.pi, math.pi, 25), math.pi / 2, -math.pi / 2, 2.5])
def test_bayle_rrp_angles_are_the_joints_and_j_bar_the_printed_one(q5):
    robot = robots.bayle_rrp()
    q1, q2, q3, q4, q6 = 0.3, -0.4, 2.9, -1.1, 0.7
    q = np.array([q1, q2, q3, q4, q5, q6])
    xi = np.asarray(K.forward(robot, q))
    c5, s5, c34, s34 = math.cos(q5), math.sin(q5), math.cos(q3 + q4), math.sin(q3 + q4)
    dk = [q1 + q6 * c5 * c34, q2 + q6 * c5 * s34, q6 * s5, q3 + q4, q5]  # Bayle §5.2 DK
    np.testing.assert_allclose(xi[:3], dk[:3], atol=1e-14)
    np.testing.assert_allclose(_wrapped(xi[3:] - dk[3:]), 0.0, atol=1e-14)
    printed = np.array(  # Bayle §5.2, J̄(q_a, ϑ)
        [
            [math.cos(q3), -q6 * c5 * s34, -q6 * c5 * s34, -q6 * s5 * c34, c5 * c34],
            [math.sin(q3), q6 * c5 * c34, q6 * c5 * c34, -q6 * s5 * s34, c5 * s34],
            [0, 0, 0, q6 * c5, s5],
            [0, 1, 1, 0, 0],
            [0, 0, 0, 1, 0],
        ]
    )
    np.testing.assert_allclose(np.asarray(K.reduced_jacobian(robot, q)), printed, atol=1e-14)
