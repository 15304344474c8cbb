"""Simulation specifications in TOML (``mobman simulate SPEC.toml``).

```toml
duration = 20.0                  # s
dt = 0.01                        # s
q0 = [0.0, 0.0, 0.0, 0.6, 1.2]   # or a string "0, 0, 0, pi/4, pi/3"
measures = ["arm_w5", "system_w5"]   # optional
integrator = "auto"              # optional: auto | lie | rk4

[robot]                          # a built-in robot (``mobman robots``) with keyword parameters
name = "bayle-planar"
params = { l1 = 0.5, l2 = 0.5 }

[task]                           # optional, default: the robot's own task
kind = "position"                # position | planar_angle | elevation | mount_position | elbow_angle | stack
components = "xy"                # stack: tasks = [{kind = ...}, ...]

[reference]
kind = "ellipse"                 # line | ellipse | polyline
center = [1.0, 0.0]
semi_axes = [0.6, 0.3]
period = 20.0

[law]
kind = "bayle"                   # bayle | nait-chabane | augmented
damping = 0.0                    # optional: damping, damping_threshold, normalized, saturate
# augmented: extra = { kind = "mount_position" }

[criterion]                      # optional (bayle, nait-chabane)
kind = "manipulability"          # manipulability | blend | joint_limits
measure = "eccentricity"
which = "system"
# blend: system = {...}, arm = {...}, alpha = { start = 0.5, end = 1.5, coordinate = 0 }

[gains]
W = 2.0                          # bayle: W (error), k (self-motion); nait-chabane: W (null space), feedback
k = 1.0                          # augmented: feedback
```

Every mistake raises :class:`~mobman.InputError` naming the field (``reference.period``, ``gains.W`` …) and
what is allowed; the command line turns it into one line and exit status 2.
"""

from __future__ import annotations

import tomllib
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from mobman.control import criteria, laws, references
from mobman.control.simulation import INTEGRATORS, _measure_names
from mobman.errors import InputError, MobmanError
from mobman.model import robots
from mobman.model.robot import MobileManipulator
from mobman.model.task import Elevation, FunctionTask, MountPosition, PlanarAngle, Position, Task, stack

TOP_KEYS = ("duration", "dt", "q0", "measures", "integrator", "robot", "task", "reference", "law", "criterion", "gains")


@dataclass
class Spec:
    """A parsed specification: everything :func:`mobman.control.simulate` needs."""

    robot: MobileManipulator
    task: Task
    law: Any
    reference: references.Reference
    q0: np.ndarray
    duration: float
    dt: float
    measures: tuple[str, ...]
    integrator: str


def _table(data: dict, key: str, field: str, required: bool = True) -> dict | None:
    value = data.get(key)
    if value is None:
        if required:
            raise InputError(f"{field}: missing (a [{field}] table)")
        return None
    if not isinstance(value, dict):
        raise InputError(f"{field}: must be a table, got {value!r}")
    return value


def _keys(table: dict, field: str, allowed: tuple[str, ...]) -> None:
    for key in table:
        if key not in allowed:
            raise InputError(f"{field}.{key}: unknown key; allowed: {', '.join(allowed)}")


def _kind(table: dict, field: str, kinds: dict) -> Any:
    kind = table.get("kind")
    if kind not in kinds:
        raise InputError(f"{field}.kind: {kind!r} not one of {', '.join(kinds)}")
    return kinds[kind]


def _number(table: dict, key: str, field: str, default: Any = None, positive: bool = False) -> float:
    value = table.get(key, default)
    if value is None:
        raise InputError(f"{field}.{key}: missing (a number)" if field else f"{key}: missing (a number)")
    name = f"{field}.{key}" if field else key
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not np.isfinite(value):
        raise InputError(f"{name}: must be a finite number, got {value!r}")
    if positive and value <= 0:
        raise InputError(f"{name}: must be > 0, got {value!r}")
    return float(value)


def _array(value, name: str) -> np.ndarray:
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"{name}: must be a number or an array of numbers, got {value!r}") from None
    if not np.all(np.isfinite(arr)):
        raise InputError(f"{name}: must be finite, got {value!r}")
    return arr


def _build(field: str, factory, /, **kwargs):
    """Call a constructor; its ModelError becomes an InputError naming the spec field."""
    try:
        return factory(**kwargs)
    except MobmanError as exc:
        raise InputError(f"{field}: {exc}") from None
    except TypeError as exc:
        raise InputError(f"{field}: {exc}") from None


