"""Every drop-in of the engine against the plain definition it replaces (mobman.engine.kernels): the same
values and the same forward-mode derivatives, on random inputs and at the angles ±π/2, π.

The test walks the registry: a new drop-in without an example here fails ``test_every_drop_in_has_examples``.
"""

from __future__ import annotations

import math

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import mobman  # noqa: F401  (float64; imports the model, whose definitions register themselves)
from mobman.control import avoidance  # noqa: F401  (its definition of the nearest pairs registers)
from mobman.engine import kernels
from mobman.model import robots, spatial, spectra  # noqa: F401  (spectra: its definitions register)

RNG = np.random.default_rng(19)
ANGLES = np.array([-math.pi, -math.pi / 2, 0.0, math.pi / 2, math.pi, 0.3, -2.1])


def _rotations(count: int) -> np.ndarray:
    """Rotation matrices, among them turns by ±π/2 and π about the axes."""
    rs = [spatial.rot_z(a) @ spatial.rot_x(b) for a, b in zip(ANGLES, ANGLES[::-1])]
    rs += [np.linalg.qr(RNG.normal(size=(3, 3)))[0] for _ in range(count)]
    return np.stack(rs)


def _symmetric(n: int, batch: tuple[int, ...] = ()) -> np.ndarray:
    """Symmetric matrices with well separated eigenvalues (the eigenvectors are then differentiable)."""
    q = np.linalg.qr(RNG.normal(size=batch + (n, n)))[0]
    w = np.arange(n, 0, -1, dtype=float) + RNG.uniform(0, 0.3, size=batch + (n,))
    return (q * w[..., None, :]) @ np.swapaxes(q, -1, -2)


def _symmetrized(a):
    """(A + Aᵀ) / 2: the solvers read one triangle of A, so derivatives are compared along symmetric A."""
    return 0.5 * (a + jnp.swapaxes(a, -1, -2))


def _projectors(out):
    """Eigenvalues and v_i v_iᵀ (the eigenvectors up to their signs)."""
    w, v = out
    return w, jnp.einsum("...ai,...bi->...iab", v, v)


def _tool(frames):
    return frames.links[0][0][-1], frames.links[0][1][-1]


def _panda_q() -> np.ndarray:
    robot = robots.panda_differential()
    q = RNG.uniform(-math.pi, math.pi, size=(3, robot.n_q))
    q[0, :] = ANGLES[np.arange(robot.n_q) % len(ANGLES)]
    return q


PANDA = robots.panda_differential()


# name → (cases: tuples of arguments, index of the argument differentiated, view of the result compared,
#         map of the differentiated argument before the call)
def _distances(count: int) -> np.ndarray:
    """Signed distances as a scene gives them: positive and negative, repeated values, a −0 and a 0."""
    d = RNG.uniform(-0.2, 3.0, count)
    d[:6] = [0.5, 0.5, -0.0, 0.0, 0.5, -0.2]
    return d


