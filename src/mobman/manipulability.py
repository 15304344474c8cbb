"""Manipulability measures of arms and of whole nonholonomic mobile manipulators (Nait-Chabane §3, Bayle §6–7).

For a Jacobian J (m × k) with singular values σ_1 ≥ … ≥ σ_m (Nait-Chabane eq. 15–17):

- Yoshikawa's manipulability w = σ_1⋯σ_m = √det(J Jᵀ) (eq. 13, 17),
- the inverse condition number w2 = σ_m / σ_1 (eq. 18),
- the eccentricity of the manipulability ellipsoid w5 = √(1 − σ_m² / σ_1²) (eq. 19; Bayle et al.).

They apply to the arm's Jacobian J_a (platform fixed), to the reduced Jacobian J̄ = J S of the whole system
(ξ̇ = J̄ η, Bayle eq. 2) and to the normalised J̄_N = J̄ · R, R = diag(v_max, ω_max, q̇_a,max…) (Nait-Chabane
eq. 20–26), which gives the mixed units of η a common scale. A rank-deficient J gives w = 0, w2 = 0, w5 = 1;
a J holding NaN gives NaN measures inside compiled code and an InputError at the public functions.

**Restricted measures.** When the velocity degree D̄ is smaller than m (``robots.bayle_rrp``: J̄ is 5 × 5 of
rank ≤ 4 everywhere), the plain measures are identically degenerate. ``rank=r`` restricts them to the
admissible subspace, the span of the r largest singular directions: w = σ_1⋯σ_r, w2 = σ_r / σ_1,
w5 = √(1 − σ_r² / σ_1²). ``rank="auto"`` (in :func:`analyze`, :func:`gradient`) uses D̄ for the system and the
generic rank of J_a for the arm whenever it is below m, and plain measures otherwise.

**Numerics.** Singular values come from the eigenvalues λ_i = σ_i² of the smaller Gram matrix (J Jᵀ or Jᵀ J):
the measures over all of them read λ_max, λ_min and det (:func:`mobman.model.spectra.extremes`, run by the
engine's tridiagonalisation and Laguerre's method, :mod:`mobman.engine.extremes`), restricted measures the r
largest (:func:`mobman.model.spectra.eigvalsh`, the engine's batched Jacobi solver,
:mod:`mobman.engine.linalg`). Both have absolute accuracy about eps · σ_1² on λ, so
σ_i to about eps · σ_1² / σ_i² (relative) and a tiny σ to about √eps · σ_1 absolute (see docs/manipulability.md).
Gradients use the eigenvalue perturbation rule; they are finite everywhere, exact away from repeated singular
values of the ones involved (w5 and w2 at σ_1 = σ_r, which is where w5 = 0, get a zero derivative).
"""

from __future__ import annotations

import math
from functools import lru_cache, reduce
from typing import Any, Literal

import jax
import jax.numpy as jnp
import numpy as np
import numpy.typing as npt

from mobman import kinematics as K
from mobman.checks import real_array
from mobman.engine.batched import batched, traced
from mobman.errors import InputError, ModelError, SingularConfigurationError
from mobman.model import spatial, spectra
from mobman.model.robot import MobileManipulator
from mobman.model.tasks import Task

MEASURES = ("yoshikawa", "inverse_condition", "eccentricity")
WHICH = ("arm", "system", "system_normalized")

Rank = int | Literal["auto"] | None


# --- measures of a Jacobian ---------------------------------------------------------------------


def _safe_sqrt(x: jnp.ndarray) -> jnp.ndarray:
    """√x for x ≥ 0 (negative rounding errors clipped), with a finite (zero) derivative at x = 0."""
    x = jnp.maximum(x, 0.0)
    positive = x > 0
    return jnp.where(positive, jnp.sqrt(jnp.where(positive, x, 1.0)), 0.0)


def _safe_ratio(num: jnp.ndarray, den: jnp.ndarray) -> jnp.ndarray:
    """num / den, 0 where den = 0 (finite derivative)."""
    ok = den > 0
    return jnp.where(ok, num / jnp.where(ok, den, 1.0), 0.0)


def _check_rank(rank: object, p: int) -> None:
    if rank is not None and not (isinstance(rank, (int, np.integer)) and 1 <= rank <= p):
        raise InputError(
            f"rank must be None or an integer in 1..{p} (the number of singular values), got {rank!r}"
        )


