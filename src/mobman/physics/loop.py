"""A control law closed on MuJoCo: η from the *measured* state at the control rate, turned into wheel and
joint velocity commands, integrated by MuJoCo's physics (the model of :func:`mobman.physics.to_mjspec`).

Every control period h_c (``control_dt``) the law computes η = law(q, t, ξ*(t), ξ̇*(t)) (Bayle eq. 5–6 and
the other laws of :mod:`mobman.control.laws`) at the configuration q that MuJoCo's state gives
(:func:`mobman.physics.state.measured_q`); η is held for the period (zero-order hold, as
``integrator="hold"`` of :func:`mobman.control.simulation.simulate`) and commanded to the servos:

- driven wheels (differential drive, skid-steer): the actuator speeds u = T⁻¹ η_p (``eta_to_wheel_speeds``;
  Korayem eq. 14–15), each wheel's (side's) velocity servo;
- a car: each rear wheel at (u1 cos φ − y u1 sin φ / L) / r (the rear axle's speed and the yaw rate
  θ̇ = u1 sin φ / L of Tchoń eq. 31 at the wheel's lateral position y), the steering servo at u2;
- an omnidirectional platform: η_p = (ẋ, ẏ, θ̇) to its slide and hinge servos;
- the arm joints: q̇_a to their integrated-velocity servos.

With ``feedforward`` (a robot with its inertials, a :class:`~mobman.dynamics.DynamicModel`), each actuator
also gets the torque mobman's reduced dynamics asks for the commanded motion held at that velocity,
τ_ff = B(q)⁻¹ b(q, η) (the gravity and velocity-product terms of Yamamoto & Yun eq. 15–16 with η̇ = 0; a held
command has no acceleration to feed), applied as a generalized force on the actuator's joint; the servo makes
up the rest, its force range narrowed each period to [−τ_max − τ_ff, τ_max − τ_ff] so that the sum keeps the
actuator's torque limit.

MuJoCo then takes h_c / h steps of its own (``model.opt.timestep`` h; h_c must be a multiple of it). The
record holds, per control instant, the measured q, the commanded η and the platform's nonholonomic constraint
violation G(q_p) q̇_p measured on the simulated velocities (m/s: the wheels' lateral slip for a differential
drive). A state that becomes non-finite, or a MuJoCo warning of an unstable step, stops the run there; the
record up to that instant is kept and :attr:`PhysicsRun.stopped` says when and why.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import lru_cache, partial
from typing import Any, Callable

import jax
import jax.numpy as jnp
import numpy as np
import numpy.typing as npt

from mobman.control.laws import Law
from mobman.control.references import Reference
from mobman.dynamics.inertia import DynamicModel
from mobman.errors import InputError
from mobman.model.platforms.base import Platform
from mobman.model.platforms.car import CarLike
from mobman.model.robot import MobileManipulator, actuator_names
from mobman.model.scene import Scene
from mobman.model.tasks import Task
from mobman.physics.mjcf import mujoco_module, to_mjspec
from mobman.physics.state import StateReader, set_configuration


@dataclass
class PhysicsRun:
    """The record of a run on physics, one row per control instant t_k = k h_c, k = 0 … N (t_N = duration).

    ``q`` (N, n_q) measured, ``eta`` (N, n_eta) commanded, ``slip`` (N, n_q_p − n_eta_p) the platform's
    constraint violation G(q_p) q̇_p (m/s), ``stopped`` None for a complete run, else the time and reason it
    stopped; ``series`` what a ``probe`` of :func:`run_on_physics` recorded, by name, one row per instant."""

    t: np.ndarray
    q: np.ndarray
    eta: np.ndarray
    slip: np.ndarray
    stopped: str | None = None
    series: dict[str, np.ndarray] = field(default_factory=dict)


Probe = Callable[[Any], Callable[[Any], dict[str, np.ndarray]]]
"""A function of the compiled ``MjModel`` giving the function of the ``MjData`` that :func:`run_on_physics`
calls at every recorded instant (:mod:`mobman.physics.probe`)."""

UNSTABLE = ("BADQPOS", "BADQVEL", "BADQACC", "BADCTRL")
"""MuJoCo's warnings that stop a run: a non-finite or huge position, velocity, acceleration or command."""


def compiled_control(
    robot: MobileManipulator,
    task: Task,
    law: Law,
    reference: Reference,
    feedforward: DynamicModel | None = None,
) -> Callable[[np.ndarray, float], np.ndarray]:
    """η = law(q, t, ξ*(t), ξ̇*(t)) for one measured configuration q (n_q,) at time t, as a NumPy array: the
    law and the reference compiled ahead of time into one program (``jax.jit(…).lower(…).compile()``), their
    numbers flattened once, so that a call passes only arrays (no tracing-cache lookup, no pytree walk of
    the law). The program is shared by every law and reference of the same structure (as :func:`jax.jit`'s
    cache shares it): a new gain or a new line does not compile again. With ``feedforward`` (the robot's
    :class:`DynamicModel`), the same program also gives τ_ff = B(q)⁻¹ b(q, η) after η: (η, τ_ff) in one
    array, one call per control step."""
    leaves, tree = jax.tree_util.tree_flatten((law, reference))
    leaves = [jnp.asarray(leaf) for leaf in leaves]
    shapes = tuple((leaf.shape, leaf.dtype) for leaf in leaves)
    program = _control_program(robot, task, tree, shapes, feedforward)
    return lambda q, t: np.asarray(program(leaves, q, t))


