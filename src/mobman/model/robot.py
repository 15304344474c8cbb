"""A mobile manipulator: a platform, one fixed mount per arm, and one or more arms.

Generalized coordinates are q = [q_p, q_a1, q_a2, …] (platform first, Bayle §2) and quasi-velocities
η = [η_p, q̇_a1, q̇_a2, …] (Bayle §4.2), related by q̇ = S(q) η with S block-diagonal:
S(q) = diag(S_p(q_p), I). The model is an immutable, hashable dataclass: it can be a static argument of
:func:`jax.jit`. All methods here work on one configuration; :mod:`mobman.kinematics` batches them.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, replace
from functools import cached_property, partial
from typing import TYPE_CHECKING, Any

import jax
import jax.numpy as jnp
import numpy as np
import numpy.typing as npt

from mobman.checks import all_finite, real_array
from mobman.errors import InputError, ModelError
from mobman.model import spatial
from mobman.model.arm import Arm, Joint, LinkInertial
from mobman.model.platforms import Platform
from mobman.model.spatial import Transform
from mobman.model.visual import Visual

if TYPE_CHECKING:
    from mobman.model.tasks import Task


_all_finite = jax.jit(lambda q: jnp.all(jnp.isfinite(q)))


def _in_host_memory(q: jax.Array) -> bool:
    return all(d.platform == "cpu" for d in q.devices())


@dataclass(frozen=True)
class Mount:
    """Fixed transform from the platform frame to an arm's base frame.

    ``Mount(a, b, c)`` puts the arm base at (a, b, c) in the platform frame (Nait-Chabane's a, b, c;
    Korayem's l0 is ``Mount(l0)``), optionally turned by ``yaw`` about the vertical axis and tilted by
    ``pitch`` and ``roll``: its rotation is R_z(yaw) R_y(pitch) R_x(roll), URDF's ``rpy`` (rad).
    """

    x: float = 0.0
    y: float = 0.0
    z: float = 0.0
    yaw: float = 0.0
    roll: float = 0.0
    pitch: float = 0.0

    def __post_init__(self) -> None:
        for name in ("x", "y", "z", "yaw", "roll", "pitch"):
            if not math.isfinite(getattr(self, name)):
                raise ModelError(f"Mount: {name} must be finite, got {getattr(self, name)!r}")

    @property
    def transform(self) -> Transform:
        rotation = spatial.rot_z(self.yaw) @ spatial.rot_y(self.pitch) @ spatial.rot_x(self.roll)
        return spatial.transform(rotation, (self.x, self.y, self.z))


Body = tuple[int, int]
"""A body of the robot: (-1, 0) the platform, (arm, link) the link joint ``link`` of arm ``arm`` moves,
(-2, k) the :class:`Follower` ``k``."""

PLATFORM: Body = (-1, 0)

FOLLOWER = -2
"""The first entry of a follower's :data:`Body`."""


@dataclass(frozen=True)
class Follower:
    """A body off the arm chains moved by a joint that follows an arm coordinate (a URDF ``<mimic>`` joint:
    HSR's torso rises with its arm lift at half its travel). ``joint`` is that joint (its ``origin`` in the
    frame of the ``parent`` body, its ``visuals`` the shapes of the body), moved by the motion variable
    ``multiplier · q[leader] + joint.offset`` (URDF's mimic: multiplier · q_leader + offset); ``leader`` is the
    coordinate's index in q. The joint's ``lower`` and ``upper`` are the URDF's limits of that motion variable,
    kept to write the joint back (nothing moves it there: it follows). A follower carries no coordinate of its own, so it adds no column to J̄; its mass,
    where it has one, stays in the body it hangs from (the dynamics of a real robot keep it there, at the
    posture where the leader is 0)."""

    joint: Joint
    parent: Body
    leader: int
    multiplier: float = 1.0

    def __post_init__(self) -> None:
        if not isinstance(self.joint, Joint):
            raise ModelError(f"Follower: joint must be a Joint, got {type(self.joint).__name__}")
        object.__setattr__(self, "parent", (int(self.parent[0]), int(self.parent[1])))
        if not math.isfinite(self.multiplier):
            raise ModelError(
                f"Follower {self.joint.name!r}: multiplier must be finite, got {self.multiplier!r}"
            )

    def pose(
        self, parent: tuple[jnp.ndarray, jnp.ndarray], q: jnp.ndarray | np.ndarray
    ) -> tuple[jnp.ndarray, jnp.ndarray]:
        """World pose (R, p) of the follower's frame from its parent's world pose at configuration q."""
        return self.joint.pose_after(parent, self.multiplier * jnp.asarray(q)[..., self.leader])


@dataclass(frozen=True)
class Frames:
    """World poses of one configuration: platform, each mount, each arm's joint frames and tool frame, each
    follower's frame."""

    platform: tuple[jnp.ndarray, jnp.ndarray]
    mounts: tuple[tuple[jnp.ndarray, jnp.ndarray], ...]
    links: tuple[tuple[jnp.ndarray, jnp.ndarray], ...]
    """per arm: R (n_joints + 1, 3, 3) and p (n_joints + 1, 3); the last entry is the tool frame."""
    followers: tuple[tuple[jnp.ndarray, jnp.ndarray], ...] = ()
    """per :class:`Follower`: R (3, 3) and p (3,)."""

    def body(self, body: Body) -> tuple[jnp.ndarray, jnp.ndarray]:
        """The world pose (R, p) of a :data:`Body`."""
        kind, index = body
        if kind == PLATFORM[0]:
            return self.platform
        if kind == FOLLOWER:
            return self.followers[index]
        rs, ps = self.links[kind]
        return rs[..., index, :, :], ps[..., index, :]


MAX_JOINTS = 64
"""Most arm joints a robot may have, all arms together (TIAGo dual has 14, a humanoid's upper body about 30)."""


def _first_tool_position() -> Task:
    """The default operational task: the first arm's tool position."""
    from mobman.model.tasks import Position

    return Position()


@dataclass(frozen=True)
class MobileManipulator:
    """Platform + mounts + arms, with an operational task ξ = f(q) (default: first arm's tool position).

    ``mounts`` left empty puts every arm base at the platform frame's origin (one ``Mount()`` per arm).

    ``platform_visuals`` are the shapes of the platform body in the platform frame (for drawing only: they
    take no part in equality or hashing); each arm joint carries the shapes of its own link. ``followers``
    are the bodies off the chains that follow an arm coordinate (:class:`Follower`).
    """

    platform: Platform
    arms: tuple[Arm, ...]
    mounts: tuple[Mount, ...] = ()
    task: Task = field(default_factory=_first_tool_position)
    name: str = "mobile-manipulator"
    parameters: tuple[tuple[str, float], ...] = field(default=(), compare=True)
    platform_visuals: tuple[Visual, ...] = field(default=(), compare=False)
    followers: tuple[Follower, ...] = ()

    def __post_init__(self) -> None:
        arms = (self.arms,) if isinstance(self.arms, Arm) else tuple(self.arms)
        if not arms:
            raise ModelError(f"{self.name}: a mobile manipulator needs at least one arm")
        mounts = tuple(Mount() for _ in arms) if self.mounts in (None, ()) else self.mounts
        mounts = (mounts,) if isinstance(mounts, Mount) else tuple(mounts)
        if len(mounts) != len(arms):
            raise ModelError(f"{self.name}: {len(mounts)} mounts given for {len(arms)} arms")
        joints = sum(arm.n_joints for arm in arms)
        if joints > MAX_JOINTS:
            raise ModelError(
                f"{self.name}: {joints} arm joints, more than the {MAX_JOINTS} a robot may have (every program "
                "is compiled for the robot's joints: one of hundreds would take minutes to compile)"
            )
        object.__setattr__(self, "arms", arms)
        object.__setattr__(self, "mounts", mounts)
        object.__setattr__(self, "parameters", tuple((str(k), float(v)) for k, v in self.parameters))
        object.__setattr__(self, "platform_visuals", tuple(self.platform_visuals))
        if self.task is None:
            object.__setattr__(self, "task", _first_tool_position())
        object.__setattr__(self, "followers", tuple(self.followers))
        self._check_followers()

    def _check_followers(self) -> None:
        n_platform = self.platform.n_q
        links = {(a, k) for a, arm in enumerate(self.arms) for k in range(arm.n_joints)}
        for k, follower in enumerate(self.followers):
            if not isinstance(follower, Follower):
                raise ModelError(f"{self.name}: followers must be Follower, got {type(follower).__name__}")
            name = follower.joint.name or f"follower {k}"
            total = n_platform + sum(a.n_joints for a in self.arms)
            if not n_platform <= follower.leader < total:
                raise ModelError(
                    f"{self.name}: follower {name!r} leads from q[{follower.leader}], not an arm coordinate "
                    f"(q[{n_platform}] to q[{total - 1}])"
                )
            parent = follower.parent
            if not (parent == PLATFORM or parent in links or parent in {(FOLLOWER, i) for i in range(k)}):
                raise ModelError(
                    f"{self.name}: follower {name!r} hangs from {parent}, not the platform (-1, 0), an arm link "
                    f"(arm, link) or an earlier follower (-2, index)"
                )

    def __hash__(self) -> int:
        # The robot is a static argument of compiled functions and is hashed on every call: hash the nested
        # description once (it is immutable). The cached value is not pickled (string hashes are per process).
        cached = self.__dict__.get("_hash")
        if cached is None:
            cached = hash(
                (self.platform, self.arms, self.mounts, self.task, self.name, self.parameters, self.followers)
            )
            object.__setattr__(self, "_hash", cached)
        return cached

    def __getstate__(self) -> dict:
        return {k: v for k, v in self.__dict__.items() if k != "_hash"}

    # --- layout --------------------------------------------------------------------------------------

    @cached_property
    def n_q(self) -> int:
        """Mobility index M = dim q."""
        return self.platform.n_q + sum(a.n_joints for a in self.arms)

    @cached_property
    def n_eta(self) -> int:
        """Mobility degree δ = dim η."""
        return self.platform.n_eta + sum(a.n_joints for a in self.arms)

    @property
    def n_platform(self) -> int:
        return self.platform.n_q

    def arm_slice(self, index: int) -> slice:
        """Position of arm ``index``'s coordinates in q."""
        start = self.platform.n_q + sum(a.n_joints for a in self.arms[:index])
        return slice(start, start + self.arms[index].n_joints)

    def arm_eta_slice(self, index: int) -> slice:
        """Position of arm ``index``'s joint velocities in η."""
        start = self.platform.n_eta + sum(a.n_joints for a in self.arms[:index])
        return slice(start, start + self.arms[index].n_joints)

    @property
    def coordinate_names(self) -> tuple[str, ...]:
        """The names of q: the platform's, then each arm's joints. Several arms whose joint names collide (two
        copies of one arm) have theirs prefixed by the arm's name (or ``arm1``, ``arm2``, … when those collide
        too); joint names that are unique across the arms, as a URDF's, stay as they are."""
        names = list(self.platform.coordinate_names)
        joints = [n for arm in self.arms for n in arm.coordinate_names]
        if len(set(joints)) == len(joints):
            return tuple(names + joints)
        labels = [a.name for a in self.arms]
        if len(set(labels)) != len(labels):
            labels = [f"arm{i + 1}" for i in range(len(self.arms))]
        for label, arm in zip(labels, self.arms):
            names += [f"{label}.{n}" for n in arm.coordinate_names]
        return tuple(names)

    @property
    def control_names(self) -> tuple[str, ...]:
        names = list(self.platform.control_names)
        for name in self.coordinate_names[self.platform.n_q :]:
            names.append(name + "_dot")
        return tuple(names)

    @property
    def velocity_limits(self) -> tuple[float, ...] | None:
        """Maximum |η_i| for every quasi-velocity, or None if any is unknown."""
        limits = [self.platform.velocity_limits] + [a.velocity_limits for a in self.arms]
        known = [v for v in limits if v is not None]
        return tuple(v for part in known for v in part) if len(known) == len(limits) else None

    @property
    def position_limits(self) -> tuple[tuple[float, float], ...]:
        """(lower, upper) for every coordinate (platform coordinates are unbounded)."""
        return ((-math.inf, math.inf),) * self.platform.n_q + tuple(
            lim for a in self.arms for lim in a.position_limits
        )

    def limit_violations(self, q: npt.ArrayLike) -> np.ndarray:
        """Which coordinates of configurations q (..., n_q) lie outside :attr:`position_limits` (a joint's
        [lower, upper]), boolean (..., n_q); ``.any(-1)`` flags each configuration."""
        q = self.validate_q(q)
        lower, upper = np.array(self.position_limits, dtype=float).T
        return (q < lower) | (q > upper)

    def with_task(self, task: "Task") -> "MobileManipulator":
        """The same robot with another operational task."""
        return replace(self, task=task)

    def with_mount(self, mount: Mount, arm: int = 0) -> "MobileManipulator":
        """The same robot with arm ``arm`` fixed to the platform by ``mount`` (in the platform frame)."""
        if not (isinstance(arm, int) and 0 <= arm < len(self.arms)):
            raise InputError(f"{self.name}: arm must be in 0..{len(self.arms) - 1}, got {arm!r}")
        if not isinstance(mount, Mount):
            raise InputError(f"mount must be a Mount, got {type(mount).__name__}")
        return replace(self, mounts=self.mounts[:arm] + (mount,) + self.mounts[arm + 1 :])

    def with_link_inertials(self, inertials: "Sequence[LinkInertial]", arm: int = 0) -> "MobileManipulator":
        """The same robot with the links of arm ``arm`` given ``inertials`` (one per joint), for the dynamics."""
        if not (isinstance(arm, int) and 0 <= arm < len(self.arms)):
            raise InputError(f"{self.name}: arm must be in 0..{len(self.arms) - 1}, got {arm!r}")
        chain = self.arms[arm]
        if len(inertials) != chain.n_joints:
            raise InputError(
                f"inertials: arm {arm} ({chain.name}) has {chain.n_joints} links, got {len(inertials)}"
            )
        joints = tuple(
            replace(j, inertial=inertial) for j, inertial in zip(chain.joints, inertials, strict=True)
        )
        arms = self.arms[:arm] + (replace(chain, joints=joints),) + self.arms[arm + 1 :]
        return replace(self, arms=arms)

    def validate_q(self, q: npt.ArrayLike) -> np.ndarray:
        """Check a configuration (or a batch): last axis of size n_q, finite values. Returns float64 NumPy."""
        try:
            arr = real_array(q, f"{self.name}: a configuration")
        except InputError:
            raise
        except (TypeError, ValueError):
            raise InputError(
                f"{self.name}: a configuration is {self.n_q} numbers ({', '.join(self.coordinate_names)}) or a "
                f"batch of them, got {type(q).__name__} {str(q)[:40]!r}"
            ) from None
        self._check_q(arr.shape, lambda: all_finite(arr))
        return arr

    def validate_q_on_device(self, q: jax.Array) -> jax.Array:
        """:meth:`validate_q` for a ``jax.Array``, checked where it lives: on an accelerator the finiteness
        test is one reduction on the device, so a batch is not copied to the host and back (measured on an
        H200: that round trip cost 20 ms per million configurations, twice the kinematics itself); in host
        memory NumPy reads it in place (cheaper than a compiled call for one configuration).
        Returns the array itself when it is float64."""
        if _in_host_memory(q):
            self.validate_q(q)  # NumPy reads host memory in place
        elif q.dtype.kind == "c":
            raise InputError(
                f"{self.name}: a configuration must be real numbers, got complex ones ({q.dtype})"
            )
        else:
            self._check_q(q.shape, lambda: bool(_all_finite(q)))
        return q if q.dtype == jnp.float64 else q.astype(jnp.float64)

    def _check_q(self, shape: tuple[int, ...], finite: Callable[[], bool]) -> None:
        if not shape or shape[-1] != self.n_q:
            got = shape[-1] if shape else 1
            raise InputError(
                f"{self.name}: a configuration has {self.n_q} coordinates "
                f"({', '.join(self.coordinate_names)}), got {got}"
            )
        if not finite():
            raise InputError(f"{self.name}: configuration contains NaN or infinite values")

    # --- per-configuration functions (unbatched) -------------------------------------------------

    def S(self, q: jnp.ndarray) -> jnp.ndarray:
        """S(q) = diag(S_p(q_p), I_{n_a}), shape (n_q, n_eta) (Bayle §4.2)."""
        n_p = self.platform.n_q
        s_p = self.platform.S(q[:n_p])
        n_a = self.n_q - n_p
        top = jnp.concatenate([s_p, jnp.zeros((n_p, n_a), dtype=s_p.dtype)], axis=1)
        bottom = jnp.concatenate(
            [jnp.zeros((n_a, self.platform.n_eta), dtype=s_p.dtype), jnp.eye(n_a, dtype=s_p.dtype)], axis=1
        )
        return jnp.concatenate([top, bottom], axis=0)

    def apply_S(self, j: jnp.ndarray, q: jnp.ndarray) -> jnp.ndarray:
        """J S(q) for a (m, n_q) matrix J, as [J_p S_p(q_p), J_a] without forming S (Bayle eq. 2). For one
        configuration this keeps XLA's program small (no n_q × n_eta S: one product with the platform's small
        S_p); batched it is as fast as J S."""
        n_p = self.platform.n_q
        j_p, j_a = jax.lax.split(j, (n_p, j.shape[1] - n_p), axis=1)
        return jnp.concatenate([spatial.matmul_expanded(j_p, self.platform.S(q[:n_p])), j_a], axis=1)

    def q_dot(self, q: jnp.ndarray, eta: jnp.ndarray) -> jnp.ndarray:
        """q̇ = S(q) η (n_q,) for one configuration, as [S_p(q_p) η_p, η_a] without forming S (Bayle eq. 1)."""
        n_p = self.platform.n_q
        eta_p, eta_a = jax.lax.split(eta, (self.platform.n_eta, eta.shape[0] - self.platform.n_eta))
        return jnp.concatenate([spatial.matvec(self.platform.S(q[:n_p]), eta_p), eta_a])

    def constraints(self, q: jnp.ndarray) -> jnp.ndarray:
        """G(q) = [G_p(q_p) 0] with G(q) q̇ = 0 (Bayle §4.2), shape (n_q − n_eta, n_q)."""
        g_p = self.platform.constraints(q[: self.platform.n_q])
        return jnp.concatenate([g_p, jnp.zeros((g_p.shape[0], self.n_q - self.platform.n_q), g_p.dtype)], 1)

    def frames(self, q: jnp.ndarray | np.ndarray) -> Frames:
        """World poses of the platform, mounts and every arm frame at one configuration."""
        # one split of q (not a slice per use): its reverse-mode transpose is one concatenation
        n_p = self.platform.n_q
        sizes = (1, 1, 1, n_p - 3) + tuple(a.n_joints for a in self.arms)
        x, y, theta, _, *arm_qs = jax.lax.split(q, sizes, axis=-1)
        platform = spatial.planar_pose(x[..., 0], y[..., 0], theta[..., 0])
        mounts, links = [], []
        for arm, mount, q_a in zip(self.arms, self.mounts, arm_qs):
            mount_pose = spatial.compose_fixed_pose(platform, mount.transform)
            mounts.append(mount_pose)
            links.append(arm.link_poses(q_a, base=mount_pose))
        frames = Frames(platform, tuple(mounts), tuple(links))
        if not self.followers:
            return frames
        followers: list[tuple[jnp.ndarray, jnp.ndarray]] = []
        for follower in self.followers:
            parent = replace(frames, followers=tuple(followers)).body(follower.parent)
            followers.append(follower.pose(parent, q))
        return replace(frames, followers=tuple(followers))

    def point_jacobian(
        self,
        q: jnp.ndarray,
        frames: Frames,
        point: jnp.ndarray,
        arm: int | None,
        upto: int,
        coupled: bool = True,
    ) -> tuple[jnp.ndarray, jnp.ndarray]:
        """Linear (3 × n_q) and angular (3 × n_q) velocity Jacobians of a point rigidly attached to
        frame ``upto`` of arm ``arm`` (only joints ≤ upto move it; ``arm=None``: attached to the platform).

        Columns: platform x, y → unit vectors, θ → e_z × (p − o_platform) (further platform coordinates, such
        as a steering angle, do not move the body); revolute joint j → a_j × (p − o_j), prismatic → a_j
        (the geometric Jacobian), multiplied by the arm's coupling matrix (``coupled=False``: the columns of
        the joints' motion variables, see :meth:`couple`). Differentiated by autodiff through ``frames``;
        :func:`mobman.model.frame_jacobian.frame_jacobian` gives the same columns with a closed-form derivative.
        """
        n_p = self.platform.n_q
        origin = frames.platform[1]
        dtype = origin.dtype
        e_z = jnp.array([0.0, 0.0, 1.0], dtype=dtype)
        lin = [jnp.array([1.0, 0.0, 0.0], dtype=dtype), jnp.array([0.0, 1.0, 0.0], dtype=dtype)]
        lin.append(spatial.cross(e_z, point - origin))
        ang = [jnp.zeros(3, dtype), jnp.zeros(3, dtype), e_z]
        lin += [jnp.zeros(3, dtype)] * (n_p - 3)
        ang += [jnp.zeros(3, dtype)] * (n_p - 3)
        j_lin = [jnp.stack(lin, axis=1)]
        j_ang = [jnp.stack(ang, axis=1)]
        for i, a in enumerate(self.arms):
            n = a.n_joints
            if i != arm:
                j_lin.append(jnp.zeros((3, n), dtype))
                j_ang.append(jnp.zeros((3, n), dtype))
                continue
            rs, ps = frames.links[i]
            frame_rs = spatial.unstack(rs, axis=0)
            axes = jnp.stack([spatial.matvec_constant(r, jt.axis) for r, jt in zip(frame_rs, a.joints)])
            revolute = np.array([jt.kind == "revolute" for jt in a.joints])
            moves = np.arange(n) <= upto
            lin_cols = jnp.where(revolute[:, None], spatial.cross(axes, point - ps[:n]), axes)
            ang_cols = jnp.where(revolute[:, None], axes, 0.0)
            lin_cols = jnp.where(moves[:, None], lin_cols, 0.0).T
            ang_cols = jnp.where(moves[:, None], ang_cols, 0.0).T
            j_lin.append(lin_cols)
            j_ang.append(ang_cols)
        linear, angular = jnp.concatenate(j_lin, axis=1), jnp.concatenate(j_ang, axis=1)
        return (self.couple(linear), self.couple(angular)) if coupled else (linear, angular)

    def body_point_jacobian(
        self, q: jnp.ndarray, frames: Frames, point: jnp.ndarray, body: Body
    ) -> tuple[jnp.ndarray, jnp.ndarray]:
        """Linear and angular (3 × n_q) velocity Jacobians of a point fixed in ``body`` (:data:`Body`): the
        platform's or a link's :meth:`point_jacobian`; a follower's is its parent's plus, in its leader's
        column, the multiplier times its joint's geometric column (a × (p − o) and a for a revolute joint, a
        and 0 for a prismatic one, a its axis in the world)."""
        kind, index = body
        if kind != FOLLOWER:
            return self.point_jacobian(q, frames, point, None if kind < 0 else kind, index)
        follower = self.followers[index]
        linear, angular = self.body_point_jacobian(q, frames, point, follower.parent)
        rotation, origin = frames.followers[index]
        axis = spatial.matvec_constant(rotation, follower.joint.axis)
        if follower.joint.kind == "revolute":
            columns = (spatial.cross(axis, point - origin), axis)
        else:
            columns = (axis, jnp.zeros_like(axis))
        m, k = follower.multiplier, follower.leader
        return linear.at[:, k].add(m * columns[0]), angular.at[:, k].add(m * columns[1])

    @cached_property
    def _coupled(self) -> bool:
        return any(a.coupling is not None for a in self.arms)

    def couple(self, columns: jnp.ndarray) -> jnp.ndarray:
        """Columns over the joints' motion variables (platform first) → columns over q: each arm's block
        times its coupling matrix C (motion = C q_a). Unchanged when no arm is coupled."""
        return self._map_arm_blocks(columns, lambda arm, b: b @ arm.coupling_matrix)

    def motion_rates(self, q_dot: jnp.ndarray) -> jnp.ndarray:
        """q̇ → the rates of the platform coordinates and of the joints' motion variables (C q̇_a per arm)."""
        return self._map_arm_blocks(q_dot, lambda arm, b: arm.motion_variables(b))

    def _map_arm_blocks(self, x: jnp.ndarray, fn: Callable[[Arm, jnp.ndarray], jnp.ndarray]) -> jnp.ndarray:
        """x (..., n_q) with ``fn(arm, block)`` applied to the block of every coupled arm (the last axis split
        as platform, arm 1, arm 2, …); x itself when no arm is coupled."""
        if not self._coupled:
            return x
        blocks = jax.lax.split(x, (self.platform.n_q,) + tuple(a.n_joints for a in self.arms), axis=-1)
        arms = [fn(a, b) if a.coupling is not None else b for b, a in zip(blocks[1:], self.arms)]
        return jnp.concatenate([blocks[0], *arms], axis=-1)

    def describe(self) -> dict:
        """A JSON-friendly description: name, parameters, coordinates, controls, limits (and the followers,
        where the robot has some: each joint, the coordinate it follows, the multiplier and the offset)."""
        out: dict[str, Any] = {
            "name": self.name,
            "parameters": dict(self.parameters),
            "platform": type(self.platform).__name__,
            "coordinates": list(self.coordinate_names),
            "controls": list(self.control_names),
            "task": list(self.task.names),
            "velocity_limits": None if self.velocity_limits is None else list(self.velocity_limits),
            "M": self.n_q,
            "delta": self.n_eta,
        }
        if self.followers:
            out["followers"] = [
                {
                    "joint": f.joint.name,
                    "leader": self.coordinate_names[f.leader],
                    "multiplier": f.multiplier,
                    "offset": f.joint.offset,
                }
                for f in self.followers
            ]
        return out


def actuator_names(robot: MobileManipulator) -> tuple[str, ...]:
    """The actuators of a robot in τ order: the platform's (``platform.actuator_names``: its driven wheels, or
    one per quasi-velocity), then the arm joints."""
    return robot.platform.actuator_names + tuple(robot.coordinate_names[robot.n_platform :])


def compiled_frames(robot: MobileManipulator, q: npt.ArrayLike) -> Frames:
    """:meth:`MobileManipulator.frames` of configurations q (..., n_q) as NumPy arrays from one compiled
    program: evaluated operation by operation, each of its few dozen operations would be compiled on its own
    (seconds in all). q is taken as checked (:func:`mobman.kinematics.frames` checks it)."""
    return Frames(*jax.tree.map(np.asarray, _frames_program(robot, jnp.asarray(q, dtype=float))))


@partial(jax.jit, static_argnums=0)
def _frames_program(robot: MobileManipulator, q: jax.Array) -> tuple:
    poses = robot.frames(q)
    return poses.platform, poses.mounts, poses.links, poses.followers
