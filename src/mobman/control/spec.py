"""Simulation specifications in TOML (``mobman simulate SPEC.toml``).

```toml
duration = 20.0                  # s
dt = 0.01                        # s
q0 = [0.0, 0.0, 0.0, 0.6, 1.2]   # or a string "0, 0, 0, pi/4, pi/3"
measures = ["arm_w5", "system_w5"]   # optional
integrator = "auto"              # optional: auto | lie | rk4 | hold

[robot]                          # a built-in robot (``mobman robots``) with keyword parameters,
                                 # or file = "robot.toml" (mobman.io.robot_file), relative to the spec
name = "bayle-planar"
params = { l1 = 0.5, l2 = 0.5 }

[task]                           # optional, default: the robot's own task
kind = "position"                # position | planar_angle | elevation | mount_position | elbow_angle | pose
components = "xy"                # | stack: tasks = [{kind = ...}, ...]; pose: arm, link, label
                                 # planar_angle: sequence = "ZYX" (heading of x) | "ZXY"

[reference]
kind = "ellipse"                 # line | ellipse | polyline | pose
center = [1.0, 0.0]
semi_axes = [0.6, 0.3]
period = 20.0
# pose (for a pose task): start = [x, y, z], end = [x, y, z] (m), each orientation as a rotation vector
# start_rotvec = [rx, ry, rz] (rad) or as start_rpy = [roll, pitch, yaw] (rad, R = Rz(yaw) Ry(pitch)
# Rx(roll)), likewise end_rotvec or end_rpy; duration (s), timing = "quintic" (linear | cubic | quintic)

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

from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from mobman.control import criteria, laws, references
from mobman.control.simulation import INTEGRATORS, parse_measure_names
from mobman.errors import InputError, MobmanError
from mobman.io import robot_file
from mobman.io import spec as fields
from mobman.io.numbers import parse_vector
from mobman.model import robots, spatial
from mobman.model.robot import MobileManipulator
from mobman.model.task import (
    HEADING_SEQUENCES,
    Elevation,
    FunctionTask,
    MountPosition,
    PlanarAngle,
    Pose,
    Position,
    Task,
    stack,
)

TOP_KEYS = (
    "duration",
    "dt",
    "q0",
    "measures",
    "integrator",
    "robot",
    "task",
    "reference",
    "law",
    "criterion",
    "gains",
)


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


def _task(table: dict, field: str) -> Task:
    def position(t):
        fields.keys(t, field, ("kind", "components", "arm", "link", "label"))
        return fields.build(
            field,
            Position,
            components=t.get("components", "xyz"),
            arm=t.get("arm", 0),
            link=t.get("link", -1),
            label=t.get("label", "ee"),
        )

    def mount(t):
        fields.keys(t, field, ("kind", "components", "arm"))
        return fields.build(field, MountPosition, components=t.get("components", "xy"), arm=t.get("arm", 0))

    def planar(t):
        fields.keys(t, field, ("kind", "arm", "link", "sequence"))
        sequence = fields.text(t, "sequence", field, "ZYX", allowed=HEADING_SEQUENCES)
        return fields.build(
            field, PlanarAngle, arm=t.get("arm", 0), link=t.get("link", -1), sequence=sequence
        )

    def elevation(t):
        fields.keys(t, field, ("kind", "arm", "link"))
        return fields.build(field, Elevation, arm=t.get("arm", 0), link=t.get("link", -1))

    def pose(t):
        fields.keys(t, field, ("kind", "arm", "link", "label"))
        return fields.build(
            field, Pose, arm=t.get("arm", 0), link=t.get("link", -1), label=t.get("label", "ee")
        )

    def elbow(t):
        fields.keys(t, field, ("kind",))
        return FunctionTask(robots.elbow_angle, ("beta",))

    def stacked(t):
        fields.keys(t, field, ("kind", "tasks"))
        parts = t.get("tasks")
        if not isinstance(parts, list) or not parts or not all(isinstance(p, dict) for p in parts):
            raise InputError(f"{field}.tasks: a list of task tables")
        return stack(*(_task(p, f"{field}.tasks[{i}]") for i, p in enumerate(parts)))

    kinds = {
        "position": position,
        "mount_position": mount,
        "planar_angle": planar,
        "elevation": elevation,
        "elbow_angle": elbow,
        "pose": pose,
        "stack": stacked,
    }
    return fields.kind(table, field, kinds)(table)


def _reference(data: dict) -> references.Reference:
    table = fields.table(data, "reference", "reference")
    f = "reference"

    def line(t):
        fields.keys(t, f, ("kind", "start", "end", "duration", "timing"))
        return fields.build(
            f,
            references.Line,
            start=fields.array(t.get("start"), f"{f}.start"),
            end=fields.array(t.get("end"), f"{f}.end"),
            duration=fields.number(t, "duration", f, positive=True),
            timing=t.get("timing", "linear"),
        )

    def ellipse(t):
        fields.keys(t, f, ("kind", "center", "semi_axes", "period", "phase", "angle", "rotation"))
        angle = t.get("angle")
        return fields.build(
            f,
            references.Ellipse,
            center=fields.array(t.get("center"), f"{f}.center"),
            semi_axes=fields.array(t.get("semi_axes"), f"{f}.semi_axes"),
            period=fields.number(t, "period", f, positive=True),
            phase=fields.number(t, "phase", f, 0.0),
            angle=None if angle is None else fields.number(t, "angle", f),
            rotation=fields.number(t, "rotation", f, 0.0),
        )

    def polyline(t):
        fields.keys(t, f, ("kind", "points", "durations", "timing"))
        return fields.build(
            f,
            references.Polyline,
            points=fields.array(t.get("points"), f"{f}.points"),
            durations=fields.array(t.get("durations"), f"{f}.durations"),
            timing=t.get("timing", "quintic"),
        )

    def orientation(t, end):
        given = [k for k in (f"{end}_rotvec", f"{end}_rpy") if k in t]
        if len(given) != 1:
            raise InputError(f"{f}: give one of {end}_rotvec, {end}_rpy (rad), got {given or 'neither'}")
        values = fields.array(t[given[0]], f"{f}.{given[0]}")
        if values.shape != (3,):
            raise InputError(f"{f}.{given[0]}: 3 numbers, got shape {values.shape}")
        if given[0].endswith("rotvec"):
            return values
        return spatial.euler_matrix(values[::-1], "ZYX")

    def pose(t):
        keys = ("start", "end", "start_rotvec", "start_rpy", "end_rotvec", "end_rpy", "duration", "timing")
        fields.keys(t, f, ("kind", *keys))
        return fields.build(
            f,
            references.PoseReference,
            start=(fields.array(t.get("start"), f"{f}.start"), orientation(t, "start")),
            end=(fields.array(t.get("end"), f"{f}.end"), orientation(t, "end")),
            duration=fields.number(t, "duration", f, positive=True),
            timing=t.get("timing", "quintic"),
        )

    kinds = {"line": line, "ellipse": ellipse, "polyline": polyline, "pose": pose}
    return fields.kind(table, f, kinds)(table)


def _criterion(table: dict, field: str) -> criteria.Criterion:
    def manipulability(t):
        fields.keys(t, field, ("kind", "measure", "which", "sign", "power"))
        return fields.build(
            field,
            criteria.Manipulability,
            measure=t.get("measure", "eccentricity"),
            which=t.get("which", "system"),
            sign=t.get("sign"),
            power=t.get("power", 1),
        )

    def blend(t):
        fields.keys(t, field, ("kind", "system", "arm", "alpha"))
        alpha = fields.table(t, "alpha", f"{field}.alpha")
        fields.keys(alpha, f"{field}.alpha", ("start", "end", "coordinate", "alpha_start", "alpha_end"))
        transition = fields.build(f"{field}.alpha", criteria.CubicTransition, **alpha)
        return criteria.Blend(
            _criterion(fields.table(t, "system", f"{field}.system"), f"{field}.system"),
            _criterion(fields.table(t, "arm", f"{field}.arm"), f"{field}.arm"),
            transition,
        )

    def joint_limits(t):
        fields.keys(t, field, ("kind",))
        return criteria.JointLimitDistance()

    kinds = {"manipulability": manipulability, "blend": blend, "joint_limits": joint_limits}
    return fields.kind(table, field, kinds)(table)


def _law(data: dict):
    table = fields.table(data, "law", "law")
    gains = fields.table(data, "gains", "gains", required=False) or {}
    criterion_table = fields.table(data, "criterion", "criterion", required=False)
    criterion = None if criterion_table is None else _criterion(criterion_table, "criterion")
    options = {k: table[k] for k in ("damping", "damping_threshold", "normalized", "saturate") if k in table}
    for key in ("damping", "damping_threshold"):
        if key in options:
            options[key] = fields.number(table, key, "law")
    for key in ("normalized", "saturate"):
        if key in options and not isinstance(options[key], bool):
            raise InputError(f"law.{key}: must be true or false, got {options[key]!r}")

    def gain(key, default=None):
        return default if gains.get(key) is None else fields.array(gains[key], f"gains.{key}")

    def bayle(t):
        fields.keys(t, "law", ("kind", "damping", "damping_threshold", "normalized", "saturate"))
        fields.keys(gains, "gains", ("W", "k"))
        return fields.build(
            "gains",
            laws.BaylePseudoInverse,
            W=gain("W", 1.0),
            k=gain("k", 0.0),
            criterion=criterion,
            **options,
        )

    def nait_chabane(t):
        fields.keys(t, "law", ("kind", "damping", "damping_threshold", "normalized", "saturate"))
        fields.keys(gains, "gains", ("W", "feedback"))
        return fields.build(
            "gains",
            laws.NaitChabane,
            W=gain("W", 1.0),
            criterion=criterion,
            feedback=gain("feedback"),
            **options,
        )

    def augmented(t):
        fields.keys(t, "law", ("kind", "extra", "damping", "damping_threshold", "normalized", "saturate"))
        fields.keys(gains, "gains", ("feedback",))
        if criterion is not None:
            raise InputError("criterion: the augmented-Jacobian law has no self-motion, remove [criterion]")
        extra = _task(fields.table(t, "extra", "law.extra"), "law.extra")
        return fields.build(
            "gains", laws.AugmentedJacobian, extra=extra, feedback=gain("feedback"), **options
        )

    return fields.kind(table, "law", {"bayle": bayle, "nait-chabane": nait_chabane, "augmented": augmented})(
        table
    )


def parse(data: dict, base: Path | None = None) -> Spec:
    """Build a :class:`Spec` from a TOML document already read into a dict."""
    fields.keys(data, "spec", TOP_KEYS)
    robot = robot_file.robot_table(data, base)
    task_table = fields.table(data, "task", "task", required=False)
    task = robot.task if task_table is None else _task(task_table, "task")
    try:
        task.check(robot)
    except MobmanError as exc:
        raise InputError(f"task: {exc}") from None
    q0 = data.get("q0")
    if isinstance(q0, str):
        q0 = parse_vector(q0, "q0", robot.n_q)
    q0 = fields.array(q0 if q0 is not None else [], "q0")
    if q0.shape != (robot.n_q,):
        raise InputError(f"q0: {robot.n_q} values ({', '.join(robot.coordinate_names)}), got {q0.size}")
    measures = data.get("measures", [])
    if not isinstance(measures, list) or not all(isinstance(m, str) for m in measures):
        raise InputError(f'measures: a list of names such as "system_w5", got {measures!r}')
    parse_measure_names(measures)
    integrator = data.get("integrator", "auto")
    if integrator not in INTEGRATORS:
        raise InputError(f"integrator: {integrator!r} not one of {', '.join(INTEGRATORS)}")
    law = _law(data)
    reference = _reference(data)
    from mobman.control.simulation import controlled_task

    ctask = controlled_task(law, task)
    if reference.dim != ctask.dim:
        raise InputError(
            f"reference: {reference.dim} components, the controlled task {ctask.names} has {ctask.dim}"
        )
    criterion = getattr(law, "criterion", None)
    if isinstance(criterion, criteria.Blend) and criterion.alpha.coordinate >= ctask.dim:
        raise InputError(
            f"criterion.alpha.coordinate: {criterion.alpha.coordinate} out of range 0..{ctask.dim - 1} "
            f"(the controlled task {', '.join(ctask.names)})"
        )
    duration = fields.number(data, "duration", "", positive=True)
    dt = fields.number(data, "dt", "", positive=True)
    if dt > duration:
        raise InputError(f"dt: {dt} s is longer than duration {duration} s")
    return Spec(robot, task, law, reference, q0, duration, dt, tuple(measures), integrator)


def load(path: Path) -> Spec:
    """Read and parse a TOML specification file."""
    data = fields.read_toml(path)
    with fields.naming(path):
        return parse(data, Path(path).parent)


__all__ = ["Spec", "load", "parse"]
