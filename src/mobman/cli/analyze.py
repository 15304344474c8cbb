"""``mobman analyze``: kinematics, redundancy, singularities and manipulability of a robot at configurations.

For each configuration: the coordinates outside the joint limits (also a warning on standard error;
``--strict-limits`` makes it an error), ξ, J, J̄, the representation-singular flag (the task's coordinates
singular as a representation, distinct from KSC / VSC; quantities that need a finite J̄ are then null where it
is not), their ranks, the singular values of J̄, the KSC / VSC flags with their orders, and w / w2 / w5 of the arm (J_a), the system (J̄) and the normalised system (J̄_N); once per robot the
redundancy report (M, δ, D, R, D̄, R̄). Measures are restricted to the admissible subspace where D̄ < m
(``restricted`` / ``measure_rank`` say so). ``--symbolic`` adds J̄ in closed form and the factored
rank-drop conditions.

Default configuration (no ``--q`` / ``--q-file``): the platform at the origin (all platform coordinates 0)
and arm joint k (k = 1, 2, … within each arm) at 0.5·k rad or m, clipped to the joint limits — a regular
posture of every built-in robot (no joint pair aligned, no VSC).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import typer
from rich.console import Console
from rich.table import Table

from mobman import kinematics as K
from mobman import manipulability as mp
from mobman import redundancy
from mobman.cli.app import app
from mobman.cli.common import UrdfOption, array_text, load_robot, read_configurations, urdf_options
from mobman.cli.limits import STRICT_HELP, outside_limits
from mobman.errors import InputError
from mobman.io import dump_json
from mobman.io.numbers import parse_vector
from mobman.model.robot import MobileManipulator

LEVELS = ("arm", "system", "system_normalized")


def default_configuration(robot: MobileManipulator) -> np.ndarray:
    """Platform at the origin, arm joint k of each arm at 0.5·k (rad or m), clipped to the joint limits."""
    q = np.zeros(robot.n_q)
    for i, arm in enumerate(robot.arms):
        q[robot.arm_slice(i)] = 0.5 * np.arange(1, arm.n_joints + 1)
    lower, upper = np.array(robot.position_limits).T
    return np.clip(q, lower, upper)


def _configurations(robot: MobileManipulator, q: str | None, q_file: Path | None) -> np.ndarray:
    if q is not None and q_file is not None:
        raise InputError("give either --q or --q-file, not both")
    if q_file is not None:
        return read_configurations(q_file, robot)
    if q is not None:
        return parse_vector(q, "--q", robot.n_q)[None, :]
    return default_configuration(robot)[None, :]


def _regular_quantities(robot: MobileManipulator, q: np.ndarray, jbar: np.ndarray) -> list[dict]:
    """Ranks, singular values, KSC / VSC and measures of configurations whose J̄ is finite (one batched call
    per quantity)."""
    d, d_bar = redundancy.ranks(robot, q)
    ksc = redundancy.is_kinematic_singular(robot, q)
    vsc = redundancy.is_velocity_singular(robot, q)
    sigma = np.linalg.svd(jbar, compute_uv=False)
    measures = mp.analyze(robot, q, rank="auto")
    out = []
    for k in range(q.shape[0]):
        manipulability: dict[str, Any] = {
            level: None
            if measures[level] is None
            else {name: float(v[k]) for name, v in measures[level].items()}
            for level in LEVELS
        }
        manipulability["restricted"] = bool(measures["restricted"])
        manipulability["measure_rank"] = measures["ranks"]
        out.append(
            {
                "rank_J": int(d[k]),
                "rank_J_bar": int(d_bar[k]),
                "singular_values": sigma[k],
                "kinematic_singular": bool(ksc.singular[k]),
                "kinematic_singularity_order": int(ksc.order[k]),
                "velocity_singular": bool(vsc.singular[k]),
                "velocity_singularity_order": int(vsc.order[k]),
                "manipulability": manipulability,
            }
        )
    return out


UNDEFINED = dict.fromkeys(
    (
        "rank_J",
        "rank_J_bar",
        "singular_values",
        "kinematic_singular",
        "kinematic_singularity_order",
        "velocity_singular",
        "velocity_singularity_order",
        "manipulability",
    )
)
"""What a configuration whose J or J̄ is not finite (a representation singularity) reports instead: null."""


def analysis(robot: MobileManipulator, q: np.ndarray, outside: list[list[str]] | None = None) -> dict:
    """The JSON-ready analysis of configurations q (n, n_q): one batched call per quantity.

    ``representation_singular`` flags the configurations where the task's coordinates are singular as a
    representation (distinct from KSC and VSC); where J or J̄ is not finite there, the quantities computed
    from them are null. ``outside_limits`` names the coordinates outside the joint limits (``outside``:
    already found by the caller)."""
    report = redundancy.redundancy_report(robot)
    first = K.first_order(robot, q)
    xi, jac, jbar = (np.asarray(first[name]) for name in ("xi", "J", "J_bar"))
    representation = np.asarray(first["representation_singular"], dtype=bool)
    finite = np.isfinite(jac).all(axis=(-2, -1)) & np.isfinite(jbar).all(axis=(-2, -1))
    regular = iter(_regular_quantities(robot, q[finite], jbar[finite]) if finite.any() else ())
    if outside is None:
        outside = [
            [robot.coordinate_names[i] for i in np.flatnonzero(row)] for row in robot.limit_violations(q)
        ]
    results = []
    for k in range(q.shape[0]):
        results.append(
            {
                "q": q[k],
                "outside_limits": outside[k],
                "xi": xi[k],
                "J": jac[k],
                "J_bar": jbar[k],
                "representation_singular": bool(representation[k]),
                **(next(regular) if finite[k] else UNDEFINED),
            }
        )
    return {
        "robot": robot.name,
        "params": dict(robot.parameters),
        "coordinates": list(robot.coordinate_names),
        "controls": list(robot.control_names),
        "task": list(robot.task.names),
        "redundancy": report.as_dict(),
        "results": results,
    }


def symbolic_analysis(robot: MobileManipulator) -> dict:
    """J̄ in closed form and the factored rank-drop conditions (VSC and KSC)."""
    from mobman import symbolic

    model = symbolic.model(robot)
    velocity = symbolic.rank_drop_conditions(robot)
    kinematic = symbolic.rank_drop_conditions(robot, which="kinematic")
    return {
        "coordinates": [str(v) for v in model.q],
        "J_bar": str(model.reduced_jacobian()),
        "J_bar_latex": symbolic.sp.latex(model.reduced_jacobian()),
        "velocity_singular_where": str(velocity.condition),
        "kinematic_singular_where": str(kinematic.condition),
        "_pretty": symbolic.sp.pretty(model.reduced_jacobian(), use_unicode=True, wrap_line=False),
    }


@app.command("analyze")
def analyze_command(
    robot_name: str = typer.Argument(
        ..., metavar="ROBOT", help="A built-in robot (see `mobman robots`), a .toml or a .urdf file."
    ),
    param: list[str] = typer.Option(None, "--param", help="Robot parameter NAME=VALUE (repeatable)."),
    tip: list[str] = UrdfOption.tip,
    base: str = UrdfOption.base,
    platform: str = UrdfOption.platform,
    wheels: str = UrdfOption.wheels,
    lock: list[str] = UrdfOption.lock,
    platform_option: list[str] = UrdfOption.platform_option,
    q: str = typer.Option(
        None, "--q", help="One configuration v1,v2,… in the robot's coordinate order (pi allowed)."
    ),
    q_file: Path = typer.Option(
        None,
        "--q-file",
        help="CSV file: one configuration per row (numbers or expressions such as pi/2), optional header "
        "of the coordinate names.",
    ),
    json_output: bool = typer.Option(False, "--json", help="Print one JSON object."),
    symbolic: bool = typer.Option(
        False, "--symbolic", help="Also give J̄ in closed form and rank-drop conditions."
    ),
    strict_limits: bool = typer.Option(False, "--strict-limits", help=STRICT_HELP),
) -> None:
    """Kinematics, redundancy (M, δ, D, R, D̄, R̄), singularities and manipulability at configurations."""
    robot = load_robot(robot_name, param, urdf_options(tip, base, platform, wheels, lock, platform_option))
    configurations = _configurations(robot, q, q_file)
    field = "--q-file" if q_file is not None else "--q"
    outside = outside_limits(robot, configurations, field, strict_limits)
    result = analysis(robot, configurations, outside)
    if q is None and q_file is None:
        result["default_configuration"] = True
        typer.echo(
            "note: no --q or --q-file: analysing the default configuration (platform at the origin, arm joint k "
            "at 0.5·k rad or m, clipped to its limits)",
            err=True,
        )
    sym = symbolic_analysis(robot) if symbolic else None
    if json_output:
        if sym is not None:
            result["symbolic"] = {k: v for k, v in sym.items() if not k.startswith("_")}
        typer.echo(dump_json(result))
        return
    _print(result, sym)


def _print(result: dict, sym: dict | None) -> None:
    console = Console()
    head = Table(title=f"{result['robot']}", show_header=False)
    head.add_row("parameters", ", ".join(f"{k}={v:g}" for k, v in result["params"].items()) or "—")
    head.add_row("coordinates q", ", ".join(result["coordinates"]))
    head.add_row("controls η", ", ".join(result["controls"]))
    head.add_row("task ξ", ", ".join(result["task"]))
    console.print(head)
    red = Table(title="redundancy (Bayle §3–4)")
    labels = {"M": "M", "delta": "δ", "D": "D", "R": "R", "D_bar": "D̄", "R_bar": "R̄"}
    for key in labels.values():
        red.add_column(key, justify="right")
    red.add_row(*(str(result["redundancy"][k]) for k in labels))
    console.print(red)
    for i, r in enumerate(result["results"], start=1):
        table = Table(title=f"configuration {i}", show_header=False)
        table.add_row("q", array_text(r["q"]))
        table.add_row("outside joint limits", ", ".join(r["outside_limits"]) or "no")
        table.add_row("ξ", array_text(r["xi"]))
        table.add_row("J", array_text(r["J"]))
        table.add_row("J̄", array_text(r["J_bar"]))
        table.add_row("representation singular", str(r["representation_singular"]))
        if r["rank_J"] is None:
            table.add_row(
                "rank, singular values, KSC, VSC", "undefined (J̄ not finite: representation singular)"
            )
            console.print(table)
            continue
        table.add_row("rank J, rank J̄", f"{r['rank_J']}, {r['rank_J_bar']}")
        table.add_row("singular values of J̄", array_text(r["singular_values"], 6))
        table.add_row(
            "kinematic singular (order)", f"{r['kinematic_singular']} ({r['kinematic_singularity_order']})"
        )
        table.add_row(
            "velocity singular (order)", f"{r['velocity_singular']} ({r['velocity_singularity_order']})"
        )
        console.print(table)
        man = r["manipulability"]
        ranks = ", ".join(
            f"{level} {rank}" for level, rank in man["measure_rank"].items() if rank is not None
        )
        note = "restricted to the admissible subspace" if man["restricted"] else "plain"
        mtable = Table(
            title=f"manipulability, configuration {i} ({note}{'; ranks ' + ranks if ranks else ''})"
        )
        for column in ("Jacobian", "w (yoshikawa)", "w2 (inverse condition)", "w5 (eccentricity)"):
            mtable.add_column(column, justify="right")
        for level, label in zip(LEVELS, ("arm J_a", "system J̄", "normalised J̄_N")):
            m = man[level]
            if m is None:
                mtable.add_row(label, "—", "—", "—")
            else:
                mtable.add_row(
                    label, *(f"{m[k]:.6g}" for k in ("yoshikawa", "inverse_condition", "eccentricity"))
                )
        console.print(mtable)
    if sym is not None:
        console.print(f"J̄(q), q = ({', '.join(sym['coordinates'])}):")
        console.print(sym["_pretty"], soft_wrap=True, markup=False, highlight=False)
        console.print(f"velocity singular (d̄ < D̄) where: {sym['velocity_singular_where']}", markup=False)
        console.print(f"kinematic singular (d < D) where: {sym['kinematic_singular_where']}", markup=False)
