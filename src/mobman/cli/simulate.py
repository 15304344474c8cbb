"""``mobman simulate SPEC.toml``: closed-loop simulation of an operational task (see mobman.control.spec);
``mobman simulate ROBOT --target x,y,z[,roll,pitch,yaw]``: the same without a file, toward a point or a pose of
the tool (:func:`target_spec`).

A run reaches its goal when its final tracking error ‖ξ*(T) − ξ(T)‖ is at most ``--tolerance`` (default
:data:`TOLERANCE`, in the task's units: m for positions, rad for angles); one that does not ends with one line
saying by how much, and exit status 3, its results printed and written.

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

from mobman.cli import collisions
from mobman.cli.app import app
from mobman.cli.common import (
    MAX_STEPS,
    UrdfOption,
    check_disk,
    check_steps,
    load_robot,
    not_reached,
    progress_bar,
    refuse_urdf_options,
    urdf_options,
)
from mobman.cli.limits import STRICT_HELP, outside_limits
from mobman.errors import InputError
from mobman.io import dump_json, trajectories
from mobman.io.numbers import parse_vector
from mobman.io.output import check_folder, results_folder, save_figure, write_text
from mobman.model.tasks import MountPosition, OrientationTask, Position

if TYPE_CHECKING:
    from mobman.control.simulation import SimulationResult
    from mobman.control.spec import Spec
    from mobman.model.robot import MobileManipulator
    from mobman.model.tasks import Task
    from mobman.physics.run import SpecRun

PROGRESS_STEPS = 5000
"""Runs with more steps than this show a progress bar (computed in compiled chunks)."""

STREAM_STEPS = 100_000
"""Runs with more steps than this are computed and written in pieces of this many samples."""

PLOT_SAMPLES = 10_000
"""Most samples drawn in the figures (and saved in ``trajectories.json``) of a run computed in pieces."""


TOLERANCE = 1e-3
"""Default ``--tolerance``: the largest final tracking error of a run that reaches its goal (1 mm, 1 mrad)."""

TARGET_LAWS = ("qp", "bayle")
"""The laws of ``simulate ROBOT --target``: the QP law within the robot's limits, or Bayle's (eq. 5–6)."""

TARGET_DURATION, TARGET_DT = 10.0, 0.01
"""``simulate ROBOT --target``'s ``--duration`` and ``--dt`` (s) when not given (``--law``: the first of
:data:`TARGET_LAWS`)."""

TARGET_GAIN = 2.0
"""W (1/s) of ``simulate ROBOT --target``: a lag left when the reference stops decays as exp(−W t)."""

TARGET_DAMPING = 0.05
"""λ_max of Bayle's law in ``simulate ROBOT --target``: damped least squares where σ_min < 0.05 only (a
target out of reach stretches the arm into a singular configuration)."""


def default_configuration(robot: MobileManipulator) -> np.ndarray:
    """The robot's default configuration: every coordinate at 0, clipped to its joint limits."""
    lower, upper = np.asarray(robot.position_limits, dtype=float).T
    return np.clip(np.zeros(robot.n_q), lower, upper)


