"""mobman.studies.sweep: a planar 2R arm's designs against their closed forms (w ≤ l1 l2, mean 2 l1 l2 / π,
reach l1 + l2, coverage the lattice points of the annulus; its mount: the annulus moved, the arm's measures
kept, the system's w by Cauchy–Binet), a robot given as an object, designs the robot refuses, a resumed
sweep and bad input."""

from __future__ import annotations

import numpy as np
import pytest

from mobman.errors import InputError
from mobman.io.urdf import load_urdf, write_urdf
from mobman.model.robot import Mount
from mobman.model.robots import build
from mobman.redundancy import sample_configurations
from mobman.studies import store
from mobman.studies.sweep import STATISTICS, from_study, sweep

SAMPLES = 4000


@pytest.fixture(scope="module")
def grid():
    return sweep("bayle-planar", {"l1": [0.3, 0.5, 0.7], "l2": [0.4, 0.6]}, samples=SAMPLES)


def test_the_statistics_of_w_are_the_closed_form_s(grid):
    l1, l2 = np.meshgrid([0.3, 0.5, 0.7], [0.4, 0.6], indexing="ij")
    product = l1 * l2
    m = grid.metrics
    assert grid.shape == (3, 2) and grid.computed.all() and not grid.failures
    # w = l1 l2 |sin q5| with q5 uniform over [−π, π]: max l1 l2, mean 2 l1 l2 / π, median l1 l2 sin(π/4)
    assert np.all(m["max"] <= product + 1e-12) and np.all(m["max"] >= 0.999 * product)
    standard_error = product * np.sqrt(0.5 - 4 / np.pi**2) / np.sqrt(SAMPLES)
    assert np.all(np.abs(m["mean"] - 2 * product / np.pi) <= 4 * standard_error)
    np.testing.assert_allclose(m["median"], product * np.sin(np.pi / 4), rtol=0.03)
    np.testing.assert_allclose(m["p10"], product * np.sin(np.pi / 20), rtol=0.1)
    np.testing.assert_allclose(m["reach"], l1 + l2, rtol=1e-12)
    # common random numbers: every design sees the same q5, so the statistics scale exactly with l1 l2
    np.testing.assert_allclose(m["mean"] / product, m["mean"][0, 0] / product[0, 0], rtol=1e-12)


def test_the_ranking_is_by_the_metric_and_the_design_names_every_parameter(grid):
    best = grid.ranking("mean", 2)
    assert best == [(2, 1), (1, 1)]
    assert grid.design(best[0]) == {"l1": 0.7, "l2": 0.6}
    with pytest.raises(InputError, match="metric must be one of mean"):
        grid.ranking("volume")


def test_coverage_counts_the_lattice_points_of_the_annulus():
    result = sweep(
        "bayle-planar",
        {"l1": [0.5, 0.7]},
        fixed={"l2": 0.5},
        samples=100,
        bounds=[-1, 1, -1, 1, 0, 0],
        step=0.1,
    )
    i, j = np.meshgrid(np.arange(-10, 11), np.arange(-10, 11))
    d2 = i**2 + j**2  # in tenths of a metre
    expected = [((d2 >= 0) & (d2 <= 100)).mean(), ((d2 >= 4) & (d2 <= 144)).mean()]
    np.testing.assert_allclose(result.metrics["coverage"], expected, rtol=0, atol=1e-15)


def annulus_coverage(centre: tuple[int, int], inner: int, outer: int) -> float:
    """The share of the 21 × 21 lattice points of [−1, 1]² (tenths of a metre) whose squared distance from
    ``centre`` lies in [inner, outer]: the cells a planar 2R arm mounted there reaches."""
    i, j = np.meshgrid(np.arange(-10, 11), np.arange(-10, 11))
    d2 = (i - centre[0]) ** 2 + (j - centre[1]) ** 2
    return float(((d2 >= inner) & (d2 <= outer)).mean())


