"""URDF in and out: a mobile manipulator from a robot's URDF file (read with yourdfpy), and back to URDF.

Reading (:func:`load_urdf`, :func:`read_urdf`)
---------------------------------------------
- **Chains.** Each arm is the chain of joints from the ``base`` link to one ``tip`` link. URDF joints map one
  to one onto :class:`mobman.Joint` (fixed ``origin``, then motion about ``axis``): ``revolute`` and
  ``prismatic`` keep their position, velocity and effort limits; ``continuous`` is a revolute joint without
  position limits. Fixed joints are folded into the next joint's origin (after the last moving joint, into
  the arm's tool transform). Joints named in ``locked`` are held at the given value and folded the same way
  (e.g. a torso shared by two arms, which mobman's arms cannot share). A ``floating`` or ``planar`` joint on a
  chain is an error naming it, and so are a simulator's virtual base joints (two prismatic joints across the
  base's plane and a revolute one about its vertical starting the chain, joint_x, joint_y, joint_rz: the
  platform's x, y, θ already move the base); the error names the link below them to take as the base.
- **Mimic joints** (q = multiplier · q_leader + offset) follow a leader that does not move with q (a locked
  joint, a passive one held at 0, another mimic): they are held at that value, on the chains (folded like a
  locked joint) or off them. A mimic of an arm coordinate (directly or through other mimics) cannot follow it
  in a serial arm: on a chain it is an error (lock the leader). Off the chains (HSR's torso following its arm
  lift at half its travel) it follows: its link and what hangs from it become a
  :class:`mobman.model.robot.Follower`, a body moved by multiplier · q_coordinate + offset, with its own visual
  and collision shapes; its mass stays lumped into the body it hangs from, at the posture where the
  coordinate is 0 (mobman's dynamics have no body off the chains that moves).
- **Everything off the chains** (wheels, casters, fingers, head, suspension) is passive: held at zero (or
  its ``locked`` value) and listed in the :class:`UrdfSummary`. Its links move rigidly with the link they
  hang from, and their inertials and visuals are lumped into it.
- **Inertials.** Each arm joint carries the lumped inertial of the link it moves (with everything rigidly
  attached), in the joint frame after its motion: total mass, centre of mass, inertia about it by the
  parallel-axis theorem. The platform body (base link and all that hangs from it, wheels included) becomes a
  :class:`mobman.model.inertial.PlatformBody`; only its mass, centre of mass and inertia about the vertical enter
  the planar motion of the platform. The wheels' spin inertia about their axle (a_wᵀ I a_w, the same for both
  wheels up to 1e-12, else the mean) becomes :class:`mobman.model.inertial.Wheel` ``(0, I_w, 0)``: the wheels' mass
  and their inertia about the vertical are already in the body.
- **Platform.** ``platform="auto"`` (or ``"differential"``) looks for two ``continuous`` joints off the chains
  with a common horizontal axle (parallel axes along the line joining the joint origins, perpendicular to the
  base's x axis); if several pairs qualify, the pair with velocity or effort limits (the driven wheels, not the
  casters) is taken; ``wheels=(right, left)`` names them. The wheel radius comes from the wheel link's
  collision cylinder or sphere (else its collision mesh's extent across the axle, else the visual geometry),
  the half track from the joint origins; ``wheel_radius=`` and ``half_track=`` override both. The platform
  frame (the origin of q_p = (x, y, θ)) is the axle midpoint on the ground the wheels stand on (the axle's
  height less the wheel radius below the base link; the base link itself within 1 µm), axes of the base
  frame, so heights are heights above the ground; the base → platform offset is folded into each arm's first
  joint. Where the wheels are fixed joints or absent (simulator exports), a differential drive is built from
  the ``wheel_radius`` and ``half_track`` given, its frame at the base link, and a skid-steer from those and
  its ``wheelbase``; ``platform_options={"base_height": h}`` puts the platform frame h below the base link
  where no wheel gives the ground (a :class:`UrdfWarning` says so when nothing gives it). ``"omnidirectional"``
  puts q_p at the base frame, and so does ``"fixed"`` (an arm on a base that does not move: no wheels needed)
  and any other platform kind without a URDF reader of its own (its parameters from ``platform_options``).
  ``"skid_steer"`` takes four continuous joints on two axles (front, rear); the platform frame is their
  centre on the ground, the half track and the wheelbase come from the joint origins; a skid-steer's ``x_icr`` and
  ``track_factor`` are not in a URDF: pass them in ``platform_options``.
- **Velocity limits.** A per-wheel speed limit |φ̇| ≤ φ̇_max makes the admissible (v, ω) set the diamond
  |v|/(r φ̇_max) + |ω|/(r φ̇_max / b) ≤ 1 (Yamamoto & Yun eq. 23–26: v = r(φ̇_r + φ̇_l)/2,
  ω = r(φ̇_r − φ̇_l)/(2b)). The platform keeps ``wheel_speed_max``: the kinematic ellipsoids use the diamond
  exactly (wheel coordinates), and the normalised measures (Nait-Chabane's R) use its vertices
  v_max = r φ̇_max, ω_max = r φ̇_max / b, each reached with the other quasi-velocity zero.
- **Visuals** (boxes, cylinders, spheres, meshes) are recorded as :class:`mobman.model.visual.Visual` in the
  frame of the platform or of the joint that moves them, for the viewer; ``package://`` and relative mesh
  paths are resolved from the URDF's location (yourdfpy's resolver, walking up its folders). A mesh that
  cannot be found is left out and listed in the summary (yourdfpy's log line per mesh is filtered out);
  :meth:`UrdfSummary.mesh_note` is the one line a drawing of the robot says about them. A mesh found must be
  a mesh file (:data:`MESH_SUFFIXES`), and a path written relative to the robot must stay in its folder: a
  relative path in the URDF's folder, ``package://PACKAGE/…`` in that package (the URDF's nearest ancestor
  folder of that name) or the URDF's folder; an absolute path names its file itself. No other file is read.
- **Errors** name the link or joint: a tip that is not below the base, no wheel pair (with the continuous
  joints seen), a shared moving joint, a floating joint, virtual base joints or a mimic of an arm coordinate
  on a chain, a platform option that is not one of the platform's parameters (naming those), a file that is
  not URDF or cannot be read.
- **Files that lie** are refused in one line naming the file and what is wrong, before any of it is used: XML
  that is not well-formed (parsed strictly first: yourdfpy's parser would repair a truncated file), a link or
  joint name used twice, a link below two joints, joints that form a cycle (a link its own ancestor), an
  origin, axis or inertia that is not finite, a NaN limit, a velocity or effort limit below 0 (0 reads as no
  limit: URDF requires both attributes and writers put 0 where they know none; a joint of a chain whose velocity
  limit reads so gets a note), a mass below 0, a mesh that is
  not a mesh file or lies outside the robot's folder. yourdfpy's own log lines are held back while it reads. A ``.xacro`` file must be expanded first: ``xacro robot.urdf.xacro > robot.urdf``.

Writing (:func:`write_urdf`)
----------------------------
Every built-in robot writes to a URDF that reads back to the same ξ, J̄ and M: the platform link
``base_footprint`` (the platform frame), for a platform with driven wheels (differential drive, skid-steer)
one continuous wheel joint per wheel at its centre (x, y, r) with a cylinder collision of radius r and the
per-wheel speed limit (read back with ``platform="skid_steer"`` and the ``platform_options`` x_icr and
track_factor for a skid-steer), for a car a steering joint and its front
wheel (read back with ``platform="car"``); each arm's mount and joint offsets folded into the joint origins.
An arm with a coupling (motion = C q_a, which URDF cannot state) is written in its motion variables: the URDF's
coordinates are C q_a. Given a platform body and wheels (:mod:`mobman.model.inertial`), they are written as
link inertials too.
"""

from __future__ import annotations

import contextlib
import difflib
import functools
import logging
import math
import os
import warnings
from dataclasses import dataclass, field, fields
from pathlib import Path
from typing import Any, Iterator, Mapping, NoReturn, Sequence

import numpy as np
import numpy.typing as npt

from mobman.errors import InputError, ModelError
from mobman.model import spatial
from mobman.model.arm import Arm, Joint, LinkInertial
from mobman.model.inertial import PlatformBody, Wheel
from mobman.model.platforms import Platform, platform_class, platform_kinds
from mobman.model.platforms.urdf_form import UrdfPlatform, UrdfWheel, distance
from mobman.model.robot import (
    FOLLOWER,
    PLATFORM,
    Follower,
    MobileManipulator,
    actuator_names,
    compiled_frames,
)
from mobman.model.visual import Visual

_MOVING = ("revolute", "continuous", "prismatic")
_AXLE_TOL = 1e-4  # alignment tolerance of wheel axles (URDF angles are often rounded: 1.5708 for π/2)
_ON_THE_GROUND = 1e-6  # a base link within 1 µm of the wheels' ground is on it (mesh radii are float32)
READING_OPTIONS = ("base_height",)
"""The ``platform_options`` that are not a platform's parameters but say how the file is read:
``base_height``, the base link's height above the ground (m)."""


class UrdfWarning(UserWarning):
    """What :func:`read_urdf` reads differently from the file, said once per reading (also in
    :attr:`UrdfSummary.notes`): a platform frame whose height no wheel defines, a chain joint's velocity
    limit of 0."""


