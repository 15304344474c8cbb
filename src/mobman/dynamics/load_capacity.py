"""Maximum allowable load along a given motion (dynamic load-carrying capacity; Korayem et al. §5, eq. 34).

For a motion (q(t), η(t), η̇(t)) the reduced inverse dynamics (:mod:`mobman.dynamics.reduced`, Yamamoto
eq. 15–16) gives the actuator torques τ = B⁻¹ (P η̇ + b). Every body enters M(q) and the potential as a sum,
and a payload of mass m (inertia m·I₁ about its centre of mass, I₁ its inertia per kilogram) contributes
m × (its unit-mass terms). P and b are therefore affine in m while B does not depend on it, so

    τ(t; m) = τ0(t) + m τ1(t),   τ0 = τ(t; 0),   τ1 = τ(t; 1) − τ(t; 0)                           (1)

exactly (no linearisation). Actuator i, running at speed ω_i = (Bᵀ η)_i (its torque's power conjugate),
allows lower_i(ω_i) ≤ τ_i ≤ upper_i(ω_i) (:mod:`mobman.dynamics.actuators`, Korayem eq. 34). Each sample
and actuator bounds m from above:

    τ1 > 0:  m ≤ (upper − τ0)/τ1;     τ1 < 0:  m ≤ (τ0 − lower)/(−τ1);     τ1 = 0:  no bound,

and the maximum allowable load is the smallest of these bounds over every actuator and every instant; the
pair that attains it is the limiting actuator and time. Nothing bounds m when every τ1 vanishes on the
limited actuators (e.g. a horizontal arm at rest): ``max_load`` is then ``math.inf`` and the limiting actuator
and time are ``None``. When even m = 0 leaves an envelope, :class:`InfeasibleMotionError` names the actuator,
the time and the torques. Entries |τ1| ≤ 1e-9 (1 + max|τ0| + max|τ1|) are treated as zero (round-off of (1)).

How τ0 and τ1 are computed (one compiled, vectorised evaluation over the samples, no loop over time):
the Newton–Euler generalized force of every body (:func:`mobman.dynamics.equations.body_forces_one`, one
Jacobian evaluation and its forward-mode derivative per sample); τ0 = B⁻¹ Sᵀ Σ (all bodies but the payload)
and τ1 = B⁻¹ Sᵀ Q₁, Q₁ the force of a 1-kg payload. Both are checked against the reduced inverse dynamics of
:mod:`mobman.dynamics.reduced` (Lagrange form) in the tests.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from functools import partial

import jax
import jax.numpy as jnp
import numpy as np
import numpy.typing as npt

from mobman.dynamics import equations as eq
from mobman.dynamics import reduced
from mobman.dynamics.actuators import Actuator, actuator_list, envelope_coefficients
from mobman.dynamics.inertia import DynamicModel
from mobman.engine.batched import blocked
from mobman.errors import InputError, ModelError
from mobman.model.inertial import Payload

ZERO_TOLERANCE = 1e-9
"""Relative size below which an entry of τ1 counts as zero, and by which m = 0 may exceed an envelope."""


class InfeasibleMotionError(ModelError):
    """The motion needs torques outside an actuator's envelope even without a load."""


