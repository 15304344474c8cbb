"""The ``mobman`` command itself: help, ``mobman robots``, ``mobman reproduce`` (registry, index, errors)."""

import json
from types import SimpleNamespace

import pytest

from mobman.cli import main
from mobman.experiments import REPRODUCTIONS
from mobman.experiments.report import Reproduction
from mobman.model import robots


def test_robots_json_lists_every_builtin_robot_with_its_defaults(capsys):
    main(["robots", "--json"])
    entries = {e["name"]: e for e in json.loads(capsys.readouterr().out)["robots"]}
    assert set(entries) == set(robots.ROBOTS)
    assert entries["korayem-planar"]["parameters"] == {"l0": 0.4, "l1": 0.5, "l2": 0.5}
    assert entries["tchon-car-rtr"]["coordinates"] == list(robots.tchon_car_rtr().coordinate_names)


def test_robots_table(capsys, monkeypatch):
    monkeypatch.setenv("COLUMNS", "300")  # wide enough that rich does not fold the names
    main(["robots"])
    out = capsys.readouterr().out
    assert all(name in out for name in robots.ROBOTS)


def test_every_registered_reproduction_module_exists():
    from mobman.experiments import module

    for name in REPRODUCTIONS:
        mod = module(name)
        assert callable(mod.run) and isinstance(mod.TITLE, str), name


def test_reproduce_all_writes_each_result_and_an_index(tmp_path, monkeypatch, capsys):
    ran = []

    def fake(name):
        def run(out, quick=False):
            ran.append((name, quick))
            return Reproduction(name, f"title of {name}", {"name": name}, "report text")

        return SimpleNamespace(run=run)

    monkeypatch.setattr("mobman.cli.reproduce.module", fake)
    main(["reproduce", "all", "--out", str(tmp_path), "--quick"])
    assert ran == [(name, True) for name in REPRODUCTIONS]
    for name in REPRODUCTIONS:
        assert json.loads((tmp_path / name / "results.json").read_text()) == {"name": name}
        assert (tmp_path / name / "report.md").read_text().startswith(f"# title of {name}")
    index = (tmp_path / "index.md").read_text()
    assert all(f"[{name}]({name}/report.md)" in index for name in REPRODUCTIONS)


@pytest.mark.parametrize(
    ("argv", "needle"),
    [
        (["reproduce", "no-such-paper"], "unknown reproduction"),
        (["analyze"], "ROBOT"),
        (["no-such-command"], ""),
    ],
)
def test_bad_usage_is_one_line_and_exit_status_2(argv, needle, capsys):
    with pytest.raises(SystemExit) as exc:
        main(argv)
    assert exc.value.code == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("error:") and len(err.splitlines()) == 1 and needle in err


def test_help_lists_the_commands(capsys):
    try:
        main(["--help"])
    except SystemExit as exc:  # depending on the CLI library's version, help may exit with status 0
        assert exc.code == 0
    assert "reproduce" in capsys.readouterr().out
