"""The task registry (mobman.model.tasks.base): kinds found by name, a typo answered with the closest kind, and
a task kind defined in this file — one class, no other edit — found by kind from a table and working in the
numerical and the symbolic kinematics; the Euler angles' closed form against the numerical angles; a task
restricted to some rows."""

from __future__ import annotations

import math
from dataclasses import dataclass

import jax.numpy as jnp
import numpy as np
import pytest
import sympy as sp

from mobman import kinematics as K
from mobman import symbolic as S
from mobman.errors import InputError, ModelError
from mobman.io.tasks import task as task_from_table
from mobman.model import robots, spatial
from mobman.model.tasks import EulerAngles, Position, Task, stack, task_class, task_kinds
from mobman.redundancy import sample_configurations

SPECIAL = np.array([0.0, math.pi / 2, -math.pi / 2, math.pi, -math.pi])


@dataclass(frozen=True)
class JointSum(Task):
    """ξ = Σ_i q_i over ``joints`` (indices into q): a task kind that exists only in this test file."""

    kind = "test_joint_sum"

    joints: tuple[int, ...] = (3, 4)
    label: str = "s"

    @property
    def names(self) -> tuple[str, ...]:
        return (self.label,)

    def value(self, robot, q, frames):
        return jnp.sum(jnp.stack([q[i] for i in self.joints]))[None]

    def symbolic(self, kin):
        return [sum(kin.q[i] for i in self.joints)]


def _configurations(robot, n: int, seed: int) -> np.ndarray:
    """Random configurations over the whole range, half of the angles replaced by 0, ±π/2 or ±π."""
    rng = np.random.default_rng(seed)
    q = sample_configurations(robot, n, seed)
    kinds = ["revolute"] * robot.platform.n_q + [j.kind for a in robot.arms for j in a.joints]
    angles = [i for i, kind in enumerate(kinds) if kind == "revolute" and i >= 2]
    special = rng.choice(SPECIAL, size=(n, len(angles)))
    q[:, angles] = np.where(rng.random((n, len(angles))) < 0.5, q[:, angles], special)
    return q


def test_the_built_in_kinds_are_registered():
    assert {
        "position",
        "mount_position",
        "planar_angle",
        "elevation",
        "euler_angles",
        "pose",
        "stack",
    } <= set(task_kinds())
    assert task_class("position") is Position and task_class("euler_angles") is EulerAngles


def test_an_unknown_kind_names_the_closest_one():
    with pytest.raises(ModelError, match="did you mean 'planar_angle'"):
        task_class("planar_angel")
    with pytest.raises(
        InputError, match=r"task\.kind: 'eulerangles' not one of .*did you mean 'euler_angles'"
    ):
        task_from_table({"kind": "eulerangles"}, "task")


def test_a_kind_is_taken_once():
    with pytest.raises(ModelError, match="'position' is already"):

        @dataclass(frozen=True)
        class Impostor(Task):
            kind = "position"


def test_a_task_defined_here_works_by_kind():
    """From a table by kind (its fields as keys), J and J̄ = J S against the closed form ∂ξ/∂q = indicator
    row, and the symbolic ξ and J exactly."""
    robot = robots.bayle_planar()
    task = task_from_table({"kind": "test_joint_sum", "joints": [3, 4], "label": "sum"}, "task")
    assert task == JointSum((3, 4), "sum") and task.names == ("sum",)
    with pytest.raises(InputError, match=r"task\.joints\[1\]: must be an integer"):
        task_from_table({"kind": "test_joint_sum", "joints": [3, "4"]}, "task")
    q = _configurations(robot, 16, seed=3)
    indicator = np.zeros((1, robot.n_q))
    indicator[0, [3, 4]] = 1.0
    np.testing.assert_allclose(K.forward(robot, q, task)[:, 0], q[:, 3] + q[:, 4], atol=1e-15)
    np.testing.assert_allclose(K.jacobian(robot, q, task), np.broadcast_to(indicator, (16, 1, robot.n_q)))
    s = np.asarray(K.S(robot, q))
    np.testing.assert_allclose(K.reduced_jacobian(robot, q, task), indicator @ s, atol=1e-15)
    model = S.model(robot)
    x, y, theta, q4, q5 = model.q
    assert sp.simplify(model.forward(task)[0] - (q4 + q5)) == 0
    assert model.jacobian(task) == sp.Matrix([[0, 0, 0, 1, 1]])
    stacked = model.forward(stack(Position("xy"), task))
    assert stacked.shape == (3, 1) and sp.simplify(stacked[2] - (q4 + q5)) == 0


@pytest.mark.parametrize("sequence", spatial.EULER_SEQUENCES)
def test_euler_angles_closed_form_equals_the_numerical_angles(sequence):
    """The symbolic Euler angles of Bayle's RRP tool frame, evaluated, equal the numerical ones (modulo 2π)
    over the whole range, away from the gimbal lock where the angles are undefined."""
    robot = robots.bayle_rrp()
    task = EulerAngles(sequence)
    model = S.model(robot)
    fn = sp.lambdify(model.q, model.forward(task), "numpy")
    q = _configurations(robot, 24, seed=5)
    numeric = np.asarray(K.forward(robot, q, task))
    regular = ~np.asarray(K.representation_singular(robot, q, task))
    assert regular.sum() >= 8
    closed = np.stack([np.asarray(fn(*row), dtype=float).reshape(-1) for row in q])
    wrapped = np.angle(np.exp(1j * (closed - numeric)))
    np.testing.assert_allclose(wrapped[regular], 0.0, atol=1e-9)


def test_a_stacks_reduced_jacobian_is_j_s_formed_part_by_part():
    """Task.reduced_jacobian = J S (Bayle eq. 2); a stack forms it part by part, with the same numbers, for a
    stack that mixes a task with its own (autodiff) Jacobian and closed-form ones."""
    import jax

    robot = robots.manus_platform()
    task = stack(Position("xyz"), EulerAngles("ZYX"), JointSum())
    q = sample_configurations(robot, 6, seed=4)
    q[:, 2] = [*SPECIAL, 0.7]  # headings 0, ±π/2, ±π
    reduced = jax.jit(lambda x: task.reduced_jacobian(robot, x, robot.frames(x)))
    for qi in q:
        frames = robot.frames(qi)
        by_parts = reduced(qi)
        whole = np.asarray(task.jacobian(robot, qi, frames)) @ np.asarray(robot.S(qi))
        np.testing.assert_allclose(by_parts, whole, rtol=0, atol=1e-13)


def _random_q(robot, n=5, seed=0):
    return np.random.default_rng(seed).uniform(-2, 2, size=(n, robot.n_q))


@pytest.mark.parametrize("task", [Position("xz"), EulerAngles("ZYX", select=(2, 0))])
def test_task_rows_are_the_chosen_rows_of_the_full_task(task):
    """A task restricted to some rows gives exactly those rows of the full task's value and Jacobian."""
    robot = robots.manus_platform()
    full = Position("xyz") if isinstance(task, Position) else EulerAngles("ZYX")
    rows = [0, 2] if isinstance(task, Position) else [2, 0]
    q = _random_q(robot, 3)
    np.testing.assert_array_equal(K.jacobian(robot, q, task), np.asarray(K.jacobian(robot, q, full))[:, rows])
    np.testing.assert_array_equal(K.forward(robot, q, task), np.asarray(K.forward(robot, q, full))[:, rows])
