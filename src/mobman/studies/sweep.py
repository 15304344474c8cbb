"""Design sweeps: a robot's parameters varied over a grid, each design scored.

Every combination of the values given for the parameters is one design. The parameters are those of the
robot's constructor for a built-in robot (link lengths, offsets, velocity limits: the keyword parameters of a
robot of :mod:`mobman.model.robots`, as ``mobman robots`` lists them) and, for every robot, built-in or read
from a file, the pose of the scored arm's mount in the platform frame (:data:`mobman.model.robots.MOUNT`:
``mount.x``, ``mount.y``, ``mount.z`` in m and ``mount.yaw``, ``mount.pitch``, ``mount.roll`` in rad, each
replacing the robot's own value):
where to fix the arm on the platform. A robot read from a URDF file has its arm mounted at the platform
frame's origin, so there they are offsets from the file's own placement (``mount.z = 0.1`` raises TIAGo's
torso and arm by 10 cm). Each design is scored by

- the manipulability of its arm's tool over seeded random postures within the joint limits
  (:func:`mobman.redundancy.sample_configurations`, the same seed for every design, so that designs are
  compared on the same draws scaled to their limits: common random numbers): the mean, the 10th percentile,
  the median and the largest value of Yoshikawa's w, the inverse condition number w2 or the eccentricity w5
  (Nait-Chabane eq. 17–19) of the arm's position Jacobian J_a (``level="arm"``) or of the whole system's
  J̄ = J S (``level="system"``, Bayle eq. 2), the rows along the axes the tool moves
  (:func:`mobman.studies.maps.moving_axes`);
- its horizontal reach (:func:`mobman.studies.placement.reach_radius`);
- with ``bounds`` and ``step``, the share of that box's cells its tool reaches with the platform parked
  (``coverage``, :func:`mobman.studies.maps.reachability_map`): how well the design serves a given workspace.

Each design compiles its own programs (a robot is a static argument of mobman's compiled functions), about a
second or more per design, so a sweep is worth spreading over a Dask cluster. It is a study of
:mod:`mobman.studies.store`: one design per unit of work by default, kept in a Zarr store when one is given
(resumable), computed on Dask when asked.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Mapping
from dataclasses import dataclass
from functools import partial
from typing import Any

import numpy as np
import numpy.typing as npt

from mobman import manipulability as mp
from mobman.errors import InputError, MobmanError
from mobman.model import robots
from mobman.model.robot import MobileManipulator
from mobman.redundancy import sample_configurations
from mobman.studies import maps, options
from mobman.studies import store as studies
from mobman.studies.placement import reach_radius

KIND = "design-sweep"

STATISTICS = ("mean", "p10", "median", "max")
"""The statistics of the measure over the sampled postures, each a metric of the sweep."""

MAX_DESIGNS = 100_000
"""Largest grid of designs :func:`sweep` accepts."""


@dataclass(frozen=True)
class DesignSweep:
    """A design sweep's results (module notes). ``parameters``: each varied parameter's values, in the order
    of the grid's axes; ``metrics``: each metric over the grid, shape (len(values) for each parameter):
    :data:`STATISTICS` of the measure, ``reach`` (m) and, when a box was given, ``coverage`` (0 to 1); NaN
    for a design not computed, or one the robot's constructor refused (its reason in ``failures``, by
    design index)."""

    robot: str
    parameters: dict[str, np.ndarray]
    fixed: dict[str, float]
    metrics: dict[str, np.ndarray]
    computed: np.ndarray
    failures: dict[tuple[int, ...], str]
    measure: str
    level: str

    @property
    def shape(self) -> tuple[int, ...]:
        return tuple(len(v) for v in self.parameters.values())

    def design(self, index: tuple[int, ...]) -> dict[str, float]:
        """The parameters of the design at ``index`` of the grid (the fixed ones included)."""
        return {**self.fixed, **{name: float(v[i]) for (name, v), i in zip(self.parameters.items(), index)}}

    def ranking(self, metric: str = "mean", count: int = 5) -> list[tuple[int, ...]]:
        """The indices of the ``count`` designs with the highest ``metric``, best first (NaN last, left out)."""
        if metric not in self.metrics:
            raise InputError(f"metric must be one of {', '.join(self.metrics)}, got {metric!r}")
        values = self.metrics[metric].ravel()
        order = [int(k) for k in np.argsort(-np.where(np.isnan(values), -np.inf, values), kind="stable")]
        kept = [k for k in order if not np.isnan(values[k])][:count]
        return [tuple(int(i) for i in np.unravel_index(k, self.shape)) for k in kept]


def sweep(
    robot: str | MobileManipulator,
    parameters: Mapping[str, npt.ArrayLike],
    *,
    fixed: dict[str, float] | None = None,
    arm: int = 0,
    samples: int = 2000,
    measure: str = "yoshikawa",
    level: str = "arm",
    seed: int = 0,
    bounds: npt.ArrayLike | None = None,
    step: float | None = None,
    store: str | None = None,
    chunk: int | None = None,
    scheduler: str | None = None,
    progress: studies.Progress | None = None,
) -> DesignSweep:
    """Score every design of the grid ``parameters`` (name → values) of ``robot``: a built-in robot's
    command-line name, whose constructor's parameters and mount can be varied, or a robot (read from a file,
    say), whose mount can be (:func:`mobman.model.robots.design`; module notes).

    ``fixed``: the robot's other parameters (its defaults otherwise); ``arm``: whose tool is scored;
    ``samples``: postures per design; ``measure``: one of :data:`mobman.manipulability.MEASURES`;
    ``level``: ``"arm"`` or ``"system"``; ``bounds`` (6 numbers, m) and ``step`` (m): the box of the
    ``coverage`` metric (:func:`mobman.studies.maps.reachability_map`, its other options at their defaults);
    ``store``, ``chunk`` (designs per unit of work: 1 for a new sweep, the store's own for one resumed),
    ``scheduler``, ``progress``: :func:`mobman.studies.store.run`.
    """
    source: str | MobileManipulator
    if isinstance(robot, MobileManipulator):
        source, name = robot, robot.name
    elif isinstance(robot, str) and robots.command_name(robot) in robots.ROBOTS:
        source = name = robots.command_name(robot)
    else:
        raise InputError(
            f"robot must be a built-in robot's name ({', '.join(robots.ROBOTS)}) or a MobileManipulator, "
            f"got {robot!r}"
        )
    studies.check_options(store, chunk, scheduler)
    fixed = _fixed(fixed)
    described = f"robot {name}" if isinstance(source, str) else f"the given robot {name!r}"
    grid = _grid(described, robots.parameter_names(source), parameters, fixed)
    samples = options.count(samples, "samples")
    seed = options.seed(seed)
    if not (isinstance(arm, (int, np.integer)) and arm >= 0):
        raise InputError(f"arm must be an integer ≥ 0, got {arm!r}")
    # the robot's digest is in the definition: a store computed for another robot of the name is refused
    base = robots.build(name) if isinstance(source, str) else source
    if arm >= len(base.arms):
        raise InputError(
            f"arm must be in 0..{len(base.arms) - 1} ({name} has {len(base.arms)} arm(s)), got {arm}"
        )
    options.scoring(measure, level)
    if (bounds is None) != (step is None):
        raise InputError("bounds and step go together: give both for the coverage of a box, or neither")
    box = None if bounds is None else maps.parse_bounds(bounds).tolist()
    step = None if step is None else options.distance(step, "step")
    if box is not None:  # the coverage's grid, counted before any design is built
        maps.grid_shape(np.asarray(box), float(step))  # type: ignore[arg-type]
    # a design's postures and the Jacobian (3 × n_q) of each at once
    options.memory({"samples": samples}, samples * base.n_q * 4)
    shape = tuple(len(v) for v in grid.values())
    designs = math.prod(shape)
    if designs > MAX_DESIGNS:
        raise InputError(f"{designs:,} designs ({' × '.join(map(str, shape))}), more than {MAX_DESIGNS:,}")
    metrics = _metrics(box is not None)
    columns = {m: studies.Column() for m in metrics}
    columns["refused"] = studies.Column((), "bool", False)
    definition = {
        "study": KIND,
        "robot": name,
        "digest": maps.robot_digest(base),
        "parameters": {k: v.tolist() for k, v in grid.items()},
        "fixed": fixed,
        "arm": int(arm),
        "samples": int(samples),
        "measure": measure,
        "level": level,
        "seed": int(seed),
        "bounds": box,
        "step": None if step is None else float(step),
    }
    compute = partial(
        _designs, source, {k: v.tolist() for k, v in grid.items()}, fixed, int(arm), int(samples), measure,
        level, int(seed), box, None if step is None else float(step),
    )  # fmt: skip
    study = studies.run(
        compute,
        designs,
        columns,
        definition,
        store=store,
        chunk=chunk,
        new_chunk=1,
        scheduler=scheduler,
        progress=progress,
    )
    return from_study(study)


def from_study(study: studies.Study) -> DesignSweep:
    """A design sweep from its study's results (:func:`mobman.studies.store.read` of a sweep's store). Only
    a built-in robot's constructor refuses designs, so the reasons of the refused ones are found again from
    the robot's name."""
    d = study.definition
    if d.get("study") != KIND:
        raise InputError(f"the study is a {d.get('study')!r}, not a {KIND}")
    parameters = {k: np.asarray(v, dtype=float) for k, v in d["parameters"].items()}
    shape = tuple(len(v) for v in parameters.values())
    fixed = {k: float(v) for k, v in d["fixed"].items()}
    failures = {}
    for k in np.flatnonzero(study.columns["refused"]):
        index = tuple(int(i) for i in np.unravel_index(k, shape))
        design = {name: float(v[i]) for (name, v), i in zip(parameters.items(), index)}
        built = _build(d["robot"], {**fixed, **design}, int(d["arm"]))
        failures[index] = built if isinstance(built, str) else "refused"
    return DesignSweep(
        robot=d["robot"],
        parameters=parameters,
        fixed=fixed,
        metrics={k: v.reshape(shape) for k, v in study.columns.items() if k != "refused"},
        computed=study.done.reshape(shape),
        failures=failures,
        measure=d["measure"],
        level=d["level"],
    )


