"""Explicit Runge–Kutta methods given by their Butcher tableau, on a vector space or on a Lie group.

An explicit s-stage method (c, A, b) advances y' = f(t, y) by one step h (Hairer, Nørsett & Wanner, *Solving
Ordinary Differential Equations I*, §II.1):

    Y_i = y + h Σ_{j<i} a_ij k_j,    k_i = f(t + c_i h, Y_i),    y_next = y + h Σ_i b_i k_i.

A commutator-free Lie group method (Celledoni, Marthinsen & Owren, "Commutator-free Lie group methods",
*Future Generation Computer Systems* 19, 2003) integrates y' = y · f(t, y) on a Lie group acting on the state,
the slopes k_i lying in its Lie algebra. Each stage and the output compose E exponentials, one row of
coefficients per exponential:

    Y_i = y ∘ exp(h Σ_j α¹_ij k_j) ∘ … ∘ exp(h Σ_j α^E_ij k_j),
    y_next = y ∘ exp(h Σ_j β¹_j k_j) ∘ … ∘ exp(h Σ_j β^E_j k_j).

On an abelian group (Rⁿ, ``exp(y, u) = y + u``) the exponentials add up: the method is the classical one of
A = Σ_e α^e, b = Σ_e β^e. A :class:`Tableau` is the case E = 1; ``exp`` is passed in (the group action
y ∘ exp(u), e.g. the exact flow of a platform at constant velocity), addition when omitted.

The state y and the slopes k_i are pytrees (the slopes may have another structure than the state on a group).
"""

from __future__ import annotations

from typing import Any, Callable, NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

Exp = Callable[[Any, Any], Any]
"""exp(y, u) = y ∘ exp(u): the state y moved by the Lie-algebra increment u (a pytree like the slopes)."""


class Tableau(NamedTuple):
    """Butcher tableau of an explicit method: nodes c, strictly lower-triangular rows of A (row i has i
    entries), weights b, and the order of the method."""

    c: tuple[float, ...]
    A: tuple[tuple[float, ...], ...]
    b: tuple[float, ...]
    order: int


class CommutatorFreeTableau(NamedTuple):
    """Tableau of a commutator-free Lie group method: nodes c, one set of strictly lower-triangular rows α^e
    (row i has i entries) and one row of weights β^e per exponential e = 1 … E, and the order."""

    c: tuple[float, ...]
    A: tuple[tuple[tuple[float, ...], ...], ...]
    b: tuple[tuple[float, ...], ...]
    order: int


AnyTableau = Tableau | CommutatorFreeTableau

RK4 = Tableau(
    c=(0.0, 0.5, 0.5, 1.0),
    A=((), (0.5,), (0.0, 0.5), (0.0, 0.0, 1.0)),
    b=(1 / 6, 1 / 3, 1 / 3, 1 / 6),
    order=4,
)
"""The classical 4-stage method of order 4 (Hairer, Nørsett & Wanner, §II.1)."""

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
"""The 12-stage method of order 8 of Dormand & Prince (Hairer, Nørsett & Wanner, §II.5, DOP853), with a fixed
step and without its error estimator; coefficients as in SciPy's ``dop853_coefficients``."""

CF4 = CommutatorFreeTableau(
    c=(0.0, 0.5, 0.5, 1.0),
    A=(
        ((), (0.5,), (0.0, 0.5), (0.5, 0.0, 0.0)),
        ((), (0.0,), (0.0, 0.0), (-0.5, 0.0, 1.0)),
    ),
    b=((1 / 4, 1 / 6, 1 / 6, -1 / 12), (-1 / 12, 1 / 6, 1 / 6, 1 / 4)),
    order=4,
)
"""The commutator-free Lie group method of order 4 of Celledoni, Marthinsen & Owren (2003), two exponentials
per stage and output:

    Y1 = y,  Y2 = y ∘ exp(h k1/2),  Y3 = y ∘ exp(h k2/2),  Y4 = Y2 ∘ exp(h (k3 − k1/2)),
    y_next = y ∘ exp(h (3k1 + 2k2 + 2k3 − k4)/12) ∘ exp(h (−k1 + 2k2 + 2k3 + 3k4)/12).

On an abelian group it is :data:`RK4`."""


