"""``mobman plan``: endogenous-configuration motion planning (Tchoń et al. 2002) for a built-in robot.

The unknowns are the platform controls over [0, T] (a truncated Fourier series with ``--harmonics``
harmonics per control) and the arm joint positions x; the platform starts at ``--start`` = q_p(0), all its
coordinates (e.g. ``5,0,0,pi/6`` for the car: x, y, θ, φ), default the origin. Initial guess: the constant
term of control i is 0.01·(−1)^i (the paper's λ01 = 0.01, λ02 = −0.01), other coefficients 0, x = ``--x``
(default 0 clipped to the joint limits). A start configuration (``--start``, ``--x``) outside the robot's joint
limits gives a warning line (``outside_limits`` in ``--json``); ``--strict-limits`` makes it an error (exit 2,
nothing written).

With ``--scene FILE`` the planned motion is checked against the scene's obstacles and floor and against the
robot itself (:mod:`mobman.planning.clearance`, the collision spheres of ``mobman distance`` at
``--cover-tolerance``): its smallest distance, the closest pair, and the first collision (time, pair, depth).
``--avoid`` also plans around them: the pseudo-inverse algorithm's null-space term (Tchoń et al. eq. 16) is the
gradient that pushes every pair of the path farther than ``--influence-distance``, scaled by ``--avoid-gain``
(:func:`mobman.planning.clearance.avoidance`); it moves the path without moving its end.

A plan reaches its goal (``reached`` in ``--json``) when the algorithm converged (‖K − y_d‖ ≤ ``--tol``), its
arm joint positions x lie within the robot's joint limits (a plan that ends outside them cannot be executed),
and, with ``--scene``, its motion is free of collision.
Otherwise the command ends with one line saying what was not reached and by how much, and exit status 3 (the
report printed, the figures written).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import jax
import jax.numpy as jnp
import numpy as np
import typer
from rich.console import Console
from rich.table import Table

from mobman.cli.app import app
from mobman.cli.common import UrdfOption, array_text, load_robot, not_reached, urdf_options
from mobman.cli.limits import STRICT_HELP, outside_limits
from mobman.errors import InputError
from mobman.io import dump_json, trajectories
from mobman.io.numbers import parse_vector
from mobman.io.output import check_folder, results_folder
from mobman.model.collision_model import DEFAULT_TOLERANCE
from mobman.model.robot import MobileManipulator
from mobman.model.tasks import FunctionTask
from mobman.planning.algorithms import ALGORITHMS, Options, PlanResult, plan
from mobman.planning.basis import Fourier
from mobman.planning.clearance import (
    GAIN,
    INFLUENCE,
    PairAt,
    PathClearance,
    avoidance,
    path_clearance,
)
from mobman.planning.endpoint import MAX_HORIZON, PlanningSetting, configuration_path, dexterity

MAX_HARMONICS = 100
"""Largest accepted --harmonics (2·100 + 1 coefficients per control)."""

MAX_ITERATIONS = 100_000
"""Largest accepted --max-iterations."""

DEFAULT_EXTENSIONS = {"tchon-car-rtr": "x3, theta + x1"}
"""The paper's ȳ = (x3, q3 + x1) for the car + RTR arm (q = (x, y, θ, φ, x1, x2, x3))."""


@dataclass(frozen=True)
class CoordinateSums:
    """h(q) = (Σ_{i ∈ group} q_i for each group): an output extension chosen by coordinates, not by code."""

    groups: tuple[tuple[int, ...], ...]

    def __call__(self, q: jax.Array) -> jax.Array:
        return jnp.stack([sum((q[i] for i in group[1:]), q[group[0]]) for group in self.groups])


def _coordinate(term: str, robot: MobileManipulator) -> int:
    names = robot.coordinate_names
    index_text = term[2:-1] if term.startswith("q[") and term.endswith("]") else term
    if index_text.isdigit():
        index = int(index_text)
        if index >= robot.n_q:
            raise InputError(
                f"--extension: index {index} is out of range; {robot.name} has coordinates 0..{robot.n_q - 1} "
                f"({', '.join(names)})"
            )
        return index
    if term in names:
        return names.index(term)
    raise InputError(
        f"--extension: {term!r} is not a coordinate of {robot.name}; give names ({', '.join(names)}) or "
        f"0-based indices 0..{robot.n_q - 1}, joined by + for a sum"
    )