@dataclass(frozen=True)
class UrdfSummary:
    """What :func:`read_urdf` took from a URDF file and what it left out.

    ``chains``: per arm, the joints kept (base to tip); ``folded``: fixed joints folded into origins;
    ``locked``: joints held at a value; ``passive``: moving joints off the chains, held at zero (their links
    lumped into the link they hang from); ``mimics``: (joint, leader, value) of the mimic joints held at their
    leader's held value; ``followers``: (joint, coordinate, multiplier, offset) of the mimic joints off the
    chains that follow an arm coordinate (q = multiplier · q_coordinate + offset; the robot's
    :class:`~mobman.model.robot.Follower` bodies); ``wheels``: (right, left) wheel joints; ``base_height``: the base link's height above
    the ground the platform frame is on (None: no wheel defines the ground and the platform frame is at the
    base link's height); ``platform_limits``: how the platform's velocity limits were obtained;
    ``missing_meshes``: mesh files that could not be found (:meth:`mesh_note`); ``notes``: what is read
    differently from the file (each also a :class:`UrdfWarning`).
    """

    path: str
    name: str
    base: str
    tips: tuple[str, ...]
    platform: str
    chains: tuple[tuple[str, ...], ...]
    folded: tuple[str, ...]
    locked: tuple[tuple[str, float], ...]
    passive: tuple[str, ...]
    wheels: tuple[str, str] | None = None
    wheel_radius: float | None = None
    half_track: float | None = None
    reference_point: tuple[float, float] = (0.0, 0.0)
    base_height: float | None = None
    platform_limits: str = ""
    missing_meshes: tuple[str, ...] = ()
    mimics: tuple[tuple[str, str, float], ...] = ()
    followers: tuple[tuple[str, str, float, float], ...] = ()
    notes: tuple[str, ...] = ()

    def lines(self) -> list[str]:
        """The summary as readable lines."""
        out = [f"{self.name} from {self.path}: base {self.base}, platform {self.platform}"]
        for tip, chain in zip(self.tips, self.chains):
            out.append(f"arm to {tip}: {len(chain)} joints ({', '.join(chain)})")
        if self.wheels is not None:
            out.append(
                f"wheels {self.wheels[0]} (right), {self.wheels[1]} (left): radius {self.wheel_radius:.6g} m, "
                f"half track {self.half_track:.6g} m; platform frame at the axle midpoint "
                f"({self.reference_point[0]:.6g}, {self.reference_point[1]:.6g}) in {self.base}"
            )
        if self.base_height is None:
            out.append(f"platform frame at the height of {self.base}: heights are measured from it")
        else:
            out.append(f"platform frame on the ground, {self.base_height:.6g} m below {self.base}")
        if self.platform_limits:
            out.append(self.platform_limits)
        out.append(f"fixed joints folded: {len(self.folded)}")
        if self.locked:
            out.append("locked: " + ", ".join(f"{n} = {v:.6g}" for n, v in self.locked))
        if self.passive:
            out.append(f"passive joints off the chains, held at 0: {', '.join(self.passive)}")
        if self.mimics:
            held = ", ".join(f"{n} = {v:.6g} (follows {leader})" for n, leader, v in self.mimics)
            out.append(f"mimic joints held at their leader's value: {held}")
        if self.followers:
            moved = ", ".join(f"{n} = {m:.6g} · {c} + {o:.6g}" for n, c, m, o in self.followers)
            out.append(f"joints off the chains following an arm coordinate: {moved}")
        if self.missing_meshes:
            out.append(f"meshes not found (not drawn): {', '.join(self.missing_meshes)}")
        out.extend(self.notes)
        return out

    def mesh_note(self) -> str | None:
        """One line on the meshes that could not be found (None when every one was): what a drawing of the
        robot says, once, instead of a line per mesh."""
        n = len(self.missing_meshes)
        if not n:
            return None
        where = os.path.dirname(os.path.abspath(self.path))
        return (
            f"{n} mesh{'es' if n > 1 else ''} of {self.name} not found from {where} (package:// and relative "
            "paths are searched from the file's folder up): those links are drawn without them"
        )

    def __str__(self) -> str:
        return "\n".join(self.lines())


@dataclass(frozen=True)
class UrdfModel:
    """A robot read from a URDF file, with what the kinematic model does not hold.

    ``body`` (the platform with everything off the chains, wheels included) and ``wheel`` (spin inertia) are
    None where the URDF has no inertials; ``effort_limits``: the actuators' effort limits in the order of
    :func:`mobman.model.robot.actuator_names` (wheels, then joints; None where the URDF gives none).
    :meth:`mobman.dynamics.DynamicModel.from_urdf` makes the dynamic model.
    """

    robot: MobileManipulator
    summary: UrdfSummary
    body: PlatformBody | None = None
    wheel: Wheel | None = None
    effort_limits: tuple[float | None, ...] = field(default=())

    def torque_limits(self) -> np.ndarray:
        """τ_max of every actuator from the URDF's effort limits (ModelError naming one that is missing)."""
        missing = [n for n, v in zip(actuator_names(self.robot), self.effort_limits) if v is None]
        if missing:
            raise ModelError(f"{self.robot.name}: the URDF gives no effort limit for {', '.join(missing)}")
        return np.asarray(self.effort_limits, dtype=float)


# --- reading ---------------------------------------------------------------------------------------

URDF_SUFFIXES = (".urdf", ".xacro")
"""The file name endings that mark a robot description as URDF (a xacro file is refused with the command
that expands it)."""


def is_urdf_path(name: str | os.PathLike[str]) -> bool:
    """Whether ``name`` names a URDF (or xacro) file by its ending (:data:`URDF_SUFFIXES`), as the command
    line and robot files tell a URDF path from a robot's name."""
    return str(name).lower().endswith(URDF_SUFFIXES)


def _parse(path: str | os.PathLike[str]) -> tuple[Any, Path]:
    """The file read by yourdfpy, after it is found well-formed XML with unique link and joint names
    (yourdfpy's parser repairs a damaged file and keeps one of two links of a name) and its numbers checked
    (:func:`_check_numbers`); every error one line naming the file."""
    if not isinstance(path, (str, os.PathLike)) or isinstance(os.fspath(path), bytes):
        raise InputError(f"path must be a URDF file's path (str or os.PathLike), got {type(path).__name__}")
    file = Path(path)
    if file.suffix.lower() == ".xacro":
        target = file.stem if file.stem.endswith(".urdf") else file.stem + ".urdf"
        raise InputError(
            f"{file}: a xacro file; expand it to URDF first: xacro {file.name} > {target} "
            "(the xacro tool: pip install xacro, or ROS's xacro package)"
        )
    if not file.is_file():
        raise InputError(f"{file}: no such file")
    stat = file.stat()
    return _parsed(file, stat.st_mtime_ns, stat.st_size)


@functools.lru_cache(maxsize=8)
def _parsed(file: Path, mtime_ns: int, size: int) -> tuple[Any, Path]:
    """:func:`_parse` of an existing file, kept per version of the file (its modification time and size): a
    command reads a robot's file for its chains and again for its collision shapes."""
    import yourdfpy

    try:
        text = file.read_text(errors="replace")
    except OSError as exc:
        raise InputError(f"{file}: cannot read ({exc.strerror})") from None
    if "<xacro:" in text:
        raise InputError(
            f"{file}: contains xacro macros; expand it to URDF first: xacro {file.name} > expanded.urdf"
        )
    if "<robot" not in text:
        raise InputError(f"{file}: not a URDF file (no <robot> element)")
    _check_names(_strict_xml(file), file)
    with _yourdfpy_lines() as said:
        try:
            urdf = yourdfpy.URDF.load(
                str(file),
                build_scene_graph=False,
                build_collision_scene_graph=False,
                load_meshes=False,
                load_collision_meshes=False,
            )
        except Exception as exc:  # noqa: BLE001 - any parser failure is a bad file
            lines = "".join(f"; {r.getMessage()}" for r in said if r.levelno >= logging.WARNING)
            raise InputError(
                f"{file}: not a readable URDF file ({type(exc).__name__}: {exc}{lines})"
            ) from None
    if urdf.robot is None or not urdf.robot.links:
        raise InputError(f"{file}: not a URDF file (no links)")
    _check_numbers(urdf.robot, file)
    return urdf, file


def _strict_xml(file: Path) -> Any:
    """The root element of ``file`` parsed as strict XML (Expat: no external entity or DTD is read): an
    InputError naming the line and column where it is not well-formed (a truncated file, a tag never closed)."""
    from xml.etree import ElementTree

    try:
        return ElementTree.parse(file).getroot()
    except ElementTree.ParseError as exc:
        raise InputError(f"{file}: not well-formed XML ({exc}): a truncated or damaged file") from None


def _check_names(root: Any, file: Path) -> None:
    """Every link and every joint of the ``<robot>`` element ``root`` named, each name once."""
    if root.tag != "robot":
        raise InputError(f"{file}: not a URDF file (its root element is <{root.tag}>, not <robot>)")
    for kind in ("link", "joint"):
        names = [element.get("name") for element in root.findall(kind)]
        if None in names or "" in names:
            raise InputError(f"{file}: a <{kind}> without a name")
        repeated = sorted({n for n in names if names.count(n) > 1})
        if repeated:
            raise InputError(f"{file}: {kind} names used twice: {', '.join(map(repr, repeated))}")


