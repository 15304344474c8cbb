"""The load capacity checked on physics: a motion run on MuJoCo with a payload, the arm's actuators held to
their envelopes.

:func:`mobman.dynamics.max_load` predicts the largest payload m* that a motion can carry with every
actuator inside its torque envelope (Korayem et al.; the reduced inverse dynamics of Yamamoto & Yun eq.
15–16, affine in the payload's mass). :func:`run_with_load` runs the same motion on MuJoCo's model of the
robot (:func:`mobman.physics.to_mjspec`) carrying a payload of a given mass, so that a prediction can be
seen to hold on an independent rigid-body engine: at 0.9 m* the arm tracks the motion with every torque
inside its envelope, at 1.2 m* the limiting actuator saturates and the arm falls behind.

**The run.** The platform is prescribed (``to_mjspec(..., platform="prescribed")``: joints x, y, θ), as in
Korayem et al.'s case studies, whose base follows a planned motion: the arm's torques depend on the base's
motion, not on what drives it. The desired configuration q_d(t) is the motion's samples interpolated by a
cubic spline (q̇_d, q̈_d its derivatives). Every physics step a computed-torque servo asks MuJoCo's inverse
dynamics (``mj_inverse``) for the generalized forces τ_req that give the acceleration

    q̈* = q̈_d + 2 ω_s (q̇_d − q̇) + ω_s² (q_d − q)        (ω_s = 2π · ``bandwidth``),

applies them to the platform's joints as they are and to each arm joint clipped to its actuator's envelope
[T⁻(ω), T⁺(ω)] at the joint's measured speed ω (a :class:`mobman.dynamics.DCMotor`'s torque–speed lines or a
:class:`mobman.dynamics.TorqueBox`), and steps. A step is *saturated* for a joint whose τ_req lies outside
its envelope. The envelope is the only limit: contacts and joint limits are off (no floor, no obstacle) and so
are the model's own servos.

The arm's actuators are the ones checked: where a motion's capacity is set by a wheel, the prescribed
platform does not test it (the limiting actuator of Korayem's cases and of ``docs/examples/tiago_load.toml``
is an arm joint).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from mobman.dynamics.actuators import Actuator, envelope_coefficients
from mobman.dynamics.inertia import DynamicModel
from mobman.dynamics.load_capacity import LoadCapacity, unit_payload_model
from mobman.errors import InputError
from mobman.model.inertial import Payload
from mobman.physics.mjcf import mujoco_module, to_mjspec

BANDWIDTH = 10.0
"""Hz of the computed-torque servo's critically damped error dynamics (module notes)."""


@dataclass(frozen=True)
class LoadRun:
    """A motion run on MuJoCo with a payload (:func:`run_with_load`).

    ``mass``: the payload (kg); ``names``: the arm's actuators (joints); at each physics step ``t`` (N,):
    the measured ``q`` and desired ``q_desired`` configurations (N, n_q), the torques the servo asked for,
    ``required`` (N, n_a), those applied, ``applied`` (within the envelope), the envelope ``lower``,
    ``upper`` at the measured speeds and ``saturated`` (N, n_a): required outside the envelope."""

    mass: float
    names: tuple[str, ...]
    t: np.ndarray
    q: np.ndarray
    q_desired: np.ndarray
    required: np.ndarray
    applied: np.ndarray
    lower: np.ndarray
    upper: np.ndarray
    saturated: np.ndarray

    @property
    def tracking_error(self) -> float:
        """The largest |q − q_d| of an arm joint over the run (rad or m)."""
        n_a = len(self.names)
        return float(np.max(np.abs(self.q[:, -n_a:] - self.q_desired[:, -n_a:])))

    @property
    def first_saturation(self) -> float | None:
        """The time of the first saturated step (s), None when no actuator saturated."""
        steps = np.flatnonzero(self.saturated.any(axis=1))
        return float(self.t[steps[0]]) if steps.size else None

    @property
    def saturated_steps(self) -> dict[str, int]:
        """Per actuator, the steps at which it saturated."""
        return {name: int(n) for name, n in zip(self.names, self.saturated.sum(axis=0))}

    def as_dict(self) -> dict:
        """The run's figures, JSON-ready."""
        return {
            "mass_kg": self.mass,
            "tracking_error": self.tracking_error,
            "saturated_steps": self.saturated_steps,
            "first_saturation": self.first_saturation,
            "peak_torque": dict(zip(self.names, np.max(np.abs(self.required), axis=0).tolist())),
        }


