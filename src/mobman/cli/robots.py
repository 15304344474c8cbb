"""``mobman robots``: list the built-in robots with their parameters and coordinates (the real robots, read
from URDF files, with the install line of the ``robots`` extra when it is missing), and the parameters every
robot takes (its arm's mount, :data:`mobman.model.robots.MOUNT`)."""

from __future__ import annotations

import inspect

import typer
from rich.console import Console
from rich.markup import escape
from rich.table import Table

from mobman.cli.app import app
from mobman.io import dump_json
from mobman.io.real_robots import EXTRA, REAL_ROBOTS
from mobman.model.robots import MOUNT, ROBOTS


@app.command("robots")
def robots_command(json_output: bool = typer.Option(False, "--json", help="Print one JSON object.")) -> None:
    """List the built-in robots, their parameters (defaults) and coordinate names."""
    entries: list[dict] = []
    for name, factory in ROBOTS.items():
        if name in REAL_ROBOTS and not REAL_ROBOTS[name].available():
            summary = (factory.__doc__ or "").strip().splitlines()[0]
            entries.append(
                {
                    "name": name,
                    "parameters": {},
                    "coordinates": [],
                    "task": [],
                    "summary": f"{summary}; needs {EXTRA}",
                }
            )
            continue
        robot = factory()
        defaults = {p.name: p.default for p in inspect.signature(factory).parameters.values()}
        entries.append(
            {
                **robot.describe(),
                "name": name,
                "parameters": defaults,
                "summary": (factory.__doc__ or "").strip().splitlines()[0],
            }
        )
    if json_output:
        typer.echo(dump_json({"robots": entries, "every_robot": list(MOUNT)}))
        return
    table = Table(
        title="built-in robots",
        caption=f"every robot, built in or a .toml or .urdf file, also takes --param {', '.join(MOUNT)}: "
        "the mount of its arm (--arm where a command has it) in the platform frame, m and rad",
    )
    table.add_column("name", no_wrap=True)  # a name is what the user types: never split
    for column in ("parameters", "coordinates q", "task ξ", "summary"):
        table.add_column(column, overflow="fold")
    for e in entries:
        params = ", ".join(f"{k}={v}" for k, v in e["parameters"].items()) or "—"
        table.add_row(
            e["name"], params, ", ".join(e["coordinates"]), ", ".join(e["task"]), escape(e["summary"])
        )
    Console().print(table)
