"""``mobman simulate SPEC --physics mujoco`` (or a spec's ``[physics] engine``): the spec's law closed on
MuJoCo (:func:`mobman.physics.run.simulate_on_physics`; docs/physics.md).

The results folder holds what a kinematic run's holds (``results.json`` with the same series, at the control
instants, so ``mobman view --results`` replays the measured motion; the figures; ``trajectories.json``) and
the physics: ``results.json``'s ``physics`` (the wheels and actuators by name) and
``series.physics`` (slips, contact forces, torques, the deviation from the kinematic run), the physics metrics
among the metrics, and ``physics.png``. A run that diverges stops where it diverged: its series up to there
are written (atomically, as every results folder), and it ends with one line saying when and why, exit
status 3.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from mobman.cli.common import load_dynamics, not_reached
from mobman.errors import InputError, ModelError
from mobman.io import robot_file
from mobman.io import spec as fields
from mobman.io.output import save_figure
from mobman.io.real_robots import REAL_ROBOTS
from mobman.io.urdf import is_urdf_path
from mobman.model.robots import command_name

if TYPE_CHECKING:
    from mobman.control.spec import Spec
    from mobman.dynamics import DynamicModel
    from mobman.model.robot import MobileManipulator
    from mobman.physics.run import SpecRun

DYNAMIC = "the robot's dynamic model"
STAND_INS = "stand-in inertials (mobman has no dynamic model of this robot; docs/physics.md)"
"""How the inertials of a robot without a dynamic model are described."""


def physics_model(
    source: str, robot: MobileManipulator, option: str, urdf: dict | None = None
) -> tuple[MobileManipulator | DynamicModel, np.ndarray | None, str]:
    """The model to build on MuJoCo for the robot ``source`` (as the command line names it; ``robot`` as read):
    its dynamic model and torque limits where mobman has them (:func:`mobman.cli.common.load_dynamics`), else
    the robot itself (stand-in inertials) and no limits; and which of the two, in words. A URDF file or a
    real robot without inertials is refused (ModelError naming ``option``)."""
    try:
        model, limits = load_dynamics(source, robot, option, urdf)
        return model, limits, DYNAMIC
    except ModelError:
        if is_urdf_path(source) or command_name(source) in REAL_ROBOTS:
            raise
        return robot, None, STAND_INS


def spec_model(path: Path, robot: MobileManipulator) -> tuple[MobileManipulator | DynamicModel, Any, str]:
    """:func:`physics_model` of a spec file's ``[robot]`` table: a URDF file's (or a real robot's) inertials
    and effort limits, a built-in robot by name."""
    from mobman.dynamics import DynamicModel

    data = fields.read_toml(path)
    urdf = robot_file.urdf_table(data, path.parent)
    if urdf is None:
        return physics_model(str(data["robot"].get("name", "")), robot, "[physics]")
    try:
        dynamics = DynamicModel.from_urdf(urdf)
    except ModelError as exc:
        raise ModelError(f"[physics]: {exc}") from None
    mounted = replace(dynamics, robot=replace(dynamics.robot, mounts=robot.mounts))
    return mounted, urdf.torque_limits(), DYNAMIC


def prepare(
    option: str | None, parsed: Spec, source: str, spec_file: bool, urdf: dict | None
) -> tuple[str, tuple[MobileManipulator | DynamicModel, Any, str]] | None:
    """The engine of the run (``--physics``, checked, else the spec's ``[physics] engine``) and the robot's
    model for it (:func:`spec_model` of a spec file, else :func:`physics_model` of ROBOT); None for a
    kinematic run. The engine's install line, if it is missing, comes here, before any work."""
    from mobman.control.spec import ENGINES
    from mobman.physics.mjcf import mujoco_module

    if option is not None and option not in ENGINES:
        raise InputError(f"--physics: {option!r} not one of {', '.join(ENGINES)}")
    engine = option or (parsed.physics.engine if parsed.physics is not None else None)
    if engine is None:
        return None
    mujoco_module()
    if spec_file:
        return engine, spec_model(Path(source), parsed.robot)
    return engine, physics_model(source, parsed.robot, "--physics", urdf)


def run_physics(
    parsed: Spec, engine: str, model: tuple[MobileManipulator | DynamicModel, Any, str]
) -> tuple[dict, SpecRun]:
    """Run ``parsed`` on ``engine`` with its ``[physics]`` settings (the defaults without), the robot's
    ``model`` (:func:`physics_model`); the metrics (the kinematic run's and the physics ones) and the run.
    A run that diverged before its second instant, with no series to show, is ended here (exit 3)."""
    from mobman.control import metrics
    from mobman.physics.run import simulate_on_physics, with_engine

    robot_model, limits, inertials = model
    run = simulate_on_physics(parsed, with_engine(parsed.physics, engine, parsed.dt), robot_model, limits)
    if len(run.result.t) < 2:
        not_reached("simulate", f"the physics run stopped at {run.stopped}")
    summary = metrics.summarize(run.result, parsed.robot)
    summary["q_final"] = run.result.q[-1].tolist()
    summary["inertials"] = inertials
    return summary | run.metrics, run


def physics_figure(path: Path, run: SpecRun) -> None:
    """``physics.png``: the physics series of a run against time."""
    from mobman.viz import plot_timeseries

    series = run.series
    lateral = series["slip_lateral"]
    panels: dict[str, dict[str, Any]] = {
        "lateral slip G q̇ (m/s)": {f"row {i}": lateral[:, i] for i in range(lateral.shape[1])},
        "longitudinal slip (m/s)": {w: series["slip_longitudinal"][:, i] for i, w in enumerate(run.wheels)},
        "normal force (N)": {w: series["contact_normal"][:, i] for i, w in enumerate(run.wheels)},
        "torque (N·m, N)": {a: series["torque"][:, i] for i, a in enumerate(run.actuators)},
        "‖ξ − ξ_kinematic‖": {"deviation": series["deviation"]},
    }
    save_figure(plot_timeseries(run.result.t, {k: v for k, v in panels.items() if v}), path, dpi=120)