def run_with_load(
    model: DynamicModel,
    t: npt.ArrayLike,
    q: npt.ArrayLike,
    actuators: Mapping[str, Actuator],
    mass: float,
    *,
    payload: Payload | None = None,
    timestep: float = 1e-3,
    bandwidth: float = BANDWIDTH,
) -> LoadRun:
    """Run the motion q (N, n_q) at times t (N,) on MuJoCo carrying ``mass`` kg shaped like ``payload``
    (default: the model's payload, else a point mass at the tool of arm 0; :func:`unit_payload_model`), the
    arm joints held to the envelopes of ``actuators`` (by name, :attr:`DynamicModel.actuator_names`; a joint
    left out is unlimited). The platform's coordinates must be x, y, θ (module notes)."""
    mj = mujoco_module()
    t, q = np.asarray(t, dtype=float), np.asarray(q, dtype=float)
    robot = model.robot
    if t.ndim != 1 or t.size < 4 or not np.all(np.diff(t) > 0):
        raise InputError(f"t must be at least 4 increasing times, got shape {t.shape}")
    if q.shape != (t.size, robot.n_q):
        raise InputError(f"q must have shape ({t.size}, {robot.n_q}), got {q.shape}")
    for name, value in (("mass", mass), ("timestep", timestep), ("bandwidth", bandwidth)):
        if not (math.isfinite(value) and value >= 0 and (value > 0 or name == "mass")):
            raise InputError(
                f"{name} must be a finite number {'≥' if name == 'mass' else '>'} 0, got {value!r}"
            )
    unknown = set(actuators) - set(model.actuator_names)
    if unknown:
        raise InputError(
            f"actuators: unknown {sorted(unknown)}; the actuators are {', '.join(model.actuator_names)}"
        )
    unit = unit_payload_model(model, payload).payload
    assert unit is not None  # unit_payload_model gives the model a 1-kg payload
    loaded = model.with_payload(unit.scaled(mass) if mass > 0 else None)
    compiled = to_mjspec(loaded, platform="prescribed", timestep=timestep).compile()
    compiled.opt.gravity[:] = loaded.gravity
    compiled.opt.disableflags |= (
        mj.mjtDisableBit.mjDSBL_CONTACT | mj.mjtDisableBit.mjDSBL_ACTUATION | mj.mjtDisableBit.mjDSBL_LIMIT
    )
    data = mj.MjData(compiled)

    from scipy.interpolate import CubicSpline

    path = CubicSpline(t, q, axis=0)
    steps = np.arange(t[0], t[-1] + 0.5 * timestep, timestep)
    n_a = robot.n_q - robot.n_platform
    names = model.actuator_names[-n_a:]
    coefficients = envelope_coefficients([actuators.get(name) for name in names])
    omega = 2 * math.pi * bandwidth
    record = {key: np.empty((steps.size, robot.n_q if key == "q" else n_a)) for key in _SERIES}
    desired, rates, accelerations = (path(steps, order) for order in (0, 1, 2))  # q_d, q̇_d, q̈_d at every step
    data.qpos[:], data.qvel[:] = desired[0], rates[0]
    for k, (q_d, q_dot_d, q_ddot_d) in enumerate(zip(desired, rates, accelerations)):
        record["q"][k] = data.qpos
        data.qacc[:] = q_ddot_d + 2 * omega * (q_dot_d - data.qvel) + omega**2 * (q_d - data.qpos)
        mj.mj_inverse(compiled, data)
        required = data.qfrc_inverse.copy()
        speed = data.qvel[-n_a:]
        lower = coefficients[0] + coefficients[1] * speed
        upper = coefficients[2] + coefficients[3] * speed
        applied = required.copy()
        applied[-n_a:] = np.clip(required[-n_a:], lower, upper)
        record["required"][k], record["applied"][k] = required[-n_a:], applied[-n_a:]
        record["lower"][k], record["upper"][k] = lower, upper
        data.qfrc_applied[:] = applied
        mj.mj_step(compiled, data)
    saturated = (record["required"] < record["lower"]) | (record["required"] > record["upper"])
    return LoadRun(float(mass), tuple(names), steps, q_desired=desired, saturated=saturated, **record)


FRACTIONS = (0.9, 1.2)
"""The payloads :func:`check_capacity` runs, as fractions of the predicted capacity."""


def check_capacity(
    model: DynamicModel,
    t: npt.ArrayLike,
    q: npt.ArrayLike,
    actuators: Mapping[str, Actuator],
    capacity: LoadCapacity,
    *,
    payload: Payload | None = None,
    timestep: float = 1e-3,
) -> tuple[LoadRun, ...]:
    """The motion run on MuJoCo (:func:`run_with_load`) with payloads of :data:`FRACTIONS` of the capacity
    ``capacity`` that :func:`mobman.dynamics.max_load` predicted for it: the prediction holds on physics when
    the first run never saturates and the last one does."""
    if not capacity.bounded:
        raise InputError("capacity: unbounded (no limited actuator depends on the load): nothing to check")
    return tuple(
        run_with_load(model, t, q, actuators, f * capacity.max_load, payload=payload, timestep=timestep)
        for f in FRACTIONS
    )


_SERIES = ("q", "required", "applied", "lower", "upper")
"""The series :func:`run_with_load` records step by step: the configuration (n_q columns), then per arm
actuator (n_a)."""


__all__ = ["BANDWIDTH", "FRACTIONS", "LoadRun", "check_capacity", "run_with_load"]
