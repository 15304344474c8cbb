"""Parsing helpers shared by the commands: robot names (and their dynamic models), the URDF reading options,
NAME=VALUE parameters, vectors, CSV files."""

from __future__ import annotations

import contextlib
import csv
import os
import shutil
import sys
import tempfile
import warnings
from collections.abc import Callable, Iterator
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
import numpy.typing as npt
import typer
from rich.console import Console
from rich.progress import BarColumn, Progress, TextColumn, TimeRemainingColumn

from mobman.cli.app import INTERRUPTED, NOT_REACHED
from mobman.engine.memory import available_memory, size
from mobman.errors import InputError
from mobman.io.numbers import parse_number, parse_vector
from mobman.io.spec import read_text
from mobman.io.urdf import is_urdf_path
from mobman.model.robot import MobileManipulator
from mobman.model.robots import MOUNT, command_name, design
from mobman.studies.floor import FootprintDisc, KeepOut, footprint_disc, keep_out_regions

if TYPE_CHECKING:
    from mobman.dynamics import DynamicModel
    from mobman.io.urdf import UrdfModel
    from mobman.studies.maps import ReachabilityMap


def parse_params(items: list[str] | None, option: str = "--param") -> dict[str, float]:
    """``["l1=0.5", "l2=0.3"]`` → {"l1": 0.5, "l2": 0.3}; one clear error naming ``option`` for a malformed
    item."""
    params: dict[str, float] = {}
    for item in items or []:
        if "=" not in item:
            raise InputError(f"{option} {item!r}: expected NAME=VALUE")
        name, value = item.split("=", 1)
        params[name.strip()] = parse_number(value, f"{option} {name.strip()}")
    return params


# --- how a URDF file is read: the same options on every command that takes a ROBOT --------------------


class UrdfOption:
    """The command-line options of :func:`urdf_options`, as the defaults of each command's parameters."""

    tip = typer.Option(
        None, "--tip", help="URDF file: end-effector link, one per arm (repeatable; default arm_tool_link)."
    )
    base = typer.Option(None, "--base", help="URDF file: the platform link (default base_footprint).")
    platform = typer.Option(
        None,
        "--platform",
        help="URDF file: the platform kind: auto (a differential drive found from its wheels, the default), "
        "differential, car, skid_steer, omnidirectional or fixed.",
    )
    wheels = typer.Option(
        None, "--wheels", help="URDF file: the drive wheels' joints RIGHT,LEFT (default: found in the file)."
    )
    lock = typer.Option(
        None, "--lock", help="URDF file: hold a joint at a value, JOINT=VALUE (rad or m; repeatable)."
    )
    platform_option = typer.Option(
        None,
        "--platform-option",
        help="URDF file: a platform parameter KEY=VALUE that the file does not state or that overrides it "
        "(repeatable): wheel_radius and half_track (m; wheels that are fixed joints or absent), a skid-steer's "
        "wheelbase, x_icr, track_factor, wheel_speed_max, …; and base_height, the base link's height above "
        "the ground (m) where no wheel gives it.",
    )


class FloorOption:
    """The command-line options of :func:`floor_arguments` (``mobman place``, ``mobman view``)."""

    keep_out = typer.Option(
        None,
        "--keep-out",
        help="A floor rectangle x_min,x_max,y_min,y_max (m) the platform may not overlap, e.g. a table "
        "(repeatable).",
    )
    footprint = typer.Option(
        None,
        "--footprint",
        help="With --keep-out: the disc covering the platform, radius or radius,x,y in the platform frame (m); "
        "default: the disc covering its drawn shapes.",
    )


def floor_arguments(
    robot: MobileManipulator, keep_out: list[str] | None, footprint: str | None
) -> tuple[tuple[KeepOut, ...], FootprintDisc | None]:
    """``--keep-out`` and ``--footprint`` checked: the keep-out regions and the disc covering the platform (by
    default :func:`mobman.studies.floor.footprint_disc` of ``robot``), or no region and None."""
    if not keep_out:
        if footprint is not None:
            raise InputError("--footprint: give it with --keep-out (the regions it keeps the platform off)")
        return (), None
    try:
        regions = keep_out_regions([parse_vector(region, "--keep-out", 4) for region in keep_out])
        disc = (
            footprint_disc(robot)
            if footprint is None
            else FootprintDisc.of(parse_vector(footprint, "--footprint"))
        )
    except InputError as exc:  # "keep_out must …", "footprint radius must …" as the options
        raise InputError("--" + str(exc).replace("_", "-", 1)) from None
    return regions, disc


