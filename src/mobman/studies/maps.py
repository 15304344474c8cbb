"""Reachability maps: where around its platform an arm's tool reaches, and how well.

The space around the platform is cut into a grid of cells (``step`` apart, in the platform frame: origin at
its reference point, x forward, z up; the platform at (x, y, θ) = 0). For each cell centre p the arm's
inverse kinematics is solved with the platform parked, from several starting postures within the joint
limits (:mod:`mobman.studies.reaching`, the task ``Position("xyz")`` of the arm's tool). A cell is reached
when the tool gets within ``tolerance`` of p; it is scored by a manipulability measure at the posture found
(:mod:`mobman.manipulability`): Yoshikawa's w, the inverse condition number w2 or the eccentricity w5 of the
arm's position Jacobian J_a (its rows along the axes the tool moves: x and y for a planar arm) (``level="arm"``: how well the arm alone moves its tool there) or of the whole
system's J̄ = J S (``level="system"``, Bayle eq. 2: with what the platform's admissible velocities add).
Given a collision model or a scene, a start's posture counts only when it is free of collision: of the robot
with itself (the self pairs of its collision model) and with the scene's obstacles and floor
(:mod:`mobman.studies.clearance`); a cell that only colliding postures reach is ``colliding``, not reached
(TIAGo's hand held inside its own base, for one).

Such a map (a capability or reachability map: Zacharias, Borst, Hirzinger, IROS 2007; Vahrenkamp, Asfour,
Dillmann, ICRA 2013) answers design and placement questions for a whole workspace at once. It is a study of
:mod:`mobman.studies.store`: its cells, in C order of the grid, are computed in chunks, kept in a Zarr store
when one is given (resumable), and on a Dask cluster when asked.
"""

from __future__ import annotations

import dataclasses
import hashlib
import math
from dataclasses import dataclass
from functools import partial
from typing import Any

import numpy as np
import numpy.typing as npt

from mobman import kinematics as K
from mobman.errors import InputError
from mobman.manipulability import MEASURES
from mobman.model.collision_model import CollisionModel
from mobman.model.robot import MobileManipulator
from mobman.model.scene import Scene
from mobman.model.tasks import Position, Task
from mobman.redundancy import sample_configurations
from mobman.studies import options
from mobman.studies import store as studies
from mobman.studies.clearance import Clearance, clearance_of, free_postures
from mobman.studies.reaching import best, reach, starting_postures

MAX_CELLS = 10_000_000
"""Largest grid :func:`reachability_map` accepts (a cell holds a posture: TIAGo's take 88 bytes each)."""

SAMPLES = 4096
"""Random postures the default bounds are measured on (:func:`default_bounds`)."""

KIND = "reachability-map"


@dataclass(frozen=True)
class ReachabilityMap:
    """A reachability map (module notes). ``axes``: the cell centres along x, y and z (m, platform frame);
    per cell, shape ``(len(x), len(y), len(z))``: ``reached``, ``error`` (the distance from the tool to the
    centre at the posture found; NaN where not computed), ``score`` (the measure there; NaN where not
    reached) and ``q`` (…, n_q: the posture, the platform's coordinates 0; NaN where not computed), and
    ``computed`` (False for cells of an unfinished study read back from its store). ``arm``: whose tool;
    ``scored``: the tool's coordinates the measure's rows are (the axes it moves along); ``digest``:
    :func:`robot_digest` of the robot it was computed for; ``step``: the distance between cell centres (m);
    ``colliding``: cells that a start reached only with postures in collision (module notes; all False when
    the postures were not checked); ``clearance``: what they were checked against
    (:meth:`mobman.studies.clearance.Clearance.describe`), None when not."""

    axes: tuple[np.ndarray, np.ndarray, np.ndarray]
    reached: np.ndarray
    error: np.ndarray
    score: np.ndarray
    q: np.ndarray
    computed: np.ndarray
    measure: str
    level: str
    tolerance: float
    arm: int = 0
    scored: str = "xyz"
    digest: str = ""
    step: float = 0.0
    colliding: np.ndarray | None = None
    clearance: dict | None = None

    @property
    def shape(self) -> tuple[int, int, int]:
        return (len(self.axes[0]), len(self.axes[1]), len(self.axes[2]))

    @property
    def fraction(self) -> float:
        """The share of the computed cells that are reached."""
        computed = int(self.computed.sum())
        return float(self.reached.sum() / computed) if computed else math.nan

    def centres(self) -> np.ndarray:
        """Every cell's centre, shape (…, 3)."""
        return np.stack(np.meshgrid(*self.axes, indexing="ij"), axis=-1)

    def best(self) -> tuple[int, int, int] | None:
        """The index of the reached cell with the highest score, None when no cell is reached."""
        if not self.reached.any():
            return None
        flat = int(np.nanargmax(np.where(self.reached, self.score, -np.inf)))
        return tuple(int(i) for i in np.unravel_index(flat, self.shape))  # type: ignore[return-value]

    def cell(self, point: npt.ArrayLike) -> tuple[int, int, int]:
        """The index of the cell whose centre is nearest ``point`` (x, y, z)."""
        p = np.asarray(point, dtype=float)
        if p.shape != (3,) or not np.all(np.isfinite(p)):
            raise InputError(f"point must be 3 finite numbers (x, y, z), got {point!r}")
        return tuple(int(np.argmin(np.abs(axis - c))) for axis, c in zip(self.axes, p))  # type: ignore[return-value]