def _check_numbers(robot: Any, file: Path) -> None:
    """The numbers of every joint and link the way URDF defines them, else an InputError naming the file, the
    joint or link and the field: origins and axes finite; limits not NaN, velocity and effort ≥ 0 (URDF
    requires both attributes of a revolute or prismatic joint's ``<limit>``, and writers put 0 where they
    know no limit: 0 reads as none); a link's mass finite and ≥ 0, its inertia and inertial origin finite."""

    def refuse(what: str, text: str) -> NoReturn:
        raise InputError(f"{file}: {what}: {text}")

    for j in robot.joints:
        what = f"joint {j.name!r}"
        if j.origin is not None and not np.all(np.isfinite(np.asarray(j.origin, dtype=float))):
            refuse(what, "origin (xyz, rpy) must be finite numbers")
        if j.axis is not None and not np.all(np.isfinite(np.asarray(j.axis, dtype=float))):
            refuse(what, "axis must be 3 finite numbers")
        if j.limit is not None:
            for name in ("lower", "upper", "velocity", "effort"):
                value = getattr(j.limit, name)
                if value is not None and math.isnan(value):
                    refuse(what, f"limit {name} is NaN")
            for name, unit in (("velocity", "rad/s or m/s"), ("effort", "N·m or N")):
                value = getattr(j.limit, name)
                if value is not None and value < 0:
                    refuse(what, f"limit {name} must be ≥ 0 ({unit}; 0: none given), got {value:g}")
        if j.mimic is not None:
            for name in ("multiplier", "offset"):
                value = getattr(j.mimic, name)
                if value is not None and not math.isfinite(value):
                    refuse(what, f"mimic {name} must be finite, got {value!r}")
    for link in robot.links:
        inertial = link.inertial
        if inertial is None:
            continue
        what = f"link {link.name!r}"
        mass = inertial.mass
        if mass is not None and not (math.isfinite(mass) and mass >= 0):
            refuse(what, f"mass must be a finite number ≥ 0 (kg), got {mass:g}")
        for name, value in (("inertia", inertial.inertia), ("inertial origin", inertial.origin)):
            if value is not None and not np.all(np.isfinite(np.asarray(value, dtype=float))):
                refuse(what, f"{name} must be finite numbers")


def _motion(kind: str, axis: np.ndarray, value: float) -> np.ndarray:
    t = np.eye(4)
    if kind == "prismatic":
        t[:3, 3] = value * axis
    else:
        t[:3, :3] = _rodrigues(axis, value)
    return t


def _rodrigues(axis: np.ndarray, angle: float) -> np.ndarray:
    k = spatial.skew(axis)
    return np.eye(3) + math.sin(angle) * k + (1.0 - math.cos(angle)) * k @ k


def _origin(joint: Any) -> np.ndarray:
    return np.eye(4) if joint.origin is None else np.asarray(joint.origin, dtype=float)


def _axis(joint: Any) -> np.ndarray:
    axis = np.array([1.0, 0.0, 0.0]) if joint.axis is None else np.asarray(joint.axis, dtype=float)
    norm = np.linalg.norm(axis)
    if not norm > 0:
        raise ModelError(f"URDF joint {joint.name!r}: zero axis")
    return axis / norm


def _limit(value: float | None) -> float | None:
    return None if value is None or not value > 0 else float(value)


@dataclass
class _Tree:
    """The URDF's kinematic tree: joints by name and by child link, children per link, the root link."""

    joints: dict
    parent_joint: dict
    children: dict
    links: dict
    root: str

    @classmethod
    def of(cls, robot: Any, file: Path) -> "_Tree":
        """The tree of the file's joints, checked to be one: each joint between two links of the file, each
        link below one joint at most, one root, and every link below it (a link that is its own ancestor is
        a cycle, which no walk through the tree would leave)."""
        links = {link.name: link for link in robot.links}
        joints = {j.name: j for j in robot.joints}
        parent_joint: dict = {}
        children: dict = {}
        for j in robot.joints:
            for end in (j.parent, j.child):
                if end not in links:
                    raise InputError(f"{file}: joint {j.name!r} names {end!r}, not a link of the file")
            if j.child in parent_joint:
                raise InputError(
                    f"{file}: link {j.child!r} is the child of two joints, "
                    f"{parent_joint[j.child].name!r} and {j.name!r}"
                )
            parent_joint[j.child] = j
            children.setdefault(j.parent, []).append(j)
        roots = [name for name in links if name not in parent_joint]
        if len(roots) != 1:
            raise InputError(
                f"{file}: expected one root link, found {', '.join(roots) or 'none'}"
                + ("" if roots else ": the joints form a cycle")
            )
        below, stack = {roots[0]}, [roots[0]]
        while stack:
            for j in children.get(stack.pop(), []):
                below.add(j.child)
                stack.append(j.child)
        if len(below) < len(links):
            link = next(name for name in links if name not in below)
            cycle = [link]
            while (link := parent_joint[link].parent) not in cycle:
                cycle.append(link)
            loop = " → ".join([link, *reversed(cycle[cycle.index(link) + 1 :]), link])
            raise InputError(f"{file}: the joints form a cycle, link {link!r} is its own ancestor ({loop})")
        return cls(joints, parent_joint, children, links, roots[0])

    def path(self, base: str, tip: str) -> list:
        """Joints from ``base`` down to ``tip`` (ModelError when tip is not below base)."""
        for name, what in ((base, "base"), (tip, "tip")):
            if name not in self.links:
                raise ModelError(f"URDF: no link named {name!r} ({what}); links: {', '.join(self.links)}")
        chain, link = [], tip
        while link != base:
            joint = self.parent_joint.get(link)
            if joint is None:
                raise ModelError(
                    f"URDF: tip link {tip!r} is not below base link {base!r} (its chain ends at root {link!r})"
                )
            chain.append(joint)
            link = joint.parent
        return chain[::-1]


def _poses(tree: _Tree, locked: Mapping[str, float]) -> dict[str, np.ndarray]:
    """Pose of every link in the root frame with each moving joint at its locked value or zero."""
    poses = {tree.root: np.eye(4)}
    stack = [tree.root]
    while stack:
        link = stack.pop()
        for j in tree.children.get(link, []):
            t = poses[link] @ _origin(j)
            if j.type in _MOVING:
                t = t @ _motion(j.type, _axis(j), locked.get(j.name, 0.0))
            poses[j.child] = t
            stack.append(j.child)
    return poses


def _groups(tree: _Tree, starts: dict[str, tuple[int, int]]) -> dict[str, tuple[int, int] | None]:
    """The body each link moves with: (arm, joint index) of the chain joint above it, None for the platform.

    ``starts`` maps the child link of every chain joint to its (arm, index). Links above the base move with
    the platform too.
    """
    groups: dict[str, tuple[int, int] | None] = {tree.root: starts.get(tree.root)}
    stack = [tree.root]
    while stack:
        link = stack.pop()
        for j in tree.children.get(link, []):
            groups[j.child] = starts.get(j.child, groups[link])
            stack.append(j.child)
    return groups


def _lump(parts: list[tuple[float, np.ndarray, np.ndarray]]) -> tuple[float, np.ndarray, np.ndarray] | None:
    """(mass, com, inertia about com) of rigid parts given as (mass, com, inertia about own com) in one frame
    (parallel-axis theorem; a part of zero mass adds its inertia only)."""
    if not parts:
        return None
    mass = float(sum(m for m, _, _ in parts))
    com = np.asarray(sum(m * c for m, c, _ in parts)) / mass if mass > 0 else np.zeros(3)
    inertia = np.zeros((3, 3))
    for m, c, i in parts:
        d = c - com
        inertia += i + m * (d @ d * np.eye(3) - np.outer(d, d))
    return mass, com, 0.5 * (inertia + inertia.T)


def _inertial_parts(
    tree: _Tree, links: list[str], frame: np.ndarray, poses: Mapping[str, np.ndarray]
) -> list:
    """The inertials of ``links`` expressed in the frame of pose ``frame`` (root coordinates)."""
    inv = np.linalg.inv(frame)
    parts = []
    for name in links:
        inertial = tree.links[name].inertial
        if inertial is None:
            continue
        mass = float(inertial.mass or 0.0)
        i_local = np.zeros((3, 3)) if inertial.inertia is None else np.asarray(inertial.inertia, dtype=float)
        if mass < 0 or (mass == 0 and not np.any(i_local)):
            continue
        t = inv @ poses[name] @ (np.eye(4) if inertial.origin is None else np.asarray(inertial.origin))
        parts.append((mass, t[:3, 3].copy(), t[:3, :3] @ i_local @ t[:3, :3].T))
    return parts


def _color(visual: Any, materials: dict) -> tuple[float, float, float, float]:
    material = getattr(visual, "material", None)  # a <collision> has none
    if material is not None and material.color is None and material.name in materials:
        material = materials[material.name]
    if material is None or material.color is None:
        return (0.7, 0.7, 0.75, 1.0)
    r, g, b, a = (float(np.clip(v, 0.0, 1.0)) for v in np.asarray(material.color.rgba).ravel()[:4])
    return r, g, b, a