URDF_FLAGS = {
    "tip": "--tip",
    "base": "--base",
    "platform": "--platform",
    "wheels": "--wheels",
    "locked": "--lock",
    "platform_options": "--platform-option",
}
"""The command-line option of each :func:`mobman.io.urdf.read_urdf` argument the commands take."""


def urdf_options(
    tip: list[str] | None = None,
    base: str | None = None,
    platform: str | None = None,
    wheels: str | None = None,
    lock: list[str] | None = None,
    platform_option: list[str] | None = None,
) -> dict:
    """The :func:`mobman.io.urdf.read_urdf` arguments given on the command line (``--tip``, ``--base``,
    ``--platform``, ``--wheels RIGHT,LEFT``, ``--lock JOINT=VALUE``, ``--platform-option KEY=VALUE``); those
    not given keep read_urdf's defaults."""
    given = {
        "tip": tuple(tip) if tip else None,
        "base": base,
        "platform": platform,
        "wheels": None if wheels is None else tuple(name.strip() for name in wheels.split(",")),
        "locked": parse_params(lock, "--lock") if lock else None,
        "platform_options": parse_params(platform_option, "--platform-option") if platform_option else None,
    }
    return {key: value for key, value in given.items() if value is not None}


MAX_STEPS = 10**6
"""Default limit of the time steps of one run (``--max-steps`` raises it)."""

BYTES_PER_VALUE = 64
"""Memory estimate per stored float of a run: the value (8 bytes), the compiled loop's copies and the JSON text
of ``results.json``."""


def check_steps(
    steps: int, values_per_step: int, field: str, max_steps: int = MAX_STEPS, held: int | None = None
) -> None:
    """Refuse, before any work, a run of ``steps`` time steps storing ``values_per_step`` floats each that
    exceeds ``max_steps`` (InputError naming ``--max-steps``) or the machine's available memory; ``held``:
    the steps in memory at once for a run computed in pieces (default all of them)."""
    need = (steps if held is None else held) * values_per_step * BYTES_PER_VALUE
    estimate = f"{steps:.3g} steps, about {size(need)} of memory"
    if steps > max_steps:
        raise InputError(
            f"{field}: {estimate}: more than the limit of {max_steps:.3g} steps; use a larger dt or a shorter "
            "duration, or raise the limit with --max-steps"
        )
    available = available_memory()
    if available is not None and need > available:
        raise InputError(
            f"{field}: {estimate}: more than the {size(available)} available; use a larger dt or a shorter "
            "duration"
        )


def check_disk(out: Path, need: int, field: str = "--out") -> None:
    """Refuse, before any work, results of about ``need`` bytes that the file system of ``out`` has no room
    for (InputError naming ``field``)."""
    parent = Path(os.path.abspath(out))
    while not parent.exists():
        parent = parent.parent
    try:
        free = shutil.disk_usage(parent).free
    except OSError:
        return
    if need > free:
        raise InputError(
            f"{field} {out}: the results take about {size(need)}, more than the {size(free)} free there; "
            "use a larger dt, a shorter duration or another folder"
        )


def check_figure(figure: Path | None, field: str = "--figure") -> None:
    """Refuse, before any work, a figure file that is not a .png or whose folder cannot be written into
    (InputError naming ``field``)."""
    if figure is None:
        return
    if figure.suffix.lower() != ".png":
        raise InputError(f"{field} must name a .png file, got {str(figure)!r}")
    if figure.is_dir():
        raise InputError(f"{field} {figure}: is a folder; name a .png file")
    folder = Path(os.path.abspath(figure)).parent
    if not folder.is_dir():
        raise InputError(f"{field} {figure}: the folder {folder} does not exist")
    try:  # the figure is written through a temporary sibling: probe that folder, leaving nothing behind
        os.rmdir(tempfile.mkdtemp(dir=folder, prefix=".mobman-probe-"))
    except OSError as exc:
        raise InputError(f"{field} {figure}: cannot write into {folder} ({exc.strerror or exc})") from None


def not_reached(command: str, reason: str) -> None:
    """End a run that finished without reaching its goal: one warning line and exit status 3 (its results
    are already printed and written)."""
    typer.echo(f"warning: mobman {command}: {reason}", err=True)
    raise typer.Exit(NOT_REACHED)


class StudyOption:
    """The command-line options of a study (``mobman map``, ``mobman sweep``; :mod:`mobman.studies.store`), as
    the defaults of each command's parameters."""

    store = typer.Option(
        None, "--store", help="Zarr store (a folder) the results are kept in; an unfinished one is resumed."
    )
    scheduler = typer.Option(
        None,
        "--scheduler",
        help="Compute on Dask: 'local', 'local:N' (N worker processes) or a scheduler's address "
        "tcp://HOST:PORT (needs mobman[studies]).",
    )
    quiet = typer.Option(False, "--quiet", help="No progress bar.")