def tool_positions(robot: MobileManipulator, arm: int) -> np.ndarray:
    """Arm ``arm``'s tool positions (:data:`SAMPLES`, 3) at seeded postures within the joint limits
    (:func:`mobman.redundancy.sample_configurations`), the platform at 0."""
    q = sample_configurations(robot, SAMPLES, seed=0)
    q[:, : robot.n_platform] = 0.0
    return np.asarray(K.forward(robot, q, Position("xyz", arm=arm)))


def moving_axes(tool: np.ndarray) -> np.ndarray:
    """Which of x, y, z the tool moves along over the postures ``tool`` (:func:`tool_positions`): a planar
    arm's z is fixed."""
    low, high = tool.min(axis=0), tool.max(axis=0)
    return high - low > 1e-9 * np.maximum(1.0, np.abs(high))


def scored_task(tool: np.ndarray, arm: int) -> Position:
    """The tool's position along the axes it moves (:func:`moving_axes` of ``tool``): the rows a posture's
    measure is taken of (a planar arm's constant z would make w zero)."""
    return Position("".join(c for c, m in zip("xyz", moving_axes(tool)) if m), arm=arm)


def default_bounds(tool: np.ndarray, step: float) -> np.ndarray:
    """Bounds (3, 2) of the tool positions ``tool`` (:func:`tool_positions`), widened to whole steps and one
    more on each side (postures at the corners of the limits are rare among random ones). An axis the tool
    does not move along is the single value it keeps."""
    low, high = tool.min(axis=0), tool.max(axis=0)
    bounds = np.stack([np.floor(low / step) * step - step, np.ceil(high / step) * step + step], axis=1)
    flat = ~moving_axes(tool)
    bounds[flat] = np.stack([low, low], axis=1)[flat]
    return bounds


def grid_shape(bounds: np.ndarray, step: float) -> tuple[int, int, int]:
    """The cells along each axis of :func:`grid_axes`, counted before any is made: an InputError naming
    ``step`` when they are more than :data:`MAX_CELLS` in all."""
    shape = tuple(math.floor((hi - lo) / step + 1e-9) + 1 for lo, hi in bounds)
    cells = math.prod(shape)
    if cells > MAX_CELLS:
        raise InputError(
            f"step {step:g} m makes {cells:,} cells ({' × '.join(f'{n:,}' for n in shape)}), more than "
            f"{MAX_CELLS:,}: give a larger step or smaller bounds"
        )
    return shape


