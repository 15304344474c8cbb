"""`mobman place` (mobman.cli.place): the ranked placements as JSON and as a table, exit status 3 when no base
reaches the target, one line and exit status 2 for bad options."""

from __future__ import annotations

import json

import numpy as np
import pytest
from lift_robot import HIGHEST, LOWEST, lift_file

from mobman import kinematics as K
from mobman.cli import main
from mobman.model import robots


def _run(args: list[str], capsys) -> tuple[int, str, str]:
    try:
        main(args)
        code = 0
    except SystemExit as exc:
        code = int(exc.code or 0)
    out = capsys.readouterr()
    return code, out.out, out.err


GRID = ["--radii", "0.4,0.7", "--bearings", "2", "--headings", "4", "--starts", "3"]


def test_tiago_json_ranks_bases_that_reach_the_target(capsys):
    code, out, err = _run(["place", "tiago", "--target", "1,0.5,0.8", *GRID, "--top", "3", "--json"], capsys)
    assert code == 0, err
    report = json.loads(out)
    assert report["candidates"] == 16 and report["reached"] >= 3
    assert report["task"] == ["x_ee", "y_ee", "z_ee"]
    ranking = report["ranking"]
    assert len(ranking) == 3 and ranking[0] == report["best"]
    assert [e["score"] for e in ranking] == sorted((e["score"] for e in ranking), reverse=True)
    q = np.array([e["q"] for e in ranking])
    np.testing.assert_allclose(q[:, :3], [e["base"] for e in ranking])
    tool = np.asarray(K.forward(robots.build("tiago"), q))
    assert np.abs(tool - [1.0, 0.5, 0.8]).max() <= 1e-6


def test_the_table_names_the_reached_count(capsys, monkeypatch):
    monkeypatch.setenv("COLUMNS", "200")
    code, out, _ = _run(["place", "tiago", "--target", "1,0.5,0.8", *GRID], capsys)
    assert code == 0
    assert "bases reach" in out and "of 16" in out and "yoshikawa" in out


def test_no_base_reaching_the_target_exits_3_with_the_candidates_reported(capsys):
    # Bayle's planar robot with its heading task: a parked platform leaves the 2R arm two joints for three
    # coordinates, so the grid's bases miss the target
    args = ["place", "bayle-planar", "--target", "0.5,0.5,0.3", "--radii", "0.5", "--bearings", "3"]
    code, out, err = _run([*args, "--headings", "3", "--starts", "1", "--json"], capsys)
    assert code == 3
    assert json.loads(out)["best"] is None and json.loads(out)["reached"] == 0
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(
        "warning: mobman place: no base of the 9 reaches the target"
    )


@pytest.mark.parametrize(
    "target, radii, why",
    [
        # the lift robot (tests/lift_robot.py): the tool at the heights 0.5 to 1.1 m, 0.5 m from the lift
        ("1,0.5,1.5", "0.4,0.7", f"the target's height 1.5 m is {1.5 - HIGHEST:.3g} m above the highest point "
         f"the tool reaches ({HIGHEST:.4g} m, with any posture within the joint limits)"),
        ("1,0.5,0.2", "0.4,0.7", f"the target's height 0.2 m is {LOWEST - 0.2:.3g} m below the lowest point "
         f"the tool reaches ({LOWEST:.4g} m, with any posture within the joint limits)"),
        ("1,0.5,0.8", "3,4", "every base lies 3 m or more from the target, farther than the arm reaches ("),
    ],
)  # fmt: skip
def test_a_target_beyond_the_robot_s_reach_is_said_with_its_numbers(tmp_path, capsys, target, radii, why):
    args = ["place", str(lift_file(tmp_path)), "--target", target, "--radii", radii, "--bearings", "2"]
    code, out, err = _run([*args, "--headings", "4", "--starts", "2", "--json"], capsys)
    (line,) = err.strip().splitlines()
    assert code == 3 and json.loads(out)["reached"] == 0
    assert line.startswith("warning: mobman place: no base of the 16 reaches the target (closest error ")
    assert f"): {why}" in line and "try" not in line


