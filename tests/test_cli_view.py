"""``mobman view``: one-line errors with exit status 2, and ``--screenshot`` rendered by headless chromium.

Screenshots go to the ``artifacts`` folder (conftest.py).
"""

from __future__ import annotations

import socket
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from mobman.cli import main
from mobman.io import trajectories
from mobman.model import robots


def _run(args, capsys):
    with pytest.raises(SystemExit) as info:
        main(args)
    return info.value.code, capsys.readouterr().err


def _motion_folder(path: Path, robot) -> Path:
    t = np.linspace(0.0, 1.0, 5)
    trajectories.write(path, [trajectories.Motion.of("line", robot, t, np.zeros((5, robot.n_q)))])
    return path


def test_unknown_robot(capsys):
    code, err = _run(["view", "no-such-robot"], capsys)
    assert code == 2 and "unknown robot 'no-such-robot'" in err and len(err.strip().splitlines()) == 1


def test_configuration_of_the_wrong_size(capsys):
    code, err = _run(["view", "bayle-rrp", "--q", "0,0,0", "--port", "0"], capsys)
    assert code == 2 and "--q: expected 6 values, got 3" in err and len(err.strip().splitlines()) == 1


def test_results_of_another_robot_name_it(tmp_path, capsys):
    folder = _motion_folder(tmp_path / "run", robots.korayem_planar(l1=0.7))
    code, err = _run(["view", "bayle-rrp", "--results", str(folder), "--port", "0"], capsys)
    assert code == 2 and len(err.strip().splitlines()) == 1
    assert "korayem-planar (l0=0.4, l1=0.7, l2=0.5)" in err and "not of bayle-rrp" in err


def test_missing_results(tmp_path, capsys):
    code, err = _run(["view", "bayle-rrp", "--results", str(tmp_path), "--port", "0"], capsys)
    assert code == 2 and "no trajectories.json" in err


def test_port_in_use_says_so_and_suggests_another(capsys):
    with socket.socket() as busy:
        busy.bind(("127.0.0.1", 0))
        busy.listen()
        port = busy.getsockname()[1]
        code, err = _run(["view", "bayle-rrp", "--port", str(port)], capsys)
    assert code == 2 and len(err.strip().splitlines()) == 1
    assert f"--port {port}: already in use on 127.0.0.1" in err
    suggested = int(err.rsplit("--port", 1)[1].split()[0])
    assert suggested != port


def test_screenshot_of_a_paper_robot(artifacts, robot_pixels, capsys):
    png = artifacts / "view_bayle-rrp.png"
    main(["view", "bayle-rrp", "--q", "0.2,0.1,pi/6,pi/3,pi/4,0.6", "--port", "0", "--screenshot", str(png)])
    assert f"screenshot: {png}" in capsys.readouterr().out
    assert Image.open(png).size == (1280, 800)
    assert robot_pixels(png.read_bytes()).sum() > 300  # the links are drawn


def test_screenshot_of_tiago_draws_its_meshes(artifacts, robot_pixels, capsys):
    """TIAGo from its URDF: the meshes' dark arm and hand and the base's orange ring are drawn (the scene left
    of the side panel; an empty scene has neither)."""
    png = artifacts / "view_tiago.png"
    main(["view", "tiago", "--port", "0", "--screenshot", str(png)])
    assert f"screenshot: {png}" in capsys.readouterr().out
    scene = np.asarray(Image.open(png).convert("RGB"), dtype=float)[:, :900]
    assert (scene.max(axis=-1) < 60).sum() > 1000  # the black arm links and hand
    assert robot_pixels(png.read_bytes())[:, :900].sum() > 300  # the orange ring of the PMB2 base


def test_serves_on_loopback_and_prints_its_url(monkeypatch, capsys):
    import urllib.request

    import mobman.cli.view as view

    seen = []

    def stop(_seconds):  # instead of waiting for Ctrl-C: fetch the page, then interrupt
        url = capsys.readouterr().out.split(" at ")[1].split()[0]
        seen.append((url, urllib.request.urlopen(url, timeout=10).status))
        raise KeyboardInterrupt

    monkeypatch.setattr(view.time, "sleep", stop)
    main(["view", "bayle-rrp", "--port", "0"])
    ((url, status),) = seen
    assert url.startswith("http://127.0.0.1:") and status == 200
