"""The viewer: its scene tree, poses and ellipsoid checked against closed forms, and the page in a real browser.

The browser is Debian's chromium driven by Playwright (software WebGL); the server binds 127.0.0.1 on a free
port and is stopped by the fixture. Screenshots go to the ``artifacts`` folder (conftest.py).
"""

from __future__ import annotations

import dataclasses
import shutil
import time

import numpy as np
import pytest
from playwright.sync_api import sync_playwright

from mobman.errors import InputError
from mobman.io import trajectories
from mobman.model import Elevation, PlanarAngle, Position, robots, stack
from mobman.model.visual import Visual
from mobman.viz import viewer as viewer_module
from mobman.viz.viewer import Viewer

CHROMIUM_ARGS = ["--no-sandbox", "--use-angle=swiftshader", "--enable-unsafe-swiftshader"]
T = np.linspace(0.0, 2.0, 21)
# bayle-rrp: q = (x, y, θ, q4, q5, q6); every coordinate moves, q5 passes exactly π/2 (arm vertical)
Q = np.stack(
    [
        0.6 * T / 2,
        0.2 * T / 2,
        0.5 * T / 2,
        np.pi * T / 2,
        0.2 + (np.pi / 2 - 0.2) * T / 2,
        0.3 + 0.3 * T / 2,
    ],
    axis=1,
)


def tool_position(q: np.ndarray) -> np.ndarray:
    """Closed form of bayle-rrp's tool: the arm base at the platform point, q4 about z, q5 lifts, q6 slides."""
    x, y, theta, q4, q5, q6 = q
    heading = theta + q4
    return np.array([x, y, 0.0]) + q6 * np.array(
        [np.cos(heading) * np.cos(q5), np.sin(heading) * np.cos(q5), np.sin(q5)]
    )


def semi_axes(q: np.ndarray) -> np.ndarray:
    """Singular values of J̄_p = (∂p/∂q) S(q) by central differences of the closed form (NumPy SVD)."""
    h = 1e-6
    jac = np.stack(
        [(tool_position(q + h * e) - tool_position(q - h * e)) / (2 * h) for e in np.eye(6)], axis=1
    )
    s = np.zeros((6, 5))
    s[0, 0], s[1, 0], s[2, 1] = np.cos(q[2]), np.sin(q[2]), 1.0
    s[3:, 2:] = np.eye(3)
    return np.linalg.svd(jac @ s, compute_uv=False)


@pytest.fixture(scope="module")
def viewer(tmp_path_factory):
    folder = tmp_path_factory.mktemp("motion")
    robot = robots.bayle_rrp()
    trajectories.write(folder, [trajectories.Motion.of("sweep", robot, T, Q)])
    with Viewer(robot, port=0) as v:
        v.load_results(folder)
        yield v


def test_scene_tree_holds_every_link_frame_and_path(viewer):
    names = set(viewer.nodes)
    for joint in ("q4", "q5", "q6"):
        assert {f"/robot/rrp/{joint}", f"/robot/rrp/{joint}/link"} <= names
    assert {
        "/world",
        "/robot/platform",
        "/robot/rrp/tool",
        "/ellipsoid",
        "/paths/ee",
        "/paths/platform",
    } <= names
    assert viewer.url.startswith("http://127.0.0.1:")


def test_time_moves_the_robot_and_resizes_the_ellipsoid_as_the_closed_form_says(viewer):
    scales = []
    for k in (0, 10, 20):
        viewer.set_time(T[k])
        np.testing.assert_allclose(viewer.nodes["/robot/rrp/tool"].position, tool_position(Q[k]), atol=1e-9)
        np.testing.assert_allclose(
            viewer.nodes["/robot/platform"].position, [Q[k, 0], Q[k, 1], 0.0], atol=1e-12
        )
        scales.append(np.sort(np.asarray(viewer.nodes["/ellipsoid"].scale))[::-1])
    # one drawing factor for the viewer's lifetime: the drawn axes are proportional to the singular values
    for k, scale in zip((0, 10, 20), scales):
        np.testing.assert_allclose(
            scale / scales[0][0], semi_axes(Q[k]) / semi_axes(Q[0])[0], rtol=1e-6, atol=1e-3
        )
    assert abs(scales[2][0] - scales[0][0]) > 0.01 * scales[0][0]


