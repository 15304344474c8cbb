"""mobman.model.tasks.stack: Stack and stack() — rows, names, Jacobian and reduced Jacobian are the parts'
concatenated (against the parts alone and a planar closed form), flattening, error, checks."""

from __future__ import annotations

import jax.numpy as jnp
import numpy as np
import pytest

from mobman import kinematics as K
from mobman.errors import ModelError
from mobman.model import robots
from mobman.model.tasks import (
    Elevation,
    MountPosition,
    PlanarAngle,
    Pose,
    Position,
    Stack,
    Task,
    stack,
    task_class,
)

from task_checks import configurations


def _wrapped(a: np.ndarray) -> np.ndarray:
    return np.angle(np.exp(1j * a))


BAYLE = robots.bayle_planar()
Q = configurations(BAYLE.n_q)


def test_bayle_planar_stack_is_tool_position_and_heading():
    """Bayle §5.1: ξ = (x_ee, y_ee, θ + q4 + q5), J̄ in (v, ω, q̇4, q̇5) in closed form."""
    task = BAYLE.task
    assert isinstance(task, Stack)
    x, y, theta, q4, q5 = Q.T
    a1, a12 = theta + q4, theta + q4 + q5
    xi = np.asarray(K.forward(BAYLE, Q))
    np.testing.assert_allclose(xi[:, 0], x + 0.5 * np.cos(a1) + 0.5 * np.cos(a12), rtol=0, atol=1e-14)
    np.testing.assert_allclose(xi[:, 1], y + 0.5 * np.sin(a1) + 0.5 * np.sin(a12), rtol=0, atol=1e-14)
    np.testing.assert_allclose(_wrapped(xi[:, 2] - a12), 0.0, rtol=0, atol=1e-14)
    s1, c1, s12, c12 = 0.5 * np.sin(a1), 0.5 * np.cos(a1), 0.5 * np.sin(a12), 0.5 * np.cos(a12)
    one, zero = np.ones_like(x), np.zeros_like(x)
    expected = np.stack(
        [
            np.stack([np.cos(theta), -s1 - s12, -s1 - s12, -s12], -1),
            np.stack([np.sin(theta), c1 + c12, c1 + c12, c12], -1),
            np.stack([zero, one, one, one], -1),
        ],
        1,
    )
    np.testing.assert_allclose(np.asarray(K.reduced_jacobian(BAYLE, Q)), expected, rtol=0, atol=1e-14)


PARTS = (Position("xy"), PlanarAngle(), MountPosition("yx"))


@pytest.mark.parametrize("function", [K.forward, K.jacobian, K.reduced_jacobian], ids=lambda f: f.__name__)
def test_rows_are_the_concatenation_of_the_parts(function):
    whole = np.asarray(function(BAYLE, Q, stack(*PARTS)))
    parts = np.concatenate([np.asarray(function(BAYLE, Q, part)) for part in PARTS], axis=1)
    np.testing.assert_allclose(whole, parts, rtol=0, atol=1e-15)
    assert whole.shape[1] == 2 + 1 + 2


def test_names_and_dimension_are_the_parts_in_order():
    task = stack(*PARTS)
    assert task.names == ("x_ee", "y_ee", "angle", "y_f", "x_f")
    assert task.dim == 5
    assert task.tasks == PARTS


def test_nested_stacks_are_flattened_by_stack():
    inner = stack(Position("xy"), PlanarAngle())
    outer = stack(inner, stack(MountPosition("yx")))
    assert outer == stack(*PARTS)
    assert all(not isinstance(t, Stack) for t in outer.tasks)
    # the class itself keeps what it is given (as a tuple): a nested Stack stays one part
    nested = Stack([inner, Position("z")])
    assert nested.tasks == (inner, Position("z")) and nested.dim == 4
    np.testing.assert_allclose(
        np.asarray(K.forward(BAYLE, Q, nested)),
        np.asarray(K.forward(BAYLE, Q, stack(inner, Position("z")))),
        atol=0,
    )


def test_from_table_flattens_like_stack():
    inner = stack(Position("xy"), PlanarAngle())
    assert Stack.from_table({"tasks": [inner, Elevation()]}) == stack(
        Position("xy"), PlanarAngle(), Elevation()
    )
    assert task_class("stack") is Stack


@pytest.mark.parametrize("tasks", [(), [], ("position",), (Position(), 3)], ids=repr)
def test_a_stack_needs_one_or_more_tasks(tasks):
    with pytest.raises(ModelError, match="^Stack: give one or more tasks$"):
        Stack(tasks)


def test_stack_of_nothing_is_refused():
    with pytest.raises(ModelError, match="Stack: give one or more tasks"):
        stack()


def test_check_reaches_every_part():
    with pytest.raises(ModelError, match="arm index 1 out of range 0..0"):
        K.forward(BAYLE, Q[0], stack(Position(), MountPosition(arm=1)))
    with pytest.raises(ModelError, match="link index 4 out of range"):
        stack(PlanarAngle(), Position(link=4)).check(BAYLE)


def test_error_is_the_difference_for_vector_parts_and_each_parts_error_otherwise():
    rng = np.random.default_rng(1)
    vector = stack(Position("xy"), PlanarAngle())
    assert vector.euclidean
    a, b = rng.normal(size=(2, 4, 3))
    np.testing.assert_array_equal(np.asarray(vector.error(jnp.asarray(a), jnp.asarray(b))), a - b)
    mixed = stack(Position("z"), Pose())
    assert not mixed.euclidean
    a, b = rng.normal(size=(2, 4, 7))
    got = np.asarray(mixed.error(jnp.asarray(a), jnp.asarray(b)))
    np.testing.assert_array_equal(got[:, 0], a[:, 0] - b[:, 0])
    np.testing.assert_array_equal(
        got[:, 1:], np.asarray(Pose().error(jnp.asarray(a[:, 1:]), jnp.asarray(b[:, 1:])))
    )


def test_representation_singular_if_any_part_is():
    robot = robots.bayle_planar()
    q = Q[:3]
    # the planar heading of a z-up arm is never singular; a stack with only such parts is not
    assert not np.any(K.representation_singular(robot, q, stack(Position(), PlanarAngle())))

    class _Always(Task):
        @property
        def names(self) -> tuple[str, ...]:
            return ("one",)

        def value(self, robot, q, frames):
            return jnp.ones(1)

        def representation_singular(self, robot, q, frames):
            return jnp.asarray(True)

    assert np.all(K.representation_singular(robot, q, stack(Position(), _Always())))
