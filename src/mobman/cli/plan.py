"""``mobman plan``: endogenous-configuration motion planning (Tchoń et al. 2002) for a built-in robot.

The unknowns are the platform controls over [0, T] (a truncated Fourier series with ``--harmonics``
harmonics per control) and the arm joint positions x; the platform starts at ``--start`` = q_p(0), all its
coordinates (e.g. ``5,0,0,pi/6`` for the car: x, y, θ, φ), default the origin. Initial guess: the constant
term of control i is 0.01·(−1)^i (the paper's λ01 = 0.01, λ02 = −0.01), other coefficients 0, x = ``--x``
(default 0 clipped to the joint limits).
"""

from __future__ import annotations

import math
from pathlib import Path

import jax.numpy as jnp
import numpy as np
import typer
from rich.console import Console
from rich.table import Table

from mobman.cli import app
from mobman.cli.common import load_robot, parse_vector
from mobman.errors import InputError
from mobman.io import dump_json, trajectories
from mobman.model.robot import MobileManipulator
from mobman.model.task import FunctionTask
from mobman.planning.algorithms import ALGORITHMS, Options, plan
from mobman.planning.basis import Fourier
from mobman.planning.endpoint import PlanningSetting, configuration_path, dexterity
from mobman.planning.figures import plot_convergence, plot_paths

DEFAULT_EXTENSIONS = {"tchon-car-rtr": "q[6], q[2] + q[4]"}
"""The paper's ȳ = (x3, q3 + x1) for the car + RTR arm (q = (q1, q2, q3, q4, x1, x2, x3), 0-based)."""

_FUNCTIONS = {
    "sin": jnp.sin,
    "cos": jnp.cos,
    "tan": jnp.tan,
    "atan2": jnp.arctan2,
    "sqrt": jnp.sqrt,
    "pi": math.pi,
}


def extension_task(text: str) -> FunctionTask:
    """An output extension h(q) from comma-separated expressions of q (0-based, platform first)."""
    items = [item.strip() for item in text.split(",") if item.strip()]
    if not items:
        raise InputError("--extension: give one or more expressions of q, e.g. 'q[6], q[2] + q[4]'")
    code = []
    for item in items:
        try:
            code.append(compile(item, "--extension", "eval"))
        except SyntaxError:
            raise InputError(f"--extension: {item!r} is not an expression of q") from None

    def h(q):
        return jnp.stack(
            [
                jnp.asarray(eval(c, {"__builtins__": {}}, {**_FUNCTIONS, "q": q}))  # noqa: S307
                for c in code
            ]
        )

    return FunctionTask(h, tuple(items))


def initial_configuration(setting: PlanningSetting, x0: np.ndarray) -> np.ndarray:
    lam = np.zeros((setting.n_controls, setting.basis.size))
    lam[:, 0] = 0.01 * (-1.0) ** np.arange(setting.n_controls)
    return np.concatenate([lam.reshape(-1), x0])


def _joints(robot: MobileManipulator, text: str | None) -> np.ndarray:
    p = robot.n_q - robot.platform.n_q
    if text is not None:
        return parse_vector(text, "--x", p)
    lower, upper = np.array(robot.position_limits[robot.platform.n_q :]).reshape(p, 2).T
    return np.clip(np.zeros(p), lower, upper)


def _step(text: str) -> float | str:
    if text == "adaptive":
        return text
    try:
        value = float(text)
    except ValueError:
        raise InputError(f"--step: expected a number > 0 or 'adaptive', got {text!r}") from None
    if not (math.isfinite(value) and value > 0):
        raise InputError(f"--step: expected a number > 0 or 'adaptive', got {text!r}")
    return value


