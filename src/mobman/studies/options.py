"""The options the studies share, checked once: counts (starts, iterations, samples), distances (a step, a
tolerance), vectors (a target, a centre, a keep-out region) and the scoring of a posture (a manipulability
measure and the Jacobian it is taken of), and the budget of a request: its iterations and the memory of its
largest array, refused before any work. Each check raises :class:`~mobman.errors.InputError` with one line
naming the option and its allowed range; the command line names the option as its flag."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from mobman.engine.memory import available_memory, size
from mobman.errors import InputError
from mobman.manipulability import MEASURES

LEVELS = ("arm", "system")
"""The Jacobian a posture is scored by: the arm's J_a (the platform parked) or the whole system's J̄ = J S."""


def count(value: Any, name: str) -> int:
    """``value`` as an integer ≥ 1."""
    if not (isinstance(value, (int, np.integer)) and not isinstance(value, bool) and value >= 1):
        raise InputError(f"{name} must be an integer ≥ 1, got {value!r}")
    return int(value)


MAX_ITERATIONS = 10_000
"""Most damped least-squares steps per start (:mod:`mobman.studies.reaching`): the solver reaches a target
within tens of steps (60 by default), so more only spends time."""

MAX_TOLERANCE = 0.1
"""Largest tolerance of a reached target (m, or rad for an angle): beyond it a "reached" posture may be
anywhere near."""

BYTES_PER_VALUE = 32
"""Memory estimate per float of a batched solver's arrays: the value (8 bytes) and the compiled program's
copies of it (the Jacobians, Gram matrices and steps of every row at once)."""


def iterations(value: Any, name: str = "iterations") -> int:
    """``value`` as an integer from 1 to :data:`MAX_ITERATIONS`."""
    n = count(value, name)
    if n > MAX_ITERATIONS:
        raise InputError(f"{name} must be an integer from 1 to {MAX_ITERATIONS:,}, got {n:,}")
    return n


def seed(value: Any) -> int:
    """``value`` as the seed of NumPy's random generator: an integer ≥ 0."""
    if not (isinstance(value, (int, np.integer)) and not isinstance(value, bool) and value >= 0):
        raise InputError(f"seed must be an integer ≥ 0, got {value!r}")
    return int(value)


def tolerance(value: Any, name: str = "tolerance") -> float:
    """``value`` as a finite tolerance > 0 and at most :data:`MAX_TOLERANCE`."""
    if not (
        isinstance(value, (int, float, np.integer, np.floating))
        and not isinstance(value, bool)
        and math.isfinite(value)
        and 0 < value <= MAX_TOLERANCE
    ):
        raise InputError(f"{name} must be a number > 0 and ≤ {MAX_TOLERANCE:g} (m or rad), got {value!r}")
    return float(value)


def memory(counts: dict[str, int], values: int) -> None:
    """Refuse, before any work, a batch that holds ``values`` floats at once (:data:`BYTES_PER_VALUE` each)
    when that exceeds the machine's available memory: the message names the largest of ``counts`` (option →
    the count it asks for), the rest, the estimate and the limit."""
    available = available_memory()
    need = values * BYTES_PER_VALUE
    if available is None or need <= available:
        return
    name = max(counts, key=lambda key: counts[key])
    rest = ", ".join(f"{key} {counts[key]:,}" for key in counts if key != name)
    raise InputError(
        f"{name} {counts[name]:,}: {'with ' + rest + ', ' if rest else ''}the computation holds about "
        f"{size(need)} at once, more than the {size(available)} of memory available; ask for fewer"
    )


def distance(value: Any, name: str) -> float:
    """``value`` as a finite distance > 0 (m)."""
    if not (
        isinstance(value, (int, float, np.integer, np.floating))
        and not isinstance(value, bool)
        and math.isfinite(value)
        and value > 0
    ):
        raise InputError(f"{name} must be a finite distance > 0 (m), got {value!r}")
    return float(value)


def vector(value: Any, name: str, size: int, names: str) -> np.ndarray:
    """``value`` as ``size`` finite numbers, ``names`` naming them in the message."""
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be {size} numbers ({names}), got {value!r}") from None
    if arr.shape != (size,):
        raise InputError(f"{name} must be {size} numbers ({names}), got shape {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise InputError(f"{name} contains NaN or infinite values")
    return arr


def scoring(measure: Any, level: Any) -> None:
    """``measure`` one of :data:`mobman.manipulability.MEASURES`, ``level`` one of :data:`LEVELS`."""
    if measure not in MEASURES:
        raise InputError(f"measure must be one of {', '.join(MEASURES)}, got {measure!r}")
    if level not in LEVELS:
        raise InputError(f"level must be one of {', '.join(LEVELS)}, got {level!r}")


__all__ = [
    "BYTES_PER_VALUE",
    "LEVELS",
    "MAX_ITERATIONS",
    "MAX_TOLERANCE",
    "count",
    "distance",
    "iterations",
    "memory",
    "scoring",
    "seed",
    "tolerance",
    "vector",
]
