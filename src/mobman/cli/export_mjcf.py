"""``mobman export-mjcf ROBOT [--scene FILE] --out robot.xml``: the robot as a MuJoCo model (MJCF), for MuJoCo's viewer, mink
or a physics run (:func:`mobman.physics.to_mjspec`; docs/physics.md).

The inertials and motor limits are those of the robot's dynamic model where mobman has one
(:func:`mobman.cli.common.load_dynamics`: a URDF file and the real robots, their URDF inertials and effort
limits; ``yamamoto-dual-arm``, Yamamoto & Yun's Tables 1–2); any other robot is exported with the stand-in
inertials of :func:`mobman.physics.mjcf.dynamic_model` and its joints' own limits, and says so. The file is
written atomically; ``--json`` prints what was built.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import typer

from mobman.cli.app import app
from mobman.cli.common import UrdfOption, load_dynamics, load_robot, urdf_options
from mobman.errors import ModelError
from mobman.io import dump_json
from mobman.io.output import write_text
from mobman.io.real_robots import REAL_ROBOTS
from mobman.io.scene import load as load_scene
from mobman.io.urdf import is_urdf_path
from mobman.model.robots import command_name

if TYPE_CHECKING:
    from mobman.dynamics import DynamicModel
    from mobman.model.robot import MobileManipulator


@app.command("export-mjcf")
def export_mjcf_command(
    robot_name: str = typer.Argument(
        ..., metavar="ROBOT", help="A built-in robot (see `mobman robots`), a .toml or a .urdf file."
    ),
    out: Path = typer.Option(Path("robot.xml"), "--out", help="The MJCF file written."),
    scene_file: Path = typer.Option(
        None, "--scene", help="A scene file (TOML: [[obstacle]] tables): its obstacles in the model."
    ),
    param: list[str] = typer.Option(None, "--param", help="Robot parameter NAME=VALUE (repeatable)."),
    friction: float = typer.Option(1.0, "--friction", help="Sliding friction of the wheels on the floor."),
    timestep: float = typer.Option(0.001, "--timestep", help="MuJoCo's time step (s)."),
    tip: list[str] = UrdfOption.tip,
    base: str = UrdfOption.base,
    platform: str = UrdfOption.platform,
    wheels: str = UrdfOption.wheels,
    lock: list[str] = UrdfOption.lock,
    json_output: bool = typer.Option(False, "--json", help="Print one JSON object."),
) -> None:
    """Write the robot as a MuJoCo model: a free platform on its wheels, the arms, the actuators."""
    from mobman.physics.mjcf import mjcf_text, mujoco_module, to_mjspec

    mujoco_module()  # the install line before any work
    urdf = urdf_options(tip, base, platform, wheels, lock)
    robot = load_robot(robot_name, param, urdf)
    model: MobileManipulator | DynamicModel
    try:
        model, limits = load_dynamics(robot_name, robot, "export-mjcf", urdf)
        source = "the robot's dynamic model"
    except ModelError:
        if is_urdf_path(robot_name) or command_name(robot_name) in REAL_ROBOTS:
            raise  # a URDF without inertials or effort limits
        model, limits = robot, None
        source = "stand-in inertials (mobman has no dynamic model of this robot; docs/physics.md)"
    if out.is_dir():
        raise ModelError(f"--out {out}: a folder; give the path of the .xml file to write")
    scene = None if scene_file is None else load_scene(scene_file)
    spec = to_mjspec(model, scene, torque_limits=limits, friction=friction, timestep=timestep)
    compiled = spec.compile()
    write_text(out, mjcf_text(spec))
    actuators = [compiled.actuator(i).name for i in range(compiled.nu)]
    report = {
        "robot": robot.name,
        "out": str(out),
        "platform": robot.platform.kind,
        "obstacles": [] if scene is None else [o.name for o in scene.obstacles],
        "inertials": source,
        "mass": float(compiled.body_subtreemass[compiled.body("platform").id]),
        "bodies": int(compiled.nbody - 1),
        "joints": int(compiled.njnt),
        "actuators": actuators,
    }
    if json_output:
        typer.echo(dump_json(report))
        return
    typer.echo(
        f"{out}: {robot.name} ({robot.platform.kind}), {report['mass']:.6g} kg, {report['bodies']} bodies, "
        f"{len(actuators)} actuators; {source}"
    )
