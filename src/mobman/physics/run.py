"""A simulation specification run on MuJoCo and compared with its kinematic run (``mobman simulate SPEC
--physics mujoco``; docs/physics.md).

:func:`simulate_on_physics` closes the spec's law on the MuJoCo model of the robot
(:func:`mobman.physics.run_on_physics` with the :class:`~mobman.control.spec.PhysicsSettings`: physics step,
control rate, friction, a payload at the tool) and returns:

- ``result``: a :class:`~mobman.control.simulation.SimulationResult` of the *measured* run, at the control
  instants: the measured q, the commanded η, ξ(q) and ξ*(t), the error e(ξ*, ξ), the measures, and the law's
  flags (``saturated``, ``damped``, …) as the law gave them at the measured states;
- ``series``: the physics series (:mod:`mobman.physics.probe`): the platform's lateral slip G(q_p) q̇_p, each
  wheel's longitudinal slip, its contact forces, each actuator's torque and whether it is at its limit, and
  ``deviation`` ‖e(ξ_kin(t), ξ(t))‖, the distance of the measured task value from the kinematic run's
  (:meth:`~mobman.control.spec.Spec.simulate`, linearly interpolated to the control instants);
- ``metrics``: the physics metrics (:func:`physics_metrics`), to add to :func:`mobman.control.metrics.summarize`'s.
"""

from __future__ import annotations

import contextlib
import dataclasses
from collections.abc import Iterator
from dataclasses import dataclass
from functools import partial
from typing import Any

import jax
import jax.numpy as jnp
import numpy as np
import numpy.typing as npt

from mobman.control.laws import Law
from mobman.control.references import Reference
from mobman.control.simulation import SimulationResult, compute_measures
from mobman.control.spec import PhysicsSettings, Spec
from mobman.dynamics.inertia import DynamicModel
from mobman.errors import InputError
from mobman.model.inertial import Payload
from mobman.model.robot import MobileManipulator
from mobman.model.tasks import Task
from mobman.physics.loop import PhysicsRun, run_on_physics
from mobman.physics.mjcf import dynamic_model, mujoco_module
from mobman.physics.probe import wheel_names, wheel_probe


@dataclass
class SpecRun:
    """A spec run on physics (module docstring); ``wheels`` and ``actuators`` name the columns of the
    per-wheel and per-actuator series, ``stopped`` says when and why a run that diverged stopped (None for a
    complete run)."""

    result: SimulationResult
    series: dict[str, np.ndarray]
    metrics: dict[str, Any]
    wheels: list[str]
    actuators: list[str]
    stopped: str | None


@contextlib.contextmanager
def quiet_warnings() -> Iterator[None]:
    """MuJoCo's warnings kept off the terminal and out of ``MUJOCO_LOG.TXT`` during the block: a run reads them
    from ``data.warning`` and says itself why it stopped."""
    mj = mujoco_module()
    previous = mj.get_mju_user_warning()
    mj.set_mju_user_warning(lambda message: None)
    try:
        yield
    finally:
        mj.set_mju_user_warning(previous)


@partial(jax.jit, static_argnums=(0, 1))
def _replay(
    robot: MobileManipulator, task: Task, law: Law, reference: Reference, q: jax.Array, t: jax.Array
) -> tuple[jax.Array, jax.Array, dict[str, jax.Array]]:
    """ξ*, ξ and the law's recorded entries at each measured (q, t) of a record (the law is a function of
    (q, t) only, so these are its values during the run)."""
    ctask = law.controlled_task(task)

    def one(qi: jax.Array, ti: jax.Array) -> tuple[jax.Array, jax.Array, dict[str, jax.Array]]:
        xs, xsd = reference._one(ti)
        return xs, ctask.value(robot, qi, robot.frames(qi)), law(robot, task, qi, ti, xs, xsd).recorded()

    return jax.vmap(one)(q, t)


def measured_result(spec: Spec, run: PhysicsRun) -> SimulationResult:
    """The record of a run on physics as a :class:`SimulationResult` (module docstring)."""
    robot, task = spec.robot, spec.task
    xi_star, xi, info = jax.tree.map(
        np.asarray, _replay(robot, task, spec.law, spec.reference, jnp.asarray(run.q), jnp.asarray(run.t))
    )
    ctask = spec.law.controlled_task(task)
    return SimulationResult(
        t=run.t,
        q=run.q,
        eta=run.eta,
        xi=xi,
        xi_star=xi_star,
        error=np.asarray(ctask.error(xi_star, xi)),
        measures=compute_measures(robot, run.q, task, spec.measures) if spec.measures else {},
        saturated=info.pop("saturated"),
        damped=info.pop("damped"),
        info=info,
        robot=robot,
        task=task,
    )


