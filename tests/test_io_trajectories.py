"""mobman.io.trajectories: motions q(t) with their robot's identity, written to and read from trajectories.json."""

from __future__ import annotations

import json
import os
from pathlib import Path

import jax.numpy as jnp
import numpy as np
import pytest

from mobman.errors import InputError
from mobman.io import trajectories
from mobman.io.trajectories import FILENAME, Motion
from mobman.model import robots

RNG = np.random.default_rng(7)


def _motion(label: str = "run", samples: int = 4, robot_name: str = "bayle-planar") -> Motion:
    """A motion of 5 coordinates with full-precision values (no short decimal form)."""
    t = np.sort(RNG.uniform(0.0, 3.0, samples))
    q = RNG.uniform(-np.pi, np.pi, (samples, 5))
    return Motion(label, robot_name, (("l1", 0.5), ("l2", 0.5)), t, q)


def _write_raw(folder: Path, content: str | bytes) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / FILENAME
    if isinstance(content, bytes):
        path.write_bytes(content)
    else:
        path.write_text(content)
    return path


def _entry(**changes: object) -> dict:
    entry: dict = {
        "label": "run",
        "robot": {"name": "bayle-planar", "parameters": {"l1": 0.5}, "factory": ""},
        "t": [0.0, 1.0],
        "q": [[0.0, 1.0], [2.0, 3.0]],
    }
    entry.update(changes)
    return entry


# --- Motion ----------------------------------------------------------------------------------------------


def test_motion_of_takes_the_robot_identity_and_float_arrays():
    robot = robots.bayle_planar(l1=0.7, l2=0.4)
    motion = Motion.of("circle", robot, [0, 1, 2], [[0, 0, 0, 1, 2]] * 3)
    assert motion.label == "circle"
    assert motion.robot_name == "bayle-planar"
    assert motion.parameters == (("l1", 0.7), ("l2", 0.4))
    assert motion.factory == ""
    assert isinstance(motion.t, np.ndarray) and motion.t.dtype == np.float64
    assert isinstance(motion.q, np.ndarray) and motion.q.dtype == np.float64
    np.testing.assert_array_equal(motion.t, [0.0, 1.0, 2.0])
    assert motion.q.shape == (3, 5)
    np.testing.assert_array_equal(motion.q[:, 4], [2.0, 2.0, 2.0])


def test_motion_of_accepts_jax_arrays():
    motion = Motion.of("run", robots.bayle_planar(), jnp.array([0.0, 0.5]), jnp.zeros((2, 5)))
    assert isinstance(motion.t, np.ndarray) and isinstance(motion.q, np.ndarray)
    assert motion.q.shape == (2, 5) and motion.q.dtype == np.float64


def test_motion_of_names_the_factory_as_module_and_function():
    motion = Motion.of("run", robots.bayle_rrp(), [0.0], [[0.0] * 6], factory=robots.bayle_rrp)
    assert motion.factory == "mobman.model.robots:bayle_rrp"


def test_describes_the_robot_that_made_it():
    motion = Motion.of("run", robots.bayle_planar(l1=0.6), [0.0], [[0.0] * 5])
    assert motion.describes(robots.bayle_planar(l1=0.6))
    assert motion.describes(robots.build("bayle-planar", l1=0.6))
    assert not motion.describes(robots.bayle_planar())
    assert not motion.describes(robots.korayem_planar())


@pytest.mark.parametrize(
    ("name", "parameters", "same"),
    [
        ("bayle-planar", (("l1", 0.5), ("l2", 0.5)), True),
        ("bayle-planar", (("l2", 0.5), ("l1", 0.5)), True),
        ("bayle-planar", (("l1", 0.5 * (1 + 1e-14)), ("l2", 0.5)), True),
        ("bayle-planar", (("l1", 0.5 * (1 + 1e-9)), ("l2", 0.5)), False),
        ("bayle-planar", (("l1", 0.5),), False),
        ("bayle-planar", (("l1", 0.5), ("l2", 0.5), ("l3", 0.5)), False),
        ("bayle-planar", (("l1", 0.5), ("L2", 0.5)), False),
        ("korayem-planar", (("l1", 0.5), ("l2", 0.5)), False),
    ],
    ids=["same", "other-order", "within-1e-12", "beyond-1e-12", "fewer", "more", "other-key", "other-name"],
)
def test_describes_compares_name_and_parameters(name: str, parameters: tuple, same: bool):
    motion = Motion("run", name, parameters, np.zeros(1), np.zeros((1, 5)))
    assert motion.describes(robots.bayle_planar()) is same


@pytest.mark.parametrize(
    ("name", "parameters", "label"),
    [
        ("bayle-planar", (("l1", 0.5), ("l2", 0.25)), "bayle-planar (l1=0.5, l2=0.25)"),
        (
            "bayle-planar",
            (("l1", 0.123456789), ("l2", 1234567.0)),
            "bayle-planar (l1=0.123457, l2=1.23457e+06)",
        ),
        ("bayle-rrp", (), "bayle-rrp"),
    ],
    ids=["parameters", "six-digits", "no-parameters"],
)
def test_robot_label_reads_as_name_and_parameters(name: str, parameters: tuple, label: str):
    assert Motion("run", name, parameters, np.zeros(1), np.zeros((1, 5))).robot_label == label


