"""A mobile manipulator as a MuJoCo model (``MjSpec``): a free platform on real wheels, the arms with their
inertials, joint limits and velocity-commanded actuators with mobman's motor limits.

The model (:func:`to_mjspec`; :func:`mjcf_text` is the MJCF file MuJoCo's viewer and mink open):

- **world**: a floor plane (friction ``friction``), gravity −9.81 m/s² along z, time step ``timestep``, the
  ``implicitfast`` integrator (the servos' damping is implicit) and an elliptic friction cone with
  ``impratio`` 10 (stiff tangential contact: a rolling wheel creeps little); the scene's obstacles
  (:class:`mobman.model.scene.Scene`) as static geoms (:func:`add_scene`).
- **platform**: the body ``platform`` with a free joint, its frame at floor level (mobman's platform frame:
  x forward, z up, the wheel centres ``radius`` above it). Its inertial is mobman's platform body
  (:class:`mobman.model.inertial.PlatformBody`: mass, centre of mass, I_c about the vertical); the horizontal
  moments, which mobman's planar platform model does not hold, are completed as a flat disc's,
  I_xx = I_yy = I_c / 2 (:func:`completed_inertia`).
- **wheels** (:meth:`Platform.wheels`): one body per wheel at its centre with a hinge about the axle (y), a
  sphere of the wheel's radius touching the floor under the centre (full sliding friction: rolling without
  slipping holds while friction holds; lateral slip is measurable) and a cylinder drawn. A driven wheel has
  mobman's wheel inertia (m_w; I_w about the axle, I_m about a diameter). A URDF robot's wheels are part of
  its lumped platform body (wheel mass 0): each wheel body then takes the mass of a uniform disc of its spin
  inertia, m = 2 I_w / r², out of the platform body, whose centre of mass and vertical moment change so that
  the total mass, the robot's centre of mass and its moment of inertia about the platform's vertical axis
  are unchanged (:meth:`_Builder.carved_inertia_z`).
- **platform kinds**: *differential*: two driven wheels and two frictionless caster spheres (contact normal
  only, ``condim`` 1) on the centre line at the ends of the footprint; *skid_steer*: four wheels, each side's
  pair coupled by an equality (the drive belt) and driven by one actuator on a tendon of their mean speed;
  *car*: driven rear wheels (one actuator each, as an open differential) and two front wheels each on a
  steering hinge about the vertical, the left hinge kept at the right one's angle by an equality (parallel
  steering: the steering angle φ of Tchoń's bicycle model at both wheels, which scrub slightly when turning);
  *omnidirectional*: no wheels: planar slide joints x, y and a hinge θ (the body held at floor level by its
  joints, not by contacts), each with a velocity servo (η_p = (ẋ, ẏ, θ̇) exactly); *fixed*: the platform
  welded to the world. Another kind
  has no MuJoCo form (:class:`mobman.ModelError`). ``platform="prescribed"`` builds, for any platform whose
  coordinates are (x, y, θ), the platform body on slide joints x, y and a hinge θ named by mobman's
  coordinates, without wheels or platform actuators: a caller drives the platform along a prescribed motion
  (the load-capacity check, :mod:`mobman.physics.load`; Korayem et al. prescribe the base's motion).
- **arms**: one body per joint in its joint frame after the motion (mobman's origin, then the motion about
  ``axis``; the offset folded into the body frame, so MuJoCo's joint position is mobman's q), the link's
  :class:`mobman.LinkInertial` (principal moments completed by :func:`completed_inertia` where the papers give
  only the planar ones), mobman's position limits, a capsule of 2 cm radius to the next joint (drawn, and
  touching the scene's obstacles, never the floor or the robot itself), a site ``<arm>_tool`` at the tool
  frame and the payload (:class:`mobman.Payload`) as a body fixed there.
- **actuators**: a velocity servo per driven wheel (per wheel side for a skid-steer), force = k_v (u − φ̇),
  and an integrated-velocity servo per arm joint (the command is q̇; a position servo holds the integrated
  position, so a joint at rest stays put up to the static deflection τ_gravity / k_p), both clamped to the
  torque limits (``torque_limits``, default the joints' ``effort_max``) and their commands to mobman's
  speed limits. Gains: a first-order velocity response of time constant 0.02 s for the wheels (the robot's
  mass reflected through them), a critically damped position servo of 25 Hz for the joints (the inertia
  MuJoCo computes at the compiled configuration). The DC-motor torque–speed line of
  :class:`mobman.dynamics.DCMotor` is not modelled (a constant torque box).

A robot without inertials (most of the papers' kinematic examples) gets documented stand-ins
(:func:`dynamic_model`): a 1-kg rod of radius 5 cm along each link, a 20-kg platform body, 1-kg disc wheels.
"""

