"""A robot described in a TOML file (platform, DH arm, mount, task), used like a built-in one.

The file below describes the geometry of `bayle_planar`; its kinematics equal the built-in robot's. The
file is written to a temporary folder (the format: the docstring of `mobman.io.robot_file`).

    python examples/07_robot_from_a_file.py
"""

import tempfile
from pathlib import Path

import numpy as np

from mobman import kinematics
from mobman.io import robot_file
from mobman.model import robots

ROBOT = Path(__file__).resolve().parents[1] / "docs" / "examples" / "planar_robot.toml"

with tempfile.TemporaryDirectory() as folder:
    path = Path(folder) / "robot.toml"
    path.write_text(ROBOT.read_text())
    robot = robot_file.load(path)

print(f"{robot.name}: coordinates {robot.coordinate_names}, task dimension {robot.task.dim}")
q = np.random.default_rng(0).uniform(-np.pi, np.pi, (1_000, robot.n_q))
built_in = robots.bayle_planar()
for name, fn in (("ξ", kinematics.forward), ("J̄", kinematics.reduced_jacobian)):
    ours, theirs = fn(robot, q), fn(built_in, q, robot.task)  # the same task: the (x, y) position
    difference = float(np.max(np.abs(np.asarray(ours) - np.asarray(theirs))))
    print(f"{name}: max difference from the built-in bayle_planar over 1,000 configurations {difference:.1e}")
