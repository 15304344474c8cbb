"""The recursive algorithms (CRBA for M, RNEA for M q̈ + c + g; mobman.dynamics.recursive) against the
definitions they replace: M = Σ m J_vᵀ J_v + J_ωᵀ I J_ω over the bodies' Jacobians, c + g by Lagrange's
equations (autodiff of that M and of V), on the papers' robots with dynamics, TIAGo and TIAGo dual (with a
payload), a coupled arm (the Manus) and a car-like platform (no wheel bodies, a steering coordinate).
Values to 1e-10, and the derivatives the library takes (∂M/∂q in the Coriolis matrix, gradients through the
reduced terms)."""

from __future__ import annotations

import math
from functools import partial

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import mobman
from mobman import dynamics as dyn
from mobman.dynamics import equations, reduced
from mobman.experiments.korayem_load import dynamic_model
from mobman.io.real_robots import urdf_model
from mobman.model import robots

PAYLOAD = dyn.Payload(1.5, (0.01, 0.002, 0.0, 0.002, 0.02, 0.0, 0.0, 0.0, 0.03), com=(0.05, -0.02, 0.04))


def _inertials(n: int, seed: int) -> list[mobman.LinkInertial]:
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(n):
        a = rng.normal(size=(3, 3))
        out.append(
            mobman.LinkInertial(
                float(rng.uniform(1.0, 4.0)),
                tuple(rng.uniform(-0.1, 0.2, 3)),
                tuple((0.02 * a @ a.T + 0.005 * np.eye(3)).ravel()),
            )
        )
    return out


def _models() -> dict[str, dyn.DynamicModel]:
    manus = robots.manus_platform()
    car = robots.tchon_car_rtr()
    body = dyn.PlatformBody(30.0, 1.2, com=(0.04, -0.02, 0.2))
    return {
        "yamamoto": dyn.yamamoto_model(dyn.Payload(2.0, PAYLOAD.inertia, PAYLOAD.com, arm=1), (0, 0, -9.81)),
        "korayem": dynamic_model(),
        "manus (coupled)": dyn.DynamicModel(
            manus.with_link_inertials(_inertials(manus.arms[0].n_joints, 1)),
            body,
            dyn.Wheel(2.0, 0.02, 0.05),
            PAYLOAD,
        ),
        "car-like": dyn.DynamicModel(car.with_link_inertials(_inertials(car.arms[0].n_joints, 2)), body),
        "tiago": dyn.DynamicModel.from_urdf(urdf_model("tiago")).with_payload(PAYLOAD),
        "tiago-dual": dyn.DynamicModel.from_urdf(urdf_model("tiago-dual")).with_payload(
            dyn.Payload(0.8, PAYLOAD.inertia, PAYLOAD.com, arm=1)
        ),
    }


MODELS = _models()


def _states(robot: mobman.MobileManipulator, seed: int = 0, n: int = 5):
    """Configurations over the whole joint range, the first rows at exactly 0, ±π/2 and π; q̈ and η."""
    rng = np.random.default_rng(seed)
    q = rng.uniform(-math.pi, math.pi, (n, robot.n_q))
    q[:, :2] = rng.uniform(-3.0, 3.0, (n, 2))
    q[0, 2:], q[1, 2:], q[2, 2:], q[3, 2:] = 0.0, math.pi / 2, -math.pi / 2, math.pi
    return q, rng.normal(size=(n, robot.n_q)), rng.normal(size=(n, robot.n_eta))


@pytest.fixture(params=list(MODELS))
def case(request):
    model = MODELS[request.param]
    return model, _states(model.robot)


def _relative(a, b) -> float:
    a, b = np.asarray(a), np.asarray(b)
    return float(np.abs(a - b).max() / max(1.0, np.abs(b).max()))


