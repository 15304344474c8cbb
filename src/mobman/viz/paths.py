"""Platform and end-effector paths with the robot drawn at a few instants.

The robot's geometry comes from the model layer only: :meth:`MobileManipulator.frames` gives the world
poses of the platform, the mounts and every arm frame; the platform is drawn as a rectangle with its
heading and its driving wheels, each arm as the polyline mount → joint frames → tool (top view: the
projection on the floor).
"""

from __future__ import annotations

from functools import lru_cache
from typing import Callable, Mapping

import jax
import numpy as np
import numpy.typing as npt
from matplotlib.axes import Axes
from matplotlib.figure import Figure
from matplotlib.patches import Polygon

from mobman.model.robot import MobileManipulator


def figure_of(ax: Axes) -> Figure:
    """The top-level figure holding ``ax`` (also when ``ax`` is in a subfigure)."""
    fig = ax.figure
    return fig if isinstance(fig, Figure) else fig.figure


def finish_plane(ax: Axes, title: str | None = None) -> None:
    """Equal-aspect x–y axes in metres with a grid, the legend and an optional title."""
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.grid(True, alpha=0.3)
    ax.legend(loc="best", fontsize=8)
    if title:
        ax.set_title(title)


@lru_cache(maxsize=32)
def _frames_fn(robot: MobileManipulator) -> Callable:
    def one(q):
        f = robot.frames(q)
        return f.platform, f.mounts, f.links

    return jax.jit(jax.vmap(one))


def frame_points(robot: MobileManipulator, q: npt.ArrayLike) -> dict[str, np.ndarray]:
    """World points of configurations ``q`` (N, n_q), batched in one compiled call.

    Returns ``platform`` (N, 3) origin, ``heading`` (N, 2) unit x axis of the platform, and per arm
    ``arm{i}`` (N, n_joints + 2, 3): the mount point, every joint frame origin, then the tool point.
    """
    q = np.atleast_2d(robot.validate_q(q))
    (r_p, p_p), mounts, links = _frames_fn(robot)(q)
    out = {"platform": np.asarray(p_p), "heading": np.asarray(r_p[:, :2, 0])}
    for i, ((_, p_m), (_, p_l)) in enumerate(zip(mounts, links)):
        out[f"arm{i}"] = np.concatenate([np.asarray(p_m)[:, None, :], np.asarray(p_l)], axis=1)
    return out


def _platform_size(robot: MobileManipulator) -> tuple[float, float, float]:
    """(body length, body width, wheel radius) used for drawing, from the platform's parameters."""
    half_track = float(getattr(robot.platform, "half_track", 0.25))
    radius = float(getattr(robot.platform, "wheel_radius", 0.1))
    reach = max((abs(m.x) for m in robot.mounts), default=0.0)
    length = max(2.0 * half_track, 2.0 * reach + 0.1)
    return length, 1.6 * half_track, radius


def _rectangle(
    center: npt.ArrayLike, heading: npt.ArrayLike, length: float, width: float, rear: float
) -> np.ndarray:
    """Corners of a rectangle of the given size, ``rear`` behind ``center`` along ``heading``."""
    u = np.asarray(heading) / np.linalg.norm(heading)
    n = np.array([-u[1], u[0]])
    back, front = -rear, length - rear
    return np.array(
        [
            center + back * u - width / 2 * n,
            center + front * u - width / 2 * n,
            center + front * u + width / 2 * n,
            center + back * u + width / 2 * n,
        ]
    )


def draw_robot(
    ax: Axes,
    robot: MobileManipulator,
    points: dict[str, np.ndarray],
    k: int,
    alpha: float = 1.0,
    color: str = "0.3",
) -> None:
    """Draw configuration ``k`` of :func:`frame_points` output on a top-view axes."""
    length, width, radius = _platform_size(robot)
    center = points["platform"][k, :2]
    heading = points["heading"][k]
    reach = max((m.x for m in robot.mounts), default=0.0)
    rear = (length - max(reach, 0.0) - 0.05) if reach > 0 else length / 2
    body = _rectangle(center, heading, length, width, rear=rear)
    ax.add_patch(Polygon(body, closed=True, fill=False, edgecolor=color, alpha=alpha, lw=1.0))
    n = np.array([-heading[1], heading[0]])
    half_track = float(getattr(robot.platform, "half_track", width / 2))
    for side in (-1.0, 1.0):
        wheel = _rectangle(
            center + side * half_track * n, heading, 2 * radius, 0.25 * radius + 0.02, rear=radius
        )
        ax.add_patch(Polygon(wheel, closed=True, facecolor=color, edgecolor=color, alpha=alpha))
    tip = center + 0.6 * length * heading
    ax.annotate(
        "", xy=tuple(tip), xytext=tuple(center), arrowprops=dict(arrowstyle="->", color=color, alpha=alpha)
    )
    for key in (k_ for k_ in points if k_.startswith("arm")):
        chain = points[key][k]
        ax.plot(chain[:, 0], chain[:, 1], "-o", color="tab:blue", alpha=alpha, ms=3, lw=2)


