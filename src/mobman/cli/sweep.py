"""``mobman sweep``: a robot's parameters varied over a grid, every design scored (:mod:`mobman.studies.sweep`).

``--vary NAME=START:STOP:COUNT`` (evenly spaced values, both ends included) or ``--vary NAME=V1,V2,…`` once
per varied parameter; ``--param NAME=VALUE`` fixes another. The parameters are a built-in robot's own (as
``mobman robots`` lists them) and, for every robot, built-in or a .toml or .urdf file, the scored arm's mount
``mount.x``, ``mount.y``, ``mount.z`` (m), ``mount.yaw``, ``mount.pitch`` and ``mount.roll`` (rad) in the
platform frame. Each design is
scored by the manipulability of its arm's tool over seeded random postures (``--samples``, ``--measure``,
``--level``), its horizontal reach and, with ``--bounds`` and ``--step``, the share of that box it reaches
(``coverage``). ``--store`` keeps the
designs in a Zarr store as they are computed (a stopped sweep is resumed by the same command);
``--scheduler`` computes them on a Dask cluster. The best designs by ``--rank-by`` are printed; exit status 3
when no design could be built.
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
    load_robot,
    not_reached,
    parse_params,
    progress_bar,
    refuse_urdf_options,
    resumable,
    study_arguments,
    urdf_options,
)
from mobman.errors import InputError
from mobman.io import dump_json
from mobman.io.numbers import parse_number, parse_vector
from mobman.manipulability import MEASURES
from mobman.model.robot import MobileManipulator
from mobman.model.robots import ROBOTS, command_name
from mobman.studies.options import LEVELS
from mobman.studies.sweep import DesignSweep, sweep

MAX_COUNT = 10_000
"""Most values one ``--vary NAME=START:STOP:COUNT`` gives."""

OPTIONS = ("arm", "samples", "measure", "level", "seed", "bounds", "step", "store", "chunk", "scheduler")
"""The keyword arguments of :func:`mobman.studies.sweep.sweep` that are options of the command."""


def parse_values(item: str) -> tuple[str, np.ndarray]:
    """``"l1=0.3:0.8:6"`` → ("l1", 6 values from 0.3 to 0.8); ``"l1=0.3,0.5"`` → ("l1", [0.3, 0.5])."""
    if "=" not in item:
        raise InputError(f"--vary {item!r}: expected NAME=START:STOP:COUNT or NAME=V1,V2,…")
    name, text = (part.strip() for part in item.split("=", 1))
    field = f"--vary {name}"
    if ":" not in text:
        return name, parse_vector(text, field)
    parts = text.split(":")
    if len(parts) != 3:
        raise InputError(f"{field}: expected START:STOP:COUNT, got {text!r}")
    start, stop = parse_number(parts[0], field), parse_number(parts[1], field)
    count = parts[2].strip()
    if not (count.isdigit() and 1 <= int(count) <= MAX_COUNT):
        raise InputError(f"{field}: COUNT must be an integer from 1 to {MAX_COUNT}, got {count!r}")
    return name, np.linspace(start, stop, int(count))


def _as_option(message: str) -> str:
    """A message about a keyword argument (``"samples must be …"``) as one about its option."""
    keyword = message.split(" ", 1)[0].rstrip(":")
    if keyword == "parameters":
        return "--vary" + message[len("parameters") :]
    if keyword == "fixed":
        return "--param" + message[len("fixed") :]
    return f"--{message}" if keyword in OPTIONS else message


def _entry(result: DesignSweep, index: tuple[int, ...]) -> dict[str, Any]:
    return {
        "design": result.design(index),
        "metrics": {name: float(values[index]) for name, values in result.metrics.items()},
    }


@app.command("sweep")
def sweep_command(
    robot_name: str = typer.Argument(
        ..., metavar="ROBOT", help="A built-in robot (see `mobman robots`), a .toml or a .urdf file."
    ),
    vary: list[str] = typer.Option(
        ...,
        "--vary",
        help="NAME=START:STOP:COUNT or NAME=V1,V2,… (repeatable: one grid axis each). NAME: a built-in "
        "robot's parameter, or the scored arm's mount.x, mount.y, mount.z (m), mount.yaw, mount.pitch, "
        "mount.roll (rad).",
    ),
    params: list[str] | None = typer.Option(None, "--param", help="A fixed robot parameter NAME=VALUE."),
    arm: int = typer.Option(0, "--arm", help="The arm whose tool is scored (0 for the first)."),
    samples: int = typer.Option(2000, "--samples", help="Random postures per design (≥ 1)."),
    measure: str = typer.Option("yoshikawa", "--measure", help=f"one of {', '.join(MEASURES)}"),
    level: str = typer.Option(
        "arm", "--level", help=f"one of {', '.join(LEVELS)}: J_a (platform parked) or J̄ = J S."
    ),
    seed: int = typer.Option(0, "--seed", help="Seed of the random postures (the same for every design)."),
    bounds: str | None = typer.Option(
        None, "--bounds", help="x_min,x_max,y_min,y_max,z_min,z_max of a box to score coverage of (m)."
    ),
    step: float | None = typer.Option(None, "--step", help="Cell size of the --bounds box (m)."),
    store: Path | None = StudyOption.store,
    chunk: int | None = typer.Option(
        None, "--chunk", help="Designs per unit of work (≥ 1; default 1, or the store's own)."
    ),
    scheduler: str | None = StudyOption.scheduler,
    rank_by: str | None = typer.Option(
        None,
        "--rank-by",
        help="Metric the designs are ranked by (default: coverage with --bounds, else mean).",
    ),
    top: int = typer.Option(5, "--top", help="Designs listed, best first (≥ 1)."),
    tip: list[str] | None = UrdfOption.tip,
    base: str | None = UrdfOption.base,
    platform: str | None = UrdfOption.platform,
    wheels: str | None = UrdfOption.wheels,
    lock: list[str] | None = UrdfOption.lock,
    platform_option: list[str] | None = UrdfOption.platform_option,
    quiet: bool = StudyOption.quiet,
    json_output: bool = typer.Option(False, "--json", help="Print one JSON object."),
) -> None:
    """Score every design of a grid of a robot's parameters by manipulability, reach and coverage."""
    if top < 1:
        raise InputError(f"--top must be ≥ 1, got {top}")
    urdf = urdf_options(tip, base, platform, wheels, lock, platform_option)
    source: str | MobileManipulator
    if command_name(robot_name) in ROBOTS:  # rebuilt for each design from its parameters
        refuse_urdf_options(urdf, f"robot {robot_name!r}")
        source = robot_name
    else:  # a file: its mount is what can vary (--param fixes it too, hence not the file's --param)
        source = load_robot(robot_name, None, urdf)
    grid = dict(parse_values(item) for item in vary)
    if len(grid) != len(vary):
        raise InputError("--vary: a parameter is given twice")
    box = None if bounds is None else parse_vector(bounds, "--bounds", 6)
    with resumable("sweep", store), progress_bar("sweeping", not (quiet or json_output)) as bar:
        try:
            result = sweep(
                source,
                grid,
                fixed=parse_params(params),
                arm=arm,
                samples=samples,
                measure=measure,
                level=level,
                seed=seed,
                bounds=box,
                step=step,
                **study_arguments(store, chunk, scheduler, bar),
            )
        except InputError as exc:
            raise InputError(_as_option(str(exc))) from None
    metric = rank_by or ("coverage" if box is not None else "mean")
    try:
        ranking = [_entry(result, index) for index in result.ranking(metric, top)]
    except InputError as exc:
        raise InputError(f"--rank-by: {exc}") from None
    report = {
        "robot": robot_name,
        "parameters": result.parameters,
        "fixed": result.fixed,
        "measure": measure,
        "level": level,
        "designs": int(np.prod(result.shape)),
        "computed": int(result.computed.sum()),
        "failed": len(result.failures),
        "failures": [{"design": result.design(i), "reason": r} for i, r in result.failures.items()],
        "rank_by": metric,
        "ranking": ranking,
        "store": None if store is None else str(store),
    }
    if json_output:
        typer.echo(dump_json(report))
    else:
        _print(report, list(result.metrics))
    if not ranking:
        not_reached("sweep", f"none of the {report['designs']} designs could be built (see failures)")


def _print(report: dict, metrics: list[str]) -> None:
    console = Console()
    console.print(
        f"mobman sweep {report['robot']}: {report['computed']} of {report['designs']} designs computed, "
        f"{report['failed']} refused by the robot; best by {report['rank_by']} ({report['level']} "
        f"{report['measure']})"
    )
    table = Table()
    names = list(report["parameters"])
    for column in ["rank", *names, *metrics]:
        table.add_column(column)
    for k, entry in enumerate(report["ranking"], start=1):
        table.add_row(
            str(k),
            *(f"{entry['design'][n]:.4g}" for n in names),
            *(f"{entry['metrics'][m]:.4g}" for m in metrics),
        )
    console.print(table)
    for failure in report["failures"][:3]:
        console.print(f"refused: {failure['design']}: {failure['reason']}")
    if report["store"] is not None:
        console.print(f"store: {report['store']}")