def extension_task(text: str, robot: MobileManipulator) -> FunctionTask:
    """An output extension h(q) from a comma-separated list of coordinates of ``robot`` or sums of them:
    each item is a coordinate name or 0-based index (``q[i]`` also accepted), ``a + b`` adds coordinates,
    e.g. ``"x3, theta + x1"`` = ``"6, 2 + 4"`` = ``"q[6], q[2] + q[4]"`` for ``tchon-car-rtr``."""
    items = [item.strip() for item in text.split(",")]
    if not any(items):
        raise InputError("--extension: give one or more coordinates of q, e.g. 'x3, theta + x1'")
    groups = []
    for item in items:
        terms = [term.strip() for term in item.split("+")]
        if not all(terms):
            raise InputError(f"--extension: {item!r} has an empty item; expected coordinates joined by +")
        groups.append(tuple(_coordinate(term, robot) for term in terms))
    return FunctionTask(CoordinateSums(tuple(groups)), tuple(items))


def initial_configuration(setting: PlanningSetting, x0: np.ndarray) -> np.ndarray:
    lam = np.zeros((setting.n_controls, setting.basis.size))
    lam[:, 0] = 0.01 * (-1.0) ** np.arange(setting.n_controls)
    return np.concatenate([lam.reshape(-1), x0])


def _joints(robot: MobileManipulator, text: str | None) -> np.ndarray:
    p = robot.n_q - robot.platform.n_q
    if text is not None:
        return parse_vector(text, "--x", p)
    lower, upper = np.array(robot.position_limits[robot.platform.n_q :]).reshape(p, 2).T
    return np.clip(np.zeros(p), lower, upper)


def _step(text: str) -> float | str:
    if text == "adaptive":
        return text
    try:
        value = float(text)
    except ValueError:
        raise InputError(f"--step: expected a number > 0 or 'adaptive', got {text!r}") from None
    if not (math.isfinite(value) and value > 0):
        raise InputError(f"--step: expected a number > 0 or 'adaptive', got {text!r}")
    return value