def test_crba_and_rnea_equal_the_definitions(case):
    """M, M q̈ + c + g, c + g and g by the recursion equal the Jacobian form, Lagrange's equations and ∂V/∂q;
    the reduced P = Sᵀ M S and b = Sᵀ (M Ṡ η + c + g) equal the products with the definitions' (q̇ = S η:
    arbitrary rates are compared with Pinocchio on a holonomic base in test_dynamics_pinocchio.py)."""
    model, (q, q_ddot, eta) = case

    def both(x, a, e):
        s = model.robot.S(x)
        v = s @ e
        m_ref = equations.mass_matrix_definition_one(model, x)
        bias_ref = equations.lagrange_bias_one(model, x, v)
        b_ref = s.T @ (m_ref @ reduced.s_dot_eta(model, x, e) + bias_ref)
        return (
            (equations.mass_matrix_one(model, x), m_ref),
            (equations.generalized_force_one(model, x, v, a), m_ref @ a + bias_ref),
            (equations.bias_one(model, x, v), bias_ref),
            (equations.gravity_one(model, x), jax.grad(partial(equations.potential_energy_one, model))(x)),
            (reduced.reduced_mass_matrix_one(model, x), s.T @ m_ref @ s),
            (reduced.reduced_bias_one(model, x, e), b_ref),
        )

    pairs = jax.jit(jax.vmap(both))(q, q_ddot, eta)
    assert np.abs(np.asarray(pairs[0][1])).max() > 1.0
    assert np.abs(np.asarray(pairs[2][1])).max() > 0.1
    for ours, reference in pairs:
        assert _relative(ours, reference) < 1e-10


@pytest.mark.parametrize("name", ["manus (coupled)"])
def test_derivatives_of_the_recursion_equal_those_of_the_definitions(name):
    """∂M/∂q (the Coriolis matrix's Christoffel symbols) and a gradient through P and b agree with the
    definitions' derivatives (on the robot with coupled joints: the recursion's code is the same for every
    robot, whose values the test above checks)."""
    model = MODELS[name]
    q, _, eta = _states(model.robot, seed=1)
    x, e = q[4], eta[4]
    dm = jax.jit(jax.jacfwd(partial(equations.mass_matrix_one, model)))(x)
    dm_ref = jax.jit(jax.jacfwd(partial(equations.mass_matrix_definition_one, model)))(x)
    assert np.abs(np.asarray(dm_ref)).max() > 0.1
    assert _relative(dm, dm_ref) < 1e-10

    def scalar(p_fn, b_fn, x, e):
        return jnp.sum(jnp.sin(p_fn(x))) + jnp.sum(jnp.cos(b_fn(x, e)))

    def p_ref(x):
        s = model.robot.S(x)
        return s.T @ equations.mass_matrix_definition_one(model, x) @ s

    def b_ref(x, e):
        s = model.robot.S(x)
        m = equations.mass_matrix_definition_one(model, x)
        return s.T @ (m @ reduced.s_dot_eta(model, x, e) + equations.lagrange_bias_one(model, x, s @ e))

    p_ours, b_ours = partial(reduced.reduced_mass_matrix_one, model), partial(reduced.reduced_bias_one, model)
    ours = jax.jit(jax.grad(partial(scalar, p_ours, b_ours), argnums=(0, 1)))(x, e)
    reference = jax.jit(jax.grad(partial(scalar, p_ref, b_ref), argnums=(0, 1)))(x, e)
    for a, b in zip(ours, reference):
        assert _relative(a, b) < 1e-10


def test_input_matrix_by_blocks_equals_s_transpose_e(case):
    """B = diag(S_pᵀ E_p, C_1ᵀ, …) (reduced.input_matrix_one) equals Sᵀ E with S and E formed, for a coupled
    arm, two arms and a platform without driven wheels too."""
    model, (q, _, _) = case
    for x in q:
        expected = np.asarray(model.robot.S(x)).T @ np.asarray(equations.actuation_matrix_one(model, x))
        np.testing.assert_allclose(np.asarray(reduced.input_matrix_one(model, x)), expected, atol=1e-14)
