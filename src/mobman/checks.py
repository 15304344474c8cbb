"""Validation of scalar parameters: each check returns the value as a float or raises
:class:`~mobman.errors.ModelError` naming the owner, the field and the allowed range."""

from __future__ import annotations

import math

from mobman.errors import ModelError


def finite(value, name: str, owner: str) -> float:
    """``value`` as a finite float."""
    if isinstance(value, bool):
        raise ModelError(f"{owner}: {name} must be a number, got {value!r}")
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise ModelError(f"{owner}: {name} must be a number, got {value!r}") from None
    if not math.isfinite(number):
        raise ModelError(f"{owner}: {name} must be finite, got {value!r}")
    return number


def positive(value, name: str, owner: str) -> float:
    """``value`` as a finite float > 0."""
    number = finite(value, name, owner)
    if number <= 0:
        raise ModelError(f"{owner}: {name} must be a finite number > 0, got {value!r}")
    return number


def non_negative(value, name: str, owner: str) -> float:
    """``value`` as a finite float ≥ 0."""
    number = finite(value, name, owner)
    if number < 0:
        raise ModelError(f"{owner}: {name} must be a finite number ≥ 0, got {value!r}")
    return number