def test_the_mount_moves_the_annulus_and_keeps_the_arm_s_measures():
    # l1 = l2 = 0.5: the tool reaches the disc of radius 1 about the mount, whatever its yaw
    result = sweep(
        "bayle-planar",
        {"mount.x": [0.0, 0.2], "mount.yaw": [0.0, np.pi / 2, np.pi]},
        fixed={"mount.y": -0.3},
        samples=200,
        bounds=[-1, 1, -1, 1, 0, 0],
        step=0.1,
    )
    m = result.metrics
    expected = [annulus_coverage((0, -3), 0, 100), annulus_coverage((2, -3), 0, 100)]
    np.testing.assert_allclose(m["coverage"], np.repeat(np.array(expected)[:, None], 3, axis=1), atol=1e-15)
    for name in STATISTICS:  # J_a turns with the mount: its singular values do not change
        np.testing.assert_allclose(m[name], m[name][0, 0], rtol=1e-12)
    np.testing.assert_allclose(m["reach"][:, 0], [np.hypot(0.0, 0.3) + 1, np.hypot(0.2, 0.3) + 1], rtol=1e-12)
    assert result.design((1, 2)) == {"mount.y": -0.3, "mount.x": 0.2, "mount.yaw": np.pi}


def test_the_system_s_w_with_the_mount_moved_is_cauchy_binet_s():
    samples = 300
    result = sweep(
        "bayle-planar", {"mount.x": [0.0, 0.3], "mount.y": [0.0, -0.2]}, level="system", samples=samples
    )
    q = sample_configurations(build("bayle-planar"), samples, seed=0)
    l1 = l2 = 0.5
    q4, q45 = q[:, 3], q[:, 3] + q[:, 4]
    arm = np.stack([l1 * np.cos(q4) + l2 * np.cos(q45), l1 * np.sin(q4) + l2 * np.sin(q45)])
    for i, mx in enumerate([0.0, 0.3]):
        for j, my in enumerate([0.0, -0.2]):
            # J̄ (2 × 4, platform frame): v along x, ω turning the tool's lever r = mount + arm, then J_a
            r = arm + np.array([[mx], [my]])
            columns = [
                np.stack([np.ones_like(q4), np.zeros_like(q4)]),
                np.stack([-r[1], r[0]]),
                np.stack([-arm[1], arm[0]]),
                np.stack([-l2 * np.sin(q45), l2 * np.cos(q45)]),
            ]
            # det(J̄ J̄ᵀ) is the sum of the squared 2 × 2 minors (Cauchy–Binet)
            minors = [a[0] * b[1] - a[1] * b[0] for k, a in enumerate(columns) for b in columns[k + 1 :]]
            w = np.sqrt(sum(x**2 for x in minors))
            assert result.metrics["mean"][i, j] == pytest.approx(w.mean(), rel=1e-12)
            assert result.metrics["max"][i, j] == pytest.approx(w.max(), rel=1e-12)


def test_a_robot_given_as_an_object_varies_its_mount(tmp_path):
    path = tmp_path / "planar.urdf"
    write_urdf(build("bayle-planar"), path)
    robot = load_urdf(path, tip="tool_link")
    options = {"samples": 200, "bounds": [-1, 1, -1, 1, 0, 0], "step": 0.1}
    given = sweep(robot, {"mount.x": [0.0, 0.2]}, **options)
    built = sweep("bayle-planar", {"mount.x": [0.0, 0.2]}, **options)
    assert given.robot == robot.name
    for name in given.metrics:
        np.testing.assert_allclose(given.metrics[name], built.metrics[name], rtol=1e-12, atol=1e-15)
    with pytest.raises(
        InputError, match="the given robot 'bayle-planar' has no parameter 'l1'; its parameters: mount.x"
    ):
        sweep(robot, {"l1": [0.5]})
    with pytest.raises(InputError, match=r"arm must be in 0..0 \(bayle-planar has 1 arm\(s\)\), got 1"):
        sweep(robot, {"mount.x": [0.0]}, arm=1)
    # the store keeps the robot's digest: another robot of the same name is refused
    kept = str(tmp_path / "sweep.zarr")
    sweep(robot, {"mount.x": [0.0]}, samples=10, store=kept)
    with pytest.raises(InputError, match="digest"):
        sweep(robot.with_mount(Mount(z=0.1)), {"mount.x": [0.0]}, samples=10, store=kept)


