"""Parsing helpers shared by the commands: robot names, NAME=VALUE parameters, vectors, CSV files."""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np
import typer

from mobman.cli import NOT_REACHED
from mobman.errors import InputError
from mobman.io.numbers import parse_number, parse_vector
from mobman.model.robot import MobileManipulator
from mobman.model.robots import build


def parse_params(items: list[str] | None) -> dict[str, float]:
    """``["l1=0.5", "l2=0.3"]`` → {"l1": 0.5, "l2": 0.3}; one clear error for a malformed item."""
    params: dict[str, float] = {}
    for item in items or []:
        if "=" not in item:
            raise InputError(f"--param {item!r}: expected NAME=VALUE")
        name, value = item.split("=", 1)
        params[name.strip()] = parse_number(value, f"--param {name.strip()}")
    return params


def not_reached(command: str, reason: str) -> None:
    """End a run that finished without reaching its goal: one warning line and exit status 3 (its results
    are already printed and written)."""
    typer.echo(f"warning: mobman {command}: {reason}", err=True)
    raise typer.Exit(NOT_REACHED)


def load_robot(name: str, params: list[str] | None = None) -> MobileManipulator:
    """A built-in robot by name with --param overrides, or a robot description file (a path ending in .toml)."""
    if name.endswith(".toml"):
        from mobman.io import robot_file

        if params:
            raise InputError("--param applies to built-in robots; edit the robot file instead")
        return robot_file.load(name)
    return build(name, **parse_params(params))


def read_configurations(path: Path, robot: MobileManipulator) -> np.ndarray:
    """Configurations from a CSV file: one per row in the robot's coordinate order, optional header line."""
    try:
        with open(path, newline="") as handle:
            rows = [row for row in csv.reader(handle) if row and any(cell.strip() for cell in row)]
    except OSError as exc:
        raise InputError(f"--q-file {path}: cannot read ({exc.strerror})") from None
    if rows and not _numeric(rows[0]):
        header = [c.strip() for c in rows[0]]
        if header != list(robot.coordinate_names):
            raise InputError(
                f"--q-file {path}: header {header} does not match coordinates {list(robot.coordinate_names)}"
            )
        rows = rows[1:]
    if not rows:
        raise InputError(f"--q-file {path}: no configurations")
    out = []
    for i, row in enumerate(rows, start=1):
        if not _numeric(row):
            raise InputError(f"--q-file {path}: row {i} is not numeric")
        out.append(parse_vector(",".join(row), f"--q-file {path} row {i}", robot.n_q))
    return np.stack(out)


def _numeric(row: list[str]) -> bool:
    try:
        [float(c) for c in row]
        return True
    except ValueError:
        return False
