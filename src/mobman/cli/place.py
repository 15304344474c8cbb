"""``mobman place``: where to park the platform for a target of the task (:mod:`mobman.studies.placement`).

Tries every platform pose of a polar grid around the target (``--radii`` × ``--bearings`` × ``--headings``),
solves the arm's inverse kinematics from ``--starts`` postures within the joint limits for each, and ranks the
bases that reach the target by a manipulability measure of the posture (``--measure``, ``--level``). Exit
status 3 when no base reaches it (the candidates are still printed).
"""

from __future__ import annotations

from typing import Any

import numpy as np
import typer
from rich.console import Console
from rich.table import Table

from mobman.cli.app import app
from mobman.cli.common import UrdfOption, load_robot, not_reached, urdf_options
from mobman.errors import InputError
from mobman.io import dump_json
from mobman.io.numbers import parse_vector
from mobman.manipulability import MEASURES
from mobman.studies.placement import LEVELS, Placement, place


def _entry(result: Placement, k: int) -> dict[str, Any]:
    return {
        "base": result.bases[k],
        "q": result.q[k],
        "error": float(result.error[k]),
        "score": float(result.score[k]),
    }


OPTIONS = ("radii", "bearings", "headings", "starts", "iterations", "tolerance", "measure", "level")
"""The keyword arguments of :func:`mobman.studies.placement.place` that are options of the command."""


def _as_option(message: str) -> str:
    """``place``'s message about a keyword argument (``"bearings must be …"``) as one about its option
    (``"--bearings must be …"``)."""
    keyword = message.split(" ", 1)[0]
    return f"--{message}" if keyword in OPTIONS else message


@app.command("place")
def place_command(
    robot_name: str = typer.Argument(
        ..., metavar="ROBOT", help="A built-in robot (see `mobman robots`), a .toml or a .urdf file."
    ),
    target: str = typer.Option(..., "--target", help="The task's target ξ*, e.g. 1,0.5,0.8 for x, y, z."),
    centre: str | None = typer.Option(
        None, "--centre", help="x,y the grid is centred on (default: the target's x, y)."
    ),
    radii: str | None = typer.Option(
        None,
        "--radii",
        help="Distances of the bases from the centre, e.g. 0.4,0.6,0.8 (default: 8 up to the reach).",
    ),
    bearings: int = typer.Option(16, "--bearings", help="Directions around the centre (≥ 1)."),
    headings: int = typer.Option(16, "--headings", help="Platform headings over [−π, π) (≥ 1)."),
    starts: int = typer.Option(4, "--starts", help="Starting postures of the arm per base (≥ 1)."),
    iterations: int = typer.Option(60, "--iterations", help="Damped least-squares steps per start (≥ 1)."),
    tolerance: float = typer.Option(
        1e-6, "--tolerance", help="Largest task error of a reached target (> 0)."
    ),
    measure: str = typer.Option("yoshikawa", "--measure", help=f"one of {', '.join(MEASURES)}"),
    level: str = typer.Option(
        "arm", "--level", help=f"one of {', '.join(LEVELS)}: J_a (platform parked) or J̄ = J S."
    ),
    top: int = typer.Option(5, "--top", help="Bases listed, best first (≥ 1)."),
    params: list[str] | None = typer.Option(None, "--param", help="Robot parameter NAME=VALUE."),
    tip: list[str] | None = UrdfOption.tip,
    base: str | None = UrdfOption.base,
    platform: str | None = UrdfOption.platform,
    wheels: str | None = UrdfOption.wheels,
    lock: list[str] | None = UrdfOption.lock,
    json_output: bool = typer.Option(False, "--json", help="Print one JSON object."),
) -> None:
    """Find platform poses from which the arm reaches --target, ranked by manipulability."""
    if top < 1:
        raise InputError(f"--top must be ≥ 1, got {top}")
    robot = load_robot(robot_name, params, urdf_options(tip, base, platform, wheels, lock))
    try:
        result = place(
            robot,
            parse_vector(target, "--target", robot.task.dim),
            centre=None if centre is None else parse_vector(centre, "--centre", 2),
            radii=None if radii is None else parse_vector(radii, "--radii"),
            bearings=bearings,
            headings=headings,
            starts=starts,
            iterations=iterations,
            tolerance=tolerance,
            measure=measure,
            level=level,
        )
    except InputError as exc:
        raise InputError(_as_option(str(exc))) from None
    ranking = [_entry(result, int(k)) for k in result.ranking(top)]
    report = {
        "robot": robot_name,
        "coordinates": list(robot.coordinate_names),
        "task": list(robot.task.names),
        "target": result.target,
        "measure": measure,
        "level": level,
        "tolerance": tolerance,
        "candidates": int(result.bases.shape[0]),
        "reached": int(result.reached.sum()),
        "best": ranking[0] if ranking else None,
        "ranking": ranking,
    }
    if json_output:
        typer.echo(dump_json(report))
    else:
        _print(report, robot_name, robot.n_platform)
    if not ranking:
        closest = float(np.min(result.error))
        not_reached(
            "place",
            f"no base of the {report['candidates']} reaches the target (closest error {closest:.3e}); try "
            "other --radii or more --starts",
        )


def _print(report: dict, robot_name: str, n_platform: int) -> None:
    table = Table(
        title=f"mobman place {robot_name}: {report['reached']} of {report['candidates']} bases reach "
        f"{np.array2string(np.asarray(report['target']), precision=4)} ({report['level']} {report['measure']})"
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
            np.array2string(np.asarray(entry["q"])[n_platform:], precision=3),
        )
    Console().print(table)