def load_map(path: Path, robot: MobileManipulator) -> "ReachabilityMap":
    """The reachability map in the store ``path`` (``mobman map --store``), which must be one of ``robot``;
    errors name ``--map``."""
    from mobman.studies import store
    from mobman.studies.maps import from_study, robot_digest

    try:
        study = store.read(path)
        reachability = from_study(study)
    except InputError as exc:
        raise InputError(f"--map: {exc}") from None
    if reachability.digest != robot_digest(robot):
        raise InputError(
            f"--map: the map was computed for another robot ({study.definition.get('robot')!r}) than "
            f"{robot.name!r}"
        )
    return reachability


@contextlib.contextmanager
def resumable(command: str, store: Path | None) -> Iterator[None]:
    """A study's run: interrupted (Ctrl-C) with a ``store``, one line saying what the store keeps and exit
    status 130 (:data:`mobman.cli.app.INTERRUPTED`); the same command resumes it."""
    try:
        yield
    except KeyboardInterrupt:
        if store is None:
            raise
        from mobman.studies.store import read

        done = read(store).done
        typer.echo(
            f"interrupted: mobman {command} stopped; {store} keeps {int(done.sum()):,} of {done.size:,} rows: "
            "run the same command again to resume",
            err=True,
        )
        sys.exit(INTERRUPTED)  # SystemExit: past the command line library, which would report it again


@contextlib.contextmanager
def progress_bar(label: str, show: bool) -> Iterator[Callable[[float], None] | None]:
    """A progress callback (fraction done) drawing a bar labelled ``label`` on standard error, or None when
    not ``show`` or when standard error is not a terminal (a log file gets no bar)."""
    console = Console(stderr=True)
    if not (show and console.is_terminal):
        yield None
        return
    columns = (TextColumn(label), BarColumn(), TextColumn("{task.percentage:>3.0f}%"), TimeRemainingColumn())
    with Progress(*columns, console=console, transient=True) as progress:
        bar = progress.add_task(label, total=1.0)
        yield lambda f: progress.update(bar, completed=f)


def study_arguments(
    store: Path | None, chunk: int | None, scheduler: str | None, bar: Callable[[float], None] | None
) -> dict:
    """The keyword arguments of a study's function (:func:`mobman.studies.store.run`'s ``store``, ``chunk``,
    ``scheduler`` and ``progress``) from its command's options and progress bar (:func:`progress_bar`)."""
    return {
        "store": None if store is None else str(store),
        "chunk": chunk,
        "scheduler": scheduler,
        "progress": None if bar is None else lambda done, total: bar(done / total),
    }


def refuse_urdf_options(urdf: dict | None, what: str) -> None:
    """One line naming the URDF options given (:func:`urdf_options`) for ``what``, which is not a URDF file."""
    if urdf:
        flags = ", ".join(URDF_FLAGS[key] for key in urdf)
        raise InputError(f"{flags}: for a URDF file (a path ending in .urdf), not {what}")


def read_urdf_file(name: str, urdf: dict | None = None, drawn: bool = False, say: bool = True) -> "UrdfModel":
    """:func:`mobman.io.urdf.read_urdf` of a URDF file (kept on disk between commands:
    :mod:`mobman.io.urdf_cache`) with the ``urdf`` options (:func:`urdf_options`); with
    ``say``, what it reads differently from the file (:attr:`mobman.io.urdf.UrdfSummary.notes`) on one line
    each on standard error, and for a robot that will be ``drawn`` the meshes not found in one line."""
    from mobman.io import urdf_cache
    from mobman.io.urdf import UrdfWarning

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UrdfWarning)
        model = urdf_cache.read(name, **(urdf or {}))
    if say:
        lines = [*model.summary.notes, *([model.summary.mesh_note()] if drawn else [])]
        for line in lines:
            if line:
                typer.echo(f"warning: {line}", err=True)
    return model


