"""``mobman simulate SPEC.toml``: closed-loop simulation of an operational task (see mobman.control.spec).

A run of more than :data:`STREAM_STEPS` steps is computed in pieces of that many samples, one after the other
(:func:`mobman.control.simulate_pieces`), so that memory holds one piece: the metrics are accumulated piece by
piece and, with ``--out``, each time series is appended to a NumPy file ``NAME.npy`` of the results folder
(``results.json`` names the files); the figures and ``trajectories.json`` of such a run show every k-th sample
(at most :data:`PLOT_SAMPLES`).

An initial configuration ``q0`` outside the robot's joint limits gives a warning line (``outside_limits`` in the
metrics); ``--strict-limits`` makes it an error (exit 2).
"""

from __future__ import annotations

import contextlib
import math
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
import typer
from rich.console import Console
from rich.table import Table

from mobman.cli.app import app
from mobman.cli.common import MAX_STEPS, check_disk, check_steps, not_reached, progress_bar
from mobman.cli.limits import STRICT_HELP, outside_limits
from mobman.io import dump_json, trajectories
from mobman.io.output import check_folder, results_folder, save_figure, write_text

if TYPE_CHECKING:
    from mobman.control.simulation import SimulationResult
    from mobman.control.spec import Spec

PROGRESS_STEPS = 5000
"""Runs with more steps than this show a progress bar (computed in compiled chunks)."""

STREAM_STEPS = 100_000
"""Runs with more steps than this are computed and written in pieces of this many samples."""

PLOT_SAMPLES = 10_000
"""Most samples drawn in the figures (and saved in ``trajectories.json``) of a run computed in pieces."""


def _steps(spec: Spec) -> int:
    return int(round(spec.duration / spec.dt)) + 1


def _values_per_step(spec: Spec) -> int:
    """Floats stored per time step: q, η (and the law's diagnostics), ξ, ξ*, the error, the measures."""
    robot = spec.robot
    return 2 * robot.n_q + 3 * robot.n_eta + 3 * spec.task.dim + len(spec.measures) + 4


def _run(spec: Spec, quiet: bool) -> SimulationResult:
    with progress_bar("simulating", not quiet and _steps(spec) > PROGRESS_STEPS) as progress:
        return spec.simulate(progress)


