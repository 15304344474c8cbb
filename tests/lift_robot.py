"""A robot whose tool height is a joint: a vertical lift (prismatic, 0.2 to 0.8 m) mounted 0.3 m up, and a
horizontal link of 0.5 m turning about it, on a differential drive. The tool is at the height 0.3 + q1, so
it reaches every height from 0.5 to 1.1 m and no other, and 0.5 m from the lift's axis."""

from __future__ import annotations

from pathlib import Path

LIFT = """
name = "lift"
task = "xyz"

[platform]
kind = "differential"
wheel_radius = 0.1
half_track = 0.25
v_max = 0.5
omega_max = 1.0

[[arms]]
name = "lift-arm"
convention = "dh"
table = [[0.0, 0.0, 0.0, 0.0], [0.0, 0.0, 0.5, 0.0]]
kinds = "PR"
limits = [[0.2, 0.8], [-3.1, 3.1]]
mount = [0.0, 0.0, 0.3, 0.0]
"""

LOWEST, HIGHEST = 0.5, 1.1
"""The tool's heights at the lift's limits (m)."""


def lift_file(folder: Path) -> Path:
    """The robot file of the lift robot, written into ``folder``."""
    path = folder / "lift.toml"
    path.write_text(LIFT)
    return path