def test_robot_label_of_a_built_robot():
    motion = Motion.of("run", robots.bayle_rrp(), [0.0], [[0.0] * 6])
    assert motion.robot_label == "bayle-rrp"


# --- write and read --------------------------------------------------------------------------------------


def test_write_then_read_gives_the_same_motions_exactly(tmp_path: Path):
    first = _motion("reference", samples=5)
    second = Motion(
        "planned",
        "korayem-planar",
        (("l0", 0.4), ("l1", 1 / 3)),
        np.array([0.0]),
        RNG.normal(size=(1, 5)),
        factory="mobman.model.robots:korayem_planar",
    )
    path = trajectories.write(tmp_path, [first, second])
    assert path == tmp_path / FILENAME
    read = trajectories.read(tmp_path)
    assert len(read) == 2
    for mine, back in zip([first, second], read):
        assert back.label == mine.label
        assert back.robot_name == mine.robot_name
        assert back.parameters == mine.parameters
        assert back.factory == mine.factory
        assert back.robot_label == mine.robot_label
        assert back.t.dtype == np.float64 and back.q.dtype == np.float64
        assert back.t.shape == mine.t.shape and back.q.shape == mine.q.shape
        assert np.array_equal(back.t, mine.t) and np.array_equal(back.q, mine.q)


def test_a_read_motion_describes_the_robot_that_made_it(tmp_path: Path):
    robot = robots.bayle_planar(l1=0.3, l2=0.45)
    trajectories.write(tmp_path, [Motion.of("run", robot, [0.0, 0.1], np.zeros((2, 5)))])
    (motion,) = trajectories.read(tmp_path)
    assert motion.describes(robot)
    assert not motion.describes(robots.bayle_planar())


def test_write_produces_the_documented_layout(tmp_path: Path):
    motion = Motion(
        "run", "bayle-planar", (("l1", 0.5),), np.array([0.0, 1.0]), np.array([[1.0, 2.0], [3.0, 4.0]])
    )
    path = trajectories.write(tmp_path, [motion])
    assert json.loads(path.read_text(encoding="utf-8")) == {
        "motions": [
            {
                "label": "run",
                "robot": {"name": "bayle-planar", "parameters": {"l1": 0.5}, "factory": ""},
                "t": [0.0, 1.0],
                "q": [[1.0, 2.0], [3.0, 4.0]],
            }
        ]
    }


def test_write_keeps_the_file_strict_json_when_q_holds_nan(tmp_path: Path):
    motion = Motion("run", "bayle-planar", (), np.array([0.0, 1.0]), np.array([[0.0], [np.nan]]))
    path = trajectories.write(tmp_path, [motion])

    def refuse(token: str) -> None:
        raise AssertionError(f"non-standard JSON token {token}")

    assert json.loads(path.read_text(), parse_constant=refuse)["motions"][0]["q"] == [[0.0], [None]]


def test_write_creates_the_folder_and_replaces_an_old_file(tmp_path: Path):
    folder = tmp_path / "results" / "run"
    trajectories.write(folder, [_motion("old")])
    trajectories.write(folder, [_motion("new"), _motion("newer")])
    assert [m.label for m in trajectories.read(folder)] == ["new", "newer"]
    assert sorted(p.name for p in folder.iterdir()) == [FILENAME]


def test_a_failed_write_leaves_the_old_file_whole(tmp_path: Path, monkeypatch: pytest.MonkeyPatch):
    trajectories.write(tmp_path, [_motion("old")])
    before = (tmp_path / FILENAME).read_bytes()

    def fail(fd: int) -> None:
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(os, "fsync", fail)
    with pytest.raises(OSError):
        trajectories.write(tmp_path, [_motion("new", samples=50)])
    assert (tmp_path / FILENAME).read_bytes() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == [FILENAME]


# --- locate ----------------------------------------------------------------------------------------------


def test_locate_finds_the_file_from_the_folder_a_results_file_or_itself(tmp_path: Path):
    path = trajectories.write(tmp_path, [_motion()])
    (tmp_path / "results.json").write_text("{}")
    assert trajectories.locate(tmp_path) == path
    assert trajectories.locate(str(tmp_path)) == path
    assert trajectories.locate(tmp_path / "results.json") == path
    assert trajectories.locate(path) == path


def test_locate_a_path_that_does_not_exist(tmp_path: Path):
    missing = tmp_path / "nothing"
    with pytest.raises(InputError) as info:
        trajectories.locate(missing)
    assert str(info.value) == f"--results {missing}: no such file or folder"