@app.command("plan")
def plan_command(
    robot_name: str = typer.Argument(
        ..., metavar="ROBOT", help="A built-in robot (see `mobman robots`), a .toml or a .urdf file."
    ),
    target: str = typer.Option(..., "--target", help="Desired task value y_d at time T, e.g. 0,0,1."),
    algorithm: str = typer.Option("pinv", "--algorithm", help=f"one of {', '.join(ALGORITHMS)}"),
    horizon: float = typer.Option(1.0, "--horizon", help=f"Control horizon T in (0, {MAX_HORIZON:g}] s."),
    harmonics: int = typer.Option(2, "--harmonics", help="Fourier harmonics per control (≥ 0)."),
    start: str | None = typer.Option(None, "--start", help="Platform start pose q_p(0), e.g. 5,0,0,pi/6."),
    joints: str | None = typer.Option(None, "--x", help="Initial arm joint positions x0."),
    step: str = typer.Option("1", "--step", help="Continuation step Δθ (1 = Newton) or 'adaptive'."),
    gamma: float = typer.Option(1.0, "--gamma", help="Rate γ > 0."),
    tol: float = typer.Option(1e-12, "--tol", help="Stop when ‖K − y_d‖ ≤ tol."),
    max_iterations: int = typer.Option(200, "--max-iterations", help="Iteration cap."),
    extension: str | None = typer.Option(
        None,
        "--extension",
        help="Output extension for 'extended': coordinates (names or 0-based indices) or sums, e.g. 'x3, theta+x1'.",
    ),
    params: list[str] | None = typer.Option(None, "--param", help="Robot parameter NAME=VALUE."),
    tip: list[str] | None = UrdfOption.tip,
    base: str | None = UrdfOption.base,
    platform: str | None = UrdfOption.platform,
    wheels: str | None = UrdfOption.wheels,
    lock: list[str] | None = UrdfOption.lock,
    platform_option: list[str] | None = UrdfOption.platform_option,
    json_output: bool = typer.Option(False, "--json", help="Print one JSON object."),
    out: Path | None = typer.Option(None, "--out", help="Folder for the path and convergence figures."),
    strict_limits: bool = typer.Option(False, "--strict-limits", help=STRICT_HELP),
    scene_path: Path | None = typer.Option(
        None,
        "--scene",
        help="Scene file (TOML, [[obstacle]] tables, optional floor): check the planned motion against it and "
        "the robot itself.",
    ),
    cover_tolerance: float = typer.Option(
        DEFAULT_TOLERANCE,
        "--cover-tolerance",
        help="Cover tolerance of the collision spheres (m, > 0): how far they may reach beyond the robot.",
    ),
    avoid: bool = typer.Option(
        False, "--avoid", help="Plan around the --scene's obstacles (null-space term of --algorithm pinv)."
    ),
    influence_distance: float = typer.Option(
        INFLUENCE, "--influence-distance", help="--avoid: pairs closer than this are pushed apart (m, > 0)."
    ),
    avoid_gain: float = typer.Option(
        GAIN, "--avoid-gain", help="--avoid: the gain of the null-space term (1/m², > 0)."
    ),
) -> None:
    """Plan platform controls and arm joint positions that bring the task to --target at time T."""
    if algorithm not in ALGORITHMS:
        raise InputError(f"--algorithm must be one of {', '.join(ALGORITHMS)}, got {algorithm!r}")
    if not 0 < horizon <= MAX_HORIZON:
        raise InputError(f"--horizon must be a number in (0, {MAX_HORIZON:g}] s, got {horizon}")
    if not 0 <= harmonics <= MAX_HARMONICS:
        raise InputError(f"--harmonics must be in 0..{MAX_HARMONICS}, got {harmonics}")
    if not 1 <= max_iterations <= MAX_ITERATIONS:
        raise InputError(f"--max-iterations must be in 1..{MAX_ITERATIONS}, got {max_iterations}")
    if avoid and scene_path is None:
        raise InputError("--avoid: needs --scene FILE (the obstacles to plan around)")
    if avoid and algorithm != "pinv":
        raise InputError(f"--avoid: works through the null space of --algorithm pinv, got {algorithm!r}")
    for name, value in (("--influence-distance", influence_distance), ("--avoid-gain", avoid_gain)):
        if not (math.isfinite(value) and value > 0):
            raise InputError(f"{name} must be a finite number > 0, got {value!r}")
    urdf = urdf_options(tip, base, platform, wheels, lock, platform_option)
    robot = load_robot(robot_name, params, urdf)
    model, world = None, None
    if scene_path is not None:
        from mobman.cli.distance import collision_tolerance, robot_collision_model
        from mobman.io import scene as scene_file

        world = scene_file.load(scene_path)
        model = robot_collision_model(
            robot_name, robot, urdf, collision_tolerance(cover_tolerance, "--cover-tolerance")
        )
    if out is not None:
        check_folder(out, "plan")
    setting = PlanningSetting(robot, Fourier(harmonics), horizon=horizon)
    y_d = parse_vector(target, "--target", setting.output.dim)
    q0 = (
        parse_vector(start, "--start", robot.platform.n_q)
        if start is not None
        else np.zeros(robot.platform.n_q)
    )
    x0 = _joints(robot, joints)
    z0 = initial_configuration(setting, x0)
    start_outside = outside_limits(
        robot,
        np.concatenate([q0, x0])[None],
        "start (--start, --x)",
        strict_limits,
        note="planned from there",
    )[0]
    ext = None
    if algorithm == "extended":
        text = extension if extension is not None else DEFAULT_EXTENSIONS.get(robot_name)
        if text is None:
            raise InputError(
                "--algorithm extended needs --extension (coordinates of q, e.g. '2, 3+4') for this robot"
            )
        ext = extension_task(text, robot)
    nullspace = None
    if avoid and model is not None and world is not None:
        nullspace = avoidance(setting, model, world, influence_distance, avoid_gain)
    options = Options(
        algorithm,
        _step(step),
        gamma=gamma,
        tol=tol,
        max_iterations=max_iterations,
        extension=ext,
        nullspace=nullspace,
    )
    result = plan(setting, z0, q0, y_d, options)
    end = np.concatenate([q0, result.x])
    beyond = _limit_excess(robot, end, slice(robot.platform.n_q, None))
    coarse = setting.jacobian_setting
    d0, d1 = dexterity(coarse, z0, q0), dexterity(coarse, result.z, q0)
    report: dict[str, Any] = {
        "robot": robot_name,
        "algorithm": algorithm,
        "step": options.step,
        "horizon": horizon,
        "harmonics": harmonics,
        "start": q0,
        "target": y_d,
        "status": result.status,
        "converged": result.converged,
        "iterations": result.iterations,
        "final_error": result.final_error,
        "dexterity_start": d0,
        "dexterity_end": d1,
        "lambda": result.lam,
        "x": result.x,
        "outside_limits": {"start": start_outside, "end": list(beyond)},
        "reached": bool(result.converged and not beyond),
        "error_history": result.errors,
    }
    if avoid:
        report["avoidance"] = {"influence_distance": influence_distance, "gain": avoid_gain}
    clearance = None
    if model is not None and world is not None:
        clearance = path_clearance(model, world, *configuration_path(setting, result.z, q0))
        report.update(_clearance_report(clearance))
        report["reached"] = report["reached"] and clearance.first_collision is None
    if out is not None:
        from mobman.planning.figures import plot_convergence, plot_paths  # matplotlib: only with --out

        with results_folder(out, "plan") as staging:
            t, q = configuration_path(setting, result.z, q0)
            trajectories.write(
                staging, [trajectories.Motion.of(f"{algorithm}, {result.status}", robot, t, q)]
            )
            title = f"{robot_name}: {algorithm}, {result.status}"
            plot_paths(setting, result.z, q0, y_d, title, staging / "paths.png")
            plot_convergence(
                {algorithm: result.errors}, tol, f"{robot_name}: convergence", staging / "convergence.png"
            )
        report["figures"] = [str(out / "paths.png"), str(out / "convergence.png")]
    if json_output:
        typer.echo(dump_json(report))
    else:
        _print(report, result, options, robot_name, algorithm)
    if not report["reached"]:
        missed = [] if result.converged else [f"{result.status} after {result.iterations} iterations"]
        if beyond:
            missed.append(f"the plan ends outside the joint limits: {_outside(robot, end, beyond)}")
        hit = None if clearance is None else clearance.first_collision
        if hit is not None:
            missed.append(
                f"the motion collides at t = {hit.time:.4g} s: {hit.pair[0]} against {hit.pair[1]}, "
                f"{-hit.distance:.3g} m deep"
            )
        not_reached("plan", f"not reached: {'; '.join(missed)} (final error {result.final_error:.3e})")