def simulate_on_physics(
    spec: Spec,
    settings: PhysicsSettings,
    model: MobileManipulator | DynamicModel,
    torque_limits: npt.ArrayLike | None = None,
) -> SpecRun:
    """Run ``spec`` on MuJoCo with ``settings`` (the robot's inertials from ``model``: a
    :class:`DynamicModel`, or the robot itself for stand-ins, :func:`mobman.physics.mjcf.dynamic_model`;
    ``torque_limits`` per actuator) and compare it with the spec's kinematic run."""
    if settings.feedforward and not isinstance(model, DynamicModel):
        raise InputError(
            f"physics.feedforward: needs the robot's inertials; {model.name} has none in mobman (a real robot, "
            f"a URDF file with inertials or yamamoto-dual-arm has them)"
        )
    dynamics = dynamic_model(model)
    if settings.payload > 0:
        dynamics = dynamics.with_payload(Payload(settings.payload))
    names: dict[str, list[str]] = {}

    def probe(compiled: Any) -> Any:
        names["wheels"] = wheel_names(compiled)
        names["actuators"] = [compiled.actuator(i).name for i in range(compiled.nu)]
        return wheel_probe(compiled)

    with quiet_warnings():
        run = run_on_physics(
            dynamics,
            spec.law,
            spec.reference,
            spec.q0,
            spec.duration,
            1.0 / settings.control_rate,
            task=spec.task,
            friction=settings.friction,
            timestep=settings.timestep,
            torque_limits=torque_limits,
            probe=probe,
            scene=getattr(spec.law, "scene", None),  # the obstacles the whole-body QP law avoids
            feedforward=settings.feedforward,
        )
    result = measured_result(spec, run)
    kinematic = spec.simulate()
    ctask = spec.law.controlled_task(spec.task)
    xi_kinematic = np.stack(
        [np.interp(run.t, kinematic.t, kinematic.xi[:, i]) for i in range(ctask.dim)], axis=-1
    )
    series = {
        "slip_lateral": run.slip,
        **run.series,
        "deviation": np.linalg.norm(
            np.asarray(ctask.error(jnp.asarray(xi_kinematic), jnp.asarray(result.xi))), axis=-1
        ),
    }
    platform = [np.interp(run.t[-1], kinematic.t, kinematic.q[:, i]) for i in (0, 1)]
    metrics = physics_metrics(settings, series, float(np.linalg.norm(run.q[-1, :2] - platform)))
    metrics["kinematic_final_error"] = float(np.linalg.norm(kinematic.error[-1]))
    metrics["stopped"] = run.stopped
    return SpecRun(result, series, metrics, names["wheels"], names["actuators"], run.stopped)


def _stat(values: np.ndarray, how: Any) -> float | None:
    return float(how(np.abs(values))) if np.size(values) else None


def physics_metrics(settings: PhysicsSettings, series: dict[str, np.ndarray], platform_end: float) -> dict:
    """The physics metrics of a run's ``series`` (JSON-friendly; None where a series is empty, as the lateral
    slip of an omnidirectional platform):

    ``slip_lateral_median`` / ``_max`` (m/s, |G(q_p) q̇_p| over the constraint rows and the instants),
    ``slip_longitudinal_median`` / ``_max`` (m/s, over the wheels), ``contact_normal_min`` / ``_max`` (N, a
    wheel's force from the floor after the first instant: 0 when it leaves it), ``friction_used_max`` (the largest ratio of a wheel's
    friction to its normal force: near ``friction`` the wheel slides), ``torque_max`` (N·m, the largest
    |τ| of any servo), ``torque_saturated_steps`` (the instants where a servo is at its torque limit),
    ``kinematic_deviation_max`` / ``_final`` (‖e(ξ_kin, ξ)‖ in the task's units) and
    ``kinematic_platform_distance`` (m, the platforms' (x, y) apart at the end)."""
    # from the second instant on: the robot is placed on the floor at rest, its contacts not yet loaded
    normal, tangential = series["contact_normal"][1:], series["contact_tangential"][1:]
    touching = normal > 1e-9
    return {
        "physics_engine": settings.engine,
        "physics_timestep": settings.timestep,
        "control_rate": settings.control_rate,
        "friction": settings.friction,
        "payload": settings.payload,
        "feedforward": settings.feedforward,
        "slip_lateral_median": _stat(series["slip_lateral"], np.median),
        "slip_lateral_max": _stat(series["slip_lateral"], np.max),
        "slip_longitudinal_median": _stat(series["slip_longitudinal"], np.median),
        "slip_longitudinal_max": _stat(series["slip_longitudinal"], np.max),
        "contact_normal_min": _stat(normal, np.min),
        "contact_normal_max": _stat(normal, np.max),
        "friction_used_max": float(np.max(tangential[touching] / normal[touching]))
        if np.any(touching)
        else None,
        "torque_max": _stat(series["torque"], np.max),
        "torque_saturated_steps": int(np.count_nonzero(np.any(series["at_limit"], axis=-1))),
        "kinematic_deviation_max": float(np.max(series["deviation"])),
        "kinematic_deviation_final": float(series["deviation"][-1]),
        "kinematic_platform_distance": platform_end,
    }


def with_engine(settings: PhysicsSettings | None, engine: str, dt: float) -> PhysicsSettings:
    """``settings`` (the defaults of a ``[physics]`` table for a spec ``dt`` when None) on ``engine``."""
    from mobman.control.spec import physics_settings

    return dataclasses.replace(settings or physics_settings({}, dt), engine=engine)


__all__ = [
    "SpecRun",
    "measured_result",
    "physics_metrics",
    "quiet_warnings",
    "simulate_on_physics",
    "with_engine",
]
