"""`mobman sweep` (mobman.cli.sweep): the grid from --vary, the ranking as JSON and as a table, the mount of a
robot read from a URDF file, a store resumed, exit status 3 when no design can be built, one line and exit
status 2 for bad options."""

from __future__ import annotations

import json

import numpy as np
import pytest

from mobman.cli.sweep import parse_values
from mobman.errors import InputError
from mobman.io.urdf import write_urdf
from mobman.model.robots import build


def test_vary_takes_a_range_or_a_list():
    name, values = parse_values("l1=0.3:0.7:5")
    assert name == "l1"
    np.testing.assert_allclose(values, [0.3, 0.4, 0.5, 0.6, 0.7])
    assert parse_values(" l2 = 0.5, pi/8 ")[1].tolist() == [0.5, np.pi / 8]
    for item, message in [
        ("l1", "expected NAME=START:STOP:COUNT"),
        ("l1=1:2", "expected START:STOP:COUNT"),
        ("l1=1:2:0", "COUNT must be an integer from 1"),
        ("l1=1:2:x", "COUNT must be an integer from 1"),
        ("l1=a:2:3", "--vary l1"),
    ]:
        with pytest.raises(InputError, match=message):
            parse_values(item)


def test_the_json_report_ranks_the_designs_by_coverage(cli_run):
    code, out, err = cli_run(
        ["sweep", "bayle-planar", "--vary", "l1=0.3,0.7", "--param", "l2=0.5", "--samples", "500"]
        + ["--bounds", "-1,1,-1,1,0,0", "--step", "0.2", "--json"]
    )
    assert code == 0, err
    report = json.loads(out)
    assert report["designs"] == 2 and report["failed"] == 0 and report["rank_by"] == "coverage"
    first, second = report["ranking"]
    assert first["design"] == {"l1": 0.7, "l2": 0.5} and second["design"] == {"l1": 0.3, "l2": 0.5}
    assert first["metrics"]["reach"] == pytest.approx(1.2) and second["metrics"]["reach"] == pytest.approx(
        0.8
    )
    assert first["metrics"]["coverage"] > second["metrics"]["coverage"] > 0


def test_the_mount_of_a_robot_read_from_a_urdf_file(cli_run, tmp_path):
    path = tmp_path / "planar.urdf"
    write_urdf(build("bayle-planar"), path)
    args = ["sweep", str(path), "--tip", "tool_link", "--samples", "100"]
    code, out, err = cli_run([*args, "--vary", "mount.x=0:0.4:3", "--param", "mount.y=0.1", "--json"])
    assert code == 0, err
    report = json.loads(out)
    assert report["robot"] == str(path) and report["fixed"] == {"mount.y": 0.1}
    # the arm's measures do not move with its mount: the ranking keeps the grid's order; the reach grows
    assert [entry["design"]["mount.x"] for entry in report["ranking"]] == [0.0, 0.2, 0.4]
    reach = [entry["metrics"]["reach"] for entry in report["ranking"]]
    np.testing.assert_allclose(reach, np.hypot([0.0, 0.2, 0.4], 0.1) + 1.0, rtol=1e-12)
    for option, message in [
        (
            ["--vary", "l1=1,2"],
            "--vary: the given robot 'bayle-planar' has no parameter 'l1'; its parameters: mount.x",
        ),
        (
            ["--vary", "mount.x=0", "--param", "l1=2"],
            "--param: the given robot 'bayle-planar' has no parameter",
        ),
    ]:
        code, out, err = cli_run([*args, *option])
        assert code == 2 and message in err and err.count("\n") == 1 and out == ""


def test_the_table_and_a_store_resumed(cli_run, tmp_path, monkeypatch):
    monkeypatch.setenv("COLUMNS", "200")
    store = tmp_path / "sweep.zarr"
    args = ["sweep", "bayle-planar", "--vary", "l1=0.3:0.5:2", "--samples", "300", "--store", str(store)]
    code, out, err = cli_run([*args, "--quiet"])
    assert code == 0, err
    assert "2 of 2 designs computed" in out and "best by mean" in out and f"store: {store}" in out
    code, again, _ = cli_run([*args, "--quiet"])
    assert code == 0 and again == out
    code, _, err = cli_run([*args[:-2], "--samples", "400", "--store", str(store)])
    assert code == 2 and "samples: 400 asked, 300 in the store" in err and err.count("\n") == 1


def test_no_design_built_is_exit_status_3(cli_run):
    code, out, err = cli_run(["sweep", "bayle-planar", "--vary", "l1=0,-1", "--samples", "10", "--json"])
    assert code == 3
    report = json.loads(out)
    assert (
        report["failed"] == 2
        and "l1 (a length) must be a finite number > 0" in report["failures"][0]["reason"]
    )
    assert "none of the 2 designs could be built" in err


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--vary", "l3=1,2"], "--vary: robot bayle-planar has no parameter 'l3'"),
        (["--vary", "l1=1,2", "--vary", "l1=3"], "--vary: a parameter is given twice"),
        (["--vary", "l1=1", "--param", "l1=2"], "--vary: l1 is both varied and fixed"),
        (["--vary", "l1=1", "--param", "x=2"], "--param: robot bayle-planar has no parameter 'x'"),
        (["--vary", "l1=1", "--samples", "0"], "--samples must be an integer ≥ 1"),
        (["--vary", "l1=1", "--step", "0.1"], "bounds and step go together"),
        (["--vary", "l1=1", "--samples", "10", "--rank-by", "w"], "--rank-by: metric must be one of mean"),
        (["--vary", "l1=1", "--top", "0"], "--top must be ≥ 1"),
        (
            ["--vary", "mount.z=1", "--tip", "hand"],
            "--tip: for a URDF file (a path ending in .urdf), not robot",
        ),
    ],
)
def test_bad_options_are_one_line_and_exit_status_2(cli_run, args, message):
    code, out, err = cli_run(["sweep", "bayle-planar", *args])
    assert code == 2, err
    assert message in err and err.count("\n") == 1 and out == ""
