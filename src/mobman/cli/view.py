"""``mobman view ROBOT``: the robot (or a run's motions) in the browser, served by :class:`mobman.viz.viewer.Viewer`."""

from __future__ import annotations

from pathlib import Path
from time import sleep

import typer

from mobman.cli.app import app
from mobman.cli.common import (
    FloorOption,
    UrdfOption,
    floor_arguments,
    load_dynamics,
    load_map,
    load_robot,
    parse_vector,
    refuse_urdf_options,
    urdf_options,
)
from mobman.errors import InputError

DEFAULT_PORT = 8080
"""Where an interactive view is served unless --port says otherwise (a screenshot takes any free port)."""


def _is_results(name: str) -> bool:
    path = Path(name)
    return path.is_dir() or (path.is_file() and path.suffix == ".json")


@app.command("view")
def view_command(
    robot_name: str = typer.Argument(
        ..., metavar="ROBOT", help="built-in robot, robot file, or a results folder (its robot is used)"
    ),
    q: str | None = typer.Option(None, "--q", help="Configuration to show, e.g. 0,0,0,0.3,pi/4."),
    results: Path | None = typer.Option(
        None, "--results", help="Results folder or JSON file with a motion (simulate/plan --out, reproduce)."
    ),
    motion: str | None = typer.Option(None, "--motion", help="Label of the motion to show first."),
    port: int | None = typer.Option(
        None,
        "--port",
        help=f"Port to serve on (0: any free port); default {DEFAULT_PORT}, and any free port for --screenshot.",
    ),
    host: str = typer.Option("127.0.0.1", "--host", help="Address to bind (loopback by default)."),
    normalized: bool = typer.Option(
        False, "--normalized", help="Ellipsoid of J̄ · diag(η_max) (needs velocity limits)."
    ),
    dynamic: bool = typer.Option(
        False,
        "--dynamic",
        help="Also the dynamic ellipsoid (URDF inertials and effort limits, or yamamoto-dual-arm).",
    ),
    screenshot_path: Path | None = typer.Option(
        None, "--screenshot", help="Render one PNG headless (chromium) into this file and exit."
    ),
    reachability: Path | None = typer.Option(
        None, "--map", help="A reachability map's store (mobman map --store) to draw around the platform."
    ),
    scene_path: Path | None = typer.Option(
        None,
        "--scene",
        help="Scene file (TOML, [[obstacle]] tables, optional floor): its obstacles and the closest pair's segment.",
    ),
    spheres: bool = typer.Option(
        False, "--spheres", help="Start with the robot's collision spheres shown (a panel box toggles them)."
    ),
    keep_out: list[str] | None = FloorOption.keep_out,
    footprint: str | None = FloorOption.footprint,
    params: list[str] | None = typer.Option(None, "--param", help="Robot parameter NAME=VALUE."),
    tip: list[str] | None = UrdfOption.tip,
    base: str | None = UrdfOption.base,
    platform: str | None = UrdfOption.platform,
    wheels: str | None = UrdfOption.wheels,
    lock: list[str] | None = UrdfOption.lock,
    platform_option: list[str] | None = UrdfOption.platform_option,
) -> None:
    """Serve a 3D view of a robot, a configuration or a run's motions in the browser."""
    from mobman.io import trajectories

    try:
        from mobman.viz.viewer import Viewer, motions_of, robot_of
    except ImportError as exc:
        raise InputError(
            f"mobman view needs the viewer extra ({exc.name} is missing): pip install 'mobman[viewer]'"
        ) from None

    if port is None:
        port = 0 if screenshot_path is not None else DEFAULT_PORT
    if not 0 <= port <= 65535:
        raise InputError(f"--port must be in 0..65535, got {port}")
    results_as_robot = False
    urdf = urdf_options(tip, base, platform, wheels, lock, platform_option)
    if _is_results(robot_name):
        if results is not None:
            raise InputError("give the results either as ROBOT or with --results, not both")
        results = Path(robot_name)
        results_as_robot = True
        refuse_urdf_options(urdf, "a results folder (its robot is rebuilt from the results)")
        robot = robot_of(trajectories.read(results)[0])
    else:
        robot = load_robot(robot_name, params, urdf, drawn=True)
    configuration = None if q is None else parse_vector(q, "--q", robot.n_q)
    if results is not None:
        motions_of(robot, results)  # a results file of another robot: said before serving anything
    dynamics = None
    if dynamic:
        # a results folder names its robot; a URDF file is read again for its inertials and effort limits
        dynamics = load_dynamics(robot.name if results_as_robot else robot_name, robot, "--dynamic", urdf)
    drawn = None
    if reachability is not None:
        drawn = load_map(reachability, robot)
    regions, disc = floor_arguments(robot, keep_out, footprint)
    clearance = None
    if scene_path is not None or spheres:
        from mobman.cli.distance import robot_collision_model
        from mobman.io import scene as scene_file
        from mobman.model.collision_model import DEFAULT_TOLERANCE
        from mobman.model.scene import Scene

        world = Scene() if scene_path is None else scene_file.load(scene_path)
        name = robot.name if results_as_robot else robot_name
        clearance = (world, robot_collision_model(name, robot, urdf, DEFAULT_TOLERANCE))
    viewer = Viewer(robot, host=host, port=port, normalized=normalized, dynamics=dynamics)
    try:
        if disc is not None:
            boxes = [[r.x_min, r.x_max, r.y_min, r.y_max] for r in regions]
            viewer.show_floor(boxes, (disc.radius, disc.x, disc.y))
        if clearance is not None:
            viewer.show_scene(*clearance, spheres=spheres)
        if drawn is not None:
            viewer.show_map(drawn.centres()[drawn.reached], drawn.score[drawn.reached], drawn.step)
        if results is not None:
            viewer.load_results(results, motion)
        if configuration is not None:
            viewer.show(configuration)
        if screenshot_path is not None:
            from mobman.viz.screenshot import screenshot

            typer.echo(f"screenshot: {screenshot(viewer.url, screenshot_path)}")
            return
        typer.echo(f"mobman view: {robot.name} at {viewer.url} (Ctrl-C to stop)")
        while True:
            sleep(1.0)
    except KeyboardInterrupt:
        pass
    finally:
        viewer.close()
