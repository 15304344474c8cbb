"""Exported programs kept on disk (mobman.engine.exported): the same values as plain jit, read back by a later
process without tracing, keyed by everything that changes a program, and never used for traced calls or
static arguments that name code outside mobman."""

from __future__ import annotations

import dataclasses
import subprocess
import sys
from pathlib import Path

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from mobman import kinematics
from mobman.engine import exported
from mobman.errors import InputError
from mobman.model import robots


@pytest.fixture
def folder(tmp_path):
    """Exported programs kept in a fresh folder for the test, turned off after it."""
    path = exported.enable(tmp_path)
    yield path
    exported.disable()


def _stored(folder: Path) -> set[str]:
    return {p.name for p in folder.glob("*.exported")}


def _scaled(robot, q, factor):
    return kinematics.forward(robot, q) * factor


def test_values_equal_plain_jit_and_each_program_is_stored_once(folder):
    robot = robots.bayle_planar()
    q = np.random.default_rng(0).uniform(-np.pi, np.pi, (5, robot.n_q))
    q[0, 2], q[1, 2], q[2, 2] = np.pi / 2, -np.pi / 2, np.pi
    expected = [
        np.asarray(kinematics.reduced_jacobian.one(robot, qi, robot.task)) for qi in q
    ]  # traced definition
    jbar = np.asarray(kinematics.reduced_jacobian(robot, q))  # batched program, exported
    np.testing.assert_allclose(jbar, np.stack(expected), rtol=0, atol=1e-15)
    one = np.asarray(kinematics.reduced_jacobian(robot, q[3]))  # the one-configuration program, exported
    np.testing.assert_allclose(one, expected[3], rtol=0, atol=1e-15)
    stored = _stored(folder)
    assert len(stored) == 2
    kinematics.reduced_jacobian(robot, q)
    kinematics.reduced_jacobian(robot, q[::-1])
    assert _stored(folder) == stored  # the same robot and shapes: no new program


def test_another_robot_option_or_shape_is_another_program(folder):
    robot = robots.bayle_planar()
    q = np.zeros((3, robot.n_q))
    kinematics.forward(robot, q)
    count = len(_stored(folder))
    longer = robots.bayle_planar(l1=0.7)
    np.testing.assert_allclose(
        np.asarray(kinematics.forward(longer, q))[0, :2], [0.7 + 0.5, 0.0], atol=1e-15
    )  # the arm stretched along the platform's x axis: l1 + l2
    assert len(_stored(folder)) == count + 1
    kinematics.forward(robot, np.zeros((4, robot.n_q)))
    assert len(_stored(folder)) == count + 2


LATER_PROCESS = """
import sys
import numpy as np
from pathlib import Path
from mobman import kinematics
from mobman.engine import exported
from mobman.model import robots, arm
exported.enable(Path(sys.argv[1]))
traced = []
original = arm.Arm.link_poses
def spy(self, *args, **kwargs):
    traced.append(1)
    return original(self, *args, **kwargs)
arm.Arm.link_poses = spy
q = np.array([[0.3, -0.2, np.pi / 2, 0.4, -1.1]])
jbar = kinematics.reduced_jacobian(robots.bayle_planar(), q)
print(len(traced))
print(repr(np.asarray(jbar).tolist()))
"""


def test_a_later_process_reads_the_program_without_tracing(tmp_path):
    """Two fresh processes (the test's own may have registered test kernels): the first traces and keeps
    the program, the second reads it back without tracing the kinematics, with the same values."""

    def run() -> tuple[str, str]:
        args = [sys.executable, "-c", LATER_PROCESS, str(tmp_path)]
        out = subprocess.run(args, capture_output=True, text=True, check=True)
        traces, values = out.stdout.strip().splitlines()
        return traces, values

    first_traces, first = run()
    stored = _stored(tmp_path / "exported")
    assert first_traces != "0" and len(stored) == 1
    traces, again = run()
    assert traces == "0"  # the kinematics were never traced: the program came from the disk
    assert again == first and _stored(tmp_path / "exported") == stored
    q = np.array([[0.3, -0.2, np.pi / 2, 0.4, -1.1]])
    expected = np.asarray(kinematics.reduced_jacobian(robots.bayle_planar(), q))  # this process: plain jit
    np.testing.assert_allclose(np.array(eval(again)), expected, rtol=0, atol=1e-15)


def test_a_damaged_file_is_exported_afresh(folder):
    robot = robots.bayle_planar()
    q = np.array([[0.1, 0.2, np.pi, -0.3, 0.8]])
    first = exported.jit(_scaled, static_argnums=(0, 2), name="scaled forward")
    expected = np.asarray(first(robot, q, 2.0))
    (path,) = folder.glob("*.exported")
    path.write_bytes(b"not a program")
    later = exported.jit(_scaled, static_argnums=(0, 2), name="scaled forward")  # as a later process would
    np.testing.assert_array_equal(np.asarray(later(robot, q, 2.0)), expected)
    assert path.stat().st_size > 100  # written again, whole
    np.testing.assert_allclose(expected, 2.0 * np.asarray(kinematics.forward(robot, q)), rtol=0, atol=1e-15)


def test_traced_arguments_use_plain_jit(folder):
    robot = robots.bayle_planar()
    q = jnp.array([0.1, 0.2, np.pi / 2, -0.3, 0.8])
    g = jax.grad(lambda q: jnp.sum(kinematics.forward.one(robot, q, robot.task) ** 2))(q)
    assert np.all(np.isfinite(np.asarray(g)))
    assert _stored(folder) == set()


@dataclasses.dataclass(frozen=True)
class Foreign:
    """A static option whose class lives outside mobman: its code could change without its pickle changing."""

    factor: float = 2.0


def _times(option, x):
    return x * option.factor


def test_a_static_argument_naming_code_outside_mobman_is_not_stored(folder):
    program = exported.jit(_times, static_argnums=(0,))
    np.testing.assert_array_equal(np.asarray(program(Foreign(), np.arange(3.0))), [0.0, 2.0, 4.0])
    assert _stored(folder) == set()
    builtin = exported.jit(_times_builtin, static_argnums=(0,))
    np.testing.assert_array_equal(np.asarray(builtin(3.0, np.arange(3.0))), [0.0, 3.0, 6.0])
    assert len(_stored(folder)) == 1


def _times_builtin(factor, x):
    return x * factor


def test_off_by_default_and_an_unwritable_folder_is_named(tmp_path):
    exported.disable()
    robot = robots.bayle_planar()
    kinematics.forward(robot, np.zeros(robot.n_q))
    assert not list(tmp_path.rglob("*.exported"))
    blocker = tmp_path / "file"
    blocker.write_text("")
    with pytest.raises(InputError, match="exported programs' folder .*file/exported"):
        exported.enable(blocker)


def _with_callback(x):
    return jax.pure_callback(lambda v: np.asarray(v) * 2.0, jax.ShapeDtypeStruct(x.shape, x.dtype), x)


def test_a_program_that_cannot_be_exported_runs_as_plain_jit_and_is_not_tried_again(folder, monkeypatch):
    program = exported.jit(_with_callback, name="a host callback")
    np.testing.assert_array_equal(np.asarray(program(np.arange(3.0))), [0.0, 2.0, 4.0])
    assert _stored(folder) == set() and len(list(folder.glob("*.plain"))) == 1
    tried = []
    monkeypatch.setattr(exported, "_export", lambda *args: tried.append(args))
    later = exported.jit(_with_callback, name="a host callback")  # as a later process would
    np.testing.assert_array_equal(np.asarray(later(np.arange(3.0))), [0.0, 2.0, 4.0])
    assert tried == []
