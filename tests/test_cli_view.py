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


def test_urdf_options_for_a_results_folder_are_refused(tmp_path, capsys):
    folder = _motion_folder(tmp_path / "run", robots.bayle_rrp())
    code, err = _run(["view", str(folder), "--tip", "tool_link", "--port", "0"], capsys)
    assert code == 2 and len(err.strip().splitlines()) == 1
    assert "--tip: for a URDF file (a path ending in .urdf), not a results folder" in err


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


def _time_wait_port() -> int:
    """A loopback port whose only socket waits in TIME_WAIT, as a viewer's port does once a browser's
    connection to it has closed: a listener bound as servers bind (SO_REUSEADDR) accepts a connection and
    closes its end first."""
    with socket.socket() as listener:
        listener.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        listener.bind(("127.0.0.1", 0))
        listener.listen()
        port = listener.getsockname()[1]
        with socket.create_connection(("127.0.0.1", port)) as client:
            accepted, _ = listener.accept()
            accepted.close()  # the accepting side closes first: its socket goes to TIME_WAIT
            client.recv(1)  # the server's FIN has arrived
    with socket.socket() as plain, pytest.raises(OSError):
        plain.bind(("127.0.0.1", port))  # a bind without SO_REUSEADDR is refused: the port is in TIME_WAIT
    return port


def test_a_port_in_time_wait_is_served(monkeypatch, capsys):
    """The port check binds as the server does (SO_REUSEADDR), so it lets the server take a port that only
    TIME_WAIT connections hold, such as the one the previous view just served."""
    import mobman.cli.view as view

    port = _time_wait_port()

    def stop(_seconds):
        raise KeyboardInterrupt

    monkeypatch.setattr(view, "sleep", stop)  # the view's wait only: the server's threads sleep too
    main(["view", "bayle-rrp", "--port", str(port)])
    assert f"at http://127.0.0.1:{port}" in capsys.readouterr().out


def test_two_screenshots_in_a_row_take_any_free_port(artifacts, robot_pixels, monkeypatch, capsys):
    """Without --port a screenshot serves on a free port, not the interactive view's default, which may be
    taken (here: held by another listener)."""
    import mobman.cli.view as view

    with socket.socket() as busy:
        busy.bind(("127.0.0.1", 0))
        busy.listen()
        monkeypatch.setattr(view, "DEFAULT_PORT", busy.getsockname()[1])
        for k in range(2):
            png = artifacts / f"view_bayle-rrp_{k}.png"
            main(["view", "bayle-rrp", "--q", "0.2,0.1,pi/6,pi/3,pi/4,0.6", "--screenshot", str(png)])
            assert f"screenshot: {png}" in capsys.readouterr().out
            assert robot_pixels(png.read_bytes()).sum() > 300


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

    monkeypatch.setattr(view, "sleep", stop)
    main(["view", "bayle-rrp", "--port", "0"])
    ((url, status),) = seen
    assert url.startswith("http://127.0.0.1:") and status == 200


def _shape(wxyz, scale) -> np.ndarray:
    """R diag(s²) Rᵀ of a drawn ellipsoid node (independent of the signs and order of its axes)."""
    import viser.transforms as vtf

    r = vtf.SO3(np.asarray(wxyz)).as_matrix()
    return r @ np.diag(np.asarray(scale) ** 2) @ r.T