def _squared_singular_values(j: jnp.ndarray) -> jnp.ndarray:
    """σ_i² (..., min(m, k)), descending, from the smaller Gram matrix."""
    return spectra.eigvalsh(spectra.gram(j))


def _measures(top: jnp.ndarray, low: jnp.ndarray, product: jnp.ndarray, undefined: jnp.ndarray) -> dict:
    """w, w2, w5 from σ_1², σ_r² and σ_1² ⋯ σ_r² (all ≥ 0); NaN where ``undefined``."""
    ratio = jnp.clip(_safe_ratio(low, top), 0.0, 1.0)
    out = {
        "yoshikawa": _safe_sqrt(product),
        "inverse_condition": _safe_sqrt(ratio),
        "eccentricity": jnp.where(top > 0, _safe_sqrt(1.0 - ratio), 1.0),
    }
    return {k: jnp.where(undefined, jnp.asarray(jnp.nan, v.dtype), v) for k, v in out.items()}


def measures_one(j: jnp.ndarray, rank: int | None = None) -> dict[str, jnp.ndarray]:
    """The measures of one m × k Jacobian (as :func:`measures`), unvalidated: for traced code.

    Over all p = min(m, k) singular values they need only σ_1², σ_p² and their product det of the Gram
    matrix (:func:`mobman.model.spectra.extremes`); restricted to a rank r < p, the r largest of all."""
    m, p = j.shape[-2], min(j.shape[-2:])
    if rank is None and p < m:  # fewer columns than rows: σ_{p+1..m} = 0, always degenerate
        zero = jnp.zeros(j.shape[:-2], j.dtype)
        return {"yoshikawa": zero, "inverse_condition": zero, "eccentricity": zero + 1.0}
    if rank is None or rank == p:
        top, low, det = spectra.extremes(spectra.gram(j))
        top, low = jnp.maximum(top, 0.0), jnp.maximum(low, 0.0)
        # a NaN in J: NaN measures, never w = 0 or w5 = 1; the product of the eigenvalues clipped at 0
        return _measures(top, low, jnp.where(low > 0, det, 0.0), jnp.isnan(top + low + det))
    lam = jnp.maximum(_squared_singular_values(j), 0.0)
    parts = spatial.unstack(lam)  # one split (one concatenation in reverse mode), not a slice per use
    return _measures(
        parts[0], parts[rank - 1], reduce(jnp.multiply, parts[:rank]), jnp.isnan(reduce(jnp.add, parts))
    )


def _as_jacobian(j: npt.ArrayLike) -> jnp.ndarray:
    if traced(j):
        return j
    # a float64 jax.Array passes as it is: a converted copy would leave jit's fast dispatch path (~35 µs)
    if isinstance(j, jax.Array) and j.dtype == jnp.float64:
        arr = j
    else:
        try:
            arr = jnp.asarray(real_array(j, "a Jacobian"))
        except InputError:
            raise
        except (TypeError, ValueError):
            raise InputError(f"a Jacobian must be an array of numbers, got {type(j).__name__}") from None
    if arr.ndim < 2 or 0 in arr.shape[-2:]:
        raise InputError(f"a Jacobian must have shape (..., m, k) with m, k ≥ 1, got shape {arr.shape}")
    # σ_max ≤ √(m k) max|J| and w ≤ σ_max^m: below this bound J Jᵀ and its determinant stay finite
    m, k = arr.shape[-2:]
    largest = (np.finfo(float).max / 4.0) ** (1.0 / (2 * m)) / math.sqrt(m * k)
    if not bool(_all_within(arr, largest)):
        host = np.asarray(arr)
        if np.isfinite(host).all():
            raise InputError(
                f"the Jacobian's entries reach {np.abs(host).max():.3g}, beyond {largest:.3g} for a {m} × {k} "
                "matrix: its measures would overflow float64 (give it in other units)"
            )
        bad = np.argwhere(~np.isfinite(host).all(axis=(-2, -1)))
        where = f" at batch index {tuple(int(i) for i in bad[0])}" if bad.size else ""
        raise InputError(f"the Jacobian holds NaN or infinite entries{where}: its measures are undefined")
    return arr


_all_within = jax.jit(lambda a, bound: jnp.all(jnp.abs(a) <= bound))  # False for NaN too


def _jacobian_argument(j: npt.ArrayLike) -> tuple:
    return (_as_jacobian(j),)


def _jacobian_and_rank(j: npt.ArrayLike, rank: int | None = None) -> tuple:
    j = _as_jacobian(j)
    _check_rank(rank, min(j.shape[-2:]))
    return j, None if rank is None else int(rank)


