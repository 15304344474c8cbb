"""Bayle et al. (2003) Fig. 5 and 6 at the reduced (``quick``) resolution: files, schema and the paper's claims.

The claims are re-checked from the simulated paths with quantities computed here independently of the code
under test (NumPy SVD of J̄ for w5, the closed-form cubic of eq. 7 for α).
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from mobman import kinematics as K
from mobman.cli import main
from mobman.experiments import bayle2003 as b
from mobman.io import trajectories
from mobman.model import robots
from mobman.model.tasks import Position

QUICK_DT = 0.05
RUN_FIELDS = {
    "run",
    "criterion",
    "k",
    "max_error",
    "rms_error",
    "final_error",
    "graining_points",
    "v_initial",
    "control_effort",
    "acceleration_variation",
    "damped_steps",
    "saturated_steps",
    "median_system_w5",
    "fraction_system_w5_below_threshold",
    "max_limit_ratio",
    "initial_error",
    "sigma_min_initial",
    "sigma_min_final",
    "sigma_min_min",
    "system_w5_min",
    "arm_w5_min",
}
FIG6_FIELDS = {
    "transition_x",
    "alpha_initial",
    "alpha_final",
    "zone_samples",
    "zone1_mean_system_w5",
    "zone1_mean_arm_w5",
    "zone3_mean_system_w5",
    "zone3_mean_arm_w5",
    "zone3_final_arm_w5",
    "max_error",
    "graining_points",
}


@pytest.fixture(scope="module")
def out(tmp_path_factory):
    path = tmp_path_factory.mktemp("bayle2003")
    b.run(path, quick=True).write(path)
    return path


@pytest.fixture(scope="module")
def results(out):
    return json.loads((out / "results.json").read_text())


@pytest.fixture(scope="module")
def setup():
    robot, task = robots.bayle_planar(l1=b.L1, l2=b.L2), Position("xy")
    return robot, task, np.asarray(b.SETTINGS["q0"]), 30.0, QUICK_DT


@pytest.fixture(scope="module")
def fig5(setup, out):  # ``out`` first: the reproduction has compiled these simulations
    return b._fig5(*setup)[1]


@pytest.fixture(scope="module")
def fig6(setup, out):
    return b._fig6(*setup)


def _svd_w5(robot, task, q):
    """w5 = √(1 − σ_min²/σ_max²) of J̄ by NumPy's SVD (independent of mobman.manipulability)."""
    sigma = np.linalg.svd(np.asarray(K.reduced_jacobian(robot, q, task)), compute_uv=False)
    return np.sqrt(1.0 - (sigma[..., -1] / sigma[..., 0]) ** 2)


def test_files_and_schema(out, results):
    for name in ("fig5_paths", "fig5_measures", "fig6_paths", "fig6_measures"):
        data = (out / f"{name}.png").read_bytes()
        assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 10_000
    report = (out / "report.md").read_text()
    assert "Claim (ellipse close to a circle most of the time): holds" in report
    assert "zone 1): holds" in report
    assert set(results) == {"settings", "fig5", "fig6"}
    assert [r["k"] for r in results["fig5"]] == [*b.GAINS, *(k for _, k in b.POWERED)]
    assert [r["criterion"] for r in results["fig5"]] == ["w5"] * len(b.GAINS) + ["w5^2", "w5^4"]
    for row in results["fig5"]:
        assert RUN_FIELDS <= set(row)
    assert FIG6_FIELDS <= set(results["fig6"])
    assert results["settings"]["dt"] == QUICK_DT


def test_fig5_ellipse_is_near_a_circle_most_of_the_time(setup, fig5):
    robot, task = setup[:2]
    transient = b.SETTINGS["transient"]
    for name, _criterion, k, r in fig5:
        after = r.t >= transient
        w5 = _svd_w5(robot, task, r.q)[after]
        assert np.allclose(w5, r.measures["system_w5"][after], atol=1e-6)
        near_circle = np.mean(w5 < 0.5)  # σ_min/σ_max > 0.87
        if k == 0.0:  # no optimisation: the minimum-norm solution drifts to an elongated ellipse
            assert near_circle < 0.1, name
            assert np.median(w5) > 0.9, name
        else:
            assert near_circle >= 0.9, name
            assert np.median(w5) < 0.35, name