from __future__ import annotations

import math
from dataclasses import replace
from typing import TYPE_CHECKING, Any

import numpy as np
import numpy.typing as npt

from mobman.dynamics.inertia import DynamicModel
from mobman.errors import InputError, ModelError
from mobman.model import spatial
from mobman.model.arm import Joint, LinkInertial
from mobman.model.inertial import PlatformBody, Wheel
from mobman.model.robot import MobileManipulator, actuator_names
from mobman.model.scene import Scene

if TYPE_CHECKING:
    import mujoco

INSTALL = 'pip install -e ".[physics]"'
"""The line that installs MuJoCo with mobman."""

KINDS = ("differential", "skid_steer", "car", "omnidirectional", "fixed")

PLATFORM_FORMS = ("wheels", "prescribed")
"""How :func:`to_mjspec` builds the platform: on its wheels, or on joints x, y, θ driven by the caller."""
"""The platform kinds with a MuJoCo form."""

WHEEL_TIME_CONSTANT = 0.02
"""Time constant (s) of the wheel velocity servos' first-order response."""

JOINT_SERVO_HZ = 25.0
"""Natural frequency (Hz) of the arm joints' position servos (critically damped)."""

CASTER_FRICTION = 0.0
"""Casters and support spheres push only along the contact normal (``condim`` 1)."""

STAND_IN_LINK_MASS = 1.0
STAND_IN_LINK_RADIUS = 0.05
STAND_IN_BODY_MASS = 20.0
STAND_IN_WHEEL_MASS = 1.0
"""Stand-in inertials (kg, m) of a robot without a dynamic model (:func:`dynamic_model`)."""

MIN_MOMENT = 1e-9
"""Smallest principal moment of inertia (kg m²) given to MuJoCo, which refuses moving bodies without one."""

ROBOT_GROUP = 1
"""Contact bit of the robot's wheels and casters: they touch the floor and the obstacles, never each other."""

BODY_GROUP = 2
"""Contact bit of the platform's box and the arm's link capsules: they touch the obstacles only."""


def mujoco_module() -> Any:
    """The ``mujoco`` package, or :class:`mobman.ModelError` with the line that installs it."""
    try:
        import mujoco
    except ImportError:
        raise ModelError(f"the MuJoCo export needs the physics extra: {INSTALL}") from None
    return mujoco


def dynamic_model(robot: MobileManipulator | DynamicModel) -> DynamicModel:
    """The dynamic model exported: ``robot`` itself when it is a :class:`DynamicModel`, else the robot with
    stand-ins for what it lacks: every link without an inertial a uniform rod of
    :data:`STAND_IN_LINK_MASS` kg and radius :data:`STAND_IN_LINK_RADIUS` m from its joint to the next joint's
    origin (the tool's for the last), a platform body of :data:`STAND_IN_BODY_MASS` kg with the vertical
    inertia of a uniform box of its footprint, wheels of :data:`STAND_IN_WHEEL_MASS` kg as uniform discs."""
    if isinstance(robot, DynamicModel):
        return robot
    if not isinstance(robot, MobileManipulator):
        raise InputError(f"robot must be a MobileManipulator or a DynamicModel, got {type(robot).__name__}")
    arms = []
    for arm in robot.arms:
        ends = [j.origin for j in arm.joints[1:]] + [arm.tool]
        joints = tuple(
            j if j.inertial is not None else replace(j, inertial=_rod(spatial.as_matrix(end)[:3, 3]))
            for j, end in zip(arm.joints, ends)
        )
        arms.append(replace(arm, joints=joints))
    foot = robot.platform.footprint()
    m = STAND_IN_BODY_MASS
    body = PlatformBody(m, m * (foot.length**2 + foot.width**2) / 12.0, (foot.x_centre, 0.0, 0.0))
    radius = max((w.radius for w in robot.platform.wheels()), default=0.1)
    m_w = STAND_IN_WHEEL_MASS
    wheel = Wheel(m_w, m_w * radius**2 / 2.0, m_w * radius**2 / 4.0)
    return DynamicModel(replace(robot, arms=tuple(arms)), body, wheel)


def _rod(end: np.ndarray) -> LinkInertial:
    """A uniform rod of mass m and radius ρ from the origin to ``end``: I = m(L²/12 + ρ²/4) across, m ρ²/2
    along."""
    m, rho = STAND_IN_LINK_MASS, STAND_IN_LINK_RADIUS
    length = float(np.linalg.norm(end))
    axis = end / length if length > 0 else np.array([0.0, 0.0, 1.0])
    across, along = m * (length**2 / 12 + rho**2 / 4), m * rho**2 / 2
    inertia = across * np.eye(3) + (along - across) * np.outer(axis, axis)
    return LinkInertial(m, tuple(end / 2), tuple(inertia.ravel()))