def _visuals(
    tree: _Tree,
    links: list[str],
    frame: np.ndarray,
    poses: Mapping[str, np.ndarray],
    directory: str,
    materials: dict,
    missing: list,
    element: str = "visuals",
) -> tuple:
    """The visual shapes of ``links`` in the frame of pose ``frame`` (``element="collisions"``: their collision
    shapes); meshes not found are left out and their file names added to ``missing``."""
    inv = np.linalg.inv(frame)
    shapes = []
    for name in links:
        for visual in getattr(tree.links[name], element):
            g = visual.geometry
            if g is None:
                continue
            origin = inv @ poses[name] @ (np.eye(4) if visual.origin is None else np.asarray(visual.origin))
            common: dict[str, Any] = {
                "origin": tuple(origin.ravel()),
                "rgba": _color(visual, materials),
                "name": name,
            }
            if g.box is not None:
                shapes.append(Visual("box", size=tuple(np.asarray(g.box.size).ravel()), **common))
            elif g.cylinder is not None:
                shapes.append(Visual("cylinder", size=(g.cylinder.radius, g.cylinder.length), **common))
            elif g.sphere is not None:
                shapes.append(Visual("sphere", size=(g.sphere.radius,), **common))
            elif g.mesh is not None:
                resolved = _mesh_file(g.mesh.filename, directory, name)
                if resolved is None:
                    missing.append(g.mesh.filename)
                    continue
                scale = np.broadcast_to(np.asarray(1.0 if g.mesh.scale is None else g.mesh.scale, float), 3)
                shapes.append(Visual("mesh", filename=resolved, scale=tuple(scale), **common))
    return tuple(shapes)


class _YourdfpyLines(logging.Filter):
    """Holds back yourdfpy's log lines while it parses a file or resolves a mesh path, so that a reading says
    one line at most, mobman's: a line per mesh file it cannot resolve is dropped (:func:`read_urdf` lists
    them in its summary and a drawing says them in one line, :meth:`UrdfSummary.mesh_note`); the others are
    kept in ``held`` for the error that refuses the file."""

    def __init__(self) -> None:
        super().__init__()
        self.held: list[logging.LogRecord] = []

    def filter(self, record: logging.LogRecord) -> bool:
        if not str(record.msg).startswith("Unable to resolve filename"):
            self.held.append(record)
        return False


@contextlib.contextmanager
def _yourdfpy_lines() -> Iterator[list[logging.LogRecord]]:
    """yourdfpy's log lines held back (:class:`_YourdfpyLines`) while the block runs; yields those kept."""
    logger = logging.getLogger("yourdfpy.urdf")
    lines = _YourdfpyLines()
    logger.addFilter(lines)
    try:
        yield lines.held
    finally:
        logger.removeFilter(lines)


MESH_SUFFIXES = (".stl", ".dae", ".obj", ".ply", ".off", ".glb", ".gltf")
"""The mesh file types a URDF's ``<mesh filename=…>`` may name."""


def _mesh_file(filename: str, directory: str, link: str) -> str | None:
    """The mesh file ``filename`` of ``link`` resolved from the URDF's folder ``directory`` (yourdfpy's
    resolver: ``package://`` and relative paths searched from the folder up), None where no file is found.
    A file found must be a mesh file (:data:`MESH_SUFFIXES`), and a path written relative to the robot must
    stay in the robot's folder: a relative path in the URDF's folder, a ``package://PACKAGE/`` path in that
    package (the URDF's nearest ancestor folder of that name) or its folder; else an InputError. An
    absolute path (``/…``, ``file:///…``) names its file itself, as :func:`write_urdf` writes a robot's
    meshes where they are installed."""
    from yourdfpy import filename_handler_magic

    try:
        with _yourdfpy_lines():
            resolved = filename_handler_magic(filename, dir=directory)
    except (TypeError, ValueError):  # yourdfpy's resolver fails on a package path without a file below it
        raise InputError(f"link {link!r}: mesh {filename!r} names no file of a package") from None
    if not os.path.isfile(resolved):
        return None
    found = Path(resolved).resolve()
    if found.suffix.lower() not in MESH_SUFFIXES:
        raise InputError(
            f"link {link!r}: mesh {filename!r} is {found}, not a mesh file ({', '.join(MESH_SUFFIXES)})"
        )
    if not (filename.startswith("file://") or os.path.isabs(filename)):
        folder = Path(directory).resolve()
        roots = [folder]
        if filename.startswith("package://"):
            package = filename[len("package://") :].split("/", 1)[0]
            roots += [a for a in folder.parents if package and a.name == package][:1]
        if not any(found.is_relative_to(root) for root in roots):
            where = " or ".join(str(r) for r in roots)
            raise InputError(
                f"link {link!r}: mesh {filename!r} is {found}, outside the robot's folder {where}"
            )
    return str(found)


def _geometry_radius(link: Any, axle_local: np.ndarray, directory: str) -> float | None:
    """Radius of a wheel link about its axle (in the link frame) from its collision, else visual, geometry: a
    sphere's or a cylinder's along the axle radius, a mesh's half width across the axle."""
    for shapes in (link.collisions, link.visuals):
        for shape in shapes:
            g = shape.geometry
            if g is None:
                continue
            if g.sphere is not None:
                return float(g.sphere.radius)
            pose = np.eye(4) if shape.origin is None else np.asarray(shape.origin, dtype=float)
            rotation = pose[:3, :3]
            if g.cylinder is not None and abs(abs(rotation[:, 2] @ axle_local) - 1.0) < 1e-6:
                return float(g.cylinder.radius)
            if g.mesh is not None:
                resolved = _mesh_file(g.mesh.filename, directory, link.name)
                if resolved is not None:
                    import trimesh

                    mesh = trimesh.load(resolved, force="mesh")
                    scale = np.broadcast_to(np.asarray(1.0 if g.mesh.scale is None else g.mesh.scale), 3)
                    # trimesh types load() as returning the base Geometry; force="mesh" gives a Trimesh
                    points = (np.asarray(mesh.vertices) * scale) @ rotation.T  # type: ignore[attr-defined]
                    across = np.linalg.svd(np.outer(axle_local, axle_local) - np.eye(3))[0][:, :2]
                    extent = np.ptp(points @ across, axis=0)  # the mesh's widths across the axle
                    return float(np.mean(extent) / 2)
    return None


