"""``mobman distance``: the signed distances between a robot at one configuration and a scene (and itself).

The robot's collision spheres (cover tolerance ``--tolerance``), covering the ``<collision>`` shapes of a robot
read from a URDF file (the real robots built in too) or the generated geometry of the papers' robots
(:mod:`mobman.model.collision_model`), against the obstacles and floor of the scene file (:mod:`mobman.io.scene`) and its own
self-collision pairs (:mod:`mobman.collision`). Printed: the minimum distance, the closest pair with its
witness points, and the distance of every pair of a robot body (the platform, a link) with an obstacle, the
floor or another body (the smallest over their spheres), closest first. A negative distance is a penetration.
Default configuration: the robot's neutral posture (every coordinate 0, clipped to the joint limits).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import typer
from rich.console import Console
from rich.table import Table

from mobman import collision
from mobman.cli.app import app
from mobman.cli.common import UrdfOption, array_text, load_robot, urdf_options
from mobman.cli.limits import STRICT_HELP, outside_limits
from mobman.errors import InputError
from mobman.io import dump_json, urdf_cache
from mobman.io import scene as scene_file
from mobman.io.numbers import parse_vector
from mobman.io.real_robots import REAL_ROBOTS
from mobman.io.urdf import is_urdf_path
from mobman.model.collision_model import DEFAULT_TOLERANCE, CollisionModel, collision_model, neutral_posture
from mobman.model.robot import MobileManipulator
from mobman.model.scene import Scene
from mobman.studies.clearance import COVER_TOLERANCE


def body_pairs(model: CollisionModel, scene: Scene, q: np.ndarray) -> dict:
    """The JSON-ready distances at one configuration q (n_q,): minimum, closest pair (None without pairs),
    and per pair of a body with an obstacle, the floor or another body the smallest distance over their
    spheres, closest first."""
    out = collision.distances(model, scene, q)
    names = collision.pair_names(model, scene)
    best: dict[tuple[str, str], int] = {}
    for k, key in enumerate(names):
        if key not in best or out.distance[k] < out.distance[best[key]]:
            best[key] = k
    order = sorted(best.values(), key=lambda k: out.distance[k])
    pairs = [{"robot": names[k][0], "other": names[k][1], "distance": float(out.distance[k])} for k in order]
    if not order:
        return {"min_distance": None, "in_collision": False, "closest": None, "pairs": pairs}
    k = order[0]
    minimum = float(out.distance[k])
    closest = {
        **pairs[0],
        "robot_point": out.robot_point[k],
        "other_point": out.other_point[k],
        "normal": out.normal[k],
    }
    return {
        "min_distance": minimum,
        "in_collision": minimum < 0,
        "closest": closest,
        "pairs": pairs,
    }


def robot_collision_model(
    name: str, robot: MobileManipulator, urdf: dict, tolerance: float
) -> CollisionModel:
    """The collision model of the robot named ``name`` on the command line: the spheres covering the
    ``<collision>`` shapes of its URDF file (a .urdf path or a built-in real robot, read with the ``urdf``
    options), else those of :func:`mobman.model.collision_model.collision_model`."""
    if is_urdf_path(name):
        path, options = name, dict(urdf or {})
    elif name in REAL_ROBOTS:
        spec = REAL_ROBOTS[name]
        path, options = str(spec.path()), {"tip": spec.tips, "base": spec.base, "name": name}
        options["locked"] = dict(spec.locked)
    else:
        return collision_model(robot, tolerance)
    return urdf_cache.collision_model(path, robot, tolerance, **options)


class ClearanceOption:
    """The command-line options of :func:`clearance_arguments` (``mobman place``, ``mobman map``)."""

    scene = typer.Option(
        None,
        "--scene",
        help="Scene file (TOML, [[obstacle]] tables, optional floor): postures must be free of its obstacles; "
        "its boxes on the floor keep the platform off.",
    )
    collision = typer.Option(
        True,
        "--collision/--no-collision",
        help="Accept only postures free of collision with the robot itself (and the --scene).",
    )
    cover = typer.Option(
        COVER_TOLERANCE,
        "--cover-tolerance",
        help="Cover tolerance of the collision spheres (m, > 0): how far they may reach beyond the robot.",
    )


def clearance_arguments(
    name: str, robot: MobileManipulator, urdf: dict, scene: Path | None, check: bool, cover: float
) -> dict:
    """``--scene``, ``--collision`` and ``--cover-tolerance`` as the ``scene`` and ``collision`` arguments of
    the studies (:mod:`mobman.studies.clearance`): the collision model of :func:`robot_collision_model`
    unless ``--no-collision`` (then no --scene either)."""
    if scene is not None and not check:
        raise InputError("--scene: postures are checked against a scene only with --collision")
    if not check:
        return {}
    world = None if scene is None else scene_file.load(scene)
    return {
        "scene": world,
        "collision": robot_collision_model(
            name, robot, urdf, collision_tolerance(cover, "--cover-tolerance")
        ),
    }


def collision_tolerance(value: float, option: str = "--tolerance") -> float:
    """``--tolerance`` (``option``) checked: a finite number > 0 (m)."""
    if not (np.isfinite(value) and value > 0):
        raise InputError(f"{option}: must be a finite number > 0 (m), got {value!r}")
    return float(value)


@app.command("distance")
def distance_command(
    robot_name: str = typer.Argument(
        ..., metavar="ROBOT", help="A built-in robot (see `mobman robots`), a .toml or a .urdf file."
    ),
    scene: Path = typer.Option(
        None, "--scene", help="Scene file (TOML, [[obstacle]] tables, optional floor)."
    ),
    param: list[str] = typer.Option(None, "--param", help="Robot parameter NAME=VALUE (repeatable)."),
    tip: list[str] = UrdfOption.tip,
    base: str = UrdfOption.base,
    platform: str = UrdfOption.platform,
    wheels: str = UrdfOption.wheels,
    lock: list[str] = UrdfOption.lock,
    platform_option: list[str] = UrdfOption.platform_option,
    q: str = typer.Option(
        None, "--q", help="The configuration v1,v2,… in the robot's coordinate order (pi allowed)."
    ),
    tolerance: float = typer.Option(
        DEFAULT_TOLERANCE,
        "--tolerance",
        help="Cover tolerance (m): how far the spheres reach beyond the robot.",
    ),
    json_output: bool = typer.Option(False, "--json", help="Print one JSON object."),
    strict_limits: bool = typer.Option(False, "--strict-limits", help=STRICT_HELP),
) -> None:
    """Minimum distance, closest pair and per-pair distances of a robot to a scene and to itself."""
    robot = load_robot(robot_name, param, urdf_options(tip, base, platform, wheels, lock, platform_option))
    world = Scene() if scene is None else scene_file.load(scene)
    configuration = neutral_posture(robot) if q is None else parse_vector(q, "--q", robot.n_q)
    outside = outside_limits(robot, configuration[None], "--q", strict_limits)[0]
    options = urdf_options(tip, base, platform, wheels, lock, platform_option)
    model = robot_collision_model(robot_name, robot, options, collision_tolerance(tolerance))
    result = {
        "robot": robot.name,
        "q": configuration,
        "outside_limits": outside,
        "tolerance": model.tolerance,
        "spheres": len(model.spheres),
        **body_pairs(model, world, configuration),
    }
    if json_output:
        typer.echo(dump_json(result))
        return
    _print(result)


def _print(result: dict) -> None:
    console = Console()
    closest = result["closest"]
    head = Table(title=f"{result['robot']}: distances", show_header=False)
    head.add_row("q", array_text(result["q"]))
    head.add_row("spheres (cover tolerance)", f"{result['spheres']} ({result['tolerance']:g} m)")
    if closest is None:
        head.add_row("minimum distance", "no pair (an empty scene and no self-collision pair)")
    else:
        note = "  (in collision)" if result["in_collision"] else ""
        head.add_row("minimum distance (m)", f"{result['min_distance']:.6g}{note}")
        head.add_row("closest pair", f"{closest['robot']} – {closest['other']}")
    console.print(head)
    table = Table(title="pairs, closest first")
    for column in ("robot", "other", "distance (m)"):
        table.add_column(column, justify="right" if column.startswith("distance") else "left")
    for pair in result["pairs"]:
        table.add_row(pair["robot"], pair["other"], f"{pair['distance']:.6g}")
    console.print(table)
