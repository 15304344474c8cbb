"""The options the studies share, checked once: counts (starts, iterations, samples), distances (a step, a
tolerance), vectors (a target, a centre, a keep-out region) and the scoring of a posture (a manipulability
measure and the Jacobian it is taken of). Each check raises :class:`~mobman.errors.InputError` with one line
naming the option and its allowed range; the command line names the option as its flag."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from mobman.errors import InputError
from mobman.manipulability import MEASURES

LEVELS = ("arm", "system")
"""The Jacobian a posture is scored by: the arm's J_a (the platform parked) or the whole system's J̄ = J S."""


def count(value: Any, name: str) -> int:
    """``value`` as an integer ≥ 1."""
    if not (isinstance(value, (int, np.integer)) and not isinstance(value, bool) and value >= 1):
        raise InputError(f"{name} must be an integer ≥ 1, got {value!r}")
    return int(value)


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


__all__ = ["LEVELS", "count", "distance", "scoring", "vector"]