class _PlatformReader:
    """The view of the URDF file that a platform's ``from_urdf`` reads (:class:`mobman.model.platforms.urdf_form.
    UrdfReader`): wheel-joint candidates are the continuous joints off the chains hanging from the platform."""

    def __init__(
        self,
        tree: _Tree,
        passive: list,
        groups: Mapping[str, tuple[int, int] | None],
        poses: Mapping[str, np.ndarray],
        base_pose: np.ndarray,
        directory: str,
        wheels: tuple[str, str] | None,
        options: Mapping[str, float],
    ) -> None:
        self.tree, self.poses, self.directory = tree, poses, directory
        self.inv = np.linalg.inv(base_pose)
        self.candidates = [j for j in passive if j.type == "continuous" and groups[j.parent] is None]
        self.on_platform = [j for j in passive if groups[j.parent] is None]
        self.wheels, self.options = wheels, options

    def _centre_axis(self, joint: Any) -> tuple[np.ndarray, np.ndarray]:
        """Centre and axle of a wheel joint in the base frame (the joint frame after its motion is the wheel
        link's frame; its pose at the reference configuration)."""
        t = self.inv @ self.poses[joint.child]
        return t[:3, 3], t[:3, :3] @ _axis(joint)

    def _common_axle(self, a: Any, b: Any) -> bool:
        (pa, axa), (pb, axb) = self._centre_axis(a), self._centre_axis(b)
        d = pb - pa
        separation = np.linalg.norm(d)
        return bool(
            separation > _AXLE_TOL
            and abs(abs(axa @ axb) - 1.0) < _AXLE_TOL
            and abs(abs(d @ axa) / separation - 1.0) < _AXLE_TOL
            and abs(axa[2]) < _AXLE_TOL
        )

    def wheel(self, name: str) -> UrdfWheel:
        """The wheel joint ``name`` with its centre."""
        return self._wheel(self.tree.joints[name])

    def _wheel(self, joint: Any) -> UrdfWheel:
        x, y, z = (float(v) for v in self._centre_axis(joint)[0])
        return UrdfWheel(joint.name, x, y, z)

    def _sides(self, a: Any, b: Any) -> tuple[UrdfWheel, UrdfWheel]:
        """(right, left) of an axle, ModelError unless it is along the base's y axis."""
        (pa, axis), (pb, _) = self._centre_axis(a), self._centre_axis(b)
        right, left = (a, b) if pa[1] < pb[1] else (b, a)
        if abs(abs(axis[1]) - 1.0) > _AXLE_TOL:
            raise ModelError(
                f"URDF: the axle of {right.name!r} and {left.name!r} is not along the y axis of the base link "
                "(the platform's heading is the base's x axis)"
            )
        return self._wheel(right), self._wheel(left)

    def _pairs(self) -> list[tuple]:
        c = self.candidates
        return [(a, b) for k, a in enumerate(c) for b in c[k + 1 :] if self._common_axle(a, b)]

    def continuous_joints(self) -> tuple[str, ...]:
        return tuple(j.name for j in self.candidates)

    def axles(self) -> list[tuple[UrdfWheel, UrdfWheel]]:
        return [self._sides(a, b) for a, b in self._pairs()]

    def wheel_pair(self) -> tuple[UrdfWheel, UrdfWheel]:
        if self.wheels is not None:
            pair = []
            for name in self.wheels:
                if name not in self.tree.joints:
                    raise ModelError(f"wheels: no joint named {name!r} in the URDF")
                if self.tree.joints[name].type not in ("continuous", "revolute"):
                    raise ModelError(
                        f"wheels: joint {name!r} is {self.tree.joints[name].type}, not continuous"
                    )
                pair.append(self.tree.joints[name])
            if not self._common_axle(*pair):
                raise ModelError(
                    f"wheels: joints {self.wheels[0]!r} and {self.wheels[1]!r} have no common horizontal axle"
                )
            return self._sides(*pair)
        pairs = self._pairs()
        pairs = [p for p in pairs if all(j.limit is not None for j in p)] or pairs  # driven wheels first
        if not pairs:
            seen = ", ".join(self.continuous_joints()) or "none"
            raise ModelError(
                "URDF: no pair of wheel joints with a common horizontal axle (two continuous joints off the arm "
                f"chains); continuous joints seen: {seen}; name the drive wheels (wheels=(right, left), "
                "--wheels RIGHT,LEFT), give the wheel radius and half track where the wheels are fixed joints or "
                "absent (--platform-option wheel_radius=R --platform-option half_track=B) or choose another "
                "platform (platform='omnidirectional' or 'fixed', --platform)"
            )
        if len(pairs) > 1:
            listed = "; ".join(f"({a.name}, {b.name})" for a, b in pairs)
            raise ModelError(
                f"URDF: several wheel pairs qualify: {listed}; name one with wheels=(right, left) (--wheels RIGHT,LEFT)"
            )
        return self._sides(*pairs[0])

    def steering_joints(self) -> list[UrdfWheel]:
        wheels = set(self.wheels or ()) | {
            name for pair in self._pairs() for name in (pair[0].name, pair[1].name)
        }
        out = []
        for j in self.on_platform:
            if j.type == "revolute" and j.name not in wheels:
                if abs(abs(self._centre_axis(j)[1][2]) - 1.0) < 1e-9:
                    out.append(self._wheel(j))
        return out

    def _geometry_radius(self, wheel: UrdfWheel) -> float | None:
        joint = self.tree.joints[wheel.name]
        return _geometry_radius(self.tree.links[joint.child], _axis(joint), self.directory)

    def wheel_radius(self, wheel: UrdfWheel) -> float:
        if "wheel_radius" in self.options:
            return float(self.options["wheel_radius"])
        r = self._geometry_radius(wheel)
        if r is None:
            raise ModelError(
                f"URDF link {self.tree.joints[wheel.name].child!r}: no cylinder, sphere or mesh gives the wheel "
                "radius; give it: --platform-option wheel_radius=R (platform_options={'wheel_radius': R})"
            )
        return r

    def half_track(self, measured: float) -> float:
        return float(self.options.get("half_track", measured))

    def base_height(self, wheels: Sequence[UrdfWheel], radius: float | None = None) -> float | None:
        if radius is None:
            radius = self.options.get("wheel_radius", self._geometry_radius(wheels[0]))
        if radius is None:
            return None
        height = float(radius) - float(np.mean([w.z for w in wheels]))
        return 0.0 if abs(height) < _ON_THE_GROUND else height

    def without_wheels(self, *names: str) -> bool:
        return self.wheels is None and not self._pairs() and all(n in self.options for n in names)

    def wheel_speed(self, wheels: Sequence[UrdfWheel]) -> float | None:
        joints = [self.tree.joints[w.name] for w in wheels]
        speeds = [j.limit.velocity for j in joints if j.limit is not None and _limit(j.limit.velocity)]
        return min(speeds) if len(speeds) == len(joints) else None

    def build(self, cls, **values):
        allowed = [f.name for f in fields(cls) if f.init]
        for key in self.options:
            if key not in allowed:
                listed = ", ".join([*allowed, *READING_OPTIONS])
                raise ModelError(
                    f"platform option {key!r}: not a parameter of {cls.__name__} (the {cls.kind} platform; "
                    f"allowed: {listed})"
                )
        return cls(**{**{k: v for k, v in values.items() if k in allowed}, **self.options})


def _spin_inertia(tree: _Tree, joint: Any, poses: Mapping[str, np.ndarray]) -> float:
    """a_wᵀ I a_w of the wheel link (and what is fixed to it) about the axle through its centre of mass."""
    frame = poses[joint.child]
    parts = _inertial_parts(tree, [joint.child], frame, poses)
    lumped = _lump(parts)
    if lumped is None:
        return 0.0
    axis = _axis(joint)
    return float(axis @ lumped[2] @ axis)


def _mimic_values(
    tree: _Tree, locked: Mapping[str, float], paths: Sequence[Sequence[Any]], tips: Sequence[str]
) -> tuple[dict[str, float], list[tuple[str, str, float]], list[tuple[str, str, float, float]]]:
    """Where each mimic joint is: URDF's q = multiplier · q_leader + offset. One whose leader does not move
    with q (locked, or a passive joint held at 0, or a mimic of those) is held at its value. One that moves
    with a chain coordinate (directly or through other mimics: q = slope · q_coordinate + intercept) follows
    it: on a chain it is an error (mobman's arms have one coordinate per joint), off the chains it moves a
    :class:`mobman.model.robot.Follower`. Returns the held values (the ``locked`` ones included, a follower's
    at its coordinate's 0), the (joint, leader, value) of each mimic held and the (joint, coordinate,
    slope, intercept) of each follower."""
    coordinates = {
        j.name: t
        for t, joints in zip(tips, paths)
        for j in joints
        if j.type in _MOVING and j.name not in locked and j.mimic is None
    }
    on_paths = {j.name: t for t, joints in zip(tips, paths) for j in joints}
    # per joint: (slope, intercept, coordinate): q = slope · q_coordinate + intercept (slope 0: held)
    known: dict[str, tuple[float, float, str | None]] = {n: (0.0, v, None) for n, v in locked.items()}
    mimics: list[tuple[str, str, float]] = []
    followers: list[tuple[str, str, float, float]] = []

    def value(joint: Any, seen: tuple[str, ...]) -> tuple[float, float, str | None]:
        if joint.name in known:
            return known[joint.name]
        if joint.name in coordinates:
            return 1.0, 0.0, joint.name
        if joint.mimic is None or joint.type not in _MOVING:
            return 0.0, 0.0, None
        if joint.name in seen:
            raise ModelError(f"URDF mimic joints {' → '.join((*seen, joint.name))}: a cycle")
        leader = tree.joints.get(joint.mimic.joint)
        if leader is None:
            raise ModelError(
                f"URDF joint {joint.name!r} mimics {joint.mimic.joint!r}, which is not a joint of the file"
            )
        slope, intercept, coordinate = value(leader, (*seen, joint.name))
        multiplier = 1.0 if joint.mimic.multiplier is None else float(joint.mimic.multiplier)
        offset = 0.0 if joint.mimic.offset is None else float(joint.mimic.offset)
        known[joint.name] = (multiplier * slope, multiplier * intercept + offset, coordinate)
        return known[joint.name]

    for joint in tree.joints.values():
        if joint.mimic is None or joint.name in locked or joint.type not in _MOVING:
            continue
        slope, intercept, coordinate = value(joint, ())
        if coordinate is None:
            mimics.append((joint.name, joint.mimic.joint, intercept))
            continue
        if joint.name in on_paths:
            raise ModelError(
                f"URDF joint {joint.name!r} on the chain to {on_paths[joint.name]!r} mimics "
                f"{joint.mimic.joint!r}, which moves with {coordinate!r} of the chain to "
                f"{coordinates[coordinate]!r}: mobman's arms have one coordinate per joint; lock {coordinate} "
                f"(locked={{{coordinate!r}: value}}, --lock) and it follows"
            )
        followers.append((joint.name, coordinate, slope, intercept))
    return {name: intercept for name, (_, intercept, _) in known.items()}, mimics, followers


def _follower_joints(
    tree: _Tree, following: Sequence[tuple[str, str, float, float]]
) -> list[tuple[Any, tuple[str, float, float]]]:
    """The joints of ``following`` (joint, coordinate, slope, intercept) with their (coordinate, slope,
    intercept), in the order of a walk down the tree: a follower below another comes after it."""
    wanted = {name: (coordinate, slope, intercept) for name, coordinate, slope, intercept in following}
    order, stack = [], [tree.root]
    while stack:
        for j in tree.children.get(stack.pop(), []):
            if j.name in wanted:
                order.append(j)
            stack.append(j.child)
    return [(j, wanted[j.name]) for j in order]


def _planar_base_joints(chain: Sequence[Any], poses: Mapping[str, np.ndarray], base_pose: np.ndarray) -> list:
    """The virtual base joints a simulator export starts the chain with (joint_x, joint_y, joint_rz): two
    prismatic joints across the base's plane and at most one revolute joint about its vertical (after them
    only at their point, as exports stack them); [] when the chain does not start so."""
    inv = np.linalg.inv(base_pose)
    run: list = []
    translations: list[np.ndarray] = []
    turned = False
    for j in chain:
        axis = (inv @ poses[j.parent] @ _origin(j))[:3, :3] @ _axis(j)
        if j.type == "prismatic" and abs(axis[2]) < _AXLE_TOL and len(translations) < 2:
            translations.append(axis)
        elif (
            j.type != "prismatic"
            and not turned
            and abs(abs(axis[2]) - 1.0) < _AXLE_TOL
            and (len(translations) < 2 or np.allclose(_origin(j)[:3, 3], 0.0))
        ):
            turned = True
        else:
            break
        run.append(j)
    if len(translations) < 2 or abs(np.cross(translations[0], translations[1])[2]) < _AXLE_TOL:
        return []
    return run


