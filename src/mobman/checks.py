"""Validation of scalar parameters: each check returns the value as a float or raises
:class:`~mobman.errors.ModelError` naming the owner, the field and the allowed range; and, for the public
functions' array arguments, :func:`real_array` (no complex numbers) and :func:`all_finite`."""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt

from mobman.errors import InputError, ModelError


def all_finite(arr: np.ndarray) -> bool:
    """No NaN or infinity in the host array ``arr``: a few elements (one configuration, one velocity) as
    Python floats, three times faster than NumPy's test, which matters before a one-configuration compiled
    call of a few tens of µs. A finite sum settles it; a sum that overflowed from finite values is told apart
    by the test of each one."""
    if arr.size <= 32:
        values = arr.ravel().tolist()
        return math.isfinite(sum(values)) or all(map(math.isfinite, values))
    return bool(np.isfinite(arr).all())


def real_array(value: npt.ArrayLike, name: str) -> np.ndarray:
    """``value`` as a float64 NumPy array; an :class:`~mobman.errors.InputError` naming ``name`` where it holds
    complex numbers (NumPy's cast would drop their imaginary parts without a word). What is not numbers
    raises NumPy's TypeError or ValueError, for the caller's message."""
    arr = np.asarray(value)
    if arr.dtype.kind == "c":
        raise InputError(f"{name} must be real numbers, got complex ones ({arr.dtype})")
    return arr.astype(float, copy=False)


def finite(value: float, name: str, owner: str) -> float:
    """``value`` as a finite float."""
    if isinstance(value, bool):
        raise ModelError(f"{owner}: {name} must be a number, got {value!r}")
    try:
        number = float(value)
    except (TypeError, ValueError, OverflowError):
        raise ModelError(f"{owner}: {name} must be a number, got {value!r}") from None
    if not math.isfinite(number):
        raise ModelError(f"{owner}: {name} must be finite, got {value!r}")
    return number


def positive(value: float, name: str, owner: str) -> float:
    """``value`` as a finite float > 0."""
    number = finite(value, name, owner)
    if number <= 0:
        raise ModelError(f"{owner}: {name} must be a finite number > 0, got {value!r}")
    return number


def non_negative(value: float, name: str, owner: str) -> float:
    """``value`` as a finite float ≥ 0."""
    number = finite(value, name, owner)
    if number < 0:
        raise ModelError(f"{owner}: {name} must be a finite number ≥ 0, got {value!r}")
    return number


def vector3(value: npt.ArrayLike, name: str, owner: str) -> tuple[float, float, float]:
    """``value`` as 3 finite floats."""
    values = tuple(np.ravel(np.asarray(value, dtype=object)))
    if len(values) != 3:
        raise ModelError(f"{owner}: {name} must be 3 numbers, got {value!r}")
    x, y, z = (finite(v, f"{name}[{i}]", owner) for i, v in enumerate(values))
    return x, y, z


def inertia_tensor(value: npt.ArrayLike, name: str, owner: str) -> tuple[float, ...]:
    """A symmetric positive semi-definite 3 × 3 tensor (9 numbers row-major, or its diagonal as 3)."""
    try:
        tensor = np.asarray(value, dtype=float)
    except (TypeError, ValueError, OverflowError):
        raise ModelError(f"{owner}: {name} must be 9 numbers (3 × 3, row-major) or 3 (diagonal)") from None
    if tensor.size == 3:
        tensor = np.diag(tensor.ravel())
    if tensor.size != 9 or not np.all(np.isfinite(tensor)):
        raise ModelError(f"{owner}: {name} must be 9 finite numbers (3 × 3, row-major) or 3 (diagonal)")
    tensor = tensor.reshape(3, 3)
    scale = max(1.0, float(np.abs(tensor).max()))
    if not np.allclose(tensor, tensor.T, atol=1e-12 * scale):
        raise ModelError(f"{owner}: {name} must be symmetric")
    if np.linalg.eigvalsh(tensor).min() < -1e-12 * scale:
        raise ModelError(f"{owner}: {name} must be positive semi-definite (eigenvalues ≥ 0)")
    return tuple(float(v) for v in tensor.ravel())