def coefficients(tab: AnyTableau) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(c (s,), A (E, s, s) strictly lower triangular, b (E, s)) of a tableau; E = 1 for a :class:`Tableau`."""
    rows = (tab.A,) if isinstance(tab, Tableau) else tab.A
    weights = (tab.b,) if isinstance(tab, Tableau) else tab.b
    A = np.zeros((len(rows), len(tab.c), len(tab.c)))
    for e, matrix in enumerate(rows):
        for i, row in enumerate(matrix):
            A[e, i, : len(row)] = row
    return np.asarray(tab.c, dtype=float), A, np.asarray(weights, dtype=float)


def add(y: Any, u: Any) -> Any:
    """y + u: the group action of a vector space (the default ``exp``)."""
    return jax.tree.map(jnp.add, y, u)


def _increment(h: float, weights: np.ndarray, slopes: list) -> Any:
    """h Σ_j w_j k_j over the slopes k_j with a nonzero weight (the zero pytree of k_0 when there is none)."""
    terms = [(w, k) for w, k in zip(weights, slopes) if w != 0.0]
    if not terms:
        return jax.tree.map(jnp.zeros_like, slopes[0])
    return jax.tree.map(lambda *ks: h * sum(w * k for (w, _), k in zip(terms, ks)), *(k for _, k in terms))


def _stage(inputs: Any, i: int) -> Any:
    """Stage i's entry of a pytree with a leading stage axis."""
    return jax.tree.map(lambda a: a[i], inputs)


def step(
    tab: AnyTableau,
    f: Callable,
    y: Any,
    t: Any,
    h: Any,
    *,
    exp: Exp | None = None,
    has_aux: bool = False,
    inputs: Any = None,
) -> Any:
    """One step of the method (module docstring): y_next; with ``has_aux``, f(t, y) returns (k, aux) and the
    step (y_next, aux) with every stage's aux stacked along a leading axis of length s. ``inputs``, if given,
    holds an exogenous signal at the stage times t + c_i h (a pytree with a leading axis s): then stage i
    evaluates f(t + c_i h, Y_i, inputs[i])."""
    y_next, _, aux = step_path(tab, f, y, t, h, exp=exp, has_aux=has_aux, inputs=inputs)
    return (y_next, aux) if has_aux else y_next


def step_path(
    tab: AnyTableau,
    f: Callable,
    y: Any,
    t: Any,
    h: Any,
    *,
    exp: Exp | None = None,
    has_aux: bool = False,
    inputs: Any = None,
) -> tuple[Any, list, Any]:
    """:func:`step` with the junctions of the output's composition: (y_next, [y ∘ exp(h Σ β¹_j k_j), …] the
    E − 1 points between its exponentials, the stages' aux stacked or None)."""
    exp = add if exp is None else exp
    c, A, b = coefficients(tab)
    slopes: list[Any] = []
    auxes: list[Any] = []
    for i in range(len(c)):
        y_i = y
        for alpha in A[:, i, :i]:
            if np.any(alpha):
                y_i = exp(y_i, _increment(h, alpha, slopes))
        out = f(t + c[i] * h, y_i) if inputs is None else f(t + c[i] * h, y_i, _stage(inputs, i))
        k_i, aux = out if has_aux else (out, None)
        slopes.append(k_i)
        auxes.append(aux)
    points = [y]
    for beta in b:
        points.append(exp(points[-1], _increment(h, beta, slopes)))
    aux = jax.tree.map(lambda *a: jnp.stack(a), *auxes) if has_aux else None
    return points[-1], points[1:-1], aux


def integrate(
    tab: AnyTableau,
    f: Callable,
    y0: Any,
    t0: float,
    h: float,
    n: int,
    *,
    exp: Exp | None = None,
    stepper: Callable | None = None,
) -> tuple[Any, Any]:
    """n steps from y0 at t0 in one ``lax.scan``: (y after n steps, the states after every step stacked).
    ``stepper`` is :func:`step` (the default) or a drop-in with its signature."""
    stepper = step if stepper is None else stepper

    def one(y, k):
        y_next = stepper(tab, f, y, t0 + k * h, h, exp=exp)
        return y_next, y_next

    return jax.lax.scan(one, y0, jnp.arange(n, dtype=float))


__all__ = [
    "CF4",
    "DOP853",
    "RK4",
    "CommutatorFreeTableau",
    "Exp",
    "Tableau",
    "add",
    "coefficients",
    "integrate",
    "step",
    "step_path",
]
