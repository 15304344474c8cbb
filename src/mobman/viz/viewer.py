"""The robot in the browser: a viser scene with the robot, its frames, paths and manipulability ellipsoid.

:class:`Viewer` serves one robot (on loopback by default) and shows a configuration (:meth:`Viewer.show`) or
the motions saved with a run's results (:meth:`Viewer.load_results`, ``trajectories.json``). The side panel
holds the measures w, w2, w5 of J̄ = J S (Bayle et al. 2003, eq. 2; Nait-Chabane et al. 2006, eq. 17–19), the
reduced Jacobian itself with the kinematic / velocity singularity flags KSC / VSC (Bayle §3, §4.2), joint
sliders, and for a motion a time slider, play / pause and the measures plotted against time.

The ellipsoid drawn at each arm's tool is the kinematic manipulability ellipsoid {J̄_p η : ‖η‖ ≤ 1} of the
reduced Jacobian J̄_p of that tool's position (Nait-Chabane §3.1), or with ``normalized=True`` that of
J̄_p · diag(η_max) (eq. 23), scaled by one constant factor for the viewer's lifetime so that its changes of size
show. Given a dynamic model, the dynamic ellipsoid of each tool's accelerations at rest is drawn too (Yamamoto &
Yun 1999, eq. 27–38). A robot with several arms also gets the measures of each arm's J̄_p in the panel.

A reachability map (:mod:`mobman.studies.maps`, :meth:`Viewer.show_map`) is drawn as a cloud of its reached
cells' centres, coloured by their score, attached to the platform (the map's frame), so it moves with it.
Keep-out regions of the floor and the disc covering the platform (:mod:`mobman.studies.floor`,
:meth:`Viewer.show_floor`) are drawn as patches on the floor, the disc moving with the platform.

A scene (:mod:`mobman.model.scene`, :meth:`Viewer.show_scene`) is drawn as its primitives and floor plane, with
the robot's collision spheres (:mod:`mobman.model.collision_model`; a panel box shows or hides them) and the
segment between the witness points of the closest pair (:func:`mobman.collision.distances`: robot–obstacle,
robot–floor and self pairs), coloured by that pair's signed distance from green (far) to red (contact).

Links are drawn from the robot's :class:`~mobman.model.visual.Visual` shapes (URDF meshes, boxes, cylinders,
spheres); a robot without them gets cylinders between successive joint origins, and a platform body and wheels
from its dimensions. Importing this module needs the ``viewer`` extra (viser, trimesh).
"""

from __future__ import annotations

import importlib
import itertools
import os
import socket
import sys
import threading
import time
from dataclasses import dataclass
from pathlib import Path

import jax
import jax.numpy as jnp
import numpy as np
import numpy.typing as npt
import trimesh
import viser
import viser.transforms as vtf
import viser.uplot

from mobman import collision, kinematics, manipulability, redundancy
from mobman.dynamics import DynamicModel, ellipsoids
from mobman.errors import InputError
from mobman.io import trajectories
from mobman.model.collision_model import CollisionModel, collision_model
from mobman.model.robot import MobileManipulator
from mobman.model.robots import ROBOTS, design
from mobman.model.scene import Obstacle, Scene
from mobman.model.tasks import Position
from mobman.model.visual import Visual

LINK_COLOR = (255, 140, 26)
"""Orange: the generated links (what a screenshot's robot pixels are looked for by)."""
JOINT_COLOR = (60, 60, 70)
BODY_COLOR = (96, 112, 140)
WHEEL_COLOR = (35, 35, 40)
ELLIPSOID_COLOR = (60, 130, 230)
DYNAMIC_COLOR = (220, 60, 60)
EE_PATH_COLOR = (20, 160, 60)
PLATFORM_PATH_COLOR = (150, 60, 200)
KEEP_OUT_COLOR = (200, 40, 40)
FOOTPRINT_COLOR = (250, 190, 20)
OBSTACLE_COLOR = (50, 170, 170)
"""Teal: the scene's obstacles (drawn at :data:`OBSTACLE_OPACITY`)."""
OBSTACLE_OPACITY = 0.8
FLOOR_COLOR = (150, 150, 150)
SPHERE_COLOR = (230, 80, 200)
"""Magenta: the robot's collision spheres (translucent)."""
NEAR_COLOR = (220, 30, 30)
"""The closest pair's segment at contact or in penetration (distance ≤ 0)."""
FAR_COLOR = (30, 170, 60)
"""The closest pair's segment at :data:`CLEARANCE_FAR` or farther."""
CLEARANCE_FAR = 0.3
"""Distance (m) from which the closest pair's segment is drawn all green; below it the colour goes linearly
to red at contact."""
FLOOR_PATCH = 0.01
"""Thickness (m) of the patches drawn on the floor: keep-out regions and the platform's footprint disc."""
MEASURES = {"yoshikawa": "w", "inverse_condition": "w2", "eccentricity": "w5"}
"""The measures of the panel, by their symbols in Nait-Chabane et al. (2006), eq. 17–19."""
Dynamics = tuple[DynamicModel, np.ndarray]
"""A dynamic model and its actuator torque limits (N·m: wheels, then joints)."""
CHUNK = 64
"""Configurations per compiled block (as many as :func:`mobman.redundancy.redundancy_report` samples: the
same compiled Jacobians serve both)."""
ELLIPSOID_SIZE = 0.4
"""Largest semi-axis drawn for the first configuration shown, as a fraction of the robot's reach; the drawing
factor then stays fixed."""


@jax.tree_util.register_dataclass
@dataclass(frozen=True)
class Snapshot:
    """What the viewer draws for a batch of configurations (leading axis T): the frames (platform pose, joint
    and tool frames of each arm, each follower's frame), the ellipsoid at each arm's tool (centre (T, A, 3), semi-axes (T, A, 3),
    directions (T, A, 3, 3) for A arms), J̄, the measures and the flags."""

    q: np.ndarray
    platform: tuple[np.ndarray, np.ndarray]
    links: tuple[tuple[np.ndarray, np.ndarray], ...]
    followers: tuple[tuple[np.ndarray, np.ndarray], ...]
    centre: np.ndarray
    axes: np.ndarray
    directions: np.ndarray
    jbar: np.ndarray
    measures: dict[str, np.ndarray]
    vsc: np.ndarray
    ksc: np.ndarray
    defined: np.ndarray
    """False where J (so J̄, the measures and the flags) is undefined: the task's coordinates are singular as a
    representation there (:func:`mobman.kinematics.representation_singular`)."""
    dynamic: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None
    """The dynamic ellipsoid of each tool's accelerations at rest (centre, semi-axes, directions; arm axis
    second, as for the kinematic one), when drawn."""

    def at(self, k: int) -> "Snapshot":
        """The k-th configuration, as a batch of one."""
        return jax.tree.map(lambda a: a[k : k + 1], self)