@lru_cache(maxsize=16)
def _control_program(
    robot: MobileManipulator,
    task: Task,
    tree: Any,
    shapes: tuple[tuple[tuple[int, ...], Any], ...],
    feedforward: DynamicModel | None,
) -> Any:
    from mobman.dynamics.reduced import inverse_dynamics_one

    def control(leaves: list[jax.Array], q: jax.Array, t: jax.Array) -> jax.Array:
        law, reference = jax.tree_util.tree_unflatten(tree, leaves)
        xi_star, xi_star_dot = reference(t)
        eta = law(robot, task, q, t, xi_star, xi_star_dot).eta
        if feedforward is None:
            return eta
        return jnp.concatenate([eta, inverse_dynamics_one(feedforward, q, eta, jnp.zeros_like(eta))])

    arguments = [jax.ShapeDtypeStruct(shape, dtype) for shape, dtype in shapes]
    return jax.jit(control).lower(arguments, jnp.zeros(robot.n_q), jnp.zeros(())).compile()


def _slip_record(platform: Platform, q: np.ndarray, rates: np.ndarray) -> np.ndarray:
    """G(q_p) q̇_p (N, n_q_p − n_eta_p) over a record of configurations q (N, n_q) and measured platform
    rates (N, n_q_p): the constraint violation, in one compiled call on the record padded to a power of two
    (runs of similar lengths share the program)."""
    n, rows = len(q), platform.n_q - platform.n_eta
    if not (n and rows):
        return np.zeros((n, rows))
    size = 1 << (n - 1).bit_length()
    q_p = np.zeros((size, platform.n_q))
    padded = np.zeros((size, platform.n_q))
    q_p[:n], padded[:n] = q[:, : platform.n_q], rates
    return np.asarray(_slip(platform, q_p, padded))[:n]


@partial(jax.jit, static_argnums=0)
def _slip(platform: Platform, q_p: jax.Array, rates: jax.Array) -> jax.Array:
    return jax.vmap(lambda qi, ri: platform.constraints(qi) @ ri)(q_p, rates)


class _FeedForward:
    """τ_ff = B(q)⁻¹ b(q, η) of a :class:`DynamicModel` (given by the control program,
    :func:`compiled_control`) written as generalized forces on the joints of its MuJoCo model's actuators,
    and the servos' force ranges narrowed by them (module docstring)."""

    def __init__(self, model: Any, dynamics: DynamicModel) -> None:
        mj = mujoco_module()
        names = actuator_names(dynamics.robot)
        known = {model.actuator(i).name: i for i in range(model.nu)}
        ids = [known.get(name, -1) for name in names]
        joint = int(mj.mjtTrn.mjTRN_JOINT)
        unsupported = [n for n, i in zip(names, ids) if i < 0 or int(model.actuator_trntype[i]) != joint]
        if unsupported:
            raise InputError(
                f"feedforward: needs one joint actuator per actuator of the dynamic model; the "
                f"{dynamics.robot.platform.kind} platform's {', '.join(unsupported)} are not (differential "
                f"drive, omnidirectional and fixed platforms have them)"
            )
        self.model, self.ids = model, np.array(ids, dtype=int)
        self.dofs = np.array([model.jnt_dofadr[model.actuator_trnid[i, 0]] for i in ids], dtype=int)
        self.limited = model.actuator_forcelimited[self.ids].astype(bool)
        self.range = np.array(model.actuator_forcerange[self.ids])

    def apply(self, data: Any, tau: np.ndarray) -> None:
        tau = np.where(self.limited, np.clip(tau, self.range[:, 0], self.range[:, 1]), tau)
        data.qfrc_applied[self.dofs] = tau
        limited = self.ids[self.limited]
        self.model.actuator_forcerange[limited] = self.range[self.limited] - tau[self.limited, None]


class _Commands:
    """Writes η into ``data.ctrl`` for the actuators of a model built by :func:`to_mjspec`."""

    def __init__(self, model: Any, robot: MobileManipulator) -> None:
        self.robot, platform = robot, robot.platform
        joints = robot.coordinate_names[robot.n_platform :]
        self.joints = np.array([model.actuator(name).id for name in joints], dtype=int)
        self.kind = platform.kind
        if self.kind == "car":
            self.rear = [
                (model.actuator(f"wheel_rear_{'right' if s.y < 0 else 'left'}").id, s)
                for s in platform.wheels()[:2]
            ]
            self.steering = model.actuator("steering").id
        else:
            self.platform = np.array([model.actuator(n).id for n in platform.actuator_names], dtype=int)
            # u = T⁻¹ η_p (eta_to_wheel_speeds) as a NumPy matrix: one product per control step
            self.to_speeds = np.linalg.inv(platform.actuator_matrix()) if platform.wheel_actuated else None

    def apply(self, data: Any, q: np.ndarray, eta: np.ndarray) -> None:
        platform, n_p = self.robot.platform, self.robot.platform.n_eta
        eta_p = eta[:n_p]
        if isinstance(platform, CarLike):
            u1, u2 = eta_p
            phi = q[3]
            for actuator, site in self.rear:
                speed = u1 * math.cos(phi) - site.y * u1 * math.sin(phi) / platform.length
                data.ctrl[actuator] = speed / site.radius
            data.ctrl[self.steering] = u2
        elif n_p:
            data.ctrl[self.platform] = eta_p if self.to_speeds is None else self.to_speeds @ eta_p
        data.ctrl[self.joints] = eta[n_p:]


