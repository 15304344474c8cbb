"""URDF readings kept on disk (mobman.io.urdf_cache): read back equal to a fresh reading without parsing the
file again, and read afresh whenever the file, an option, a drawn mesh or the kept file itself changes."""

from __future__ import annotations

import os
import pickle
import warnings

import numpy as np
import pytest
import trimesh
from urdf_samples import husky

from mobman import kinematics
from mobman.io import urdf_cache
from mobman.io.urdf import UrdfWarning, read_urdf

MESHED = """<?xml version="1.0"?>
<robot name="meshed">
  <link name="base_link"><visual><geometry><mesh filename="meshes/body.stl"/></geometry></visual></link>
  <link name="wheel_r_link"><collision><origin rpy="1.5707963267948966 0 0"/>
    <geometry><cylinder radius="0.1" length="0.05"/></geometry></collision></link>
  <joint name="wheel_r" type="continuous"><parent link="base_link"/><child link="wheel_r_link"/>
    <origin xyz="0 -0.2 0.1"/><axis xyz="0 1 0"/><limit effort="5" velocity="10"/></joint>
  <link name="wheel_l_link"><collision><origin rpy="1.5707963267948966 0 0"/>
    <geometry><cylinder radius="0.1" length="0.05"/></geometry></collision></link>
  <joint name="wheel_l" type="continuous"><parent link="base_link"/><child link="wheel_l_link"/>
    <origin xyz="0 0.2 0.1"/><axis xyz="0 1 0"/><limit effort="5" velocity="10"/></joint>
  <link name="tool"/>
  <joint name="shoulder" type="revolute"><parent link="base_link"/><child link="tool"/>
    <origin xyz="0.2 0 0.5"/><axis xyz="0 0 1"/><limit lower="-3" upper="3" velocity="1" effort="10"/></joint>
</robot>
"""


@pytest.fixture
def kept(tmp_path, monkeypatch):
    """Readings kept in a fresh folder; ``kept.parsed`` counts the readings that parsed a file."""
    urdf_cache.enable(tmp_path / "cache")
    parsed = []

    def counting(*args, **kwargs):
        parsed.append(args[0])
        return read_urdf(*args, **kwargs)

    monkeypatch.setattr(urdf_cache, "read_urdf", counting)
    yield parsed
    urdf_cache.disable()


@pytest.fixture
def meshed(tmp_path):
    (tmp_path / "robot" / "meshes").mkdir(parents=True)
    trimesh.creation.box((0.4, 0.3, 0.2)).export(tmp_path / "robot" / "meshes" / "body.stl")
    path = tmp_path / "robot" / "meshed.urdf"
    path.write_text(MESHED)
    return path


def test_a_kept_reading_equals_a_fresh_one_and_parses_nothing(kept, meshed):
    first = urdf_cache.read(meshed, tip="tool", base="base_link")
    again = urdf_cache.read(meshed, tip="tool", base="base_link")
    assert kept == [meshed]  # the second reading came from the disk
    fresh = read_urdf(meshed, tip="tool", base="base_link")
    assert again.robot == fresh.robot and again.summary == fresh.summary
    assert again.robot.platform_visuals == fresh.robot.platform_visuals  # visuals are not compared by ==
    q = np.array([0.3, -0.2, np.pi / 2, 1.1])
    np.testing.assert_array_equal(
        np.asarray(kinematics.forward(again.robot, q)), np.asarray(kinematics.forward(first.robot, q))
    )


def test_another_option_or_an_edited_file_is_read_afresh(kept, meshed):
    urdf_cache.read(meshed, tip="tool", base="base_link")
    urdf_cache.read(meshed, tip="tool", base="base_link", platform_options={"base_height": 0.0})
    assert len(kept) == 2
    meshed.write_text(MESHED.replace('xyz="0.2 0 0.5"', 'xyz="0.3 0 0.5"'))
    moved = urdf_cache.read(meshed, tip="tool", base="base_link")
    assert len(kept) == 3
    xi = np.asarray(kinematics.forward(moved.robot, np.zeros(moved.robot.n_q)))
    np.testing.assert_allclose(xi[:2], [0.3, 0.0], atol=1e-12)  # the edited shoulder position


def test_a_changed_or_missing_mesh_is_read_afresh_and_not_kept(kept, meshed):
    urdf_cache.read(meshed, tip="tool", base="base_link")
    mesh = meshed.parent / "meshes" / "body.stl"
    stat = mesh.stat()
    os.utime(mesh, ns=(stat.st_atime_ns, stat.st_mtime_ns + 10**9))
    urdf_cache.read(meshed, tip="tool", base="base_link")
    assert len(kept) == 2
    mesh.unlink()
    for _ in range(2):
        model = urdf_cache.read(meshed, tip="tool", base="base_link")
    assert model.summary.missing_meshes == ("meshes/body.stl",)
    assert len(kept) == 4  # a reading with a mesh missing is never kept


def test_the_notes_are_said_again_when_read_back(kept, tmp_path):
    path = husky(tmp_path, wheels="none")
    options = {"tip": "tool", "base": "base_link", "platform": "differential"}
    options["platform_options"] = {"wheel_radius": 0.1651, "half_track": 0.2854}
    for _ in range(2):
        with warnings.catch_warnings(record=True) as said:
            warnings.simplefilter("always")
            model = urdf_cache.read(path, **options)
        assert model.summary.notes
        assert [str(w.message) for w in said if w.category is UrdfWarning] == list(model.summary.notes)
    assert len(kept) == 1


def test_a_damaged_or_foreign_kept_file_is_never_used(kept, meshed, tmp_path):
    urdf_cache.read(meshed, tip="tool", base="base_link")
    (path,) = (tmp_path / "cache" / "urdf").glob("*.pickle")
    path.write_bytes(b"damaged")
    urdf_cache.read(meshed, tip="tool", base="base_link")
    assert len(kept) == 2
    path.write_bytes(pickle.dumps((os.getcwd, ())))  # names a function outside mobman: never unpickled
    model = urdf_cache.read(meshed, tip="tool", base="base_link")
    assert len(kept) == 3 and model.robot.n_q == 4


def test_off_the_reading_is_never_kept(tmp_path, meshed):
    urdf_cache.disable()
    urdf_cache.read(meshed, tip="tool", base="base_link")
    assert not list(tmp_path.rglob("*.pickle"))


def test_a_kept_collision_model_equals_a_fresh_one_and_is_not_rebuilt(kept, meshed, monkeypatch):
    from mobman.io.urdf import collision_shapes
    from mobman.model.collision_model import CollisionModel

    model = read_urdf(meshed, tip="tool", base="base_link")
    fresh = CollisionModel.from_shapes(model.robot, collision_shapes(model), 0.05)
    first = urdf_cache.collision_model(meshed, model.robot, 0.05, tip="tool", base="base_link")
    built = []
    monkeypatch.setattr(urdf_cache.CollisionModel, "from_shapes", lambda *args: built.append(args))
    again = urdf_cache.collision_model(meshed, model.robot, 0.05, tip="tool", base="base_link")
    assert built == [] and again == first == fresh
    urdf_cache.collision_model(meshed, model.robot, 0.1, tip="tool", base="base_link")  # another tolerance
    assert len(built) == 1
