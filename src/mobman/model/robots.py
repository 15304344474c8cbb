"""The papers' robots, every dimension a keyword argument named as in the paper, a Franka Panda on a
differential-drive base, and the real robots.

Where a paper gives no value, the default is a documented choice (see ``docs/kinematics.md``). Each robot
carries its paper's operational task. On the command line the names use hyphens (``bayle-planar``). The real
robots (TIAGo, TIAGo dual, Stretch) are read from their URDF files by :mod:`mobman.io.real_robots`, which
registers them here (:func:`register`) when :mod:`mobman.io` is imported.
"""

from __future__ import annotations

import inspect
import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import replace

from mobman import checks
from mobman.errors import ModelError
from mobman.model import spatial
from mobman.model.arm import Arm, Joint, LinkInertial
from mobman.model.platforms import CarLike, DifferentialDrive
from mobman.model.robot import MobileManipulator, Mount
from mobman.model.tasks import Elevation, PlanarAngle, Pose, Position, stack

_UP = (0.0, 0.0, 1.0)
_LIFT = (0.0, -1.0, 0.0)  # rotating about −y lifts the x axis: positive angle = elevation


def _check_lengths(owner: str, **lengths: float) -> None:
    """Link lengths, wheel radii, track widths: finite and > 0."""
    for name, value in lengths.items():
        checks.positive(value, f"{name} (a length)", owner)


def _check_offsets(owner: str, **offsets: float) -> None:
    """Offsets along a link or of a mount: finite and ≥ 0 (0 is a valid geometry)."""
    for name, value in offsets.items():
        checks.non_negative(value, f"{name} (an offset)", owner)


def _check_finite(owner: str, **values: float) -> None:
    for name, value in values.items():
        checks.finite(value, name, owner)


def _translation(x: float = 0.0, y: float = 0.0, z: float = 0.0) -> spatial.Transform:
    return spatial.transform(None, (x, y, z))


def planar_arm(
    lengths: Sequence[float],
    names: Sequence[str] | None = None,
    velocity_max: Sequence[float] | None = None,
    inertials: Sequence[LinkInertial | None] | None = None,
    name: str = "arm",
) -> Arm:
    """A horizontal planar arm: revolute joints about the vertical axis, links along x."""
    joints = []
    for i, _ in enumerate(lengths):
        joints.append(
            Joint(
                "revolute",
                _UP,
                _translation(lengths[i - 1]) if i else spatial.IDENTITY,
                name=names[i] if names else f"q{i + 1}",
                velocity_max=None if velocity_max is None else velocity_max[i],
                inertial=None if inertials is None else inertials[i],
            )
        )
    return Arm(tuple(joints), _translation(lengths[-1]), name=name)


def bayle_planar(l1: float = 0.5, l2: float = 0.5) -> MobileManipulator:
    """HILARE-like platform + horizontal 2R arm at the axle midpoint (Bayle §5.1), M = 5, ξ = (x, y, angle).

    The paper gives no link lengths: 0.5 m each is a choice. Velocity limits (for the normalised measures)
    are also a choice: v_max = 0.5 m/s, ω_max = 1 rad/s, |q̇_a| ≤ π/2 rad/s.
    """
    _check_lengths("bayle_planar", l1=l1, l2=l2)
    arm = planar_arm((l1, l2), names=("q4", "q5"), velocity_max=(math.pi / 2,) * 2)
    return MobileManipulator(
        DifferentialDrive(v_max=0.5, omega_max=1.0),
        (arm,),
        task=stack(Position("xy"), PlanarAngle()),
        name="bayle-planar",
        parameters=(("l1", l1), ("l2", l2)),
    )


def bayle_rrp() -> MobileManipulator:
    """HILARE-like platform + RRP arm (Bayle §5.2), M = 6; ξ = EE position, heading ϑ + q4, elevation q5.

    Joint 4 turns about the vertical, joint 5 lifts the arm, joint 6 slides along it; the base of the arm
    is at the axle midpoint, as in the paper's direct kinematics. The two angles are read about the lift
    axis (the tool frame's y axis, always horizontal): ξ4 = ϑ + q4 and ξ5 = q5 over the whole turn of q5,
    through the vertical and past it (no representation singularity).
    """
    arm = Arm(
        (
            Joint("revolute", _UP, name="q4", velocity_max=math.pi / 2),
            Joint("revolute", _LIFT, name="q5", velocity_max=math.pi / 2),
            Joint("prismatic", (1.0, 0.0, 0.0), name="q6", lower=0.0, velocity_max=0.5),
        ),
        name="rrp",
    )
    return MobileManipulator(
        DifferentialDrive(v_max=0.5, omega_max=1.0),
        (arm,),
        task=stack(Position("xyz"), PlanarAngle("ZXY"), Elevation()),
        name="bayle-rrp",
    )