def grid_axes(bounds: np.ndarray, step: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Cell centres along each axis: from its lower bound, ``step`` apart, up to its upper bound
    (:func:`grid_shape`)."""
    return tuple(lo + step * np.arange(n) for (lo, _), n in zip(bounds, grid_shape(bounds, step)))


def reachability_map(
    robot: MobileManipulator,
    *,
    arm: int = 0,
    bounds: npt.ArrayLike | None = None,
    step: float = 0.05,
    starts: int = 8,
    iterations: int = 60,
    tolerance: float = 1e-4,
    measure: str = "yoshikawa",
    level: str = "arm",
    seed: int = 0,
    collision: CollisionModel | None = None,
    scene: Scene | None = None,
    store: str | None = None,
    chunk: int | None = None,
    scheduler: str | None = None,
    progress: studies.Progress | None = None,
) -> ReachabilityMap:
    """The reachability map of arm ``arm``'s tool (module notes).

    ``bounds``: (x_min, x_max, y_min, y_max, z_min, z_max) of the cell centres (m, platform frame), by
    default :func:`default_bounds`; ``step``: the distance between centres (m); ``starts``, ``iterations``:
    starting postures per cell and damped least-squares steps from each (:mod:`mobman.studies.reaching`;
    the starts are seeded by ``seed``); ``tolerance``: the largest distance (m) of a reached cell's centre;
    ``measure``: one of :data:`mobman.manipulability.MEASURES`; ``level``: ``"arm"`` or ``"system"``.
    ``collision``: the robot's collision model, whose self pairs (and, with ``scene``, whose spheres against
    the scene's obstacles and floor, the platform parked at the origin) a posture must be free of; with a
    ``scene`` alone, the robot's :func:`~mobman.model.collision_model.collision_model` at
    :data:`mobman.studies.clearance.COVER_TOLERANCE`; neither: postures are not checked. ``store``, ``chunk``, ``scheduler``, ``progress``: where and how the cells are computed
    (:func:`mobman.studies.store.run`); a store that holds this map, finished or not, is read and completed.
    """
    studies.check_options(store, chunk, scheduler)
    if not (isinstance(arm, (int, np.integer)) and 0 <= arm < len(K.checked_robot(robot).arms)):
        raise InputError(f"arm must be an integer from 0 to {len(robot.arms) - 1}, got {arm!r}")
    step = options.distance(step, "step")
    starts, iterations = options.count(starts, "starts"), options.iterations(iterations)
    tolerance = options.tolerance(tolerance)
    seed = options.seed(seed)
    options.scoring(measure, level)
    checks = clearance_of(robot, collision, scene)
    tool = tool_positions(robot, int(arm))
    box = default_bounds(tool, float(step)) if bounds is None else parse_bounds(bounds)
    axes = grid_axes(box, float(step))
    cells = math.prod(len(a) for a in axes)
    # the solver's rows of a chunk, each start's Jacobian (3 × n_q) and posture at once
    rows = min(cells, chunk if isinstance(chunk, int) and chunk > 0 else studies.CHUNK)
    options.memory({"starts": starts, "chunk": rows}, rows * starts * robot.n_q * 4)
    task = Position("xyz", arm=arm)
    scored = scored_task(tool, int(arm))
    columns = {
        "reached": studies.Column((), "bool", False),
        "error": studies.Column(),
        "score": studies.Column(),
        "q": studies.Column((robot.n_q,)),
        "colliding": studies.Column((), "bool", False),
    }
    definition = {
        "study": KIND,
        "robot": robot.name,
        "robot_digest": robot_digest(robot),
        "arm": int(arm),
        "bounds": box.tolist(),
        "step": float(step),
        "starts": int(starts),
        "iterations": int(iterations),
        "tolerance": float(tolerance),
        "measure": measure,
        "level": level,
        "scored": scored.components,
        "seed": int(seed),
        "clearance": None if checks is None else checks.describe(),
    }
    compute = partial(
        _cells, robot, task, scored, axes, starting_postures(robot, int(starts), int(seed)), int(iterations),
        float(tolerance), measure, level, checks,
    )  # fmt: skip
    study = studies.run(
        compute, cells, columns, definition, store=store, chunk=chunk, scheduler=scheduler, progress=progress
    )
    return from_study(study)


def from_study(study: studies.Study) -> ReachabilityMap:
    """A map from its study's results (:func:`mobman.studies.store.read` of a map's store)."""
    d = study.definition
    if d.get("study") != KIND:
        raise InputError(f"the study is a {d.get('study')!r}, not a {KIND}")
    _check_definition(d, len(study.done))
    axes = grid_axes(np.asarray(d["bounds"], dtype=float), float(d["step"]))
    shape = tuple(len(a) for a in axes)
    c = study.columns
    return ReachabilityMap(
        axes=axes,
        reached=c["reached"].reshape(shape),
        error=c["error"].reshape(shape),
        score=c["score"].reshape(shape),
        q=c["q"].reshape(shape + c["q"].shape[1:]),
        computed=study.done.reshape(shape),
        measure=d["measure"],
        level=d["level"],
        tolerance=float(d["tolerance"]),
        arm=int(d["arm"]),
        scored=d["scored"],
        digest=d["robot_digest"],
        step=float(d["step"]),
        colliding=c["colliding"].reshape(shape) if "colliding" in c else np.zeros(shape, bool),
        clearance=d.get("clearance"),
    )


def _check_definition(d: dict[str, Any], rows: int) -> None:
    """A map's definition as :func:`reachability_map` writes it, its grid of ``rows`` cells: an InputError
    naming the first field that is not (a store edited or damaged)."""

    def field(name: str, ok: Any, allowed: str) -> Any:
        value = d.get(name)
        try:
            good = ok(value)
        except (TypeError, ValueError):
            good = False
        if not good:
            raise InputError(
                f"the map's {name} must be {allowed}, got {_shown(value)} (a damaged or edited store)"
            )
        return value

    box = parse_bounds(field("bounds", lambda v: np.shape(v) in ((3, 2), (6,)), "6 numbers (3 × 2)"))
    step = options.distance(field("step", lambda v: float(v) > 0, "a distance > 0 (m)"), "the map's step")
    cells = math.prod(math.floor((hi - lo) / step + 1e-9) + 1 for lo, hi in box)
    if cells != rows:
        raise InputError(
            f"the map's step {step:g} m and bounds make {cells:,} cells, the store holds {rows:,} "
            "(a damaged or edited store)"
        )
    field("arm", lambda v: isinstance(v, int) and not isinstance(v, bool) and v >= 0, "an integer ≥ 0")
    field("tolerance", lambda v: math.isfinite(v) and v > 0, "a distance > 0 (m)")
    field("measure", lambda v: isinstance(v, str) and v in MEASURES, f"one of {', '.join(MEASURES)}")
    field(
        "level", lambda v: isinstance(v, str) and v in options.LEVELS, f"one of {', '.join(options.LEVELS)}"
    )
    field("scored", lambda v: isinstance(v, str) and v and set(v) <= set("xyz"), "axes among x, y, z")
    field("robot_digest", lambda v: isinstance(v, str), "a string")


def _shown(value: Any) -> str:
    text = repr(value)
    return text if len(text) <= 40 else text[:39] + "…"


def robot_digest(robot: MobileManipulator) -> str:
    """A short digest of the robot's description: its platform, mounts and arms (kinematics, limits and
    inertials), not its task nor its visual shapes (whose mesh files lie where a machine installed them). A
    store computed for another robot of the same name is refused."""
    parts = (robot.platform, robot.mounts, robot.arms) + ((robot.followers,) if robot.followers else ())
    text = repr(_described(parts))
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def _described(value: Any) -> Any:
    """``value`` as nested tuples of its dataclasses' fields, the visual shapes left out."""
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return (type(value).__name__,) + tuple(
            (f.name, _described(getattr(value, f.name)))
            for f in dataclasses.fields(value)
            if f.name not in ("visuals", "platform_visuals")
        )
    if isinstance(value, (tuple, list)):
        return tuple(_described(v) for v in value)
    return value