def test_tiago_dynamic_ellipsoid_is_the_one_of_its_urdf_inertials_and_effort_limits(monkeypatch, capsys):
    """`mobman view tiago --dynamic --q …`: the red node is the ellipsoid of the tool's accelerations at rest from
    TIAGo's URDF inertials and effort limits (mobman.dynamics, checked there against Pinocchio), drawn at the
    tool shifted by its centre (gravity) in the drawing's scale."""
    import mobman.cli.view as view
    import mobman.viz.viewer as viewer_module
    from mobman.dynamics import DynamicModel
    from mobman.dynamics.ellipsoids import dynamic_ellipsoid
    from mobman.io.real_robots import urdf_model
    from mobman.model.tasks import Position

    served = []

    class Recorder(viewer_module.Viewer):
        def __init__(self, *args, **kwargs):
            super().__init__(*args, **kwargs)
            served.append(self)

    def stop(_seconds):
        raise KeyboardInterrupt

    monkeypatch.setattr(viewer_module, "Viewer", Recorder)
    monkeypatch.setattr(view, "sleep", stop)
    # heading exactly π/2, arm_1 at π/2, arm_4 at its lower limit (q = x, y, θ, torso, arm_1 … arm_7)
    q = np.array([0.4, -0.2, np.pi / 2, 0.2, np.pi / 2, -1.2, -2.0, -0.32, 1.0, -1.0, 0.5])
    main(["view", "tiago", "--dynamic", "--q", ",".join(repr(float(v)) for v in q), "--port", "0"])
    assert "mobman view: tiago at http://127.0.0.1:" in capsys.readouterr().out
    (v,) = served
    assert {"/ellipsoid", "/ellipsoid_dynamic"} <= set(v.nodes)
    model = urdf_model("tiago")
    # a block of the viewer's size: the dynamics compiled for the viewer serve here too
    block = np.broadcast_to(q, (viewer_module.CHUNK, q.size))
    e = dynamic_ellipsoid(DynamicModel.from_urdf(model), block, model.torque_limits(), task=Position("xyz"))
    axes, directions, centre = e.axes[0], e.directions[0], np.asarray(e.center)[0]
    np.testing.assert_allclose(v.snapshot.dynamic[1][0, 0], axes, rtol=1e-9)
    node = v.nodes["/ellipsoid_dynamic"]
    factor = max(node.scale) / axes[0]
    shape = directions @ np.diag(axes**2) @ directions.T
    np.testing.assert_allclose(
        _shape(node.wxyz, node.scale), factor**2 * shape, atol=1e-9 * factor**2 * shape.max()
    )
    tool = np.asarray(v.nodes["/robot/arm_tool_link/tool"].position)
    np.testing.assert_allclose(node.position, tool + factor * centre, atol=1e-9)


@pytest.mark.parametrize(
    ("robot", "message"),
    [
        ("stretch", "--dynamic: stretch: the URDF gives no effort limit for wheel_right, wheel_left"),
        ("bayle-rrp", "robot bayle-rrp: --dynamic needs a dynamic model"),
        ("arm.urdf", "--dynamic: DynamicModel: arm 0 (tool) joint 0 (j1) has no inertial"),
    ],
)
def test_dynamic_without_inertials_or_effort_limits_is_one_line(
    robot, message, tmp_path, monkeypatch, capsys
):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "arm.urdf").write_text(URDF_WITHOUT_LINK_INERTIALS)
    urdf = ["--tip", "tool"] if robot.endswith(".urdf") else []
    code, err = _run(["view", robot, *urdf, "--dynamic", "--port", "0"], capsys)
    assert code == 2 and message in err and len(err.strip().splitlines()) == 1


URDF_WITHOUT_LINK_INERTIALS = """<robot name="bare">
  <link name="base_footprint"><inertial><mass value="20"/><origin xyz="0 0 0.1"/>
    <inertia ixx="1" iyy="1" izz="1" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="wheel_right"><inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial>
    <collision><geometry><cylinder radius="0.1" length="0.03"/></geometry></collision></link>
  <link name="wheel_left"><inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial>
    <collision><geometry><cylinder radius="0.1" length="0.03"/></geometry></collision></link>
  <joint name="wheel_right_joint" type="continuous"><parent link="base_footprint"/><child link="wheel_right"/>
    <origin xyz="0 -0.2 0.1" rpy="-1.5708 0 0"/><axis xyz="0 0 1"/><limit effort="5" velocity="10"/></joint>
  <joint name="wheel_left_joint" type="continuous"><parent link="base_footprint"/><child link="wheel_left"/>
    <origin xyz="0 0.2 0.1" rpy="-1.5708 0 0"/><axis xyz="0 0 1"/><limit effort="5" velocity="10"/></joint>
  <link name="upper"/>
  <link name="tool"/>
  <joint name="j1" type="revolute"><parent link="base_footprint"/><child link="upper"/><origin xyz="0 0 0.3"/>
    <axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="10" velocity="1"/></joint>
  <joint name="j2" type="fixed"><parent link="upper"/><child link="tool"/><origin xyz="0.4 0 0"/></joint>
</robot>
"""