def manus_platform(
    L2: float = 0.12, L3: float = 0.35, L4: float = 0.35, a: float = 0.12, b: float = 0.12, c: float = 0.4
) -> MobileManipulator:
    """The three Manus positioning joints on a differential platform (Nait-Chabane eq. 3, 8, 27–28).

    Arm coordinates are the paper's: q_a1 about the vertical, q_a2 and q_a3 the *absolute* elevation angles
    of the upper arm and forearm (the Manus has a parallelogram linkage), modelled with a coupling matrix.
    L2 ≥ 0 is the shoulder's lateral offset (0.12 m: the paper's retracted point (0, 0.12, 0)); L3 = L4 =
    0.35 m are a choice (the paper gives none). The arm base is at (a, b, c) in the platform frame: the
    paper's simulations state (0.12, 0.12, 0.4) m while §4.1 uses a = b = 0. The arm frame {A} is turned by
    −π/2 about the vertical with respect to the platform frame {P} (eq. 8: the tool is at
    (a + x_a2, b − x_a1, c + x_a3) in {P}, and x4 = φ + θ_p − π/2), so the arm's x_a2 axis points along the
    platform's heading and q_a1 = π/2 points the arm forward. Velocity limits are the paper's
    u_max = (0.33 m/s, 0.55 rad/s, π/3, π/3, π/3 rad/s).
    """
    _check_offsets("manus_platform", L2=L2)
    _check_lengths("manus_platform", L3=L3, L4=L4)
    _check_finite("manus_platform", a=a, b=b, c=c)
    w = math.pi / 3
    arm = Arm(
        (
            Joint("revolute", _UP, name="qa1", velocity_max=w),
            Joint("revolute", _LIFT, _translation(0.0, L2), name="qa2", velocity_max=w),
            Joint("revolute", _LIFT, _translation(L3), name="qa3", velocity_max=w),
        ),
        tool=_translation(L4),
        coupling=(1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, -1.0, 1.0),
        name="manus",
    )
    return MobileManipulator(
        DifferentialDrive(v_max=0.33, omega_max=0.55),
        (arm,),
        (Mount(a, b, c, yaw=-math.pi / 2),),
        task=Position("xyz"),
        name="manus-platform",
        parameters=(("L2", L2), ("L3", L3), ("L4", L4), ("a", a), ("b", b), ("c", c)),
    )


def korayem_planar(l0: float = 0.4, l1: float = 0.5, l2: float = 0.5) -> MobileManipulator:
    """Differential platform + planar 2R arm mounted at F, l0 ≥ 0 ahead of the axle (Korayem eq. 20–25).

    ξ = (x_e, y_e). Korayem's generalized coordinates are those of F; here q_p is the axle midpoint, a
    change of coordinates with unit Jacobian determinant, so the augmented-Jacobian determinants agree.
    Wheel radius 0.1 m and half-track 0.25 m are a choice (not in the seed text).
    """
    _check_offsets("korayem_planar", l0=l0)
    _check_lengths("korayem_planar", l1=l1, l2=l2)
    arm = planar_arm((l1, l2), names=("theta1", "theta2"), velocity_max=(3.5, 3.5))
    return MobileManipulator(
        DifferentialDrive(wheel_radius=0.1, half_track=0.25, wheel_speed_max=3.5),
        (arm,),
        (Mount(l0),),
        task=Position("xy"),
        name="korayem-planar",
        parameters=(("l0", l0), ("l1", l1), ("l2", l2)),
    )


def tchon_car_rtr(l2: float = 0.6, l3: float = 0.4, length: float = 1.0) -> MobileManipulator:
    """Kinematic car + RTR arm (Tchoń et al. eq. 31), ξ = y = EE position.

    q = (q1, q2, q3, q4, x1, x2, x3): rear-axle midpoint, orientation, steering angle; x1 turns the arm
    about the vertical, x2 slides it vertically, x3 lifts the last link. The car length is the unit (1).
    """
    _check_lengths("tchon_car_rtr", l2=l2, l3=l3, length=length)
    arm = Arm(
        (
            Joint("revolute", _UP, name="x1"),
            Joint("prismatic", _UP, name="x2"),
            Joint("revolute", _LIFT, _translation(l2), name="x3"),
        ),
        tool=_translation(l3),
        name="rtr",
    )
    platform = CarLike(length=length)
    return MobileManipulator(
        platform,
        (arm,),
        task=Position("xyz"),
        name="tchon-car-rtr",
        parameters=(("l2", l2), ("l3", l3), ("length", length)),
    )


