"""``mobman distance``: the minimum distance, the closest pair and the per-pair distances of a robot and a scene,
against coal's distance of the robot's own (generated) shapes: never larger, smaller by at most the cover
tolerance; bad input as one line and exit 2."""

from __future__ import annotations

import coal
import numpy as np
import pytest

from mobman.model import robots, spatial
from mobman.model.collision_model import generated_shapes
from mobman.model.robot import MobileManipulator

SCENE = """
[[obstacle]]
name = "ball"
shape = "sphere"
size = [0.1]
position = [1.25, 0.3, 0.0]

[[obstacle]]
name = "wall"
shape = "box"
size = [4.0, 0.1, 1.0]
position = [0.0, -0.9, 0.0]
rpy = [0.0, 0.0, 0.1]
"""
Q = "0.2,0.1,0.3,-0.4,0.6"


def _link_distance(robot: MobileManipulator, q: np.ndarray, link: int, centre, radius: float) -> float:
    """coal's distance of the generated cylinder of arm link ``link`` to a sphere obstacle."""
    shape = generated_shapes(robot)[(0, link)][0]
    rs, ps = (np.asarray(v) for v in robot.frames(q).links[0])
    pose = spatial.as_matrix(spatial.transform(rs[link], ps[link])) @ spatial.as_matrix(shape.origin)
    request, result = coal.DistanceRequest(), coal.DistanceResult()
    return coal.distance(
        coal.Cylinder(*shape.size),
        coal.Transform3s(pose[:3, :3], pose[:3, 3]),
        coal.Sphere(radius),
        coal.Transform3s(np.eye(3), np.asarray(centre, dtype=float)),
        request,
        result,
    )


def test_distance_json(cli_json, tmp_path):
    path = tmp_path / "scene.toml"
    path.write_text(SCENE)
    out = cli_json(["distance", "bayle-planar", "--scene", str(path), "--q", Q])
    robot = robots.ROBOTS["bayle-planar"]()
    q = np.array([0.2, 0.1, 0.3, -0.4, 0.6])
    pairs = {(p["robot"], p["other"]): p["distance"] for p in out["pairs"]}
    assert out["min_distance"] == min(pairs.values()) == out["pairs"][0]["distance"]
    assert (out["closest"]["robot"], out["closest"]["other"]) == (
        out["pairs"][0]["robot"],
        out["pairs"][0]["other"],
    )
    assert {other for _, other in pairs} >= {"ball", "wall"}
    tolerance = out["tolerance"]
    for link, name in enumerate(robot.coordinate_names[3:]):
        exact = _link_distance(robot, q, link, (1.25, 0.3, 0.0), 0.1)
        assert exact - tolerance - 1e-9 <= pairs[(name, "ball")] <= exact + 1e-9
    gap = np.asarray(out["closest"]["robot_point"]) - np.asarray(out["closest"]["other_point"])
    assert float(gap @ np.asarray(out["closest"]["normal"])) == pytest.approx(out["min_distance"], abs=1e-9)


def test_a_penetration_is_negative_and_the_table_names_it(cli_run, tmp_path):
    path = tmp_path / "scene.toml"
    path.write_text(SCENE.replace("position = [1.25, 0.3, 0.0]", "position = [0.0, 0.0, 0.0]"))
    code, out, err = cli_run(["distance", "bayle-planar", "--scene", str(path)])
    assert code == 0, err
    assert "in collision" in out and "platform" in out and "ball" in out


@pytest.mark.parametrize(
    "args, message",
    [
        (["--scene", "SCENE", "--q", "0,0,0"], "--q"),
        (["--scene", "SCENE", "--tolerance", "0"], "--tolerance: must be a finite number > 0"),
        (["--scene", "BAD"], "obstacle 'ball': shape must be one of"),
        (["--scene", "MISSING"], "cannot read"),
    ],
)
def test_bad_input_is_one_line_and_exit_2(cli_run, tmp_path, args, message):
    good, bad = tmp_path / "scene.toml", tmp_path / "bad.toml"
    good.write_text(SCENE)
    bad.write_text(SCENE.replace('"sphere"', '"cone"'))
    paths = {"SCENE": str(good), "BAD": str(bad), "MISSING": str(tmp_path / "none.toml")}
    code, out, err = cli_run(["distance", "bayle-planar", *(paths.get(a, a) for a in args)])
    assert code == 2 and message in err and len(err.strip().splitlines()) == 1
