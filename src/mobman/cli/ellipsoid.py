"""``mobman ellipsoid``: the task-space ellipsoid of a robot at one configuration (Yamamoto & Yun §3).

``--kind kinematic`` (default): the task velocities reachable with every actuator rate within its maximum
(eq. 23–26: wheel speeds for a differential drive with per-wheel limits, else the platform's η limits, and
the joint rates). ``--kind dynamic``: the task accelerations reachable with every actuator torque
within its maximum (eq. 27–38), from rest or, with ``--eta``, at the given quasi-velocities (the velocity
terms shift the centre, μ_o); it needs the robot's dynamic model (inertials of the platform, wheels and
links) and its torque limits, built in for ``yamamoto-dual-arm`` (Tables 1–2), the real robots and URDF files (their
inertials and effort limits; :func:`mobman.cli.common.load_dynamics`) — other robots get a one-line error. ``--held``: the ellipsoid of an object held rigidly by all arms (coordinates x_o, y_o, angle_o), at the
centroid of the tool points; with ``--grasp point`` the hands hold it at one point through pivots (x_o, y_o).

Printed: principal semi-axes (major first), their unit directions (in the task coordinates), the centre and
the volume, the representation-singular flag (the task's coordinates singular as a representation: the
ellipsoid's axes along them are then meaningless; where its Jacobian is not finite the command says so and
exits 2) and the coordinates outside the joint limits (also a warning on standard error; ``--strict-limits``
makes it an error); ``--json`` gives the same as one JSON object.
"""

from __future__ import annotations

import numpy as np
import typer
from rich.console import Console
from rich.table import Table

from mobman import kinematics as K
from mobman.cli.app import app
from mobman.cli.common import UrdfOption, load_dynamics, load_robot, urdf_options
from mobman.cli.limits import STRICT_HELP, outside_limits
from mobman.dynamics.ellipsoids import (
    CLOSED_CHAIN_SINGULAR,
    GRASPS,
    Ellipsoid,
    Method,
    dynamic_ellipsoid,
    grasp_task,
    kinematic_ellipsoid,
)
from mobman.dynamics.grasp import HeldObject
from mobman.errors import InputError
from mobman.io import dump_json
from mobman.io.numbers import parse_vector

KINDS = ("kinematic", "dynamic")
METHODS: tuple[Method, ...] = ("exact", "paper")


def ellipsoid_report(e: Ellipsoid) -> dict:
    """The JSON-ready description of one (unbatched) ellipsoid."""
    return {
        "names": list(e.names),
        "axes": e.axes,
        "directions": [e.directions[:, k] for k in range(len(e.names))],
        "center": e.center,
        "volume": float(e.volume),
        "feasible": bool(e.feasible),
        "singular": bool(e.singular),
    }


def _positive(value: float, field: str) -> float:
    if not (np.isfinite(value) and value > 0):
        raise InputError(f"{field} must be a finite number > 0, got {value!r}")
    return float(value)