def jacobians(q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """J and J̄ = J S of bayle-rrp's task (tool position, heading ξ4 = θ + q4, elevation ξ5 = q5: Bayle §5.2), by
    central differences."""

    def task(q):
        return np.concatenate([tool_position(q), [q[2] + q[3], q[4]]])

    h = 1e-6
    jac = np.stack([(task(q + h * e) - task(q - h * e)) / (2 * h) for e in np.eye(6)], axis=1)
    s = np.zeros((6, 5))
    s[0, 0], s[1, 0], s[2, 1] = np.cos(q[2]), np.sin(q[2]), 1.0
    s[3:, 2:] = np.eye(3)
    return jac, jac @ s


def test_configurations_update_jbar_and_the_singular_flags(viewer):
    rng = np.random.default_rng(0)
    generic = rng.uniform(-np.pi, np.pi, (16, 6))
    generic[:, 5] = rng.uniform(0.1, 1.0, 16)
    d_max = max(np.linalg.matrix_rank(jacobians(q)[0], tol=1e-6) for q in generic)
    d_bar_max = max(np.linalg.matrix_rank(jacobians(q)[1], tol=1e-6) for q in generic)
    for q in ([0.0, 0.0, 0.0, 0.3, 0.4, 0.0], [1.0, -1.0, np.pi, -0.3, 0.4, 0.5], generic[0]):
        q = np.asarray(q)
        viewer.show(q)
        jac, jbar = jacobians(q)
        np.testing.assert_allclose(viewer.snapshot.jbar[0], jbar, atol=1e-6)
        vsc = np.linalg.matrix_rank(jbar, tol=1e-6) < d_bar_max
        ksc = np.linalg.matrix_rank(jac, tol=1e-6) < d_max
        html = viewer.flags_html.content
        assert ("VSC: singular" in html) == vsc and ("KSC: singular" in html) == ksc
        w = viewer.snapshot.measures["w (J̄)"][0]
        # D̄ < m = 5 for this task: w is the product of the D̄ largest singular values (the admissible subspace)
        assert w == pytest.approx(np.prod(np.linalg.svd(jbar, compute_uv=False)[:d_bar_max]), abs=1e-6)
        assert f"| w (J̄) | {w:.4g} |" in viewer.measures_md.content
        np.testing.assert_allclose(viewer.nodes["/robot/rrp/tool"].position, tool_position(q), atol=1e-9)
    # the arm pointing straight up (q5 = π/2) is an ordinary configuration of Bayle's coordinates
    up = np.array([0.0, 0.0, 0.0, 0.3, np.pi / 2, 0.5])
    viewer.show(up)
    assert viewer.snapshot.defined[0] and "undefined" not in viewer.flags_html.content
    np.testing.assert_allclose(viewer.snapshot.jbar[0], jacobians(up)[1], atol=1e-6)
    np.testing.assert_allclose(viewer.nodes["/robot/rrp/tool"].position, [0.0, 0.0, 0.5], atol=1e-12)


def test_a_representation_singularity_is_shown_as_undefined():
    """With the heading of the tool's x axis (ZYX yaw) as a coordinate, the arm pointing up has no heading:
    J̄ is undefined there and the panel says so instead of showing flags."""
    robot = robots.bayle_rrp().with_task(stack(Position("xyz"), PlanarAngle(), Elevation()))
    with Viewer(robot, port=0) as v:
        v.show(np.array([0.0, 0.0, 0.0, 0.3, np.pi / 2, 0.5]))
        assert not v.snapshot.defined[0] and "undefined" in v.flags_html.content


def test_visual_shapes_replace_the_generated_links(tmp_path):
    """A robot with visuals (as a URDF gives them): a box and an STL mesh on joint q4, a platform cylinder."""
    import trimesh

    mesh_file = tmp_path / "link.stl"
    trimesh.creation.box(extents=(0.2, 0.2, 0.2)).export(mesh_file)
    shift = np.eye(4)
    shift[:3, 3] = (0.1, 0.0, 0.05)
    box = Visual("box", tuple(shift.ravel()), (0.4, 0.2, 0.1), rgba=(0.2, 0.4, 0.8, 1.0), name="shell")
    stl = Visual("mesh", filename=str(mesh_file), scale=(0.5, 0.5, 0.5), name="motor")
    plain = robots.bayle_rrp()
    arm = plain.arms[0]
    joints = (dataclasses.replace(arm.joints[0], visuals=(box, stl)),) + arm.joints[1:]
    robot = dataclasses.replace(
        plain,
        arms=(dataclasses.replace(arm, joints=joints),),
        platform_visuals=(Visual("cylinder", size=(0.3, 0.1), name="base"),),
    )
    with Viewer(robot, port=0) as v:
        names = set(v.nodes)
        assert {"/robot/rrp/q4/shell", "/robot/rrp/q4/motor", "/robot/platform/base"} <= names
        assert "/robot/rrp/q4/link" not in names and "/robot/rrp/q5/link" in names
        assert not any(n.startswith("/robot/platform/wheel") for n in names)
        corners = np.array([[x, y, z] for x in (-0.1, 0.3) for y in (-0.1, 0.1) for z in (0.0, 0.1)])
        drawn = np.asarray(v.nodes["/robot/rrp/q4/shell"].vertices)
        np.testing.assert_allclose(np.unique(drawn.round(6), axis=0), corners, atol=1e-6)
        np.testing.assert_allclose(
            np.abs(np.asarray(v.nodes["/robot/rrp/q4/motor"].vertices)).max(), 0.05, atol=1e-6
        )
        assert tuple(v.nodes["/robot/rrp/q4/shell"].color) == (51, 102, 204)


def test_browser_connects_and_the_time_slider_moves_the_robot_pixels(viewer, artifacts, robot_pixels):
    out = artifacts
    viewer.set_time(0.0)
    with sync_playwright() as pw:
        browser = pw.chromium.launch(executable_path=shutil.which("chromium"), args=CHROMIUM_ARGS)
        try:
            page = browser.new_page(viewport={"width": 1100, "height": 750})
            page.goto(viewer.url)
            page.wait_for_selector("canvas")
            viewer.wait_for_client(timeout=30)
            assert page.get_by_text("mobman: bayle-rrp").count() >= 1
            before = _settled(page)
            pose = viewer.nodes["/robot/rrp/q6"].position.copy()
            page.get_by_role("slider").first.focus()  # the time slider heads the panel
            page.keyboard.press("End")
            deadline = time.monotonic() + 20  # the server runs the slider's callback in its own thread
            while time.monotonic() < deadline and not np.allclose(
                viewer.nodes["/robot/rrp/tool"].position, tool_position(Q[-1]), atol=1e-9
            ):
                time.sleep(0.05)
            assert viewer.time_slider.value == pytest.approx(T[-1])
            np.testing.assert_allclose(
                viewer.nodes["/robot/rrp/tool"].position, tool_position(Q[-1]), atol=1e-9
            )
            assert np.linalg.norm(viewer.nodes["/robot/rrp/q6"].position - pose) > 0.1
            after = _settled(page)
            page.get_by_role("button", name="play / pause").click()  # at the end: plays again from the start
            deadline = time.monotonic() + 20
            while not 0 < viewer.time_slider.value < T[-1] and time.monotonic() < deadline:
                time.sleep(0.05)
            assert 0 < viewer.time_slider.value < T[-1]
            page.get_by_role("button", name="play / pause").click()
        finally:
            browser.close()
    (out / "viewer_bayle-rrp_start.png").write_bytes(before)
    (out / "viewer_bayle-rrp_end.png").write_bytes(after)
    first, last = robot_pixels(before), robot_pixels(after)
    assert first.sum() > 200 and last.sum() > 200
    assert (first ^ last).sum() > 200


def _settled(page) -> bytes:
    previous = page.screenshot()
    for _ in range(40):
        time.sleep(0.3)
        shot = page.screenshot()
        if shot == previous:
            return shot
        previous = shot
    return shot


def test_a_saved_motion_rebuilds_the_robot_with_its_arm_s_mount(tmp_path):
    from mobman.io import trajectories
    from mobman.viz.viewer import robot_of

    robot = robots.design("bayle-planar", {"l1": 0.6, "mount.x": 0.2, "mount.yaw": 0.5})
    trajectories.write(tmp_path, [trajectories.Motion.of("still", robot, [0.0], np.zeros((1, robot.n_q)))])
    assert robot_of(trajectories.read(tmp_path)[0]) == robot


def test_several_motions_one_chosen_by_label(tmp_path):
    robot = robots.bayle_rrp()
    still = np.broadcast_to(Q[5], Q.shape)
    trajectories.write(
        tmp_path,
        [trajectories.Motion.of("sweep", robot, T, Q), trajectories.Motion.of("still", robot, T, still)],
    )
    (tmp_path / "results.json").write_text("{}")  # a run's results: the motions are read beside them
    with Viewer(robot, port=0) as v:
        assert v.load_results(tmp_path / "results.json", motion="still") == ["sweep", "still"]
        v.set_time(T[-1])
        np.testing.assert_allclose(v.nodes["/robot/rrp/tool"].position, tool_position(Q[5]), atol=1e-9)
        with pytest.raises(InputError, match="--motion 'jump': not in"):
            v.load_results(tmp_path, motion="jump")


def test_two_arm_robot_gets_an_ellipsoid_and_the_measures_at_each_tool():
    """tiago-dual: at each arm's tool the ellipsoid {J̄ₚ η : ‖η‖ ≤ 1} of that tool's position (J̄ₚ = ∂p/∂q S by
    central differences of the drawn tool frames, S of the differential drive in closed form), one drawing factor
    for both arms, and w, w2, w5 of each J̄ₚ in the panel (NumPy SVD)."""
    import viser.transforms as vtf

    from mobman import kinematics

    robot = robots.build("tiago-dual")
    lower, upper = (np.array(v) for v in zip(*robot.position_limits))
    rng = np.random.default_rng(3)
    q = np.concatenate([[0.3, -0.4, np.pi], rng.uniform(lower[3:], upper[3:])])
    q[3], q[12] = np.pi / 2, np.pi  # arm_right_1 at its upper limit, arm_left_3 at π
    h = 1e-6
    steps = np.concatenate([q + h * np.eye(robot.n_q), q - h * np.eye(robot.n_q)])
    # padded to a block of the viewer's size: the frames compiled for the viewer serve here too
    steps = np.concatenate([steps, np.broadcast_to(q, (viewer_module.CHUNK - len(steps), robot.n_q))])
    tools = [np.asarray(p)[:, -1] for _, p in kinematics.frames(robot, steps).links]
    s = np.zeros((robot.n_q, robot.n_eta))
    s[0, 0], s[1, 0], s[2, 1] = np.cos(q[2]), np.sin(q[2]), 1.0
    s[3:, 2:] = np.eye(robot.n_q - 3)
    labels = ("arm_right_tool_link", "arm_left_tool_link")
    with Viewer(robot, port=0) as v:
        v.show(q)
        assert "/ellipsoid" not in v.nodes and "/ellipsoid_dynamic" not in v.nodes
        factors = []
        for tool, label in zip(tools, labels):
            j_p = ((tool[: robot.n_q] - tool[robot.n_q : 2 * robot.n_q]) / (2 * h)).T @ s
            sigma = np.linalg.svd(j_p, compute_uv=False)
            node = v.nodes[f"/ellipsoid_{label}"]
            np.testing.assert_allclose(node.position, v.nodes[f"/robot/{label}/tool"].position, atol=1e-12)
            factors.append(max(node.scale) / sigma[0])
            r = vtf.SO3(np.asarray(node.wxyz)).as_matrix()
            drawn = r @ np.diag(np.asarray(node.scale) ** 2) @ r.T / factors[-1] ** 2
            np.testing.assert_allclose(drawn, j_p @ j_p.T, rtol=1e-6, atol=1e-6 * sigma[0] ** 2)
            measures = v.snapshot.measures
            np.testing.assert_allclose(measures[f"w (J̄ₚ {label})"][0], np.prod(sigma), rtol=1e-6)
            np.testing.assert_allclose(measures[f"w2 (J̄ₚ {label})"][0], sigma[-1] / sigma[0], rtol=1e-6)
            np.testing.assert_allclose(
                measures[f"w5 (J̄ₚ {label})"][0], np.sqrt(1 - (sigma[-1] / sigma[0]) ** 2), rtol=1e-6
            )
            assert f"w (J̄ₚ {label})" in v.measures_md.content
        np.testing.assert_allclose(factors[0], factors[1], rtol=1e-6)


@pytest.mark.slow  # compiles the reduced dynamics of a two-arm robot for a block of configurations
def test_dynamic_ellipsoid_is_drawn_where_a_dynamic_model_exists():
    """yamamoto-dual-arm with its dynamic model: each arm's red ellipsoid's axes follow the accelerations of its
    tool reachable at rest (Yamamoto & Yun eq. 27–38, computed by mobman.dynamics and checked there against Pinocchio)."""
    from mobman.dynamics import yamamoto_model
    from mobman.dynamics.ellipsoids import dynamic_ellipsoid
    from mobman.experiments.yamamoto1999 import torque_limits
    from mobman.model.tasks import Position

    model = yamamoto_model()
    robot, limits = model.robot, torque_limits(model.robot)
    qs = np.array([[0, 0, 0, 0.3, 0.8, 1.1, -0.3, -0.8, -1.1], [0, 0, 0.5, 0.1, 1.5, -0.4, -0.2, -1.2, 0.9]])
    with Viewer(robot, port=0, dynamics=(model, limits)) as v:
        drawn = []
        for q in qs:
            v.show(q)
            drawn.append([np.asarray(v.nodes[f"/ellipsoid_dynamic_arm{i}"].scale) for i in (1, 2)])
            for i in (1, 2):
                np.testing.assert_allclose(
                    v.nodes[f"/ellipsoid_dynamic_arm{i}"].position, v.nodes[f"/robot/arm{i}/tool"].position
                )
    # each arm's ellipsoid, both in the one drawing scale of the viewer; qs padded to a block of the viewer's
    # size: the dynamics compiled for the viewer serve here too
    block = np.concatenate([qs, np.broadcast_to(qs[-1], (viewer_module.CHUNK - len(qs), robot.n_q))])
    expected = [dynamic_ellipsoid(model, block, limits, task=Position("xyz", arm=i)).axes for i in (0, 1)]
    for k in (0, 1):
        for i in (0, 1):
            np.testing.assert_allclose(
                drawn[k][i] / drawn[0][0][0], expected[i][k] / expected[0][0][0], rtol=1e-6, atol=1e-3
            )
    assert abs(drawn[1][0][0] - drawn[0][0][0]) > 0.01 * drawn[0][0][0]


def test_a_reachability_map_is_drawn_on_the_platform_coloured_by_its_score():
    from mobman.studies.maps import reachability_map

    robot = robots.bayle_planar(l1=0.7, l2=0.4)
    result = reachability_map(robot, bounds=[-1.2, 1.2, -1.2, 1.2, 0, 0], step=0.2)
    points, score = result.centres()[result.reached], result.score[result.reached]
    with Viewer(robot, port=0) as v:
        colors = v.show_map(points, score, 0.2)
        assert "/robot/platform/reachability" in v.nodes  # moves with the platform
        # viridis: dark blue at the lowest score, yellow at the highest
        low, high = score == score.min(), score == score.max()
        np.testing.assert_array_equal(colors[low], [[68, 1, 84]] * int(low.sum()))
        np.testing.assert_array_equal(colors[high], [[253, 231, 37]] * int(high.sum()))
        with pytest.raises(InputError, match="points must be"):
            v.show_map(points[:, :2], score)


def test_keep_out_regions_lie_on_the_floor_and_the_footprint_moves_with_the_platform():
    with Viewer(robots.bayle_planar(), port=0) as v:
        v.show_floor([[1.0, 2.0, -1.0, 1.0], [-1.0, -0.5, 0.0, 3.0]], (0.3, 0.1, 0.0))
        ground = v.nodes["/ground"].position[2]
        patch = np.asarray(v.nodes["/keep_out/0"].vertices)
        np.testing.assert_allclose(patch.min(axis=0), [1.0, -1.0, ground], atol=1e-6)
        np.testing.assert_allclose(patch.max(axis=0), [2.0, 1.0, ground + 0.01], atol=1e-6)
        np.testing.assert_allclose(np.asarray(v.nodes["/keep_out/1"].vertices).min(axis=0)[:2], [-1.0, 0.0])
        # the disc is a child of the platform's node, so it moves with it: in the platform frame, about (0.1, 0)
        disc = np.asarray(v.nodes["/robot/platform/footprint"].vertices)
        distance = np.hypot(disc[:, 0] - 0.1, disc[:, 1])
        assert distance.max() == pytest.approx(0.3, abs=1e-6) and disc[:, 2].min() >= ground
        for regions, footprint in (
            ([[2.0, 1.0, 0.0, 1.0]], (0.3, 0.0, 0.0)),
            ([[0, 1, 0, 1]], (0.0, 0.0, 0.0)),
        ):
            with pytest.raises(InputError, match="show_floor: keep_out must be rows"):
                v.show_floor(regions, footprint)


def test_mobman_view_draws_a_map_store_and_refuses_another_robot_s(tmp_path, cli_run):
    path = tmp_path / "map.zarr"
    from mobman.studies.maps import reachability_map

    reachability_map(robots.bayle_planar(), step=0.25, store=str(path))
    code, _, err = cli_run(
        ["view", "bayle-rrp", "--map", str(path), "--port", "0", "--screenshot", str(tmp_path / "x.png")]
    )
    assert code == 2 and "--map: the map was computed for another robot ('bayle-planar')" in err
    code, _, err = cli_run(["view", "bayle-planar", "--map", str(tmp_path / "none.zarr")])
    assert code == 2 and "--map: store" in err and "no such study" in err


def _rpy_matrix(roll: float, pitch: float, yaw: float) -> np.ndarray:
    """R = Rz(yaw) Ry(pitch) Rx(roll), written out (the scene file's convention)."""
    cr, sr, cp, sp, cy, sy = (
        np.cos(roll),
        np.sin(roll),
        np.cos(pitch),
        np.sin(pitch),
        np.cos(yaw),
        np.sin(yaw),
    )
    rz = np.array([[cy, -sy, 0.0], [sy, cy, 0.0], [0.0, 0.0, 1.0]])
    ry = np.array([[cp, 0.0, sp], [0.0, 1.0, 0.0], [-sp, 0.0, cp]])
    rx = np.array([[1.0, 0.0, 0.0], [0.0, cr, -sr], [0.0, sr, cr]])
    return rz @ ry @ rx


def test_a_scene_s_obstacles_spheres_and_closest_pair_are_drawn_and_follow_the_posture():
    """Every primitive of a scene at its pose and size (viser's box, icosphere and cylinder; a capsule as a
    cylinder with a sphere at each end), the floor slab's top on the floor plane, the collision spheres off
    until the panel's box is ticked, on the platform's spheres at R(θ) c + (x, y, 0), and the closest pair's
    segment between the witness points of mobman.collision's nearest pair, red in penetration."""
    import viser.transforms as vtf

    from mobman import collision
    from mobman.model.collision_model import collision_model
    from mobman.model.scene import Obstacle, Scene

    robot = robots.bayle_rrp()
    obstacles = (
        Obstacle("wall", "box", (0.2, 2.0, 1.0), (1.0, 0.0, 0.5), (0.1, -0.2, np.pi / 2)),
        Obstacle("ball", "sphere", (0.15,), (-1.0, 0.5, 0.3)),
        Obstacle("post", "cylinder", (0.1, 0.8), (0.0, -1.2, 0.4), (np.pi / 2, 0.0, 0.0)),
        Obstacle("bar", "capsule", (0.05, 0.6), (-0.5, -0.5, 1.0), (0.0, np.pi, 0.3)),
    )
    scene = Scene(obstacles, floor=-0.1)
    model = collision_model(robot)
    with Viewer(robot, port=0) as v:
        v.show_scene(scene, model)
        for o in obstacles:
            node = v.nodes[f"/scene/{o.name}"]
            np.testing.assert_allclose(node.position, o.position, atol=1e-12)
            np.testing.assert_allclose(
                vtf.SO3(np.asarray(node.wxyz)).as_matrix(), _rpy_matrix(*o.rpy), atol=1e-12
            )
        assert tuple(v.nodes["/scene/wall"].dimensions) == (0.2, 2.0, 1.0)
        assert v.nodes["/scene/ball"].radius == 0.15
        assert (v.nodes["/scene/post"].radius, v.nodes["/scene/post"].height) == (0.1, 0.8)
        assert (v.nodes["/scene/bar/body"].radius, v.nodes["/scene/bar/body"].height) == (0.05, 0.6)
        for end, z in (("top", 0.3), ("bottom", -0.3)):
            np.testing.assert_allclose(v.nodes[f"/scene/bar/{end}"].position, [0.0, 0.0, z])
            assert v.nodes[f"/scene/bar/{end}"].radius == 0.05
        floor = v.nodes["/scene/floor"]
        assert floor.position[2] + floor.dimensions[2] / 2 == pytest.approx(-0.1, abs=1e-12)

        spheres = v.nodes["/collision/spheres"]
        assert not spheres.visible
        v.spheres_checkbox.value = True
        assert spheres.visible
        np.testing.assert_allclose(spheres.batched_scales, [s.radius for s in model.spheres], rtol=1e-6)

        # θ = π/2: the platform's spheres turned a quarter about z; the arm reaching into the wall at x = 1
        for q in ([0.3, -0.2, np.pi / 2, 0.4, 0.3, 0.5], [0.5, 0.0, 0.0, 0.0, 0.2, 0.6]):
            q = np.asarray(q)
            v.show(q)
            turn = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]) if q[2] else np.eye(3)
            on_platform = [k for k, s in enumerate(model.spheres) if s.body == (-1, 0)]
            expected = np.array([turn @ model.spheres[k].centre for k in on_platform]) + [q[0], q[1], 0.0]
            np.testing.assert_allclose(spheres.batched_positions[on_platform], expected, atol=1e-6)
            out = collision.distances(model, scene, q)
            k = int(np.argmin(out.distance))
            segment = v.nodes["/collision/closest"].points[0]
            np.testing.assert_allclose(segment, [out.robot_point[k], out.other_point[k]], atol=1e-6)
            assert v.closest == (collision.pair_names(model, scene)[k], pytest.approx(out.distance[k]))
            assert tuple(v.nodes["/collision/closest"].colors[0, 0]) == viewer_module.clearance_color(
                out.distance[k]
            )
        assert v.closest[1] < 0 and v.closest[0] == ("q6", "wall")  # the arm's last link is in the wall
        assert tuple(v.nodes["/collision/closest"].colors[0, 0]) == viewer_module.NEAR_COLOR
        assert "q6 – wall" in v.clearance_md.content and "(in collision)" in v.clearance_md.content


