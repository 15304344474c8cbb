"""Parsing helpers shared by the commands: robot names, NAME=VALUE parameters, vectors, CSV files."""

from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np

from mobman.errors import InputError
from mobman.model.robot import MobileManipulator
from mobman.model.robots import build


def parse_params(items: list[str] | None) -> dict[str, float]:
    """``["l1=0.5", "l2=0.3"]`` → {"l1": 0.5, "l2": 0.3}; one clear error for a malformed item."""
    params: dict[str, float] = {}
    for item in items or []:
        if "=" not in item:
            raise InputError(f"--param {item!r}: expected NAME=VALUE")
        name, value = item.split("=", 1)
        try:
            params[name.strip()] = float(value)
        except ValueError:
            raise InputError(f"--param {name.strip()}: {value!r} is not a number") from None
        if not math.isfinite(params[name.strip()]):
            raise InputError(f"--param {name.strip()}: value must be finite")
    return params


def load_robot(name: str, params: list[str] | None = None, urdf: dict | None = None) -> MobileManipulator:
    """A built-in robot by name with --param overrides, a robot description file (a path ending in .toml), or
    a URDF file (a path ending in .urdf, read by :func:`mobman.io.urdf.load_urdf` with the ``urdf`` options)."""
    if name.endswith(".urdf"):
        from mobman.io.urdf import load_urdf

        if params:
            raise InputError("--param applies to built-in robots; a URDF file takes --tip and --base")
        return load_urdf(name, **{k: v for k, v in (urdf or {}).items() if v})
    if name.endswith(".toml"):
        from mobman.io import robot_file

        if params:
            raise InputError("--param applies to built-in robots; edit the robot file instead")
        return robot_file.load(name)
    return build(name, **parse_params(params))


def parse_vector(text: str, field: str, size: int | None = None) -> np.ndarray:
    """``"0.1,0.2,pi/2"`` → array; accepts ``pi`` expressions; checks size and finiteness."""
    values = []
    for token in text.replace(";", ",").split(","):
        token = token.strip()
        if not token:
            continue
        try:
            values.append(float(token))
        except ValueError:
            try:
                values.append(float(eval(token, {"__builtins__": {}}, {"pi": math.pi})))  # noqa: S307
            except Exception:
                raise InputError(f"{field}: {token!r} is not a number") from None
    arr = np.asarray(values, dtype=float)
    if size is not None and arr.size != size:
        raise InputError(f"{field}: expected {size} values, got {arr.size}")
    if not np.all(np.isfinite(arr)):
        raise InputError(f"{field}: values must be finite (no NaN or inf)")
    return arr


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