def test_targets_repeated_are_reached_from_one_base(capsys):
    targets = np.array([[1.0, 0.5, 0.8], [1.1, 0.2, 0.9]])
    args = ["place", "tiago", *(a for t in targets for a in ("--target", ",".join(map(str, t)))), *GRID]
    code, out, err = _run([*args, "--top", "3", "--json"], capsys)
    assert code == 0, err
    report = json.loads(out)
    np.testing.assert_array_equal(report["target"], targets)
    q = np.array([e["q"] for e in report["ranking"]])  # (ranked, 2 targets, n_q)
    assert q.shape[1] == 2 and report["reached"] >= len(q) > 0
    np.testing.assert_array_equal(q[:, 0, :3], q[:, 1, :3])  # one base for both
    for k in range(2):
        tool = np.asarray(K.forward(robots.build("tiago"), q[:, k]))
        assert np.abs(tool - targets[k]).max() <= 1e-6
    assert [e["score"] for e in report["ranking"]] == sorted(
        (e["score"] for e in report["ranking"]), reverse=True
    )
    code, _, err = _run(
        ["place", "bayle-planar", "--target", "0,0,0", "--target", "1,0,0", "--map", "m.zarr"], capsys
    )
    assert code == 2 and "--map: one --target" in err and err.count("\n") == 1


def test_keep_out_regions_leave_out_the_bases_whose_platform_would_overlap_them(capsys):
    table = [0.7, 1.6, 0.0, 1.2]
    args = ["place", "tiago", "--target", "1,0.5,0.8", *GRID, "--top", "20", "--json"]
    code, out, err = _run([*args, "--keep-out", ",".join(map(str, table))], capsys)
    assert code == 0, err
    report = json.loads(out)
    radius = report["footprint"]["radius"]
    assert radius == pytest.approx(0.27, abs=0.005)  # TIAGo's base, 54 cm across
    assert 0 < report["blocked"] < report["candidates"] == 16
    for entry in report["ranking"]:  # TIAGo's disc is centred on its platform's origin (within 5 mm)
        x, y, _ = entry["base"]
        gap = np.hypot(max(table[0] - x, 0, x - table[1]), max(table[2] - y, 0, y - table[3]))
        assert gap >= radius - 0.005
    code, out, err = _run([*args, "--keep-out", "-5,5,-5,5", "--footprint", "0.1"], capsys)
    assert code == 3 and json.loads(out)["blocked"] == 16
    assert err.strip() == "warning: mobman place: every base of the 16 is blocked by --keep-out"


@pytest.mark.parametrize(
    ("options", "field"),
    [
        (["--target", "1,0.5"], "--target"),
        (["--target", "1,0.5,0.8", "--bearings", "0"], "--bearings must be an integer ≥ 1, got 0"),
        (["--target", "1,0.5,0.8", "--headings", "0"], "--headings must be an integer ≥ 1"),
        (["--target", "1,0.5,0.8", "--starts", "0"], "--starts must be an integer ≥ 1"),
        (["--target", "1,0.5,0.8", "--iterations", "0"], "--iterations must be an integer ≥ 1"),
        (["--target", "1,0.5,0.8", "--tolerance", "0"], "--tolerance must be a number > 0 and ≤ 0.1"),
        (
            ["--target", "1,0.5,0.8", "--radii", "0.5,-1"],
            "--radii must be one or more finite distances ≥ 0 (m), got 0.5, -1",
        ),
        (["--target", "1,0.5,0.8", "--measure", "volume"], "--measure must be one of"),
        (["--target", "1,0.5,0.8", "--level", "wheels"], "--level must be one of"),
        (["--target", "1,0.5,0.8", "--top", "0"], "--top"),
        (["--target", "1,0.5,0.8", "--centre", "1"], "--centre"),
        (["--target", "1,0.5,0.8", "--keep-out", "1,2,3"], "--keep-out: expected 4 values, got 3"),
        (["--target", "1,0.5,0.8", "--footprint", "0.3"], "--footprint: give it with --keep-out"),
        (
            ["--target", "1,0.5,0.8", "--keep-out", "2,1,0,1"],
            "--keep-out must have x_min < x_max and y_min < y_max (x_min, x_max, y_min, y_max), got 2, 1, 0, 1",
        ),
        (
            ["--target", "1,0.5,0.8", "--keep-out", "0,1,0,1", "--footprint", "0"],
            "--footprint radius must be > 0",
        ),
        (
            ["--target", "1,0.5,0.8", "--keep-out", "0,1,0,1", "--footprint", "1,2"],
            "--footprint must be a radius",
        ),
    ],
)
def test_bad_options_are_one_line_and_exit_2(capsys, options, field):
    code, _, err = _run(["place", "tiago", *options], capsys)
    lines = err.strip().splitlines()
    assert code == 2 and len(lines) == 1 and field in lines[0] and lines[0].startswith("error:")