def _fixed(fixed: Mapping[str, float] | None) -> dict[str, float]:
    """The fixed parameters as finite floats (an InputError naming one that is not)."""
    if not isinstance(fixed, (Mapping, type(None))):
        raise InputError(f"fixed: a mapping of parameter names to values, got {type(fixed).__name__}")
    out = {}
    for key, value in (fixed or {}).items():
        if not (isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(value, bool)):
            raise InputError(f"fixed: {key} must be a number, got {value!r}")
        if not math.isfinite(value):
            raise InputError(f"fixed: {key} must be finite, got {value!r}")
        out[str(key)] = float(value)
    return out


def _grid(
    robot: str, allowed: list[str], parameters: Mapping[str, npt.ArrayLike], fixed: dict[str, float]
) -> dict[str, np.ndarray]:
    if not parameters:
        raise InputError(f"parameters: give at least one parameter of {robot} to vary ({', '.join(allowed)})")
    grid = {}
    for key, values in parameters.items():
        if key not in allowed:
            raise InputError(
                f"parameters: {robot} has no parameter {key!r}; its parameters: {', '.join(allowed)}"
            )
        if key in fixed:
            raise InputError(f"parameters: {key} is both varied and fixed")
        try:
            arr = np.asarray(values, dtype=float).ravel()
        except (TypeError, ValueError):
            raise InputError(f"parameters: {key} must be numbers, got {values!r}") from None
        if arr.size == 0 or not np.all(np.isfinite(arr)):
            raise InputError(f"parameters: {key} must be one or more finite numbers")
        grid[key] = arr
    for key in fixed:
        if key not in allowed:
            raise InputError(f"fixed: {robot} has no parameter {key!r}; its parameters: {', '.join(allowed)}")
    return grid