def read_urdf(
    path: str | os.PathLike[str],
    tip: str | Sequence[str] = "arm_tool_link",
    base: str = "base_footprint",
    platform: str = "auto",
    wheels: tuple[str, str] | None = None,
    wheel_radius: float | None = None,
    half_track: float | None = None,
    name: str | None = None,
    locked: Mapping[str, float] | None = None,
    platform_options: Mapping[str, float] | None = None,
) -> UrdfModel:
    """Read a mobile manipulator from a URDF file (see the module docstring for every rule).

    ``tip``: the end-effector link, or several (one arm each); ``base``: the platform link; ``platform``:
    ``"auto"`` | ``"differential"`` | ``"car"`` | ``"skid_steer"`` | ``"omnidirectional"`` | ``"fixed"``;
    ``wheels``: (right, left) wheel joint names; ``wheel_radius``, ``half_track``: override the values read
    (the same as these keys of ``platform_options``); ``name``: the robot's name (default the URDF's);
    ``locked``: joints held at fixed values (rad or m); ``platform_options``: the platform's parameters that
    the file does not state or that override it (a skid-steer's ``x_icr`` and ``track_factor``, a wheel
    radius and half track where the wheels are fixed joints or absent) and ``base_height``, the base link's
    height above the ground (m) where the wheels do not give it. Returns the robot, its :class:`UrdfSummary`,
    the platform's inertials and the effort limits; what is read differently from the file is also a
    :class:`UrdfWarning`.
    """
    kinds = ("auto", *platform_kinds())
    if platform not in kinds:
        close = difflib.get_close_matches(str(platform), kinds, n=1)
        hint = f" (did you mean {close[0]!r}?)" if close else ""
        raise ModelError(f"platform must be one of {', '.join(kinds)}, got {platform!r}{hint}")
    if wheels is not None and (isinstance(wheels, str) or len(wheels) != 2):
        raise ModelError(f"wheels: two joint names (right, left), got {wheels!r}")
    options = dict(platform_options or {})
    options.update(
        {k: v for k, v in (("wheel_radius", wheel_radius), ("half_track", half_track)) if v is not None}
    )
    for key, value in options.items():
        if not isinstance(value, (int, float)) or isinstance(value, bool) or not math.isfinite(value):
            raise ModelError(f"platform option {key}: must be a finite number, got {value!r}")
    given_height = options.pop("base_height", None)
    urdf, file = _parse(path)
    try:
        return _read(urdf, file, tip, base, platform, wheels, name, locked, options, given_height)
    except InputError as exc:  # what the file holds (its tree, its meshes): said with the file's name
        text = str(exc)
        raise InputError(text if text.startswith(f"{file}: ") else f"{file}: {text}") from None


def _read(
    urdf: Any,
    file: Path,
    tip: str | Sequence[str],
    base: str,
    platform: str,
    wheels: tuple[str, str] | None,
    name: str | None,
    locked: Mapping[str, float] | None,
    options: dict[str, float],
    given_height: float | None,
) -> UrdfModel:
    """:func:`read_urdf` of the parsed file ``urdf`` with its checked options."""
    tree = _Tree.of(urdf.robot, file)
    tips = (tip,) if isinstance(tip, str) else tuple(tip) if isinstance(tip, (list, tuple)) else (tip,)
    if not tips:
        raise ModelError("tip: give at least one tip link")
    for t in tips:
        if not isinstance(t, str):
            raise ModelError(f"tip: a link's name or a list of them, got {t!r}")
    if not isinstance(locked, (Mapping, type(None))):
        raise ModelError(f"locked: a mapping of joint names to values, got {type(locked).__name__}")
    locked = dict(locked or {})
    for joint_name, value in locked.items():
        if joint_name not in tree.joints or tree.joints[joint_name].type not in _MOVING:
            raise ModelError(f"locked: {joint_name!r} is not a moving joint of the URDF")
        if not isinstance(value, (int, float, np.integer, np.floating)) or isinstance(value, bool):
            raise ModelError(f"locked: {joint_name} must be a number (rad or m), got {value!r}")
        if not math.isfinite(value):
            raise ModelError(f"locked: {joint_name} must be finite, got {value!r}")
    paths = [tree.path(base, t) for t in tips]
    held, mimics, following = _mimic_values(tree, locked, paths, tips)
    notes: list[str] = []
    poses = _poses(tree, held)
    base_pose = poses[base]
    chains: list[list] = []
    owner: dict[str, str] = {}
    for t, joints in zip(tips, paths):
        chain = []
        for j in joints:
            if j.type in ("floating", "planar"):
                raise ModelError(f"URDF joint {j.name!r} on the chain to {t!r} is {j.type}: not supported")
            if j.type not in _MOVING or j.name in held:
                continue
            if j.name in owner:
                raise ModelError(
                    f"URDF joint {j.name!r} is on the chains to {owner[j.name]!r} and {t!r}; mobman's arms share "
                    f"no joint: lock it with locked={{{j.name!r}: value}}"
                )
            owner[j.name] = t
            chain.append(j)
        if not chain:
            raise ModelError(f"URDF: no moving joint between {base!r} and {t!r}")
        virtual = _planar_base_joints(chain, poses, base_pose)
        if virtual:
            raise ModelError(
                f"URDF joints {', '.join(j.name for j in virtual)} on the chain to {t!r} move {base!r} in the "
                "plane (a simulator's virtual base joints): the platform's x, y, θ already do; read the robot "
                f"from the link below them (--base {virtual[-1].child}, base={virtual[-1].child!r})"
            )
        chains.append(chain)
    starts = {j.child: (i, k) for i, chain in enumerate(chains) for k, j in enumerate(chain)}
    groups = _groups(tree, starts)  # the bodies that carry each link's mass
    follower_joints = _follower_joints(tree, following)
    shown = _groups(tree, starts | {j.child: (FOLLOWER, f) for f, (j, _) in enumerate(follower_joints)})
    on_chain = {j.name for chain in chains for j in chain}
    passive = [
        j for j in urdf.robot.joints if j.type in _MOVING and j.name not in on_chain and j.name not in locked
    ]
    directory = str(file.parent)

    # platform: its frame on the ground the wheels define (or base_height given), at their reference point
    reader = _PlatformReader(tree, passive, groups, poses, base_pose, directory, wheels, options)
    reading = platform_class("differential" if platform == "auto" else platform).from_urdf(reader)
    platform_model = reading.platform
    wheel_joints = [tree.joints[n] for n in reading.wheel_joints]
    height = reading.base_height if given_height is None else float(given_height)
    if height is None and platform_model.wheels():
        notes.append(
            f"no wheel joint of the file gives the ground under {base!r}: the platform frame is at its height and "
            f"every height is measured from it; give its height above the ground: --platform-option "
            "base_height=H (platform_options={'base_height': H}), or choose a base link on the ground"
        )
    offset = np.array([*reading.reference, -(height or 0.0)])
    summary_extra = _platform_summary(reading, reader)
    wheel_pair = tuple(wheel_joints) or None
    platform_pose = base_pose @ spatial.as_matrix(spatial.transform(None, tuple(offset)))

    # arms
    missing: list[str] = []
    materials = {m.name: m for m in urdf.robot.materials if m.name}
    by_group: dict = {}
    for link, g in groups.items():
        by_group.setdefault(g, []).append(link)
    by_shape: dict = {}  # the bodies that carry each link's shapes: the followers' links their own
    for link, g in shown.items():
        by_shape.setdefault(g, []).append(link)
    arms = []
    folded: list[str] = []
    for i, (t, joints) in enumerate(zip(tips, paths)):
        chain_names = {j.name for j in chains[i]}
        acc = np.linalg.inv(platform_pose) @ base_pose
        arm_joints: list[Joint] = []
        for j in joints:
            if j.name not in chain_names:
                acc = acc @ _origin(j)
                if j.type in _MOVING:
                    acc = acc @ _motion(j.type, _axis(j), held[j.name])
                else:
                    folded.append(j.name)
                continue
            k = len(arm_joints)
            frame = poses[j.child]
            lumped = _lump(_inertial_parts(tree, by_group.get((i, k), []), frame, poses))
            limit = j.limit
            bounded = j.type != "continuous" and limit is not None
            arm_joints.append(
                Joint(
                    kind="prismatic" if j.type == "prismatic" else "revolute",
                    axis=tuple(_axis(j)),
                    origin=tuple((acc @ _origin(j)).ravel()),
                    name=j.name,
                    lower=float(limit.lower) if bounded and limit.lower is not None else -math.inf,
                    upper=float(limit.upper) if bounded and limit.upper is not None else math.inf,
                    velocity_max=None if limit is None else _limit(limit.velocity),
                    effort_max=None if limit is None else _limit(limit.effort),
                    inertial=None
                    if lumped is None or lumped[0] <= 0
                    else LinkInertial(lumped[0], tuple(lumped[1]), tuple(lumped[2].ravel())),
                    visuals=_visuals(
                        tree, by_shape.get((i, k), []), frame, poses, directory, materials, missing
                    ),
                )
            )
            acc = np.eye(4)
        arms.append(Arm(tuple(arm_joints), tuple(acc.ravel()), name=t))

    unlimited = [
        j.name for i in range(len(tips)) for j in chains[i] if j.limit is not None and j.limit.velocity == 0
    ]
    if unlimited:
        notes.append(
            f"velocity limit 0 read as none given (URDF requires the attribute and writers put 0 where they know "
            f"no limit): joint{'s' * (len(unlimited) > 1)} {', '.join(map(repr, unlimited))}"
        )
    platform_links = by_group.get(None, [])
    shapes = functools.partial(
        _visuals, poses=poses, directory=directory, materials=materials, missing=missing
    )
    frames = {None: platform_pose} | {
        (i, k): poses[j.child] for i, c in enumerate(chains) for k, j in enumerate(c)
    }
    frames |= {(FOLLOWER, f): poses[j.child] for f, (j, _) in enumerate(follower_joints)}
    coordinate = {
        j.name: sum(map(len, chains[:i])) + k for i, c in enumerate(chains) for k, j in enumerate(c)
    }
    followers = []
    for f, (j, (leader, slope, intercept)) in enumerate(follower_joints):
        parent = shown[j.parent]
        limit = j.limit
        bounded = j.type != "continuous" and limit is not None
        joint = Joint(
            kind="prismatic" if j.type == "prismatic" else "revolute",
            axis=tuple(_axis(j)),
            origin=tuple((np.linalg.inv(frames[parent]) @ poses[j.parent] @ _origin(j)).ravel()),
            offset=intercept,
            name=j.name,
            lower=float(limit.lower) if bounded and limit.lower is not None else -math.inf,
            upper=float(limit.upper) if bounded and limit.upper is not None else math.inf,
            visuals=shapes(tree, by_shape.get((FOLLOWER, f), []), frame=poses[j.child]),
        )
        index = platform_model.n_q + coordinate[leader]
        followers.append(Follower(joint, PLATFORM if parent is None else parent, index, slope))
    robot = MobileManipulator(
        platform_model,
        tuple(arms),
        name=name or urdf.robot.name or file.stem,
        platform_visuals=shapes(tree, by_shape.get(None, []), frame=platform_pose),
        followers=tuple(followers),
    )
    body, wheel = _platform_inertials(tree, platform_links, platform_pose, poses, wheel_pair)
    efforts = _platform_efforts(platform_model, wheel_joints)
    efforts += [j.effort_max for a in arms for j in a.joints]
    summary = UrdfSummary(
        path=str(file),
        name=robot.name,
        base=base,
        tips=tips,
        platform=type(platform_model).__name__,
        chains=tuple(tuple(j.name for j in chain) for chain in chains),
        folded=tuple(folded),
        locked=tuple(locked.items()),
        passive=tuple(j.name for j in passive if j.mimic is None),
        missing_meshes=tuple(dict.fromkeys(missing)),
        base_height=height,
        mimics=tuple(mimics),
        followers=tuple(following),
        notes=tuple(notes),
        **summary_extra,
    )
    for note in notes:
        warnings.warn(note, UrdfWarning, stacklevel=3)
    return UrdfModel(robot, summary, body, wheel, tuple(efforts))