@batched({0: 2}, validate=_jacobian_argument)
def singular_values(j: jax.Array) -> jnp.ndarray:
    """Singular values of (..., m, k) matrices, shape (..., min(m, k)), descending."""
    return _safe_sqrt(_squared_singular_values(j))


@batched({0: 2}, static=(1,), validate=_jacobian_and_rank)
def measures(j: jax.Array, rank: int | None = None) -> dict[str, jnp.ndarray]:
    """The three measures of (..., m, k) Jacobians, each of shape (...) (Nait-Chabane eq. 17–19).

    ``{"yoshikawa": w, "inverse_condition": w2, "eccentricity": w5}``; with ``rank=r`` they are restricted to
    the r largest singular values (w = σ_1⋯σ_r, σ_min = σ_r). Rank-deficient: w = 0, w2 = 0, w5 = 1.
    A Jacobian with NaN or infinite entries raises InputError.
    """
    return measures_one(j, rank)


def yoshikawa(j: npt.ArrayLike, rank: int | None = None) -> jnp.ndarray:
    """w = σ_1⋯σ_m = √det(J Jᵀ) (Yoshikawa; Nait-Chabane eq. 13, 17), or σ_1⋯σ_r with ``rank=r``."""
    return measures(j, rank)["yoshikawa"]


def inverse_condition(j: npt.ArrayLike, rank: int | None = None) -> jnp.ndarray:
    """w2 = σ_m / σ_1 (Nait-Chabane eq. 18), or σ_r / σ_1 with ``rank=r``."""
    return measures(j, rank)["inverse_condition"]


def eccentricity(j: npt.ArrayLike, rank: int | None = None) -> jnp.ndarray:
    """w5 = √(1 − σ_m² / σ_1²) (Nait-Chabane eq. 19), or with σ_r in place of σ_m with ``rank=r``."""
    return measures(j, rank)["eccentricity"]


@batched({0: 2}, validate=_jacobian_argument)
def ellipsoid(j: jax.Array) -> tuple[jnp.ndarray, jnp.ndarray]:
    """Manipulability ellipsoid {J η : ‖η‖ ≤ 1} of (..., m, k) Jacobians (Nait-Chabane §3.1).

    Returns the principal semi-axes (..., m), descending (the singular values, zero-padded when k < m), and
    their unit directions (..., m, m) as columns (the left singular vectors, eigenvectors of J Jᵀ).
    """
    lam, u = spectra.eigh(spatial.matmul_expanded(j, j.T))
    return _safe_sqrt(lam), u


# --- Jacobians of a robot -------------------------------------------------------------------------


def _limits(robot: MobileManipulator) -> np.ndarray:
    limits = robot.velocity_limits
    if limits is None:
        raise ModelError(
            f"{robot.name}: normalised measures need velocity limits for every quasi-velocity "
            f"({', '.join(robot.control_names)}); give the platform's (v_max, ω_max) and every joint's velocity_max"
        )
    return np.asarray(limits, dtype=float)


def _check_arm(robot: MobileManipulator, arm: int) -> None:
    if not (isinstance(arm, (int, np.integer)) and 0 <= arm < len(robot.arms)):
        raise InputError(f"{robot.name}: arm index must be in 0..{len(robot.arms) - 1}, got {arm!r}")


def arm_jacobian(
    robot: MobileManipulator, q: npt.ArrayLike, task: Task | None = None, arm: int = 0
) -> jnp.ndarray:
    """J_a: the columns of J = ∂ξ/∂q for arm ``arm``'s coordinates (platform fixed), shape (..., m, n_a)."""
    _check_arm(robot, arm)
    return K.jacobian(robot, q, task)[..., robot.arm_slice(arm)]


def system_jacobian(
    robot: MobileManipulator, q: npt.ArrayLike, task: Task | None = None, normalized: bool = False
) -> jnp.ndarray:
    """J̄ = J S (Bayle eq. 2), or J̄_N = J̄ · diag(robot.velocity_limits) (Nait-Chabane eq. 23), (..., m, δ).

    Raises ModelError for ``normalized=True`` when the robot lacks velocity limits.
    """
    jbar = K.reduced_jacobian(robot, q, task)
    return jbar * _limits(robot) if normalized else jbar


# --- restricted rank ------------------------------------------------------------------------------


