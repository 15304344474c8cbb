"""``mobman simulate SPEC.toml``: closed-loop simulation of an operational task (see mobman.control.spec)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import typer
from rich.console import Console
from rich.progress import BarColumn, Progress, TextColumn, TimeRemainingColumn
from rich.table import Table

from mobman.cli.app import app
from mobman.cli.common import MAX_STEPS, check_steps, not_reached
from mobman.io import dump_json, trajectories
from mobman.io.output import check_folder, results_folder, save_figure, write_text

PROGRESS_STEPS = 5000
"""Runs with more steps than this show a progress bar (computed in compiled chunks)."""


def _steps(spec) -> int:
    return int(round(spec.duration / spec.dt)) + 1


def _values_per_step(spec) -> int:
    """Floats stored per time step: q, η (and the law's diagnostics), ξ, ξ*, the error, the measures."""
    robot = spec.robot
    return 2 * robot.n_q + 3 * robot.n_eta + 3 * spec.task.dim + len(spec.measures) + 4


def _run(spec, quiet: bool):
    from mobman.control import simulate

    args = (spec.robot, spec.task, spec.law, spec.reference, spec.q0, spec.duration, spec.dt)
    kwargs = {"measures": spec.measures, "integrator": spec.integrator}
    steps = _steps(spec)
    if quiet or steps <= PROGRESS_STEPS:
        return simulate(*args, **kwargs)
    columns = (
        TextColumn("simulating"),
        BarColumn(),
        TextColumn("{task.percentage:>3.0f}%"),
        TimeRemainingColumn(),
    )
    with Progress(*columns, console=Console(stderr=True), transient=True) as progress:
        bar = progress.add_task("simulate", total=1.0)
        return simulate(*args, **kwargs, progress=lambda f: progress.update(bar, completed=f))


def _write(out: Path, spec_path: Path, result, summary: dict) -> list[Path]:
    from mobman.viz import plot_paths, plot_timeseries

    series = {
        "t": result.t,
        "q": result.q,
        "eta": result.eta,
        "xi": result.xi,
        "xi_star": result.xi_star,
        "error": result.error,
        "measures": result.measures,
        "saturated": result.saturated,
        "damped": result.damped,
    }
    write_text(
        out / "results.json", dump_json({"spec": str(spec_path), "metrics": summary, "series": series})
    )
    trajectories.write(out, [trajectories.Motion.of(spec_path.stem, result.robot, result.t, result.q)])
    figures = [out / "paths.png", out / "timeseries.png"]
    save_figure(plot_paths(result.robot, result.q, reference=result.xi_star[:, :2]), figures[0], dpi=120)
    panels = {
        "‖ξ* − ξ‖": {"error": np.linalg.norm(result.error, axis=-1)},
        "η": {name: result.eta[:, i] for i, name in enumerate(result.robot.control_names)},
    }
    if result.measures:
        panels["measures"] = dict(result.measures)
    save_figure(plot_timeseries(result.t, panels), figures[1], dpi=120)
    return figures


@app.command("simulate")
def simulate_command(
    spec_path: Path = typer.Argument(..., metavar="SPEC.toml", help="TOML specification (docs/control.md)."),
    out: Path | None = typer.Option(None, "--out", help="Write results.json and figures into this folder."),
    json_output: bool = typer.Option(False, "--json", help="Print the metrics as one JSON object."),
    max_steps: int = typer.Option(
        MAX_STEPS, "--max-steps", help="Refuse runs of more time steps than this (duration / dt)."
    ),
) -> None:
    """Simulate a control law tracking an operational reference; print the run's metrics."""
    from mobman.control import metrics, spec

    parsed = spec.load(spec_path)
    check_steps(_steps(parsed), _values_per_step(parsed), "duration / dt", max_steps)
    if out is not None:
        check_folder(out, "simulate")
    result = _run(parsed, quiet=json_output)
    summary = metrics.summarize(result, parsed.robot)
    summary["q_final"] = result.q[-1].tolist()
    if out is not None:
        with results_folder(out, "simulate") as staging:
            _write(staging, spec_path, result, summary)
    if json_output:
        typer.echo(dump_json(summary))
    else:
        _print(spec_path, parsed, result, summary, out)
    saturated = summary["saturated_steps"]
    if saturated or not np.all(np.isfinite(result.q)):
        reason = f"the controls saturated at {saturated} of {len(result.t)} samples" if saturated else ""
        not_reached("simulate", reason or "the state left the finite numbers")


def _print(spec_path: Path, parsed, result, summary: dict, out: Path | None) -> None:
    table = Table(title=f"{spec_path.name}: {parsed.robot.name}, {len(result.t)} samples")
    table.add_column("metric")
    table.add_column("value", justify="right")
    for key, value in summary.items():
        shown = (
            ", ".join(f"{v:.4g}" for v in value)
            if isinstance(value, list)
            else (f"{value:.4g}" if isinstance(value, float) else str(value))
        )
        table.add_row(key, shown)
    Console().print(table)
    if out is not None:
        Console().print(f"results: {out / 'results.json'}")