@app.command("ellipsoid")
def ellipsoid_command(
    robot_name: str = typer.Argument(
        ..., metavar="ROBOT", help="A built-in robot (see `mobman robots`), a .toml or a .urdf file."
    ),
    q: str = typer.Option(
        ..., "--q", help="The configuration v1,v2,… in the robot's coordinate order (pi allowed)."
    ),
    kind: str = typer.Option(
        "kinematic", "--kind", help="kinematic (velocities) or dynamic (accelerations)."
    ),
    param: list[str] = typer.Option(None, "--param", help="Robot parameter NAME=VALUE (repeatable)."),
    tip: list[str] = UrdfOption.tip,
    base: str = UrdfOption.base,
    platform: str = UrdfOption.platform,
    wheels: str = UrdfOption.wheels,
    lock: list[str] = UrdfOption.lock,
    platform_option: list[str] = UrdfOption.platform_option,
    held: bool = typer.Option(
        False, "--held", help="Ellipsoid of an object held by all the arms (see --grasp)."
    ),
    grasp: str = typer.Option(
        "rigid", "--grasp", help="--held: rigid, or point (hands at one point, pivots)."
    ),
    object_mass: float = typer.Option(2.0, "--object-mass", help="Held object's mass, kg (dynamic, --held)."),
    object_inertia: float = typer.Option(
        0.01, "--object-inertia", help="Held object's inertia about the vertical, kg m² (dynamic, --held)."
    ),
    method: str = typer.Option(
        "exact", "--method", help="Dynamic: exact (image of the torque ball) or paper (eq. 31–38)."
    ),
    eta: str = typer.Option(
        None,
        "--eta",
        help="Dynamic: quasi-velocities v1,v2,… (platform, then joint rates); default at rest.",
    ),
    json_output: bool = typer.Option(False, "--json", help="Print one JSON object."),
    strict_limits: bool = typer.Option(False, "--strict-limits", help=STRICT_HELP),
) -> None:
    """Principal axes (major first), directions and volume of the kinematic or dynamic task-space ellipsoid."""
    if kind not in KINDS:
        raise InputError(f"--kind must be one of {', '.join(KINDS)}, got {kind!r}")
    if method not in METHODS:
        raise InputError(f"--method must be one of {', '.join(METHODS)}, got {method!r}")
    if grasp not in GRASPS:
        raise InputError(f"--grasp must be one of {', '.join(GRASPS)}, got {grasp!r}")
    urdf = urdf_options(tip, base, platform, wheels, lock, platform_option)
    robot = load_robot(robot_name, param, urdf)
    configuration = parse_vector(q, "--q", robot.n_q)
    robot.validate_q(configuration)
    outside = outside_limits(robot, configuration[None], "--q", strict_limits)[0]
    if eta is not None and kind != "dynamic":
        raise InputError(
            "--eta applies to --kind dynamic only (the kinematic ellipsoid has no velocity terms)"
        )
    velocities = None if eta is None else parse_vector(eta, "--eta", robot.n_eta)
    task = grasp_task(robot, grasp) if held else robot.task
    representation = bool(K.representation_singular(robot, configuration, task))
    if kind == "kinematic":
        e = kinematic_ellipsoid(robot, configuration, held=held, grasp=grasp)
    else:
        model, limits = load_dynamics(robot_name, robot, "--kind dynamic", urdf)
        obj = None
        if held:
            obj = HeldObject(
                _positive(object_mass, "--object-mass"),
                (0.0, 0.0, _positive(object_inertia, "--object-inertia")),
            )
        e = dynamic_ellipsoid(
            model, configuration, limits, eta=velocities, obj=obj, method=method, grasp=grasp
        )
    result = {
        "robot": robot.name,
        "params": dict(robot.parameters),
        "q": configuration,
        "outside_limits": outside,
        "representation_singular": representation,
        "kind": kind,
        "held": held,
        **({"grasp": grasp} if held else {}),
        "units": "m/s, rad/s" if kind == "kinematic" else "m/s², rad/s²",
        **({"method": method, "torque_limits": limits, "eta": velocities} if kind == "dynamic" else {}),
        **ellipsoid_report(e),
    }
    if json_output:
        typer.echo(dump_json(result))
        return
    _print(result)


def _print(result: dict) -> None:
    console = Console()
    title = f"{result['kind']} ellipsoid of {result['robot']}" + (" (held object)" if result["held"] else "")
    if result["kind"] == "dynamic":
        title += f", method {result['method']}"
    table = Table(title=title)
    table.add_column("axis", justify="right")
    table.add_column(f"semi-axis ({result['units']})", justify="right")
    table.add_column("direction (" + ", ".join(result["names"]) + ")")
    for k, (length, direction) in enumerate(zip(result["axes"], result["directions"]), start=1):
        table.add_row(str(k), f"{length:.6g}", ", ".join(f"{v:+.4f}" for v in direction))
    console.print(table)
    console.print("centre: " + ", ".join(f"{v:.6g}" for v in result["center"]))
    console.print(f"volume: {result['volume']:.6g}" + ("" if result["feasible"] else " (empty: infeasible)"))
    if result["singular"]:
        console.print(f"singular: {CLOSED_CHAIN_SINGULAR}", soft_wrap=True)  # one line, whatever the width
    console.print(f"representation singular: {result['representation_singular']}")
    console.print("outside joint limits: " + (", ".join(result["outside_limits"]) or "no"))