def test_fig5_tracking_and_conditioning(results):
    rows = {r["run"]: r for r in results["fig5"]}
    none = rows["P = w5, k = 0"]
    # the minimum-norm run meets a singular J̄; damping keeps it bounded instead of blowing up
    assert none["sigma_min_min"] < b.SETTINGS["damping_threshold"] and none["damped_steps"] > 0
    assert none["max_limit_ratio"] < 5.0
    for name, r in rows.items():
        assert np.isfinite(r["max_error"])
        if r["k"] > 0:
            assert r["damped_steps"] == 0 and r["sigma_min_min"] > 0.5, name
    for name in ("P = w5, k = 0.1", "P = w5, k = 0.5", "P = w5², k = 0.5", "P = w5⁴, k = 2"):
        assert rows[name]["max_error"] < 0.02, name
    # the non-smooth w5 and w5² gradients chatter (platform manoeuvres); the smooth w5⁴ does not
    assert rows["P = w5², k = 0.5"]["graining_points"] < rows["P = w5, k = 0.5"]["graining_points"] / 3
    assert rows["P = w5⁴, k = 2"]["graining_points"] <= 5 < rows["P = w5², k = 0.5"]["graining_points"]


def test_fig6_follows_the_alpha_schedule(setup, fig6):
    robot, task = setup[:2]
    ref, alpha, (x0, x1), r = fig6
    tau = np.clip((r.xi_star[:, 0] - x0) / (x1 - x0), 0.0, 1.0)
    a = 1.0 - (3.0 * tau**2 - 2.0 * tau**3)  # eq. 7: α(x0) = 1, α(x1) = 0, α' = 0 at both ends
    assert np.allclose(np.asarray(alpha(r.xi_star)), a, atol=1e-12)
    assert a[0] == 1.0 and a[-1] == 0.0 and np.all(np.diff(a) <= 1e-15)
    sys_w5, arm_w5 = r.measures["system_w5"], r.measures["arm_w5"]
    # the law minimised P = α w5⁴(J̄) + (1 − α) w5⁴(J_a) at the recorded samples
    assert np.allclose(r.info["P"], a * _svd_w5(robot, task, r.q) ** 4 + (1 - a) * arm_w5**4, atol=1e-6)
    zone1, zone3 = a == 1.0, a == 0.0
    assert zone1.sum() > 50 and zone3.sum() > 50
    # zone 1: the whole system is dexterous while the arm is not (Bayle's remark on Fig. 6)
    assert np.mean(sys_w5[zone1]) < 0.2 and np.mean(arm_w5[zone1]) > 0.8
    # zone 3: the arm criterion takes over: the arm becomes dexterous, the whole system less so
    assert arm_w5[-1] < 0.1 and np.mean(sys_w5[zone3]) > 3 * np.mean(sys_w5[zone1])
    assert np.max(np.linalg.norm(r.error, axis=-1)) < 0.01
    assert (
        np.count_nonzero(np.diff(np.sign(r.eta[np.abs(r.eta[:, 0]) > 1e-3, 0])) != 0) <= 5
    )  # smooth: few manoeuvres


def test_trajectories_hold_every_motion_with_its_robot(out, fig5, fig6):
    motions = trajectories.read(out)
    assert [m.label for m in motions] == [f"Fig. 5: {name}" for name, *_ in fig5] + ["Fig. 6"]
    robot = robots.bayle_planar(l1=b.L1, l2=b.L2)
    assert all(m.describes(robot) and not m.describes(robots.bayle_planar()) for m in motions)
    for motion, r in zip(motions, [run for *_, run in fig5] + [fig6[3]]):
        np.testing.assert_allclose(motion.q, r.q, rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(motion.t, r.t, rtol=1e-12, atol=1e-12)


def test_view_of_the_results_folder_renders_the_robot(out, artifacts, robot_pixels, capsys):
    png = artifacts / "view_bayle2003.png"
    main(["view", str(out), "--port", "0", "--screenshot", str(png)])
    assert f"screenshot: {png}" in capsys.readouterr().out
    assert robot_pixels(png.read_bytes()).sum() > 50  # the links are drawn