@app.command("plan")
def plan_command(
    robot_name: str = typer.Argument(..., metavar="ROBOT", help="built-in robot (see `mobman robots`)"),
    target: str = typer.Option(..., "--target", help="Desired task value y_d at time T, e.g. 0,0,1."),
    algorithm: str = typer.Option("pinv", "--algorithm", help=f"one of {', '.join(ALGORITHMS)}"),
    horizon: float = typer.Option(1.0, "--horizon", help="Control horizon T > 0."),
    harmonics: int = typer.Option(2, "--harmonics", help="Fourier harmonics per control (≥ 0)."),
    start: str | None = typer.Option(None, "--start", help="Platform start pose q_p(0), e.g. 5,0,0,pi/6."),
    joints: str | None = typer.Option(None, "--x", help="Initial arm joint positions x0."),
    step: str = typer.Option("1", "--step", help="Continuation step Δθ (1 = Newton) or 'adaptive'."),
    gamma: float = typer.Option(1.0, "--gamma", help="Rate γ > 0."),
    tol: float = typer.Option(1e-12, "--tol", help="Stop when ‖K − y_d‖ ≤ tol."),
    max_iterations: int = typer.Option(200, "--max-iterations", help="Iteration cap."),
    extension: str | None = typer.Option(
        None, "--extension", help="Output extension h(q) for 'extended', e.g. 'q[6], q[2]+q[4]'."
    ),
    params: list[str] | None = typer.Option(None, "--param", help="Robot parameter NAME=VALUE."),
    json_output: bool = typer.Option(False, "--json", help="Print one JSON object."),
    out: Path | None = typer.Option(None, "--out", help="Folder for the path and convergence figures."),
) -> None:
    """Plan platform controls and arm joint positions that bring the task to --target at time T."""
    if algorithm not in ALGORITHMS:
        raise InputError(f"--algorithm must be one of {', '.join(ALGORITHMS)}, got {algorithm!r}")
    if not (math.isfinite(horizon) and horizon > 0):
        raise InputError(f"--horizon must be a finite number > 0, got {horizon}")
    if harmonics < 0:
        raise InputError(f"--harmonics must be ≥ 0, got {harmonics}")
    robot = load_robot(robot_name, params)
    setting = PlanningSetting(robot, Fourier(harmonics), horizon=horizon)
    y_d = parse_vector(target, "--target", setting.output.dim)
    q0 = (
        parse_vector(start, "--start", robot.platform.n_q)
        if start is not None
        else np.zeros(robot.platform.n_q)
    )
    z0 = initial_configuration(setting, _joints(robot, joints))
    ext = None
    if algorithm == "extended":
        text = extension if extension is not None else DEFAULT_EXTENSIONS.get(robot_name)
        if text is None:
            raise InputError("--algorithm extended needs --extension (expressions of q) for this robot")
        ext = extension_task(text)
    options = Options(
        algorithm, _step(step), gamma=gamma, tol=tol, max_iterations=max_iterations, extension=ext
    )
    result = plan(setting, z0, q0, y_d, options)
    coarse = setting.jacobian_setting
    d0, d1 = dexterity(coarse, z0, q0), dexterity(coarse, result.z, q0)
    report = {
        "robot": robot_name,
        "algorithm": algorithm,
        "step": options.step,
        "horizon": horizon,
        "harmonics": harmonics,
        "start": q0,
        "target": y_d,
        "status": result.status,
        "converged": result.converged,
        "iterations": result.iterations,
        "final_error": result.final_error,
        "dexterity_start": d0,
        "dexterity_end": d1,
        "lambda": result.lam,
        "x": result.x,
        "error_history": result.errors,
    }
    if out is not None:
        out.mkdir(parents=True, exist_ok=True)
        t, q = configuration_path(setting, result.z, q0)
        trajectories.write(out, [trajectories.Motion.of(f"{algorithm}, {result.status}", robot, t, q)])
        report["figures"] = [
            str(p)
            for p in (
                plot_paths(
                    setting,
                    result.z,
                    q0,
                    y_d,
                    f"{robot_name}: {algorithm}, {result.status}",
                    out / "paths.png",
                ),
                plot_convergence(
                    {algorithm: result.errors}, tol, f"{robot_name}: convergence", out / "convergence.png"
                ),
            )
        ]
    if json_output:
        typer.echo(dump_json(report))
        return
    table = Table(title=f"mobman plan {robot_name} ({algorithm}, Δθ = {options.step})")
    table.add_column("quantity")
    table.add_column("value", overflow="fold")
    for key in ("status", "iterations", "final_error", "dexterity_start", "dexterity_end"):
        value = report[key]
        table.add_row(key, f"{value:.3e}" if isinstance(value, float) else str(value))
    table.add_row("lambda", np.array2string(result.lam, precision=4))
    table.add_row("x", np.array2string(result.x, precision=4))
    for f in report.get("figures", []):
        table.add_row("figure", f)
    Console().print(table)