def evaluate(
    robot: MobileManipulator, q: npt.ArrayLike, normalized: bool = False, dynamics: Dynamics | None = None
) -> Snapshot:
    """Everything the viewer draws for configurations q (T, n_q), computed in blocks of :data:`CHUNK`
    configurations (one compilation per robot serves a single configuration and a whole motion).

    ``dynamics`` = (DynamicModel, torque limits): also the dynamic ellipsoid of each tool position's
    accelerations at rest (Yamamoto & Yun eq. 27–38, :func:`mobman.dynamics.ellipsoids.dynamic_ellipsoid`)."""
    q = robot.validate_q(np.atleast_2d(q))
    blocks = [_evaluate(robot, q[k : k + CHUNK], normalized, dynamics) for k in range(0, len(q), CHUNK)]
    return jax.tree.map(lambda *parts: np.concatenate(parts), *blocks)


def _evaluate(
    robot: MobileManipulator, q: np.ndarray, normalized: bool, dynamics: Dynamics | None
) -> Snapshot:
    n = len(q)
    padded = np.concatenate([q, np.broadcast_to(q[-1], (CHUNK - n, q.shape[1]))])
    frames = kinematics.frames(robot, padded)
    jbar = np.asarray(kinematics.reduced_jacobian(robot, padded))
    limits = robot.velocity_limits
    tools = [Position("xyz", arm=i) for i in range(len(robot.arms))]
    j_p = np.stack([np.asarray(kinematics.reduced_jacobian(robot, padded, tool)) for tool in tools], axis=1)
    if normalized:
        j_p = j_p * np.asarray(limits)
    axes, directions = (np.asarray(a) for a in manipulability.ellipsoid(j_p))
    report = redundancy.redundancy_report(robot)
    # below full row rank everywhere (D̄ < m), the measures of the admissible subspace: the D̄ largest σ
    rank = report.D_bar if report.D_bar < jbar.shape[-2] else None
    measures = {f"{s} (J̄)": v for s, v in _measures(jbar, rank).items()}
    if limits is not None:
        measures.update({f"{s} (J̄_N)": v for s, v in _measures(jbar * np.asarray(limits), rank).items()})
    if len(tools) > 1:
        symbol = "J̄ₚ·η_max" if normalized else "J̄ₚ"
        for i, (tool, label) in enumerate(zip(tools, arm_labels(robot))):
            generic = redundancy.redundancy_report(robot, tool).D_bar  # below 3: a planar arm, say
            measures.update(
                {
                    f"{s} ({symbol} {label})": v
                    for s, v in _measures(j_p[:, i], generic if generic < 3 else None).items()
                }
            )
    jac = np.asarray(kinematics.jacobian(robot, padded))
    # where the task's coordinates are singular as a representation (the heading of a vertical axis, a gimbal
    # lock) J is not the derivative of a chart, and may hold NaN: no rank, no flags
    finite = np.isfinite(jac).all(axis=(-2, -1)) & np.isfinite(jbar).all(axis=(-2, -1))
    defined = finite & ~kinematics.representation_singular(robot, padded)
    d = kinematics.rank(np.where(defined[:, None, None], jac, 0.0), redundancy.RTOL)
    d_bar = kinematics.rank(np.where(defined[:, None, None], jbar, 0.0), redundancy.RTOL)
    links = tuple((np.asarray(r), np.asarray(p)) for r, p in frames.links)
    dynamic = None
    if dynamics is not None:
        model, torque_limits = dynamics
        each = [ellipsoids.dynamic_ellipsoid(model, padded, torque_limits, task=tool) for tool in tools]
        center, semi_axes, axis_directions = (
            np.stack([np.asarray(getattr(e, part)) for e in each], axis=1)
            for part in ("center", "axes", "directions")
        )
        dynamic = (center, semi_axes, axis_directions)
    snap = Snapshot(
        padded,
        (np.asarray(frames.platform[0]), np.asarray(frames.platform[1])),
        links,
        tuple((np.asarray(r), np.asarray(p)) for r, p in frames.followers),
        np.stack([p[:, -1] for _, p in links], axis=1),
        axes,
        directions,
        jbar,
        measures,
        defined & (d_bar < report.D_bar),
        defined & (d < report.D),
        defined,
        dynamic,
    )
    return jax.tree.map(lambda a: a[:n], snap)


def _measures(j: np.ndarray, rank: int | None) -> dict[str, np.ndarray]:
    return {MEASURES[k]: np.asarray(v) for k, v in manipulability.measures(j, rank).items()}


def arm_labels(robot: MobileManipulator) -> list[str]:
    """The arms' names as scene node names (``arm1``, ``arm2``, … where two arms share a name)."""
    labels = [_node_name(a.name) for a in robot.arms]
    return labels if len(set(labels)) == len(labels) else [f"arm{i + 1}" for i in range(len(labels))]


def ellipsoid_node(kind: str, robot: MobileManipulator, arm: int) -> str:
    """The scene node of arm ``arm``'s ellipsoid, ``kind`` "kinematic" or "dynamic": ``/ellipsoid`` and
    ``/ellipsoid_dynamic`` for a one-arm robot, suffixed ``_<arm label>`` (:func:`arm_labels`) for several arms."""
    name = "/ellipsoid" if kind == "kinematic" else "/ellipsoid_dynamic"
    return name if len(robot.arms) == 1 else f"{name}_{arm_labels(robot)[arm]}"


def robot_of(motion: trajectories.Motion) -> MobileManipulator:
    """The robot that made a saved motion: its builder function, or the built-in robot with its parameters."""
    if motion.factory:
        module, _, function = motion.factory.partition(":")
        if not module.startswith("mobman."):
            raise InputError(f"results: robot builder {motion.factory!r} is not part of mobman")
        try:
            robot = getattr(importlib.import_module(module), function)()
        except (ImportError, AttributeError):
            raise InputError(f"results: robot builder {motion.factory!r} not found") from None
        return robot
    if motion.robot_name not in ROBOTS:
        raise InputError(
            f"results: {motion.robot_label} is not a built-in robot; give its description file as ROBOT"
        )
    return design(motion.robot_name, dict(motion.parameters))