EXAMPLES = {
    "mobman.control.avoidance.nearest": (
        [(_distances(200), 32), (_distances(7), 7), (_distances(1000), 1)],
        0,
        lambda out: out[0],
        None,
    ),
    "mobman.model.spatial.unstack": (
        [(RNG.normal(size=(4, 3)),), (RNG.normal(size=(2, 3, 5)), 0), (_rotations(2), -2)],
        0,
        None,
        None,
    ),
    "mobman.model.spatial.rows": (
        [
            (RNG.normal(size=(6, 9)), (0, 2, 5)),
            (RNG.normal(size=(3, 4)), (0, 1, 2)),
            (RNG.normal(size=(3,)), (2, 0)),
        ],
        0,
        None,
        None,
    ),
    "mobman.model.spatial.matmul_expanded": (
        [(_rotations(3), _rotations(3)[::-1]), (RNG.normal(size=(6, 9)), RNG.normal(size=(9, 6)))],
        0,
        None,
        None,
    ),
    "mobman.model.spatial.matvec_constant": (
        [(_rotations(3), np.array([0.0, 1.0, -0.3])), (_rotations(1), np.zeros(3))],
        0,
        None,
        None,
    ),
    "mobman.model.spatial.matmul_constant": (
        [(_rotations(3), spatial.rot_x(math.pi / 2)), (_rotations(2), RNG.normal(size=(3, 3)))],
        0,
        None,
        None,
    ),
    "mobman.model.spatial.shared": (
        [(RNG.normal(size=(4, 3)),), (_rotations(2),), (ANGLES,)],
        0,
        None,
        None,
    ),
    "mobman.model.spatial.cross": (
        [
            (RNG.normal(size=(5, 3)), RNG.normal(size=(5, 3))),
            (RNG.normal(size=(3, 4)), RNG.normal(size=(3, 4)), 0),
        ],
        0,
        None,
        None,
    ),
    "mobman.model.arm.rodrigues": (
        [
            (spatial.rot_y(math.pi / 2), spatial.skew([0.0, 0.0, 1.0]), ANGLES),
            (np.eye(3), spatial.skew(np.array([1.0, 2.0, -0.5]) / np.sqrt(5.25)), ANGLES),
        ],
        2,
        None,
        None,
    ),
    "mobman.model.spectra.eigvalsh": (
        [
            (_symmetric(2),),
            (_symmetric(3),),
            (_symmetric(6),),
            (_symmetric(6, (4,)),),
            (_symmetric(3, (2, 3)),),
        ],
        0,
        None,
        _symmetrized,
    ),
    "mobman.model.spectra.extremes": (
        [
            (_symmetric(2),),
            (_symmetric(3),),
            (_symmetric(6),),
            (_symmetric(6, (4,)),),
            (_symmetric(8, (2,)),),
            (-_symmetric(5, (3,)),),  # negative definite: the lower start −1, no Sturm shortcut
        ],
        0,
        None,
        _symmetrized,
    ),
    "mobman.model.spectra.eigh": (
        [(_symmetric(2),), (_symmetric(6),), (_symmetric(4, (3,)),)],
        0,
        _projectors,
        _symmetrized,
    ),
    "mobman.model.frame_jacobian.frame_jacobian": (
        [(PANDA, _tool, 0, 6, q) for q in _panda_q()],
        4,
        None,
        None,
    ),
}


def test_every_drop_in_has_examples():
    registered = {n for n, k in kernels.registry().items() if k.drop_in is not None}
    assert registered, "no drop-in registered"
    assert registered <= set(EXAMPLES), f"drop-ins without examples: {sorted(registered - set(EXAMPLES))}"
    defined = {n for n, k in kernels.registry().items() if k.definition is not None}
    assert registered <= defined, f"drop-ins for no definition: {sorted(registered - defined)}"


def _as_function(fn, args, wrt, view, lift):
    def f(x):
        full = list(args)
        full[wrt] = x if lift is None else lift(x)
        out = fn(*full)
        return out if view is None else view(out)

    return f


def _assert_close(got, want, rtol):
    for a, b in zip(jax.tree.leaves(got), jax.tree.leaves(want)):
        a, b = np.asarray(a), np.asarray(b)
        assert a.shape == b.shape
        scale = max(1.0, float(np.max(np.abs(b))) if b.size else 1.0)
        np.testing.assert_allclose(a, b, rtol=0, atol=rtol * scale)


@pytest.mark.parametrize("name", sorted(EXAMPLES))
def test_drop_in_equals_its_definition_with_its_derivative(name):
    kernel = kernels.registry()[name]
    assert kernel.drop_in is not None and kernel.definition is not None
    cases, wrt, view, lift = EXAMPLES[name]

    def with_derivative(f, wrap):  # the value and the derivative in one compiled program
        return jax.jit(lambda x: (wrap(f)(x), wrap(jax.jacfwd(f))(x)))

    for args in cases:
        plain = _as_function(kernel.definition, args, wrt, view, lift)
        tuned = _as_function(kernel.drop_in, args, wrt, view, lift)
        x = jnp.asarray(args[wrt], dtype=float)
        # once, and batched (drop-ins may take another path under vmap): two copies, values and derivatives
        for arg, wrap in ((x, lambda f: f), (jnp.stack([x, x]), jax.vmap)):
            (value, derivative), (want, want_derivative) = (
                with_derivative(f, wrap)(arg) for f in (tuned, plain)
            )
            _assert_close(value, want, 1e-12)
            _assert_close(derivative, want_derivative, 1e-9)


def test_a_definition_runs_its_drop_in_and_keeps_the_plain_function():
    kernel = kernels.registry()["mobman.model.spatial.matmul_expanded"]
    assert spatial.matmul_expanded.definition is kernel.definition
    a = RNG.normal(size=(3, 3))
    np.testing.assert_allclose(spatial.matmul_expanded(jnp.asarray(a), jnp.asarray(a)), a @ a, atol=1e-14)


def test_a_second_drop_in_for_one_definition_is_refused():
    with pytest.raises(ValueError, match="already registered"):
        kernels.drop_in("mobman.model.spatial.matmul_expanded")(lambda a, b: a @ b)