def _platform_summary(reading: UrdfPlatform, reader: _PlatformReader) -> dict:
    """The summary's lines on the platform: its wheels (the (right, left) pair the platform names), the
    reference point and how its velocity limits were obtained."""
    platform = reading.platform
    if reading.sides is None:
        return dict(platform_limits=f"platform velocity limits: none ({platform.kind}, not in URDF)")
    right, left = (reader.wheel(n) for n in reading.sides)
    r, b = reader.wheel_radius(right), reader.half_track(distance(right, left) / 2)
    speed = reader.wheel_speed([reader.wheel(n) for n in reading.wheel_joints])
    if speed is None:
        limits_text = "platform velocity limits: none (the wheel joints give no velocity limit)"
    else:
        v, w = platform.velocity_limits or (r * speed, r * speed / b)
        limits_text = (
            f"platform velocity limits from the wheel speed limit {speed:.6g} rad/s: the diamond "
            f"|v|/{v:.6g} + |ω|/{w:.6g} ≤ 1; normalised measures use its vertices "
            f"v_max = {v:.6g} m/s, ω_max = {w:.6g} rad/s"
        )
    return dict(
        wheels=reading.sides,
        wheel_radius=float(r),
        half_track=b,
        reference_point=(float(reading.reference[0]), float(reading.reference[1])),
        platform_limits=limits_text,
    )


def _platform_efforts(platform: Platform, wheel_joints: Sequence[Any]) -> list[float | None]:
    """Effort limits of the platform's actuators: per actuator the sum of its wheels' joint efforts (None
    where one is missing); None for a platform without driven wheels."""
    if not platform.wheel_actuated:
        return [None] * platform.n_eta
    efforts: list[float | None] = []
    for k in range(platform.n_eta):
        joints = [j for j, w in zip(wheel_joints, platform.wheels()) if w.actuator == k]
        values = [None if j.limit is None else _limit(j.limit.effort) for j in joints]
        known = [v for v in values if v is not None]
        efforts.append(float(sum(known)) if len(known) == len(values) else None)
    return efforts


def _platform_inertials(tree, links, platform_pose, poses, wheel_pair):
    lumped = _lump(_inertial_parts(tree, links, platform_pose, poses))
    if lumped is None or lumped[0] <= 0:
        return None, None
    mass, com, inertia = lumped
    body = PlatformBody(mass, float(inertia[2, 2]), tuple(com))
    if wheel_pair is None:
        return body, None
    spins = [_spin_inertia(tree, j, poses) for j in wheel_pair]
    return body, Wheel(0.0, float(np.mean(spins)), 0.0)


def load_urdf(
    path: str | os.PathLike[str],
    tip: str | Sequence[str] = "arm_tool_link",
    base: str = "base_footprint",
    platform: str = "auto",
    wheels: tuple[str, str] | None = None,
    wheel_radius: float | None = None,
    half_track: float | None = None,
    name: str | None = None,
    locked: Mapping[str, float] | None = None,
    platform_options: Mapping[str, float] | None = None,
) -> MobileManipulator:
    """A :class:`mobman.MobileManipulator` from a URDF file in one line (:func:`read_urdf`'s robot).

    >>> robot = load_urdf("tiago.urdf", tip="arm_tool_link")  # doctest: +SKIP
    """
    return read_urdf(
        path, tip, base, platform, wheels, wheel_radius, half_track, name, locked, platform_options
    ).robot


def inspect_urdf(path: str | os.PathLike[str], **options: Any) -> UrdfSummary:
    """What :func:`read_urdf` keeps and leaves out of a URDF file (chains, wheels, passive joints)."""
    return read_urdf(path, **options).summary


def collision_shapes(model: UrdfModel) -> dict[tuple[int, int], tuple[Visual, ...]]:
    """The ``<collision>`` shapes of a robot read by :func:`read_urdf`, per body ((−1, 0) the platform, (arm,
    joint index) a link, (−2, k) a follower, as :mod:`mobman.model.collision_model` numbers them), each in its
    body's frame (the frames its visuals are in): what :meth:`mobman.model.collision_model.CollisionModel.from_shapes` covers
    with spheres. Links off the chains go with the body they hang from; meshes not found are left out."""
    summary, robot = model.summary, model.robot
    urdf, file = _parse(summary.path)
    tree = _Tree.of(urdf.robot, file)
    held = dict(summary.locked) | {joint: value for joint, _, value in summary.mimics}
    held |= {follower.joint.name: follower.joint.offset for follower in robot.followers}
    poses = _poses(tree, held)
    starts = {
        tree.joints[name].child: (i, k)
        for i, chain in enumerate(summary.chains)
        for k, name in enumerate(chain)
    }
    starts |= {tree.joints[f.joint.name].child: (FOLLOWER, k) for k, f in enumerate(robot.followers)}
    rotations, origins = compiled_frames(robot, np.zeros(robot.n_q)).links[0]  # the platform at the origin
    first = spatial.as_matrix(spatial.transform(np.asarray(rotations[0]), tuple(np.asarray(origins[0]))))
    frames: dict[tuple[int, int] | None, np.ndarray] = {
        None: poses[tree.joints[summary.chains[0][0]].child] @ np.linalg.inv(first)
    }
    frames |= {body: poses[child] for child, body in starts.items()}
    shapes: dict[tuple[int, int], tuple[Visual, ...]] = {}
    for link, body in _groups(tree, starts).items():
        found = _visuals(tree, [link], frames[body], poses, str(file.parent), {}, [], element="collisions")
        key = (-1, 0) if body is None else body
        shapes[key] = shapes.get(key, ()) + found
    return shapes


# --- writing ---------------------------------------------------------------------------------------


def _u_inertial(mass: float, com: npt.ArrayLike, inertia: npt.ArrayLike) -> "object":
    from yourdfpy import Inertial

    origin = np.eye(4)
    origin[:3, 3] = com
    return Inertial(origin=origin, mass=float(mass), inertia=np.asarray(inertia, dtype=float).reshape(3, 3))