def motions_of(robot: MobileManipulator, path: Path | str) -> list[trajectories.Motion]:
    """The motions of ``robot`` saved in a results folder or file; an error naming the robot they are of when
    none is."""
    motions = trajectories.read(path)
    mine = [m for m in motions if _made_by(robot, m)]
    if not mine:
        others = sorted({m.robot_label for m in motions})
        raise InputError(
            f"--results {path}: motions of {', '.join(others)}, not of {_label(robot)}; "
            f"view them with `mobman view {path}`"
        )
    for m in mine:
        if m.q.shape[1] != robot.n_q:
            raise InputError(
                f"--results {path}: motion {m.label!r} has {m.q.shape[1]} coordinates, {robot.name} {robot.n_q}"
            )
        bad = ~np.isfinite(m.q).all(axis=1)
        if bad.any():
            raise InputError(
                f"--results {path}: motion {m.label!r} has non-finite configurations from t = {m.t[bad][0]:g} s"
            )
    return mine


def _made_by(robot: MobileManipulator, motion: trajectories.Motion) -> bool:
    if motion.factory or motion.robot_name in ROBOTS:
        try:
            return robot_of(motion) == robot
        except InputError:
            return False
    return motion.describes(robot)


def _label(robot: MobileManipulator) -> str:
    params = ", ".join(f"{k}={v:.6g}" for k, v in robot.parameters)
    return f"{robot.name} ({params})" if params else robot.name


SERVER_REUSES_ADDRESS = os.name == "posix" and sys.platform != "cygwin"
"""Whether the viewer's server binds with SO_REUSEADDR (asyncio's ``create_server`` default): it may then
serve a port whose earlier connections wait in TIME_WAIT, such as one a previous viewer just closed."""


def _check_port_free(host: str, port: int) -> None:
    """InputError naming ``--port`` if the server could not bind ``port`` (binding as the server does)."""
    if port == 0:
        return
    with socket.socket(socket.AF_INET6 if ":" in host else socket.AF_INET, socket.SOCK_STREAM) as s:
        if SERVER_REUSES_ADDRESS:
            s.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        try:
            s.bind((host, port))
        except OSError:
            raise InputError(
                f"--port {port}: already in use on {host}; try another, e.g. --port {_free_port(host)}"
            ) from None


def _free_port(host: str) -> int:
    with socket.socket(socket.AF_INET6 if ":" in host else socket.AF_INET, socket.SOCK_STREAM) as s:
        s.bind((host, 0))
        return s.getsockname()[1]


def clearance_color(distance: float) -> tuple[int, int, int]:
    """The closest pair's colour at a signed ``distance`` (m): :data:`NEAR_COLOR` (red) at contact or in
    penetration, :data:`FAR_COLOR` (green) from :data:`CLEARANCE_FAR` on, linear in between."""
    s = min(max(distance / CLEARANCE_FAR, 0.0), 1.0)
    near, far = np.array(NEAR_COLOR), np.array(FAR_COLOR)
    red, green, blue = (int(round(c)) for c in (1 - s) * near + s * far)
    return red, green, blue


_centres = jax.jit(collision.centres_one, static_argnums=0)
"""The world centres of a collision model's spheres at one configuration (compiled once per model)."""


def _wxyz(r: np.ndarray) -> np.ndarray:
    return vtf.SO3.from_matrix(r).wxyz


def _segment_pose(d: np.ndarray) -> tuple[np.ndarray, float]:
    """Rotation taking the z axis onto d, and |d| (a unit cylinder along z becomes the segment 0 → d)."""
    length = float(np.linalg.norm(d))
    if length < 1e-9:
        return np.array([1.0, 0.0, 0.0, 0.0]), 0.0
    z = d / length
    helper = np.array([1.0, 0.0, 0.0]) if abs(z[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    x = np.cross(helper, z)
    x /= np.linalg.norm(x)
    return _wxyz(np.stack([x, np.cross(z, x), z], axis=1)), length


def _mesh(visual: Visual) -> trimesh.Trimesh:
    """The shape of a visual as a triangle mesh in the frame it is attached to."""
    if visual.kind == "box":
        mesh = trimesh.creation.box(extents=visual.size)
    elif visual.kind == "cylinder":
        mesh = trimesh.creation.cylinder(radius=visual.size[0], height=visual.size[1], sections=24)
    elif visual.kind == "sphere":
        mesh = trimesh.creation.icosphere(subdivisions=2, radius=visual.size[0])
    else:
        try:
            mesh = trimesh.load(visual.filename, force="mesh")
        except (OSError, ValueError) as exc:
            raise InputError(f"visual {visual.name!r}: cannot read mesh {visual.filename} ({exc})") from None
        mesh.apply_scale(visual.scale)
    mesh.apply_transform(np.asarray(visual.origin).reshape(4, 4))
    return mesh


def _platform_shapes(robot: MobileManipulator) -> tuple[tuple[Visual, ...], float]:
    """Generated platform body, wheels and mount pillars (for a platform without visuals), and the ground
    height."""
    box, wheels = robot.platform.footprint(), robot.platform.wheels()
    h = box.height
    body = Visual(
        "box",
        _pose(np.eye(3), (box.x_centre, 0.0, -h / 2)),
        (box.length, box.width, h),
        rgba=_rgba(BODY_COLOR),
        name="body",
    )
    turn = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]])  # wheel axis along y
    shapes = [body] + [
        Visual(
            "cylinder",
            _pose(turn, (w.x, w.y, -h / 2)),
            (w.radius, 0.4 * w.radius),
            rgba=_rgba(WHEEL_COLOR),
            name=f"wheel{i}",
        )
        for i, w in enumerate(wheels)
    ]
    # a pillar from the deck up to each arm mounted above it
    shapes += [
        Visual(
            "cylinder",
            _pose(np.eye(3), (m.x, m.y, m.z / 2)),
            (0.6 * h, m.z),
            rgba=_rgba(BODY_COLOR),
            name=f"mount{i}",
        )
        for i, m in enumerate(robot.mounts)
        if m.z > 1e-6
    ]
    return tuple(shapes), -h / 2 - max((w.radius for w in wheels), default=h)


def _pose(r: np.ndarray, p: npt.ArrayLike) -> tuple[float, ...]:
    t = np.eye(4)
    t[:3, :3], t[:3, 3] = r, p
    return tuple(t.ravel())