def completed_inertia(inertia: npt.ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """Principal moments (3,) and the rotation (3 × 3, columns the principal axes, det +1) of a symmetric
    inertia tensor, made physical for MuJoCo: where the two smaller moments sum to less than the largest (the
    papers give only the moment about the axis their planar motion turns about), both are raised by half the
    difference (a flat plate: I = I_z / 2 across, exact for a disc), and every moment is at least
    :data:`MIN_MOMENT`. A physical tensor is returned unchanged (to rounding)."""
    moments, axes = np.linalg.eigh(np.asarray(inertia, dtype=float).reshape(3, 3))
    if np.linalg.det(axes) < 0:
        axes[:, 0] = -axes[:, 0]
    moments = np.maximum(moments, 0.0)
    deficit = moments[2] - moments[0] - moments[1]
    if deficit > 0:
        moments[:2] += deficit / 2
    return np.maximum(moments, MIN_MOMENT), axes


def to_mjspec(
    robot: MobileManipulator | DynamicModel,
    scene: Scene | None = None,
    *,
    torque_limits: npt.ArrayLike | None = None,
    friction: float = 1.0,
    timestep: float = 1e-3,
    platform: str = "wheels",
) -> "mujoco.MjSpec":
    """The robot as a MuJoCo model (the module docstring lists what is built), standing at q = 0.

    robot: a :class:`DynamicModel` (its inertials, payload), or a :class:`MobileManipulator` (its link
    inertials where it has them, stand-ins for the rest: :func:`dynamic_model`); torque_limits: |τ| per
    actuator in the order of :func:`mobman.model.robot.actuator_names` (wheels, then joints; N·m or N; ``inf``
    for none), default the joints' ``effort_max`` and unlimited wheels; friction: the sliding friction
    coefficient of the wheels on the floor (> 0); timestep: MuJoCo's step (s, > 0); scene: obstacles
    (:class:`mobman.model.scene.Scene`) added as static geoms (:func:`add_scene`); platform: ``"wheels"``
    (the platform on its wheels, as its kind is built) or ``"prescribed"`` (on joints x, y, θ; module notes).

    Returns the :class:`mujoco.MjSpec`; ``spec.compile()`` is the ``MjModel``, :func:`mjcf_text` the MJCF
    text.
    Bodies, joints and actuators carry mobman's names: ``platform``, the wheels of
    :meth:`Platform.urdf_joints` (``wheel_right``, …), the arm joints by ``robot.coordinate_names``.
    """
    mj = mujoco_module()
    model = dynamic_model(robot)
    kind = model.robot.platform.kind
    if kind not in KINDS:
        raise ModelError(f"platform kind {kind!r}: no MuJoCo form; the export supports {', '.join(KINDS)}")
    if not (math.isfinite(friction) and friction > 0):
        raise InputError(f"friction must be a finite number > 0, got {friction!r}")
    if not (math.isfinite(timestep) and timestep > 0):
        raise InputError(f"timestep must be a finite number > 0 (s), got {timestep!r}")
    if platform not in PLATFORM_FORMS:
        raise InputError(f"platform must be one of {', '.join(PLATFORM_FORMS)}, got {platform!r}")
    planar = model.robot.n_platform == 3 and model.robot.coordinate_names[:3] == ("x", "y", "theta")
    if platform == "prescribed" and not planar:
        raise ModelError(f"{model.robot.name}: a prescribed platform needs the coordinates x, y, theta alone")
    limits = _torque_limits(model.robot, torque_limits)
    if any(arm.coupling is not None for arm in model.robot.arms):
        raise ModelError(f"{model.robot.name}: an arm with a joint coupling has no MuJoCo form")
    spec = _world(mj, model.robot.name, friction, timestep)
    builder = _Builder(mj, spec, model, limits)
    if platform == "wheels":
        builder.platform()
    else:
        builder.prescribed_platform()
    builder.arms()
    if scene is not None:
        add_scene(spec, scene)
    builder.tune(spec.compile())
    return spec


FINDERS = {"body": "body", "inertial": "body", "joint": "joint", "geom": "geom", "site": "site"}
"""The ``MjSpec`` finder of each named MJCF element (an inertial is its body's); actuators are ``general``."""

INERTIAL_FIELDS = {"pos": "ipos", "quat": "iquat", "diaginertia": "inertia"}
"""The body's field of each attribute of its ``<inertial>`` element."""


def mjcf_text(spec: "mujoco.MjSpec") -> str:
    """The MJCF text of ``spec`` (``spec.to_xml()``) with every number of its bodies, inertials, joints,
    geoms, sites and actuators written at full precision (17 significant digits): MuJoCo's writer keeps 6,
    which moves a mass or a joint limit by up to 5e-7 of its value. Loading the text gives the spec's
    model."""
    import xml.etree.ElementTree as ET

    root = ET.fromstring(spec.to_xml())
    bodies = {b.get("name"): b for b in root.iter("body")}
    for element in root.iter():
        name = element.get("name")
        if element.tag == "inertial":
            owner = next(b for b in bodies.values() if element in list(b))
            source, fields = spec.body(owner.get("name")), INERTIAL_FIELDS
        elif name and element.tag in FINDERS:
            source, fields = getattr(spec, FINDERS[element.tag])(name), {}
        elif name and element.tag == "general":
            source, fields = spec.actuator(name), {}
        else:
            continue
        for attribute, text in element.attrib.items():
            if attribute == "rgba":  # colours are single precision
                continue
            value = getattr(source, fields.get(attribute, attribute), None)
            if not isinstance(value, (float, np.ndarray)):  # enumerations, flags, names: as written
                continue
            numbers = np.atleast_1d(np.asarray(value, dtype=float))[: len(text.split())]
            if np.all(np.isfinite(numbers)):
                element.set(attribute, " ".join(format(v, ".17g") for v in numbers))
    return ET.tostring(root, encoding="unicode")


OBSTACLE_SIZES = {
    "box": lambda size: [v / 2 for v in size],
    "sphere": lambda size: [size[0], 0.0, 0.0],
    "cylinder": lambda size: [size[0], size[1] / 2, 0.0],
    "capsule": lambda size: [size[0], size[1] / 2, 0.0],
}
"""MuJoCo's geom size of each obstacle shape of :mod:`mobman.model.scene` (half extents, half lengths)."""


def add_scene(spec: "mujoco.MjSpec", scene: Scene) -> None:
    """The scene's obstacles as static geoms of the world, named as in the scene, touched by the wheels, the
    platform's box and the arm's link capsules (2 cm around each link's segment: an approximation of the
    links' shapes). The physics floor is the plane z = 0 the wheels stand on: a scene floor elsewhere is a
    ModelError."""
    mj = mujoco_module()
    if scene.floor not in (None, 0.0):
        raise ModelError(f"scene floor = {scene.floor:g} m: the physics floor is z = 0, under the wheels")
    for obstacle in scene.obstacles:
        spec.worldbody.add_geom(
            name=obstacle.name,
            type=getattr(mj.mjtGeom, f"mjGEOM_{obstacle.shape.upper()}"),
            size=OBSTACLE_SIZES[obstacle.shape](obstacle.size),
            pos=list(obstacle.position),
            quat=_quat(mj, obstacle.rotation),
            contype=0,
            conaffinity=ROBOT_GROUP | BODY_GROUP,
            rgba=[0.6, 0.4, 0.3, 1.0],
        )


def _torque_limits(robot: MobileManipulator, given: npt.ArrayLike | None) -> np.ndarray:
    names = actuator_names(robot)
    if given is None:
        joints = [j.effort_max for a in robot.arms for j in a.joints]
        values = [math.inf] * robot.platform.n_eta + [math.inf if e is None else e for e in joints]
        return np.asarray(values, dtype=float)
    limits = np.asarray(given, dtype=float).ravel()
    if limits.size != len(names):
        raise InputError(f"torque_limits: {len(names)} values ({', '.join(names)}), got {limits.size}")
    if np.any(np.isnan(limits)) or np.any(limits <= 0):
        raise InputError("torque_limits: every limit must be > 0 (inf for none)")
    return limits


def _world(mj: Any, name: str, friction: float, timestep: float) -> "mujoco.MjSpec":
    spec = mj.MjSpec()
    spec.modelname = name
    spec.compiler.inertiafromgeom = mj.mjtInertiaFromGeom.mjINERTIAFROMGEOM_FALSE
    spec.compiler.autolimits = True
    spec.compiler.degree = False  # every angle in radians, as in mobman
    spec.option.timestep = timestep
    spec.option.integrator = mj.mjtIntegrator.mjINT_IMPLICITFAST
    spec.option.cone = mj.mjtCone.mjCONE_ELLIPTIC
    spec.option.impratio = 10.0
    spec.worldbody.add_geom(
        name="floor",
        type=mj.mjtGeom.mjGEOM_PLANE,
        size=[0.0, 0.0, 0.05],
        friction=[friction, 0.005, 0.0001],
        contype=0,
        conaffinity=ROBOT_GROUP,
        rgba=[0.8, 0.8, 0.8, 1.0],
    )
    spec.worldbody.add_light(pos=[0.0, 0.0, 4.0], dir=[0.0, 0.0, -1.0])
    return spec


def _quat(mj: Any, rotation: np.ndarray) -> np.ndarray:
    quat = np.zeros(4)
    mj.mju_mat2Quat(quat, np.ascontiguousarray(rotation, dtype=float).ravel())
    return quat


class _Builder:
    """Adds the platform, the wheels, the arms and the actuators of ``model`` to ``spec``."""

    def __init__(self, mj: Any, spec: Any, model: DynamicModel, limits: np.ndarray) -> None:
        self.mj, self.spec, self.model, self.limits = mj, spec, model, limits
        self.robot = model.robot
        self.wheel_actuators: list[tuple[Any, float | None]] = []  # (actuator, wheel radius)
        self.joint_actuators: list[Any] = []

    # --- inertials ------------------------------------------------------------------------------------

    def inertial(self, body: Any, mass: float, com: Any, inertia: Any) -> None:
        moments, axes = completed_inertia(inertia)
        body.mass = float(mass)
        body.ipos = np.asarray(com, dtype=float)
        body.inertia = moments
        body.iquat = _quat(self.mj, axes)
        body.explicitinertial = True

    # --- platform ---------------------------------------------------------------------------------------

    def platform(self) -> None:
        mj, platform = self.mj, self.robot.platform
        kind, sites, body = platform.kind, platform.wheels(), self.model.body
        if kind == "fixed":
            self.base = self.spec.worldbody.add_body(name="platform")
        elif kind == "omnidirectional":
            self.base = self.planar_base()
        else:
            self.base = self.spec.worldbody.add_body(name="platform")
            self.base.add_freejoint(name="platform")
        wheel, masses = self.wheel_inertials()
        carved = sum(masses) if self.model.wheel is None or self.model.wheel.mass == 0 else 0.0
        if carved >= body.mass:
            raise ModelError(
                f"{self.robot.name}: the wheels' disc masses ({carved:g} kg) exceed the platform body's mass"
            )
        com = np.asarray(body.com, dtype=float)
        inertia_z = body.inertia_z
        if carved:
            centres = sum(m * np.array([s.x, s.y, s.radius]) for m, s in zip(masses, sites))
            com = (body.mass * com - centres) / (body.mass - carved)
            inertia_z = self.carved_inertia_z(com, sites, masses, wheel)
        flat = np.diag([inertia_z / 2, inertia_z / 2, inertia_z])
        self.inertial(self.base, body.mass - carved, com, flat)
        foot = platform.footprint()
        lift = sites[0].radius if sites else 0.0
        self.base.add_geom(
            name="platform_body",
            type=mj.mjtGeom.mjGEOM_BOX,
            size=[foot.length / 2, foot.width / 2, foot.height / 2],
            pos=[foot.x_centre, 0.0, foot.height / 2 + lift],
            contype=BODY_GROUP,
            conaffinity=0,
            rgba=[0.3, 0.3, 0.35, 0.6],
        )
        if kind == "car":
            self.car(sites, wheel, masses)
        elif kind in ("differential", "skid_steer"):
            names = [j.name for j in platform.urdf_joints()]
            joints = [
                self.wheel(self.base, n, s.x, s.y, s.radius, m, wheel)
                for n, s, m in zip(names, sites, masses)
            ]
            if kind == "differential":
                self.casters(foot, sites[0].radius)
                for k, name in enumerate(platform.actuator_names):
                    self.wheel_actuator(name, "joint", joints[k], k, sites[k].radius)
            else:
                self.sides(joints, sites)

    def prescribed_platform(self) -> None:
        """The platform body (mobman's lumped body: its mass, centre of mass and vertical moment) on slide
        joints along world x and y and a hinge about z, named by the platform's coordinates; no wheels, no
        actuators (module notes)."""
        mj, body = self.mj, self.model.body
        self.base = self.spec.worldbody.add_body(name="platform")
        kinds = ("mjJNT_SLIDE", "mjJNT_SLIDE", "mjJNT_HINGE")
        for name, axis, kind in zip(self.robot.coordinate_names[:3], np.eye(3), kinds):
            self.base.add_joint(name=name, type=getattr(mj.mjtJoint, kind), axis=axis)
        flat = np.diag([body.inertia_z / 2, body.inertia_z / 2, body.inertia_z])
        self.inertial(self.base, body.mass, body.com, flat)

    def carved_inertia_z(self, com: np.ndarray, sites: Any, masses: list[float], wheel: Wheel) -> float:
        """The vertical moment I_c' (about the vertical through ``com``) of the platform body left when the
        wheel bodies are carved out of mobman's lumped body, such that the robot's moment about the platform's
        vertical axis is unchanged (parallel-axis theorem):
        I_c' = I_c + m_c |c_xy|² − (m_c − Σ m_i) |c'_xy|² − Σ (m_i |p_i,xy|² + I_zz,i), I_zz,i the wheel body's
        vertical moment (its :func:`completed_inertia`). ModelError where the wheels would need more than the
        lump holds."""
        body = self.model.body
        moments, axes = completed_inertia(np.diag([wheel.I_m, wheel.I_w, wheel.I_m]))
        wheel_zz = float((axes @ np.diag(moments) @ axes.T)[2, 2])
        wheels = sum(m * (s.x**2 + s.y**2) + wheel_zz for m, s in zip(masses, sites))
        lump = body.inertia_z + body.mass * float(np.sum(np.asarray(body.com)[:2] ** 2))
        inertia_z = lump - (body.mass - sum(masses)) * float(np.sum(com[:2] ** 2)) - wheels
        if inertia_z < 0:
            raise ModelError(
                f"{self.robot.name}: the wheel bodies' vertical inertia exceeds the platform body's "
                f"({lump:g} kg m² about the platform's vertical)"
            )
        return inertia_z

    def wheel_inertials(self) -> tuple[Wheel, list[float]]:
        """The wheel's inertia and each wheel's mass (in the order of ``platform.wheels()``): mobman's driven
        wheel; for a wheel mass of 0 (a URDF's lumped platform) or no wheel (a platform actuated on its
        quasi-velocities), the mass of a uniform disc of its spin inertia (a stand-in disc of
        :data:`STAND_IN_WHEEL_MASS` kg, at most a tenth of the body, where that is 0 too)."""
        sites = self.robot.platform.wheels()
        wheel = self.model.wheel or Wheel(0.0, 0.0, 0.0)
        if wheel.mass > 0 or not sites:
            return wheel, [wheel.mass] * len(sites)
        if wheel.I_w == 0:
            m = min(STAND_IN_WHEEL_MASS, self.model.body.mass / 10 / len(sites))
            r = sites[0].radius
            wheel = Wheel(0.0, m * r**2 / 2, m * r**2 / 4)
        return wheel, [2 * wheel.I_w / s.radius**2 for s in sites]

    def sides(self, joints: list[str], sites: Any) -> None:
        """A skid-steer's sides: one actuator per side on the mean speed of its two wheels (a tendon), the
        pair kept at one angle (the drive belt)."""
        for k, name in enumerate(self.robot.platform.actuator_names):
            pair = [j for j, s in zip(joints, sites) if s.actuator == k]
            tendon = self.spec.add_tendon(name=name)
            for joint in pair:
                tendon.wrap_joint(joint, 0.5)
            self.couple(pair[1], pair[0])
            self.wheel_actuator(name, "tendon", name, k, sites[0].radius)

    def couple(self, follower: str, leader: str) -> None:
        """An equality holding joint ``follower`` at joint ``leader``'s position."""
        equality = self.spec.add_equality(type=self.mj.mjtEq.mjEQ_JOINT, name1=follower, name2=leader)
        polynomial = np.zeros_like(equality.data)
        polynomial[1] = 1.0  # q_follower = q_leader
        equality.data = polynomial

    def planar_base(self) -> Any:
        """The omnidirectional platform: slides along world x and y and a hinge about z, each with a velocity
        servo commanding η_p = (ẋ, ẏ, θ̇)."""
        mj = self.mj
        base = self.spec.worldbody.add_body(name="platform")
        names = self.robot.platform.actuator_names
        for name, axis, kind in zip(
            names, ([1, 0, 0], [0, 1, 0], [0, 0, 1]), ("mjJNT_SLIDE", "mjJNT_SLIDE", "mjJNT_HINGE")
        ):
            base.add_joint(name=name, type=getattr(mj.mjtJoint, kind), axis=axis)
        for k, name in enumerate(names):
            self.wheel_actuator(name, "joint", name, k, None)
        return base

    def wheel(self, parent: Any, name: str, x: float, y: float, r: float, mass: float, wheel: Wheel) -> str:
        mj = self.mj
        body = parent.add_body(name=name, pos=[x, y, r])
        self.inertial(body, mass, [0.0, 0.0, 0.0], np.diag([wheel.I_m, wheel.I_w, wheel.I_m]))
        body.add_joint(name=name, type=mj.mjtJoint.mjJNT_HINGE, axis=[0.0, 1.0, 0.0])
        body.add_geom(
            name=f"{name}_contact",
            type=mj.mjtGeom.mjGEOM_SPHERE,
            size=[r, 0.0, 0.0],
            contype=ROBOT_GROUP,
            conaffinity=0,
            condim=3,
            group=3,
        )
        body.add_geom(
            name=f"{name}_drawn",
            type=mj.mjtGeom.mjGEOM_CYLINDER,
            size=[r, 0.2 * r, 0.0],
            quat=[math.sqrt(0.5), math.sqrt(0.5), 0.0, 0.0],
            contype=0,
            conaffinity=0,
            rgba=[0.1, 0.1, 0.1, 1.0],
        )
        return name

    def casters(self, foot: Any, wheel_radius: float) -> None:
        """Two frictionless spheres on the centre line at the footprint's ends, as tall as the wheels."""
        radius = 0.5 * wheel_radius
        for label, sign in (("front", 1.0), ("rear", -1.0)):
            x = foot.x_centre + sign * (foot.length / 2 - radius)
            self.support(self.base, f"caster_{label}", [x, 0.0, radius], radius)

    def support(self, body: Any, name: str, pos: list[float], radius: float) -> None:
        body.add_geom(
            name=name,
            type=self.mj.mjtGeom.mjGEOM_SPHERE,
            size=[radius, 0.0, 0.0],
            pos=pos,
            contype=ROBOT_GROUP,
            conaffinity=0,
            condim=1,
            priority=1,  # its condim, not the floor's, sets the contact's
            rgba=[0.5, 0.5, 0.5, 1.0],
        )

    def car(self, sites: Any, wheel: Wheel, masses: list[float]) -> None:
        """Driven rear wheels (one velocity servo each) and front wheels on steering hinges, the left one kept
        at the right one's angle; the steering servo ``steering`` takes the steering rate u2."""
        mj = self.mj
        for site, mass in zip(sites[:2], masses[:2]):
            name = self.wheel(
                self.base, f"wheel_rear_{_side(site)}", site.x, site.y, site.radius, mass, wheel
            )
            self.wheel_actuator(name, "joint", name, None, site.radius)
        for site, mass in zip(sites[2:], masses[2:]):
            knuckle = self.base.add_body(name=f"steering_{_side(site)}", pos=[site.x, site.y, 0.0])
            self.inertial(knuckle, 1e-3, [0.0, 0.0, site.radius], np.eye(3) * 1e-6)
            knuckle.add_joint(
                name=f"steering_{_side(site)}", type=mj.mjtJoint.mjJNT_HINGE, axis=[0.0, 0.0, 1.0]
            )
            self.wheel(knuckle, f"wheel_front_{_side(site)}", 0.0, 0.0, site.radius, mass, wheel)
        self.couple("steering_left", "steering_right")
        steering = self.spec.add_actuator(
            name="steering", target="steering_right", trntype=mj.mjtTrn.mjTRN_JOINT
        )
        steering.set_to_intvelocity(kp=1.0, dampratio=1.0)
        self.joint_actuators.append(steering)

    def wheel_actuator(
        self, name: str, target_kind: str, target: str, k: int | None, radius: float | None
    ) -> None:
        mj = self.mj
        trn = mj.mjtTrn.mjTRN_JOINT if target_kind == "joint" else mj.mjtTrn.mjTRN_TENDON
        actuator = self.spec.add_actuator(name=name, target=target, trntype=trn)
        actuator.set_to_velocity(kv=1.0)
        platform = self.robot.platform
        if k is not None:
            speeds = platform.actuator_speed_limits
            if speeds is None and not platform.wheel_actuated and platform.velocity_limits is not None:
                speeds = platform.velocity_limits
            if speeds is not None:
                actuator.ctrlrange = [-speeds[k], speeds[k]]
                actuator.ctrllimited = True
            if math.isfinite(self.limits[k]):
                actuator.forcerange = [-self.limits[k], self.limits[k]]
                actuator.forcelimited = True
        self.wheel_actuators.append((actuator, radius))

    # --- arms -------------------------------------------------------------------------------------------

    def arms(self) -> None:
        mj, robot = self.mj, self.robot
        names = iter(robot.coordinate_names[robot.n_platform :])
        k = robot.platform.n_eta
        for index, (arm, mount) in enumerate(zip(robot.arms, robot.mounts)):
            parent = self.base.add_body(name=f"{arm.name}_mount" if len(robot.arms) > 1 else "mount")
            parent.pos = spatial.as_matrix(mount.transform)[:3, 3]
            parent.quat = _quat(mj, spatial.as_matrix(mount.transform)[:3, :3])
            for i, joint in enumerate(arm.joints):
                name = next(names)
                parent = self.link(parent, name, joint)
                end = arm.joints[i + 1].origin if i + 1 < arm.n_joints else arm.tool
                self.drawn_link(parent, name, spatial.as_matrix(end)[:3, 3])
                self.joint_actuator(name, joint, k)
                k += 1
            tool = spatial.as_matrix(arm.tool)
            parent.add_site(name=f"{arm.name}_tool", pos=tool[:3, 3], quat=_quat(mj, tool[:3, :3]))
            payload = self.model.payload
            if payload is not None and payload.arm == index and payload.mass > 0:
                load = parent.add_body(name="payload", pos=tool[:3, 3], quat=_quat(mj, tool[:3, :3]))
                self.inertial(load, payload.mass, payload.com, np.reshape(payload.inertia, (3, 3)))

    def link(self, parent: Any, name: str, joint: Joint) -> Any:
        mj = self.mj
        origin = spatial.as_matrix(joint.origin)
        axis = np.asarray(joint.axis)
        rotation, position = origin[:3, :3], origin[:3, 3]
        if joint.kind == "revolute":
            k = spatial.skew(axis)
            rotation = rotation @ (
                np.eye(3) + math.sin(joint.offset) * k + (1 - math.cos(joint.offset)) * k @ k
            )
        else:
            position = position + joint.offset * rotation @ axis
        body = parent.add_body(name=name, pos=position, quat=_quat(mj, rotation))
        inertial = joint.inertial
        assert inertial is not None  # dynamic_model fills every link
        self.inertial(body, inertial.mass, inertial.com, inertial.inertia_matrix)
        kind = mj.mjtJoint.mjJNT_HINGE if joint.kind == "revolute" else mj.mjtJoint.mjJNT_SLIDE
        added = body.add_joint(name=name, type=kind, axis=axis)
        if math.isfinite(joint.lower) and math.isfinite(joint.upper):
            added.range = [joint.lower, joint.upper]
            added.limited = True
        return body

    def drawn_link(self, body: Any, name: str, end: np.ndarray) -> None:
        """A capsule of radius 2 cm from the joint frame to ``end`` (drawn; it touches the obstacles only)."""
        length = float(np.linalg.norm(end))
        if length < 1e-6:
            return
        quat = np.zeros(4)
        self.mj.mju_quatZ2Vec(quat, np.asarray(end, dtype=float))
        body.add_geom(
            name=f"{name}_drawn",
            type=self.mj.mjtGeom.mjGEOM_CAPSULE,
            pos=np.asarray(end, dtype=float) / 2,
            quat=quat,
            size=[0.02, length / 2, 0.0],
            contype=BODY_GROUP,
            conaffinity=0,
            rgba=[0.9, 0.5, 0.1, 1.0],
        )

    def joint_actuator(self, name: str, joint: Joint, k: int) -> None:
        actuator = self.spec.add_actuator(name=name, target=name, trntype=self.mj.mjtTrn.mjTRN_JOINT)
        actuator.set_to_intvelocity(kp=1.0, dampratio=1.0)
        if math.isfinite(joint.lower) and math.isfinite(joint.upper):
            actuator.actrange = [joint.lower, joint.upper]
            actuator.actlimited = True
        if joint.velocity_max is not None:
            actuator.ctrlrange = [-joint.velocity_max, joint.velocity_max]
            actuator.ctrllimited = True
        if math.isfinite(self.limits[k]):
            actuator.forcerange = [-self.limits[k], self.limits[k]]
            actuator.forcelimited = True
        self.joint_actuators.append(actuator)

    # --- gains ------------------------------------------------------------------------------------------

    def tune(self, compiled: Any) -> None:
        """Set the servo gains from the compiled model's inertia (see the module docstring): a wheel servo
        moves its own inertia and 1/n of the robot's mass at the wheel's radius (n driven wheels or sides)."""
        mass = float(compiled.body_subtreemass[self.base.id])
        n = max(len(self.wheel_actuators), 1)
        for actuator, radius in self.wheel_actuators:
            own = 0.0
            if actuator.trntype == self.mj.mjtTrn.mjTRN_JOINT:
                own = float(compiled.dof_M0[compiled.jnt_dofadr[compiled.actuator_trnid[actuator.id, 0]]])
            reflected = 0.0 if radius is None else mass * radius**2 / n
            actuator.set_to_velocity(kv=(own + reflected) / WHEEL_TIME_CONSTANT)
        omega = 2 * math.pi * JOINT_SERVO_HZ
        for actuator in self.joint_actuators:
            dof = compiled.jnt_dofadr[compiled.actuator_trnid[actuator.id, 0]]
            actuator.set_to_intvelocity(kp=float(compiled.dof_M0[dof]) * omega**2, dampratio=1.0)


def _side(site: Any) -> str:
    return "right" if site.y < 0 else "left"