def test_a_map_s_cells_are_the_candidates(tmp_path, capsys):
    store = tmp_path / "map.zarr"
    code, _, err = _run(["map", "bayle-planar", "--step", "0.2", "--store", str(store), "--quiet"], capsys)
    assert code == 0, err
    code, out, err = _run(
        ["place", "bayle-planar", "--target", "0.3,-0.4,0", "--map", str(store), "--json"], capsys
    )
    assert code == 0, err
    report = json.loads(out)
    assert report["task"] == ["x_ee", "y_ee", "z_ee"] and report["reached"] == report["candidates"] > 0
    assert report["best"]["score"] == pytest.approx(0.25, abs=0.02)  # l1 l2 at the elbow's right angle
    for args, message in [
        (["--target", "0.3,-0.4,0", "--radii", "1"], "--map: --radii do not apply with a map"),
        (["--target", "0.3,-0.4"], "--target: expected 3 values, got 2"),
        (["--target", "0.3,-0.4,0", "--param", "l1=0.6"], "--map: the map was computed for another robot"),
    ]:
        base = ["place", "bayle-planar", "--map", str(store)]
        code, out, err = _run([*base, *args], capsys)
        assert code == 2 and message in err and err.count("\n") == 1, err
    code, _, err = _run(["place", "bayle-planar", "--target", "0.3,-0.4,2", "--map", str(store)], capsys)
    assert (
        code == 3 and "no reached cell of the map lies within half a step of the target's height 2 m" in err
    )
    # the planar arm works in its plane z = 0: its cells and its tool stay there
    assert "(its reached cells lie at 0–0 m; 2 m above the highest point the tool reaches, 0 m)" in err


@pytest.mark.parametrize(
    ("text", "field"),
    [
        ('[[obstacle]]\nname = "table"\nshape = "cube"\nsize = [1.0]\n', "shape must be one of"),
        ('[[obstacle]]\nname = "table"\nshape = "box"\nsize = [1.0, -1.0, 1.0]\n', "size[1] (y) must be > 0"),
        (
            '[[obstacle]]\nname = "table"\nshape = "box"\nsize = [1, 1, 1]\nposition = [0, nan, 0]\n',
            "position",
        ),
        ('[[obstacle]]\nname = "table"\nshap = "box"\n', "unknown key 'shap'"),
    ],
)
def test_a_bad_scene_is_one_line_and_exit_2(tmp_path, capsys, text, field):
    path = tmp_path / "scene.toml"
    path.write_text(text)
    for command in (["place", "tiago", "--target", "1,0,0.8"], ["map", "tiago"]):
        code, _, err = _run([*command, "--scene", str(path)], capsys)
        lines = err.strip().splitlines()
        assert code == 2 and len(lines) == 1 and field in lines[0] and "table" in lines[0], lines
    code, _, err = _run(
        ["place", "tiago", "--target", "1,0,0.8", "--scene", str(tmp_path / "none.toml")], capsys
    )
    assert code == 2 and len(err.strip().splitlines()) == 1 and "none.toml" in err


def test_a_scene_s_table_keeps_the_platform_and_the_arm_off(tmp_path, capsys):
    path = tmp_path / "scene.toml"
    path.write_text(
        '[[obstacle]]\nname = "table"\nshape = "box"\nsize = [0.6, 1.0, 0.75]\nposition = [1.2, 0, 0.375]\n'
    )
    args = [
        "place",
        "tiago",
        "--target",
        "0.95,0,0.9",
        "--radii",
        "0.5,1.2",
        "--bearings",
        "4",
        "--headings",
        "4",
    ]
    code, out, err = _run([*args, "--starts", "8", "--scene", str(path), "--json"], capsys)
    report = json.loads(out)
    assert code == 0, err
    assert report["collision"]["obstacles"] == ["table"] and report["collision"]["tolerance"] == 0.1
    assert report["blocked"] >= 1 and report["colliding"] >= 1 and report["reached"] >= 1
    assert report["reached"] + report["blocked"] + report["colliding"] <= report["candidates"]