def _robot(data: dict) -> MobileManipulator:
    table = _table(data, "robot", "robot")
    _keys(table, "robot", ("name", "params"))
    name = table.get("name")
    if not isinstance(name, str):
        raise InputError(f"robot.name: a built-in robot name ({', '.join(robots.ROBOTS)}), got {name!r}")
    params = table.get("params", {})
    if not isinstance(params, dict):
        raise InputError(f"robot.params: must be a table of NAME = number, got {params!r}")
    params = {k: _number(params, k, "robot.params") for k in params}
    return _build("robot", robots.build, name=name, **params)


def _task(table: dict, field: str) -> Task:
    def position(t):
        _keys(t, field, ("kind", "components", "arm", "link", "label"))
        return _build(field, Position, components=t.get("components", "xyz"), arm=t.get("arm", 0),
                      link=t.get("link", -1), label=t.get("label", "ee"))

    def mount(t):
        _keys(t, field, ("kind", "components", "arm"))
        return _build(field, MountPosition, components=t.get("components", "xy"), arm=t.get("arm", 0))

    def angle(cls):
        def make(t):
            _keys(t, field, ("kind", "arm", "link"))
            return _build(field, cls, arm=t.get("arm", 0), link=t.get("link", -1))

        return make

    def elbow(t):
        _keys(t, field, ("kind",))
        return FunctionTask(robots.elbow_angle, ("beta",))

    def stacked(t):
        _keys(t, field, ("kind", "tasks"))
        parts = t.get("tasks")
        if not isinstance(parts, list) or not parts or not all(isinstance(p, dict) for p in parts):
            raise InputError(f"{field}.tasks: a list of task tables")
        return stack(*(_task(p, f"{field}.tasks[{i}]") for i, p in enumerate(parts)))

    kinds = {"position": position, "mount_position": mount, "planar_angle": angle(PlanarAngle),
             "elevation": angle(Elevation), "elbow_angle": elbow, "stack": stacked}
    return _kind(table, field, kinds)(table)


def _reference(data: dict) -> references.Reference:
    table = _table(data, "reference", "reference")
    f = "reference"

    def line(t):
        _keys(t, f, ("kind", "start", "end", "duration", "timing"))
        return _build(f, references.Line, start=_array(t.get("start"), f"{f}.start"), end=_array(t.get("end"), f"{f}.end"),
                      duration=_number(t, "duration", f, positive=True), timing=t.get("timing", "linear"))

    def ellipse(t):
        _keys(t, f, ("kind", "center", "semi_axes", "period", "phase", "angle", "rotation"))
        angle = t.get("angle")
        return _build(f, references.Ellipse, center=_array(t.get("center"), f"{f}.center"),
                      semi_axes=_array(t.get("semi_axes"), f"{f}.semi_axes"),
                      period=_number(t, "period", f, positive=True), phase=_number(t, "phase", f, 0.0),
                      angle=None if angle is None else _number(t, "angle", f),
                      rotation=_number(t, "rotation", f, 0.0))

    def polyline(t):
        _keys(t, f, ("kind", "points", "durations", "timing"))
        return _build(f, references.Polyline, points=_array(t.get("points"), f"{f}.points"),
                      durations=_array(t.get("durations"), f"{f}.durations"), timing=t.get("timing", "quintic"))

    return _kind(table, f, {"line": line, "ellipse": ellipse, "polyline": polyline})(table)


def _criterion(table: dict | None, field: str) -> criteria.Criterion | None:
    if table is None:
        return None

    def manipulability(t):
        _keys(t, field, ("kind", "measure", "which", "sign", "power"))
        return _build(field, criteria.Manipulability, measure=t.get("measure", "eccentricity"),
                      which=t.get("which", "system"), sign=t.get("sign"), power=t.get("power", 1))

    def blend(t):
        _keys(t, field, ("kind", "system", "arm", "alpha"))
        alpha = _table(t, "alpha", f"{field}.alpha")
        _keys(alpha, f"{field}.alpha", ("start", "end", "coordinate", "alpha_start", "alpha_end"))
        transition = _build(f"{field}.alpha", criteria.CubicTransition, **alpha)
        return criteria.Blend(_criterion(_table(t, "system", f"{field}.system"), f"{field}.system"),
                              _criterion(_table(t, "arm", f"{field}.arm"), f"{field}.arm"), transition)

    def joint_limits(t):
        _keys(t, field, ("kind",))
        return criteria.JointLimitDistance()

    kinds = {"manipulability": manipulability, "blend": blend, "joint_limits": joint_limits}
    return _kind(table, field, kinds)(table)


