"""Scene files in TOML: read, and every bad file a one-line error naming the file, the obstacle and the field."""

from __future__ import annotations

import pytest

from mobman.errors import InputError
from mobman.io import scene as scene_file

TEXT = """
floor = 0.0

[[obstacle]]
name = "table"
shape = "box"                # box | sphere | cylinder | capsule
size = [0.8, 1.2, 0.75]
position = [1.3, 0.0, 0.375]
rpy = [0.0, 0.0, 0.5]

[[obstacle]]
name = "pole"
shape = "capsule"
size = [0.05, 1.0]
position = [0.0, 1.0, 0.6]
"""


def test_a_scene_file_reads(tmp_path):
    path = tmp_path / "scene.toml"
    path.write_text(TEXT)
    scene = scene_file.load(path)
    assert [o.name for o in scene.obstacles] == ["table", "pole"]
    assert scene.obstacles[0].rpy == (0.0, 0.0, 0.5) and scene.obstacles[1].rpy == (0.0, 0.0, 0.0)
    assert scene.obstacles[1].size == (0.05, 1.0) and scene.floor == 0.0


@pytest.mark.parametrize(
    "old, new, message",
    [
        ('shape = "capsule"', 'shape = "cone"', "obstacle 'pole': shape must be one of"),
        ("size = [0.05, 1.0]", "size = [0.05, -1.0]", r"obstacle 'pole': size\[1\] \(length\) must be > 0"),
        (
            "position = [0.0, 1.0, 0.6]",
            "position = [0.0, nan, 0.6]",
            r"obstacle 'pole': position\[1\] must be finite",
        ),
        ("position = [0.0, 1.0, 0.6]", "colour = 1", "obstacle 'pole': unknown key 'colour'"),
        ("floor = 0.0", "floor = inf", "scene: floor must be finite"),
        ("floor = 0.0", "ground = 0.0", "scene: unknown key 'ground'"),
        ("size = [0.05, 1.0]", "size = [0.05, 1.0", "invalid TOML"),
    ],
)
def test_bad_files_name_the_file_obstacle_and_field(tmp_path, old, new, message):
    path = tmp_path / "scene.toml"
    path.write_text(TEXT.replace(old, new))
    with pytest.raises(InputError, match=message) as info:
        scene_file.load(path)
    assert str(info.value).startswith(f"{path}: ") and "\n" not in str(info.value)


def test_a_missing_file(tmp_path):
    with pytest.raises(InputError, match="cannot read"):
        scene_file.load(tmp_path / "none.toml")