@dataclass(frozen=True)
class LoadCapacity:
    """The maximum allowable load along a motion, and the torques behind it.

    max_load: kg (``math.inf`` when no actuator limits it); limiting_actuator / limiting_time: where the
    bound is attained (``None`` when unbounded); names: actuator names in τ order; t (N,); tau0, tau1 (N, n):
    τ = tau0 + m tau1; speed (N, n): actuator speeds; lower, upper (N, n): the envelopes at those speeds;
    actuator_load (n,): the largest load each actuator alone allows, actuator_time (n,) when (NaN if
    unbounded); profile (N,): the largest load each instant alone allows (inf where none is bounded).
    """

    max_load: float
    limiting_actuator: str | None
    limiting_time: float | None
    names: tuple[str, ...]
    t: np.ndarray
    tau0: np.ndarray
    tau1: np.ndarray
    speed: np.ndarray
    lower: np.ndarray
    upper: np.ndarray
    actuator_load: np.ndarray
    actuator_time: np.ndarray
    profile: np.ndarray

    @property
    def bounded(self) -> bool:
        return math.isfinite(self.max_load)

    def torques(self, mass: float) -> np.ndarray:
        """Required torques τ0 + m τ1 (N, n) for a load of ``mass`` kg (eq. 1)."""
        return self.tau0 + float(mass) * self.tau1

    def summary(self) -> dict:
        """The JSON-ready result: capacity, limiting actuator and time, and the per-actuator capacities."""
        return {
            "max_load_kg": self.max_load if self.bounded else None,
            "bounded": self.bounded,
            "limiting_actuator": self.limiting_actuator,
            "limiting_time": self.limiting_time,
            "per_actuator": {
                name: {
                    "max_load_kg": float(m) if math.isfinite(m) else None,
                    "time": float(t) if math.isfinite(m) else None,
                }
                for name, m, t in zip(self.names, self.actuator_load, self.actuator_time)
            },
        }


def unit_payload_model(model: DynamicModel, payload: Payload | None = None) -> DynamicModel:
    """``model`` carrying a load of 1 kg shaped like ``payload`` (default: the model's payload, else a point
    mass at the tool of arm 0); its inertia is taken per kilogram (:meth:`Payload.scaled`)."""
    template = payload if payload is not None else model.payload
    template = Payload(1.0) if template is None else template
    if not isinstance(template, Payload):
        raise InputError(f"payload must be a Payload, got {type(template).__name__}")
    if template.mass == 0:
        template = replace(template, mass=1.0)
    return model.with_payload(template.scaled(1.0))


def _affine_one(
    model: DynamicModel, q: jax.Array, eta: jax.Array, eta_dot: jax.Array
) -> tuple[jax.Array, jax.Array, jax.Array]:
    """(τ0, τ1, ω) at one sample; ``model`` carries the unit-mass payload.

    With q̇ = S η, q̈ = S η̇ + Ṡ η and B = Sᵀ E: the Newton–Euler generalized forces of every body
    (:func:`mobman.dynamics.equations.body_forces_one`) sum to M q̈ + c + g; τ0 = B⁻¹ Sᵀ (the sum over every
    body but the payload) is the reduced inverse dynamics without payload (eq. 15–16) and τ1 = B⁻¹ Sᵀ Q₁,
    Q₁ the unit payload's own force, so that τ0 + m τ1 is exactly the reduced inverse dynamics with m kg.
    """
    s = model.robot.S(q)
    b_mat = reduced.input_matrix_one(model, q)
    q_dot = s @ eta
    q_ddot = s @ eta_dot + reduced.s_dot_eta(model, q, eta)
    forces, wheel = eq.body_forces_one(model, q, q_dot, q_ddot)
    both = jnp.stack([jnp.sum(forces[:-1], axis=0) + wheel, forces[-1]], axis=1)
    tau = jnp.linalg.solve(b_mat, s.T @ both)
    return tau[:, 0], tau[:, 1], b_mat.T @ eta


def _bounds(tau0, tau1, speed, coefficients):
    """Envelopes, per-sample load bounds and the worst margin at m = 0 (all arrays (N, n))."""
    lower = coefficients[0] + coefficients[1] * speed
    upper = coefficients[2] + coefficients[3] * speed
    scale = 1.0 + jnp.max(jnp.abs(tau0)) + jnp.max(jnp.abs(tau1))
    eps = ZERO_TOLERANCE * scale
    bound = jnp.where(
        tau1 > eps,
        (upper - tau0) / jnp.where(tau1 > eps, tau1, 1.0),
        jnp.where(tau1 < -eps, (tau0 - lower) / jnp.where(tau1 < -eps, -tau1, 1.0), jnp.inf),
    )
    margin = jnp.minimum(upper - tau0, tau0 - lower)
    return lower, upper, jnp.maximum(bound, 0.0), margin, eps


