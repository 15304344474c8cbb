"""Matplotlib figures of mobile-manipulator motions (Agg backend, no pyplot state).

Every figure function takes plain arrays (configurations over time, a robot) and returns a
:class:`matplotlib.figure.Figure`; saving it is the caller's business (``fig.savefig(path)``).

- :mod:`mobman.viz.paths` top view of platform and end-effector paths with the robot drawn at a few
  instants; a 3-D view for spatial arms.
- :mod:`mobman.viz.ellipses` manipulability ellipses along a path (SVD of 2 × k Jacobians).
- :mod:`mobman.viz.timeseries` measures, coordinates and velocities versus time.
- :mod:`mobman.viz.maps` reachability maps from above and from the side.
- :mod:`mobman.viz.torques` required actuator torques against their envelopes (load capacity).
"""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

from mobman.viz.ellipses import ellipse_outline, plot_ellipses  # noqa: E402
from mobman.viz.maps import best_along, plot_reachability  # noqa: E402
from mobman.viz.paths import draw_robot, frame_points, plot_paths, plot_paths_3d  # noqa: E402
from mobman.viz.timeseries import draw_curves, plot_timeseries  # noqa: E402
from mobman.viz.torques import plot_load_runs, plot_torques  # noqa: E402

__all__ = [
    "draw_curves",
    "draw_robot",
    "best_along",
    "ellipse_outline",
    "frame_points",
    "plot_ellipses",
    "plot_paths",
    "plot_paths_3d",
    "plot_reachability",
    "plot_timeseries",
    "plot_load_runs",
    "plot_torques",
]
