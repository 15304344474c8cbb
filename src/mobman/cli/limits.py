"""Configurations outside the robot's joint limits, for the commands that take one: a warning line on
standard error per configuration (with ``--strict-limits``: an error, exit 2) and the names for the output."""

from __future__ import annotations

import numpy as np
import typer

from mobman.errors import InputError
from mobman.model.robot import MobileManipulator

STRICT_HELP = "Refuse (exit 2) a configuration outside the robot's joint limits instead of warning."


def outside_limits(
    robot: MobileManipulator,
    q: np.ndarray,
    field: str,
    strict: bool,
    coordinates: slice = slice(None),
    note: str = "analysed as given",
) -> list[list[str]]:
    """Names of the coordinates of each configuration q (n, n_q) outside the joint limits; warns on standard
    error for each such configuration (ending with ``note``), or raises InputError naming ``field`` when
    ``strict``. ``coordinates``: the coordinates checked (default all, e.g. ``slice(3, None)`` for the arm's)."""
    violations = np.zeros(np.shape(q), dtype=bool)
    violations[:, coordinates] = robot.limit_violations(q)[:, coordinates]
    limits = robot.position_limits
    names = robot.coordinate_names
    out = []
    for k, row in enumerate(violations):
        bad = list(np.flatnonzero(row))
        out.append([names[i] for i in bad])
        if not bad:
            continue
        label = field if len(violations) == 1 else f"{field}, configuration {k + 1}"
        detail = ", ".join(
            f"{names[i]} = {q[k, i]:g} outside [{limits[i][0]:g}, {limits[i][1]:g}]" for i in bad
        )
        if strict:
            raise InputError(f"{label}: {detail} (the robot's joint limits)")
        typer.echo(f"warning: {label}: {detail} (the robot's joint limits); {note}", err=True)
    return out
