"""``mobman place``: where to park the platform for a target of the task (:mod:`mobman.studies.placement`).

Tries every platform pose of a polar grid around the target (``--radii`` × ``--bearings`` × ``--headings``;
``--target`` repeated: targets reached from the same base, each with a posture of its own),
solves the arm's inverse kinematics from ``--starts`` postures within the joint limits for each, and ranks the
bases that reach the target by a manipulability measure of the posture (``--measure``, ``--level``).
``--keep-out`` regions of the floor (repeatable) leave out the bases from which the platform, covered by the
disc of ``--footprint`` (by default the one covering the platform's drawn shapes), would overlap one of them
(:mod:`mobman.studies.floor`). A posture counts only when the robot there is free of collision with itself and
with the obstacles and floor of ``--scene`` (``--no-collision``: not checked; :mod:`mobman.studies.clearance`),
whose boxes on the floor are keep-out regions too; bases reached only with colliding postures are counted apart.
A progress bar on standard error follows the inverse kinematics (``--quiet``: none).
Exit status 3 when no base reaches it (the candidates are still printed), with
one line saying why: a target beyond the robot's reach (its height above or below what any posture reaches,
or every base farther than the arm reaches; :func:`mobman.studies.placement.out_of_reach`), or else the
closest error and what to try.
"""

from __future__ import annotations

from dataclasses import asdict
from pathlib import Path
from typing import Any

import numpy as np
import typer
from rich.console import Console
from rich.table import Table

from mobman.cli.app import app
from mobman.cli.common import (
    FloorOption,
    StudyOption,
    UrdfOption,
    array_text,
    floor_arguments,
    load_map,
    load_robot,
    not_reached,
    progress_bar,
    urdf_options,
)
from mobman.cli.distance import ClearanceOption, clearance_arguments
from mobman.errors import InputError
from mobman.io import dump_json
from mobman.io.numbers import parse_vector
from mobman.manipulability import MEASURES
from mobman.model.robot import MobileManipulator
from mobman.model.tasks import Position
from mobman.studies.maps import ReachabilityMap
from mobman.studies.placement import LEVELS, Placement, out_of_reach, place, place_with_map


def _entry(result: Placement, k: int) -> dict[str, Any]:
    return {
        "base": result.bases[k],
        "q": result.q[k],
        "error": float(result.error[k]),
        "score": float(result.score[k]),
    }


OPTIONS = ("radii", "bearings", "headings", "starts", "iterations", "tolerance", "measure", "level", "target")
"""The keyword arguments of :func:`mobman.studies.placement.place` that are options of the command."""


def _as_option(message: str) -> str:
    """``place``'s message about a keyword argument (``"bearings must be …"``) as one about its option
    (``"--bearings must be …"``)."""
    keyword = message.split(" ", 1)[0]
    if keyword == "reachability:":
        return "--map:" + message[len(keyword) :]
    return f"--{message}" if keyword in OPTIONS else message


