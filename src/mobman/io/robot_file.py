"""Robot description files: a mobile manipulator in TOML, for robots that are not built in.

A file names a platform, one or more arms given by DH tables, and where each arm is mounted::

    name = "my-robot"
    task = "xy"                      # optional: components of arm 0's tool position (default "xyz")

    [platform]
    kind = "differential"            # car | differential | fixed | omnidirectional | skid_steer
    wheel_radius = 0.1               # the platform's parameters (the fields of its class)
    half_track = 0.25
    v_max = 0.5
    omega_max = 1.0

    [[arms]]
    name = "arm"
    convention = "dh"                # dh: rows (θ, d, a, α); modified-dh: rows (α_{i−1}, a_{i−1}, θ_i, d_i)
    table = [[0.0, 0.0, 0.5, 0.0], [0.0, 0.0, 0.5, 0.0]]
    kinds = "RR"                     # optional: R (revolute) or P (prismatic) per joint, default all revolute
    velocity_max = [1.57, 1.57]      # optional, rad/s or m/s per joint
    limits = [[-3.1, 3.1], [-2.6, 2.6]]   # optional position limits per joint
    tool = [0.0, 0.0, 0.0]           # optional: tool point in the last link frame (m)
    mount = [0.0, 0.0, 0.0, 0.0]     # optional: arm base x, y, z (m) and yaw (rad) in the platform frame,
                                     # or x, y, z, roll, pitch, yaw (URDF's xyz and rpy)

The ``[platform]`` keys are the fields of the platform's class (docs/platforms.md):

- ``differential`` (:class:`mobman.DifferentialDrive`): ``wheel_radius``, ``half_track``, and ``v_max`` with
  ``omega_max`` or ``wheel_speed_max``;
- ``skid_steer`` (:class:`mobman.SkidSteer`): ``wheel_radius``, ``half_track``, ``wheelbase``, ``x_icr``,
  ``track_factor``, and ``v_max`` with ``omega_max`` or ``wheel_speed_max``;
- ``car`` (:class:`mobman.CarLike`): ``length``, ``u1_max``, ``u2_max``;
- ``omnidirectional`` (:class:`mobman.Omnidirectional`): ``limits = [vx, vy, omega]``;
- ``fixed`` (:class:`mobman.Fixed`): no keys (the arm's base does not move).

Wherever the command line takes a built-in robot name, a path ending in ``.toml`` loads such a file; a
``[robot]`` table of a spec file takes ``file = "robot.toml"`` (relative to the spec) instead of ``name``, or a
URDF file with the options of :func:`mobman.io.urdf.read_urdf` (:func:`urdf_table`)::

    [robot]
    file = "my_robot.urdf"           # relative to the spec
    tip = "tool0"                    # optional, or a list of tips (one arm each); default arm_tool_link
    base = "base_link"               # optional, default base_footprint
    platform = "auto"                # optional: auto | car | differential | fixed | omnidirectional | skid_steer
    wheels = ["wheel_right_joint", "wheel_left_joint"]   # optional: the drive wheels (right, left)
    locked = { head_1_joint = 0.0 }  # optional: joints held at a value (rad or m)
    platform_options = { wheel_radius = 0.0613, half_track = 0.1875 }   # optional: platform parameters the
                                     # file lacks or that override it, and base_height (m above the ground)
"""

from __future__ import annotations

import dataclasses
from pathlib import Path
from typing import TYPE_CHECKING

from mobman.errors import InputError
from mobman.io import spec as fields
from mobman.io.urdf import is_urdf_path
from mobman.model import robots
from mobman.model.arm import Arm
from mobman.model.platforms import Platform, platform_class, platform_kinds
from mobman.model.robot import MobileManipulator, Mount
from mobman.model.spatial import transform
from mobman.model.tasks import Position

CONVENTIONS = {"dh": Arm.from_dh, "modified-dh": Arm.from_modified_dh}
ARM_KEYS = ("name", "convention", "table", "kinds", "velocity_max", "limits", "tool", "mount")
URDF_KEYS = ("file", "tip", "base", "platform", "wheels", "locked", "platform_options")
"""The keys of a ``[robot]`` table that names a URDF file."""

