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
kind = "position"                # a task kind (mobman.model.tasks.task_kinds()): position | planar_angle |
components = "xy"                # elevation | euler_angles | mount_position | elbow_angle | pose | stack;
                                 # the other keys are the task's fields (mobman.io.tasks): position:
                                 # components, arm, link, point, label; planar_angle: sequence = "ZYX"
                                 # (heading of x) | "ZXY"; stack: tasks = [{kind = ...}, ...]

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

[physics]                        # optional: run on a physics engine (mobman.physics, docs/physics.md)
engine = "mujoco"                # or leave it out and give ``mobman simulate --physics mujoco``
timestep = 0.001                 # s, the physics step
control_rate = 100.0             # Hz, the law's rate (default 1 / dt); its period a multiple of timestep
friction = 1.0                   # the wheels' sliding friction on the floor
payload = 0.0                    # kg held at the first arm's tool
feedforward = false              # true: the reduced dynamics' B⁻¹ b(q, η) added to the servos (inertials needed)
```

A ``[scene]`` table (``[[scene.obstacle]]`` tables and ``floor``, the form of a scene file:
:mod:`mobman.io.scene`) or ``scene = "scene.toml"`` (relative to the spec) gives the obstacles that the ``qp``
law avoids, with ``[law]`` options ``collision_margin``, ``influence_distance``, ``collision_gain`` (docs/collision.md).

Every mistake raises :class:`~mobman.InputError` naming the field (``reference.period``, ``gains.W`` …) and
what is allowed; the command line turns it into one line and exit status 2.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable

import numpy as np

from mobman.control import criteria, laws, references
from mobman.control.simulation import INTEGRATORS, SimulationResult, parse_measure_names, simulate
from mobman.errors import InputError, MobmanError
from mobman.io import robot_file, tasks
from mobman.io import scene as scene_file
from mobman.io import spec as fields
from mobman.io.numbers import parse_vector
from mobman.model import spatial
from mobman.model.robot import MobileManipulator
from mobman.model.scene import Scene
from mobman.model.tasks import Task

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
    "scene",
    "physics",
)

ENGINES = ("mujoco",)
"""The physics engines a spec's ``[physics]`` table (``mobman simulate --physics``) may name."""


@dataclass(frozen=True)
class PhysicsSettings:
    """The ``[physics]`` table: the run on a physics engine (:mod:`mobman.physics`) instead of mobman's
    kinematic integration. ``engine`` (one of :data:`ENGINES`; None: the table only sets the numbers, the
    command line's ``--physics`` picks the engine), ``timestep`` the physics step h (s), ``control_rate`` the
    law's rate 1/h_c (Hz; h_c a whole multiple of h), ``friction`` the wheels' sliding friction on the floor,
    ``payload`` a mass (kg) held at the first arm's tool, ``feedforward`` the reduced dynamics' torques
    B⁻¹ b(q, η) added to the servos (:func:`mobman.physics.run_on_physics`)."""

    engine: str | None = None
    timestep: float = 1e-3
    control_rate: float = 100.0
    friction: float = 1.0
    payload: float = 0.0
    feedforward: bool = False

    @property
    def substeps(self) -> int:
        """Physics steps per control period h_c / h."""
        return round(1.0 / (self.control_rate * self.timestep))


def physics_settings(table: dict, dt: float, field: str = "physics") -> PhysicsSettings:
    """The :class:`PhysicsSettings` of a ``[physics]`` table (``control_rate`` by default 1 / the spec's
    ``dt``); InputError naming the field: an unknown engine, a non-positive step, rate or friction, a
    negative payload, a control period that is not a whole multiple of the physics step."""
    fields.keys(table, field, ("engine", "timestep", "control_rate", "friction", "payload", "feedforward"))
    feedforward = table.get("feedforward", False)
    if not isinstance(feedforward, bool):
        raise InputError(f"{field}.feedforward: must be true or false, got {feedforward!r}")
    engine = fields.text(table, "engine", field, allowed=ENGINES)
    settings = PhysicsSettings(
        engine,
        fields.number(table, "timestep", field, 1e-3, positive=True),
        fields.number(table, "control_rate", field, 1.0 / dt, positive=True),
        fields.number(table, "friction", field, 1.0, positive=True),
        fields.number(table, "payload", field, 0.0),
        feedforward,
    )
    if settings.payload < 0:
        raise InputError(f"{field}.payload: a mass ≥ 0 kg, got {settings.payload!r}")
    period = 1.0 / settings.control_rate
    if settings.substeps < 1 or not np.isclose(settings.substeps * settings.timestep, period, rtol=1e-9):
        raise InputError(
            f"{field}.control_rate: {settings.control_rate:g} Hz, its period {period:g} s is not a whole "
            f"multiple of {field}.timestep {settings.timestep:g} s"
        )
    return settings


@dataclass
class Spec:
    """A parsed specification: everything :func:`mobman.control.simulate` needs."""

    robot: MobileManipulator
    task: Task
    law: laws.Law
    reference: references.Reference
    q0: np.ndarray
    duration: float
    dt: float
    measures: tuple[str, ...]
    integrator: str
    physics: PhysicsSettings | None = None

    def arguments(self) -> dict[str, Any]:
        """The keyword arguments of :func:`mobman.control.simulate` (and ``simulate_pieces``) it sets."""
        names = ("robot", "task", "law", "reference", "q0", "duration", "dt", "measures", "integrator")
        return {name: getattr(self, name) for name in names}

    def simulate(self, progress: Callable[[float], None] | None = None) -> SimulationResult:
        """The run it describes: :func:`mobman.control.simulate` with its fields."""
        return simulate(**self.arguments(), progress=progress)


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


def _law(data: dict) -> laws.Law:
    """The law of ``[law]`` by its kind (:func:`mobman.control.laws.law_kinds`): its gains from ``[gains]``,
    its other fields from ``[law]``, its criterion from ``[criterion]``."""
    table = fields.table(data, "law", "law")
    cls = fields.kind(table, "law", {kind: laws.law_class(kind) for kind in laws.law_kinds()})
    gains = fields.table(data, "gains", "gains", required=False) or {}
    values = fields.dataclass_values(cls, gains, "gains", names=cls.gains, other_keys=())
    values |= fields.dataclass_values(
        cls,
        table,
        "law",
        names=[f.name for f in dataclasses.fields(cls) if f.name not in cls.gains],
        convert={Task: tasks.task},
    )
    criterion_table = fields.table(data, "criterion", "criterion", required=False)
    if criterion_table is not None:
        if "criterion" not in {f.name for f in dataclasses.fields(cls)}:
            raise InputError(f"criterion: the {table['kind']} law has no self-motion, remove [criterion]")
        values["criterion"] = _criterion(criterion_table, "criterion")
    return fields.build("gains", cls, **values)


def parse(data: dict, base: Path | None = None, robot: MobileManipulator | None = None) -> Spec:
    """Build a :class:`Spec` from a TOML document already read into a dict. ``robot``: the robot, where the
    caller has built it already (a load-capacity spec's top-level [robot]); the document's [robot] table is
    then not read."""
    fields.keys(data, "spec", TOP_KEYS)
    if robot is None:
        robot = robot_file.robot_table(data, base)
    task_table = fields.table(data, "task", "task", required=False)
    task = robot.task if task_table is None else tasks.task(task_table, "task")
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
    ctask = law.controlled_task(task)
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
    if "scene" in data:
        law = with_scene(law, _scene(data["scene"], base))
    physics_table = fields.table(data, "physics", "physics", required=False)
    physics = None if physics_table is None else physics_settings(physics_table, dt)
    return Spec(robot, task, law, reference, q0, duration, dt, tuple(measures), integrator, physics)


def _scene(value: Any, base: Path | None) -> Scene:
    """The scene of a spec's ``scene`` entry: a ``[scene]`` table or a scene file's path (relative to ``base``)."""
    if isinstance(value, str):
        path = Path(value) if base is None else base / value
        return scene_file.load(path)
    if not isinstance(value, dict):
        raise InputError(
            f'scene: a [scene] table or a scene file\'s path (scene = "scene.toml"), got {value!r}'
        )
    return scene_file.parse(value, "scene")


def with_scene(law: laws.Law, scene: Scene) -> laws.Law:
    """``law`` avoiding the obstacles of ``scene`` (only the ``qp`` law does)."""
    if not isinstance(law, laws.WholeBodyQP):
        raise InputError(f'scene: the {law.kind} law does not avoid collisions; give [law] kind = "qp"')
    return dataclasses.replace(law, scene=scene)


def load(path: Path) -> Spec:
    """Read and parse a TOML specification file."""
    data = fields.read_toml(path)
    with fields.naming(path):
        return parse(data, Path(path).parent)


__all__ = ["ENGINES", "PhysicsSettings", "Spec", "load", "parse", "physics_settings", "with_scene"]