def target_spec(
    robot: MobileManipulator, target: np.ndarray, q0: np.ndarray, law: str, duration: float, dt: float
) -> Spec:
    """The run of ``simulate ROBOT --target``, as the specification document it stands for
    (:func:`mobman.control.spec.parse`): the tool of the first arm (a ``position`` task x, y, z for 3 values
    of ``target``, a ``pose`` task for 6: x, y, z, roll, pitch, yaw with R = Rz(yaw) Ry(pitch) Rx(roll))
    moved from its pose at ``q0`` to the target in the first half of ``duration`` (a ``line`` or ``pose``
    reference with quintic timing), then held there; ``law`` (one of :data:`TARGET_LAWS`) with
    W = :data:`TARGET_GAIN` and no self-motion."""
    from mobman import kinematics
    from mobman.control import spec
    from mobman.model.tasks import Pose

    if law not in TARGET_LAWS:
        raise InputError(f"--law must be one of {', '.join(TARGET_LAWS)}, got {law!r}")
    for name, value in (("--duration", duration), ("--dt", dt)):
        if not (math.isfinite(value) and value > 0):
            raise InputError(f"{name} must be a finite number > 0 s, got {value!r}")
    motion = {"duration": duration / 2, "timing": "quintic"}
    if len(target) == 3:
        start = np.asarray(kinematics.forward(robot, q0, Position("xyz")))
        task = {"kind": "position", "components": "xyz"}
        reference = {"kind": "line", "start": start.tolist(), "end": target.tolist(), **motion}
    else:
        start = np.asarray(kinematics.forward(robot, q0, Pose()))
        task = {"kind": "pose"}
        reference = {
            "kind": "pose",
            "start": start[:3].tolist(),
            "start_rotvec": start[3:].tolist(),
            "end": target[:3].tolist(),
            "end_rpy": target[3:].tolist(),
            **motion,
        }
    options = {"damping": TARGET_DAMPING} if law == "bayle" else {}
    document = {
        "duration": duration,
        "dt": dt,
        "q0": q0.tolist(),
        "task": task,
        "reference": reference,
        "law": {"kind": law, **options},
        "gains": {"W": TARGET_GAIN},
    }
    return spec.parse(document, robot=robot)


def _unit(task: Task) -> str:
    """The unit of a task's error, with its leading space: m for positions, rad for angles, none for others
    (a pose's error holds both)."""
    if isinstance(task, (Position, MountPosition)):
        return " m"
    return " rad" if isinstance(task, OrientationTask) else ""


def _judge(summary: dict, tolerance: float) -> None:
    """Add to a run's metrics the ``tolerance`` and whether the run ``reached`` its goal: a finite final state
    and a final tracking error within the tolerance."""
    final = summary["final_error"]
    finite = bool(np.all(np.isfinite(summary["q_final"]))) and math.isfinite(final)
    summary["tolerance"] = tolerance
    summary["reached"] = finite and final <= tolerance


def _not_reached(summary: dict, unit: str, samples: int) -> None:
    """End a run that did not reach its goal (:func:`_judge`): one line, by how much and what held it back."""
    if not np.all(np.isfinite(summary["q_final"])):
        not_reached("simulate", "not reached: the state left the finite numbers")
    saturated = summary["saturated_steps"]
    cause = f"; the limits cut the controls at {saturated} of {samples} samples" if saturated else ""
    not_reached(
        "simulate",
        f"not reached: final error {summary['final_error']:.3g}{unit} > tolerance {summary['tolerance']:g}"
        f"{unit}{cause}",
    )


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
        **{name: result.info[name] for name in ("min_distance",) if name in result.info},
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


def _figures(out: Path, name: str, result: SimulationResult) -> list[Path]:
    from mobman.viz import plot_paths, plot_timeseries

    assert result.robot is not None  # a run of simulate() records its robot
    trajectories.write(out, [trajectories.Motion.of(name, result.robot, result.t, result.q)])
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


def _write(out: Path, source: dict, name: str, result: SimulationResult, summary: dict) -> list[Path]:
    """``results.json`` (``source``: what the run was made from, the metrics, the series) and the figures."""
    write_text(out / "results.json", dump_json({**source, "metrics": summary, "series": _series(result)}))
    return _figures(out, name, result)


def _write_physics(out: Path, source: dict, name: str, run: SpecRun, summary: dict) -> list[Path]:
    """The results of a run on physics (:mod:`mobman.cli.physics_run`): :func:`_write`'s, with the physics
    series and names in ``results.json`` and ``physics.png``."""
    from mobman.cli.physics_run import physics_figure

    series = {**_series(run.result), "physics": run.series}
    names = {"wheels": run.wheels, "actuators": run.actuators}
    document = {**source, "physics": names, "metrics": summary, "series": series}
    write_text(out / "results.json", dump_json(document))
    physics_figure(out / "physics.png", run)
    return [*_figures(out, name, run.result), out / "physics.png"]