def test_keep_out_regions_are_drawn_on_the_floor(artifacts, capsys):
    """A table in front of the platform: its translucent red patch covers thousands of pixels that the same
    view without it does not have (red well above green, green and blue alike: not the links' orange)."""

    def red_patch(png: Path) -> int:
        rgb = np.asarray(Image.open(png).convert("RGB"), dtype=float)[:, :900]
        red, green, blue = rgb[..., 0], rgb[..., 1], rgb[..., 2]
        return int(((red - green > 50) & (np.abs(green - blue) < 25)).sum())

    shots = []
    for name, extra in (
        ("view_keep_out.png", ["--keep-out", "-1,-0.45,-0.5,0.5"]),
        ("view_no_keep_out.png", []),
    ):
        png = artifacts / name
        main(["view", "bayle-rrp", "--port", "0", *extra, "--screenshot", str(png)])
        shots.append(red_patch(png))
    assert shots[0] > 3000 and shots[1] < 0.1 * shots[0], shots
    capsys.readouterr()


@pytest.mark.parametrize(
    ("options", "message"),
    [
        (["--keep-out", "1,2,3"], "--keep-out: expected 4 values, got 3"),
        (["--keep-out", "1,1,0,1"], "--keep-out must have x_min < x_max and y_min < y_max"),
        (["--keep-out", "0,1,0,1", "--footprint", "-1"], "--footprint radius must be > 0 (m), got -1"),
        (["--footprint", "0.3"], "--footprint: give it with --keep-out"),
    ],
)
def test_bad_floor_options_are_one_line(options, message, capsys):
    code, err = _run(["view", "bayle-rrp", "--port", "0", *options], capsys)
    assert code == 2 and len(err.strip().splitlines()) == 1 and message in err, err


SCENE = """
floor = -0.1

[[obstacle]]
name = "table"
shape = "box"
size = [0.6, 1.2, 0.5]
position = [1.1, 0.0, 0.25]
"""


def test_a_scene_and_the_collision_spheres_are_drawn(tmp_path, artifacts, capsys):
    """The table in front of the arm covers thousands of teal pixels (green and blue alike, well above red),
    the spheres' magenta a thousand more (red and blue well above green)."""

    def pixels(png: Path) -> tuple[int, int]:
        rgb = np.asarray(Image.open(png).convert("RGB"), dtype=float)[:, :900]
        red, green, blue = rgb[..., 0], rgb[..., 1], rgb[..., 2]
        teal = (green - red > 60) & (np.abs(green - blue) < 30)
        magenta = (red - green > 40) & (blue - green > 25)
        return int(teal.sum()), int(magenta.sum())

    scene = tmp_path / "scene.toml"
    scene.write_text(SCENE)
    png = artifacts / "view_scene_spheres.png"
    q = "0,0,0,0,0.3,0.7"
    main(["view", "bayle-rrp", "--q", q, "--scene", str(scene), "--spheres", "--screenshot", str(png)])
    assert f"screenshot: {png}" in capsys.readouterr().out
    teal, magenta = pixels(png)
    assert teal > 3000 and magenta > 1000, (teal, magenta)


@pytest.mark.parametrize(
    ("text", "message"),
    [
        (
            '[[obstacle]]\nname = "cone"\nshape = "cone"\nsize = [1.0]\n',
            "obstacle 'cone': shape must be one of",
        ),
        (
            '[[obstacle]]\nname = "t"\nshape = "box"\nsize = [1.0, -1.0, 1.0]\n',
            "obstacle 't': size[1] (y) must be > 0",
        ),
        ('[[obstacle]]\nname = "t"\nshape = "sphere"\nsize = [1.0]\nposition = [0, nan, 0]\n', "position[1]"),
        (
            '[[obstacle]]\nname = "t"\nshape = "sphere"\nsize = [1.0]\ncolour = "red"\n',
            "unknown key 'colour'",
        ),
    ],
)
def test_a_bad_scene_is_one_line(text, message, tmp_path, capsys):
    scene = tmp_path / "scene.toml"
    scene.write_text(text)
    code, err = _run(["view", "bayle-rrp", "--port", "0", "--scene", str(scene)], capsys)
    assert code == 2 and len(err.strip().splitlines()) == 1 and message in err and "scene.toml" in err, err
    code, err = _run(["view", "bayle-rrp", "--port", "0", "--scene", str(tmp_path / "none.toml")], capsys)
    assert code == 2 and len(err.strip().splitlines()) == 1 and "none.toml" in err, err