def _designs(
    source: str | MobileManipulator,
    grid: dict[str, list[float]],
    fixed: dict[str, float],
    arm: int,
    samples: int,
    measure: str,
    level: str,
    seed: int,
    box: list[list[float]] | None,
    step: float | None,
    start: int,
    stop: int,
) -> dict[str, np.ndarray]:
    """The designs [start, stop) of the grid in C order, one after the other (each compiles its own
    programs)."""
    combos = list(itertools.product(*grid.values()))[start:stop]
    rows: list[dict[str, Any]] = []
    for combo in combos:
        robot = _build(source, {**fixed, **dict(zip(grid, combo))}, arm)
        if isinstance(robot, str):  # a design the constructor refuses (a length ≤ 0): recorded, not fatal
            rows.append({"refused": True})
        else:
            rows.append(_score(robot, arm, samples, measure, level, seed, box, step))
    names = _metrics(box is not None)
    out = {m: np.array([r.get(m, math.nan) for r in rows], dtype=float) for m in names}
    out["refused"] = np.array([r.get("refused", False) for r in rows], dtype=bool)
    return out


def _metrics(coverage: bool) -> list[str]:
    """The metrics of a sweep: the statistics of the measure, the reach and, for a box, its coverage."""
    return list(STATISTICS) + ["reach"] + (["coverage"] if coverage else [])


def _build(source: str | MobileManipulator, design: dict[str, float], arm: int) -> MobileManipulator | str:
    """The design of ``source`` (:func:`mobman.model.robots.design`), or why it cannot be built."""
    try:
        return robots.design(source, design, arm)
    except MobmanError as exc:
        return str(exc)


def _score(
    robot: MobileManipulator,
    arm: int,
    samples: int,
    measure: str,
    level: str,
    seed: int,
    box: list[list[float]] | None,
    step: float | None,
) -> dict[str, float]:
    """One design's metrics (module notes)."""
    scored = maps.scored_task(maps.tool_positions(robot, arm), arm)
    q = sample_configurations(robot, samples, seed)
    values = np.asarray(mp.jacobian_and_measures(robot, q, level, scored)[1][measure])
    row = {
        "mean": float(np.mean(values)),
        "p10": float(np.percentile(values, 10)),
        "median": float(np.median(values)),
        "max": float(np.max(values)),
        "reach": reach_radius(robot, arm),
    }
    if box is not None and step is not None:
        row["coverage"] = maps.reachability_map(robot, arm=arm, bounds=np.ravel(box), step=step).fraction
    return row


__all__ = ["DesignSweep", "KIND", "MAX_DESIGNS", "STATISTICS", "from_study", "sweep"]