@jax.jit
def _evaluate(tau0, tau1, speed, coefficients):
    lower, upper, bound, margin, eps = _bounds(tau0, tau1, speed, coefficients)
    load, index, profile = jnp.min(bound, axis=0), jnp.argmin(bound, axis=0), jnp.min(bound, axis=1)
    return lower, upper, load, index, profile, margin, eps


@partial(jax.jit, static_argnums=(0,))
def _capacity(
    model: DynamicModel, q: jax.Array, eta: jax.Array, eta_dot: jax.Array, coefficients: jax.Array
) -> tuple[jax.Array, ...]:
    tau0, tau1, speed = blocked(partial(_affine_one, model))(q, eta, eta_dot)
    return (tau0, tau1, speed) + _evaluate(tau0, tau1, speed, coefficients)


def load_torques(
    model: DynamicModel,
    q: npt.ArrayLike,
    eta: npt.ArrayLike,
    eta_dot: npt.ArrayLike,
    payload: Payload | None = None,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(τ0, τ1, ω) along the samples: τ = τ0 + m τ1 for a load of m kg (eq. 1) and the actuator speeds
    ω = Bᵀ η; shapes (N, n_actuators). ``payload`` shapes the load (see :func:`unit_payload_model`)."""
    q, eta, eta_dot = _motion(model, q, eta, eta_dot)
    tau0, tau1, speed, *_ = _capacity(
        unit_payload_model(model, payload),
        q,
        eta,
        eta_dot,
        jnp.asarray(envelope_coefficients((None,) * model.n_actuators)),
    )
    return np.asarray(tau0), np.asarray(tau1), np.asarray(speed)


def _motion(
    model: DynamicModel, q: npt.ArrayLike, eta: npt.ArrayLike, eta_dot: npt.ArrayLike
) -> tuple[np.ndarray | jax.Array, np.ndarray | jax.Array, np.ndarray | jax.Array]:
    q = eq.validated_q(model, q)
    eta = reduced.validated_eta(model, eta, "eta")
    eta_dot = reduced.validated_eta(model, eta_dot, "eta_dot")
    if q.ndim != 2 or eta.shape != (q.shape[0], model.robot.n_eta) or eta_dot.shape != eta.shape:
        raise InputError(
            f"motion: q must be (N, {model.robot.n_q}) and eta, eta_dot (N, {model.robot.n_eta}) "
            f"samples, got {tuple(q.shape)}, {tuple(eta.shape)}, {tuple(eta_dot.shape)}"
        )
    if q.shape[0] < 1:
        raise InputError("motion: at least one sample is needed")
    return q, eta, eta_dot


def eta_dot_from_samples(t: npt.ArrayLike, eta: npt.ArrayLike) -> np.ndarray:
    """η̇ from samples η(t_k) by second-order finite differences (``np.gradient``, one-sided at the ends)."""
    t = np.asarray(t, dtype=float)
    eta = np.asarray(eta, dtype=float)
    if t.ndim != 1 or t.size < 3 or eta.shape[0] != t.size:
        raise InputError(f"t must be 1-D with ≥ 3 samples matching eta, got t {t.shape}, eta {eta.shape}")
    if not np.all(np.diff(t) > 0):
        raise InputError("t must be strictly increasing")
    return np.gradient(eta, t, axis=0, edge_order=2)


def max_load(
    model: DynamicModel,
    t: npt.ArrayLike,
    q: npt.ArrayLike,
    eta: npt.ArrayLike,
    eta_dot: npt.ArrayLike,
    actuators: Actuator | Sequence[Actuator | None] | Mapping[str, Actuator | None],
    payload: Payload | None = None,
) -> LoadCapacity:
    """The largest payload mass keeping every actuator inside its envelope at every sample (eq. 1).

    t (N,), q (N, n_q), eta and eta_dot (N, n_eta): the motion (reduced coordinates, q̇ = S η). actuators:
    one per ``model.actuator_names`` (a sequence, a mapping name → actuator, or one for all; ``None`` =
    unlimited). payload: the shape of the load (centre of mass, inertia per kg, arm), default the model's
    payload or a point mass at the tool of arm 0. Raises :class:`InfeasibleMotionError` when the motion
    leaves an envelope even without a load.
    """
    names = model.actuator_names
    coefficients = envelope_coefficients(actuator_list(names, actuators))
    q, eta, eta_dot = _motion(model, q, eta, eta_dot)
    times = np.asarray(t, dtype=float)
    samples = np.shape(q)[0]
    if times.shape != (samples,) or not np.all(np.isfinite(times)):
        raise InputError(f"t must hold {samples} finite sample times, got shape {times.shape}")
    unit = unit_payload_model(model, payload)
    out = jax.device_get(_capacity(unit, q, eta, eta_dot, jnp.asarray(coefficients)))
    return _result(names, times, *out)


def capacity_from_torques(
    names: Sequence[str],
    t: npt.ArrayLike,
    tau0: npt.ArrayLike,
    tau1: npt.ArrayLike,
    speed: npt.ArrayLike,
    actuators: Actuator | Sequence[Actuator | None] | Mapping[str, Actuator | None],
) -> LoadCapacity:
    """The maximum allowable load for torques already known to be τ0 + m τ1 (eq. 1), e.g. from
    :func:`load_torques`, scaled or combined by the caller; arrays (N, n) in the order of ``names``."""
    names = tuple(names)
    coefficients = envelope_coefficients(actuator_list(names, actuators))
    t = np.asarray(t, dtype=float)
    arrays = [np.asarray(a, dtype=float) for a in (tau0, tau1, speed)]
    if any(a.shape != (t.size, len(names)) or not np.all(np.isfinite(a)) for a in arrays):
        raise InputError(f"tau0, tau1, speed must be finite arrays of shape ({t.size}, {len(names)})")
    out = jax.device_get(_evaluate(*arrays, jnp.asarray(coefficients)))
    return _result(names, t, *arrays, *out)


def _result(
    names: tuple[str, ...],
    t: np.ndarray,
    tau0: np.ndarray,
    tau1: np.ndarray,
    speed: np.ndarray,
    lower: np.ndarray,
    upper: np.ndarray,
    load: np.ndarray,
    index: np.ndarray,
    profile: np.ndarray,
    margin: np.ndarray,
    eps: float | np.ndarray,
) -> LoadCapacity:
    k, i = np.unravel_index(np.argmin(margin), margin.shape)
    if margin[k, i] < -eps:
        raise InfeasibleMotionError(
            f"max_load: even without a load, actuator {names[i]!r} needs τ = {tau0[k, i]:.6g} "
            f"at t = {t[k]:.4g} s, "
            f"outside its envelope [{lower[k, i]:.6g}, {upper[k, i]:.6g}] (speed {speed[k, i]:.4g}): "
            "the motion is infeasible for these actuators"
        )
    limiting = int(np.argmin(load))
    bounded = bool(np.isfinite(load[limiting]))
    return LoadCapacity(
        max_load=float(load[limiting]) if bounded else math.inf,
        limiting_actuator=names[limiting] if bounded else None,
        limiting_time=float(t[index[limiting]]) if bounded else None,
        names=tuple(names),
        t=t,
        tau0=np.asarray(tau0),
        tau1=np.asarray(tau1),
        speed=np.asarray(speed),
        lower=lower,
        upper=upper,
        actuator_load=load,
        actuator_time=np.where(np.isfinite(load), t[index], np.nan),
        profile=profile,
    )


__all__ = [
    "InfeasibleMotionError",
    "LoadCapacity",
    "ZERO_TOLERANCE",
    "capacity_from_torques",
    "eta_dot_from_samples",
    "load_torques",
    "max_load",
    "unit_payload_model",
]
