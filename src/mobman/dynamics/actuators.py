"""Actuator torque limits: constant torque boxes and DC-motor torque–speed lines (Korayem eq. 34).

Every actuator here has an envelope whose bounds are affine in the actuator speed ω (rad/s, or m/s for a
linear actuator):

    lower(ω) = lower_0 + lower_slope ω ≤ τ ≤ upper(ω) = upper_0 + upper_slope ω

- :class:`TorqueBox` lower ≤ τ ≤ upper, independent of the speed;
- :class:`DCMotor` the torque–speed characteristic of a DC motor (Korayem et al. eq. 34)

      T⁺ = k1 − k2 ω,   T⁻ = −k1 − k2 ω,   k1 = T_s (stall torque),   k2 = T_s / ω_nl (ω_nl: no-load speed).

The speed of an actuator is the rate of the coordinate its torque works on: τᵀ ω is its power. For the
reduced dynamics P η̇ + b = B τ (:mod:`mobman.dynamics.reduced`) this is ω = Bᵀ η (wheel spin rates for a
differential drive, joint rates for the arm). :func:`envelope_coefficients` stacks the four coefficients of a
set of actuators (``None`` = unlimited) so that the envelopes along a whole trajectory are one array
expression.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from mobman import checks
from mobman.errors import InputError, ModelError


class _AffineEnvelope:
    """Shared behaviour of actuators whose bounds are affine in the speed (see the module docstring)."""

    def coefficients(self) -> tuple[float, float, float, float]:
        """(lower_0, lower_slope, upper_0, upper_slope)."""
        raise NotImplementedError

    def limits(self, speed: npt.ArrayLike) -> tuple[np.ndarray, np.ndarray]:
        """(lower(ω), upper(ω)) at the speeds ``speed`` (any shape)."""
        lower_0, lower_slope, upper_0, upper_slope = self.coefficients()
        speed = np.asarray(speed, dtype=float)
        return lower_0 + lower_slope * speed, upper_0 + upper_slope * speed


@dataclass(frozen=True)
class TorqueBox(_AffineEnvelope):
    """Constant torque limits lower ≤ τ ≤ upper (N·m, or N for a prismatic joint); finite, lower < upper."""

    lower: float
    upper: float

    def __post_init__(self) -> None:
        object.__setattr__(self, "lower", checks.finite(self.lower, "lower", "TorqueBox"))
        object.__setattr__(self, "upper", checks.finite(self.upper, "upper", "TorqueBox"))
        if not self.lower < self.upper:
            raise ModelError(
                f"TorqueBox: lower must be < upper, got lower = {self.lower!r}, upper = {self.upper!r}"
            )

    @classmethod
    def symmetric(cls, limit: float) -> "TorqueBox":
        """|τ| ≤ limit (limit > 0)."""
        limit = checks.positive(limit, "limit", "TorqueBox")
        return cls(-limit, limit)

    def coefficients(self) -> tuple[float, float, float, float]:
        return (self.lower, 0.0, self.upper, 0.0)


@dataclass(frozen=True)
class DCMotor(_AffineEnvelope):
    """A DC motor (after its gearbox): T⁺ = k1 − k2 ω, T⁻ = −k1 − k2 ω with k1 = stall_torque and
    k2 = stall_torque / no_load_speed (Korayem et al. eq. 34).

    stall_torque: k1 = T_s > 0 (N·m); no_load_speed: ω_nl > 0 (rad/s). The motor can drive (τ ω > 0) only
    while |ω| < ω_nl; beyond, both bounds have the sign of −ω (it can only brake).
    """

    stall_torque: float
    no_load_speed: float

    def __post_init__(self) -> None:
        object.__setattr__(
            self, "stall_torque", checks.positive(self.stall_torque, "stall_torque", "DCMotor")
        )
        object.__setattr__(
            self, "no_load_speed", checks.positive(self.no_load_speed, "no_load_speed", "DCMotor")
        )

    @property
    def k1(self) -> float:
        """k1 = T_s, the stall torque (N·m)."""
        return self.stall_torque

    @property
    def k2(self) -> float:
        """k2 = T_s / ω_nl (N·m·s/rad), the slope of the torque–speed line."""
        return self.stall_torque / self.no_load_speed

    def coefficients(self) -> tuple[float, float, float, float]:
        return (-self.k1, -self.k2, self.k1, -self.k2)


Actuator = TorqueBox | DCMotor


def actuator_list(
    names: Sequence[str],
    actuators: Actuator | Sequence[Actuator | None] | Mapping[str, Actuator | None] | None,
) -> tuple[Actuator | None, ...]:
    """One actuator (or ``None`` = unlimited) per name, in the order of ``names``.

    ``actuators`` is a single actuator (used for all), a sequence with one entry per name, or a mapping
    name → actuator (names left out are unlimited).
    """
    names = tuple(names)
    if actuators is None or isinstance(actuators, (TorqueBox, DCMotor)):
        result = (actuators,) * len(names)
    elif isinstance(actuators, Mapping):
        unknown = [key for key in actuators if key not in names]
        if unknown:
            raise InputError(
                f"actuators: unknown actuator {unknown[0]!r}; the actuators are {', '.join(names)}"
            )
        result = tuple(actuators.get(name) for name in names)
    else:
        result = tuple(actuators)
        if len(result) != len(names):
            raise InputError(
                f"actuators: expected {len(names)} entries ({', '.join(names)}), got {len(result)}"
            )
    for name, actuator in zip(names, result):
        if actuator is not None and not isinstance(actuator, (TorqueBox, DCMotor)):
            raise InputError(f"actuators[{name!r}] must be a TorqueBox, a DCMotor or None, got {actuator!r}")
    return result


def envelope_coefficients(actuators: Sequence[Actuator | None]) -> np.ndarray:
    """Array (4, n): (lower_0, lower_slope, upper_0, upper_slope) per actuator; ``None`` is (−∞, 0, +∞, 0)."""
    unlimited = (-math.inf, 0.0, math.inf, 0.0)
    rows = [unlimited if a is None else a.coefficients() for a in actuators]
    return np.array(rows, dtype=float).T.reshape(4, -1)


__all__ = ["Actuator", "DCMotor", "TorqueBox", "actuator_list", "envelope_coefficients"]