if TYPE_CHECKING:
    from mobman.io.urdf import UrdfModel


def _vector(entries: dict, key: str, field: str, size: int) -> list[float] | None:
    if key not in entries:
        return None
    values = fields.array(entries[key], f"{field}.{key}")
    if values.shape != (size,):
        raise InputError(f"{field}.{key}: {size} numbers, got shape {values.shape}")
    return [float(v) for v in values]


def _mount(entries: dict, field: str) -> dict[str, float]:
    """The ``mount`` entry as :class:`Mount` fields: x, y, z, yaw or x, y, z, roll, pitch, yaw."""
    if "mount" not in entries:
        return {}
    values = fields.array(entries["mount"], f"{field}.mount")
    names = {4: ("x", "y", "z", "yaw"), 6: ("x", "y", "z", "roll", "pitch", "yaw")}.get(values.size)
    if values.ndim != 1 or names is None:
        raise InputError(
            f"{field}.mount: 4 numbers (x, y, z, yaw) or 6 (x, y, z, roll, pitch, yaw), got shape {values.shape}"
        )
    return {name: float(v) for name, v in zip(names, values)}


def _arm(entries: dict, field: str) -> tuple[Arm, Mount]:
    if not isinstance(entries, dict):
        raise InputError(f"{field}: must be a table")
    fields.keys(entries, field, ARM_KEYS)
    convention = fields.text(entries, "convention", field, "dh", tuple(CONVENTIONS))
    table = fields.array(entries.get("table"), f"{field}.table")
    if table.ndim != 2 or table.shape[1] != 4 or not len(table):
        raise InputError(f"{field}.table: one row of 4 numbers per joint, got shape {table.shape}")
    n = len(table)
    kinds = fields.text(entries, "kinds", field)
    if kinds is not None and (len(kinds) != n or set(kinds) - {"R", "P"}):
        raise InputError(
            f"{field}.kinds: one letter R (revolute) or P (prismatic) per joint ({n}), got {kinds!r}"
        )
    limits = None
    if "limits" in entries:
        limits = fields.array(entries["limits"], f"{field}.limits")
        if limits.shape != (n, 2):
            raise InputError(
                f"{field}.limits: one [lower, upper] pair per joint ({n}), got shape {limits.shape}"
            )
    tool = _vector(entries, "tool", field, 3) or [0.0, 0.0, 0.0]
    mount = _mount(entries, field)
    arm = fields.build(
        field,
        CONVENTIONS[convention],
        table=table.tolist(),
        kinds=kinds,
        tool=transform(None, tuple(tool)),
        limits=None if limits is None else [tuple(row) for row in limits.tolist()],
        velocity_limits=_vector(entries, "velocity_max", field, n),
        name=fields.text(entries, "name", field, field),
    )
    return arm, fields.build(f"{field}.mount", Mount, **mount)


def _platform(entries: dict) -> Platform:
    cls = fields.kind(entries, "platform", {kind: platform_class(kind) for kind in platform_kinds()})
    parameters = tuple(f.name for f in dataclasses.fields(cls) if f.init)
    fields.keys(entries, "platform", ("kind", *parameters))
    values = {
        key: tuple(fields.array(value, f"platform.{key}").tolist())
        if isinstance(value, list)
        else fields.number(entries, key, "platform")
        for key, value in entries.items()
        if key != "kind"
    }
    return fields.build("platform", cls, **values)


def parse(data: dict, source: str = "robot file") -> MobileManipulator:
    """A :class:`MobileManipulator` from a parsed robot description (see the module docstring)."""
    fields.keys(data, "", ("name", "task", "platform", "arms"))
    platform = _platform(fields.table(data, "platform", "platform"))
    arms = data.get("arms")
    if not isinstance(arms, list) or not arms:
        raise InputError("arms: at least one [[arms]] table")
    parts = [_arm(entries, f"arms[{i}]") for i, entries in enumerate(arms)]
    components = fields.text(data, "task", "", "xyz")
    task = fields.build("task", Position, components=components)
    return fields.build(
        source,
        MobileManipulator,
        platform=platform,
        arms=tuple(arm for arm, _ in parts),
        mounts=tuple(mount for _, mount in parts),
        task=task,
        name=fields.text(data, "name", "", "robot-file"),
    )