def load_robot(
    name: str, params: list[str] | None = None, urdf: dict | None = None, arm: int = 0, drawn: bool = False
) -> MobileManipulator:
    """A built-in robot by name with --param overrides, a robot description file (a path ending in .toml), or
    a URDF file (a path ending in .urdf, read by :func:`read_urdf_file` with the ``urdf`` options,
    :func:`urdf_options`, saying the meshes it lacks when the robot will be ``drawn``). Every robot also takes
    the --param ``mount.x``, ``mount.y``, ``mount.z``, ``mount.yaw``, ``mount.pitch`` and ``mount.roll`` of
    arm ``arm``'s mount (:func:`mobman.model.robots.design`); a file takes no other."""
    values = parse_params(params)
    if is_urdf_path(name) or name.endswith(".toml"):
        other = [key for key in values if key not in MOUNT]
        if other:
            rest = (
                "a URDF file takes --tip, --base, --platform, --wheels, --lock and --platform-option"
                if is_urdf_path(name)
                else "edit the robot file instead"
            )
            raise InputError(
                f"--param {other[0]}: a robot file takes only its arm's mount ({', '.join(MOUNT)}); {rest}"
            )
    if is_urdf_path(name):
        return design(read_urdf_file(name, urdf, drawn).robot, values, arm)
    refuse_urdf_options(urdf, f"robot {name!r}")
    if name.endswith(".toml"):
        from mobman.io import robot_file

        return design(robot_file.load(name), values, arm)
    if os.sep in name or Path(name).is_file():
        raise InputError(
            f"{name}: not a robot name; a robot file ends in .urdf (a URDF) or .toml (a robot description)"
        )
    return design(name, values, arm)


def load_dynamics(
    name: str, robot: MobileManipulator, option: str, urdf: dict | None = None
) -> tuple["DynamicModel", np.ndarray]:
    """The dynamic model of the robot ``name`` (as :func:`load_robot` reads it, ``robot``) and its actuators'
    torque limits (N·m: wheels, then joints), for the command-line option ``option`` that asks for them.

    A URDF file and the built-in real robots (``tiago``, ``tiago-dual``, ``stretch``): the URDF's inertials
    and effort limits, gravity 9.81 m/s²; ``yamamoto-dual-arm``: Yamamoto & Yun's Tables 1–2 (horizontal motion,
    no gravity). Anything else, or a URDF without an inertial or effort limit: ModelError naming what is missing.
    """
    from mobman.dynamics import DynamicModel, yamamoto_platform
    from mobman.errors import ModelError
    from mobman.io.real_robots import REAL_ROBOTS, urdf_model

    key = command_name(name)
    if is_urdf_path(name) or key in REAL_ROBOTS:
        try:
            model = urdf_model(key) if key in REAL_ROBOTS else read_urdf_file(name, urdf, say=False)
            dynamics, limits = DynamicModel.from_urdf(model), model.torque_limits()
        except ModelError as exc:
            raise ModelError(f"{option}: {exc}") from None
        # the arms as --param mounted them (a mount carries no mass: the inertials stay the URDF's)
        mounted = replace(dynamics.robot, mounts=robot.mounts)
        return replace(dynamics, robot=mounted), limits
    if key != "yamamoto-dual-arm":
        raise ModelError(
            f"robot {name}: {option} needs a dynamic model (platform, wheel and link inertials and torque "
            f"limits): a URDF file with them, or one of yamamoto-dual-arm, {', '.join(REAL_ROBOTS)}"
        )
    from mobman.experiments.yamamoto1999 import torque_limits

    body, wheel = yamamoto_platform()
    return DynamicModel(robot, body, wheel, None, (0.0, 0.0, 0.0)), torque_limits(robot)


def read_configurations(path: Path, robot: MobileManipulator) -> np.ndarray:
    """Configurations from a CSV file: one per row in the robot's coordinate order, each value a number or an
    expression as on the command line (``pi/2``); an optional header line of the coordinate names."""
    text = read_text(path, f"--q-file {path}")
    try:
        rows = [row for row in csv.reader(text.splitlines()) if row and any(cell.strip() for cell in row)]
    except csv.Error as exc:
        raise InputError(f"--q-file {path}: not a CSV file ({exc})") from None
    if rows and _is_header(rows[0]):
        header = [c.strip() for c in rows[0]]
        if header != list(robot.coordinate_names):
            raise InputError(
                f"--q-file {path}: header {header} does not match coordinates {list(robot.coordinate_names)}"
            )
        rows = rows[1:]
    if not rows:
        raise InputError(f"--q-file {path}: no configurations")
    return np.stack(
        [parse_vector(",".join(row), f"--q-file {path} row {i}", robot.n_q) for i, row in enumerate(rows, 1)]
    )


def _is_header(row: list[str]) -> bool:
    """A header names the coordinates: none of its cells is a number or an expression."""
    for cell in row:
        try:
            parse_number(cell, "")
        except InputError:
            continue
        return False
    return True


def array_text(values: npt.ArrayLike, digits: int = 4) -> str:
    """``values`` for a table: fixed-point notation with ``digits`` decimals, never e-notation (a value below
    the last decimal prints as 0), lines of at most 120 characters."""
    return np.array2string(
        np.asarray(values, dtype=float), precision=digits, suppress_small=True, max_line_width=120
    )