@app.command("place")
def place_command(
    robot_name: str = typer.Argument(
        ..., metavar="ROBOT", help="A built-in robot (see `mobman robots`), a .toml or a .urdf file."
    ),
    target: list[str] = typer.Option(
        ...,
        "--target",
        help="The task's target ξ*, e.g. 1,0.5,0.8 for x, y, z; repeated, targets reached from the same base.",
    ),
    centre: str | None = typer.Option(
        None, "--centre", help="x,y the grid is centred on (default: the target's x, y)."
    ),
    radii: str | None = typer.Option(
        None,
        "--radii",
        help="Distances of the bases from the centre, e.g. 0.4,0.6,0.8 (default: 8 up to the reach).",
    ),
    bearings: int | None = typer.Option(None, "--bearings", help="Directions around the centre (≥ 1; 16)."),
    headings: int = typer.Option(16, "--headings", help="Platform headings over [−π, π) (≥ 1)."),
    starts: int | None = typer.Option(
        None, "--starts", help="Starting postures of the arm per base (≥ 1; 4)."
    ),
    iterations: int | None = typer.Option(
        None,
        "--iterations",
        help="Damped least-squares steps per start (≥ 1; 60, or 20 from a --map's postures).",
    ),
    tolerance: float = typer.Option(
        1e-6, "--tolerance", help="Largest task error of a reached target (> 0)."
    ),
    measure: str | None = typer.Option(
        None, "--measure", help=f"one of {', '.join(MEASURES)} (default yoshikawa)"
    ),
    level: str | None = typer.Option(
        None, "--level", help=f"one of {', '.join(LEVELS)}: J_a (platform parked, the default) or J̄ = J S."
    ),
    reachability: Path | None = typer.Option(
        None,
        "--map",
        help="A reachability map's store (mobman map --store) whose cells give the candidate bases for a point "
        "target x,y,z (inverse reachability), scored by its measure.",
    ),
    keep_out: list[str] | None = FloorOption.keep_out,
    footprint: str | None = FloorOption.footprint,
    scene: Path | None = ClearanceOption.scene,
    collision: bool = ClearanceOption.collision,
    cover: float = ClearanceOption.cover,
    top: int = typer.Option(5, "--top", help="Bases listed, best first (≥ 1)."),
    params: list[str] | None = typer.Option(None, "--param", help="Robot parameter NAME=VALUE."),
    tip: list[str] | None = UrdfOption.tip,
    base: str | None = UrdfOption.base,
    platform: str | None = UrdfOption.platform,
    wheels: str | None = UrdfOption.wheels,
    lock: list[str] | None = UrdfOption.lock,
    platform_option: list[str] | None = UrdfOption.platform_option,
    quiet: bool = StudyOption.quiet,
    json_output: bool = typer.Option(False, "--json", help="Print one JSON object."),
) -> None:
    """Find platform poses from which the arm reaches --target, ranked by manipulability."""
    if top < 1:
        raise InputError(f"--top must be ≥ 1, got {top}")
    urdf = urdf_options(tip, base, platform, wheels, lock, platform_option)
    robot = load_robot(robot_name, params, urdf)
    grid = {
        "centre": None if centre is None else parse_vector(centre, "--centre", 2),
        "radii": None if radii is None else parse_vector(radii, "--radii"),
        "bearings": bearings,
        "starts": starts,
        "measure": measure,
        "level": level,
    }
    given: dict[str, Any] = {name: value for name, value in grid.items() if value is not None}
    solver: dict[str, Any] = {"headings": headings, "tolerance": tolerance}
    solver["keep_out"], solver["footprint"] = floor_arguments(robot, keep_out, footprint)
    solver.update(clearance_arguments(robot_name, robot, urdf, scene, collision, cover))
    if iterations is not None:
        solver["iterations"] = iterations
    with progress_bar("placing", not (quiet or json_output)) as bar:
        solver["progress"] = None if bar is None else lambda done, total: bar(done / total)
        try:
            if reachability is None:
                task = robot.task
                targets = [parse_vector(value, "--target", task.dim) for value in target]
                result = place(
                    robot, targets[0] if len(targets) == 1 else np.stack(targets), **given, **solver
                )
            else:
                if given:
                    raise InputError(
                        f"--map: {', '.join('--' + name for name in given)} do not apply with a map (its cells are "
                        "the candidates, its measure and level score them)"
                    )
                if len(target) > 1:
                    raise InputError("--map: one --target (a map's cells are placed for a point target)")
                reached = load_map(reachability, robot)
                task = Position("xyz", arm=reached.arm)
                result = place_with_map(robot, reached, parse_vector(target[0], "--target", 3), **solver)
        except InputError as exc:
            raise InputError(_as_option(str(exc))) from None
    ranking = [_entry(result, int(k)) for k in result.ranking(top)]
    report = {
        "robot": robot_name,
        "coordinates": list(robot.coordinate_names),
        "task": list(task.names),
        "target": result.target,
        "measure": result.measure,
        "level": result.level,
        "tolerance": tolerance,
        "candidates": int(result.bases.shape[0]),
        "reached": int(result.reached.sum()),
        "blocked": int(np.sum(result.blocked)),
        "colliding": int(np.sum(result.colliding)),
        "collision": None if "collision" not in solver else _clearance(solver),
        "footprint": None if result.footprint is None else asdict(result.footprint),
        "best": ranking[0] if ranking else None,
        "ranking": ranking,
    }
    if json_output:
        typer.echo(dump_json(report))
    else:
        _print(report, robot_name, robot.n_platform)
    if not ranking and not report["candidates"]:
        not_reached("place", _no_cell_at_height(robot, reached, float(result.target[2])))
    if not ranking and np.all(result.blocked):
        not_reached("place", f"every base of the {report['candidates']} is blocked by --keep-out")
    if not ranking and report["colliding"]:
        not_reached(
            "place",
            f"no base of the {report['candidates']} reaches the target with a posture free of collision "
            f"({report['colliding']} reach it only with colliding postures"
            + (f", {report['blocked']} blocked by --keep-out or the scene" if report["blocked"] else "")
            + ")",
        )
    if not ranking:
        closest = float(np.min(result.error[~result.blocked]))
        why = out_of_reach(robot, result, task)
        advice = (
            "a map over more of the space" if reachability is not None else "other --radii or more --starts"
        )
        not_reached(
            "place",
            f"no base of the {report['candidates']} reaches the target (closest error {closest:.3e}"
            + (f", {report['blocked']} blocked by --keep-out" if report["blocked"] else "")
            + (f"): {why}" if why is not None else f"); try {advice}"),
        )