def _clearance_report(clearance: PathClearance) -> dict[str, Any]:
    """The JSON fields of a path's clearance: ``min_distance`` (m), ``closest`` (pair, time, distance, witness
    points) and ``first_collision`` (time, pair, depth; None when free)."""

    def pair(p: PairAt) -> dict[str, Any]:
        return {"robot": p.pair[0], "other": p.pair[1], "time": p.time}

    closest, hit = clearance.closest, clearance.first_collision
    return {
        "min_distance": clearance.min_distance,
        "closest": None
        if closest is None
        else {
            **pair(closest),
            "distance": closest.distance,
            "robot_point": closest.robot_point,
            "other_point": closest.other_point,
        },
        "first_collision": None if hit is None else {**pair(hit), "depth": -hit.distance},
    }


def _limit_excess(robot: MobileManipulator, q: np.ndarray, coordinates: slice) -> dict[str, float]:
    """The ``coordinates`` of one configuration q (n_q) outside the robot's joint limits, by name: how far
    (m or rad), positive above the upper limit, negative below the lower one (a non-finite value is not
    counted: it is no plan at all)."""
    lower, upper = np.asarray(robot.position_limits, dtype=float)[coordinates].T
    values = np.asarray(q, dtype=float)[coordinates]
    excess = np.where(values > upper, values - upper, np.where(values < lower, values - lower, 0.0))
    names = robot.coordinate_names[coordinates]
    return {name: float(e) for name, e in zip(names, excess) if e != 0.0}


def _outside(robot: MobileManipulator, q: np.ndarray, beyond: dict[str, float]) -> str:
    """The coordinates of :func:`_limit_excess` in words: value, excess and limits, in m or rad."""
    names = list(robot.coordinate_names)
    kinds = ["platform"] * robot.n_platform + [j.kind for arm in robot.arms for j in arm.joints]
    items = []
    for name, excess in beyond.items():
        i = names.index(name)
        unit = "m" if kinds[i] == "prismatic" else "rad"
        lower, upper = robot.position_limits[i]
        side = "above" if excess > 0 else "below"
        items.append(
            f"{name} = {q[i]:.4g} {unit}, {abs(excess):.3g} {unit} {side} its limits [{lower:.4g}, {upper:.4g}]"
        )
    return ", ".join(items)


def _print(report: dict, result: PlanResult, options: Options, robot_name: str, algorithm: str) -> None:
    table = Table(title=f"mobman plan {robot_name} ({algorithm}, Δθ = {options.step})")
    table.add_column("quantity")
    table.add_column("value", overflow="fold")
    for key in ("status", "reached", "iterations", "final_error", "dexterity_start", "dexterity_end"):
        value = report[key]
        table.add_row(key, f"{value:.3e}" if isinstance(value, float) else str(value))
    if "min_distance" in report:
        closest, hit = report["closest"], report["first_collision"]
        if closest is None:
            table.add_row("min_distance", "no pair (an empty scene and no self-collision pair)")
        else:
            table.add_row("min_distance", f"{closest['distance']:.4g} m")
            table.add_row(
                "closest", f"{closest['robot']} – {closest['other']} at t = {closest['time']:.4g} s"
            )
        if hit is not None:
            at = f"t = {hit['time']:.4g} s: {hit['robot']} – {hit['other']}, {hit['depth']:.3g} m deep"
            table.add_row("first_collision", at)
        else:
            table.add_row("first_collision", "none")
    table.add_row("lambda", array_text(result.lam))
    table.add_row("x", array_text(result.x))
    for f in report.get("figures", []):
        table.add_row("figure", f)
    Console().print(table)