def load(path: Path | str) -> MobileManipulator:
    """Read a robot description file."""
    data = fields.read_toml(Path(path))
    with fields.naming(path):
        return parse(data)


def robot_table(data: dict, base: Path | None = None, urdf: "UrdfModel | None" = None) -> MobileManipulator:
    """The robot of the ``[robot]`` table: a built-in ``name`` with optional ``params`` (NAME = number: its
    constructor's and the first arm's mount, ``"mount.z" = 0.1``, :func:`mobman.model.robots.design`), a
    robot description ``file`` (this module's format), or a URDF ``file`` with its reading options
    (:func:`urdf_table`); a file's path is relative to ``base``. ``urdf``: what :func:`urdf_table` read of
    the same table, taken instead of reading the file again."""
    entry = fields.table(data, "robot", "robot")
    path = _urdf_file(entry, base)
    if path is not None:
        return (urdf or _read_urdf(entry, path)).robot
    fields.keys(entry, "robot", ("name", "params", "file"))
    if "file" in entry:
        if "name" in entry or "params" in entry:
            raise InputError("robot: give either file or name (with params), not both")
        return load(_path(entry, base))
    name = entry.get("name")
    if not isinstance(name, str):
        raise InputError(f"robot.name: a built-in robot name ({', '.join(robots.ROBOTS)}), got {name!r}")
    params = entry.get("params", {})
    if not isinstance(params, dict):
        raise InputError(f"robot.params: must be a table of NAME = number, got {params!r}")
    params = {k: fields.number(params, k, "robot.params") for k in params}
    source = name if urdf is None else urdf.robot  # a real robot's, read already
    return fields.build("robot", robots.design, source=source, params=params)


def urdf_table(data: dict, base: Path | None = None) -> "UrdfModel | None":
    """The URDF model behind the ``[robot]`` table (robot, inertials, effort limits): a built-in real robot by
    ``name`` (``tiago``, …) or a URDF ``file`` (relative to ``base``) read with the table's ``tip``, ``base``,
    ``platform``, ``wheels``, ``locked`` and ``platform_options`` (:func:`mobman.io.urdf.read_urdf`); None for
    any other robot."""
    from mobman.io.real_robots import REAL_ROBOTS, urdf_model

    entry = fields.table(data, "robot", "robot")
    urdf = _urdf_file(entry, base)
    if urdf is not None:
        return _read_urdf(entry, urdf)
    name = entry.get("name")
    key = robots.command_name(name) if isinstance(name, str) else None
    return urdf_model(key) if "file" not in entry and key in REAL_ROBOTS else None


def _path(entry: dict, base: Path | None) -> Path:
    path = Path(fields.text(entry, "file", "robot"))
    return path if base is None or path.is_absolute() else base / path


def _urdf_file(entry: dict, base: Path | None) -> Path | None:
    """The path of the table's ``file`` when it names a URDF file."""
    return _path(entry, base) if is_urdf_path(entry.get("file", "")) else None


def _names(value: object, field: str) -> tuple[str, ...]:
    names = (value,) if isinstance(value, str) else value
    if not isinstance(names, list | tuple) or not names or not all(isinstance(n, str) and n for n in names):
        raise InputError(f"{field}: a link or joint name or a list of them, got {value!r}")
    return tuple(names)


def _read_urdf(entry: dict, path: Path) -> "UrdfModel":
    from mobman.io.urdf import read_urdf

    fields.keys(entry, "robot", URDF_KEYS)
    options: dict = {key: fields.text(entry, key, "robot") for key in ("base", "platform") if key in entry}
    if "tip" in entry:
        options["tip"] = _names(entry["tip"], "robot.tip")
    if "wheels" in entry:
        wheels = _names(entry["wheels"], "robot.wheels")
        if len(wheels) != 2:
            raise InputError(f"robot.wheels: two joint names [right, left], got {list(wheels)}")
        options["wheels"] = wheels
    for key in ("locked", "platform_options"):
        if key in entry:
            values = fields.table(entry, key, f"robot.{key}")
            options[key] = {name: fields.number(values, name, f"robot.{key}") for name in values}
    return read_urdf(path, **options)