@lru_cache(maxsize=64)
def admissible_ranks(robot: MobileManipulator, task: Task | None = None) -> dict[str, int]:
    """Generic ranks {"arm": rank J_a, "system": D̄} (maximum over seeded random configurations, as in
    :func:`mobman.redundancy.redundancy_report`); ``"system_normalized"`` equals ``"system"``."""
    from mobman import redundancy

    q = redundancy.sample_configurations(robot)  # the report's samples: their J is one compiled program
    j_arm = np.asarray(K.first_order(robot, q, task)["J"])[..., robot.arm_slice(0)]
    d_arm = int(K.rank(j_arm, redundancy.RTOL).max())
    d_bar = redundancy.redundancy_report(robot, task).D_bar
    return {"arm": d_arm, "system": d_bar, "system_normalized": d_bar}


def _resolve_rank(robot: MobileManipulator, task: Task | None, which: str, rank: Rank) -> int | None:
    """The rank used for ``which``: ``None`` (plain), an integer, or ``"auto"`` (generic rank if below m)."""
    if rank != "auto":
        return rank
    m = (task or robot.task).dim
    r = admissible_ranks(robot, task)[which]
    if r == 0:
        moved_by = "the arm's joints" if which == "arm" else "any quasi-velocity"
        raise ModelError(
            f"{robot.name}: the {which} Jacobian is zero at every sampled configuration: the task "
            f"({', '.join((task or robot.task).names)}) does not move with {moved_by} (links of zero length?), "
            "so its measures are undefined"
        )
    return r if r < m else None


# --- whole-robot analysis -------------------------------------------------------------------------


def analyze(robot: MobileManipulator, q: npt.ArrayLike, task: Task | None = None, rank: Rank = None) -> dict:
    """The three measures of the arm (J_a), the system (J̄) and the normalised system (J̄_N), batched.

    Returns ``{"arm": {...}, "system": {...}, "system_normalized": {...} or None (no velocity limits),
    "restricted": bool, "ranks": {"arm": r or None, "system": r or None}}``, each ``{...}`` holding
    ``yoshikawa``, ``inverse_condition`` and ``eccentricity`` arrays of the leading shape of q.

    ``rank=None``: plain measures; an integer r: system measures restricted to the r largest singular values
    (the arm's to min(r, n_a)); ``"auto"``: restricted to the admissible subspace wherever the generic rank
    (D̄ for the system) is below m. ``restricted`` says whether any reported measure is a restricted one.
    """
    first = K.first_order(robot, q, task)  # the program analyze's other quantities come from
    jac = np.asarray(first["J"])
    if not np.isfinite(jac).all():
        raise SingularConfigurationError(
            "manipulability: J holds NaN or infinite entries at configurations where the task's coordinates "
            "are singular as a representation (see mobman.kinematics.representation_singular)"
        )
    jbar = np.asarray(first["J_bar"])
    j_arm = jac[..., robot.arm_slice(0)]
    ranks: dict[str, int | None]
    if isinstance(rank, (int, np.integer)):
        ranks = {"arm": min(int(rank), j_arm.shape[-1]), "system": int(rank)}
    else:
        ranks = {
            "arm": _resolve_rank(robot, task, "arm", rank),
            "system": _resolve_rank(robot, task, "system", rank),
        }
    out: dict[str, Any] = {"arm": measures(j_arm, ranks["arm"]), "system": measures(jbar, ranks["system"])}
    limits = robot.velocity_limits
    out["system_normalized"] = (
        None if limits is None else measures(jbar * np.asarray(limits), ranks["system"])
    )
    out["restricted"] = any(r is not None for r in ranks.values())
    out["ranks"] = ranks
    return out


def jacobian_one(robot: MobileManipulator, task: Task, which: str, q: jnp.ndarray) -> jnp.ndarray:
    """J_a, J̄ or J̄_N (``which``: ``"arm"``, ``"system"``, ``"system_normalized"``) of one configuration
    ``q`` (n_q,), unvalidated: for traced code (the kernel of the batched functions below)."""
    if which == "arm":
        return K.jacobian_one(robot, task, q)[:, robot.arm_slice(0)]
    j = K.reduced_jacobian_one(robot, task, q)
    return j * np.asarray(robot.velocity_limits) if which == "system_normalized" else j


def _prepare(robot: MobileManipulator, which: str, task: Task | None, rank: Rank) -> tuple[Task, int | None]:
    """Check ``which`` and the rank; returns the task and the resolved rank (None: plain measures).

    The checks of one set of options are done once (cached): a call for one configuration is mostly fixed
    overhead, and Python work before the dispatch costs two to three times its own time there (measured)."""
    try:
        return _prepared(robot, which, task, rank)
    except TypeError:  # an unhashable option: checked without the cache, for its error message
        return _check_options(robot, which, task, rank)


