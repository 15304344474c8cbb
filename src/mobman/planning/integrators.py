"""Fixed-step explicit Runge–Kutta schemes for the endpoint map and its variational system.

A scheme is a Butcher tableau (c, A, b). Explicit Runge–Kutta methods commute with linearisation: integrating
the variational system (Tchoń et al. eqs. 5–7) together with the state by the same tableau on the same grid
gives exactly the derivative of the discrete endpoint map, so the variational and the autodiff Jacobians agree
to rounding error whatever the step.

- ``"rk4"``: the classical 4-stage method of order 4;
- ``"dop853"``: the 12-stage method of order 8 of Dormand & Prince (Hairer, Nørsett & Wanner, *Solving
  Ordinary Differential Equations I*, §II.5, DOP853), used here with a fixed step and without its error
  estimator. Coefficients as in SciPy's ``dop853_coefficients`` (rows of A summing to c to 1e-15).

The planners integrate thousands of times: order 8 reaches 1e-14 with ~100 steps where RK4 needs ~8000, and
the cost of a ``lax.scan`` on a CPU is dominated by the number of steps.
"""

from __future__ import annotations

from typing import Any, Callable, NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from mobman.errors import InputError


class Tableau(NamedTuple):
    """Butcher tableau of an explicit method: nodes c, lower-triangular rows A (row i has i entries),
    weights b."""

    c: tuple[float, ...]
    A: tuple[tuple[float, ...], ...]
    b: tuple[float, ...]
    order: int


RK4 = Tableau(
    c=(0.0, 0.5, 0.5, 1.0),
    A=((), (0.5,), (0.0, 0.5), (0.0, 0.0, 1.0)),
    b=(1 / 6, 1 / 3, 1 / 3, 1 / 6),
    order=4,
)

DOP853 = Tableau(
    c=(
        0.0,
        0.05260015195876773,
        0.0789002279381516,
        0.1183503419072274,
        0.2816496580927726,
        0.3333333333333333,
        0.25,
        0.3076923076923077,
        0.6512820512820513,
        0.6,
        0.8571428571428571,
        1.0,
    ),
    A=(
        (),
        (0.05260015195876773,),
        (0.0197250569845379, 0.0591751709536137),
        (0.02958758547680685, 0.0, 0.08876275643042054),
        (0.2413651341592667, 0.0, -0.8845494793282861, 0.924834003261792),
        (0.037037037037037035, 0.0, 0.0, 0.17082860872947386, 0.12546768756682242),
        (0.037109375, 0.0, 0.0, 0.17025221101954405, 0.06021653898045596, -0.017578125),
        (
            0.03709200011850479,
            0.0,
            0.0,
            0.17038392571223998,
            0.10726203044637328,
            -0.015319437748624402,
            0.008273789163814023,
        ),
        (
            0.6241109587160757,
            0.0,
            0.0,
            -3.3608926294469414,
            -0.868219346841726,
            27.59209969944671,
            20.154067550477894,
            -43.48988418106996,
        ),
        (
            0.47766253643826434,
            0.0,
            0.0,
            -2.4881146199716677,
            -0.590290826836843,
            21.230051448181193,
            15.279233632882423,
            -33.28821096898486,
            -0.020331201708508627,
        ),
        (
            -0.9371424300859873,
            0.0,
            0.0,
            5.186372428844064,
            1.0914373489967295,
            -8.149787010746927,
            -18.52006565999696,
            22.739487099350505,
            2.4936055526796523,
            -3.0467644718982196,
        ),
        (
            2.273310147516538,
            0.0,
            0.0,
            -10.53449546673725,
            -2.0008720582248625,
            -17.9589318631188,
            27.94888452941996,
            -2.8589982771350235,
            -8.87285693353063,
            12.360567175794303,
            0.6433927460157636,
        ),
    ),
    b=(
        0.054293734116568765,
        0.0,
        0.0,
        0.0,
        0.0,
        4.450312892752409,
        1.8915178993145003,
        -5.801203960010585,
        0.3111643669578199,
        -0.1521609496625161,
        0.20136540080403034,
        0.04471061572777259,
    ),
    order=8,
)

METHODS = {"rk4": RK4, "dop853": DOP853}


def tableau(method: str) -> Tableau:
    """The tableau of a method name (``METHODS``)."""
    if method not in METHODS:
        raise InputError(f"method must be one of {', '.join(METHODS)}, got {method!r}")
    return METHODS[method]


def nodes(method: str) -> np.ndarray:
    """Stage times c_i ∈ [0, 1] within a step."""
    return np.asarray(tableau(method).c)


def _matrices(method: str) -> tuple[np.ndarray, np.ndarray]:
    """A as a full strictly lower-triangular (stages × stages) matrix, and b."""
    tab = tableau(method)
    A = np.zeros((len(tab.c), len(tab.c)))
    for i, row in enumerate(tab.A):
        A[i, : len(row)] = row
    return A, np.asarray(tab.b)


def step(method: str, rhs: Callable, state: Any, inputs: Any, h: float) -> Any:
    """One explicit Runge–Kutta step of d state/dt = rhs(state, input) (state a pytree) with stage inputs
    ``inputs[i]`` (the input at time t + c_i h).

    The stages run in a ``lax.fori_loop`` over a buffer of slopes K (row i of A only reaches the slopes
    already computed), so ``rhs`` is traced once: compilation time does not grow with the number of stages.
    """
    A_np, b_np = _matrices(method)
    stages = b_np.size
    A, b = jnp.asarray(A_np), jnp.asarray(b_np)
    slopes = jax.tree.map(lambda a: jnp.zeros((stages,) + jnp.shape(a), jnp.result_type(a)), state)

    def stage(i, slopes):
        at = jax.tree.map(lambda a, k: a + h * _weighted(A[i], k), state, slopes)
        k_i = rhs(at, inputs[i])
        return jax.tree.map(lambda k, new: k.at[i].set(new), slopes, k_i)

    slopes = jax.lax.fori_loop(0, stages, stage, slopes)
    return jax.tree.map(lambda a, k: a + h * _weighted(b, k), state, slopes)


def _weighted(w: jnp.ndarray, slopes: jnp.ndarray) -> jnp.ndarray:
    """Σ_j w_j slopes[j] as a broadcast product and sum (fuses into one loop; batched tiny ``dot`` calls are
    slow on a CPU under ``vmap``)."""
    return jnp.sum(w.reshape((-1,) + (1,) * (slopes.ndim - 1)) * slopes, axis=0)
