"""Kinematic and velocity redundancy, singular configurations and consistency relations (Bayle §3–4).

Definitions (Bayle et al. 2003):

- M = dim q (mobility index), δ = dim η (mobility degree);
- d(q) = rank J(q), D = max_q d(q), kinematic redundancy R = M − D; kinematically singular configurations
  (KSC) are those with d(q) < D, of singularity order D − d(q) (§3);
- d̄(q) = rank J̄(q), D̄ = max_q d̄(q) (eq. 4), velocity redundancy R̄ = δ − D̄; velocity singular
  configurations (VSC) are those with d̄(q) < D̄, of order D̄ − d̄(q) (§4.2);
- when D̄ < m not every ξ̇ is admissible: ξ̇ must satisfy the consistency relations yᵀ ξ̇ = 0 for every y in
  the left null space of J̄ (§4.3, §5.2).

**How D and D̄ are found.** A maximum over the configuration space cannot be enumerated; the rank of an
analytic matrix function takes its maximum on an open dense set, so a handful of random configurations find
it with probability one. :func:`redundancy_report` draws ``samples`` configurations with a seeded generator
(platform coordinates and unbounded revolute joints uniform in [−π, π], joints with two finite limits uniform
between them, one-sided limits over one metre/radian beyond the finite bound, unbounded prismatic joints in
[−1, 1]) and takes the maximum rank. Numerical ranks count the singular values above ``rtol · σmax``
(:func:`mobman.kinematics.rank`, default ``rtol = 1e-9``, absolute floor 1e-12).
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass
from functools import lru_cache
from typing import NamedTuple

import numpy as np
import numpy.typing as npt

from mobman import kinematics as K
from mobman.errors import SingularConfigurationError
from mobman.model.robot import MobileManipulator
from mobman.model.tasks import Task

RTOL = 1e-9
"""Default relative rank tolerance: singular values ≤ RTOL · σmax count as zero."""


@dataclass(frozen=True)
class RedundancyReport:
    """Mobility index and degree, degrees of freedom of the EE and redundancy degrees (Bayle §3–4)."""

    M: int
    delta: int
    D: int
    R: int
    D_bar: int
    R_bar: int

    def as_dict(self) -> dict[str, int]:
        return asdict(self)


class Singularity(NamedTuple):
    """Result of a singularity test: a boolean flag and the singularity order (0 when regular), batched."""

    singular: np.ndarray
    order: np.ndarray


def sample_configurations(robot: MobileManipulator, samples: int = 64, seed: int = 0) -> np.ndarray:
    """Seeded random configurations, shape (samples, n_q), drawn as described in the module docstring."""
    rng = np.random.default_rng(seed)
    bounds = []
    kinds = ["revolute"] * robot.platform.n_q + [j.kind for a in robot.arms for j in a.joints]
    for kind, (lo, hi) in zip(kinds, robot.position_limits):
        span = math.pi if kind == "revolute" else 1.0
        if math.isfinite(lo) and math.isfinite(hi):
            bounds.append((lo, hi))
        elif math.isfinite(lo):
            bounds.append((lo, lo + span))
        elif math.isfinite(hi):
            bounds.append((hi - span, hi))
        else:
            bounds.append((-span, span))
    low, high = zip(*bounds)
    return rng.uniform(low, high, size=(samples, robot.n_q))


def ranks(
    robot: MobileManipulator, q: npt.ArrayLike, task: Task | None = None, rtol: float = RTOL
) -> tuple[np.ndarray, np.ndarray]:
    """(d(q), d̄(q)) = (rank J(q), rank J̄(q)), integer arrays with the leading shape of q."""
    first = K.first_order(robot, q, task)
    j, jbar = np.asarray(first["J"]), np.asarray(first["J_bar"])
    _check_finite(j, "J")
    return K.rank(j, rtol), K.rank(jbar, rtol)


def _check_finite(a: np.ndarray, name: str) -> None:
    """SingularConfigurationError where a Jacobian is not finite (a representation singularity of the task)."""
    bad = ~np.isfinite(a).all(axis=(-2, -1))
    if bad.any():
        index = tuple(int(i) for i in np.argwhere(bad)[0])
        where = f" at configuration {index}" if index else ""
        raise SingularConfigurationError(
            f"{name} holds NaN or infinite entries{where}: the task's coordinates are singular "
            "as a representation there (see mobman.kinematics.representation_singular); its rank is undefined"
        )


@lru_cache(maxsize=64)
def redundancy_report(
    robot: MobileManipulator, task: Task | None = None, samples: int = 64, seed: int = 0, rtol: float = RTOL
) -> RedundancyReport:
    """M, δ, D, R = M − D, D̄, R̄ = δ − D̄ for the robot and task (its own task by default).

    D and D̄ are the maximum ranks of J and J̄ over ``samples`` seeded random configurations (module docstring).
    The result is cached per (robot, task, samples, seed, rtol).
    """
    d, d_bar = ranks(robot, sample_configurations(robot, samples, seed), task, rtol)
    big_d, big_d_bar = int(d.max()), int(d_bar.max())
    return RedundancyReport(
        M=robot.n_q,
        delta=robot.n_eta,
        D=big_d,
        R=robot.n_q - big_d,
        D_bar=big_d_bar,
        R_bar=robot.n_eta - big_d_bar,
    )


def _singularity(generic_rank: int, rank: np.ndarray) -> Singularity:
    order = np.maximum(generic_rank - rank, 0)
    return Singularity(order > 0, order)


def is_kinematic_singular(
    robot: MobileManipulator, q: npt.ArrayLike, task: Task | None = None, rtol: float = RTOL
) -> Singularity:
    """KSC test d(q) < D, with singularity order D − d(q) (Bayle §3), batched over q."""
    d, _ = ranks(robot, q, task, rtol)
    return _singularity(redundancy_report(robot, task, rtol=rtol).D, d)


def is_velocity_singular(
    robot: MobileManipulator, q: npt.ArrayLike, task: Task | None = None, rtol: float = RTOL
) -> Singularity:
    """VSC test d̄(q) < D̄, with singularity order D̄ − d̄(q) (Bayle §4.2), batched over q."""
    _, d_bar = ranks(robot, q, task, rtol)
    return _singularity(redundancy_report(robot, task, rtol=rtol).D_bar, d_bar)


def is_consistent(
    robot: MobileManipulator,
    q: npt.ArrayLike,
    xi_dot: npt.ArrayLike,
    task: Task | None = None,
    rtol: float = RTOL,
) -> np.ndarray:
    """Consistency test rank[J̄ | ξ̇] = rank J̄ (Bayle §4.3): ξ̇ is realisable by some η (batched)."""
    return K.is_consistent(robot, q, xi_dot, task, rtol)


def consistency_relations(
    robot: MobileManipulator, q: npt.ArrayLike, task: Task | None = None, rtol: float = RTOL
) -> np.ndarray:
    """Rows y with yᵀ J̄(q) = 0 spanning the relations yᵀ ξ̇ = 0 that hold almost everywhere, (..., m − D̄, m).

    They are the left singular vectors of J̄ for its m − D̄ smallest singular values, orthonormal (Bayle §5.2).
    Where D̄ = m there are none (shape (..., 0, m)). At a VSC (d̄(q) < D̄) the left null space is larger: these
    rows are then one orthonormal subset of it, and :func:`is_consistent` is the complete test.
    """
    report = redundancy_report(robot, task, rtol=rtol)
    jbar = np.asarray(K.reduced_jacobian(robot, q, task))
    _check_finite(jbar, "J̄")
    u, _, _ = np.linalg.svd(jbar, full_matrices=True)
    return np.swapaxes(u[..., :, report.D_bar :], -1, -2)


__all__ = [
    "RTOL",
    "RedundancyReport",
    "Singularity",
    "consistency_relations",
    "is_consistent",
    "is_kinematic_singular",
    "is_velocity_singular",
    "ranks",
    "redundancy_report",
    "sample_configurations",
]