def test_the_clearance_colour_goes_from_red_at_contact_to_green_far_away():
    near, far = np.array(viewer_module.NEAR_COLOR), np.array(viewer_module.FAR_COLOR)
    assert viewer_module.clearance_color(-0.5) == viewer_module.clearance_color(0.0) == tuple(near)
    assert viewer_module.clearance_color(viewer_module.CLEARANCE_FAR) == tuple(far)
    assert viewer_module.clearance_color(5.0) == tuple(far)
    halfway = viewer_module.clearance_color(viewer_module.CLEARANCE_FAR / 2)
    np.testing.assert_allclose(halfway, (near + far) / 2, atol=0.5)


def test_a_follower_s_shapes_move_with_its_leader():
    """A mast on bayle-rrp's platform rising at half q6 (a URDF mimic joint off the chain): drawn with its box
    at the platform's position plus 0.2 + q6 / 2 m up."""
    from mobman.model.arm import Joint
    from mobman.model.robot import Follower

    box = Visual("box", size=(0.1, 0.1, 0.4), name="pole")
    mast = Joint("prismatic", (0.0, 0.0, 1.0), offset=0.2, name="mast", visuals=(box,))
    robot = dataclasses.replace(robots.bayle_rrp(), followers=(Follower(mast, (-1, 0), 5, 0.5),))
    with Viewer(robot, port=0) as v:
        assert "/robot/followers/mast/pole" in v.nodes
        for q in Q[[0, -1]]:
            v.show(q)
            expected = [q[0], q[1], 0.2 + q[5] / 2]
            np.testing.assert_allclose(v.nodes["/robot/followers/mast"].position, expected, atol=1e-12)