def _cells(
    robot: MobileManipulator,
    task: Task,
    scored: Task,
    axes: tuple[np.ndarray, ...],
    starts: np.ndarray,
    iterations: int,
    tolerance: float,
    measure: str,
    level: str,
    checks: Clearance | None,
    start: int,
    stop: int,
) -> dict[str, Any]:
    """The map's cells [start, stop) in C order: reach each centre (``task``) with postures free of
    collision (``checks``), score the reached ones (``scored``'s rows of J)."""
    index = np.unravel_index(np.arange(start, stop), tuple(len(a) for a in axes))
    centres = np.stack([axis[i] for axis, i in zip(axes, index)], axis=-1)
    found, errors = reach(robot, np.zeros(3), centres, starts, task, iterations)
    close = errors <= tolerance
    free = free_postures(checks, found, close)
    q, error, score = best(robot, found, errors, tolerance, scored, measure, level, free)
    reached = ~np.isnan(score)
    return {
        "reached": reached,
        "error": np.where(np.isinf(error), math.nan, error),
        "score": score,
        "q": q,
        "colliding": close.any(axis=-1) & ~reached,
    }


def parse_bounds(value: npt.ArrayLike) -> np.ndarray:
    """(x_min, x_max, y_min, y_max, z_min, z_max) → bounds (3, 2), checked."""
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise InputError(
            f"bounds must be 6 numbers x_min, x_max, y_min, y_max, z_min, z_max, got {value!r}"
        ) from None
    if arr.size != 6 or not np.all(np.isfinite(arr)):
        raise InputError(
            f"bounds must be 6 finite numbers x_min, x_max, y_min, y_max, z_min, z_max (m), got {arr.size}"
            + ("" if arr.size != 6 else " with NaN or infinite values")
        )
    box = arr.reshape(3, 2)
    for name, (lo, hi) in zip("xyz", box):
        if lo > hi:
            raise InputError(f"bounds: {name}_min {lo:g} is above {name}_max {hi:g}")
    return box


__all__ = [
    "KIND",
    "MAX_CELLS",
    "ReachabilityMap",
    "SAMPLES",
    "default_bounds",
    "from_study",
    "grid_axes",
    "grid_shape",
    "moving_axes",
    "parse_bounds",
    "reachability_map",
    "robot_digest",
    "scored_task",
    "tool_positions",
]
