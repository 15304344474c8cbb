"""Small URDF files written by the tests of URDF reading (``tests/test_io_urdf.py``,
``tests/test_cli_urdf_options.py``), with their forward kinematics by hand."""

from __future__ import annotations

from pathlib import Path

import numpy as np

HUSKY_WHEEL = """
  <link name="{name}_link"><collision><origin rpy="1.5707963267948966 0 0"/>
    <geometry><cylinder radius="0.1651" length="0.1143"/></geometry></collision></link>
  <joint name="{name}" type="continuous"><parent link="base_link"/><child link="{name}_link"/>
    <origin xyz="{x} {y} 0.03282"/><axis xyz="0 1 0"/><limit effort="20" velocity="10"/></joint>"""
HUSKY_ARM = """
  <link name="lift_link"/>
  <joint name="lift" type="prismatic"><parent link="base_link"/><child link="lift_link"/>
    <origin xyz="0.1 0.05 0.2"/><axis xyz="0 0 1"/><limit lower="0" upper="0.5" velocity="0.1" effort="100"/></joint>
  <link name="tool"/>
  <joint name="wrist" type="revolute"><parent link="lift_link"/><child link="tool"/>
    <origin xyz="0.3 0 0"/><axis xyz="0 0 1"/><limit lower="-3" upper="3" velocity="1" effort="10"/></joint>"""


def husky(folder: Path, wheels: str = "continuous") -> Path:
    """A skid-steer like Clearpath's Husky: base_link 0.1651 − 0.03282 = 0.13228 m above the ground its four
    wheels (radius 0.1651 m, axles at x = ±0.256 m, track 2 · 0.2854 m) stand on; a lift at (0.1, 0.05, 0.2)
    and a wrist 0.3 m ahead of it. ``wheels="fixed"``: the wheels as fixed joints (simulator exports);
    ``"none"``: no wheel links."""
    parts = ['<?xml version="1.0"?>\n<robot name="husky">', '  <link name="base_link"/>', HUSKY_ARM]
    if wheels != "none":
        for name, x, y in [("front_right", 0.256, -0.2854), ("front_left", 0.256, 0.2854)]:
            parts.append(HUSKY_WHEEL.format(name=name, x=x, y=y))
        for name, x, y in [("rear_right", -0.256, -0.2854), ("rear_left", -0.256, 0.2854)]:
            parts.append(HUSKY_WHEEL.format(name=name, x=x, y=y))
    text = "\n".join([*parts, "</robot>"]).replace('type="continuous"', f'type="{wheels}"')
    path = folder / f"husky_{wheels}.urdf"
    path.write_text(text)
    return path


def husky_tool(q: np.ndarray, height: float) -> np.ndarray:
    """The tool position of the Husky-like robot by hand: lift at (0.1, 0.05, height + 0.2) in the platform
    frame, the tool 0.3 m along the wrist's x axis, itself turned by the wrist angle about the vertical."""
    x, y, theta, lift, wrist = q.T
    c, s = np.cos(theta), np.sin(theta)
    local = np.stack([0.1 + 0.3 * np.ones_like(x), 0.05 * np.ones_like(x)])
    return np.stack(
        [x + c * local[0] - s * local[1], y + s * local[0] + c * local[1], height + 0.2 + lift], -1
    )