def run_on_physics(
    robot: MobileManipulator | DynamicModel,
    law: Law,
    reference: Reference,
    q0: npt.ArrayLike,
    duration: float,
    control_dt: float,
    *,
    task: Task | None = None,
    friction: float = 1.0,
    timestep: float = 1e-3,
    torque_limits: npt.ArrayLike | None = None,
    probe: Probe | None = None,
    scene: Scene | None = None,
    feedforward: bool = False,
) -> PhysicsRun:
    """Run ``law`` tracking ``reference`` (of ``task``, default the robot's) from q0 for ``duration`` seconds
    on the MuJoCo model of ``robot`` (:func:`to_mjspec` with ``friction``, ``timestep``, ``torque_limits``
    and the obstacles of ``scene``, which the platform and the arm's links touch),
    the law evaluated every ``control_dt`` seconds (a multiple of ``timestep``) at the measured state; with
    ``feedforward`` (``robot`` a :class:`DynamicModel`), the reduced dynamics' τ_ff = B⁻¹ b(q, η) added to
    the servos (module docstring)."""
    mj = mujoco_module()
    kinematic = robot.robot if isinstance(robot, DynamicModel) else robot
    task = kinematic.task if task is None else task
    for name, value in (("duration", duration), ("control_dt", control_dt)):
        if not (math.isfinite(value) and value > 0):
            raise InputError(f"{name} must be a finite number > 0 (s), got {value!r}")
    substeps = round(control_dt / timestep)
    if substeps < 1 or not math.isclose(substeps * timestep, control_dt, rel_tol=1e-9):
        raise InputError(
            f"control_dt = {control_dt!r} s must be a whole multiple of the physics step {timestep!r} s"
        )
    if feedforward and not isinstance(robot, DynamicModel):
        raise InputError(
            "feedforward: needs the robot's inertials (a DynamicModel: a real robot, a URDF file with "
            "inertials, yamamoto-dual-arm), got a MobileManipulator without them"
        )
    spec = to_mjspec(robot, scene, torque_limits=torque_limits, friction=friction, timestep=timestep)
    model = spec.compile()
    data = mj.MjData(model)
    set_configuration(model, data, kinematic, q0)
    commands, reader = _Commands(model, kinematic), StateReader(model, kinematic)
    dynamics = robot if feedforward and isinstance(robot, DynamicModel) else None
    feed = None if dynamics is None else _FeedForward(model, dynamics)
    control = compiled_control(kinematic, task, law, reference, dynamics)
    n = int(round(duration / control_dt))
    unstable_at = np.array([int(getattr(mj.mjtWarning, f"mjWARN_{w}")) for w in UNSTABLE])
    ts, qs, etas, rates = [], [], [], []
    sample, samples = None if probe is None else probe(model), []
    stopped = None
    for k in range(n + 1):  # t_0 … t_N = duration, as mobman.control.simulation records
        q = reader.q(data)
        command = control(q, k * control_dt)  # η, then τ_ff with a feed-forward
        eta = command[: kinematic.n_eta]
        if not math.isfinite(q.sum() + command.sum()):  # a NaN or an infinity anywhere
            stopped = f"t = {k * control_dt:.6g} s: non-finite state or command"
            break
        ts.append(k * control_dt)
        qs.append(q)
        etas.append(eta)
        rates.append(reader.rates(data))
        if sample is not None:
            samples.append(sample(data))
        if k == n:
            break
        commands.apply(data, q, eta)
        if feed is not None:
            feed.apply(data, command[kinematic.n_eta :])
        mj.mj_step(model, data, nstep=substeps)
        if data.warning.number[unstable_at].any():
            unstable = [w for w, i in zip(UNSTABLE, unstable_at) if data.warning[i].number]
            stopped = (
                f"t = {k * control_dt:.6g} to {(k + 1) * control_dt:.6g} s: MuJoCo reports an unstable step "
                f"({', '.join(unstable)}: a non-finite or huge value; MuJoCo reset its state)"
            )
            break
    q_record = np.array(qs).reshape(len(qs), kinematic.n_q)
    slip = _slip_record(kinematic.platform, q_record, np.array(rates).reshape(len(qs), -1))
    series = {name: np.array([s[name] for s in samples]) for name in (samples[0] if samples else {})}
    return PhysicsRun(
        np.array(ts), q_record, np.array(etas).reshape(len(qs), kinematic.n_eta), slip, stopped, series
    )