def _rgba(rgb: tuple[int, int, int]) -> tuple[float, float, float, float]:
    return (rgb[0] / 255, rgb[1] / 255, rgb[2] / 255, 1.0)


def _node_name(text: str) -> str:
    return "".join(c if c.isalnum() or c in "-_." else "_" for c in text) or "_"


class Viewer:
    """A viser scene of ``robot`` served at ``http://host:port`` (``port=0``: any free port).

    >>> from mobman.model.robots import bayle_rrp
    >>> viewer = Viewer(bayle_rrp(), port=0)  # doctest: +SKIP
    >>> viewer.show([0, 0, 0, 0.3, 0.5, 0.4])  # doctest: +SKIP
    >>> viewer.close()  # doctest: +SKIP

    ``normalized=True`` draws the ellipsoid of J̄_p · diag(η_max) (the robot needs velocity limits); ``dynamics``
    adds the dynamic ellipsoid at each tool. :attr:`nodes` maps scene node names to their viser handles (the
    ellipsoids' names: :func:`ellipsoid_node`); :attr:`time_slider` is the time slider of a
    loaded motion (None before :meth:`load_results`); :attr:`measures_md`, :attr:`flags_html` and
    :attr:`jbar_md` are the panel's measures, KSC / VSC flags and J̄; :attr:`snapshot` what is drawn now.
    After :meth:`show_scene`, :attr:`collision` is the (collision model, scene) drawn and :attr:`closest` the
    closest pair's names and signed distance (m) at the configuration shown.
    """

    def __init__(
        self,
        robot: MobileManipulator,
        host: str = "127.0.0.1",
        port: int = 8080,
        *,
        normalized: bool = False,
        dynamics: Dynamics | None = None,
    ) -> None:
        if normalized and robot.velocity_limits is None:
            manipulability.system_jacobian(robot, np.zeros(robot.n_q), normalized=True)  # raises ModelError
        _check_port_free(host, port)
        self.robot = robot
        self.normalized = normalized
        self.dynamics = dynamics
        self.server = viser.ViserServer(host=host, port=port, label=f"mobman: {robot.name}", verbose=False)
        if port and self.server.get_port() != port:
            self.server.stop()
            raise InputError(
                f"--port {port}: already in use on {host}; try another, e.g. --port {_free_port(host)}"
            )
        self.host = host
        self.nodes: dict[str, viser.SceneNodeHandle] = {}
        self.time_slider: viser.GuiSliderHandle | None = None
        self.motions: list[trajectories.Motion] = []
        self.snapshot: Snapshot | None = None
        self._motion: Snapshot | None = None
        self._ellipsoid_factor: dict[str, float] = {}
        self._syncing = False
        self._playing = threading.Event()
        self._closed = threading.Event()
        self._player: threading.Thread | None = None
        self._motion_gui: list = []
        self.collision: tuple[CollisionModel, Scene] | None = None
        self.closest: tuple[tuple[str, str], float] | None = None
        self.server.scene.set_up_direction("+z")
        # no shadows, no environment map: software WebGL (headless chromium, remote desktops) draws it in seconds
        self.server.scene.configure_default_lights(cast_shadow=False)
        self.server.scene.configure_environment_map(None)
        self.server.scene.add_light_hemisphere(
            "/light", sky_color=(255, 255, 255), ground_color=(90, 90, 100)
        )
        self._build_scene()
        self._aim_camera(np.zeros((1, 3)))
        self._build_panel()
        lower, upper = self._slider_ranges()
        self.show(np.clip(np.zeros(robot.n_q), lower, upper))

    # --- public API ----------------------------------------------------------------------------------

    @property
    def url(self) -> str:
        """The address to open in a browser."""
        host = f"[{self.host}]" if ":" in self.host else self.host
        return f"http://{host}:{self.server.get_port()}"

    def show(self, q: npt.ArrayLike) -> None:
        """Draw configuration ``q`` (n_q values): robot, frames, ellipsoid, measures, J̄ and the flags."""
        q = np.asarray(q, dtype=float)
        if q.ndim != 1:
            raise InputError(f"{self.robot.name}: show() takes one configuration of {self.robot.n_q} values")
        snap = evaluate(self.robot, q, self.normalized, self.dynamics)
        self._draw(snap)
        self._set_sliders(snap.q[0])

    def load_results(self, path: Path | str, motion: str | None = None) -> list[str]:
        """Load the motions saved with a run's results (a folder, its ``results.json`` or ``trajectories.json``)
        made by this robot; show the first (or the one labelled ``motion``). Returns the labels loaded."""
        mine = motions_of(self.robot, path)
        labels = [m.label for m in mine]
        if motion is not None and motion not in labels:
            raise InputError(f"--motion {motion!r}: not in {path}; choose among: {', '.join(labels)}")
        self.motions = mine
        self._build_motion_panel(labels)
        self._select(labels.index(motion) if motion is not None else 0)
        return labels

    def show_map(self, points: npt.ArrayLike, score: npt.ArrayLike, size: float = 0.05) -> np.ndarray:
        """Draw the reached cells of a reachability map (:mod:`mobman.studies.maps`) as points at their
        centres ``points`` (N, 3, the platform frame) attached to the platform, coloured by their ``score``
        (N,) from dark blue (the lowest) to yellow (the highest; matplotlib's viridis); ``size``: a point's
        size (m), the map's step. Returns the colours (N, 3, 0–255)."""
        from matplotlib import colormaps

        points, score = np.asarray(points, dtype=float), np.asarray(score, dtype=float)
        if points.ndim != 2 or points.shape[1] != 3 or score.shape != points.shape[:1]:
            raise InputError(
                f"show_map: points must be (N, 3) and score (N,), got {points.shape}, {score.shape}"
            )
        span = float(np.ptp(score)) if score.size else 0.0
        shade = (score - score.min()) / span if span > 0 else np.ones_like(score)
        colors = np.round(255 * colormaps["viridis"](shade)[:, :3]).astype(np.uint8)
        self._keep(
            self.server.scene.add_point_cloud(
                "/robot/platform/reachability", points, colors, point_size=0.6 * size, precision="float32"
            )
        )
        return colors

    def show_floor(self, keep_out: npt.ArrayLike, footprint: npt.ArrayLike) -> None:
        """Draw keep-out regions of the floor, ``keep_out`` (M, 4: x_min, x_max, y_min, y_max, world frame), as
        red patches (nodes ``/keep_out/0``, …) and the disc covering the platform, ``footprint`` (radius, x,
        y in the platform frame), as a yellow patch under it that moves with it (``/robot/platform/footprint``):
        what base placement keeps apart (:mod:`mobman.studies.floor`)."""
        regions = np.asarray(keep_out, dtype=float).reshape(-1, 4) if np.size(keep_out) else np.zeros((0, 4))
        disc = np.asarray(footprint, dtype=float)
        if disc.shape != (3,) or not disc[0] > 0 or np.any(regions[:, [0, 2]] >= regions[:, [1, 3]]):
            raise InputError(
                "show_floor: keep_out must be rows x_min < x_max, y_min < y_max and footprint radius > 0, x, y; "
                f"got {regions.tolist()} and {disc.tolist()}"
            )
        ground = self.nodes["/ground"].position[2]
        translucent = (*_rgba(KEEP_OUT_COLOR)[:3], 0.5)
        for k, (x0, x1, y0, y1) in enumerate(regions):
            centre = ((x0 + x1) / 2, (y0 + y1) / 2, ground + FLOOR_PATCH / 2)
            patch = Visual("box", _pose(np.eye(3), centre), (x1 - x0, y1 - y0, FLOOR_PATCH), rgba=translucent)
            self._add_visual(f"/keep_out/{k}", patch)
        # in the platform frame, which moves in the plane z = 0: on the floor wherever the platform goes
        disc_shape = Visual(
            "cylinder",
            _pose(np.eye(3), (disc[1], disc[2], ground + 1.5 * FLOOR_PATCH)),
            (disc[0], FLOOR_PATCH),
            rgba=(*_rgba(FOOTPRINT_COLOR)[:3], 0.6),
        )
        self._add_visual("/robot/platform/footprint", disc_shape)

    def show_scene(self, scene: Scene, model: CollisionModel | None = None, spheres: bool = False) -> None:
        """Draw the obstacles of ``scene`` (nodes ``/scene/<name>``: viser boxes, spheres and cylinders at their
        poses, a capsule as a cylinder and two spheres under one frame) and its floor plane (``/scene/floor``, a
        thin slab whose top is the plane), the collision spheres of ``model`` (default the robot's
        :func:`~mobman.model.collision_model.collision_model`; node ``/collision/spheres``, shown while the
        panel's "collision spheres" box is ticked, ``spheres`` its initial state) and the segment between the
        witness points of the closest pair (``/collision/closest``, robot point first), coloured by
        :func:`clearance_color`. The spheres, the segment and the panel's line follow every configuration
        shown afterwards."""
        model = collision_model(self.robot) if model is None else model
        if model.robot != self.robot:
            raise InputError(
                f"show_scene: the collision model is of {model.robot.name}, not of {self.robot.name}"
            )
        used: set[str] = set()
        for obstacle in scene.obstacles:
            name = f"/scene/{_node_name(obstacle.name)}"
            name = name if name not in used else f"{name}_{len(used)}"
            used.add(name)
            self._add_obstacle(name, obstacle)
        if scene.floor is not None:
            self._keep(
                self.server.scene.add_box(
                    "/scene/floor",
                    FLOOR_COLOR,
                    (10.0, 10.0, FLOOR_PATCH),
                    opacity=0.35,
                    position=(0.0, 0.0, scene.floor - FLOOR_PATCH / 2),
                    cast_shadow=False,
                )
            )
        ball = trimesh.creation.icosphere(subdivisions=2, radius=1.0)
        n = len(model.spheres)
        handle = self.server.scene.add_batched_meshes_simple(
            "/collision/spheres",
            ball.vertices,
            ball.faces,
            batched_wxyzs=np.tile([1.0, 0.0, 0.0, 0.0], (n, 1)),
            batched_positions=np.zeros((n, 3)),
            batched_scales=np.array([s.radius for s in model.spheres]),
            batched_colors=SPHERE_COLOR,
            opacity=0.5,
            cast_shadow=False,
            visible=spheres,
        )
        self._keep(handle)
        self._keep(
            self.server.scene.add_line_segments(
                "/collision/closest", np.zeros((1, 2, 3)), FAR_COLOR, thickness=4.0, thickness_units="screen"
            )
        )
        gui = self.server.gui
        self.spheres_checkbox = gui.add_checkbox("collision spheres", spheres, order=-4)
        self.spheres_checkbox.on_update(lambda _: setattr(handle, "visible", self.spheres_checkbox.value))
        self.clearance_md = gui.add_markdown("", order=-4.5)
        self.collision = (model, scene)
        if scene.obstacles:  # the camera takes in the obstacles and the robot
            robot_at = np.zeros((1, 3)) if self.snapshot is None else self.snapshot.platform[1]
            self._aim_camera(np.concatenate([robot_at, [o.position for o in scene.obstacles]]))
        if self.snapshot is not None:
            self._draw(self.snapshot)

    def set_time(self, t: float) -> None:
        """Show the loaded motion at the sample nearest to time ``t`` (as the time slider does)."""
        # (viser defines the setter of a GUI input's ``value`` apart from its getter, which mypy reads as a
        # read-only property: hence the ``type: ignore[misc]`` of each assignment)
        self._time_slider().value = float(t)  # type: ignore[misc]

    def wait_for_client(self, timeout: float = 30.0) -> None:
        """Block until a browser is connected (for scripted screenshots)."""
        deadline = time.monotonic() + timeout
        while not self.server.get_clients():
            if time.monotonic() > deadline:
                raise TimeoutError(f"no browser connected to {self.url} within {timeout:g} s")
            time.sleep(0.05)

    def close(self) -> None:
        """Stop playing and stop the server."""
        self._closed.set()
        self._playing.clear()
        if self._player is not None:
            self._player.join(timeout=2.0)
        self.server.stop()

    def __enter__(self) -> "Viewer":
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    # --- scene -----------------------------------------------------------------------------------------

    def _keep(self, handle: viser.SceneNodeHandle) -> None:
        self.nodes[handle.name] = handle

    def _add_visual(self, name: str, visual: Visual) -> None:
        mesh = _mesh(visual)
        textured = visual.kind == "mesh" and getattr(mesh.visual, "kind", None) is not None
        if textured:
            self._keep(self.server.scene.add_mesh_trimesh(name, mesh))
            return
        red, green, blue = (int(round(255 * c)) for c in visual.rgba[:3])
        color = (red, green, blue)
        opacity = None if visual.rgba[3] >= 1.0 else visual.rgba[3]
        self._keep(
            self.server.scene.add_mesh_simple(name, mesh.vertices, mesh.faces, color=color, opacity=opacity)
        )

    def _build_scene(self) -> None:
        scene, robot = self.server.scene, self.robot
        shapes, ground = (robot.platform_visuals, 0.0) if robot.platform_visuals else _platform_shapes(robot)
        self._keep(scene.add_frame("/world", axes_length=0.3, axes_radius=0.008))
        self._keep(scene.add_grid("/ground", width=10.0, height=10.0, position=(0.0, 0.0, ground)))
        self._keep(scene.add_frame("/robot/platform", axes_length=0.25, axes_radius=0.01))
        for k, visual in enumerate(shapes):
            self._add_visual(f"/robot/platform/{_node_name(visual.name or f'visual{k}')}", visual)
        reach = max(
            0.3, float(np.max(np.abs(np.asarray(kinematics.frames(robot, np.zeros(robot.n_q)).links[0][1]))))
        )
        self._reach = reach
        self._radius = 0.025 * min(1.0, reach)
        self._arm_nodes: list[list[str]] = []
        self._generated: list[list[bool]] = []
        unit = trimesh.creation.cylinder(radius=self._radius, height=1.0, sections=20)
        unit.apply_translation((0.0, 0.0, 0.5))
        ball = trimesh.creation.icosphere(subdivisions=2, radius=1.4 * self._radius)
        for arm, label in zip(robot.arms, arm_labels(robot)):
            names, generated = [], []
            for joint, coordinate in zip(arm.joints, arm.coordinate_names):
                node = f"/robot/{label}/{_node_name(joint.name or coordinate)}"
                self._keep(scene.add_frame(node, show_axes=False))
                names.append(node)
                generated.append(not joint.visuals)
                for k, visual in enumerate(joint.visuals):
                    self._add_visual(f"{node}/{_node_name(visual.name or f'visual{k}')}", visual)
                if not joint.visuals:
                    self._keep(
                        scene.add_mesh_simple(f"{node}/link", unit.vertices, unit.faces, color=LINK_COLOR)
                    )
                    self._keep(
                        scene.add_mesh_simple(f"{node}/joint", ball.vertices, ball.faces, color=JOINT_COLOR)
                    )
            tool = f"/robot/{label}/tool"
            self._keep(scene.add_frame(tool, axes_length=0.12, axes_radius=0.006))
            names.append(tool)
            self._arm_nodes.append(names)
            self._generated.append(generated)
        self._follower_nodes: list[str] = []
        for k, follower in enumerate(robot.followers):
            node = f"/robot/followers/{_node_name(follower.joint.name or f'follower{k}')}"
            self._keep(scene.add_frame(node, show_axes=False))
            self._follower_nodes.append(node)
            for i, visual in enumerate(follower.joint.visuals):
                self._add_visual(f"{node}/{_node_name(visual.name or f'visual{i}')}", visual)
        sphere = trimesh.creation.icosphere(subdivisions=3, radius=1.0)
        shown = (("kinematic", ELLIPSOID_COLOR), ("dynamic", DYNAMIC_COLOR))[: 2 if self.dynamics else 1]
        for (kind, color), index in itertools.product(shown, range(len(robot.arms))):
            name = ellipsoid_node(kind, robot, index)
            self._keep(
                scene.add_mesh_simple(
                    name, sphere.vertices, sphere.faces, color=color, opacity=0.35, cast_shadow=False
                )
            )

    def _aim_camera(self, points: np.ndarray) -> None:
        """Point the initial camera at the middle of ``points`` and the robot, from far enough to see them."""
        low, high = points.min(axis=0), points.max(axis=0)
        centre = (low + high) / 2
        extent = max(float(np.max(high - low)), 2.0 * self._reach)
        camera = self.server.initial_camera
        camera.look_at = centre
        camera.position = centre + extent * np.array([0.7, -1.0, 0.65])

    def _draw(self, snap: Snapshot) -> None:
        """Move every node to the poses of a one-configuration snapshot and refresh the panel."""
        self.snapshot = snap
        nodes = self.nodes
        with self.server.atomic():
            r, p = snap.platform
            nodes["/robot/platform"].wxyz, nodes["/robot/platform"].position = _wxyz(r[0]), p[0]
            for (rs, ps), names, generated in zip(snap.links, self._arm_nodes, self._generated):
                wxyz = _wxyz(rs[0])
                for i, name in enumerate(names):
                    nodes[name].wxyz, nodes[name].position = wxyz[i], ps[0, i]
                    if i < len(generated) and generated[i]:
                        local = rs[0, i].T @ (ps[0, i + 1] - ps[0, i])
                        turn, length = _segment_pose(local)
                        link = nodes[f"{name}/link"]
                        assert isinstance(link, viser.MeshHandle)  # a generated link is a mesh
                        link.wxyz, link.scale = turn, (1.0, 1.0, max(length, 1e-6))
                        link.visible = length > 1e-9
            for (r, p), name in zip(snap.followers, self._follower_nodes):
                nodes[name].wxyz, nodes[name].position = _wxyz(r[0]), p[0]
            self._draw_ellipsoid(snap)
            if self.collision is not None:
                self._draw_collision(snap.q)
        self._update_panel(snap)

    def _draw_collision(self, q: np.ndarray) -> None:
        """Move the collision spheres to configuration q (1, n_q) and draw its closest pair's segment."""
        assert self.collision is not None
        model, scene = self.collision
        spheres = self.nodes["/collision/spheres"]
        segment = self.nodes["/collision/closest"]
        assert isinstance(spheres, viser.BatchedMeshHandle) and isinstance(segment, viser.LineSegmentsHandle)
        spheres.batched_positions = np.asarray(_centres(model, jnp.asarray(q[0])))
        out = collision.distances(model, scene, q)
        if not out.distance.shape[-1]:
            segment.visible = False
            self.closest = None
            self.clearance_md.content = "**Closest pair**: none (no obstacle, no floor, no self pair)"
            return
        k = int(np.argmin(out.distance[0]))
        d = float(out.distance[0, k])
        robot_body, other = collision.pair_names(model, scene)[k]
        self.closest = ((robot_body, other), d)
        segment.points = np.stack([out.robot_point[0, k], out.other_point[0, k]])[None]
        segment.colors = np.broadcast_to(np.array(clearance_color(d), dtype=np.uint8), (1, 2, 3))
        segment.visible = True
        state = " (in collision)" if d < 0 else ""
        self.clearance_md.content = f"**Closest pair** {robot_body} – {other}: {d:.4g} m{state}"

    def _add_obstacle(self, name: str, obstacle: Obstacle) -> None:
        scene, color, alpha = self.server.scene, OBSTACLE_COLOR, OBSTACLE_OPACITY
        wxyz, at = _wxyz(obstacle.rotation), np.asarray(obstacle.position)
        size = obstacle.size
        if obstacle.shape == "box":
            box = scene.add_box(
                name, color, np.asarray(size), opacity=alpha, cast_shadow=False, wxyz=wxyz, position=at
            )
            self._keep(box)
        elif obstacle.shape == "sphere":
            ball = scene.add_icosphere(name, size[0], color, opacity=alpha, cast_shadow=False, position=at)
            self._keep(ball)
        elif obstacle.shape == "cylinder":  # viser's cylinder: its axis along its own z, as the scene's
            rod = scene.add_cylinder(
                name, size[0], size[1], color, opacity=alpha, cast_shadow=False, wxyz=wxyz, position=at
            )
            self._keep(rod)
        else:  # a capsule: the straight part and a sphere at each end, in the capsule's frame
            radius, length = size
            self._keep(scene.add_frame(name, show_axes=False, wxyz=wxyz, position=at))
            body = scene.add_cylinder(f"{name}/body", radius, length, color, opacity=alpha, cast_shadow=False)
            self._keep(body)
            for end, z in (("top", length / 2), ("bottom", -length / 2)):
                cap = scene.add_icosphere(
                    f"{name}/{end}", radius, color, opacity=alpha, cast_shadow=False, position=(0.0, 0.0, z)
                )
                self._keep(cap)

    def _draw_ellipsoid(self, snap: Snapshot) -> None:
        for arm in range(len(self.robot.arms)):
            self._draw_one("kinematic", arm, snap.centre[0], snap.axes[0], snap.directions[0])
            if snap.dynamic is not None:
                centre, axes, directions = snap.dynamic
                self._draw_one("dynamic", arm, snap.centre[0], axes[0], directions[0], centre[0, arm])

    def _draw_one(
        self,
        kind: str,
        arm: int,
        at: np.ndarray,
        axes: np.ndarray,
        directions: np.ndarray,
        offset: np.ndarray | None = None,
    ) -> None:
        """Arm ``arm``'s ellipsoid node of ``kind`` at its tool ``at[arm]`` (+ its own centre ``offset``, in the
        drawing's scale), from the semi-axes and directions of every arm: one drawing factor per kind for the
        viewer's lifetime, set by the largest semi-axis of the first configuration shown (the arms' ellipsoids
        compare)."""
        if kind not in self._ellipsoid_factor and np.isfinite(axes).all():
            self._ellipsoid_factor[kind] = ELLIPSOID_SIZE * self._reach / max(float(np.max(axes)), 1e-9)
        at, axes, directions = at[arm], axes[arm], directions[arm].copy()
        finite = bool(np.isfinite(axes).all() and np.isfinite(directions).all())
        node = self.nodes[ellipsoid_node(kind, self.robot, arm)]
        assert isinstance(node, viser.MeshHandle)  # an ellipsoid is a mesh
        node.visible = finite and kind in self._ellipsoid_factor
        if not node.visible:
            return
        factor = self._ellipsoid_factor[kind]
        if np.linalg.det(directions) < 0:
            directions[:, -1] *= -1.0
        node.position = at if offset is None else at + factor * offset
        node.wxyz = _wxyz(directions)
        sx, sy, sz = (float(max(a * factor, 1e-4)) for a in axes)
        node.scale = (sx, sy, sz)

    # --- panel -----------------------------------------------------------------------------------------

    def _slider_ranges(self) -> tuple[np.ndarray, np.ndarray]:
        lower, upper = (np.array(v, dtype=float) for v in zip(*self.robot.position_limits))
        n_p = self.robot.platform.n_q
        default_lo = np.array([-3.0, -3.0, -np.pi] + [-1.0] * (n_p - 3) + [-np.pi] * (self.robot.n_q - n_p))
        kinds = ["platform"] * n_p + [j.kind for a in self.robot.arms for j in a.joints]
        prismatic = np.array([k == "prismatic" for k in kinds])
        lo = np.where(np.isfinite(lower), lower, np.where(prismatic, -1.0, default_lo))
        hi = np.where(np.isfinite(upper), upper, np.where(prismatic, np.maximum(lo, 0.0) + 1.0, -default_lo))
        return lo, hi

    def _build_panel(self) -> None:
        gui = self.server.gui
        self.measures_md = gui.add_markdown("")
        self.flags_html = gui.add_html("")
        self.jbar_md = gui.add_markdown("")
        lo, hi = self._slider_ranges()
        self._sliders = []
        with gui.add_folder("Configuration q"):
            for name, a, b in zip(self.robot.coordinate_names, lo, hi):
                slider = gui.add_slider(name, min=float(a), max=float(b), step=1e-3, initial_value=float(a))
                slider.on_update(self._on_joint_slider)
                self._sliders.append(slider)

    def _on_joint_slider(self, _event: viser.GuiEvent) -> None:
        if self._syncing:
            return
        self.show(np.array([s.value for s in self._sliders]))

    def _set_sliders(self, q: np.ndarray) -> None:
        self._syncing = True
        try:
            for slider, value in zip(self._sliders, q):
                slider.value = float(np.clip(value, slider.min, slider.max))  # type: ignore[misc]
        finally:
            self._syncing = False

    def _update_panel(self, snap: Snapshot) -> None:
        rows = "\n".join(
            f"| {name} | {float(v[0]):.4g} |" if snap.defined[0] else f"| {name} | undefined |"
            for name, v in snap.measures.items()
        )
        d_bar = redundancy.redundancy_report(self.robot).D_bar
        rank = f" (of the {d_bar} largest σ: D̄ = {d_bar} < m)" if d_bar < self.robot.task.dim else ""
        self.measures_md.content = f"**Measures**{rank}\n\n| measure | value |\n|---|---|\n{rows}"

        def flag(name: str, singular: bool) -> str:
            color, text = ("#d32f2f", "singular") if singular else ("#2e7d32", "regular")
            return f'<span style="color:{color};font-weight:bold">{name}: {text}</span>'

        if not snap.defined[0]:
            self.flags_html.content = (
                '<div style="padding:0 0.75em;color:#ef6c00;font-weight:bold">J̄ undefined here: the task is '
                "not differentiable at this configuration</div>"
            )
            return
        self.flags_html.content = f'<div style="padding:0 0.75em">{flag("VSC", bool(snap.vsc[0]))} · {flag("KSC", bool(snap.ksc[0]))}</div>'
        jbar = snap.jbar[0]
        header = "| " + " | ".join(self.robot.control_names) + " |"
        rule = "|" + "---|" * jbar.shape[1]
        body = "\n".join("| " + " | ".join(f"{v:.3f}" for v in row) + " |" for row in jbar)
        self.jbar_md.content = (
            f"**J̄ = J S** (rows {', '.join(self.robot.task.names)})\n\n{header}\n{rule}\n{body}"
        )

    def _build_motion_panel(self, labels: list[str]) -> None:
        for handle in self._motion_gui:
            handle.remove()
        gui = self.server.gui
        self._motion_gui = []
        if len(labels) > 1:
            choice = gui.add_dropdown("motion", tuple(labels), initial_value=labels[0], order=-3)
            choice.on_update(lambda _: self._select(labels.index(choice.value)))
            self._motion_gui.append(choice)
        self.time_slider = gui.add_slider(
            "time (s)", min=0.0, max=1.0, step=1e-3, initial_value=0.0, order=-2
        )
        self.time_slider.on_update(lambda _: self._on_time())
        self._play = gui.add_button("play / pause", order=-1.5)
        self._play.on_click(lambda _: self._toggle_play())
        self._plot: viser.GuiUplotHandle | None = None
        self._motion_gui += [self.time_slider, self._play]
        if self._player is None:
            self._player = threading.Thread(target=self._play_loop, daemon=True)
            self._player.start()

    def _select(self, index: int) -> None:
        motion = self.motions[index]
        self._playing.clear()
        self._motion = evaluate(self.robot, motion.q, self.normalized, self.dynamics)
        self._times = motion.t
        scene = self.server.scene
        tools = self._motion.centre
        platform = self._motion.platform[1]
        self._aim_camera(np.concatenate([*np.swapaxes(tools, 0, 1), platform]))
        suffixes = [""] if len(self.robot.arms) == 1 else [f"_{label}" for label in arm_labels(self.robot)]
        paths = [(f"/paths/ee{s}", tools[:, i], EE_PATH_COLOR) for i, s in enumerate(suffixes)]
        for name, points, color in [*paths, ("/paths/platform", platform, PLATFORM_PATH_COLOR)]:
            segments = (
                np.stack([points[:-1], points[1:]], axis=1)
                if len(points) > 1
                else np.stack([points, points], 1)
            )
            self._keep(
                scene.add_line_segments(name, segments, colors=color, thickness=2.0, thickness_units="screen")
            )
        if self._plot is not None:
            self._plot.remove()
        plotted = {n: v for n, v in self._motion.measures.items() if n.endswith("(J̄)")}
        self._plotted = plotted
        top = max(1.0, float(np.nanmax(np.concatenate(list(plotted.values())))))
        palette = ("#1f77b4", "#9467bd", "#2ca02c")  # no orange: the links' colour
        series = [viser.uplot.Series(label="t (s)")]
        series += [
            viser.uplot.Series(label=name, stroke=palette[i % len(palette)], width=1.5)
            for i, name in enumerate(plotted)
        ]
        series.append(
            viser.uplot.Series(label="now", stroke="#d32f2f", width=0, points={"show": True, "size": 8})
        )
        self._plot = self.server.gui.add_uplot(
            self._plot_data(0),
            tuple(series),
            title="measures of J̄ along the motion",
            scales={
                "x": viser.uplot.Scale(time=False, auto=True),
                "y": viser.uplot.Scale(range=(0.0, 1.05 * top)),
            },
            aspect=1.4,
            order=-1,
        )
        self._motion_gui.append(self._plot)
        for coordinate in (0, 1):  # the platform's x and y sliders cover the motion
            values, q_slider = motion.q[:, coordinate], self._sliders[coordinate]
            q_slider.min = min(q_slider.min, float(np.floor(values.min())) - 1.0)
            q_slider.max = max(q_slider.max, float(np.ceil(values.max())) + 1.0)
        slider = self._time_slider()
        self._syncing = True
        slider.min, slider.max = float(self._times[0]), float(self._times[-1])
        slider.step = float(max(np.min(np.diff(self._times)) if len(self._times) > 1 else 1e-3, 1e-6))
        self._syncing = False
        slider.value = float(self._times[0])  # type: ignore[misc]
        self._on_time()

    def _time_slider(self) -> viser.GuiSliderHandle:
        """The time slider of the loaded motion (created by :meth:`load_results`)."""
        if self.time_slider is None:
            raise InputError("no motion loaded: call load_results first")
        return self.time_slider

    def _index(self) -> int:
        t = self._time_slider().value
        k = int(np.searchsorted(self._times, t))
        if k > 0 and (k == len(self._times) or t - self._times[k - 1] < self._times[k] - t):
            k -= 1
        return min(k, len(self._times) - 1)

    def _on_time(self) -> None:
        if self._syncing or self._motion is None:
            return
        k = self._index()
        snap = self._motion.at(k)
        self._draw(snap)
        self._set_sliders(snap.q[0])
        if self._plot is not None:
            self._plot.data = self._plot_data(k)

    def _plot_data(self, k: int) -> tuple[np.ndarray, ...]:
        """The plotted measures against time, and the marker series: the last one's value at sample k only."""
        values = list(self._plotted.values())
        now = np.full_like(self._times, np.nan)
        now[k] = values[-1][k]
        return (self._times, *values, now)

    def _toggle_play(self) -> None:
        if self._playing.is_set():
            self._playing.clear()
        else:
            slider = self._time_slider()
            if slider.value >= self._times[-1]:
                slider.value = float(self._times[0])  # type: ignore[misc]
            self._playing.set()

    def _play_loop(self) -> None:
        period = 0.05
        while not self._closed.is_set():
            if not self._playing.wait(timeout=0.2):
                continue
            start = time.monotonic()
            slider = self._time_slider()
            t = min(slider.value + period, float(self._times[-1]))
            slider.value = t  # type: ignore[misc]
            if t >= self._times[-1]:
                self._playing.clear()
            time.sleep(max(0.0, period - (time.monotonic() - start)))


__all__ = [
    "Snapshot",
    "Viewer",
    "arm_labels",
    "clearance_color",
    "ellipsoid_node",
    "evaluate",
    "motions_of",
    "robot_of",
]