@lru_cache(maxsize=256, typed=True)  # typed: rank=1.0 is refused, not taken for a cached rank=1
def _prepared(robot: MobileManipulator, which: str, task: Task | None, rank: Rank) -> tuple[Task, int | None]:
    return _check_options(robot, which, task, rank)


def _check_options(
    robot: MobileManipulator, which: str, task: Task | None, rank: Rank
) -> tuple[Task, int | None]:
    if which not in WHICH:
        raise InputError(f"which must be one of {', '.join(WHICH)}, got {which!r}")
    if which == "system_normalized":
        _limits(robot)
    task = K.resolve_task(robot, task)
    r = _resolve_rank(robot, task, which, rank)
    _check_rank(r, min(task.dim, robot.arms[0].n_joints if which == "arm" else robot.n_eta))
    return task, None if r is None else int(r)


def _validated_options(
    robot: MobileManipulator,
    q: npt.ArrayLike,
    which: str = "system",
    task: Task | None = None,
    rank: Rank = None,
) -> tuple:
    task, r = _prepare(robot, which, task, rank)
    return robot, K.validated_q(robot, q), which, task, r


@batched({1: 1}, static=(0, 2, 3, 4), validate=_validated_options)
def jacobian_and_measures(
    robot: MobileManipulator,
    q: npt.ArrayLike,
    which: str = "system",
    task: Task | None = None,
    rank: Rank = None,
) -> tuple[jnp.ndarray, dict[str, jnp.ndarray]]:
    """The Jacobian ``which`` (``"arm"`` J_a, ``"system"`` J̄ = J S or ``"system_normalized"`` J̄_N) and its
    three measures, in one compiled call (batched).

    Returns ``(J, {"yoshikawa": w, "inverse_condition": w2, "eccentricity": w5})``, the same values as
    :func:`system_jacobian` (or :func:`arm_jacobian`) followed by :func:`measures`, with ``rank`` as in
    :func:`gradient`. For one configuration this is the fast path: one dispatch instead of two, and no
    wait for the first call's result before the second starts. Where the task's coordinates are singular as a
    representation (:func:`mobman.kinematics.representation_singular`), J and the measures hold NaN: this
    fast path does not test its output (:func:`measures` of such a J raises InputError).
    """
    assert task is not None and rank != "auto"  # resolved by the validator
    j = jacobian_one(robot, task, which, jnp.asarray(q))
    return j, measures_one(j, rank)


def _validated_gradient_options(
    robot: MobileManipulator,
    q: npt.ArrayLike,
    which: str = "system",
    measure: str = "eccentricity",
    task: Task | None = None,
    rank: Rank = None,
) -> tuple:
    if measure not in MEASURES:
        raise InputError(f"measure must be one of {', '.join(MEASURES)}, got {measure!r}")
    task, r = _prepare(robot, which, task, rank)
    return robot, K.validated_q(robot, q), which, measure, task, r


@batched({1: 1}, static=(0, 2, 3, 4, 5), validate=_validated_gradient_options)
def gradient(
    robot: MobileManipulator,
    q: npt.ArrayLike,
    which: str = "system",
    measure: str = "eccentricity",
    task: Task | None = None,
    rank: Rank = None,
) -> jnp.ndarray:
    """∂P/∂q (..., n_q) of a measure P ∈ {yoshikawa, inverse_condition, eccentricity} of the arm, system
    or normalised-system Jacobian, by autodiff (batched, compiled). Finite wherever J is (see the module notes
    on repeated singular values); NaN where the task's coordinates are singular as a representation
    (:func:`mobman.kinematics.representation_singular`). The criterion gradients of Nait-Chabane §4.3 / Bayle §7 are this function.
    """

    assert task is not None and rank != "auto"  # resolved by the validator

    def value(qq):
        return measures_one(jacobian_one(robot, task, which, qq), rank)[measure]

    return jax.grad(value)(q)


__all__ = [
    "MEASURES",
    "admissible_ranks",
    "analyze",
    "arm_jacobian",
    "eccentricity",
    "ellipsoid",
    "gradient",
    "inverse_condition",
    "jacobian_and_measures",
    "jacobian_one",
    "measures",
    "measures_one",
    "singular_values",
    "system_jacobian",
    "yoshikawa",
]