def _series(result: SimulationResult) -> dict:
    """The time series of a run that results.json holds, by name (``measures``: a table of them)."""
    return {
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


def _files(series: dict) -> dict:
    """The time series by the stem of their NumPy file: ``NAME``, ``measures_NAME`` for a measure."""
    flat = {name: values for name, values in series.items() if name != "measures"}
    return {**flat, **{f"measures_{name}": values for name, values in series["measures"].items()}}


def stream(
    spec: Spec, folder: Path | None, quiet: bool = True, chunk: int = STREAM_STEPS
) -> tuple[dict, SimulationResult]:
    """Run ``spec`` in pieces of ``chunk`` samples; with a ``folder``, append each time series to
    ``folder/NAME.npy``. Returns the run's metrics and the run's last piece."""
    from mobman.control import metrics, simulate_pieces

    n = _steps(spec)
    summary = metrics.RunningSummary(spec.robot)
    files: dict[str, np.memmap] = {}
    piece, k0 = None, 0
    with progress_bar("simulating", not quiet) as progress:
        for piece in simulate_pieces(**spec.arguments(), chunk=chunk):
            summary.add(piece)
            if folder is not None:
                for name, values in _files(_series(piece)).items():
                    values = np.asarray(values)
                    if name not in files:
                        files[name] = np.lib.format.open_memmap(
                            folder / f"{name}.npy",
                            mode="w+",
                            dtype=values.dtype,
                            shape=(n, *values.shape[1:]),
                        )
                    files[name][k0 : k0 + len(values)] = values
            k0 += len(piece.t)
            if progress is not None:
                progress(k0 / n)
    for array in files.values():
        array.flush()
    files.clear()  # closes the files
    assert piece is not None  # a run has at least one piece
    return summary.metrics(), piece


def _decimated(folder: Path, spec: Spec, samples: int) -> tuple[SimulationResult, int]:
    """Every k-th sample (and the last) of a run written in pieces into ``folder``, as a result to draw."""
    from mobman.control.simulation import SimulationResult

    stride = max(1, math.ceil(samples / PLOT_SAMPLES))
    rows = np.unique(np.append(np.arange(0, samples, stride), samples - 1))

    def read(name: str) -> np.ndarray:
        return np.asarray(np.load(folder / f"{name}.npy", mmap_mode="r")[rows])

    measures = {name: read(f"measures_{name}") for name in spec.measures}
    return SimulationResult(
        read("t"),
        read("q"),
        read("eta"),
        read("xi"),
        read("xi_star"),
        read("error"),
        measures,
        read("saturated"),
        read("damped"),
        robot=spec.robot,
        task=spec.task,
    ), stride


def _figures(out: Path, spec_path: Path, result: SimulationResult) -> list[Path]:
    from mobman.viz import plot_paths, plot_timeseries

    assert result.robot is not None  # a run of simulate() records its robot
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


def _write(out: Path, spec_path: Path, result: SimulationResult, summary: dict) -> list[Path]:
    write_text(
        out / "results.json",
        dump_json({"spec": str(spec_path), "metrics": summary, "series": _series(result)}),
    )
    return _figures(out, spec_path, result)


def _write_streamed(out: Path, spec_path: Path, spec: Spec, summary: dict) -> list[Path]:
    samples = _steps(spec)
    result, stride = _decimated(out, spec, samples)
    files: dict[str, str | dict[str, str]] = {
        name: f"{name}.npy" for name in _series(result) if name != "measures"
    }
    files["measures"] = {name: f"measures_{name}.npy" for name in spec.measures}
    document = {
        "spec": str(spec_path),
        "metrics": summary,
        "samples": samples,
        "series": files,
        "figure_stride": stride,
    }
    write_text(out / "results.json", dump_json(document))
    return _figures(out, spec_path, result)


@app.command("simulate")
def simulate_command(
    spec_path: Path = typer.Argument(..., metavar="SPEC.toml", help="TOML specification (docs/control.md)."),
    out: Path | None = typer.Option(None, "--out", help="Write results.json and figures into this folder."),
    json_output: bool = typer.Option(False, "--json", help="Print the metrics as one JSON object."),
    max_steps: int = typer.Option(
        MAX_STEPS, "--max-steps", help="Refuse runs of more time steps than this (duration / dt)."
    ),
    strict_limits: bool = typer.Option(False, "--strict-limits", help=STRICT_HELP),
) -> None:
    """Simulate a control law tracking an operational reference; print the run's metrics."""
    from mobman.control import metrics, spec

    parsed = spec.load(spec_path)
    steps = _steps(parsed)
    streamed = steps > STREAM_STEPS
    check_steps(steps, _values_per_step(parsed), "duration / dt", max_steps, held=min(steps, STREAM_STEPS))
    outside = outside_limits(parsed.robot, parsed.q0[None], "q0", strict_limits)[0]
    if out is not None:
        check_folder(out, "simulate")
        if streamed:  # the time series go to files: 8 bytes a value
            check_disk(out, steps * _values_per_step(parsed) * 8)
    if streamed:
        folder = results_folder(out, "simulate") if out is not None else contextlib.nullcontext(None)
        with folder as staging:
            summary, last = stream(parsed, staging, quiet=json_output, chunk=STREAM_STEPS)
            summary["q_final"] = np.asarray(last.q[-1]).tolist()
            summary["outside_limits"] = outside
            if staging is not None:
                _write_streamed(staging, spec_path, parsed, summary)
    else:
        result = _run(parsed, quiet=json_output)
        summary = metrics.summarize(result, parsed.robot)
        summary["q_final"] = result.q[-1].tolist()
        summary["outside_limits"] = outside
        if out is not None:
            with results_folder(out, "simulate") as staging:
                _write(staging, spec_path, result, summary)
    if json_output:
        typer.echo(dump_json(summary))
    else:
        _print(spec_path, parsed, steps, summary, out)
    saturated = summary["saturated_steps"]
    if saturated or not np.all(np.isfinite(summary["q_final"])):
        reason = f"the controls saturated at {saturated} of {steps} samples" if saturated else ""
        not_reached("simulate", reason or "the state left the finite numbers")


def _print(spec_path: Path, parsed: Spec, samples: int, summary: dict, out: Path | None) -> None:
    table = Table(title=f"{spec_path.name}: {parsed.robot.name}, {samples} samples")
    table.add_column("metric")
    table.add_column("value", justify="right")
    for key, value in summary.items():
        shown = (
            (", ".join(f"{v:.4g}" if isinstance(v, float) else str(v) for v in value) or "none")
            if isinstance(value, list)
            else (f"{value:.4g}" if isinstance(value, float) else str(value))
        )
        table.add_row(key, shown)
    Console().print(table)
    if out is not None:
        Console().print(f"results: {out / 'results.json'}")