def _u_visuals(visuals: Sequence[Visual]) -> list:
    from yourdfpy import Box, Color, Cylinder, Geometry, Material, Mesh, Sphere
    from yourdfpy import Visual as UVisual

    shapes = []
    for v in visuals:
        if v.kind == "box":
            geometry = Geometry(box=Box(np.asarray(v.size)))
        elif v.kind == "cylinder":
            geometry = Geometry(cylinder=Cylinder(*v.size))
        elif v.kind == "sphere":
            geometry = Geometry(sphere=Sphere(v.size[0]))
        else:
            geometry = Geometry(mesh=Mesh(v.filename, np.asarray(v.scale)))
        material = Material(name=None, color=Color(np.asarray(v.rgba)))
        shapes.append(
            UVisual(
                name=v.name or None, origin=spatial.as_matrix(v.origin), geometry=geometry, material=material
            )
        )
    return shapes


def _wheel(
    name: str,
    parent: str,
    xyz: tuple[float, float, float],
    radius: float,
    speed: float | None,
    wheel: Wheel | None,
) -> tuple[Any, Any]:
    """A continuous wheel joint turning about the platform's y axis, with its link (cylinder collision)."""
    from yourdfpy import Collision, Cylinder, Geometry, Limit, Link
    from yourdfpy import Joint as UJoint

    origin = np.eye(4)
    origin[:3, :3] = spatial.rot_x(-math.pi / 2)  # the joint's z axis along the platform's y axis
    origin[:3, 3] = xyz
    inertial = None
    if wheel is not None and (wheel.mass > 0 or wheel.I_w > 0 or wheel.I_m > 0):
        # about the centre: I_m about the diameters (local x, y), I_w about the axle (local z)
        inertial = _u_inertial(wheel.mass, (0.0, 0.0, 0.0), np.diag([wheel.I_m, wheel.I_m, wheel.I_w]))
    collision = Collision(name=None, origin=np.eye(4), geometry=Geometry(cylinder=Cylinder(radius, 0.02)))
    link = Link(f"{name}_link", inertial=inertial, collisions=[collision])
    limit = None if speed is None else Limit(effort=None, velocity=float(speed))
    joint = UJoint(
        f"{name}_joint", "continuous", parent, link.name, origin, np.array([0.0, 0.0, 1.0]), limit=limit
    )
    return link, joint


def _platform_urdf(
    robot: MobileManipulator, body: PlatformBody | None, wheel: Wheel | None
) -> tuple[list, list]:
    """The platform link and the joints of the platform's URDF form (:meth:`Platform.urdf_joints`)."""
    from yourdfpy import Joint as UJoint
    from yourdfpy import Limit, Link

    inertial = None
    if body is not None:
        inertial = _u_inertial(body.mass, body.com, np.diag([0.0, 0.0, body.inertia_z]))
    links = [Link("base_footprint", inertial=inertial, visuals=_u_visuals(robot.platform_visuals))]
    joints: list = []
    for part in robot.platform.urdf_joints():
        if part.radius is not None:
            link, joint = _wheel(
                part.name, part.parent, part.xyz, part.radius, part.speed, wheel if part.driven else None
            )
        else:
            origin = np.eye(4)
            origin[:3, 3] = part.xyz
            lower, upper = part.limits or (-math.pi, math.pi)
            link = Link(f"{part.name}_link")
            joint = UJoint(
                f"{part.name}_joint",
                "revolute",
                part.parent,
                link.name,
                origin,
                np.array([0.0, 0.0, 1.0]),
                limit=Limit(effort=None, velocity=None, lower=lower, upper=upper),
            )
        links.append(link)
        joints.append(joint)
    return links, joints


def _limit_value(value: float) -> float | None:
    return None if not math.isfinite(value) else float(value)


def write_urdf(
    robot: MobileManipulator,
    path: str | os.PathLike[str],
    body: PlatformBody | None = None,
    wheel: Wheel | None = None,
) -> Path:
    """Write a robot as URDF, with its platform ``body`` and driving ``wheel`` inertials where given (those of
    a :class:`mobman.dynamics.DynamicModel`: ``write_urdf(model.robot, path, model.body, model.wheel)``).

    The platform link is ``base_footprint``; arm ``i``'s joints keep their names (prefixed by the arm's name
    when there are several arms) and end in the fixed joint to ``<prefix>tool_link``. Read it back with
    ``read_urdf(path, tip=[tool links], platform=...)`` (the platform's ``kind``: ``"car"`` for a car,
    ``"omnidirectional"`` for a holonomic platform, …): :func:`urdf_tips` gives the tips. Returns the path written.
    """
    from yourdfpy import URDF, Inertial, Limit, Link, Robot
    from yourdfpy import Joint as UJoint

    if not isinstance(robot, MobileManipulator):
        raise ModelError(f"write_urdf: robot must be a MobileManipulator, got {type(robot).__name__}")
    links, joints = _platform_urdf(robot, body, wheel)
    for i, (arm, mount) in enumerate(zip(robot.arms, robot.mounts)):
        prefix = _arm_prefix(robot, i)
        parent, previous = "base_footprint", spatial.as_matrix(mount.transform)
        for joint in arm.joints:
            axis = np.asarray(joint.axis)
            origin = previous @ spatial.as_matrix(joint.origin) @ _motion(joint.kind, axis, joint.offset)
            bounded = math.isfinite(joint.lower) or math.isfinite(joint.upper)
            kind = joint.kind if joint.kind == "prismatic" or bounded else "continuous"
            limit = Limit(
                effort=joint.effort_max or 0.0,
                velocity=joint.velocity_max or 0.0,
                lower=_limit_value(joint.lower) if kind != "continuous" else None,
                upper=_limit_value(joint.upper) if kind != "continuous" else None,
            )
            inertial: Inertial | None = None
            if joint.inertial is not None:
                inertial = _u_inertial(joint.inertial.mass, joint.inertial.com, joint.inertial.inertia)
            child = f"{prefix}{joint.name}_link"
            links.append(Link(child, inertial=inertial, visuals=_u_visuals(joint.visuals)))
            joints.append(UJoint(f"{prefix}{joint.name}", kind, parent, child, origin, axis, limit=limit))
            parent, previous = child, np.eye(4)
        tool = f"{prefix}tool_link"
        links.append(Link(tool))
        joints.append(UJoint(f"{prefix}tool_joint", "fixed", parent, tool, spatial.as_matrix(arm.tool)))
    for link, joint in _followers_urdf(robot):
        links.append(link)
        joints.append(joint)
    file = Path(path)
    xml = URDF(
        Robot(robot.name, links=links, joints=joints), build_scene_graph=False, load_meshes=False
    ).write_xml()
    for joint in joints:  # yourdfpy reads <mimic> but does not write it
        if joint.mimic is not None:
            (element,) = xml.getroot().findall(f"joint[@name='{joint.name}']")
            attributes = {"multiplier": repr(joint.mimic.multiplier), "offset": repr(joint.mimic.offset)}
            element.append(element.makeelement("mimic", {"joint": joint.mimic.joint, **attributes}))
    xml.write(str(file), xml_declaration=True, pretty_print=True)
    return file


def _followers_urdf(robot: MobileManipulator) -> list[tuple[Any, Any]]:
    """Each follower as a link (its visuals) and a mimic joint of its leader's joint, below the link of the
    body it hangs from (as :func:`write_urdf` names the links)."""
    from yourdfpy import Joint as UJoint
    from yourdfpy import Limit, Link, Mimic

    names = {PLATFORM: "base_footprint"}
    coordinates = []
    for i, arm in enumerate(robot.arms):
        prefix = _arm_prefix(robot, i)
        names |= {(i, k): f"{prefix}{joint.name}_link" for k, joint in enumerate(arm.joints)}
        coordinates += [f"{prefix}{joint.name}" for joint in arm.joints]
    out = []
    for k, follower in enumerate(robot.followers):
        joint = follower.joint
        child = f"{joint.name}_link"
        names[(FOLLOWER, k)] = child
        bounded = math.isfinite(joint.lower) or math.isfinite(joint.upper)
        kind = joint.kind if joint.kind == "prismatic" or bounded else "continuous"
        limit = Limit(
            effort=0.0,
            velocity=0.0,
            lower=_limit_value(joint.lower) if kind != "continuous" else None,
            upper=_limit_value(joint.upper) if kind != "continuous" else None,
        )
        mimic = Mimic(
            joint=coordinates[follower.leader - robot.n_platform],
            multiplier=follower.multiplier,
            offset=joint.offset,
        )
        urdf_joint = UJoint(
            joint.name,
            kind,
            names[follower.parent],
            child,
            spatial.as_matrix(joint.origin),
            np.asarray(joint.axis),
            limit=limit,
            mimic=mimic,
        )
        out.append((Link(child, visuals=_u_visuals(joint.visuals)), urdf_joint))
    return out


def _arm_prefix(robot: MobileManipulator, index: int) -> str:
    if len(robot.arms) == 1:
        return ""
    labels = [a.name for a in robot.arms]
    if len(set(labels)) != len(labels):
        labels = [f"arm{k + 1}" for k in range(len(robot.arms))]
    return f"{labels[index]}_"


def urdf_tips(robot: MobileManipulator) -> tuple[str, ...]:
    """The tool links that :func:`write_urdf` writes, one per arm."""
    return tuple(f"{_arm_prefix(robot, i)}tool_link" for i in range(len(robot.arms)))