def _write_streamed(out: Path, source: dict, name: str, spec: Spec, summary: dict) -> list[Path]:
    samples = _steps(spec)
    result, stride = _decimated(out, spec, samples)
    files: dict[str, str | dict[str, str]] = {
        name: f"{name}.npy" for name in _series(result) if name != "measures"
    }
    files["measures"] = {name: f"measures_{name}.npy" for name in spec.measures}
    document = {
        **source,
        "metrics": summary,
        "samples": samples,
        "series": files,
        "figure_stride": stride,
    }
    write_text(out / "results.json", dump_json(document))
    return _figures(out, name, result)


@app.command("simulate")
def simulate_command(
    source: str = typer.Argument(
        ...,
        metavar="SPEC.toml | ROBOT",
        help="A TOML specification (docs/control.md); with --target, a robot: built-in (see `mobman robots`), "
        "a .toml or a .urdf file.",
    ),
    target: str | None = typer.Option(
        None,
        "--target",
        help="Simulate ROBOT toward the tool target x,y,z (m) or x,y,z,roll,pitch,yaw (m, rad), without a spec.",
    ),
    q: str | None = typer.Option(
        None, "--q", help="With --target: the start configuration (default: 0 clipped to the joint limits)."
    ),
    law: str | None = typer.Option(None, "--law", help="With --target: qp (the default) or bayle."),
    duration: float | None = typer.Option(
        None,
        "--duration",
        help="With --target: the run's length (s, default 10); the reference moves for half.",
    ),
    dt: float | None = typer.Option(None, "--dt", help="With --target: the time step (s, default 0.01)."),
    tolerance: float = typer.Option(
        TOLERANCE,
        "--tolerance",
        help="Largest final tracking error ‖ξ* − ξ‖ of a run that reaches its goal (m for positions, rad for "
        "angles); above it, exit 3.",
    ),
    params: list[str] | None = typer.Option(
        None, "--param", help="With --target: robot parameter NAME=VALUE."
    ),
    tip: list[str] | None = UrdfOption.tip,
    base: str | None = UrdfOption.base,
    platform: str | None = UrdfOption.platform,
    wheels: str | None = UrdfOption.wheels,
    lock: list[str] | None = UrdfOption.lock,
    platform_option: list[str] | None = UrdfOption.platform_option,
    out: Path | None = typer.Option(None, "--out", help="Write results.json and figures into this folder."),
    json_output: bool = typer.Option(False, "--json", help="Print the metrics as one JSON object."),
    max_steps: int = typer.Option(
        MAX_STEPS, "--max-steps", help="Refuse runs of more time steps than this (duration / dt)."
    ),
    strict_limits: bool = typer.Option(False, "--strict-limits", help=STRICT_HELP),
    scene: Path | None = typer.Option(
        None, "--scene", help="Scene file (TOML) whose obstacles the qp law avoids (docs/collision.md)."
    ),
    physics: str | None = typer.Option(
        None, "--physics", help="Run on a physics engine: mujoco (docs/physics.md; or the spec's [physics])."
    ),
) -> None:
    """Simulate a control law tracking an operational reference (a spec file, or ROBOT --target); print the
    run's metrics. Exit 3 when the final tracking error is above --tolerance."""
    from mobman.cli import physics_run
    from mobman.control import metrics, spec

    if not (math.isfinite(tolerance) and tolerance > 0):
        raise InputError(f"--tolerance must be a finite number > 0 (m or rad), got {tolerance!r}")
    urdf = urdf_options(tip, base, platform, wheels, lock, platform_option)
    given = {"--q": q, "--law": law, "--duration": duration, "--dt": dt, "--param": params or None}
    extra: dict = {}
    if target is None:
        refuse_urdf_options(urdf, "a spec file (give ROBOT and --target)")
        if any(value is not None for value in given.values()):
            flags = ", ".join(name for name, value in given.items() if value is not None)
            raise InputError(f"{flags}: only with ROBOT --target; a spec file sets them itself")
        if not (source.endswith(".toml") or Path(source).is_file()):
            raise InputError(
                f"{source!r} is not a spec file (SPEC.toml); to simulate a robot toward a target, give "
                "--target x,y,z or x,y,z,roll,pitch,yaw"
            )
        parsed = spec.load(Path(source))
        name, title, origin = Path(source).stem, Path(source).name, {"spec": source}
    else:
        robot = load_robot(source, params, urdf)
        start = parse_vector(q, "--q", robot.n_q) if q is not None else default_configuration(robot)
        goal = parse_vector(target, "--target", None)
        if goal.size not in (3, 6):
            raise InputError(
                f"--target: 3 values x,y,z (m) or 6 x,y,z,roll,pitch,yaw (m, rad), got {goal.size}"
            )
        kind = TARGET_LAWS[0] if law is None else law
        length = TARGET_DURATION if duration is None else duration
        parsed = target_spec(robot, goal, start, kind, length, TARGET_DT if dt is None else dt)
        name = title = f"{source} to {target}"
        origin = extra = {
            "robot": source,
            "target": goal.tolist(),
            "q0": start.tolist(),
            "law": kind,
        }
    parsed, said = collisions.prepare(parsed, scene)
    extra = {**extra, **said}
    steps = _steps(parsed)
    streamed = steps > STREAM_STEPS
    check_steps(steps, _values_per_step(parsed), "duration / dt", max_steps, held=min(steps, STREAM_STEPS))
    outside = outside_limits(parsed.robot, parsed.q0[None], "q0", strict_limits)[0]
    on_physics = physics_run.prepare(physics, parsed, source, target is None, urdf)
    if out is not None:
        check_folder(out, "simulate")
        if streamed:  # the time series go to files: 8 bytes a value
            check_disk(out, steps * _values_per_step(parsed) * 8)
    if on_physics is not None:
        summary, physics_record = physics_run.run_physics(parsed, *on_physics)
        summary["outside_limits"] = outside
        summary |= extra
        _judge(summary, tolerance)
        if out is not None:
            with results_folder(out, "simulate") as staging:
                _write_physics(staging, origin, name, physics_record, summary)
    elif streamed:
        folder = results_folder(out, "simulate") if out is not None else contextlib.nullcontext(None)
        with folder as staging:
            summary, last = stream(parsed, staging, quiet=json_output, chunk=STREAM_STEPS)
            summary["q_final"] = np.asarray(last.q[-1]).tolist()
            summary["outside_limits"] = outside
            summary |= extra
            _judge(summary, tolerance)
            if staging is not None:
                _write_streamed(staging, origin, name, parsed, summary)
    else:
        result = _run(parsed, quiet=json_output)
        summary = metrics.summarize(result, parsed.robot)
        summary["q_final"] = result.q[-1].tolist()
        summary["outside_limits"] = outside
        summary |= extra
        _judge(summary, tolerance)
        if out is not None:
            with results_folder(out, "simulate") as staging:
                _write(staging, origin, name, result, summary)
    if json_output:
        typer.echo(dump_json(summary))
    else:
        _print(title, parsed, steps, summary, out)
    if summary.get("stopped"):
        not_reached("simulate", f"the physics run stopped at {summary['stopped']}")
    if not summary["reached"]:
        _not_reached(summary, _unit(parsed.law.controlled_task(parsed.task)), steps)


def _print(name: str, parsed: Spec, samples: int, summary: dict, out: Path | None) -> None:
    table = Table(title=f"{name}: {parsed.robot.name}, {samples} samples")
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
