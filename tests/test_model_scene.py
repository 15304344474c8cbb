"""The scene: obstacles as primitives, their validation (one line naming the obstacle and the field) and their
rotation R = Rz(yaw) Ry(pitch) Rx(roll) against SciPy's extrinsic xyz Euler angles."""

from __future__ import annotations

import math

import jax
import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from mobman.errors import MobmanError, ModelError
from mobman.model.scene import MAX_OBSTACLES, Obstacle, Scene

TABLE = {"name": "table", "shape": "box", "size": [0.8, 1.2, 0.75], "position": [1.3, 0.0, 0.375]}


@pytest.mark.parametrize(
    "rpy",
    [(0.0, 0.0, 0.0), (math.pi / 2, -math.pi / 2, math.pi), (0.3, -1.1, 2.5), (math.pi, math.pi / 2, -0.4)],
)
def test_rotation_is_rz_ry_rx(rpy):
    obstacle = Obstacle("o", "sphere", (0.1,), rpy=rpy)
    expected = Rotation.from_euler("xyz", rpy).as_matrix()  # extrinsic x, y, z: Rz Ry Rx
    np.testing.assert_allclose(obstacle.rotation, expected, atol=1e-14)


def test_a_table_reads_with_defaults():
    scene = Scene.from_table(
        {"obstacle": [TABLE, {"name": "ball", "shape": "sphere", "size": [0.2]}], "floor": 0.0}
    )
    table, ball = scene.obstacles
    assert table.size == (0.8, 1.2, 0.75) and table.rpy == (0.0, 0.0, 0.0)
    assert ball.position == (0.0, 0.0, 0.0)
    assert scene.names == ("table", "ball", "floor")
    assert Scene.from_table(scene.describe()) == scene


def test_a_scene_is_a_static_argument():
    scene = Scene((Obstacle("ball", "sphere", (0.2,), (1.0, 0.0, 0.0)),))
    same = Scene((Obstacle("ball", "sphere", [0.2], [1, 0, 0]),))
    assert hash(scene) == hash(same) and scene == same

    @jax.jit
    def shifted(x):
        return x + scene.obstacles[0].position[0]

    assert float(
        jax.jit(lambda x, s: x + s.obstacles[0].size[0], static_argnums=1)(1.0, same)
    ) == pytest.approx(1.2)
    assert float(shifted(1.0)) == 2.0


@pytest.mark.parametrize(
    "change, message",
    [
        (
            {"shape": "cone"},
            r"obstacle 'table': shape must be one of box, sphere, cylinder, capsule, got 'cone'",
        ),
        ({"shape": "bx"}, r"did you mean 'box'"),
        ({"size": [0.8, 1.2]}, r"obstacle 'table': size must be 3 numbers \(box: \[x, y, z\]"),
        ({"size": [0.8, -1.2, 0.75]}, r"obstacle 'table': size\[1\] \(y\) must be > 0"),
        ({"size": [0.8, 0.0, 0.75]}, r"obstacle 'table': size\[1\] \(y\) must be > 0"),
        ({"size": [0.8, float("inf"), 0.75]}, r"obstacle 'table': size\[1\] must be finite"),
        ({"position": [1.0, float("nan"), 0.0]}, r"obstacle 'table': position\[1\] must be finite"),
        ({"rpy": [0.0, 0.0, float("inf")]}, r"obstacle 'table': rpy\[2\] must be finite"),
        ({"rpy": [0.0, 0.0]}, r"obstacle 'table': rpy must be 3 numbers"),
        ({"position": "here"}, r"obstacle 'table': position must be 3 numbers"),
        ({"colour": "red"}, r"obstacle 'table': unknown key 'colour'"),
        ({"size": None}, r"obstacle 'table': size must be 3 numbers"),
    ],
)
def test_bad_obstacles_are_one_line_naming_obstacle_and_field(change, message):
    with pytest.raises(ModelError, match=message) as info:
        Scene.from_table({"obstacle": [{**TABLE, **change}]})
    assert "\n" not in str(info.value)


@pytest.mark.parametrize("missing", ["name", "shape", "size"])
def test_a_missing_key_is_named(missing):
    table = {k: v for k, v in TABLE.items() if k != missing}
    with pytest.raises(MobmanError, match=f"missing '{missing}'"):
        Scene.from_table({"obstacle": [table]})


def test_sphere_and_capsule_sizes():
    with pytest.raises(ModelError, match=r"obstacle 'b': size must be 1 numbers \(sphere: \[radius\]"):
        Obstacle("b", "sphere", (0.1, 0.2))
    with pytest.raises(ModelError, match=r"obstacle 'c': size\[1\] \(length\) must be > 0"):
        Obstacle("c", "capsule", (0.1, 0.0))


def test_scene_limits_and_names():
    many = [{"name": f"o{k}", "shape": "sphere", "size": [0.1]} for k in range(MAX_OBSTACLES + 1)]
    with pytest.raises(
        ModelError, match=f"scene: {MAX_OBSTACLES + 1} obstacles, at most {MAX_OBSTACLES} allowed"
    ):
        Scene.from_table({"obstacle": many})
    with pytest.raises(ModelError, match="obstacle 'o0': name used twice"):
        Scene.from_table({"obstacle": [many[0], many[0]]})
    with pytest.raises(ModelError, match="scene: unknown key 'obstacles'"):
        Scene.from_table({"obstacles": []})
    with pytest.raises(ModelError, match="scene: floor must be finite"):
        Scene((), float("nan"))
    with pytest.raises(ModelError, match=r"obstacle 2: must be a table"):
        Scene.from_table({"obstacle": [TABLE, 3]})
