"""The law interface (mobman.control.laws.base): the typed per-step result as a JAX pytree, the registry by
kind, and a law defined in this file — one class, no other edit — found by kind from a specification and
simulated, its η checked against the formula computed from the kinematics."""

from __future__ import annotations

from dataclasses import dataclass

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from mobman import kinematics as K
from mobman.control import laws, simulate, spec
from mobman.control._tree import pytree
from mobman.control.laws import Law, LawStep, PseudoInverseStep
from mobman.control.laws.base import positive_gain
from mobman.errors import InputError, ModelError
from mobman.model import Position, robots


@pytree("k", "damping", "damping_threshold")
@dataclass(frozen=True, eq=False)
class JacobianTranspose(Law):
    """η = k J̄ᵀ e, the Jacobian-transpose law: a law kind that exists only in this test file."""

    kind = "test_jacobian_transpose"
    gains = ("k",)

    k: np.ndarray = 1.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "k", positive_gain(self.k, "k", "JacobianTranspose"))
        self.check_options("JacobianTranspose")

    def __call__(self, robot, task, q, t, xi_star, xi_star_dot) -> LawStep:
        task = robot.task if task is None else task
        frames = robot.frames(q)
        jbar = robot.apply_S(task.jacobian(robot, q, frames), q)
        e = task.error(xi_star, task.value(robot, q, frames))
        eta, ratio, saturated = self.saturation(robot, self.k * (jbar.T @ e))
        zero = jnp.zeros((), eta.dtype)
        return LawStep(eta, zero, zero, ratio, saturated, jnp.zeros((), bool))


SPEC = {
    "duration": 0.5,
    "dt": 0.05,
    "q0": [0.0, 0.0, 0.0, 0.6, 1.2],
    "robot": {"name": "bayle-planar"},
    "task": {"kind": "position", "components": "xy"},
    "reference": {"kind": "line", "start": [0.9, 0.3], "end": [1.1, 0.5], "duration": 0.5},
    "law": {"kind": "test_jacobian_transpose"},
    "gains": {"k": 2.0},
}


def test_the_built_in_laws_are_registered():
    assert {"bayle", "nait-chabane", "augmented"} <= set(laws.law_kinds())
    assert laws.law_class("augmented") is laws.AugmentedJacobian


def test_an_unknown_kind_names_the_closest_one():
    with pytest.raises(ModelError, match="did you mean 'nait-chabane'"):
        laws.law_class("nait_chabane")
    with pytest.raises(InputError, match=r"law\.kind: 'bayl' not one of .*did you mean 'bayle'"):
        spec.parse(dict(SPEC, law={"kind": "bayl"}))


def test_the_step_is_a_pytree():
    """jit and vmap return the typed result; an entry the law has nothing for (no criterion: P) is None and
    left out of what is recorded."""
    robot, task = robots.bayle_planar(), Position("xy")
    q = jnp.array([0.2, 0.1, 0.3, 0.7, 1.1])
    xs, xsd = jnp.array([1.3, 0.6]), jnp.array([0.1, -0.2])
    law = laws.BaylePseudoInverse(W=2.0)
    step = jax.jit(lambda qq: law(robot, task, qq, 0.0, xs, xsd))(q)
    assert isinstance(step, PseudoInverseStep) and step.P is None
    assert set(step.recorded()) == {"damping", "sigma_min", "limit_ratio", "saturated", "damped"}
    batch = jax.vmap(lambda qq: law(robot, task, qq, 0.0, xs, xsd))(jnp.stack([q, q + 0.1]))
    assert batch.eta.shape == (2, robot.n_eta) and batch.sigma_min.shape == (2,)
    np.testing.assert_allclose(batch.eta[0], step.eta, atol=1e-14)


def test_a_law_defined_here_works_by_kind():
    parsed = spec.parse(SPEC)
    assert isinstance(parsed.law, JacobianTranspose) and float(parsed.law.k) == 2.0
    with pytest.raises(InputError, match=r"gains\.W: unknown key; allowed: k"):
        spec.parse(dict(SPEC, gains={"W": 1.0}))
    with pytest.raises(InputError, match="no self-motion"):
        spec.parse(dict(SPEC, criterion={"kind": "joint_limits"}))
    result = simulate(
        parsed.robot, parsed.task, parsed.law, parsed.reference, parsed.q0, parsed.duration, parsed.dt
    )
    assert set(result.info) == {"damping", "sigma_min", "limit_ratio", "q_mid"}  # q_mid: the Lie integrator
    jbar = np.asarray(K.reduced_jacobian(parsed.robot, result.q, parsed.task))
    e = result.xi_star - np.asarray(K.forward(parsed.robot, result.q, parsed.task))
    np.testing.assert_allclose(result.eta, 2.0 * np.einsum("kij,ki->kj", jbar, e), atol=1e-12)
    np.testing.assert_allclose(result.error, e, atol=1e-12)
    assert not result.saturated.any() and not result.damped.any()
