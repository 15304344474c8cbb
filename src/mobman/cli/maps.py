"""``mobman map``: where around its platform an arm's tool reaches, and how well
(:mod:`mobman.studies.maps`).

Solves the arm's inverse kinematics, the platform parked, for every cell centre of a grid around the
platform (``--bounds``, ``--step``) and scores the reached cells by a manipulability measure (``--measure``,
``--level``). ``--store`` keeps the cells in a Zarr store as they are computed: a run stopped (Ctrl-C, a lost
machine) is resumed by the same command. ``--scheduler`` computes them on a Dask cluster. ``--figure`` draws
the map from above and from the side. A posture counts only when the robot there is free of collision with
itself and with the obstacles and floor of ``--scene`` (``--no-collision``: not checked;
:mod:`mobman.studies.clearance`); cells reached only with colliding postures are counted apart. Exit status 3 when no cell is reached.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import typer
from rich.console import Console
from rich.table import Table

from mobman.cli.app import app
from mobman.cli.common import (
    StudyOption,
    UrdfOption,
    array_text,
    check_figure,
    load_robot,
    not_reached,
    progress_bar,
    resumable,
    study_arguments,
    urdf_options,
)
from mobman.cli.distance import ClearanceOption, clearance_arguments
from mobman.errors import InputError
from mobman.io import dump_json
from mobman.io.numbers import parse_vector
from mobman.manipulability import MEASURES
from mobman.studies.maps import ReachabilityMap, reachability_map
from mobman.studies.options import LEVELS

OPTIONS = (
    "arm",
    "bounds",
    "step",
    "starts",
    "iterations",
    "tolerance",
    "measure",
    "level",
    "seed",
    "store",
    "chunk",
    "scheduler",
)
"""The keyword arguments of :func:`mobman.studies.maps.reachability_map` that are options of the command."""


def _as_option(message: str) -> str:
    """A message about a keyword argument (``"step must be …"``) as one about its option (``"--step …"``)."""
    keyword = message.split(" ", 1)[0].rstrip(":")
    return f"--{message}" if keyword in OPTIONS else message


def _summary(result: ReachabilityMap, n_platform: int) -> dict[str, Any]:
    best = result.best()
    return {
        "shape": list(result.shape),
        "axes": {name: [float(a[0]), float(a[-1])] for name, a in zip("xyz", result.axes)},
        "cells": int(np.prod(result.shape)),
        "computed": int(result.computed.sum()),
        "reached": int(result.reached.sum()),
        "colliding": None
        if result.colliding is None or result.clearance is None
        else int(result.colliding.sum()),
        "fraction": result.fraction,
        "best": None
        if best is None
        else {
            "centre": result.centres()[best],
            "score": float(result.score[best]),
            "q": result.q[best][n_platform:],
        },
        "layers": [
            {"z": float(z), "reached": int(result.reached[:, :, k].sum())}
            for k, z in enumerate(result.axes[2])
        ],
    }


@app.command("map")
def map_command(
    robot_name: str = typer.Argument(
        ..., metavar="ROBOT", help="A built-in robot (see `mobman robots`), a .toml or a .urdf file."
    ),
    arm: int = typer.Option(0, "--arm", help="The arm whose tool is mapped (0 for the first)."),
    bounds: str | None = typer.Option(
        None,
        "--bounds",
        help="x_min,x_max,y_min,y_max,z_min,z_max of the cell centres (m, platform frame; default: the "
        "tool's sampled reach).",
    ),
    step: float = typer.Option(0.05, "--step", help="Distance between cell centres (m, > 0)."),
    starts: int = typer.Option(8, "--starts", help="Starting postures of the arm per cell (≥ 1)."),
    iterations: int = typer.Option(60, "--iterations", help="Damped least-squares steps per start (≥ 1)."),
    tolerance: float = typer.Option(1e-4, "--tolerance", help="Largest distance of a reached centre (m)."),
    measure: str = typer.Option("yoshikawa", "--measure", help=f"one of {', '.join(MEASURES)}"),
    level: str = typer.Option(
        "arm", "--level", help=f"one of {', '.join(LEVELS)}: J_a (platform parked) or J̄ = J S."
    ),
    seed: int = typer.Option(0, "--seed", help="Seed of the random starting postures."),
    scene: Path | None = ClearanceOption.scene,
    collision: bool = ClearanceOption.collision,
    cover: float = ClearanceOption.cover,
    store: Path | None = StudyOption.store,
    chunk: int | None = typer.Option(
        None, "--chunk", help="Cells per unit of work (≥ 1; default 4096, or the store's own)."
    ),
    scheduler: str | None = StudyOption.scheduler,
    figure: Path | None = typer.Option(None, "--figure", help="Draw the map into this PNG file."),
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
    """Map where the arm's tool reaches around the platform, scored by manipulability."""
    check_figure(figure)
    urdf = urdf_options(tip, base, platform, wheels, lock, platform_option)
    robot = load_robot(robot_name, params, urdf, arm)
    checks = clearance_arguments(robot_name, robot, urdf, scene, collision, cover)
    box = None if bounds is None else parse_vector(bounds, "--bounds", 6)
    with resumable("map", store), progress_bar("mapping", not (quiet or json_output)) as bar:
        try:
            result = reachability_map(
                robot,
                arm=arm,
                bounds=box,
                step=step,
                starts=starts,
                iterations=iterations,
                tolerance=tolerance,
                measure=measure,
                level=level,
                seed=seed,
                **checks,
                **study_arguments(store, chunk, scheduler, bar),
            )
        except InputError as exc:
            raise InputError(_as_option(str(exc))) from None
    report = {
        "robot": robot_name,
        "arm": arm,
        "step": step,
        "measure": measure,
        "level": level,
        "tolerance": tolerance,
        "store": None if store is None else str(store),
        **_summary(result, robot.n_platform),
    }
    if figure is not None:
        from mobman.io.output import save_figure
        from mobman.viz.maps import plot_reachability

        title = f"{robot_name}: {report['reached']} of {report['cells']} cells reached ({level} {measure})"
        save_figure(
            plot_reachability(result.axes, result.score, result.reached, measure, title), figure, dpi=110
        )
    if json_output:
        typer.echo(dump_json(report))
    else:
        _print(report, robot_name)
    if report["reached"] == 0:
        not_reached(
            "map", f"no cell of the {report['cells']} is reached; check --bounds or give more --starts"
        )


def _print(report: dict, robot_name: str) -> None:
    console = Console()
    console.print(
        f"mobman map {robot_name}: {report['reached']} of {report['cells']} cells reached "
        f"({report['fraction']:.1%}; {report['level']} {report['measure']}, step {report['step']:g} m)"
        + ("" if report["colliding"] is None else f"; {report['colliding']} reached only in collision")
    )
    table = Table()
    for column in ("z (m)", "cells reached"):
        table.add_column(column)
    for layer in report["layers"]:
        table.add_row(f"{layer['z']:.3f}", str(layer["reached"]))
    console.print(table)
    best = report["best"]
    if best is not None:
        centre = array_text(best["centre"], 3)
        posture = array_text(best["q"], 3)
        console.print(f"best cell {centre}: {report['measure']} {best['score']:.4g} at q (arm) {posture}")
    if report["store"] is not None:
        console.print(f"store: {report['store']}")
