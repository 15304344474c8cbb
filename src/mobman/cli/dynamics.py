"""``mobman load-capacity SPEC.toml``: maximum allowable load along a motion (mobman.dynamics.load_capacity).

The specification (see ``docs/load_capacity.md`` and ``docs/examples/korayem_load.toml``):

```toml
gravity = [0.0, 0.0, -9.81]          # optional (m/s²)

[robot]                              # a built-in robot with keyword parameters
name = "korayem-planar"
params = { l0 = 0.4, l1 = 0.5, l2 = 0.5 }

[motion]
kind = "korayem"                     # korayem: a case study of Korayem et al. (robot korayem-planar)
case = 1                             # 1: extra task (α, β); 2: extra task F
dt = 0.01                            # s
# kind = "control": [motion.control] holds a `mobman simulate` specification without its [robot]

[platform]                           # PlatformBody
mass = 40.0
inertia_z = 2.0
com = [0.0, 0.0, 0.0]                # optional

[wheel]                              # Wheel (platforms with driven wheels: differential, skid_steer)
mass = 1.0
I_w = 0.005
I_m = 0.0025

[[links]]                            # one per joint, in order; arm = 0 by default
mass = 5.0
com = [0.25, 0.0, 0.0]
inertia = [0.0, 0.10417, 0.10417]    # 3 (diagonal) or 9 numbers, about the centre of mass

[payload]                            # optional: shape of the load (inertia per kg), default a point mass
com = [0.0, 0.0, 0.0]
inertia = [0.0, 0.0, 0.0]
arm = 0

# actuators = "urdf"                 # a robot read from a URDF (tiago, …, or [robot] file = "….urdf"): |τ| ≤
                                     # the URDF's effort limits; without [platform], [wheel] and [[links]]
                                     # its URDF inertials are used
[actuators.theta1]                   # one table per limited actuator (others are unlimited)
kind = "dc_motor"                    # dc_motor: stall_torque, no_load_speed | torque_box: lower, upper
stall_torque = 63.22
no_load_speed = 3.5
```

Every mistake raises :class:`~mobman.InputError` naming the field; the command line prints one line and
exits with status 2.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
import typer
from rich.console import Console
from rich.table import Table

from mobman.cli.app import app
from mobman.cli.common import MAX_STEPS, check_steps, not_reached
from mobman.control.spec import parse as parse_control
from mobman.errors import InputError
from mobman.io import dump_json, robot_file
from mobman.io import spec as fields
from mobman.io.output import check_folder, results_folder, save_figure, write_text

if TYPE_CHECKING:
    from mobman.dynamics import DynamicModel, LoadCapacity, Payload
    from mobman.io.urdf import UrdfModel
    from mobman.model.robot import MobileManipulator

TOP_KEYS = ("gravity", "robot", "motion", "platform", "wheel", "links", "payload", "actuators")
ACTUATOR_KINDS = {"dc_motor": ("stall_torque", "no_load_speed"), "torque_box": ("lower", "upper")}


@dataclass
class LoadSpec:
    """A parsed load-capacity specification: the dynamic model, the motion, the actuators."""

    model: "DynamicModel"
    t: np.ndarray
    q: np.ndarray
    eta: np.ndarray
    actuators: dict
    motion: str


def _vector(
    table: dict, key: str, field: str, size: tuple[int, ...], default: Sequence[float] | None = None
) -> tuple[float, ...]:
    value = table.get(key, default)
    if value is None:
        raise InputError(f"{field}.{key}: missing")
    arr = fields.array(value, f"{field}.{key}")
    if arr.size not in size:
        raise InputError(f"{field}.{key}: {' or '.join(map(str, size))} numbers, got {arr.size}")
    return tuple(arr.ravel())


def _inertials(data: dict, robot: MobileManipulator, urdf: UrdfModel | None) -> DynamicModel:
    """Platform body, wheel, link inertials attached to the robot, payload. A robot read from a URDF (a real
    robot such as ``tiago``, or a URDF file), ``urdf``, given without [platform], [wheel] and [[links]] takes
    them from its URDF."""
    from dataclasses import replace

    from mobman import dynamics as dyn
    from mobman.model.arm import LinkInertial

    if urdf is not None and not any(k in data for k in ("platform", "wheel", "links")):
        g_x, g_y, g_z = _vector(data, "gravity", "spec", (3,), (0.0, 0.0, -9.81))
        model = dyn.DynamicModel.from_urdf(urdf, (g_x, g_y, g_z))
        # the robot as [robot] made it: the URDF's, its arm perhaps mounted elsewhere (a mount has no mass)
        return replace(model, robot=robot, payload=_payload(data, robot))
    platform = fields.table(data, "platform", "platform")
    fields.keys(platform, "platform", ("mass", "inertia_z", "com"))
    body = fields.build(
        "platform",
        dyn.PlatformBody,
        mass=fields.number(platform, "mass", "platform"),
        inertia_z=fields.number(platform, "inertia_z", "platform"),
        com=_vector(platform, "com", "platform", (3,), (0.0, 0.0, 0.0)),
    )
    wheel = None
    wheel_table = fields.table(data, "wheel", "wheel", required=False)
    if wheel_table is not None:
        fields.keys(wheel_table, "wheel", ("mass", "I_w", "I_m"))
        values = {k: fields.number(wheel_table, k, "wheel") for k in ("mass", "I_w", "I_m")}
        wheel = fields.build("wheel", dyn.Wheel, **values)
    links = data.get("links")
    if not isinstance(links, list) or not all(isinstance(link, dict) for link in links):
        raise InputError("links: missing or not an array of tables ([[links]] with mass, com, inertia)")
    per_arm: dict[int, list] = {}
    for k, link in enumerate(links):
        field = f"links[{k}]"
        fields.keys(link, field, ("mass", "com", "inertia", "arm"))
        arm = link.get("arm", 0)
        if isinstance(arm, bool) or not isinstance(arm, int) or not 0 <= arm < len(robot.arms):
            raise InputError(f"{field}.arm: an arm index in 0..{len(robot.arms) - 1}, got {arm!r}")
        per_arm.setdefault(arm, []).append(
            fields.build(
                field,
                LinkInertial,
                mass=fields.number(link, "mass", field),
                com=_vector(link, "com", field, (3,)),
                inertia=_vector(link, "inertia", field, (3, 9)),
            )
        )
    for arm, inertials in sorted(per_arm.items()):
        n = robot.arms[arm].n_joints
        if len(inertials) != n:
            joints = ", ".join(j.name for j in robot.arms[arm].joints)
            raise InputError(
                f"links: arm {arm} has {n} links ({joints}), got {len(inertials)} [[links]] entries"
            )
        robot = robot.with_link_inertials(inertials, arm)
    gravity = _vector(data, "gravity", "spec", (3,), (0.0, 0.0, -9.81))
    return fields.build(
        "spec",
        dyn.DynamicModel,
        robot=robot,
        body=body,
        wheel=wheel,
        payload=_payload(data, robot),
        gravity=gravity,
    )


def _payload(data: dict, robot: MobileManipulator) -> Payload:
    """The [payload] table's load shape (per kg), a point mass at arm 0's tool by default."""
    from mobman import dynamics as dyn

    payload = dyn.Payload(1.0)
    payload_table = fields.table(data, "payload", "payload", required=False)
    if payload_table is not None:
        fields.keys(payload_table, "payload", ("com", "inertia", "arm"))
        arm = payload_table.get("arm", 0)
        if isinstance(arm, bool) or not isinstance(arm, int) or not 0 <= arm < len(robot.arms):
            raise InputError(f"payload.arm: an arm index in 0..{len(robot.arms) - 1}, got {arm!r}")
        payload = fields.build(
            "payload",
            dyn.Payload,
            mass=1.0,
            com=_vector(payload_table, "com", "payload", (3,), (0.0, 0.0, 0.0)),
            inertia=_vector(payload_table, "inertia", "payload", (3, 9), (0.0,) * 9),
            arm=arm,
        )
    return payload


def _actuators(data: dict, names: tuple[str, ...], urdf: UrdfModel | None) -> dict:
    from mobman.dynamics.actuators import DCMotor, TorqueBox

    if data.get("actuators") == "urdf":
        return _urdf_actuators(names, urdf)
    table = fields.table(data, "actuators", "actuators")
    if not table:
        raise InputError(
            f"actuators: at least one [actuators.NAME] table; the actuators are {', '.join(names)}"
        )
    result = {}
    for name, entry in table.items():
        field = f"actuators.{name}"
        if name not in names:
            raise InputError(f"{field}: unknown actuator; the actuators are {', '.join(names)}")
        if not isinstance(entry, dict):
            raise InputError(f"{field}: must be a table with kind = dc_motor | torque_box")
        kind = fields.text(entry, "kind", field, allowed=tuple(ACTUATOR_KINDS))
        if kind is None:
            raise InputError(f"{field}.kind: missing; one of {', '.join(ACTUATOR_KINDS)}")
        keys = ACTUATOR_KINDS[kind]
        fields.keys(entry, field, ("kind",) + keys)
        factory = DCMotor if kind == "dc_motor" else TorqueBox
        result[name] = fields.build(field, factory, **{k: fields.number(entry, k, field) for k in keys})
    return result


def _urdf_actuators(names: tuple[str, ...], urdf: UrdfModel | None) -> dict:
    """``actuators = "urdf"``: |τ| ≤ the URDF's effort limit for every actuator that has one (a robot read
    from a URDF: a real robot or a URDF file)."""
    from mobman.dynamics.actuators import TorqueBox
    from mobman.io.real_robots import REAL_ROBOTS

    if urdf is None:
        raise InputError(
            f'actuators: "urdf" takes the effort limits of a robot read from a URDF (a real robot: '
            f'{", ".join(REAL_ROBOTS)}, or [robot] file = "….urdf")'
        )
    return {n: TorqueBox.symmetric(v) for n, v in zip(names, urdf.effort_limits) if v is not None}


def _motion(
    data: dict, robot: MobileManipulator, max_steps: int, base: Path | None
) -> tuple[np.ndarray, np.ndarray, np.ndarray, str]:
    """(t, q, η, description) of the motion table."""

    table = fields.table(data, "motion", "motion")
    kind = table.get("kind")
    if kind == "korayem":
        from mobman.experiments import korayem_kinematics

        fields.keys(table, "motion", ("kind", "case", "dt"))
        if robot.name != "korayem-planar":
            raise InputError(
                f"motion.kind: 'korayem' needs robot.name = \"korayem-planar\", got {robot.name!r}"
            )
        case = table.get("case")
        cases = {m.number: m for m in korayem_kinematics.models()}
        if isinstance(case, bool) or not isinstance(case, int) or case not in cases:
            raise InputError(f"motion.case: 1 (extra task α, β) or 2 (extra task F), got {case!r}")
        dt = fields.number(table, "dt", "motion", 0.01, positive=True)
        if dt > 0.1:
            raise InputError(f"motion.dt: at most 0.1 s (the motion lasts 2 s), got {dt}")
        check_steps(int(round(2.0 / dt)) + 1, 3 * (robot.n_q + robot.n_eta), "motion.dt", max_steps)
        run = korayem_kinematics.run_model(robot, cases[case], dt)
        return run.t, run.q, run.eta, f"Korayem case {case}, dt = {dt} s"
    if kind == "control":
        fields.keys(table, "motion", ("kind", "control"))
        control = fields.table(table, "control", "motion.control")
        if "robot" in control:
            raise InputError("motion.control.robot: the robot is the top-level [robot]")
        try:
            spec = parse_control(control, base, robot)
        except InputError as exc:
            raise InputError(f"motion.control: {exc}") from None
        steps = int(round(spec.duration / spec.dt)) + 1
        check_steps(steps, 3 * (robot.n_q + robot.n_eta), "motion.control: duration / dt", max_steps)
        run = spec.simulate()
        return run.t, run.q, run.eta, f"control simulation, {spec.duration} s, dt = {spec.dt} s"
    raise InputError(f"motion.kind: {kind!r} not one of korayem, control")


def parse(data: dict, base: Path | None = None, max_steps: int = MAX_STEPS) -> LoadSpec:
    """Build a :class:`LoadSpec` from a TOML document already read into a dict (the motion is simulated)."""
    fields.keys(data, "spec", TOP_KEYS)
    urdf = robot_file.urdf_table(data, base)
    robot = robot_file.robot_table(data, base, urdf)
    model = _inertials(data, robot, urdf)
    actuators = _actuators(data, model.actuator_names, urdf)
    t, q, eta, motion = _motion(data, model.robot, max_steps, base)
    return LoadSpec(model, t, q, eta, actuators, motion)


def load(path: Path, max_steps: int = MAX_STEPS) -> LoadSpec:
    """Read, parse and simulate a load-capacity specification."""
    data = fields.read_toml(path)
    with fields.naming(path):
        return parse(data, Path(path).parent, max_steps)


@app.command("load-capacity")
def load_capacity_command(
    spec_path: Path = typer.Argument(
        ..., metavar="SPEC.toml", help="TOML specification (docs/load_capacity.md)."
    ),
    out: Path | None = typer.Option(
        None, "--out", help="Write results.json and torques.png into this folder."
    ),
    json_output: bool = typer.Option(False, "--json", help="Print the result as one JSON object."),
    max_steps: int = typer.Option(
        MAX_STEPS, "--max-steps", help="Refuse motions of more time steps than this (duration / dt)."
    ),
    physics: str | None = typer.Option(
        None,
        "--physics",
        help="mujoco: run the motion on MuJoCo with 0.9 and 1.2 times the capacity (needs mobman[physics]).",
    ),
) -> None:
    """Maximum payload mass keeping every actuator inside its torque–speed envelope along the motion."""
    from mobman.dynamics.load_capacity import eta_dot_from_samples, max_load

    if physics not in (None, "mujoco"):
        raise InputError(f"--physics must be mujoco, got {physics!r}")
    if out is not None:
        check_folder(out, "load-capacity")
    spec = load(spec_path, max_steps)
    eta_dot = eta_dot_from_samples(spec.t, spec.eta)
    result = max_load(spec.model, spec.t, spec.q, spec.eta, eta_dot, spec.actuators)
    summary = {
        "spec": str(spec_path),
        "robot": spec.model.robot.name,
        "motion": spec.motion,
        **result.summary(),
    }
    runs = () if physics is None else _on_physics(spec, result)
    if runs:
        summary["physics"] = _physics_summary(runs, result)
    if out is not None:
        from mobman.viz import plot_torques

        series = {
            "t": result.t,
            "tau0": result.tau0,
            "tau1": result.tau1,
            "speed": result.speed,
            "lower": result.lower,
            "upper": result.upper,
            "actuators": list(result.names),
        }
        title = f"{spec_path.name}: required torques vs envelopes"
        with results_folder(out, "load-capacity") as staging:
            write_text(staging / "results.json", dump_json({**summary, "series": series}))
            save_figure(plot_torques(result, title), staging / "torques.png", dpi=120)
            if runs:
                from mobman.viz import plot_load_runs

                title = f"{spec_path.name} on MuJoCo: {result.limiting_actuator}'s torque vs its envelope"
                figure = plot_load_runs(runs, str(result.limiting_actuator), title)
                save_figure(figure, staging / "physics_torques.png", dpi=120)
    if json_output:
        typer.echo(dump_json(summary))
    else:
        _print(spec_path, spec, result, summary, out)
    if runs:
        _check_physics(summary["physics"])
    envelope = (result.tau0, result.tau1, result.lower, result.upper)
    if not result.bounded and not all(np.all(np.isfinite(a)) for a in envelope):
        not_reached(
            "load-capacity", "unbounded because some torques or envelopes are not finite (check the data)"
        )


def _on_physics(spec: LoadSpec, result: LoadCapacity) -> tuple:
    """The motion run on MuJoCo with :data:`mobman.physics.load.FRACTIONS` of the capacity."""
    from mobman.physics.load import check_capacity

    try:
        return check_capacity(spec.model, spec.t, spec.q, spec.actuators, result)
    except InputError as exc:
        raise InputError(f"--physics: {exc}") from None


def _physics_summary(runs: tuple, result: LoadCapacity) -> dict:
    """Each run's figures, with the limiting actuator's torque at the limiting time as MuJoCo's inverse
    dynamics asked for it and as mobman predicts it (τ0 + m τ1)."""
    assert result.limiting_time is not None  # a bounded capacity has its limiting time
    name, time = str(result.limiting_actuator), float(result.limiting_time)
    column = result.names.index(name)
    sample = int(np.argmin(np.abs(result.t - time)))
    entries = []
    for run in runs:
        step = int(np.argmin(np.abs(run.t - time)))
        entries.append(
            {
                **run.as_dict(),
                "fraction": run.mass / result.max_load,
                "at_limiting_time": {
                    "mujoco": float(run.required[step, run.names.index(name)]),
                    "mobman": float(result.torques(run.mass)[sample, column]),
                },
            }
        )
    return {"engine": "mujoco", "limiting_actuator": name, "runs": entries}


def _check_physics(physics: dict) -> None:
    """Exit status 3 unless the first run never saturated and the last one did."""
    below, above = physics["runs"][0], physics["runs"][-1]
    if below["first_saturation"] is not None:
        not_reached(
            "load-capacity",
            f"on MuJoCo {below['fraction']:.0%} of the capacity saturated at t = {below['first_saturation']:.3f} s",
        )
    if above["first_saturation"] is None:
        not_reached("load-capacity", f"on MuJoCo {above['fraction']:.0%} of the capacity never saturated")


def _print(spec_path: Path, spec: LoadSpec, result: LoadCapacity, summary: dict, out: Path | None) -> None:
    load_text = (
        f"{result.max_load:.4f} kg"
        if result.bounded
        else "unbounded (no limited actuator depends on the load)"
    )
    table = Table(title=f"{spec_path.name}: {spec.model.robot.name}, {spec.motion}")
    table.add_column("actuator")
    table.add_column("max load (kg)", justify="right")
    table.add_column("at t (s)", justify="right")
    for name, entry in summary["per_actuator"].items():
        limited = name in spec.actuators
        table.add_row(
            name,
            "unlimited"
            if not limited
            else ("—" if entry["max_load_kg"] is None else f"{entry['max_load_kg']:.4f}"),
            "" if entry["time"] is None else f"{entry['time']:.4f}",
        )
    console = Console()
    console.print(table)
    console.print(f"maximum allowable load: {load_text}")
    if result.bounded:
        console.print(f"limiting actuator: {result.limiting_actuator} at t = {result.limiting_time:.4f} s")
    if "physics" in summary:
        physics = Table(title=f"on MuJoCo: {summary['physics']['limiting_actuator']} at the limiting time")
        for column in (
            "payload (kg)",
            "of capacity",
            "saturated steps",
            "tracking error",
            "τ MuJoCo",
            "τ mobman",
        ):
            physics.add_column(column, justify="right")
        for run in summary["physics"]["runs"]:
            torque = run["at_limiting_time"]
            physics.add_row(
                f"{run['mass_kg']:.4f}",
                f"{run['fraction']:.0%}",
                str(sum(run["saturated_steps"].values())),
                f"{run['tracking_error']:.2e}",
                f"{torque['mujoco']:.4f}",
                f"{torque['mobman']:.4f}",
            )
        console.print(physics)
    if out is not None:
        console.print(f"results: {out / 'results.json'}, figure: {out / 'torques.png'}")
