"""mobman.viz.paths: the drawn frames, paths and robots match the model layer (forward kinematics)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from matplotlib.figure import Figure

from mobman import kinematics as K
from mobman import viz
from mobman.model import robots
from mobman.model.tasks import MountPosition, Position


@pytest.fixture(scope="module")
def korayem_run():
    robot = robots.korayem_planar()
    t = np.linspace(0.0, 1.0, 12)
    q = np.stack([t, 0.3 * t, 0.8 * t, -1.0 + t, 1.0 + 0.5 * t], axis=1)
    return robot, q


def test_frame_points_match_kinematics(korayem_run):
    robot, q = korayem_run
    pts = viz.frame_points(robot, q)
    np.testing.assert_allclose(pts["platform"][:, :2], q[:, :2], atol=1e-14)
    np.testing.assert_allclose(pts["heading"], np.stack([np.cos(q[:, 2]), np.sin(q[:, 2])], 1), atol=1e-14)
    np.testing.assert_allclose(pts["arm0"][:, 0, :2], K.forward(robot, q, MountPosition()), atol=1e-14)
    np.testing.assert_allclose(pts["arm0"][:, -1, :2], K.forward(robot, q, Position("xy")), atol=1e-14)


def test_plot_paths_draws_model_paths_and_wheels(korayem_run, tmp_path):
    robot, q = korayem_run
    fig = viz.plot_paths(robot, q, instants=(0, 11), extra={"F": K.forward(robot, q, MountPosition())})
    assert isinstance(fig, Figure)
    ax = fig.axes[0]
    lines = {line.get_label(): line for line in ax.lines}
    np.testing.assert_allclose(
        np.asarray(lines["end effector"].get_xydata()), K.forward(robot, q, Position("xy")), atol=1e-12
    )
    np.testing.assert_allclose(
        np.asarray(lines["platform (axle midpoint)"].get_xydata()), q[:, :2], atol=1e-12
    )
    # two instants: 1 body + 2 wheels each; wheel centres at ±half_track across the heading
    assert len(ax.patches) == 6
    wheel_centres = np.array([p.get_xy()[:4].mean(axis=0) for p in ax.patches[4:6]])
    d = wheel_centres - q[11, :2]
    np.testing.assert_allclose(np.linalg.norm(d, axis=1), robot.platform.half_track, atol=1e-12)
    np.testing.assert_allclose(d @ [math.cos(q[11, 2]), math.sin(q[11, 2])], 0.0, atol=1e-12)
    fig.savefig(tmp_path / "paths.png")
    assert (tmp_path / "paths.png").read_bytes()[:4] == b"\x89PNG"


def test_plot_paths_3d_and_ellipses(tmp_path):
    robot = robots.manus_platform()
    q = np.tile([0.0, 0.0, 0.0, math.pi / 2, math.pi / 3, -math.pi / 3], (5, 1))
    q[:, 0] = np.linspace(0.0, 0.5, 5)
    fig = viz.plot_paths_3d(robot, q, instants=2)
    tool = [line for line in fig.axes[0].lines if line.get_label() == "end effector"][0]
    np.testing.assert_allclose(np.asarray(tool.get_data_3d()).T, K.forward(robot, q), atol=1e-12)
    jac = np.asarray(K.reduced_jacobian(robot, q))[:, :2, :]
    fig = viz.plot_ellipses(np.asarray(K.forward(robot, q))[:, :2], jac, scale=0.2)
    assert len([line for line in fig.axes[0].lines if line.get_label() != "_nolegend_"]) >= 5
    fig.savefig(tmp_path / "ellipses.png")
