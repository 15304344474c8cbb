"""`mobman robots` (mobman.cli.robots): the built-in robots as a table and as JSON, and the mount's parameters
every robot takes."""

import json

from mobman.cli import main
from mobman.model import robots


def test_robots_json_lists_every_builtin_robot_with_its_defaults(capsys):
    main(["robots", "--json"])
    report = json.loads(capsys.readouterr().out)
    assert report["every_robot"] == [
        "mount.x",
        "mount.y",
        "mount.z",
        "mount.yaw",
        "mount.pitch",
        "mount.roll",
    ]
    entries = {e["name"]: e for e in report["robots"]}
    assert set(entries) == set(robots.ROBOTS)
    assert entries["korayem-planar"]["parameters"] == {"l0": 0.4, "l1": 0.5, "l2": 0.5}
    assert entries["tchon-car-rtr"]["coordinates"] == list(robots.tchon_car_rtr().coordinate_names)


def test_robots_table(capsys, monkeypatch):
    monkeypatch.setenv("COLUMNS", "300")  # wide enough that rich does not fold the names
    main(["robots"])
    out = capsys.readouterr().out
    assert all(name in out for name in robots.ROBOTS)
    assert "also takes --param mount.x, mount.y, mount.z, mount.yaw, mount.pitch, mount.roll" in out


def test_robots_table_at_80_columns_keeps_every_name_whole(capsys, monkeypatch):
    monkeypatch.setenv("COLUMNS", "80")
    main(["robots"])
    lines = capsys.readouterr().out.splitlines()
    assert max(len(line) for line in lines) <= 80
    names = {line.split("│")[1].strip() for line in lines if line.startswith("│")} - {""}
    assert names == set(robots.ROBOTS)  # each name whole on its row's first line, none split