def yamamoto_dual_arm(
    L1: float = 0.5, L2: float = 0.5, L3: float = 0.5, b: float = 0.171, r: float = 0.075
) -> MobileManipulator:
    """Two planar 3-link arms with a common base at the axle midpoint (Yamamoto & Yun Tables 1–2).

    Link inertials from Table 1 (L_ci, m_i, I_i); joint speed limit 3.14 rad/s; wheel speed limit 1/r rad/s.
    The default task is the first arm's tool position and heading (the held object is handled by
    :mod:`mobman.dynamics`).
    """
    _check_lengths("yamamoto_dual_arm", L1=L1, L2=L2, L3=L3, b=b, r=r)
    lengths = (L1, L2, L3)
    com = (0.25, 0.25, 0.1)
    masses = (10.0, 6.0, 2.0)
    inertia_z = (0.5, 0.3, 0.01)
    inertials = tuple(
        LinkInertial(m, (lc, 0.0, 0.0), (0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, iz))
        for m, lc, iz in zip(masses, com, inertia_z)
    )
    arms = tuple(
        planar_arm(
            lengths,
            names=("theta1", "theta2", "theta3"),
            velocity_max=(3.14,) * 3,
            inertials=inertials,
            name=f"arm{k}",
        )
        for k in (1, 2)
    )
    return MobileManipulator(
        DifferentialDrive(wheel_radius=r, half_track=b, wheel_speed_max=1.0 / r),
        arms,
        task=stack(Position("xy"), PlanarAngle()),
        name="yamamoto-dual-arm",
        parameters=(("L1", L1), ("L2", L2), ("L3", L3), ("b", b), ("r", r)),
    )


PANDA_MODIFIED_DH = (
    (0.0, 0.0, 0.0, 0.333),
    (-math.pi / 2, 0.0, 0.0, 0.0),
    (math.pi / 2, 0.0, 0.0, 0.316),
    (math.pi / 2, 0.0825, 0.0, 0.0),
    (-math.pi / 2, -0.0825, 0.0, 0.384),
    (math.pi / 2, 0.0, 0.0, 0.0),
    (math.pi / 2, 0.088, 0.0, 0.0),
)
"""Franka Emika Panda, modified DH (Craig) rows (α_{i−1}, a_{i−1}, θ_i, d_i), from Franka's documentation."""
PANDA_LIMITS = (
    (-2.8973, 2.8973),
    (-1.7628, 1.7628),
    (-2.8973, 2.8973),
    (-3.0718, -0.0698),
    (-2.8973, 2.8973),
    (-0.0175, 3.7525),
    (-2.8973, 2.8973),
)
"""The Panda's joint position limits (rad)."""
PANDA_SPEEDS = (2.175, 2.175, 2.175, 2.175, 2.61, 2.61, 2.61)
"""The Panda's joint speed limits (rad/s)."""


def panda_differential(v_max: float = 1.0, omega_max: float = 1.5, height: float = 0.4) -> MobileManipulator:
    """A Franka Panda (7 joints, flange 0.107 m along the last z axis) on a differential-drive base, its
    base ``height`` m above the axle midpoint; task: the flange pose (:class:`~mobman.model.tasks.Pose`).

    The base's speed limits (v_max = 1 m/s, ω_max = 1.5 rad/s) and the mount height are a choice; the
    arm's joint position and speed limits are Franka's.
    """
    _check_lengths("panda_differential", v_max=v_max, omega_max=omega_max)
    _check_finite("panda_differential", height=height)
    arm = Arm.from_modified_dh(
        PANDA_MODIFIED_DH,
        tool=_translation(z=0.107),
        limits=PANDA_LIMITS,
        velocity_limits=PANDA_SPEEDS,
        name="panda",
    )
    return MobileManipulator(
        DifferentialDrive(v_max=v_max, omega_max=omega_max),
        (arm,),
        (Mount(z=height),),
        task=Pose(),
        name="panda-differential",
        parameters=(("v_max", v_max), ("omega_max", omega_max), ("height", height)),
    )


PAPER_ROBOTS: dict[str, Callable[..., MobileManipulator]] = {
    "bayle-planar": bayle_planar,
    "bayle-rrp": bayle_rrp,
    "manus-platform": manus_platform,
    "korayem-planar": korayem_planar,
    "tchon-car-rtr": tchon_car_rtr,
    "yamamoto-dual-arm": yamamoto_dual_arm,
}

