"""`mobman map` (mobman.cli.maps): the map as JSON and as a table, the annulus moved with the arm's mount, its
figure, a store resumed, exit status 3 when no cell is reached, one line and exit status 2 for bad options."""

from __future__ import annotations

import json

import numpy as np
import pytest

PLANE = ["--bounds", "-1.2,1.2,-1.2,1.2,0,0", "--step", "0.2", "--param", "l1=0.7", "--param", "l2=0.4"]


def test_the_json_report_counts_the_annulus_and_names_the_best_cell(cli_run):
    code, out, err = cli_run(
        ["map", "bayle-planar", *PLANE, "--no-collision", "--json"]
    )  # the kinematic annulus
    assert code == 0, err
    report = json.loads(out)
    x = np.linspace(-1.2, 1.2, 13)
    d = np.hypot(*np.meshgrid(x, x))
    annulus = int(((d >= 0.3 - 1e-9) & (d <= 1.1 + 1e-9)).sum())
    assert report["shape"] == [13, 13, 1] and report["cells"] == 169
    assert report["reached"] == annulus and report["computed"] == 169
    assert report["fraction"] == pytest.approx(annulus / 169)
    best = report["best"]
    assert np.linalg.norm(best["centre"]) == pytest.approx(np.sqrt(0.7**2 + 0.4**2), abs=0.15)
    assert best["score"] == pytest.approx(0.7 * 0.4 * abs(np.sin(best["q"][1])), abs=1e-12)
    assert report["layers"] == [{"z": 0.0, "reached": annulus}]


def test_the_annulus_moves_with_the_arm_s_mount(cli_run):
    code, out, err = cli_run(
        ["map", "bayle-planar", *PLANE, "--param", "mount.x=0.4", "--no-collision", "--json"]
    )
    assert code == 0, err
    x = np.linspace(-1.2, 1.2, 13)
    d = np.hypot(*np.meshgrid(x - 0.4, x))
    assert json.loads(out)["reached"] == int(((d >= 0.3 - 1e-9) & (d <= 1.1 + 1e-9)).sum())


def test_the_table_the_figure_and_a_store_resumed(cli_run, tmp_path, monkeypatch):
    monkeypatch.setenv("COLUMNS", "200")
    store, figure = tmp_path / "map.zarr", tmp_path / "map.png"
    args = ["map", "bayle-planar", *PLANE, "--store", str(store), "--chunk", "50", "--quiet"]
    code, out, err = cli_run([*args, "--figure", str(figure)])
    assert code == 0, err
    assert "cells reached" in out and "best cell" in out and f"store: {store}" in out
    assert figure.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    code, again, err = cli_run(args)  # read back, nothing computed again
    assert code == 0, err
    assert again.splitlines()[0] == out.splitlines()[0]
    code, _, err = cli_run(["map", "bayle-planar", *PLANE[:2], "--step", "0.1", "--store", str(store)])
    assert code == 2 and err.count("\n") == 1
    assert "--store" in err and "holds another study" in err


def test_no_cell_reached_is_exit_status_3(cli_run):
    code, out, err = cli_run(["map", "bayle-planar", "--bounds", "3,4,3,4,0,0", "--step", "0.5", "--json"])
    assert code == 3
    assert json.loads(out)["reached"] == 0 and "no cell of the 9 is reached" in err


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--step", "0"], "--step must be a finite distance > 0"),
        (["--bounds", "1,2,3"], "--bounds: expected 6 values, got 3"),
        (["--bounds", "1,0,0,1,0,1"], "--bounds: x_min 1 is above x_max 0"),
        (["--starts", "0"], "--starts must be an integer ≥ 1"),
        (["--measure", "volume"], "--measure must be one of"),
        (["--level", "x"], "--level must be one of arm, system"),
        (["--arm", "2"], "--arm must be an integer from 0 to 0"),
        (["--chunk", "0"], "--chunk must be an integer ≥ 1"),
        (["--scheduler", "lokal", "--step", "0.5"], "--scheduler must be 'local'"),
        (["--figure", "map.jpg"], "--figure must name a .png file"),
    ],
)
def test_bad_options_are_one_line_and_exit_status_2(cli_run, args, message):
    code, out, err = cli_run(["map", "bayle-planar", *args])
    assert code == 2, err
    assert message in err and err.count("\n") == 1 and out == ""


def test_ctrl_c_keeps_the_store_s_chunks_says_so_and_the_same_command_resumes(cli_run, tmp_path, monkeypatch):
    from mobman.studies import maps

    store = tmp_path / "map.zarr"
    args = ["map", "bayle-planar", *PLANE, "--store", str(store), "--chunk", "50", "--json"]
    cells = maps._cells

    def stopped_at_the_third_chunk(*arguments):
        if arguments[-2] == 100:
            raise KeyboardInterrupt
        return cells(*arguments)

    monkeypatch.setattr(maps, "_cells", stopped_at_the_third_chunk)
    code, out, err = cli_run(args)
    assert code == 130 and out == ""
    assert err.strip() == (
        f"interrupted: mobman map stopped; {store} keeps 100 of 169 rows: run the same command again to resume"
    )
    monkeypatch.setattr(maps, "_cells", cells)
    code, out, err = cli_run(args)
    assert code == 0, err
    assert json.loads(out)["computed"] == 169


def test_ctrl_c_without_a_store_removes_everything(cli_run, monkeypatch):
    from mobman.studies import maps

    def stopped(*arguments):
        raise KeyboardInterrupt

    monkeypatch.setattr(maps, "_cells", stopped)
    code, out, err = cli_run(["map", "bayle-planar", *PLANE])
    assert code == 130 and err.strip() == "interrupted: mobman map stopped; partial output removed"