@pytest.mark.parametrize("where", ["empty-folder", "results-file-alone", "folder-named-like-the-file"])
def test_locate_a_place_without_a_trajectories_file(tmp_path: Path, where: str):
    target = {
        "empty-folder": tmp_path,
        "results-file-alone": tmp_path / "results.json",
        "folder-named-like-the-file": tmp_path,
    }[where]
    if where == "results-file-alone":
        target.write_text("{}")
    if where == "folder-named-like-the-file":
        (tmp_path / FILENAME).mkdir()
    with pytest.raises(InputError) as info:
        trajectories.locate(target)
    assert str(info.value).startswith(
        f"--results {target}: no {FILENAME} there (written by mobman simulate --out"
    )


def test_read_of_a_missing_folder_is_an_input_error(tmp_path: Path):
    with pytest.raises(InputError, match="no such file or folder"):
        trajectories.read(tmp_path / "nothing")


# --- read of malformed files -----------------------------------------------------------------------------


MALFORMED = {
    "empty": "",
    "not-json": "{not json",
    "a-list": "[]",
    "a-number": "3",
    "no-motions": "{}",
    "motions-not-a-list": json.dumps({"motions": 3}),
    "motion-not-a-table": json.dumps({"motions": [3]}),
    "no-label": json.dumps({"motions": [{k: v for k, v in _entry().items() if k != "label"}]}),
    "no-q": json.dumps({"motions": [{k: v for k, v in _entry().items() if k != "q"}]}),
    "no-robot-name": json.dumps({"motions": [_entry(robot={"parameters": {}})]}),
    "robot-a-string": json.dumps({"motions": [_entry(robot="bayle-planar")]}),
    "robot-a-list": json.dumps({"motions": [_entry(robot=["bayle-planar"])]}),
    "parameters-a-list": json.dumps({"motions": [_entry(robot={"name": "x", "parameters": [0.5]})]}),
    "parameter-a-string": json.dumps(
        {"motions": [_entry(robot={"name": "x", "parameters": {"l1": "long"}})]}
    ),
    "parameter-null": json.dumps({"motions": [_entry(robot={"name": "x", "parameters": {"l1": None}})]}),
    "t-longer-than-q": json.dumps({"motions": [_entry(t=[0.0, 1.0, 2.0])]}),
    "t-2d": json.dumps({"motions": [_entry(t=[[0.0, 1.0]])]}),
    "q-1d": json.dumps({"motions": [_entry(q=[0.0, 1.0])]}),
    "no-samples": json.dumps({"motions": [_entry(t=[], q=[])]}),
    "q-ragged": json.dumps({"motions": [_entry(q=[[0.0, 1.0], [2.0]])]}),
    "q-string": json.dumps({"motions": [_entry(q=[[0.0, "a"], [2.0, 3.0]])]}),
    "t-scalar": json.dumps({"motions": [_entry(t=0.0, q=[[0.0]])]}),
    "deeply-nested": "[" * 100_000,
}
"""Contents of a trajectories file that is not one, by what is wrong with it."""


@pytest.mark.parametrize("content", list(MALFORMED.values()), ids=list(MALFORMED))
def test_read_of_a_malformed_file_is_one_input_error(tmp_path: Path, content: str):
    path = _write_raw(tmp_path, content)
    with pytest.raises(InputError) as info:
        trajectories.read(tmp_path)
    message = str(info.value)
    assert message.startswith(f"--results {path}: not a readable trajectories file (")
    assert "\n" not in message


def test_read_names_differing_sizes(tmp_path: Path):
    _write_raw(tmp_path, json.dumps({"motions": [_entry(t=[0.0])]}))
    with pytest.raises(InputError, match=r"\(t and q sizes differ\)$"):
        trajectories.read(tmp_path)


def test_read_of_a_file_without_motions(tmp_path: Path):
    path = _write_raw(tmp_path, json.dumps({"motions": []}))
    with pytest.raises(InputError) as info:
        trajectories.read(tmp_path)
    assert str(info.value) == f"--results {path}: holds no motion"


@pytest.mark.parametrize(
    ("content", "phrase"),
    [(b'{"motions": "\xff"}', "not UTF-8 text"), (b'{"motions"\0}', "binary content")],
    ids=["not-utf8", "binary"],
)
def test_read_of_a_file_that_is_not_text(tmp_path: Path, content: bytes, phrase: str):
    path = _write_raw(tmp_path, content)
    with pytest.raises(InputError) as info:
        trajectories.read(tmp_path)
    message = str(info.value)
    assert message.startswith(f"--results {path}: ")
    assert phrase in message
    assert message.count(str(path)) == 1


def test_read_takes_defaults_for_absent_parameters_and_factory(tmp_path: Path):
    _write_raw(tmp_path, json.dumps({"motions": [_entry(robot={"name": "bayle-rrp"})]}))
    (motion,) = trajectories.read(tmp_path)
    assert motion.robot_name == "bayle-rrp"
    assert motion.parameters == ()
    assert motion.factory == ""
    assert motion.describes(robots.bayle_rrp())