def _instants(n: int, instants: int | tuple[int, ...]) -> np.ndarray:
    if isinstance(instants, int):
        return np.unique(np.linspace(0, n - 1, max(instants, 1)).round().astype(int))
    return np.asarray(instants, dtype=int)


def plot_paths(
    robot: MobileManipulator,
    q: npt.ArrayLike,
    ee: npt.ArrayLike | None = None,
    instants: int | tuple[int, ...] = 5,
    reference: npt.ArrayLike | None = None,
    extra: Mapping[str, np.ndarray] | None = None,
    title: str | None = None,
    ax: Axes | None = None,
) -> Figure:
    """Top view: platform reference-point path, end-effector path and the robot at a few instants.

    q: configurations over time (N, n_q). ee: end-effector xy over time (N, 2) (default: the last arm
    point of the first arm). reference: the desired xy path (N, 2) to overlay. extra: further labelled
    xy paths (e.g. Korayem's base point F). instants: how many evenly spaced instants to draw, or their
    indices. Returns a new Figure, or the figure holding ``ax`` when one is given.
    """
    points = frame_points(robot, q)
    fig = Figure(figsize=(6.4, 5.2)) if ax is None else figure_of(ax)
    ax = fig.add_subplot(1, 1, 1) if ax is None else ax
    ee = points["arm0"][:, -1, :2] if ee is None else np.asarray(ee)
    if reference is not None:
        ref = np.asarray(reference)
        ax.plot(ref[:, 0], ref[:, 1], ":", color="k", lw=1, label="reference")
    ax.plot(
        points["platform"][:, 0],
        points["platform"][:, 1],
        color="tab:orange",
        lw=1.5,
        label="platform (axle midpoint)",
    )
    ax.plot(ee[:, 0], ee[:, 1], color="tab:green", lw=1.5, label="end effector")
    for label, path in (extra or {}).items():
        path = np.asarray(path)
        ax.plot(path[:, 0], path[:, 1], "--", lw=1.2, label=label)
    idx = _instants(len(ee), instants)
    for j, k in enumerate(idx):
        draw_robot(ax, robot, points, int(k), alpha=0.35 + 0.65 * (j + 1) / len(idx))
    finish_plane(ax, title)
    return fig


def plot_paths_3d(
    robot: MobileManipulator, q: npt.ArrayLike, instants: int | tuple[int, ...] = 4, title: str | None = None
) -> Figure:
    """3-D view: platform path on the floor, end-effector path, the arm and platform outline at instants."""
    points = frame_points(robot, q)
    fig = Figure(figsize=(6.4, 5.2))
    ax = fig.add_subplot(1, 1, 1, projection="3d")
    p = points["platform"]
    ee = points["arm0"][:, -1]
    ax.plot(p[:, 0], p[:, 1], p[:, 2], color="tab:orange", label="platform (axle midpoint)")
    ax.plot(ee[:, 0], ee[:, 1], ee[:, 2], color="tab:green", label="end effector")
    length, width, _ = _platform_size(robot)
    idx = _instants(len(p), instants)
    for j, k in enumerate(idx):
        a = 0.35 + 0.65 * (j + 1) / len(idx)
        body = _rectangle(p[k, :2], points["heading"][k], length, width, rear=length / 2)
        loop = np.vstack([body, body[:1]])
        ax.plot(loop[:, 0], loop[:, 1], np.zeros(len(loop)), color="0.3", alpha=a)
        for key in (k_ for k_ in points if k_.startswith("arm")):
            chain = points[key][k]
            ax.plot(chain[:, 0], chain[:, 1], chain[:, 2], "-o", color="tab:blue", alpha=a, ms=3, lw=2)
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_zlabel("z (m)")
    ax.legend(loc="upper left", fontsize=8)
    if title:
        ax.set_title(title)
    return fig