def _no_cell_at_height(robot: MobileManipulator, reached: ReachabilityMap, height: float) -> str:
    """Why a map has no candidate for a target: the heights its reached cells span and, where the target's
    height is beyond them, the highest (lowest) point the tool reaches
    (:func:`mobman.studies.placement.closest_height`)."""
    from mobman.studies.placement import closest_height

    z = reached.centres()[reached.reached][:, 2]
    message = f"no reached cell of the map lies within half a step of the target's height {height:.4g} m"
    if not z.size:
        return message + " (the map reaches no cell)"
    message += f" (its reached cells lie at {z.min():.4g}–{z.max():.4g} m"
    nearest = closest_height(robot, height, Position("xyz", arm=reached.arm))
    if nearest is not None and abs(height - nearest) > reached.step / 2:
        side = "above the highest" if height > nearest else "below the lowest"
        message += f"; {abs(height - nearest):.3g} m {side} point the tool reaches, {nearest:.4g} m"
    return message + ")"


def _clearance(solver: dict) -> dict:
    """The report's account of the collision checks: the cover and the scene's obstacles."""
    model, scene = solver["collision"], solver["scene"]
    return {
        "tolerance": model.tolerance,
        "spheres": len(model.spheres),
        "obstacles": [] if scene is None else [o.name for o in scene.obstacles],
    }


def _print(report: dict, robot_name: str, n_platform: int) -> None:
    blocked = f", {report['blocked']} blocked by --keep-out" if report["footprint"] is not None else ""
    if report["collision"] is not None:
        blocked += f", {report['colliding']} only in collision"
    table = Table(
        title=f"mobman place {robot_name}: {report['reached']} of {report['candidates']} bases reach "
        f"{array_text(report['target'])} ({report['level']} {report['measure']}"
        f"{blocked})"
    )
    for column in ("rank", "x", "y", "θ", report["measure"], "error", "q (arm)"):
        table.add_column(column, overflow="fold")
    for k, entry in enumerate(report["ranking"], start=1):
        x, y, theta = entry["base"]
        table.add_row(
            str(k),
            f"{x:.3f}",
            f"{y:.3f}",
            f"{theta:.3f}",
            f"{entry['score']:.4g}",
            f"{entry['error']:.1e}",
            # one posture per target, a line each
            "\n".join(array_text(q[n_platform:], 3) for q in np.atleast_2d(entry["q"])),
        )
    Console().print(table)