def test_designs_the_robot_refuses_are_recorded_and_the_others_computed():
    result = sweep("bayle-planar", {"l2": [0.5, 0.0, -1.0]}, samples=100)
    assert sorted(result.failures) == [(1,), (2,)]
    assert "l2 (a length) must be a finite number > 0, got 0.0" in result.failures[(1,)]
    assert np.isfinite(result.metrics["mean"][0]) and np.isnan(result.metrics["mean"][1:]).all()
    assert result.ranking("mean") == [(0,)]


def test_a_sweep_kept_in_a_store_is_read_back_and_resumed(tmp_path):
    path = str(tmp_path / "sweep.zarr")
    calls = []

    def stop_after_one(done, total):
        calls.append(done)
        if done == 1:
            raise KeyboardInterrupt

    options = {"samples": 200, "store": path}
    with pytest.raises(KeyboardInterrupt):
        sweep("korayem-planar", {"l1": [0.4, 0.5, 0.6]}, progress=stop_after_one, **options)
    stopped = from_study(store.read(path))
    assert list(stopped.computed) == [True, False, False]
    resumed = sweep("korayem-planar", {"l1": [0.4, 0.5, 0.6]}, **options)
    fresh = sweep("korayem-planar", {"l1": [0.4, 0.5, 0.6]}, samples=200)
    for name in STATISTICS + ("reach",):
        np.testing.assert_array_equal(resumed.metrics[name], fresh.metrics[name])
    with pytest.raises(InputError, match="samples: 300 asked, 200 in the store"):
        sweep("korayem-planar", {"l1": [0.4, 0.5, 0.6]}, samples=300, store=path)


@pytest.mark.parametrize(
    ("args", "options", "message"),
    [
        (("robot-x", {"l1": [1]}), {}, "robot must be a built-in robot's name"),
        (("bayle-planar", {}), {}, "give at least one parameter of robot bayle-planar to vary"),
        (("bayle-planar", {"l3": [1]}), {}, "has no parameter 'l3'; its parameters: l1, l2"),
        (("bayle-planar", {"l1": []}), {}, "l1 must be one or more finite numbers"),
        (("bayle-planar", {"l1": [np.nan]}), {}, "l1 must be one or more finite numbers"),
        (("bayle-planar", {"l1": [1]}), {"fixed": {"l1": 1.0}}, "l1 is both varied and fixed"),
        (
            ("bayle-planar", {"l1": [1]}),
            {"fixed": {"x": 1.0}},
            "fixed: robot bayle-planar has no parameter 'x'",
        ),
        (("bayle-planar", {"l1": [1]}), {"samples": 0}, "samples must be an integer ≥ 1"),
        (("bayle-planar", {"l1": [1]}), {"measure": "w9"}, "measure must be one of"),
        (("bayle-planar", {"l1": [1]}), {"level": "x"}, "level must be one of arm, system"),
        (("bayle-planar", {"l1": [1]}), {"step": 0.1}, "bounds and step go together"),
        (("bayle-planar", {"l1": [1]}), {"bounds": [0, 1, 0, 1, 0, 0], "step": -1.0}, "step must be"),
        (("bayle-planar", {"l1": np.ones(400), "l2": np.ones(400)}), {}, "more than 100,000"),
        (("tiago", {"l1": [1]}), {}, "its parameters: mount.x, mount.y, mount.z, mount.yaw"),
        (("bayle-planar", {"mount.x": [1]}), {"fixed": {"mount.x": 0.0}}, "mount.x is both varied and fixed"),
    ],
)
def test_bad_input_is_one_error_naming_the_field(args, options, message):
    with pytest.raises(InputError, match=message):
        sweep(*args, **options)