def _law(data: dict):
    table = _table(data, "law", "law")
    gains = _table(data, "gains", "gains", required=False) or {}
    criterion = _criterion(_table(data, "criterion", "criterion", required=False), "criterion")
    options = {k: table[k] for k in ("damping", "damping_threshold", "normalized", "saturate") if k in table}
    for key in ("damping", "damping_threshold"):
        if key in options:
            options[key] = _number(table, key, "law")
    for key in ("normalized", "saturate"):
        if key in options and not isinstance(options[key], bool):
            raise InputError(f"law.{key}: must be true or false, got {options[key]!r}")

    def gain(key, default=None):
        return default if gains.get(key) is None else _array(gains[key], f"gains.{key}")

    def bayle(t):
        _keys(t, "law", ("kind", "damping", "damping_threshold", "normalized", "saturate"))
        _keys(gains, "gains", ("W", "k"))
        return _build("gains", laws.BaylePseudoInverse, W=gain("W", 1.0), k=gain("k", 0.0), criterion=criterion,
                      **options)

    def nait_chabane(t):
        _keys(t, "law", ("kind", "damping", "damping_threshold", "normalized", "saturate"))
        _keys(gains, "gains", ("W", "feedback"))
        return _build("gains", laws.NaitChabane, W=gain("W", 1.0), criterion=criterion, feedback=gain("feedback"),
                      **options)

    def augmented(t):
        _keys(t, "law", ("kind", "extra", "damping", "damping_threshold", "normalized", "saturate"))
        _keys(gains, "gains", ("feedback",))
        if criterion is not None:
            raise InputError("criterion: the augmented-Jacobian law has no self-motion, remove [criterion]")
        extra = _task(_table(t, "extra", "law.extra"), "law.extra")
        return _build("gains", laws.AugmentedJacobian, extra=extra, feedback=gain("feedback"), **options)

    return _kind(table, "law", {"bayle": bayle, "nait-chabane": nait_chabane, "augmented": augmented})(table)


def parse(data: dict) -> Spec:
    """Build a :class:`Spec` from a TOML document already read into a dict."""
    _keys(data, "spec", TOP_KEYS)
    robot = _robot(data)
    task_table = _table(data, "task", "task", required=False)
    task = robot.task if task_table is None else _task(task_table, "task")
    try:
        task.check(robot)
    except MobmanError as exc:
        raise InputError(f"task: {exc}") from None
    q0 = data.get("q0")
    if isinstance(q0, str):
        from mobman.cli.common import parse_vector

        q0 = parse_vector(q0, "q0", robot.n_q)
    q0 = _array(q0 if q0 is not None else [], "q0")
    if q0.shape != (robot.n_q,):
        raise InputError(f"q0: {robot.n_q} values ({', '.join(robot.coordinate_names)}), got {q0.size}")
    measures = data.get("measures", [])
    if not isinstance(measures, list) or not all(isinstance(m, str) for m in measures):
        raise InputError(f"measures: a list of names such as \"system_w5\", got {measures!r}")
    _measure_names(measures)
    integrator = data.get("integrator", "auto")
    if integrator not in INTEGRATORS:
        raise InputError(f"integrator: {integrator!r} not one of {', '.join(INTEGRATORS)}")
    law = _law(data)
    reference = _reference(data)
    from mobman.control.simulation import controlled_task

    ctask = controlled_task(law, task)
    if reference.dim != ctask.dim:
        raise InputError(f"reference: {reference.dim} components, the controlled task {ctask.names} has {ctask.dim}")
    duration = _number(data, "duration", "", positive=True)
    dt = _number(data, "dt", "", positive=True)
    if dt > duration:
        raise InputError(f"dt: {dt} s is longer than duration {duration} s")
    return Spec(robot, task, law, reference, q0, duration, dt, tuple(measures), integrator)


def load(path: Path) -> Spec:
    """Read and parse a TOML specification file."""
    try:
        with open(path, "rb") as handle:
            data = tomllib.load(handle)
    except OSError as exc:
        raise InputError(f"{path}: cannot read ({exc.strerror})") from None
    except tomllib.TOMLDecodeError as exc:
        raise InputError(f"{path}: invalid TOML ({exc})") from None
    return parse(data)


__all__ = ["Spec", "load", "parse"]