# the papers' robots, the Panda on a differential base, then those added by register(): the real robots read
# from their URDF files (mobman[robots]; io/real_robots.py, registered when mobman.io is imported)
ROBOTS: dict[str, Callable[..., MobileManipulator]] = {
    **PAPER_ROBOTS,
    "panda-differential": panda_differential,
}


def register(name: str, factory: Callable[..., MobileManipulator]) -> None:
    """Add a robot to :data:`ROBOTS` (and so to :func:`build`, the command line and robot files) under its
    command-line ``name`` (lower case, words joined by ``-``); ``factory`` builds it, its keyword parameters
    being the robot's parameters. Registering the same factory again is a no-op; a name already taken by
    another factory is a ModelError."""
    if not isinstance(name, str) or not name or name != name.lower() or "_" in name or " " in name:
        raise ModelError(
            f"register: name must be a lower-case command-line name (words joined by -), got {name!r}"
        )
    if not callable(factory):
        raise ModelError(f"register: factory of {name!r} must be callable, got {type(factory).__name__}")
    if ROBOTS.get(name, factory) is not factory:
        raise ModelError(f"register: the robot name {name!r} is taken")
    ROBOTS[name] = factory


def command_name(name: str) -> str:
    """The command-line name that ``name`` spells: underscores read as hyphens (``tiago_dual``: ``tiago-dual``)."""
    return name.replace("_", "-")


def build(name: str, **params: float) -> MobileManipulator:
    """A built-in robot by its command-line name, with keyword parameters; clear errors otherwise."""
    key = command_name(name)
    if key not in ROBOTS:
        raise ModelError(f"unknown robot {name!r}; built-in robots: {', '.join(ROBOTS)}")
    factory = ROBOTS[key]
    allowed = list(inspect.signature(factory).parameters)
    for p in params:
        if p not in allowed:
            raise ModelError(
                f"robot {key}: unknown parameter {p!r}; allowed: {', '.join(allowed) if allowed else 'none'}"
            )
    return factory(**params)


MOUNT = {
    "mount.x": "x",
    "mount.y": "y",
    "mount.z": "z",
    "mount.yaw": "yaw",
    "mount.pitch": "pitch",
    "mount.roll": "roll",
}
"""The parameters every robot takes besides its constructor's: the fields of an arm's :class:`Mount`, the
pose of its base in the platform frame (m; rad, URDF's roll, pitch and yaw), each replacing the robot's
own."""


def parameter_names(source: str | MobileManipulator) -> list[str]:
    """The parameters of a design of ``source`` (:func:`design`): a built-in robot's constructor's (``source``
    its command-line name), then :data:`MOUNT`; a robot given as an object has only :data:`MOUNT`."""
    if isinstance(source, MobileManipulator):
        return list(MOUNT)
    return list(inspect.signature(ROBOTS[command_name(source)]).parameters) + list(MOUNT)


def design(
    source: str | MobileManipulator, params: Mapping[str, float] | None = None, arm: int = 0
) -> MobileManipulator:
    """A design of a robot: the built-in robot ``source`` (its command-line name) built with its
    constructor's parameters among ``params``, or the robot ``source`` itself, with arm ``arm`` fixed to the
    platform as the :data:`MOUNT` parameters among ``params`` say (``{"mount.z": 0.3}``: its base 0.3 m above
    the platform frame's origin). The first arm's mount parameters join the robot's ``parameters``, so that
    a motion saved with it rebuilds it. ModelError names an unknown robot or parameter, a value the
    constructor refuses, or an arm to mount that the robot does not have."""
    params = dict(params or {})
    if isinstance(source, str) and command_name(source) not in ROBOTS:
        build(source)  # the error naming the built-in robots
    unknown = [k for k in params if k not in parameter_names(source)]
    if unknown:
        name = source.name if isinstance(source, MobileManipulator) else command_name(source)
        raise ModelError(
            f"robot {name}: unknown parameter {unknown[0]!r}; allowed: {', '.join(parameter_names(source))}"
        )
    own = {k: v for k, v in params.items() if k not in MOUNT}
    robot = source if isinstance(source, MobileManipulator) else build(source, **own)
    placed = {k: float(v) for k, v in params.items() if k in MOUNT}
    if not placed:
        return robot
    if not (isinstance(arm, int) and 0 <= arm < len(robot.arms)):
        raise ModelError(f"robot {robot.name}: arm {arm!r} to mount: the robot has {len(robot.arms)} arm(s)")
    mounted = robot.with_mount(replace(robot.mounts[arm], **{MOUNT[k]: v for k, v in placed.items()}), arm)
    if arm != 0:
        return mounted
    return replace(mounted, parameters=tuple({**dict(robot.parameters), **placed}.items()))
